//! The crate's one error type.

use std::path::PathBuf;

/// Everything that can go wrong while loading or validating a scene.
///
/// Every variant names the file; parse and validation errors also name the line, the
/// field and the offending value, so a user can fix a hand-written scene without guessing.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read at all.
    #[error("{path}: cannot read scene file: {source}")]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The file is not valid TOML, has an unknown field, or a field of the wrong type.
    #[error("{path}:{line}: {message}")]
    Parse {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the problem (0 when the parser gave no position).
        line: usize,
        /// What the parser said, including the field where it knows it.
        message: String,
    },
    /// A structure file (PDB, mmCIF, GRO, XYZ) could not be read; its message names the
    /// file, the line and the field.
    #[error(transparent)]
    Structure(#[from] molecule::Error),
    /// The path is not a scene file this program reads: not a regular file, too large, or of
    /// another type.
    #[error("{path}: {reason}")]
    NotAScene {
        /// The path given.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// The file parsed but a value is out of its allowed range.
    #[error("{path}:{line}: {field} = {value}: {reason}")]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the table that holds the field.
        line: usize,
        /// Dotted path of the field, e.g. `spheres[2].radius`.
        field: String,
        /// The value as written.
        value: String,
        /// Why it is rejected and what is allowed.
        reason: String,
    },
}
