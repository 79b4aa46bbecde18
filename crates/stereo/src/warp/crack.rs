//! The crack rule: a pixel its own eye did not reach, inside a surface that the own eye
//! covers around it, is a crack of that surface and takes its colour.
//!
//! A forward warp puts each source pixel on one target pixel, so wherever the new view
//! magnifies a surface (a step towards it, the side of a turn the image stretches to, the
//! side of a sphere that a sideways step turns to the eye) some target pixels get none:
//! single pixels, or whole rows or columns one or two pixels wide. Left to the other eye,
//! such a crack takes whatever of the other eye's lands there, which may be a surface the
//! own eye's hides (the background the other eye saw beside a sphere: speckles); left to the
//! row rule, a crack row across a sphere takes the background beside it (a stripe).
//!
//! A run of one or two such pixels along a column, or else along the row, whose two ends
//! (the own eye's pixels just above and below it, or left and right) are at depths within
//! [`tolerance`] of each other, is a crack of the surface they are on. Each of its pixels
//! takes the colour of the farther end (the upper or the left one on a tie): the ends are
//! one surface, so either is its colour, and where they are two surfaces close in depth, an
//! edge narrower than the tolerance, the farther is the hole rule's choice too. It is
//! [`WarpClass::Crack`]: the own eye's surface, at that end's depth. A landing of the other
//! eye there loses to it unless it is nearer than both ends by more than the tolerance (a
//! surface in front that the own eye did not see); one behind them is hidden by the
//! surface. Columns come first, from the own eye's landings alone; then rows, where the
//! column cracks count as the own eye's (so a pixel where a crack row crosses a crack
//! column is a crack of its row). What neither fills is left to the other eye and the hole
//! rule, as an occluder's edge is (its ends are far apart in depth).
//!
//! The rule reads the keys of the two rows above and the two below, which may be in another
//! band: the bands resolve the rows that are not within two rows of another band, keep a
//! copy of their first and last four rows of keys, and the rows at the seams are resolved
//! from those copies once every band is done (`warp/mod.rs`; `docs/design/timewarp.md`, "Seams"), so a crack at a seam is
//! filled as one inside a band.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use std::ops::Range;

use tracer::EyeView;

use super::scatter::{DEPTH, EMPTY};
use super::WarpClass;

/// The farthest a crack's end is from it, in pixels (runs of up to 2): the rows of keys the
/// rule reads above and below a row.
pub(crate) const REACH: usize = 2;

/// The relative depth difference below which the two ends of a run of holes are one surface
/// (the rule in the module doc), for targets of `view`'s size and window: 17 times the
/// angular size of a pixel at the view's centre (δ = 1/(pixels per unit · d), radians;
/// smaller off the axis).
///
/// Along a surface seen at an angle α from its normal, the depth changes by about
/// n·δ·tan α from one pixel to the next (n its depth), and a crack's ends are up to three
/// pixels apart (a run of two). The factor 17 = 3 · tan 80° takes every surface turned
/// less than 80° from the eye: of a sphere ρ pixels in radius, that leaves a ring of
/// ρ·(1 − sin 80°) = 0.015·ρ pixels at its silhouette, less than a pixel up to ρ = 66
/// pixels. At 800 pixels across a 45° field that is 1.8 %, at 160 pixels 9 %; an edge
/// between two surfaces closer in depth than that is taken for a crack (and filled from the
/// farther, as the hole rule would fill it).
#[must_use]
pub(crate) fn tolerance(view: &EyeView) -> f32 {
    17.0 / (view.pixels_per_unit() * view.distance())
}

/// The depth of a key word of either eye (+∞ for the background).
fn depth(key: i32) -> f32 {
    f32::from_bits((key & DEPTH) as u32)
}

/// Whether a key word is of the own eye.
fn own(key: i32) -> bool {
    key < 0
}

/// Whether the run of holes between the own eye's keys `a` and `b` is a crack for its pixel
/// whose key is `here` (the other eye's landing, or [`EMPTY`]), and if so which end it
/// takes: `false` for `a`, `true` for `b`.
fn crack(a: i32, b: i32, here: i32, tolerance: f32) -> Option<bool> {
    let (da, db) = (depth(a), depth(b));
    // Equal for two ends on the background, where the difference is not a number.
    let near = da.min(db);
    if da != db && (da - db).abs() > tolerance * near {
        return None;
    }
    if here != EMPTY && depth(here) * (1.0 + tolerance) < near {
        return None;
    }
    Some(db > da)
}

