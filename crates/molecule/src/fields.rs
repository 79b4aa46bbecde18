//! What a structure file says of each atom besides its position, element and chain: the atom
//! and residue names, the residue number and insertion code, the B-factor and occupancy, and
//! whether it is a `HETATM` — the columns of the wwPDB "Atomic Coordinate Entry Format
//! Version 3.3" `ATOM` record, the mmCIF `_atom_site` items that carry the same, and the GRO
//! manual's residue and atom names.
//!
//! Kept as columns of the file's atoms, names interned: 2 + 2 + 4 + 1 + 4 + 4 + 1 = 18 bytes
//! an atom read ([`AtomFields::BYTES_PER_ATOM`]). An expanded assembly does not copy them: its
//! atoms point back to the file's ([`crate::Molecule::atom`]).

use std::collections::HashMap;

use crate::error::Error;

/// A residue number no file gave (XYZ files, or a blank column).
const NO_NUMBER: i32 = i32::MIN;

/// What a reader passes for one atom, as the file spells it (bytes, surrounding blanks
/// trimmed here).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FieldsIn<'t> {
    pub(crate) name: &'t [u8],
    pub(crate) residue: &'t [u8],
    pub(crate) residue_number: Option<i32>,
    /// The insertion code, `None` when blank.
    pub(crate) insertion_code: Option<u8>,
    /// The B-factor (temperature factor, Å²), `None` when the file gives none.
    pub(crate) b_factor: Option<f32>,
    pub(crate) occupancy: Option<f32>,
    pub(crate) hetero: bool,
}

impl FieldsIn<'_> {
    /// An atom the file names nothing of (XYZ).
    pub(crate) const NONE: FieldsIn<'static> = FieldsIn {
        name: b"",
        residue: b"",
        residue_number: None,
        insertion_code: None,
        b_factor: None,
        occupancy: None,
        hetero: false,
    };
}

/// Short strings given small indices in the order first met.
#[derive(Clone, Debug, Default)]
struct Names {
    table: Vec<Box<str>>,
    lookup: HashMap<Box<[u8]>, u16>,
}

impl Names {
    /// The index of `name`, made on first sight; `None` past 65,536 distinct names.
    fn index(&mut self, name: &[u8]) -> Option<u16> {
        if let Some(&index) = self.lookup.get(name) {
            return Some(index);
        }
        let index = u16::try_from(self.table.len()).ok()?;
        self.table.push(String::from_utf8_lossy(name).into());
        self.lookup.insert(name.into(), index);
        Some(index)
    }

    fn heap_bytes(&self) -> usize {
        self.table.iter().map(|s| s.len() * 2 + size_of::<Box<str>>()).sum()
    }
}

/// The per-atom fields of a file's atoms, as columns (see the module doc for the bytes).
#[derive(Clone, Debug, Default)]
pub struct AtomFields {
    names: Vec<u16>,
    residues: Vec<u16>,
    residue_numbers: Vec<i32>,
    insertion_codes: Vec<u8>,
    b_factors: Vec<f32>,
    occupancies: Vec<f32>,
    hetero: Vec<bool>,
    name_table: Names,
    residue_table: Names,
}

impl AtomFields {
    /// The bytes the columns hold per atom.
    pub const BYTES_PER_ATOM: usize = 2 + 2 + 4 + 1 + 4 + 4 + 1;

    /// Adds atom `fields`; `file` and `line` name it in the error past 65,536 distinct atom
    /// or residue names.
    pub(crate) fn push(&mut self, fields: &FieldsIn<'_>, file: &str, line: u64) -> Result<(), Error> {
        let too_many = |what: &str| Error::Malformed {
            file: file.to_owned(),
            line,
            why: format!("more than {} distinct {what} names", u32::from(u16::MAX) + 1),
        };
        let name = self.name_table.index(fields.name.trim_ascii()).ok_or_else(|| too_many("atom"))?;
        let residue = self.residue_table.index(fields.residue.trim_ascii()).ok_or_else(|| too_many("residue"))?;
        self.names.push(name);
        self.residues.push(residue);
        self.residue_numbers.push(fields.residue_number.unwrap_or(NO_NUMBER));
        self.insertion_codes.push(fields.insertion_code.unwrap_or(0));
        self.b_factors.push(fields.b_factor.unwrap_or(f32::NAN));
        self.occupancies.push(fields.occupancy.unwrap_or(f32::NAN));
        self.hetero.push(fields.hetero);
        Ok(())
    }

    /// Reserves room for `atoms` more.
    pub(crate) fn reserve(&mut self, atoms: usize) {
        self.names.reserve(atoms);
        self.residues.reserve(atoms);
        self.residue_numbers.reserve(atoms);
        self.insertion_codes.reserve(atoms);
        self.b_factors.reserve(atoms);
        self.occupancies.reserve(atoms);
        self.hetero.reserve(atoms);
    }

    /// Gives back unused capacity once reading is done; the name lookups are dropped.
    pub(crate) fn shrink(&mut self) {
        self.names.shrink_to_fit();
        self.residues.shrink_to_fit();
        self.residue_numbers.shrink_to_fit();
        self.insertion_codes.shrink_to_fit();
        self.b_factors.shrink_to_fit();
        self.occupancies.shrink_to_fit();
        self.hetero.shrink_to_fit();
        self.name_table.lookup = HashMap::new();
        self.residue_table.lookup = HashMap::new();
    }

