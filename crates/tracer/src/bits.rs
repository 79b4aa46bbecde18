//! A bit per pixel, row by row: each row starts on a fresh 64-bit word, so rows can be
//! written in parallel (one `&mut [u64]` per row) and scanned a word at a time.

/// One bit per pixel of a `width` × `height` image, row-major; row j is the words
/// `words[j·stride..(j + 1)·stride]`, pixel i of it bit `i % 64` of word `i / 64`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PixelBits {
    width: u32,
    height: u32,
    stride: usize,
    words: Vec<u64>,
}

impl PixelBits {
    /// All clear, `width` × `height`.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        let mut bits = Self::default();
        bits.resize(width, height);
        bits
    }

    /// Changes the size and clears every bit, reusing the allocation where it is large
    /// enough.
    pub fn resize(&mut self, width: u32, height: u32) {
        (self.width, self.height) = (width, height);
        self.stride = (width as usize).div_ceil(64);
        self.words.clear();
        self.words.resize(self.stride * height as usize, 0);
    }

    /// Makes this a copy of `other`, reusing the allocation.
    pub fn copy_from(&mut self, other: &Self) {
        (self.width, self.height, self.stride) = (other.width, other.height, other.stride);
        self.words.clear();
        self.words.extend_from_slice(&other.words);
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Words per row.
    #[must_use]
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Whether pixel (i, j) is set.
    #[must_use]
    pub fn get(&self, i: u32, j: u32) -> bool {
        get(self.row(j), i)
    }

    /// Whether pixel `k` (a row-major index) is set.
    #[must_use]
    pub fn get_index(&self, k: usize) -> bool {
        let w = self.width as usize;
        self.get((k % w) as u32, (k / w) as u32)
    }

    /// Sets or clears pixel (i, j).
    pub fn set(&mut self, i: u32, j: u32, on: bool) {
        let stride = self.stride;
        set(&mut self.words[j as usize * stride..][..stride], i, on);
    }

    /// Clears every bit.
    pub fn clear(&mut self) {
        self.words.fill(0);
    }

    /// Row j's words.
    #[must_use]
    pub fn row(&self, j: u32) -> &[u64] {
        &self.words[j as usize * self.stride..][..self.stride]
    }

    /// The words, row after row.
    #[must_use]
    pub fn words(&self) -> &[u64] {
        &self.words
    }

    /// The words, row after row, to write (split them by [`PixelBits::stride`]).
    pub fn words_mut(&mut self) -> &mut [u64] {
        &mut self.words
    }

    /// Pixels set.
    #[must_use]
    pub fn count(&self) -> u64 {
        self.words.iter().map(|w| u64::from(w.count_ones())).sum()
    }
}

/// Whether bit i of a row is set.
#[inline]
#[must_use]
pub fn get(row: &[u64], i: u32) -> bool {
    row[i as usize / 64] >> (i % 64) & 1 != 0
}

/// Sets or clears bit i of a row.
#[inline]
pub fn set(row: &mut [u64], i: u32, on: bool) {
    let (word, bit) = (&mut row[i as usize / 64], 1u64 << (i % 64));
    if on {
        *word |= bit;
    } else {
        *word &= !bit;
    }
}

/// The set bits of a row, ascending.
#[must_use]
pub fn ones(row: &[u64]) -> Ones<'_> {
    Ones { row, next: 0, base: 0, bits: 0 }
}

/// The set bits of a row, ascending ([`ones`]).
#[derive(Clone, Debug)]
pub struct Ones<'a> {
    row: &'a [u64],
    /// The next word to load.
    next: usize,
    /// The first pixel of the current word.
    base: u32,
    /// What is left of the current word.
    bits: u64,
}

impl Iterator for Ones<'_> {
    type Item = u32;

    #[inline]
    fn next(&mut self) -> Option<u32> {
        while self.bits == 0 {
            let &word = self.row.get(self.next)?;
            (self.base, self.bits) = (self.next as u32 * 64, word);
            self.next += 1;
        }
        let b = self.bits.trailing_zeros();
        self.bits &= self.bits - 1;
        Some(self.base + b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_land_in_their_row_and_column() {
        let mut bits = PixelBits::new(130, 3);
        assert_eq!(bits.stride(), 3);
        for (i, j) in [(0, 0), (63, 0), (64, 1), (129, 2), (5, 2)] {
            bits.set(i, j, true);
        }
        assert!(bits.get(63, 0) && bits.get(64, 1) && bits.get(129, 2) && !bits.get(64, 0));
        assert!(bits.get_index(2 * 130 + 129));
        assert_eq!(ones(bits.row(0)).collect::<Vec<_>>(), [0, 63]);
        assert_eq!(ones(bits.row(2)).collect::<Vec<_>>(), [5, 129]);
        assert_eq!(bits.count(), 5);
        bits.set(63, 0, false);
        assert_eq!(bits.count(), 4);
        bits.resize(10, 10);
        assert_eq!(bits.count(), 0);
    }
}
