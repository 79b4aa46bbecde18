//! [`BinnedView::trace_pixels`]: chosen pixels of a row with full primary rays.

use super::{by_lanes, lanes, BinnedView};
use crate::sink::{Columns, Observe, RowSink};
use crate::stats::RayCounts;
use crate::wavefront::with_wavefront;

impl BinnedView<'_> {
    /// Traces the pixels `cols` (ascending columns) of row `j` with full primary rays into
    /// `sink`.
    pub(crate) fn trace_pixels(
        &self,
        j: u32,
        cols: impl IntoIterator<Item = u32>,
        counts: &mut RayCounts,
        sink: &mut RowSink<impl Columns, impl Observe>,
    ) {
        with_wavefront(|wavefront| {
            by_lanes(cols, lanes(), |base, mask| {
                counts.primary += u64::from(mask.count_ones());
                self.push_traced(wavefront, (base, j, mask), sink);
            });
            wavefront.shade(self.tracer, crate::cue::SeedRow::of(self.view, j), counts);
            sink.emit(wavefront, self.view, true);
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Eye;
    use crate::render::Renderer;
    use crate::scene::Scene;
    use crate::tracer::Tracer;

    fn scene(name: &str) -> Scene {
        crate::testing::scene(name)
    }

    #[test]
    fn pixel_lists_count_the_rays_a_full_trace_casts() {
        let scene = scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.9);
        let (w, h) = (61, 34);
        let view = scene.camera.view(Eye::Right, w, h);
        let mut renderer = Renderer::new();
        let batch = renderer.batch(&tracer, &view);
        let (mut listed, mut plain) = (RayCounts::default(), RayCounts::default());
        for j in 0..h {
            // Every other pixel, then the rest: scattered lists, whole quads and lone pixels.
            let mut rgb = vec![0; w as usize];
            batch.trace_pixels(j, (0..w).step_by(2), &mut listed, (&mut rgb, None));
            batch.trace_pixels(j, (1..w).step_by(2), &mut listed, (&mut rgb, None));
            for i in 0..w {
                let _ = tracer.trace_pixel(&view, i, j, &mut plain);
            }
        }
        assert_eq!(listed, plain, "primary, shadow and mirror rays");
    }
}
