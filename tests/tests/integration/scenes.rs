//! Every scene in assets/scenes loads, and exact mode matches the full trace on it.

use stereo::{Mode, Options, Quality, StereoFrame};
use stereotrace_tests::scene_files;
use tracer::{Eye, Pixels, Renderer, Scene, Target, Tracer};

#[test]
fn exact_mode_equals_the_full_trace_on_every_scene() {
    let files = scene_files();
    assert!(files.len() >= 4, "expected the seed scene and at least three more, found {files:?}");
    let (w, h) = (320, 180);
    let mut frame = StereoFrame::new();
    let mut reference = Vec::new();
    let mut renderer = Renderer::new();
    for path in files {
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        for t in [0.0, 2.7] {
            let tracer = Tracer::new(&scene, t);
            renderer.render(&tracer, &scene.camera.view(Eye::Right, w, h), Pixels::All, Target::colour(&mut reference));
            let stats = frame.render(&tracer, &scene.camera, w, h, Options { mode: Mode::Exact, retrace_edges: false });
            let q = Quality::compare(&frame.right().rgb, &reference);
            assert!(
                q.share_identical() >= 0.999,
                "{}: t = {t}: exact mode differs from full on {:.3}% of pixels: {q:?}",
                path.display(),
                100.0 * q.share_not_identical
            );
            assert!(stats.right_ray_ratio() < 1.0, "{}: exact mode saved no rays", path.display());
        }
    }
}

/// Supersampled (2 × 2 samples per pixel), exact mode still matches the full trace: on the
/// samples, where reprojection works, and on the images filtered down from them.
#[test]
fn exact_mode_equals_the_full_trace_when_supersampled() {
    let (w, h, s) = (160, 90, 2);
    let (sw, sh) = (w * s, h * s);
    let mut frame = StereoFrame::new();
    let mut renderer = Renderer::new();
    let (mut reference, mut filtered_reference, mut filtered_right) = (Vec::new(), Vec::new(), Vec::new());
    for path in scene_files() {
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let tracer = Tracer::new(&scene, 1.3);
        renderer.render(&tracer, &scene.camera.view(Eye::Right, sw, sh), Pixels::All, Target::colour(&mut reference));
        let stats = frame.render(&tracer, &scene.camera, sw, sh, Options { mode: Mode::Exact, retrace_edges: false });
        assert_eq!(stats.pixels.total(), u64::from(sw * sh), "{}: the classes count samples", path.display());
        let q = Quality::compare(&frame.right().rgb, &reference);
        assert!(
            q.share_identical() >= 0.999,
            "{}: exact mode differs from full on {:.3}% of samples: {q:?}",
            path.display(),
            100.0 * q.share_not_identical
        );
        stereo::downsample(&reference, (sw, sh), &mut filtered_reference, (w, h));
        stereo::downsample(&frame.right().rgb, (sw, sh), &mut filtered_right, (w, h));
        let q = Quality::compare(&filtered_right, &filtered_reference);
        assert!(
            q.share_identical() >= 0.999,
            "{}: filtered, exact mode differs from full on {:.3}% of pixels: {q:?}",
            path.display(),
            100.0 * q.share_not_identical
        );
    }
}
