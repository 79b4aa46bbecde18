//! What the end-to-end tests share: the binary run from the workspace root, a scratch
//! directory per test process, and the PNGs the binary writes, decoded.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Output, Stdio};

/// The workspace root, where the binary runs (so `assets/…` paths resolve).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The bundled seed scene.
pub fn seed_scene() -> PathBuf {
    root().join("assets/scenes/seed.toml")
}

/// Runs `stereotrace` from the workspace root with `env` set, and waits for it.
pub fn stereotrace_with(env: &[(&str, &str)], args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stereotrace"))
        .args(args)
        .envs(env.iter().copied())
        .current_dir(root())
        .output()
        .unwrap_or_else(|e| panic!("cannot run stereotrace: {e}"))
}

/// Runs `stereotrace` from the workspace root, sends it Ctrl-C (SIGINT) once a line of its
/// progress on stderr contains `marker`, and waits for it: its exit status and the rest of
/// its stderr.
pub fn interrupted(args: &[&str], marker: &str) -> (ExitStatus, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_stereotrace"))
        .args(args)
        .current_dir(root())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run stereotrace: {e}"));
    let Some(stderr) = child.stderr.take() else { panic!("stderr is piped") };
    let mut stderr = BufReader::new(stderr);
    let mut line = String::new();
    while !line.contains(marker) {
        line.clear();
        let read = stderr.read_line(&mut line).unwrap_or_else(|e| panic!("reading stderr: {e}"));
        assert!(read > 0, "stereotrace ended before printing {marker:?}");
    }
    let kill = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    assert!(kill.is_ok_and(|s| s.success()), "kill -INT");
    let mut rest = String::new();
    stderr.read_to_string(&mut rest).unwrap_or_else(|e| panic!("reading stderr: {e}"));
    (child.wait().unwrap_or_else(|e| panic!("waiting for stereotrace: {e}")), rest)
}

/// Runs `stereotrace` from the workspace root, and waits for it.
pub fn stereotrace(args: &[&str]) -> Output {
    stereotrace_with(&[], args)
}

/// The arguments `ok` with `flag`'s value replaced by `value`, or the flag added: one bad
/// argument in an otherwise good command line.
pub fn with_flag<'a>(ok: &[&'a str], flag: &'a str, value: &'a str) -> Vec<&'a str> {
    let mut args = ok.to_vec();
    match args.iter().position(|&a| a == flag) {
        Some(i) => args[i + 1] = value,
        None => args.extend([flag, value]),
    }
    args
}

/// A path for `name` in this test process's scratch directory.
pub fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stereotrace-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir.join(name)
}

/// Decodes an 8-bit RGB PNG, as the binary writes them: (width, height, RGB bytes).
pub fn read_rgb_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let file = File::open(path).unwrap_or_else(|e| panic!("cannot open {}: {e}", path.display()));
    let mut reader =
        png::Decoder::new(BufReader::new(file)).read_info().unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut buf = vec![0; reader.output_buffer_size().unwrap_or_default()];
    let info = reader.next_frame(&mut buf).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(
        (info.color_type, info.bit_depth),
        (png::ColorType::Rgb, png::BitDepth::Eight),
        "{}: stereotrace writes 8-bit RGB",
        path.display()
    );
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

/// Decodes an 8-bit RGB PNG: (width, height, `0x00RRGGBB` pixels).
pub fn read_png(path: &Path) -> (u32, u32, Vec<u32>) {
    let (w, h, rgb) = read_rgb_png(path);
    let pixels =
        rgb.chunks_exact(3).map(|c| (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2])).collect();
    (w, h, pixels)
}
