//! Generated sphere fields: N spheres through the view of a fixed camera, as a
//! `tracer::Scene` built in code (no file), from a fixed seed.
//!
//! The camera is thousand.toml's (IPD 0.65, d = 12, 60° horizontal field of view, at the
//! origin looking down +z), with its two lights and `max_depth` 3. Sphere centres are uniform
//! in depth z ∈ [20, 60] and uniform across the 16:9 view at that depth (gen_scenes.py's
//! layout, without its rejection of overlaps). Radii grow with depth, r = ρ·z·U(0.6, 1.4),
//! so every sphere covers about the same solid angle, and ρ is chosen so a primary ray
//! meets τ = 3 spheres on average (1 − e⁻³ ≈ 95 % of the pixels hit something) at every N:
//! the image looks alike at 1k and 1M, only finer. A quarter of the spheres are mirrors
//! (reflectivity 0.5), the rest matte.

use glam::Vec3;
use tracer::{Camera, Light, Material, Motion, RenderSettings, Scene, SceneSphere};

/// Spheres a primary ray meets on average.
const OPTICAL_DEPTH: f32 = 3.0;
/// Depth range of the centres.
const Z_NEAR: f32 = 20.0;
const Z_FAR: f32 = 60.0;
const FOV_DEG: f32 = 60.0;
const ASPECT: f32 = 16.0 / 9.0;

/// SplitMix64: a fixed-seed generator with no dependency.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [a, b).
    fn uniform(&mut self, a: f32, b: f32) -> f32 {
        let u = (self.next() >> 40) as f32 / (1u64 << 24) as f32;
        a + (b - a) * u
    }
}

/// The field of `n` spheres from `seed`.
#[must_use]
pub fn field(n: usize, seed: u64) -> Scene {
    let mut rng = SplitMix(seed);
    let half = (FOV_DEG.to_radians() / 2.0).tan();
    // The view's cross-section at depth z is (2·half·z)·(2·half·z/aspect); a sphere of radius
    // ρ·z covers π·ρ²·z² of it, so τ = n·π·ρ² / (4·half²/aspect) (E[U²] ≈ 1).
    let rho = (OPTICAL_DEPTH * 4.0 * half * half / ASPECT / (n as f32 * std::f32::consts::PI)).sqrt();
    let spheres = (0..n)
        .map(|_| {
            let z = rng.uniform(Z_NEAR, Z_FAR);
            let x = rng.uniform(-1.0, 1.0) * half * z;
            let y = rng.uniform(-1.0, 1.0) * half * z / ASPECT;
            let radius = rho * z * rng.uniform(0.6, 1.4);
            let hue = rng.uniform(0.0, 1.0);
            let color = Vec3::from_array(
                [0.0, 1.0, 2.0].map(|k: f32| 0.5 + 0.45 * (std::f32::consts::TAU * (hue + k / 3.0)).cos()),
            );
            let mirror = rng.uniform(0.0, 1.0) < 0.25;
            let material = Material {
                color,
                diffuse: 0.75,
                specular: if mirror { 0.4 } else { 0.2 },
                shininess: 40.0,
                reflectivity: if mirror { 0.5 } else { 0.0 },
            };
            SceneSphere { radius, motion: Motion::Static(Vec3::new(x, y, z)), material }
        })
        .collect();
    Scene {
        camera: Camera { ipd: 0.65, distance: 12.0, fov_deg: FOV_DEG, ..Camera::default() },
        render: RenderSettings { max_depth: 3, ..RenderSettings::default() },
        lights: vec![
            Light { position: Vec3::new(-20.0, 30.0, -10.0), color: Vec3::new(0.9, 0.9, 0.85) },
            Light { position: Vec3::new(25.0, 10.0, 5.0), color: Vec3::new(0.35, 0.35, 0.45) },
        ],
        spheres,
        structures: Vec::new(),
    }
}
