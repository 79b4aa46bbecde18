//! Image quality of a right eye against the full trace.

/// How far an image is from a reference, both 8-bit sRGB `0x00RRGGBB`. Errors are in 8-bit
/// levels per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quality {
    /// Peak signal-to-noise ratio over all channels, dB; +∞ for identical images.
    pub psnr_db: f64,
    /// Mean absolute error per channel, levels (0–255).
    pub mean_abs: f64,
    /// Largest absolute error of any channel, levels.
    pub max_abs: u8,
    /// Share of pixels with an error above 2 levels (2/255) on any channel, 0..1.
    pub share_over_2_255: f64,
    /// Share of pixels that differ at all, 0..1.
    pub share_not_identical: f64,
}

impl Quality {
    /// Compares `image` against `reference` (same length).
    #[must_use]
    pub fn compare(image: &[u32], reference: &[u32]) -> Self {
        assert_eq!(image.len(), reference.len(), "images differ in size");
        if image.is_empty() {
            return Self { psnr_db: f64::INFINITY, ..Self::default() };
        }
        let (mut sum_abs, mut sum_sq, mut max_abs, mut over, mut differ) = (0u64, 0u64, 0u8, 0u64, 0u64);
        for (&a, &b) in image.iter().zip(reference) {
            if a == b {
                continue;
            }
            differ += 1;
            let mut worst = 0u8;
            for shift in [16, 8, 0] {
                let e = ((a >> shift) as u8).abs_diff((b >> shift) as u8);
                sum_abs += u64::from(e);
                sum_sq += u64::from(e) * u64::from(e);
                worst = worst.max(e);
            }
            max_abs = max_abs.max(worst);
            if worst > 2 {
                over += 1;
            }
        }
        let samples = image.len() as f64 * 3.0;
        let mse = sum_sq as f64 / samples;
        Self {
            psnr_db: if mse == 0.0 { f64::INFINITY } else { 10.0 * (255.0 * 255.0 / mse).log10() },
            mean_abs: sum_abs as f64 / samples,
            max_abs,
            share_over_2_255: over as f64 / image.len() as f64,
            share_not_identical: differ as f64 / image.len() as f64,
        }
    }

    /// Share of pixels identical to the reference.
    #[must_use]
    pub fn share_identical(&self) -> f64 {
        1.0 - self.share_not_identical
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_are_perfect() {
        let a = [0x0012_3456, 0x00FF_FFFF];
        let q = Quality::compare(&a, &a);
        assert!(q.psnr_db.is_infinite());
        assert_eq!((q.mean_abs, q.max_abs, q.share_not_identical), (0.0, 0, 0.0));
    }

    #[test]
    fn known_errors() {
        // One of two pixels off by 3 levels in red only: MSE = 9/6, mean = 3/6.
        let a = [0x0003_0000, 0x0000_0000];
        let b = [0x0000_0000, 0x0000_0000];
        let q = Quality::compare(&a, &b);
        assert_eq!(q.max_abs, 3);
        assert!((q.mean_abs - 0.5).abs() < 1e-12);
        assert!((q.psnr_db - 10.0 * (255.0f64 * 255.0 / 1.5).log10()).abs() < 1e-9);
        assert_eq!(q.share_over_2_255, 0.5);
        assert_eq!(q.share_not_identical, 0.5);
        // Off by exactly 2: not over the threshold.
        let q = Quality::compare(&[0x0000_0002], &[0]);
        assert_eq!(q.share_over_2_255, 0.0);
        assert_eq!(q.share_not_identical, 1.0);
    }
}
