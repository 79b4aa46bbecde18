//! Stages 2 and 3 over the whole right image: where every left pixel lands (Adelson &
//! Hodges 1993, the seed paper's Algorithm 1, one scanline at a time in
//! `reproject/scanline.rs`) and which right pixels must still be retraced
//! (`classify.rs`).
//!
//! [`Reprojection::new`] decides, from the scene, the camera and the mode, how the frame is
//! reprojected: the eyes' disparity in pixels, the width of the right border strip that is
//! retraced whatever lands there, and whether object edges are retraced.
//! [`reproject_and_classify`] then makes the source map and the class of every right pixel
//! in one pass over the left film's planes.

mod scanline;

#[cfg(test)]
mod equivalence;

use fearless_simd::{dispatch, Simd};
use rayon::prelude::*;
use tracer::{Camera, Disparity, EyeView, Film, Tracer};

use crate::classify::{classify_row, Edges, KeyRows, GAP_OBJECT};
use crate::mode::Options;
use crate::stats::PixelClass;
pub use scanline::{reproject_row, NO_SOURCE};
use scanline::{reproject_row_keyed, KeyedRow};

/// How one frame is reprojected and classified (see [`reproject_and_classify`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Reprojection {
    /// The eyes' disparity in pixels.
    pub disparity: Disparity,
    /// Width of the right border strip that is always retraced.
    pub strip: usize,
    /// Which neighbours make a pixel an edge (a pixel next to a gap is one too), retraced.
    pub edges: Edges,
}

impl Reprojection {
    /// How the right eye of view `rv` is reprojected from the left, for `tracer`'s scene
    /// seen by `camera`, with the options of the frame.
    pub fn new(tracer: &Tracer, camera: &Camera, rv: &EyeView, opts: Options) -> Self {
        let disparity = Disparity::in_pixels(camera, rv);
        let strip = right_border_strip(tracer, camera, disparity, rv.width as usize);
        // With IPD 0 every left pixel lands exactly on its own centre: the reprojection is
        // exact and no edge needs a second look.
        let edges = if disparity.scale == 0.0 { Edges::Off } else { opts.edges() };
        Self { disparity, strip, edges }
    }
}

/// Width in pixels of the strip at the right edge of the right image that must be retraced
/// whatever lands there.
///
/// A point in front of the window (z < 0) shifts left by e·z/(d+z), so near things the
/// left eye sees just past its right edge appear inside the right image, where the
/// reprojection can only have put the farther surfaces the left eye did see. The strip is
/// as wide as the largest such shift, from the nearest sphere point in the scene; a sphere
/// reaching the eyes' plane makes it the whole row.
fn right_border_strip(tracer: &Tracer, camera: &Camera, disparity: Disparity, w: usize) -> usize {
    let forward = camera.world_from_head() * glam::Vec3::Z;
    let Some(nearest) = tracer.nearest_depth(camera.position, forward) else { return 0 };
    if nearest <= 0.0 {
        return w;
    }
    let z = nearest - camera.distance;
    if z >= 0.0 {
        return 0;
    }
    let shift = -disparity.at(z);
    if shift <= 0.0 {
        return 0;
    }
    // One pixel of margin for where the left eye's last pixel centre lands.
    (shift.ceil() as usize + 1).min(w)
}

/// Rows per band of the reprojection pass: each band reprojects two halo rows, but the
/// band's keys stay in the core's L2 cache (16 measured faster than 8 or 32 at 1280×720).
pub(crate) const BAND: usize = 16;

/// Per-thread scratch of the reprojection pass, kept across frames: rayon's
/// `for_each_init` would allocate afresh for every split of the work, every frame.
struct BandScratch {
    /// Targets of the row being reprojected.
    targets: Vec<i32>,
    /// Object key plane of a band and its halo rows.
    object: Vec<u32>,
    /// Source map of a halo row; a band's own rows are written straight into the output.
    halo_src: Vec<u32>,
}

thread_local! {
    /// This thread's [`BandScratch`].
    static BAND_SCRATCH: std::cell::RefCell<BandScratch> = const {
        std::cell::RefCell::new(BandScratch {
            targets: Vec::new(),
            object: Vec::new(),
            halo_src: Vec::new(),
        })
    };
}

/// Stages 2 and 3 over the whole image: the source map `src` and the class `mask` of every
/// right pixel, from the left film's `z` and `object` planes.
///
/// The rows go in bands, each reprojected with one halo row above and below into per-thread
/// scratch and classified at once while its keys are in cache: one pass over the left planes
/// instead of a reprojection pass and a classification pass. A band's own source rows go
/// straight into `src`; of a halo row only the keys are kept. The bands are independent, so
/// the result does not depend on the number of threads.
pub(crate) fn reproject_and_classify(left: &Film, p: Reprojection, src: &mut [u32], mask: &mut [PixelClass]) {
    let w = left.width() as usize;
    debug_assert!(
        src.len() == left.z.len() && mask.len() == left.z.len(),
        "the source map and the mask must have the left film's size"
    );
    let h = src.len() / w;
    let bands = src.par_chunks_mut(w * BAND).zip(mask.par_chunks_mut(w * BAND));
    bands.enumerate().for_each(|(b, (src_band, mask_band))| band(left, p, (b, h), src_band, mask_band));
}

