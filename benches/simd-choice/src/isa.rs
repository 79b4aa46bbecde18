//! The run-time choice of lane width, made once per process.

use std::sync::OnceLock;

/// The environment variable that forces the 4-lane fallback: `STEREOTRACE_LANES=4`.
pub const LANES_VAR: &str = "STEREOTRACE_LANES";

/// Which instruction set the lane kernels run with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Isa {
    /// 8 lanes: AVX2 with FMA (x86-64-v3).
    Avx2,
    /// 4 lanes: the portable baseline (SSE2 on x86-64; SSE4.2 where a crate's 4-lane
    /// token needs it, see each module).
    Fallback,
}

impl Isa {
    /// The best instruction set this CPU has.
    #[must_use]
    pub fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
            return Self::Avx2;
        }
        Self::Fallback
    }

    /// The instruction set for this process: [`Isa::detect`], or the fallback when
    /// `STEREOTRACE_LANES=4`. Read once; every later call returns the same answer.
    pub fn current() -> Self {
        static CURRENT: OnceLock<Isa> = OnceLock::new();
        *CURRENT.get_or_init(|| match std::env::var(LANES_VAR).as_deref() {
            Ok("4") => Self::Fallback,
            _ => Self::detect(),
        })
    }

    /// Lanes per batch.
    #[must_use]
    pub fn lanes(self) -> usize {
        match self {
            Self::Avx2 => 8,
            Self::Fallback => 4,
        }
    }
}

/// How a kernel evaluates: its `a·b + c`, and its highlight's underflow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mode {
    /// Separate or fused multiply-add.
    pub fma: Fma,
    /// Exact or floored highlight powers.
    pub highlight: Highlight,
}

impl Mode {
    /// What `shade.rs` does today: separate multiply and add, exact highlight powers.
    pub const EXACT: Self = Self { fma: Fma::Separate, highlight: Highlight::Exact };
    /// Separate multiply and add, highlight powers floored at [`HIGHLIGHT_FLOOR`].
    pub const FLOORED: Self = Self { fma: Fma::Separate, highlight: Highlight::Floored };
    /// Fused multiply-add, exact highlight powers.
    pub const FUSED: Self = Self { fma: Fma::Fused, highlight: Highlight::Exact };
}

/// Calls `$f::<FUSED, FLOORED>($args)` with the const parameters `$mode` names.
#[macro_export]
macro_rules! with_mode {
    ($mode:expr, $f:ident($($arg:expr),* $(,)?)) => {
        match ($mode.fma, $mode.highlight) {
            ($crate::Fma::Separate, $crate::Highlight::Exact) => $f::<false, false>($($arg),*),
            ($crate::Fma::Separate, $crate::Highlight::Floored) => $f::<false, true>($($arg),*),
            ($crate::Fma::Fused, $crate::Highlight::Exact) => $f::<true, false>($($arg),*),
            ($crate::Fma::Fused, $crate::Highlight::Floored) => $f::<true, true>($($arg),*),
        }
    };
}

/// 2^-63: a floored highlight treats any power of n·h below it as 0. Two factors at or above
/// it multiply to at least 2^-126, the smallest normal `f32`, so no product is subnormal.
pub const HIGHLIGHT_FLOOR: f32 = 1.084_202_2e-19;

/// How the highlight's (n·h)^e treats values that underflow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Highlight {
    /// `shade.rs`'s repeated squaring as it is. About one lit light-hit in seven underflows
    /// into subnormals (n·h < 0.11 for e = 40), and every SIMD multiply that makes one costs
    /// a microcode assist on Intel without FTZ/DAZ.
    Exact,
    /// Each square and product below [`HIGHLIGHT_FLOOR`] becomes 0. A change to the shading
    /// rule, to be made in the scalar path too; it cannot change a packed pixel (a term below
    /// 2^-63 is far under half an ulp of any value that encodes above 0).
    Floored,
}

/// How `a·b + c` is evaluated in the kernels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fma {
    /// A rounded multiply, then a rounded add: bit-identical to the scalar reference.
    Separate,
    /// The crate's `mul_add`: fused (one rounding) where the instruction set has FMA.
    Fused,
}
