//! Real structures: 1TII (5,684 atoms) and 2BTV (49,061 atoms; its 60-fold assembly
//! 2,943,660), and the same atoms written as mmCIF, GRO, XYZ and gzip and read back.

use std::fmt::Write as _;
use std::io::Write;
use std::time::Instant;

use glam::Vec3;
use molecule::{Element, Format, ReadOptions};

use crate::{loud, real_file, scratch_dir, two_btv, two_btv_required_in_ci, ONE_TII, SPC216};

/// The ATOM and HETATM records of a PDB text, counted as `grep -c` would.
fn atom_records(text: &str) -> usize {
    text.lines().filter(|l| l.starts_with("ATOM  ") || l.starts_with("HETATM")).count()
}

#[test]
fn one_tii_atoms_elements_and_a_known_atom() {
    let Some(path) = real_file(ONE_TII.as_ref(), true) else { return };
    let m = molecule::read(&path, &ReadOptions::default()).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(atom_records(&text), 5684, "the file holds 5,684 ATOM + HETATM records");
    assert_eq!(m.len(), 5684, "every record read");
    assert_eq!(m.format(), Format::Pdb, "format from the name");
    let count = |e: Element| m.elements().iter().filter(|&&x| x == e).count();
    assert_eq!(
        (count(Element::C), count(Element::N), count(Element::O), count(Element::S)),
        (3405, 956, 1278, 45),
        "element counts of columns 77-78"
    );
    assert!(m.warnings().is_empty(), "a clean file: {:?}", m.warnings());
    assert_eq!(m.chain_ids(), ["D", "E", "F", "G", "H", "A", "C", ""], "chains in file order; the waters have none");
    // ATOM 1: N of GLY D 1 at file (42.053, -9.336, 17.867).
    assert_eq!(m.positions()[0], Vec3::new(42.053, -9.336, -17.867), "mapped to (x, y, -z)");
    let n = m.elements()[0];
    assert_eq!(n, Element::N, "atom 1 is nitrogen");
    assert_eq!(n.radius(), 1.55, "Bondi's nitrogen");
    assert_eq!(n.jmol_srgb(), [0x30, 0x50, 0xF8], "Jmol's nitrogen blue");
    let linear = n.linear_colour();
    assert!(linear.abs_diff_eq(Vec3::new(0.029_557, 0.080_219, 0.938_686), 1e-5), "in linear light: {linear}");
    assert!(m.assemblies().is_empty(), "1TII has no REMARK 350");
    let b = m.bounds(1.0).unwrap();
    assert!(m.positions().iter().all(|&p| p.cmpge(b.min).all() && p.cmple(b.max).all()), "the box holds every atom");
}

#[test]
fn one_tii_fields_of_the_first_a_middle_and_the_last_atom_are_the_files() {
    let Some(path) = real_file(ONE_TII.as_ref(), true) else { return };
    let m = molecule::read(&path, &ReadOptions::default()).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let records: Vec<&str> = text.lines().filter(|l| l.starts_with("ATOM  ") || l.starts_with("HETATM")).collect();
    for i in [0, records.len() / 2, records.len() - 1] {
        let (r, a) = (records[i], m.atom(i).unwrap());
        let field = |range: std::ops::Range<usize>| r.get(range).unwrap_or("").trim();
        let number = |range| field(range).parse::<f32>().ok();
        assert_eq!(a.name, field(12..16), "atom {i}: name");
        assert_eq!(a.residue_name, field(17..20), "atom {i}: residue");
        assert_eq!(a.residue_number, field(22..26).parse().ok(), "atom {i}: residue number");
        assert_eq!(a.insertion_code, field(26..27).chars().next(), "atom {i}: insertion code");
        assert_eq!(a.chain, field(21..22), "atom {i}: chain");
        assert_eq!((a.occupancy, a.b_factor), (number(54..60), number(60..66)), "atom {i}: occupancy, B");
        assert_eq!(a.hetero, r.starts_with("HETATM"), "atom {i}: HETATM");
        let xyz = [number(30..38), number(38..46), number(46..54)].map(Option::unwrap);
        assert_eq!(a.file_position, xyz, "atom {i}: the file's coordinates");
    }
    let last = m.atom(records.len() - 1).unwrap();
    assert!(last.hetero && last.residue_name == "HOH", "1TII ends with waters: {last:?}");
    let (lo, hi) = m.fields().b_factor_range().unwrap();
    assert!(lo > 0.0 && hi > lo, "B-factors span {lo}..{hi}");
}

