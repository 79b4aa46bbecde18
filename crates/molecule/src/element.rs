//! Chemical elements: symbols, Jmol CPK colours and van der Waals radii.
//!
//! Colours are Jmol's CPK table (<https://jmol.sourceforge.net/jscolors/>), 8-bit sRGB as Jmol
//! lists them; [`Element::linear_colour`] converts them to the linear 0..1 light the scene uses
//! (the IEC 61966-2-1 sRGB transfer function). Jmol colours elements up to Mt (109); later
//! elements and [`Element::UNKNOWN`] take Jmol's colour for an unknown atom, deep pink `FF1493`.
//!
//! Radii are van der Waals radii in Ångström: A. Bondi, "van der Waals Volumes and Radii",
//! J. Phys. Chem. 68 (1964) 441–451, Table I, where Bondi gives one; otherwise S. Alvarez,
//! "A cartography of the van der Waals territories", Dalton Trans. 42 (2013) 8617–8636,
//! Table 1. Elements neither tabulates (Pm, Po to Ra, Fm and later) and the unknown element
//! take [`FALLBACK_RADIUS`], carbon's Bondi radius. [`Element::radius_source`] says which.

use glam::Vec3;

/// The radius, in Ångström, of an element neither Bondi nor Alvarez tabulates and of
/// [`Element::UNKNOWN`]: 1.7 Å, carbon's Bondi radius (most atoms of a biomolecule whose
/// element cannot be told are carbons).
pub const FALLBACK_RADIUS: f32 = 1.70;

/// Jmol's colour for an unknown element, 8-bit sRGB (deep pink, `FF1493`).
pub const UNKNOWN_SRGB: [u8; 3] = [0xFF, 0x14, 0x93];

/// Where an element's radius comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusSource {
    /// Bondi 1964, Table I.
    Bondi1964,
    /// Alvarez 2013, Table 1 (Bondi gives none).
    Alvarez2013,
    /// Neither: [`FALLBACK_RADIUS`].
    Fallback,
}

/// A chemical element, stored as its atomic number in one byte; 0 is [`Element::UNKNOWN`].
///
/// Only 0..=118 can be made, so every lookup is in the table.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Element(u8);

struct Data {
    symbol: &'static [u8],
    srgb: u32,
    radius: f32,
    source: RadiusSource,
}

const fn d(symbol: &'static [u8], srgb: u32, radius: f32, source: RadiusSource) -> Data {
    Data { symbol, srgb, radius, source }
}

use RadiusSource::{Alvarez2013, Bondi1964, Fallback};

