//! The warp stage of timewarp: the last traced stereo pair, moved to the newest head pose
//! by its depth, so that the display never waits for the tracer.
//!
//! The full 6-DoF, per-pixel forward warp of Mark, McMillan & Bishop ("Post-rendering 3D
//! warping", I3D 1997), as VR runtimes' timewarp does at every refresh (van Waveren, VRST
//! 2016): every traced pixel, guard band included, lands in both target eyes by its depth;
//! the own eye's pixels win, the other eye's fill its disocclusions (Adelson & Hodges'
//! reprojection, IEEE CG&A 1995). [`Warp::warp`] makes both eyes together in bands of 32
//! rows: `map.rs` (one composite map per eye pair), `scatter.rs` (landing, in SIMD lanes),
//! `resolve.rs` (winners, then the hole rule) and `crack.rs` (the crack rule), and the rows
//! at the bands' seams last. Same bytes for any thread count and lane width; a warm
//! [`Warp`] allocates nothing.
//!
//! The design (the stages, the crack and hole rules, the seams, the guarantees):
//! `docs/design/timewarp.md`; its cost: `docs/performance-notes.md`, "Timewarp's warp".

mod crack;
mod map;
mod resolve;
mod scatter;

#[cfg(test)]
mod tests;

use std::sync::{Mutex, PoisonError};

use fearless_simd::Level;
use rayon::prelude::*;
use tracer::{Eye, EyeView, Film};

use crack::{tolerance, Window, REACH};
use map::{rows_reached, EyeShift, WarpMap};
use resolve::{fill_uncovered_rows, resolve};
use scatter::{scatter, Band, Keys, KeysMut, Source, EMPTY};

/// Target rows per band: each band's keys (32 rows of 800 pixels, both eyes: 200 kB) stay
/// in the core's cache while both eyes land in them and they are resolved (16 measured
/// the same, 8 and 64 slower).
const BAND_ROWS: usize = 32;

/// One traced eye as the warp reads it.
#[derive(Clone, Copy, Debug)]
pub struct WarpSource<'a> {
    /// The view as traced, maybe with a guard band ([`tracer::Camera::view_with_margin`]).
    pub view: EyeView,
    /// Its colours, `view.width` × `view.height`, packed sRGB `0x00RRGGBB`.
    pub rgb: &'a [u32],
    /// Its head-space depths beyond the window (the film's `z`), +∞ for background.
    pub z: &'a [f32],
}

impl<'a> WarpSource<'a> {
    /// The colour and depth of `film`, traced through `view` (with a record that keeps the
    /// depth: [`tracer::Record::Keys`] or [`tracer::Record::Full`]).
    #[must_use]
    pub fn from_film(view: EyeView, film: &'a Film) -> Self {
        Self { view, rgb: &film.rgb, z: &film.z }
    }
}

/// Where a warped pixel came from.
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WarpClass {
    /// From this eye's traced frame.
    Warped,
    /// A crack in this eye's warped surface (where the new view magnifies it), filled
    /// from the surface around it by the crack rule (module doc): this eye's too.
    Crack,
    /// A hole this eye left, filled by the other eye's warped pixel.
    OtherEye,
    /// A hole neither eye covers, filled by the hole rule (module doc).
    Filled,
}

/// How many pixels of one warped eye are of each class.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WarpCounts {
    /// Pixels from this eye ([`WarpClass::Warped`]).
    pub warped: u64,
    /// Cracks in this eye's surface, filled from it ([`WarpClass::Crack`]): this eye's
    /// pixels too, not holes.
    pub crack: u64,
    /// Holes filled by the other eye ([`WarpClass::OtherEye`]).
    pub other_eye: u64,
    /// Holes filled by the hole rule ([`WarpClass::Filled`]).
    pub filled: u64,
}

impl WarpCounts {
    /// All the pixels counted: the eye's size.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.warped + self.crack + self.other_eye + self.filled
    }

    /// This eye's pixels: warped, and its cracks filled from its own surface.
    #[must_use]
    pub fn own(&self) -> u64 {
        self.warped + self.crack
    }

    /// The holes this eye left: filled from the other eye or by the hole rule.
    #[must_use]
    pub fn holes(&self) -> u64 {
        self.other_eye + self.filled
    }
}

