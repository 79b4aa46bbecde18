//! The headless commands, `stereotrace render`, `bench` and `sweep`, and what only they use.
//!
//! The modules, in order: each uses only those listed before it (and the shared modules at
//! the top of the crate: the arguments, the scene setup, the reference trace, the crop).
//! - `report`, the JSON keys;
//! - `render` (one frame, or an animation, to PNG files and the JSON report) and `bench`
//!   (every mode on the same frames);
//! - `plot`, the sweep's figure, and `sweep`, which measures each step with `bench`'s loop.

pub mod report;

pub mod bench;
pub mod render;

pub mod plot;
pub mod sweep;
