//! Services for a second view: what `stereo` needs to make one eye from the other eye's
//! visible-surface record (Adelson & Hodges 1993, "Stereoscopic ray-tracing"), in one place.
//!
//! A [`SecondView`] is an eye's view with its screen bins built, made by
//! [`crate::Renderer::second_view`]. For a row's pixels, given as lists, it gives:
//! - [`SecondView::trace_pixels`]: full primary rays (the retrace of gaps, borders, object
//!   edges and shadow boundaries), bit-for-bit the pixels [`crate::Renderer::render`]
//!   would make;
//! - [`SecondView::reshade`]: surfaces the other eye saw, re-lit for these pixels' rays.
//!   Their view-independent light and light visibility are kept; highlights and mirror rays
//!   are recomputed (`reshade` mode);
//! - [`SecondView::shade_on`]: each pixel's own ray against the one sphere the other eye saw
//!   there, shaded with that eye's light visibility, and fully retraced where it misses
//!   that sphere (`exact` mode).
//!
//! Every list is shaded as one batch of the thread's wavefront (`wavefront.rs`), so the
//! pixels of a second view go through the very kernels a first view's do.
//!
//! And [`Tracer::nearest_depth`] bounds how near the eyes any sphere comes, which bounds
//! how far anything can shift between the eyes.
//!
//! **Light bits.** Visibility travels as bits: bit k of [`Surface::lights`] (and of the
//! film's `lights` plane) is set when light k reaches the point. A point of a surface is the
//! same point from either eye, so its bits hold for the second view as for the first; only
//! what depends on the direction of view is recomputed.

use fearless_simd::{dispatch, prelude::*, Simd};
use glam::Vec3;

use crate::camera::EyeView;
use crate::film::Film;
use crate::primary::BinnedView;
use crate::ray::Ray;
use crate::simd::F;
use crate::stats::RayCounts;
use crate::surface::Hit;
use crate::swept::Touch;
use crate::tracer::Tracer;
use crate::wavefront::{with_wavefront, Wavefront};

/// One eye's view, ready to trace and re-shade lists of its pixels (see the module doc).
#[derive(Clone, Copy, Debug)]
pub struct SecondView<'a> {
    eye: BinnedView<'a>,
    /// Whether to mark the pixels whose ray trees meet a moving sphere's swept volume.
    mark: bool,
}

/// Marks a tag of [`SecondView::shade_on`] whose pixel was retraced.
const RETRACED: u32 = 1 << 31;

/// Groups ascending pixel columns by the aligned group of `lanes` (a power of two, at most
/// 32) they fall in: calls `group(first column, lane mask)` once per group.
pub(crate) fn by_lanes(cols: impl IntoIterator<Item = u32>, lanes: u32, mut group: impl FnMut(u32, u32)) {
    debug_assert!(lanes.is_power_of_two() && lanes <= 32, "{lanes} lanes");
    let mut current: Option<(u32, u32)> = None;
    for i in cols {
        let base = i & !(lanes - 1);
        match &mut current {
            Some((b, mask)) if *b == base => *mask |= 1 << (i - base),
            _ => {
                if let Some((b, mask)) = current.take() {
                    group(b, mask);
                }
                current = Some((base, 1 << (i - base)));
            }
        }
    }
    if let Some((b, mask)) = current {
        group(b, mask);
    }
}

impl<'a> SecondView<'a> {
    /// The services of `eye`, whose bins are built.
    pub(crate) fn new(eye: BinnedView<'a>) -> Self {
        Self { eye, mark: false }
    }

    /// This view, telling with each pixel it hands out where that pixel's ray tree meets the
    /// moving spheres' swept volumes (`swept.rs`): the `touch` argument of the `out`
    /// callbacks, otherwise always [`Touch::NONE`].
    #[must_use]
    pub fn marking(self, mark: bool) -> Self {
        Self { mark, ..self }
    }

    /// Hands `out(tag, background colour, touch)` again for each pixel of row `j` that
    /// [`SecondView::push_traced`] found seeing only background and whose primary ray meets
    /// a swept volume (when marking): the pixels' marks, found in lanes.
    fn mark_background(&self, wavefront: &mut Wavefront, j: u32, out: &mut impl FnMut(u32, u32, Touch)) {
        if self.mark {
            let rgb = self.eye.tracer.background_rgb;
            wavefront.mark_background(self.eye.tracer, self.eye.view, (j, !RETRACED), &mut |tag, touch| {
                out(tag, rgb, touch);
            });
        }
    }