/// [`reproject_and_classify`] of only the rows that can have changed. Right row j's sources
/// and classes are a function of the plan and of left rows j − 1, j and j + 1 (the rows
/// its band reads, which `band` reads with the same halo whichever bands run). So with the
/// same plan as the last frame, a band needs redoing only if a row it reads had a pixel
/// retraced (`left_rows`, a flag per left row). A redone band first saves its rows' last
/// sources and classes into `was` (for the caller to compare) and is flagged in `redone`
/// (a flag per right row); the others keep theirs. Returns the rows redone.
pub(crate) fn reproject_and_classify_rows(
    left: &Film,
    p: Reprojection,
    (src, mask): (&mut [u32], &mut [PixelClass]),
    left_rows: &[bool],
    (src_was, mask_was, redone): (&mut [u32], &mut [PixelClass], &mut [bool]),
) -> usize {
    let w = left.width() as usize;
    debug_assert!(
        src.len() == left.z.len()
            && mask.len() == left.z.len()
            && src_was.len() == src.len()
            && mask_was.len() == src.len(),
        "the source maps and the masks must have the left film's size"
    );
    let h = src.len() / w;
    let bands = (
        (src.par_chunks_mut(w * BAND), mask.par_chunks_mut(w * BAND)),
        (src_was.par_chunks_mut(w * BAND), mask_was.par_chunks_mut(w * BAND)),
        redone.par_chunks_mut(BAND),
    );
    bands
        .into_par_iter()
        .enumerate()
        .map(|(b, ((src_band, mask_band), (src_was, mask_was), redone))| {
            let j0 = b * BAND;
            let reads = j0.saturating_sub(1)..(j0 + redone.len() + 1).min(h);
            let again = left_rows[reads].iter().any(|&r| r);
            redone.fill(again);
            if !again {
                return 0;
            }
            src_was.copy_from_slice(src_band);
            mask_was.copy_from_slice(mask_band);
            band(left, p, (b, h), src_band, mask_band);
            redone.len()
        })
        .sum()
}

/// Stages 2 and 3 of band `b` of an image `h` rows high: its rows' sources and classes.
fn band(left: &Film, p: Reprojection, (b, h): (usize, usize), src_band: &mut [u32], mask_band: &mut [PixelClass]) {
    band_then(left, p, (b, h), (src_band, mask_band), |_, _, _, _| {});
}

/// [`band`], then `row(r, sources, classes, objects)` for each row r of the band in turn:
/// its sources, its classes, and the object of the left pixel each source names (what the
/// classification read; anything where there is no source), while they are in cache.
pub(crate) fn band_then(
    left: &Film,
    p: Reprojection,
    (b, h): (usize, usize),
    (src_band, mask_band): (&mut [u32], &mut [PixelClass]),
    mut row: impl FnMut(usize, &[u32], &[PixelClass], &[u32]),
) {
    let w = left.width() as usize;
    BAND_SCRATCH.with_borrow_mut(|scratch| {
        let BandScratch { targets, object, halo_src } = scratch;
        let (j0, rows) = (b * BAND, src_band.len() / w);
        let (lo, hi) = (j0.saturating_sub(1), (j0 + rows + 1).min(h));
        object.resize((hi - lo) * w, GAP_OBJECT);
        halo_src.resize(w, NO_SOURCE);
        // One dispatch for the band's rows: the scanline kernels run inside it.
        dispatch!(tracer::simd_level(), simd => simd.vectorize(|| {
            for (j, object) in (lo..hi).zip(object.chunks_exact_mut(w)) {
                let src = if (j0..j0 + rows).contains(&j) {
                    &mut src_band[(j - j0) * w..(j - j0 + 1) * w]
                } else {
                    &mut halo_src[..]
                };
                let left_row = j * w..(j + 1) * w;
                let row = KeyedRow {
                    left_object: &left.object[left_row.clone()],
                    src: &mut *src,
                    object: &mut *object,
                };
                reproject_row_keyed(simd, &left.z[left_row], p.disparity, (j * w) as u32, row, targets);
                src[w - p.strip..].fill(NO_SOURCE);
                object[w - p.strip..].fill(GAP_OBJECT);
            }
        }));
        let last = hi - lo - 1;
        for (r, out) in mask_band.chunks_mut(w).enumerate() {
            // This row's index in the scratch, and its neighbours' (itself at the edges).
            let k = j0 - lo + r;
            let at = [k.saturating_sub(1), k, (k + 1).min(last)].map(|k| k * w..(k + 1) * w);
            let src = &src_band[r * w..(r + 1) * w];
            let beyond = [key_beyond(left, src[0], -1), key_beyond(left, src[w - 1], 1)];
            let rows = KeyRows { object: at.map(|r| &object[r]), beyond };
            classify_row(rows, p.edges, out);
        }
        for (r, (src, class)) in src_band.chunks(w).zip(mask_band.chunks(w)).enumerate() {
            row(r, src, class, &object[(j0 - lo + r) * w..(j0 - lo + r + 1) * w]);
        }
    });
}

/// The key (object) of the right pixel beyond a row's end next to an end pixel
/// whose source is `s`: that source's neighbour on the border's side in the left row
/// (`step` −1 before the first pixel, +1 after the last), or a gap if it has none or there
/// is no source (`classify.rs` has why).
fn key_beyond(left: &Film, s: u32, step: isize) -> u32 {
    let w = left.width() as usize;
    if s == NO_SOURCE {
        return GAP_OBJECT;
    }
    let (s, column) = (s as usize, s as usize % w);
    match column.checked_add_signed(step) {
        Some(c) if c < w => left.object[s - column + c],
        _ => GAP_OBJECT,
    }
}