/// The first pixel at or after `k` whose key is not its own eye's, or `keys.len()`.
#[inline(always)]
pub(crate) fn next_hole(keys: &[i32], mut k: usize) -> usize {
    // Past the own eye's pixels 32 at a time, then 8, then one at a time: their words are
    // all negative, and so is their bitwise and, which runs in vectors.
    let all_own = |keys: &[i32]| keys.iter().fold(-1, |all, &key| all & key) < 0;
    while k + 32 <= keys.len() && all_own(&keys[k..k + 32]) {
        k += 32;
    }
    while k + 8 <= keys.len() && all_own(&keys[k..k + 8]) {
        k += 8;
    }
    while k < keys.len() && own(keys[k]) {
        k += 1;
    }
    k
}

/// The first pixel after `k` whose key is its own eye's, or `keys.len()`.
pub(crate) fn next_own(keys: &[i32], k: usize) -> usize {
    keys[k + 1..].iter().position(|&key| own(key)).map_or(keys.len(), |n| k + 1 + n)
}

/// A window of consecutive rows of one target eye: its keys and its image, `width` pixels a
/// row. Rows outside it are taken as beyond the image's edge.
pub(crate) struct Window<'a> {
    /// The rows' key words.
    pub keys: &'a [i32],
    /// The rows of the image: the landed colours, and the resolved ones.
    pub out: &'a mut [u32],
    /// The rows' width in pixels.
    pub width: usize,
}

impl Window<'_> {
    /// Applies the crack rule to the run `run` of pixels of row `r` of the window that its
    /// own eye did not reach (between two of its pixels, or the row's ends): the cracks'
    /// colours go to the image and their class to `classes` (the row's). `keys` is left
    /// with the keys of the run and of the own eye's pixels just beyond it (where the row
    /// has them), where each crack has the key of the end it copied (the own eye's surface,
    /// for the hole rule); its first pixel is returned. Returns how many cracks there are,
    /// and how many of them the other eye had reached.
    pub fn cracks(
        &mut self,
        r: usize,
        run: Range<usize>,
        tolerance: f32,
        classes: &mut [WarpClass],
        keys: &mut Vec<i32>,
    ) -> (usize, u64, u64) {
        let w = self.width;
        let row = &self.keys[r * w..][..w];
        let rows = self.keys.len() / w;
        let (from, to) = (run.start.saturating_sub(1), (run.end + 1).min(w));
        keys.clear();
        keys.extend_from_slice(&row[from..to]);
        let (mut cracks, mut over_other) = (0, 0);
        // Columns, from the own eye's landings alone: the rows two and one above, one and
        // two below (`None` beyond the window).
        let near = |up: usize, down: usize| {
            let j = (r + down).wrapping_sub(up);
            (j < rows).then(|| &self.keys[j * w..][..w])
        };
        let [above_2, above_1, below_1, below_2] = [near(2, 0), near(1, 0), near(0, 1), near(0, 2)];
        let at = |row: Option<&[i32]>, c: usize| row.map_or(EMPTY, |row| row[c]);
        for c in run.clone() {
            // The run's ends along the column: the own eye's pixels nearest above and below,
            // at most three rows apart (a run of one, or of two).
            let (a, up) = if own(at(above_1, c)) { (at(above_1, c), 1) } else { (at(above_2, c), 2) };
            let (b, down) = if own(at(below_1, c)) { (at(below_1, c), 1) } else { (at(below_2, c), 2) };
            if !(own(a) && own(b) && up + down <= REACH + 1) {
                continue;
            }
            if let Some(far) = crack(a, b, row[c], tolerance) {
                let end = if far { r + down } else { r - up };
                self.out[r * w + c] = self.out[end * w + c];
                keys[c - from] = if far { b } else { a };
                classes[c] = WarpClass::Crack;
                cracks += 1;
                over_other += u64::from(row[c] != EMPTY);
            }
        }
        // A run without column cracks, longer than a row crack or at the row's end, has no
        // row cracks either.
        if cracks == 0 && (run.len() > REACH || run.start == 0 || run.end == w) {
            return (from, 0, 0);
        }
        // Then rows, where the column cracks are the own eye's: runs of up to REACH pixels
        // between two of them (`keys` ends at the row's ends or at the own eye's pixels).
        let out = &mut self.out[r * w + from..r * w + to];
        let classes = &mut classes[from..to];
        let mut start = next_hole(keys, 0);
        while start < keys.len() {
            let end = next_own(keys, start);
            if start > 0 && end < keys.len() && end - start <= REACH {
                let (a, b) = (keys[start - 1], keys[end]);
                for k in start..end {
                    if let Some(far) = crack(a, b, keys[k], tolerance) {
                        let end = if far { end } else { start - 1 };
                        out[k] = out[end];
                        over_other += u64::from(keys[k] != EMPTY);
                        keys[k] = keys[end];
                        classes[k] = WarpClass::Crack;
                        cracks += 1;
                    }
                }
            }
            start = next_hole(keys, end);
        }
        (from, cracks, over_other)
    }
}

