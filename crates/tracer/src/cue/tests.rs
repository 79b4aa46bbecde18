//! The cues against closed forms, and both shading paths against each other with the cues
//! on, at every lane width.

use fearless_simd::dispatch;
use glam::Vec3;

use super::*;
use crate::camera::{Camera, Eye};
use crate::material::Material;
use crate::render::{Pixels, Renderer, Target};
use crate::scene::{RenderSettings, SceneSphere};
use crate::stats::RayCounts;
use crate::surface::NO_OBJECT;
use crate::tracer::Tracer;
use crate::wavefront::with_wavefront;

/// A big sphere whose top is the origin (normal +y) and, when `small` is given as
/// (distance L, radius ρ, angle θ from the normal), a small sphere centred L from the
/// origin at θ; occlusion with `samples` rays within `distance`.
fn sky(small: Option<(f32, f32, f32)>, samples: u32, distance: f32) -> Tracer {
    let m = Material::default();
    let mut spheres =
        vec![SceneSphere { radius: 1000.0, motion: Motion::Static(Vec3::new(0.0, -1000.0, 0.0)), material: m }];
    if let Some((l, rho, theta)) = small {
        let c = l * Vec3::new(theta.sin(), theta.cos(), 0.0);
        spheres.push(SceneSphere { radius: rho, motion: Motion::Static(c), material: m });
    }
    let cues = Cues { ambient_occlusion: AmbientOcclusion { samples, distance, strength: 1.0 }, ..Cues::default() };
    let scene = Scene {
        camera: Camera { position: Vec3::new(0.0, 50.0, -500.0), ..Camera::default() },
        render: RenderSettings { cues, ..RenderSettings::default() },
        lights: Vec::new(),
        spheres,
        structures: Vec::new(),
    };
    Tracer::new(&scene, 0.0)
}

/// The occluded share at the origin of the big sphere, for pixel `pixel`.
fn share_at_top(tracer: &Tracer, pixel: (u32, u32)) -> f32 {
    tracer.occluded_share(0, (Vec3::ZERO, Vec3::Y), pixel, &mut RayCounts::default())
}

#[test]
fn a_sphere_above_the_horizon_occludes_sin2_alpha_cos_theta() {
    // The cosine-weighted solid angle of a cap of angular radius α whose axis is θ from the
    // normal, wholly above the horizon: sin²α · cos θ (of π).
    for (l, rho, theta_deg) in [(10.0, 6.0, 30.0), (10.0, 4.0, 0.0), (20.0, 10.0, 50.0), (8.0, 5.0, 20.0)] {
        let theta = f32::to_radians(theta_deg);
        let alpha = f32::asin(rho / l);
        assert!(theta + alpha < std::f32::consts::FRAC_PI_2, "the test sphere is above the horizon");
        let want = alpha.sin().powi(2) * theta.cos();
        let tracer = sky(Some((l, rho, theta)), 4096, 1e4);
        for pixel in [(0, 0), (17, 3), (640, 479)] {
            let got = share_at_top(&tracer, pixel);
            assert!(
                (got - want).abs() <= 0.01 * want,
                "L {l}, ρ {rho}, θ {theta_deg}°, pixel {pixel:?}: {got} against {want}"
            );
        }
    }
}

#[test]
fn a_lone_sphere_and_an_occluder_beyond_the_distance_occlude_nothing() {
    let lone = sky(None, 256, 1e4);
    assert_eq!(share_at_top(&lone, (5, 7)), 0.0, "a sphere does not occlude itself");
    let far = sky(Some((10.0, 6.0, 0.3)), 256, 3.9);
    assert_eq!(share_at_top(&far, (5, 7)), 0.0, "the occluder's nearest point is 4 away");
    let near = sky(Some((10.0, 6.0, 0.3)), 256, 4.1);
    assert!(share_at_top(&near, (5, 7)) > 0.0, "…and 4.1 reaches it");
}

#[test]
fn directions_are_unit_cosine_weighted_and_leave_outwards() {
    // Over many samples the mean of n·ω of a cosine-weighted direction is 2/3.
    let n = Vec3::new(0.3, -0.5, 0.81).normalize();
    let (mut sum, count) = (0.0f64, 4096);
    for s in 0..count {
        let d = ao::sample_direction(n, (3, 9), s);
        assert!((d.length() - 1.0).abs() < 1e-5 && d.dot(n) > 0.0, "sample {s}: {d}");
        sum += f64::from(d.dot(n));
    }
    assert!((sum / f64::from(count) - 2.0 / 3.0).abs() < 2e-3, "mean cos {}", sum / f64::from(count));
    assert_ne!(ao::sample_direction(n, (3, 9), 5), ao::sample_direction(n, (4, 9), 5), "pixels differ");
}

