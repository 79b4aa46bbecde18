//! The warp against closed forms: its own pose gives the frame back, a sideways step moves
//! a point by the conventions' disparity formula, a turn moves the background by the
//! rotation, the nearer surface wins, a disocclusion of known width is filled as the rule
//! says, and the bytes do not depend on the threads or the lane width.

use fearless_simd::Level;
use glam::{Vec2, Vec3};
use tracer::{Camera, Disparity, Eye, EyeView, Film, Pixels, Record, Renderer, Scene, Target, Tracer};

use super::map::{EyeShift, WarpMap};
use super::scatter::land_one;
use super::{Warp, WarpClass, WarpCounts, WarpSource};

mod cracks;

const EYES: [Eye; 2] = [Eye::Left, Eye::Right];

/// One eye's colour and depth planes.
type Planes = (Vec<u32>, Vec<f32>);

/// The warp's output for both eyes.
struct Warped {
    out: [Vec<u32>; 2],
    classes: [Vec<WarpClass>; 2],
    counts: [WarpCounts; 2],
}

/// Warps the planes of `views` to `targets` with a new `Warp`, at `level`.
fn warp_at(level: Level, frames: &[Planes; 2], views: &[EyeView; 2], targets: &[EyeView; 2]) -> Warped {
    let sources = [0, 1].map(|e| WarpSource { view: views[e], rgb: &frames[e].0, z: &frames[e].1 });
    let (mut out, mut classes) = ([Vec::new(), Vec::new()], [Vec::new(), Vec::new()]);
    let [o0, o1] = &mut out;
    let [c0, c1] = &mut classes;
    let counts = Warp::new().warp_at(level, &sources, [&targets[0], &targets[1]], [o0, o1], [c0, c1]);
    for e in 0..2 {
        assert_eq!(counts[e].total(), u64::from(targets[e].width * targets[e].height), "eye {e}: the counts add up");
        let count = |c| classes[e].iter().filter(|&&k| k == c).count() as u64;
        let counted = WarpCounts {
            warped: count(WarpClass::Warped),
            crack: count(WarpClass::Crack),
            other_eye: count(WarpClass::OtherEye),
            filled: count(WarpClass::Filled),
        };
        assert_eq!(counts[e], counted, "eye {e}: the counts are the classes'");
    }
    Warped { out, classes, counts }
}

/// [`warp_at`] the level `Warp::warp` runs at.
fn warp(frames: &[Planes; 2], views: &[EyeView; 2], targets: &[EyeView; 2]) -> Warped {
    warp_at(tracer::widest_simd_level(), frames, views, targets)
}

/// Both eyes of the seed scene traced through `camera`, `w` × `h` with a guard band.
fn traced(camera: &Camera, w: u32, h: u32, margin: (u32, u32)) -> ([Planes; 2], [EyeView; 2]) {
    let scene = tracer::testing::scene("seed.toml");
    let tracer = Tracer::new(&scene, 0.0);
    let views = EYES.map(|eye| camera.view_with_margin(eye, w, h, margin));
    let frames = views.map(|view| {
        let mut film = Film::new(view.width, view.height);
        Renderer::new().render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Keys));
        (film.rgb, film.z)
    });
    (frames, views)
}

/// A frame of `view` made pixel by pixel: `f(c, r)` is the colour and depth of shown pixel
/// (c, r) (negative or past the shown size in the guard band).
fn synthetic(view: &EyeView, f: impl Fn(i32, i32) -> (u32, f32)) -> Planes {
    let (mx, my) = (view.margin.0 as i32, view.margin.1 as i32);
    (0..view.height as i32)
        .flat_map(|j| (0..view.width as i32).map(move |i| (i - mx, j - my)))
        .map(|(c, r)| f(c, r))
        .unzip()
}

fn seed_camera() -> Camera {
    Camera { ipd: 0.65, distance: 12.0, fov_deg: 45.0, ..Camera::default() }
}

