//! The compact result of a read: one array per attribute (structure of arrays), 15 bytes an
//! atom plus the file's per-atom fields ([`AtomFields`], 18 bytes an atom read), and the
//! builder the readers fill it through.

use glam::Vec3;

use crate::assembly::Assembly;
use crate::bounds::{self, Bounds, Sphere};
use crate::element::Element;
use crate::error::{Error, Warning};
use crate::fields::AtomFields;
use crate::options::{Format, Limits};
use crate::origin::{Atom, Origin};

pub(crate) use crate::builder::Builder;

/// The atoms of a structure file, in the crate's left-handed space, Ångström.
///
/// Atom `i` is at `positions()[i]`, is an `elements()[i]` and belongs to chain
/// `chain_ids()[chains()[i]]`; [`Molecule::atom`] gives all the file says of it. A position
/// is the file's (x, y, z) as (x, y, −z): see the crate doc for why that keeps the
/// molecule's chirality. Each atom costs 12 + 1 + 2 = 15 bytes, and each atom read from the
/// file [`AtomFields::BYTES_PER_ATOM`] more (an expanded assembly points back to them, 4
/// bytes per atom of its parts); [`Molecule::heap_bytes`] counts what the arrays hold.
#[derive(Clone, Debug)]
pub struct Molecule {
    pub(crate) source: String,
    pub(crate) format: Format,
    pub(crate) positions: Vec<Vec3>,
    pub(crate) elements: Vec<Element>,
    pub(crate) chains: Vec<u16>,
    pub(crate) chain_ids: Vec<String>,
    pub(crate) fields: AtomFields,
    /// The model read (PDB `MODEL` serial, mmCIF `pdbx_PDB_model_num`), when the file
    /// numbers its models.
    pub(crate) model: Option<u32>,
    /// Where each atom comes from among the file's.
    pub(crate) origin: Origin,
    pub(crate) assemblies: Vec<Assembly>,
    pub(crate) applied: Option<usize>,
    pub(crate) warnings: Vec<Warning>,
    pub(crate) warnings_total: usize,
}

impl Molecule {
    /// The file (as named to the read) the atoms came from.
    #[must_use]
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The file's format.
    #[must_use]
    pub fn format(&self) -> Format {
        self.format
    }

    /// The number of atoms.
    #[must_use]
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether there are no atoms (a read never returns such a molecule).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The atoms' centres, Ångström, in the crate's left-handed space.
    #[must_use]
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// The atoms' elements.
    #[must_use]
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// Each atom's chain, an index into [`Molecule::chain_ids`].
    #[must_use]
    pub fn chains(&self) -> &[u16] {
        &self.chains
    }

    /// The chains' ids, in the order first met: PDB column 22 (blank: `""`), mmCIF
    /// `label_asym_id` (`auth_asym_id` when absent); GRO and
    /// XYZ files have one chain, `""`.
    #[must_use]
    pub fn chain_ids(&self) -> &[String] {
        &self.chain_ids
    }

    /// The biological assemblies the file lists (empty for GRO and XYZ).
    #[must_use]
    pub fn assemblies(&self) -> &[Assembly] {
        &self.assemblies
    }

    /// The assembly these atoms are, when one was expanded; `None` for the file's atoms as
    /// they are.
    #[must_use]
    pub fn applied_assembly(&self) -> Option<&Assembly> {
        self.applied.and_then(|i| self.assemblies.get(i))
    }

    /// The warnings kept, at most [`Limits::max_warnings`], in file order.
    #[must_use]
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// How many warnings the read raised, kept or not.
    #[must_use]
    pub fn warnings_total(&self) -> usize {
        self.warnings_total
    }

