//! The categories and `_atom_site` columns the reader knows, by their tags, and the row of
//! `_atom_site` values they fill.

use crate::field::parse_f32;

use super::tokens::is_null;

/// The categories read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Category {
    AtomSite,
    OperList,
    AssemblyGen,
    Other,
}

impl Category {
    pub(super) fn of(tag: &[u8]) -> (Self, &[u8]) {
        let (category, item) = match tag.iter().position(|&b| b == b'.') {
            Some(dot) => (tag.get(..dot).unwrap_or_default(), tag.get(dot + 1..).unwrap_or_default()),
            None => (tag, &b""[..]),
        };
        let category = if category.eq_ignore_ascii_case(b"_atom_site") {
            Self::AtomSite
        } else if category.eq_ignore_ascii_case(b"_pdbx_struct_oper_list") {
            Self::OperList
        } else if category.eq_ignore_ascii_case(b"_pdbx_struct_assembly_gen") {
            Self::AssemblyGen
        } else {
            Self::Other
        };
        (category, item)
    }
}

/// What an `_atom_site` column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum AtomColumn {
    Skip,
    X,
    Y,
    Z,
    Symbol,
    Name,
    Residue,
    Alt,
    Asym,
    AuthAsym,
    Model,
    Group,
    AuthSeq,
    LabelSeq,
    InsCode,
    BFactor,
    Occupancy,
}

impl AtomColumn {
    pub(super) fn of(item: &[u8]) -> Self {
        const ITEMS: [(&[u8], AtomColumn); 16] = [
            (b"Cartn_x", AtomColumn::X),
            (b"Cartn_y", AtomColumn::Y),
            (b"Cartn_z", AtomColumn::Z),
            (b"type_symbol", AtomColumn::Symbol),
            (b"label_atom_id", AtomColumn::Name),
            (b"label_comp_id", AtomColumn::Residue),
            (b"label_alt_id", AtomColumn::Alt),
            (b"label_asym_id", AtomColumn::Asym),
            (b"auth_asym_id", AtomColumn::AuthAsym),
            (b"pdbx_PDB_model_num", AtomColumn::Model),
            (b"group_PDB", AtomColumn::Group),
            (b"auth_seq_id", AtomColumn::AuthSeq),
            (b"label_seq_id", AtomColumn::LabelSeq),
            (b"pdbx_PDB_ins_code", AtomColumn::InsCode),
            (b"B_iso_or_equiv", AtomColumn::BFactor),
            (b"occupancy", AtomColumn::Occupancy),
        ];
        ITEMS.iter().find(|(name, _)| name.eq_ignore_ascii_case(item)).map_or(Self::Skip, |&(_, column)| column)
    }

    pub(super) fn field(self) -> &'static str {
        match self {
            Self::X => "Cartn_x",
            Self::Y => "Cartn_y",
            _ => "Cartn_z",
        }
    }
}

/// One `_atom_site` row as its values stream past; the buffers are reused row after row.
#[derive(Default)]
pub(super) struct AtomRow {
    pub(super) xyz: [f32; 3],
    /// Which of x, y, z the row has given.
    pub(super) has: [bool; 3],
    pub(super) symbol: Vec<u8>,
    pub(super) name: Vec<u8>,
    pub(super) residue: Vec<u8>,
    pub(super) alt: Vec<u8>,
    pub(super) asym: Vec<u8>,
    pub(super) auth_asym: Vec<u8>,
    pub(super) model: Vec<u8>,
    pub(super) group: Vec<u8>,
    pub(super) auth_seq: Vec<u8>,
    pub(super) label_seq: Vec<u8>,
    pub(super) ins_code: Vec<u8>,
    pub(super) b_factor: Vec<u8>,
    pub(super) occupancy: Vec<u8>,
}

impl AtomRow {
    /// Keeps `value` as column `kind`'s; a coordinate is read as it comes, and why it is not
    /// a number is the error.
    pub(super) fn keep(&mut self, kind: AtomColumn, value: &[u8]) -> Result<(), &'static str> {
        let buffer = match kind {
            AtomColumn::X | AtomColumn::Y | AtomColumn::Z => {
                let axis = match kind {
                    AtomColumn::X => 0,
                    AtomColumn::Y => 1,
                    _ => 2,
                };
                self.has[axis] = true;
                self.xyz[axis] = parse_f32(value)?;
                return Ok(());
            }
            AtomColumn::Symbol => &mut self.symbol,
            AtomColumn::Name => &mut self.name,
            AtomColumn::Residue => &mut self.residue,
            AtomColumn::Alt => &mut self.alt,
            AtomColumn::Asym => &mut self.asym,
            AtomColumn::AuthAsym => &mut self.auth_asym,
            AtomColumn::Model => &mut self.model,
            AtomColumn::Group => &mut self.group,
            AtomColumn::AuthSeq => &mut self.auth_seq,
            AtomColumn::LabelSeq => &mut self.label_seq,
            AtomColumn::InsCode => &mut self.ins_code,
            AtomColumn::BFactor => &mut self.b_factor,
            AtomColumn::Occupancy => &mut self.occupancy,
            AtomColumn::Skip => return Ok(()),
        };
        buffer.clear();
        buffer.extend_from_slice(value);
        Ok(())
    }

    /// Empties the row for the next, keeping its buffers.
    pub(super) fn clear(&mut self) {
        self.has = [false; 3];
        for buffer in [
            &mut self.symbol,
            &mut self.name,
            &mut self.residue,
            &mut self.alt,
            &mut self.asym,
            &mut self.auth_asym,
            &mut self.model,
            &mut self.group,
            &mut self.auth_seq,
            &mut self.label_seq,
            &mut self.ins_code,
            &mut self.b_factor,
            &mut self.occupancy,
        ] {
            buffer.clear();
        }
    }
}

/// A value, or nothing for CIF's null values (`.` and `?`).
pub(super) fn value(v: &[u8]) -> &[u8] {
    if is_null(v) {
        b""
    } else {
        v
    }
}
