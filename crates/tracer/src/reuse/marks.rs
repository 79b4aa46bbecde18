//! Per-pixel marks of where each pixel's ray tree meets the moving spheres' swept volumes
//! (`swept.rs`): a bit per pixel (set: the tree meets some volume) for fast scans, and the
//! [`Touch`] (which ring, which arc of it) of the marked pixels. After a frame at t₀, the
//! pixels that can differ at t₁ are the marked ones whose touch meets a moving sphere's
//! wedge at t₀ or at t₁ ([`Marks::select`]). So that `select` need not test every mark each
//! frame, the marks keep an index, `near`: the pixels that may meet a window about each
//! ring's wedges, rebuilt when the wedges leave it. Why the index selects exactly what a scan
//! of every mark would: `docs/design/reuse-exactness.md`.

use rayon::prelude::*;

use super::swept::{Arc, Touch};
use crate::bits::{self, PixelBits};

/// The marks of a `width` × `height` image (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct Marks {
    bits: PixelBits,
    /// Per pixel, row-major; meaningful where the bit is set ([`Touch::NONE`] elsewhere).
    touch: Vec<Touch>,
    /// The pixels that may meet a window (the module doc).
    near: PixelBits,
    /// Per ring, the window `near` was built for; empty when it must be built again.
    windows: Vec<Arc>,
    /// Per ring, the arc that holds its wedges of a `select` (kept for its allocation).
    wanted: Vec<Arc>,
}

/// What a pass over the rows of [`Marks`] may change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rewrite {
    /// Every pixel: the next [`Marks::select`] builds its index again.
    All,
    /// A few pixels, such as those [`Marks::select`] chose: its index is kept.
    Few,
}

/// One row of [`Marks`], to write.
#[derive(Debug)]
pub struct MarksRow<'a> {
    /// The row's bits.
    bits: &'a mut [u64],
    /// The row's touches.
    touch: &'a mut [Touch],
    /// The row of the index.
    near: &'a mut [u64],
}

/// A band of rows of [`Marks`], to write one row after another ([`Marks::bands_mut`]).
#[derive(Debug)]
pub struct MarksBand<'a> {
    bits: &'a mut [u64],
    touch: &'a mut [Touch],
    near: &'a mut [u64],
    /// Words per row of `bits` and `near`.
    stride: usize,
    /// Pixels per row of `touch`.
    width: usize,
}

impl MarksBand<'_> {
    /// The band's rows, top to bottom.
    pub fn rows(&mut self) -> impl Iterator<Item = MarksRow<'_>> {
        let bits = self.bits.chunks_mut(self.stride);
        let near = self.near.chunks_mut(self.stride);
        bits.zip(self.touch.chunks_mut(self.width)).zip(near).map(|((bits, touch), near)| MarksRow {
            bits,
            touch,
            near,
        })
    }
}

