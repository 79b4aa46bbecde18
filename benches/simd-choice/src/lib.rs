//! One shading kernel, written four ways, to choose stereotrace's runtime-dispatched SIMD crate
//! (issue 12) by measurement.
//!
//! The kernel is what `tracer/src/shade.rs` does for one hit with known light visibility
//! (Whitted 1980 with Blinn–Phong highlights), over structure-of-arrays lanes:
//!
//! ```text
//! l_k = normalize(light_k − p)          ndl_k = n·l_k        lit_k = ndl_k > 0 ∧ vis bit k
//! diffuse = c · (ambient + kd · Σ_lit ndl_k · I_k)
//! h_k = normalize_or_zero(l_k − d)      ndh_k = n·h_k
//! L = diffuse + (ks · Σ_{lit, ndh_k > 0} ndh_k^e · I_k + kr · L_mirror)
//! ```
//!
//! then packed to 8-bit sRGB with the project's exact table encoder ([`srgb`]).
//!
//! - [`scalar`]: the reference, plain `f32` and `glam::Vec3`, in shade.rs's operation order.
//! - [`wide_mv`]: `wide` lane types behind a small lane trait, `multiversion` for dispatch.
//! - [`pulp_arch`]: `pulp`'s `WithSimd` kernel, run on its `V3` (AVX2+FMA) or `V2` token.
//! - [`fearless`]: `fearless_simd`'s generic kernel over `S: Simd`, run on an `Avx2` or SSE token.
//!
//! Each SIMD version takes an [`Isa`] (8-lane AVX2+FMA or the 4-lane fallback) and a
//! [`Mode`]: [`Fma`] (separate multiply and add, bit-identical to the scalar reference, or
//! fused) and [`Highlight`] (exact, or floored so that it never computes subnormals).
//! [`Isa::current`] is the one dispatch decision a program makes: it detects the CPU once and
//! honours `STEREOTRACE_LANES=4`, which forces the fallback.

pub mod fearless;
pub mod hits;
pub mod isa;
pub mod lanes;
pub mod pulp_arch;
pub mod scalar;
pub mod srgb;
pub mod wide_mv;

pub use hits::{Hits, Light, Scene, Shaded};
pub use isa::{Fma, Highlight, Isa, Mode, HIGHLIGHT_FLOOR};
