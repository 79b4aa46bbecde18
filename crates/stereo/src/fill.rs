//! Stage 5: the colours of the reprojected right pixels, from what the left eye saw at
//! their sources (its visible-surface record, `tracer::Surface`), in one of two ways:
//! - reshade: reuse the left hit and recompute only the view-dependent light (highlight
//!   and reflection) for the right pixel-centre ray's direction;
//! - exact: intersect the right pixel-centre ray with the one sphere the reprojection
//!   names, and shade that hit as a full trace does, with shadow rays of its own (the left
//!   hit's light visibility is not reused: a shadow thinner than a pixel can fall between
//!   the two hits). A ray that misses the sphere is on a silhouette the edge test did not
//!   catch: the pixel is retraced and marked an edge.
//!
//! A reprojected miss keeps the left eye's background colour either way. Copy mode fills
//! its reprojected pixels in stage 4's pass (`retrace.rs`), so it has no stage 5. Exact
//! mode does stage 4 in stage 5's pass instead: each row is one batch of the tracer's
//! wavefront ([`PixelBatch::shade_row`]), its retraced pixels beside its reprojected ones,
//! so the batch fills whole vectors of lanes and the row is read once. On a fresh frame it
//! goes further and does stages 2 to 5 in one pass over bands of rows
//! ([`reproject_and_fill_exact`]): a band is reprojected and classified, then made at once,
//! while the left film's rows it reads are still in cache.
//!
//! Exact mode can keep the right eye's first-hit planes (object and head-space depth) as
//! it makes each pixel ([`HitPlanes`]): a reprojected pixel's is the hit of its own ray on
//! the sphere its source saw, a traced pixel's its trace's, and a pixel that takes the
//! background colour sees background, bit for bit a first-hits pass of the right view,
//! since exact mode's right eye is the full trace's.

use std::cell::RefCell;
use std::ops::Add;
use std::time::Instant;

use rayon::iter::Either;
use rayon::prelude::*;
use tracer::reuse::{Marks, MarksRow, Rewrite};
use tracer::{EyeView, Film, HitsColumns, PixelBatch, RayCounts, RowPlan, KEEP, NO_OBJECT, TRACE};

use crate::image::Image;
use crate::mode::Mode;
use crate::reproject::{band_then, Reprojection, BAND};
use crate::retrace::{chosen, row_of, Redo};
use crate::stats::PixelClass;

/// How stage 5 fills a reprojected pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Fill {
    /// Reuse the left hit, re-shade its view-dependent light ([`Mode::Reshade`]).
    Reshade,
    /// Intersect the named sphere and shade it afresh ([`Mode::Exact`]).
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

/// The right eye's first-hit planes, object and depth, that exact mode keeps as it makes
/// the pixels (see the module doc); `None`: not kept.
pub(crate) type HitPlanes<'a> = Option<(&'a mut [u32], &'a mut [f32])>;

/// The rows of `planes`, `w` pixels wide, or `None` for each of `rows` rows without them.
fn hit_rows(
    planes: HitPlanes<'_>,
    w: usize,
    rows: usize,
) -> impl IndexedParallelIterator<Item = Option<HitsColumns<'_>>> {
    match planes {
        Some((object, z)) => Either::Left(object.par_chunks_mut(w).zip(z.par_chunks_mut(w)).map(Some)),
        None => Either::Right(rayon::iter::repeat_n((), rows).map(|()| None)),
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
    /// Its first-hit planes, when kept (exact mode).
    hits: Option<HitsColumns<'a>>,
}

