//! Reads molecular structure files into compact atom arrays for the tracer: `.pdb`, `.cif` /
//! `.mmcif`, `.gro` and `.xyz`, each optionally gzipped.
//!
//! This crate owns file reading, elements (colours, radii), biological assemblies and the
//! bounds of a set of atoms. It depends on no other crate of the workspace. Why it reads PDB
//! and mmCIF itself rather than with `pdbtbx`, and what an atom costs:
//! `docs/design/molecule-files.md`.
//!
//! ```no_run
//! let options = molecule::ReadOptions { assembly: true, ..molecule::ReadOptions::default() };
//! let virus = molecule::read("2btv.pdb.gz", &options)?;
//! for (position, element) in virus.positions().iter().zip(virus.elements()) {
//!     let (radius, colour) = (element.radius(), element.linear_colour());
//!     # let _ = (position, radius, colour);
//! }
//! # Ok::<(), molecule::Error>(())
//! ```
//!
//! # Space and units
//!
//! Positions are in Ångström, in the project's left-handed space (+x right, +y up, +z into
//! the scene): an atom at file (x, y, z) is stored at (x, y, −z), which keeps the molecule's
//! chirality (the design doc says why). Assembly operators are mapped the same way (see
//! [`Operator::from_file_rows`]). GRO nanometres are scaled by 10. A [`Molecule`] is a
//! structure of arrays, 15 bytes an atom.
//!
//! # Bounded reading
//!
//! A read never blocks, panics or takes unbounded memory on bad input:
//!
//! - a path that is not a regular file (a directory, `/dev/zero`, a FIFO, a socket) is
//!   refused from its metadata, before it is opened;
//! - [`Limits`]: 512 MiB on disk, 2 GiB decompressed (enforced while decompressing: a gzip
//!   bomb stops there), 1 MiB a line, 16 Mi atoms in the file or after assembly expansion,
//!   100 warnings kept;
//! - a gzip stream is recognised by its magic bytes, whatever the name; a `.gz` name on
//!   anything else is an error;
//! - truncated or malformed files (non-numeric or non-finite coordinates, short records,
//!   counts that do not match, loops cut short, empty files) are errors naming the file, the
//!   1-based line and the field: `1tii.pdb:1234: ATOM x = "12.3a4": not a number`.
//!
//! Things read with a documented fallback (an unknown element, skipped models or alternate
//! locations, an assembly asked for and absent) are [`Warning`]s in the result, naming file
//! and line; the library prints nothing.
//!
//! # Sources
//!
//! - PDB: wwPDB, "Atomic Coordinate Entry Format Version 3.3" (2011): `ATOM`/`HETATM`
//!   columns, the atom-name alignment rule, `REMARK 350` BIOMT records.
//! - mmCIF: the PDBx/mmCIF dictionary (wwPDB, mmcif.wwpdb.org), categories `atom_site`,
//!   `pdbx_struct_oper_list`, `pdbx_struct_assembly_gen`; CIF syntax per Hall, Allen &
//!   Brown, Acta Cryst. A47 (1991) 655–685 (CIF 1.1).
//! - GRO: the GROMACS reference manual, "File formats: gro".
//! - Colours: Jmol's CPK colours, <https://jmol.sourceforge.net/jscolors/>.
//! - Radii: A. Bondi, J. Phys. Chem. 68 (1964) 441–451; S. Alvarez, Dalton Trans. 42 (2013)
//!   8617–8636 where Bondi has none.

mod assembly;
mod bounds;
mod builder;
mod element;
mod error;
mod field;
mod fields;
mod gro;
mod input;
mod mmcif;
mod molecule;
mod options;
mod origin;
mod pdb;
mod xyz;

use std::io::BufRead;
use std::path::Path;

pub use assembly::{Assembly, AssemblyPart, Operator};
pub use bounds::{bounding_sphere, bounds, enclosing_sphere, sphere_bounds, Bounds, Sphere};
pub use element::{srgb_to_linear, Element, RadiusSource, FALLBACK_RADIUS, UNKNOWN_SRGB};
pub use error::{Error, Warning, MAX_VALUE_CHARS};
pub use fields::AtomFields;
pub use molecule::{AtomRecords, Molecule};
pub use options::{Format, Limits, ReadOptions};
pub use origin::Atom;

/// Reads the structure file at `path`: its format from [`ReadOptions::format`] or the name,
/// gzip from the magic bytes, the assembly when [`ReadOptions::assembly`] asks.
///
/// # Errors
/// Every [`Error`] variant; see the crate doc's "Bounded reading".
pub fn read(path: impl AsRef<Path>, options: &ReadOptions) -> Result<Molecule, Error> {
    let path = path.as_ref();
    let file = path.display().to_string();
    let format = format_of(path, &file, options)?;
    let (raw, _) = input::open_file(path, &file, &options.limits)?;
    read_stream(&file, raw, format, options)
}

/// Reads a structure from bytes already in memory (plain or gzip), named `name` in messages;
/// the format from [`ReadOptions::format`] or `name`.
///
/// # Errors
/// As [`read`], less the file-system ones.
pub fn parse(bytes: &[u8], name: &str, options: &ReadOptions) -> Result<Molecule, Error> {
    let format = format_of(Path::new(name), name, options)?;
    if bytes.len() as u64 > options.limits.max_file_bytes {
        return Err(Error::FileTooLarge {
            file: name.to_owned(),
            size: bytes.len() as u64,
            limit: options.limits.max_file_bytes,
        });
    }
    read_stream(name, Box::new(bytes), format, options)
}

fn format_of(path: &Path, file: &str, options: &ReadOptions) -> Result<Format, Error> {
    options.format.or_else(|| Format::from_path(path)).ok_or_else(|| Error::UnknownFormat { file: file.to_owned() })
}

fn read_stream<'a>(
    file: &'a str,
    raw: Box<dyn BufRead + 'a>,
    format: Format,
    options: &ReadOptions,
) -> Result<Molecule, Error> {
    let limits = &options.limits;
    let mut lines = input::Lines::new(file, raw, limits)?;
    let molecule = match format {
        Format::Pdb => pdb::read(&mut lines, limits, options.assembly)?,
        Format::Mmcif => mmcif::read(&mut lines, limits, options.assembly)?,
        Format::Gro => gro::read(&mut lines, limits)?,
        Format::Xyz => xyz::read(&mut lines, limits)?,
    };
    if !options.assembly {
        return Ok(molecule);
    }
    if molecule.assemblies().is_empty() {
        let mut molecule = molecule;
        molecule.warn(
            0,
            "an assembly was asked for but the file lists none: its atoms as they are".to_owned(),
            limits.max_warnings,
        );
        return Ok(molecule);
    }
    molecule.expand_assembly(0, limits)
}