#[test]
fn depth_cue_blends_towards_the_background() {
    let bg = Vec3::new(0.1, 0.2, 0.3);
    let linear = DepthCue { mode: DepthCueMode::Linear, start: 10.0, end: 20.0, density: 0.0 };
    assert_eq!(linear.apply(Vec3::ONE, bg, 5.0), Vec3::ONE);
    assert!((linear.apply(Vec3::ONE, bg, 15.0) - (Vec3::ONE + bg) * 0.5).length() < 1e-6);
    assert_eq!(linear.apply(Vec3::ONE, bg, 25.0), bg);
    let exp2 = DepthCue { mode: DepthCueMode::Exp2, start: 10.0, end: 20.0, density: 0.1 };
    assert!((exp2.kept(20.0) - (-1.0f32).exp()).abs() < 1e-6);
    assert_eq!(exp2.kept(3.0), 1.0);
}

/// `name` with every cue on: occlusion (`samples` rays within `distance`), Exp2 depth cue.
pub(crate) fn with_cues(mut scene: Scene, samples: u32) -> Scene {
    let sized = sized(bounds(&scene), scene.camera.position, samples);
    scene.render.cues =
        Cues { ambient_occlusion: AmbientOcclusion { strength: 0.9, ..sized.ambient_occlusion }, ..sized };
    scene
}

#[test]
fn lanes_of_every_width_shade_the_plain_paths_radiance_with_the_cues_on() {
    let mut scenes: Vec<(&str, Scene, f32)> = [("seed.toml", 0.8), ("many.toml", 0.0)]
        .map(|(name, t)| (name, with_cues(crate::testing::scene(name), 6), t))
        .into();
    // 1TII with the cues a structure opens with (8 occlusion rays, Exp2 depth cueing).
    let tii = std::path::Path::new("/usr/share/pymol/data/demo/1tii.pdb");
    if tii.exists() {
        scenes.push(("1tii.pdb", Scene::load(tii).expect("1TII loads"), 0.0));
    } else {
        crate::testing::skipped("1tii.pdb is not installed (pymol-data)");
    }
    for (name, scene, t) in scenes {
        let tracer = Tracer::new(&scene, t);
        let (w, h) = (83, 45);
        let view = scene.camera.view(Eye::Left, w, h);
        // Every width this CPU has: 4, 8 and, with AVX-512, 16 lanes.
        for level in crate::simd::levels() {
            let mut hits = 0;
            for j in (0..h).step_by(3) {
                with_wavefront(|wavefront| {
                    for i in 0..w {
                        let ray = view.primary_ray(i, j);
                        if let Some(hit) = tracer.intersect(&ray, f32::INFINITY) {
                            wavefront.push_hit(&ray, hit, i);
                        }
                    }
                    let mut counts = RayCounts::default();
                    dispatch!(level, simd => wavefront.shade_in(simd, &tracer, SeedRow::of(&view, j), &mut counts));
                    for e in 0..wavefront.len() {
                        let i = wavefront.tag(e);
                        let plain = tracer.pixel_radiance(&view, i, j).expect("a hit");
                        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                        assert_eq!(bits(wavefront.radiance(e)), bits(plain), "{name} {level:?} ({i}, {j})");
                    }
                    hits += wavefront.len();
                });
            }
            assert!(hits > 200, "{name}: {hits} hits, too few to test");
        }
    }
}

