//! The crate's one error type, and the warnings a read collects instead of printing.
//!
//! Every message starts with the file as it was named, then the 1-based line where the line
//! is known: `1tii.pdb:1234: ATOM x = "12.3a4": not a number`.

use std::fmt;

/// Why a molecule file could not be read.
///
/// `file` is the path (or name) as the caller gave it; `line` is 1-based and counts the lines
/// of the decompressed text. Values quoted in a message are cut to [`MAX_VALUE_CHARS`]
/// characters, so a message stays short whatever the input.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The operating system refused to open or read the file, or its gzip stream is corrupt.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: String,
        /// What the operating system or the gzip decoder said.
        source: std::io::Error,
    },
    /// The path names a directory, a device, a FIFO or a socket: it is refused before any read.
    #[error("{file}: not a regular file ({kind})")]
    NotAFile {
        /// The file.
        file: String,
        /// What it is instead: "directory", "FIFO", "character device", ...
        kind: &'static str,
    },
    /// The file on disk is larger than [`Limits::max_file_bytes`](crate::Limits::max_file_bytes).
    #[error("{file}: {size} bytes on disk, above the limit of {limit} bytes")]
    FileTooLarge {
        /// The file.
        file: String,
        /// Its size on disk (at least this much when the file grew while it was read).
        size: u64,
        /// The limit in force.
        limit: u64,
    },
    /// The gzipped file decompresses to more than
    /// [`Limits::max_decompressed_bytes`](crate::Limits::max_decompressed_bytes); reading
    /// stopped at the limit.
    #[error("{file}: decompresses to more than the limit of {limit} bytes")]
    DecompressedTooLarge {
        /// The file.
        file: String,
        /// The limit in force.
        limit: u64,
    },
    /// The structure has more atoms than [`Limits::max_atoms`](crate::Limits::max_atoms),
    /// counted in the file or after expanding a biological assembly.
    #[error("{file}: {count} atoms{what}, above the limit of {limit}")]
    TooManyAtoms {
        /// The file.
        file: String,
        /// The number of atoms reached (or announced by the file, or the assembly's size).
        count: u64,
        /// Where they were counted: empty for the file, " after assembly expansion" otherwise.
        what: &'static str,
        /// The limit in force.
        limit: usize,
    },
    /// The file holds no atoms: it is empty, or has no atom records.
    #[error("{file}: no atoms: {why}")]
    NoAtoms {
        /// The file.
        file: String,
        /// What was found instead: "the file is empty", "no ATOM or HETATM record", ...
        why: &'static str,
    },
    /// Neither [`ReadOptions::format`](crate::ReadOptions::format) nor the file name says
    /// which format the file is in.
    #[error("{file}: unknown format: name the file .pdb, .ent, .cif, .mmcif, .gro or .xyz (optionally .gz), or set ReadOptions::format")]
    UnknownFormat {
        /// The file.
        file: String,
    },
    /// A field holds a value that cannot be used.
    #[error("{file}:{line}: {record} {field} = {value:?}: {why}")]
    Field {
        /// The file.
        file: String,
        /// The 1-based line.
        line: u64,
        /// The record or category: "ATOM", "HETATM", "REMARK 350", "_atom_site", "count", ...
        record: &'static str,
        /// The field: "x", "Cartn_x", "BIOMT2 row", ...
        field: &'static str,
        /// The value found (cut to [`MAX_VALUE_CHARS`] characters).
        value: String,
        /// Why it cannot be used: "not a number", "not finite", ...
        why: &'static str,
    },
    /// The file's structure is broken at a line: a short record, a count that the file does
    /// not hold, a loop cut short, an empty file.
    #[error("{file}:{line}: {why}")]
    Malformed {
        /// The file.
        file: String,
        /// The 1-based line (the last line read when the file ends too early).
        line: u64,
        /// What is wrong, naming the record and field when there is one.
        why: String,
    },
}

/// The longest value a message quotes, in characters; longer values end in "…".
pub const MAX_VALUE_CHARS: usize = 40;

/// `bytes` as text for a message: surrounding spaces dropped, invalid UTF-8 replaced, cut to
/// [`MAX_VALUE_CHARS`].
pub(crate) fn quote(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes.trim_ascii());
    let mut out: String = text.chars().take(MAX_VALUE_CHARS).collect();
    if text.chars().nth(MAX_VALUE_CHARS).is_some() {
        out.push('…');
    }
    out
}

/// Something in the file that was read with a documented fallback instead of failing: an
/// unknown element, models or alternate locations skipped, an assembly asked for and absent.
///
/// A read keeps at most [`Limits::max_warnings`](crate::Limits::max_warnings) of them; the
/// library never prints them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// The file.
    pub file: String,
    /// The 1-based line, or 0 when the warning is about the whole file.
    pub line: u64,
    /// What was found and what was done about it.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(f, "{}:{}: {}", self.file, self.line, self.message)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quote_cuts_long_values_and_replaces_invalid_utf8() {
        assert_eq!(quote(b"  12.3a4"), "12.3a4", "a short value is kept, without its padding");
        let long = quote(&[b'7'; 100]);
        assert_eq!(long.chars().count(), MAX_VALUE_CHARS + 1, "cut to the limit plus the ellipsis: {long}");
        assert!(long.ends_with('…'), "a cut value says so: {long}");
        assert_eq!(quote(&[b'a', 0xff, b'b']), "a\u{fffd}b", "invalid UTF-8 is replaced, not an error");
    }

    #[test]
    fn field_error_reads_file_line_record_field_value() {
        let e = Error::Field {
            file: "1tii.pdb".into(),
            line: 1234,
            record: "ATOM",
            field: "x",
            value: "12.3a4".into(),
            why: "not a number",
        };
        assert_eq!(e.to_string(), r#"1tii.pdb:1234: ATOM x = "12.3a4": not a number"#, "the documented message form");
    }
}
