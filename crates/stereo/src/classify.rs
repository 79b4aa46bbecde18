//! Which reprojected pixels are still sent to retrace: object edges.
//!
//! A reprojected pixel whose source object differs from a neighbour's sits on a
//! silhouette, where the right pixel-centre ray may see another object than the reprojected
//! sample ("drag" in the seed paper).
//!
//! Exact mode reads all eight neighbours: the diagonal ones find the corner of an object, or
//! a sliver of one, that touches the pixel only across a diagonal. `copy` and `reshade` with
//! their edges retraced read the four beside, above and below: they remove drag and are not
//! exact anyway. Exact mode sends no shadow boundary back: each of its reprojected pixels
//! casts its own shadow rays (`fill.rs`). Reused light bits were wrong where a shadow
//! thinner than a pixel fell between the left hit and the right one, which no neighbour's
//! bits can show: on the real molecule 1TII (`pymol-data`) at 800×600, one pixel
//! (design/reprojection.md, "Shadows: exact mode casts its own").
//!
//! A pixel next to a gap is an edge too: a gap is a depth discontinuity (a disocclusion or
//! a stretched surface), and the surface just past it may be seen by the right pixel-centre
//! ray while its reprojected sample is the background or another object (a near sphere's
//! silhouette moves by a different amount than the background behind it).
//!
//! At a row's ends the missing neighbour is the one the reprojection would give the pixel
//! just beyond the image: the end pixel's source's own neighbour on that side in the left
//! row (as a surface running on past the edge would land there), or a gap where the left
//! eye saw nothing past the source (`reproject.rs` reads it). Were it the end pixel itself,
//! a silhouette between the end pixel's own point and its source, on the border's side,
//! would go unseen.
//!
//! The pass reads one compact 32-bit plane per right pixel, the object id of its source,
//! carried along by the reprojection scan (`reproject/scanline.rs`), never the left eye's
//! full records. A gap is marked in it by [`GAP_OBJECT`], which no sample has: a miss is
//! [`tracer::NO_OBJECT`] (`u32::MAX`) and a hit is a sphere index, below the scene's sphere
//! count. So "object differs from a neighbour's" already covers "neighbour is a gap", and a
//! row is classified with 32-bit lane compares and masks, without a branch per pixel.

use crate::stats::PixelClass;

/// Object plane of a right pixel that no left pixel fills: one below
/// [`tracer::NO_OBJECT`], so it is no sphere index in any scene of fewer than
/// `u32::MAX - 1` spheres. That is not checked, as no user can reach it: such a scene would
/// not fit in memory (over 4·10⁹ spheres), and even then a sphere of that index would only
/// be taken for a gap, so retraced: right, only slower.
pub(crate) const GAP_OBJECT: u32 = tracer::NO_OBJECT - 1;

/// Which neighbours make a reprojected pixel an edge (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Edges {
    /// None: edges are not retraced.
    Off,
    /// The four beside, above and below (`copy` and `reshade` with their edges retraced).
    Sides,
    /// All eight, the diagonal ones too (`exact`).
    Around,
}

/// The object planes of three consecutive right rows: the row classified and its neighbours
/// above and below (the row itself at the image's top or bottom edge), all the same width.
#[derive(Clone, Copy)]
pub(crate) struct KeyRows<'a> {
    /// Object ids (or [`GAP_OBJECT`]) of the rows above, at and below the row.
    pub object: [&'a [u32]; 3],
    /// Object ids of the row's neighbours beyond its first and its last pixel (see the
    /// module doc).
    pub beyond: [u32; 2],
}

/// Classifies one right row into `out`: [`PixelClass::RetracedGap`] where it has no source;
/// else [`PixelClass::RetracedEdge`] if a neighbour that `edges` reads is a gap or has
/// another object; else [`PixelClass::Reprojected`]. Neighbours above or below the image
/// count as the pixel itself; those beyond the row's ends are `rows.beyond`.
pub(crate) fn classify_row(rows: KeyRows<'_>, edges: Edges, out: &mut [PixelClass]) {
    // One monomorphised loop per choice, so that each does only its own tests.
    match edges {
        Edges::Off => classify::<false, false>(rows, out),
        Edges::Sides => classify::<true, false>(rows, out),
        Edges::Around => classify::<true, true>(rows, out),
    }
}