#[test]
fn a_render_with_the_cues_is_the_plain_path_and_the_same_for_any_thread_count() {
    let scene = with_cues(crate::testing::scene("seed.toml"), 5);
    let tracer = Tracer::new(&scene, 0.3);
    let (w, h) = (61, 37);
    let view = scene.camera.view(Eye::Right, w, h);
    let render = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
        let mut rgb = Vec::new();
        let counts = pool.install(|| Renderer::new().render(&tracer, &view, Pixels::All, Target::colour(&mut rgb)));
        (rgb, counts)
    };
    let (one, counts) = render(1);
    assert_eq!(render(2), (one.clone(), counts), "2 threads");
    assert_eq!(render(3), (one.clone(), counts), "3 threads");
    let mut plain = RayCounts::default();
    for j in 0..h {
        for i in 0..w {
            assert_eq!(one[(j * w + i) as usize], tracer.trace_pixel(&view, i, j, &mut plain).rgb, "({i}, {j})");
        }
    }
    assert_eq!(counts, plain, "the occlusion rays are counted as shadow rays, alike");
    let mut off = RayCounts::default();
    let bare = Tracer::new(&crate::testing::scene("seed.toml"), 0.3);
    let _ =
        (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).map(|(i, j)| bare.trace_pixel(&view, i, j, &mut off)).count();
    assert!(counts.shadow > off.shadow + 1000, "occlusion rays were cast: {} against {}", counts.shadow, off.shadow);
}

#[test]
fn outlines_fall_behind_a_silhouette_and_not_on_a_crease() {
    // A 7 × 3 image: object 1 near on the left, object 2 at the same depth touching it (a
    // crease), then object 3 far behind, then background.
    let object = [1, 1, 2, 2, 3, 3, crate::surface::NO_OBJECT].repeat(3);
    let z = [1.0, 1.0, 1.0, 1.0, 50.0, 50.0, f32::INFINITY].repeat(3);
    let mut rgb = vec![0x00ff_ffff; 21];
    outline(&mut rgb, &object, &z, (7, 3), Outline { width: 1.0, window: 10.0, ink: 1.0 });
    let row: Vec<bool> = rgb[7..14].iter().map(|&c| c == 0).collect();
    assert_eq!(row, [false, false, false, false, true, false, true], "behind object 2, and the background");
    let mut wide = vec![0x00ff_ffff; 21];
    outline(&mut wide, &object, &z, (7, 3), Outline { width: 2.0, window: 10.0, ink: 1.0 });
    assert_eq!(wide[7..14].iter().filter(|&&c| c == 0).count(), 3, "two pixels behind object 2, one before the sky");
}

#[test]
fn an_inked_outline_takes_its_share_of_the_light() {
    // The silhouette of the test above with ink 1/4: the outlined pixels keep 3/4 of their
    // linear light, the others all of it.
    let object = [1, 1, 2, 2, 3, 3, crate::surface::NO_OBJECT].repeat(3);
    let z = [1.0, 1.0, 1.0, 1.0, 50.0, 50.0, f32::INFINITY].repeat(3);
    let grey = 0x00b4_b4b4;
    let mut rgb = vec![grey; 21];
    outline(&mut rgb, &object, &z, (7, 3), Outline { width: 1.0, window: 10.0, ink: 0.25 });
    let kept = u32::from(crate::color::linear_to_srgb8(crate::color::srgb8_to_linear(0xb4) * 0.75));
    assert!(kept < 0xb4 && kept > 0x80, "{kept:#x}");
    let row = &rgb[7..14];
    assert_eq!(row[4], kept * 0x0001_0101, "behind object 2");
    assert_eq!(row[6], kept * 0x0001_0101, "the background");
    assert_eq!(row[0..4], [grey; 4], "in front and on the crease");
}

#[test]
fn outlines_drawn_by_chunks_are_the_plain_definition_pixel_by_pixel() {
    // Random planes of few objects and scattered depths, misses among them, at sizes
    // around the 512-pixel chunk and below the reach, and at every width to 8 (and between).
    let mut rng = crate::testing::XorShift::new(0x5eed_0071);
    for (w, h) in [(1, 1), (3, 2), (63, 5), (64, 4), (65, 7), (130, 9), (511, 3), (512, 2), (1029, 4)] {
        let n = w * h;
        let object: Vec<u32> =
            (0..n).map(|_| if rng.range(0.0, 1.0) < 0.1 { NO_OBJECT } else { rng.range(0.0, 4.0) as u32 }).collect();
        let z: Vec<f32> =
            object.iter().map(|&o| if o == NO_OBJECT { f32::INFINITY } else { rng.range(0.0, 40.0) }).collect();
        for width in [0.5, 1.0, 1.5, 2.0, 3.0, 4.5, 8.0] {
            let style = Outline { width, window: 10.0, ink: 1.0 };
            let mut rgb = vec![0x00ff_ffff; n];
            outline(&mut rgb, &object, &z, (w as u32, h as u32), style);
            let (reach, r2) = (width.floor() as isize, width * width);
            for k in 0..n {
                let at = ((k % w) as isize, (k / w) as isize);
                let plain = outline::drawn(at, (w, h), (&object, &z), (reach, r2, 10.0), (object[k], z[k]));
                assert_eq!(rgb[k] == 0, plain, "{w}×{h}, width {width}, pixel {at:?}");
            }
            // Drawn onto a copy of other colours, black or inked: the copy, then the lines.
            let from: Vec<u32> = (0..n).map(|_| rng.range(1.0, 16_777_215.0) as u32).collect();
            for ink in [1.0, 0.4] {
                let style = Outline { ink, ..style };
                let mut copied = from.clone();
                outline(&mut copied, &object, &z, (w as u32, h as u32), style);
                let mut onto = vec![7; n];
                outline_from(&from, &mut onto, &object, &z, (w as u32, h as u32), style);
                assert_eq!(onto, copied, "{w}×{h}, width {width}, ink {ink}: onto a copy");
            }
        }
    }
}

