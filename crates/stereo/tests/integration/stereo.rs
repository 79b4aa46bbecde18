//! Closed-form and structural tests of the reprojection (Adelson & Hodges 1993).

use glam::Vec3;
use proptest::prelude::*;
use stereo::{reproject_row, Mode, Options, PixelClass, Quality, StereoFrame, NO_SOURCE};
use tracer::{
    Camera, Disparity, Eye, Film, Light, Material, Motion, Pixels, Record, RenderSettings, Renderer, Scene,
    SceneSphere, Target, Tracer,
};

fn seed() -> Scene {
    tracer::testing::scene("seed.toml")
}

fn full_right(tracer: &Tracer, camera: &Camera, w: u32, h: u32) -> Vec<u32> {
    let mut rgb = Vec::new();
    Renderer::new().render(tracer, &camera.view(Eye::Right, w, h), Pixels::All, Target::colour(&mut rgb));
    rgb
}

const REPROJECTING: [Mode; 3] = [Mode::Copy, Mode::Reshade, Mode::Exact];

#[test]
fn zero_ipd_reprojects_every_pixel_and_copies_the_left_eye() {
    let mut scene = seed();
    scene.camera.ipd = 0.0;
    let tracer = Tracer::new(&scene, 0.3);
    let mut frame = StereoFrame::new();
    for mode in REPROJECTING {
        for retrace_edges in [false, true] {
            let stats = frame.render(&tracer, &scene.camera, 160, 90, Options { mode, retrace_edges });
            assert_eq!(stats.pixels.reprojected, 160 * 90, "{mode}");
            assert_eq!(stats.right.rays.primary, 0, "{mode}");
            assert_eq!(frame.right().rgb, frame.left().rgb, "{mode}: right differs from left at IPD 0");
        }
    }
}

#[test]
fn a_point_at_known_depth_lands_where_the_right_camera_sees_it() {
    let camera = Camera { ipd: 0.65, distance: 12.0, fov_deg: 45.0, ..Camera::default() };
    let (w, h) = (640u32, 360u32);
    let (lv, rv) = (camera.view(Eye::Left, w, h), camera.view(Eye::Right, w, h));
    let disparity = Disparity::in_pixels(&camera, &rv);
    // Behind the window, on it, and in front of it.
    for z in [25.0f32, 3.0, 0.0, -4.0, -9.0] {
        for i in [40u32, 200, 320, 500] {
            let ray = lv.primary_ray(i, 100);
            // The point on the left pixel's ray at head-space depth z.
            let t = (z - lv.head_z(ray.origin)) / (lv.head_z(ray.origin + ray.dir) - lv.head_z(ray.origin));
            let p = ray.at(t);
            let expected = rv.project(p).unwrap().x;
            let mut zs = vec![f32::INFINITY; w as usize];
            zs[i as usize] = lv.head_z(p);
            let mut src = vec![0; w as usize];
            reproject_row(&zs, disparity, 0, &mut src, &mut Vec::new());
            let landed = src.iter().position(|&s| s == i);
            let Some(j) = landed else {
                assert!(!(0.0..w as f32).contains(&expected), "z = {z}, i = {i}: dropped but visible at {expected}");
                continue;
            };
            assert!(
                (j as f32 + 0.5 - expected).abs() <= 0.5 + 1e-3,
                "z = {z}, i = {i}: landed in {j}, right camera sees {expected}"
            );
        }
    }
}

fn sphere(center: Vec3, radius: f32, color: Vec3) -> SceneSphere {
    SceneSphere {
        radius,
        motion: Motion::Static(center),
        material: Material { color, specular: 0.4, shininess: 30.0, reflectivity: 0.3, ..Material::default() },
    }
}

