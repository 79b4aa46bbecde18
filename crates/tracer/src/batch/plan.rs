//! [`BinnedView::shade_row`]: a row made by a plan, exact mode's one pass.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{dispatch, prelude::*, Simd};
use glam::Vec3;

use super::BinnedView;
use crate::film::Film;
use crate::ray::Ray;
use crate::simd::{F, U};
use crate::sink::{Columns, Observe, RowSink};
use crate::stats::RayCounts;
use crate::surface::{Hit, NO_OBJECT};
use crate::wavefront::{per_object, with_wavefront, Wavefront};

/// A [`crate::PixelBatch::shade_row`] plan entry: trace the pixel afresh.
pub const TRACE: u32 = u32::MAX;
/// A [`crate::PixelBatch::shade_row`] plan entry: leave the pixel as it is.
pub const KEEP: u32 = u32::MAX - 1;

/// A row's plan for [`crate::PixelBatch::shade_row`]: two slices with an entry per column.
///
/// Where `source` names a pixel of the other view's film, `object` holds that pixel's
/// object, read from the film in column order: a group of lanes then reads them in one
/// load, instead of a load per lane at scattered sources and a vector rebuilt from scalar
/// stores. Elsewhere it may hold anything.
#[derive(Clone, Copy, Debug)]
pub struct RowPlan<'a> {
    /// A pixel of the other view's film (a row-major index), [`TRACE`] or [`KEEP`].
    pub source: &'a [u32],
    /// The object of the pixel `source` names.
    pub object: &'a [u32],
}

