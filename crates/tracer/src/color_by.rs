//! The colour schemes of a structure's atoms (`--color`, `structures[].color_by`) and the
//! atoms a scene can hide (`--hide`): their names, and the colour each scheme gives an atom.
//!
//! Sources of the palettes:
//! - `element`: Jmol's CPK colours (`molecule::Element::linear_colour`);
//! - `chain`: Kelly's 22 colours of maximum contrast (K. L. Kelly, "Twenty-two colors of
//!   maximum contrast", Color Engineering 3(6), 1965) without white and black: 20 colours,
//!   given to the chains in the order their first atom comes (chain `k` of the file takes
//!   colour `k mod 20`), so a chain's colour is stable for a file;
//! - `residue`: RasMol's "shapely" scheme (RasMol 2.6 `transfor.c`, tabulated in E. Martz,
//!   "RasMol/Chime Color RGB Values", <https://www.umass.edu/microbio/rasmol/rascolor.htm>);
//! - `plddt`: AlphaFold DB's four confidence bands and colours (<https://alphafold.ebi.ac.uk>);
//! - `bfactor` blue–white–red and `rainbow` blue to red (hue 240° to 0°), each quantised to
//!   [`STEPS`] steps, so that a structure keeps at most 256 kinds of atom.
//!
//! Colours are given in sRGB bytes, as their sources give them, and used in linear light.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;
use molecule::srgb_to_linear;

/// How a structure's atoms are coloured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ColorBy {
    /// Jmol's CPK colour of the atom's element (the default).
    #[default]
    Element,
    /// One colour per chain.
    Chain,
    /// RasMol's shapely colour of the residue.
    Residue,
    /// Blue–white–red over the B-factors' range (or a given one).
    BFactor,
    /// AlphaFold's pLDDT bands, read from the B-factor column.
    Plddt,
    /// Blue to red from the N to the C terminus of each chain, by residue number.
    Rainbow,
    /// Ligands and waters by element, the polymer one neutral grey.
    Hetero,
}

impl ColorBy {
    /// Every scheme, in the order the C key cycles them.
    pub const ALL: [ColorBy; 7] = [
        ColorBy::Element,
        ColorBy::Chain,
        ColorBy::Residue,
        ColorBy::BFactor,
        ColorBy::Plddt,
        ColorBy::Rainbow,
        ColorBy::Hetero,
    ];

    /// The scheme's name, as `--color` takes it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ColorBy::Element => "element",
            ColorBy::Chain => "chain",
            ColorBy::Residue => "residue",
            ColorBy::BFactor => "bfactor",
            ColorBy::Plddt => "plddt",
            ColorBy::Rainbow => "rainbow",
            ColorBy::Hetero => "hetero",
        }
    }

    /// The scheme after this one in [`ColorBy::ALL`], wrapping round.
    #[must_use]
    pub fn next(self) -> Self {
        let k = Self::ALL.iter().position(|&c| c == self).unwrap_or(0);
        Self::ALL[(k + 1) % Self::ALL.len()]
    }
}

impl fmt::Display for ColorBy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ColorBy {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL.into_iter().find(|c| c.name() == s).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|c| c.name()).collect();
            format!("unknown colour scheme `{s}`: expected one of {}", names.join(", "))
        })
    }
}

/// A scheme and the B-factor range `bfactor` spans (`None`: the file's own).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Coloring {
    /// The scheme.
    pub by: ColorBy,
    /// `--color-range A,B` (A < B), for `bfactor`.
    pub range: Option<(f32, f32)>,
}

/// `A,B`: two finite numbers, A < B.
///
/// # Errors
/// A message naming the value when it is not that.
pub fn parse_color_range(s: &str) -> Result<(f32, f32), String> {
    let bad = || format!("`{s}`: expected two finite numbers A,B with A < B (a B-factor range, e.g. 0,100)");
    let (a, b) = s.split_once(',').ok_or_else(bad)?;
    let (a, b): (f32, f32) = (a.trim().parse().map_err(|_| bad())?, b.trim().parse().map_err(|_| bad())?);
    if a.is_finite() && b.is_finite() && a < b {
        Ok((a, b))
    } else {
        Err(bad())
    }
}

/// Which atoms are out of the scene (`--hide water,hydrogen,hetero`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Hide {
    /// Residues HOH, WAT, H2O, DOD, SOL, TIP3.
    pub water: bool,
    /// Element H (and D, which the readers read as H).
    pub hydrogen: bool,
    /// HETATM records (ligands, ions, waters).
    pub hetero: bool,
}

/// The residue names of water.
pub const WATER_NAMES: [&str; 6] = ["HOH", "WAT", "H2O", "DOD", "SOL", "TIP3"];

