//! The right eye's rule of temporal reuse: which right pixels of a `copy`, `reshade` or
//! `exact` frame are made again. The right eye is made from the current left eye, so it can
//! change where no ray of its own moved. A right pixel is made again when (1) its class or
//! source differs from the last frame's, (2) its source is a left pixel retraced this frame,
//! or (3) its own rays, as marked last frame, meet a moving sphere's wedge then or now; every
//! other pixel keeps its bytes, class and marks. The argument: `docs/design/reuse-exactness.md`.

use rayon::prelude::*;
use tracer::bits;
use tracer::reuse::{Arc, Marks};
use tracer::PixelBits;

use crate::reproject::NO_SOURCE;
use crate::stats::PixelClass;

/// This frame's stage-3 output against the last frame's, and what changed on the left.
#[derive(Debug)]
pub(crate) struct Changes<'a> {
    /// This frame's classes and sources.
    pub now: (&'a [PixelClass], &'a [u32]),
    /// The last frame's.
    pub before: (&'a [PixelClass], &'a [u32]),
    /// The left pixels retraced this frame.
    pub left_retraced: &'a PixelBits,
    /// Where the right pixels' own rays met the swept volumes last frame.
    pub right_marks: &'a mut Marks,
    /// The moving spheres' wedges last frame and now.
    pub wedges: [&'a [Arc]; 2],
    /// Per right row, whether stages 2 and 3 redid it (the others kept their classes and
    /// sources, so rules 1 and 2 cannot hold there).
    pub rows: &'a [bool],
}

/// Sets in `redo` (sized as the marks) the right pixels the rule makes again, and gives each
/// of them its stage-3 class in `mask`; the other pixels of `mask` keep their final class
/// from the last frame. Returns how many are made again, and how many of each class (by
/// discriminant) they had in the last frame.
pub(crate) fn plan_right(
    changes: Changes<'_>,
    mask: &mut [PixelClass],
    redo: &mut PixelBits,
) -> (u64, [u64; PixelClass::COUNT]) {
    let Changes { now: (class, src), before: (class_was, src_was), left_retraced, right_marks, wedges, rows } = changes;
    let w = right_marks.width() as usize;
    // Rule 3 first: the right pixels whose own rays may meet a sphere at either instant.
    right_marks.select(wedges, redo);
    if w == 0 {
        return (0, [0; PixelClass::COUNT]);
    }
    let stride = redo.stride();
    redo.words_mut()
        .par_chunks_mut(stride)
        .zip(mask.par_chunks_mut(w))
        .enumerate()
        .map(|(j, (row, mask))| {
            let base = j * w;
            let left_row = left_retraced.row(j as u32);
            let any_left = left_row.iter().any(|&word| word != 0);
            // A row stages 2-3 left alone, or redid to the same classes and sources, with no
            // retraced left pixel to read: only rule 3 can hold (its bits are set already).
            // (Sources lie in their own row: reprojection runs along scanlines.)
            let same = |a: &[PixelClass], b: &[PixelClass], c: &[u32], d: &[u32]| a == b && c == d;
            let row_range = base..base + w;
            if !rows[j]
                || (!any_left
                    && same(
                        &class[row_range.clone()],
                        &class_was[row_range.clone()],
                        &src[row_range.clone()],
                        &src_was[row_range],
                    ))
            {
                let (mut made, mut was) = (0, [0u64; PixelClass::COUNT]);
                for i in bits::ones(row) {
                    was[mask[i as usize] as usize] += 1;
                    mask[i as usize] = class[base + i as usize];
                    made += 1;
                }
                return (made, was);
            }
            // 64 pixels at a time: rules 1 and 2 as a word of bits (rule 3's are set
            // already), then the pixels it names.
            let sources = SourcesRetraced::of(left_row, (base, w));
            let (mut made, mut was) = (0, [0u64; PixelClass::COUNT]);
            for (k, word) in row.iter_mut().enumerate() {
                let r = base + 64 * k..(base + 64 * k + 64).min(base + w);
                let again = *word
                    | changed(&class[r.clone()], &class_was[r.clone()], &src[r.clone()], &src_was[r.clone()])
                    | sources.word(&src[r], left_retraced);
                *word = again;
                for b in bits::ones(std::slice::from_ref(&again)) {
                    let i = 64 * k + b as usize;
                    was[mask[i] as usize] += 1;
                    mask[i] = class[base + i];
                    made += 1;
                }
            }
            (made, was)
        })
        .reduce(|| (0, [0; PixelClass::COUNT]), |(m, a), (n, b)| (m + n, std::array::from_fn(|c| a[c] + b[c])))
}

