//! The stereo crate's integration tests, in one test binary (as tiny-skia's
//! `tests/integration`): closed-form and structural tests of the reprojection (`stereo`),
//! exact temporal reuse (`reuse`), and no allocation in a warm frame (`alloc`, which counts
//! only the allocations of its own threads, so it shares the binary safely).
//!
//! The property tests' regression seeds are in `tests/proptest-regressions/<module>.txt`:
//! with this `main.rs` beside the modules, proptest's default persistence
//! (`SourceParallel("proptest-regressions")`) looks for them there.

mod alloc;
mod cues;
mod reuse;
mod stereo;
