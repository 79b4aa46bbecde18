//! The parallel renderer: one eye, every pixel, rows spread over rayon's pool.

use rayon::prelude::*;

use crate::camera::EyeView;
use crate::film::{Film, Shading, Surface, NO_OBJECT};
use crate::primary::{PrimaryBins, TILE};
use crate::stats::RayCounts;
use crate::world::Tracer;

/// Traces every pixel of `view` into `film` (resized to the view if needed) and returns the
/// rays cast.
///
/// First hits are found through screen-space bins ([`PrimaryBins`], kept in the film and
/// rebuilt for `view`), the rest through the BVH. Rows are independent work items; each
/// row counts its own rays and the counts are summed afterwards, so the result — pixels and
/// counts — is the same for any thread count. Nothing is allocated per pixel or per ray,
/// nor per frame once the film has its size.
pub fn render_eye(tracer: &Tracer, view: &EyeView, film: &mut Film) -> RayCounts {
    film.resize(view.width, view.height);
    let w = view.width as usize;
    if w == 0 || view.height == 0 {
        return RayCounts::default();
    }
    film.bins.build(tracer, view);
    let bins = &film.bins;
    (
        film.rgb.par_chunks_mut(w),
        film.z.par_chunks_mut(w),
        film.object.par_chunks_mut(w),
        film.lights.par_chunks_mut(w),
        film.shading.par_chunks_mut(w),
    )
        .into_par_iter()
        .enumerate()
        .map(|(j, (rgb, z, object, lights, shading))| {
            let mut counts = RayCounts::default();
            let j = j as u32;
            for span in spans(w) {
                if bins.is_empty_at(span.start as u32, j) {
                    // Background without a sphere test. The shading entries of a miss are
                    // left as they are: nothing reads them (see `Film::surface`).
                    counts.primary += span.len() as u64;
                    rgb[span.clone()].fill(tracer.background_rgb);
                    z[span.clone()].fill(f32::INFINITY);
                    object[span.clone()].fill(NO_OBJECT);
                    lights[span].fill(0);
                    continue;
                }
                for i0 in span.clone().step_by(4) {
                    let n = (span.end - i0).min(4);
                    tracer.trace_primary4(bins, i0 as u32, j, n, &mut counts, |k, s| {
                        let i = i0 + k;
                        rgb[i] = s.rgb;
                        z[i] = s.z;
                        object[i] = s.surface.object;
                        lights[i] = s.surface.lights;
                        if s.surface.is_hit() {
                            let Surface { point, normal, diffuse, .. } = s.surface;
                            shading[i] = Shading { point, normal, diffuse };
                        }
                    });
                }
            }
            counts
        })
        .sum()
}

/// The pixel spans of a `w`-pixel row that fall in one screen tile each.
fn spans(w: usize) -> impl Iterator<Item = std::ops::Range<usize>> {
    let tile = TILE as usize;
    (0..w.div_ceil(tile)).map(move |t| t * tile..((t + 1) * tile).min(w))
}

