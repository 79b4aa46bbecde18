//! The workspace's end-to-end tests, in one test binary (as tiny-skia's `tests/integration`):
//! golden images of the seed scene (`golden`) and every bundled scene loaded and rendered
//! exactly (`scenes`), and real molecular structures (`molecules`). The helpers are the crate's library, `src/lib.rs`.

mod golden;
mod molecules;
mod scenes;
