//! The PDB reader: fixed columns of `ATOM`/`HETATM` records, `MODEL`s and `REMARK 350`
//! biological assemblies, after the wwPDB "Atomic Coordinate Entry Format Version 3.3"
//! (2011), sections "Coordinate Section" and "Remarks 350".
//!
//! Columns read (1-based, as the spec numbers them): 13–16 atom name, 17 alternate location,
//! 18–20 residue name, 22 chain, 23–26 residue number, 27 insertion code, 31–38 x, 39–46 y,
//! 47–54 z (Ångström), 55–60 occupancy, 61–66 B-factor, 77–78 element. A record shorter
//! than 54 columns is an error; a missing element column falls back to the atom name; a
//! blank or unreadable residue number, occupancy or B-factor is kept as none (unreadable
//! with a warning).
//!
//! What is kept: model 1 only (later `MODEL`s are skipped with a warning); of alternate
//! locations, blank and the first letter seen in the file (usually `A`; the others are
//! skipped with a warning). Reading stops at `END`.

use crate::assembly::{Assembly, AssemblyPart, Operator};
use crate::element::Element;
use crate::error::{quote, Error};
use crate::field::{columns, finite, optional, parse_count, parse_f32, parse_f64};
use crate::fields::FieldsIn;
use crate::input::Lines;
use crate::molecule::{Builder, Molecule};
use crate::options::{Format, Limits};

/// The columns of the last coordinate: a shorter `ATOM` record is cut.
const COORDINATES_END: usize = 54;

/// The element of a PDB atom name (columns 13–16) by the spec's alignment rule: a one-letter
/// element's name starts in column 14 (column 13 blank or a digit, as in `" CA "` or
/// `"1HB "`), a two-letter element's in column 13 (`"FE  "`, `"CL1 "`). Names that fill
/// column 13 but are not two-letter elements take their first letter. Two exceptions from
/// practice: four-character hydrogen names start in column 13 (`"HG21"` is hydrogen, not
/// mercury), and in `ATOM` records (standard residues) a name starting C, H, N, O, S or P is
/// that element even when left-justified (`"CA  "` is carbon, not calcium).
#[must_use]
pub(crate) fn element_from_name(name: &[u8], hetero: bool) -> Element {
    let byte = |i: usize| name.get(i).copied().unwrap_or(b' ');
    let (first, second) = (byte(0), byte(1));
    if first == b' ' || first.is_ascii_digit() {
        return Element::from_symbol(&[second]).unwrap_or(Element::UNKNOWN);
    }
    let single = Element::from_symbol(&[first]);
    let organic = matches!(first.to_ascii_uppercase(), b'C' | b'H' | b'N' | b'O' | b'S' | b'P');
    let rest_blank = byte(2) == b' ' && byte(3) == b' ';
    let hydrogen_name = first.eq_ignore_ascii_case(&b'H') && !rest_blank;
    // A standard residue's C, H, N, O, S or P name is that element, never a two-letter one.
    let two_letter_allowed = hetero || !organic;
    if second.is_ascii_alphabetic() && !hydrogen_name && two_letter_allowed {
        if let Some(two) = Element::from_symbol(&[first, second]) {
            return two;
        }
    }
    single.unwrap_or(Element::UNKNOWN)
}

/// What `REMARK 350` has said so far.
#[derive(Default)]
struct Remark350 {
    assemblies: Vec<Assembly>,
    /// BIOMT rows of the operator being read: serial, rows so far.
    pending: Option<(String, Vec<[f64; 4]>)>,
}