impl std::ops::Add for WarpCounts {
    type Output = Self;

    fn add(self, other: Self) -> Self {
        Self {
            warped: self.warped + other.warped,
            crack: self.crack + other.crack,
            other_eye: self.other_eye + other.other_eye,
            filled: self.filled + other.filled,
        }
    }
}

/// The warp of a traced stereo pair to a new head pose, keeping its buffers from frame to
/// frame: a warm `Warp` allocates nothing.
#[derive(Debug, Default)]
pub struct Warp {
    /// The target rows each row of each source eye can reach, in either target eye.
    reach: [Vec<Option<(u32, u32)>>; 2],
    /// Each thread's scratch, reused band after band.
    scratch: Vec<Mutex<Scratch>>,
    /// Each band's first and last [`SEAM`] rows of keys, of each target eye (`EMPTY` past
    /// the band's rows), for the crack rule at the seams between bands.
    seams: [Vec<i32>; 2],
    /// Which rows of each target eye something reached.
    covered: [Vec<bool>; 2],
}

/// One thread's scratch.
#[derive(Debug, Default)]
struct Scratch {
    /// The visibility keys of one band of each target eye (`scatter.rs`).
    keys: [Keys; 2],
    /// A row's keys as the hole rule sees them, after the crack rule (`crack.rs`).
    row: Vec<i32>,
}

/// The rows of keys kept at each edge of a band: the rows the crack rule resolves at a seam
/// ([`REACH`] on each side), and the rows it reads beyond them.
const SEAM: usize = 2 * REACH;