#[test]
fn one_tii_as_gemmi_writes_mmcif_has_the_pdb_files_fields() {
    // A real mmCIF writer's output (gemmi, Debian's `gemmi`; .ci/run installs it): its own
    // items and order, `?` and `.` nulls, auth_seq_id beside label_seq_id.
    let Some(path) = real_file(ONE_TII.as_ref(), true) else { return };
    let gemmi = std::process::Command::new("gemmi").arg("--version").output();
    if gemmi.is_err() {
        assert!(std::env::var_os("CI").is_none(), "gemmi is absent under CI: .ci/run installs it");
        loud("\n*** SKIPPED: gemmi is absent; apt-get install gemmi to run this test ***\n");
        return;
    }
    let dir = scratch_dir("gemmi");
    let cif = dir.join("1tii.cif");
    let status = std::process::Command::new("gemmi").arg("convert").arg(&path).arg(&cif).status().unwrap();
    assert!(status.success(), "gemmi convert {} {}", path.display(), cif.display());
    let (pdb, cif) = (
        molecule::read(&path, &ReadOptions::default()).unwrap(),
        molecule::read(&cif, &ReadOptions::default()).unwrap(),
    );
    assert_eq!(cif.len(), pdb.len(), "every atom");
    for i in [0, pdb.len() / 2, pdb.len() - 1] {
        let (a, b) = (pdb.atom(i).unwrap(), cif.atom(i).unwrap());
        let fields = |a: &molecule::Atom<'_>| {
            (a.name.to_owned(), a.residue_name.to_owned(), a.residue_number, a.insertion_code, a.b_factor, a.occupancy)
        };
        assert_eq!(fields(&b), fields(&a), "atom {i}: name, residue, number, code, B, occupancy");
        assert_eq!((b.element, b.file_position, b.model), (a.element, a.file_position, Some(1)), "atom {i}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn gromacs_spc216_fields_of_the_first_a_middle_and_the_last_atom_are_the_files() {
    // 216 SPC waters as GROMACS ships them (Debian's gromacs-data; .ci/run installs it).
    let Some(path) = real_file(SPC216.as_ref(), true) else { return };
    let m = molecule::read(&path, &ReadOptions::default()).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().skip(2).take(648).collect();
    assert_eq!(m.len(), 648, "the count line's 648 atoms");
    for i in [0, 323, 647] {
        let (line, a) = (lines[i], m.atom(i).unwrap());
        let field = |range: std::ops::Range<usize>| line.get(range).unwrap_or("").trim();
        assert_eq!(a.residue_number, field(0..5).parse().ok(), "atom {i}: residue number");
        assert_eq!((a.residue_name, a.name), (field(5..10), field(10..15)), "atom {i}: residue and atom names");
        let nm = |range| field(range).parse::<f32>().unwrap() * 10.0;
        let xyz = [nm(20..28), nm(28..36), nm(36..44)];
        assert!(a.file_position.iter().zip(xyz).all(|(a, b)| (a - b).abs() < 1e-4), "atom {i}: {:?}", a.file_position);
    }
    assert_eq!(m.atom(647).map(|a| (a.residue_number, a.name)), Some((Some(216), "HW2")), "the last atom");
}

#[test]
fn one_tii_reads_the_same_as_mmcif_gro_xyz_and_gzip() {
    let Some(path) = real_file(ONE_TII.as_ref(), true) else { return };
    let pdb = molecule::read(&path, &ReadOptions::default()).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let records: Vec<&str> = text.lines().filter(|l| l.starts_with("ATOM  ") || l.starts_with("HETATM")).collect();
    let (mut cif, mut gro, mut xyz) = (String::new(), String::new(), String::new());
    cif.push_str("data_1TII\nloop_\n_atom_site.group_PDB\n_atom_site.type_symbol\n_atom_site.label_atom_id\n");
    cif.push_str("_atom_site.label_comp_id\n_atom_site.label_asym_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n");
    writeln!(gro, "1TII as gro\n{}", records.len()).unwrap();
    writeln!(xyz, "{}\n1TII as xyz", records.len()).unwrap();
    for r in &records {
        let field = |a: usize, b: usize| r[a..b].trim();
        let (x, y, z) = (field(30, 38), field(38, 46), field(46, 54));
        let (name, residue, element) = (field(12, 16), field(17, 20), field(76, 78));
        let chain = if field(21, 22).is_empty() { "." } else { field(21, 22) };
        writeln!(cif, "{} {element} {name} {residue} {chain} {x} {y} {z}", field(0, 6)).unwrap();
        let nm = |v: &str| v.parse::<f64>().unwrap() / 10.0;
        // GRO names its atoms by element here, so the name rule gives the same element.
        writeln!(gro, "{:>5}{:<5}{:>5}{:>5}{:8.4}{:8.4}{:8.4}", 1, residue, element, 1, nm(x), nm(y), nm(z)).unwrap();
        writeln!(xyz, "{element} {x} {y} {z}").unwrap();
    }
    gro.push_str("   10.0   10.0   10.0\n");
    let dir = scratch_dir("formats");
    let write = |name: &str, bytes: &[u8]| {
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    };
    let gzip = |bytes: &[u8]| {
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        e.write_all(bytes).unwrap();
        e.finish().unwrap()
    };
    let cases = [
        (write("1tii.cif", cif.as_bytes()), 1e-6),
        (write("1tii.gro", gro.as_bytes()), 1e-3), // 4 decimals of nm: 1e-3 Å
        (write("1tii.xyz", xyz.as_bytes()), 1e-6),
        (write("1tii.pdb.gz", &gzip(text.as_bytes())), 0.0),
        (write("1tii.cif.gz", &gzip(cif.as_bytes())), 1e-6),
        (write("gzip-without-gz-name.pdb", &gzip(text.as_bytes())), 0.0),
    ];
    for (path, tolerance) in cases {
        let m = molecule::read(&path, &ReadOptions::default()).unwrap();
        let name = path.file_name().unwrap().to_string_lossy();
        assert_eq!(m.len(), pdb.len(), "{name}: atom count");
        assert_eq!(m.elements(), pdb.elements(), "{name}: elements");
        let worst =
            m.positions().iter().zip(pdb.positions()).map(|(a, b)| (*a - *b).abs().max_element()).fold(0.0, f32::max);
        assert!(worst <= tolerance, "{name}: positions differ by {worst}");
        assert!(m.warnings().is_empty(), "{name}: {:?}", m.warnings());
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn two_btv_asymmetric_unit_and_assembly() {
    // CI may not have the shared folder: this one skips, with a note, even there.
    let Some(path) = real_file(&two_btv(), two_btv_required_in_ci()) else { return };
    let start = Instant::now();
    let unit = molecule::read(&path, &ReadOptions::default()).unwrap();
    let read_time = start.elapsed();
    assert_eq!(unit.len(), 49_061, "ATOM + HETATM records of 2BTV");
    assert_eq!(unit.chain_ids().len(), 15, "chains A, B, C to J, P to T");
    let assembly = &unit.assemblies()[0];
    assert_eq!((assembly.id.as_str(), assembly.parts.len()), ("1", 1), "BIOMOLECULE 1, one APPLY");
    assert_eq!(assembly.parts[0].chains.len(), 15, "APPLY names every chain");
    assert_eq!(assembly.parts[0].operators.len(), 60, "60 BIOMT operators");
    assert_eq!(unit.assembly_len(0), Some(2_943_660), "counted before building");

    let start = Instant::now();
    let virus = molecule::read(&path, &ReadOptions { assembly: true, ..ReadOptions::default() }).unwrap();
    let assembly_time = start.elapsed();
    loud(&format!("2BTV: read {read_time:?} (49,061 atoms), with the assembly {assembly_time:?} (2,943,660 atoms)"));
    assert_eq!(virus.len(), 2_943_660, "60 copies");
    assert_eq!(virus.applied_assembly().map(|a| a.id.as_str()), Some("1"), "says which assembly");
    assert!(virus.heap_bytes() <= 16 * virus.len(), "{} bytes an atom", virus.heap_bytes() / virus.len());
    // Operator 2 (REMARK 350 BIOMT 2) on ATOM 1, N of VAL A 57 at file (216.934, -8.171, 276.852).
    let p = [216.934_f64, -8.171, 276.852];
    let rows = [
        [0.808_320, -0.518_657, 0.278_593, -52.570_42],
        [0.481_343, 0.309_714, -0.819_992, 154.732_41],
        [0.339_010, 0.796_914, 0.500_000, 94.350_00],
    ];
    let moved = rows.map(|r| r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3]);
    let expected = Vec3::new(moved[0] as f32, moved[1] as f32, -moved[2] as f32);
    let got = virus.positions()[49_061];
    assert!(got.abs_diff_eq(expected, 2e-3), "copy 2 of atom 1: {got} vs {expected}");
    assert_eq!(virus.positions()[0], unit.positions()[0], "operator 1 is the identity");
    let copy = virus.atom(49_061).unwrap();
    assert_eq!((copy.file_index, copy.operator), (0, Some("2")), "copy 2 of atom 1 points back to it");
    assert_eq!(
        (copy.name, copy.residue_name, copy.residue_number, copy.chain),
        ("N", "VAL", Some(57), "A"),
        "its fields"
    );
    assert_eq!(virus.atom(virus.len() - 1).map(|a| (a.file_index, a.operator)), Some((49_060, Some("60"))), "the last");
    let s = virus.bounding_sphere(1.0).unwrap();
    loud(&format!("2BTV assembly bounding sphere: centre {}, radius {} Å", s.centre, s.radius));
    assert!((300.0..450.0).contains(&s.radius), "a core about 70 nm across: radius {} Å", s.radius);
}