/// Indexed by atomic number: symbol, Jmol colour (0xRRGGBB, sRGB), radius (Å), its source.
#[expect(clippy::unreadable_literal, reason = "colours as Jmol's table writes them, RRGGBB")]
const TABLE: [Data; 119] = [
    d(b"Xx", 0xFF1493, FALLBACK_RADIUS, Fallback), // 0
    d(b"H", 0xFFFFFF, 1.20, Bondi1964),            // 1
    d(b"He", 0xD9FFFF, 1.40, Bondi1964),           // 2
    d(b"Li", 0xCC80FF, 1.82, Bondi1964),           // 3
    d(b"Be", 0xC2FF00, 1.98, Alvarez2013),         // 4
    d(b"B", 0xFFB5B5, 1.91, Alvarez2013),          // 5
    d(b"C", 0x909090, 1.70, Bondi1964),            // 6
    d(b"N", 0x3050F8, 1.55, Bondi1964),            // 7
    d(b"O", 0xFF0D0D, 1.52, Bondi1964),            // 8
    d(b"F", 0x90E050, 1.47, Bondi1964),            // 9
    d(b"Ne", 0xB3E3F5, 1.54, Bondi1964),           // 10
    d(b"Na", 0xAB5CF2, 2.27, Bondi1964),           // 11
    d(b"Mg", 0x8AFF00, 1.73, Bondi1964),           // 12
    d(b"Al", 0xBFA6A6, 2.25, Alvarez2013),         // 13
    d(b"Si", 0xF0C8A0, 2.10, Bondi1964),           // 14
    d(b"P", 0xFF8000, 1.80, Bondi1964),            // 15
    d(b"S", 0xFFFF30, 1.80, Bondi1964),            // 16
    d(b"Cl", 0x1FF01F, 1.75, Bondi1964),           // 17
    d(b"Ar", 0x80D1E3, 1.88, Bondi1964),           // 18
    d(b"K", 0x8F40D4, 2.75, Bondi1964),            // 19
    d(b"Ca", 0x3DFF00, 2.62, Alvarez2013),         // 20
    d(b"Sc", 0xE6E6E6, 2.58, Alvarez2013),         // 21
    d(b"Ti", 0xBFC2C7, 2.46, Alvarez2013),         // 22
    d(b"V", 0xA6A6AB, 2.42, Alvarez2013),          // 23
    d(b"Cr", 0x8A99C7, 2.45, Alvarez2013),         // 24
    d(b"Mn", 0x9C7AC7, 2.45, Alvarez2013),         // 25
    d(b"Fe", 0xE06633, 2.44, Alvarez2013),         // 26
    d(b"Co", 0xF090A0, 2.40, Alvarez2013),         // 27
    d(b"Ni", 0x50D050, 1.63, Bondi1964),           // 28
    d(b"Cu", 0xC88033, 1.40, Bondi1964),           // 29
    d(b"Zn", 0x7D80B0, 1.39, Bondi1964),           // 30
    d(b"Ga", 0xC28F8F, 1.87, Bondi1964),           // 31
    d(b"Ge", 0x668F8F, 2.29, Alvarez2013),         // 32
    d(b"As", 0xBD80E3, 1.85, Bondi1964),           // 33
    d(b"Se", 0xFFA100, 1.90, Bondi1964),           // 34
    d(b"Br", 0xA62929, 1.85, Bondi1964),           // 35
    d(b"Kr", 0x5CB8D1, 2.02, Bondi1964),           // 36
    d(b"Rb", 0x702EB0, 3.21, Alvarez2013),         // 37
    d(b"Sr", 0x00FF00, 2.84, Alvarez2013),         // 38
    d(b"Y", 0x94FFFF, 2.75, Alvarez2013),          // 39
    d(b"Zr", 0x94E0E0, 2.52, Alvarez2013),         // 40
    d(b"Nb", 0x73C2C9, 2.56, Alvarez2013),         // 41
    d(b"Mo", 0x54B5B5, 2.45, Alvarez2013),         // 42
    d(b"Tc", 0x3B9E9E, 2.44, Alvarez2013),         // 43
    d(b"Ru", 0x248F8F, 2.46, Alvarez2013),         // 44
    d(b"Rh", 0x0A7D8C, 2.44, Alvarez2013),         // 45
    d(b"Pd", 0x006985, 1.63, Bondi1964),           // 46
    d(b"Ag", 0xC0C0C0, 1.72, Bondi1964),           // 47
    d(b"Cd", 0xFFD98F, 1.58, Bondi1964),           // 48
    d(b"In", 0xA67573, 1.93, Bondi1964),           // 49
    d(b"Sn", 0x668080, 2.17, Bondi1964),           // 50
    d(b"Sb", 0x9E63B5, 2.47, Alvarez2013),         // 51
    d(b"Te", 0xD47A00, 2.06, Bondi1964),           // 52
    d(b"I", 0x940094, 1.98, Bondi1964),            // 53
    d(b"Xe", 0x429EB0, 2.16, Bondi1964),           // 54
    d(b"Cs", 0x57178F, 3.48, Alvarez2013),         // 55
    d(b"Ba", 0x00C900, 3.03, Alvarez2013),         // 56
    d(b"La", 0x70D4FF, 2.98, Alvarez2013),         // 57
    d(b"Ce", 0xFFFFC7, 2.88, Alvarez2013),         // 58
    d(b"Pr", 0xD9FFC7, 2.92, Alvarez2013),         // 59
    d(b"Nd", 0xC7FFC7, 2.95, Alvarez2013),         // 60
    d(b"Pm", 0xA3FFC7, FALLBACK_RADIUS, Fallback), // 61
    d(b"Sm", 0x8FFFC7, 2.90, Alvarez2013),         // 62
    d(b"Eu", 0x61FFC7, 2.87, Alvarez2013),         // 63
    d(b"Gd", 0x45FFC7, 2.83, Alvarez2013),         // 64
    d(b"Tb", 0x30FFC7, 2.79, Alvarez2013),         // 65
    d(b"Dy", 0x1FFFC7, 2.87, Alvarez2013),         // 66
    d(b"Ho", 0x00FF9C, 2.81, Alvarez2013),         // 67
    d(b"Er", 0x00E675, 2.83, Alvarez2013),         // 68
    d(b"Tm", 0x00D452, 2.79, Alvarez2013),         // 69
    d(b"Yb", 0x00BF38, 2.80, Alvarez2013),         // 70
    d(b"Lu", 0x00AB24, 2.74, Alvarez2013),         // 71
    d(b"Hf", 0x4DC2FF, 2.63, Alvarez2013),         // 72
    d(b"Ta", 0x4DA6FF, 2.53, Alvarez2013),         // 73
    d(b"W", 0x2194D6, 2.57, Alvarez2013),          // 74
    d(b"Re", 0x267DAB, 2.49, Alvarez2013),         // 75
    d(b"Os", 0x266696, 2.48, Alvarez2013),         // 76
    d(b"Ir", 0x175487, 2.41, Alvarez2013),         // 77
    d(b"Pt", 0xD0D0E0, 1.75, Bondi1964),           // 78
    d(b"Au", 0xFFD123, 1.66, Bondi1964),           // 79
    d(b"Hg", 0xB8B8D0, 1.55, Bondi1964),           // 80
    d(b"Tl", 0xA6544D, 1.96, Bondi1964),           // 81
    d(b"Pb", 0x575961, 2.02, Bondi1964),           // 82
    d(b"Bi", 0x9E4FB5, 2.54, Alvarez2013),         // 83
    d(b"Po", 0xAB5C00, FALLBACK_RADIUS, Fallback), // 84
    d(b"At", 0x754F45, FALLBACK_RADIUS, Fallback), // 85
    d(b"Rn", 0x428296, FALLBACK_RADIUS, Fallback), // 86
    d(b"Fr", 0x420066, FALLBACK_RADIUS, Fallback), // 87
    d(b"Ra", 0x007D00, FALLBACK_RADIUS, Fallback), // 88
    d(b"Ac", 0x70ABFA, 2.80, Alvarez2013),         // 89
    d(b"Th", 0x00BAFF, 2.93, Alvarez2013),         // 90
    d(b"Pa", 0x00A1FF, 2.88, Alvarez2013),         // 91
    d(b"U", 0x008FFF, 1.86, Bondi1964),            // 92
    d(b"Np", 0x0080FF, 2.82, Alvarez2013),         // 93
    d(b"Pu", 0x006BFF, 2.81, Alvarez2013),         // 94
    d(b"Am", 0x545CF2, 2.83, Alvarez2013),         // 95
    d(b"Cm", 0x785CE3, 3.05, Alvarez2013),         // 96
    d(b"Bk", 0x8A4FE3, 3.40, Alvarez2013),         // 97
    d(b"Cf", 0xA136D4, 3.05, Alvarez2013),         // 98
    d(b"Es", 0xB31FD4, 2.70, Alvarez2013),         // 99
    d(b"Fm", 0xB31FBA, FALLBACK_RADIUS, Fallback), // 100
    d(b"Md", 0xB30DA6, FALLBACK_RADIUS, Fallback), // 101
    d(b"No", 0xBD0D87, FALLBACK_RADIUS, Fallback), // 102
    d(b"Lr", 0xC70066, FALLBACK_RADIUS, Fallback), // 103
    d(b"Rf", 0xCC0059, FALLBACK_RADIUS, Fallback), // 104
    d(b"Db", 0xD1004F, FALLBACK_RADIUS, Fallback), // 105
    d(b"Sg", 0xD90045, FALLBACK_RADIUS, Fallback), // 106
    d(b"Bh", 0xE00038, FALLBACK_RADIUS, Fallback), // 107
    d(b"Hs", 0xE6002E, FALLBACK_RADIUS, Fallback), // 108
    d(b"Mt", 0xEB0026, FALLBACK_RADIUS, Fallback), // 109
    d(b"Ds", 0xFF1493, FALLBACK_RADIUS, Fallback), // 110
    d(b"Rg", 0xFF1493, FALLBACK_RADIUS, Fallback), // 111
    d(b"Cn", 0xFF1493, FALLBACK_RADIUS, Fallback), // 112
    d(b"Nh", 0xFF1493, FALLBACK_RADIUS, Fallback), // 113
    d(b"Fl", 0xFF1493, FALLBACK_RADIUS, Fallback), // 114
    d(b"Mc", 0xFF1493, FALLBACK_RADIUS, Fallback), // 115
    d(b"Lv", 0xFF1493, FALLBACK_RADIUS, Fallback), // 116
    d(b"Ts", 0xFF1493, FALLBACK_RADIUS, Fallback), // 117
    d(b"Og", 0xFF1493, FALLBACK_RADIUS, Fallback), // 118
];

