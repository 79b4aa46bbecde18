//! Which reprojected pixels are still sent to retrace: object edges and shadow boundaries.
//!
//! A reprojected pixel whose source object differs from a 4-neighbour's sits on a
//! silhouette, where the right pixel-centre ray may see another object than the reprojected
//! sample ("drag" in the seed paper). One whose per-light visibility differs from a
//! neighbour's sits on a shadow edge (or a terminator), where reusing visibility from the
//! left hit may be wrong for the right pixel centre. A pixel next to a gap is an edge too:
//! a gap is a depth discontinuity (a disocclusion or a stretched surface), and the surface
//! just past it may be seen by the right pixel-centre ray while its reprojected sample is
//! the background or another object (a near sphere's silhouette moves by a different
//! amount than the background behind it).
//!
//! The pass reads one compact 8-byte key per right pixel (object id and light bits of its
//! source, gathered during reprojection), never the left eye's full records.

use crate::stats::PixelClass;

/// Key of a right pixel that no left pixel fills.
pub(crate) const GAP_KEY: u64 = u64::MAX;

/// The key of a reprojected sample: object id in the high half, light bits in the low half.
#[inline]
pub(crate) fn key(object: u32, lights: u32) -> u64 {
    (u64::from(object) << 32) | u64::from(lights)
}

/// Classifies right row `j` from the key plane `keys` (whole image, row-major, `w` wide)
/// into `out` (this row only).
pub(crate) fn classify_row(keys: &[u64], w: usize, j: usize, edges: bool, shadows: bool, out: &mut [PixelClass]) {
    let h = keys.len() / w;
    let row = &keys[j * w..(j + 1) * w];
    let above = if j > 0 { &keys[(j - 1) * w..j * w] } else { row };
    let below = if j + 1 < h { &keys[(j + 1) * w..(j + 2) * w] } else { row };
    // Bits that must agree with a neighbour: the object (edges) and/or the lights (shadows).
    let object_bits = if edges { 0xFFFF_FFFF_0000_0000 } else { 0 };
    let light_bits = if shadows { 0x0000_0000_FFFF_FFFF } else { 0 };
    for (i, class) in out.iter_mut().enumerate() {
        let me = row[i];
        if me == GAP_KEY {
            *class = PixelClass::RetracedGap;
            continue;
        }
        let left = if i > 0 { row[i - 1] } else { me };
        let right = if i + 1 < w { row[i + 1] } else { me };
        let (mut edge, mut shadow) = (false, false);
        for n in [left, right, above[i], below[i]] {
            if n == GAP_KEY {
                edge |= edges;
            } else {
                let diff = n ^ me;
                edge |= diff & object_bits != 0;
                shadow |= diff & light_bits != 0;
            }
        }
        *class = if edge {
            PixelClass::RetracedEdge
        } else if shadow {
            PixelClass::RetracedShadow
        } else {
            PixelClass::Reprojected
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn classes(keys: &[u64], w: usize, edges: bool, shadows: bool) -> Vec<PixelClass> {
        let mut out = vec![PixelClass::Traced; keys.len()];
        for (j, row) in out.chunks_mut(w).enumerate() {
            classify_row(keys, w, j, edges, shadows, row);
        }
        out
    }

    #[test]
    fn edges_shadows_and_gaps() {
        use PixelClass::{Reprojected as P, RetracedEdge as E, RetracedGap as G, RetracedShadow as S};
        let (a, b, a_dark) = (key(0, 1), key(1, 1), key(0, 0));
        // One row: a a b b | a a_dark a | gap a
        let keys = [a, a, b, b, a, a_dark, a, GAP_KEY, a];
        assert_eq!(classes(&keys, 9, true, true), vec![P, E, E, E, E, S, E, G, E]);
        assert_eq!(classes(&keys, 9, false, true), vec![P, P, P, P, S, S, S, G, P]);
        assert_eq!(classes(&keys, 9, false, false), vec![P, P, P, P, P, P, P, G, P]);
        // Vertical neighbours count too.
        let keys = [a, a, a, b];
        assert_eq!(classes(&keys, 2, true, false), vec![P, E, E, E]);
    }
}
