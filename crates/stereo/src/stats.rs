//! What a stereo frame cost and how its right-eye pixels were made.

use tracer::RayCounts;

/// How one right-eye pixel was made. Every pixel has exactly one class.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum PixelClass {
    /// Filled from a reprojected left pixel.
    Reprojected = 0,
    /// Retraced: no left pixel landed here, or it lies in a stretched span (a gap, the
    /// disoccluded strip, or the border the left eye never saw).
    #[default]
    RetracedGap = 1,
    /// Retraced: its reprojected object differs from a neighbour's (a silhouette).
    RetracedEdge = 2,
    /// Traced from scratch because the mode is `full`.
    Traced = 3,
}

impl PixelClass {
    /// How many classes there are: arrays of counts by class discriminant have this length.
    pub const COUNT: usize = 4;
}

/// Pixel counts per class for the right eye.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelCounts {
    /// [`PixelClass::Reprojected`].
    pub reprojected: u64,
    /// [`PixelClass::RetracedGap`].
    pub retraced_gap: u64,
    /// [`PixelClass::RetracedEdge`].
    pub retraced_edge: u64,
    /// [`PixelClass::Traced`] (full mode).
    pub traced: u64,
}

impl PixelCounts {
    /// Counts the classes of a mask.
    #[must_use]
    pub fn of(mask: &[PixelClass]) -> Self {
        // One vectorisable count per class (a histogram's increments of one counter chain
        // through memory, pixel after pixel).
        let count = |class: PixelClass| {
            let one = |chunk: &[PixelClass]| chunk.iter().map(|&p| u32::from(p as u8 == class as u8)).sum::<u32>();
            mask.chunks(1 << 16).map(|chunk| u64::from(one(chunk))).sum::<u64>()
        };
        let (reprojected, retraced_gap, retraced_edge) =
            (count(PixelClass::Reprojected), count(PixelClass::RetracedGap), count(PixelClass::RetracedEdge));
        let traced = mask.len() as u64 - reprojected - retraced_gap - retraced_edge;
        Self { reprojected, retraced_gap, retraced_edge, traced }
    }

    /// Counts the classes of a mask in parallel, in chunks: the same counts as
    /// [`PixelCounts::of`].
    #[must_use]
    pub fn of_par(mask: &[PixelClass]) -> Self {
        use rayon::prelude::*;
        mask.par_chunks(1 << 16).map(Self::of).reduce(Self::default, |a, b| Self {
            reprojected: a.reprojected + b.reprojected,
            retraced_gap: a.retraced_gap + b.retraced_gap,
            retraced_edge: a.retraced_edge + b.retraced_edge,
            traced: a.traced + b.traced,
        })
    }

    /// The counts as an array, by class discriminant.
    #[must_use]
    pub(crate) fn to_array(self) -> [u64; PixelClass::COUNT] {
        [self.reprojected, self.retraced_gap, self.retraced_edge, self.traced]
    }

    /// The counts of an array, by class discriminant.
    #[must_use]
    pub(crate) fn from_array(n: [u64; PixelClass::COUNT]) -> Self {
        Self { reprojected: n[0], retraced_gap: n[1], retraced_edge: n[2], traced: n[3] }
    }

    /// All pixels.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.reprojected + self.retraced_gap + self.retraced_edge + self.traced
    }

    /// Share of pixels reprojected, 0..1.
    #[must_use]
    pub fn reprojected_share(&self) -> f64 {
        if self.total() == 0 {
            0.0
        } else {
            self.reprojected as f64 / self.total() as f64
        }
    }
}

/// One eye's cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EyeStats {
    /// Rays cast for this eye, by kind.
    pub rays: RayCounts,
    /// Wall time for this eye, milliseconds.
    pub ms: f64,
}

/// Wall time per stage, milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Tracing the left eye.
    pub trace_left: f64,
    /// Reprojection and classification of the right eye.
    pub reproject: f64,
    /// Retracing the right eye's gap and edge pixels (all pixels in full
    /// mode); in copy mode this pass also copies the reprojected pixels' colours.
    pub retrace: f64,
    /// Filling the reprojected pixels by reshade or exact shading (0 in copy mode, whose
    /// gather is part of `retrace`).
    pub reshade: f64,
    /// The right eye's depth pass, for a timewarp (0 unless the frame keeps depths; not part
    /// of the right eye's time).
    pub depth: f64,
}

/// How much of a frame was made anew rather than kept from the last one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Reuse {
    /// Whether the frame reused the last one (only the scene time changed, reuse on).
    pub reused: bool,
    /// Pixels of both eyes traced or made again (every pixel of a fresh frame).
    pub made: u64,
    /// Pixels of both eyes.
    pub pixels: u64,
}

impl Reuse {
    /// Share of the pixels made anew, 0..1 (1 for a fresh frame, 0 for an empty one).
    #[must_use]
    pub fn retraced_share(&self) -> f64 {
        ratio(self.made as f64, self.pixels as f64)
    }
}

/// Everything measured about one stereo frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// The left eye (always fully traced).
    pub left: EyeStats,
    /// The right eye.
    pub right: EyeStats,
    /// Right-eye pixels by class.
    pub pixels: PixelCounts,
    /// Time per stage.
    pub stages: StageTimes,
    /// Exact mode's pixels tested against the one sphere their source saw, alone or in their
    /// screen tile's search (not scene rays, so not in `right.rays`).
    pub sphere_tests: u64,
    /// What was kept from the last frame.
    pub reuse: Reuse,
}

impl FrameStats {
    /// The right eye's rays as a share of the left eye's.
    #[must_use]
    pub fn right_ray_ratio(&self) -> f64 {
        ratio(self.right.rays.total() as f64, self.left.rays.total() as f64)
    }

    /// The right eye's time as a share of the left eye's.
    #[must_use]
    pub fn right_time_ratio(&self) -> f64 {
        ratio(self.right.ms, self.left.ms)
    }
}

fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 {
        a / b
    } else {
        0.0
    }
}