impl Remark350 {
    fn line(&mut self, file: &str, line: u64, text: &[u8]) -> Result<(), Error> {
        let body = columns(text, 10..text.len()).trim_ascii();
        let malformed = |why: &str| Error::Malformed { file: file.to_owned(), line, why: format!("REMARK 350: {why}") };
        if let Some(id) = body.strip_prefix(b"BIOMOLECULE:") {
            self.close_operator(&malformed)?;
            self.assemblies
                .push(Assembly { id: String::from_utf8_lossy(id.trim_ascii()).into_owned(), parts: Vec::new() });
        } else if let Some(chains) = after(body, b"APPLY THE FOLLOWING TO CHAINS:") {
            self.close_operator(&malformed)?;
            let assembly = self.assemblies.last_mut().ok_or_else(|| malformed("APPLY before BIOMOLECULE"))?;
            assembly.parts.push(AssemblyPart { chains: chain_list(chains), operators: Vec::new() });
        } else if let Some(chains) = after(body, b"AND CHAINS:") {
            let part = self
                .assemblies
                .last_mut()
                .and_then(|a| a.parts.last_mut())
                .ok_or_else(|| malformed("AND CHAINS before APPLY"))?;
            part.chains.extend(chain_list(chains));
        } else if body.starts_with(b"BIOMT") {
            self.biomt(file, line, body, &malformed)?;
        }
        Ok(())
    }

    /// `BIOMTn serial r_n1 r_n2 r_n3 t_n`.
    fn biomt(&mut self, file: &str, line: u64, body: &[u8], malformed: &dyn Fn(&str) -> Error) -> Result<(), Error> {
        let mut tokens = body.split(u8::is_ascii_whitespace).filter(|t| !t.is_empty());
        let name = tokens.next().unwrap_or_default();
        let row = match name {
            b"BIOMT1" => 0,
            b"BIOMT2" => 1,
            b"BIOMT3" => 2,
            _ => return Err(malformed(&format!("{} is not BIOMT1, BIOMT2 or BIOMT3", quote(name)))),
        };
        let serial = String::from_utf8_lossy(tokens.next().unwrap_or_default()).into_owned();
        let mut values = [0.0; 4];
        for (i, value) in values.iter_mut().enumerate() {
            let token = tokens.next().ok_or_else(|| malformed(&format!("{} has {i} of its 4 numbers", quote(name))))?;
            let field = if i == 3 { "BIOMT translation" } else { "BIOMT matrix" };
            *value = parse_f64(token).map_err(|why| Error::Field {
                file: file.to_owned(),
                line,
                record: "REMARK 350",
                field,
                value: quote(token),
                why,
            })?;
        }
        match (&mut self.pending, row) {
            (pending @ None, 0) => *pending = Some((serial, vec![values])),
            (Some((pending_serial, rows)), 1 | 2) if rows.len() == row && *pending_serial == serial => {
                rows.push(values);
            }
            _ => return Err(malformed(&format!("{} {} out of order", quote(name), quote(serial.as_bytes())))),
        }
        if let Some((serial, rows)) = self.pending.take_if(|(_, rows)| rows.len() == 3) {
            let part = self
                .assemblies
                .last_mut()
                .and_then(|a| a.parts.last_mut())
                .ok_or_else(|| malformed("BIOMT before APPLY"))?;
            part.operators.push(Operator::from_file_rows(serial, [rows[0], rows[1], rows[2]]));
        }
        Ok(())
    }

    fn close_operator(&self, malformed: &dyn Fn(&str) -> Error) -> Result<(), Error> {
        match &self.pending {
            Some((serial, rows)) => Err(malformed(&format!("BIOMT {serial} has {} of its 3 rows", rows.len()))),
            None => Ok(()),
        }
    }
}

/// The text after `label`, when `body` holds it.
fn after<'t>(body: &'t [u8], label: &[u8]) -> Option<&'t [u8]> {
    body.windows(label.len()).position(|w| w == label).and_then(|at| body.get(at + label.len()..))
}

/// `A, B, P,` as chain ids.
fn chain_list(text: &[u8]) -> Vec<String> {
    text.split(|&b| b == b',')
        .map(<[u8]>::trim_ascii)
        .filter(|id| !id.is_empty())
        .map(|id| String::from_utf8_lossy(id).into_owned())
        .collect()
}

