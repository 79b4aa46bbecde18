//! The headless commands, `stereotrace render`, `bench`, `sweep` and `timewarp`, and what only
//! they use.
//!
//! The modules, in order: each uses only those listed before it (and the shared modules at
//! the top of the crate: the arguments, the scene setup, the reference trace, the crop).
//! - `report`, the JSON keys;
//! - `render` (one frame, or an animation, to PNG files and the JSON report) and `bench`
//!   (every mode on the same frames);
//! - `plot`, the sweep's figure (and what every figure shares), and `sweep`, which measures
//!   each step with `bench`'s loop;
//! - `age_plot`, the timewarp's figure, and `timewarp`, which warps traced frames to the poses
//!   of a moving head and scores them against traces there.

pub mod report;

pub mod bench;
pub mod render;

pub mod plot;
pub mod sweep;

pub mod age_plot;
pub mod timewarp;

pub mod pick;
