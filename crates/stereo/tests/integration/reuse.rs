//! Exact temporal reuse (`stereo/src/reuse/`): every reused frame is the fresh frame, byte for byte,
//! in every mode, on random scenes with orbiting spheres at random times and steps.

use glam::Vec3;
use proptest::prelude::*;
use stereo::{Mode, Options, StereoFrame};
use tracer::testing::scene;
use tracer::{Camera, Light, Material, Motion, RenderSettings, Scene, SceneSphere, Tracer};

/// Everything a frame shows and records, to compare two frames by.
#[derive(Debug, PartialEq)]
struct Shown {
    left: Vec<u32>,
    z: Vec<u32>,
    object: Vec<u32>,
    lights: Vec<u32>,
    right: Vec<u32>,
    /// The right eye's first hits, object and depth bits, when kept.
    right_hits: Option<(Vec<u32>, Vec<u32>)>,
    mask: Vec<stereo::PixelClass>,
    pixels: stereo::PixelCounts,
}

fn shown(frame: &StereoFrame, mode: Mode) -> Shown {
    let left = frame.left();
    let keys = mode != Mode::Full;
    let keep = |v: &[u32]| if keys { v.to_vec() } else { Vec::new() };
    Shown {
        left: left.rgb.clone(),
        z: if keys { left.z.iter().map(|z| z.to_bits()).collect() } else { Vec::new() },
        object: keep(&left.object),
        lights: keep(&left.lights),
        right: frame.right().rgb.clone(),
        right_hits: frame
            .first_hits(tracer::Eye::Right)
            .map(|(object, z)| (object.to_vec(), z.iter().map(|z| z.to_bits()).collect())),
        mask: frame.mask().to_vec(),
        pixels: frame.stats().pixels,
    }
}

/// Renders `times` with reuse on, in one frame, and checks each against a fresh frame, both
/// keeping depths if `depths` (then the right eye's first hits too, which the right eye's
/// own pass makes in full and exact modes, and keeps where it does not make a pixel again);
/// returns the share of pixels retraced in each reused frame.
fn check_reuse(scene: &Scene, times: &[f32], (w, h): (u32, u32), opts: Options, depths: bool) -> Vec<f64> {
    let mut reusing = StereoFrame::new();
    reusing.set_reuse(Some(scene));
    reusing.set_depths(depths);
    let mut fresh = StereoFrame::new();
    fresh.set_depths(depths);
    let mut tracer = Tracer::new(scene, times[0]);
    let mut shares = Vec::new();
    for (k, &t) in times.iter().enumerate() {
        tracer.advance(scene, t);
        let stats = reusing.render(&tracer, &scene.camera, w, h, opts);
        assert_eq!(stats.reuse.reused, k > 0, "frame {k} at t = {t}: reused after the first (which marks)");
        fresh.render(&tracer, &scene.camera, w, h, opts);
        if depths {
            crate::cues::assert_kept_first_hits(&tracer, &fresh, &format!("{opts:?} frame {k} at t = {t}, fresh"));
        }
        let (a, b) = (shown(&reusing, opts.mode), shown(&fresh, opts.mode));
        if a != b {
            let differ = a.right.iter().zip(&b.right).filter(|(x, y)| x != y).count();
            let left = a.left.iter().zip(&b.left).filter(|(x, y)| x != y).count();
            let hits = a.right_hits != b.right_hits;
            panic!(
                "{opts:?} frame {k} at t = {t}: {left} left and {differ} right pixels differ from a fresh frame \
                 (right first hits differ: {hits})"
            );
        }
        if k > 0 {
            shares.push(stats.reuse.retraced_share());
        }
    }
    shares
}

fn every_option() -> impl Iterator<Item = Options> {
    Mode::ALL.into_iter().flat_map(|mode| [false, true].map(|retrace_edges| Options { mode, retrace_edges }))
}

/// `scene` with every orbiting sphere stopped where it is at t = 0: nothing moves.
fn still(scene: &Scene) -> Scene {
    let mut still = scene.clone();
    for (k, sphere) in still.spheres.iter_mut().enumerate() {
        sphere.motion = Motion::Static(scene.sphere_at(k, 0.0).center);
    }
    still
}

