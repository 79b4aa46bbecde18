//! Reads molecular structure files into compact atom arrays for the tracer: `.pdb`, `.cif` /
//! `.mmcif`, `.gro` and `.xyz`, each optionally gzipped.
//!
//! This crate owns file reading, elements (colours, radii), biological assemblies and the
//! bounds of a set of atoms. It depends on no other crate of the workspace.
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
//! the scene). Structure files use a right-handed frame; an atom at file (x, y, z) is stored
//! at (x, y, −z). That reflection is what keeps the molecule's chirality: a right-handed
//! frame drawn as left-handed with the coordinates copied as they are would show every
//! molecule as its mirror image (L-amino acids as D, right-handed helices left-handed);
//! negating one axis undoes the change of handedness. Assembly operators are mapped the same
//! way (see [`Operator::from_file_rows`]). GRO nanometres are scaled by 10.
//!
//! # Memory and speed
//!
//! A [`Molecule`] is a structure of arrays: a `Vec3` position (12 bytes), an [`Element`] (1
//! byte) and a chain index (2 bytes) per atom, 15 bytes in all; readers stream the text a
//! line at a time in a reused buffer and keep no per-atom `String`. An assembly is written
//! straight into arrays of its exact size. 2BTV's 60-fold assembly, 2,943,660 atoms, takes
//! 44 MB.
//!
//! # Why our own PDB and mmCIF readers, not `pdbtbx`
//!
//! The issue proposed `pdbtbx` (0.12.0, the current release), the Rust crate made for PDB
//! and mmCIF. `benches/readers.rs` reads the same bytes with both (release build, this
//! project's shared 2-core machine, file already in memory and decompressed; peak heap by a
//! counting allocator):
//!
//! | input | time, ours | time, pdbtbx | peak heap, ours | peak heap, pdbtbx |
//! |---|---|---|---|---|
//! | 1TII, 5,684 atoms | 0.55 ms | 8.9 ms | 0.1 MiB (22 B/atom) | 1.9 MiB (347 B/atom) |
//! | 2BTV, 49,061 atoms | 4.6 ms | 80 ms | 0.9 MiB (20 B/atom) | 15.0 MiB (320 B/atom) |
//! | 2BTV assembly, 2,943,660 atoms | 32 ms | 221 ms | 44.0 MiB (15.7 B/atom) | 50.8 MiB (18.1 B/atom) |
//!
//! Criterion medians of 10 samples; a second run at a busier moment was about 35 % slower for
//! both readers, the ratios unchanged. pdbtbx read 1TII with `only_atomic_coords` (see
//! below); its assembly row is pdbtbx's read, the BIOMT rows parsed from its remarks and
//! the expansion written in the bench, since pdbtbx has none. Its heap there is mostly the
//! same 2.9 M compact atoms (13 bytes each, without chains) plus its 15 MiB hierarchy.
//!
//! pdbtbx builds a full hierarchy (models, chains, residues, conformers, atoms with `String`
//! names, `f64` coordinates, serial numbers, B-factors) that the tracer does not use: it is
//! 15 to 17 times slower, and its structures cost about 320 bytes an atom, more than the
//! whole 200-bytes-per-sphere budget were an assembly held in them; it has no assembly
//! expansion. On malformed input (checked by the bench) it did not panic on the hand-made
//! cases (a non-numeric x, a short `ATOM` line, an empty input, random bytes): its errors
//! show the line with a marker under the columns and the expected type ("not of the right
//! kind (f64)"), not the field's name, nor the file when reading from memory. But it
//! refuses 1TII whole at its most lenient level (8 breaking errors on `SEQADV` and `SSBOND`
//! records that have nothing to do with coordinates), and it panicked on 26 of 2,000 random
//! line mutations of 1TII ("Invalid characters in Conformer creation"), where ours returned
//! an error or a molecule every time.
//! So the crate reads PDB and mmCIF itself, to the specifications below; `pdbtbx` stays
//! only as the bench's comparison (a dev-dependency).
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
pub use bounds::{bounding_sphere, bounds, Bounds, Sphere};
pub use element::{srgb_to_linear, Element, RadiusSource, FALLBACK_RADIUS, UNKNOWN_SRGB};
pub use error::{Error, Warning, MAX_VALUE_CHARS};
pub use fields::AtomFields;
pub use molecule::Molecule;
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
