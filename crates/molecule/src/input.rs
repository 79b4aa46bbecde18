//! Bounded reading: a path is checked before it is opened, a gzip stream is recognised by its
//! magic bytes and decompressed under a cap, and text comes out one line at a time in a
//! reused buffer, each line under a cap, counted from 1.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use flate2::bufread::MultiGzDecoder;

use crate::error::Error;
use crate::options::Limits;

/// The first two bytes of every gzip member (RFC 1952).
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// The read buffer: large enough that line reads rarely reach the operating system.
const BUFFER_BYTES: usize = 256 << 10;

/// What the file-type check calls a path that is not a regular file.
fn kind_of(file_type: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "FIFO";
        }
        if file_type.is_char_device() {
            return "character device";
        }
        if file_type.is_block_device() {
            return "block device";
        }
        if file_type.is_socket() {
            return "socket";
        }
    }
    if file_type.is_dir() {
        "directory"
    } else {
        "not a regular file"
    }
}

/// Opens `path` for [`Lines`]: refuses anything but a regular file (before opening it, so a
/// FIFO never blocks and `/dev/zero` is never read) and a file above
/// [`Limits::max_file_bytes`].
pub(crate) fn open_file(path: &Path, file: &str, limits: &Limits) -> Result<(Box<dyn BufRead>, u64), Error> {
    let io = |source| Error::Io { file: file.to_owned(), source };
    let check = |metadata: std::fs::Metadata| {
        if !metadata.file_type().is_file() {
            return Err(Error::NotAFile { file: file.to_owned(), kind: kind_of(metadata.file_type()) });
        }
        if metadata.len() > limits.max_file_bytes {
            return Err(Error::FileTooLarge {
                file: file.to_owned(),
                size: metadata.len(),
                limit: limits.max_file_bytes,
            });
        }
        Ok(metadata.len())
    };
    check(std::fs::metadata(path).map_err(io)?)?;
    let opened = File::open(path).map_err(io)?;
    // Checked again on what was opened, in case the path changed in between.
    let size = check(opened.metadata().map_err(io)?)?;
    let capped = opened.take(limits.max_file_bytes.saturating_add(1));
    Ok((Box::new(BufReader::with_capacity(BUFFER_BYTES, capped)), size))
}

/// Whether the byte stream is gzip, and the cap the line reader enforces on its text.
enum Cap {
    /// Plain text: at most this many bytes (the file-size limit).
    Plain(u64),
    /// Decompressed text: at most this many bytes.
    Decompressed(u64),
}

/// The lines of a file's text, decompressed if it is gzip, one at a time.
pub(crate) struct Lines<'a> {
    file: &'a str,
    reader: Box<dyn BufRead + 'a>,
    buffer: Vec<u8>,
    line: u64,
    consumed: u64,
    cap: Cap,
    max_line_bytes: usize,
}

impl<'a> Lines<'a> {
    /// Lines from `raw`, a plain or gzip byte stream named `file`. A stream that starts with
    /// gzip's magic bytes is decompressed whatever its name; a name ending in `.gz` on a
    /// stream without them is an error.
    pub(crate) fn new(file: &'a str, mut raw: Box<dyn BufRead + 'a>, limits: &Limits) -> Result<Self, Error> {
        let head = raw.fill_buf().map_err(|source| Error::Io { file: file.to_owned(), source })?;
        let gzip = head.starts_with(&GZIP_MAGIC);
        if !gzip && file.to_ascii_lowercase().ends_with(".gz") {
            return Err(Error::Malformed {
                file: file.to_owned(),
                line: 1,
                why: "named .gz but does not start with gzip's magic bytes 1f 8b".to_owned(),
            });
        }
        let (reader, cap): (Box<dyn BufRead + 'a>, Cap) = if gzip {
            let text = MultiGzDecoder::new(raw).take(limits.max_decompressed_bytes.saturating_add(1));
            (Box::new(BufReader::with_capacity(BUFFER_BYTES, text)), Cap::Decompressed(limits.max_decompressed_bytes))
        } else {
            (raw, Cap::Plain(limits.max_file_bytes))
        };
        Ok(Self {
            file,
            reader,
            buffer: Vec::with_capacity(256),
            line: 0,
            consumed: 0,
            cap,
            max_line_bytes: limits.max_line_bytes,
        })
    }

