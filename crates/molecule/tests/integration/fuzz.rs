//! No panic on any input: random bytes, and random line mutations of real structures in every
//! format, fed to every reader (proptest, fixed by its default seed persistence).

use std::fmt::Write;

use proptest::prelude::*;

use molecule::{Limits, ReadOptions};

use crate::SMALL_PDB;

/// SMALL_PDB's atoms in the other three formats, with a two-operator assembly in the mmCIF.
#[expect(clippy::unwrap_used, reason = "a test helper: the bundled sample's numbers parse")]
fn samples() -> Vec<(&'static str, String)> {
    let records: Vec<&str> = SMALL_PDB.lines().filter(|l| l.starts_with("ATOM") || l.starts_with("HETATM")).collect();
    let mut cif = String::from("data_1TII\nloop_\n_atom_site.group_PDB\n_atom_site.type_symbol\n_atom_site.label_atom_id\n_atom_site.label_alt_id\n_atom_site.label_asym_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n_atom_site.pdbx_PDB_model_num\n");
    let mut gro = format!("small\n{}\n", records.len());
    let mut xyz = format!("{}\nsmall\n", records.len());
    for r in &records {
        let f = |a: usize, b: usize| r[a..b].trim();
        writeln!(
            cif,
            "{} {} '{}' . {} {} {} {} 1",
            f(0, 6),
            f(76, 78),
            f(12, 16),
            f(21, 22),
            f(30, 38),
            f(38, 46),
            f(46, 54)
        )
        .unwrap();
        let nm = |v: &str| v.parse::<f64>().unwrap() / 10.0;
        writeln!(
            gro,
            "{:>5}{:<5}{:>5}{:>5}{:8.3}{:8.3}{:8.3}",
            1,
            f(17, 20),
            f(12, 16),
            1,
            nm(f(30, 38)),
            nm(f(38, 46)),
            nm(f(46, 54))
        )
        .unwrap();
        writeln!(xyz, "{} {} {} {}", f(76, 78), f(30, 38), f(38, 46), f(46, 54)).unwrap();
    }
    cif.push_str("#\n_pdbx_struct_assembly_gen.assembly_id 1\n_pdbx_struct_assembly_gen.oper_expression '(1-2)'\n_pdbx_struct_assembly_gen.asym_id_list D,E\n#\nloop_\n_pdbx_struct_oper_list.id\n_pdbx_struct_oper_list.matrix[1][1]\n_pdbx_struct_oper_list.matrix[1][2]\n_pdbx_struct_oper_list.matrix[1][3]\n_pdbx_struct_oper_list.vector[1]\n_pdbx_struct_oper_list.matrix[2][1]\n_pdbx_struct_oper_list.matrix[2][2]\n_pdbx_struct_oper_list.matrix[2][3]\n_pdbx_struct_oper_list.vector[2]\n_pdbx_struct_oper_list.matrix[3][1]\n_pdbx_struct_oper_list.matrix[3][2]\n_pdbx_struct_oper_list.matrix[3][3]\n_pdbx_struct_oper_list.vector[3]\n1 1 0 0 0 0 1 0 0 0 0 1 0\n2 0 -1 0 20 1 0 0 0 0 0 1 -3.5\n");
    gro.push_str("   5.0   5.0   5.0\n");
    vec![("s.pdb", SMALL_PDB.to_owned()), ("s.cif", cif), ("s.gro", gro), ("s.xyz", xyz)]
}

#[test]
fn the_samples_read_whole() {
    for (name, text) in samples() {
        let options =
            ReadOptions { assembly: name.ends_with("pdb") || name.ends_with("cif"), ..ReadOptions::default() };
        let m = molecule::parse(text.as_bytes(), name, &options).unwrap();
        let expected = if options.assembly { 20 } else { 10 };
        assert_eq!(m.len(), expected, "{name}: {:?}", m.warnings());
        assert!(m.warnings().is_empty(), "{name}: {:?}", m.warnings());
    }
}

/// Small limits, so random input also reaches them.
fn options(assembly: bool) -> ReadOptions {
    let limits = Limits { max_atoms: 64, max_line_bytes: 512, max_warnings: 4, ..Limits::default() };
    ReadOptions { assembly, limits, ..ReadOptions::default() }
}

