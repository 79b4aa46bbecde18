//! From a target's keys to its image: each pixel's winner, and the hole rule for the pixels
//! neither eye reached.
//!
//! A pixel's key (`scatter.rs`) left the winner's colour in the image and says whose it
//! is: [`WarpClass::Warped`] or [`WarpClass::OtherEye`]. The rest are
//! [`WarpClass::Filled`], by the rule of the module doc (`warp/mod.rs`): along the row, each
//! run of holes takes the colour of the farther of the covered pixels on its left and on
//! its right (the larger target depth: the background side of a disocclusion, which is what
//! the occluder uncovered; the left one on a tie), or of the one that exists; a row without
//! a covered pixel copies the nearest covered row above, else the nearest below; a frame
//! with none is black. The rule reads only the target's keys and its own output, so it is
//! as deterministic as they are. Bands of rows are resolved in parallel, each row on its
//! own; the rows nothing reached are copied after, in one pass over the image.

use fearless_simd::{dispatch, Level, Simd};

use super::scatter::{Keys, DEPTH, EMPTY};
use super::{WarpClass, WarpCounts};

/// Resolves a band of target rows (`keys`, rows of `width` pixels) into its rows of `out`
/// and `classes`, filling holes along rows with a covered pixel, and notes in `covered`
/// which rows have one; [`fill_uncovered_rows`] does the rest once every band is resolved.
pub(crate) fn resolve_band(
    level: Level,
    keys: &Keys,
    width: usize,
    out: &mut [u32],
    classes: &mut [WarpClass],
    covered: &mut [bool],
) -> WarpCounts {
    // Compiled for the SIMD level's instruction set, where the rows' loops run in its
    // vectors.
    dispatch!(level, simd => simd.vectorize(
        #[inline(always)]
        || resolve_rows(keys, width, out, classes, covered),
    ))
}

/// [`resolve_band`]'s work.
#[expect(clippy::inline_always, reason = "inlined into the dispatched function, whose target features it needs")]
#[inline(always)]
fn resolve_rows(
    keys: &Keys,
    width: usize,
    out: &mut [u32],
    classes: &mut [WarpClass],
    covered: &mut [bool],
) -> WarpCounts {
    let mut counts = WarpCounts::default();
    if width == 0 {
        return counts;
    }
    let rows = keys.depth.chunks_exact(width).zip(out.chunks_exact_mut(width)).zip(classes.chunks_exact_mut(width));
    for (((depth, out), classes), covered) in rows.zip(covered) {
        let (warped, other) = resolve_row(depth, classes);
        counts.warped += warped;
        counts.other_eye += other;
        *covered = warped + other > 0;
        if !*covered {
            // Black, until `fill_uncovered_rows`.
            out.fill(0);
        } else if warped + other < width as u64 {
            fill_row(depth, out);
        }
    }
    counts.filled = keys.depth.len() as u64 - counts.warped - counts.other_eye;
    counts
}

/// The hole rule's last part, once every row is resolved: a row nothing reached (black,
/// `covered` false) copies the nearest covered row above, else the nearest below. A frame
/// nothing reached stays black.
pub(crate) fn fill_uncovered_rows(out: &mut [u32], width: usize, covered: &[bool]) {
    let Some(first) = covered.iter().position(|&c| c) else { return };
    let row = |j: usize| j * width..(j + 1) * width;
    for j in 0..first {
        out.copy_within(row(first), j * width);
    }
    let mut last = first;
    for (j, &covered) in covered.iter().enumerate().skip(first + 1) {
        if covered {
            last = j;
        } else {
            out.copy_within(row(last), j * width);
        }
    }
}

/// Each pixel of a row its class, from its keys' first words `depth` (its colour is in
/// place, or, for a hole, left for [`fill_row`]). Returns how many pixels came from the own
/// eye and from the other. Branch-free, so that it runs in vectors.
#[expect(clippy::inline_always, reason = "inlined into the dispatched function, whose target features it needs")]
#[inline(always)]
fn resolve_row(depth: &[i32], classes: &mut [WarpClass]) -> (u64, u64) {
    // Pixels with a word of the other eye or none, and holes.
    let (mut flagged, mut holes) = (0_u32, 0_u32);
    for (&depth, class) in depth.iter().zip(classes) {
        let (flag, hole) = (u32::from(depth >= 0), u32::from(depth == EMPTY));
        *class = match flag + hole {
            0 => WarpClass::Warped,
            1 => WarpClass::OtherEye,
            _ => WarpClass::Filled,
        };
        flagged += flag;
        holes += hole;
    }
    (depth.len() as u64 - u64::from(flagged), u64::from(flagged - holes))
}

/// The hole rule along one row with at least one covered pixel: each run of holes takes the
/// colour of the farther of its two covered neighbours (the left on a tie), or of the one
/// it has.
fn fill_row(keys: &[i32], out: &mut [u32]) {
    let depth = |k: usize| keys[k] & DEPTH;
    let w = keys.len();
    let mut k = 0;
    while k < w {
        // Past covered pixels 16 at a time (a comparison without an early exit runs in
        // vectors), then one at a time.
        while k + 16 <= w && keys[k..k + 16].iter().fold(0, |holes, &key| holes | u8::from(key == EMPTY)) == 0 {
            k += 16;
        }
        if k == w || keys[k] != EMPTY {
            k += 1;
            continue;
        }
        let start = k;
        while k < w && keys[k] == EMPTY {
            k += 1;
        }
        let from = match (start.checked_sub(1), (k < w).then_some(k)) {
            (Some(left), Some(right)) => {
                if depth(right) > depth(left) {
                    right
                } else {
                    left
                }
            }
            (Some(side), None) | (None, Some(side)) => side,
            (None, None) => return,
        };
        let colour = out[from];
        out[start..k].fill(colour);
    }
}
