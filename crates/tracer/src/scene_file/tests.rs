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
    // The cues are off, and sized to the scene for whoever turns them on.
    let cues = s.render.cues;
    assert_eq!(RenderSettings { cues: crate::cue::Cues::default(), ..s.render }, RenderSettings::default());
    assert!(
        !cues.ambient_occlusion.is_on() && cues.depth_cue.mode == crate::cue::DepthCueMode::Off && cues.outline == 0
    );
    assert_eq!(cues.ambient_occlusion.distance, 8.0, "a ball of radius 2.5: at least 8");
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

/// A folder of its own under the system's temporary folder, for files a test writes.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("stereotrace-scene-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Water: an oxygen and two hydrogens (Å), as an XYZ file.
const WATER: &str = "3\nwater\nO 0.0 0.0 0.0\nH 0.757 0.586 0.0\nH -0.757 0.586 0.0\n";

#[test]
fn structures_are_placed_beside_spheres() {
    let dir = scratch("structures");
    std::fs::write(dir.join("water.xyz"), WATER).unwrap();
    let scene_path = dir.join("s.toml");
    let src = "[[spheres]]\ncenter = [0, 0, 40]\nradius = 1\n\n[[structures]]\npath = \"water.xyz\"\nradius_scale = 0.25\noffset = [1, 2, 30]\nspecular = 0.5\n\n[[structures]]\npath = \"water.xyz\"\ncolor = [0.1, 0.2, 0.3]\noffset = [0, 0, 20]\n";
    std::fs::write(&scene_path, src).unwrap();
    let scene = Scene::load(&scene_path).unwrap();
    assert_eq!((scene.spheres.len(), scene.structures.len(), scene.sphere_count()), (1, 2, 7));
    // Atoms follow the scene's own spheres; the file's z is flipped into our left-handed
    // space, then the offset is added.
    let h = scene.sphere_at(2, 0.0);
    assert_eq!(h.center, Vec3::new(1.757, 2.586, 30.0));
    let hydrogen = molecule::Element::from_symbol(b"H").unwrap();
    assert_eq!(h.radius, 0.25 * hydrogen.radius(), "radius scale");
    let (own, coloured) = (&scene.structures[0], &scene.structures[1]);
    // Water's atoms are O, H, H: two kinds, the oxygen's first.
    assert_eq!((own.kind_ids.as_slice(), own.kinds.len()), (&[0, 1, 1][..], 2), "one kind an element");
    assert_eq!(own.kind(1).material.color, hydrogen.linear_colour(), "the element's colour");
    assert_eq!(own.kind(1).material.specular, 0.5, "the table's material");
    assert_eq!(coloured.kind(1).material.color, Vec3::new(0.1, 0.2, 0.3), "one colour for all");
    assert_eq!(coloured.kind(1).radius, hydrogen.radius(), "the default scale");
    assert_eq!(scene.sphere_at(4, 0.0).center, Vec3::new(0.0, 0.0, 20.0), "the second structure's oxygen");
}

#[test]
fn a_bad_structure_names_the_scene_line_field_and_the_files_own_error() {
    let dir = scratch("bad-structures");
    std::fs::write(dir.join("short.xyz"), "3\nwater\nO 0.0 0.0 0.0\nH 0.7 x 0.0\nH -0.7 0.5 0.0\n").unwrap();
    let bad = |src: &str| {
        let path = dir.join("s.toml");
        std::fs::write(&path, src).unwrap();
        Scene::load(&path).unwrap_err().to_string()
    };
    let e = bad("[[structures]]\npath = \"short.xyz\"\n");
    assert!(e.contains("s.toml:1: structures[0].path = short.xyz") && e.contains("short.xyz:4:"), "{e}");
    let e = bad("[[structures]]\npath = \"absent.pdb\"\n");
    assert!(e.contains("structures[0].path = absent.pdb") && e.contains("absent.pdb"), "{e}");
    let e = bad("[[structures]]\npath = \"short.xyz\"\nradius_scale = 0\n");
    assert!(e.contains("structures[0].radius_scale = 0: must be > 0"), "{e}");
    let e = bad("[[structures]]\npath = \"short.xyz\"\nspecular = 2\n");
    assert!(e.contains("structures[0].specular = 2: must be 0 to 1"), "{e}");
    let e = bad("[camera]\nipd = 0.5\n");
    assert!(e.contains("a scene needs at least one [[spheres]] or [[structures]] table"), "{e}");
}

