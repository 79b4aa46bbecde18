//! Services for a second view: what `stereo` needs to make one eye from the other eye's
//! visible-surface record (Adelson & Hodges 1993, "Stereoscopic ray-tracing"), in one place.
//!
//! A [`SecondView`] is an eye's view with its screen bins built, made by
//! [`crate::Renderer::second_view`]. For a row's pixels it gives:
//! - [`SecondView::trace_pixels`]: full primary rays (the retrace of gaps, borders, object
//!   edges and shadow boundaries), bit-for-bit the pixels [`crate::Renderer::render`]
//!   would make;
//! - [`SecondView::reshade`]: surfaces the other eye saw, re-lit for these pixels' rays.
//!   Their view-independent light and light visibility are kept; highlights and mirror rays
//!   are recomputed (`reshade` mode);
//! - [`SecondView::shade_row`]: a whole row by a plan, a pixel of the other eye per column
//!   (or none: trace afresh, or keep): each pixel's own ray against the one sphere the
//!   other eye saw there, shaded with that eye's light visibility, and fully retraced where
//!   it misses that sphere or the plan says so (`exact` mode). The plan ([`RowPlan`])
//!   holds each source's sphere and light bits in column order, so it is read a group of
//!   lanes at a time, by vector loads and compares. A group whose rays all hit their
//!   spheres enters the batch in vector stores, as a first view's rows do; a group with
//!   pixels to trace as well searches its screen tile's spheres once for all its lanes,
//!   and a planned pixel whose nearest sphere is its own takes that hit (its `t` is the
//!   lone test's, bit for bit) with its light bits.
//!
//! Every row's pixels are shaded as one batch of the thread's wavefront (`wavefront.rs`), so
//! the pixels of a second view go through the very kernels a first view's do.
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
use crate::marks::MarksRow;
use crate::primary::BinnedView;
use crate::ray::Ray;
use crate::simd::{F, U};
use crate::stats::RayCounts;
use crate::surface::Hit;
use crate::surface::NO_OBJECT;
use crate::swept::Touch;
use crate::tracer::Tracer;
use crate::wavefront::per_object;
use crate::wavefront::{with_wavefront, Wavefront};

/// One eye's view, ready to trace and re-shade lists of its pixels (see the module doc).
#[derive(Clone, Copy, Debug)]
pub struct SecondView<'a> {
    eye: BinnedView<'a>,
    /// Whether to mark the pixels whose ray trees meet a moving sphere's swept volume.
    mark: bool,
}

/// A [`SecondView::shade_row`] plan entry: trace the pixel afresh.
pub const TRACE: u32 = u32::MAX;
/// A [`SecondView::shade_row`] plan entry: leave the pixel as it is.
pub const KEEP: u32 = u32::MAX - 1;

/// A row's plan for [`SecondView::shade_row`]: three slices with an entry per column.
///
/// Where `source` names a pixel of the other view's film, `object` and `lights` hold that
/// pixel's object and light bits, read from the film in column order: a group of lanes then
/// reads them in one load each, instead of a load per lane at scattered sources and a
/// vector rebuilt from scalar stores. Elsewhere they may hold anything.
#[derive(Clone, Copy, Debug)]
pub struct RowPlan<'a> {
    /// A pixel of the other view's film (a row-major index), [`TRACE`] or [`KEEP`].
    pub source: &'a [u32],
    /// The object of the pixel `source` names.
    pub object: &'a [u32],
    /// The light bits of the pixel `source` names.
    pub lights: &'a [u32],
}

impl<'a> RowPlan<'a> {
    /// The plan `source` (entries as [`RowPlan::source`]), its objects and light bits read
    /// from `film` into `object` and `lights` (cleared first).
    pub fn read(film: &Film, source: &'a [u32], (object, lights): (&'a mut Vec<u32>, &'a mut Vec<u32>)) -> Self {
        object.clear();
        lights.clear();
        for &s in source {
            let (o, l) = if s < KEEP { (film.object[s as usize], film.lights[s as usize]) } else { (NO_OBJECT, 0) };
            object.push(o);
            lights.push(l);
        }
        Self { source, object, lights }
    }

    /// Columns in the row.
    #[must_use]
    pub fn len(&self) -> usize {
        self.source.len()
    }

