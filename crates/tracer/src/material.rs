//! Surface materials (Whitted 1980, with Blinn–Phong highlights) and how each one's
//! highlight exponent is evaluated.

use glam::Vec3;

/// Surface material (Whitted 1980 with Blinn–Phong highlights).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Linear albedo, each channel 0..1.
    pub color: Vec3,
    /// Lambert diffuse coefficient, 0..1.
    pub diffuse: f32,
    /// Highlight strength, 0..1.
    pub specular: f32,
    /// Blinn–Phong exponent, ≥ 1.
    pub shininess: f32,
    /// Mirror reflectivity, 0..1.
    pub reflectivity: f32,
}

impl Default for Material {
    fn default() -> Self {
        Self { color: Vec3::ONE, diffuse: 0.7, specular: 0.0, shininess: 32.0, reflectivity: 0.0 }
    }
}

/// The smallest factor or product the highlight's repeated squaring keeps (2⁻⁶³): below
/// it, a term counts as 0.
pub(crate) const TINY: f32 = 1.0 / 9_223_372_036_854_775_808.0;

/// How a material's highlight exponent is evaluated: by repeated squaring for whole
/// exponents up to 256 (the common case, several times faster than `powf`), `powf`
/// otherwise. Decided once per material when the tracer is updated; every eye and mode
/// shades through [`Exponent::power`], so the choice never makes two paths disagree.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) enum Exponent {
    /// A whole exponent.
    Whole(u32),
    /// Any other exponent.
    #[default]
    Real,
}

impl Exponent {
    /// The evaluation of `shininess`.
    pub(crate) fn of(shininess: f32) -> Self {
        if shininess.fract() == 0.0 && (0.0..=256.0).contains(&shininess) {
            Self::Whole(shininess as u32)
        } else {
            Self::Real
        }
    }

    /// `base^shininess`, with `self` = [`Exponent::of`]`(shininess)`, for `base` in
    /// (0, 1] (a highlight's n·h).
    ///
    /// A whole exponent is taken by repeated squaring in which every factor and product
    /// below [`TINY`] counts as 0: a highlight that faint cannot change a pixel, and it keeps
    /// every value of the loop a normal float (each is 0 or ≥ 2⁻⁶³, so each product is 0 or
    /// ≥ 2⁻¹²⁶), where subnormal products would cost the CPU a microcode assist each. The
    /// lane kernels do the same, step for step.
    #[inline]
    pub(crate) fn power(self, base: f32, shininess: f32) -> f32 {
        match self {
            Exponent::Whole(mut e) => {
                let flush = |x: f32| if x < TINY { 0.0 } else { x };
                let (mut base, mut acc) = (flush(base), 1.0f32);
                while e > 0 {
                    if e & 1 == 1 {
                        acc = flush(acc * base);
                    }
                    base = flush(base * base);
                    e >>= 1;
                }
                acc
            }
            Exponent::Real => base.powf(shininess),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_exponents_square_and_the_rest_use_powf() {
        assert_eq!(Exponent::of(32.0), Exponent::Whole(32));
        assert_eq!(Exponent::of(256.0), Exponent::Whole(256));
        assert_eq!(Exponent::of(257.0), Exponent::Real);
        assert_eq!(Exponent::of(2.5), Exponent::Real);
        for (base, s) in [(0.9f32, 1.0f32), (0.5, 7.0), (0.99, 32.0), (0.7, 100.0)] {
            let got = Exponent::of(s).power(base, s);
            let want = f64::from(base).powf(f64::from(s)) as f32;
            assert!((got - want).abs() <= 1e-5 * want, "{base}^{s}: {got} vs {want}");
        }
        assert_eq!(Exponent::Real.power(0.5, 2.5), 0.5f32.powf(2.5), "non-whole exponents go through powf");
        // Faint highlights count as 0 rather than passing through subnormal floats.
        assert_eq!(TINY, 2f32.powi(-63), "the threshold");
        assert_eq!(Exponent::of(40.0).power(0.1, 40.0), 0.0, "0.1^40 = 1e-40 is below 2^-63");
        assert_eq!(Exponent::of(2.0).power(2f32.powi(-31), 2.0), 2f32.powi(-62), "kept: the square is above 2^-63");
        assert_eq!(Exponent::of(2.0).power(2f32.powi(-32), 2.0), 0.0, "flushed: the square is 2^-64");
    }
}
