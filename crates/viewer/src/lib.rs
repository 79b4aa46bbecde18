//! # viewer — what the `stereotrace` binary shares with the end-to-end tests
//!
//! The binary (`src/main.rs`, which dispatches to `src/window/`, the viewer window, or to
//! `src/cli/`, the headless `render`, `bench`, `sweep` and `timewarp`) is this package's main target;
//! this library holds the one piece the root `tests` crate needs as well, so that
//! there is one PNG writer: [`write_png`], which never leaves a half-written file (and
//! [`write_bytes`], the same for the sweep's CSV and SVG).

mod png_out;

pub use png_out::{parent_dir, write_bytes, write_png};