impl Hide {
    /// Whether nothing is hidden.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self == Self::default()
    }
}

impl FromStr for Hide {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let mut hide = Hide::default();
        for item in s.split(',').map(str::trim) {
            match item {
                "water" => hide.water = true,
                "hydrogen" => hide.hydrogen = true,
                "hetero" => hide.hetero = true,
                _ => return Err(format!("unknown item `{item}` in `{s}`: expected water, hydrogen or hetero")),
            }
        }
        Ok(hide)
    }
}

/// The number of colours a continuous scheme (`bfactor`, `rainbow`) is quantised to.
pub const STEPS: u8 = 32;

/// sRGB bytes to linear light.
fn linear([r, g, b]: [u8; 3]) -> Vec3 {
    Vec3::new(srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b))
}

/// Kelly's colours of maximum contrast, white and black left out (see the module doc).
const KELLY: [[u8; 3]; 20] = [
    [0xF3, 0xC3, 0x00], // yellow
    [0x87, 0x56, 0x92], // purple
    [0xF3, 0x84, 0x00], // orange
    [0xA1, 0xCA, 0xF1], // light blue
    [0xBE, 0x00, 0x32], // red
    [0xC2, 0xB2, 0x80], // buff
    [0x84, 0x84, 0x82], // grey
    [0x00, 0x88, 0x56], // green
    [0xE6, 0x8F, 0xAC], // purplish pink
    [0x00, 0x67, 0xA5], // blue
    [0xF9, 0x93, 0x79], // yellowish pink
    [0x60, 0x4E, 0x97], // violet
    [0xF6, 0xA6, 0x00], // orange yellow
    [0xB3, 0x44, 0x6C], // purplish red
    [0xDC, 0xD3, 0x00], // greenish yellow
    [0x88, 0x2D, 0x17], // reddish brown
    [0x8D, 0xB6, 0x00], // yellow green
    [0x65, 0x45, 0x22], // yellowish brown
    [0xE2, 0x58, 0x22], // reddish orange
    [0x2B, 0x3D, 0x26], // olive green
];

/// The number of chain colours.
pub const CHAIN_COLOURS: usize = KELLY.len();

/// Chain `k`'s colour (chains numbered in the order their first atom comes).
#[must_use]
pub fn chain_colour(k: usize) -> Vec3 {
    linear(KELLY[k % KELLY.len()])
}

/// RasMol's shapely colours, by residue name; [`SHAPELY_OTHER`] for the rest.
const SHAPELY: [(&str, [u8; 3]); 29] = [
    ("ALA", [140, 255, 140]),
    ("ARG", [0, 0, 124]),
    ("ASN", [255, 124, 112]),
    ("ASP", [160, 0, 66]),
    ("CYS", [255, 255, 112]),
    ("GLN", [255, 76, 76]),
    ("GLU", [102, 0, 0]),
    ("GLY", [255, 255, 255]),
    ("HIS", [112, 112, 255]),
    ("ILE", [0, 76, 0]),
    ("LEU", [69, 94, 69]),
    ("LYS", [71, 71, 184]),
    ("MET", [184, 160, 66]),
    ("PHE", [83, 76, 66]),
    ("PRO", [82, 82, 82]),
    ("SER", [255, 112, 66]),
    ("THR", [184, 76, 0]),
    ("TRP", [79, 70, 0]),
    ("TYR", [140, 112, 76]),
    ("VAL", [255, 140, 255]),
    ("ASX", [255, 0, 255]),
    ("GLX", [255, 0, 255]),
    ("A", [160, 160, 255]),
    ("C", [255, 140, 75]),
    ("G", [255, 112, 112]),
    ("T", [160, 255, 160]),
    ("U", [184, 184, 184]),
    ("DA", [160, 160, 255]),
    ("DC", [255, 140, 75]),
];

/// Shapely's colour of residues it does not list.
const SHAPELY_OTHER: [u8; 3] = [255, 0, 255];

/// Residue `name`'s shapely colour (DNA's DG and DT as G and T).
#[must_use]
pub fn residue_colour(name: &str) -> Vec3 {
    shapely_colour(usize::from(shapely_slot(name)))
}

/// Residue `name`'s entry in the shapely table; one past its end for residues it lacks.
pub(crate) fn shapely_slot(name: &str) -> u16 {
    let name = match name {
        "DG" => "G",
        "DT" => "T",
        n => n,
    };
    SHAPELY.iter().position(|(n, _)| *n == name).unwrap_or(SHAPELY.len()) as u16
}

/// The colour of entry `slot` of the shapely table (past its end: shapely's "other").
pub(crate) fn shapely_colour(slot: usize) -> Vec3 {
    linear(SHAPELY.get(slot).map_or(SHAPELY_OTHER, |&(_, c)| c))
}

