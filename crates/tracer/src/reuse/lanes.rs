//! The marking of `tree.rs` over whole vectors of entries: each entry's own segments — the
//! ray that found it, its shadow rays, its mirror ray if that met nothing — against each
//! moving sphere's washer (`swept.rs`), in lanes. Where a segment meets a
//! washer, the arc it crosses is finished in scalar code from the lanes' diamond angles
//! (`SweptRing::arc_between`). The tests are the scalar `SweptRing::touch`'s, made
//! branch-free; they are conservative, so their rounding does not matter.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{prelude::*, Simd};

use super::level::{LevelMarks, LevelRays};
use super::swept::{SweptRing, Touch};
use super::Swept;
use crate::camera::EyeView;
use crate::scene::Light;
use crate::simd::{dot, each3, load, load3, mask_of, splat3, F, M};

/// A stand-in for +∞ as a segment's end: far beyond any scene, small enough that products
/// of it stay finite or +∞ rather than NaN.
const FAR: f32 = 1e30;

/// One vector of segments `o + s·d`, 0 ≤ s ≤ `s_max`, against `ring`: per lane whether the
/// segment meets the washer, and if so the diamond angles of the ends of its part in the
/// slab and the outer cylinder, and whether its arc must be the whole circle (rounding at
/// a tangent, or an end near the axis).
#[inline(always)]
fn cross<S: Simd>(simd: S, ring: &SweptRing, o: [F<S>; 3], d: [F<S>; 3], s_max: F<S>) -> (M<S>, M<S>, F<S>, F<S>) {
    let splat = |x: f32| F::<S>::splat(simd, x);
    let (zero, one) = (splat(0.0), splat(1.0));
    let s_max = s_max.min(splat(FAR));
    // From the segment's point nearest the centre, as `SweptRing`'s scalar test does.
    let q = each3(|a| o[a] - splat3(simd, ring.center)[a]);
    let (along, dd) = (-dot::<S>(q, d), dot::<S>(d, d));
    let to_end = along.simd_ge(s_max * dd);
    let foot = along / dd.simd_gt(zero).select(dd, one);
    let s0 = along.simd_le(zero).select(zero, to_end.select(s_max, foot));
    let q = each3(|a| q[a] + s0 * d[a]);
    // The ball that holds the washer.
    let far = dot::<S>(q, q).simd_gt(splat(ring.ball2()));
    // The slab.
    let h = splat(ring.half_height);
    let flat = d[1].simd_eq(zero);
    let inv = one / flat.select(one, d[1]);
    let (a1, b1) = ((-h - q[1]) * inv, (h - q[1]) * inv);
    let (lo, hi) = (-s0, s_max - s0);
    let lo = flat.select(lo, lo.max(a1.min(b1)));
    let hi = flat.select(hi, hi.min(a1.max(b1)));
    let in_slab = flat.select(q[1].abs().simd_le(h), lo.simd_le(hi));
    // The annulus: ρ²(s) = A·s² + 2B·s + K.
    let big_a = d[0] * d[0] + d[2] * d[2];
    let big_b = q[0] * d[0] + q[2] * d[2];
    let big_k = q[0] * q[0] + q[2] * q[2];
    let rho2 = |s: F<S>| (big_a * s + splat(2.0) * big_b) * s + big_k;
    let slanted = big_a.simd_gt(zero);
    let vertex = slanted.select((-big_b / slanted.select(big_a, one)).max(lo).min(hi), lo);
    let least = rho2(vertex);
    let greatest = slanted.select(rho2(lo).max(rho2(hi)), big_k);
    let (outer2, inner2) = (splat(ring.outer * ring.outer), splat(ring.inner * ring.inner));
    let meets = !far & in_slab & least.simd_le(outer2) & greatest.simd_ge(inner2);
    // The part inside the outer cylinder, for the arc.
    let disc = big_b * big_b - big_a * (big_k - outer2);
    let clip = slanted & disc.simd_gt(zero);
    let root = disc.max(zero).sqrt();
    let a_safe = slanted.select(big_a, one);
    let lo = clip.select(lo.max((-big_b - root) / a_safe), lo);
    let hi = clip.select(hi.min((-big_b + root) / a_safe), hi);
    let pa = each3(|a| q[a] + lo * d[a]);
    let pb = each3(|a| q[a] + hi * d[a]);
    let m2 = splat(ring.margin * ring.margin);
    let near_axis = (pa[0] * pa[0] + pa[2] * pa[2]).simd_lt(m2) | (pb[0] * pb[0] + pb[2] * pb[2]).simd_lt(m2);
    let full = !lo.simd_le(hi) | hi.simd_ge(splat(FAR * 0.5)) | near_axis;
    (meets, full, diamond(simd, pa[0], -pa[2]), diamond(simd, pb[0], -pb[2]))
}