/// Directions spread over the sphere (a Fibonacci lattice of `n` points).
fn fibonacci(n: u32) -> impl Iterator<Item = Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n).map(move |k| {
        let y = 1.0 - 2.0 * (k as f32 + 0.5) / n as f32;
        let r = (1.0 - y * y).sqrt();
        let phi = golden * k as f32;
        Vec3::new(r * phi.cos(), y, r * phi.sin())
    })
}

#[test]
fn on_1tii_lonely_atoms_are_lighter_than_crowded_ones() {
    // Each atom's ambient factor, through the shading's own occlusion rays: the mean of
    // 1 − occluded share over points of its surface that no other atom covers (0 for an
    // atom with none). Lonely atoms must be lighter, on average, than crowded ones, by at
    // least 0.25.
    let path = std::path::Path::new("/usr/share/pymol/data/demo/1tii.pdb");
    if !path.exists() {
        crate::testing::skipped("1tii.pdb is not installed (pymol-data)");
        return;
    }
    let mut scene = Scene::load(path).expect("1TII loads");
    scene.render.cues.ambient_occlusion.samples = 16;
    let tracer = Tracer::new(&scene, 0.0);
    let (centers, radii) = (&tracer.scene.centers, &tracer.scene.radii);
    let n = centers.len();
    // Neighbours by a sweep along x.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| centers[a].x.total_cmp(&centers[b].x));
    let near = |k: usize, reach: f32| {
        let x = centers[k].x;
        let lo = order.partition_point(|&o| centers[o].x < x - reach);
        order[lo..]
            .iter()
            .take_while(move |&&o| centers[o].x <= x + reach)
            .copied()
            .filter(move |&o| o != k)
            .filter(move |&o| centers[o].distance(centers[k]) < reach)
    };
    // Every third atom: its neighbour count and its ambient factor.
    let atoms: Vec<(usize, f32)> = (0..n)
        .step_by(3)
        .map(|k| {
            let covering: Vec<usize> = near(k, radii[k] + 2.5).collect();
            let mut factors = Vec::new();
            for (s, u) in fibonacci(24).enumerate() {
                let p = centers[k] + radii[k] * u;
                if covering.iter().any(|&o| p.distance(centers[o]) < radii[o]) {
                    continue;
                }
                factors.push(1.0 - share(&tracer, k as u32, (p, u), (k as u32, s as u32)));
            }
            let factor = if factors.is_empty() { 0.0 } else { factors.iter().sum::<f32>() / factors.len() as f32 };
            (near(k, 8.0).count(), factor)
        })
        .collect();
    let mean = |f: &dyn Fn(usize) -> bool| {
        let v: Vec<f32> = atoms.iter().filter(|a| f(a.0)).map(|a| a.1).collect();
        (v.iter().sum::<f32>() / v.len().max(1) as f32, v.len())
    };
    // No atom of 1TII has fewer than 10 neighbours within 8 Å (its 215 waters included: the
    // least has 17), so the lonely atoms are the tenth with the fewest.
    assert_eq!(mean(&|c| c < 10).1, 0, "1TII has atoms with fewer than 10 neighbours after all");
    let mut counts: Vec<usize> = atoms.iter().map(|a| a.0).collect();
    counts.sort_unstable();
    let (low, high) = (counts[counts.len() / 10], counts[counts.len() * 9 / 10]);
    let (lonely, crowded, over_30) = (mean(&|c| c < low), mean(&|c| c > high), mean(&|c| c > 30));
    assert!(lonely.1 > 100 && crowded.1 > 100 && over_30.1 > 1000, "groups {lonely:?} {crowded:?} {over_30:?}");
    for (name, other) in [("the tenth with the most", crowded), ("more than 30", over_30)] {
        assert!(
            lonely.0 - other.0 >= 0.25,
            "the tenth with the fewest neighbours (< {low}): mean factor {} ({} atoms); {name}: {} ({} atoms)",
            lonely.0,
            lonely.1,
            other.0,
            other.1
        );
    }
}