    /// Whether the row has no column.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.source.is_empty()
    }
}

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
            wavefront.mark_background(self.eye.tracer, self.eye.view, (j, u32::MAX), &mut |tag, touch| {
                out(tag, rgb, touch);
            });
        }
    }

    /// Marks the batch's samples of row `j`, when marking; `own` says whether their rays
    /// are this view's (not another view's, whose pixels carry those rays' marks).
    fn mark_batch(&self, wavefront: &mut Wavefront, j: u32, own: bool) {
        if self.mark {
            wavefront.mark_dynamic(self.eye.tracer, |tag| own && self.eye.bins.may_meet_moving(tag, j));
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
    /// background go straight to `out(column, colour, touch)`. Tags are columns.
    pub(crate) fn push_traced(
        &self,
        wavefront: &mut Wavefront,
        base: u32,
        j: u32,
        mask: u32,
        out: &mut impl FnMut(u32, u32, Touch),
    ) {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.push_traced_in(simd, wavefront, (base, j, mask), out),
        ));
    }

    #[expect(clippy::inline_always, reason = "inlined into the dispatched closure, whose target features it needs")]
    #[inline(always)]
    fn push_traced_in<S: Simd>(
        &self,
        simd: S,
        wavefront: &mut Wavefront,
        (base, j, mask): (u32, u32, u32),
        out: &mut impl FnMut(u32, u32, Touch),
    ) {
        let lanes = F::<S>::LEN;
        debug_assert!(
            (base as usize).is_multiple_of(lanes) && u64::from(mask) < 1 << lanes,
            "group {base}, mask {mask:b}"
        );
        if self.eye.bins.is_empty_at(base, j) {
            for i in crate::bits::ones(&[u64::from(mask)]) {
                self.background(wavefront, (base + i, j), out);
            }
            return;
        }
        let hits = self.eye.hits_lanes(simd, base, j);
        self.push_found_in(simd, wavefront, (base, j, mask), hits, None, out);
    }

    /// A pixel (i, j) whose primary ray sees only background: its colour to `out`, and its
    /// column noted for [`SecondView::mark_background`] when marking and it may be marked.
    fn background(&self, wavefront: &mut Wavefront, (i, j): (u32, u32), out: &mut impl FnMut(u32, u32, Touch)) {
        // Marked later, together (`mark_background`).
        out(i, self.eye.tracer.background_rgb, Touch::NONE);
        if self.mark && self.eye.bins.may_meet_moving(i, j) {
            wavefront.push_background(i);
        }
    }

    /// Pushes the pixels `mask` names of the group of lanes from `base` on row `j`, whose
    /// first hits are `hits` (the bins' search: `t`, +∞ for none, sphere and ray direction
    /// per lane), with light bits where `known` has them (as [`Wavefront::push_lanes`]
    /// takes them); the ones that see only background go to `out`.
    #[expect(clippy::inline_always, reason = "inlined into the dispatched closure, whose target features it needs")]
    #[inline(always)]
    fn push_found_in<S: Simd>(
        &self,
        simd: S,
        wavefront: &mut Wavefront,
        (base, j, mask): (u32, u32, u32),
        hits: (F<S>, U<S>, [F<S>; 3]),
        known: Option<(U<S>, u32)>,
        out: &mut impl FnMut(u32, u32, Touch),
    ) {
        let view = self.eye.view;
        let hit = hits.0.abs().simd_lt(F::<S>::splat(simd, f32::INFINITY)).to_bitmask() as u32;
        if mask == hit && u64::from(mask) == (1 << F::<S>::LEN) - 1 {
            // Every ray of the group hits: into the batch whole.
            wavefront.push_lanes(simd, view.origin, hits, base, known);
            return;
        }
        let (t, ids, d) = (hits.0.as_slice(), hits.1.as_slice(), crate::simd::each3(|a| hits.2[a].as_slice()));
        let bits = known.as_ref().map(|(bits, which)| (bits.as_slice(), *which));
        for l in crate::bits::ones(&[u64::from(mask)]) {
            let (i, k) = (base + l, l as usize);
            if hit & (1 << l) != 0 {
                let ray = Ray::new(view.origin, Vec3::new(d[0][k], d[1][k], d[2][k]));
                let lights = bits.and_then(|(bits, which)| (which & (1 << l) != 0).then(|| bits[k]));
                wavefront.push_hit(&ray, Hit { t: t[k], object: ids[k] }, lights, i);
            } else {
                self.background(wavefront, (i, j), out);
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
                self.push_traced(wavefront, base, j, mask, &mut out);
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

    /// Makes the pixels of row `j` as `plan` says, in one batch. Its source per column is:
    /// - the index (row-major) of a pixel of the other view's film: this pixel's own primary
    ///   ray is tested against the one sphere that pixel saw (the plan's object), and where
    ///   it hits, shaded with that pixel's light bits (the plan's); where it misses (a
    ///   silhouette) the pixel is traced afresh and its column pushed to `missed`; where
    ///   that pixel saw only background ([`NO_OBJECT`]), this one is background too, and
    ///   takes the scene's background colour;
    /// - [`TRACE`]: traced afresh, with a full primary ray;
    /// - [`KEEP`]: left as it is.
    ///
    /// Colours go to `rgb` (the row), and when marking, each pixel made is marked in `marks`
    /// (a pixel that takes a background colour carries no ray of its own and is left
    /// unmarked). Returns the pixels tested against the sphere their plan names, alone or
    /// in their tile's search (not scene rays, so not counted in `counts`).
    ///
    /// With the sphere the pixel really sees and its true light bits, a pixel is bit-for-bit
    /// the full trace's: the ray, its `t` and the shading are the same operations on the same
    /// values.
    pub fn shade_row(
        &self,
        j: u32,
        plan: RowPlan<'_>,
        (rgb, marks): (&mut [u32], Option<&mut MarksRow<'_>>),
        counts: &mut RayCounts,
        missed: &mut Vec<u32>,
    ) -> u64 {
        debug_assert!(
            plan.source.len() == rgb.len() && plan.object.len() == rgb.len() && plan.lights.len() == rgb.len(),
            "a plan entry per pixel of the row"
        );
        missed.clear();
        // Marks only when this view marks and the caller keeps them.
        let mut marks = marks.filter(|_| self.mark);
        with_wavefront(|wavefront| {
            let tests = dispatch!(crate::simd::level(), simd => simd.vectorize(
                #[inline(always)]
                || self.push_row_in(simd, wavefront, j, plan, counts, (missed, rgb, &mut marks)),
            ));
            wavefront.shade(self.eye.tracer, counts);
            // Colours in a plain loop; marks, when kept, in one of their own.
            for e in 0..wavefront.len() {
                rgb[wavefront.tag(e) as usize] = wavefront.rgb(e);
            }
            if let Some(marks) = marks {
                self.mark_batch(wavefront, j, true);
                for e in 0..wavefront.len() {
                    marks.set(wavefront.tag(e), self.touch(wavefront, e));
                }
                self.mark_background(wavefront, j, &mut |i, _, touch| marks.set(i, touch));
            }
            tests
        })
    }

    /// The first half of [`SecondView::shade_row`] with the lanes of `simd`: each group of
    /// lanes of the row read from the plan, aimed and pushed into the batch (a group that
    /// hits its spheres in every lane in vector stores). The colours made without shading
    /// go straight to `rgb`, and the marks of traced pixels that see background to `marks`.
    /// Returns the pixels tested against their planned spheres.
    #[expect(clippy::inline_always, reason = "inlined into the dispatched closure, whose target features it needs")]
    #[inline(always)]
    fn push_row_in<S: Simd>(
        &self,
        simd: S,
        wavefront: &mut Wavefront,
        j: u32,
        plan: RowPlan<'_>,
        counts: &mut RayCounts,
        (missed, rgb, marks): (&mut Vec<u32>, &mut [u32], &mut Option<&mut MarksRow<'_>>),
    ) -> u64 {
        let (tracer, view) = (self.eye.tracer, self.eye.view);
        let lanes = F::<S>::LEN;
        let all = (1u32 << lanes) - 1;
        let inf = F::<S>::splat(simd, f32::INFINITY);
        let origin = crate::simd::splat3(simd, view.origin);
        let splat = |x: u32| U::<S>::splat(simd, x);
        let (mut objects, mut short) = ([0u32; 16], [[KEEP; 16]; 3]);
        let mut tests = 0;
        for base in (0..plan.len()).step_by(lanes) {
            let end = (base + lanes).min(plan.len());
            let [source, object, lights] = if end - base == lanes {
                [&plan.source[base..end], &plan.object[base..end], &plan.lights[base..end]]
            } else {
                // The row's last, short group, its missing lanes kept.
                for (pad, part) in short.iter_mut().zip([plan.source, plan.object, plan.lights]) {
                    pad[..end - base].copy_from_slice(&part[base..end]);
                    pad[end - base..].fill(KEEP);
                }
                let [a, b, c] = &short;
                [&a[..lanes], &b[..lanes], &c[..lanes]]
            };
            // The group's lanes by what the plan says, each set a vector compare.
            let entries = U::<S>::from_slice(simd, source);
            let ids = U::<S>::from_slice(simd, object);
            let mut traced = entries.simd_eq(splat(TRACE)).to_bitmask() as u32;
            let given = all & !traced & !(entries.simd_eq(splat(KEEP)).to_bitmask() as u32);
            let background = given & ids.simd_eq(splat(NO_OBJECT)).to_bitmask() as u32;
            let named = given & !background;
            for l in crate::bits::ones(&[u64::from(background)]) {
                // The other view's pixel is the background colour (not read from its film,
                // where it has long left the cache). Marked nowhere: its ray is that view's.
                rgb[base + l as usize] = tracer.background_rgb;
            }
            tests += u64::from(named.count_ones());
            // A group of traced and named lanes searches its tile's spheres once for all of
            // them (its traced lanes need that anyway): a named lane whose nearest sphere is
            // its own takes that hit, bit for bit its lone test's, with its light bits. The
            // other named lanes are tested alone, as a group of named lanes only is.
            let (mut found, mut alone) = (None, named);
            if named != 0 && traced != 0 && !self.eye.bins.is_empty_at(base as u32, j) {
                let hits = self.eye.hits_lanes(simd, base as u32, j);
                let own = (hits.0.simd_lt(inf) & hits.1.simd_eq(ids)).to_bitmask() as u32 & named;
                (found, alone) = (Some((hits, own)), named & !own);
            }
            if alone != 0 {
                // The other lanes aim at a named lane's sphere, and are left out.
                let first = splat(object[alone.trailing_zeros() as usize]);
                let ids = crate::simd::mask_of(simd, u64::from(alone)).select(ids, first);
                let one =
                    (ids.simd_eq(first).to_bitmask() as u32 == all).then(|| object[alone.trailing_zeros() as usize]);
                ids.store_slice(&mut objects[..lanes]);
                let at = (&objects[..lanes], one);
                let columns = splat(base as u32) + crate::simd::lane_index(simd);
                let d = view.primary_dirs_at(simd, F::<S>::float_from(columns), j);
                let c = crate::simd::each3(|a| per_object(simd, at, |o| tracer.centers[o][a]));
                let r = per_object(simd, at, |o| tracer.radii[o]);
                let t = crate::simd::spheres_t(simd, origin, d, (c, r), inf);
                let hit = t.simd_lt(inf).to_bitmask() as u32 & alone;
                if hit == all {
                    let known = U::<S>::from_slice(simd, lights);
                    wavefront.push_lanes(simd, view.origin, (t, ids, d), base as u32, Some((known, all)));
                } else {
                    let (ts, dirs) = (t.as_slice(), crate::simd::each3(|a| d[a].as_slice()));
                    for l in crate::bits::ones(&[u64::from(hit)]) {
                        let l = l as usize;
                        let ray = Ray::new(view.origin, Vec3::new(dirs[0][l], dirs[1][l], dirs[2][l]));
                        let hit = Hit { t: ts[l], object: objects[l] };
                        wavefront.push_hit(&ray, hit, Some(lights[l]), (base + l) as u32);
                    }
                }
                // The silhouettes the named spheres missed are traced afresh.
                let miss = alone & !hit;
                missed.extend(crate::bits::ones(&[u64::from(miss)]).map(|l| base as u32 + l));
                traced |= miss;
            }
            let mut out = |i: u32, colour: u32, touch: Touch| {
                rgb[i as usize] = colour;
                if let Some(marks) = marks.as_deref_mut() {
                    marks.set(i, touch);
                }
            };
            counts.primary += u64::from(traced.count_ones());
            if let Some((hits, own)) = found {
                let known = (U::<S>::from_slice(simd, lights), own);
                self.push_found_in(simd, wavefront, (base as u32, j, traced | own), hits, Some(known), &mut out);
            } else if traced != 0 {
                self.push_traced_in(simd, wavefront, (base as u32, j, traced), &mut out);
            }
        }
        tests
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

    /// Row `j` of `second` made by `plan` (sources on `film`) into `rgb`: the sphere tests.
    fn plan_row(
        second: &SecondView<'_>,
        j: u32,
        (film, plan): (&Film, &[u32]),
        rgb: &mut [u32],
        missed: &mut Vec<u32>,
    ) -> u64 {
        let (mut object, mut lights) = (Vec::new(), Vec::new());
        let plan = RowPlan::read(film, plan, (&mut object, &mut lights));
        second.shade_row(j, plan, (rgb, None), &mut RayCounts::default(), missed)
    }

    /// A colour no traced pixel has: its high byte is set.
    const UNTOUCHED: u32 = 0xFF00_FF00;

    #[test]
    fn a_planned_row_is_the_full_trace_wherever_its_sphere_and_bits_are_true() {
        let scene = scene("many.toml");
        let tracer = Tracer::new(&scene, 0.0);
        let (w, h) = (94, 54); // a short last group of lanes
        let view = scene.camera.view(Eye::Right, w, h);
        let mut renderer = Renderer::new();
        let second = renderer.second_view(&tracer, &view);
        let n = tracer.sphere_count() as u32;
        let mut plain = RayCounts::default();
        let truth: Vec<_> = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| tracer.trace_pixel(&view, i, j, &mut plain))
            .collect();
        // A film that names, for pixel (i, j), the sphere and light bits `pick` gives, or
        // background (object NO_OBJECT) of a colour of its own, which a planned pixel does not
        // take: it takes the scene's background colour.
        let film_of = |pick: &dyn Fn(u32, u32) -> Option<(u32, u32)>| {
            let mut film = Film::new(w, h);
            for (k, (i, j)) in (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).enumerate() {
                (film.object[k], film.lights[k], film.rgb[k]) = match pick(i, j) {
                    Some((object, lights)) => (object, lights, UNTOUCHED),
                    None => (NO_OBJECT, 0, 0x0012_3400 | i),
                };
            }
            film
        };
        let (mut counts, mut missed) = (RayCounts::default(), Vec::new());
        let (mut hits, mut retraced, mut kept, mut copied) = (0, 0, 0, 0);

        // Aimed at arbitrary spheres, with some pixels traced, some kept and some taking a
        // background colour: retraced exactly where the lone sphere test misses, and then
        // with the full trace's colour.
        let film = film_of(&|i, j| (i % 5 != 2).then_some(((i * 13 + 7 * j) % n, 0)));
        for j in 0..h {
            let plan: Vec<u32> = (0..w)
                .map(|i| match i % 7 {
                    3 => TRACE,
                    5 => KEEP,
                    _ => j * w + i,
                })
                .collect();
            let mut rgb = vec![UNTOUCHED; w as usize];
            let tests = plan_row(&second, j, (&film, &plan), &mut rgb, &mut missed);
            let named = plan.iter().filter(|&&s| s < KEEP && film.object[s as usize] != NO_OBJECT).count();
            assert_eq!(tests, named as u64, "row {j}: one sphere test per named pixel");
            for (i, (&source, &got)) in plan.iter().zip(&rgb).enumerate() {
                let (i, k) = (i as u32, (j * w) as usize + i);
                let full = truth[k].rgb;
                let miss = source < KEEP
                    && film.object[k] != NO_OBJECT
                    && tracer.intersect_object(&view.primary_ray(i, j), film.object[k]).is_none();
                assert_eq!(missed.contains(&i), miss, "({i}, {j}): listed as missed");
                let want = match source {
                    KEEP => {
                        kept += 1;
                        UNTOUCHED
                    }
                    TRACE => full,
                    // The scene's background, not the film's colour there.
                    _ if film.object[k] == NO_OBJECT => {
                        copied += 1;
                        tracer.background_rgb
                    }
                    _ if miss => {
                        retraced += 1;
                        full
                    }
                    // Shaded with made-up bits: only made.
                    _ => got & 0x00FF_FFFF,
                };
                assert_eq!(got, want, "({i}, {j}), plan {source}");
            }
        }
        // Every pixel of the row aimed at one sphere: whole groups of lanes retraced.
        let film = film_of(&|_, j| Some((j % n, 0)));
        for j in 0..h {
            let plan: Vec<u32> = (0..w).map(|i| j * w + i).collect();
            let mut rgb = vec![UNTOUCHED; w as usize];
            plan_row(&second, j, (&film, &plan), &mut rgb, &mut missed);
            for i in 0..w {
                let miss = tracer.intersect_object(&view.primary_ray(i, j), j % n).is_none();
                assert_eq!(missed.contains(&i), miss, "({i}, {j}), one sphere");
                if miss {
                    assert_eq!(rgb[i as usize], truth[(j * w + i) as usize].rgb, "({i}, {j}) retraced");
                }
            }
        }
        // Aimed at what each pixel sees, with its true light bits: the full trace.
        let film = film_of(&|i, j| {
            let s = truth[(j * w + i) as usize].surface;
            s.is_hit().then_some((s.object, s.lights))
        });
        for j in 0..h {
            let plan: Vec<u32> = (0..w).map(|i| j * w + i).collect();
            let mut rgb = vec![UNTOUCHED; w as usize];
            plan_row(&second, j, (&film, &plan), &mut rgb, &mut missed);
            assert!(missed.is_empty(), "row {j}: every named sphere is hit");
            for i in 0..w {
                let k = (j * w + i) as usize;
                let want = if truth[k].surface.is_hit() { truth[k].rgb } else { tracer.background_rgb };
                assert_eq!(rgb[i as usize], want, "({i}, {j})");
                hits += usize::from(truth[k].surface.is_hit());
            }
            // And every pixel traced afresh.
            second.trace_pixels(j, 0..w, &mut counts, |i, rgb, _| {
                assert_eq!(rgb, truth[(j * w + i) as usize].rgb, "({i}, {j}) traced");
            });
        }
        assert!(hits > 500 && retraced > 500, "the view sees spheres: {hits} hits, {retraced} retraced");
        assert!(kept > 500 && copied > 500, "{kept} kept, {copied} copied");
    }

    #[test]
    fn a_group_of_planned_and_traced_lanes_is_the_full_trace() {
        // Big spheres, so that many groups of lanes hit in every lane: traced lanes among
        // planned ones (true spheres and light bits) enter the batch whole, each lane with
        // its own light bits or none.
        let scene = scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.4);
        let (w, h) = (160, 90);
        let view = scene.camera.view(Eye::Right, w, h);
        let mut renderer = Renderer::new();
        let second = renderer.second_view(&tracer, &view);
        let mut plain = RayCounts::default();
        let truth: Vec<_> = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| tracer.trace_pixel(&view, i, j, &mut plain))
            .collect();
        let mut film = Film::new(w, h);
        for (k, shaded) in truth.iter().enumerate() {
            (film.object[k], film.lights[k], film.rgb[k]) = (shaded.surface.object, shaded.surface.lights, shaded.rgb);
        }
        let (lanes, mut whole) = (SecondView::lanes(), 0);
        let mut missed = Vec::new();
        for j in 0..h {
            let plan: Vec<u32> = (0..w).map(|i| if (i + j) % 5 == 1 { TRACE } else { j * w + i }).collect();
            let mut rgb = vec![UNTOUCHED; w as usize];
            plan_row(&second, j, (&film, &plan), &mut rgb, &mut missed);
            assert!(missed.is_empty(), "row {j}: every planned sphere is hit");
            for i in 0..w {
                assert_eq!(rgb[i as usize], truth[(j * w + i) as usize].rgb, "({i}, {j})");
            }
            let hits = |i: u32| truth[(j * w + i) as usize].surface.is_hit();
            whole += (0..w / lanes).filter(|g| (g * lanes..(g + 1) * lanes).all(hits)).count();
        }
        assert!(whole > 100, "{whole} groups of lanes that hit in every lane");
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
