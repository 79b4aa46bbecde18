//! Tests: a render finds the same first hits through the screen bins and through the BVH, so
//! every image, record, mark and count is the same whichever [`FirstHits`] it takes.

use glam::Vec3;

use super::*;
use crate::batch::{RowPlan, KEEP, TRACE};
use crate::camera::{Camera, Eye};
use crate::material::Material;
use crate::reuse::Swept;
use crate::scene::{Light, Motion, Scene, SceneSphere};
use crate::testing::XorShift;

/// Every plane of a film, the depths and `t` as bits.
type Planes = (Vec<u32>, Vec<u32>, Vec<u32>, Vec<u32>, Vec<u32>, Vec<crate::surface::Shading>);

fn planes(film: &Film) -> Planes {
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    (film.rgb.clone(), bits(&film.z), bits(&film.t), film.object.clone(), film.lights.clone(), film.shading.clone())
}

/// Renders `view` of `tracer` with `first_hits`: the full film, the colour-only image, the
/// depth pass, the marks and the counts.
fn every_target(
    tracer: &Tracer,
    view: &EyeView,
    swept: &Swept,
    first_hits: FirstHits,
) -> (Planes, Vec<u32>, Vec<u32>, Vec<crate::reuse::Touch>, RayCounts) {
    let mut renderer = Renderer::new().with_first_hits(first_hits);
    let (mut film, mut marks) = (Film::new(1, 1), Marks::default());
    let target = Target::film(&mut film, Record::Full).marking(&mut marks, swept);
    let counts = renderer.render(tracer, view, Pixels::All, target);
    let (mut rgb, mut z) = (Vec::new(), Vec::new());
    assert_eq!(renderer.render(tracer, view, Pixels::All, Target::colour(&mut rgb)), counts);
    renderer.render(tracer, view, Pixels::All, Target::depth(&mut z));
    let touches = (0..film.rgb.len()).map(|k| marks.touch(k)).collect();
    (planes(&film), rgb, z.iter().map(|z| z.to_bits()).collect(), touches, counts)
}

/// Asserts that both searches give every target of `view` alike, and returns its hits.
fn assert_alike(name: &str, tracer: &Tracer, view: &EyeView, swept: &Swept) -> usize {
    let bins = every_target(tracer, view, swept, FirstHits::Bins);
    let bvh = every_target(tracer, view, swept, FirstHits::Bvh);
    assert_eq!(every_target(tracer, view, swept, FirstHits::Sliced), bvh, "{name}: the sliced bins, then BVH");
    let (w, h) = (view.width, view.height);
    let (a, b) = (&bins.0, &bvh.0);
    for k in 0..a.0.len() {
        let at = |p: &Planes| (p.0[k], p.1[k], p.2[k], p.3[k], p.4[k], p.5[k]);
        assert_eq!(at(a), at(b), "{name} {w}×{h} pixel ({}, {}): bins, then BVH", k as u32 % w, k as u32 / w);
    }
    assert_eq!(bins, bvh, "{name} {w}×{h}: colour-only, depth, marks, counts");
    a.3.iter().filter(|&&o| o != crate::surface::NO_OBJECT).count()
}

#[test]
fn the_bundled_scenes_render_alike_through_the_bins_and_the_bvh() {
    for (name, t) in [("seed.toml", 0.7), ("many.toml", 0.3), ("thousand.toml", 0.0), ("window.toml", 0.2)] {
        let scene = crate::testing::scene(name);
        let tracer = Tracer::new(&scene, t);
        let swept = Swept::of(&scene);
        for (w, h) in [(1, 1), (7, 5), (50, 38), (83, 45)] {
            for eye in [Eye::Left, Eye::Right] {
                assert_alike(name, &tracer, &scene.camera.view(eye, w, h), &swept);
            }
        }
        let camera = Camera { yaw_deg: 12.0, ..scene.camera };
        let hits = assert_alike(name, &tracer, &camera.view_with_margin(Eye::Left, 96, 54, (9, 5)), &swept);
        assert!(hits > 100, "{name}: {hits} hits");
    }
}

/// A scene of `n` random spheres ahead of the camera, some of them copies of others (equal
/// `t` for different spheres: a tie to break), some around and behind the eye.
fn random_scene(rng: &mut XorShift, n: usize) -> Scene {
    let mut scene = crate::testing::scene("seed.toml");
    scene.lights = vec![Light { position: Vec3::new(5.0, 8.0, -3.0), color: Vec3::ONE }];
    let eye = scene.camera.position;
    scene.spheres = (0..n)
        .map(|_| {
            let center = eye + Vec3::new(rng.range(-6.0, 6.0), rng.range(-4.0, 4.0), rng.range(-2.0, 25.0));
            let material = Material { reflectivity: rng.range(0.0, 0.6), ..Material::default() };
            SceneSphere { radius: rng.range(0.05, 1.2), motion: Motion::Static(center), material }
        })
        .collect();
    for _ in 0..n / 4 {
        let copy = scene.spheres[rng.below(n)];
        let at = rng.below(scene.spheres.len());
        scene.spheres.insert(at, copy);
    }
    scene
}

#[test]
fn random_spheres_render_alike_through_the_bins_and_the_bvh() {
    let mut rng = XorShift::new(0x5EED_0033);
    for case in 0..12 {
        let n = [3, 9, 40, 200, 700][case % 5];
        let scene = random_scene(&mut rng, n);
        let tracer = Tracer::new(&scene, 0.0);
        let swept = Swept::of(&scene);
        let camera = Camera { yaw_deg: rng.range(-20.0, 20.0), pitch_deg: rng.range(-10.0, 10.0), ..scene.camera };
        let (w, h) = (8 + rng.below(60) as u32, 4 + rng.below(40) as u32);
        let eye = if case % 2 == 0 { Eye::Left } else { Eye::Right };
        assert_alike(&format!("case {case}, {n} spheres"), &tracer, &camera.view(eye, w, h), &swept);
    }
}

