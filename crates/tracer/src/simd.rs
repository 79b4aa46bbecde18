//! The one choice of instruction set for the lane kernels, made once per process, and the
//! lane helpers every kernel shares.
//!
//! The shading kernels (`wavefront/lanes.rs`) are generic over `fearless_simd`'s [`Simd`]
//! token and run at the [`Level`] chosen here: 8 lanes with AVX2 and FMA on x86-64 CPUs
//! that have them, otherwise the portable 4-lane baseline (SSE2 on x86-64, NEON on
//! aarch64). The build itself stays portable: nothing in the repository sets `target-cpu`.
//! `STEREOTRACE_LANES` picks a width instead: `4` forces the 4-lane path, `16` AVX-512's
//! sixteen lanes on a CPU that has them (Ice Lake's set, as `fearless_simd` detects it), `8`
//! the default's. CI runs the image tests at each width this CPU has.
//!
//! Sixteen lanes are not the default: where they were measured they were no faster
//! (`docs/performance-notes.md#sixteen-lanes`). The BVH's nodes and leaves are eight wide,
//! so their tests run on eight lanes (`f32x8`) at every level.
//!
//! Every kernel uses separate multiplies and adds (never `mul_add`), and IEEE division and
//! square root, so each lane computes bit-for-bit what the scalar code does: the lane width
//! changes speed, never an image.
//!
//! [`Simd`]: fearless_simd::Simd

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use std::sync::OnceLock;

use fearless_simd::{prelude::*, Level, Simd, SimdFloat};
use glam::Vec3;

/// The environment variable that picks the lane width: `4`, `8` or `16`.
pub const LANES_VAR: &str = "STEREOTRACE_LANES";

/// The lane widths [`STEREOTRACE_LANES`](LANES_VAR) may ask for.
pub const LANE_WIDTHS: [usize; 3] = [4, 8, 16];

/// The level of `lanes` lanes on this CPU (4 on every CPU; 8 with AVX2 and FMA; 16 with
/// AVX-512), or `None` where it has no such level.
#[must_use]
pub fn level_of(lanes: usize) -> Option<Level> {
    match lanes {
        4 => Some(Level::baseline()),
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        8 => Level::new().as_avx2().map(Simd::level),
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        16 => Level::new().as_avx512().map(Simd::level),
        _ => None,
    }
}

/// Every level this CPU has, narrowest first: 4 lanes, then 8 and 16 where it has them
/// (what the tests hold to the same bits).
#[must_use]
pub fn levels() -> Vec<Level> {
    LANE_WIDTHS.iter().filter_map(|&lanes| level_of(lanes)).collect()
}

/// The lane width `STEREOTRACE_LANES` asks for, if it is set to one this CPU has (the
/// viewer refuses any other value before tracing: `check_lanes_env`).
#[must_use]
pub fn asked_lanes() -> Option<usize> {
    let asked = std::env::var(LANES_VAR).ok()?.trim().parse().ok()?;
    level_of(asked).map(|_| asked)
}

/// The level the kernels run at, and its lane width.
#[inline]
fn chosen() -> (Level, usize) {
    static CHOSEN: OnceLock<(Level, usize)> = OnceLock::new();
    *CHOSEN.get_or_init(|| {
        let lanes = asked_lanes().unwrap_or(if level_of(8).is_some() { 8 } else { 4 });
        (level_of(lanes).unwrap_or_else(Level::baseline), lanes)
    })
}

/// The level the lane kernels run at (the instruction set of [`lane_width`]'s lanes). Other
/// crates' kernels (stereo's scanline reprojection) dispatch on it too, so that one process
/// runs one instruction set and `STEREOTRACE_LANES=4` reaches them as well.
#[inline]
#[must_use]
pub fn level() -> Level {
    chosen().0
}

/// The widest instruction set of this CPU (AVX-512's 16 lanes where it has them, else as
/// [`level`]), or [`level`] when `STEREOTRACE_LANES` picks a width. Only for a kernel whose
/// results are shown not to depend on the lane width, and that gains from the width: the
/// timewarp's warp (`stereo`'s `warp/`), whose tests compare its bytes at every width. The
/// shading kernels stay at [`level`], 8 lanes unless asked: sixteen were not faster.
#[must_use]
pub fn widest_level() -> Level {
    static WIDEST: OnceLock<Level> = OnceLock::new();
    *WIDEST.get_or_init(|| if asked_lanes().is_some() || lane_width() == 4 { level() } else { Level::new() })
}

/// How many lanes the shading kernels run with in this process: 8 (AVX2 + FMA), 4, or 16
/// when `STEREOTRACE_LANES=16` asks for them.
#[must_use]
pub fn lane_width() -> usize {
    chosen().1
}

