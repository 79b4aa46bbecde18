//! [`PixelBatch::reshade`]: surfaces another view saw, re-lit for this view's pixels.

use super::PixelBatch;
use crate::camera::EyeView;
use crate::film::Film;
use crate::reuse::Touch;
use crate::stats::RayCounts;
use crate::surface::Hit;
use crate::wavefront::with_wavefront;

impl PixelBatch<'_> {
    /// Re-shades, for each `(column, source)` of row `j` (ascending columns), the surface
    /// that pixel `source` (a row-major index) of the other eye's `film`, rendered for
    /// `other`, saw, for the ray of this pixel: the other eye's hit point, normal,
    /// view-independent light and light bits (the point and normal remade from its ray and
    /// `t`, the light from its bits: bit-for-bit what it shaded), with highlights and
    /// reflection recomputed for this ray. Casts no shadow ray for the surface itself, and
    /// hands each colour to `out(column, colour, touch)`. Seen along the ray that found it, a
    /// surface re-shades to bit-for-bit its own pixel. The film must keep at least
    /// [`crate::Record::Keys`], and each source must have seen a sphere.
    pub fn reshade(
        &self,
        j: u32,
        (other, film): (&EyeView, &Film),
        items: impl IntoIterator<Item = (u32, u32)>,
        counts: &mut RayCounts,
        mut out: impl FnMut(u32, u32, Touch),
    ) {
        debug_assert_ne!(film.record(), crate::Record::Colour, "re-shading needs the other eye's record");
        let (view, w) = (self.eye.view, film.width());
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
            wavefront.shade(self.eye.tracer, counts);
            self.mark_batch(wavefront, j, false);
            for e in 0..wavefront.len() {
                out(wavefront.tag(e), wavefront.rgb(e), self.touch(wavefront, e));
            }
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

    fn scene(name: &str) -> Scene {
        let path = format!("{}/../../assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
        Scene::load(path).expect("scene loads")
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
            let items = (0..w).filter(|&i| film.object[(j * w + i) as usize] != NO_OBJECT).map(|i| (i, j * w + i));
            batch.reshade(j, (&view, &film), items, &mut counts, |i, rgb, _| {
                assert_eq!(rgb, film.rgb[(j * w + i) as usize], "({i}, {j})");
                reshaded += 1;
            });
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
            let items = (0..w)
                .map(|i| (i, source(i, j)))
                .filter(|&(_, (si, sj))| film.object[(sj * w + si) as usize] != NO_OBJECT)
                .map(|(i, (si, sj))| (i, sj * w + si));
            batch.reshade(j, (&lv, &film), items, &mut counts, |i, rgb, _| {
                let (si, sj) = source(i, j);
                let k = (sj * w + si) as usize;
                let keys = (film.t[k], film.object[k], film.lights[k]);
                let d = rv.primary_ray(i, j).dir;
                assert_eq!(rgb, tracer.reshaded_rgb(&lv.primary_ray(si, sj), keys, d), "({i}, {j})");
                reshaded[usize::from(sj != j)] += 1;
            });
        }
        assert!(reshaded[0] > 100 && reshaded[1] > 10, "sources on the row and off it: {reshaded:?}");
    }
}