    /// The bytes the per-atom arrays hold on the heap (their capacities), the figure the
    /// memory budget is about.
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        self.positions.capacity() * size_of::<Vec3>()
            + self.elements.capacity() * size_of::<Element>()
            + self.chains.capacity() * size_of::<u16>()
            + self.fields.heap_bytes()
            + self.origin.heap_bytes()
    }

    /// The per-atom fields of the file's atoms (index them by [`Atom::file_index`]).
    #[must_use]
    pub fn fields(&self) -> &AtomFields {
        &self.fields
    }

    /// The model these atoms are, when the file numbers its models.
    #[must_use]
    pub fn model(&self) -> Option<u32> {
        self.model
    }

    /// All the file says of atom `i`, and where an assembly put it; `None` past the end.
    #[must_use]
    pub fn atom(&self, i: usize) -> Option<Atom<'_>> {
        self.atom_at(i, *self.positions.get(i)?)
    }

    /// [`Molecule::atom`] for atom `i` at `position` (the crate's space).
    fn atom_at(&self, i: usize, position: Vec3) -> Option<Atom<'_>> {
        let (file_index, operator) = self.origin.of(i)?;
        let operator = operator.and_then(|(part, op)| {
            self.applied_assembly().and_then(|a| a.parts.get(part)).and_then(|p| p.operators.get(op))
        });
        Some(Atom {
            index: i,
            file_index,
            element: *self.elements.get(i)?,
            chain: self.chain_ids.get(usize::from(self.chains[i])).map_or("", String::as_str),
            name: self.fields.name(file_index),
            residue_name: self.fields.residue_name(file_index),
            residue_number: self.fields.residue_number(file_index),
            insertion_code: self.fields.insertion_code(file_index),
            b_factor: self.fields.b_factor(file_index),
            occupancy: self.fields.occupancy(file_index),
            hetero: self.fields.is_hetero(file_index),
            model: self.model,
            file_position: [position.x, position.y, -position.z],
            operator: operator.map(|o| o.id.as_str()),
        })
    }

    /// The positions, and the rest without them ([`AtomRecords`]): for a scene, which keeps
    /// the atoms' positions placed and reads the rest to colour and pick.
    #[must_use]
    pub fn into_parts(mut self) -> (Vec<Vec3>, AtomRecords) {
        let positions = std::mem::take(&mut self.positions);
        (positions, AtomRecords(self))
    }

    /// The box around every atom's sphere, radius = element radius × `radius_scale`; `None`
    /// when there are no atoms.
    #[must_use]
    pub fn bounds(&self, radius_scale: f32) -> Option<Bounds> {
        bounds::bounds(&self.positions, &self.elements, radius_scale)
    }

    /// A sphere around every atom's sphere (centred on the box's centre); `None` when there
    /// are no atoms.
    #[must_use]
    pub fn bounding_sphere(&self, radius_scale: f32) -> Option<Sphere> {
        bounds::bounding_sphere(&self.positions, &self.elements, radius_scale)
    }

    /// The positions and elements, giving up the rest.
    #[must_use]
    pub fn into_arrays(self) -> (Vec<Vec3>, Vec<Element>) {
        (self.positions, self.elements)
    }

    /// The number of atoms assembly `index` has, without building it; `None` when there is
    /// no such assembly.
    #[must_use]
    pub fn assembly_len(&self, index: usize) -> Option<u64> {
        let assembly = self.assemblies.get(index)?;
        let per_chain = self.atoms_per_chain();
        let total = assembly
            .parts
            .iter()
            .map(|part| {
                let atoms: u64 =
                    self.chain_mask(&part.chains).iter().zip(&per_chain).filter(|(on, _)| **on).map(|(_, n)| n).sum();
                atoms * part.operators.len() as u64
            })
            .sum();
        Some(total)
    }

    fn atoms_per_chain(&self) -> Vec<u64> {
        let mut counts = vec![0_u64; self.chain_ids.len()];
        for &chain in &self.chains {
            if let Some(n) = counts.get_mut(usize::from(chain)) {
                *n += 1;
            }
        }
        counts
    }

    fn chain_mask(&self, chains: &[String]) -> Vec<bool> {
        self.chain_ids.iter().map(|id| chains.iter().any(|c| c == id)).collect()
    }

    /// The molecule that assembly `index` makes: every part's operators applied to its
    /// chains, written straight into new compact arrays (part by part, operator by operator,
    /// atoms in file order). Warnings and assemblies are carried over.
    ///
    /// # Errors
    /// [`Error::TooManyAtoms`] when the assembly would exceed `limits.max_atoms` (checked
    /// before allocating); [`Error::NoAtoms`] when its chains hold none;
    /// [`Error::Malformed`] when there is no assembly `index`.
    pub fn expand_assembly(&self, index: usize, limits: &Limits) -> Result<Molecule, Error> {
        let (Some(assembly), Some(total)) = (self.assemblies.get(index), self.assembly_len(index)) else {
            return Err(Error::Malformed {
                file: self.source.clone(),
                line: 0,
                why: format!("no assembly {index}: the file lists {}", self.assemblies.len()),
            });
        };
        if total > limits.max_atoms as u64 {
            return Err(Error::TooManyAtoms {
                file: self.source.clone(),
                count: total,
                what: " after assembly expansion",
                limit: limits.max_atoms,
            });
        }
        if total == 0 {
            return Err(Error::NoAtoms { file: self.source.clone(), why: "the assembly's chains hold none" });
        }
        let total = total as usize;
        let mut positions = Vec::with_capacity(total);
        let mut elements = Vec::with_capacity(total);
        let mut chains = Vec::with_capacity(total);
        let mut origin = Origin::assembly();
        for part in &assembly.parts {
            let mask = self.chain_mask(&part.chains);
            let selected = |i: &usize| mask.get(usize::from(self.chains[*i])).copied().unwrap_or(false);
            let indices: Vec<usize> = (0..self.len()).filter(selected).collect();
            let source: Vec<Vec3> = indices.iter().map(|&i| self.positions[i]).collect();
            let source_elements: Vec<Element> = indices.iter().map(|&i| self.elements[i]).collect();
            let source_chains: Vec<u16> = indices.iter().map(|&i| self.chains[i]).collect();
            let file_indices = indices.iter().map(|&i| self.origin.of(i).map_or(0, |(file, _)| file));
            origin.push_part(file_indices, part.operators.len());
            for operator in &part.operators {
                positions.extend(source.iter().map(|&p| operator.apply(p)));
                elements.extend_from_slice(&source_elements);
                chains.extend_from_slice(&source_chains);
            }
        }
        Ok(Molecule {
            source: self.source.clone(),
            format: self.format,
            positions,
            elements,
            chains,
            chain_ids: self.chain_ids.clone(),
            fields: self.fields.clone(),
            model: self.model,
            origin,
            assemblies: self.assemblies.clone(),
            applied: Some(index),
            warnings: self.warnings.clone(),
            warnings_total: self.warnings_total,
        })
    }

    /// Adds a warning to a finished molecule, under the same cap the read used.
    pub(crate) fn warn(&mut self, line: u64, message: String, max_warnings: usize) {
        self.warnings_total += 1;
        if self.warnings.len() < max_warnings {
            self.warnings.push(Warning { file: self.source.clone(), line, message });
        }
    }
}

