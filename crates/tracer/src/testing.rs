//! What the workspace's tests and benches share, so that each is written once: the bundled
//! scenes by name, one small deterministic generator, and how a test says it skipped. Not
//! part of the crate's API (hidden from its docs); public so that the other crates' tests
//! and benches reach it.

use std::path::PathBuf;

use crate::scene::Scene;

/// The path of a bundled scene, `assets/scenes/<name>` (e.g. `"seed.toml"`).
#[must_use]
pub fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes").join(name)
}

/// The bundled scene `name`, loaded.
///
/// # Panics
/// If it does not load: the bundled scenes always do.
#[must_use]
pub fn scene(name: &str) -> Scene {
    let path = scene_path(name);
    Scene::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Says that a test is skipped, and why, as `SKIPPED: reason` on the process's standard
/// error: written to it directly, past the test harness's capture of `eprintln!`, so that
/// a plain `cargo test` shows it.
pub fn skipped(reason: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr().lock(), "SKIPPED: {reason}");
}

/// Marsaglia's xorshift32 (13, 17, 5; "Xorshift RNGs", J. Stat. Softw. 8, 2003): a small
/// deterministic generator, so that a random test's failure names a case to rerun.
#[derive(Clone, Debug)]
pub struct XorShift(u32);

impl XorShift {
    /// The generator from `seed`; 0, which xorshift never leaves, is taken as 1.
    #[must_use]
    pub fn new(seed: u32) -> Self {
        Self(seed.max(1))
    }

    /// The next 32 bits.
    pub fn next_u32(&mut self) -> u32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        self.0
    }

    /// Uniform in `0..n` (up to the modulo's bias, which the tests do not mind), `n > 0`.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u32() as usize) % n
    }

    /// Uniform in `[0, 1)`, to the 24 bits of an `f32`'s mantissa.
    pub fn unit(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 / (1u32 << 24) as f32
    }

    /// Uniform in `[lo, hi)` (to rounding).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_generator_is_marsaglias_xorshift32() {
        // Marsaglia's paper starts from y = 2463534242.
        let mut rng = XorShift::new(2_463_534_242);
        assert_eq!(rng.next_u32(), 723_471_715, "the first output of the paper's seed");
        let mut zero = XorShift::new(0);
        assert_ne!(zero.next_u32(), 0, "a zero seed does not stick at zero");
        let mut rng = XorShift::new(7);
        assert!((0..1000).all(|_| rng.below(6) < 6), "below stays below");
        assert!((0..1000).map(|_| rng.unit()).all(|x| (0.0..1.0).contains(&x)), "unit stays below 1");
        assert!((0..1000).map(|_| rng.range(-2.0, 3.0)).all(|x| (-2.0..=3.0).contains(&x)), "range stays in");
    }

    #[test]
    fn every_bundled_scene_loads_by_name() {
        assert!(scene("seed.toml").sphere_count() > 0, "the seed scene has spheres");
        assert!(scene_path("many.toml").is_file(), "many.toml is there");
    }
}
