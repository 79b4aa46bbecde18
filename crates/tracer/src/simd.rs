//! The one choice of instruction set for the lane kernels, made once per process.
//!
//! The shading kernels (`wavefront/lanes.rs`) are generic over `fearless_simd`'s [`Simd`]
//! token and run at the [`Level`] chosen here: 8 lanes with AVX2 and FMA on x86-64 CPUs
//! that have them, otherwise the portable 4-lane baseline (SSE2 on x86-64, NEON on
//! aarch64). The build itself stays portable: nothing in the repository sets `target-cpu`.
//! `STEREOTRACE_LANES=4` forces the 4-lane path (CI runs the image tests both ways).
//!
//! Every kernel uses separate multiplies and adds (never `mul_add`), and IEEE division and
//! square root, so each lane computes bit-for-bit what the scalar code does: the lane width
//! changes speed, never an image.
//!
//! [`Simd`]: fearless_simd::Simd

use std::sync::OnceLock;

use fearless_simd::{Level, Simd};

/// The environment variable that forces the 4-lane fallback when set to `4`.
pub const LANES_VAR: &str = "STEREOTRACE_LANES";

/// The level the kernels run at, and its lane width.
fn chosen() -> (Level, usize) {
    static CHOSEN: OnceLock<(Level, usize)> = OnceLock::new();
    *CHOSEN.get_or_init(|| {
        let forced = std::env::var(LANES_VAR).is_ok_and(|v| v.trim() == "4");
        match Level::new().as_avx2() {
            Some(avx2) if !forced => (avx2.level(), 8),
            _ => (Level::baseline(), 4),
        }
    })
}

/// The level the lane kernels run at.
pub(crate) fn level() -> Level {
    chosen().0
}

/// How many lanes the shading kernels run with in this process: 8 (AVX2 + FMA) or 4.
#[must_use]
pub fn lane_width() -> usize {
    chosen().1
}
