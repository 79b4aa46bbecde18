//! [`BinnedView::reshade`]: surfaces another view saw, re-lit for this view's pixels.

use super::BinnedView;
use crate::camera::EyeView;
use crate::film::Film;
use crate::sink::{Columns, Observe, RowSink};
use crate::stats::RayCounts;
use crate::surface::Hit;
use crate::wavefront::with_wavefront;

impl BinnedView<'_> {
    /// Re-shades, for each `(column, source)` of row `j` (ascending columns), the surface
    /// that pixel `source` (a row-major index) of the other eye's `film`, rendered for
    /// `other`, saw, for the ray of this pixel, into `sink` (see
    /// [`crate::PixelBatch::reshade`]). The samples' first rays are the other view's.
    pub(crate) fn reshade(
        &self,
        j: u32,
        (other, film): (&EyeView, &Film),
        items: impl IntoIterator<Item = (u32, u32)>,
        counts: &mut RayCounts,
        sink: &mut RowSink<impl Columns, impl Observe>,
    ) {
        debug_assert_ne!(film.record(), crate::Record::Colour, "re-shading needs the other eye's record");
        let (view, w) = (self.view, film.width());
        let row = j * w..(j + 1) * w;
        with_wavefront(|wavefront| {
            for (i, s) in items {
                let k = s as usize;
                // A source is on this row unless the views are not a stereo pair's.
                let source = if row.contains(&s) { (s - row.start, j) } else { (s % w, s / w) };
                let hit = Hit { t: film.t[k], object: film.object[k] };
                wavefront.push_seen_at(i, source, hit, film.lights[k]);
            }
            wavefront.aim_seen(view, j, other);
            // The sources are `other`'s pixels: seeded in its shown image.
            wavefront.shade(self.tracer, crate::cue::SeedRow::of(other, j), counts);
            sink.emit(wavefront, view, false);
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Eye;
    use crate::film::Record;
    use crate::render::{Pixels, Renderer, Target};
    use crate::scene::Scene;
    use crate::surface::NO_OBJECT;
    use crate::tracer::Tracer;

    /// A colour no shaded pixel has: its high byte is set.
    const UNTOUCHED: u32 = 0xFF00_FF00;

    fn scene(name: &str) -> Scene {
        crate::testing::scene(name)
    }

    #[test]
    fn a_surface_reshaded_along_its_own_ray_is_its_pixel() {
        let scene = scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.3);
        let (w, h) = (64, 36);
        let view = scene.camera.view(Eye::Left, w, h);
        let mut film = Film::new(1, 1);
        Renderer::new().render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Keys));
        let mut renderer = Renderer::new();
        let batch = renderer.batch(&tracer, &view);
        let (mut counts, mut reshaded) = (RayCounts::default(), 0);
        for j in 0..h {
            let hit = |&i: &u32| film.object[(j * w + i) as usize] != NO_OBJECT;
            let mut rgb = vec![UNTOUCHED; w as usize];
            batch.reshade(j, (&view, &film), (0..w).filter(hit).map(|i| (i, j * w + i)), &mut counts, (&mut rgb, None));
            for i in 0..w {
                let want = if hit(&i) { film.rgb[(j * w + i) as usize] } else { UNTOUCHED };
                assert_eq!(rgb[i as usize], want, "({i}, {j})");
                reshaded += usize::from(hit(&i));
            }
        }
        assert!(reshaded > 100, "the view sees spheres: {reshaded}");
    }

    #[test]
    fn a_surface_reshaded_for_the_other_eye_is_the_plain_paths() {
        // Right pixel i of row j re-shades left pixel i + 5 of row j (a source on its own
        // row, the stereo pair's case) or, every seventh pixel, of row j + 1 (any other).
        let scene = scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.3);
        let (w, h) = (64, 36);
        let (lv, rv) = (scene.camera.view(Eye::Left, w, h), scene.camera.view(Eye::Right, w, h));
        let mut film = Film::new(1, 1);
        Renderer::new().render(&tracer, &lv, Pixels::All, Target::film(&mut film, Record::Keys));
        let mut renderer = Renderer::new();
        let batch = renderer.batch(&tracer, &rv);
        let (mut counts, mut reshaded) = (RayCounts::default(), [0; 2]);
        let source = |i: u32, j: u32| if i % 7 == 3 { ((i + 5) % w, (j + 1) % h) } else { ((i + 5) % w, j) };
        for j in 0..h {
            let hit = |i: u32| {
                let (si, sj) = source(i, j);
                film.object[(sj * w + si) as usize] != NO_OBJECT
            };
            let items = (0..w).filter(|&i| hit(i)).map(|i| (i, source(i, j))).map(|(i, (si, sj))| (i, sj * w + si));
            let mut rgb = vec![UNTOUCHED; w as usize];
            batch.reshade(j, (&lv, &film), items, &mut counts, (&mut rgb, None));
            for i in 0..w {
                let (si, sj) = source(i, j);
                let k = (sj * w + si) as usize;
                let keys = (film.t[k], film.object[k], film.lights[k]);
                let d = rv.primary_ray(i, j).dir;
                let want = if hit(i) { tracer.reshaded_rgb(&lv.primary_ray(si, sj), keys, d) } else { UNTOUCHED };
                assert_eq!(rgb[i as usize], want, "({i}, {j})");
                reshaded[usize::from(sj != j)] += usize::from(hit(i));
            }
        }
        assert!(reshaded[0] > 100 && reshaded[1] > 10, "sources on the row and off it: {reshaded:?}");
    }
}
