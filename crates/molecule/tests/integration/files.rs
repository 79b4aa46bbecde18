//! The file-system side of bounded reading: what is not a regular file is refused before it
//! is read, and every size limit holds.

use std::io::Write;
use std::sync::mpsc;
use std::time::Duration;

use molecule::{Error, Limits, ReadOptions};

use crate::{real_file, scratch_dir, two_btv, SMALL_PDB};

#[test]
fn a_directory_is_not_a_file() {
    let dir = scratch_dir("directory");
    let named = dir.join("looks-like.pdb");
    std::fs::create_dir(&named).unwrap();
    let e = molecule::read(&named, &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, Error::NotAFile { kind: "directory", .. }), "{e}");
    assert!(e.to_string().ends_with("looks-like.pdb: not a regular file (directory)"), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn dev_zero_is_refused_before_any_read() {
    let options = ReadOptions { format: Some(molecule::Format::Pdb), ..ReadOptions::default() };
    let e = molecule::read("/dev/zero", &options).unwrap_err();
    assert_eq!(e.to_string(), "/dev/zero: not a regular file (character device)", "never read");
}

#[test]
fn a_fifo_is_refused_without_blocking() {
    let dir = scratch_dir("fifo");
    let fifo = dir.join("pipe.pdb");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        crate::loud("\n*** SKIPPED: mkfifo is not available ***\n");
        return;
    }
    // Opening a FIFO for reading blocks until a writer comes: the read runs on a thread and
    // must answer within seconds.
    let (send, receive) = mpsc::channel();
    let path = fifo.clone();
    std::thread::spawn(move || send.send(molecule::read(&path, &ReadOptions::default()).map(|m| m.len())));
    let result = receive.recv_timeout(Duration::from_secs(10)).expect("the read blocked on the FIFO");
    let e = result.unwrap_err();
    assert!(matches!(e, Error::NotAFile { kind: "FIFO", .. }), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_missing_file_and_an_unknown_name_are_errors() {
    let e = molecule::read("/nonexistent/x.pdb", &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, Error::Io { .. }), "{e}");
    assert!(e.to_string().starts_with("/nonexistent/x.pdb: "), "{e}");
    let e = molecule::parse(SMALL_PDB.as_bytes(), "notes.txt", &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, Error::UnknownFormat { .. }), "{e}");
    let options = ReadOptions { format: Some(molecule::Format::Pdb), ..ReadOptions::default() };
    assert_eq!(molecule::parse(SMALL_PDB.as_bytes(), "notes.txt", &options).unwrap().len(), 10, "unless told");
}

#[test]
fn a_file_above_the_size_limit_is_refused_from_its_metadata() {
    let dir = scratch_dir("size");
    let path = dir.join("big.pdb");
    std::fs::write(&path, SMALL_PDB).unwrap();
    let limits = Limits { max_file_bytes: 100, ..Limits::default() };
    let e = molecule::read(&path, &ReadOptions { limits, ..ReadOptions::default() }).unwrap_err();
    let size = SMALL_PDB.len() as u64;
    assert!(matches!(e, Error::FileTooLarge { size: s, limit: 100, .. } if s == size), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_gzip_bomb_stops_at_the_decompressed_limit() {
    let dir = scratch_dir("bomb");
    let path = dir.join("bomb.pdb.gz");
    let mut e = flate2::write::GzEncoder::new(std::fs::File::create(&path).unwrap(), flate2::Compression::best());
    let block = format!("{:<79}\n", "REMARK").repeat(1 << 14);
    for _ in 0..52 {
        e.write_all(block.as_bytes()).unwrap();
    }
    e.finish().unwrap();
    assert!(std::fs::metadata(&path).unwrap().len() < 1 << 20, "65 MiB of REMARK lines packs small");
    let limits = Limits { max_decompressed_bytes: 8 << 20, ..Limits::default() };
    let e = molecule::read(&path, &ReadOptions { limits, ..ReadOptions::default() }).unwrap_err();
    assert!(matches!(e, Error::DecompressedTooLarge { limit, .. } if limit == 8 << 20), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_truncated_gzip_file_is_an_error() {
    let Some(path) = real_file(&two_btv(), crate::two_btv_required_in_ci()) else { return };
    let bytes = std::fs::read(path).unwrap();
    let dir = scratch_dir("truncated");
    let cut = dir.join("2btv-cut.pdb.gz");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let e = molecule::read(&cut, &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, Error::Io { .. }), "{e}");
    assert!(e.to_string().contains("2btv-cut.pdb.gz: "), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_atom_limit_holds_in_the_file_and_after_expansion() {
    let limits = Limits { max_atoms: 9, ..Limits::default() };
    let e = molecule::parse(SMALL_PDB.as_bytes(), "small.pdb", &ReadOptions { limits, ..ReadOptions::default() })
        .unwrap_err();
    assert_eq!(e.to_string(), "small.pdb: 10 atoms, above the limit of 9", "in the file");
    let limits = Limits { max_atoms: 18, ..Limits::default() };
    let options = ReadOptions { assembly: true, limits, ..ReadOptions::default() };
    let e = molecule::parse(SMALL_PDB.as_bytes(), "small.pdb", &options).unwrap_err();
    assert_eq!(e.to_string(), "small.pdb: 20 atoms after assembly expansion, above the limit of 18", "after expansion");
}

#[test]
fn an_assembly_asked_of_a_file_without_one_is_a_warning() {
    let options = ReadOptions { assembly: true, ..ReadOptions::default() };
    let m = molecule::parse(b"1\nx\nC 0 0 0\n", "one.xyz", &options).unwrap();
    assert_eq!(m.len(), 1, "the atoms as they are");
    assert!(m.warnings()[0].message.starts_with("an assembly was asked for"), "{:?}", m.warnings());
}

#[test]
fn the_small_structure_expands_by_its_operators() {
    let options = ReadOptions { assembly: true, ..ReadOptions::default() };
    let m = molecule::parse(SMALL_PDB.as_bytes(), "small.pdb", &options).unwrap();
    assert_eq!(m.len(), 20, "two copies of chains D and E");
    // BIOMT 2: (x, y, z) -> (20 - y, x, z - 3.5) in file space; atom 1 at (42.053, -9.336, 17.867).
    let p = m.positions()[10];
    assert!(p.abs_diff_eq(glam::Vec3::new(29.336, 42.053, -14.367), 1e-4), "{p}");
}
