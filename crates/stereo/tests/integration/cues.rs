//! The cues (ambient occlusion, depth cueing, outlines) in a stereo pair: exact mode's right
//! eye, outlines included, is the full trace's, and the bytes do not depend on the thread
//! count.

use stereo::{Mode, Options, Outlined, StereoFrame};
use tracer::{sized_cues, AmbientOcclusion, Cues, Eye, Renderer, Scene, Tracer};

/// `scene` with every cue on, sized to it: `samples` occlusion rays, Exp2 depth cueing,
/// outlines `outline` pixels wide.
fn with_cues(mut scene: Scene, samples: u32, outline: u32) -> Scene {
    let sized = sized_cues(tracer::scene_bounds(&scene), scene.camera.position, samples);
    let ambient_occlusion = AmbientOcclusion { strength: 0.8, ..sized.ambient_occlusion };
    scene.render.cues = Cues { ambient_occlusion, outline, ..sized };
    scene
}

/// Both eyes of a `w` × `h` pair in `mode`, outlined, on `threads` threads.
fn pair(tracer: &Tracer, scene: &Scene, (w, h): (u32, u32), mode: Mode, threads: usize) -> [Vec<u32>; 2] {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap_or_else(|e| panic!("a pool: {e}"));
    pool.install(|| {
        let mut frame = StereoFrame::new();
        frame.render(tracer, &scene.camera, w, h, Options { mode, retrace_edges: false });
        let mut outlined = Outlined::new();
        outlined.eyes(tracer, &frame, scene.render.cues.outline as f32).map(<[u32]>::to_vec)
    })
}

fn exact_is_full(scene: &Scene, size: (u32, u32)) {
    let tracer = Tracer::new(scene, 0.4);
    let full = pair(&tracer, scene, size, Mode::Full, 2);
    let exact = pair(&tracer, scene, size, Mode::Exact, 2);
    assert_eq!(exact[0], full[0], "the left eyes");
    let differ = exact[1].iter().zip(&full[1]).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "exact's right eye differs from full's on {differ} pixels");
    assert_eq!(pair(&tracer, scene, size, Mode::Exact, 1), exact, "1 thread against 2");
    let outlined = full[1].iter().filter(|&&c| c == 0).count();
    assert!(outlined > 50, "the outlines are drawn: {outlined} pixels");
}

#[test]
fn exact_is_full_with_every_cue_on_the_seed_scene() {
    exact_is_full(&with_cues(tracer::testing::scene("seed.toml"), 6, 2), (160, 90));
}

/// 1TII as a structure file opens (its default cues on), or `None`, said, where pymol-data
/// is not installed.
fn tii() -> Option<Scene> {
    let path = "/usr/share/pymol/data/demo/1tii.pdb";
    if !std::path::Path::new(path).exists() {
        tracer::testing::skipped("1tii.pdb is not installed (pymol-data)");
        return None;
    }
    Some(Scene::load(path).unwrap_or_else(|e| panic!("1TII loads: {e}")))
}

#[test]
fn exact_is_full_with_every_cue_on_1tii() {
    let Some(scene) = tii() else { return };
    assert!(scene.render.cues.ambient_occlusion.is_on() && scene.render.cues.outline == 1, "on by default");
    exact_is_full(&scene, (200, 150));
}

/// Each eye's first hits as `frame` kept them against a first-hits pass of that eye's view
/// (`tracer::first_hits`), bit for bit; names the first pixel that differs.
pub(crate) fn assert_kept_first_hits(tracer: &Tracer, frame: &StereoFrame, at: &str) {
    for (k, eye) in [Eye::Left, Eye::Right].into_iter().enumerate() {
        let view = &frame.views().eyes[k];
        let (mut object, mut z) = (Vec::new(), Vec::new());
        tracer::first_hits(&mut Renderer::new(), tracer, view, &mut object, &mut z);
        let kept = frame.first_hits(eye).unwrap_or_else(|| panic!("{at}: {eye:?}'s planes kept"));
        assert!(kept.0.len() == object.len() && kept.1.len() == z.len(), "{at}: {eye:?}'s planes' size");
        let differ = (0..object.len()).find(|&p| (kept.0[p], kept.1[p].to_bits()) != (object[p], z[p].to_bits()));
        if let Some(p) = differ {
            let (i, j) = (p as u32 % view.width, p as u32 / view.width);
            let n = (0..object.len()).filter(|&p| (kept.0[p], kept.1[p].to_bits()) != (object[p], z[p].to_bits()));
            panic!(
                "{at}: {eye:?}'s first hits differ on {} pixels, first ({i}, {j}): kept object {} at z {:e}, a \
                 first-hits pass {} at z {:e}",
                n.count(),
                kept.0[p],
                kept.1[p],
                object[p],
                z[p]
            );
        }
    }
}

/// A frame's shown size and its guard band.
type Sized = ((u32, u32), (u32, u32));

/// The planes outlines read, of a frame that keeps depths, at each of `sizes` in every mode:
/// the left film's, and the right eye's from its own pass (full and exact modes) or a
/// first-hits pass (copy, reshade), all a first-hits pass's of each eye's view; none before
/// depths are kept in full mode (the left film keeps colour alone).
fn kept_first_hits_are_a_first_hits_pass(scene: &Scene, sizes: &[Sized]) {
    let tracer = Tracer::new(scene, 0.4);
    let mut frame = StereoFrame::new();
    let (size, margin) = sizes[0];
    frame.render_banded(&tracer, &scene.camera, size, margin, Options { mode: Mode::Full, retrace_edges: false });
    assert!(frame.first_hits(Eye::Left).is_none() && frame.first_hits(Eye::Right).is_none(), "no depths kept");
    frame.set_depths(true);
    for &(size, margin) in sizes {
        for opts in
            Mode::ALL.into_iter().flat_map(|mode| [false, true].map(|retrace_edges| Options { mode, retrace_edges }))
        {
            frame.render_banded(&tracer, &scene.camera, size, margin, opts);
            assert_kept_first_hits(&tracer, &frame, &format!("{size:?} band {margin:?} {opts:?}"));
            let seen = frame.first_hits(Eye::Right).map(|(object, _)| object.iter().any(|&o| o != tracer::NO_OBJECT));
            assert_eq!(seen, Some(true), "{size:?} {opts:?}: the right eye sees something");
        }
    }
}

#[test]
fn a_frame_keeps_each_eyes_first_hits_as_a_pass_of_their_own_finds_them() {
    let scene = with_cues(tracer::testing::scene("seed.toml"), 0, 1);
    kept_first_hits_are_a_first_hits_pass(&scene, &[((96, 54), (0, 0)), ((160, 90), (7, 3))]);
}

#[test]
fn on_1tii_a_frame_keeps_each_eyes_first_hits_as_a_pass_of_their_own_finds_them() {
    let Some(mut scene) = tii() else { return };
    scene.render.cues.ambient_occlusion = AmbientOcclusion::default();
    // The size, and a guard band.
    kept_first_hits_are_a_first_hits_pass(&scene, &[((800, 600), (0, 0)), ((300, 200), (12, 8))]);
}

#[test]
fn a_moving_scene_with_occlusion_is_not_reused() {
    let mut frame = StereoFrame::new();
    let many = tracer::testing::scene("many.toml");
    frame.set_reuse(Some(&many));
    assert!(frame.reuse(), "without occlusion, reused");
    frame.set_reuse(Some(&with_cues(many, 4, 0)));
    assert!(!frame.reuse(), "occlusion rays are not marked: traced afresh");
}