#[test]
fn warping_a_frame_to_its_own_pose_gives_it_back_bit_for_bit() {
    let turned = Camera { yaw_deg: 20.0, pitch_deg: -7.0, position: Vec3::new(1.0, 2.0, -3.0), ..seed_camera() };
    let (w, h) = (96, 64);
    for camera in [seed_camera(), turned] {
        for margin in [(0, 0), (6, 4)] {
            let (frames, views) = traced(&camera, w, h, margin);
            // The shown part, without a band.
            let warped = warp(&frames, &views, &EYES.map(|eye| camera.view(eye, w, h)));
            for e in 0..2 {
                let shown: Vec<u32> = (0..h)
                    .flat_map(|r| (0..w).map(move |c| ((r + margin.1) * views[e].width + c + margin.0) as usize))
                    .map(|k| frames[e].0[k])
                    .collect();
                assert_eq!(warped.counts[e].warped, u64::from(w * h), "{margin:?} eye {e}: every pixel warped");
                let first = (0..shown.len()).find(|&k| warped.out[e][k] != shown[k]);
                assert_eq!(first, None, "{margin:?} eye {e}: the first pixel that differs (row-major)");
            }
            // And to the very views traced, band and all.
            let warped = warp(&frames, &views, &views);
            for (e, (out, classes)) in warped.out.iter().zip(&warped.classes).enumerate() {
                assert_eq!(*out, frames[e].0, "{margin:?} eye {e}: the banded frame itself");
                assert!(classes.iter().all(|&c| c == WarpClass::Warped), "{margin:?} eye {e}");
            }
        }
    }
}

/// Whether the target pixel (c, r) contains the continuous point `p`, give or take the
/// warp's rounding.
fn contains(c: usize, r: usize, p: Vec2) -> bool {
    let eps = 2e-3;
    let (c, r) = (c as f32, r as f32);
    p.x >= c - eps && p.x < c + 1.0 + eps && p.y >= r - eps && p.y < r + 1.0 + eps
}

#[test]
fn a_sideways_step_moves_a_point_by_the_disparity_formula() {
    // The head steps Δ to the right, not turning. Seen by one eye at the window, a point at
    // depth z moves by Δ·z/(d+z) (the eye's own shift, as the left-to-right eye shift
    // e·z/(d+z)), and the window moves with the head by Δ: in the new image it lands
    // Δ·z/(d+z) − Δ window units along (a point on the window, z = 0, moves by −Δ; the
    // background, z = ∞, stays).
    let camera = seed_camera();
    let (w, h, margin) = (120, 80, (8, 6));
    let (mut frames, views) = traced(&camera, w, h, margin);
    for frame in &mut frames {
        // Each pixel's colour is its index, so the output says where each landed.
        frame.0 = (0..frame.0.len() as u32).collect();
    }
    for delta in [0.37_f32, -0.21] {
        let moved = Camera { position: Vec3::new(delta, 0.0, 0.0), ..camera };
        let targets = EYES.map(|eye| moved.view(eye, w, h));
        let warped = warp(&frames, &views, &targets);
        for e in 0..2 {
            let (view, z) = (&views[e], &frames[e].1);
            let shift = |z: f32| Disparity { scale: delta, distance: camera.distance }.at(z) - delta;
            let expected = |k: usize| {
                let (i, j) = ((k % view.width as usize) as f32, (k / view.width as usize) as f32);
                let centre = Vec2::new(i - margin.0 as f32 + 0.5, j - margin.1 as f32 + 0.5);
                centre + Vec2::new(shift(z[k]) * view.pixels_per_unit(), 0.0)
            };
            // Every pixel the own eye covers holds a source pixel whose closed-form landing
            // lies in it.
            let mut checked = 0;
            for (t, (&k, &class)) in warped.out[e].iter().zip(&warped.classes[e]).enumerate() {
                if class == WarpClass::Warped {
                    let p = expected(k as usize);
                    assert!(
                        contains(t % w as usize, t / w as usize, p),
                        "Δ {delta} eye {e}: source {k} at {t}, not {p}"
                    );
                    checked += 1;
                }
            }
            assert!(checked > (w * h) as usize * 9 / 10, "eye {e}: {checked} pixels warped");
            // The sphere's centre pixel lands where the formula puts it.
            let centre = view.project(Vec3::new(0.0, 0.0, 15.0)).unwrap().floor();
            let k = centre.y as usize * view.width as usize + centre.x as usize;
            assert!(z[k] < 5.0, "the centre pixel sees the white sphere");
            let t = warped.out[e].iter().position(|&s| s as usize == k).unwrap();
            assert!(contains(t % w as usize, t / w as usize, expected(k)), "eye {e}: the sphere's centre at {t}");
            let (p, _) =
                land_one(&WarpMap::new(view, &targets[e]), k as u32 % view.width, k as u32 / view.width, z[k]).unwrap();
            assert!((p - expected(k)).length() < 1e-3, "eye {e}: the kernel puts it at {p}, not {}", expected(k));
        }
    }
}

