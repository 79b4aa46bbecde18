//! The shading queue: hits in structure-of-arrays lanes, the lights, and the output.

use glam::Vec3;

/// Lights the kernels shade with (the benchmark case).
pub const LIGHTS: usize = 2;

/// A point light.
#[derive(Clone, Copy, Debug)]
pub struct Light {
    /// World-space position.
    pub position: Vec3,
    /// Linear intensity per channel.
    pub color: Vec3,
}

/// What every hit of a batch shares.
#[derive(Clone, Copy, Debug)]
pub struct Scene {
    /// Ambient term added to the diffuse light.
    pub ambient: f32,
    /// The point lights.
    pub lights: [Light; LIGHTS],
}

/// Primary hits waiting to be shaded, one entry per hit in each array.
#[derive(Clone, Debug, Default)]
pub struct Hits {
    /// Hit point.
    pub p: [Vec<f32>; 3],
    /// Unit outward normal.
    pub n: [Vec<f32>; 3],
    /// Unit view direction, towards the surface.
    pub d: [Vec<f32>; 3],
    /// Material colour (linear).
    pub c: [Vec<f32>; 3],
    /// Lambert coefficient.
    pub kd: Vec<f32>,
    /// Highlight coefficient (0 for no highlight).
    pub ks: Vec<f32>,
    /// Whole Blinn–Phong exponent, 0..=256, per hit: lanes of one batch come from different
    /// spheres, so they need not share a material.
    pub e: Vec<u32>,
    /// Mirror coefficient.
    pub kr: Vec<f32>,
    /// Radiance the mirror ray brought back (from the previous wavefront stage).
    pub mirror: [Vec<f32>; 3],
    /// Bit k: light k reaches the point (from the shadow stage).
    pub vis: Vec<u32>,
}

/// Shaded hits: linear radiance and the packed sRGB pixel.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Shaded {
    /// Linear radiance per channel.
    pub linear: [Vec<f32>; 3],
    /// `0x00RRGGBB` sRGB.
    pub rgb: Vec<u32>,
}

impl Shaded {
    /// Output room for `n` hits.
    #[must_use]
    pub fn new(n: usize) -> Self {
        Self { linear: [vec![0.0; n], vec![0.0; n], vec![0.0; n]], rgb: vec![0; n] }
    }
}

/// A small deterministic generator (SplitMix64), so inputs are fixed without a `rand` dependency.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// The seed scene's lights plus a second, dimmer one, as in the kernel.
#[must_use]
pub fn seed_scene() -> Scene {
    Scene {
        ambient: 0.1,
        lights: [
            Light { position: Vec3::new(-6.0, 10.0, -8.0), color: Vec3::ONE },
            Light { position: Vec3::new(8.0, 6.0, 4.0), color: Vec3::new(0.5, 0.45, 0.4) },
        ],
    }
}

/// The seed scene's spheres (centre, radius) and materials (colour, kd, ks, e, kr), plus a
/// matte one (ks = kr = 0) and a tight highlight (e = 256) to cover every branch.
const SPHERES: [(Vec3, f32); 7] = [
    (Vec3::new(0.0, 0.0, 15.0), 2.5),
    (Vec3::new(-2.6, -0.4, 11.4), 0.8),
    (Vec3::new(-4.8, 0.0, 15.0), 1.0),
    (Vec3::new(4.8, 0.0, 15.0), 1.0),
    (Vec3::new(2.1, 3.3, 14.0), 0.45),
    (Vec3::new(0.0, -1002.5, 15.0), 1000.0),
    (Vec3::new(1.5, 1.8, 10.0), 0.6),
];
const MATERIALS: [(Vec3, f32, f32, u32, f32); 7] = [
    (Vec3::new(1.0, 1.0, 1.0), 0.6, 0.6, 60, 0.5),
    (Vec3::new(0.16, 0.78, 0.24), 0.7, 0.3, 40, 0.2),
    (Vec3::new(0.25, 0.88, 0.82), 0.7, 0.3, 40, 0.2),
    (Vec3::new(0.59, 0.16, 0.78), 0.7, 0.3, 40, 0.2),
    (Vec3::new(1.0, 0.75, 0.16), 0.7, 0.3, 40, 0.2),
    (Vec3::new(0.8, 0.8, 0.8), 0.9, 0.0, 40, 0.0),
    (Vec3::new(0.9, 0.3, 0.3), 0.5, 0.8, 256, 0.1),
];

/// `n` hits on the scene's spheres seen from the origin, with fixed pseudo-random normals
/// (camera-facing), materials, mirror radiance and shadows (about one lit light in six is
/// shadowed). Consecutive hits come from runs of 1–16 on one sphere, as a tile's would.
#[must_use]
pub fn generate(n: usize, seed: u64) -> Hits {
    let mut rng = SplitMix(seed);
    let scene = seed_scene();
    let mut h = Hits::default();
    let mut sphere = 0;
    let mut run = 0;
    for _ in 0..n {
        if run == 0 {
            sphere = (rng.next() % SPHERES.len() as u64) as usize;
            run = 1 + rng.next() % 16;
        }
        run -= 1;
        let (center, radius) = SPHERES[sphere];
        let (color, kd, ks, e, kr) = MATERIALS[sphere];
        // A normal on the hemisphere facing the origin.
        let n = loop {
            let v = Vec3::new(rng.unit(), rng.unit(), rng.unit()) * 2.0 - Vec3::ONE;
            if v.length_squared() > 1e-3 && v.length_squared() <= 1.0 {
                let v = v.normalize();
                break if v.dot(center) > 0.0 { -v } else { v };
            }
        };
        let p = center + radius * n;
        let d = p.normalize();
        let mut vis = 0;
        for (k, light) in scene.lights.iter().enumerate() {
            if n.dot(light.position - p) > 0.0 && !rng.next().is_multiple_of(6) {
                vis |= 1 << k;
            }
        }
        for axis in 0..3 {
            h.p[axis].push(p[axis]);
            h.n[axis].push(n[axis]);
            h.d[axis].push(d[axis]);
            h.c[axis].push(color[axis]);
            h.mirror[axis].push(rng.unit());
        }
        h.kd.push(kd);
        h.ks.push(ks);
        h.e.push(e);
        h.kr.push(kr);
        h.vis.push(vis);
    }
    h
}

impl Hits {
    /// Number of hits.
    #[must_use]
    pub fn len(&self) -> usize {
        self.kd.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.kd.is_empty()
    }
}