pub(crate) type F<S> = <S as Simd>::f32s;
pub(crate) type U<S> = <S as Simd>::u32s;
pub(crate) type M<S> = <S as Simd>::mask32s;

/// `[f(0), f(1), f(2)]`, kept inline (`array::map` may not be, and an out-of-line call
/// loses the dispatched target features).
#[inline(always)]
pub(crate) fn each3<T>(f: impl Fn(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// Lanes `j..` of a column.
#[inline(always)]
pub(crate) fn load<S: Simd>(simd: S, column: &[f32], j: usize) -> F<S> {
    F::<S>::from_slice(simd, &column[j..j + F::<S>::LEN])
}

/// Lanes `j..` of three columns.
#[inline(always)]
pub(crate) fn load3<S: Simd>(simd: S, c: &[Vec<f32>; 3], j: usize) -> [F<S>; 3] {
    each3(|a| load(simd, &c[a], j))
}

/// Stores a vector of three into lanes `j..` of three columns.
#[inline(always)]
pub(crate) fn store3<S: Simd>(v: [F<S>; 3], c: &mut [Vec<f32>; 3], j: usize) {
    for (a, x) in v.iter().enumerate() {
        x.store_slice(&mut c[a][j..j + F::<S>::LEN]);
    }
}

/// glam's `Vec3::dot`, lane by lane.
#[inline(always)]
pub(crate) fn dot<S: Simd>(a: [F<S>; 3], b: [F<S>; 3]) -> F<S> {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// A vector splatted across the lanes.
#[inline(always)]
pub(crate) fn splat3<S: Simd>(simd: S, v: Vec3) -> [F<S>; 3] {
    [F::<S>::splat(simd, v.x), F::<S>::splat(simd, v.y), F::<S>::splat(simd, v.z)]
}

/// Lane `l` of a vector of three.
#[inline(always)]
pub(crate) fn lane3<S: Simd>(v: &[F<S>; 3], l: usize) -> Vec3 {
    Vec3::new(v[0].as_slice()[l], v[1].as_slice()[l], v[2].as_slice()[l])
}

/// The direction to light `k` and its distance, as [`Tracer::to_light`] computes them.
#[inline(always)]
pub(crate) fn to_light<S: Simd>(simd: S, light: Vec3, p: [F<S>; 3]) -> ([F<S>; 3], F<S>) {
    let light = splat3(simd, light);
    let v = each3(|a| light[a] - p[a]);
    let dist = dot::<S>(v, v).sqrt();
    let recip = F::<S>::splat(simd, 1.0) / dist;
    (each3(|a| v[a] * recip), dist)
}

/// [`crate::spawn_ray`]'s origins for rays leaving the points `p` (normals `n`) along `dir`, lane
/// by lane.
#[inline(always)]
pub(crate) fn spawn_origins<S: Simd>(simd: S, p: [F<S>; 3], n: [F<S>; 3], dir: [F<S>; 3]) -> [F<S>; 3] {
    use crate::ray::{SPAWN_ULPS_IN, SPAWN_ULPS_OUT};
    let zero = F::<S>::splat(simd, 0.0);
    // The largest |pᵢ| (as the largest bit pattern, for finite p), its exponent field at
    // least the smallest normal's, times 2⁻²³: ulp(‖p‖∞), as `ray::ulp_of_largest`.
    let max = |a: F<S>, b: F<S>| a.simd_gt(b).select(a, b);
    let abs = each3(|a| p[a].abs());
    let largest: U<S> = max(abs[0], max(abs[1], abs[2])).bitcast();
    let exponent = largest & 0x7f80_0000;
    let floor = U::<S>::splat(simd, f32::MIN_POSITIVE.to_bits());
    let ulp = exponent.simd_gt(floor).select(exponent, floor).bitcast::<F<S>>() * f32::EPSILON;
    let outwards = dot::<S>(dir, n).simd_ge(zero);
    let ulps = outwards.select(F::<S>::splat(simd, SPAWN_ULPS_OUT), F::<S>::splat(simd, -SPAWN_ULPS_IN));
    let offset = ulps * ulp;
    each3(|a| p[a] + offset * n[a])
}

/// Lane l holds 2^l (a constant to load, not lanes to write one by one: a vector written as
/// scalars and read back whole stalls on the store-to-load forwarding).
#[inline(always)]
fn lane_bits<S: Simd>(simd: S) -> U<S> {
    const BITS: [u32; 16] = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768];
    U::<S>::from_slice(simd, &BITS[..U::<S>::LEN])
}

/// Lane l holds l.
#[inline(always)]
pub(crate) fn lane_index<S: Simd>(simd: S) -> U<S> {
    const INDEX: [u32; 16] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15];
    U::<S>::from_slice(simd, &INDEX[..U::<S>::LEN])
}

/// A mask from bit l of `bits` for each lane l.
#[inline(always)]
pub(crate) fn mask_of<S: Simd>(simd: S, bits: u64) -> M<S> {
    let bit = lane_bits(simd);
    (U::<S>::splat(simd, bits as u32) & bit).simd_eq(bit)
}

/// Each lane's ray (origin `o`, unit direction `d`) against the sphere (`center`, `radius`):
/// its nearest `t` in `(0, t_max)`, +∞ where there is none: [`spheres_t`] with one sphere.
#[inline(always)]
pub(crate) fn sphere_t<S: Simd>(simd: S, o: [F<S>; 3], d: [F<S>; 3], center: Vec3, radius: f32, t_max: F<S>) -> F<S> {
    spheres_t(simd, o, d, (splat3(simd, center), F::<S>::splat(simd, radius)), t_max)
}

/// **The ray–sphere test**, with a ray and a sphere per lane: lane l's nearest `t` in
/// `(0, t_max)` of the ray (origin `o`, unit direction `d`) against the sphere (`c`, `r`),
/// +∞ where there is none. Generic over the vector: the native lanes `F<S>` (BVH leaves,
/// screen tiles, every sphere of a small scene) or four lanes `f32x4<S>` (the packets of
/// light cells and cones); [`crate::intersect_sphere`] is its lane 0. Every query that
/// tests a sphere therefore reports bit-for-bit the same `t`.
#[inline(always)]
pub(crate) fn spheres_t<S: Simd, V: SimdFloat<S, Element = f32>>(
    simd: S,
    o: [V; 3],
    d: [V; 3],
    (c, r): ([V; 3], V),
    t_max: V,
) -> V {
    let (oc, r2, cc) = origin_terms(o, (c, r));
    nearest_root(simd, oc, d, r2, cc, t_max)
}

/// The terms of [`spheres_t`] that do not depend on the direction, as [`nearest_root`]
/// takes them: `oc` = o − c, r², |oc|² − r²; made once for the rays of a shared origin.
#[inline(always)]
pub(crate) fn origin_terms<V>(o: [V; 3], (c, r): ([V; 3], V)) -> ([V; 3], V, V)
where
    V: Copy + std::ops::Add<Output = V> + std::ops::Sub<Output = V> + std::ops::Mul<Output = V>,
{
    let oc = each3(|a| o[a] - c[a]);
    let r2 = r * r;
    (oc, r2, dot3(oc, oc) - r2)
}

/// glam's `Vec3::dot` over any lanes: `(x·x' + y·y') + z·z'`.
#[inline(always)]
fn dot3<V: Copy + std::ops::Add<Output = V> + std::ops::Mul<Output = V>>(a: [V; 3], b: [V; 3]) -> V {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The core of [`spheres_t`], also run with a sphere's origin terms precomputed once for
/// many rays from one origin (an eye's screen tiles): `oc` = origin − centre, `d` unit,
/// `r2` = r², `cc` = |oc|² − r².
///
/// Numerically stable: the discriminant is r² − |oc − (oc·d)d|², which keeps its precision
/// for distant, small spheres (Haines et al., "Precision Improvements for Ray/Sphere
/// Intersection", Ray Tracing Gems ch. 7), and the roots come from q = −b − sign(b)·√Δ as
/// cc/q and q, avoiding the cancellation of (−b ± √Δ).
#[inline(always)]
pub(crate) fn nearest_root<S: Simd, V: SimdFloat<S, Element = f32>>(
    simd: S,
    oc: [V; 3],
    d: [V; 3],
    r2: V,
    cc: V,
    t_max: V,
) -> V {
    let (zero, inf) = (V::splat(simd, 0.0), V::splat(simd, f32::INFINITY));
    let Some((touched, t0, q)) = roots::<S, V, false>(simd, oc, d, r2, cc) else {
        return inf;
    };
    let (near, far) = (t0.min_precise(q), t0.max_precise(q));
    let near_ok = near.simd_gt(zero) & near.simd_lt(t_max);
    let far_ok = far.simd_gt(zero) & far.simd_lt(t_max);
    let t = near_ok.select(near, far_ok.select(far, inf));
    touched.select(t, inf)
}

/// Whether [`nearest_root`] gives a root (`t` < ∞), lane by lane, with its arithmetic but
/// without ordering the two roots: a root lies in (0, `t_max`) whichever of cc/q and q is
/// the nearer, so an any-hit test asks it of both. The same answer bit for bit (a test
/// checks), with the `min`, `max` and selects left out, and a lane whose sphere lies wholly
/// behind the origin dropped before the roots are made: an occlusion ray's line goes back
/// into the molecule, and meets spheres there that no ray can hit.
#[inline(always)]
pub(crate) fn has_root<S: Simd, V: SimdFloat<S, Element = f32>>(
    simd: S,
    oc: [V; 3],
    d: [V; 3],
    r2: V,
    cc: V,
    t_max: V,
) -> bool {
    let Some((touched, t0, q)) = roots::<S, V, true>(simd, oc, d, r2, cc) else {
        return false;
    };
    let zero = V::splat(simd, 0.0);
    let within = |t: V| t.simd_gt(zero) & t.simd_lt(t_max);
    (touched & (within(t0) | within(q))).any_true()
}

/// [`nearest_root`]'s two roots, unordered: the lanes whose line meets the sphere, cc/q and
/// q; `None` when no lane's does. `AHEAD`: only the lanes whose sphere can lie ahead count
/// as met, the others dropped before the roots are made: a sphere the origin lies outside
/// of (cc > 0) with its centre behind it (b = oc·d > 0) has both roots negative (their
/// product cc, their sum −2b), in floating point too (q = −b − √Δ < 0, so cc/q < 0).
#[inline(always)]
fn roots<S: Simd, V: SimdFloat<S, Element = f32>, const AHEAD: bool>(
    simd: S,
    oc: [V; 3],
    d: [V; 3],
    r2: V,
    cc: V,
) -> Option<(V::Mask, V, V)> {
    let zero = V::splat(simd, 0.0);
    let b = dot3(oc, d);
    let p = each3(|a| oc[a] - b * d[a]);
    let disc = r2 - dot3(p, p);
    let touched = disc.simd_ge(zero);
    let touched = if AHEAD { touched & (cc.simd_le(zero) | b.simd_lt(zero)) } else { touched };
    if !touched.any_true() {
        return None;
    }
    let sq = disc.sqrt();
    let q = b.simd_gt(zero).select(-b - sq, -b + sq);
    Some((touched, cc / q, q))
}

#[cfg(test)]
mod tests {
    use fearless_simd::dispatch;
    use glam::Vec3;
    use proptest::prelude::*;

    use super::*;

    /// (`nearest_root` gives a root, `has_root`) for the lanes' spheres: lane k's origin
    /// less its centre `at(k).0`, put on the sphere (its radius `at(k).1` times `at(k).2`)
    /// unless that is 0.
    fn answers<S: Simd>(simd: S, at: &dyn Fn(usize) -> ([f32; 3], f32, f32), d: Vec3, t_max: f32) -> (bool, bool) {
        let n = F::<S>::LEN;
        let col = |f: &dyn Fn(usize) -> f32| F::<S>::from_slice(simd, &(0..n).map(f).collect::<Vec<_>>());
        let oc = each3(|a| {
            col(&|k| {
                let (o, r, on) = at(k);
                let v = Vec3::from(o);
                if on > 0.0 && v.length() > 1e-3 {
                    (v.normalize() * r * on)[a]
                } else {
                    v[a]
                }
            })
        });
        let r2 = col(&|k| at(k).1 * at(k).1);
        let cc = dot3(oc, oc) - r2;
        let (d, t_max) = (splat3(simd, d), F::<S>::splat(simd, t_max));
        let t = nearest_root(simd, oc, d, r2, cc, t_max);
        (t.simd_lt(F::<S>::splat(simd, f32::INFINITY)).any_true(), has_root(simd, oc, d, r2, cc, t_max))
    }

    proptest! {
        /// On lanes of spheres about rays from near and far (the origin on the sphere, inside
        /// it, tangent rays among them), [`has_root`] answers as [`nearest_root`] does.
        #[test]
        fn has_root_is_nearest_roots_answer(
            lanes in proptest::collection::vec((
                proptest::array::uniform3(-3.0f32..3.0),
                0.0f32..2.0,
                prop_oneof![Just(0.0f32), Just(1.0), 0.0f32..2.0],
            ), 8),
            dir in proptest::array::uniform3(-1.0f32..1.0),
            t_max in prop_oneof![Just(f32::INFINITY), 0.01f32..10.0],
            lane in 0usize..8,
        ) {
            let d = Vec3::from(dir).try_normalize().unwrap_or(Vec3::X);
            let at = |k: usize| lanes[(k + lane) % lanes.len()];
            for level in levels() {
                let (want, got) = dispatch!(level, simd => answers(simd, &at, d, t_max));
                prop_assert_eq!(got, want, "{:?}", level);
            }
        }
    }
}
