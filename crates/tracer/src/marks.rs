//! Per-pixel marks of where each pixel's ray tree meets the moving spheres' swept volumes
//! (`swept.rs`): a bit per pixel (set: the tree meets some volume) for fast scans, and the
//! [`Touch`] (which ring, which arc of it) of the marked pixels.
//!
//! After a frame at t₀, the pixels that can differ at t₁ are the marked ones whose touch
//! meets a moving sphere's wedge at t₀ or at t₁ ([`Marks::select`]); every other pixel is
//! the same at t₁, byte for byte (the lemma of `swept.rs`).

use rayon::prelude::*;

use crate::bits::{self, PixelBits};
use crate::swept::{Arc, Touch};

/// The marks of a `width` × `height` image (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct Marks {
    bits: PixelBits,
    /// Per pixel, row-major; meaningful where the bit is set ([`Touch::NONE`] elsewhere).
    touch: Vec<Touch>,
}

/// One row of [`Marks`], to write.
#[derive(Debug)]
pub struct MarksRow<'a> {
    /// The row's bits.
    pub bits: &'a mut [u64],
    /// The row's touches.
    pub touch: &'a mut [Touch],
}

impl MarksRow<'_> {
    /// Pixel `i`'s tree meets the swept volumes as `touch` says.
    #[inline]
    pub fn set(&mut self, i: u32, touch: Touch) {
        bits::set(self.bits, i, touch.is_some());
        self.touch[i as usize] = touch;
    }

    /// Unmarks every pixel of the row.
    pub fn clear(&mut self) {
        self.bits.fill(0);
        self.touch.fill(Touch::NONE);
    }

    /// Unmarks the pixels that `only` (a row of a [`PixelBits`]) names; `None`: all.
    pub fn clear_only(&mut self, only: Option<&[u64]>) {
        let Some(only) = only else { return self.clear() };
        for i in bits::ones(only) {
            self.set(i, Touch::NONE);
        }
    }
}

impl Marks {
    /// No pixel marked, `width` × `height`.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        let mut marks = Self::default();
        marks.resize(width, height);
        marks
    }

    /// Changes the size and unmarks every pixel, reusing the allocations where they are
    /// large enough.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.bits.resize(width, height);
        self.touch.clear();
        self.touch.resize(width as usize * height as usize, Touch::NONE);
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.bits.width()
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.bits.height()
    }

    /// The marked pixels.
    #[must_use]
    pub fn bits(&self) -> &PixelBits {
        &self.bits
    }

    /// Where pixel `k`'s (row-major) tree meets the swept volumes.
    #[must_use]
    pub fn touch(&self, k: usize) -> Touch {
        self.touch[k]
    }

    /// The rows, to write in parallel.
    pub fn rows_mut(&mut self) -> impl IndexedParallelIterator<Item = MarksRow<'_>> {
        let (stride, w) = (self.bits.stride().max(1), (self.bits.width() as usize).max(1));
        self.bits
            .words_mut()
            .par_chunks_mut(stride)
            .zip(self.touch.par_chunks_mut(w))
            .map(|(bits, touch)| MarksRow { bits, touch })
    }

    /// Sets in `out` (resized to these marks) the marked pixels whose tree meets one of the
    /// `wedges` (per ring, in the tracer's order; each list one instant); returns how many.
    /// With the wedges of t₀ and t₁, these are the pixels that may differ between them.
    pub fn select(&self, wedges: [&[Arc]; 2], out: &mut PixelBits) -> u64 {
        out.resize(self.width(), self.height());
        let (stride, w) = (self.bits.stride(), self.width() as usize);
        if stride == 0 {
            return 0;
        }
        out.words_mut()
            .par_chunks_mut(stride)
            .enumerate()
            .map(|(j, row)| {
                let mut n = 0;
                for i in bits::ones(self.bits.row(j as u32)) {
                    let touch = self.touch[j * w + i as usize];
                    let hit = wedges.iter().any(|list| {
                        list.iter().enumerate().any(|(ring, &wedge)| touch.meets_wedge(ring as u32, wedge))
                    });
                    if hit {
                        bits::set(row, i, true);
                        n += 1;
                    }
                }
                n
            })
            .sum()
    }
}