#[test]
fn reused_frames_of_the_bundled_scenes_are_fresh_frames() {
    for name in ["seed.toml", "many.toml", "window.toml", "thousand.toml"] {
        for scene in [scene(name), still(&scene(name))] {
            check_scene(name, &scene);
        }
    }
}

/// Every option of [`check_reuse`] on `scene` (called `name`): an animated scene keeps
/// something of each frame, a still one everything (and its tracer is never asked to mark).
fn check_scene(name: &str, scene: &Scene) {
    for (k, opts) in every_option().enumerate() {
        // Depths kept for every other option: each mode with and without.
        let shares = check_reuse(scene, &[0.0, 1.0 / 60.0, 0.5, 0.51, 3.7], (96, 54), opts, k % 2 == 1);
        if scene.is_animated() {
            assert!(shares.iter().all(|&s| s < 1.0), "{name} {opts:?}: something is kept ({shares:?})");
        } else {
            assert!(shares.iter().all(|&s| s == 0.0), "{name} {opts:?}: a still scene keeps everything");
        }
    }
}

#[test]
fn anything_but_time_starts_afresh() {
    let scene = scene("seed.toml");
    let tracer = Tracer::new(&scene, 0.0);
    let opts = Options { mode: Mode::Exact, retrace_edges: true };
    let mut frame = StereoFrame::new();
    frame.set_reuse(Some(&scene));
    let first = frame.render(&tracer, &scene.camera, 64, 36, opts);
    assert!(!first.reuse.reused && first.reuse.retraced_share() == 1.0, "the first frame is fresh");
    assert!(frame.render(&tracer, &scene.camera, 64, 36, opts).reuse.reused, "same request: reused");
    let moved = Camera { position: Vec3::new(0.1, 0.0, 0.0), ..scene.camera };
    assert!(!frame.render(&tracer, &moved, 64, 36, opts).reuse.reused, "the head moved");
    assert!(!frame.render(&tracer, &moved, 64, 36, opts).reuse.reused, "held still once: marks, fresh");
    assert!(frame.render(&tracer, &moved, 64, 36, opts).reuse.reused, "held still twice: reused");
    assert!(!frame.render(&tracer, &moved, 64, 37, opts).reuse.reused, "resized");
    assert!(!frame.render(&tracer, &moved, 64, 37, Options { mode: Mode::Copy, ..opts }).reuse.reused, "mode");
    let mut lit = scene.clone();
    lit.lights[0].position.x += 1.0;
    let stats = frame.render(&Tracer::new(&lit, 0.0), &moved, 64, 37, Options { mode: Mode::Copy, ..opts });
    assert!(!stats.reuse.reused, "a light moved");
    let mut deeper = Tracer::new(&lit, 0.0);
    deeper.set_max_depth(1);
    let stats = frame.render(&deeper, &moved, 64, 37, Options { mode: Mode::Copy, ..opts });
    assert!(!stats.reuse.reused, "reflection depth");
    let copy = Options { mode: Mode::Copy, ..opts };
    assert!(!frame.render(&deeper, &moved, 64, 37, copy).reuse.reused, "held still once: marks, fresh");
    assert!(frame.render(&deeper, &moved, 64, 37, copy).reuse.reused, "held still twice: reused");
    frame.set_depths(true);
    assert!(!frame.render(&deeper, &moved, 64, 37, copy).reuse.reused, "depths kept from now on");
    assert!(!frame.render(&deeper, &moved, 64, 37, copy).reuse.reused, "held still once: marks, fresh");
    assert!(frame.render(&deeper, &moved, 64, 37, copy).reuse.reused, "held still twice: reused");
    frame.set_depths(false);
    assert!(!frame.render(&deeper, &moved, 64, 37, copy).reuse.reused, "depths no longer kept");
    frame.set_reuse(None);
    assert!(!frame.render(&deeper, &moved, 64, 37, Options { mode: Mode::Copy, ..opts }).reuse.reused, "reuse off");
}