impl Element {
    /// An element the file does not name, or names with a symbol that is not an element.
    pub const UNKNOWN: Self = Self(0);
    /// Hydrogen.
    pub const H: Self = Self(1);
    /// Carbon.
    pub const C: Self = Self(6);
    /// Nitrogen.
    pub const N: Self = Self(7);
    /// Oxygen.
    pub const O: Self = Self(8);
    /// Phosphorus.
    pub const P: Self = Self(15);
    /// Sulfur.
    pub const S: Self = Self(16);
    /// The heaviest element named so far, oganesson (118).
    pub const MAX_ATOMIC_NUMBER: u8 = 118;

    /// The element with atomic number `z`, or `None` above 118. `0` gives [`Element::UNKNOWN`].
    #[must_use]
    pub const fn from_atomic_number(z: u8) -> Option<Self> {
        if z <= Self::MAX_ATOMIC_NUMBER {
            Some(Self(z))
        } else {
            None
        }
    }

    /// The element whose symbol is `symbol`, ignoring ASCII case and surrounding spaces
    /// (`"FE"`, `" C"`, `"cl"`). The hydrogen isotopes `D` and `T` give hydrogen. `None` for
    /// anything else, including `"Xx"` and the empty string.
    #[must_use]
    pub fn from_symbol(symbol: &[u8]) -> Option<Self> {
        let symbol = symbol.trim_ascii();
        match symbol {
            [] => None,
            // The elements of biomolecules first: one byte, no table scan.
            [b'C' | b'c'] => Some(Self::C),
            [b'N' | b'n'] => Some(Self::N),
            [b'O' | b'o'] => Some(Self::O),
            [b'H' | b'h' | b'D' | b'd' | b'T' | b't'] => Some(Self::H),
            [b'S' | b's'] => Some(Self::S),
            [b'P' | b'p'] => Some(Self::P),
            _ => TABLE
                .iter()
                .enumerate()
                .skip(1)
                .find(|(_, data)| data.symbol.eq_ignore_ascii_case(symbol))
                .and_then(|(z, _)| u8::try_from(z).ok())
                .map(Self),
        }
    }