/// What a [`Molecule`] knows of its atoms besides their positions: elements, chains, the
/// file's fields and where an assembly put each atom ([`Molecule::into_parts`]). It costs 1 +
/// 2 bytes an atom, plus the file's fields.
#[derive(Clone, Debug)]
pub struct AtomRecords(pub(crate) Molecule);

impl AtomRecords {
    /// The number of atoms.
    #[must_use]
    pub fn len(&self) -> usize {
        self.0.elements.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.elements.is_empty()
    }

    /// All the file says of atom `i`, which is at `position` (the crate's space, as
    /// [`Molecule::positions`] had it); `None` past the end.
    #[must_use]
    pub fn atom(&self, i: usize, position: Vec3) -> Option<Atom<'_>> {
        self.0.atom_at(i, position)
    }

    /// The atoms' elements.
    #[must_use]
    pub fn elements(&self) -> &[Element] {
        &self.0.elements
    }

    /// Each atom's chain, an index into [`AtomRecords::chain_ids`].
    #[must_use]
    pub fn chains(&self) -> &[u16] {
        &self.0.chains
    }

    /// The chains' ids ([`Molecule::chain_ids`]).
    #[must_use]
    pub fn chain_ids(&self) -> &[String] {
        &self.0.chain_ids
    }

    /// Atom `i`'s index among the file's atoms ([`Atom::file_index`]), to read
    /// [`AtomRecords::fields`] by; `None` past the end.
    #[must_use]
    pub fn file_index(&self, i: usize) -> Option<usize> {
        self.0.origin.of(i).map(|(file, _)| file).filter(|_| i < self.len())
    }

    /// The per-atom fields of the file's atoms.
    #[must_use]
    pub fn fields(&self) -> &AtomFields {
        &self.0.fields
    }

    /// The heap bytes held (no positions).
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        self.0.heap_bytes()
    }
}

