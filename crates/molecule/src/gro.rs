//! The GROMACS `.gro` reader, after the GROMACS manual's "gro" file format page: a title
//! line, a line with the number of atoms, one fixed-column line per atom, a box line.
//!
//! Atom lines: residue number (columns 1–5), residue name (6–10), atom name (11–15), atom
//! number (16–20), then x, y, z in nanometres, each 8 columns wide with 3 decimals — or, as
//! the manual allows, wider with more decimals, the width being the distance between the
//! decimal points of the first atom's x and y. Velocities after them are ignored.
//! Coordinates are scaled to Ångström (×10). The element is read from the atom name
//! ([`element_from_bare_name`]), there being no element column. The residue number, residue
//! name and atom name are kept as the atom's fields. Only the first frame is read.

use crate::element::element_from_bare_name;
use crate::error::{quote, Error};
use crate::field::{columns, optional, parse_count, parse_f64};
use crate::fields::FieldsIn;
use crate::input::Lines;
use crate::molecule::{Builder, Molecule};
use crate::options::{Format, Limits};

/// Where the coordinates start (0-based column).
const COORDINATES_START: usize = 20;

/// The coordinate field width: 8, or the distance between the first line's decimal points.
fn field_width(line: &[u8]) -> usize {
    let rest = columns(line, COORDINATES_START..line.len());
    let mut dots = rest.iter().enumerate().filter(|(_, &b)| b == b'.').map(|(i, _)| i);
    match (dots.next(), dots.next()) {
        (Some(first), Some(second)) if (8..=20).contains(&(second - first)) => second - first,
        _ => 8,
    }
}