/// Reads `bytes` as `name`; whatever the result, a molecule returned is well formed.
fn check(bytes: &[u8], name: &str, assembly: bool) {
    if let Ok(m) = molecule::parse(bytes, name, &options(assembly)) {
        assert!(!m.is_empty(), "{name}: a molecule has atoms");
        assert_eq!(m.positions().len(), m.elements().len(), "{name}: arrays agree");
        assert_eq!(m.positions().len(), m.chains().len(), "{name}: arrays agree");
        assert!(m.positions().iter().all(|p| p.is_finite()), "{name}: finite positions");
        assert!(m.chains().iter().all(|&c| usize::from(c) < m.chain_ids().len()), "{name}: chains in range");
        assert!(m.warnings().len() <= 4, "{name}: warnings capped");
    }
}

/// One line mutation: a byte replaced, a line cut, dropped, duplicated, or swapped with the next.
#[derive(Clone, Debug)]
enum Mutation {
    Byte { line: usize, at: usize, byte: u8 },
    Cut { line: usize, at: usize },
    Drop { line: usize },
    Duplicate { line: usize },
    Swap { line: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let byte = prop_oneof![
        Just(b' '),
        Just(b'.'),
        Just(b'-'),
        Just(b'x'),
        Just(b'\''),
        Just(b';'),
        Just(b'_'),
        Just(b'#'),
        any::<u8>()
    ];
    prop_oneof![
        (0..64_usize, 0..90_usize, byte).prop_map(|(line, at, byte)| Mutation::Byte { line, at, byte }),
        (0..64_usize, 0..90_usize).prop_map(|(line, at)| Mutation::Cut { line, at }),
        (0..64_usize).prop_map(|line| Mutation::Drop { line }),
        (0..64_usize).prop_map(|line| Mutation::Duplicate { line }),
        (0..64_usize).prop_map(|line| Mutation::Swap { line }),
    ]
}

fn mutate(text: &str, mutations: &[Mutation]) -> Vec<u8> {
    let mut lines: Vec<Vec<u8>> = text.lines().map(|l| l.as_bytes().to_vec()).collect();
    for m in mutations {
        let n = lines.len().max(1);
        match *m {
            Mutation::Byte { line, at, byte } => {
                if let Some(l) = lines.get_mut(line % n) {
                    if !l.is_empty() {
                        let k = at % l.len();
                        l[k] = byte;
                    }
                }
            }
            Mutation::Cut { line, at } => {
                if let Some(l) = lines.get_mut(line % n) {
                    l.truncate(at);
                }
            }
            Mutation::Drop { line } => {
                if !lines.is_empty() {
                    lines.remove(line % n);
                }
            }
            Mutation::Duplicate { line } => {
                if let Some(l) = lines.get(line % n).cloned() {
                    lines.insert(line % n, l);
                }
            }
            Mutation::Swap { line } => {
                if n > 1 {
                    lines.swap(line % n, (line + 1) % n);
                }
            }
        }
    }
    lines.join(&b'\n')
}

proptest! {
    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2048), assembly: bool) {
        for name in ["r.pdb", "r.cif", "r.gro", "r.xyz", "r.pdb.gz"] {
            check(&bytes, name, assembly);
        }
    }

    #[test]
    fn random_text_lines_never_panic(lines in proptest::collection::vec("[ -~]{0,90}", 0..40), assembly: bool) {
        let text = lines.join("\n");
        for name in ["r.pdb", "r.cif", "r.gro", "r.xyz"] {
            check(text.as_bytes(), name, assembly);
        }
    }

    #[test]
    fn mutated_real_files_never_panic(mutations in proptest::collection::vec(mutation(), 1..6), assembly: bool) {
        for (name, text) in samples() {
            check(&mutate(&text, &mutations), name, assembly);
        }
    }

    #[test]
    fn mutated_gzip_never_panics(at in 0..400_usize, byte: u8, cut in 0..400_usize) {
        use std::io::Write as _;
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        e.write_all(SMALL_PDB.as_bytes()).unwrap();
        let mut packed = e.finish().unwrap();
        let k = at % packed.len();
        packed[k] = byte;
        packed.truncate(packed.len() - cut % packed.len());
        check(&packed, "m.pdb.gz", false);
    }
}
