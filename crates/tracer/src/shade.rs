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
//! background. At a primary hit, with the scene's cues on (`cue/`), the ambient term is
//! scaled by the open share that occlusion rays find (seeded by the pixel), and the
//! radiance is depth cued towards the background by the hit's distance.
//!
//! This is the plain path: a pixel at a time, recursively, as the formula reads. The
//! renderer shades through the same operations batched in SIMD lanes (`wavefront.rs`), and
//! tests compare the two pixel by pixel, bit for bit.

use glam::Vec3;

use crate::accel::Origin;
use crate::camera::EyeView;
use crate::color::pack_rgb;
use crate::ray::{reflect, spawn_ray, Ray};
use crate::stats::RayCounts;
use crate::surface::{Hit, Surface};
use crate::tracer::Tracer;

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

impl Tracer {
    /// Radiance arriving along `ray`, a mirror ray spawned from sphere `from` (normal `n`
    /// there), at depth `depth`.
    fn trace_reflection(&self, from: u32, n: Vec3, ray: &Ray, depth: u32, counts: &mut RayCounts) -> Vec3 {
        match self.accel.intersect(ray, f32::INFINITY, Origin::Surface { sphere: from, normal: n }) {
            Some(Hit { t, object }) => self.shade_hit(ray, (t, object), (depth, None), counts).0,
            None => self.scene.settings.background,
        }
    }

    /// Traces the primary ray of pixel (i, j) of `view` through the BVH and shades it fully:
    /// the plain path, which the screen bins and every second-view service are tested
    /// against.
    #[inline]
    #[must_use]
    pub fn trace_pixel(&self, view: &EyeView, i: u32, j: u32, counts: &mut RayCounts) -> Shaded {
        counts.primary += 1;
        let ray = view.primary_ray(i, j);
        match self.intersect(&ray, f32::INFINITY) {
            Some(Hit { t, object }) => {
                let pixel = crate::cue::SeedRow::of(view, j).shown((i, j));
                self.shade_primary_hit(view, &ray, (t, object), pixel, counts)
            }
            None => self.miss_sample(),
        }
    }

    /// The linear radiance the plain path finds for pixel (i, j) of `view`, before it is
    /// packed; `None` for a miss (a test oracle for the batched shading, whose packed
    /// colours alone would hide differences below an sRGB step).
    #[cfg(test)]
    pub(crate) fn pixel_radiance(&self, view: &EyeView, i: u32, j: u32) -> Option<Vec3> {
        let ray = view.primary_ray(i, j);
        let hit = self.intersect(&ray, f32::INFINITY)?;
        let pixel = crate::cue::SeedRow::of(view, j).shown((i, j));
        let color = self.shade_hit(&ray, (hit.t, hit.object), (0, Some(pixel)), &mut RayCounts::default()).0;
        Some(self.depth_cued(color, hit.t))
    }

    /// The plain path's re-shading (a test oracle for [`crate::PixelBatch::reshade`]): the
    /// surface that `ray` (another view's) met at `t` on `object`, lit by the lights
    /// `lights` names, seen along the unit direction `d`, packed.
    #[cfg(test)]
    pub(crate) fn reshaded_rgb(&self, ray: &Ray, (t, object, lights): (f32, u32, u32), d: Vec3) -> u32 {
        let p = ray.at(t);
        let n = (p - self.scene.centers[object as usize]).normalize();
        let ambient = self.scene.settings.ambient;
        let (diffuse, lights) = self.diffuse_light((object, p, n), ambient, |k, _, _| lights & (1 << k) != 0);
        let surface = Surface { point: p, normal: n, diffuse, object, lights };
        pack_rgb(diffuse + self.view_dependent(&surface, d, 0, &mut RayCounts::default()))
    }

    /// Shades the first hit (`t`, `object`) of the primary ray of the pixel whose place in
    /// the shown image is `pixel`, casting its shadow, occlusion and reflection rays.
    #[inline]
    pub(crate) fn shade_primary_hit(
        &self,
        view: &EyeView,
        ray: &Ray,
        (t, object): (f32, u32),
        pixel: (u32, u32),
        counts: &mut RayCounts,
    ) -> Shaded {
        let (color, surface) = self.shade_hit(ray, (t, object), (0, Some(pixel)), counts);
        Shaded { rgb: pack_rgb(self.depth_cued(color, t)), z: view.head_z(surface.point), surface }
    }

    /// A primary hit's radiance `color` at distance `t`, depth cued (`cue/fog.rs`).
    #[inline]
    pub(crate) fn depth_cued(&self, color: Vec3, t: f32) -> Vec3 {
        let settings = &self.scene.settings;
        settings.cues.depth_cue.apply(color, settings.background, t)
    }

