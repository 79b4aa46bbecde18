//! `fearless_simd`: the kernel is an `#[inline(always)]` function generic over `S: Simd`,
//! on the native-width vector `S::f32s` (8 lanes on `Avx2`, 4 on `Sse4_2`/`Sse2`, 16 on
//! `Avx512`) with ordinary operators; one `dispatch!` at the top runs it with the chosen
//! [`Level`]'s target features.
//!
//! `Level::new()` returns the best level (here AVX-512, which the issue does not want), so
//! the level is narrowed first: `as_avx2()` for 8 lanes, `Level::baseline()` (SSE2) or
//! `as_sse4_2()` for 4. `mul_add` is fused on `Avx2`/`Avx512` and a separate multiply and add
//! on SSE levels; `*` then `+` is never fused.

#![expect(
    clippy::inline_always,
    reason = "a SIMD kernel must inline into the function that enables its target features"
)]

use fearless_simd::{dispatch, prelude::*, Level};

use crate::hits::{Hits, Scene, Shaded, LIGHTS};
use crate::isa::{Isa, Mode, HIGHLIGHT_FLOOR};
use crate::lanes::{each3, each_light, exponent_bits, map3};
use crate::with_mode;
use crate::{scalar, srgb};

/// `a·b + c`: `mul_add` when `FUSED`, else two rounded operations.
#[inline(always)]
fn madd<S: Simd, const FUSED: bool>(a: S::f32s, b: S::f32s, c: S::f32s) -> S::f32s {
    if FUSED {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// a·b in glam's order, `(ax·bx + ay·by) + az·bz`.
#[inline(always)]
fn dot<S: Simd, const FUSED: bool>(a: [S::f32s; 3], b: [S::f32s; 3]) -> S::f32s {
    madd::<S, FUSED>(a[2], b[2], madd::<S, FUSED>(a[1], b[1], a[0] * b[0]))
}

/// Mask: `u & bit != 0`.
#[inline(always)]
fn has_bit<S: Simd>(simd: S, u: S::u32s, bit: u32) -> S::mask32s {
    let bit = S::u32s::splat(simd, bit);
    (u & bit).simd_eq(bit)
}

/// Shades the `S::f32s::LEN` hits from `i`.
#[inline(always)]
fn shade_lanes<S: Simd, const FUSED: bool, const FLOORED: bool>(
    simd: S,
    scene: &Scene,
    h: &Hits,
    i: usize,
    out: &mut Shaded,
) {
    let j = i..i + S::f32s::LEN;
    let ld = |a: &[f32]| S::f32s::from_slice(simd, &a[j.clone()]);
    let ld3 = |a: &[Vec<f32>; 3]| each3(|k| ld(&a[k]));
    let (p, n, d, c) = (ld3(&h.p), ld3(&h.n), ld3(&h.d), ld3(&h.c));
    let (kd, ks, kr) = (ld(&h.kd), ld(&h.ks), ld(&h.kr));
    let e = S::u32s::from_slice(simd, &h.e[j.clone()]);
    let vis = S::u32s::from_slice(simd, &h.vis[j.clone()]);
    let splat = |x: f32| S::f32s::splat(simd, x);
    let (zero, one, floor) = (splat(0.0), splat(1.0), splat(HIGHLIGHT_FLOOR));

    // Diffuse, and each light's n·h and whether it shines.
    let mut sum = [zero; 3];
    let mut ndh = [zero; LIGHTS];
    let mut shine = [S::mask32s::splat(simd, false); LIGHTS];
    for (k, light) in scene.lights.iter().enumerate() {
        let v = each3(|a| splat(light.position[a]) - p[a]);
        let rcp = one / dot::<S, FUSED>(v, v).sqrt();
        let l = map3(v, |x| x * rcp);
        let ndl = dot::<S, FUSED>(n, l);
        let lit = ndl.simd_gt(zero) & has_bit(simd, vis, 1 << k);
        sum = each3(|a| lit.select(madd::<S, FUSED>(ndl, splat(light.color[a]), sum[a]), sum[a]));
        // A zero-length l − d gives NaN here (glam gives 0); neither is > 0.
        let hv = each3(|a| l[a] - d[a]);
        let rcp = one / dot::<S, FUSED>(hv, hv).sqrt();
        ndh[k] = dot::<S, FUSED>(n, map3(hv, |x| x * rcp));
        shine[k] = lit & ndh[k].simd_gt(zero);
    }
    // ndh^e per lane by repeated squaring, all lights at once: the scalar loop's products in
    // its order (acc·1 is exact). Lanes that do not shine square 0 rather than whatever n·h
    // they have, and the last square is skipped: both would only make subnormals, which
    // cost a microcode assist per instruction on Intel.
    let mut base = each_light(|k| shine[k].select(ndh[k], zero));
    let mut acc = [one; LIGHTS];
    let bits = exponent_bits(&h.e[j.clone()]);
    for bit in 0..bits {
        let take = has_bit(simd, e, 1 << bit);
        for k in 0..LIGHTS {
            acc[k] *= take.select(base[k], one);
            if FLOORED {
                acc[k] = acc[k].simd_lt(floor).select(zero, acc[k]);
            }
            if bit + 1 < bits {
                base[k] = base[k] * base[k];
                if FLOORED {
                    base[k] = base[k].simd_lt(floor).select(zero, base[k]);
                }
            }
        }
    }
    let mut spec = [zero; 3];
    for (k, light) in scene.lights.iter().enumerate() {
        let strength = ks * acc[k];
        spec = each3(|a| shine[k].select(madd::<S, FUSED>(strength, splat(light.color[a]), spec[a]), spec[a]));
    }
    let amb = splat(scene.ambient);
    for a in 0..3 {
        let diffuse = c[a] * madd::<S, FUSED>(kd, sum[a], amb);
        let view = madd::<S, FUSED>(kr, ld(&h.mirror[a]), spec[a]);
        (diffuse + view).store_slice(&mut out.linear[a][j.clone()]);
    }
    srgb::pack_span(&out.linear[0][j.clone()], &out.linear[1][j.clone()], &out.linear[2][j.clone()], &mut out.rgb[j]);
}

/// All whole lane groups, then the tail with the scalar reference.
#[inline(always)]
fn shade_all<S: Simd, const FUSED: bool, const FLOORED: bool>(simd: S, scene: &Scene, h: &Hits, out: &mut Shaded) {
    let lanes = S::f32s::LEN;
    let whole = h.len() / lanes * lanes;
    for i in (0..whole).step_by(lanes) {
        shade_lanes::<S, FUSED, FLOORED>(simd, scene, h, i, out);
    }
    scalar::shade_range::<FLOORED>(scene, h, whole..h.len(), out);
}

/// The level for `isa`: AVX2 (not AVX-512) for 8 lanes, the SSE2 baseline for 4.
#[must_use]
pub fn level(isa: Isa) -> Level {
    match (isa, Level::new().as_avx2()) {
        (Isa::Avx2, Some(avx2)) => avx2.level(),
        _ => Level::baseline(),
    }
}

/// The SSE4.2 level where the CPU has it (else the baseline): the better 4-lane fallback.
#[must_use]
pub fn sse4_2() -> Level {
    Level::new().as_sse4_2().map_or_else(Level::baseline, Simd::level)
}

/// Shades every hit at `level`, in `mode`.
pub fn shade_at(level: Level, mode: Mode, scene: &Scene, h: &Hits, out: &mut Shaded) {
    with_mode!(mode, run(level, scene, h, out));
}

/// The one dispatch point: runs the kernel with `level`'s target features.
fn run<const FUSED: bool, const FLOORED: bool>(level: Level, scene: &Scene, h: &Hits, out: &mut Shaded) {
    dispatch!(level, simd => shade_all::<_, FUSED, FLOORED>(simd, scene, h, out));
}

/// Shades every hit with `isa`'s lane width, in `mode`.
pub fn shade(isa: Isa, mode: Mode, scene: &Scene, h: &Hits, out: &mut Shaded) {
    shade_at(level(isa), mode, scene, h, out);
}