/// `swept.rs`'s diamond angle of (x, y), lane by lane.
#[inline(always)]
fn diamond<S: Simd>(simd: S, y: F<S>, x: F<S>) -> F<S> {
    let splat = |v: f32| F::<S>::splat(simd, v);
    let zero = splat(0.0);
    let (ax, ay) = (x.abs(), y.abs());
    let sum = ax + ay;
    let r = sum.simd_gt(zero).select(ay / sum.simd_gt(zero).select(sum, splat(1.0)), zero);
    let upper = y.simd_ge(zero);
    let right = x.simd_ge(zero);
    upper.select(right.select(r, splat(2.0) - r), right.select(splat(4.0) - r, splat(2.0) + r))
}

/// Unions into `marks.touch` what the segments of one vector (entries `k..`) meet, lane by
/// lane where `valid`.
#[inline(always)]
fn add<S: Simd>(
    simd: S,
    swept: &Swept,
    marks: &mut LevelMarks,
    k: usize,
    segment: ([F<S>; 3], [F<S>; 3], F<S>),
    valid: M<S>,
) {
    if !valid.any_true() {
        return;
    }
    let (o, d, s_max) = segment;
    for (r, ring) in swept.rings().iter().enumerate() {
        let (meets, full, fa, fb) = cross(simd, ring, o, d, s_max);
        let hit = meets & valid;
        if !hit.any_true() {
            continue;
        }
        let (bits, full) = (hit.to_bitmask(), full.to_bitmask());
        for l in 0..F::<S>::LEN {
            if bits & (1 << l) != 0 {
                let arc = SweptRing::arc_between(fa.as_slice()[l], fb.as_slice()[l], full & (1 << l) != 0);
                let e = k + l;
                marks.touch[e] = marks.touch[e].union(Touch { ring: r as u32, arc });
            }
        }
    }
}

/// Where the primary rays of the pixels `tags` names (columns) of row `j` of `view`, rays
/// that meet no sphere, meet the volumes: `out(tag, touch)` for each that meets one. In
/// lanes, as [`mark`].
pub(super) fn mark_background(
    swept: &Swept,
    view: &EyeView,
    (j, tags): (u32, &[u32]),
    out: &mut impl FnMut(u32, Touch),
) {
    fearless_simd::dispatch!(crate::simd::level(), simd => simd.vectorize(
        #[inline(always)]
        || background_in(simd, swept, view, (j, tags), out),
    ));
}

#[inline(always)]
fn background_in<S: Simd>(
    simd: S,
    swept: &Swept,
    view: &EyeView,
    (j, tags): (u32, &[u32]),
    out: &mut impl FnMut(u32, Touch),
) {
    let lanes = F::<S>::LEN;
    let o = splat3(simd, view.origin);
    let inf = F::<S>::splat(simd, f32::INFINITY);
    for chunk in tags.chunks(lanes) {
        let columns = F::<S>::from_fn(simd, |l| chunk.get(l).copied().unwrap_or(chunk[0]) as f32);
        let d = view.primary_dirs_at(simd, columns, j);
        let mut touches = [Touch::NONE; 16];
        for (r, ring) in swept.rings().iter().enumerate() {
            let (meets, full, fa, fb) = cross(simd, ring, o, d, inf);
            let (bits, full) = (meets.to_bitmask(), full.to_bitmask());
            for (l, touch) in touches.iter_mut().enumerate().take(chunk.len()) {
                if bits & (1 << l) != 0 {
                    let arc = SweptRing::arc_between(fa.as_slice()[l], fb.as_slice()[l], full & (1 << l) != 0);
                    *touch = touch.union(Touch { ring: r as u32, arc });
                }
            }
        }
        for (&tag, &touch) in chunk.iter().zip(&touches) {
            if touch.is_some() {
                out(tag, touch);
            }
        }
    }
}

