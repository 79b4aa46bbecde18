//! Stage 4: full primary rays for the right pixels the reprojection does not fill (gaps,
//! the border strip, and the edges the mode sends back), traced
//! exactly as [`Mode::Full`](crate::Mode::Full) traces every pixel.
//!
//! In copy mode the same pass over the image also gives each reprojected pixel its source's
//! colour (the seed paper's stage 5), so the right image is swept once.

use rayon::prelude::*;
use tracer::bits;
use tracer::reuse::{Marks, MarksRow, Rewrite};
use tracer::{PixelBatch, PixelBits, RayCounts};

use crate::image::Image;
use crate::stats::PixelClass;

/// Which right pixels stages 4 and 5 make, and where they mark them.
#[derive(Debug)]
pub(crate) struct Redo<'a> {
    /// The pixels to make; `None`: all of them.
    pub only: Option<&'a PixelBits>,
    /// Where each pixel's own ray trees (the rays this eye casts for it) meet the moving
    /// spheres' swept volumes: cleared for each pixel made by stage 4, then set as the
    /// traces of stages 4 and 5 say. Left alone unless `mark`.
    pub marks: &'a mut Marks,
    /// Whether this frame marks (see `StereoFrame::set_reuse`).
    pub mark: bool,
}

impl<'a> Redo<'a> {
    /// The marks' rows (for a pass that makes what `only` names: a few pixels, or all),
    /// the selection, and whether to mark: what stages 4 and 5 start from, with
    /// [`row_of`] for each row.
    pub(crate) fn rows(self) -> (impl IndexedParallelIterator<Item = MarksRow<'a>>, Option<&'a PixelBits>, bool) {
        let Self { only, marks, mark } = self;
        let rewrite = if only.is_some() { Rewrite::Few } else { Rewrite::All };
        (marks.rows_mut(rewrite), only, mark)
    }
}

/// Row `j` of a selection (`None`: every pixel), and whether it names no pixel there.
pub(crate) fn row_of(only: Option<&PixelBits>, j: usize) -> (Option<&[u64]>, bool) {
    let row = only.map(|bits| bits.row(j as u32));
    (row, row.is_some_and(|row| row.iter().all(|&word| word == 0)))
}

/// The columns of a `w`-pixel row to make, ascending, given the row's selection (`None`:
/// all).
pub(crate) fn chosen(only: Option<&[u64]>, w: usize) -> Chosen<'_> {
    match only {
        None => Chosen::All(0..w as u32),
        Some(row) => Chosen::Some(bits::ones(row)),
    }
}

/// The iterator of [`chosen`].
#[derive(Clone, Debug)]
pub(crate) enum Chosen<'a> {
    /// Every column.
    All(std::ops::Range<u32>),
    /// The set bits of a row.
    Some(bits::Ones<'a>),
}

impl Iterator for Chosen<'_> {
    type Item = u32;

    #[inline]
    fn next(&mut self) -> Option<u32> {
        match self {
            Self::All(range) => range.next(),
            Self::Some(ones) => ones.next(),
        }
    }
}

/// Stage 4 over the image: every right pixel of `redo` that `mask` does not mark
/// [`PixelClass::Reprojected`] is traced by `right`, the right eye's view, into `out`; with
/// `copy_from` (the left eye's colours), every reprojected one takes the colour of its
/// source in `src`, and without, keeps what `out` holds. Pixels outside `redo` are not
/// touched. Returns the rays cast.
pub(crate) fn retrace(
    right: PixelBatch<'_>,
    mask: &[PixelClass],
    src: &[u32],
    copy_from: Option<&[u32]>,
    out: &mut Image,
    redo: Redo<'_>,
) -> RayCounts {
    let w = out.width as usize;
    debug_assert!(
        mask.len() == out.rgb.len() && src.len() == out.rgb.len() && out.rgb.len() == w * out.height as usize,
        "the mask, the source map and the image must have one size"
    );
    let (marks, only, mark) = redo.rows();
    out.rgb
        .par_chunks_mut(w)
        .zip(mask.par_chunks(w))
        .zip(src.par_chunks(w))
        .zip(marks)
        .enumerate()
        .map(|(j, (((rgb, mask), src), mut marks))| {
            let mut counts = RayCounts::default();
            let (only, empty) = row_of(only, j);
            if empty {
                // Nothing to make in this row.
                return counts;
            }
            if mark {
                marks.clear_only(only);
            }
            if let Some(left) = copy_from {
                for i in chosen(only, w).map(|i| i as usize) {
                    if mask[i] == PixelClass::Reprojected {
                        rgb[i] = left[src[i] as usize];
                    }
                }
            }
            let traced = chosen(only, w).filter(|&i| mask[i as usize] != PixelClass::Reprojected);
            right.trace_pixels(j as u32, traced, &mut counts, (rgb, mark.then_some(&mut marks)));
            counts
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use tracer::{Eye, Pixels, Renderer, Target, Tracer};

    use super::*;

    /// A colour no traced pixel has: its high byte is set.
    const UNTOUCHED: u32 = 0xFF00_FF00;

    #[test]
    fn retraced_pixels_are_the_full_trace_and_reprojected_ones_are_copied() {
        let scene = tracer::testing::scene("window.toml");
        let tracer = Tracer::new(&scene, 0.7);
        let (w, h) = (122, 68);
        let n = (w * h) as usize;
        let rv = scene.camera.view(Eye::Right, w, h);
        let mut full = Vec::new();
        let full_counts = Renderer::new().render(&tracer, &rv, Pixels::All, Target::colour(&mut full));
        let mut renderer = Renderer::new();
        let right = renderer.batch(&tracer, &rv);
        let image = || Image { width: w, height: h, rgb: vec![UNTOUCHED; n] };

        // Every pixel retraced: the full trace, ray for ray.
        let mut out = image();
        let mut marks = Marks::new(w, h);
        let all = Redo { only: None, marks: &mut marks, mark: true };
        let counts = retrace(right, &vec![PixelClass::RetracedGap; n], &vec![0; n], None, &mut out, all);
        assert!(out.rgb == full, "retracing every pixel differs from the full trace");
        assert_eq!(counts, full_counts);

        // A mix of classes, in runs and alone, with and without copying the sources.
        let classes = [PixelClass::RetracedGap, PixelClass::RetracedEdge, PixelClass::Traced];
        let mask: Vec<PixelClass> =
            (0..n).map(|k| if k % 11 < 5 || k % 7 == 0 { PixelClass::Reprojected } else { classes[k % 3] }).collect();
        let src: Vec<u32> = (0..n as u32).rev().collect();
        let left: Vec<u32> = (0..n as u32).map(|s| 0x0100_0000 | s).collect();
        let retraced = mask.iter().filter(|&&c| c != PixelClass::Reprojected).count() as u64;
        for copy_from in [None, Some(&left[..])] {
            let mut out = image();
            let counts =
                retrace(right, &mask, &src, copy_from, &mut out, Redo { only: None, marks: &mut marks, mark: true });
            assert_eq!(counts.primary, retraced, "one primary ray per retraced pixel");
            for k in 0..n {
                let expected = match (mask[k], copy_from) {
                    (PixelClass::Reprojected, Some(left)) => left[src[k] as usize],
                    (PixelClass::Reprojected, None) => UNTOUCHED,
                    _ => full[k],
                };
                let got = out.rgb[k];
                assert!(got == expected, "pixel {k} ({:?}, copy {}): {got:#x}", mask[k], copy_from.is_some());
            }
        }
    }
}