#[cfg(test)]
mod tests {
    use glam::Mat3;

    use super::*;
    use crate::assembly::{AssemblyPart, Operator};
    use crate::fields::FieldsIn;

    fn two_chains() -> Molecule {
        let mut b = Builder::new("t.pdb", &Limits::default());
        let a = b.chain(b"A", 1).unwrap();
        b.push([1.0, 2.0, 3.0], Element::C, a, &FieldsIn::NONE, 1).unwrap();
        let c = b.chain(b"B", 2).unwrap();
        b.push([0.0, 0.0, 1.0], Element::O, c, &FieldsIn::NONE, 2).unwrap();
        let a_again = b.chain(b"A", 3).unwrap();
        assert_eq!(a_again, a, "a chain keeps its index");
        b.push([4.0, 5.0, 6.0], Element::N, a, &FieldsIn::NONE, 3).unwrap();
        let shift = |id: &str, x: f32| Operator {
            id: id.into(),
            rotation: Mat3::IDENTITY,
            translation: Vec3::new(x, 0.0, 0.0),
        };
        let assembly = Assembly {
            id: "1".into(),
            parts: vec![
                AssemblyPart { chains: vec!["A".into()], operators: vec![shift("1", 0.0), shift("2", 10.0)] },
                AssemblyPart { chains: vec!["B".into(), "Z".into()], operators: vec![shift("3", 100.0)] },
            ],
        };
        b.finish(Format::Pdb, vec![assembly], "none").unwrap()
    }

    #[test]
    fn atoms_are_stored_at_x_y_minus_z() {
        let m = two_chains();
        assert_eq!(m.positions()[0], Vec3::new(1.0, 2.0, -3.0), "file (1, 2, 3)");
        assert_eq!(m.chain_ids(), ["A", "B"], "chains in order met");
        assert_eq!(m.chains(), [0, 1, 0], "chain per atom");
        // The name tables hold one empty name each.
        let fields = 3 * AtomFields::BYTES_PER_ATOM + 2 * size_of::<Box<str>>();
        assert_eq!(m.heap_bytes(), 3 * 15 + fields, "15 bytes an atom once shrunk, and the fields");
        assert_eq!(m.fields().len(), 3, "a field row per atom");
    }