/// Stage 5 over the image: every right pixel of `redo` that `mask` marks
/// [`PixelClass::Reprojected`] is filled into `out` from its source in `src` on the `left`
/// film (rendered for the view `lv`), as `how` says, by `right`, the right eye's view.
/// For [`Fill::Reshade`], stage 4 has traced the other pixels and cleared the marks of
/// `redo`'s pixels, and this sets those of the pixels it shades; [`Fill::Exact`] does
/// stage 4's part itself (see the module doc), and writes the first-hit planes `hits` of
/// the pixels it makes, if given (only it keeps them).
pub(crate) fn fill(
    right: PixelBatch<'_>,
    (lv, left): (&EyeView, &Film),
    how: Fill,
    (mask, src): (&mut [PixelClass], &[u32]),
    (out, hits): (&mut Image, HitPlanes<'_>),
    redo: Redo<'_>,
) -> Filled {
    let (w, h) = (out.width as usize, out.height as usize);
    debug_assert!(
        mask.len() == out.rgb.len() && src.len() == out.rgb.len() && out.rgb.len() == w * h,
        "the mask, the source map and the image must have one size"
    );
    debug_assert!(
        hits.as_ref().is_none_or(|(object, z)| how == Fill::Exact && object.len() == w * h && z.len() == w * h),
        "first-hit planes of the image's size, in exact mode"
    );
    let (marks, only, mark) = redo.rows();
    out.rgb
        .par_chunks_mut(w)
        .zip(mask.par_chunks_mut(w))
        .zip(src.par_chunks(w))
        .zip(marks.zip(hit_rows(hits, w, h)))
        .enumerate()
        .map(|(j, (((rgb, mask), src), (marks, hits)))| {
            let (only, empty) = row_of(only, j);
            if empty {
                // Nothing to make in this row.
                return Filled::default();
            }
            let row = Row { j: j as u32, rgb, mask, src, only, marks: mark.then_some(marks), hits };
            match how {
                Fill::Reshade => reshade_row(right, (lv, left), row),
                Fill::Exact => exact_row(right, left, row, None),
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
fn reshade_row(right: PixelBatch<'_>, (lv, left): (&EyeView, &Film), row: Row<'_>) -> Filled {
    let Row { j, rgb, mask, src, only, mut marks, hits } = row;
    debug_assert!(hits.is_none(), "reshade mode keeps no first hits");
    let mut rays = RayCounts::default();
    with_list(|list| {
        list_row(left, (mask, src), rgb, only, list);
        right.reshade(j, (lv, left), list.iter().copied(), &mut rays, (rgb, marks.as_mut()));
    });
    Filled { rays, sphere_tests: 0 }
}

/// One row of [`Fill::Exact`], stages 4 and 5 in one batch: each reprojected pixel's own ray
/// against the sphere its source saw, shaded with shadow rays of its own (the silhouettes
/// it misses are retraced and marked edges), every other pixel of the row traced afresh. A
/// pixel whose source saw background takes its colour. `seen` holds, per column, the object
/// of the pixel's source, where the caller has it at hand (`None`: read from the film here).
/// The row's first-hit planes, if kept, are written for the pixels made.
fn exact_row(right: PixelBatch<'_>, left: &Film, row: Row<'_>, seen: Option<&[u32]>) -> Filled {
    let Row { j, rgb, mask, src, only, mut marks, hits } = row;
    if let Some(marks) = marks.as_mut() {
        marks.clear_only(only);
    }
    let mut rays = RayCounts::default();
    with_plan(|Plan { source, object, missed }| {
        let entry =
            |(&class, &source): (&PixelClass, &u32)| if class == PixelClass::Reprojected { source } else { TRACE };
        match only {
            // One plain loop the compiler vectorises.
            None => source.extend(mask.iter().zip(src).map(entry)),
            Some(bits) => {
                source.resize(rgb.len(), KEEP);
                for i in chosen(Some(bits), rgb.len()).map(|i| i as usize) {
                    source[i] = entry((&mask[i], &src[i]));
                }
            }
        }
        let plan = match seen {
            Some(object) => RowPlan { source, object },
            None => RowPlan::read(left, source, object),
        };
        debug_assert!(
            plan.source.iter().zip(plan.object).all(|(&s, &o)| s >= KEEP || left.object[s as usize] == o),
            "row {j}: the plan's objects are its sources'"
        );
        let sphere_tests = right.shade_row(j, plan, ((rgb, marks.as_mut()), hits), &mut rays, missed);
        for &i in missed.iter() {
            mask[i as usize] = PixelClass::RetracedEdge;
        }
        Filled { rays, sphere_tests }
    })
}

/// What [`reproject_and_fill_exact`] cost: stage 5's rays and tests, and the thread time
/// (seconds, summed over threads) of its reprojection and of its shading.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct FusedExact {
    pub filled: Filled,
    pub reproject_s: f64,
    pub fill_s: f64,
}

impl Add for FusedExact {
    type Output = Self;
    fn add(self, other: Self) -> Self {
        Self {
            filled: self.filled + other.filled,
            reproject_s: self.reproject_s + other.reproject_s,
            fill_s: self.fill_s + other.fill_s,
        }
    }
}

/// Stages 2 to 5 of a fresh [`Fill::Exact`] frame in one pass over bands of rows: each
/// band is reprojected and classified (`reproject.rs`: `src` and `class`, copied to `mask`)
/// and at once made, row by row, as [`fill`] makes it (`exact_row`), into `out` (and its
/// first-hit planes `hits`, if given), marking into `marks` if `mark`.
///
/// The result is [`reproject_and_classify`](crate::reproject::reproject_and_classify)
/// followed by [`fill`], byte for byte: a band's rows depend only on the left film, and a
/// row's fill only on its own row of the source map and classes. But the fill takes each
/// source's object from the keys the band's classification has just gathered, and its rows of `src` and `mask` were just written: all still in the core's
/// cache, where two passes over the image read them back from memory.
pub(crate) fn reproject_and_fill_exact(
    right: PixelBatch<'_>,
    left: &Film,
    p: Reprojection,
    (src, class, mask): (&mut [u32], &mut [PixelClass], &mut [PixelClass]),
    (out, hits): (&mut Image, HitPlanes<'_>),
    (marks, mark): (&mut Marks, bool),
) -> FusedExact {
    let (w, h) = (out.width as usize, out.height as usize);
    debug_assert!(
        [src.len(), class.len(), mask.len(), left.z.len(), w * h].iter().all(|&n| n == out.rgb.len()),
        "the planes must have the image's size"
    );
    debug_assert!(
        hits.as_ref().is_none_or(|(object, z)| object.len() == w * h && z.len() == w * h),
        "first-hit planes of the image's size"
    );
    let band_pixels = (w * BAND).max(1);
    let bands = out.rgb.len().div_ceil(band_pixels);
    out.rgb
        .par_chunks_mut(band_pixels)
        .zip(mask.par_chunks_mut(band_pixels))
        .zip(src.par_chunks_mut(band_pixels))
        .zip(class.par_chunks_mut(band_pixels))
        .zip(marks.bands_mut(Rewrite::All, BAND).zip(hit_rows(hits, band_pixels, bands)))
        .enumerate()
        .map(|(b, ((((rgb, mask), src), class), (mut marks, hits)))| {
            let t = Instant::now();
            let mut reproject_s = 0.0;
            let (mut rows, mut marks) = (rgb.chunks_mut(w).zip(mask.chunks_mut(w)), marks.rows());
            let mut hits = hits.map(|(object, z)| object.chunks_mut(w).zip(z.chunks_mut(w)));
            let mut filled = Filled::default();
            band_then(left, p, (b, h), (src, class), |k, src, class, seen| {
                if k == 0 {
                    reproject_s = t.elapsed().as_secs_f64();
                }
                // (`band_then` calls once for each of the band's rows, in order.)
                if let (Some((rgb, mask)), marks) = (rows.next(), marks.next()) {
                    mask.copy_from_slice(class);
                    let j = (b * BAND + k) as u32;
                    let hits = hits.as_mut().and_then(Iterator::next);
                    let row = Row { j, rgb, mask, src, only: None, marks: marks.filter(|_| mark), hits };
                    filled = filled + exact_row(right, left, row, Some(seen));
                }
            });
            FusedExact { filled, reproject_s, fill_s: t.elapsed().as_secs_f64() - reproject_s }
        })
        .reduce(FusedExact::default, FusedExact::add)
}

/// A row's plan for [`PixelBatch::shade_row`], its buffers, and the list of missed
/// silhouettes.
#[derive(Default)]
struct Plan {
    source: Vec<u32>,
    object: Vec<u32>,
    missed: Vec<u32>,
}

thread_local! {
    /// This thread's [`Plan`], reused from row to row.
    static PLAN: RefCell<Plan> = const {
        RefCell::new(Plan { source: Vec::new(), object: Vec::new(), missed: Vec::new() })
    };
}

/// Runs `f` with this thread's plan (its source emptied). A nested call gets its own.
fn with_plan<R>(f: impl FnOnce(&mut Plan) -> R) -> R {
    PLAN.with(|cell| match cell.try_borrow_mut() {
        Ok(mut plan) => {
            plan.source.clear();
            f(&mut plan)
        }
        Err(_) => f(&mut Plan::default()),
    })
}

#[cfg(test)]
mod tests {
    use tracer::reuse::Swept;
    use tracer::{Eye, Pixels, Record, Renderer, Target, Tracer};

    use super::*;
    use crate::mode::Options;
    use crate::reproject::reproject_and_classify;

    /// The one pass of a fresh exact frame is the two passes it replaces (stages 2 and 3
    /// over the image, then [`fill`]), byte for byte: colours, classes, sources and marks;
    /// and the first-hit planes both keep are a first-hits pass's of the right view.
    #[test]
    fn one_banded_pass_is_the_two_passes() {
        for (name, t) in [("seed.toml", 0.8), ("many.toml", 0.0), ("thousand.toml", 0.3)] {
            let scene = tracer::testing::scene(name);
            let tracer = Tracer::new(&scene, t);
            // Rows that end in a short band, and a short group of lanes.
            let (w, h) = (101, 3 * BAND as u32 + 5);
            let (lv, rv) = (scene.camera.view(Eye::Left, w, h), scene.camera.view(Eye::Right, w, h));
            let (mut left, mut left_marks, swept) = (Film::new(1, 1), Marks::default(), Swept::of(&scene));
            let target = Target::film(&mut left, Record::Keys).marking(&mut left_marks, &swept);
            Renderer::new().render(&tracer, &lv, Pixels::All, target);
            let p = Reprojection::new(&tracer, &scene.camera, &rv, Options { mode: Mode::Exact, retrace_edges: false });
            let n = (w * h) as usize;
            let (mut object, mut z) = (Vec::new(), Vec::new());
            tracer::first_hits(&mut Renderer::new(), &tracer, &rv, &mut object, &mut z);
            let bits = |z: &[f32]| z.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
            for mark in [false, true] {
                let mut renderer = Renderer::new();
                let right = renderer.batch(&tracer, &rv).marking(mark.then_some(&swept));
                let frame = || (vec![7u32; n], vec![PixelClass::Traced; n], vec![PixelClass::Traced; n]);
                let image = || Image { width: w, height: h, rgb: vec![0; n] };
                let planes = || (vec![7u32; n], vec![-1.0f32; n]);
                let ((mut object1, mut z1), (mut object2, mut z2)) = (planes(), planes());

                let ((mut src, mut class, mut mask), mut out, mut marks) = (frame(), image(), Marks::new(w, h));
                let one = reproject_and_fill_exact(
                    right,
                    &left,
                    p,
                    (&mut src, &mut class, &mut mask),
                    (&mut out, Some((&mut object1[..], &mut z1[..]))),
                    (&mut marks, mark),
                );

                let ((mut src2, mut class2, _), mut out2, mut marks2) = (frame(), image(), Marks::new(w, h));
                reproject_and_classify(&left, p, &mut src2, &mut class2);
                let mut mask2 = class2.clone();
                let redo = Redo { only: None, marks: &mut marks2, mark };
                let out2_hits = (&mut out2, Some((&mut object2[..], &mut z2[..])));
                let two = fill(right, (&lv, &left), Fill::Exact, (&mut mask2, &src2), out2_hits, redo);

                let at = format!("{name}, marking {mark}");
                assert_eq!((src, class), (src2, class2), "{at}: sources and classes");
                assert_eq!(mask, mask2, "{at}: classes after the silhouettes found");
                assert_eq!(out.rgb, out2.rgb, "{at}: colours");
                assert_eq!(marks.bits(), marks2.bits(), "{at}: marked pixels");
                assert!((0..n).all(|k| marks.touch(k) == marks2.touch(k)), "{at}: the marks' touches");
                assert_eq!((one.filled.rays, one.filled.sphere_tests), (two.rays, two.sphere_tests), "{at}: costs");
                assert!(mask.contains(&PixelClass::Reprojected) && mask.contains(&PixelClass::RetracedGap), "{at}");
                assert!(!mark || marks.bits().count() > 0 || name == "many.toml", "{at}: something marked");
                assert_eq!((&object1, bits(&z1)), (&object, bits(&z)), "{at}: the one pass's first hits");
                assert_eq!((&object2, bits(&z2)), (&object, bits(&z)), "{at}: the two passes' first hits");
            }
        }
    }
}
