//! Reading a scene file's text: what a path that is not a regular file is, and a read
//! bounded in size however the file grows meanwhile.

use std::path::Path;

use crate::error::SceneError;

/// What kind of file-system object `meta` describes, for messages (the structure readers'
/// words).
pub(super) fn file_kind(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_dir() {
        "directory"
    } else if t.is_fifo() {
        "FIFO"
    } else if t.is_char_device() {
        "character device"
    } else if t.is_block_device() {
        "block device"
    } else if t.is_socket() {
        "socket"
    } else {
        "not a file"
    }
}

/// The text of the file at `path`, refusing more than `limit` bytes however the file grew
/// since its size was looked at.
pub(super) fn read_bounded(path: &Path, limit: u64) -> Result<String, SceneError> {
    use std::io::Read;
    let io = |source| SceneError::Io { path: path.to_path_buf(), source };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut src = String::new();
    file.take(limit + 1).read_to_string(&mut src).map_err(io)?;
    if src.len() as u64 > limit {
        return Err(SceneError::NotAScene {
            path: path.to_path_buf(),
            reason: format!("more than the limit of {limit} bytes for a TOML scene"),
        });
    }
    Ok(src)
}
