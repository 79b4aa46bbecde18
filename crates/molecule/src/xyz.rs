//! The XYZ reader: a line with the number of atoms, a comment line, then one line per atom,
//! `El x y z` (element symbol or atomic number, Ångström), whitespace-separated; further
//! columns (extended XYZ) are ignored. Only the first frame is read.

use crate::element::Element;
use crate::error::{quote, Error};
use crate::field::{parse_count, parse_f32};
use crate::fields::FieldsIn;
use crate::input::Lines;
use crate::molecule::{Builder, Molecule};
use crate::options::{Format, Limits};

/// Reads an XYZ file's first frame.
pub(crate) fn read(lines: &mut Lines<'_>, limits: &Limits) -> Result<Molecule, Error> {
    let file = lines.file();
    let malformed = |line: u64, why: String| Error::Malformed { file: file.to_owned(), line, why };
    let Some((_, count_line)) = lines.next_line()? else {
        return Err(Error::NoAtoms { file: file.to_owned(), why: "the file is empty" });
    };
    let count = parse_count(count_line).map_err(|why| Error::Field {
        file: file.to_owned(),
        line: 1,
        record: "count",
        field: "atoms",
        value: quote(count_line),
        why,
    })?;
    if count > limits.max_atoms as u64 {
        return Err(Error::TooManyAtoms { file: file.to_owned(), count, what: "", limit: limits.max_atoms });
    }
    if lines.next_line()?.is_none() {
        return Err(malformed(1, format!("the count line says {count} atoms; the file ends before the comment line")));
    }
    let mut atoms = Builder::new(file, limits);
    atoms.reserve(usize::try_from(count).unwrap_or(usize::MAX), 1 << 20);
    let chain = atoms.chain(b"", 1)?;
    for k in 0..count {
        let Some((line, text)) = lines.next_line()? else {
            return Err(malformed(1, format!("the count line says {count} atoms; the file ends after {k}")));
        };
        let mut fields = text.split(u8::is_ascii_whitespace).filter(|t| !t.is_empty());
        let symbol = fields.next().unwrap_or_default();
        let mut xyz = [0.0; 3];
        for (value, field) in xyz.iter_mut().zip(["x", "y", "z"]) {
            let Some(bytes) = fields.next() else {
                return Err(malformed(
                    line,
                    format!("atom line {:?} has no {field}; it needs El x y z (is the count on line 1, {count}, too large?)", quote(text)),
                ));
            };
            *value = parse_f32(bytes).map_err(|why| Error::Field {
                file: file.to_owned(),
                line,
                record: "atom",
                field,
                value: quote(bytes),
                why,
            })?;
        }
        let by_number =
            std::str::from_utf8(symbol).ok().and_then(|s| s.parse::<u8>().ok()).and_then(Element::from_atomic_number);
        let element = Element::from_symbol(symbol).or(by_number).unwrap_or_else(|| {
            atoms.warn(line, || format!("element {:?} is not an element: unknown (Xx)", quote(symbol)));
            Element::UNKNOWN
        });
        atoms.push(xyz, element, chain, &FieldsIn::NONE, line)?;
    }
    // What follows is nothing, or the next frame's count.
    while let Some((line, text)) = lines.next_line()? {
        let text = text.trim_ascii();
        if text.is_empty() {
            continue;
        }
        if parse_count(text).is_ok() {
            atoms.warn(0, || "several frames: only the first is read".to_owned());
            break;
        }
        return Err(malformed(
            line,
            format!(
                "{:?} follows the {count} atoms the count line (line 1) says (is the count too small?)",
                quote(text)
            ),
        ));
    }
    atoms.finish(Format::Xyz, Vec::new(), "the count line says 0 atoms")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_text(text: &str) -> Result<Molecule, Error> {
        let mut lines = Lines::new("t.xyz", Box::new(text.as_bytes()), &Limits::default())?;
        read(&mut lines, &Limits::default())
    }

    const WATER: &str = "3\nwater\nO 0.0 0.0 0.1173\nH 0.0 0.7572 -0.4692\n1 0.0 -0.7572 -0.4692\n";

    #[test]
    fn atoms_by_symbol_or_number() {
        let m = read_text(WATER).unwrap();
        assert_eq!(m.elements(), [Element::O, Element::H, Element::H], "symbol or atomic number");
        assert_eq!(m.positions()[1], glam::Vec3::new(0.0, 0.7572, 0.4692), "(x, y, -z)");
        let two_frames = format!("{WATER}{WATER}");
        let m = read_text(&two_frames).unwrap();
        assert_eq!((m.len(), m.warnings().len()), (3, 1), "the first frame, with a warning");
    }

    #[test]
    fn a_count_that_lies_is_an_error() {
        let e = read_text(&WATER.replacen('3', "4", 1)).unwrap_err();
        assert_eq!(e.to_string(), "t.xyz:1: the count line says 4 atoms; the file ends after 3", "too large");
        let e = read_text(&WATER.replacen('3', "2", 1)).unwrap_err();
        assert!(e.to_string().starts_with(r#"t.xyz:5: "1 0.0 -0.7572 -0.4692" follows the 2 atoms"#), "too small: {e}");
        let e = read_text("x\nwater\n").unwrap_err();
        assert_eq!(e.to_string(), r#"t.xyz:1: count atoms = "x": not a whole number"#, "not a count");
    }

    #[test]
    fn bad_atom_lines_name_line_and_field() {
        let e = read_text(&WATER.replace("0.7572 -0.4692", "0.7572 -0.4.92")).unwrap_err();
        assert_eq!(e.to_string(), r#"t.xyz:4: atom z = "-0.4.92": not a number"#, "non-numeric z");
        let e = read_text(&WATER.replace("H 0.0 0.7572 -0.4692", "H 0.0")).unwrap_err();
        assert!(e.to_string().starts_with(r#"t.xyz:4: atom line "H 0.0" has no y"#), "short line: {e}");
        let m = read_text(&WATER.replacen("O ", "Qq ", 1)).unwrap();
        assert_eq!(m.elements()[0], Element::UNKNOWN, "unknown element");
        assert_eq!(m.warnings()[0].to_string(), r#"t.xyz:3: element "Qq" is not an element: unknown (Xx)"#, "warned");
        let e = read_text("").unwrap_err();
        assert_eq!(e.to_string(), "t.xyz: no atoms: the file is empty", "empty");
    }
}