#[test]
fn what_is_not_a_scene_file_is_refused_before_it_is_read() {
    let e = |path: &Path| Scene::load(path).unwrap_err().to_string();
    assert_eq!(e(Path::new("/dev/zero")), "/dev/zero: not a regular file (character device)");
    let dir = scratch("not-a-file");
    assert!(e(&dir).ends_with("not a regular file (directory)"), "{}", e(&dir));
    let fifo = dir.join("fifo.toml");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success());
    if made {
        // Refused from its metadata: reading it would block forever.
        assert!(e(&fifo).ends_with("not a regular file (FIFO)"), "{}", e(&fifo));
    } else {
        crate::testing::skipped("the FIFO case (no mkfifo here)");
    }
    let huge = dir.join("huge.toml");
    std::fs::File::create(&huge).unwrap().set_len(MAX_TOML_BYTES + 1).unwrap();
    assert!(e(&huge).contains("above the limit of 67108864 for a TOML scene"), "{}", e(&huge));
    let other = dir.join("notes.txt");
    std::fs::write(&other, MINIMAL).unwrap();
    assert!(e(&other).contains("not a scene file: name it .toml"), "{}", e(&other));
    let missing = dir.join("missing.toml");
    assert!(e(&missing).contains("missing.toml"), "{}", e(&missing));
}

#[test]
fn a_structure_s_color_by_recolours_it_and_a_bad_one_is_named() {
    let dir = scratch("color-by");
    let tii = "/usr/share/pymol/data/demo/1tii.pdb";
    let path = dir.join("s.toml");
    let write =
        |by: &str| std::fs::write(&path, format!("[[structures]]\npath = \"{tii}\"\ncolor_by = \"{by}\"\n")).unwrap();
    write("chain");
    let scene = Scene::load(&path).unwrap();
    let s = &scene.structures[0];
    let chain_a = (0..s.positions.len()).filter(|&k| s.atom(k).unwrap().chain == "A");
    let colours: Vec<_> = chain_a.map(|k| s.kind(k).material.color).collect();
    assert!(colours.windows(2).all(|w| w[0] == w[1]), "chain A in one colour");
    assert_ne!(colours[0], s.kind(0).material.color, "chain D in another");
    write("chian");
    let e = Scene::load(&path).unwrap_err().to_string();
    assert!(e.contains("s.toml:1: structures[0].color_by = chian: unknown colour scheme `chian`"), "{e}");
}

#[test]
fn the_cues_are_read_and_bad_ones_name_their_field() {
    let src = format!(
        "[render]\nambient_occlusion = {{ samples = 16, distance = 3.5 }}\n\
         depth_cue = {{ mode = \"linear\", start = 10, end = 30 }}\noutline = 2\n{MINIMAL}"
    );
    let cues = Scene::from_toml(&src, "c.toml").unwrap().render.cues;
    let ao = cues.ambient_occlusion;
    assert_eq!((ao.samples, ao.distance, ao.strength), (16, 3.5, 1.0));
    let cue = cues.depth_cue;
    assert_eq!((cue.mode, cue.start, cue.end), (crate::cue::DepthCueMode::Linear, 10.0, 30.0));
    assert_eq!(cues.outline, 2);
    for (field, want) in [
        ("ambient_occlusion = { samples = 2000 }", "render.ambient_occlusion.samples = 2000: must be 0 (off) to 1024"),
        ("ambient_occlusion = { samples = 4, distance = -1 }", "render.ambient_occlusion.distance = -1: must be"),
        ("ambient_occlusion = { samples = 4, distance = nan }", "render.ambient_occlusion.distance = NaN: must be"),
        ("ambient_occlusion = { samples = 4, strength = 2 }", "render.ambient_occlusion.strength = 2: must be 0 to 1"),
        ("depth_cue = { mode = \"fog\" }", "render.depth_cue.mode = fog: \"fog\": must be off, linear or exp2"),
        ("depth_cue = { mode = \"linear\", start = 5, end = 5 }", "render.depth_cue.end = 5: must be beyond start"),
        ("outline = 9", "render.outline = 9: must be 0 (off) to 8 pixels"),
        ("outline = -1", "render.outline = -1: must be"),
    ] {
        let e = err(&format!("[render]\n{field}\n{MINIMAL}"));
        assert!(e.starts_with("bad.toml:1: ") && e.contains(want), "{field}: {e}");
    }
}
