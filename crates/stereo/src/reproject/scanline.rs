//! Per-scanline reprojection of the left eye into the right (Adelson & Hodges 1993, the
//! seed paper's Algorithm 1).
//!
//! For the off-axis parallel camera a point at head-space depth z seen at window position
//! x_l by the left eye is at x_r = x_l + e·z/(d+z) for the right eye, on the same scanline
//! ([`tracer::Disparity`]). In pixels, left pixel i's centre lands at the continuous
//! position i + ½ + e·z/(d+z)·W/w (w the window width), i.e. in right pixel
//! j = ⌊i + ½ + shift⌋.
//!
//! The scan goes left to right and keeps `oldx`, the previous target:
//! - a write to j replaces whatever an earlier pixel wrote there: for a < b whose targets
//!   cross, b is the nearer surface (nearer points shift less), so "later wins" resolves
//!   occlusion without a z-buffer;
//! - when j − oldx > 1, every right pixel strictly between them is marked for retracing,
//!   even if an earlier (farther, further-left) write landed there: the surface stretched in
//!   the right view, or a surface the left eye never saw is disoccluded;
//! - pixels no left pixel lands on (the border strip the left eye never saw) stay unmarked
//!   and are retraced too, and so is the span after the last target: it lies beyond the
//!   left eye's window edge (a near object cut by the right edge of the left image is seen
//!   further in by the right eye), so any earlier write there is a farther surface;
//! - a miss is a point at infinity and shifts by exactly e·W/w, like any other pixel.
//!
//! Where this differs from the printed Algorithm 1, and why:
//! - the printed `let oldx = j` sits after the pixel loop; it must be inside it, once per
//!   pixel, or the gap test compares against the previous scanline;
//! - the printed lines 8 and 15 say "left image" where they mean the right image's pixel j;
//! - targets beyond the right edge are clamped to W (the paper's `M`) so the span up to the
//!   edge is still gap-tested, and targets left of 0 are dropped without a write;
//! - the paper reprojects the left *colour*; here a reprojected pixel only names its source
//!   left pixel, and the mode decides what to reuse from its visible-surface record.
//!
//! How it runs, per row: first every target at once, in SIMD lanes (the division is most of
//! the arithmetic); then the scan, which writes runs of targets that go up one by
//! one a block of four pixels at a time and takes the rules above pixel by pixel only where
//! a run breaks (see `scan` for why that changes nothing). For the frame's pass the scan
//! also carries each source's object id, read in scanline order alongside its target, into
//! the right row's key plane for the classification (`classify.rs`), so
//! no second pass gathers them by source index.
//!
//! SIMD: `fearless_simd`, dispatched at run time on the tracer's level
//! ([`tracer::simd_level`], so `STEREOTRACE_LANES=4` reaches it too): the targets in the
//! native vector (8 lanes with AVX2, 4 otherwise), the scan's blocks in `i32x4`/`u32x4`. It
//! replaced `wide` (SSE2, fixed at compile time) as it is not slower: the measurement is in
//! `docs/performance-notes.md`, "The scanline's SIMD crate".

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use std::ops::{Add, Div, Range, Sub};

use fearless_simd::{dispatch, i32x4, prelude::*, u32x4, Simd, SimdCvtTruncate};
use tracer::Disparity;

use crate::classify::GAP_OBJECT;

/// "No left pixel fills this right pixel": it must be retraced.
pub const NO_SOURCE: u32 = u32::MAX;

/// Reprojects one scanline.
///
/// `z` holds the left row's head-space depths (+∞ for a miss); `disparity` is the eyes'
/// disparity in pixels ([`Disparity::in_pixels`]). On return `src[j]` is `row_base + i` for
/// the left pixel i that fills right pixel j, or [`NO_SOURCE`]. `targets` is scratch space,
/// reused across calls to avoid allocating per row.
///
/// # Panics
///
/// If `z` and `src` differ in length.
pub fn reproject_row(z: &[f32], disparity: Disparity, row_base: u32, src: &mut [u32], targets: &mut Vec<i32>) {
    assert_eq!(z.len(), src.len(), "a depth row and its source row differ in length");
    dispatch!(tracer::simd_level(), simd => simd.vectorize(|| {
        row_targets(simd, z, disparity, targets);
        scan(targets, &mut Sources { simd, src, row_base });
    }));
}