#[test]
fn a_turn_moves_the_background_by_the_rotation() {
    // Yaw θ to the right: a background direction at angle φ from the view axis (towards +x,
    // measured from this eye) is at φ − θ after it, so its window point is
    // x' = e + d·tan(φ − θ) and y' = y·cos φ / cos(φ − θ). The eye's own move (it turns
    // about the head's centre) does not move a point at infinity.
    let camera = seed_camera();
    let (w, h) = (120, 80);
    let views = EYES.map(|eye| camera.view(eye, w, h));
    let frames = views.map(|v| synthetic(&v, |c, r| ((r * w as i32 + c) as u32, f32::INFINITY)));
    for yaw in [3.0_f32, -11.0] {
        let turned = Camera { yaw_deg: yaw, ..camera };
        let targets = EYES.map(|eye| turned.view(eye, w, h));
        let warped = warp(&frames, &views, &targets);
        for (e, v) in views.iter().enumerate() {
            let (window, d, eye) = (v.window_size().as_dvec2(), f64::from(v.distance()), f64::from(v.eye_offset()));
            let theta = f64::from(yaw).to_radians();
            let expected = |k: u32| {
                let (c, r) = (f64::from(k % w) + 0.5, f64::from(k / w) + 0.5);
                let (x, y) = ((c / f64::from(w) - 0.5) * window.x, (0.5 - r / f64::from(h)) * window.y);
                let phi = ((x - eye) / d).atan();
                let (x, y) = (eye + d * (phi - theta).tan(), y * phi.cos() / (phi - theta).cos());
                Vec2::new(((x / window.x + 0.5) * f64::from(w)) as f32, ((0.5 - y / window.y) * f64::from(h)) as f32)
            };
            let mut checked = 0;
            for (t, (&k, &class)) in warped.out[e].iter().zip(&warped.classes[e]).enumerate() {
                if class == WarpClass::Warped {
                    assert!(contains(t % w as usize, t / w as usize, expected(k)), "yaw {yaw} eye {e}: {k} at {t}");
                    checked += 1;
                }
            }
            // The turn exposes a strip of about d·tan θ window units at one side.
            let exposed = (f64::from(w) * d * theta.tan().abs() / window.x).ceil() as u64;
            assert!(checked as u64 >= u64::from(h) * (u64::from(w) - exposed) * 4 / 5, "yaw {yaw} eye {e}: {checked}");
        }
    }
}

const NEAR: u32 = 0xff_0000;
const FAR: u32 = 0x00_00ff;

