//! Which reprojected pixels are still sent to retrace: object edges and shadow boundaries.
//!
//! A reprojected pixel whose source object differs from a 4-neighbour's sits on a
//! silhouette, where the right pixel-centre ray may see another object than the reprojected
//! sample ("drag" in the seed paper). One whose per-light visibility differs from a
//! neighbour's sits on a shadow edge (or a terminator), where reusing visibility from the
//! left hit may be wrong for the right pixel centre. Only reprojected neighbours are
//! compared: a gap neighbour is retraced anyway.

use tracer::Surface;

use crate::reproject::NO_SOURCE;
use crate::stats::PixelClass;

/// Classifies right row `j` from the source map `src` (whole image, row-major, `w` wide)
/// into `out` (this row only).
pub(crate) fn classify_row(
    src: &[u32],
    left: &[Surface],
    w: usize,
    j: usize,
    edges: bool,
    shadows: bool,
    out: &mut [PixelClass],
) {
    let h = src.len() / w;
    let row = &src[j * w..(j + 1) * w];
    let above = (j > 0).then(|| &src[(j - 1) * w..j * w]);
    let below = (j + 1 < h).then(|| &src[(j + 1) * w..(j + 2) * w]);
    for (i, (class, &s)) in out.iter_mut().zip(row).enumerate() {
        *class = if s == NO_SOURCE {
            PixelClass::RetracedGap
        } else if !(edges || shadows) {
            PixelClass::Reprojected
        } else {
            let me = &left[s as usize];
            let neighbours =
                [(i > 0).then(|| row[i - 1]), row.get(i + 1).copied(), above.map(|r| r[i]), below.map(|r| r[i])];
            let mut class = PixelClass::Reprojected;
            for n in neighbours.into_iter().flatten().filter(|&n| n != NO_SOURCE) {
                let other = &left[n as usize];
                if edges && other.object != me.object {
                    class = PixelClass::RetracedEdge;
                    break;
                }
                if shadows && other.lights != me.lights {
                    class = PixelClass::RetracedShadow;
                }
            }
            class
        };
    }
}