/// The left row's keys (see `classify.rs`) and the right row's planes they are carried to.
pub(super) struct KeyedRow<'a> {
    /// The left row's object ids.
    pub left_object: &'a [u32],
    /// Source map of the right row, as [`reproject_row`] writes it.
    pub src: &'a mut [u32],
    /// Object id of each right pixel's source, or [`GAP_OBJECT`].
    pub object: &'a mut [u32],
}

/// [`reproject_row`] that also carries each source's classification key, read in scanline
/// order along with its target rather than gathered afterwards by source index: on return
/// `row.object[j]` is the left pixel's that `row.src[j]` names, or [`GAP_OBJECT`] where it
/// is [`NO_SOURCE`]. Its caller dispatches, once
/// for a band of rows, and runs it inside `simd.vectorize`.
#[inline(always)]
pub(super) fn reproject_row_keyed<S: Simd>(
    simd: S,
    z: &[f32],
    disparity: Disparity,
    row_base: u32,
    row: KeyedRow<'_>,
    targets: &mut Vec<i32>,
) {
    let w = z.len();
    debug_assert!(
        [row.left_object.len(), row.src.len(), row.object.len()].iter().all(|&n| n == w),
        "a keyed row's planes differ in length from its depth row"
    );
    row_targets(simd, z, disparity, targets);
    scan(targets, &mut Keyed { simd, row, row_base });
}

/// Where the centre of left pixel `i` at depth `z` lands in the right row, in pixels, in
/// one lane (`f32`) or in SIMD lanes (`splat` makes a lane value of a constant) with the
/// same operations in the same order: x = i + ½ + e·z/(d+z) = (i + ½ + e) − e·d/(d+z), the
/// disparity's shortfall, which is 0 for z = +∞, so a miss shifts by exactly e rather than
/// ∞/∞.
#[inline(always)]
fn landing<T>(i: T, z: T, disparity: Disparity, splat: impl Fn(f32) -> T) -> T
where
    T: Add<Output = T> + Sub<Output = T> + Div<Output = T>,
{
    (i + splat(0.5 + disparity.scale)) - disparity.shortfall_in(z, &splat)
}

/// The target right pixel of every left pixel of a row, into `targets`: j = ⌊x⌋ of its
/// [`landing`] x, clamped to [−1, W] (the paper's M for targets past the right edge; −1
/// for targets left of the image, which are dropped). In the level's native vector: 8 lanes
/// with AVX2, 4 otherwise.
#[inline(always)]
fn row_targets<S: Simd>(simd: S, z: &[f32], disparity: Disparity, targets: &mut Vec<i32>) {
    row_targets_in::<S, S::f32s, S::i32s>(simd, z, disparity, targets);
}

/// Lane l holds l, for up to 16 lanes (a constant to load, not lanes to write one by one).
const LANE_INDEX: [f32; 16] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0];

/// [`row_targets`] in lanes of `V` (and `I`, the integers of as many lanes).
#[inline(always)]
fn row_targets_in<S, V, I>(simd: S, z: &[f32], disparity: Disparity, targets: &mut Vec<i32>)
where
    S: Simd,
    V: SimdFloat<S, Element = f32>,
    I: SimdInt<S, Element = i32> + SimdCvtTruncate<V>,
{
    let w = z.len() as i32;
    let target = |i: usize, zi: f32| {
        let x = landing(i as f32, zi, disparity, |c| c).clamp(-1.0, w as f32);
        // ⌊x⌋ for x ≥ −1 is a truncation of x + 1, minus 1: no libm floorf.
        (x + 1.0) as i32 - 1
    };
    // Every entry is overwritten: no need to clear.
    targets.resize(z.len(), 0);
    // A vector at a time (the same operations in the same order as `target`). The clamp's
    // bounds are never NaN, so `max` then `min` (maxps and minps on x86) give what `clamp`
    // gives for every x, and a NaN depth gets the target −1 either way; the truncation
    // (cvttps2dq) is exact, x + 1 being in [0, W + 1].
    let n = V::LEN;
    let lane = V::from_slice(simd, &LANE_INDEX[..n]);
    let (lo, hi) = (V::splat(simd, -1.0), V::splat(simd, w as f32));
    let whole = z.len() / n * n;
    for (c, (zs, ts)) in z[..whole].chunks_exact(n).zip(targets[..whole].chunks_exact_mut(n)).enumerate() {
        let i = V::splat(simd, (c * n) as f32) + lane;
        let x = landing(i, V::from_slice(simd, zs), disparity, |c| V::splat(simd, c)).max(lo).min(hi);
        let t = I::truncate_from(x + 1.0) - 1;
        t.store_slice(ts);
    }
    for i in whole..z.len() {
        targets[i] = target(i, z[i]);
    }
}

