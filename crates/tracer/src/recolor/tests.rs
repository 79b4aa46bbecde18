//! The schemes on real files, and hidden atoms out of every ray.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::accel::Origin;
use crate::color_by::{plddt_colour, ColorBy, Coloring, Hide};
use crate::ray::{spawn_ray, Ray};
use crate::scene::{Light, Scene, Structure};
use crate::structure::{read_structure, StructureOptions};
use crate::tracer::Tracer;

const TII: &str = "/usr/share/pymol/data/demo/1tii.pdb";

fn tii() -> Structure {
    read_structure(Path::new(TII), &StructureOptions::default()).unwrap()
}

fn colour(s: &Structure, k: usize) -> Vec3 {
    s.kind(k).material.color
}

fn recoloured(by: ColorBy) -> Structure {
    let mut s = tii();
    s.recolor(&Coloring { by, range: None });
    s
}

/// A file in the temp folder, named for the test, holding `text`.
fn temp_file(name: &str, text: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("stereotrace-{}-{name}", std::process::id()));
    std::fs::write(&path, text).unwrap();
    path
}

/// A PDB atom record of chain A, B-factor 10 (columns as the format gives them).
fn pdb_line(record: &str, name: &str, residue: &str, number: i32, p: [f32; 3], element: &str) -> String {
    format!(
        "{record:<6}{number:>5} {name:<4} {residue:>3} A{number:>4}    {:8.3}{:8.3}{:8.3}{:6.2}{:6.2}          {element:>2}\n",
        p[0], p[1], p[2], 1.0, 10.0
    )
}

#[test]
fn chain_gives_one_colour_per_chain_id() {
    let s = recoloured(ColorBy::Chain);
    let mut by_chain: Vec<(String, Vec3)> = Vec::new();
    for k in 0..s.positions.len() {
        let chain = s.atom(k).unwrap().chain.to_owned();
        match by_chain.iter().find(|(c, _)| *c == chain) {
            Some((_, c)) => assert_eq!(*c, colour(&s, k), "atom {k} of chain {chain}"),
            None => by_chain.push((chain, colour(&s, k))),
        }
    }
    assert!(by_chain.len() >= 5, "1TII has {} chains", by_chain.len());
    for (i, (a, ca)) in by_chain.iter().enumerate() {
        for (b, cb) in &by_chain[..i] {
            assert_ne!(ca, cb, "chains {a} and {b} share a colour");
        }
    }
    // Atoms keep their element radii.
    let plain = tii();
    assert!((0..s.positions.len()).all(|k| s.kind(k).radius == plain.kind(k).radius));
}

#[test]
fn bfactor_is_monotone_in_the_b_factor() {
    let s = recoloured(ColorBy::BFactor);
    // Along blue–white–red, red rises then blue falls: red − blue rises with the B-factor.
    let mut atoms: Vec<(f32, f32)> = (0..s.positions.len())
        .map(|k| (s.atom(k).unwrap().b_factor.unwrap(), colour(&s, k).x - colour(&s, k).z))
        .collect();
    atoms.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in atoms.windows(2) {
        assert!(w[0].1 <= w[1].1, "B {} gives {} but B {} gives {}", w[0].0, w[0].1, w[1].0, w[1].1);
    }
    let (lo, hi) = (atoms[0], atoms[atoms.len() - 1]);
    assert_eq!((lo.1, hi.1), (-1.0, 1.0), "blue at the lowest B ({}), red at the highest ({})", lo.0, hi.0);
    // A given range: every atom at or above its top is red, at or below its bottom blue.
    let mut s = tii();
    s.recolor(&Coloring { by: ColorBy::BFactor, range: Some((20.0, 30.0)) });
    let (mut red, mut blue) = (0, 0);
    for k in 0..s.positions.len() {
        let b = s.atom(k).unwrap().b_factor.unwrap();
        if b >= 30.0 {
            assert_eq!(colour(&s, k), Vec3::X, "atom {k}, B {b}");
            red += 1;
        } else if b <= 20.0 {
            assert_eq!(colour(&s, k), Vec3::Z, "atom {k}, B {b}");
            blue += 1;
        }
    }
    assert!(red > 100 && blue > 100, "{red} red, {blue} blue");
}

