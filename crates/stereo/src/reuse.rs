//! Exact temporal reuse: while only the scene time moves, a frame retraces only the pixels
//! that can have changed, and is byte for byte the frame a fresh trace would give.
//!
//! Adelson & Hodges carried reprojection across time ("Generating exact ray-traced
//! animation frames by reprojection", IEEE CG&A 15(3), 1995); this is the exact half of
//! that idea, for scenes whose only motion is the tracer's orbits.
//!
//! ## When a frame may reuse the last one
//!
//! Only when nothing but the time changed: the same head pose, IPD, distance, size, mode
//! and edge options, and a tracer with the same [`tracer::Tracer::fingerprint`] (still
//! spheres, radii, materials, swept volumes, lights, reflection depth). Anything else, and
//! the first frame, starts fresh. Every frame, fresh or reused, marks as it traces.
//!
//! ## The left eye (and the right eye of `full` mode)
//!
//! A pixel is *dynamic* when some ray of its tree — primary, shadow or mirror, at any depth —
//! meets the swept volume of a moving sphere (`tracer`'s `swept.rs`). The tracer marks it
//! in the film while tracing ([`tracer::Renderer::render_marking`]).
//!
//! *Lemma.* A pixel that is not dynamic at time t₀ has the same colour, record and mark at
//! every time t₁. Sketch, by induction down its tree: its primary ray does not depend on
//! time; a segment that does not meet any swept volume meets no moving sphere at any time
//! (each moving sphere stays in its volume, which a debug assertion checks whenever a
//! tracer places it), so it meets the same still spheres at the same parameters, and its
//! hit point, normal, shadow rays and mirror ray are the same operations on the same values;
//! each of those is again a segment of the tree, which by assumption meets no volume.
//!
//! So a reused eye retraces exactly its pixels marked last frame, marking them anew; the
//! others keep their bytes, and their (clear) marks stay true.
//!
//! ## The right eye of `copy`, `reshade` and `exact`
//!
//! It is made from the current left eye, so it can change where no ray of its own moved.
//! Stages 2 and 3 (reprojection and classification, cheap) run over the whole image every
//! frame. A right pixel p is then a function F of: its class c(p) and source s(p) from
//! stage 3; the left pixel s(p)'s colour and record; and the rays the right eye casts for p
//! itself (a retrace, exact mode's ray against one sphere, reshade's highlights and mirror
//! rays), which stages 4 and 5 mark as above. F is the same code on the same values in
//! every frame, and it reads no other pixel (stages 4 and 5 are pixel by pixel).
//!
//! *Rule.* Right pixel p is made again when
//! 1. c(p) or s(p) differs from the last frame's, or
//! 2. its source s(p) is a left pixel retraced this frame, or
//! 3. its own rays were marked dynamic last frame.
//!
//! *Conservative.* If none holds, c(p) and s(p) are as before; the left pixel s(p) was not
//! retraced, so its colour and record are last frame's bytes; and by the lemma p's own rays
//! give what they gave. So F gives last frame's colour, final class and mark: p may keep
//! them. A retraced left pixel may well come out unchanged; rule 2 does not ask.
//!
//! Kept pixels also keep their final class (exact mode turns a missed silhouette into an
//! edge in stage 5), so the mask and pixel counts of a reused frame are the fresh frame's.

use rayon::prelude::*;
use tracer::bits;
use tracer::PixelBits;

use crate::reproject::NO_SOURCE;
use crate::stats::PixelClass;

/// This frame's stage-3 output against the last frame's, and what changed on the left.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Changes<'a> {
    /// This frame's classes and sources.
    pub now: (&'a [PixelClass], &'a [u32]),
    /// The last frame's.
    pub before: (&'a [PixelClass], &'a [u32]),
    /// The left pixels retraced this frame.
    pub left_retraced: &'a PixelBits,
    /// The right pixels whose own rays were marked dynamic last frame.
    pub right_marked: &'a PixelBits,
}

/// Sets in `redo` (sized as the marks) the right pixels the rule makes again, and gives each
/// of them its stage-3 class in `mask`; the other pixels of `mask` keep their final class
/// from the last frame. Returns how many are made again.
pub(crate) fn plan_right(changes: Changes<'_>, mask: &mut [PixelClass], redo: &mut PixelBits) -> u64 {
    let Changes { now: (class, src), before: (class_was, src_was), left_retraced, right_marked } = changes;
    let w = right_marked.width() as usize;
    let stride = redo.stride();
    if w == 0 {
        return 0;
    }
    redo.words_mut()
        .par_chunks_mut(stride)
        .zip(mask.par_chunks_mut(w))
        .enumerate()
        .map(|(j, (row, mask))| {
            let base = j * w;
            let mut made = 0;
            for (i, mask) in mask.iter_mut().enumerate() {
                let k = base + i;
                let s = src[k];
                let again = class[k] != class_was[k]
                    || s != src_was[k]
                    || (s != NO_SOURCE && left_retraced.get_index(s as usize))
                    || bits::get(right_marked.row(j as u32), i as u32);
                bits::set(row, i as u32, again);
                if again {
                    *mask = class[k];
                    made += 1;
                }
            }
            made
        })
        .sum()
}