    /// The atomic number; 0 for [`Element::UNKNOWN`].
    #[must_use]
    pub const fn atomic_number(self) -> u8 {
        self.0
    }

    /// Whether this is a real element (not [`Element::UNKNOWN`]).
    #[must_use]
    pub const fn is_known(self) -> bool {
        self.0 != 0
    }

    fn data(self) -> &'static Data {
        // `self.0 <= 118` by construction; the fallback keeps the lookup total all the same.
        TABLE.get(usize::from(self.0)).unwrap_or(&TABLE[0])
    }

    /// The symbol with its usual capitalisation ("C", "Fe"); "Xx" for [`Element::UNKNOWN`].
    #[must_use]
    pub fn symbol(self) -> &'static str {
        std::str::from_utf8(self.data().symbol).unwrap_or("Xx")
    }

    /// The van der Waals radius in Ångström (Bondi 1964, else Alvarez 2013, else
    /// [`FALLBACK_RADIUS`]).
    #[must_use]
    pub fn radius(self) -> f32 {
        self.data().radius
    }

    /// Which table [`Element::radius`] comes from.
    #[must_use]
    pub fn radius_source(self) -> RadiusSource {
        self.data().source
    }

    /// Jmol's CPK colour as 8-bit sRGB, as Jmol's table lists it.
    #[must_use]
    pub fn jmol_srgb(self) -> [u8; 3] {
        let [_, r, g, b] = self.data().srgb.to_be_bytes();
        [r, g, b]
    }

    /// Jmol's CPK colour in linear light, 0..1 per channel, the form scene colours take.
    #[must_use]
    pub fn linear_colour(self) -> Vec3 {
        let [r, g, b] = self.jmol_srgb();
        Vec3::new(srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b))
    }
}