/// Reads a PDB file's atoms (model 1), and its assemblies.
pub(crate) fn read(lines: &mut Lines<'_>, limits: &Limits, want_assembly: bool) -> Result<Molecule, Error> {
    let file = lines.file();
    let mut atoms = Builder::new(file, limits);
    let mut remark = Remark350::default();
    let mut remark_error: Option<Error> = None;
    let mut models = 0_u64;
    let mut other_model_atoms = 0_u64;
    let mut first_alt: Option<u8> = None;
    let mut other_alt_atoms = 0_u64;
    let mut first_other_alt_line = 0_u64;
    while let Some((line, text)) = lines.next_line()? {
        let record = columns(text, 0..6).trim_ascii_end();
        let hetero = match record {
            b"ATOM" => false,
            b"HETATM" => true,
            b"MODEL" => {
                models += 1;
                atoms.set_model_if(models == 1, parse_count(columns(text, 6..text.len())).ok());
                continue;
            }
            b"END" => break,
            b"REMARK" if columns(text, 6..10) == b" 350" => {
                if remark_error.is_none() {
                    remark_error = remark.line(file, line, text).err();
                }
                continue;
            }
            _ => continue,
        };
        if models > 1 {
            other_model_atoms += 1;
            continue;
        }
        let name = if hetero { "HETATM" } else { "ATOM" };
        if text.len() < COORDINATES_END {
            return Err(Error::Malformed {
                file: file.to_owned(),
                line,
                why: format!(
                    "{name} record has {} columns; its coordinates end at column {COORDINATES_END}",
                    text.len()
                ),
            });
        }
        let alt = columns(text, 16..17).first().copied().unwrap_or(b' ');
        if alt != b' ' {
            match first_alt {
                None => first_alt = Some(alt),
                Some(first) if first == alt => {}
                Some(_) => {
                    other_alt_atoms += 1;
                    if first_other_alt_line == 0 {
                        first_other_alt_line = line;
                    }
                    continue;
                }
            }
        }
        let mut xyz = [0.0; 3];
        for (value, (range, field)) in xyz.iter_mut().zip([(30..38, "x"), (38..46, "y"), (46..54, "z")]) {
            let bytes = columns(text, range);
            *value = parse_f32(bytes).map_err(|why| Error::Field {
                file: file.to_owned(),
                line,
                record: if hetero { "HETATM" } else { "ATOM" },
                field,
                value: quote(bytes),
                why,
            })?;
        }
        let element = element_of(&mut atoms, text, hetero, line);
        let chain = atoms.chain(columns(text, 21..22).trim_ascii(), line)?;
        let fields = fields_of(&mut atoms, text, hetero, line);
        atoms.push(xyz, element, chain, &fields, line)?;
    }
    if lines.line() == 0 {
        return Err(Error::NoAtoms { file: file.to_owned(), why: "the file is empty" });
    }
    if other_model_atoms > 0 {
        atoms.warn(0, || {
            format!("{models} models; only model 1 is read ({other_model_atoms} atoms of later models skipped)")
        });
    }
    if other_alt_atoms > 0 {
        let kept = char::from(first_alt.unwrap_or(b'A'));
        atoms.warn(first_other_alt_line, || {
            format!("alternate locations other than {kept:?}: {other_alt_atoms} atoms skipped (the first here)")
        });
    }
    let mut assemblies = remark.assemblies;
    if let Some(e) = remark_error {
        if want_assembly {
            return Err(e);
        }
        atoms.warn(0, || format!("assemblies ignored: {e}"));
        assemblies.clear();
    }
    assemblies.retain(|a| !a.parts.is_empty());
    atoms.finish(Format::Pdb, assemblies, "no ATOM or HETATM record")
}