    /// The number of atoms.
    #[must_use]
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// Atom `i`'s name (PDB columns 13–16 trimmed, mmCIF `label_atom_id`, GRO columns
    /// 11–15; `""` when the file has none).
    #[must_use]
    pub fn name(&self, i: usize) -> &str {
        &self.name_table.table[usize::from(self.names[i])]
    }

    /// Atom `i`'s residue name (PDB columns 18–20, mmCIF `label_comp_id`, GRO columns 6–10).
    #[must_use]
    pub fn residue_name(&self, i: usize) -> &str {
        &self.residue_table.table[usize::from(self.residues[i])]
    }

    /// Atom `i`'s residue number (PDB columns 23–26, mmCIF `auth_seq_id` else
    /// `label_seq_id`, GRO columns 1–5), `None` when the file gives none.
    #[must_use]
    pub fn residue_number(&self, i: usize) -> Option<i32> {
        Some(self.residue_numbers[i]).filter(|&n| n != NO_NUMBER)
    }

    /// Atom `i`'s insertion code (PDB column 27, mmCIF `pdbx_PDB_ins_code`), `None` when
    /// blank.
    #[must_use]
    pub fn insertion_code(&self, i: usize) -> Option<char> {
        Some(self.insertion_codes[i]).filter(|&c| c != 0).map(char::from)
    }

    /// Atom `i`'s B-factor, Å² (PDB columns 61–66, mmCIF `B_iso_or_equiv`); AlphaFold
    /// stores its pLDDT here. `None` when the file gives none.
    #[must_use]
    pub fn b_factor(&self, i: usize) -> Option<f32> {
        Some(self.b_factors[i]).filter(|b| !b.is_nan())
    }

    /// Atom `i`'s occupancy (PDB columns 55–60, mmCIF `occupancy`), `None` when the file
    /// gives none.
    #[must_use]
    pub fn occupancy(&self, i: usize) -> Option<f32> {
        Some(self.occupancies[i]).filter(|o| !o.is_nan())
    }

    /// Whether atom `i` is a `HETATM` (PDB record name, mmCIF `group_PDB`).
    #[must_use]
    pub fn is_hetero(&self, i: usize) -> bool {
        self.hetero[i]
    }

    /// The B-factors' range over the atoms that have one, `None` if none has.
    #[must_use]
    pub fn b_factor_range(&self) -> Option<(f32, f32)> {
        self.b_factors.iter().filter(|b| !b.is_nan()).fold(None, |range, &b| match range {
            None => Some((b, b)),
            Some((lo, hi)) => Some((b.min(lo), b.max(hi))),
        })
    }

    /// The heap bytes the columns and name tables hold.
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        self.names.capacity() * 2
            + self.residues.capacity() * 2
            + self.residue_numbers.capacity() * 4
            + self.insertion_codes.capacity()
            + self.b_factors.capacity() * 4
            + self.occupancies.capacity() * 4
            + self.hetero.capacity()
            + self.name_table.heap_bytes()
            + self.residue_table.heap_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_interned_and_blanks_are_none() {
        let mut fields = AtomFields::default();
        let ca = FieldsIn {
            name: b" CA ",
            residue: b"GLY",
            residue_number: Some(-3),
            insertion_code: Some(b'A'),
            b_factor: Some(12.5),
            occupancy: Some(0.5),
            hetero: false,
        };
        fields.push(&ca, "t.pdb", 1).unwrap();
        fields.push(&FieldsIn { name: b"CA", hetero: true, ..ca }, "t.pdb", 2).unwrap();
        fields.push(&FieldsIn::NONE, "t.xyz", 3).unwrap();
        fields.shrink();
        assert_eq!((fields.name(0), fields.name(1), fields.name(2)), ("CA", "CA", ""), "trimmed, one entry");
        assert_eq!(fields.name_table.table.len(), 2, "CA and the empty name");
        assert_eq!(fields.residue_name(0), "GLY", "residue");
        assert_eq!((fields.residue_number(0), fields.residue_number(2)), (Some(-3), None), "numbers");
        assert_eq!((fields.insertion_code(0), fields.insertion_code(2)), (Some('A'), None), "codes");
        assert_eq!((fields.b_factor(0), fields.b_factor(2)), (Some(12.5), None), "B-factors");
        assert_eq!((fields.occupancy(1), fields.occupancy(2)), (Some(0.5), None), "occupancies");
        assert_eq!((fields.is_hetero(0), fields.is_hetero(1)), (false, true), "HETATM");
        assert_eq!(fields.b_factor_range(), Some((12.5, 12.5)), "the range skips atoms without one");
    }

    #[test]
    fn past_65536_names_is_an_error_naming_the_line() {
        let mut fields = AtomFields::default();
        for k in 0..=u32::from(u16::MAX) {
            let name = k.to_string();
            fields.push(&FieldsIn { name: name.as_bytes(), ..FieldsIn::NONE }, "big.pdb", 1).unwrap();
        }
        let e = fields.push(&FieldsIn { name: b"one more", ..FieldsIn::NONE }, "big.pdb", 70_000).unwrap_err();
        assert_eq!(e.to_string(), "big.pdb:70000: more than 65536 distinct atom names", "message");
    }
}
