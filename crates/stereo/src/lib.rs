//! # stereo — the second eye by reprojection
//!
//! This crate owns the stereo pair: it traces the left eye with `tracer`, reprojects every
//! left pixel into the right eye (Adelson & Hodges 1993, "Stereoscopic ray-tracing", as
//! re-implemented in Piszczek's seed paper, Algorithm 1), decides which right pixels must be
//! retraced and why, fills the right image in one of four [`Mode`]s, and measures the result
//! ([`FrameStats`], [`Quality`]).
//!
//! The stages, each parallel over rows and each timed:
//! 1. trace the left eye fully (colour + visible-surface record);
//! 2. reproject (`reproject.rs`): per scanline, left pixel i lands at right pixel
//!    ⌊i + ½ + e·z/(d+z) · W/window⌋, later writes win, stretched spans are gaps;
//! 3. classify (`classify.rs`): reprojected pixels on object edges or shadow boundaries are
//!    sent to retrace, as the mode asks;
//! 4. retrace the gaps, border, edges and shadow boundaries with full primary rays;
//! 5. fill the reprojected pixels: copy the left colour, reshade, or shade exactly (copy
//!    mode does this in stage 4's pass over the image, so the right image is swept once).

mod classify;
mod frame;
mod layout;
mod mask;
mod metrics;
mod mode;
mod reproject;
mod stats;

pub use frame::{Image, StereoFrame};
pub use layout::{anaglyph_pixel, compose, Layout};
pub use mask::{mask_color, mask_image, MASK_LEGEND};
pub use metrics::Quality;
pub use mode::{Mode, Options};
pub use reproject::{reproject_row, NO_SOURCE};
pub use stats::{EyeStats, FrameStats, PixelClass, PixelCounts, StageTimes};
