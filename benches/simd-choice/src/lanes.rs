//! Helpers every lane kernel shares.
//!
//! `[T; 3]::map` is not used in kernels: it goes through `core::array::try_map`, which LLVM
//! may leave out of line, and an out-of-line function does not have the dispatched target
//! features, so every SIMD operation inside it becomes a call (measured: fearless_simd and
//! pulp ran slower than scalar that way). These `#[inline(always)]` versions keep the body
//! inside the dispatched function.

#![expect(
    clippy::inline_always,
    reason = "a SIMD kernel must inline into the function that enables its target features"
)]

use crate::hits::LIGHTS;

/// `[f(a₀), f(a₁), f(a₂)]`.
#[inline(always)]
pub fn map3<T: Copy, U>(a: [T; 3], f: impl Fn(T) -> U) -> [U; 3] {
    [f(a[0]), f(a[1]), f(a[2])]
}

/// `[f(0), f(1), f(2)]`.
#[inline(always)]
pub fn each3<U>(f: impl Fn(usize) -> U) -> [U; 3] {
    [f(0), f(1), f(2)]
}

/// `[f(0), f(1), …]`, one per light.
#[inline(always)]
pub fn each_light<U>(f: impl Fn(usize) -> U) -> [U; LIGHTS] {
    [f(0), f(1)]
}

/// Squaring steps a group of per-lane exponents needs: the binary digits of the largest.
/// Scalar, per group: the group's lanes usually share one or two materials.
#[inline(always)]
#[must_use]
pub fn exponent_bits(e: &[u32]) -> u32 {
    32 - e.iter().fold(0, |a, &e| a | e).leading_zeros()
}
