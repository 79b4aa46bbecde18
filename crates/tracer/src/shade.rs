//! Whitted shading (Whitted 1980, "An improved illumination model for shaded display").
//!
//! At a hit with unit normal n, material (colour c, kd, ks, shininess s, kr) and view
//! direction d (towards the surface):
//!
//! ```text
//! L = c · (ambient + kd · Σ_k V_k · max(0, n·l_k) · I_k)      view-independent ("diffuse")
//!   + ks · Σ_k V_k · max(0, n·h_k)^s · I_k                    view-dependent: highlight
//!   + kr · L(reflected ray r = d − 2(d·n)n)                   view-dependent: reflection
//! ```
//!
//! with l_k the unit vector to light k, h_k = normalize(l_k − d) (Blinn–Phong) and V_k the
//! light's visibility: 1 when the surface faces the light (n·l > 0) and a shadow ray towards
//! it is unblocked. Reflection recurses up to `max_depth` bounces; a miss returns the
//! background. The two parts are computed by separate functions so that `stereo` can reuse
//! the first from the other eye and recompute only the second.

use glam::Vec3;

use crate::camera::EyeView;
use crate::color::pack_rgb;
use crate::film::Surface;
use crate::ray::{reflect, spawn_ray, Ray};
use crate::stats::RayCounts;
use crate::world::Tracer;

/// How many lights' directions the diffuse step hands on to the highlight step.
const KEPT_LIGHTS: usize = 4;

/// Directions from a hit to the first [`KEPT_LIGHTS`] lights.
type LightDirs = [Vec3; KEPT_LIGHTS];

/// Where light visibility comes from when shading a hit.
#[derive(Clone, Copy, Debug)]
enum Visibility {
    /// Cast a shadow ray to each light the surface faces.
    Trace,
    /// Reuse known visibility bits (bit k = light k reaches the point).
    Known(u32),
}

/// One shaded primary sample: the pixel colour and its visible-surface record.
#[derive(Clone, Copy, Debug)]
pub struct Shaded {
    /// sRGB pixel, `0x00RRGGBB`.
    pub rgb: u32,
    /// Head-space depth beyond the window; +∞ for a miss.
    pub z: f32,
    /// What the ray saw.
    pub surface: Surface,
}

/// How a material's highlight exponent is evaluated: by repeated squaring for whole
/// exponents up to 256 (the common case, several times faster than `powf`), `powf`
/// otherwise. Decided once per material when the tracer is updated; every eye and mode
/// shades through [`highlight`], so the choice never makes two paths disagree.
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
}

/// (n·h)^shininess.
#[inline]
fn highlight(ndh: f32, shininess: f32, exponent: Exponent) -> f32 {
    match exponent {
        Exponent::Whole(mut e) => {
            let (mut base, mut acc) = (ndh, 1.0f32);
            while e > 0 {
                if e & 1 == 1 {
                    acc *= base;
                }
                base *= base;
                e >>= 1;
            }
            acc
        }
        Exponent::Real => ndh.powf(shininess),
    }
}

impl Tracer {
    /// Radiance arriving along `ray`, which is at reflection depth `depth`.
    #[must_use]
    pub fn trace(&self, ray: &Ray, depth: u32, counts: &mut RayCounts) -> Vec3 {
        match self.intersect(ray, f32::INFINITY) {
            Some((t, object)) => self.shade_hit(ray, t, object, depth, Visibility::Trace, counts).0,
            None => self.settings.background,
        }
    }

    /// Radiance arriving along `ray`, a mirror ray spawned from sphere `from` (normal `n`
    /// there), at depth `depth`.
    fn trace_reflection(&self, from: u32, n: Vec3, ray: &Ray, depth: u32, counts: &mut RayCounts) -> Vec3 {
        match self.intersect_from(from, n, ray) {
            Some((t, object)) => self.shade_hit(ray, t, object, depth, Visibility::Trace, counts).0,
            None => self.settings.background,
        }
    }

    /// Traces the primary ray of pixel (i, j) of `view` and shades it fully.
    #[inline]
    #[must_use]
    pub fn trace_pixel(&self, view: &EyeView, i: u32, j: u32, counts: &mut RayCounts) -> Shaded {
        counts.primary += 1;
        let ray = view.primary_ray(i, j);
        match self.intersect(&ray, f32::INFINITY) {
            Some((t, object)) => self.shade_primary_hit(view, &ray, t, object, counts),
            None => self.miss_sample(),
        }
    }

    /// Shades the first hit of a primary ray, casting its shadow and reflection rays.
    #[inline]
    pub(crate) fn shade_primary_hit(
        &self,
        view: &EyeView,
        ray: &Ray,
        t: f32,
        object: u32,
        counts: &mut RayCounts,
    ) -> Shaded {
        self.shaded_sample(view, ray, t, object, Visibility::Trace, counts)
    }

    /// Shades the hit of `ray` on sphere `object` at parameter `t` with known light
    /// visibility `lights` (no shadow rays), recomputing everything else. With the right
    /// visibility this is bit-for-bit what [`Tracer::trace_pixel`] would produce.
    #[inline]
    #[must_use]
    pub fn shade_known_visibility(
        &self,
        view: &EyeView,
        ray: &Ray,
        t: f32,
        object: u32,
        lights: u32,
        counts: &mut RayCounts,
    ) -> Shaded {
        self.shaded_sample(view, ray, t, object, Visibility::Known(lights), counts)
    }

