//! # stereo — the second eye by reprojection
//!
//! This crate owns the stereo pair: it traces the left eye with `tracer`, reprojects every
//! left pixel into the right eye (Adelson & Hodges 1993, "Stereoscopic ray-tracing", as
//! re-implemented in Piszczek's seed paper, Algorithm 1), decides which right pixels must be
//! retraced and why, fills the right image in one of four [`Mode`]s, and measures the result
//! ([`FrameStats`], [`Quality`]). For timewarp, it also moves a traced pair to a newer head
//! pose by its depth ([`Warp`]).
//!
//! ## The pipeline
//!
//! [`StereoFrame::render`] (`frame.rs`) runs the stages in order, each parallel over rows
//! and each timed:
//! 1. trace the left eye fully (colour + visible-surface record), by the tracer's
//!    [`Renderer`](tracer::Renderer);
//! 2. reproject (`reproject.rs` over the image, `reproject/scanline.rs` per scanline): left
//!    pixel i lands at right pixel ⌊i + ½ + e·z/(d+z) · W/window⌋ ([`tracer::Disparity`]),
//!    later writes win, stretched spans are gaps;
//! 3. classify (`classify.rs`, in the same banded pass as stage 2): reprojected pixels on
//!    object edges are sent to retrace, as the mode asks;
//! 4. retrace (`retrace.rs`) the gaps, border and edges with full
//!    primary rays, through the tracer's [`PixelBatch`](tracer::PixelBatch);
//! 5. fill (`fill.rs`) the reprojected pixels, through the same view: reshade, or shade
//!    exactly. Copy mode copies the left colour in stage 4's pass over the image instead,
//!    so the right image is swept once; exact mode does stage 4 in stage 5's pass, each row
//!    one batch of retraced and reprojected pixels together, and on a fresh frame runs
//!    stages 2 to 5 in one pass over bands of rows, each band made as soon as it is
//!    classified, while the left rows it reads are in cache.
//!
//! [`Mode::Full`] traces the whole right eye as it traces the left, with a renderer of its
//! own, and times it as stage 4.
//!
//! With reuse on ([`StereoFrame::set_reuse`]), a frame whose only change is the scene time
//! is made from the last one: each eye retraces only the pixels whose ray trees can meet a
//! moving sphere then or now, stages 2 and 3 redo only the rows a retraced left row feeds,
//! and stages 4 and 5 only the right pixels that can differ (`reuse/`: the rule; why
//! it is exact: `docs/design/reuse-exactness.md`). The frame is byte for byte a fresh one.
//!
//! ## Modules
//!
//! Each uses only modules listed above it (in brackets), so there is no cycle:
//! - `stats`, `mode`, `image`, `metrics`: the crate's plain types and measures;
//! - `classify` (stats): one right row's classes from its key planes;
//! - `reproject/scanline` (classify): Algorithm 1 for one scanline;
//! - `reproject` (reproject/scanline, classify, mode, stats): stages 2 and 3 over the image;
//! - `retrace` (image, stats): stage 4;
//! - `fill` (image, mode, reproject, retrace, stats): stage 5 (and exact mode's stage 4, and
//!   on a fresh frame its stages 2 to 5 in one banded pass);
//! - `reuse` (reproject, stats): which pixels a reused frame makes again, one entry per
//!   frame that the driver follows stage by stage;
//! - `views`: the eye views a pair is traced through, guard band included ([`StereoViews`]);
//! - `warp` (its own `map`, `scatter`, `resolve`): timewarp's warp stage, beside the
//!   pipeline: a traced stereo pair moved to a newer head pose by its depth (Mark,
//!   McMillan & Bishop 1997), the holes one eye leaves filled from the other eye, then by a
//!   rule ([`Warp`]);
//! - `frame` (reproject, retrace, fill, reuse, views, warp, image, mode, stats): the stages
//!   in order, and the pair they made with its views, which a warp reads;
//! - `mask` (stats), `layout`: how a frame is shown, beside the pipeline (the mask's colour
//!   for pixels a reused frame kept, too);
//! - `outline` (frame): each eye's outlines (`tracer`'s cue), on copies of the pair's
//!   colours, from each eye's own first hits, beside the pipeline;
//! - `downsample` (mask, stats): a supersampled frame's eyes and mask filtered down to the
//!   output size (box filter in linear light), beside the pipeline too: the stages run at
//!   the sampled size and know nothing of it.
//!
//! ## Errors
//!
//! Nothing here returns an error: rendering cannot fail. Every scene the tracer accepts
//! renders, at every size below `u32::MAX` pixels per eye (0 × 0 included). The one thing
//! a user can get wrong is a name: [`Mode`]'s and [`Layout`]'s `FromStr` give the message
//! to show, a `String` that names the value and the choices. A caller's bug is checked as
//! one: a public function `assert!`s, with a message, what its arguments must satisfy
//! where breaking it would give a wrong answer rather than a panic ([`reproject_row`]'s
//! rows of one width, [`Quality::compare`]'s images of one size, [`StereoFrame::render`]'s
//! pixel count); the preconditions of the functions inside the crate are `debug_assert!`s
//! with messages. One limit is not checked, as no input reaches it and passing it changes
//! no pixel: fewer than `u32::MAX - 1` spheres (see `classify.rs`).

mod classify;
mod downsample;
mod fill;
mod frame;
mod image;
mod layout;
mod mask;
mod metrics;
mod mode;
mod outline;
mod reproject;
mod retrace;
mod reuse;
mod stats;
mod upsample;
mod views;
mod warp;

pub use downsample::{downsample, downsample_mask, downsample_mask_kept, downsample_mask_kept_banded};
pub use frame::{marks_cover, StereoFrame};
pub use image::Image;
pub use layout::{anaglyph_pixel, compose, Layout};
pub use mask::{mask_color, mask_image, KEPT_COLOR, KEPT_LEGEND, MASK_LEGEND};
pub use metrics::Quality;
pub use mode::{Mode, Options};
pub use outline::Outlined;
pub use reproject::{reproject_row, NO_SOURCE};
pub use stats::{EyeStats, FrameStats, PixelClass, PixelCounts, Reuse, StageTimes};
pub use upsample::upsample;
pub use views::StereoViews;
pub use warp::{Warp, WarpClass, WarpCounts, WarpSource};
