//! Where each atom of a molecule comes from among the file's atoms, and the view of one atom
//! that puts together all the file says of it ([`Atom`]). An expanded assembly keeps, per
//! part, the file indices of the part's atoms once, however many operators copy them.

use crate::element::Element;

/// All a structure file says of one atom of a [`crate::Molecule`], as
/// [`crate::Molecule::atom`] gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Atom<'a> {
    /// Its index in the molecule (the sphere's, for a structure in a scene).
    pub index: usize,
    /// Its index among the atoms read from the file (the same as `index` unless an assembly
    /// was expanded).
    pub file_index: usize,
    /// Its element.
    pub element: Element,
    /// Its chain's id.
    pub chain: &'a str,
    /// The atom name (`"CA"`), `""` when the file has none.
    pub name: &'a str,
    /// The residue name (`"GLY"`), `""` when the file has none.
    pub residue_name: &'a str,
    /// The residue number, when the file gives one.
    pub residue_number: Option<i32>,
    /// The insertion code, when not blank.
    pub insertion_code: Option<char>,
    /// The B-factor, Å² (AlphaFold's pLDDT in its files), when the file gives one.
    pub b_factor: Option<f32>,
    /// The occupancy, when the file gives one.
    pub occupancy: Option<f32>,
    /// Whether it is a `HETATM`.
    pub hetero: bool,
    /// The model read, when the file numbers its models.
    pub model: Option<u32>,
    /// Its coordinates as the file writes them (right-handed x, y, z, Ångström), after the
    /// assembly's operator when one was applied.
    pub file_position: [f32; 3],
    /// The id of the assembly operator that placed this copy, when an assembly was expanded.
    pub operator: Option<&'a str>,
}

/// Where a molecule's atoms come from.
#[derive(Clone, Debug)]
pub(crate) enum Origin {
    /// Atom `i` is the file's atom `i`.
    File,
    /// The atoms are the parts of an assembly, each part's atoms once per operator.
    Assembly(Vec<Part>),
}

/// One part of an expanded assembly: its first atom, the file indices of its atoms, and how
/// many operators copy them.
#[derive(Clone, Debug)]
pub(crate) struct Part {
    start: usize,
    file_indices: Vec<u32>,
    operators: usize,
}

impl Origin {
    /// An assembly with no part yet.
    pub(crate) fn assembly() -> Self {
        Self::Assembly(Vec::new())
    }

    /// Adds the next part: the file indices of its atoms, copied by `operators` operators.
    pub(crate) fn push_part(&mut self, file_indices: impl Iterator<Item = usize>, operators: usize) {
        if let Self::Assembly(parts) = self {
            let start = parts.last().map_or(0, |p| p.start + p.file_indices.len() * p.operators);
            let file_indices = file_indices.map(|i| i as u32).collect();
            parts.push(Part { start, file_indices, operators });
        }
    }

    /// Atom `i`'s file index, and for an assembly (part, operator) indices; `None` past the
    /// assembly's end (a file molecule's end is its caller's to check).
    pub(crate) fn of(&self, i: usize) -> Option<(usize, Option<(usize, usize)>)> {
        match self {
            Self::File => Some((i, None)),
            Self::Assembly(parts) => {
                let k = parts.partition_point(|p| p.start <= i).checked_sub(1)?;
                let part = &parts[k];
                let n = part.file_indices.len();
                let offset = i - part.start;
                if n == 0 || offset >= n * part.operators {
                    return None;
                }
                Some((part.file_indices[offset % n] as usize, Some((k, offset / n))))
            }
        }
    }

    /// Calls `f(i, file)` for each atom `i` below `len` with its file index, in order, at a
    /// step's cost each (an assembly walks its parts; no search per atom).
    pub(crate) fn for_each(&self, len: usize, mut f: impl FnMut(usize, usize)) {
        match self {
            Self::File => (0..len).for_each(|i| f(i, i)),
            Self::Assembly(parts) => {
                let mut i = 0;
                for p in parts {
                    for _ in 0..p.operators {
                        for &file in &p.file_indices {
                            if i == len {
                                return;
                            }
                            f(i, file as usize);
                            i += 1;
                        }
                    }
                }
            }
        }
    }

    /// The heap bytes it holds.
    pub(crate) fn heap_bytes(&self) -> usize {
        match self {
            Self::File => 0,
            Self::Assembly(parts) => {
                parts.iter().map(|p| p.file_indices.capacity() * 4).sum::<usize>()
                    + parts.capacity() * size_of::<Part>()
            }
        }
    }
}

impl crate::AtomRecords {
    /// Calls `f(i, file)` for every atom `i` in order with its file index
    /// ([`crate::AtomRecords::file_index`]), at a step's cost each: what a pass over millions
    /// of an assembly's atoms uses.
    pub fn for_each_file_index(&self, f: impl FnMut(usize, usize)) {
        self.0.origin.for_each(self.len(), f);
    }
}
