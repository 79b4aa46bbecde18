//! Services for a second view: what `stereo` needs to make one eye from the other eye's
//! visible-surface record (Adelson & Hodges 1993, "Stereoscopic ray-tracing"), in one place.
//!
//! A [`SecondView`] is an eye's view with its screen bins built, made by
//! [`crate::Renderer::second_view`]. For pixels of that view it gives:
//! - [`SecondView::trace`] and [`SecondView::trace4`]: a full primary ray (the retrace of
//!   gaps, borders, object edges and shadow boundaries), bit-for-bit the pixel that
//!   [`crate::Renderer::render`] would make;
//! - [`SecondView::reshade`]: a surface the other eye saw, re-lit for this pixel's ray. Its
//!   view-independent light and light visibility are kept; highlights and mirror rays are
//!   recomputed (`reshade` mode);
//! - [`SecondView::shade_on4`]: this pixel's own ray against the one sphere the other eye
//!   saw there, shaded with that eye's light visibility (`exact` mode).
//!
//! And [`Tracer::nearest_depth`] bounds how near the eyes any sphere comes, which bounds
//! how far anything can shift between the eyes.
//!
//! **Light bits.** Visibility travels as bits: bit k of [`Surface::lights`] (and of the
//! film's `lights` plane) is set when light k reaches the point. A point of a surface is the
//! same point from either eye, so its bits hold for the second view as for the first; only
//! what depends on the direction of view is recomputed.

use glam::Vec3;
use wide::f32x4;

use crate::primary::BinnedView;
use crate::ray::Ray;
use crate::sphere::hits_each;
use crate::stats::RayCounts;
use crate::surface::{Surface, NO_OBJECT};
use crate::tracer::Tracer;

/// One eye's view, ready to trace and re-shade its pixels one by one (see the module doc).
#[derive(Clone, Copy, Debug)]
pub struct SecondView<'a> {
    eye: BinnedView<'a>,
}

impl<'a> SecondView<'a> {
    /// The services of `eye`, whose bins are built.
    pub(crate) fn new(eye: BinnedView<'a>) -> Self {
        Self { eye }
    }

    /// Traces and shades pixel (i, j) with a full primary ray; its sRGB colour.
    #[inline]
    #[must_use]
    pub fn trace(&self, i: u32, j: u32, counts: &mut RayCounts) -> u32 {
        self.eye.trace(i, j, counts).rgb
    }

    /// Traces and shades pixels (i + k, j), k = 0..n (n ≤ 4, all in the tile of (i, j), so
    /// i a multiple of 4), into `out(k, colour)`: [`SecondView::trace`] four at a time.
    #[inline]
    pub fn trace4(&self, i: u32, j: u32, n: usize, counts: &mut RayCounts, mut out: impl FnMut(usize, u32)) {
        self.eye.trace4(i, j, n, counts, |k, s| out(k, s.rgb));
    }

    /// Re-shades `surface`, seen by the other eye, for the ray of pixel (i, j): its kept
    /// view-independent light plus highlights and reflection recomputed for this ray. Casts
    /// no shadow ray for the surface itself. Seen along the ray that found it, a surface
    /// re-shades to bit-for-bit its own pixel.
    #[inline]
    #[must_use]
    pub fn reshade(&self, i: u32, j: u32, surface: &Surface, counts: &mut RayCounts) -> u32 {
        self.eye.tracer.reshade(self.eye.view.primary_ray(i, j).dir, surface, counts)
    }

    /// For pixels (i + k, j), k = 0..4: the pixel's own primary ray against the one sphere
    /// `objects[k]` alone, shaded with the light bits `lights[k]` where it hits. `None`
    /// where `objects[k]` is [`NO_OBJECT`] (the lane is skipped) or the ray misses that
    /// sphere (a silhouette: the caller retraces it).
    ///
    /// With the sphere the pixel really sees and its true light bits, the colour is
    /// bit-for-bit [`SecondView::trace`]'s: the ray, its `t` and the shading are the same
    /// operations on the same values.
    #[inline]
    #[must_use]
    pub fn shade_on4(
        &self,
        i: u32,
        j: u32,
        objects: [u32; 4],
        lights: [u32; 4],
        counts: &mut RayCounts,
    ) -> [Option<u32>; 4] {
        let (tracer, view) = (self.eye.tracer, self.eye.view);
        let dirs = view.primary_dirs4(i, j);
        let spheres = objects.map(|k| (k != NO_OBJECT).then(|| (tracer.centers[k as usize], tracer.radii[k as usize])));
        let t = hits_each(view.origin, spheres, dirs).to_array();
        let lane = |v: f32x4, k: usize| v.as_array()[k];
        std::array::from_fn(|k| {
            if objects[k] == NO_OBJECT || !t[k].is_finite() {
                return None;
            }
            let ray = Ray::new(view.origin, Vec3::new(lane(dirs[0], k), lane(dirs[1], k), lane(dirs[2], k)));
            Some(tracer.shade_known_visibility(view, &ray, t[k], objects[k], lights[k], counts).rgb)
        })
    }
}

