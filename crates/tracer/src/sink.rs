//! Where every pixel producer's output goes: one [`RowSink`] per row, as pbrt-v4's
//! `Film::AddSample` takes every sample whatever the integrator made it.
//!
//! A sink is the row's columns ([`Columns`]: colour only, colour and first hits, the
//! record's keys, the whole record, or depth) and an observer ([`Observe`]) beside them.
//! Producers — the render's row loop (`render/row.rs`) and the batches of chosen pixels
//! (`batch/`) — hand it the pixels that saw only background as they find them, then the
//! shaded batch once ([`RowSink::emit`]). The observer sees that batch read-only before its
//! samples are written, as Embree's intersection filter callbacks see hits without the
//! traversal knowing who listens: temporal reuse hangs its marks column there
//! (`reuse/observer.rs`), and a producer never knows whether anyone marks.
//!
//! Every producer is generic over the sink, so each kind of row is its own monomorphised
//! loop: nothing per pixel goes through a call the compiler cannot see.

use std::ops::Range;

use crate::camera::EyeView;
use crate::surface::{Shading, NO_OBJECT};
use crate::wavefront::{Levels, Wavefront};

/// What a hit pixel's record keys are: depth, hit parameter, object, light bits.
pub(crate) type Keys = (f32, f32, u32, u32);

/// A row's output: its image columns, and an observer of the batches that fill them.
#[derive(Debug)]
pub(crate) struct RowSink<C, O> {
    /// The image's columns of the row.
    pub(crate) columns: C,
    /// Who watches the row's batches (`()`: nobody).
    pub(crate) observer: O,
}

/// One row of an image's planes, written pixel by pixel.
pub(crate) trait Columns {
    /// Whether these columns need shading: `false` for depth, which takes first hits only
    /// ([`Columns::first_hit`]).
    const SHADES: bool = true;
    /// Pixels `span` were traced and saw only background, of colour `rgb`.
    fn background(&mut self, span: Range<usize>, rgb: u32);
    /// Pixel `i` takes colour `rgb` without a ray of its own (another view saw background
    /// there). Only colour rows are made this way.
    fn take(&mut self, i: usize, rgb: u32);
    /// Pixel `i` saw a sphere: its colour, and (called only by columns that keep them) its
    /// record's keys and its shading entry.
    fn hit(&mut self, i: usize, rgb: u32, keys: impl FnOnce() -> Keys, shading: impl FnOnce() -> Shading);
    /// Pixel `i`'s first hit is sphere `object` at depth `z` ([`EyeView::head_z`]): what
    /// columns that do not shade keep instead of [`Columns::hit`].
    fn first_hit(&mut self, i: usize, z: f32, object: u32) {
        let _ = (i, z, object);
    }
}

/// What watches a row's batches: told of the pixels that saw only background, then handed
/// each shaded batch once, before its samples reach the columns.
pub(crate) trait Observe {
    /// Pixels `span` of the row were traced and their primary rays met nothing.
    fn escaped(&mut self, span: Range<usize>);
    /// A batch of the row is shaded: its samples' ray trees, read-only. `own` says whether
    /// the samples' first rays are this view's (not another view's, re-shaded here).
    fn shaded(&mut self, batch: Levels<'_>, own: bool);
}

impl Observe for () {
    #[inline]
    fn escaped(&mut self, _: Range<usize>) {}

    #[inline]
    fn shaded(&mut self, _: Levels<'_>, _: bool) {}
}

impl<O: Observe> Observe for Option<O> {
    #[inline]
    fn escaped(&mut self, span: Range<usize>) {
        if let Some(observer) = self {
            observer.escaped(span);
        }
    }

    #[inline]
    fn shaded(&mut self, batch: Levels<'_>, own: bool) {
        if let Some(observer) = self {
            observer.shaded(batch, own);
        }
    }
}

impl<C: Columns, O: Observe> RowSink<C, O> {
    /// A sink of `columns`, watched by `observer`.
    pub(crate) fn new(columns: C, observer: O) -> Self {
        Self { columns, observer }
    }

    /// Pixels `span` were traced and saw only background, of colour `rgb`.
    #[inline]
    pub(crate) fn background(&mut self, span: Range<usize>, rgb: u32) {
        self.columns.background(span.clone(), rgb);
        self.observer.escaped(span);
    }

    /// Pixel `i` takes colour `rgb` without a ray of its own: nothing to observe.
    #[inline]
    pub(crate) fn take(&mut self, i: usize, rgb: u32) {
        self.columns.take(i, rgb);
    }

    /// Hands the shaded batch of `wavefront` (of a row of `view`) to the observer, then each
    /// of its samples to the columns; `own` as in [`Observe::shaded`].
    pub(crate) fn emit(&mut self, wavefront: &Wavefront, view: &EyeView, own: bool) {
        self.observer.shaded(wavefront.levels(), own);
        for e in 0..wavefront.len() {
            let keys = || {
                let (point, t, object, lights) = wavefront.keys(e);
                (view.head_z(point), t, object, lights)
            };
            let shading = || {
                let s = wavefront.surface(e);
                Shading { point: s.point, normal: s.normal, diffuse: s.diffuse }
            };
            self.columns.hit(wavefront.tag(e) as usize, wavefront.rgb(e), keys, shading);
        }
    }
}

/// One row of colour only.
#[derive(Debug)]
pub(crate) struct RgbRow<'a>(pub(crate) &'a mut [u32]);

impl Columns for RgbRow<'_> {
    #[inline]
    fn background(&mut self, span: Range<usize>, rgb: u32) {
        self.0[span].fill(rgb);
    }

    #[inline]
    fn take(&mut self, i: usize, rgb: u32) {
        self.0[i] = rgb;
    }

