//! The categories and `_atom_site` columns the reader knows, by their tags.

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