impl Warp {
    /// A warp with empty buffers; the first frame sizes them.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Warps the traced stereo pair `sources` ([left, right], one frame) to `targets`
    /// ([left, right] views of one new head pose, usually without a guard band), into
    /// `out[e]` (resized to the target's size, `width` × `height`) with each pixel's class
    /// in `classes[e]`, and returns each eye's counts.
    ///
    /// # Panics
    ///
    /// If the sources or the targets are not a left and a right eye of one head pose, if a
    /// source's planes are not of its view's size, or if a target has `u32::MAX` pixels or
    /// more.
    pub fn warp(
        &mut self,
        sources: [WarpSource<'_>; 2],
        targets: [&EyeView; 2],
        out: [&mut Vec<u32>; 2],
        classes: [&mut Vec<WarpClass>; 2],
    ) -> [WarpCounts; 2] {
        self.warp_at(tracer::widest_simd_level(), &sources, targets, out, classes)
    }

    /// [`Warp::warp`] with its lane kernels at `level`.
    pub(crate) fn warp_at(
        &mut self,
        level: Level,
        sources: &[WarpSource<'_>; 2],
        targets: [&EyeView; 2],
        mut out: [&mut Vec<u32>; 2],
        mut classes: [&mut Vec<WarpClass>; 2],
    ) -> [WarpCounts; 2] {
        check(sources, targets);
        let (w, h) = (targets[0].width as usize, targets[0].height as usize);
        let Self { reach, scratch, seams, covered } = self;
        // Each source eye to each target eye, and the target rows each source row can reach
        // in either.
        let maps = [0, 1].map(|s| [0, 1].map(|t| WarpMap::new(&sources[s].view, targets[t])));
        let [left_reach, right_reach] = reach;
        rayon::join(
            || rows_reached(level, &maps[0], sources[0].z, sources[0].view.width, left_reach),
            || rows_reached(level, &maps[1], sources[1].z, sources[1].view.width, right_reach),
        );
        let shifts = [EyeShift::between(targets[0], targets[1]), EyeShift::between(targets[1], targets[0])];
        let bands = h.div_ceil(BAND_ROWS);
        for (((covered, seams), out), classes) in
            covered.iter_mut().zip(seams.iter_mut()).zip(out.iter_mut()).zip(classes.iter_mut())
        {
            covered.resize(h, false);
            seams.resize(bands * 2 * SEAM * w, EMPTY);
            out.resize(w * h, 0);
            classes.resize(w * h, WarpClass::Filled);
        }
        if w == 0 || h == 0 {
            return [WarpCounts::default(); 2];
        }
        let tolerance = tolerance(targets[0]);
        // Each thread lands in keys of its own, band after band, so that they stay in its
        // core's cache.
        if scratch.len() < rayon::current_num_threads() {
            scratch.resize_with(rayon::current_num_threads(), Default::default);
        }
        // A thread's own scratch: no other thread locks it, and which one a band or a seam
        // gets changes nothing in it.
        let scratch = &scratch[..];
        let lock = || {
            scratch[rayon::current_thread_index().unwrap_or(0) % scratch.len()]
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
        };
        let [left_covered, right_covered] = covered;
        let [left_seams, right_seams] = seams;
        let [left_out, right_out] = out;
        let [left_classes, right_classes] = classes;
        let band = BAND_ROWS * w;
        let edges = 2 * SEAM * w;
        let band_iter = (
            (left_out.par_chunks_mut(band), right_out.par_chunks_mut(band)),
            (left_classes.par_chunks_mut(band), right_classes.par_chunks_mut(band)),
            (left_covered.par_chunks_mut(BAND_ROWS), right_covered.par_chunks_mut(BAND_ROWS)),
            (left_seams.par_chunks_mut(edges), right_seams.par_chunks_mut(edges)),
        );
        let reach = &*reach;
        let counts = band_iter
            .into_par_iter()
            .enumerate()
            .map(|(b, ((left_out, right_out), (left_classes, right_classes), (left_covered, right_covered), seams))| {
                let mut scratch = lock();
                let Scratch { keys: [left, right], row } = &mut *scratch;
                left.reset(left_out.len());
                right.reset(right_out.len());
                let first = (b * BAND_ROWS) as u32;
                for s in 0..2 {
                    let source = Source {
                        rgb: sources[s].rgb,
                        z: sources[s].z,
                        width: sources[s].view.width as usize,
                        reach: &reach[s],
                        map: &maps[s][s],
                        shift: shifts[s],
                    };
                    let left = KeysMut { depth: &mut left.depth, colour: left_out };
                    let right = KeysMut { depth: &mut right.depth, colour: right_out };
                    let keys = if s == 0 { [left, right] } else { [right, left] };
                    scatter(level, source, &mut Band { first, keys });
                }
                // The rows within reach of another band wait for the seams' pass.
                let rows = left_covered.len();
                let last = if b + 1 < bands { rows - REACH } else { rows };
                let inner = if b > 0 { REACH.min(last) } else { 0 }..last;
                let (left_seams, right_seams) = seams;
                keep_edges(&left.depth, w, left_seams);
                keep_edges(&right.depth, w, right_seams);
                let left_window = &mut Window { keys: &left.depth, out: left_out, width: w };
                let right_window = &mut Window { keys: &right.depth, out: right_out, width: w };
                let (left_covered, right_covered) =
                    (&mut left_covered[inner.clone()], &mut right_covered[inner.clone()]);
                [
                    resolve(level, left_window, inner.clone(), left_classes, left_covered, tolerance, row),
                    resolve(level, right_window, inner, right_classes, right_covered, tolerance, row),
                ]
            })
            .reduce(|| [WarpCounts::default(); 2], |a, b| [a[0] + b[0], a[1] + b[1]]);
        // The rows at the seams, from the keys the bands kept, then the rows nothing
        // reached, each eye on its own.
        let finish = |out: &mut [u32], classes: &mut [WarpClass], covered: &mut [bool], seams: &[i32]| {
            let counts = resolve_seams(level, SeamRows { out, classes, covered, seams, width: w }, tolerance, &lock);
            fill_uncovered_rows(out, w, covered);
            counts
        };
        let seam_counts = rayon::join(
            || finish(left_out, left_classes, left_covered, left_seams),
            || finish(right_out, right_classes, right_covered, right_seams),
        );
        let seam_counts = [seam_counts.0, seam_counts.1];
        [counts[0] + seam_counts[0], counts[1] + seam_counts[1]]
    }
}

/// One target eye's image, classes, rows covered and its bands' kept edges
/// ([`keep_edges`]).
struct SeamRows<'a> {
    out: &'a mut [u32],
    classes: &'a mut [WarpClass],
    covered: &'a mut [bool],
    seams: &'a [i32],
    width: usize,
}

/// Resolves the rows about every seam between two bands of one target eye, in parallel
/// (the seams are [`SEAM`] rows apart or more, and each reads only the edges its bands
/// kept), with the scratch of the thread's `lock`.
fn resolve_seams<'s>(
    level: Level,
    rows: SeamRows<'_>,
    tolerance: f32,
    lock: &(impl Fn() -> std::sync::MutexGuard<'s, Scratch> + Sync),
) -> WarpCounts {
    let SeamRows { out, classes, covered, seams, width } = rows;
    let bands = covered.len().div_ceil(BAND_ROWS);
    if bands < 2 {
        return WarpCounts::default();
    }
    // Each seam's rows from the first of the band above's last SEAM rows; its covered
    // rows from the first resolved; its kept keys, the band above's last SEAM rows then
    // the band below's first.
    let (from, covered_from, band) = ((BAND_ROWS - SEAM) * width, BAND_ROWS - REACH, BAND_ROWS * width);
    (
        out[from..].par_chunks_mut(band),
        classes[from..].par_chunks_mut(band),
        covered[covered_from..].par_chunks_mut(BAND_ROWS),
        seams[SEAM * width..].par_chunks(2 * SEAM * width),
    )
        .into_par_iter()
        .take(bands - 1)
        .map(|(out, classes, covered, keys)| {
            resolve_seam(level, keys, out, classes, covered, tolerance, &mut lock().row)
        })
        .reduce(WarpCounts::default, |a, b| a + b)
}

/// Keeps the first and the last [`SEAM`] rows of a band's `keys` (rows of `width`) in
/// `edges`, [`EMPTY`] where the band has fewer rows (past the image's last row).
fn keep_edges(keys: &[i32], width: usize, edges: &mut [i32]) {
    let kept = SEAM.min(keys.len() / width) * width;
    let (head, tail) = edges.split_at_mut(SEAM * width);
    head[..kept].copy_from_slice(&keys[..kept]);
    head[kept..].fill(EMPTY);
    let pad = tail.len() - kept;
    tail[..pad].fill(EMPTY);
    tail[pad..].copy_from_slice(&keys[keys.len() - kept..]);
}

/// Resolves the rows about one seam between two bands: `keys` are the [`SEAM`] rows above
/// it and the [`SEAM`] below ([`keep_edges`]), `out` and `classes` the image's rows from
/// the first of them on (to the next seam or the image's end), `covered` its rows from the
/// first resolved. The [`REACH`] rows on each side of the seam are resolved.
fn resolve_seam(
    level: Level,
    keys: &[i32],
    out: &mut [u32],
    classes: &mut [WarpClass],
    covered: &mut [bool],
    tolerance: f32,
    row: &mut Vec<i32>,
) -> WarpCounts {
    let width = keys.len() / (2 * SEAM);
    let rows = (out.len() / width).min(2 * SEAM);
    let out = &mut out[..rows * width];
    let resolved = REACH..rows.min(SEAM + REACH);
    let covered = &mut covered[..resolved.len()];
    resolve(level, &mut Window { keys, out, width }, resolved, classes, covered, tolerance, row)
}

/// [`Warp::warp`]'s preconditions.
fn check(sources: &[WarpSource<'_>; 2], targets: [&EyeView; 2]) {
    for (pair, what) in [([&sources[0].view, &sources[1].view], "sources"), (targets, "targets")] {
        assert!(pair[0].eye == Eye::Left && pair[1].eye == Eye::Right, "the {what} must be [left, right]");
        assert!(
            pair[0].head_position() == pair[1].head_position()
                && pair[0].world_from_head() == pair[1].world_from_head(),
            "the {what} must be two eyes of one head pose"
        );
    }
    let [left, right] = targets;
    assert!(
        (left.width, left.height, left.margin, left.window_size(), left.distance())
            == (right.width, right.height, right.margin, right.window_size(), right.distance()),
        "the targets must be two eyes of one camera: of one size, guard band, window and distance"
    );
    for s in sources {
        let n = s.view.width as usize * s.view.height as usize;
        assert!(s.rgb.len() == n && s.z.len() == n, "a source's rgb and z must be its view's size ({n} pixels)");
    }
    for t in targets {
        let n = t.width as u64 * t.height as u64;
        assert!(n < u64::from(u32::MAX), "a target of {n} pixels: fewer than u32::MAX");
    }
}