#[test]
fn a_hidden_far_surface_never_overwrites_the_near_one() {
    // A near sphere in front of a large far one, IPD exaggerated so the disocclusion is wide.
    let scene = Scene {
        structures: Vec::new(),
        camera: Camera { ipd: 2.0, distance: 10.0, fov_deg: 40.0, ..Camera::default() },
        render: RenderSettings::default(),
        lights: vec![Light { position: Vec3::new(-5.0, 8.0, -5.0), color: Vec3::ONE }],
        spheres: vec![
            sphere(Vec3::new(0.0, 0.0, 30.0), 8.0, Vec3::new(0.2, 0.3, 0.9)),
            sphere(Vec3::new(0.5, 0.0, 8.0), 1.5, Vec3::new(0.9, 0.3, 0.2)),
        ],
    };
    let tracer = Tracer::new(&scene, 0.0);
    let (w, h) = (200u32, 120u32);
    let mut truth = Film::new(w, h);
    Renderer::new().render(
        &tracer,
        &scene.camera.view(Eye::Right, w, h),
        Pixels::All,
        Target::film(&mut truth, Record::Full),
    );
    let reference = truth.rgb.clone();
    let mut frame = StereoFrame::new();
    for mode in REPROJECTING {
        frame.render(&tracer, &scene.camera, w, h, Options { mode, retrace_edges: false });
        let (mask, src) = (frame.mask(), frame.sources());
        let mut gaps = 0;
        for k in 0..(w * h) as usize {
            if mask[k] != PixelClass::Reprojected {
                gaps += 1;
                assert_eq!(
                    frame.right().rgb[k],
                    reference[k],
                    "{mode}: retraced pixel {k} differs from the full trace"
                );
                continue;
            }
            let seen = frame.left().object[src[k] as usize];
            let truth_object = truth.object[k];
            // Away from silhouettes the reprojected object is the one the right eye sees.
            let (i, j) = ((k % w as usize) as i64, (k / w as usize) as i64);
            let interior = (-1..=1).all(|dj| {
                (-1..=1).all(|di| {
                    let (x, y) = (i + di, j + dj);
                    x < 0
                        || y < 0
                        || x >= i64::from(w)
                        || y >= i64::from(h)
                        || truth.object[(y * i64::from(w) + x) as usize] == truth_object
                })
            });
            if interior && truth_object == 1 {
                assert_eq!(seen, 1, "{mode}: far surface overwrote the near sphere at {k}");
            }
        }
        assert!(gaps > 2 * 120, "{mode}: expected a disoccluded strip, got {gaps} retraced pixels");
    }
}

#[test]
fn reshade_equals_copy_without_view_dependent_light() {
    let mut scene = seed();
    for s in &mut scene.spheres {
        s.material.specular = 0.0;
        s.material.reflectivity = 0.0;
    }
    let tracer = Tracer::new(&scene, 0.0);
    let mut frame = StereoFrame::new();
    frame.render(&tracer, &scene.camera, 256, 144, Options { mode: Mode::Copy, retrace_edges: true });
    let copy = frame.right().rgb.clone();
    frame.render(&tracer, &scene.camera, 256, 144, Options { mode: Mode::Reshade, retrace_edges: true });
    assert_eq!(frame.right().rgb, copy);
}

#[test]
fn copy_shows_the_seed_papers_seams_and_exact_removes_them() {
    let scene = seed();
    let tracer = Tracer::new(&scene, 0.0);
    let (w, h) = (320, 180);
    let reference = full_right(&tracer, &scene.camera, w, h);
    let mut frame = StereoFrame::new();
    let mut quality = |mode, retrace_edges| {
        let stats = frame.render(&tracer, &scene.camera, w, h, Options { mode, retrace_edges });
        (Quality::compare(&frame.right().rgb, &reference), stats)
    };
    let (copy, copy_stats) = quality(Mode::Copy, false);
    let (reshade, _) = quality(Mode::Reshade, true);
    let (exact, exact_stats) = quality(Mode::Exact, false);
    let (_, full_stats) = quality(Mode::Full, false);
    assert!(copy.share_not_identical > 0.02, "copy should differ visibly: {copy:?}");
    assert!(reshade.psnr_db > copy.psnr_db, "reshade {reshade:?} not better than copy {copy:?}");
    assert!(exact.share_identical() >= 0.999, "exact: {exact:?}");
    assert!(copy_stats.right_ray_ratio() < 0.15);
    // Exact mode saves primary rays only: its pixels see what the full trace's see, so they
    // cast the same shadow and mirror rays.
    let (e, f) = (exact_stats.right.rays, full_stats.right.rays);
    assert!(e.primary * 4 < f.primary, "exact: {e:?}, full: {f:?}");
    assert_eq!((e.shadow, e.reflection), (f.shadow, f.reflection), "exact: {e:?}, full: {f:?}");
}