fn share(tracer: &Tracer, object: u32, at: (Vec3, Vec3), pixel: (u32, u32)) -> f32 {
    tracer.occluded_share(object, at, pixel, &mut RayCounts::default())
}

#[test]
fn a_view_with_a_guard_band_seeds_its_shown_part_as_one_without() {
    // The viewer traces its eyes with a band for the timewarp; `render` without. The
    // occlusion rays are seeded by the place in the shown image, so the shown parts agree.
    let scene = with_cues(crate::testing::scene("seed.toml"), 4);
    let tracer = Tracer::new(&scene, 0.2);
    let (w, h, (mx, my)) = (48, 30, (5, 3));
    let render = |view| {
        let mut rgb = Vec::new();
        Renderer::new().render(&tracer, &view, Pixels::All, Target::colour(&mut rgb));
        rgb
    };
    let plain = render(scene.camera.view(Eye::Left, w, h));
    let banded = render(scene.camera.view_with_margin(Eye::Left, w, h, (mx, my)));
    let bw = (w + 2 * mx) as usize;
    let shown: Vec<u32> = banded
        .chunks(bw)
        .skip(my as usize)
        .take(h as usize)
        .flat_map(|r| r[mx as usize..bw - mx as usize].to_vec())
        .collect();
    assert_eq!(shown, plain);
}

#[test]
fn a_turn_is_cos_and_sin_of_two_pi_u_within_a_millionth() {
    // Every 2⁻¹⁸ of a turn, the quarter turns themselves, and both ends.
    let steps = (0..=1u32 << 18).map(|k| k as f32 / (1u32 << 18) as f32);
    for u in steps.chain([0.125, 0.25 - f32::EPSILON, 0.375, 0.625, 0.875, 1.0 - f32::EPSILON / 2.0]) {
        let (cos, sin) = ao::turn(u);
        let angle = std::f64::consts::TAU * f64::from(u);
        let err = (f64::from(cos) - angle.cos()).abs().max((f64::from(sin) - angle.sin()).abs());
        assert!(err <= 1e-6, "u {u}: ({cos}, {sin}) against ({}, {}), off by {err}", angle.cos(), angle.sin());
    }
}

#[test]
fn directions_made_across_lanes_are_the_plain_directions_bit_for_bit() {
    // Sixteen points of scattered normals and pixels, samples in blocks from 0 and from
    // 1,000, at the process's lanes and at the baseline's.
    let points: Vec<ao::Directions> = (0..ao::HITS_MAX as u32)
        .map(|k| {
            let f = k as f32;
            let n =
                Vec3::new((f * 1.7).sin(), (f * 0.3).cos() - 0.5, (f * 2.9).sin() + if k == 3 { -2.0 } else { 0.1 });
            ao::Directions::new(n.normalize(), (k * 37 + 5, 1000 - k * 11))
        })
        .collect();
    for level in crate::simd::levels() {
        for (first, count) in [(0, 4), (0, ao::BLOCK), (1000, 7)] {
            for hits in [1, 5, ao::HITS_MAX] {
                let mut out = [[Vec3::ZERO; ao::BLOCK]; ao::HITS_MAX];
                dispatch!(level, simd => ao::directions_in(simd, &points[..hits], (first, count), &mut out));
                for (h, point) in points[..hits].iter().enumerate() {
                    for (k, got) in out[h][..count].iter().enumerate() {
                        let want = point.get(first + k as u32);
                        assert_eq!(
                            got.to_array().map(f32::to_bits),
                            want.to_array().map(f32::to_bits),
                            "{level:?}, point {h}, sample {}",
                            first + k as u32
                        );
                    }
                }
            }
        }
    }
}
