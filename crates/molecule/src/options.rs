//! What a read is asked to do: the format, whether to build the biological assembly, and the
//! limits that keep a hostile or broken file from taking the machine.

use std::path::Path;

/// A structure file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Format {
    /// Protein Data Bank format v3.3 (`.pdb`, `.ent`, `.pdb1`).
    Pdb,
    /// PDBx/mmCIF (`.cif`, `.mmcif`).
    Mmcif,
    /// GROMACS coordinates (`.gro`), in nanometres.
    Gro,
    /// XYZ (`.xyz`): a count line, a comment line, `El x y z` lines, in Ångström.
    Xyz,
}

impl Format {
    /// The format a file name says, looking through a trailing `.gz` (ASCII case ignored):
    /// `2btv.pdb.gz` is [`Format::Pdb`].
    #[must_use]
    pub fn from_path(path: &Path) -> Option<Self> {
        let name = path.file_name()?.to_str()?.to_ascii_lowercase();
        let name = name.strip_suffix(".gz").unwrap_or(&name);
        let (_, extension) = name.rsplit_once('.')?;
        match extension {
            "pdb" | "ent" | "pdb1" => Some(Self::Pdb),
            "cif" | "mmcif" => Some(Self::Mmcif),
            "gro" => Some(Self::Gro),
            "xyz" => Some(Self::Xyz),
            _ => None,
        }
    }
}

/// The bounds a read enforces. Each is checked before the memory it guards is spent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// The largest file accepted on disk, in bytes (default 512 MiB). Checked on the file's
    /// metadata before reading, and again while reading in case it grows.
    pub max_file_bytes: u64,
    /// The most bytes a gzipped file may decompress to (default 2 GiB). Enforced while
    /// decompressing, so a gzip bomb stops at the limit instead of filling memory.
    pub max_decompressed_bytes: u64,
    /// The longest line accepted, in bytes (default 1 MiB): a file without line breaks is not
    /// held in memory whole.
    pub max_line_bytes: usize,
    /// The most atoms a structure may have, in the file and after expanding an assembly
    /// (default 16 Mi = 16,777,216: about 250 MB of compact atoms).
    pub max_atoms: usize,
    /// The most warnings kept (default 100); [`Molecule::warnings_total`](crate::Molecule::warnings_total)
    /// still counts all of them.
    pub max_warnings: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_file_bytes: 512 << 20,
            max_decompressed_bytes: 2 << 30,
            max_line_bytes: 1 << 20,
            max_atoms: 16 << 20,
            max_warnings: 100,
        }
    }
}

/// How to read a file. `ReadOptions::default()` reads the asymmetric unit, the format taken
/// from the file name, within [`Limits::default`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// The format, when the file name does not say it (`None`: from the name).
    pub format: Option<Format>,
    /// Build the first biological assembly the file lists (PDB `REMARK 350` BIOMOLECULE 1,
    /// mmCIF the first `_pdbx_struct_assembly_gen` assembly) instead of the atoms as they are.
    /// A file that lists none is read as it is, with a warning.
    pub assembly: bool,
    /// The bounds enforced.
    pub limits: Limits,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_from_file_name_looks_through_gz() {
        let f = |name: &str| Format::from_path(Path::new(name));
        assert_eq!(f("2btv.pdb.gz"), Some(Format::Pdb), "gzipped PDB");
        assert_eq!(f("dir.d/1TII.PDB"), Some(Format::Pdb), "case ignored");
        assert_eq!(f("pdb1abc.ent"), Some(Format::Pdb), "the archive's .ent");
        assert_eq!(f("x.cif"), Some(Format::Mmcif), "cif");
        assert_eq!(f("x.mmcif.gz"), Some(Format::Mmcif), "mmcif.gz");
        assert_eq!(f("conf.gro"), Some(Format::Gro), "gro");
        assert_eq!(f("water.xyz"), Some(Format::Xyz), "xyz");
        assert_eq!(f("notes.txt"), None, "not a structure");
        assert_eq!(f("pdb"), None, "no extension");
        assert_eq!(f("x.gz"), None, "gz of nothing known");
    }
}