/// Packs 64 flags (0 or 1) into a word, flag b as bit b.
#[inline]
fn pack(flags: &[u8; 64]) -> u64 {
    // Eight flags at a time: the multiply gathers each byte's low bit into the top byte.
    flags.chunks_exact(8).enumerate().fold(0, |word, (k, eight)| {
        let x = u64::from_le_bytes(eight.try_into().unwrap_or([0; 8]));
        word | (x.wrapping_mul(0x0102_0408_1020_4080) >> 56) << (8 * k)
    })
}

/// Rule 1 over a word's pixels (64, or the rest of a row): bit b set where pixel b's class
/// or source differs from the last frame's.
#[inline]
fn changed(class: &[PixelClass], class_was: &[PixelClass], src: &[u32], src_was: &[u32]) -> u64 {
    let mut flags = [0u8; 64];
    let pixels = class.iter().zip(class_was).zip(src.iter().zip(src_was));
    for (flag, ((c, c_was), (s, s_was))) in flags.iter_mut().zip(pixels) {
        *flag = u8::from(c != c_was) | u8::from(s != s_was);
    }
    pack(&flags)
}

/// Rule 2 over a row: which of its right pixels read a retraced left pixel.
struct SourcesRetraced<'a> {
    /// The row of the left pixels retraced.
    left_row: &'a [u64],
    /// The row's first pixel, and the image width.
    base: usize,
    width: usize,
    /// The first column of the row's retraced pixels, and how far the last lies past it
    /// (0 and 0 if none: then column 0 is looked up, and is not retraced).
    cols: (u32, u32),
}

impl<'a> SourcesRetraced<'a> {
    fn of(left_row: &'a [u64], (base, width): (usize, usize)) -> Self {
        let mut ones = bits::ones(left_row);
        let first = ones.next();
        let last = ones.last().or(first);
        let cols = first.zip(last).map_or((0, 0), |(a, b)| (a, b - a));
        Self { left_row, base, width, cols }
    }

    /// Bit b set where pixel b of `src` (a word's sources) reads a retraced left pixel.
    /// Reprojection runs along scanlines, so a source lies in the row; one outside it (or
    /// past the retraced columns' span) is looked up only when it could be retraced.
    #[inline]
    fn word(&self, src: &[u32], left_retraced: &PixelBits) -> u64 {
        // First the columns in the span, in a pass the compiler can run in vectors; most
        // pixels are not.
        let (lo, span) = self.cols;
        let mut flags = [0u8; 64];
        for (flag, &s) in flags.iter_mut().zip(src) {
            let col = s.wrapping_sub(self.base as u32);
            let outside_row = col >= self.width as u32 && s != NO_SOURCE;
            *flag = u8::from(col.wrapping_sub(lo) <= span) | u8::from(outside_row);
        }
        let near = pack(&flags);
        bits::ones(std::slice::from_ref(&near)).fold(0, |word, b| {
            let s = src[b as usize];
            let col = s.wrapping_sub(self.base as u32);
            let retraced = if col < self.width as u32 {
                bits::get(self.left_row, col)
            } else {
                left_retraced.get_index(s as usize)
            };
            word | u64::from(retraced) << b
        })
    }
}