#[test]
fn the_nearer_surface_wins_whatever_the_order() {
    // Half the frame near (z = 0), half far (or background). A sideways step slides the near
    // half over the far one by (s_near − s_far) pixels: 6.4 − 1.6 (or 6.4 − 0). Stepping
    // left with the near half on the left, its pixels are processed before the far ones
    // that land on the same target pixels; stepping right with it on the right, after.
    let camera = Camera { ipd: 0.5, ..seed_camera() };
    let (w, h) = (64, 8);
    let ppu = camera.view(Eye::Left, w, h).pixels_per_unit();
    for far in [36.0, f32::INFINITY] {
        for near_on_the_left in [true, false] {
            let step = if near_on_the_left { -6.4 } else { 6.4 } / ppu;
            let near = |c: i32| (c < 32) == near_on_the_left;
            let views = EYES.map(|eye| camera.view(eye, w, h));
            let frames = views.map(|v| synthetic(&v, |c, _| if near(c) { (NEAR, 0.0) } else { (FAR, far) }));
            let moved = Camera { position: Vec3::new(step, 0.0, 0.0), ..camera };
            let warped = warp(&frames, &views, &EYES.map(|eye| moved.view(eye, w, h)));
            // Near source columns land 6 columns along (c + 0.5 ± 6.4), over the far ones,
            // which land 2 (c + 0.5 ± 1.6) or 0 columns along.
            let near_cols = if near_on_the_left { 6..38 } else { 26..58 };
            let row = &warped.out[0][..w as usize];
            for c in near_cols.clone() {
                assert_eq!(row[c], NEAR, "far {far}, near on the left {near_on_the_left}: column {c}");
            }
            let far_cols = (0..w as usize).filter(|c| !near_cols.contains(c) && row[*c] == FAR).count();
            assert!(far_cols >= 24, "far {far}: the far half is still there ({far_cols})");
        }
    }
}

#[test]
fn a_disocclusion_of_known_width_is_filled_by_the_other_eye_then_by_the_rule() {
    // A card on the window (z = 0, columns 20..40, rows 8..24) before a wall (z = 36, where
    // d/(d+z) = ¼). The head steps D = 9 pixels right: from the same eye, the card moves
    // −9 and the wall −2.25 pixels (landing at c − 8.5 and c − 1.75: columns c − 9 and
    // c − 2), so behind the card's right edge 7 columns (31..38) are uncovered. The eyes are
    // E = 6 pixels apart. Into the left target, the right eye's wall moves
    // −(E·¾ + D·¼) = −6.75 (lands at c − 6.25: column c − 7), so its columns from 40 fill
    // 33..38 and 31..33 are left to the rule; into the right target, the left eye's wall
    // moves +E·¾ − D·¼ = +2.25: nothing lands in 31..38. The band (4 columns) covers the
    // edge the step exposes.
    let camera = seed_camera();
    let (w, h, margin) = (64, 32, (4, 2));
    let ppu = camera.view(Eye::Left, w, h).pixels_per_unit();
    let camera = Camera { ipd: 6.0 / ppu, ..camera };
    let card = |c: i32, r: i32| (20..40).contains(&c) && (8..24).contains(&r);
    let views = EYES.map(|eye| camera.view_with_margin(eye, w, h, margin));
    let frames = views.map(|v| {
        synthetic(
            &v,
            |c, r| if card(c, r) { (0xff_0000, 0.0) } else { (0x01_0000 + ((r + 2) * 72 + c + 4) as u32, 36.0) },
        )
    });
    let moved = Camera { position: Vec3::new(9.0 / ppu, 0.0, 0.0), ..camera };
    let warped = warp(&frames, &views, &EYES.map(|eye| moved.view(eye, w, h)));
    let card_rows = 16;
    let expected = [
        WarpCounts {
            warped: u64::from(w * h) - 7 * card_rows,
            crack: 0,
            other_eye: 5 * card_rows,
            filled: 2 * card_rows,
        },
        WarpCounts { warped: u64::from(w * h) - 7 * card_rows, crack: 0, other_eye: 0, filled: 7 * card_rows },
    ];
    assert_eq!(warped.counts, expected);
    for (e, first_other) in [(0, 33), (1, 38)] {
        for r in 0..h as usize {
            let row = &warped.out[e][r * w as usize..][..w as usize];
            let classes = &warped.classes[e][r * w as usize..][..w as usize];
            for (c, &class) in classes.iter().enumerate() {
                let expected = match c {
                    _ if !(8..24).contains(&r) => WarpClass::Warped,
                    31..38 if c < first_other => WarpClass::Filled,
                    31..38 => WarpClass::OtherEye,
                    _ => WarpClass::Warped,
                };
                assert_eq!(class, expected, "eye {e}: ({c}, {r})");
            }
            // The rule fills the hole from the wall beyond it (the farther side), not the card.
            if (8..24).contains(&r) {
                assert_eq!(row[29..31], [0xff_0000; 2], "eye {e} row {r}: the card");
                assert!(row[31..first_other].iter().all(|&p| p == row[first_other]), "eye {e} row {r}: {row:x?}");
                assert_ne!(row[first_other], 0xff_0000, "eye {e} row {r}: the wall");
            }
        }
    }
}

