//! Outlines: dark lines where the depth jumps between two objects, drawn per eye from that
//! eye's own object and depth planes after shading (PyMOL's `ray_trace_mode` outlines;
//! QuteMol's depth-aware silhouettes).
//!
//! Pixel p turns black when a pixel q within the width (Euclidean, in pixels of the planes)
//! saw another object nearer than p's by more than [`OUTLINE_JUMP`] of q's distance along
//! the view axis (z + d): the line falls on the far side of a silhouette, so the nearer
//! object keeps its size, and a crease between touching spheres (no jump) is left alone.
//! A miss is infinitely far. The planes are an eye's own ([`first_hits`]: its primary rays'
//! first hits through the BVH), so a right eye made by reprojection is outlined exactly as
//! a fully traced one. Supersampled, the outline is drawn on the samples, its width scaled
//! by the supersampling, before the filter.

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
pub fn outline(rgb: &mut [u32], object: &[u32], z: &[f32], (w, h): (u32, u32), style: Outline) {
    let (w, h) = (w as usize, h as usize);
    assert!(rgb.len() == w * h && object.len() == w * h && z.len() == w * h, "planes of {w}×{h}");
    if style.width <= 0.0 || w == 0 {
        return;
    }
    let r2 = style.width * style.width;
    let reach = style.width.floor() as isize;
    rgb.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
        let own = (&object[j * w..][..w], &z[j * w..][..w]);
        for c0 in (0..w).step_by(CHUNK) {
            let span = c0..(c0 + CHUNK).min(w);
            let mut drawn = 0u64;
            // Offset by offset over the chunk: a branch-free inner loop.
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
                    for i in lo..hi {
                        let q = i.wrapping_add_signed(dx);
                        let on = behind((own.0[i], own.1[i]), (near.0[q], near.1[q]), style.window);
                        drawn |= u64::from(on) << (i - c0);
                    }
                }
            }
            for l in crate::bits::ones(&[drawn]) {
                let out = &mut row[c0 + l as usize];
                *out = inked(*out, style.ink);
            }
        }
    });
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

/// Pixels of a row drawn at once, a bit each of a word.
const CHUNK: usize = 64;

/// Whether a pixel that saw `own` (object, depth) lies behind its neighbour that saw `near`
/// (another object, nearer by more than [`OUTLINE_JUMP`] of the neighbour's distance along
/// the view axis; `window` is d).
#[inline]
fn behind(own: (u32, f32), near: (u32, f32), window: f32) -> bool {
    near.0 != own.0 && near.0 != NO_OBJECT && own.1 - near.1 > OUTLINE_JUMP * (near.1 + window)
}

/// Whether pixel (i, j), which saw `own` (object, depth), lies on an outline: the plain
/// definition, pixel by pixel, that [`outline`]'s chunks are tested against.
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