    /// Marks the batch's samples of row `j`, when marking; `own` says whether their rays
    /// are this view's (not another view's, whose pixels carry those rays' marks).
    fn mark_batch(&self, wavefront: &mut Wavefront, j: u32, own: bool) {
        if self.mark {
            wavefront.mark_dynamic(self.eye.tracer, |tag| own && self.eye.bins.may_meet_moving(tag & !RETRACED, j));
        }
    }

    /// Sample `e`'s mark ([`Touch::NONE`] when not marking).
    fn touch(&self, wavefront: &Wavefront, e: usize) -> Touch {
        if self.mark {
            wavefront.touch(e)
        } else {
            Touch::NONE
        }
    }

    /// How many columns [`SecondView::push_traced`] takes at once: the lane width.
    pub(crate) fn lanes() -> u32 {
        crate::simd::lane_width() as u32
    }

    /// Pushes the pixels `mask` names of the group of [`SecondView::lanes`] columns from
    /// `base` (a multiple of it) with full primary rays, in lanes; the ones that see only
    /// background go straight to `out(tag, colour, touch)`. Tags are columns | `flag`.
    pub(crate) fn push_traced(
        &self,
        wavefront: &mut Wavefront,
        base: u32,
        j: u32,
        mask: u32,
        flag: u32,
        out: &mut impl FnMut(u32, u32, Touch),
    ) {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.push_traced_in(simd, wavefront, (base, j, mask, flag), out),
        ));
    }

    #[expect(clippy::inline_always, reason = "inlined into the dispatched closure, whose target features it needs")]
    #[inline(always)]
    fn push_traced_in<S: Simd>(
        &self,
        simd: S,
        wavefront: &mut Wavefront,
        (base, j, mask, flag): (u32, u32, u32, u32),
        out: &mut impl FnMut(u32, u32, Touch),
    ) {
        let lanes = F::<S>::LEN;
        debug_assert!(
            (base as usize).is_multiple_of(lanes) && u64::from(mask) < 1 << lanes,
            "group {base}, mask {mask:b}"
        );
        let (tracer, view) = (self.eye.tracer, self.eye.view);
        let background = |wavefront: &mut Wavefront, i: u32, out: &mut dyn FnMut(u32, u32, Touch)| {
            // Marked later, together (`mark_background`).
            out(i | flag, tracer.background_rgb, Touch::NONE);
            if self.mark && self.eye.bins.may_meet_moving(i, j) {
                wavefront.push_background(i | flag);
            }
        };
        if self.eye.bins.is_empty_at(base, j) {
            for i in crate::bits::ones(&[u64::from(mask)]) {
                background(wavefront, base + i, out);
            }
            return;
        }
        let hits = self.eye.hits_lanes(simd, base, j);
        let hit = hits.0.abs().simd_lt(F::<S>::splat(simd, f32::INFINITY)).to_bitmask() as u32;
        if mask == hit && u64::from(mask) == (1 << lanes) - 1 {
            // Every ray of the group hits: into the batch whole.
            wavefront.push_lanes(simd, view.origin, hits, base | flag);
            return;
        }
        let (mut t, mut ids, mut d) = ([0f32; 16], [0u32; 16], [[0f32; 16]; 3]);
        hits.0.store_slice(&mut t[..lanes]);
        hits.1.store_slice(&mut ids[..lanes]);
        for (column, v) in d.iter_mut().zip(&hits.2) {
            v.store_slice(&mut column[..lanes]);
        }
        for l in crate::bits::ones(&[u64::from(mask)]) {
            let (i, k) = (base + l, l as usize);
            if hit & (1 << l) != 0 {
                let ray = Ray::new(view.origin, Vec3::new(d[0][k], d[1][k], d[2][k]));
                wavefront.push_hit(&ray, Hit { t: t[k], object: ids[k] }, None, i | flag);
            } else {
                background(wavefront, i, out);
            }
        }
    }

    /// Traces the pixels `cols` (ascending columns) of row `j` with full primary rays, and
    /// hands each pixel's sRGB colour to `out(column, colour, touch)`.
    pub fn trace_pixels(
        &self,
        j: u32,
        cols: impl IntoIterator<Item = u32>,
        counts: &mut RayCounts,
        mut out: impl FnMut(u32, u32, Touch),
    ) {
        with_wavefront(|wavefront| {
            by_lanes(cols, Self::lanes(), |base, mask| {
                counts.primary += u64::from(mask.count_ones());
                self.push_traced(wavefront, base, j, mask, 0, &mut out);
            });
            wavefront.shade(self.eye.tracer, counts);
            self.mark_batch(wavefront, j, true);
            for e in 0..wavefront.len() {
                out(wavefront.tag(e), wavefront.rgb(e), self.touch(wavefront, e));
            }
            self.mark_background(wavefront, j, &mut out);
        });
    }

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

    /// For each `(column, object, light bits)` of row `j` (ascending columns): the pixel's
    /// own primary ray against the one sphere `object` alone, shaded with `lights` where it
    /// hits; where it misses that sphere (a silhouette), the pixel is retraced with a full
    /// primary ray. Hands `out(column, colour, retraced, touch)` for each.
    ///
    /// With the sphere the pixel really sees and its true light bits, the colour is
    /// bit-for-bit the full trace's: the ray, its `t` and the shading are the same
    /// operations on the same values.
    pub fn shade_on(
        &self,
        j: u32,
        items: impl IntoIterator<Item = (u32, u32, u32)>,
        counts: &mut RayCounts,
        mut out: impl FnMut(u32, u32, bool, Touch),
    ) {
        let (tracer, view) = (self.eye.tracer, self.eye.view);
        let mut out_tagged = |tag: u32, rgb: u32, touch: Touch| out(tag & !RETRACED, rgb, tag & RETRACED != 0, touch);
        with_wavefront(|wavefront| {
            for (i, object, lights) in items {
                wavefront.push_named(i, object, lights);
            }
            wavefront.aim_named(view, j, tracer);
            // The silhouettes the named spheres missed: full primary rays, a lane group at a time.
            let missed = std::mem::take(wavefront.missed_mut());
            counts.primary += missed.len() as u64;
            by_lanes(missed.iter().copied(), Self::lanes(), |base, mask| {
                self.push_traced(wavefront, base, j, mask, RETRACED, &mut out_tagged);
            });
            *wavefront.missed_mut() = missed;
            wavefront.shade(tracer, counts);
            self.mark_batch(wavefront, j, true);
            for e in 0..wavefront.len() {
                out_tagged(wavefront.tag(e), wavefront.rgb(e), self.touch(wavefront, e));
            }
            self.mark_background(wavefront, j, &mut out_tagged);
        });
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
    use crate::surface::NO_OBJECT;

    fn scene(name: &str) -> Scene {
        let path = format!("{}/../../assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
        Scene::load(path).expect("scene loads")
    }

    #[test]
    fn single_sphere_tests_retrace_where_the_sphere_test_misses_and_shade_like_a_full_trace() {
        let scene = scene("many.toml");
        let tracer = Tracer::new(&scene, 0.0);
        let (w, h) = (94, 54); // a short last quad
        let view = scene.camera.view(Eye::Right, w, h);
        let mut renderer = Renderer::new();
        let second = renderer.second_view(&tracer, &view);
        let n = tracer.sphere_count() as u32;
        let (mut counts, mut plain, mut hits, mut retraced) = (RayCounts::default(), RayCounts::default(), 0, 0);
        for j in 0..h {
            // Aimed at arbitrary spheres: retraced exactly where the lone sphere test misses,
            // and then with the full trace's colour.
            let items: Vec<_> = (0..w).filter(|i| i % 3 != 1).map(|i| (i, (i * 13 + 7 * j) % n, 0)).collect();
            let mut seen = Vec::new();
            second.shade_on(j, items.iter().copied(), &mut counts, |i, rgb, again, _| seen.push((i, rgb, again)));
            seen.sort_unstable();
            assert_eq!(seen.len(), items.len(), "one answer per pixel");
            for (&(i, object, _), &(col, rgb, again)) in items.iter().zip(&seen) {
                let ray = view.primary_ray(i, j);
                assert_eq!((col, again), (i, tracer.intersect_object(&ray, object).is_none()), "({i}, {j})");
                if again {
                    assert_eq!(rgb, tracer.trace_pixel(&view, i, j, &mut plain).rgb, "({i}, {j}) retraced");
                    retraced += 1;
                }
            }
            // Every pixel of the row aimed at one sphere: whole groups of pixels retraced.
            let items: Vec<_> = (0..w).map(|i| (i, j % n, 0)).collect();
            second.shade_on(j, items.iter().copied(), &mut counts, |i, rgb, again, _| {
                let ray = view.primary_ray(i, j);
                assert_eq!(again, tracer.intersect_object(&ray, j % n).is_none(), "({i}, {j}), one sphere");
                if again {
                    assert_eq!(rgb, tracer.trace_pixel(&view, i, j, &mut plain).rgb, "({i}, {j}) retraced");
                }
            });
            // Aimed at what each pixel sees, with its true light bits: the full trace.
            let truth: Vec<_> = (0..w).map(|i| tracer.trace_pixel(&view, i, j, &mut plain)).collect();
            let items = (0..w).filter(|&i| truth[i as usize].surface.is_hit()).map(|i| {
                let s = truth[i as usize].surface;
                (i, s.object, s.lights)
            });
            second.shade_on(j, items, &mut counts, |i, rgb, again, _| {
                assert_eq!((rgb, again), (truth[i as usize].rgb, false), "({i}, {j})");
                hits += 1;
            });
            // And every pixel traced afresh.
            second.trace_pixels(j, 0..w, &mut counts, |i, rgb, _| {
                assert_eq!(rgb, truth[i as usize].rgb, "({i}, {j}) traced");
            });
        }
        assert!(hits > 500 && retraced > 500, "the view sees spheres: {hits} hits, {retraced} retraced");
    }

    #[test]
    fn pixel_lists_count_the_rays_a_full_trace_casts() {
        let scene = scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.9);
        let (w, h) = (61, 34);
        let view = scene.camera.view(Eye::Right, w, h);
        let mut renderer = Renderer::new();
        let second = renderer.second_view(&tracer, &view);
        let (mut listed, mut plain) = (RayCounts::default(), RayCounts::default());
        for j in 0..h {
            // Every other pixel, then the rest: scattered lists, whole quads and lone pixels.
            second.trace_pixels(j, (0..w).step_by(2), &mut listed, |_, _, _| {});
            second.trace_pixels(j, (1..w).step_by(2), &mut listed, |_, _, _| {});
            for i in 0..w {
                let _ = tracer.trace_pixel(&view, i, j, &mut plain);
            }
        }
        assert_eq!(listed, plain, "primary, shadow and mirror rays");
    }

    #[test]
    fn a_surface_reshaded_along_its_own_ray_is_its_pixel() {
        let scene = scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.3);
        let (w, h) = (64, 36);
        let view = scene.camera.view(Eye::Left, w, h);
        let mut film = Film::new(1, 1);
        Renderer::new().render_keeping(&tracer, &view, &mut film, crate::Record::Keys);
        let mut renderer = Renderer::new();
        let second = renderer.second_view(&tracer, &view);
        let (mut counts, mut reshaded) = (RayCounts::default(), 0);
        for j in 0..h {
            let items = (0..w).filter(|&i| film.object[(j * w + i) as usize] != NO_OBJECT).map(|i| (i, j * w + i));
            second.reshade(j, (&view, &film), items, &mut counts, |i, rgb, _| {
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
        Renderer::new().render_keeping(&tracer, &lv, &mut film, crate::Record::Keys);
        let mut renderer = Renderer::new();
        let second = renderer.second_view(&tracer, &rv);
        let (mut counts, mut reshaded) = (RayCounts::default(), [0; 2]);
        let source = |i: u32, j: u32| if i % 7 == 3 { ((i + 5) % w, (j + 1) % h) } else { ((i + 5) % w, j) };
        for j in 0..h {
            let items = (0..w)
                .map(|i| (i, source(i, j)))
                .filter(|&(_, (si, sj))| film.object[(sj * w + si) as usize] != NO_OBJECT)
                .map(|(i, (si, sj))| (i, sj * w + si));
            second.reshade(j, (&lv, &film), items, &mut counts, |i, rgb, _| {
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