impl MarksRow<'_> {
    /// Pixel `i`'s tree meets the swept volumes as `touch` says.
    #[inline]
    pub fn set(&mut self, i: u32, touch: Touch) {
        let marked = touch.is_some();
        bits::set(self.bits, i, marked);
        if marked {
            bits::set(self.near, i, true);
        }
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
        self.near.resize(width, height);
        self.windows.clear();
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

    /// The rows, to write in parallel, by a pass that changes what `rewrite` says.
    pub fn rows_mut(&mut self, rewrite: Rewrite) -> impl IndexedParallelIterator<Item = MarksRow<'_>> {
        if rewrite == Rewrite::All {
            self.windows.clear();
        }
        let (stride, w) = (self.bits.stride().max(1), (self.bits.width() as usize).max(1));
        let bits = self.bits.words_mut().par_chunks_mut(stride);
        let near = self.near.words_mut().par_chunks_mut(stride);
        (bits, self.touch.par_chunks_mut(w), near).into_par_iter().map(|(bits, touch, near)| MarksRow {
            bits,
            touch,
            near,
        })
    }

    /// The rows in bands of `rows` (the last band may be short), to write in parallel, by a
    /// pass that changes what `rewrite` says: [`Marks::rows_mut`] for a pass that works a
    /// band of rows at a time.
    pub fn bands_mut(&mut self, rewrite: Rewrite, rows: usize) -> impl IndexedParallelIterator<Item = MarksBand<'_>> {
        if rewrite == Rewrite::All {
            self.windows.clear();
        }
        let (stride, w, rows) = (self.bits.stride().max(1), (self.bits.width() as usize).max(1), rows.max(1));
        let bits = self.bits.words_mut().par_chunks_mut(stride * rows);
        let near = self.near.words_mut().par_chunks_mut(stride * rows);
        (bits, self.touch.par_chunks_mut(w * rows), near).into_par_iter().map(move |(bits, touch, near)| MarksBand {
            bits,
            touch,
            near,
            stride,
            width: w,
        })
    }

    /// Sets in `out` (resized to these marks) the marked pixels whose tree meets one of the
    /// `wedges` (per ring, in the tracer's order; each list one instant); returns how many.
    /// With the wedges of t₀ and t₁, these are the pixels that may differ between them.
    ///
    /// Only the pixels of the index are tested, unless the wedges have left its windows;
    /// then every marked pixel is, and the index is built again (the module doc).
    pub fn select(&mut self, wedges: [&[Arc]; 2], out: &mut PixelBits) -> u64 {
        out.resize(self.width(), self.height());
        if self.bits.stride() == 0 {
            return 0;
        }
        // Per ring, the arc that holds its wedges.
        let rings = wedges[0].len().max(wedges[1].len());
        self.wanted.clear();
        let held = |r: usize| wedges.iter().filter_map(|list| list.get(r).copied()).reduce(Arc::hull);
        self.wanted.extend((0..rings).map(|r| held(r).unwrap_or(Arc::FULL)));
        let inside = self.windows.len() == rings && self.windows.iter().zip(&self.wanted).all(|(w, a)| w.holds(*a));
        if inside {
            return self.select_near(wedges, out);
        }
        // Each window several frames' motion wide: the wanted arc, grown by its length
        // (two frames' wedges, so at least one frame's motion) at both ends.
        self.windows.clear();
        self.windows.extend(self.wanted.iter().map(|a| a.grown(a.len)));
        self.build_and_select(wedges, out)
    }

    /// [`Marks::select`] over the index.
    fn select_near(&self, wedges: [&[Arc]; 2], out: &mut PixelBits) -> u64 {
        let stride = self.bits.stride();
        let w = self.width() as usize;
        out.words_mut()
            .par_chunks_mut(stride)
            .enumerate()
            .map(|(j, row)| {
                let mut n = 0;
                for i in bits::ones(self.near.row(j as u32)) {
                    if meets_any(self.touch[j * w + i as usize], wedges) {
                        bits::set(row, i, true);
                        n += 1;
                    }
                }
                n
            })
            .sum()
    }

    /// [`Marks::select`] over every marked pixel, building the index for the windows.
    fn build_and_select(&mut self, wedges: [&[Arc]; 2], out: &mut PixelBits) -> u64 {
        let stride = self.bits.stride();
        let w = self.width() as usize;
        let (bits, touches, windows) = (&self.bits, &self.touch, &self.windows[..]);
        let rows = out.words_mut().par_chunks_mut(stride).zip(self.near.words_mut().par_chunks_mut(stride));
        rows.enumerate()
            .map(|(j, (row, near))| {
                near.fill(0);
                let mut n = 0;
                for i in bits::ones(bits.row(j as u32)) {
                    let touch = touches[j * w + i as usize];
                    if meets_any(touch, [windows, &[]]) {
                        bits::set(near, i, true);
                        if meets_any(touch, wedges) {
                            bits::set(row, i, true);
                            n += 1;
                        }
                    }
                }
                n
            })
            .sum()
    }
}

