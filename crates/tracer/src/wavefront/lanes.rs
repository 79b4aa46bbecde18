//! The wavefront's stages over SIMD lanes: `S::f32s::LEN` entries at a time (8 with AVX2,
//! 4 on the baseline), generic over `fearless_simd`'s [`Simd`] token so that one dispatch
//! (in `Wavefront::shade`) picks the instruction set for all of them.
//!
//! Each lane repeats the scalar stage's operations in the scalar stage's order: glam's dot
//! product `(x·x' + y·y') + z·z'`, normalisation as `v · (1/√(v·v))`, a separate multiply
//! and add where glam has them, never `mul_add`. IEEE arithmetic then gives every lane the
//! scalar result bit for bit, which the tests check against the recursive path. What
//! cannot run in lanes — shadow and mirror queries through the acceleration structures, and
//! `powf` for exponents that are not whole — runs per lane on the values the lanes made.
//! A batch's last entries, fewer than a vector, take the scalar stages.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{prelude::*, Simd};

use super::Level;
use crate::accel::ShadowLanes;
use crate::cue::SeedRow;
use crate::material::{Exponent, TINY};
use crate::simd::{dot, each3, lane3, load, load3, mask_of, spawn_origins, splat3, store3, to_light, F, U};
use crate::stats::RayCounts;
use crate::tracer::Tracer;

/// The sphere all of a vector's entries hit, if they hit one (the common case: pixels side by
/// side see one surface).
#[inline(always)]
pub(crate) fn one_object(objects: &[u32]) -> Option<u32> {
    let first = objects[0];
    objects.iter().all(|&o| o == first).then_some(first)
}

/// A per-entry value of each lane's sphere, `f(sphere)`: splatted when the lanes share one
/// (`one`, from [`one_object`]). Built lane by lane, a vector is stored as scalars and read
/// back whole, which stalls on the store-to-load forwarding; the splat does not.
#[inline(always)]
pub(crate) fn per_object<S: Simd>(simd: S, (objects, one): (&[u32], Option<u32>), f: impl Fn(usize) -> f32) -> F<S> {
    match one {
        Some(o) => F::<S>::splat(simd, f(o as usize)),
        None => F::<S>::from_fn(simd, |l| f(objects[l] as usize)),
    }
}

/// A per-entry value of the material of each lane's sphere.
#[inline(always)]
fn material<S: Simd>(simd: S, tracer: &Tracer, objects: &[u32], f: impl Fn(&crate::material::Material) -> f32) -> F<S> {
    per_object(simd, (objects, one_object(objects)), |o| f(tracer.scene.material(o)))
}

/// The per-lane values of a vector's spheres and materials, gathered once.
struct Gathered<S: Simd> {
    center: [F<S>; 3],
    color: [F<S>; 3],
    diffuse: F<S>,
    specular: F<S>,
    /// The whole highlight exponent (0 where it is evaluated by `powf`).
    exponent: U<S>,
    /// The bits of any lane's whole exponent.
    exponent_bits: u32,
    /// Lanes whose exponent is evaluated by `powf`.
    real: u64,
}

impl<S: Simd> Gathered<S> {
    #[inline(always)]
    fn of(simd: S, tracer: &Tracer, objects: &[u32]) -> Self {
        let at = (objects, one_object(objects));
        let whole = |o: usize| match tracer.scene.exponent(o) {
            Exponent::Whole(e) => e,
            Exponent::Real => 0,
        };
        let is_real = |o: usize| matches!(tracer.scene.exponent(o), Exponent::Real);
        let (exponent, exponent_bits, real) = if let Some(o) = at.1 {
            let real = if is_real(o as usize) { (1u64 << objects.len()) - 1 } else { 0 };
            (U::<S>::splat(simd, whole(o as usize)), whole(o as usize), real)
        } else {
            let exponent = U::<S>::from_fn(simd, |l| whole(objects[l] as usize));
            let bits = objects.iter().fold(0, |a, &o| a | whole(o as usize));
            let real = objects.iter().enumerate().fold(0u64, |r, (l, &o)| r | u64::from(is_real(o as usize)) << l);
            (exponent, bits, real)
        };
        let m = |o: usize| tracer.scene.material(o);
        Self {
            center: each3(|a| per_object(simd, at, |o| tracer.scene.centers[o][a])),
            color: each3(|a| per_object(simd, at, |o| m(o).color[a])),
            diffuse: per_object(simd, at, |o| m(o).diffuse),
            specular: per_object(simd, at, |o| m(o).specular),
            exponent,
            exponent_bits,
            real,
        }
    }
}