    /// The file's name, for messages.
    pub(crate) fn file(&self) -> &'a str {
        self.file
    }

    /// The 1-based number of the line last returned (0 before the first).
    pub(crate) fn line(&self) -> u64 {
        self.line
    }

    /// The next line's 1-based number and text without its `\n` or `\r\n`, or `None` at
    /// the end of the text.
    pub(crate) fn next_line(&mut self) -> Result<Option<(u64, &[u8])>, Error> {
        self.buffer.clear();
        let limit = self.max_line_bytes as u64 + 1;
        let read = (&mut self.reader)
            .take(limit)
            .read_until(b'\n', &mut self.buffer)
            .map_err(|source| Error::Io { file: self.file.to_owned(), source })?;
        if read == 0 {
            return Ok(None);
        }
        self.line += 1;
        self.consumed += read as u64;
        match self.cap {
            Cap::Plain(limit) if self.consumed > limit => {
                return Err(Error::FileTooLarge { file: self.file.to_owned(), size: self.consumed, limit });
            }
            Cap::Decompressed(limit) if self.consumed > limit => {
                return Err(Error::DecompressedTooLarge { file: self.file.to_owned(), limit });
            }
            _ => {}
        }
        let mut text = self.buffer.as_slice();
        if let Some(rest) = text.strip_suffix(b"\n") {
            text = rest;
        } else if read as u64 == limit {
            return Err(Error::Malformed {
                file: self.file.to_owned(),
                line: self.line,
                why: format!("line longer than the limit of {} bytes", self.max_line_bytes),
            });
        }
        Ok(Some((self.line, text.strip_suffix(b"\r").unwrap_or(text))))
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use flate2::write::GzEncoder;
    use flate2::Compression;

    use super::*;

    fn all_lines(file: &str, bytes: &[u8], limits: &Limits) -> Result<Vec<Vec<u8>>, Error> {
        let mut lines = Lines::new(file, Box::new(bytes), limits)?;
        let mut out = Vec::new();
        while let Some((_, line)) = lines.next_line()? {
            out.push(line.to_vec());
        }
        Ok(out)
    }

    fn gzip(bytes: &[u8]) -> Vec<u8> {
        let mut encoder = GzEncoder::new(Vec::new(), Compression::fast());
        encoder.write_all(bytes).unwrap();
        encoder.finish().unwrap()
    }

    #[test]
    fn lines_lose_their_endings_and_count_from_one() {
        let text = b"one\r\ntwo\n\nlast";
        let mut lines = Lines::new("t", Box::new(&text[..]), &Limits::default()).unwrap();
        assert_eq!(lines.next_line().unwrap(), Some((1, &b"one"[..])), "CRLF stripped, first line is 1");
        assert_eq!(lines.next_line().unwrap(), Some((2, &b"two"[..])), "LF stripped");
        assert_eq!(lines.next_line().unwrap(), Some((3, &b""[..])), "an empty line is a line");
        assert_eq!(lines.next_line().unwrap(), Some((4, &b"last"[..])), "a last line without LF");
        assert_eq!(lines.line(), 4, "four lines");
        assert_eq!(lines.next_line().unwrap(), None, "then the end");
    }

    #[test]
    fn gzip_is_recognised_by_its_magic_bytes_whatever_the_name() {
        let packed = gzip(b"a\nb\n");
        let lines = all_lines("no-extension", &packed, &Limits::default()).unwrap();
        assert_eq!(lines, vec![b"a".to_vec(), b"b".to_vec()], "decompressed");
    }

    #[test]
    fn a_gz_name_without_gzip_bytes_is_an_error() {
        let e = all_lines("x.pdb.gz", b"ATOM", &Limits::default()).unwrap_err();
        assert!(matches!(e, Error::Malformed { line: 1, .. }), "{e}");
        assert!(e.to_string().starts_with("x.pdb.gz:1: named .gz"), "{e}");
    }

    #[test]
    fn a_gzip_bomb_stops_at_the_decompressed_limit() {
        // 64 MiB of zeros packs to about 64 KiB; the limit is 1 MiB.
        let packed = gzip(&vec![b'\n'; 64 << 20]);
        let limits = Limits { max_decompressed_bytes: 1 << 20, ..Limits::default() };
        let e = all_lines("bomb.gz", &packed, &limits).unwrap_err();
        assert!(matches!(e, Error::DecompressedTooLarge { limit, .. } if limit == 1 << 20), "{e}");
    }

    #[test]
    fn a_truncated_gzip_stream_is_an_error() {
        let packed = gzip(&b"ATOM line\n".repeat(10_000));
        let e = all_lines("cut.gz", &packed[..packed.len() / 2], &Limits::default()).unwrap_err();
        assert!(matches!(e, Error::Io { .. }), "{e}");
        assert!(e.to_string().starts_with("cut.gz: "), "{e}");
    }

    #[test]
    fn a_line_above_the_limit_is_an_error_naming_it() {
        let limits = Limits { max_line_bytes: 8, ..Limits::default() };
        assert_eq!(all_lines("t", b"12345678\n", &limits).unwrap().len(), 1, "exactly the limit is fine");
        let e = all_lines("t", b"ok\n123456789\n", &limits).unwrap_err();
        assert!(e.to_string().starts_with("t:2: line longer than the limit of 8 bytes"), "{e}");
    }

    #[test]
    fn plain_text_above_the_file_limit_is_an_error() {
        let limits = Limits { max_file_bytes: 10, ..Limits::default() };
        let e = all_lines("t", b"0123\n5678\nabc\n", &limits).unwrap_err();
        assert!(matches!(e, Error::FileTooLarge { size: 14, limit: 10, .. }), "{e}");
    }
}