/// Whether `touch` meets one of the `wedges` (as in [`Marks::select`]).
#[inline]
fn meets_any(touch: Touch, wedges: [&[Arc]; 2]) -> bool {
    wedges.iter().any(|list| list.iter().enumerate().any(|(ring, &wedge)| touch.meets_wedge(ring as u32, wedge)))
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    /// A hash of a pixel, a frame and the seed: the test's source of touches.
    fn mix(seed: u64, i: u32, j: u32, frame: u32) -> u64 {
        let mut x = seed ^ (u64::from(i) << 40) ^ (u64::from(j) << 20) ^ u64::from(frame);
        for _ in 0..3 {
            x = (x ^ (x >> 31)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        }
        x
    }

    /// A touch of `rings` rings: none, several, or an arc of one (short ones mostly).
    fn touch_of(x: u64, rings: u32) -> Touch {
        let arc = Arc { start: (x >> 32) as u32, len: ((x >> 8) as u32) >> (x % 9) };
        match x % 8 {
            0 | 1 => Touch::NONE,
            2 if x.is_multiple_of(5) => Touch { ring: Touch::MANY_RINGS, arc: Arc::FULL },
            _ => Touch { ring: (x >> 16) as u32 % rings, arc },
        }
    }

    /// What [`Marks::select`] must give: every marked pixel tested.
    fn scan(marks: &Marks, wedges: [&[Arc]; 2]) -> PixelBits {
        let mut out = PixelBits::new(marks.width(), marks.height());
        for j in 0..marks.height() {
            for i in bits::ones(marks.bits().row(j)) {
                let k = (j * marks.width() + i) as usize;
                out.set(i, j, meets_any(marks.touch(k), wedges));
            }
        }
        out
    }

    /// Rewrites the pixels for which `chosen` holds (all of them with [`Rewrite::All`]).
    fn rewrite(
        marks: &mut Marks,
        how: Rewrite,
        (seed, frame, rings): (u64, u32, u32),
        chosen: impl Fn(u32, u32) -> bool + Sync,
    ) {
        let w = marks.width();
        marks.rows_mut(how).enumerate().for_each(|(j, mut row)| {
            let j = j as u32;
            for i in (0..w).filter(|&i| how == Rewrite::All || chosen(i, j)) {
                row.set(i, touch_of(mix(seed, i, j, frame), rings));
            }
        });
    }

    proptest! {
        #[test]
        fn the_index_selects_what_a_scan_of_every_mark_selects(
            (w, h) in (1u32..140, 1u32..5),
            seed in any::<u64>(),
            rings in 1u32..4,
            wedge_len in 0u32..1 << 30,
            steps in prop::collection::vec(prop_oneof![4 => 0u32..1 << 26, 1 => any::<u32>()], 1..24),
        ) {
            let mut marks = Marks::new(w, h);
            rewrite(&mut marks, Rewrite::All, (seed, 0, rings), |_, _| true);
            let mut wedges: Vec<Arc> = (0..rings).map(|r| Arc { start: r << 30, len: wedge_len }).collect();
            let mut out = PixelBits::default();
            for (frame, &step) in (1..).zip(&steps) {
                let next: Vec<Arc> = wedges.iter().map(|a| Arc { start: a.start.wrapping_add(step), len: a.len }).collect();
                let n = marks.select([&wedges, &next], &mut out);
                let want = scan(&marks, [&wedges, &next]);
                prop_assert_eq!(&out, &want, "frame {}", frame);
                prop_assert_eq!(n, want.count());
                // Retrace what was chosen, and now and then some other pixel or all of them.
                let how = if mix(seed, 0, 0, frame).is_multiple_of(7) { Rewrite::All } else { Rewrite::Few };
                let chosen = |i, j| out.get(i, j) || mix(seed, i, j, !frame).is_multiple_of(13);
                rewrite(&mut marks, how, (seed, frame, rings), chosen);
                wedges = next;
            }
        }
    }

    #[test]
    fn bands_hold_the_rows_in_order() {
        use std::sync::atomic::{AtomicU32, Ordering};
        // Rows of two words, and a short last band.
        let (w, h) = (70, 11);
        let (mut by_rows, mut by_bands) = (Marks::new(w, h), Marks::new(w, h));
        rewrite(&mut by_rows, Rewrite::All, (9, 1, 3), |_, _| true);
        for rows in [1, 3, 4, 11, 20] {
            let counted: Vec<AtomicU32> = (0..h).map(|_| AtomicU32::new(0)).collect();
            by_bands.bands_mut(Rewrite::All, rows).enumerate().for_each(|(b, mut band)| {
                for (k, mut row) in band.rows().enumerate() {
                    let j = (b * rows + k) as u32;
                    for i in 0..w {
                        row.set(i, touch_of(mix(9, i, j, 1), 3));
                    }
                    counted[j as usize].fetch_add(1, Ordering::Relaxed);
                }
            });
            assert!(counted.iter().all(|n| n.load(Ordering::Relaxed) == 1), "{rows} rows a band: each row once");
            assert_eq!(by_bands.bits(), by_rows.bits(), "{rows} rows a band");
            assert_eq!(by_bands.touch, by_rows.touch, "{rows} rows a band");
            by_bands = Marks::new(w, h);
        }
    }

    #[test]
    fn an_arc_holds_what_lies_in_it_and_grows_to_the_whole_circle() {
        let a = Arc { start: u32::MAX - 10, len: 20 };
        assert!(a.holds(Arc { start: u32::MAX - 10, len: 20 }) && a.holds(Arc { start: 2, len: 7 }));
        assert!(!a.holds(Arc { start: 2, len: 8 }) && !a.holds(Arc { start: u32::MAX - 11, len: 1 }));
        assert!(Arc::FULL.holds(a) && !a.holds(Arc::FULL));
        assert_eq!(a.grown(5), Arc { start: u32::MAX - 15, len: 30 });
        assert_eq!(a.grown(u32::MAX / 2), Arc::FULL);
    }
}
