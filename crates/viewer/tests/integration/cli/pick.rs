//! `stereotrace pick` on 1TII: the atom reported is the first sphere along the pixel's ray,
//! its sphere holds the reported hit point, which lies on the reported ray; misses say so
//! (exit 3), pixels outside the image are bad input (exit 2).

use std::path::Path;

use glam::Vec3;
use serde_json::Value;
use tracer::testing::{skipped, XorShift};
use tracer::{intersect_sphere, Ray, Scene};

use crate::common::stereotrace;

const TII: &str = "/usr/share/pymol/data/demo/1tii.pdb";
const SIZE: (u32, u32) = (320, 240);

fn v3(v: &Value) -> Vec3 {
    let n = |i: usize| v[i].as_f64().unwrap_or_else(|| panic!("not a vector: {v}")) as f32;
    Vec3::new(n(0), n(1), n(2))
}

/// `pick` at (x, y) of `eye`: its exit code and JSON report.
fn pick(eye: &str, (x, y): (u32, u32)) -> (Option<i32>, Value) {
    let (w, h) = (SIZE.0.to_string(), SIZE.1.to_string());
    let at = format!("{x},{y}");
    let out =
        stereotrace(&["pick", "--scene", TII, "--width", &w, "--height", &h, "--eye", eye, "--at", &at, "--json"]);
    let report = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{eye} {at}: no JSON ({e}): {}", String::from_utf8_lossy(&out.stderr)));
    (out.status.code(), report)
}

/// The closest sphere along `ray` among all of `scene`'s, found by testing each.
fn first_along(scene: &Scene, ray: &Ray) -> Option<(usize, f32)> {
    let mut best: Option<(usize, f32)> = None;
    for k in 0..scene.sphere_count() {
        let s = scene.sphere_at(k, 0.0);
        if let Some(t) = intersect_sphere(ray, s.center, s.radius, best.map_or(f32::INFINITY, |b| b.1)) {
            best = Some((k, t));
        }
    }
    best
}

#[test]
fn pick_on_1tii_reports_the_first_atom_along_the_ray_and_its_hit_point() {
    if !Path::new(TII).is_file() {
        skipped(&format!("{TII} is not installed"));
        return;
    }
    let scene = Scene::load(Path::new(TII)).unwrap();
    let mut rng = XorShift::new(35);
    let centre = (SIZE.0 / 2, SIZE.1 / 2);
    // The centre, 20 random pixels of the middle of the image (where the molecule mostly
    // is), and a corner, which sees only the background.
    let (w, h) = (SIZE.0 as usize / 2, SIZE.1 as usize / 2);
    let middle = |rng: &mut XorShift| ((w / 2 + rng.below(w)) as u32, (h / 2 + rng.below(h)) as u32);
    let pixels: Vec<_> =
        std::iter::once(centre).chain((0..20).map(|_| middle(&mut rng))).chain([(0, SIZE.1 - 1)]).collect();
    let (mut hits, mut misses) = (0, 0);
    for (k, &px) in pixels.iter().enumerate() {
        let eye = if k % 2 == 0 { "left" } else { "right" };
        let (code, r) = pick(eye, px);
        let ray = Ray::new(v3(&r["ray"]["origin"]), v3(&r["ray"]["direction"]).normalize());
        let truth = first_along(&scene, &ray);
        if r["hit"] == false {
            assert_eq!(code, Some(3), "{eye} {px:?}: a miss exits 3");
            assert_eq!(truth, None, "{eye} {px:?}: reported a miss, but the ray meets a sphere");
            misses += 1;
            continue;
        }
        assert_eq!(code, Some(0), "{eye} {px:?}: a hit");
        let atom = &r["atom"];
        let index = atom["index"].as_u64().unwrap() as usize;
        assert_eq!(truth.map(|t| t.0), Some(index), "{eye} {px:?}: the first sphere along the ray");
        assert_eq!(r["object"].as_u64(), Some(index as u64), "1TII's atoms are the only spheres");
        // The atom's sphere: its file coordinates, mirrored into the scene's left-handed
        // space (z negated), and its element's radius.
        let f = v3(&atom["file_position"]);
        let centre = Vec3::new(f.x, f.y, -f.z);
        assert!((centre - v3(&r["sphere"]["center"])).length() < 1e-3, "{eye} {px:?}: the sphere is the atom's");
        let radius = r["sphere"]["radius"].as_f64().unwrap() as f32;
        let point = v3(&r["point"]);
        let off = ((point - centre).length() - radius).abs();
        assert!(off < 1e-3 * radius, "{eye} {px:?}: the hit point is {off} Å off the atom's sphere");
        // On the ray: at the reported t, and along its direction.
        let t = r["t"].as_f64().unwrap() as f32;
        assert!((ray.at(t) - point).length() < 1e-3, "{eye} {px:?}: the point is at t along the ray");
        assert!((point - ray.origin).normalize().cross(ray.dir).length() < 1e-5, "{eye} {px:?}: on the ray");
        for key in ["chain", "residue_name", "residue_number", "name", "element", "b_factor", "occupancy"] {
            assert!(!atom[key].is_null(), "{eye} {px:?}: {key} is reported: {atom}");
        }
        hits += 1;
    }
    assert!(hits >= 10 && misses >= 1, "both cases met: {hits} hits, {misses} misses");
    assert_eq!(hits + misses, 22);
    assert!(pick("left", centre).1["hit"] == true, "the centre shows the molecule");
}

#[test]
fn pick_outside_the_image_exits_2_naming_the_value_and_a_miss_exits_3() {
    let out = stereotrace(&["pick", "--width", "64", "--height", "48", "--at", "64,10"]);
    assert_eq!(out.status.code(), Some(2), "outside the image");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--at 64,10: outside the 64×48 eye image"), "{err}");
    let out = stereotrace(&["pick", "--width", "64", "--height", "48", "--at", "3,x"]);
    assert_eq!(out.status.code(), Some(2), "not a number");
    assert!(String::from_utf8_lossy(&out.stderr).contains("`x` is not a whole number"));
    // The seed scene's top-left corner sees only the background.
    let out = stereotrace(&["pick", "--width", "64", "--height", "48", "--at", "0,0", "--json"]);
    assert_eq!(out.status.code(), Some(3), "a miss: {}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("sees no sphere"));
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["hit"], false, "the JSON says so too");
    assert!(r["ray"]["direction"].is_array(), "and gives the ray");
}

/// FRAME counts frames of the orbit animation: scene time --time + FRAME / --fps.
#[test]
fn pick_frame_is_a_frame_of_the_animation() {
    let out = stereotrace(&[
        "pick", "45", "--fps", "30", "--time", "0.5", "--width", "64", "--height", "48", "--at", "32,24", "--json",
    ]);
    let r: Value =
        serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stderr)));
    assert_eq!(r["time"], 2.0, "0.5 s + 45 frames at 30 a second");
    let out = stereotrace(&["pick", "--width", "64", "--height", "48", "--at", "32,24", "--json"]);
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["time"], 0.0, "no FRAME: the scene at --time");
}