    /// The sample of a pixel whose primary ray missed.
    #[must_use]
    pub(crate) fn miss_sample(&self) -> Shaded {
        Shaded { rgb: self.scene.background_rgb, z: f32::INFINITY, surface: Surface::MISS }
    }

    /// Shades the hit (`t`, `object`) of `ray` at reflection depth `depth`; `pixel` is the
    /// traced view's pixel whose primary ray this is (`None` deeper down: occlusion is
    /// cast at primary hits only).
    fn shade_hit(
        &self,
        ray: &Ray,
        (t, object): (f32, u32),
        (depth, pixel): (u32, Option<(u32, u32)>),
        counts: &mut RayCounts,
    ) -> (Vec3, Surface) {
        let k = object as usize;
        let p = ray.at(t);
        // Normalised rather than divided by r: the hit lies on the sphere only to rounding.
        let n = (p - self.scene.centers[k]).normalize();
        let ambient = match pixel {
            Some(pixel) => self.ambient_at(object, (p, n), pixel, counts),
            None => self.scene.settings.ambient,
        };
        let (diffuse, lights) = self.view_independent((object, p, n), ambient, counts);
        let surface = Surface { point: p, normal: n, diffuse, object, lights };
        (diffuse + self.view_dependent(&surface, ray.dir, depth, counts), surface)
    }

    /// The shadow query of one ray: whether anything blocks `ray`, spawned (by
    /// [`crate::spawn_ray`]) from the point `p` of sphere `from` (outward normal `n`)
    /// towards light `k`, before `t_max`, the distance to it.
    pub(crate) fn shadowed(&self, k: usize, from: u32, p: Vec3, n: Vec3, ray: &Ray, t_max: f32) -> bool {
        let light = (k, self.scene.lights[k].position);
        self.accel.occluded(ray, t_max, Origin::Light(self.accel.towards_light(light, from, (p, n, ray.dir))))
    }

    /// Unit direction and distance from `p` to light `k`: the one formula every shading
    /// path uses, so that a direction kept from one step equals one recomputed in another.
    #[inline]
    pub(crate) fn to_light(&self, p: Vec3, k: usize) -> (Vec3, f32) {
        let v = self.scene.lights[k].position - p;
        let dist = v.length();
        (v * dist.recip(), dist)
    }

    /// Ambient (the term `ambient`) + Lambert diffuse with hard shadows, and the visibility
    /// bits it found.
    fn view_independent(&self, (object, p, n): (u32, Vec3, Vec3), ambient: f32, counts: &mut RayCounts) -> (Vec3, u32) {
        self.diffuse_light((object, p, n), ambient, |k, l, dist| {
            counts.shadow += 1;
            !self.shadowed(k, object, p, n, &spawn_ray(p, n, l), dist)
        })
    }

    /// The view-independent light at `p` (normal `n`) on sphere `object`,
    /// colour · (ambient + kd · Σ n·l · I) over the lights the surface faces and `visible(k,
    /// l, dist)` lets through, and the bits of those lights: the one scalar formula, for the
    /// plain path and for the wavefront's leftover entries. `ambient` is the scene's, or at
    /// a primary hit with occlusion on, [`Tracer::ambient_at`]'s.
    pub(crate) fn diffuse_light(
        &self,
        (object, p, n): (u32, Vec3, Vec3),
        ambient: f32,
        mut visible: impl FnMut(usize, Vec3, f32) -> bool,
    ) -> (Vec3, u32) {
        let mut sum = Vec3::ZERO;
        let mut bits = 0u32;
        for (k, light) in self.scene.lights.iter().enumerate() {
            let (l, dist) = self.to_light(p, k);
            let ndl = n.dot(l);
            if ndl > 0.0 && visible(k, l, dist) {
                bits |= 1 << k;
                sum += ndl * light.color;
            }
        }
        let m = self.scene.material(object as usize);
        (m.color * (ambient + m.diffuse * sum), bits)
    }

    /// Blinn–Phong highlights at `p` (normal `n`) on sphere `object`, seen along `d`, from
    /// the lights the bits `lights` name: the one scalar formula, for the plain path and for
    /// the wavefront's leftover entries.
    pub(crate) fn highlight(&self, object: u32, p: Vec3, n: Vec3, d: Vec3, lights: u32) -> Vec3 {
        let (m, exponent) = (self.scene.material(object as usize), self.scene.exponent(object as usize));
        let mut out = Vec3::ZERO;
        if m.specular > 0.0 {
            for (k, light) in self.scene.lights.iter().enumerate() {
                if lights & (1 << k) == 0 {
                    continue;
                }
                let l = self.to_light(p, k).0;
                let ndh = n.dot((l - d).normalize_or_zero());
                if ndh > 0.0 {
                    out += m.specular * exponent.power(ndh, m.shininess) * light.color;
                }
            }
        }
        out
    }