/// Columns 13–27 and 55–66 of an `ATOM` or `HETATM` record (see the module doc).
fn fields_of<'t>(atoms: &mut Builder<'_>, text: &'t [u8], hetero: bool, line: u64) -> FieldsIn<'t> {
    let record = if hetero { "HETATM" } else { "ATOM" };
    let code = columns(text, 26..27).first().copied().filter(|&c| c != b' ');
    FieldsIn {
        name: columns(text, 12..16),
        residue: columns(text, 17..20),
        residue_number: optional(atoms, (record, "resSeq"), columns(text, 22..26), line, |t| t.parse().ok()),
        insertion_code: code,
        b_factor: optional(atoms, (record, "tempFactor"), columns(text, 60..66), line, finite),
        occupancy: optional(atoms, (record, "occupancy"), columns(text, 54..60), line, finite),
        hetero,
    }
}

/// The element from columns 77–78, else from the atom name; unknown with a warning.
fn element_of(atoms: &mut Builder<'_>, text: &[u8], hetero: bool, line: u64) -> Element {
    let symbol = columns(text, 76..78);
    if let Some(element) = Element::from_symbol(symbol) {
        return element;
    }
    let name = columns(text, 12..16);
    let element = element_from_name(name, hetero);
    if !symbol.trim_ascii().is_empty() {
        atoms.warn(line, || {
            format!(
                "element {:?} (columns 77-78) is not an element; {} from atom name {:?}",
                quote(symbol),
                element.symbol(),
                quote(name)
            )
        });
    } else if !element.is_known() {
        atoms.warn(line, || format!("no element in columns 77-78 nor atom name {:?}: unknown (Xx)", quote(name)));
    }
    element
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_text(text: &str, want_assembly: bool) -> Result<Molecule, Error> {
        let mut lines = Lines::new("t.pdb", Box::new(text.as_bytes()), &Limits::default())?;
        read(&mut lines, &Limits::default(), want_assembly)
    }

    const TWO_ATOMS: &str = "\
ATOM      1  N   GLY D   1      42.053  -9.336  17.867  1.00 43.86           N
HETATM 5470 FE   HEM A 200       1.000   2.000   3.000  1.00 20.00          FE
END
ATOM      3  C   GLY D   1      44.140 -10.512  18.447  1.00 40.48           C
";

    #[test]
    fn atoms_elements_and_chains_from_fixed_columns() {
        let m = read_text(TWO_ATOMS, false).unwrap();
        assert_eq!(m.len(), 2, "stops at END");
        assert_eq!(m.positions()[0], glam::Vec3::new(42.053, -9.336, -17.867), "(x, y, -z)");
        assert_eq!(m.elements()[1].symbol(), "Fe", "element columns 77-78");
        assert_eq!(m.chain_ids(), ["D", "A"], "column 22");
        assert!(m.warnings().is_empty(), "{:?}", m.warnings());
    }

    #[test]
    fn each_atoms_fields_from_their_columns() {
        let text = "\
MODEL        3
ATOM      1  N   GLY D   1A     42.053  -9.336  17.867  0.50 43.86           N
HETATM 5470 FE   HEM A 200       1.000   2.000   3.000  1.00 20.00          FE
ATOM      2  CA  GLY D   x      42.704 -10.253  18.851
ENDMDL
";
        let m = read_text(text, false).unwrap();
        let a = m.atom(0).unwrap();
        assert_eq!(
            (a.name, a.residue_name, a.residue_number, a.insertion_code),
            ("N", "GLY", Some(1), Some('A')),
            "ATOM"
        );
        assert_eq!(
            (a.b_factor, a.occupancy, a.hetero, a.model),
            (Some(43.86), Some(0.5), false, Some(3)),
            "columns 55-66"
        );
        assert_eq!((a.chain, a.file_position), ("D", [42.053, -9.336, 17.867]), "the file's coordinates");
        let fe = m.atom(1).unwrap();
        assert_eq!((fe.name, fe.residue_name, fe.residue_number, fe.hetero), ("FE", "HEM", Some(200), true), "HETATM");
        let short = m.atom(2).unwrap();
        assert_eq!((short.residue_number, short.b_factor, short.occupancy), (None, None, None), "unreadable or cut");
        assert_eq!(m.warnings().len(), 1, "the bad residue number is named: {:?}", m.warnings());
        assert_eq!(m.warnings()[0].to_string(), "t.pdb:4: ATOM resSeq \"x\" is not a number: none kept", "message");
        assert!(m.atom(3).is_none(), "past the end");
    }

    #[test]
    fn element_from_the_atom_name_by_the_spec_alignment() {
        let e = |name: &[u8], hetero| element_from_name(name, hetero).symbol();
        assert_eq!(e(b" CA ", false), "C", "C-alpha, column 14");
        assert_eq!(e(b"CA  ", true), "Ca", "calcium, column 13, HETATM");
        assert_eq!(e(b"CA  ", false), "C", "left-justified C-alpha in a standard residue");
        assert_eq!(e(b"FE  ", true), "Fe", "iron");
        assert_eq!(e(b"HG21", false), "H", "valine hydrogen");
        assert_eq!(e(b"HG  ", true), "Hg", "mercury");
        assert_eq!(e(b"HO5'", true), "H", "a four-character hydrogen name is not holmium");
        assert_eq!(e(b"1HB ", false), "H", "digit then hydrogen");
        assert_eq!(e(b"OXT ", false), "O", "OX is not an element");
        assert_eq!(e(b"CL1 ", true), "Cl", "chlorine with a number");
        assert_eq!(e(b" XX ", true), "Xx", "nothing known");
    }

    #[test]
    fn element_falls_back_to_the_name_with_a_warning_when_the_columns_are_wrong() {
        let text = "ATOM      1  CA  GLY D   1      42.053  -9.336  17.867  1.00 43.86          QQ\n\
                    ATOM      2  XY  GLY D   1      42.053  -9.336  17.867  1.00 43.86\n";
        let m = read_text(text, false).unwrap();
        assert_eq!(m.elements(), [Element::C, Element::UNKNOWN], "from the name, then unknown");
        assert_eq!(m.warnings().len(), 2, "{:?}", m.warnings());
        assert!(m.warnings()[0].to_string().starts_with("t.pdb:1: element \"QQ\""), "{}", m.warnings()[0]);
        assert!(m.warnings()[1].to_string().starts_with("t.pdb:2: no element"), "{}", m.warnings()[1]);
    }

    #[test]
    fn only_model_one_and_the_first_alternate_location_are_kept() {
        let text = "\
MODEL        1
ATOM      1  N  AGLY A   1       1.000   1.000   1.000  0.50 43.86           N
ATOM      2  N  BGLY A   1       1.100   1.000   1.000  0.50 43.86           N
ATOM      3  C   GLY A   1       2.000   1.000   1.000  1.00 43.86           C
ENDMDL
MODEL        2
ATOM      1  N   GLY A   1       9.000   1.000   1.000  1.00 43.86           N
ENDMDL
";
        let m = read_text(text, false).unwrap();
        assert_eq!(m.len(), 2, "the A location and the atom without one");
        assert_eq!(m.positions()[0].x, 1.0, "location A");
        let w: Vec<String> = m.warnings().iter().map(ToString::to_string).collect();
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].contains("2 models; only model 1"), "{w:?}");
        assert!(w[1].starts_with("t.pdb:3: alternate locations other than 'A'"), "{w:?}");
    }

    #[test]
    fn malformed_atoms_name_file_line_and_field() {
        let bad_x = "ATOM      1  N   GLY D   1      12.3a4  -9.336  17.867  1.00 43.86           N\n";
        let e = read_text(&format!("REMARK\n{bad_x}"), false).unwrap_err();
        assert_eq!(e.to_string(), r#"t.pdb:2: ATOM x = "12.3a4": not a number"#, "non-numeric x");
        let bad_z = "HETATM    1  N   GLY D   1      12.300  -9.336    nan   1.00 43.86           N\n";
        let e = read_text(bad_z, false).unwrap_err();
        assert_eq!(e.to_string(), r#"t.pdb:1: HETATM z = "nan": not finite"#, "NaN z");
        let short = "ATOM      1  N   GLY D   1      42.053  -9.336  17.8\n";
        let e = read_text(short, false).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.pdb:1: ATOM record has 52 columns; its coordinates end at column 54",
            "short line"
        );
    }

    #[test]
    fn empty_and_atomless_files_are_errors() {
        let e = read_text("", false).unwrap_err();
        assert_eq!(e.to_string(), "t.pdb: no atoms: the file is empty", "empty");
        let e = read_text("HEADER    NOTHING\nEND\n", false).unwrap_err();
        assert_eq!(e.to_string(), "t.pdb: no atoms: no ATOM or HETATM record", "no atoms");
    }

    const REMARK_350: &str = "\
REMARK 350 BIOMOLECULE: 1
REMARK 350 APPLY THE FOLLOWING TO CHAINS: A,
REMARK 350                    AND CHAINS: B
REMARK 350   BIOMT1   1  1.000000  0.000000  0.000000        0.00000
REMARK 350   BIOMT2   1  0.000000  1.000000  0.000000        0.00000
REMARK 350   BIOMT3   1  0.000000  0.000000  1.000000        0.00000
REMARK 350   BIOMT1   2 -1.000000  0.000000  0.000000       10.00000
REMARK 350   BIOMT2   2  0.000000 -1.000000  0.000000        0.00000
REMARK 350   BIOMT3   2  0.000000  0.000000  1.000000        5.00000
ATOM      1  N   GLY A   1       1.000   2.000   3.000  1.00 43.86           N
ATOM      2  C   GLY B   1       4.000   5.000   6.000  1.00 43.86           C
ATOM      3  O   HOH C   1       7.000   8.000   9.000  1.00 43.86           O
";

    #[test]
    fn remark_350_gives_the_assembly_operators_and_chains() {
        let m = read_text(REMARK_350, false).unwrap();
        let a = &m.assemblies()[0];
        assert_eq!(a.id, "1", "BIOMOLECULE");
        assert_eq!(a.parts.len(), 1, "one APPLY");
        assert_eq!(a.parts[0].chains, ["A", "B"], "APPLY and AND CHAINS");
        assert_eq!(a.parts[0].operators.len(), 2, "two BIOMT");
        let big = m.expand_assembly(0, &Limits::default()).unwrap();
        assert_eq!(big.len(), 4, "chains A and B twice; C is not listed");
        // File (1, 2, 3) turned about z by 180° and moved by (10, 0, 5): (9, -2, 8); ours (9, -2, -8).
        assert_eq!(big.positions()[2], glam::Vec3::new(9.0, -2.0, -8.0), "second operator on atom 1");
    }

    #[test]
    fn a_broken_remark_350_fails_only_when_the_assembly_is_wanted() {
        let broken = REMARK_350.replace("BIOMT2   2  0.000000 -1.000000", "BIOMT2   2  0.000000 -1.0x0000");
        let e = read_text(&broken, true).unwrap_err();
        assert_eq!(e.to_string(), r#"t.pdb:8: REMARK 350 BIOMT matrix = "-1.0x0000": not a number"#, "names the line");
        let m = read_text(&broken, false).unwrap();
        assert!(m.assemblies().is_empty(), "no half-read assembly");
        assert!(m.warnings()[0].message.starts_with("assemblies ignored: t.pdb:8:"), "{:?}", m.warnings());
        let missing_row =
            REMARK_350.replace("REMARK 350   BIOMT2   1  0.000000  1.000000  0.000000        0.00000\n", "");
        let e = read_text(&missing_row, true).unwrap_err();
        assert_eq!(e.to_string(), "t.pdb:5: REMARK 350: BIOMT3 1 out of order", "a missing row");
    }
}
