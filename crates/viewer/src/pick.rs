//! Picking and measuring, shared by `stereotrace pick` and the window: which sphere a
//! pixel's primary ray hits first, which atom of which structure that sphere is, the
//! distance and angle between picked atoms, and where a picked atom's label goes in each
//! eye.
//!
//! A pick is the closest hit of the pixel's primary ray ([`tracer::EyeView::primary_ray`]):
//! the sphere the tracer's object plane ([`tracer::Film::object`]) records for that pixel.
//! Object ids number the scene's own spheres first, then each structure's atoms in order
//! ([`tracer::Scene::structures`]); [`atom_of`] undoes that numbering.
//!
//! Distances and angles are measured between the file's coordinates (right-handed Å, as
//! the file writes them), in f64, so they match what a molecular viewer reports for the
//! same atoms. A label is drawn at the atom centre's projection in each eye
//! ([`label_positions`]), so it has the atom's disparity e·z/(d+z) (Adelson & Hodges 1993)
//! and floats at the atom's depth.

use glam::{Vec2, Vec3};
use tracer::{intersect_sphere, Camera, Eye, Ray, Scene};

/// Which structure, and which of its atoms, object `object` is; `None` for one of the
/// scene's own spheres or an id past the scene's spheres.
#[must_use]
pub fn atom_of(scene: &Scene, object: usize) -> Option<(usize, usize)> {
    let mut k = object.checked_sub(scene.spheres.len())?;
    for (s, structure) in scene.structures.iter().enumerate() {
        if k < structure.positions.len() {
            return Some((s, k));
        }
        k -= structure.positions.len();
    }
    None
}

/// The closest sphere `ray` hits in `scene` at time `time`: its object id and the ray
/// parameter of the hit. Every sphere is tested (no acceleration structure): what the
/// window asks for one click, where it has no tracer of its own; the same answer as the
/// tracer's closest-hit query but for exact ties. A sphere the ray's line clearly passes
/// by (by more than a thousandth of its radius) is skipped before the exact test: a click
/// on 2BTV's assembly (2.9 million atoms) took 31–44 ms (a shared 2-core machine).
#[must_use]
pub fn closest_hit(scene: &Scene, time: f32, ray: &Ray) -> Option<(u32, f32)> {
    let mut best: Option<(u32, f32)> = None;
    let mut test = |k: usize, center: Vec3, radius: f32| {
        let oc = center - ray.origin;
        let along = oc.dot(ray.dir);
        let off = oc.length_squared() - along * along;
        let reach = radius * 1.001 + 1e-4 * (1.0 + oc.length());
        if off > reach * reach || along + reach < 0.0 {
            return;
        }
        let t_max = best.map_or(f32::INFINITY, |(_, t)| t);
        if let Some(t) = intersect_sphere(ray, center, radius, t_max) {
            // Object ids are u32 (the film's plane); a scene has fewer spheres than that.
            best = Some((k as u32, t));
        }
    };
    for k in 0..scene.spheres.len() {
        let s = scene.sphere_at(k, time);
        test(k, s.center, s.radius);
    }
    let mut k = scene.spheres.len();
    for structure in &scene.structures {
        for (center, radius) in structure.atom_spheres() {
            test(k, center, radius);
            k += 1;
        }
    }
    best
}

/// The distance in Å between two file positions.
#[must_use]
pub fn distance(a: [f32; 3], b: [f32; 3]) -> f64 {
    let d = sub(a, b);
    dot(d, d).sqrt()
}

