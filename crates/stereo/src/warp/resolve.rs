//! From a target's keys to its image: each pixel's winner, the crack rule, and the hole
//! rule for the pixels left.
//!
//! A pixel's key (`scatter.rs`) left the winner's colour in the image and says whose it
//! is: [`WarpClass::Warped`] or [`WarpClass::OtherEye`]. In a row with pixels of both kinds,
//! the crack rule (`crack.rs`) makes [`WarpClass::Crack`]s of the own eye's surface. The rest
//! are [`WarpClass::Filled`], by the hole rule (`docs/design/timewarp.md`): along the row,
//! each run of holes takes the colour of the farther of the covered pixels on its left and
//! on its right (the larger target depth: the background side of a disocclusion, which is
//! what the occluder uncovered; the left one on a tie), or of the one that exists; a row
//! without a covered pixel copies the nearest covered row above, else the nearest below; a
//! frame with none is black. The rules read only the target's keys and its own output, so
//! they are as deterministic as they are. Rows are resolved in windows of consecutive rows
//! (a band, or the rows about a seam between two bands), each row on its own; the rows
//! nothing reached are copied after, in one pass over the image.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use std::ops::Range;

use fearless_simd::{dispatch, Level, Simd};

use super::crack::{next_hole, next_own, Window};
use super::scatter::{DEPTH, EMPTY};
use super::{WarpClass, WarpCounts};

/// Resolves the rows `rows` of `window` into the window's image and into `classes` (the
/// window's classes), filling holes along rows with a covered pixel, and notes in `covered`
/// (the resolved rows') which rows have one; [`fill_uncovered_rows`] does the rest once every
/// row is resolved. `scratch` holds a row's keys as the hole rule sees them.
pub(crate) fn resolve(
    level: Level,
    window: &mut Window<'_>,
    rows: Range<usize>,
    classes: &mut [WarpClass],
    covered: &mut [bool],
    tolerance: f32,
    scratch: &mut Vec<i32>,
) -> WarpCounts {
    // Compiled for the SIMD level's instruction set, where the rows' loops run in its
    // vectors.
    dispatch!(level, simd => simd.vectorize(
        #[inline(always)]
        || resolve_rows(window, rows, classes, covered, tolerance, scratch),
    ))
}

/// [`resolve`]'s work.
#[inline(always)]
fn resolve_rows(
    window: &mut Window<'_>,
    rows: Range<usize>,
    classes: &mut [WarpClass],
    covered: &mut [bool],
    tolerance: f32,
    scratch: &mut Vec<i32>,
) -> WarpCounts {
    let mut counts = WarpCounts::default();
    let width = window.width;
    if width == 0 {
        return counts;
    }
    let n = (rows.len() * width) as u64;
    let all_keys = window.keys;
    for (r, covered) in rows.zip(covered) {
        let at = r * width..(r + 1) * width;
        let classes = &mut classes[at.clone()];
        let keys = &all_keys[at.clone()];
        let (warped, mut other) = resolve_row(keys, classes);
        let mut cracks = 0;
        // Each run of pixels the own eye did not reach: its cracks, then its holes.
        let mut start = if warped < width as u64 { next_hole(keys, 0) } else { width };
        while start < width {
            let end = next_own(keys, start);
            let (from, found, over_other) = window.cracks(r, start..end, tolerance, classes, scratch);
            (cracks, other) = (cracks + found, other - over_other);
            fill_run(scratch, &mut window.out[r * width + from..][..scratch.len()]);
            start = next_hole(keys, end);
        }
        counts.warped += warped;
        counts.other_eye += other;
        counts.crack += cracks;
        *covered = warped + other + cracks > 0;
        if !*covered {
            // Black, until `fill_uncovered_rows`.
            window.out[at].fill(0);
        }
    }
    counts.filled = n - counts.warped - counts.other_eye - counts.crack;
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
/// place, or, for a hole, left for [`fill_run`]). Returns how many pixels came from the own
/// eye and from the other. Branch-free, so that it runs in vectors.
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

/// The hole rule along a stretch of a row (`keys` and `out`): a run of pixels the own eye
/// did not reach, with the own eye's pixel on each side where the row has one. Each run of
/// holes in it takes the colour of the farther of its two covered neighbours (the left on a
/// tie), or of the one it has; a stretch with none (a row nothing reached) is left as it is.
fn fill_run(keys: &[i32], out: &mut [u32]) {
    let depth = |k: usize| keys[k] & DEPTH;
    let w = keys.len();
    let mut k = 0;
    while k < w {
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