/// Traces every pixel of `view` for colour only into `rgb` (resized to the view), for
/// images whose visible-surface record nobody reads. `bins` is rebuilt for `view` (pass the
/// same one every frame to reuse its buffers). Returns the rays cast; pixels and counts are
/// those of [`render_eye`].
pub fn render_rgb(tracer: &Tracer, view: &EyeView, bins: &mut PrimaryBins, rgb: &mut Vec<u32>) -> RayCounts {
    let w = view.width as usize;
    rgb.resize(w * view.height as usize, 0);
    if w == 0 || view.height == 0 {
        return RayCounts::default();
    }
    bins.build(tracer, view);
    let bins = &*bins;
    rgb.par_chunks_mut(w)
        .enumerate()
        .map(|(j, row)| {
            let mut counts = RayCounts::default();
            let j = j as u32;
            for span in spans(w) {
                if bins.is_empty_at(span.start as u32, j) {
                    counts.primary += span.len() as u64;
                    row[span].fill(tracer.background_rgb);
                    continue;
                }
                for i0 in span.clone().step_by(4) {
                    let n = (span.end - i0).min(4);
                    tracer.trace_primary4(bins, i0 as u32, j, n, &mut counts, |k, s| row[i0 + k] = s.rgb);
                }
            }
            counts
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::camera::{Camera, Eye};
    use crate::color::{linear_to_srgb8, unpack_rgb};
    use crate::scene::{Light, Material, Motion, RenderSettings, Scene, SceneSphere};

    /// One sphere straight ahead at z = 10 (radius 1), seen by a mono camera (IPD 0) whose
    /// centre pixel of a 3×3 image looks exactly down +z.
    fn one_sphere(material: Material, lights: Vec<Light>, render: RenderSettings) -> Scene {
        Scene {
            camera: Camera { ipd: 0.0, distance: 5.0, fov_deg: 30.0, ..Camera::default() },
            render,
            lights,
            spheres: vec![SceneSphere { radius: 1.0, motion: Motion::Static(Vec3::new(0.0, 0.0, 10.0)), material }],
        }
    }

    fn centre_pixel(scene: &Scene) -> ([u8; 3], RayCounts, crate::Surface) {
        let tracer = Tracer::new(scene, 0.0);
        let view = scene.camera.view(Eye::Left, 3, 3);
        let mut film = Film::new(3, 3);
        let counts = render_eye(&tracer, &view, &mut film);
        (unpack_rgb(film.rgb[4]), counts, film.surface(4))
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
        assert_eq!(counts.primary, 9);
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
        let scene = one_sphere(m, vec![], RenderSettings { max_depth: 1, background: bg, ambient: 0.0 });
        let (px, counts, _) = centre_pixel(&scene);
        assert_eq!(px, srgb(bg), "r = d − 2(d·n)n sends the ray back past the eye");
        assert!(counts.reflection >= 1);
        let scene = one_sphere(m, vec![], RenderSettings { max_depth: 0, background: bg, ambient: 0.0 });
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
        let mut scene =
            one_sphere(mirror, vec![], RenderSettings { max_depth: 1, background: Vec3::ZERO, ambient: 1.0 });
        scene.spheres.push(SceneSphere {
            radius: 0.5,
            motion: Motion::Static(Vec3::new(0.0, 0.0, -3.0)),
            material: red,
        });
        let (px, ..) = centre_pixel(&scene);
        assert_eq!(px, [255, 0, 0]);
    }

    #[test]
    fn counts_add_up() {
        let scene = Scene::from_toml(include_str!("../../../assets/scenes/seed.toml"), "seed.toml").unwrap();
        let tracer = Tracer::new(&scene, 0.0);
        let view = scene.camera.view(Eye::Left, 64, 36);
        let mut film = Film::new(64, 36);
        let counts = render_eye(&tracer, &view, &mut film);
        assert_eq!(counts.primary, 64 * 36);
        let hits = film.object.iter().filter(|&&o| o != crate::NO_OBJECT).count() as u64;
        // Every sphere is reflective and max_depth > 0: each primary hit casts one reflection.
        assert!(counts.reflection >= hits);
        assert_eq!(counts.total(), counts.primary + counts.shadow + counts.reflection);
    }

    #[test]
    fn same_bytes_for_one_and_two_threads() {
        let scene = Scene::from_toml(include_str!("../../../assets/scenes/seed.toml"), "seed.toml").unwrap();
        let tracer = Tracer::new(&scene, 1.5);
        let view = scene.camera.view(Eye::Right, 160, 90);
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut film = Film::new(1, 1);
                let counts = render_eye(&tracer, &view, &mut film);
                (film.rgb, film.z, counts)
            })
        };
        let (a, b) = (run(1), run(2));
        assert_eq!(a.0, b.0);
        assert_eq!(
            a.1.iter().map(|z| z.to_bits()).collect::<Vec<_>>(),
            b.1.iter().map(|z| z.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(a.2, b.2);
    }

    #[test]
    fn zero_ipd_gives_identical_eyes() {
        let mut scene = Scene::from_toml(include_str!("../../../assets/scenes/seed.toml"), "seed.toml").unwrap();
        scene.camera.ipd = 0.0;
        let tracer = Tracer::new(&scene, 0.0);
        let (mut l, mut r) = (Vec::new(), Vec::new());
        render_rgb(&tracer, &scene.camera.view(Eye::Left, 96, 54), &mut PrimaryBins::new(), &mut l);
        render_rgb(&tracer, &scene.camera.view(Eye::Right, 96, 54), &mut PrimaryBins::new(), &mut r);
        assert_eq!(l, r);
        scene.camera.ipd = 0.65;
        render_rgb(&tracer, &scene.camera.view(Eye::Right, 96, 54), &mut PrimaryBins::new(), &mut r);
        assert_ne!(l, r, "a real IPD changes the right eye");
    }
}
