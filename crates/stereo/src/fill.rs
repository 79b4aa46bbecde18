//! Stage 5: the colours of the reprojected right pixels, from what the left eye saw at
//! their sources (its visible-surface record, `tracer::Surface`), in one of two ways:
//! - reshade: reuse the left hit and recompute only the view-dependent light (highlight
//!   and reflection) for the right pixel-centre ray's direction;
//! - exact: intersect the right pixel-centre ray with the one sphere the reprojection
//!   names, and shade that hit with the left hit's light visibility. A ray that misses the
//!   sphere is on a silhouette the edge test did not catch: the pixel is retraced and
//!   marked an edge.
//!
//! A reprojected miss keeps the left eye's background colour either way. Copy mode fills
//! its reprojected pixels in stage 4's pass (`retrace.rs`), so it has no stage 5. Exact
//! mode does stage 4 in stage 5's pass instead: each row is one batch of the tracer's
//! wavefront ([`SecondView::shade_row`]), its retraced pixels beside its reprojected ones,
//! so the batch fills whole vectors of lanes and the row is read once.

use std::cell::RefCell;
use std::ops::Add;

use rayon::prelude::*;
use tracer::{EyeView, Film, MarksRow, RayCounts, SecondView, KEEP, NO_OBJECT, TRACE};

use crate::image::Image;
use crate::mode::Mode;
use crate::retrace::{chosen, row_of, Redo};
use crate::stats::PixelClass;

/// How stage 5 fills a reprojected pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Fill {
    /// Reuse the left hit, re-shade its view-dependent light ([`Mode::Reshade`]).
    Reshade,
    /// Intersect the named sphere, shade with the reused visibility ([`Mode::Exact`]).
    Exact,
}

impl Fill {
    /// Stage 5 of `mode`, if it has one.
    pub fn of(mode: Mode) -> Option<Self> {
        match mode {
            Mode::Full | Mode::Copy => None,
            Mode::Reshade => Some(Self::Reshade),
            Mode::Exact => Some(Self::Exact),
        }
    }
}

/// What stage 5 cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Filled {
    /// Scene rays cast (shading, and the retraced silhouettes' primary rays).
    pub rays: RayCounts,
    /// Single-sphere tests of exact mode (not scene rays).
    pub sphere_tests: u64,
}

impl Add for Filled {
    type Output = Self;
    fn add(self, other: Self) -> Self {
        Self { rays: self.rays + other.rays, sphere_tests: self.sphere_tests + other.sphere_tests }
    }
}

/// One right row as stage 5 reads and writes it.
struct Row<'a> {
    /// The row's index.
    j: u32,
    /// Its colours.
    rgb: &'a mut [u32],
    /// Its classes; exact mode marks the silhouettes it retraces.
    mask: &'a mut [PixelClass],
    /// Its source map.
    src: &'a [u32],
    /// The pixels to make (`None`: all).
    only: Option<&'a [u64]>,
    /// Its marks, when the frame marks: where a pixel's own ray trees meet the moving
    /// spheres' swept volumes.
    marks: Option<MarksRow<'a>>,
}

/// Stage 5 over the image: every right pixel of `redo` that `mask` marks
/// [`PixelClass::Reprojected`] is filled into `out` from its source in `src` on the `left`
/// film (rendered for the view `lv`), as `how` says, by `right`, the right eye's view.
/// For [`Fill::Reshade`], stage 4 has traced the other pixels and cleared the marks of
/// `redo`'s pixels, and this sets those of the pixels it shades; [`Fill::Exact`] does
/// stage 4's part itself (see the module doc).
pub(crate) fn fill(
    right: SecondView<'_>,
    (lv, left): (&EyeView, &Film),
    how: Fill,
    (mask, src): (&mut [PixelClass], &[u32]),
    out: &mut Image,
    redo: Redo<'_>,
) -> Filled {
    let w = out.width as usize;
    debug_assert!(
        mask.len() == out.rgb.len() && src.len() == out.rgb.len() && out.rgb.len() == w * out.height as usize,
        "the mask, the source map and the image must have one size"
    );
    let (marks, only, mark) = redo.rows();
    out.rgb
        .par_chunks_mut(w)
        .zip(mask.par_chunks_mut(w))
        .zip(src.par_chunks(w))
        .zip(marks)
        .enumerate()
        .map(|(j, (((rgb, mask), src), marks))| {
            let (only, empty) = row_of(only, j);
            if empty {
                // Nothing to make in this row.
                return Filled::default();
            }
            let row = Row { j: j as u32, rgb, mask, src, only, marks: mark.then_some(marks) };
            match how {
                Fill::Reshade => reshade_row(right, (lv, left), row),
                Fill::Exact => exact_row(right, left, row),
            }
        })
        .reduce(Filled::default, Filled::add)
}

