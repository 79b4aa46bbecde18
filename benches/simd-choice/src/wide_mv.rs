//! `wide` lane types with `multiversion` dispatch.
//!
//! `wide` has no trait over its widths, so the kernel is generic over a small local
//! [`Lanes`] trait implemented for `f32x4` and `f32x8`. `wide` picks each operation's
//! instructions with `#[cfg(target_feature)]` when *it* is compiled, so in a portable build
//! `f32x8` is two SSE `f32x4` halves and `mul_add` is never fused, even when inlined into the
//! AVX2+FMA clone that `multiversion` makes: that clone only gains what LLVM re-derives
//! (VEX encoding, and 256-bit ops where it merges the halves).

#![expect(
    clippy::inline_always,
    reason = "a SIMD kernel must inline into the function that enables its target features"
)]

use std::ops::{Add, BitAnd, Div, Mul, Sub};

use multiversion::multiversion;
use wide::{f32x4, f32x8, u32x4, u32x8};

use crate::hits::{Hits, Scene, Shaded, LIGHTS};
use crate::isa::{Isa, Mode, HIGHLIGHT_FLOOR};
use crate::lanes::{each3, each_light, exponent_bits, map3};
use crate::with_mode;
use crate::{scalar, srgb};

/// A lane type: `f32` lanes, with masks as all-ones/all-zeros lanes of the same type.
pub trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + BitAnd<Output = Self>
{
    /// `u32` lanes of the same count.
    type U: Copy;
    /// Lane count.
    const LEN: usize;
    /// Every lane `x`.
    #[must_use]
    fn splat(x: f32) -> Self;
    /// The first [`Lanes::LEN`] values of `s`.
    #[must_use]
    fn load(s: &[f32]) -> Self;
    /// The first [`Lanes::LEN`] values of `s`.
    #[must_use]
    fn load_u(s: &[u32]) -> Self::U;
    /// Writes the lanes to the start of `s`.
    fn store(self, s: &mut [f32]);
    /// Lane-wise square root (correctly rounded).
    #[must_use]
    fn sqrt(self) -> Self;
    /// `self · b + c` with the crate's `mul_add`.
    #[must_use]
    fn mul_add(self, b: Self, c: Self) -> Self;
    /// Mask: `self > rhs`.
    #[must_use]
    fn gt(self, rhs: Self) -> Self;
    /// Mask: `u & bit != 0`.
    #[must_use]
    fn has_bit(u: Self::U, bit: u32) -> Self;
    /// Lane-wise `if self { t } else { f }` for a mask `self`.
    #[must_use]
    fn select(self, t: Self, f: Self) -> Self;
}

macro_rules! impl_lanes {
    ($f:ident, $u:ident, $n:literal) => {
        impl Lanes for $f {
            type U = $u;
            const LEN: usize = $n;
            #[inline(always)]
            fn splat(x: f32) -> Self {
                $f::splat(x)
            }
            #[inline(always)]
            fn load(s: &[f32]) -> Self {
                let s = &s[..$n];
                $f::new(std::array::from_fn(|j| s[j]))
            }
            #[inline(always)]
            fn load_u(s: &[u32]) -> $u {
                let s = &s[..$n];
                $u::new(std::array::from_fn(|j| s[j]))
            }
            #[inline(always)]
            fn store(self, s: &mut [f32]) {
                s[..$n].copy_from_slice(&self.to_array());
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $f::sqrt(self)
            }
            #[inline(always)]
            fn mul_add(self, b: Self, c: Self) -> Self {
                $f::mul_add(self, b, c)
            }
            #[inline(always)]
            fn gt(self, rhs: Self) -> Self {
                self.simd_gt(rhs)
            }
            #[inline(always)]
            fn has_bit(u: $u, bit: u32) -> Self {
                let bit = $u::splat(bit);
                $f::from_bits((u & bit).simd_eq(bit))
            }
            #[inline(always)]
            fn select(self, t: Self, f: Self) -> Self {
                $f::select(self, t, f)
            }
        }
    };
}
impl_lanes!(f32x4, u32x4, 4);
impl_lanes!(f32x8, u32x8, 8);