/// A random scene: spheres in front of the camera, some lights, random materials.
fn arb_scene() -> impl Strategy<Value = Scene> {
    let sphere = (-6.0f32..6.0, -3.0f32..3.0, 4.0f32..40.0, 0.2f32..3.0, 0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0)
        .prop_map(|(x, y, z, r, c, spec, refl)| SceneSphere {
            radius: r,
            motion: Motion::Static(Vec3::new(x, y, z)),
            material: Material {
                color: Vec3::new(c, 1.0 - c, 0.5),
                diffuse: 0.7,
                specular: spec,
                shininess: 20.0,
                reflectivity: refl * 0.8,
            },
        });
    let light = (-10.0f32..10.0, 0.0f32..10.0, -10.0f32..10.0)
        .prop_map(|(x, y, z)| Light { position: Vec3::new(x, y, z), color: Vec3::ONE });
    (
        proptest::collection::vec(sphere, 1..10),
        proptest::collection::vec(light, 0..3),
        0.0f32..1.5,
        2.0f32..30.0,
        20.0f32..100.0,
        0u32..4,
    )
        .prop_map(|(spheres, lights, ipd, distance, fov_deg, max_depth)| Scene {
            structures: Vec::new(),
            camera: Camera { ipd, distance, fov_deg, ..Camera::default() },
            render: RenderSettings { max_depth, ..RenderSettings::default() },
            lights,
            // Keep the eyes outside every sphere.
            spheres: spheres
                .into_iter()
                .filter(|s| matches!(s.motion, Motion::Static(c) if c.length() > s.radius + 1.0))
                .collect(),
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn every_right_pixel_is_classified_once_and_retraced_pixels_are_exact(
        scene in arb_scene(),
        w in 4u32..72,
        h in 2u32..40,
        mode in prop_oneof![Just(Mode::Copy), Just(Mode::Reshade), Just(Mode::Exact)],
        retrace_edges in any::<bool>(),
    ) {
        let tracer = Tracer::new(&scene, 0.0);
        let reference = full_right(&tracer, &scene.camera, w, h);
        let mut frame = StereoFrame::new();
        let stats = frame.render(&tracer, &scene.camera, w, h, Options { mode, retrace_edges });
        let n = u64::from(w * h);
        prop_assert_eq!(stats.pixels.total(), n);
        prop_assert_eq!(stats.pixels.traced, 0);
        let retraced = n - stats.pixels.reprojected;
        prop_assert_eq!(stats.right.rays.primary, retraced, "only retraced pixels cast primary rays");
        for (k, &class) in frame.mask().iter().enumerate() {
            if class == PixelClass::Reprojected {
                prop_assert!(frame.sources()[k] != NO_SOURCE);
            } else {
                prop_assert_eq!(frame.right().rgb[k], reference[k], "retraced pixel {} differs from the full trace", k);
            }
        }
        if mode != Mode::Exact && !retrace_edges {
            prop_assert_eq!(stats.pixels.retraced_edge, 0);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    #[test]
    fn exact_matches_full_and_threads_do_not_matter(scene in arb_scene(), t in 0.0f32..8.0) {
        let (w, h) = (128, 72);
        let tracer = Tracer::new(&scene, t);
        let reference = full_right(&tracer, &scene.camera, w, h);
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut frame = StereoFrame::new();
                let stats = frame.render(&tracer, &scene.camera, w, h, Options { mode: Mode::Exact, retrace_edges: false });
                (frame.left().rgb.clone(), frame.right().rgb.clone(), frame.left().z.clone(), stats.left.rays, stats.right.rays, stats.pixels)
            })
        };
        let (one, two) = (run(1), run(2));
        prop_assert_eq!(&one.0, &two.0);
        prop_assert_eq!(&one.1, &two.1);
        prop_assert_eq!((one.3, one.4, one.5), (two.3, two.4, two.5));
        prop_assert!(one.2.iter().all(|z| !z.is_nan()), "NaN depth in the left film");
        let q = Quality::compare(&one.1, &reference);
        prop_assert!(q.share_identical() >= 0.999, "exact differs from full on {} pixels: {:?}", q.share_not_identical * f64::from(w * h), q);
    }

    #[test]
    fn zero_ipd_gives_identical_eyes_in_every_mode(scene in arb_scene(), w in 4u32..64, h in 2u32..36) {
        let mut scene = scene;
        scene.camera.ipd = 0.0;
        let tracer = Tracer::new(&scene, 0.0);
        let mut frame = StereoFrame::new();
        for mode in Mode::ALL {
            let stats = frame.render(&tracer, &scene.camera, w, h, Options { mode, retrace_edges: true });
            prop_assert_eq!(&frame.right().rgb, &frame.left().rgb, "{}", mode);
            if mode != Mode::Full {
                prop_assert_eq!(stats.pixels.reprojected, u64::from(w * h));
            }
        }
    }
}

#[test]
fn a_near_sphere_only_the_right_eye_sees_is_retraced() {
    // Found by the property test: a sphere close to the eyes at the right edge of the view.
    // The right eye sees part of it where the left eye saw only background, so the
    // reprojection alone would paint background there.
    let scene = Scene {
        structures: Vec::new(),
        camera: Camera { ipd: 0.444, distance: 28.84, fov_deg: 57.5, ..Camera::default() },
        render: RenderSettings { max_depth: 0, ..RenderSettings::default() },
        lights: vec![],
        spheres: vec![sphere(Vec3::new(3.825, 1.617, 4.0), 2.913, Vec3::new(0.0, 1.0, 0.5))],
    };
    let (w, h) = (128, 72);
    let tracer = Tracer::new(&scene, 0.0);
    let reference = full_right(&tracer, &scene.camera, w, h);
    let mut frame = StereoFrame::new();
    for mode in REPROJECTING {
        frame.render(&tracer, &scene.camera, w, h, Options { mode, retrace_edges: true });
        let (right, mask) = (&frame.right().rgb, frame.mask());
        for j in 0..h as usize {
            for i in 120..w as usize {
                let k = j * w as usize + i;
                assert_ne!(mask[k], PixelClass::Reprojected, "{mode}: ({i}, {j}) in the right border strip");
                assert_eq!(right[k], reference[k], "{mode}: ({i}, {j})");
            }
        }
    }
}

#[test]
fn a_terminator_down_the_left_edge_is_the_full_trace() {
    // Found by the property test: a sphere cut by the left edge of the image, lit from the
    // left. The terminator runs down the right eye's first column, between each pixel's own
    // point (lit) and its source in the left eye's second column (unlit). Exact mode once
    // reused the source's light bits and retraced where a neighbour's differed; it now casts
    // each pixel's own shadow rays, so the column is lit as in the full trace.
    let material = Material { color: Vec3::new(0.0, 1.0, 0.5), ..Material::default() };
    let scene = Scene {
        structures: Vec::new(),
        camera: Camera { ipd: 0.245_735_5, distance: 16.059_79, fov_deg: 27.517_273, ..Camera::default() },
        render: RenderSettings { max_depth: 0, ..RenderSettings::default() },
        lights: vec![Light { position: Vec3::new(-9.760_212, 0.0, -5.802_552), color: Vec3::ONE }],
        spheres: vec![SceneSphere {
            radius: 1.736_977_1,
            motion: Motion::Static(Vec3::new(-5.006_510_7, 0.0, 14.495_262)),
            material,
        }],
    };
    let (w, h) = (128, 72);
    let tracer = Tracer::new(&scene, 0.0);
    let reference = full_right(&tracer, &scene.camera, w, h);
    let mut frame = StereoFrame::new();
    frame.render(&tracer, &scene.camera, w, h, Options { mode: Mode::Exact, retrace_edges: false });
    let (right, mask) = (&frame.right().rgb, frame.mask());
    let mut reprojected = 0;
    for k in 0..(w * h) as usize {
        assert_eq!(right[k], reference[k], "({}, {}), {:?}", k % w as usize, k / w as usize, mask[k]);
        reprojected += usize::from(k % w as usize == 0 && mask[k] == PixelClass::Reprojected);
    }
    assert!(reprojected >= 10, "the first column is reprojected: {reprojected} pixels");
}

#[test]
fn a_banded_frame_shows_the_plain_frame_and_keeps_both_depths() {
    // The shown part of a frame traced with a guard band is the frame without one: the left
    // eye in every mode, the right eye where the mode is exact or full (reprojecting modes
    // may reproject band pixels into the shown part, where the plain frame retraces). The
    // depths are the films' own.
    let scene = seed();
    let tracer = Tracer::new(&scene, 0.3);
    let camera = Camera { yaw_deg: 9.0, ..scene.camera };
    let (w, h, (mx, my)) = (120u32, 68u32, (17u32, 9u32));
    for mode in Mode::ALL {
        let opts = Options { mode, retrace_edges: false };
        let (mut plain, mut banded) = (StereoFrame::new(), StereoFrame::new());
        banded.set_depths(true);
        plain.render(&tracer, &camera, w, h, opts);
        banded.render_banded(&tracer, &camera, (w, h), (mx, my), opts);
        let bw = (w + 2 * mx) as usize;
        let inside = |k: usize| (k / (w as usize) + my as usize) * bw + k % (w as usize) + mx as usize;
        for k in 0..(w * h) as usize {
            assert_eq!(plain.left().rgb[k], banded.left().rgb[inside(k)], "{mode:?} left pixel {k}");
            if matches!(mode, Mode::Exact | Mode::Full) {
                assert_eq!(plain.right().rgb[k], banded.right().rgb[inside(k)], "{mode:?} right pixel {k}");
            }
        }
        // Both eyes' depths: the left film's z, and the right eye's first hits.
        let bits = |z: &[f32]| z.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
        for (eye, got) in [(Eye::Left, &banded.left().z[..]), (Eye::Right, banded.right_depth())] {
            let mut want = Vec::new();
            let view = camera.view_with_margin(eye, w, h, (mx, my));
            Renderer::new().render(&tracer, &view, Pixels::All, Target::depth(&mut want));
            assert_eq!(bits(got), bits(&want), "{mode:?}: the {eye:?} eye's depth");
        }
        assert!(plain.right_depth().is_empty(), "{mode:?}: the right eye's depth only when asked for");
    }
}
