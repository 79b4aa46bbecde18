//! From a target's keys to its image: each pixel's winner, and the hole rule for the pixels
//! neither eye reached.
//!
//! A key names its source pixel (and eye, bit 31): the pixel takes that pixel's colour and
//! is [`WarpClass::Warped`] or [`WarpClass::OtherEye`]. The rest are
//! [`WarpClass::Filled`], by the rule of the module doc (`warp/mod.rs`): along the row, each
//! run of holes takes the colour of the farther of the covered pixels on its left and on
//! its right (the larger target depth: the background side of a disocclusion, which is what
//! the occluder uncovered; the left one on a tie), or of the one that exists; a row without
//! a covered pixel copies the nearest covered row above, else the nearest below; a frame
//! with none is black. The rule reads only the target's keys and its own output, so it is
//! as deterministic as they are.

use super::scatter::{EMPTY, INDEX, OTHER};
use super::{WarpClass, WarpCounts};

/// The colours of the two source eyes, as the keys index them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Colours<'a> {
    /// The target's own eye.
    pub own: &'a [u32],
    /// The other eye (keys with [`OTHER`] set).
    pub other: &'a [u32],
}

/// Resolves the target's `keys` (rows of `width` pixels) into `out` and `classes` (both of
/// the keys' length) and counts the classes.
pub(crate) fn resolve(
    keys: &[u64],
    width: usize,
    colours: Colours<'_>,
    out: &mut [u32],
    classes: &mut [WarpClass],
) -> WarpCounts {
    debug_assert!(out.len() == keys.len() && classes.len() == keys.len(), "out and classes of the keys' size");
    let mut counts = WarpCounts::default();
    if width == 0 {
        return counts;
    }
    // The last row with a covered pixel, already filled.
    let mut last_covered: Option<usize> = None;
    for j in 0..keys.len() / width {
        let row = j * width..(j + 1) * width;
        let (warped, other) =
            resolve_row(&keys[row.clone()], colours, &mut out[row.clone()], &mut classes[row.clone()]);
        counts.warped += warped;
        counts.other_eye += other;
        if warped + other == 0 {
            // A row nothing reached copies the nearest covered row above; the rows above
            // the first covered one wait for it (below). In a frame nothing reached, every
            // pixel stays black.
            if let Some(above) = last_covered {
                out.copy_within(above * width..(above + 1) * width, row.start);
            }
            continue;
        }
        if warped + other < width as u64 {
            fill_row(&keys[row.clone()], &mut out[row.clone()]);
        }
        if last_covered.is_none() {
            for above in 0..j {
                out.copy_within(row.clone(), above * width);
            }
        }
        last_covered = Some(j);
    }
    counts.filled = keys.len() as u64 - counts.warped - counts.other_eye;
    counts
}

/// Each pixel of a row its winner's colour and class; holes `Filled`, their colour left for
/// [`fill_row`]. Returns how many pixels came from the own eye and from the other.
fn resolve_row(keys: &[u64], colours: Colours<'_>, out: &mut [u32], classes: &mut [WarpClass]) -> (u64, u64) {
    let (mut warped, mut other) = (0, 0);
    for ((&key, out), class) in keys.iter().zip(out).zip(classes) {
        let source = (key & INDEX) as usize;
        (*out, *class) = if key == EMPTY {
            (0, WarpClass::Filled)
        } else if key & OTHER == 0 {
            warped += 1;
            (colours.own[source], WarpClass::Warped)
        } else {
            other += 1;
            (colours.other[source], WarpClass::OtherEye)
        };
    }
    (warped, other)
}

/// The hole rule along one row with at least one covered pixel: each run of holes takes the
/// colour of the farther of its two covered neighbours (the left on a tie), or of the one
/// it has.
fn fill_row(keys: &[u64], out: &mut [u32]) {
    let depth = |k: usize| keys[k] >> 32;
    let w = keys.len();
    let mut k = 0;
    while k < w {
        if keys[k] != EMPTY {
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