/// Stages 1–3 over whole vectors, in one pass: hit points and normals, light bits (shadow rays per vector or per
/// lane, or the bits known at level 0) and the view-independent light, then Blinn–Phong
/// highlights from the lights the bits name. Returns how many entries it did.
#[inline(always)]
pub(super) fn shade<S: Simd>(
    simd: S,
    tracer: &Tracer,
    level: &mut Level,
    first: Option<SeedRow>,
    counts: &mut RayCounts,
) -> usize {
    let lanes = F::<S>::LEN;
    let whole = level.len() / lanes * lanes;
    let one = F::<S>::splat(simd, 1.0);
    let occludes = first.is_some() && tracer.scene.settings.cues.ambient_occlusion.is_on();
    for j in (0..whole).step_by(lanes) {
        let g = Gathered::of(simd, tracer, &level.object[j..j + lanes]);
        let d = load3(simd, &level.d, j);
        // Stage 1.
        let (o, t) = (load3(simd, &level.o, j), load(simd, &level.t, j));
        let c = g.center;
        let p = each3(|a| o[a] + t * d[a]);
        let v = each3(|a| p[a] - c[a]);
        let recip = one / dot::<S>(v, v).sqrt();
        let n = each3(|a| v[a] * recip);
        store3::<S>(p, &mut level.p, j);
        store3::<S>(n, &mut level.n, j);
        // Stage 2, its ambient term occluded per lane at level 0.
        let ambient = match first {
            Some(row) if occludes => ambient_lanes(simd, tracer, level, (j, row), counts),
            _ => F::<S>::splat(simd, tracer.scene.settings.ambient),
        };
        let bits = light_vector(simd, tracer, level, j, (p, n, &g), (ambient, first.is_some()), counts);
        // Stage 3.
        let v = load3(simd, &level.v, j);
        let out = highlight_vector(simd, tracer, &level.object[j..j + lanes], [p, n, v], bits, &g);
        store3::<S>(out, &mut level.spec, j);
    }
    whole
}

/// The ambient term of the vector of level-0 entries from `j` (their hit points and
/// normals stored), on row `row`: [`Tracer::ambient_at`] per lane, the lanes' occlusion rays
/// in packets ([`Tracer::occluded_shares_in`]).
#[inline(always)]
fn ambient_lanes<S: Simd>(
    simd: S,
    tracer: &Tracer,
    level: &Level,
    (j, row): (usize, SeedRow),
    counts: &mut RayCounts,
) -> F<S> {
    let lanes = F::<S>::LEN;
    let mut hits = [(0, (glam::Vec3::ZERO, glam::Vec3::ZERO), (0, 0)); 16];
    for (l, hit) in hits[..lanes].iter_mut().enumerate() {
        let e = j + l;
        let (p, n) = (super::get3(&level.p, e), super::get3(&level.n, e));
        *hit = (level.object[e], (p, n), row.shown(level.pixel(e, row.row)));
    }
    let mut ambient = [0f32; 16];
    tracer.occluded_shares_in(simd, &hits[..lanes], &mut ambient[..lanes], counts);
    for a in &mut ambient[..lanes] {
        *a = tracer.ambient_of(*a);
    }
    F::<S>::from_slice(simd, &ambient[..lanes])
}