    /// Re-shades a surface seen from another eye for a view along the unit direction `d`
    /// (the new pixel's ray): keeps its view-independent light and recomputes the highlight
    /// and reflection. Casts no shadow ray for the surface itself. With `d` equal to the
    /// original ray's direction the result is bit-for-bit the original pixel.
    #[inline]
    #[must_use]
    pub fn reshade(&self, d: Vec3, surface: &Surface, counts: &mut RayCounts) -> u32 {
        let view_dependent =
            self.view_dependent(surface.point, surface.normal, d, surface.object, surface.lights, None, 0, counts);
        pack_rgb(surface.diffuse + view_dependent)
    }

    /// The sample of a pixel whose primary ray missed.
    #[must_use]
    pub fn miss_sample(&self) -> Shaded {
        Shaded { rgb: self.background_rgb, z: f32::INFINITY, surface: Surface::MISS }
    }

    fn shaded_sample(
        &self,
        view: &EyeView,
        ray: &Ray,
        t: f32,
        object: u32,
        vis: Visibility,
        counts: &mut RayCounts,
    ) -> Shaded {
        let (color, surface) = self.shade_hit(ray, t, object, 0, vis, counts);
        Shaded { rgb: pack_rgb(color), z: view.head_z(surface.point), surface }
    }

    fn shade_hit(
        &self,
        ray: &Ray,
        t: f32,
        object: u32,
        depth: u32,
        vis: Visibility,
        counts: &mut RayCounts,
    ) -> (Vec3, Surface) {
        let k = object as usize;
        let p = ray.at(t);
        // Normalised rather than divided by r: the hit lies on the sphere only to rounding.
        let n = (p - self.centers[k]).normalize();
        let (diffuse, lights, dirs) = self.view_independent(object, p, n, vis, counts);
        let color = diffuse + self.view_dependent(p, n, ray.dir, object, lights, Some(&dirs), depth, counts);
        (color, Surface { point: p, normal: n, diffuse, object, lights })
    }

    /// Unit direction and distance from `p` to light `k`: the one formula every shading
    /// path uses, so that a direction kept from one step equals one recomputed in another.
    #[inline]
    fn to_light(&self, p: Vec3, k: usize) -> (Vec3, f32) {
        let v = self.lights[k].position - p;
        let dist = v.length();
        (v * dist.recip(), dist)
    }

    /// Ambient + Lambert diffuse with hard shadows, the visibility bits it found, and the
    /// directions to the first [`KEPT_LIGHTS`] lights for the highlights.
    fn view_independent(
        &self,
        object: u32,
        p: Vec3,
        n: Vec3,
        vis: Visibility,
        counts: &mut RayCounts,
    ) -> (Vec3, u32, LightDirs) {
        let mut sum = Vec3::ZERO;
        let mut bits = 0u32;
        let mut dirs = [Vec3::ZERO; KEPT_LIGHTS];
        for (k, light) in self.lights.iter().enumerate() {
            let (l, dist) = self.to_light(p, k);
            if let Some(d) = dirs.get_mut(k) {
                *d = l;
            }
            let ndl = n.dot(l);
            if ndl <= 0.0 {
                continue;
            }
            let visible = match vis {
                Visibility::Trace => {
                    counts.shadow += 1;
                    !self.shadowed(k, object, p, n, &spawn_ray(p, n, l), dist)
                }
                Visibility::Known(known) => known & (1 << k) != 0,
            };
            if visible {
                bits |= 1 << k;
                sum += ndl * light.color;
            }
        }
        let m = &self.materials[object as usize];
        (m.color * (self.settings.ambient + m.diffuse * sum), bits, dirs)
    }

    /// Blinn–Phong highlights from the visible lights plus the mirror reflection.
    fn view_dependent(
        &self,
        p: Vec3,
        n: Vec3,
        d: Vec3,
        object: u32,
        lights: u32,
        dirs: Option<&LightDirs>,
        depth: u32,
        counts: &mut RayCounts,
    ) -> Vec3 {
        let (m, exponent) = (&self.materials[object as usize], self.exponents[object as usize]);
        let mut out = Vec3::ZERO;
        if m.specular > 0.0 {
            for (k, light) in self.lights.iter().enumerate() {
                if lights & (1 << k) == 0 {
                    continue;
                }
                let l = match dirs {
                    Some(dirs) if k < KEPT_LIGHTS => dirs[k],
                    _ => self.to_light(p, k).0,
                };
                let ndh = n.dot((l - d).normalize_or_zero());
                if ndh > 0.0 {
                    out += m.specular * highlight(ndh, m.shininess, exponent) * light.color;
                }
            }
        }
        if m.reflectivity > 0.0 && depth < self.settings.max_depth {
            counts.reflection += 1;
            // d and n are unit, so r is too, to rounding: no normalisation needed.
            let reflected = spawn_ray(p, n, reflect(d, n));
            out += m.reflectivity * self.trace_reflection(object, n, &reflected, depth + 1, counts);
        }
        out
    }
}
