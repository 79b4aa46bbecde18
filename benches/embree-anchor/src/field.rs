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
//!
//! Deep fields ([`deep`]) fill the whole view frustum instead, from z = 8 to
//! 40·(N/1000)^⅓, with spheres that never overlap.

use glam::{IVec3, Vec3};
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

/// A sphere's material: a hue on the colour wheel, and a quarter of them mirrors.
fn material(rng: &mut SplitMix) -> Material {
    let hue = rng.uniform(0.0, 1.0);
    let color =
        Vec3::from_array([0.0, 1.0, 2.0].map(|k: f32| 0.5 + 0.45 * (std::f32::consts::TAU * (hue + k / 3.0)).cos()));
    let mirror = rng.uniform(0.0, 1.0) < 0.25;
    Material {
        color,
        diffuse: 0.75,
        specular: if mirror { 0.4 } else { 0.2 },
        shininess: 40.0,
        reflectivity: if mirror { 0.5 } else { 0.0 },
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
            let material = material(&mut rng);
            SceneSphere { radius, motion: Motion::Static(Vec3::new(x, y, z)), material }
        })
        .collect();
    scene(spheres)
}

/// The deep fields' nearest centre depth; the farthest is 40·(N/1000)^⅓.
const DEEP_NEAR: f32 = 8.0;
/// The share of space the deep fields' spheres would fill at the far end if every candidate
/// were kept (random sequential addition of equal spheres jams near 0.38).
const DEEP_FILL: f32 = 0.25;
/// Candidates drawn per sphere asked for, before the generator gives up.
const DEEP_TRIES: usize = 64;

/// A deep field: `n` non-overlapping spheres filling the view frustum from z = 8 to
/// z_far = 40·(n/1000)^⅓ (the camera, lights and mirrors of [`field`]), and how many
/// candidates it drew.
///
/// Centres are uniform in the frustum's volume between the two depths (z drawn with density
/// ∝ z², x and y uniform across the 16:9 view at that depth); the radius is ρ·z, so every
/// sphere covers the same solid angle, with ρ chosen so that the centres' density n/V fills
/// a share `DEEP_FILL` = 0.25 of space at z_far: n/V · (4/3)·π·(ρ·z_far)³ = 0.25, where
/// V = (4·half²/aspect)·(z_far³ − 8³)/3: ρ ≈ (0.25·0.75/(4π·n))^⅓ (0.011 at 10k, 0.0053 at
/// 100k, 0.0025 at 1M), so the farthest spheres have a radius near 0.98 at every n and the
/// nearest 8·ρ. Nearer, the fill falls as z³. A candidate overlapping an accepted sphere
/// (|c − c'| < r + r') is rejected, found through a uniform grid of cells as wide as the
/// largest sphere's diameter (so overlaps lie in the 27 neighbouring cells); after
/// 64·n candidates the field keeps what it placed (the caller reports a shortfall). Kept
/// spheres thin out towards z_far, where rejections are most frequent.
#[must_use]
pub fn deep(n: usize, seed: u64) -> (Scene, usize) {
    let mut rng = SplitMix(seed);
    let half = (FOV_DEG.to_radians() / 2.0).tan();
    let (z_near, z_far) = (DEEP_NEAR, 40.0 * (n as f32 / 1000.0).cbrt());
    let (near3, far3) = (z_near.powi(3), z_far.powi(3));
    let volume = 4.0 * half * half / ASPECT * (far3 - near3) / 3.0;
    let rho = (DEEP_FILL * volume / (n.max(1) as f32 * 4.0 / 3.0 * std::f32::consts::PI * far3)).cbrt();
    let cell = 2.0 * rho * z_far;
    let lo = Vec3::new(-half * z_far, -half * z_far / ASPECT, z_near);
    let dims = ((Vec3::new(half * z_far, half * z_far / ASPECT, z_far) - lo) / cell).ceil().as_ivec3() + 1;
    let cell_of = |p: Vec3| ((p - lo) / cell).floor().as_ivec3().clamp(IVec3::ZERO, dims - 1);
    let index = |c: IVec3| ((c.z * dims.y + c.y) * dims.x + c.x) as usize;
    // The grid: each cell's last sphere, and each sphere's predecessor in its cell.
    let mut head = vec![u32::MAX; dims.x as usize * dims.y as usize * dims.z as usize];
    let mut next: Vec<u32> = Vec::with_capacity(n);
    let mut placed: Vec<(Vec3, f32)> = Vec::with_capacity(n);
    let mut spheres = Vec::with_capacity(n);
    let mut tries = 0;
    while placed.len() < n && tries < DEEP_TRIES * n {
        tries += 1;
        let z = (near3 + rng.uniform(0.0, 1.0) * (far3 - near3)).cbrt();
        let x = rng.uniform(-1.0, 1.0) * half * z;
        let y = rng.uniform(-1.0, 1.0) * half * z / ASPECT;
        let (c, r) = (Vec3::new(x, y, z), rho * z);
        let home = cell_of(c);
        let overlaps = (-1..=1).any(|dz| {
            (-1..=1).any(|dy| {
                (-1..=1).any(|dx| {
                    let q = home + IVec3::new(dx, dy, dz);
                    if q.cmplt(IVec3::ZERO).any() || q.cmpge(dims).any() {
                        return false;
                    }
                    let mut k = head[index(q)];
                    while k != u32::MAX {
                        let (c2, r2) = placed[k as usize];
                        if c.distance_squared(c2) < (r + r2) * (r + r2) {
                            return true;
                        }
                        k = next[k as usize];
                    }
                    false
                })
            })
        });
        if overlaps {
            continue;
        }
        let k = placed.len() as u32;
        let h = &mut head[index(home)];
        next.push(*h);
        *h = k;
        placed.push((c, r));
        let material = material(&mut rng);
        spheres.push(SceneSphere { radius: r, motion: Motion::Static(c), material });
    }
    (scene(spheres), tries)
}

/// The fields' camera, lights and reflection depth around `spheres`.
fn scene(spheres: Vec<SceneSphere>) -> Scene {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_spheres_never_overlap_and_all_fit() {
        let (scene, _) = deep(10_000, 2024);
        assert_eq!(scene.spheres.len(), 10_000);
        let s: Vec<(Vec3, f32)> = scene
            .spheres
            .iter()
            .map(|s| match s.motion {
                Motion::Static(c) => (c, s.radius),
                Motion::Orbit { .. } => unreachable!("deep fields are static"),
            })
            .collect();
        for (i, &(c, r)) in s.iter().enumerate() {
            for &(c2, r2) in &s[..i] {
                assert!(c.distance(c2) >= r + r2, "spheres at {c} and {c2} overlap");
            }
        }
        let mirrors = scene.spheres.iter().filter(|s| s.material.reflectivity > 0.0).count();
        assert!((2300..2700).contains(&mirrors), "{mirrors} mirrors of 10k");
    }
}
