//! Malformed files: each error names the file, the 1-based line and the field.

use std::fmt::Write;

use molecule::{Error, ReadOptions};

use crate::{real_file, scratch_dir, ONE_TII};

fn parse(text: &str, name: &str) -> Result<molecule::Molecule, Error> {
    molecule::parse(text.as_bytes(), name, &ReadOptions::default())
}

/// 1TII with line `line` (1-based) changed by `change`.
#[expect(clippy::unwrap_used, reason = "a test helper: 1TII, present, reads")]
fn one_tii_with(line: usize, change: impl Fn(&str) -> String) -> Option<String> {
    let path = real_file(ONE_TII.as_ref(), true)?;
    let text = std::fs::read_to_string(path).unwrap();
    let lines: Vec<String> =
        text.lines().enumerate().map(|(i, l)| if i + 1 == line { change(l) } else { l.to_owned() }).collect();
    Some(lines.join("\n"))
}

/// 1TII's line of ATOM 1234.
const ATOM_1234_LINE: usize = 419 + 1234;

#[test]
fn one_tii_with_a_non_numeric_coordinate() {
    let Some(text) = one_tii_with(ATOM_1234_LINE, |l| format!("{}  12.3a4{}", &l[..30], &l[38..])) else { return };
    assert!(text.lines().nth(ATOM_1234_LINE - 1).unwrap().starts_with("ATOM   1234"), "the line of ATOM 1234");
    let e = parse(&text, "1tii.pdb").unwrap_err();
    assert_eq!(e.to_string(), format!(r#"1tii.pdb:{ATOM_1234_LINE}: ATOM x = "12.3a4": not a number"#), "x");
    let Some(text) = one_tii_with(ATOM_1234_LINE, |l| format!("{}     inf{}", &l[..46], &l[54..])) else { return };
    let e = parse(&text, "1tii.pdb").unwrap_err();
    assert_eq!(e.to_string(), format!(r#"1tii.pdb:{ATOM_1234_LINE}: ATOM z = "inf": not finite"#), "z");
}

#[test]
fn one_tii_with_a_short_atom_line() {
    let Some(text) = one_tii_with(ATOM_1234_LINE, |l| l[..50].to_owned()) else { return };
    let e = parse(&text, "1tii.pdb").unwrap_err();
    assert_eq!(
        e.to_string(),
        format!("1tii.pdb:{ATOM_1234_LINE}: ATOM record has 50 columns; its coordinates end at column 54"),
        "cut inside z"
    );
}

#[test]
fn an_empty_file_is_an_error_in_every_format() {
    let dir = scratch_dir("empty");
    for name in ["e.pdb", "e.cif", "e.gro", "e.xyz"] {
        let path = dir.join(name);
        std::fs::write(&path, "").unwrap();
        let e = molecule::read(&path, &ReadOptions::default()).unwrap_err();
        assert!(matches!(e, Error::NoAtoms { why: "the file is empty", .. }), "{name}: {e}");
        assert!(e.to_string().ends_with(&format!("{name}: no atoms: the file is empty")), "{e}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_gro_file_whose_count_lies() {
    let gro = "water\n    3\n    1SOL     OW    1   0.126   1.624   1.679\n    1SOL    HW1    2   0.190   1.661   1.747\n    1SOL    HW2    3   0.177   1.568   1.613\n   1.0   1.0   1.0\n";
    assert_eq!(parse(gro, "w.gro").unwrap().len(), 3, "the honest file reads");
    let e = parse(&gro.replace("    3\n", "    5\n"), "w.gro").unwrap_err();
    assert_eq!(
        e.to_string(),
        "w.gro:6: atom line has 18 columns; its coordinates end at column 44 (is the count on line 2, 5, too large?)",
        "too large: the box line is reached"
    );
    let e = parse(&gro.replace("    3\n", "    2\n"), "w.gro").unwrap_err();
    assert!(
        e.to_string().starts_with(r#"w.gro:5: box line "1SOL    HW2    3"#),
        "too small: an atom is read as the box: {e}"
    );
    let e = parse(&gro.replace("    3\n", "  3.5\n"), "w.gro").unwrap_err();
    assert_eq!(e.to_string(), r#"w.gro:2: count atoms = "3.5": not a whole number"#, "not a count");
}

#[test]
fn an_xyz_file_whose_count_lies() {
    let xyz = "3\nwater\nO 0.0 0.0 0.1173\nH 0.0 0.7572 -0.4692\nH 0.0 -0.7572 -0.4692\n";
    assert_eq!(parse(xyz, "w.xyz").unwrap().len(), 3, "the honest file reads");
    let e = parse(&xyz.replacen('3', "9", 1), "w.xyz").unwrap_err();
    assert_eq!(e.to_string(), "w.xyz:1: the count line says 9 atoms; the file ends after 3", "too large");
    let e = parse(&xyz.replacen('3', "1", 1), "w.xyz").unwrap_err();
    assert!(e.to_string().starts_with(r#"w.xyz:4: "H 0.0 0.7572 -0.4692" follows the 1 atoms"#), "too small: {e}");
}

#[test]
fn an_mmcif_file_cut_inside_a_row() {
    let cif = "data_x\nloop_\n_atom_site.type_symbol\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\nN 1 2 3\nC 4 5\n";
    let e = parse(cif, "cut.cif").unwrap_err();
    assert_eq!(
        e.to_string(),
        "cut.cif:8: loop of type_symbol... ends 3 values into a row of 4: values missing (truncated?)",
        "cut"
    );
    let e = parse(&cif.replace("C 4 5\n", "C 4 5 six\n"), "cut.cif").unwrap_err();
    assert_eq!(e.to_string(), r#"cut.cif:8: _atom_site Cartn_z = "six": not a number"#, "bad z");
}

#[test]
fn warnings_name_the_file_and_line_and_are_capped() {
    let mut text = String::new();
    for i in 0..300 {
        writeln!(text, "HETATM{i:>5}  QQ  UNK X   1       1.000   2.000   3.000  1.00 20.00          QQ").unwrap();
    }
    let m = parse(&text, "odd.pdb").unwrap();
    assert_eq!(m.len(), 300, "read with a fallback");
    assert!(m.elements().iter().all(|e| !e.is_known()), "unknown elements");
    assert_eq!(m.elements()[0].radius(), molecule::FALLBACK_RADIUS, "the fallback radius");
    assert_eq!(m.elements()[0].jmol_srgb(), molecule::UNKNOWN_SRGB, "Jmol's unknown pink");
    assert_eq!((m.warnings().len(), m.warnings_total()), (100, 300), "capped at 100, all counted");
    assert_eq!(
        m.warnings()[1].to_string(),
        r#"odd.pdb:2: element "QQ" (columns 77-78) is not an element; Xx from atom name "QQ""#,
        "file:line"
    );
}
