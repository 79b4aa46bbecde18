//! Outlines: dark lines where the depth jumps between two objects, drawn per eye from that
//! eye's own object and depth planes after shading (PyMOL's `ray_trace_mode` outlines;
//! QuteMol's depth-aware silhouettes).
//!
//! Pixel p turns black when a pixel q within the width (Euclidean, in pixels of the planes)
//! saw another object nearer than p's by more than [`OUTLINE_JUMP`] of q's distance along
//! the view axis (z + d): the line falls on the far side of a silhouette, so the nearer
//! object keeps its size, and a crease between touching spheres (no jump) is left alone.
//! A miss is infinitely far. The planes are an eye's own ([`first_hits`]: its primary rays'
//! first hits through the screen bins or the BVH; or the same planes, bit for bit, kept by
//! the pass that shaded the eye: a film's, a `Target::colour_with_first_hits` render's,
//! exact mode's `PixelBatch::shade_row`'s), so a right eye made by reprojection is outlined
//! exactly as a fully traced one. Supersampled, the outline is drawn on the samples, its width scaled
//! by the supersampling, before the filter. A row is drawn as a flag per pixel, OR-ed over
//! the neighbour offsets in loops the compiler vectorises, then one pass that inks (and,
//! drawn onto a copy, copies); `drawn`, the definition pixel by pixel, is its test's
//! oracle.

use rayon::prelude::*;

use crate::camera::EyeView;
use crate::color::{linear_to_srgb8, srgb8_to_linear, unpack_rgb};
use crate::render::{Pixels, Renderer, Target};
use crate::surface::NO_OBJECT;
use crate::tracer::Tracer;

/// The depth jump that draws an outline, as a share of the nearer pixel's distance.
pub const OUTLINE_JUMP: f32 = 0.03;

/// How [`outline`] draws on one eye's planes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outline {
    /// Width in pixels of the planes (the shown width times the supersampling).
    pub width: f32,
    /// The distance d from the eye to the window, so that z + d is a pixel's distance
    /// along the view axis.
    pub window: f32,
    /// How much of an outlined pixel's light the line takes, in linear light: 1 turns it
    /// black; a coarse frame's sample, k × k pixels of the image, takes the share of its
    /// area a line of the image's width covers (`width / k`), so that its lines are as dark
    /// on average as the image's and no wider.
    pub ink: f32,
}

impl Outline {
    /// Black outlines `width` pixels of `view`'s planes wide.
    #[must_use]
    pub fn of_view(view: &EyeView, width: f32) -> Self {
        Self { width, window: view.distance, ink: 1.0 }
    }
}

/// Draws the outlines of one eye into its colours `rgb` (sRGB, row-major, `w` × `h`), from
/// its object ids and head-space depths (a film's `object` and `z` planes, or
/// [`first_hits`]'s), as the module doc says. Only `rgb` is written; nothing is allocated.
///
/// # Panics
///
/// If a plane is not `w` × `h`.
pub fn outline(rgb: &mut [u32], object: &[u32], z: &[f32], size: (u32, u32), style: Outline) {
    draw(None, rgb, (object, z), size, style);
}

/// [`outline`] onto a copy: `rgb` becomes `from` (an eye's colours, `w` × `h`) with the
/// outlines drawn, in one pass over the pixels, bit for bit a copy then [`outline`].
///
/// # Panics
///
/// If `from` or a plane is not `w` × `h`, or `rgb` not as long as `from`.
pub fn outline_from(from: &[u32], rgb: &mut [u32], object: &[u32], z: &[f32], size: (u32, u32), style: Outline) {
    assert_eq!(from.len(), rgb.len(), "a copy of the colours' size");
    draw(Some(from), rgb, (object, z), size, style);
}

/// [`outline`] into `rgb`, from `from`'s colours if given (else `rgb`'s own).
///
/// A row goes by chunks of [`CHUNK`] pixels: a flag per pixel of the chunk, on the stack
/// (32 bits, as wide as the planes' lanes), OR-ed offset by offset over the chunk in a
/// branch-free loop of slices the compiler vectorises, then one pass that copies the
/// chunk's colours and inks the flagged ones. (The loop this replaced packed the flags into
/// a word's bits, a shift per pixel, and stayed scalar: about 5× slower on 1TII at
/// 800 × 600, `benches/outline.rs`.)
fn draw(from: Option<&[u32]>, rgb: &mut [u32], (object, z): (&[u32], &[f32]), (w, h): (u32, u32), style: Outline) {
    let (w, h) = (w as usize, h as usize);
    assert!(rgb.len() == w * h && object.len() == w * h && z.len() == w * h, "planes of {w}×{h}");
    if style.width <= 0.0 || w == 0 {
        if let Some(from) = from {
            rgb.copy_from_slice(from);
        }
        return;
    }
    let r2 = style.width * style.width;
    let reach = style.width.floor() as isize;
    rgb.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
        let own = (&object[j * w..][..w], &z[j * w..][..w]);
        let from = from.map(|from| &from[j * w..][..w]);
        let mut flags = [0u32; CHUNK];
        for c0 in (0..w).step_by(CHUNK) {
            let span = c0..(c0 + CHUNK).min(w);
            let flags = &mut flags[..span.len()];
            flags.fill(0);
            for dy in -reach..=reach {
                let y = j as isize + dy;
                if y < 0 || y >= h as isize {
                    continue;
                }
                let near = (&object[y as usize * w..][..w], &z[y as usize * w..][..w]);
                for dx in -reach..=reach {
                    if (dx * dx + dy * dy) as f32 > r2 || (dx, dy) == (0, 0) {
                        continue;
                    }
                    // The columns whose neighbour i + dx lies in the row.
                    let lo = span.start.max((-dx).max(0) as usize);
                    let hi = span.end.min((w as isize - dx).max(0) as usize);
                    if lo >= hi {
                        continue;
                    }
                    let q = lo.wrapping_add_signed(dx)..hi.wrapping_add_signed(dx);
                    let own = own.0[lo..hi].iter().zip(&own.1[lo..hi]);
                    let near = near.0[q.clone()].iter().zip(&near.1[q]);
                    for (flag, ((&o, &oz), (&n, &nz))) in flags[lo - c0..hi - c0].iter_mut().zip(own.zip(near)) {
                        *flag |= u32::from(behind((o, oz), (n, nz), style.window));
                    }
                }
            }
            ink_chunk(from.map(|from| &from[span.clone()]), &mut row[span], flags, style.ink);
        }
    });
}

