//! The builder the readers fill a [`Molecule`] through, atom by atom.

use std::collections::HashMap;

use glam::Vec3;

use crate::assembly::Assembly;
use crate::element::Element;
use crate::error::{Error, Warning};
use crate::fields::{AtomFields, FieldsIn};
use crate::molecule::Molecule;
use crate::options::{Format, Limits};
use crate::origin::Origin;

/// Collects atoms while a reader walks a file: enforces the atom limit on every atom, gives
/// chains small indices, and keeps the first warnings.
pub(crate) struct Builder<'a> {
    file: &'a str,
    limits: Limits,
    positions: Vec<Vec3>,
    elements: Vec<Element>,
    chains: Vec<u16>,
    chain_ids: Vec<String>,
    chain_lookup: HashMap<Box<[u8]>, u16>,
    last_chain: Option<(Box<[u8]>, u16)>,
    fields: AtomFields,
    model: Option<u32>,
    warnings: Vec<Warning>,
    warnings_total: usize,
}

impl<'a> Builder<'a> {
    pub(crate) fn new(file: &'a str, limits: &Limits) -> Self {
        Self {
            file,
            limits: *limits,
            positions: Vec::new(),
            elements: Vec::new(),
            chains: Vec::new(),
            chain_ids: Vec::new(),
            chain_lookup: HashMap::new(),
            last_chain: None,
            fields: AtomFields::default(),
            model: None,
            warnings: Vec::new(),
            warnings_total: 0,
        }
    }

    /// Reserves room for `atoms` more, never more than the atom limit nor `cap_hint` (a count
    /// read from a file is not trusted with memory).
    pub(crate) fn reserve(&mut self, atoms: usize, cap_hint: usize) {
        let n = atoms.min(self.limits.max_atoms).min(cap_hint);
        self.positions.reserve(n);
        self.elements.reserve(n);
        self.chains.reserve(n);
        self.fields.reserve(n);
    }

    /// Says which model the atoms are, the file's number for it, when `first` (the model
    /// read) and the number could be read.
    pub(crate) fn set_model_if(&mut self, first: bool, number: Option<u64>) {
        if let (true, Some(number)) = (first, number) {
            self.model = Some(u32::try_from(number).unwrap_or(u32::MAX));
        }
    }

    /// The index of chain `id`, made on first sight.
    pub(crate) fn chain(&mut self, id: &[u8], line: u64) -> Result<u16, Error> {
        if let Some((last, index)) = &self.last_chain {
            if **last == *id {
                return Ok(*index);
            }
        }
        let index = if let Some(&index) = self.chain_lookup.get(id) {
            index
        } else {
            let Ok(index) = u16::try_from(self.chain_ids.len()) else {
                return Err(Error::Malformed {
                    file: self.file.to_owned(),
                    line,
                    why: format!("more than {} chains", u16::MAX),
                });
            };
            self.chain_ids.push(String::from_utf8_lossy(id).into_owned());
            self.chain_lookup.insert(id.into(), index);
            index
        };
        self.last_chain = Some((id.into(), index));
        Ok(index)
    }

    /// Adds an atom at file coordinates (x, y, z), Ångström (it is stored at (x, y, −z)), with
    /// what the file says of it on `line`.
    #[inline]
    pub(crate) fn push(
        &mut self,
        file_xyz: [f32; 3],
        element: Element,
        chain: u16,
        fields: &FieldsIn<'_>,
        line: u64,
    ) -> Result<(), Error> {
        if self.positions.len() >= self.limits.max_atoms {
            return Err(Error::TooManyAtoms {
                file: self.file.to_owned(),
                count: self.positions.len() as u64 + 1,
                what: "",
                limit: self.limits.max_atoms,
            });
        }
        self.fields.push(fields, self.file, line)?;
        let [x, y, z] = file_xyz;
        self.positions.push(Vec3::new(x, y, -z));
        self.elements.push(element);
        self.chains.push(chain);
        Ok(())
    }

    /// Keeps a warning about `line` (0: the whole file) while under the cap; `message` is
    /// only formatted then.
    pub(crate) fn warn(&mut self, line: u64, message: impl FnOnce() -> String) {
        self.warnings_total += 1;
        if self.warnings.len() < self.limits.max_warnings {
            self.warnings.push(Warning { file: self.file.to_owned(), line, message: message() });
        }
    }

    /// The finished molecule; [`Error::NoAtoms`] when there is none.
    pub(crate) fn finish(
        mut self,
        format: Format,
        assemblies: Vec<Assembly>,
        none_why: &'static str,
    ) -> Result<Molecule, Error> {
        if self.positions.is_empty() {
            return Err(Error::NoAtoms { file: self.file.to_owned(), why: none_why });
        }
        // Growth by doubling leaves up to half the capacity unused: give it back.
        self.positions.shrink_to_fit();
        self.elements.shrink_to_fit();
        self.chains.shrink_to_fit();
        self.fields.shrink();
        Ok(Molecule {
            source: self.file.to_owned(),
            format,
            positions: self.positions,
            elements: self.elements,
            chains: self.chains,
            chain_ids: self.chain_ids,
            fields: self.fields,
            model: self.model,
            origin: Origin::File,
            assemblies,
            applied: None,
            warnings: self.warnings,
            warnings_total: self.warnings_total,
        })
    }
}