/// A random scene: a few still spheres and orbiting ones, some mirrors, one or two lights,
/// all in front of the camera.
fn scene_strategy() -> impl Strategy<Value = Scene> {
    let material = (0.0f32..1.0, 0.0f32..1.0, 1.0f32..80.0, prop_oneof![Just(0.0f32), 0.1f32..0.8]).prop_map(
        |(diffuse, specular, shininess, reflectivity)| Material {
            color: Vec3::new(0.8, 0.5, 0.3),
            diffuse,
            specular,
            shininess,
            reflectivity,
        },
    );
    let still = (prop::array::uniform3(-4.0f32..4.0), 0.3f32..2.0, material.clone()).prop_map(|(c, r, material)| {
        SceneSphere { radius: r, motion: Motion::Static(Vec3::new(c[0], c[1], c[2] + 14.0)), material }
    });
    let orbit = (prop::array::uniform3(-3.0f32..3.0), 0.0f32..4.0, 0.2f32..1.0, 1.0f32..10.0, 0.0f32..360.0).prop_map(
        |(c, radius, r, period_s, phase_deg)| SceneSphere {
            radius: r,
            motion: Motion::Orbit { center: Vec3::new(c[0], c[1], c[2] + 14.0), radius, period_s, phase_deg },
            material: Material { color: Vec3::new(0.2, 0.4, 0.9), ..material_default(r) },
        },
    );
    let light = prop::array::uniform3(-10.0f32..10.0)
        .prop_map(|p| Light { position: Vec3::new(p[0], p[1].abs() + 2.0, p[2]), color: Vec3::splat(0.8) });
    (
        prop::collection::vec(still, 1..5),
        prop::collection::vec(orbit, 1..3),
        prop::collection::vec(light, 1..3),
        1u32..4,
        0.0f32..1.0,
    )
        .prop_map(|(mut spheres, orbits, lights, max_depth, ipd)| {
            spheres.extend(orbits);
            Scene {
                structures: Vec::new(),
                camera: Camera { ipd, distance: 12.0, fov_deg: 45.0, ..Camera::default() },
                render: RenderSettings { max_depth, ..RenderSettings::default() },
                lights,
                spheres,
            }
        })
}

/// A shiny, partly mirroring material (the orbiting spheres' own reflections move too).
fn material_default(r: f32) -> Material {
    Material { diffuse: 0.7, specular: 0.5, shininess: 30.0, reflectivity: 0.3 * r, ..Material::default() }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn every_reused_frame_is_the_fresh_frame(
        scene in scene_strategy(),
        t0 in 0.0f32..20.0,
        steps in prop::collection::vec(0.001f32..2.0, 2..4),
        mode in prop::sample::select(Mode::ALL.to_vec()),
        retrace_edges in any::<bool>(),
        depths in any::<bool>(),
    ) {
        let mut times = vec![t0];
        for dt in steps {
            times.push(times[times.len() - 1] + dt);
        }
        check_reuse(&scene, &times, (48, 32), Options { mode, retrace_edges }, depths);
    }
}

/// Reused frames, like fresh ones, are the same bytes for one thread and for two.
#[test]
fn reused_frames_are_the_same_for_one_and_two_threads() {
    let scene = scene("seed.toml");
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
        pool.install(|| {
            let mut frame = StereoFrame::new();
            frame.set_reuse(Some(&scene));
            let mut tracer = Tracer::new(&scene, 0.0);
            let opts = Options { mode: Mode::Exact, retrace_edges: true };
            let mut shown = Vec::new();
            for k in 0..4 {
                tracer.advance(&scene, k as f32 / 30.0);
                let stats = frame.render(&tracer, &scene.camera, 96, 54, opts);
                shown.push((shown_of(&frame), stats.reuse));
            }
            shown
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(one.iter().skip(1).all(|(_, reuse)| reuse.reused), "frames after the first reuse");
    assert!(one == two, "one and two threads differ");
}

fn shown_of(frame: &StereoFrame) -> Shown {
    shown(frame, Mode::Exact)
}