/// Copies `from` (if given) into `out` and inks the pixels `flags` marks ([`inked`]).
#[inline]
fn ink_chunk(from: Option<&[u32]>, out: &mut [u32], flags: &[u32], ink: f32) {
    match (from, ink >= 1.0) {
        // Black: a select per pixel, in vectors.
        (Some(from), true) => {
            for ((out, &flag), &rgb) in out.iter_mut().zip(flags).zip(from) {
                *out = if flag == 0 { rgb } else { 0 };
            }
        }
        (None, true) => {
            for (out, &flag) in out.iter_mut().zip(flags) {
                *out = if flag == 0 { *out } else { 0 };
            }
        }
        (from, false) => {
            if let Some(from) = from {
                out.copy_from_slice(from);
            }
            for (out, &flag) in out.iter_mut().zip(flags) {
                if flag != 0 {
                    *out = inked(*out, ink);
                }
            }
        }
    }
}

/// An outlined pixel's colour: black, or with `ink` below 1 its colour with that share of
/// its linear light taken.
fn inked(rgb: u32, ink: f32) -> u32 {
    if ink >= 1.0 {
        return 0;
    }
    let keep = 1.0 - ink.max(0.0);
    let [r, g, b] = unpack_rgb(rgb).map(|v| u32::from(linear_to_srgb8(srgb8_to_linear(v) * keep)));
    (r << 16) | (g << 8) | b
}

/// Pixels of a row drawn at once, a flag each on the stack (2 KiB).
const CHUNK: usize = 512;

/// Whether a pixel that saw `own` (object, depth) lies behind its neighbour that saw `near`
/// (another object, nearer by more than [`OUTLINE_JUMP`] of the neighbour's distance along
/// the view axis; `window` is d).
#[inline]
#[expect(
    clippy::needless_bitwise_bool,
    reason = "all three tests made, none with a side effect: a loop of them has no branch and runs in vectors (with `&&`, 2× slower on 1TII, `benches/outline.rs`)"
)]
fn behind(own: (u32, f32), near: (u32, f32), window: f32) -> bool {
    (near.0 != own.0) & (near.0 != NO_OBJECT) & (own.1 - near.1 > OUTLINE_JUMP * (near.1 + window))
}

/// Whether pixel (i, j), which saw `own` (object, depth), lies on an outline: the plain
/// definition, pixel by pixel, that [`outline`]'s chunks are tested against (the oracle).
#[cfg(test)]
pub(crate) fn drawn(
    (i, j): (isize, isize),
    (w, h): (usize, usize),
    (object, z): (&[u32], &[f32]),
    (reach, r2, window): (isize, f32, f32),
    own: (u32, f32),
) -> bool {
    for dy in -reach..=reach {
        let y = j + dy;
        if y < 0 || y >= h as isize {
            continue;
        }
        for dx in -reach..=reach {
            let x = i + dx;
            if x < 0 || x >= w as isize || (dx * dx + dy * dy) as f32 > r2 || (dx, dy) == (0, 0) {
                continue;
            }
            let q = y as usize * w + x as usize;
            if behind(own, (object[q], z[q]), window) {
                return true;
            }
        }
    }
    false
}

/// The object and head-space depth ([`EyeView::head_z`]) of the first hit of each pixel's
/// primary ray of `view`, into `object` and `z` (resized; [`NO_OBJECT`] and +∞ for a miss):
/// the planes [`outline`] reads, the same in every stereo mode. Traced by `renderer` as a
/// first-hits pass ([`Target::first_hits`]: the screen bins or the BVH, primary rays only).
pub fn first_hits(renderer: &mut Renderer, tracer: &Tracer, view: &EyeView, object: &mut Vec<u32>, z: &mut Vec<f32>) {
    renderer.render(tracer, view, Pixels::All, Target::first_hits(object, z));
}
