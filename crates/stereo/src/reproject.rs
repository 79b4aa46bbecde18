//! Per-scanline reprojection of the left eye into the right (Adelson & Hodges 1993, the
//! seed paper's Algorithm 1).
//!
//! For the off-axis parallel camera a point at head-space depth z seen at window position
//! x_l by the left eye is at x_r = x_l + e·z/(d+z) for the right eye, on the same scanline.
//! In pixels, left pixel i's centre lands at the continuous position i + ½ + e·z/(d+z)·W/w
//! (w the window width), i.e. in right pixel j = ⌊i + ½ + shift⌋.
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

use wide::{f32x4, i32x4};

/// "No left pixel fills this right pixel": it must be retraced.
pub const NO_SOURCE: u32 = u32::MAX;

/// Reprojects one scanline.
///
/// `z` holds the left row's head-space depths (+∞ for a miss); `shift_scale` is e·W/w, the
/// shift in pixels of a point at infinity; `distance` is d. On return `src[j]` is
/// `row_base + i` for the left pixel i that fills right pixel j, or [`NO_SOURCE`].
/// `targets` is scratch space, reused across calls to avoid allocating per row.
pub fn reproject_row(
    z: &[f32],
    shift_scale: f32,
    distance: f32,
    row_base: u32,
    src: &mut [u32],
    targets: &mut Vec<i32>,
) {
    debug_assert_eq!(z.len(), src.len());
    let w = src.len() as i32;
    // First every target, in a loop the compiler vectorises:
    // x = i + ½ + e·(1 − d/(d+z)) (in pixels) = (i + ½ + e) − e·d/(d+z), written so that
    // z = +∞ shifts by exactly e rather than ∞/∞; j = ⌊x⌋ clamped to [−1, W] (the paper's M
    // for targets past the right edge; −1 for targets left of the image, which are dropped).
    let (offset, scaled_distance) = (0.5 + shift_scale, shift_scale * distance);
    let target = |i: usize, zi: f32| {
        let x = ((i as f32 + offset) - scaled_distance / (distance + zi)).clamp(-1.0, w as f32);
        // ⌊x⌋ for x ≥ −1 is a truncation of x + 1, minus 1: no libm floorf.
        (x + 1.0) as i32 - 1
    };
    targets.clear();
    targets.resize(z.len(), 0);
    // Four at a time in SIMD lanes (the same operations in the same order as `target`).
    let lane = f32x4::new([0.0, 1.0, 2.0, 3.0]);
    let (lo, hi) = (f32x4::splat(-1.0), f32x4::splat(w as f32));
    let (offset4, sd4, d4, one) =
        (f32x4::splat(offset), f32x4::splat(scaled_distance), f32x4::splat(distance), f32x4::splat(1.0));
    let whole = z.len() / 4 * 4;
    for (c, (zs, ts)) in z[..whole].chunks_exact(4).zip(targets[..whole].chunks_exact_mut(4)).enumerate() {
        let i = f32x4::splat((c * 4) as f32) + lane;
        let zv = f32x4::new([zs[0], zs[1], zs[2], zs[3]]);
        let x = ((i + offset4) - sd4 / (d4 + zv)).max(lo).min(hi);
        let t = (x + one).fast_trunc_int() - i32x4::splat(1);
        ts.copy_from_slice(t.as_array());
    }
    for i in whole..z.len() {
        targets[i] = target(i, z[i]);
    }
    // Then the scan in scanline order.
    src.fill(NO_SOURCE);
    let mut oldx: i32 = -1;
    for (i, &j) in targets.iter().enumerate() {
        if j - oldx > 1 {
            let lo = (oldx + 1).max(0) as usize;
            src[lo..j as usize].fill(NO_SOURCE);
        }
        if (0..w).contains(&j) {
            src[j as usize] = row_base + i as u32;
        }
        oldx = j;
    }
    // The right border: what lies after the last target came from beyond the left eye's
    // window edge, so only earlier, farther writes can be there. Close the scanline with a
    // target at W, as the paper's `M` does for pixels that leave the image.
    if oldx + 1 < w {
        src[(oldx + 1).max(0) as usize..].fill(NO_SOURCE);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const D: f32 = 12.0;

    fn run(z: &[f32], scale: f32) -> Vec<u32> {
        let mut src = vec![0; z.len()];
        reproject_row(z, scale, D, 0, &mut src, &mut Vec::new());
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
        reproject_row(&z, 8.0, D, 100, &mut src, &mut Vec::new());
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