/// Pixels per block of the scan's fast path: one 128-bit vector of 32-bit lanes.
const BLOCK: usize = 4;

/// Where the scan writes: the source map alone, or the source map and the keys. `j` is a
/// right pixel, `i` a left pixel, both in the row.
trait RowSink {
    /// Width of the row.
    fn width(&self) -> usize;
    /// Right pixel `j` is filled by left pixel `i`.
    fn put(&mut self, j: usize, i: usize);
    /// Writes the run of left pixels from `i` (whose target is `j`) in whole blocks of
    /// [`BLOCK`] pixels, while whole blocks fit in the row and the `targets` continue the run.
    /// Returns how many pixels continue it (0 when no whole block fits); the rest of the
    /// last block written is provisional (see [`scan`]).
    fn put_run(&mut self, j: usize, i: usize, targets: &[i32]) -> usize;
    /// Right pixels `range` are not filled.
    fn gap(&mut self, range: Range<usize>);
    /// Right pixels `j..j + BLOCK` are not filled.
    fn gap_block(&mut self, j: usize);
}

/// The scan in scanline order over the row's `targets`, writing into `sink`.
///
/// It applies the per-pixel rules, with two shortcuts that leave the result unchanged:
/// - Most of a row is runs: left pixels whose targets go up by exactly one (a surface
///   shifted by a constant whole number of pixels, typically tens of pixels long). Inside a
///   run every target is `oldx + 1`, so there is no gap and each target is written in turn.
///   A run is written a block of [`BLOCK`] pixels at a time, before the block's targets are
///   checked: the run goes on to the first target that breaks it.
/// - A short gap is filled as one whole block.
///
/// Both may write past what they stand for: a run's last block past the end of the run, a
/// gap's block past the target j that ends the gap. Such writes are provisional: once the
/// step that made them is done, each is either overwritten already or lies past the new
/// `oldx`. And after any step, every right pixel p > `oldx` is written again by a later
/// step as the per-pixel rules say: if some later target reaches p, the first one that does
/// lands on p or jumps over it from below (a gap fill over p); if none does, the scanline's
/// closing fill covers p. So the last write to every pixel is the one the per-pixel rules
/// make, in the same order.
#[inline(always)]
fn scan(targets: &[i32], sink: &mut impl RowSink) {
    let (n, w) = (targets.len(), sink.width() as i32);
    debug_assert_eq!(n, sink.width(), "a row of targets and its sink differ in width");
    let mut oldx: i32 = -1;
    let mut i = 0;
    while i < n {
        let j = targets[i];
        if j - oldx > 1 {
            // A gap: j > oldx + 1 ≥ 0. A short one is filled as a block ending at most
            // BLOCK − 1 pixels after j, which are provisional.
            let lo = (oldx + 1).max(0);
            if j - lo <= BLOCK as i32 && lo + BLOCK as i32 <= w {
                sink.gap_block(lo as usize);
            } else {
                sink.gap(lo as usize..j as usize);
            }
        }
        let run = if j >= 0 { sink.put_run(j as usize, i, targets) } else { 0 };
        if run > 0 {
            i += run;
            oldx = j + run as i32 - 1;
            continue;
        }
        // One pixel, near an edge of the image.
        if (0..w).contains(&j) {
            sink.put(j as usize, i);
        }
        oldx = j;
        i += 1;
    }
    // The right border: what lies after the last target came from beyond the left eye's
    // window edge, so only earlier, farther writes can be there. Close the scanline with a
    // target at W, as the paper's `M` does for pixels that leave the image.
    if oldx + 1 < w {
        sink.gap((oldx + 1).max(0) as usize..w as usize);
    }
}

/// Lane offsets of a block's targets.
const LANES: [i32; BLOCK] = [0, 1, 2, 3];

/// Lane offsets of a block's sources.
const SOURCE_LANES: [u32; BLOCK] = [0, 1, 2, 3];

/// How many of a block's `targets` (from the first) equal `expected`'s lanes.
#[inline(always)]
fn continuing<S: Simd>(simd: S, targets: &[i32], expected: i32x4<S>) -> usize {
    let t = i32x4::simd_from(simd, [targets[0], targets[1], targets[2], targets[3]]);
    (!(t.simd_eq(expected).to_bitmask() as u32)).trailing_zeros().min(BLOCK as u32) as usize
}