impl Tracer {
    /// The smallest depth along `forward` from `origin` of any sphere point in front of
    /// that plane: min over spheres of (forward·(c − origin) − r), ignoring spheres wholly
    /// behind it. `None` if no sphere is in front. Negative when a sphere straddles the
    /// plane. With `origin` the head and `forward` its view axis, the nearest thing either
    /// eye can see is no nearer than this.
    #[must_use]
    pub fn nearest_depth(&self, origin: Vec3, forward: Vec3) -> Option<f32> {
        self.centers
            .iter()
            .zip(&self.radii)
            .map(|(&c, &r)| (forward.dot(c - origin), r))
            .filter(|&(w, r)| w + r > 0.0)
            .map(|(w, r)| w - r)
            .reduce(f32::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Eye;
    use crate::render::Renderer;
    use crate::scene::Scene;

    fn scene(name: &str) -> Scene {
        let path = format!("{}/../../assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
        Scene::load(path).expect("scene loads")
    }

    #[test]
    fn single_sphere_tests_equal_the_sphere_test_and_shade_like_a_full_trace() {
        let scene = scene("many.toml");
        let tracer = Tracer::new(&scene, 0.0);
        let (w, h) = (96, 54);
        let view = scene.camera.view(Eye::Right, w, h);
        let mut renderer = Renderer::new();
        let second = renderer.second_view(&tracer, &view);
        let n = tracer.sphere_count() as u32;
        let (mut hits, mut counts, mut plain) = (0, RayCounts::default(), RayCounts::default());
        // Lanes aimed at arbitrary spheres hit exactly where the lone sphere test does.
        for j in 0..h {
            for i in (0..w).step_by(4) {
                let objects =
                    [i % n, NO_OBJECT, (7 * j) % n, (i + j) % n].map(|k| if k == NO_OBJECT { k } else { (k * 13) % n });
                for (k, rgb) in second.shade_on4(i, j, objects, [0; 4], &mut counts).into_iter().enumerate() {
                    let ray = view.primary_ray(i + k as u32, j);
                    let want = objects[k] != NO_OBJECT && tracer.intersect_object(&ray, objects[k]).is_some();
                    assert_eq!(rgb.is_some(), want, "({i} + {k}, {j})");
                }
            }
        }
        // Lanes aimed at what each pixel sees, with its true light bits, give the full trace.
        for j in 0..h {
            for i in (0..w).step_by(4) {
                let truth: [_; 4] = std::array::from_fn(|k| tracer.trace_pixel(&view, i + k as u32, j, &mut plain));
                let objects = truth.map(|s| s.surface.object);
                let lights = truth.map(|s| s.surface.lights);
                for (k, rgb) in second.shade_on4(i, j, objects, lights, &mut counts).into_iter().enumerate() {
                    if objects[k] != NO_OBJECT {
                        assert_eq!(rgb, Some(truth[k].rgb), "({i} + {k}, {j})");
                        hits += 1;
                    }
                }
            }
        }
        assert!(hits > 500, "the view sees spheres: {hits}");
    }

    #[test]
    fn a_surface_reshaded_along_its_own_ray_is_its_pixel() {
        let scene = scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.3);
        let view = scene.camera.view(Eye::Left, 64, 36);
        let mut renderer = Renderer::new();
        let second = renderer.second_view(&tracer, &view);
        let (mut counts, mut reshaded) = (RayCounts::default(), 0);
        for j in 0..36 {
            for i in 0..64 {
                let s = tracer.trace_pixel(&view, i, j, &mut counts);
                assert_eq!(second.trace(i, j, &mut counts), s.rgb, "({i}, {j})");
                if s.surface.is_hit() {
                    assert_eq!(second.reshade(i, j, &s.surface, &mut counts), s.rgb, "({i}, {j})");
                    reshaded += 1;
                }
            }
        }
        assert!(reshaded > 100, "the view sees spheres: {reshaded}");
    }

    #[test]
    fn nearest_depth_is_the_nearest_sphere_point_ahead() {
        let mut scene = scene("seed.toml");
        scene.spheres.truncate(2);
        scene.spheres[0].motion = crate::scene::Motion::Static(Vec3::new(0.0, 0.0, 10.0));
        scene.spheres[0].radius = 1.0;
        scene.spheres[1].motion = crate::scene::Motion::Static(Vec3::new(3.0, 0.0, -4.0));
        scene.spheres[1].radius = 1.0;
        let tracer = Tracer::new(&scene, 0.0);
        assert_eq!(tracer.nearest_depth(Vec3::ZERO, Vec3::Z), Some(9.0), "the sphere behind is ignored");
        assert_eq!(tracer.nearest_depth(Vec3::new(0.0, 0.0, 10.5), Vec3::Z), Some(-1.5), "straddling");
        assert_eq!(tracer.nearest_depth(Vec3::new(0.0, 0.0, 20.0), Vec3::Z), None, "nothing ahead");
    }
}