/// The marking over the whole vectors of `level`'s entries (whose subtrees are already in
/// `marks.touch`), every one of them; returns how many that is. The level's columns are
/// padded to whole vectors: the lanes past its end read whatever they hold and are masked
/// out. `marks.own[e]` says whether entry e's own ray is to be tested; `first` that this is
/// level 0 (whose known light bits cast no shadow rays).
#[inline(always)]
pub(super) fn mark<S: Simd>(
    simd: S,
    (swept, lights): (&Swept, &[Light]),
    level: &LevelRays<'_>,
    marks: &mut LevelMarks,
    first: bool,
) -> usize {
    let (lanes, n) = (F::<S>::LEN, level.len);
    let whole = n.div_ceil(lanes) * lanes;
    debug_assert!(level.capacity >= whole && marks.touch.len() >= whole, "the level is padded to whole vectors");
    let zero = F::<S>::splat(simd, 0.0);
    for k in (0..whole).step_by(lanes) {
        let bits =
            |f: &dyn Fn(usize) -> bool| (0..lanes).fold(0u64, |b, l| b | (u64::from(k + l < n && f(k + l)) << l));
        // The ray that found each entry.
        let mine = mask_of(simd, bits(&|e| marks.own[e]));
        let incoming = (load3(simd, level.o, k), load3(simd, level.d, k), load(simd, level.t, k));
        add(simd, swept, marks, k, incoming, mine);
        let (p, n) = (load3(simd, level.p, k), load3(simd, level.n, k));
        // The shadow rays: towards each light the surface faces, unless the bits are known.
        let traced = mask_of(simd, bits(&|e| !(first && level.known[e])));
        for light in lights {
            let to = each3(|a| splat3(simd, light.position)[a] - p[a]);
            let faces = dot::<S>(n, to).simd_gt(zero);
            add(simd, swept, marks, k, (p, to, F::<S>::splat(simd, 1.0)), traced & faces);
        }
        // The mirror rays that met nothing, to infinity.
        let lost = mask_of(simd, bits(&|e| level.reflects[e] && !marks.mirror_hit[e]));
        let v = load3(simd, level.v, k);
        let vn = dot::<S>(v, n);
        let r = each3(|a| v[a] - F::<S>::splat(simd, 2.0) * vn * n[a]);
        add(simd, swept, marks, k, (p, r, F::<S>::splat(simd, f32::INFINITY)), lost);
    }
    whole
}

#[cfg(test)]
pub(super) mod tests {
    use fearless_simd::dispatch;
    use glam::Vec3;

    use super::*;
    use crate::scene::Motion;

    /// Lane 0 of [`cross`] with the segment in every lane, as an arc.
    fn lane0<S: Simd>(simd: S, ring: &SweptRing, (o, d, s_max): (Vec3, Vec3, f32)) -> Option<super::super::Arc> {
        let (meets, full, fa, fb) = cross(simd, ring, splat3(simd, o), splat3(simd, d), F::<S>::splat(simd, s_max));
        (meets.to_bitmask() & 1 != 0)
            .then(|| SweptRing::arc_between(fa.as_slice()[0], fb.as_slice()[0], full.to_bitmask() & 1 != 0))
    }

    /// [`lane0`] at the machine's SIMD level.
    pub(in crate::reuse) fn lane0_of(ring: &SweptRing, segment: (Vec3, Vec3, f32)) -> Option<super::super::Arc> {
        dispatch!(crate::simd::level(), simd => lane0(simd, ring, segment))
    }

    /// The lanes say what the scalar `SweptRing::touch` says: the same segments meet the
    /// washer, crossing the same arcs (to the slack), on segments of every kind.
    #[test]
    fn the_lanes_meet_what_the_scalar_test_meets() {
        let motion = Motion::Orbit { center: Vec3::new(0.0, 1.2, 15.0), radius: 3.6, period_s: 8.0, phase_deg: 0.0 };
        let ring = SweptRing::of(0, 0.45, &motion).expect("an orbit");
        let mut rng = crate::testing::XorShift::new(12345);
        let mut next = || rng.unit();
        let (mut met, mut total) = (0, 0);
        for _ in 0..4000 {
            let o = Vec3::new(12.0 * next() - 6.0, 4.0 * next() - 1.0, 10.0 * next() + 10.0);
            let d = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let s_max = [1.0, 6.0, f32::INFINITY][(next() * 2.99) as usize];
            let scalar = ring.touch(o, d, s_max);
            let lanes = dispatch!(crate::simd::level(), simd => lane0(simd, &ring, (o, d, s_max)));
            total += 1;
            assert_eq!(scalar.is_some(), lanes.is_some(), "{o} + s·{d}, s ≤ {s_max}");
            if let (Some(a), Some(b)) = (scalar, lanes) {
                met += 1;
                assert!(a.overlaps(b) && a.len.abs_diff(b.len) < 1 << 12, "{o} + s·{d}: {a:?} against {b:?}");
            }
        }
        assert!(met > total / 20, "enough segments meet the washer: {met} of {total}");
    }
}