#[test]
fn plddt_puts_each_atom_in_its_band() {
    // 1TII's first 40 atoms with pLDDTs written into columns 61–66, and each one's band
    // (0 very high > 90, 1 confident 70–90, 2 low 50–70, 3 very low < 50).
    let cases =
        [(99.0, 0), (90.5, 0), (90.0, 1), (85.0, 1), (70.5, 1), (70.0, 2), (60.0, 2), (50.5, 2), (50.0, 3), (20.0, 3)];
    let text = std::fs::read_to_string(TII).unwrap();
    let mut file = String::new();
    for (k, line) in text.lines().filter(|l| l.starts_with("ATOM")).take(40).enumerate() {
        let b = cases[k % cases.len()].0;
        writeln!(file, "{}{b:6.2}{}", &line[..60], &line[66..]).unwrap();
    }
    let path = temp_file("plddt.pdb", &file);
    let mut s = read_structure(&path, &StructureOptions::default()).unwrap();
    std::fs::remove_file(&path).unwrap();
    s.recolor(&Coloring { by: ColorBy::Plddt, range: None });
    assert_eq!(s.positions.len(), 40);
    for k in 0..40 {
        let (b, band) = cases[k % cases.len()];
        assert_eq!(s.atom(k).unwrap().b_factor, Some(b), "atom {k}'s pLDDT as written");
        assert_eq!(colour(&s, k), plddt_colour(band), "atom {k}, pLDDT {b}: band {band}");
    }
}

#[test]
fn rainbow_runs_blue_to_red_along_each_chain() {
    let s = recoloured(ColorBy::Rainbow);
    // Each chain's first residue blue, its last red.
    let first = s.atom(0).unwrap();
    assert_eq!(colour(&s, 0), Vec3::Z, "chain {}'s first residue", first.chain);
    let last =
        (0..s.positions.len()).filter(|&k| !s.atom(k).unwrap().hetero && s.atom(k).unwrap().chain == first.chain);
    let last = last.max_by_key(|&k| s.atom(k).unwrap().residue_number).unwrap();
    assert_eq!(colour(&s, last), Vec3::X, "chain {}'s last residue", first.chain);
}

#[test]
fn a_hidden_atom_casts_no_shadow_and_stops_no_ray() {
    // A carbon, and a water's oxygen 3 Å above it (both radii < 1.8 Å, so apart), a light
    // straight above both.
    let text = [
        pdb_line("ATOM", "CA", "GLY", 1, [0.0, 0.0, 0.0], "C"),
        pdb_line("HETATM", "O", "HOH", 101, [0.0, 4.0, 0.0], "O"),
    ]
    .concat();
    let path = temp_file("shadow.pdb", &text);
    let structure = read_structure(&path, &StructureOptions::default()).unwrap();
    std::fs::remove_file(&path).unwrap();
    let (c, o) = (structure.positions[0], structure.positions[1]);
    let light = Light { position: c + (o - c) * 10.0, color: Vec3::ONE };
    let scene = Scene { lights: vec![light], structures: vec![structure], ..Scene::default() };
    let r = scene.structures[0].kind(0).radius;
    let up = (o - c).normalize();
    let (p, n) = (c + up * r, up);
    let ray = spawn_ray(p, n, up);
    let dist = light.position.distance(p);
    let from = Origin::Surface { sphere: 0, normal: n };
    let eye = Ray::new(c + up * 100.0, -up);

    let before = Tracer::new(&scene, 0.0);
    assert!(before.accel.occluded(&ray, dist, from), "the water shades the carbon");
    assert!(before.shadowed(0, 0, p, n, &ray, dist));
    assert_eq!(before.intersect(&eye, f32::INFINITY).map(|h| h.object), Some(1), "the eye sees the water");

    let hidden = Scene {
        structures: vec![scene.structures[0].hidden(Hide { water: true, ..Hide::default() })],
        ..scene.clone()
    };
    assert_eq!(hidden.sphere_count(), 1);
    assert_eq!(hidden.structures[0].atom(0).unwrap().name, "CA", "the atom left keeps its record");
    let after = Tracer::new(&hidden, 0.0);
    assert!(!after.accel.occluded(&ray, dist, from), "no shadow from the hidden water");
    assert!(!after.shadowed(0, 0, p, n, &ray, dist));
    assert_eq!(after.intersect(&eye, f32::INFINITY).map(|h| h.object), Some(0), "the eye sees the carbon");

    // Hydrogen and hetero name theirs.
    let s = tii();
    let h = s.hidden(Hide { hetero: true, ..Hide::default() });
    assert!(h.positions.len() < s.positions.len());
    assert!((0..h.positions.len()).all(|k| !h.atom(k).unwrap().hetero));
}