#[test]
fn rows_nothing_reached_copy_the_nearest_covered_row_and_an_empty_frame_is_black() {
    // Tilting up 12° exposes the rows above the traced frame: each copies the first row
    // something reached. Turning round, nothing lands at all: black.
    let camera = Camera { ipd: 0.0, ..seed_camera() };
    let (w, h) = (48, 32);
    let views = EYES.map(|eye| camera.view(eye, w, h));
    let frames = views.map(|v| synthetic(&v, |c, r| (1 + (r * 48 + c) as u32, f32::INFINITY)));
    let tilted = Camera { pitch_deg: 12.0, ..camera };
    let warped = warp(&frames, &views, &EYES.map(|eye| tilted.view(eye, w, h)));
    for e in 0..2 {
        let rows: Vec<&[WarpClass]> = warped.classes[e].chunks(w as usize).collect();
        let first = rows.iter().position(|row| row.iter().any(|&c| c != WarpClass::Filled)).unwrap();
        assert!(first >= 4, "eye {e}: the tilt leaves rows above the frame ({first})");
        let out: Vec<&[u32]> = warped.out[e].chunks(w as usize).collect();
        for r in 0..first {
            assert_eq!(out[r], out[first], "eye {e}: row {r} copies row {first}");
        }
        assert!(out[first].iter().all(|&p| p != 0), "eye {e}: the first covered row is all filled");
    }
    let round = Camera { yaw_deg: 180.0, ..camera };
    let warped = warp(&frames, &views, &EYES.map(|eye| round.view(eye, w, h)));
    for e in 0..2 {
        assert_eq!(warped.counts[e], WarpCounts { filled: u64::from(w * h), ..WarpCounts::default() });
        assert!(warped.out[e].iter().all(|&p| p == 0), "eye {e}: black");
    }
}

#[test]
fn the_same_bytes_for_any_thread_count_and_lane_width() {
    let camera = seed_camera();
    let (w, h, margin) = (160, 120, (8, 6));
    let (frames, views) = traced(&camera, w, h, margin);
    let moved = Camera { yaw_deg: 2.0, pitch_deg: -1.0, position: Vec3::new(0.1, 0.05, -0.2), ..camera };
    let targets = EYES.map(|eye| moved.view(eye, w, h));
    let run = |threads: usize, level: Level| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| warp_at(level, &frames, &views, &targets))
    };
    let one = run(1, tracer::simd_level());
    assert!(
        one.counts.iter().all(|c| c.crack > 0 && c.other_eye > 0 && c.filled > 0),
        "every class occurs: {:?}",
        one.counts
    );
    // Every width this CPU has (`Warp::warp` runs at the widest: AVX-512's 16 lanes on a
    // CPU that has them), on one thread and two.
    let levels = tracer::simd_levels().into_iter().flat_map(|level| [(1, level), (2, level)]);
    for (threads, level) in levels {
        let other = run(threads, level);
        assert_eq!(other.counts, one.counts, "{threads} threads, {level:?}");
        assert!(other.out == one.out && other.classes == one.classes, "{threads} threads, {level:?}: other bytes");
    }
}