#[test]
fn ties_go_to_the_lowest_sphere_id_both_ways() {
    // Copies of one sphere, given in both orders among others: every pixel that sees them
    // takes the first copy's id, whichever leaf of the BVH holds which.
    let mut rng = XorShift::new(7);
    let mut scene = random_scene(&mut rng, 60);
    let eye = scene.camera.position;
    scene.spheres.retain(|s| s.motion.center_at(0.0).distance(eye) > s.radius + 2.0);
    let view = scene.camera.view(Eye::Left, 64, 48);
    // In the middle of the view, nearer than any other sphere.
    let at = view.primary_ray(32, 24).at(1.5);
    let copy = SceneSphere { radius: 0.3, motion: Motion::Static(at), ..scene.spheres[0] };
    scene.spheres.insert(5, copy);
    scene.spheres.push(copy);
    let tracer = Tracer::new(&scene, 0.0);
    let swept = Swept::of(&scene);
    assert_alike("copies", &tracer, &view, &swept);
    let mut film = Film::new(1, 1);
    Renderer::new().with_first_hits(FirstHits::Bvh).render(
        &tracer,
        &view,
        Pixels::All,
        Target::film(&mut film, Record::Keys),
    );
    let last = scene.spheres.len() as u32 - 1;
    let seen = |id| film.object.iter().filter(|&&o| o == id).count();
    assert!(seen(5) > 10 && seen(last) == 0, "the first copy is seen, never the last: {} and {}", seen(5), seen(last));
}

#[test]
fn selections_and_batches_are_alike_through_the_bins_and_the_bvh() {
    for (name, t) in [("seed.toml", 0.4), ("thousand.toml", 0.0)] {
        let scene = crate::testing::scene(name);
        let tracer = Tracer::new(&scene, t);
        for (w, h) in [(9, 6), (61, 34)] {
            let (left, right) = (scene.camera.view(Eye::Left, w, h), scene.camera.view(Eye::Right, w, h));
            let mut other = Film::new(1, 1);
            Renderer::new().render(&tracer, &left, Pixels::All, Target::film(&mut other, Record::Keys));
            let mut bits = PixelBits::new(w, h);
            for (i, j) in (0..h).flat_map(|j| (0..w).map(move |i| (i, j))) {
                bits.set(i, j, (i * 5 + j * 3) % 7 < 2 || j == h / 2);
            }
            let run = |first_hits| {
                let mut renderer = Renderer::new().with_first_hits(first_hits);
                let mut film = other.clone();
                let only = renderer.render(&tracer, &left, Pixels::Only(&bits), Target::film(&mut film, Record::Keys));
                let batch = renderer.batch(&tracer, &right);
                let (mut counts, mut rows, mut tests, mut missed) = (RayCounts::default(), Vec::new(), 0, Vec::new());
                let mut object = Vec::new();
                for j in 0..h {
                    let mut rgb = vec![0u32; w as usize];
                    batch.trace_pixels(j, (0..w).filter(|i| (i + j) % 3 != 0), &mut counts, (&mut rgb, None));
                    rows.push(rgb.clone());
                    let items = (0..w).filter(|&i| other.object[(j * w + i) as usize] != crate::surface::NO_OBJECT);
                    batch.reshade(j, (&left, &other), items.map(|i| (i, j * w + i)), &mut counts, (&mut rgb, None));
                    rows.push(rgb.clone());
                    // Exact mode's plan: the left pixel at the same place, some traced, some kept.
                    let source: Vec<u32> =
                        (0..w).map(|i| [j * w + i, j * w + i, TRACE, KEEP][(i % 4) as usize]).collect();
                    let plan = RowPlan::read(&other, &source, &mut object);
                    let (mut hit, mut z) = (vec![7u32; w as usize], vec![-1.0f32; w as usize]);
                    let hits = Some((&mut hit[..], &mut z[..]));
                    tests += batch.shade_row(j, plan, ((&mut rgb, None), hits), &mut counts, &mut missed);
                    rows.extend([rgb, hit, z.iter().map(|z| z.to_bits()).collect()]);
                }
                (planes(&film), only, rows, counts, tests, missed)
            };
            assert_eq!(run(FirstHits::Bins), run(FirstHits::Bvh), "{name} {w}×{h}");
            assert_eq!(run(FirstHits::Sliced), run(FirstHits::Bvh), "{name} {w}×{h}: sliced");
        }
    }
}

#[test]
fn the_cheaper_search_is_the_bins_for_the_bundled_scenes_and_the_bvh_for_crowds() {
    use crate::accel::screen::Search;
    for name in ["seed.toml", "many.toml", "thousand.toml"] {
        let tracer = Tracer::new(&crate::testing::scene(name), 0.0);
        let search = FirstHits::Cheaper.search(&tracer, 50 * 38);
        assert_eq!(search, Search::Bins, "{name} at 50×38");
    }
    assert_eq!(Search::cheaper(2_900_000, 800 * 600), Search::Bvh, "a capsid at 800×600");
    assert_eq!(Search::cheaper(1_000_000, 1280 * 720), Search::Sliced, "a million spheres at 1280×720");
    assert_eq!(Search::cheaper(2_900_000, 1920 * 1080), Search::Bvh, "a capsid: too many to slice");
    assert_eq!(Search::cheaper(1_000, 1), Search::Bvh, "a thousand spheres for one pixel");
}
