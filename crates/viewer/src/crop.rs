//! `render --crop X,Y,W,H`: a rectangle of an eye image, so a figure can show a detail (a
//! lighting seam, a silhouette's drag) at the rendered resolution without an image editor.

use std::fmt;
use std::str::FromStr;

/// A rectangle of pixels: its top-left corner (column `x`, row `y`) and its size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crop {
    /// First column.
    pub x: u32,
    /// First row (0 at the top).
    pub y: u32,
    /// Width, > 0.
    pub w: u32,
    /// Height, > 0.
    pub h: u32,
}

impl FromStr for Crop {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        let nums: Option<Vec<u32>> = parts.iter().map(|p| p.parse().ok()).collect();
        match nums.as_deref() {
            Some(&[x, y, w, h]) if w > 0 && h > 0 => Ok(Self { x, y, w, h }),
            _ => Err(format!("`{s}`: expected X,Y,W,H in pixels (whole numbers, W and H > 0)")),
        }
    }
}

impl fmt::Display for Crop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x, self.y, self.w, self.h)
    }
}

impl Crop {
    /// Whether the rectangle lies inside a `width` × `height` image.
    #[must_use]
    pub fn fits(&self, width: u32, height: u32) -> bool {
        u64::from(self.x) + u64::from(self.w) <= u64::from(width)
            && u64::from(self.y) + u64::from(self.h) <= u64::from(height)
    }

    /// The rectangle's pixels of `image` (row-major, `width` wide), which it must fit.
    #[must_use]
    pub fn apply(&self, image: &[u32], width: u32) -> Vec<u32> {
        let (x, w, width) = (self.x as usize, self.w as usize, width as usize);
        (self.y as usize..(self.y + self.h) as usize)
            .flat_map(|row| &image[row * width + x..row * width + x + w])
            .copied()
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_four_whole_numbers() {
        assert_eq!("1,2,3,4".parse(), Ok(Crop { x: 1, y: 2, w: 3, h: 4 }), "X,Y,W,H");
        assert_eq!(" 0, 0 ,8,8".parse::<Crop>().map(|c| c.to_string()), Ok("0,0,8,8".into()), "spaces allowed");
        for bad in ["1,2,3", "1,2,3,4,5", "a,b,c,d", "0,0,0,4", "-1,0,2,2", ""] {
            assert!(bad.parse::<Crop>().is_err(), "{bad:?} is refused");
        }
    }

    #[test]
    fn cuts_the_named_rectangle() {
        // A 4 × 3 image whose pixel value is its index.
        let image: Vec<u32> = (0..12).collect();
        let c = Crop { x: 1, y: 1, w: 2, h: 2 };
        assert!(c.fits(4, 3) && !c.fits(2, 3) && !c.fits(4, 2), "bounds");
        assert_eq!(c.apply(&image, 4), [5, 6, 9, 10], "rows 1–2, columns 1–2");
        assert_eq!(Crop { x: 0, y: 0, w: 4, h: 3 }.apply(&image, 4), image, "the whole image");
    }
}