/// AlphaFold DB's pLDDT bands: very high (> 90), confident (70–90), low (50–70), very low
/// (< 50).
pub const PLDDT_SRGB: [[u8; 3]; 4] = [[0x00, 0x53, 0xD6], [0x65, 0xCB, 0xF3], [0xFF, 0xDB, 0x13], [0xFF, 0x7D, 0x45]];

/// The band of a pLDDT (0 very high … 3 very low); 90 is confident, 70 low, 50 very low.
#[must_use]
pub fn plddt_band(plddt: f32) -> usize {
    if plddt > 90.0 {
        0
    } else if plddt > 70.0 {
        1
    } else if plddt > 50.0 {
        2
    } else {
        3
    }
}

/// The band's colour.
#[must_use]
pub fn plddt_colour(band: usize) -> Vec3 {
    linear(PLDDT_SRGB[band.min(3)])
}

/// Step `s` of [`STEPS`] of blue–white–red: blue at 0, white half-way, red at the last.
#[must_use]
pub fn blue_white_red(s: u8) -> Vec3 {
    let x = f32::from(s.min(STEPS - 1)) / f32::from(STEPS - 1);
    // Interpolated in sRGB, as the viewers' ramps are, then to linear light.
    let srgb = if x < 0.5 { Vec3::new(2.0 * x, 2.0 * x, 1.0) } else { Vec3::new(1.0, 2.0 - 2.0 * x, 2.0 - 2.0 * x) };
    linear(to_bytes(srgb))
}

/// Step `s` of [`STEPS`] of the rainbow: hue 240° (blue) at 0 to 0° (red) at the last.
#[must_use]
pub fn rainbow(s: u8) -> Vec3 {
    let x = f32::from(s.min(STEPS - 1)) / f32::from(STEPS - 1);
    let h = (1.0 - x) * 4.0; // hue in sextants, 4 = blue
    let c = 1.0 - (h % 2.0 - 1.0).abs();
    let srgb = match h as u8 {
        0 => Vec3::new(1.0, c, 0.0),
        1 => Vec3::new(c, 1.0, 0.0),
        2 => Vec3::new(0.0, 1.0, c),
        3 => Vec3::new(0.0, c, 1.0),
        _ => Vec3::new(0.0, 0.0, 1.0),
    };
    linear(to_bytes(srgb))
}

/// A value in `[lo, hi]` as one of [`STEPS`] steps (clamped; 0 when the range is empty).
#[must_use]
pub fn step(value: f32, (lo, hi): (f32, f32)) -> u8 {
    if hi <= lo || !value.is_finite() {
        return if value >= hi && hi > lo { STEPS - 1 } else { 0 };
    }
    let x = ((value - lo) / (hi - lo)).clamp(0.0, 1.0);
    (x * f32::from(STEPS - 1)).round() as u8
}

fn to_bytes(c: Vec3) -> [u8; 3] {
    let b = (c.clamp(Vec3::ZERO, Vec3::ONE) * 255.0).round();
    [b.x as u8, b.y as u8, b.z as u8]
}

/// The polymer's colour under `hetero`: a neutral light grey.
#[must_use]
pub fn polymer_grey() -> Vec3 {
    linear([0xB4, 0xB4, 0xB4])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_bad_ones_are_named() {
        for c in ColorBy::ALL {
            assert_eq!(c.name().parse::<ColorBy>(), Ok(c));
        }
        assert_eq!(ColorBy::Hetero.next(), ColorBy::Element);
        assert!("chian".parse::<ColorBy>().unwrap_err().contains("`chian`"));
        assert_eq!("water, hydrogen".parse::<Hide>(), Ok(Hide { water: true, hydrogen: true, hetero: false }));
        assert!("water,ions".parse::<Hide>().unwrap_err().contains("`ions`"));
        assert_eq!(parse_color_range("0, 100"), Ok((0.0, 100.0)));
        for bad in ["1", "2,1", "a,b", "0,inf", "1,1"] {
            assert!(parse_color_range(bad).unwrap_err().contains(bad), "{bad}");
        }
    }

    #[test]
    fn the_ramps_run_blue_to_red() {
        assert_eq!(blue_white_red(0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(blue_white_red(STEPS - 1), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(rainbow(0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(rainbow(STEPS - 1), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(step(5.0, (0.0, 10.0)), 16);
        assert_eq!(step(-1.0, (0.0, 10.0)), 0);
        assert_eq!(step(11.0, (0.0, 10.0)), STEPS - 1);
        assert_eq!([95.0, 90.0, 80.0, 70.0, 60.0, 50.0, 10.0].map(plddt_band), [0, 1, 1, 2, 2, 3, 3]);
    }
}