#[test]
fn every_landing_lies_in_its_rows_reach_and_the_other_eye_is_the_disparity_away() {
    // The bands read only the source rows whose reach meets them (`WarpMap::rows_reached`),
    // and land the other eye's pixels by the disparity from their own eye's landing
    // (`EyeShift`): both checked pixel by pixel against the maps themselves, for turns,
    // tilts and steps in every direction.
    let camera = seed_camera();
    let (w, h, margin) = (64, 48, (6, 4));
    let (frames, views) = traced(&camera, w, h, margin);
    let poses = [
        Camera { yaw_deg: 4.0, pitch_deg: -3.0, ..camera },
        Camera { position: Vec3::new(0.3, -0.4, 0.8), ..camera },
        Camera { yaw_deg: -9.0, pitch_deg: 7.0, position: Vec3::new(-0.5, 0.6, -1.5), ..camera },
    ];
    for (p, pose) in poses.iter().enumerate() {
        let targets = EYES.map(|eye| pose.view(eye, w, h));
        for (s, (view, (_, z))) in views.iter().zip(&frames).enumerate() {
            let maps = targets.map(|t| WarpMap::new(view, &t));
            let shift = EyeShift::between(&targets[s], &targets[1 - s]);
            for j in 0..view.height {
                let row = &z[(j * view.width) as usize..][..view.width as usize];
                let nearest = row.iter().copied().fold(f32::INFINITY, f32::min);
                for (t, map) in maps.iter().enumerate() {
                    let reach = map.rows_reached(j, view.width, nearest);
                    for (i, &z) in (0..).zip(row) {
                        let Some((at, _)) = land_one(map, i, j, z) else { continue };
                        if at.y >= 0.0 && at.y < h as f32 && at.x >= 0.0 && at.x < w as f32 {
                            let (lo, hi) = reach.unwrap_or_else(|| panic!("pose {p} source {s} row {j}: no reach"));
                            let r = at.y.floor() as u32;
                            assert!(
                                (lo..=hi).contains(&r),
                                "pose {p} source {s}→{t} ({i}, {j}): row {r} not in {lo}..={hi}"
                            );
                        }
                    }
                }
                for (i, &z) in (0..).zip(row) {
                    let (Some((own, nz)), Some((other, _))) =
                        (land_one(&maps[s], i, j, z), land_one(&maps[1 - s], i, j, z))
                    else {
                        continue;
                    };
                    let parallax = if z.is_finite() { shift.parallax / nz } else { 0.0 };
                    let by_shift = own.x + shift.shift + parallax;
                    assert!(
                        (by_shift - other.x).abs() < 2e-3,
                        "pose {p} source {s} ({i}, {j}): {by_shift} and {}",
                        other.x
                    );
                    assert!(
                        (own.y - other.y).abs() < 2e-3,
                        "pose {p} source {s} ({i}, {j}): rows {} and {}",
                        own.y,
                        other.y
                    );
                }
            }
        }
    }
}

#[test]
#[should_panic(expected = "the sources must be [left, right]")]
fn the_sources_must_be_left_then_right() {
    let camera = seed_camera();
    let views = [Eye::Right, Eye::Left].map(|eye| camera.view(eye, 8, 4));
    let frames = views.map(|v| synthetic(&v, |_, _| (0, f32::INFINITY)));
    warp(&frames, &views, &EYES.map(|eye| camera.view(eye, 8, 4)));
}

#[test]
#[should_panic(expected = "the targets must be two eyes of one head pose")]
fn the_targets_must_be_one_head_pose() {
    let camera = seed_camera();
    let views = EYES.map(|eye| camera.view(eye, 8, 4));
    let frames = views.map(|v| synthetic(&v, |_, _| (0, f32::INFINITY)));
    let turned = Camera { yaw_deg: 1.0, ..camera };
    warp(&frames, &views, &[camera.view(Eye::Left, 8, 4), turned.view(Eye::Right, 8, 4)]);
}
