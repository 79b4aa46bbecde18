//! The Embree side's Whitted tracer: stereotrace's ray tree, cast through Embree.
//!
//! Per pixel of the left eye, the rays `tracer::shade` casts, in its order: the primary ray
//! (`EyeView::primary_ray`); at each hit p (normal n = normalize(p − c), `shade.rs`'s
//! formula), per light the surface faces (n·l > 0) a shadow ray from `spawn_ray(p, n, l)` up
//! to the light's distance (`rtcOccluded1`); then, while the depth is below `max_depth` and
//! the sphere reflects, the mirror ray `spawn_ray(p, n, reflect(d, n))` (`rtcIntersect1`).
//! Nothing is shaded: a running count of hits and lit lights keeps the work observable.
//! With packets, a row's primary rays go eight neighbouring pixels at a time
//! (`rtcIntersect8`), and each pixel's shadow and mirror rays follow as single rays.

use glam::Vec3;
use rayon::prelude::*;
use tracer::{reflect, spawn_ray, EyeView, Light, Ray, RayCounts, Tracer};

use crate::embree::Spheres;

/// What one pixel's ray tree did, for comparing it with stereotrace's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelTree {
    /// Rays cast, by kind.
    pub counts: RayCounts,
    /// The sphere the primary ray hit, or `u32::MAX`.
    pub first: u32,
    /// Secondary rays whose first hit (shadow rays: any blocker, asked as a closest hit) was
    /// the sphere they leave: self-intersections, which stereotrace's lookups rule out.
    pub self_hits: u64,
}

/// A Whitted tracer over an Embree scene of the same spheres as a [`Tracer`].
pub struct Whitted<'a> {
    spheres: &'a Spheres<'a>,
    centers: &'a [Vec3],
    reflective: Vec<bool>,
    lights: &'a [Light],
    max_depth: u32,
    /// The secondary rays' tnear (0: exactly our rays).
    tnear: f32,
    /// Whether rows are traced in flush-to-zero and denormals-are-zero mode, as Embree asks.
    ftz: bool,
    /// Whether primary rays go in packets of 8 (`rtcIntersect8`).
    packets: bool,
}

/// The thread's MXCSR with flush-to-zero and denormals-are-zero set, restored on drop:
/// what Embree asks of every thread that traces ("can have a severe performance impact").
struct FlushToZero(u32);

impl FlushToZero {
    const FTZ: u32 = 1 << 15;
    const DAZ: u32 = 1 << 6;

    fn on() -> Self {
        let mut old = 0u32;
        unsafe {
            std::arch::asm!("stmxcsr [{}]", in(reg) &raw mut old, options(nostack));
            let new = old | Self::FTZ | Self::DAZ;
            std::arch::asm!("ldmxcsr [{}]", in(reg) &raw const new, options(nostack));
        }
        Self(old)
    }
}

impl Drop for FlushToZero {
    fn drop(&mut self) {
        unsafe { std::arch::asm!("ldmxcsr [{}]", in(reg) &raw const self.0, options(nostack)) };
    }
}

impl<'a> Whitted<'a> {
    /// The tracer over `spheres`, built from `tracer`'s snapshot; with `packets`, primary
    /// rays go eight at a time.
    #[must_use]
    pub fn new(spheres: &'a Spheres<'a>, tracer: &'a Tracer, tnear: f32, ftz: bool, packets: bool) -> Self {
        let s = tracer.snapshot();
        Self {
            spheres,
            centers: s.centers(),
            reflective: (0..s.centers().len()).map(|k| s.material(k).reflectivity > 0.0).collect(),
            lights: s.lights(),
            max_depth: tracer.settings().max_depth,
            tnear,
            ftz,
            packets,
        }
    }

    /// Traces pixel (i, j) of `view`: the rays cast, and a count of hits and lit lights.
    /// With `probe`, shadow rays are asked as closest hits (slower) to find self-hits.
    #[inline]
    fn pixel(&self, view: &EyeView, i: u32, j: u32, probe: Option<&mut PixelTree>) -> (RayCounts, u64) {
        let ray = view.primary_ray(i, j);
        self.tree(ray, self.spheres.intersect(&ray, 0.0, f32::INFINITY), probe)
    }