thread_local! {
    /// This thread's list of a row's pixels to shade, reused from row to row (a warm frame
    /// allocates nothing).
    static LIST: RefCell<Vec<(u32, u32)>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with this thread's list, emptied. A nested call gets a list of its own.
fn with_list<R>(f: impl FnOnce(&mut Vec<(u32, u32)>) -> R) -> R {
    LIST.with(|cell| match cell.try_borrow_mut() {
        Ok(mut list) => {
            list.clear();
            f(&mut list)
        }
        Err(_) => f(&mut Vec::new()),
    })
}

/// Lists the pixels of a row that reshade mode's stage 5 shades: `(i, source)` for each
/// chosen column `i` whose pixel is reprojected and whose source on the `left` film saw a
/// surface. A reprojected pixel whose source saw background takes that colour into `rgb`
/// instead.
///
/// One plain loop over the row, before any shading: built lazily inside the shading's
/// loop, the list cost a call and its reloads per pixel (~8 % of an exact frame, measured).
fn list_row(
    left: &Film,
    (mask, src): (&[PixelClass], &[u32]),
    rgb: &mut [u32],
    only: Option<&[u64]>,
    list: &mut Vec<(u32, u32)>,
) {
    for i in chosen(only, rgb.len()) {
        let k = i as usize;
        if mask[k] != PixelClass::Reprojected {
            continue;
        }
        let s = src[k] as usize;
        if left.object[s] == NO_OBJECT {
            rgb[k] = left.rgb[s];
        } else {
            list.push((i, s as u32));
        }
    }
}

/// One row of [`Fill::Reshade`]: the surfaces seen, re-shaded as one list.
fn reshade_row(right: SecondView<'_>, (lv, left): (&EyeView, &Film), row: Row<'_>) -> Filled {
    let Row { j, rgb, mask, src, only, mut marks } = row;
    let mut rays = RayCounts::default();
    with_list(|list| {
        list_row(left, (mask, src), rgb, only, list);
        right.reshade(j, (lv, left), list.iter().copied(), &mut rays, |i, c, touch| {
            rgb[i as usize] = c;
            if let Some(marks) = marks.as_mut() {
                marks.set(i, touch);
            }
        });
    });
    Filled { rays, sphere_tests: 0 }
}

/// One row of [`Fill::Exact`], stages 4 and 5 in one batch: each reprojected pixel's own ray
/// against the sphere its source saw (the silhouettes it misses are retraced and marked
/// edges), every other pixel of the row traced afresh. A pixel whose source saw background
/// takes its colour.
fn exact_row(right: SecondView<'_>, left: &Film, row: Row<'_>) -> Filled {
    let Row { j, rgb, mask, src, only, mut marks } = row;
    if let Some(marks) = marks.as_mut() {
        marks.clear_only(only);
    }
    let mut rays = RayCounts::default();
    with_plan(|plan, missed| {
        let entry =
            |(&class, &source): (&PixelClass, &u32)| if class == PixelClass::Reprojected { source } else { TRACE };
        match only {
            // One plain loop the compiler vectorises.
            None => plan.extend(mask.iter().zip(src).map(entry)),
            Some(bits) => {
                plan.resize(rgb.len(), KEEP);
                for i in chosen(Some(bits), rgb.len()).map(|i| i as usize) {
                    plan[i] = entry((&mask[i], &src[i]));
                }
            }
        }
        let sphere_tests = right.shade_row(j, (left, plan), (rgb, marks.as_mut()), &mut rays, missed);
        for &i in missed.iter() {
            mask[i as usize] = PixelClass::RetracedEdge;
        }
        Filled { rays, sphere_tests }
    })
}

thread_local! {
    /// This thread's plan of a row ([`SecondView::shade_row`]) and its list of missed
    /// silhouettes, reused from row to row.
    static PLAN: RefCell<(Vec<u32>, Vec<u32>)> = const { RefCell::new((Vec::new(), Vec::new())) };
}

/// Runs `f` with this thread's plan (emptied) and list. A nested call gets its own.
fn with_plan<R>(f: impl FnOnce(&mut Vec<u32>, &mut Vec<u32>) -> R) -> R {
    PLAN.with(|cell| match cell.try_borrow_mut() {
        Ok(mut buffers) => {
            let (plan, missed) = &mut *buffers;
            plan.clear();
            f(plan, missed)
        }
        Err(_) => f(&mut Vec::new(), &mut Vec::new()),
    })
}
