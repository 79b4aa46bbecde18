//! Every scene in assets/scenes loads, and exact mode matches the full trace on it.

use stereo::{Mode, Options, Quality, StereoFrame};
use stereotrace_tests::scene_files;
use tracer::{Eye, Renderer, Scene, Tracer};

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
            renderer.render_rgb(&tracer, &scene.camera.view(Eye::Right, w, h), &mut reference);
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
