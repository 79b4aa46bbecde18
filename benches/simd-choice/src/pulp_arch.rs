//! `pulp`: the kernel is a [`WithSimd`] operation, generic over `S: Simd`, whose methods
//! name every operation and width (`simd.add_f32s(a, b)`); a token's `vectorize` runs it with
//! that token's target features.
//!
//! `pulp::Arch::new()` on x86-64 chooses only between `V3` (AVX2+FMA), `V4` (AVX-512, behind
//! the `x86-v4` feature) and `Scalar`, whose `f32s` is a single `f32`. So the 4-lane fallback
//! is picked here by hand: `V2` (SSE4.2, x86-64-v2) when the CPU has it, else
//! `Scalar128b` (4 lanes in plain arrays, compiled for the SSE2 baseline). Note that pulp's
//! `mul_add_f32s` is always fused: on `V2` and the scalar types it is a software `fma`, so
//! the fused variant below uses `mul_add_e_f32s` ("fused if cheap"), which `V2` also routes
//! to the software `fma`.

#![expect(
    clippy::inline_always,
    reason = "a SIMD kernel must inline into the function that enables its target features"
)]

#[cfg(target_arch = "x86_64")]
use pulp::x86::{V2, V3};
use pulp::{Scalar128b, Simd, WithSimd};

use crate::hits::{Hits, Scene, Shaded, LIGHTS};
use crate::isa::{Isa, Mode, HIGHLIGHT_FLOOR};
use crate::lanes::{each3, each_light, exponent_bits, map3};
use crate::with_mode;
use crate::{scalar, srgb};

/// Shade every hit, as one pulp operation.
struct ShadeOp<'a, const FUSED: bool, const FLOORED: bool> {
    scene: &'a Scene,
    h: &'a Hits,
    out: &'a mut Shaded,
}

impl<'a, const FUSED: bool, const FLOORED: bool> WithSimd for ShadeOp<'a, FUSED, FLOORED> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) {
        let Self { scene, h, out } = self;
        let lanes = S::F32_LANES;
        let whole = h.len() / lanes * lanes;
        let split = |a: &'a [f32]| S::as_simd_f32s(a).0;
        let split3 = |a: &'a [Vec<f32>; 3]| each3(|k| split(&a[k]));
        let (p, n, d, c, mirror) = (split3(&h.p), split3(&h.n), split3(&h.d), split3(&h.c), split3(&h.mirror));
        let (kd, ks, kr) = (split(&h.kd), split(&h.ks), split(&h.kr));
        let (e, vis) = (S::as_simd_u32s(&h.e).0, S::as_simd_u32s(&h.vis).0);
        let (zero, one, floor) = (simd.splat_f32s(0.0), simd.splat_f32s(1.0), simd.splat_f32s(HIGHLIGHT_FLOOR));
        let amb = simd.splat_f32s(scene.ambient);