    /// Blinn–Phong highlights from the lights visible at `surface` plus the mirror
    /// reflection, seen along `d`, at reflection depth `depth`.
    fn view_dependent(&self, surface: &Surface, d: Vec3, depth: u32, counts: &mut RayCounts) -> Vec3 {
        let &Surface { point: p, normal: n, object, lights, .. } = surface;
        let m = self.scene.material(object as usize);
        let mut out = self.highlight(object, p, n, d, lights);
        if m.reflectivity > 0.0 && depth < self.scene.settings.max_depth {
            counts.reflection += 1;
            // d and n are unit, so r is too, to rounding: no normalisation needed.
            let reflected = spawn_ray(p, n, reflect(d, n));
            out += m.reflectivity * self.trace_reflection(object, n, &reflected, depth + 1, counts);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Camera, Eye};
    use crate::color::{linear_to_srgb8, unpack_rgb};
    use crate::material::Material;
    use crate::scene::{Light, Motion, RenderSettings, Scene, SceneSphere};

    /// One sphere straight ahead at z = 10 (radius 1), seen by a mono camera (IPD 0) whose
    /// centre pixel of a 3×3 image looks exactly down +z.
    fn one_sphere(material: Material, lights: Vec<Light>, render: RenderSettings) -> Scene {
        Scene {
            camera: Camera { ipd: 0.0, distance: 5.0, fov_deg: 30.0, ..Camera::default() },
            render,
            lights,
            spheres: vec![SceneSphere { radius: 1.0, motion: Motion::Static(Vec3::new(0.0, 0.0, 10.0)), material }],
            structures: Vec::new(),
        }
    }

    /// The centre pixel of a 3×3 image, traced the plain way: its colour, the rays it
    /// cast and what it saw.
    fn centre_pixel(scene: &Scene) -> ([u8; 3], RayCounts, Surface) {
        let tracer = Tracer::new(scene, 0.0);
        let view = scene.camera.view(Eye::Left, 3, 3);
        let mut counts = RayCounts::default();
        let s = tracer.trace_pixel(&view, 1, 1, &mut counts);
        (unpack_rgb(s.rgb), counts, s.surface)
    }

    fn srgb(c: Vec3) -> [u8; 3] {
        [linear_to_srgb8(c.x), linear_to_srgb8(c.y), linear_to_srgb8(c.z)]
    }

    #[test]
    fn lit_sphere_centre_pixel_matches_the_closed_form() {
        // Light at the eye: n·l = 1 and n·h = 1 at the centre, so
        // L = c·(ambient + kd) + ks.
        let m = Material {
            color: Vec3::new(0.5, 0.25, 0.2),
            diffuse: 0.8,
            specular: 0.3,
            shininess: 10.0,
            reflectivity: 0.0,
        };
        let scene = one_sphere(
            m,
            vec![Light { position: Vec3::ZERO, color: Vec3::ONE }],
            RenderSettings { ambient: 0.1, ..RenderSettings::default() },
        );
        let (px, counts, surface) = centre_pixel(&scene);
        assert_eq!(px, srgb(m.color * 0.9 + Vec3::splat(0.3)));
        assert!((surface.point - Vec3::new(0.0, 0.0, 9.0)).length() < 1e-5);
        assert!((surface.normal - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-5);
        assert_eq!(surface.lights, 1);
        assert_eq!(counts, RayCounts { primary: 1, shadow: 1, reflection: 0 }, "one light faced, no mirror");
    }

    #[test]
    fn light_at_an_angle_follows_lambert() {
        // Light 45° above the hit point (0, 0, 9): n·l = cos 45°.
        let m = Material { color: Vec3::ONE, diffuse: 1.0, specular: 0.0, shininess: 1.0, reflectivity: 0.0 };
        let light = Light { position: Vec3::new(0.0, 5.0, 4.0), color: Vec3::ONE };
        let scene = one_sphere(m, vec![light], RenderSettings { ambient: 0.0, ..RenderSettings::default() });
        let (px, ..) = centre_pixel(&scene);
        assert_eq!(px, srgb(Vec3::splat(std::f32::consts::FRAC_1_SQRT_2)));
    }

    #[test]
    fn shadow_ray_goes_towards_the_light_and_an_occluder_blocks_it() {
        let m = Material { color: Vec3::ONE, diffuse: 1.0, specular: 0.5, shininess: 8.0, reflectivity: 0.0 };
        let light = Light { position: Vec3::new(0.0, 5.0, 4.0), color: Vec3::ONE };
        let mut scene = one_sphere(m, vec![light], RenderSettings { ambient: 0.2, ..RenderSettings::default() });
        // A small sphere halfway between the hit point (0, 0, 9) and the light, off the camera ray.
        scene.spheres.push(SceneSphere { radius: 0.5, motion: Motion::Static(Vec3::new(0.0, 2.5, 6.5)), material: m });
        let (px, counts, surface) = centre_pixel(&scene);
        assert_eq!(px, srgb(Vec3::splat(0.2)), "only ambient in shadow, and no highlight");
        assert_eq!(surface.lights, 0);
        assert!(counts.shadow >= 1);
        // The same occluder placed on the far side of the light casts no shadow.
        scene.spheres[1].motion = Motion::Static(Vec3::new(0.0, 7.5, 1.5));
        let (_, _, surface) = centre_pixel(&scene);
        assert_eq!(surface.lights, 1);
    }

    #[test]
    fn head_on_mirror_shows_the_background_and_depth_zero_turns_it_off() {
        let m = Material { color: Vec3::ONE, diffuse: 0.0, specular: 0.0, shininess: 1.0, reflectivity: 1.0 };
        let bg = Vec3::new(0.2, 0.4, 0.6);
        let scene = one_sphere(
            m,
            vec![],
            RenderSettings { max_depth: 1, background: bg, ambient: 0.0, ..RenderSettings::default() },
        );
        let (px, counts, _) = centre_pixel(&scene);
        assert_eq!(px, srgb(bg), "r = d − 2(d·n)n sends the ray back past the eye");
        assert!(counts.reflection >= 1);
        let scene = one_sphere(
            m,
            vec![],
            RenderSettings { max_depth: 0, background: bg, ambient: 0.0, ..RenderSettings::default() },
        );
        let (px, counts, _) = centre_pixel(&scene);
        assert_eq!(px, [0, 0, 0]);
        assert_eq!(counts.reflection, 0);
    }

    #[test]
    fn reflection_sees_a_sphere_behind_the_eye_direction() {
        // A black mirror at z = 10 and a red sphere on the axis behind the eye: the centre
        // pixel's reflection travels back along −z, past the eye, onto the red sphere.
        let mirror = Material { color: Vec3::ZERO, diffuse: 0.0, specular: 0.0, shininess: 1.0, reflectivity: 1.0 };
        let red = Material {
            color: Vec3::new(1.0, 0.0, 0.0),
            diffuse: 0.0,
            specular: 0.0,
            shininess: 1.0,
            reflectivity: 0.0,
        };
        let mut scene = one_sphere(
            mirror,
            vec![],
            RenderSettings { max_depth: 1, background: Vec3::ZERO, ambient: 1.0, ..RenderSettings::default() },
        );
        scene.spheres.push(SceneSphere {
            radius: 0.5,
            motion: Motion::Static(Vec3::new(0.0, 0.0, -3.0)),
            material: red,
        });
        let (px, ..) = centre_pixel(&scene);
        assert_eq!(px, [255, 0, 0]);
    }

    #[test]
    fn no_lights_is_allowed_and_means_ambient_only() {
        // A scene file without lights, a shiny sphere: every pixel that sees it is
        // colour · ambient, with no highlight and no shadow ray.
        let text = "[render]\nambient = 0.25\n[[spheres]]\ncenter = [0.0, 0.0, 15.0]\nradius = 2.5\n\
                    color = [0.8, 0.4, 0.2]\nspecular = 0.9\nshininess = 8\n";
        let scene = Scene::from_toml(text, "ambient.toml").expect("a scene without lights is valid");
        assert!(scene.lights.is_empty(), "no light given, none made up");
        let tracer = Tracer::new(&scene, 0.0);
        let view = scene.camera.view(Eye::Right, 48, 27);
        let (mut counts, mut hits) = (RayCounts::default(), 0);
        for j in 0..27 {
            for i in 0..48 {
                let s = tracer.trace_pixel(&view, i, j, &mut counts);
                if s.surface.is_hit() {
                    assert_eq!(unpack_rgb(s.rgb), srgb(Vec3::new(0.8, 0.4, 0.2) * 0.25), "({i}, {j})");
                    hits += 1;
                }
            }
        }
        assert!(hits > 50, "the sphere is in view: {hits}");
        assert_eq!(counts.shadow, 0, "no light, no shadow ray");
    }
}