/// `a·b + c`: fused through the crate's `mul_add` when `FUSED`, else two rounded operations.
#[inline(always)]
fn madd<V: Lanes, const FUSED: bool>(a: V, b: V, c: V) -> V {
    if FUSED {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// a·b in glam's order, `(ax·bx + ay·by) + az·bz`.
#[inline(always)]
fn dot<V: Lanes, const FUSED: bool>(a: [V; 3], b: [V; 3]) -> V {
    madd::<V, FUSED>(a[2], b[2], madd::<V, FUSED>(a[1], b[1], a[0] * b[0]))
}

#[inline(always)]
fn load3<V: Lanes>(a: &[Vec<f32>; 3], i: usize) -> [V; 3] {
    each3(|k| V::load(&a[k][i..]))
}

/// Shades the [`Lanes::LEN`] hits from `i`.
#[inline(always)]
fn shade_lanes<V: Lanes, const FUSED: bool, const FLOORED: bool>(scene: &Scene, h: &Hits, i: usize, out: &mut Shaded) {
    let j = i..i + V::LEN;
    let (zero, one, floor) = (V::splat(0.0), V::splat(1.0), V::splat(HIGHLIGHT_FLOOR));
    let (p, n, d, c) = (load3::<V>(&h.p, i), load3::<V>(&h.n, i), load3::<V>(&h.d, i), load3::<V>(&h.c, i));
    let (kd, ks, kr) = (V::load(&h.kd[i..]), V::load(&h.ks[i..]), V::load(&h.kr[i..]));
    let (e, vis) = (V::load_u(&h.e[i..]), V::load_u(&h.vis[i..]));

    // Diffuse, and each light's n·h and whether it shines.
    let mut sum = [zero; 3];
    let mut ndh = [zero; LIGHTS];
    let mut shine = [zero; LIGHTS];
    for (k, light) in scene.lights.iter().enumerate() {
        let v = each3(|a| V::splat(light.position[a]) - p[a]);
        let rcp = one / dot::<V, FUSED>(v, v).sqrt();
        let l = map3(v, |x| x * rcp);
        let ndl = dot::<V, FUSED>(n, l);
        let lit = ndl.gt(zero) & V::has_bit(vis, 1 << k);
        sum = each3(|a| lit.select(madd::<V, FUSED>(ndl, V::splat(light.color[a]), sum[a]), sum[a]));
        // A zero-length l − d gives NaN here (glam gives 0); neither is > 0.
        let hv = each3(|a| l[a] - d[a]);
        let rcp = one / dot::<V, FUSED>(hv, hv).sqrt();
        ndh[k] = dot::<V, FUSED>(n, map3(hv, |x| x * rcp));
        shine[k] = lit & ndh[k].gt(zero);
    }
    // ndh^e per lane by repeated squaring, all lights at once: the scalar loop's products in
    // its order (acc·1 is exact). Lanes that do not shine square 0 rather than whatever n·h
    // they have, and the last square is skipped: both would only make subnormals, which
    // cost a microcode assist per instruction on Intel.
    let mut base = each_light(|k| shine[k].select(ndh[k], zero));
    let mut acc = [one; LIGHTS];
    let bits = exponent_bits(&h.e[j.clone()]);
    for bit in 0..bits {
        let take = V::has_bit(e, 1 << bit);
        for k in 0..LIGHTS {
            acc[k] = acc[k] * take.select(base[k], one);
            if FLOORED {
                acc[k] = floor.gt(acc[k]).select(zero, acc[k]);
            }
            if bit + 1 < bits {
                base[k] = base[k] * base[k];
                if FLOORED {
                    base[k] = floor.gt(base[k]).select(zero, base[k]);
                }
            }
        }
    }
    let mut spec = [zero; 3];
    for (k, light) in scene.lights.iter().enumerate() {
        let strength = ks * acc[k];
        spec = each3(|a| shine[k].select(madd::<V, FUSED>(strength, V::splat(light.color[a]), spec[a]), spec[a]));
    }
    let amb = V::splat(scene.ambient);
    for a in 0..3 {
        let diffuse = c[a] * madd::<V, FUSED>(kd, sum[a], amb);
        let view = madd::<V, FUSED>(kr, V::load(&h.mirror[a][i..]), spec[a]);
        (diffuse + view).store(&mut out.linear[a][i..]);
    }
    srgb::pack_span(&out.linear[0][j.clone()], &out.linear[1][j.clone()], &out.linear[2][j.clone()], &mut out.rgb[j]);
}

/// All whole lane groups with `V`, then the tail with the scalar reference.
#[inline(always)]
fn shade_all<V: Lanes, const FUSED: bool, const FLOORED: bool>(scene: &Scene, h: &Hits, out: &mut Shaded) {
    let whole = h.len() / V::LEN * V::LEN;
    for i in (0..whole).step_by(V::LEN) {
        shade_lanes::<V, FUSED, FLOORED>(scene, h, i, out);
    }
    scalar::shade_range::<FLOORED>(scene, h, whole..h.len(), out);
}

/// 8 lanes, cloned for AVX2+FMA; multiversion picks the clone on first call.
#[multiversion(targets("x86_64+avx2+fma"))]
fn shade_8<const FUSED: bool, const FLOORED: bool>(scene: &Scene, h: &Hits, out: &mut Shaded) {
    shade_all::<f32x8, FUSED, FLOORED>(scene, h, out);
}

/// 4 lanes, the portable build's SSE2: the forced fallback never enters a multiversioned
/// function.
fn shade_4<const FUSED: bool, const FLOORED: bool>(scene: &Scene, h: &Hits, out: &mut Shaded) {
    shade_all::<f32x4, FUSED, FLOORED>(scene, h, out);
}

/// Shades every hit with `isa`'s lane width, in `mode`.
pub fn shade(isa: Isa, mode: Mode, scene: &Scene, h: &Hits, out: &mut Shaded) {
    match isa {
        Isa::Avx2 => with_mode!(mode, shade_8(scene, h, out)),
        Isa::Fallback => with_mode!(mode, shade_4(scene, h, out)),
    }
}