        for g in 0..whole / lanes {
            let at = |a: [&[S::f32s]; 3]| each3(|k| a[k][g]);
            let (p, n, d) = (at(p), at(n), at(d));

            // Diffuse, and each light's n·h and whether it shines.
            let mut sum = [zero; 3];
            let mut ndh = [zero; LIGHTS];
            let mut shine = [simd.greater_than_f32s(zero, zero); LIGHTS];
            for (k, light) in scene.lights.iter().enumerate() {
                let v = each3(|a| simd.sub_f32s(simd.splat_f32s(light.position[a]), p[a]));
                let rcp = simd.div_f32s(one, simd.sqrt_f32s(dot::<S, FUSED>(simd, v, v)));
                let l = map3(v, |x| simd.mul_f32s(x, rcp));
                let ndl = dot::<S, FUSED>(simd, n, l);
                let lit = simd.and_m32s(simd.greater_than_f32s(ndl, zero), has_bit(simd, vis[g], 1 << k));
                sum = each3(|a| {
                    let added = madd::<S, FUSED>(simd, ndl, simd.splat_f32s(light.color[a]), sum[a]);
                    simd.select_f32s(lit, added, sum[a])
                });
                // A zero-length l − d gives NaN here (glam gives 0); neither is > 0.
                let hv = each3(|a| simd.sub_f32s(l[a], d[a]));
                let rcp = simd.div_f32s(one, simd.sqrt_f32s(dot::<S, FUSED>(simd, hv, hv)));
                ndh[k] = dot::<S, FUSED>(simd, n, map3(hv, |x| simd.mul_f32s(x, rcp)));
                shine[k] = simd.and_m32s(lit, simd.greater_than_f32s(ndh[k], zero));
            }
            // ndh^e per lane by repeated squaring, all lights at once: the scalar loop's products
            // in its order (acc·1 is exact). Lanes that do not shine square 0 rather than whatever
            // n·h they have, and the last square is skipped: both would only make subnormals,
            // which cost a microcode assist per instruction on Intel.
            let i = g * lanes;
            let mut base = each_light(|k| simd.select_f32s(shine[k], ndh[k], zero));
            let mut acc = [one; LIGHTS];
            let bits = exponent_bits(&h.e[i..i + lanes]);
            for bit in 0..bits {
                let take = has_bit(simd, e[g], 1 << bit);
                for k in 0..LIGHTS {
                    acc[k] = simd.mul_f32s(acc[k], simd.select_f32s(take, base[k], one));
                    if FLOORED {
                        acc[k] = simd.select_f32s(simd.less_than_f32s(acc[k], floor), zero, acc[k]);
                    }
                    if bit + 1 < bits {
                        base[k] = simd.mul_f32s(base[k], base[k]);
                        if FLOORED {
                            base[k] = simd.select_f32s(simd.less_than_f32s(base[k], floor), zero, base[k]);
                        }
                    }
                }
            }
            let mut spec = [zero; 3];
            for (k, light) in scene.lights.iter().enumerate() {
                let strength = simd.mul_f32s(ks[g], acc[k]);
                spec = each3(|a| {
                    let added = madd::<S, FUSED>(simd, strength, simd.splat_f32s(light.color[a]), spec[a]);
                    simd.select_f32s(shine[k], added, spec[a])
                });
            }
            for a in 0..3 {
                let diffuse = simd.mul_f32s(c[a][g], madd::<S, FUSED>(simd, kd[g], sum[a], amb));
                let view = madd::<S, FUSED>(simd, kr[g], mirror[a][g], spec[a]);
                S::as_mut_simd_f32s(&mut out.linear[a][i..i + lanes]).0[0] = simd.add_f32s(diffuse, view);
            }
            let j = i..i + lanes;
            srgb::pack_span(
                &out.linear[0][j.clone()],
                &out.linear[1][j.clone()],
                &out.linear[2][j.clone()],
                &mut out.rgb[j],
            );
        }
        scalar::shade_range::<FLOORED>(scene, h, whole..h.len(), out);
    }
}

/// `a·b + c`: `mul_add_e_f32s` when `FUSED`, else two rounded operations.
#[inline(always)]
fn madd<S: Simd, const FUSED: bool>(simd: S, a: S::f32s, b: S::f32s, c: S::f32s) -> S::f32s {
    if FUSED {
        simd.mul_add_e_f32s(a, b, c)
    } else {
        simd.add_f32s(simd.mul_f32s(a, b), c)
    }
}

/// a·b in glam's order, `(ax·bx + ay·by) + az·bz`.
#[inline(always)]
fn dot<S: Simd, const FUSED: bool>(simd: S, a: [S::f32s; 3], b: [S::f32s; 3]) -> S::f32s {
    madd::<S, FUSED>(simd, a[2], b[2], madd::<S, FUSED>(simd, a[1], b[1], simd.mul_f32s(a[0], b[0])))
}

/// Mask: `u & bit != 0`.
#[inline(always)]
fn has_bit<S: Simd>(simd: S, u: S::u32s, bit: u32) -> S::m32s {
    let bit = simd.splat_u32s(bit);
    simd.equal_u32s(simd.and_u32s(u, bit), bit)
}

/// Runs the kernel with the token for `isa`: `V3` for 8 lanes, else `V2`, else `Scalar128b`.
fn run<const FUSED: bool, const FLOORED: bool>(isa: Isa, scene: &Scene, h: &Hits, out: &mut Shaded) {
    let op = ShadeOp::<FUSED, FLOORED> { scene, h, out };
    #[cfg(target_arch = "x86_64")]
    {
        if isa == Isa::Avx2 {
            if let Some(v3) = V3::try_new() {
                return Simd::vectorize(v3, op);
            }
        }
        if let Some(v2) = V2::try_new() {
            return Simd::vectorize(v2, op);
        }
    }
    let _ = isa;
    Scalar128b.vectorize(op);
}

/// Shades every hit with `isa`'s lane width, in `mode`.
pub fn shade(isa: Isa, mode: Mode, scene: &Scene, h: &Hits, out: &mut Shaded) {
    with_mode!(mode, run(isa, scene, h, out));
}

fn run_scalar128<const FUSED: bool, const FLOORED: bool>(scene: &Scene, h: &Hits, out: &mut Shaded) {
    Scalar128b.vectorize(ShadeOp::<FUSED, FLOORED> { scene, h, out });
}

/// Shades every hit with pulp's portable 4-lane `Scalar128b` (no SSE4.2 token): what a CPU
/// without SSE4.2 would run.
pub fn shade_scalar128(mode: Mode, scene: &Scene, h: &Hits, out: &mut Shaded) {
    with_mode!(mode, run_scalar128(scene, h, out));
}