#[cfg(test)]
mod tests {
    use super::super::resolve::resolve;
    use super::super::{WarpClass, WarpCounts};
    use super::{Window, EMPTY};

    /// The own eye's key word of a pixel at depth `n`.
    fn own(n: f32) -> i32 {
        (n.to_bits() | 1 << 31) as i32
    }

    /// The other eye's.
    fn other(n: f32) -> i32 {
        n.to_bits() as i32
    }

    const TOLERANCE: f32 = 0.02;

    /// Resolves a 5×5 window of the own eye's pixels at depth 10 (colour: its index), but
    /// for the keys `changed` gives, and returns the centre pixel's class and colour.
    fn centre(changed: &[(usize, i32)]) -> (WarpClass, u32, WarpCounts) {
        let mut keys = [own(10.0); 25];
        for &(k, key) in changed {
            keys[k] = key;
        }
        let mut out: Vec<u32> = (0..25).collect();
        // What lands there of the other eye has its colour.
        out[12] = 0xff;
        let (mut classes, mut covered, mut row) = (vec![WarpClass::Filled; 25], [false; 5], Vec::new());
        let window = &mut Window { keys: &keys, out: &mut out, width: 5 };
        let counts = resolve(tracer::simd_level(), window, 0..5, &mut classes, &mut covered, TOLERANCE, &mut row);
        (classes[12], out[12], counts)
    }

    /// The centre pixel's class and colour.
    fn pixel(changed: &[(usize, i32)]) -> (WarpClass, u32) {
        let (class, colour, _) = centre(changed);
        (class, colour)
    }

    #[test]
    fn a_crack_takes_its_end_and_an_other_eye_landing_behind_both_ends_is_rejected() {
        // Nothing landed: a crack, from the upper end (a tie).
        assert_eq!(pixel(&[(12, EMPTY)]), (WarpClass::Crack, 7));
        // The ends at 10 and 10.1 (within the tolerance): from the farther, below.
        assert_eq!(pixel(&[(12, EMPTY), (17, own(10.1))]), (WarpClass::Crack, 17));
        // The other eye's landing behind the ends (the background the other eye saw
        // beside the surface), or within the tolerance of them: hidden by the surface.
        for behind in [f32::INFINITY, 50.0, 10.1, 9.9] {
            let (class, colour, counts) = centre(&[(12, other(behind))]);
            assert_eq!((class, colour), (WarpClass::Crack, 7), "the other eye at {behind}");
            assert_eq!((counts.crack, counts.other_eye), (1, 0), "the other eye at {behind}");
        }
        // In front of both by more than the tolerance: a surface the own eye did not see.
        for before in [9.7, 5.0] {
            let (class, colour, counts) = centre(&[(12, other(before))]);
            assert_eq!((class, colour), (WarpClass::OtherEye, 0xff), "the other eye at {before}");
            assert_eq!((counts.crack, counts.other_eye), (0, 1), "the other eye at {before}");
        }
    }

    #[test]
    fn an_edge_is_no_crack_and_a_run_of_two_is_one() {
        // Above and left at 10, below and right at 20: an edge between two surfaces, left
        // to the hole rule (the farther side).
        let edge = [(12, EMPTY), (13, own(20.0)), (14, own(20.0)), (15, own(20.0)), (16, own(20.0)), (17, own(20.0))];
        let (class, colour, _) = centre(&edge[..]);
        assert_eq!((class, colour), (WarpClass::Filled, 13));
        // A run of two along the column (rows 2 and 3), and along the row (columns 2 and
        // 3, where a crack row crosses a crack column): cracks, from the upper (or left)
        // end. A run of three along the column, with an edge along the row, is not.
        assert_eq!(pixel(&[(12, EMPTY), (17, EMPTY)]), (WarpClass::Crack, 7));
        assert_eq!(pixel(&[(12, EMPTY), (7, EMPTY)]), (WarpClass::Crack, 2));
        assert_eq!(pixel(&[(12, EMPTY), (7, EMPTY), (17, EMPTY), (13, EMPTY)]), (WarpClass::Crack, 11));
        let column = [(12, EMPTY), (7, EMPTY), (17, EMPTY), (11, own(30.0))];
        assert_eq!(pixel(&column), (WarpClass::Filled, 11));
    }
}