/// The angle in degrees at `b` between the bonds to `a` and to `c` (0 if either is of no
/// length).
#[must_use]
pub fn angle(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> f64 {
    let (u, v) = (sub(a, b), sub(c, b));
    let norms = (dot(u, u) * dot(v, v)).sqrt();
    if norms == 0.0 {
        return 0.0;
    }
    (dot(u, v) / norms).clamp(-1.0, 1.0).acos().to_degrees()
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| f64::from(a[i]) - f64::from(b[i]))
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Where a label for a point at `centre` (world space) goes in each eye of a
/// `width` × `height` eye image seen through `camera`: the point's projection in the left
/// eye and in the right eye, continuous pixel coordinates (pixel (i, j)'s centre at
/// (i + ½, j + ½)). The two differ horizontally by the point's disparity, in pixels.
/// `None` when the point is not in front of both eyes.
#[must_use]
pub fn label_positions(camera: &Camera, (width, height): (u32, u32), centre: Vec3) -> Option<[Vec2; 2]> {
    let at = |eye| camera.view(eye, width, height).project(centre);
    Some([at(Eye::Left)?, at(Eye::Right)?])
}

#[cfg(test)]
mod tests {
    use super::*;
    use tracer::testing::XorShift;

    /// 1TII's first three atoms (N, CA and C of Gly D1), as the file's columns have them:
    /// `ATOM      1  N   GLY D   1      42.053  -9.336  17.867  1.00 43.86           N`, …
    /// The CLI's test checks that picking reads these very numbers from the file.
    pub(crate) const GLY_D1: [[f32; 3]; 3] =
        [[42.053, -9.336, 17.867], [42.704, -10.253, 18.851], [44.140, -10.512, 18.447]];

    /// The numbers above are the file's: the structure read from it gives them back.
    #[test]
    fn the_first_atoms_of_1tii_are_the_files() {
        let path = std::path::Path::new("/usr/share/pymol/data/demo/1tii.pdb");
        if !path.is_file() {
            tracer::testing::skipped("1tii.pdb is not installed");
            return;
        }
        let scene = Scene::load(path).unwrap();
        for (k, want) in GLY_D1.iter().enumerate() {
            let atom = scene.structures[0].atom(k).unwrap();
            let got = atom.file_position;
            assert!((0..3).all(|i| (got[i] - want[i]).abs() < 1e-4), "atom {k}: {got:?} vs {want:?}");
            assert_eq!((atom.residue_name, atom.chain), ("GLY", "D"));
        }
    }

    #[test]
    fn distance_and_angle_of_three_atoms_of_1tii() {
        let [n, ca, c] = GLY_D1;
        // |CA − N| = √(0.651² + 0.917² + 0.984²) = √2.232946
        assert!((distance(n, ca) - 2.232_946f64.sqrt()).abs() < 1e-5, "{}", distance(n, ca));
        assert!((distance(n, ca) - 1.4943).abs() < 1e-4, "a backbone N–CA bond, 1.49 Å");
        assert_eq!(distance(n, ca), distance(ca, n), "symmetric");
        // cos θ = (N − CA)·(C − CA) / (|N − CA| |C − CA|), N − CA = (−0.651, 0.917, −0.984),
        // C − CA = (1.436, −0.259, −0.404): (−0.934836 − 0.237503 + 0.397536) / (√2.232946 · √2.292393)
        let cos = (-0.934_836 - 0.237_503 + 0.397_536) / (2.232_946f64.sqrt() * 2.292_393f64.sqrt());
        let want = cos.acos().to_degrees();
        assert!((angle(n, ca, c) - want).abs() < 1e-3, "{} vs {want}", angle(n, ca, c));
        assert!((angle(n, ca, c) - 110.027).abs() < 0.001, "N–CA–C near tetrahedral: {}", angle(n, ca, c));
        assert_eq!(angle(n, n, c), 0.0, "a bond of no length");
        assert!((angle([1.0, 0.0, 0.0], [0.0; 3], [0.0, 2.0, 0.0]) - 90.0).abs() < 1e-12);
        assert!((angle([1.0, 0.0, 0.0], [0.0; 3], [-3.0, 0.0, 0.0]) - 180.0).abs() < 1e-12);
    }

    /// The label's horizontal difference between the eyes is the closed-form disparity
    /// e·z/(d+z) (window units, times W / window width for pixels), within half a pixel,
    /// for points all over the view and at every depth, with the head turned and moved.
    #[test]
    fn a_labels_disparity_is_the_atoms_disparity() {
        let camera = Camera {
            ipd: 1.3,
            distance: 40.0,
            fov_deg: 45.0,
            position: Vec3::new(3.0, -2.0, 5.0),
            yaw_deg: 17.0,
            pitch_deg: -8.0,
        };
        let (w, h) = (1280, 720);
        let view = camera.view(Eye::Left, w, h);
        let pixels_per_unit = w as f32 / camera.window_width();
        let mut rng = XorShift::new(35);
        for _ in 0..200 {
            let (i, j) = (rng.below(w as usize) as u32, rng.below(h as usize) as u32);
            // A point along that pixel's ray, in front of the window or behind it.
            let p = view.primary_ray(i, j).at(rng.range(20.0, 200.0));
            let [l, r] = label_positions(&camera, (w, h), p).unwrap();
            let z = view.head_z(p);
            let closed_form = camera.ipd * z / (camera.distance + z) * pixels_per_unit;
            assert!((r.x - l.x - closed_form).abs() < 0.5, "z = {z}: {} vs {closed_form}", r.x - l.x);
            assert!((r.y - l.y).abs() < 0.5, "the same row");
            assert!((l - Vec2::new(i as f32 + 0.5, j as f32 + 0.5)).length() < 0.01, "the left label on the pixel");
        }
        let behind = camera.position - 10.0 * (camera.world_from_head() * Vec3::Z);
        assert_eq!(label_positions(&camera, (w, h), behind), None, "behind the eyes: no label");
    }

    #[test]
    fn object_ids_number_the_spheres_then_each_structures_atoms() {
        let mut scene = Scene::from_toml("[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n", "s.toml").unwrap();
        let atoms = |n: usize| tracer::Structure {
            positions: vec![Vec3::ZERO; n],
            kind_ids: vec![0; n],
            kinds: vec![tracer::AtomKind { radius: 1.0, material: tracer::Material::default() }],
            ..tracer::Structure::default()
        };
        scene.structures = vec![atoms(3), atoms(2)];
        let found: Vec<_> = (0..7).map(|k| atom_of(&scene, k)).collect();
        assert_eq!(found, [None, Some((0, 0)), Some((0, 1)), Some((0, 2)), Some((1, 0)), Some((1, 1)), None]);
    }

    #[test]
    fn the_closest_hit_is_the_nearest_sphere_along_the_ray() {
        let scene = Scene::from_toml(
            "[[spheres]]\ncenter = [0.0, 0.0, 20.0]\nradius = 1.0\n[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n",
            "s.toml",
        )
        .unwrap();
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(closest_hit(&scene, 0.0, &ray), Some((1, 9.0)), "the nearer one, entered at z = 9");
        assert_eq!(closest_hit(&scene, 0.0, &Ray::new(Vec3::ZERO, Vec3::Y)), None, "a miss");
    }
}