/// Stage 2 of the vector of entries from `j`: light bits (shadow rays per vector or per
/// lane, or the bits known at level 0) and the view-independent light with the ambient
/// term `ambient`, stored; returns the bits.
#[inline(always)]
fn light_vector<S: Simd>(
    simd: S,
    tracer: &Tracer,
    level: &mut Level,
    j: usize,
    (p, n, g): ([F<S>; 3], [F<S>; 3], &Gathered<S>),
    (ambient, first): (F<S>, bool),
    counts: &mut RayCounts,
) -> U<S> {
    let lanes = F::<S>::LEN;
    let zero = F::<S>::splat(simd, 0.0);
    let u0 = U::<S>::splat(simd, 0);
    let scene = &tracer.scene;
    let objects = &level.object[j..j + lanes];
    // Level 0's entries may come with their bits known (found by another view): which
    // lanes, and their bits, once for every light.
    let (known, given) = if first {
        let known = level.known[j..j + lanes].iter().rev().fold(0u64, |b, &k| b << 1 | u64::from(k));
        (known, U::<S>::from_slice(simd, &level.lights[j..j + lanes]))
    } else {
        (0, u0)
    };
    let mut bits = u0;
    let mut sum = [zero; 3];
    for (k, light) in scene.lights.iter().enumerate() {
        let (l, dist) = to_light(simd, light.position, p);
        let ndl = dot::<S>(n, l);
        let faces = ndl.simd_gt(zero).to_bitmask();
        let bit = U::<S>::splat(simd, 1 << k);
        // Lanes whose bits are known take them; the others cast a shadow ray.
        let mut visible = if known == 0 { 0 } else { known & faces & (given & bit).simd_ne(u0).to_bitmask() };
        let need = faces & !known;
        counts.shadow += u64::from(need.count_ones());
        if need != 0 {
            let rays = ShadowLanes { light: k, p, n, l, dist, objects };
            let spheres = (&scene.centers[..], &scene.radii[..], light.position);
            visible |= need & !tracer.accel.occluded_lanes(simd, spheres, &rays, need);
        }
        if visible != 0 {
            let visible = mask_of(simd, visible);
            bits = visible.select(bits | bit, bits);
            let color = splat3(simd, light.color);
            sum = each3(|a| visible.select(sum[a] + ndl * color[a], sum[a]));
        }
    }
    let (kd, c) = (g.diffuse, g.color);
    store3::<S>(each3(|a| c[a] * (ambient + kd * sum[a])), &mut level.diffuse, j);
    bits.store_slice(&mut level.lights[j..j + lanes]);
    bits
}

/// Stage 3 of a vector of entries: Blinn–Phong highlights from the lights the bits name,
/// seen along `d`.
#[inline(always)]
fn highlight_vector<S: Simd>(
    simd: S,
    tracer: &Tracer,
    objects: &[u32],
    [p, n, d]: [[F<S>; 3]; 3],
    bits: U<S>,
    g: &Gathered<S>,
) -> [F<S>; 3] {
    let lanes = F::<S>::LEN;
    let (zero, one) = (F::<S>::splat(simd, 0.0), F::<S>::splat(simd, 1.0));
    let (u0, inf) = (U::<S>::splat(simd, 0), F::<S>::splat(simd, f32::INFINITY));
    let ks = g.specular;
    let shiny = ks.simd_gt(zero);
    let mut out = [zero; 3];
    if !shiny.any_true() {
        return out;
    }
    let steps = 32 - g.exponent_bits.leading_zeros();
    let e = g.exponent;
    for (k, light) in tracer.scene.lights.iter().enumerate() {
        let bit = U::<S>::splat(simd, 1 << k);
        let lit = shiny & (bits & bit).simd_ne(u0);
        if !lit.any_true() {
            continue;
        }
        let l = to_light(simd, light.position, p).0;
        // `normalize_or_zero`: v · (1/|v|) where that factor is finite and > 0.
        let v = each3(|a| l[a] - d[a]);
        let recip = one / dot::<S>(v, v).sqrt();
        let ok = recip.simd_gt(zero) & recip.simd_lt(inf);
        let h = each3(|a| ok.select(v[a] * recip, zero));
        let ndh = dot::<S>(n, h);
        let shine = lit & ndh.simd_gt(zero);
        // ndh^e by repeated squaring, as `Exponent::power` does for each lane: a factor or
        // product below TINY counts as 0.
        let tiny = F::<S>::splat(simd, TINY);
        let flush = |x: F<S>| x.simd_lt(tiny).select(zero, x);
        let (mut base, mut acc) = (flush(ndh), one);
        for step in 0..steps {
            let take = (e & U::<S>::splat(simd, 1 << step)).simd_ne(u0);
            acc = take.select(flush(acc * base), acc);
            base = flush(base * base);
        }
        if g.real != 0 {
            let mut lanes_real = g.real & shine.to_bitmask();
            let mut powers = [0f32; 16];
            powers[..lanes].copy_from_slice(acc.as_slice());
            while lanes_real != 0 {
                let lane = lanes_real.trailing_zeros() as usize;
                lanes_real &= lanes_real - 1;
                let shininess = tracer.scene.material(objects[lane] as usize).shininess;
                powers[lane] = ndh.as_slice()[lane].powf(shininess);
            }
            acc = F::<S>::from_slice(simd, &powers[..lanes]);
        }
        let strength = ks * acc;
        let color = splat3(simd, light.color);
        out = each3(|a| shine.select(out[a] + strength * color[a], out[a]));
    }
    out
}

