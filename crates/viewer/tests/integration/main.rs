//! End-to-end tests of the `stereotrace` binary, in one test binary (as tiny-skia's
//! `tests/integration`): the headless commands (`cli`, `crop_diff`, `replay`, `sweep`, `timewarp`) and the window
//! under Xvfb (`window`), with the helpers they share in `common`.

mod common;

mod cli;
mod crop_diff;
mod replay;
mod sweep;
mod timewarp;
mod window;