    #[test]
    fn an_assembly_copies_each_part_once_per_operator() {
        let m = two_chains();
        assert_eq!(m.assembly_len(0), Some(2 * 2 + 1), "two A atoms twice, one B atom once");
        assert_eq!(m.assembly_len(1), None, "no second assembly");
        let big = m.expand_assembly(0, &Limits::default()).unwrap();
        let xs: Vec<f32> = big.positions().iter().map(|p| p.x).collect();
        assert_eq!(xs, [1.0, 4.0, 11.0, 14.0, 100.0], "part by part, operator by operator");
        assert_eq!(big.elements(), [Element::C, Element::N, Element::C, Element::N, Element::O], "elements follow");
        assert_eq!(big.chains(), [0, 0, 0, 0, 1], "chains follow");
        assert_eq!(big.applied_assembly().map(|a| a.id.as_str()), Some("1"), "says which");
        let copy = big.atom(3).unwrap();
        assert_eq!((copy.file_index, copy.operator, copy.chain), (2, Some("2"), "A"), "file atom 2 moved by 2");
        assert_eq!(copy.file_position, [14.0, 5.0, 6.0], "the file's coordinates after the operator");
        assert_eq!(big.atom(4).map(|a| (a.file_index, a.operator)), Some((1, Some("3"))), "part B");
        assert!(big.atom(5).is_none(), "past the end");
        let (fields, origin) = (big.fields().heap_bytes(), big.origin.heap_bytes());
        assert_eq!(fields, 3 * AtomFields::BYTES_PER_ATOM + 2 * size_of::<Box<str>>(), "the file's fields, not copied");
        assert_eq!(big.heap_bytes() - fields - origin, 5 * 15, "exact allocation");
    }

    #[test]
    fn records_without_positions_give_the_same_atoms() {
        let big = two_chains().expand_assembly(0, &Limits::default()).unwrap();
        let atoms: Vec<_> = (0..big.len()).map(|i| format!("{:?}", big.atom(i))).collect();
        let (copy, bytes) = (big.clone(), big.clone().heap_bytes());
        let (positions, records) = copy.into_parts();
        assert_eq!(records.len(), 5, "every atom");
        for (i, want) in atoms.iter().enumerate() {
            assert_eq!(&format!("{:?}", records.atom(i, positions[i])), want, "atom {i}");
        }
        assert_eq!((records.file_index(3), records.file_index(5)), (Some(2), None), "file indices");
        assert_eq!(records.heap_bytes(), bytes - 5 * size_of::<Vec3>(), "no positions");
    }

    #[test]
    fn an_assembly_above_the_atom_limit_is_refused_before_allocating() {
        let limits = Limits { max_atoms: 4, ..Limits::default() };
        let e = two_chains().expand_assembly(0, &limits).unwrap_err();
        assert!(matches!(e, Error::TooManyAtoms { count: 5, limit: 4, .. }), "{e}");
        assert_eq!(e.to_string(), "t.pdb: 5 atoms after assembly expansion, above the limit of 4", "message");
    }

    #[test]
    fn the_atom_limit_holds_while_reading() {
        let mut b = Builder::new("t.xyz", &Limits { max_atoms: 1, ..Limits::default() });
        b.push([0.0; 3], Element::C, 0, &FieldsIn::NONE, 1).unwrap();
        let e = b.push([0.0; 3], Element::C, 0, &FieldsIn::NONE, 1).unwrap_err();
        assert!(matches!(e, Error::TooManyAtoms { count: 2, limit: 1, .. }), "{e}");
    }

    #[test]
    fn warnings_are_capped_but_counted() {
        let mut b = Builder::new("t.pdb", &Limits { max_warnings: 2, ..Limits::default() });
        for line in 1..=5 {
            b.warn(line, || format!("number {line}"));
        }
        b.push([0.0; 3], Element::C, 0, &FieldsIn::NONE, 1).unwrap();
        let m = b.finish(Format::Pdb, Vec::new(), "none").unwrap();
        assert_eq!(m.warnings().len(), 2, "capped");
        assert_eq!(m.warnings_total(), 5, "counted");
        assert_eq!(m.warnings()[1].to_string(), "t.pdb:2: number 2", "file:line: message");
    }
}