    #[inline]
    fn hit(&mut self, i: usize, rgb: u32, _: impl FnOnce() -> Keys, _: impl FnOnce() -> Shading) {
        self.0[i] = rgb;
    }
}

/// One row of colour and first hits: each pixel's colour, and the depth
/// ([`EyeView::head_z`], +∞ for a miss) and sphere ([`NO_OBJECT`] for a miss) of its primary
/// ray's first hit, as a [`DepthRow`] of the same view keeps them, bit for bit: an eye's own
/// planes from the pass that shades it.
#[derive(Debug)]
pub(crate) struct HitsRow<'a> {
    pub(crate) rgb: &'a mut [u32],
    pub(crate) z: &'a mut [f32],
    pub(crate) object: &'a mut [u32],
}

impl Columns for HitsRow<'_> {
    #[inline]
    fn background(&mut self, span: Range<usize>, rgb: u32) {
        self.rgb[span.clone()].fill(rgb);
        self.z[span.clone()].fill(f32::INFINITY);
        self.object[span].fill(NO_OBJECT);
    }

    /// A pixel that takes a colour without a ray sees background: it takes the colour
    /// of a pixel of another view that saw background, where its producer's caller
    /// vouches that its own ray meets nothing either (exact mode's reprojection).
    #[inline]
    fn take(&mut self, i: usize, rgb: u32) {
        self.background(i..i + 1, rgb);
    }

    #[inline]
    fn hit(&mut self, i: usize, rgb: u32, keys: impl FnOnce() -> Keys, _: impl FnOnce() -> Shading) {
        let (z, _, object, _) = keys();
        (self.rgb[i], self.z[i], self.object[i]) = (rgb, z, object);
    }
}

/// One row of a [`crate::Film`] without its shading entries: colour, depth, hit parameter,
/// object and light bits.
#[derive(Debug)]
pub(crate) struct KeysRow<'a> {
    pub(crate) rgb: &'a mut [u32],
    pub(crate) z: &'a mut [f32],
    pub(crate) t: &'a mut [f32],
    pub(crate) object: &'a mut [u32],
    pub(crate) lights: &'a mut [u32],
}

impl KeysRow<'_> {
    /// Writes pixel `i`'s colour and keys.
    #[inline]
    fn keep(&mut self, i: usize, rgb: u32, (z, t, object, lights): Keys) {
        self.rgb[i] = rgb;
        self.z[i] = z;
        self.t[i] = t;
        self.object[i] = object;
        self.lights[i] = lights;
    }
}

impl Columns for KeysRow<'_> {
    #[inline]
    fn background(&mut self, span: Range<usize>, rgb: u32) {
        self.rgb[span.clone()].fill(rgb);
        self.z[span.clone()].fill(f32::INFINITY);
        self.object[span.clone()].fill(NO_OBJECT);
        self.lights[span].fill(0);
    }

    fn take(&mut self, i: usize, rgb: u32) {
        debug_assert!(false, "a keyed row takes no colour without a ray");
        self.background(i..i + 1, rgb);
    }

    #[inline]
    fn hit(&mut self, i: usize, rgb: u32, keys: impl FnOnce() -> Keys, _: impl FnOnce() -> Shading) {
        self.keep(i, rgb, keys());
    }
}

/// One row of a [`crate::Film`]: the keys and the shading entries.
#[derive(Debug)]
pub(crate) struct FilmRow<'a> {
    pub(crate) keys: KeysRow<'a>,
    pub(crate) shading: &'a mut [Shading],
}

impl Columns for FilmRow<'_> {
    #[inline]
    fn background(&mut self, span: Range<usize>, rgb: u32) {
        // The shading entries of a miss are left as they are: nothing reads them (see
        // `Film::surface`).
        self.keys.background(span, rgb);
    }

    fn take(&mut self, i: usize, rgb: u32) {
        self.keys.take(i, rgb);
    }

    #[inline]
    fn hit(&mut self, i: usize, rgb: u32, keys: impl FnOnce() -> Keys, shading: impl FnOnce() -> Shading) {
        self.keys.keep(i, rgb, keys());
        self.shading[i] = shading();
    }
}

/// One row of first hits only: each pixel's depth, +∞ for a miss, and, when `object` is not
/// empty, the sphere it saw ([`NO_OBJECT`] for a miss).
#[derive(Debug)]
pub(crate) struct DepthRow<'a> {
    pub(crate) z: &'a mut [f32],
    pub(crate) object: &'a mut [u32],
}

impl DepthRow<'_> {
    /// Pixel `i` saw `object` at depth `z`.
    #[inline]
    fn keep(&mut self, i: usize, z: f32, object: u32) {
        self.z[i] = z;
        if let Some(o) = self.object.get_mut(i) {
            *o = object;
        }
    }
}

impl Columns for DepthRow<'_> {
    const SHADES: bool = false;

    #[inline]
    fn background(&mut self, span: Range<usize>, _: u32) {
        if !self.object.is_empty() {
            self.object[span.clone()].fill(NO_OBJECT);
        }
        self.z[span].fill(f32::INFINITY);
    }

    fn take(&mut self, i: usize, _: u32) {
        debug_assert!(false, "a depth row takes no colour");
        self.keep(i, f32::INFINITY, NO_OBJECT);
    }

    fn hit(&mut self, i: usize, _: u32, keys: impl FnOnce() -> Keys, _: impl FnOnce() -> Shading) {
        let (z, _, object, _) = keys();
        self.keep(i, z, object);
    }

    #[inline]
    fn first_hit(&mut self, i: usize, z: f32, object: u32) {
        self.keep(i, z, object);
    }
}