/// The length in whole blocks of the longest run from left pixel `i` to right pixel `j`
/// that fits in a row of `targets.len()` pixels.
#[inline(always)]
fn whole_blocks(targets: &[i32], j: usize, i: usize) -> usize {
    let n = targets.len();
    (n - j).min(n - i) / BLOCK * BLOCK
}

/// The first block of a run from left pixel `i` to right pixel `j`: the targets it expects,
/// and the sources it writes.
#[inline(always)]
fn first_block<S: Simd>(simd: S, j: usize, source: u32) -> (i32x4<S>, u32x4<S>) {
    (
        i32x4::splat(simd, j as i32) + i32x4::from_slice(simd, &LANES),
        u32x4::splat(simd, source) + u32x4::from_slice(simd, &SOURCE_LANES),
    )
}

/// Writes the source map only.
struct Sources<'a, S> {
    simd: S,
    src: &'a mut [u32],
    row_base: u32,
}

impl<S: Simd> RowSink for Sources<'_, S> {
    fn width(&self) -> usize {
        self.src.len()
    }

    #[inline(always)]
    fn put(&mut self, j: usize, i: usize) {
        self.src[j] = self.row_base + i as u32;
    }

    #[inline(always)]
    fn put_run(&mut self, j: usize, i: usize, targets: &[i32]) -> usize {
        let len = whole_blocks(targets, j, i);
        let (mut expected, mut source) = first_block(self.simd, j, self.row_base + i as u32);
        let mut run = 0;
        for (t, src) in targets[i..i + len].chunks_exact(BLOCK).zip(self.src[j..j + len].chunks_exact_mut(BLOCK)) {
            src.copy_from_slice(source.as_slice());
            let k = continuing(self.simd, t, expected);
            run += k;
            if k < BLOCK {
                break;
            }
            expected += BLOCK as i32;
            source += BLOCK as u32;
        }
        run
    }

    #[inline(always)]
    fn gap(&mut self, range: Range<usize>) {
        self.src[range].fill(NO_SOURCE);
    }

    #[inline(always)]
    fn gap_block(&mut self, j: usize) {
        self.src[j..j + BLOCK].copy_from_slice(&[NO_SOURCE; BLOCK]);
    }
}

/// Writes the source map and carries the keys.
struct Keyed<'a, S> {
    simd: S,
    row: KeyedRow<'a>,
    row_base: u32,
}

