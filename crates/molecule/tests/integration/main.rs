//! The molecule crate's integration tests, one binary: real files (1TII from Debian's
//! pymol-data, 2BTV from the project's shared molecules), the file-system bounds, malformed
//! files, and random input fed to every reader.

mod files;
mod fuzz;
mod malformed;
mod real;

use std::path::{Path, PathBuf};

/// pymol-data's 1TII, which CI installs.
pub const ONE_TII: &str = "/usr/share/pymol/data/demo/1tii.pdb";
/// GROMACS's box of 216 SPC waters (Debian's gromacs-data).
pub const SPC216: &str = "/usr/share/gromacs/top/spc216.gro";

/// The project's shared data, beside the repository: `../shared` from the project's root.
#[must_use]
pub fn shared() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared")
}

/// The shared 2BTV, read where it is: `../shared/molecules` from the project's root. Under
/// CI it is required whenever the shared data is there ([`two_btv_required_in_ci`]).
#[must_use]
pub fn two_btv() -> PathBuf {
    shared().join("molecules/2btv.pdb.gz")
}

/// Whether CI must have 2BTV: when it has the shared data beside the repository.
#[must_use]
pub fn two_btv_required_in_ci() -> bool {
    shared().is_dir()
}

/// `path` when it exists. Absent: a loud SKIPPED, or a failure under CI when `required_in_ci`.
#[must_use]
pub fn real_file(path: &Path, required_in_ci: bool) -> Option<PathBuf> {
    if path.is_file() {
        return Some(path.to_owned());
    }
    assert!(
        !(required_in_ci && std::env::var_os("CI").is_some()),
        "{} is absent under CI: .ci/run installs pymol-data (1TII), and CI has shared/ beside the repository (2BTV)",
        path.display()
    );
    loud(&format!("\n*** SKIPPED: {} is absent; install it to run this test ***\n", path.display()));
    None
}

/// Writes to the process's standard error directly, past the test harness's capture of
/// `eprintln!`, so a skip or a timing shows in a plain `cargo test`.
pub fn loud(text: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}

/// A fresh directory of this test binary's own under the system's temporary directory.
#[must_use]
#[expect(clippy::unwrap_used, reason = "a test helper: a temporary directory that cannot be made fails the test")]
pub fn scratch_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("molecule-tests-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small real structure, shipped in the test so it never skips: 1TII's first atoms (chain
/// D, then two of chain E and a water) with a REMARK 350 block of two operators.
pub const SMALL_PDB: &str = "\
HEADER    ENTEROTOXIN                             20-MAR-96   1TII
REMARK 350 BIOMOLECULE: 1
REMARK 350 APPLY THE FOLLOWING TO CHAINS: D, E
REMARK 350   BIOMT1   1  1.000000  0.000000  0.000000        0.00000
REMARK 350   BIOMT2   1  0.000000  1.000000  0.000000        0.00000
REMARK 350   BIOMT3   1  0.000000  0.000000  1.000000        0.00000
REMARK 350   BIOMT1   2  0.000000 -1.000000  0.000000       20.00000
REMARK 350   BIOMT2   2  1.000000  0.000000  0.000000        0.00000
REMARK 350   BIOMT3   2  0.000000  0.000000  1.000000       -3.50000
ATOM      1  N   GLY D   1      42.053  -9.336  17.867  1.00 43.86           N
ATOM      2  CA  GLY D   1      42.704 -10.253  18.851  1.00 41.67           C
ATOM      3  C   GLY D   1      44.140 -10.512  18.447  1.00 40.48           C
ATOM      4  O   GLY D   1      44.962 -10.836  19.303  1.00 39.86           O
ATOM      5  N   ALA D   2      44.442 -10.370  17.164  1.00 38.99           N
ATOM      6  CA  ALA D   2      45.790 -10.569  16.697  1.00 38.92           C
ATOM      7  SD  MET D  37      31.160   1.453   8.035  1.00 22.74           S
ATOM    776  N   GLY E   1      54.107  19.105  25.003  1.00 43.73           N
ATOM    777  CA  GLY E   1      53.624  20.475  25.088  1.00 41.60           C
HETATM 5470  O   HOH D 100      34.536   6.046  22.066  1.00 34.27           O
TER
END
";
