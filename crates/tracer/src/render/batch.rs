//! [`PixelBatch`]: the public face of `batch/`'s producers, for a caller that makes an
//! eye's pixels in batches of its own (a second view, a reused frame's retrace). Each call
//! hands over one row of the caller's colours, and of its marks when the batch marks; the
//! row becomes a [`RowSink`] (`sink.rs`) whose marks column is temporal reuse's observer
//! (`reuse/observer.rs`), as in a render.

use crate::batch::{BinnedView, RowPlan};
use crate::camera::EyeView;
use crate::film::Film;
use crate::reuse::{with_marks, Marker, MarksColumn, MarksRow, Swept};
use crate::sink::{Columns, HitsRow, RgbRow, RowSink};
use crate::stats::RayCounts;

/// One row of an image as a batch writes it: its colours, and its marks when the batch
/// marks ([`PixelBatch::marking`]; `None`: left alone). The marks of the pixels made must
/// have been cleared first ([`MarksRow::clear_only`]).
pub type BatchRow<'r, 'a> = (&'r mut [u32], Option<&'r mut MarksRow<'a>>);

/// One row of an eye's first-hit planes, as a batch that keeps them writes them beside its
/// colours: each pixel's sphere ([`crate::NO_OBJECT`] for a miss) and head-space depth (+∞
/// for a miss), as [`crate::Target::first_hits`] gives them.
pub type HitsColumns<'r> = (&'r mut [u32], &'r mut [f32]);

/// One eye's view with its screen bins built, ready to make batches of a row's chosen
/// pixels (`batch/`), made by [`crate::Renderer::batch`].
#[derive(Clone, Copy, Debug)]
pub struct PixelBatch<'a> {
    eye: BinnedView<'a>,
    /// What the pixels made are marked against, when marking.
    marker: Option<Marker<'a>>,
}

impl<'a> PixelBatch<'a> {
    /// The batches of `eye`, whose bins are built, not marking.
    pub(crate) fn new(eye: BinnedView<'a>) -> Self {
        Self { eye, marker: None }
    }

    /// These batches, marking each pixel they make (in the marks of its [`BatchRow`]) with
    /// where its ray tree meets `swept`'s volumes; without `swept`, marking nothing.
    #[must_use]
    pub fn marking(self, swept: Option<&'a Swept>) -> Self {
        let eye = self.eye;
        Self { marker: swept.map(|swept| Marker::new(swept, eye.view, &eye.tracer.scene.lights)), ..self }
    }

    /// Runs `f` with row `j`'s sink: `row`'s colours, and its marks when marking.
    fn sink<R>(
        &self,
        j: u32,
        (rgb, marks): BatchRow<'_, '_>,
        f: impl FnOnce(&mut RowSink<RgbRow<'_>, Option<MarksColumn<'_, '_>>>) -> R,
    ) -> R {
        self.sink_of(j, RgbRow(rgb), marks, f)
    }

    /// Runs `f` with row `j`'s sink of `columns`, and its `marks` when marking.
    fn sink_of<C: Columns, R>(
        &self,
        j: u32,
        columns: C,
        marks: Option<&mut MarksRow<'_>>,
        f: impl FnOnce(&mut RowSink<C, Option<MarksColumn<'_, '_>>>) -> R,
    ) -> R {
        with_marks(marks, self.marker.as_ref(), j, |column| f(&mut RowSink::new(columns, column)))
    }

    /// Traces the pixels `cols` (ascending columns) of row `j` with full primary rays into
    /// `row`: bit-for-bit the pixels [`crate::Renderer::render`] would make.
    pub fn trace_pixels(
        &self,
        j: u32,
        cols: impl IntoIterator<Item = u32>,
        counts: &mut RayCounts,
        row: BatchRow<'_, '_>,
    ) {
        self.sink(j, row, |sink| self.eye.trace_pixels(j, cols, counts, sink));
    }

    /// Re-shades, for each `(column, source)` of row `j` (ascending columns), the surface
    /// that pixel `source` (a row-major index) of the other eye's `film`, rendered for
    /// `other`, saw, for the ray of this pixel: the other eye's hit point, normal,
    /// view-independent light and light bits (the point and normal remade from its ray and
    /// `t`, the light from its bits: bit-for-bit what it shaded), with highlights and
    /// reflection recomputed for this ray. Casts no shadow ray for the surface itself, and
    /// writes each colour into `row`. Seen along the ray that found it, a surface re-shades
    /// to bit-for-bit its own pixel. The film must keep at least [`crate::Record::Keys`],
    /// and each source must have seen a sphere.
    pub fn reshade(
        &self,
        j: u32,
        (other, film): (&EyeView, &Film),
        items: impl IntoIterator<Item = (u32, u32)>,
        counts: &mut RayCounts,
        row: BatchRow<'_, '_>,
    ) {
        self.sink(j, row, |sink| self.eye.reshade(j, (other, film), items, counts, sink));
    }

    /// Makes the pixels of row `j` as `plan` says, in one batch. Its source per column is:
    /// - the index (row-major) of a pixel of the other view's film: this pixel's own primary
    ///   ray is tested against the one sphere that pixel saw (the plan's object), and where
    ///   it hits, shaded there with shadow rays of its own; where it misses (a silhouette)
    ///   the pixel is traced afresh and its column pushed to `missed`; where that pixel saw
    ///   only background ([`crate::NO_OBJECT`]), this one is background too, and takes the
    ///   scene's background colour;
    /// - [`crate::TRACE`]: traced afresh, with a full primary ray;
    /// - [`crate::KEEP`]: left as it is.
    ///
    /// Colours go to `row`, and when marking, each pixel made is marked there (a pixel that
    /// takes a background colour carries no ray of its own and is left unmarked). With
    /// `hits`, each pixel made also has its first hit's sphere and depth written there (see
    /// [`HitsColumns`]): the hit it was shaded at, or none where it is background (a pixel
    /// that takes the background colour included). Returns the pixels tested against the
    /// sphere their plan names, alone or in their tile's search (not scene rays, so not
    /// counted in `counts`).
    ///
    /// With the sphere the pixel really sees, a pixel is bit-for-bit the full trace's: the
    /// ray, its `t`, its shadow rays and the shading are the same operations on the same
    /// values. (Light bits reused from the other view's point would not be: a shadow thinner
    /// than a pixel can fall between that point and this one, as it did on a molecule.) So
    /// are the planes `hits` keeps, a first-hits pass's, wherever the plan names the sphere
    /// each pixel sees first, and background only where the pixel's own ray meets nothing
    /// (as exact mode's plans do: its right eye is the full trace's).
    pub fn shade_row(
        &self,
        j: u32,
        plan: RowPlan<'_>,
        (row, hits): (BatchRow<'_, '_>, Option<HitsColumns<'_>>),
        counts: &mut RayCounts,
        missed: &mut Vec<u32>,
    ) -> u64 {
        debug_assert!(
            plan.source.len() == row.0.len() && plan.object.len() == row.0.len(),
            "a plan entry per pixel of the row"
        );
        let (rgb, marks) = row;
        match hits {
            None => self.sink_of(j, RgbRow(rgb), marks, |sink| self.eye.shade_row(j, plan, sink, counts, missed)),
            Some((object, z)) => {
                debug_assert!(object.len() == rgb.len() && z.len() == rgb.len(), "planes of the row's width");
                let columns = HitsRow { rgb, z, object };
                self.sink_of(j, columns, marks, |sink| self.eye.shade_row(j, plan, sink, counts, missed))
            }
        }
    }
}