impl<S: Simd> RowSink for Keyed<'_, S> {
    fn width(&self) -> usize {
        self.row.src.len()
    }

    #[inline(always)]
    fn put(&mut self, j: usize, i: usize) {
        let r = &mut self.row;
        r.src[j] = self.row_base + i as u32;
        r.object[j] = r.left_object[i];
    }

    /// [`Sources`]' loop with the keys copied in the same blocks. Kept fused on purpose: a
    /// shared source loop followed by a separate key copy measured 10–20 % slower.
    #[inline(always)]
    fn put_run(&mut self, j: usize, i: usize, targets: &[i32]) -> usize {
        let r = &mut self.row;
        let len = whole_blocks(targets, j, i);
        let (mut expected, mut source) = first_block(self.simd, j, self.row_base + i as u32);
        let mut run = 0;
        let blocks = targets[i..i + len]
            .chunks_exact(BLOCK)
            .zip(r.src[j..j + len].chunks_exact_mut(BLOCK))
            .zip(r.object[j..j + len].chunks_exact_mut(BLOCK))
            .zip(r.left_object[i..i + len].chunks_exact(BLOCK));
        for (((t, src), object), left_object) in blocks {
            src.copy_from_slice(source.as_slice());
            object.copy_from_slice(left_object);
            let k = continuing(self.simd, t, expected);
            run += k;
            if k < BLOCK {
                break;
            }
            expected += BLOCK as i32;
            source += BLOCK as u32;
        }
        run
    }

    #[inline(always)]
    fn gap(&mut self, range: Range<usize>) {
        let r = &mut self.row;
        r.src[range.clone()].fill(NO_SOURCE);
        r.object[range].fill(GAP_OBJECT);
    }

    #[inline(always)]
    fn gap_block(&mut self, j: usize) {
        let r = &mut self.row;
        r.src[j..j + BLOCK].copy_from_slice(&[NO_SOURCE; BLOCK]);
        r.object[j..j + BLOCK].copy_from_slice(&[GAP_OBJECT; BLOCK]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const D: f32 = 12.0;

    fn run(z: &[f32], scale: f32) -> Vec<u32> {
        let mut src = vec![0; z.len()];
        reproject_row(z, Disparity { scale, distance: D }, 0, &mut src, &mut Vec::new());
        src
    }

    #[test]
    fn zero_ipd_is_the_identity() {
        let z = [f32::INFINITY, 3.0, -2.0, 0.0, 40.0];
        assert_eq!(run(&z, 0.0), vec![0, 1, 2, 3, 4]);
    }

    #[test]
    fn background_shifts_by_e_and_leaves_a_border() {
        // Every pixel at infinity, shift 3: right pixels 0..3 are the unseen border.
        let z = [f32::INFINITY; 8];
        let n = NO_SOURCE;
        assert_eq!(run(&z, 3.0), vec![n, n, n, 0, 1, 2, 3, 4]);
    }

    #[test]
    fn window_plane_does_not_move() {
        // z = 0 is the zero-parallax plane: no shift whatever the IPD.
        let z = [0.0; 6];
        assert_eq!(run(&z, 7.0), vec![0, 1, 2, 3, 4, 5]);
    }

    #[test]
    fn nearer_surface_wins_and_disocclusion_is_a_gap() {
        // Background (shift 4) then a near surface on the window (shift 0) from pixel 6 on.
        let inf = f32::INFINITY;
        let z = [inf, inf, inf, inf, inf, inf, 0.0, 0.0, 0.0, inf, inf, inf, inf, inf, inf, inf];
        let src = run(&z, 4.0);
        let n = NO_SOURCE;
        // Background 0..6 lands on 4..10; the near surface 6..9 overwrites 6..9 in place;
        // background 9.. lands on 13.., leaving 9..13 (was background 5 at 9) as a gap.
        assert_eq!(src, vec![n, n, n, n, 0, 1, 6, 7, 8, n, n, n, n, 9, 10, 11]);
    }

    #[test]
    fn stretched_span_is_retraced_even_over_an_earlier_write() {
        // Targets 0, 1, 2 then 5: pixels 3 and 4 are between consecutive targets.
        // An earlier pixel could have landed on 3, but the gap rule clears it.
        let mut src = vec![0; 8];
        // shift = scale·(1 − d/(d+z)); choose z so the shifts are 0, 0, 0, 2, 2...
        let z2 = D * 2.0 / (8.0 - 2.0); // shift 2 with scale 8
        let z = [0.0, 0.0, 0.0, z2, z2, z2, z2, z2];
        reproject_row(&z, Disparity { scale: 8.0, distance: D }, 100, &mut src, &mut Vec::new());
        let n = NO_SOURCE;
        assert_eq!(src, vec![100, 101, 102, n, n, 103, 104, 105]);
    }

    #[test]
    fn pixels_in_front_of_the_window_shift_left_and_off_the_edge() {
        // z = −d/2: shift = scale · (1 − 2) = −scale.
        let z = [-D / 2.0; 6];
        let n = NO_SOURCE;
        assert_eq!(run(&z, 2.0), vec![2, 3, 4, 5, n, n]);
    }

    #[test]
    fn the_span_after_the_last_target_is_retraced() {
        // Background (shift 3) then, at the right edge, a surface in front of the window
        // (shift −2): it lands left of where the background wrote, and the background
        // writes after it are hidden behind the part of it the left eye cannot see.
        let inf = f32::INFINITY;
        let near = -D / 2.0; // shift = 3 · (1 − 12/6) = −3
        let z = [inf, inf, inf, inf, inf, near, near, near, near];
        let n = NO_SOURCE;
        // Background 0..5 lands on 3..8; near 5..9 lands on 2..6, over the background;
        // the background left at 6 and 7 is hidden behind the near surface's unseen part.
        assert_eq!(run(&z, 3.0), vec![n, n, 5, 6, 7, 8, n, n, n]);
    }

    #[test]
    fn a_gap_that_starts_left_of_the_image_is_clipped() {
        // Pixel 0 in front of the window lands at −3, then background lands far right:
        // the span between is clipped to the image and nothing panics.
        let n = NO_SOURCE;
        let z = [-D / 2.0, f32::INFINITY, f32::INFINITY, f32::INFINITY, f32::INFINITY];
        assert_eq!(run(&z, 3.0), vec![n, n, n, n, 1]);
    }
}
