//! Tests of `scene_file.rs`.
use super::*;

const MINIMAL: &str = "[[spheres]]\ncenter = [0.0, 0.0, 15.0]\nradius = 2.5\n";

fn err(src: &str) -> String {
    Scene::from_toml(src, "bad.toml").unwrap_err().to_string()
}

#[test]
fn minimal_scene_gets_the_documented_defaults() {
    let s = Scene::from_toml(MINIMAL, "m.toml").unwrap();
    assert_eq!(s.camera, Camera::default());
    assert_eq!(s.render, RenderSettings::default());
    assert!(s.lights.is_empty());
    assert_eq!(s.spheres[0].material, Material::default());
    // Integers are accepted where floats are expected.
    let s = Scene::from_toml("[[spheres]]\ncenter = [0, 0, 15]\nradius = 2\n", "m.toml").unwrap();
    assert_eq!(s.spheres[0].radius, 2.0);
}

#[test]
fn errors_name_file_line_field_and_value() {
    let e = err("[camera]\nipd = 0.6\n\n[[spheres]]\ncenter = [0.0, 0.0, 15.0]\nradius = -1.0\n");
    assert!(e.starts_with("bad.toml:4: spheres[0].radius = -1: must be > 0"), "{e}");
    let e = err("[[spheres]]\ncenter = [0.0, 0.0, 15.0]\nradius = 1.0\nradiuss = 2.0\n");
    assert!(e.starts_with("bad.toml:4: unknown field `radiuss`"), "{e}");
    let e = err("[[spheres]]\ncenter = [0.0, 0.0, 15.0]\nradius = \"big\"\n");
    assert!(e.contains("bad.toml:3:") && e.contains("radius = \"big\""), "{e}");
    let e = err("[camera]\nfov_deg = 180.0\n[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\n");
    assert!(e.contains("camera.fov_deg = 180"), "{e}");
    let e = err("[render]\nmax_depth = 99\n[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\n");
    assert!(e.contains("render.max_depth = 99"), "{e}");
    let e = err("[[spheres]]\ncenter = [0, nan, 15]\nradius = 1\n");
    assert!(e.contains("spheres[0].center[1] = NaN"), "{e}");
    let e = err("[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\ncolor = [1.5, 0, 0]\n");
    assert!(e.contains("spheres[0].color[0] = 1.5"), "{e}");
    let e = err("[[spheres]]\nradius = 1\norbit = { center = [0, 0, 15], radius = 2, period_s = 0 }\n");
    assert!(e.contains("spheres[0].orbit.period_s = 0"), "{e}");
    let e = err("[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\n");
    assert!(e.contains("inside this sphere"), "{e}");
    let e = err("[camera]\nipd = -0.1\n");
    assert!(e.contains("camera.ipd = -0.1"), "{e}");
    let e = err("[camera]\ndistance = 0\n[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\n");
    assert!(e.contains("camera.distance = 0"), "{e}");
    let e = err("");
    assert!(e.contains("spheres = []"), "{e}");
    let e = err("[[spheres]]\nradius = 1\n");
    assert!(e.contains("needs `center` or `orbit`"), "{e}");
    let e = err(
        "[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\norbit = { center = [0, 0, 15], radius = 2, period_s = 8 }\n",
    );
    assert!(e.contains("either `center` or `orbit`, not both"), "{e}");
    let e = err("[camera\nipd = 0.5\n");
    assert!(e.starts_with("bad.toml:1:"), "malformed TOML: {e}");
    let e = err("[[spheres]]\ncenter = [0, 0, 15]\nradius = inf\n");
    assert!(e.contains("spheres[0].radius = inf: must be a finite number"), "{e}");
    let e = err("[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\nshininess = 0.5\n");
    assert!(e.contains("spheres[0].shininess = 0.5"), "{e}");
    let e = err("[[lights]]\nposition = [0, 0, 0]\ncolor = [-1, 0, 0]\n[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\n");
    assert!(e.contains("lights[0].color[0] = -1"), "{e}");
    let e = err("[camera]\npitch_deg = 95\n[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\n");
    assert!(e.contains("camera.pitch_deg = 95"), "{e}");
    let e = err("[render]\nambient = 1.5\n[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\n");
    assert!(e.contains("render.ambient = 1.5"), "{e}");
    let mut many = String::new();
    for _ in 0..33 {
        many.push_str("[[lights]]\nposition = [0, 5, 0]\n");
    }
    many.push_str("[[spheres]]\ncenter = [0, 0, 15]\nradius = 1\n");
    assert!(err(&many).contains("at most 32 lights"));
    // An orbit that sweeps through the eyes is caught too.
    let e = err("[[spheres]]\nradius = 0.5\norbit = { center = [0, 0, 3], radius = 3, period_s = 8 }\n");
    assert!(e.contains("on its orbit"), "{e}");
}

#[test]
fn missing_file_names_the_path() {
    let e = Scene::load("/nonexistent/scene.toml").unwrap_err().to_string();
    assert!(e.starts_with("/nonexistent/scene.toml: cannot read scene file"), "{e}");
}