/// The element of an atom name that carries no column alignment (GRO, mmCIF
/// `label_atom_id`): its leading letters after any digits. A two-letter element only when the
/// residue is named the same (a single-atom ion: `NA` in residue `NA`, `CL` in `CL-`);
/// otherwise the first letter (`CA` in `ALA` is carbon, `OW` is oxygen, `HW1` hydrogen); then
/// the two letters (`ZN` in `ZNX`); else [`Element::UNKNOWN`]. This is a fallback, and
/// guesses wrong where the name is ambiguous (`FE` in `HEM` reads as fluorine): mmCIF's
/// `type_symbol` comes first.
#[must_use]
pub(crate) fn element_from_bare_name(name: &[u8], residue: &[u8]) -> Element {
    let letters = |text: &[u8]| -> (usize, usize) {
        let start = text.iter().position(|b| !b.is_ascii_digit() && *b != b' ').unwrap_or(text.len());
        let len = text.get(start..).unwrap_or_default().iter().take_while(|b| b.is_ascii_alphabetic()).count();
        (start, len)
    };
    let (start, len) = letters(name);
    let name = name.get(start..start + len).unwrap_or_default();
    let (r_start, r_len) = letters(residue);
    let residue = residue.get(r_start..r_start + r_len).unwrap_or_default();
    let two = name.get(..2).and_then(Element::from_symbol);
    if name.len() == 2 && name.eq_ignore_ascii_case(residue) {
        if let Some(two) = two {
            return two;
        }
    }
    name.get(..1).and_then(Element::from_symbol).or(two).unwrap_or(Element::UNKNOWN)
}

impl std::fmt::Display for Element {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.symbol())
    }
}