impl<'a> RowPlan<'a> {
    /// The plan `source` (entries as [`RowPlan::source`]), its objects read from `film` into
    /// `object` (cleared first).
    pub fn read(film: &Film, source: &'a [u32], object: &'a mut Vec<u32>) -> Self {
        object.clear();
        object.extend(source.iter().map(|&s| if s < KEEP { film.object[s as usize] } else { NO_OBJECT }));
        Self { source, object }
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

impl BinnedView<'_> {
    /// Makes the pixels of row `j` as `plan` says, in one batch, into `sink`, pushing to
    /// `missed` the columns whose named sphere the pixel's ray misses; returns the pixels
    /// tested against the sphere their plan names (see [`crate::PixelBatch::shade_row`]).
    pub(crate) fn shade_row(
        &self,
        j: u32,
        plan: RowPlan<'_>,
        sink: &mut RowSink<impl Columns, impl Observe>,
        counts: &mut RayCounts,
        missed: &mut Vec<u32>,
    ) -> u64 {
        missed.clear();
        with_wavefront(|wavefront| {
            let tests = dispatch!(crate::simd::level(), simd => simd.vectorize(
                #[inline(always)]
                || self.push_row_in(simd, wavefront, (j, plan), counts, (missed, sink)),
            ));
            wavefront.shade(self.tracer, crate::cue::SeedRow::of(self.view, j), counts);
            sink.emit(wavefront, self.view, true);
            tests
        })
    }

    /// The first half of [`BinnedView::shade_row`] with the lanes of `simd`: each group of
    /// lanes of the row read from the plan, aimed and pushed into the batch (a group that
    /// hits its spheres in every lane in vector stores). The colours made without shading,
    /// and the traced pixels that see background, go straight to `sink`. Returns the pixels
    /// tested against their planned spheres.
    #[inline(always)]
    fn push_row_in<S: Simd>(
        &self,
        simd: S,
        wavefront: &mut Wavefront,
        (j, plan): (u32, RowPlan<'_>),
        counts: &mut RayCounts,
        (missed, sink): (&mut Vec<u32>, &mut RowSink<impl Columns, impl Observe>),
    ) -> u64 {
        let (tracer, view) = (self.tracer, self.view);
        let lanes = F::<S>::LEN;
        let all = (1u32 << lanes) - 1;
        let inf = F::<S>::splat(simd, f32::INFINITY);
        let origin = crate::simd::splat3(simd, view.origin);
        let splat = |x: u32| U::<S>::splat(simd, x);
        let (mut objects, mut short) = ([0u32; 16], [[KEEP; 16]; 2]);
        let mut tests = 0;
        for base in (0..plan.len()).step_by(lanes) {
            let end = (base + lanes).min(plan.len());
            let [source, object] = if end - base == lanes {
                [&plan.source[base..end], &plan.object[base..end]]
            } else {
                // The row's last, short group, its missing lanes kept.
                for (pad, part) in short.iter_mut().zip([plan.source, plan.object]) {
                    pad[..end - base].copy_from_slice(&part[base..end]);
                    pad[end - base..].fill(KEEP);
                }
                let [a, b] = &short;
                [&a[..lanes], &b[..lanes]]
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
                sink.take(base + l as usize, tracer.scene.background_rgb);
            }
            tests += u64::from(named.count_ones());
            // A group of traced and named lanes searches its tile's spheres once for all of
            // them (its traced lanes need that anyway): a named lane whose nearest sphere is
            // its own takes that hit, bit for bit its lone test's. The
            // other named lanes are tested alone, as a group of named lanes only is.
            let (mut found, mut alone) = (None, named);
            if named != 0 && traced != 0 && !self.bins.is_empty_at((base as u32, j), lanes) {
                let hits = self.hits_lanes(simd, (base as u32, j, traced | named));
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
                let c = crate::simd::each3(|a| per_object(simd, at, |o| tracer.scene.centers[o][a]));
                let r = per_object(simd, at, |o| tracer.scene.radii[o]);
                let t = crate::simd::spheres_t(simd, origin, d, (c, r), inf);
                let hit = t.simd_lt(inf).to_bitmask() as u32 & alone;
                if hit == all {
                    wavefront.push_lanes(simd, view.origin, (t, ids, d), base as u32);
                } else {
                    let (ts, dirs) = (t.as_slice(), crate::simd::each3(|a| d[a].as_slice()));
                    for l in crate::bits::ones(&[u64::from(hit)]) {
                        let l = l as usize;
                        let ray = Ray::new(view.origin, Vec3::new(dirs[0][l], dirs[1][l], dirs[2][l]));
                        let hit = Hit { t: ts[l], object: objects[l] };
                        wavefront.push_hit(&ray, hit, (base + l) as u32);
                    }
                }
                // The silhouettes the named spheres missed are traced afresh.
                let miss = alone & !hit;
                missed.extend(crate::bits::ones(&[u64::from(miss)]).map(|l| base as u32 + l));
                traced |= miss;
            }
            counts.primary += u64::from(traced.count_ones());
            if let Some((hits, own)) = found {
                self.push_found_in(simd, wavefront, (base as u32, traced | own), hits, sink);
            } else if traced != 0 {
                self.push_traced_in(simd, wavefront, (base as u32, j, traced), sink);
            }
        }
        tests
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Eye;
    use crate::render::{PixelBatch, Renderer};
    use crate::scene::Scene;
    use crate::stats::RayCounts;
    use crate::surface::NO_OBJECT;
    use crate::tracer::Tracer;

    fn scene(name: &str) -> Scene {
        crate::testing::scene(name)
    }

    /// Row `j` of `second` made by `plan` (sources on `film`) into `rgb`: the sphere tests.
    fn plan_row(
        batch: &PixelBatch<'_>,
        j: u32,
        (film, plan): (&Film, &[u32]),
        rgb: &mut [u32],
        missed: &mut Vec<u32>,
    ) -> u64 {
        let mut object = Vec::new();
        let plan = RowPlan::read(film, plan, &mut object);
        batch.shade_row(j, plan, ((rgb, None), None), &mut RayCounts::default(), missed)
    }

    /// A colour no traced pixel has: its high byte is set.
    const UNTOUCHED: u32 = 0xFF00_FF00;

    #[test]
    fn a_planned_row_is_the_full_trace_wherever_its_sphere_is_true() {
        let scene = scene("many.toml");
        let tracer = Tracer::new(&scene, 0.0);
        let (w, h) = (94, 54); // a short last group of lanes
        let view = scene.camera.view(Eye::Right, w, h);
        let mut renderer = Renderer::new();
        let batch = renderer.batch(&tracer, &view);
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
            let tests = plan_row(&batch, j, (&film, &plan), &mut rgb, &mut missed);
            let named = plan.iter().filter(|&&s| s < KEEP && film.object[s as usize] != NO_OBJECT).count();
            assert_eq!(tests, named as u64, "row {j}: one sphere test per named pixel");
            for (i, (&source, &got)) in plan.iter().zip(&rgb).enumerate() {
                let (i, k) = (i as u32, (j * w) as usize + i);
                let full = truth[k].rgb;
                let miss = source < KEEP
                    && film.object[k] != NO_OBJECT
                    && tracer.accel.intersect_one(&view.primary_ray(i, j), film.object[k]).is_none();
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
                        tracer.scene.background_rgb
                    }
                    _ if miss => {
                        retraced += 1;
                        full
                    }
                    // Shaded on a sphere it may not see first: only made.
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
            plan_row(&batch, j, (&film, &plan), &mut rgb, &mut missed);
            for i in 0..w {
                let miss = tracer.accel.intersect_one(&view.primary_ray(i, j), j % n).is_none();
                assert_eq!(missed.contains(&i), miss, "({i}, {j}), one sphere");
                if miss {
                    assert_eq!(rgb[i as usize], truth[(j * w + i) as usize].rgb, "({i}, {j}) retraced");
                }
            }
        }
        // Aimed at what each pixel sees: the full trace, whatever light bits the film holds
        // (here every bit wrong), since a planned pixel casts shadow rays of its own.
        let film = film_of(&|i, j| {
            let s = truth[(j * w + i) as usize].surface;
            s.is_hit().then_some((s.object, !s.lights))
        });
        for j in 0..h {
            let plan: Vec<u32> = (0..w).map(|i| j * w + i).collect();
            let mut rgb = vec![UNTOUCHED; w as usize];
            plan_row(&batch, j, (&film, &plan), &mut rgb, &mut missed);
            assert!(missed.is_empty(), "row {j}: every named sphere is hit");
            for i in 0..w {
                let k = (j * w + i) as usize;
                let want = if truth[k].surface.is_hit() { truth[k].rgb } else { tracer.scene.background_rgb };
                assert_eq!(rgb[i as usize], want, "({i}, {j})");
                hits += usize::from(truth[k].surface.is_hit());
            }
            // And every pixel traced afresh.
            let mut rgb = vec![UNTOUCHED; w as usize];
            batch.trace_pixels(j, 0..w, &mut counts, (&mut rgb, None));
            for i in 0..w {
                assert_eq!(rgb[i as usize], truth[(j * w + i) as usize].rgb, "({i}, {j}) traced");
            }
        }
        assert!(hits > 500 && retraced > 500, "the view sees spheres: {hits} hits, {retraced} retraced");
        assert!(kept > 500 && copied > 500, "{kept} kept, {copied} copied");
    }

    #[test]
    fn a_group_of_planned_and_traced_lanes_is_the_full_trace() {
        // Big spheres, so that many groups of lanes hit in every lane: traced lanes among
        // planned ones (true spheres, the film's light bits all wrong) enter the batch whole,
        // each lane casting its own shadow rays.
        let scene = scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.4);
        let (w, h) = (160, 90);
        let view = scene.camera.view(Eye::Right, w, h);
        let mut renderer = Renderer::new();
        let batch = renderer.batch(&tracer, &view);
        let mut plain = RayCounts::default();
        let truth: Vec<_> = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| tracer.trace_pixel(&view, i, j, &mut plain))
            .collect();
        let mut film = Film::new(w, h);
        for (k, shaded) in truth.iter().enumerate() {
            (film.object[k], film.lights[k], film.rgb[k]) = (shaded.surface.object, !shaded.surface.lights, shaded.rgb);
        }
        let (lanes, mut whole) = (crate::batch::lanes(), 0);
        let mut missed = Vec::new();
        for j in 0..h {
            let plan: Vec<u32> = (0..w).map(|i| if (i + j) % 5 == 1 { TRACE } else { j * w + i }).collect();
            let mut rgb = vec![UNTOUCHED; w as usize];
            plan_row(&batch, j, (&film, &plan), &mut rgb, &mut missed);
            assert!(missed.is_empty(), "row {j}: every planned sphere is hit");
            for i in 0..w {
                assert_eq!(rgb[i as usize], truth[(j * w + i) as usize].rgb, "({i}, {j})");
            }
            let hits = |i: u32| truth[(j * w + i) as usize].surface.is_hit();
            whole += (0..w / lanes).filter(|g| (g * lanes..(g + 1) * lanes).all(hits)).count();
        }
        assert!(whole > 100, "{whole} groups of lanes that hit in every lane");
    }
}