    /// The rest of a pixel's ray tree, from its primary ray `ray` and that ray's first hit.
    #[inline]
    fn tree(&self, ray: Ray, first: Option<(f32, u32)>, probe: Option<&mut PixelTree>) -> (RayCounts, u64) {
        let mut counts = RayCounts { primary: 1, ..RayCounts::default() };
        let mut sum = 0u64;
        let mut ray = ray;
        let mut hit = first;
        let mut from = u32::MAX;
        let mut depth = 0;
        let mut probe = probe;
        while let Some((t, k)) = hit {
            if let Some(p) = probe.as_deref_mut() {
                if depth == 0 {
                    p.first = k;
                }
                p.self_hits += u64::from(k == from);
            }
            sum += 1;
            let p = ray.at(t);
            let n = (p - self.centers[k as usize]).normalize();
            for light in self.lights {
                // `Tracer::to_light`'s formula.
                let v = light.position - p;
                let dist = v.length();
                let l = v * dist.recip();
                if n.dot(l) > 0.0 {
                    counts.shadow += 1;
                    let shadow = spawn_ray(p, n, l);
                    let blocked = match probe.as_deref_mut() {
                        None => self.spheres.occluded(&shadow, self.tnear, dist),
                        Some(p) => match self.spheres.intersect(&shadow, self.tnear, dist) {
                            Some((_, b)) => {
                                p.self_hits += u64::from(b == k);
                                true
                            }
                            None => false,
                        },
                    };
                    sum += u64::from(!blocked);
                }
            }
            if !self.reflective[k as usize] || depth >= self.max_depth {
                break;
            }
            counts.reflection += 1;
            ray = spawn_ray(p, n, reflect(ray.dir, n));
            hit = self.spheres.intersect(&ray, self.tnear, f32::INFINITY);
            from = k;
            depth += 1;
        }
        (counts, sum)
    }

    /// One row's rays and its count of hits and lit lights.
    fn row(&self, view: &EyeView, j: u32) -> (RayCounts, u64) {
        let _ftz = self.ftz.then(FlushToZero::on);
        let mut counts = RayCounts::default();
        let mut sum = 0;
        if self.packets {
            for i0 in (0..view.width).step_by(8) {
                let lanes = (view.width - i0).min(8) as usize;
                let rays: [Ray; 8] = std::array::from_fn(|k| view.primary_ray((i0 + k as u32).min(view.width - 1), j));
                let hits = self.spheres.intersect8(&rays, lanes);
                for (&ray, &hit) in rays.iter().zip(&hits).take(lanes) {
                    let (c, s) = self.tree(ray, hit, None);
                    counts += c;
                    sum += s;
                }
            }
        } else {
            for i in 0..view.width {
                let (c, s) = self.pixel(view, i, j, None);
                counts += c;
                sum += s;
            }
        }
        (counts, sum)
    }

    /// Every pixel of `view`, rows spread over the current rayon pool (as `Renderer::render`
    /// spreads them): the rays cast, and the count of hits and lit lights.
    pub fn render(&self, view: &EyeView) -> (RayCounts, u64) {
        (0..view.height)
            .into_par_iter()
            .map(|j| self.row(view, j))
            .reduce(|| (RayCounts::default(), 0), |a, b| (a.0 + b.0, a.1 + b.1))
    }

    /// Pixel (i, j)'s ray tree, with shadow rays asked as closest hits to count self-hits.
    #[must_use]
    pub fn probe(&self, view: &EyeView, i: u32, j: u32) -> PixelTree {
        let _ftz = self.ftz.then(FlushToZero::on);
        let mut tree = PixelTree { first: u32::MAX, ..PixelTree::default() };
        tree.counts = self.pixel(view, i, j, Some(&mut tree)).0;
        tree
    }
}