/// Reads a GRO file's first frame.
pub(crate) fn read(lines: &mut Lines<'_>, limits: &Limits) -> Result<Molecule, Error> {
    let file = lines.file();
    let malformed = |line: u64, why: String| Error::Malformed { file: file.to_owned(), line, why };
    if lines.next_line()?.is_none() {
        return Err(Error::NoAtoms { file: file.to_owned(), why: "the file is empty" });
    }
    let Some((_, count_line)) = lines.next_line()? else {
        return Err(malformed(1, "no atom-count line after the title".to_owned()));
    };
    let count = parse_count(count_line).map_err(|why| Error::Field {
        file: file.to_owned(),
        line: 2,
        record: "count",
        field: "atoms",
        value: quote(count_line),
        why,
    })?;
    if count > limits.max_atoms as u64 {
        return Err(Error::TooManyAtoms { file: file.to_owned(), count, what: "", limit: limits.max_atoms });
    }
    let mut atoms = Builder::new(file, limits);
    atoms.reserve(usize::try_from(count).unwrap_or(usize::MAX), 1 << 20);
    let chain = atoms.chain(b"", 2)?;
    let mut width = 8;
    for k in 0..count {
        let Some((line, text)) = lines.next_line()? else {
            return Err(malformed(2, format!("the count line says {count} atoms; the file ends after {k}")));
        };
        if k == 0 {
            width = field_width(text);
        }
        let end = COORDINATES_START + 3 * width;
        if text.len() < end {
            return Err(malformed(
                line,
                format!("atom line has {} columns; its coordinates end at column {end} (is the count on line 2, {count}, too large?)", text.len()),
            ));
        }
        let mut xyz = [0.0; 3];
        for (axis, (value, field)) in xyz.iter_mut().zip(["x", "y", "z"]).enumerate() {
            let start = COORDINATES_START + axis * width;
            let bytes = columns(text, start..start + width);
            let nm = parse_f64(bytes).map_err(|why| Error::Field {
                file: file.to_owned(),
                line,
                record: "atom",
                field,
                value: quote(bytes),
                why,
            })?;
            *value = (nm * 10.0) as f32;
        }
        let (residue, name) = (columns(text, 5..10), columns(text, 10..15));
        let element = element_from_bare_name(name.trim_ascii(), residue.trim_ascii());
        if !element.is_known() {
            atoms.warn(line, || format!("no element in atom name {:?}: unknown (Xx)", quote(name)));
        }
        let number = optional(&mut atoms, ("atom", "residue number"), columns(text, 0..5), line, |t| t.parse().ok());
        let fields = FieldsIn { name, residue, residue_number: number, ..FieldsIn::NONE };
        atoms.push(xyz, element, chain, &fields, line)?;
    }
    let Some((line, box_line)) = lines.next_line()? else {
        return Err(malformed(lines.line(), format!("no box line after the {count} atoms (truncated?)")));
    };
    let vectors: Vec<&[u8]> = box_line.split(u8::is_ascii_whitespace).filter(|t| !t.is_empty()).collect();
    let numbers = vectors.iter().all(|v| parse_f64(v).is_ok());
    if !numbers || !(vectors.len() == 3 || vectors.len() == 9) {
        return Err(malformed(
            line,
            format!(
                "box line {:?} is not 3 or 9 numbers (is the count on line 2, {count}, too small?)",
                quote(box_line)
            ),
        ));
    }
    if lines.next_line()?.is_some_and(|(_, l)| !l.trim_ascii().is_empty()) {
        atoms.warn(0, || "several frames: only the first is read".to_owned());
    }
    atoms.finish(Format::Gro, Vec::new(), "the count line says 0 atoms")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_text(text: &str) -> Result<Molecule, Error> {
        let mut lines = Lines::new("t.gro", Box::new(text.as_bytes()), &Limits::default())?;
        read(&mut lines, &Limits::default())
    }

    const WATER: &str = "\
Two waters and an ion, t= 0.0
    4
    1SOL     OW    1   0.126   1.624   1.679
    1SOL    HW1    2   0.190   1.661   1.747
    1SOL    HW2    3   0.177   1.568   1.613
    2NA      NA    4   1.000   2.000  -3.000
   1.86206   1.86206   1.86206
";

    #[test]
    fn residue_and_atom_names_and_numbers_are_kept() {
        let m = read_text(WATER).unwrap();
        let (a, na) = (m.atom(1).unwrap(), m.atom(3).unwrap());
        assert_eq!((a.name, a.residue_name, a.residue_number), ("HW1", "SOL", Some(1)), "columns 11-15, 6-10, 1-5");
        assert_eq!((na.name, na.residue_name, na.residue_number), ("NA", "NA", Some(2)), "the ion");
        assert_eq!((a.b_factor, a.occupancy, a.model, a.hetero), (None, None, None, false), "GRO has none");
    }

    #[test]
    fn atoms_in_angstrom_with_elements_from_names() {
        let m = read_text(WATER).unwrap();
        assert_eq!(m.len(), 4, "count line");
        assert_eq!(m.positions()[0], glam::Vec3::new(1.26, 16.24, -16.79), "nm x 10, (x, y, -z)");
        let symbols: Vec<&str> = m.elements().iter().map(|e| e.symbol()).collect();
        assert_eq!(symbols, ["O", "H", "H", "Na"], "from atom names");
        assert_eq!(m.positions()[3], glam::Vec3::new(10.0, 20.0, 30.0), "negative z");
    }

    #[test]
    fn wider_fields_are_told_by_the_decimal_points() {
        let text = "t\n1\n    1SOL     OW    1   0.12600   1.62400   1.67900\n1 1 1\n";
        let m = read_text(text).unwrap();
        assert_eq!(m.positions()[0], glam::Vec3::new(1.26, 16.24, -16.79), "10-column fields");
    }

    #[test]
    fn a_count_that_lies_is_an_error() {
        let e = read_text(&WATER.replace("    4\n", "    6\n")).unwrap_err();
        assert!(
            e.to_string().starts_with("t.gro:7: atom line has 30 columns"),
            "too many: the box line read as an atom: {e}"
        );
        let e = read_text(&WATER.replace("    4\n", "    3\n")).unwrap_err();
        assert!(e.to_string().starts_with(r#"t.gro:6: box line "2NA      NA    4"#), "too few: {e}");
        assert!(e.to_string().ends_with("(is the count on line 2, 3, too small?)"), "{e}");
        let cut: String = WATER.lines().take(4).flat_map(|l| [l, "\n"]).collect();
        let e = read_text(&cut).unwrap_err();
        assert_eq!(e.to_string(), "t.gro:2: the count line says 4 atoms; the file ends after 2", "truncated");
        let e = read_text(&WATER.replace("    4\n", "four\n")).unwrap_err();
        assert_eq!(e.to_string(), r#"t.gro:2: count atoms = "four": not a whole number"#, "not a count");
    }

    #[test]
    fn bad_coordinates_name_line_and_field() {
        let e = read_text(&WATER.replace("1.661", "1.6x1")).unwrap_err();
        assert_eq!(e.to_string(), r#"t.gro:4: atom y = "1.6x1": not a number"#, "non-numeric y");
        let e = read_text("").unwrap_err();
        assert_eq!(e.to_string(), "t.gro: no atoms: the file is empty", "empty");
    }
}