/// Stage 4 over whole vectors: the mirror rays of reflective hits, spawned in lanes and
/// traced per lane; those that meet a sphere join `next`. Returns how many entries it did.
#[inline(always)]
pub(super) fn mirrors<S: Simd>(
    simd: S,
    tracer: &Tracer,
    level: &mut Level,
    next: &mut Level,
    counts: &mut RayCounts,
) -> usize {
    let lanes = F::<S>::LEN;
    let whole = level.len() / lanes * lanes;
    let zero = F::<S>::splat(simd, 0.0);
    let background = tracer.scene.settings.background;
    let spheres = (&tracer.scene.centers[..], &tracer.scene.radii[..]);
    for j in (0..whole).step_by(lanes) {
        let objects = &level.object[j..j + lanes];
        let kr = material(simd, tracer, objects, |m| m.reflectivity);
        let reflective = kr.simd_gt(zero).to_bitmask();
        if reflective == 0 {
            continue;
        }
        let (p, n, d) = (load3(simd, &level.p, j), load3(simd, &level.n, j), load3(simd, &level.v, j));
        // r = d − 2(d·n)n, as `reflect`; then `spawn_ray`'s origin, offset along ±n.
        let twice = F::<S>::splat(simd, 2.0) * dot::<S>(d, n);
        let r = each3(|a| d[a] - twice * n[a]);
        let origin = spawn_origins(simd, p, n, r);
        tracer.accel.intersect_lanes(simd, spheres, [origin, r, n], objects, reflective, |lane, hit| {
            let e = j + lane;
            counts.reflection += 1;
            level.reflects[e] = true;
            super::set3(&mut level.mirror, e, background);
            if let Some(hit) = hit {
                next.push(lane3::<S>(&origin, lane), lane3::<S>(&r, lane), hit.t, hit.object, e as u32);
            }
        });
    }
    whole
}

/// Stage "fold" over whole vectors: each entry's radiance `D + (S + kr·L_mirror)`, or
/// `D + S` where it cast no mirror ray. Returns how many entries it did.
#[inline(always)]
pub(super) fn radiance<S: Simd>(simd: S, tracer: &Tracer, level: &mut Level) -> usize {
    let lanes = F::<S>::LEN;
    let whole = level.len() / lanes * lanes;
    for j in (0..whole).step_by(lanes) {
        let objects = &level.object[j..j + lanes];
        let (d, s, m) = (load3(simd, &level.diffuse, j), load3(simd, &level.spec, j), load3(simd, &level.mirror, j));
        let kr = material(simd, tracer, objects, |m| m.reflectivity);
        let reflects =
            mask_of(simd, level.reflects[j..j + lanes].iter().rev().fold(0u64, |b, &r| b << 1 | u64::from(r)));
        let l = each3(|a| reflects.select(d[a] + (s[a] + kr * m[a]), d[a] + s[a]));
        store3::<S>(l, &mut level.radiance, j);
    }
    whole
}