/// The neighbours beside, above and below a pixel, which come first in [`class_of`]'s
/// eight; the diagonal ones follow.
const SIDES: usize = 4;

/// The class of a pixel of source object `object` whose eight neighbours' are
/// `neighbours`: the [`SIDES`] first, then the diagonal ones, read only if `DIAGONALS`.
#[inline]
fn class_of<const EDGES: bool, const DIAGONALS: bool>(object: u32, neighbours: [u32; 8]) -> PixelClass {
    // No branches: the comparisons are side-effect free, so this compiles to lane-wise masks.
    let mut same_object = true;
    for (k, o) in neighbours.into_iter().enumerate() {
        same_object &= o == object || (!DIAGONALS && k >= SIDES);
    }
    if object == GAP_OBJECT {
        PixelClass::RetracedGap
    } else if EDGES && !same_object {
        PixelClass::RetracedEdge
    } else {
        PixelClass::Reprojected
    }
}

/// [`classify_row`] for one choice of [`Edges`].
fn classify<const EDGES: bool, const DIAGONALS: bool>(rows: KeyRows<'_>, out: &mut [PixelClass]) {
    let w = out.len();
    let ([ao, ro, bo], [before, after]) = (rows.object, rows.beyond);
    debug_assert!([ao, ro, bo].iter().all(|p| p.len() == w), "key rows differ in width from the row classified");
    // An end pixel's diagonal neighbours beyond the row's end are the pixels above and
    // below it: the row beyond has no neighbours of its own.
    let at = |i: usize, left: u32, right: u32| {
        let (up, down) = (ao[i], bo[i]);
        let diagonal = |o: &[u32], c: Option<usize>, here: u32| match c {
            Some(c) if c < w => o[c],
            _ => here,
        };
        let (before, after) = (i.checked_sub(1), Some(i + 1));
        let [a, b, c, d] =
            [diagonal(ao, before, up), diagonal(ao, after, up), diagonal(bo, before, down), diagonal(bo, after, down)];
        class_of::<EDGES, DIAGONALS>(ro[i], [left, right, up, down, a, b, c, d])
    };
    if w < 3 {
        for (i, class) in out.iter_mut().enumerate() {
            let left = if i == 0 { before } else { ro[i - 1] };
            let right = if i + 1 == w { after } else { ro[i + 1] };
            *class = at(i, left, right);
        }
        return;
    }
    out[0] = at(0, before, ro[1]);
    out[w - 1] = at(w - 1, ro[w - 2], after);
    // The interior, over equal-length slices so that the loop has no bounds checks and
    // vectorises: pixel k + 1 with its left neighbours (beside, above, below) at k and its
    // right ones at k + 2.
    let n = w - 2;
    let (o_left, o_me, o_right, o_up, o_down) = (&ro[..n], &ro[1..=n], &ro[2..], &ao[1..=n], &bo[1..=n]);
    let (o_up_left, o_up_right, o_down_left, o_down_right) = (&ao[..n], &ao[2..], &bo[..n], &bo[2..]);
    for (k, class) in out[1..=n].iter_mut().enumerate() {
        let neighbours =
            [o_left[k], o_right[k], o_up[k], o_down[k], o_up_left[k], o_up_right[k], o_down_left[k], o_down_right[k]];
        *class = class_of::<EDGES, DIAGONALS>(o_me[k], neighbours);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GAP: u32 = GAP_OBJECT;

    /// The classes of the image of `keys` (source objects), `w` wide; beyond each row's
    /// ends, `beyond` (or the end pixel's own key).
    fn classes_beyond(keys: &[u32], w: usize, edges: Edges, beyond: Option<[u32; 2]>) -> Vec<PixelClass> {
        let h = keys.len() / w;
        let mut out = vec![PixelClass::Traced; keys.len()];
        for (j, row) in out.chunks_mut(w).enumerate() {
            let rows = [j.saturating_sub(1), j, (j + 1).min(h - 1)].map(|r| r * w..(r + 1) * w);
            let beyond = beyond.unwrap_or([keys[j * w], keys[j * w + w - 1]]);
            classify_row(KeyRows { object: rows.map(|r| &keys[r]), beyond }, edges, row);
        }
        out
    }

    fn classes(keys: &[u32], w: usize, edges: Edges) -> Vec<PixelClass> {
        classes_beyond(keys, w, edges, None)
    }

    #[test]
    fn edges_and_gaps() {
        use PixelClass::{Reprojected as P, RetracedEdge as E, RetracedGap as G};
        let (a, b) = (0, 1);
        // One row: a a b b a a | gap a
        let keys = [a, a, b, b, a, a, GAP, a];
        assert_eq!(classes(&keys, 8, Edges::Around), vec![P, E, E, E, E, E, G, E]);
        assert_eq!(classes(&keys, 8, Edges::Sides), vec![P, E, E, E, E, E, G, E]);
        assert_eq!(classes(&keys, 8, Edges::Off), vec![P, P, P, P, P, P, G, P]);
        // Vertical neighbours count too.
        let keys = [a, a, a, b, a, a];
        assert_eq!(classes(&keys, 3, Edges::Sides), vec![E, P, P, E, E, P]);
    }

    #[test]
    fn diagonal_neighbours_count_too() {
        use PixelClass::{Reprojected as P, RetracedEdge as E};
        // Another object, or a gap, touching the middle pixel only at a corner is found
        // across the diagonal as across a side in exact mode; with the four sides only, it
        // is an edge only beside, above or below.
        let (a, b) = (0, 1);
        let corner = |key| [key, a, a, a, a, a, a, a, a];
        assert_eq!(classes(&corner(b), 3, Edges::Around), vec![E, E, P, E, E, P, P, P, P]);
        assert_eq!(classes(&corner(b), 3, Edges::Sides), vec![E, E, P, E, P, P, P, P, P]);
        assert_eq!(classes(&corner(GAP), 3, Edges::Around)[4], E);
        assert_eq!(classes(&corner(GAP), 3, Edges::Sides)[4], P);
        assert_eq!(classes(&corner(b), 3, Edges::Off), vec![P; 9]);
        // Two pixels wide: each end's diagonals beyond the row are the pixels above and
        // below it, its other diagonal the pixel across.
        assert_eq!(classes(&[a, a, a, a, a, b], 2, Edges::Around), vec![P, P, E, E, E, E]);
    }

    #[test]
    fn misses_next_to_gaps() {
        use PixelClass::{Reprojected as P, RetracedEdge as E, RetracedGap as G};
        // A miss is not a gap.
        let miss = tracer::NO_OBJECT;
        assert_eq!(classes(&[miss, miss, GAP], 3, Edges::Off), vec![P, P, G]);
        assert_eq!(classes(&[miss, miss, GAP, miss], 4, Edges::Sides), vec![P, E, G, E]);
        assert_eq!(classes(&[7, 7, GAP, miss], 4, Edges::Around), vec![P, E, G, E]);
    }

    #[test]
    fn the_keys_beyond_a_row_are_its_end_pixels_neighbours() {
        use PixelClass::{Reprojected as P, RetracedEdge as E};
        let (a, b) = (0, 1);
        // Another object beyond the last pixel, a gap beyond both.
        let beyond = |ends| classes_beyond(&[a, a, a, a], 4, Edges::Around, Some(ends));
        assert_eq!(beyond([a, a]), vec![P, P, P, P]);
        assert_eq!(beyond([a, b]), vec![P, P, P, E]);
        assert_eq!(beyond([GAP, GAP]), vec![E, P, P, E]);
        // Rows of one and two pixels.
        assert_eq!(classes_beyond(&[a, a], 2, Edges::Sides, Some([GAP, a])), vec![E, P]);
        assert_eq!(classes_beyond(&[a], 1, Edges::Off, Some([b, b])), vec![P]);
        assert_eq!(classes_beyond(&[a], 1, Edges::Sides, Some([a, b])), vec![E]);
    }
}