/// An 8-bit sRGB channel in linear light (IEC 61966-2-1): c/12.92 up to 0.04045, else
/// ((c + 0.055)/1.055)^2.4.
#[must_use]
pub fn srgb_to_linear(channel: u8) -> f32 {
    let c = f32::from(channel) / 255.0;
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbols_round_trip_for_every_element() {
        for z in 1..=Element::MAX_ATOMIC_NUMBER {
            let e = Element::from_atomic_number(z).unwrap();
            assert_eq!(Element::from_symbol(e.symbol().as_bytes()), Some(e), "symbol {} of Z={z}", e.symbol());
            let upper = e.symbol().to_ascii_uppercase();
            assert_eq!(Element::from_symbol(upper.as_bytes()), Some(e), "upper-case {upper}");
        }
        assert_eq!(Element::from_atomic_number(119), None, "no element 119 yet");
        assert_eq!(Element::from_symbol(b"Xx"), None, "Xx is the unknown element's name, not a symbol");
        assert_eq!(Element::from_symbol(b"  "), None, "blank is no symbol");
        assert_eq!(Element::from_symbol(b"D"), Some(Element::H), "deuterium is hydrogen");
        assert_eq!(Element::from_symbol(b" FE").map(Element::atomic_number), Some(26), "PDB columns 77-78");
    }

    #[test]
    fn bare_names_give_the_first_letter_unless_the_residue_is_the_ion() {
        let e = |name: &[u8], residue: &[u8]| element_from_bare_name(name, residue).symbol();
        assert_eq!(e(b"CA", b"ALA"), "C", "C-alpha");
        assert_eq!(e(b"CA", b"CA"), "Ca", "calcium ion");
        assert_eq!(e(b"NA", b"NA+"), "Na", "sodium ion, charge in the residue name");
        assert_eq!(e(b"  OW", b"SOL"), "O", "water oxygen");
        assert_eq!(e(b"HW1", b"SOL"), "H", "water hydrogen");
        assert_eq!(e(b"1HB", b"ALA"), "H", "leading digits");
        assert_eq!(e(b"ZN", b"ZN"), "Zn", "zinc ion");
        assert_eq!(e(b"ZN", b"ZNX"), "Zn", "no one-letter Z: the two letters");
        // The documented limit: without a residue named like it, FE reads as fluorine.
        assert_eq!(e(b"FE", b"HEM"), "F", "heme iron needs the file's element column");
        assert_eq!(e(b"XQ", b"UNK"), "Xx", "nothing known");
        assert_eq!(e(b"", b""), "Xx", "empty");
    }

    #[test]
    fn radii_are_bondi_first_then_alvarez() {
        let r = |s: &str| Element::from_symbol(s.as_bytes()).unwrap().radius();
        // Bondi 1964, Table I.
        assert_eq!(r("H"), 1.20, "H");
        assert_eq!(r("C"), 1.70, "C");
        assert_eq!(r("N"), 1.55, "N");
        assert_eq!(r("O"), 1.52, "O");
        assert_eq!(r("S"), 1.80, "S");
        assert_eq!(r("Br"), 1.85, "Br");
        assert_eq!(r("Hg"), 1.55, "Hg");
        // Alvarez 2013, where Bondi gives none.
        assert_eq!(r("Fe"), 2.44, "Fe");
        assert_eq!(r("Ca"), 2.62, "Ca");
        assert_eq!(r("Mn"), 2.45, "Mn");
        assert_eq!(Element::from_symbol(b"Fe").unwrap().radius_source(), RadiusSource::Alvarez2013, "Fe source");
        assert_eq!(Element::C.radius_source(), RadiusSource::Bondi1964, "C source");
        assert_eq!(r("Po"), FALLBACK_RADIUS, "Po: in neither table");
        assert_eq!(Element::UNKNOWN.radius(), FALLBACK_RADIUS, "unknown");
        for z in 0..=Element::MAX_ATOMIC_NUMBER {
            let e = Element::from_atomic_number(z).unwrap();
            assert!((1.0..=3.5).contains(&e.radius()), "{e} radius {} out of the tables' range", e.radius());
            let fallback = e.radius_source() == RadiusSource::Fallback;
            assert_eq!(fallback, e.radius() == FALLBACK_RADIUS && !matches!(e.symbol(), "C"), "{e} source");
        }
    }

    #[test]
    fn jmol_colours_and_their_linear_form() {
        assert_eq!(Element::C.jmol_srgb(), [0x90, 0x90, 0x90], "C");
        assert_eq!(Element::O.jmol_srgb(), [0xFF, 0x0D, 0x0D], "O");
        assert_eq!(Element::N.jmol_srgb(), [0x30, 0x50, 0xF8], "N");
        assert_eq!(Element::S.jmol_srgb(), [0xFF, 0xFF, 0x30], "S");
        assert_eq!(Element::from_symbol(b"Fe").unwrap().jmol_srgb(), [0xE0, 0x66, 0x33], "Fe");
        assert_eq!(Element::UNKNOWN.jmol_srgb(), UNKNOWN_SRGB, "unknown");
        assert_eq!(Element::H.linear_colour(), Vec3::ONE, "white stays white");
        // 0x90 = 144: (144/255 + 0.055)/1.055 = 0.5874, ^2.4 = 0.2789.
        let c = Element::C.linear_colour();
        assert!((c.x - 0.278_894).abs() < 1e-5, "carbon grey in linear light: {c}");
        assert_eq!(srgb_to_linear(0), 0.0, "black");
        assert!((srgb_to_linear(10) - 10.0 / 255.0 / 12.92).abs() < 1e-9, "the linear toe");
    }
}
