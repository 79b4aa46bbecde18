//! The crack rule against scenes whose cracks are known: a big sphere neared, stepped
//! towards and turned to, and a magnified plane, its cracks at the band seams too.

use super::*;

/// A scene of one big matte orange sphere before a pure blue background.
fn big_sphere() -> Scene {
    let toml = r"
        [camera]
        ipd = 0.65
        distance = 12.0
        fov_deg = 45.0
        [render]
        max_depth = 1
        background = [0.0, 0.0, 1.0]
        ambient = 0.2
        [[lights]]
        position = [-6.0, 10.0, -8.0]
        color = [1.0, 1.0, 1.0]
        [[spheres]]
        center = [1.0, 0.0, 20.0]
        radius = 5.0
        color = [1.0, 0.5, 0.0]
        diffuse = 0.8
        specular = 0.0
        shininess = 1.0
        reflectivity = 0.0
    ";
    Scene::from_toml(toml, "big_sphere.toml").unwrap()
}

/// Both eyes of `scene` traced through `views`.
fn trace_views(scene: &Scene, views: &[EyeView; 2]) -> [Planes; 2] {
    let tracer = Tracer::new(scene, 0.0);
    views.map(|view| {
        let mut film = Film::new(view.width, view.height);
        Renderer::new().render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Keys));
        (film.rgb, film.z)
    })
}

#[test]
fn a_step_or_a_turn_towards_a_big_sphere_leaves_cracks_filled_with_the_sphere() {
    // Nearing the sphere, or stepping and turning, the warp magnifies it: rows and columns
    // of its pixels get no source pixel. Each is a crack of the sphere, and takes its
    // colour: inside the sphere's silhouette as traced at the new pose (give or take two
    // pixels at its edge), no pixel is the other eye's (the background beside its
    // silhouette: speckles) or the row rule's (the background beside it: stripes). The
    // own eye's pixels are its own landings: at the edge that advances over the
    // background, a crack there may hold a background pixel of the own eye (the rule
    // fills only what the own eye did not reach; module doc).
    let scene = big_sphere();
    let camera = scene.camera;
    let (w, h, margin) = (160, 120, (8, 6));
    let views = EYES.map(|eye| camera.view_with_margin(eye, w, h, margin));
    let frames = trace_views(&scene, &views);
    let background = frames[0].0[0];
    assert_eq!(background, 0x00_00ff, "the corner sees the background");
    let poses = [
        ("a step towards it", Camera { position: Vec3::new(0.0, 0.0, 1.0), ..camera }),
        ("a step and a turn", Camera { yaw_deg: 6.0, position: Vec3::new(0.5, 0.0, 0.0), ..camera }),
        ("a tilt and a step", Camera { pitch_deg: 4.0, position: Vec3::new(0.0, 0.3, 0.5), ..camera }),
    ];
    for (what, pose) in poses {
        let targets = EYES.map(|eye| pose.view(eye, w, h));
        let warped = warp(&frames, &views, &targets);
        let truth = trace_views(&scene, &targets);
        for (e, (_, depth)) in truth.iter().enumerate() {
            assert!(warped.counts[e].crack > 50, "{what} eye {e}: cracks {:?}", warped.counts[e]);
            let sphere = |c: i32, r: i32| {
                (0..w as i32).contains(&c) && (0..h as i32).contains(&r) && depth[(r * w as i32 + c) as usize] < 1e3
            };
            for r in 0..h as i32 {
                for c in 0..w as i32 {
                    // Two pixels inside the silhouette all round.
                    if !(-2..=2).all(|dr| (-2..=2).all(|dc| sphere(c + dc, r + dr))) {
                        continue;
                    }
                    let k = (r * w as i32 + c) as usize;
                    let (class, colour) = (warped.classes[e][k], warped.out[e][k]);
                    assert!(
                        class == WarpClass::Warped || (class == WarpClass::Crack && colour != background),
                        "{what} eye {e}: ({c}, {r}) is {class:?}, {colour:06x}"
                    );
                }
            }
        }
    }
}

#[test]
fn a_magnified_plane_has_cracks_that_take_their_upper_or_left_neighbour_at_the_band_seams_too() {
    // A plane parallel to the window, traced at 80×60 and warped to 100×75 from the same
    // pose: every source pixel (i, j) lands on column ⌊(i + ½)·5/4⌋ and row ⌊(j + ½)·5/4⌋
    // (a quarter pixel or more from a pixel edge), so the columns and rows 2, 7, 12, … get
    // none: cracks, whose ends are at one depth, so each takes its upper neighbour, or,
    // where a crack row crosses a crack column, its left one (a column crack itself). Rows
    // 32 and 62 are beside the band seams at 32 and 64, resolved after the bands.
    let camera = Camera { ipd: 0.0, ..seed_camera() };
    let (w, h) = (100_usize, 75_usize);
    let views = EYES.map(|eye| camera.view(eye, 80, 60));
    let frames = views.map(|v| synthetic(&v, |c, r| ((r * 80 + c) as u32, 7.0)));
    let warped = warp(&frames, &views, &EYES.map(|eye| camera.view(eye, w as u32, h as u32)));
    let crack = |t: usize| t % 5 == 2;
    // The source pixel landing on target t (not a crack).
    let source =
        |t: usize| (0..80).find(|&s| (s as f32 + 0.5) * 1.25 >= t as f32 && ((s as f32 + 0.5) * 1.25) < t as f32 + 1.0);
    for e in 0..2 {
        let cracks = (w / 5) * h + (h / 5) * w - (w / 5) * (h / 5);
        assert_eq!(
            warped.counts[e],
            WarpCounts { warped: (w * h - cracks) as u64, crack: cracks as u64, ..WarpCounts::default() }
        );
        for r in 0..h {
            for c in 0..w {
                let (rr, cc) = (if crack(r) { r - 1 } else { r }, if crack(c) { c - 1 } else { c });
                let expected = (source(rr).unwrap() * 80 + source(cc).unwrap()) as u32;
                let class = if crack(r) || crack(c) { WarpClass::Crack } else { WarpClass::Warped };
                let k = r * w + c;
                assert_eq!((warped.out[e][k], warped.classes[e][k]), (expected, class), "eye {e}: ({c}, {r})");
            }
        }
    }
}
