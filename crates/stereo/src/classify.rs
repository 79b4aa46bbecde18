//! Which reprojected pixels are still sent to retrace: object edges and shadow boundaries.
//!
//! A reprojected pixel whose source object differs from a neighbour's sits on a
//! silhouette, where the right pixel-centre ray may see another object than the reprojected
//! sample ("drag" in the seed paper). One whose per-light visibility differs from a
//! neighbour's sits on a shadow edge (or a terminator), where reusing visibility from the
//! left hit may be wrong for the right pixel centre.
//!
//! Exact mode, which reads the light bits, reads all eight neighbours: the diagonal ones
//! find the corner of a shadow, or a sliver of one or of an atom, that touches the pixel
//! only across a diagonal. On the real molecule 1TII (`pymol-data`) at 1280×720, the two
//! pixels exact mode made wrong with four neighbours were such slivers
//! (design/reprojection.md, "What the argument does not cover"). `copy` and `reshade` with
//! their edges retraced read the four beside, above and below: they remove drag and are
//! not exact anyway.
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
//! a shadow boundary or a silhouette between the end pixel's own point and its source, on
//! the border's side, would go unseen: the property test found a terminator down the left
//! edge of the image that exact mode shaded unlit from the column next to it.
//!
//! The pass reads two compact 32-bit planes per right pixel, the object id and the light
//! bits of its source, carried along by the reprojection scan (`reproject/scanline.rs`),
//! never the left eye's full records. A gap is marked in the object plane alone, by
//! [`GAP_OBJECT`], which no sample has: a miss is [`tracer::NO_OBJECT`] (`u32::MAX`) and a
//! hit is a sphere index, below the scene's sphere count. So "object differs from a
//! neighbour's" already covers "neighbour is a gap", and a row is classified with SSE2's
//! 32-bit lane compares and masks, without a branch per pixel: two 32-bit planes rather
//! than one 64-bit key, which SSE2 cannot compare.

use crate::stats::PixelClass;

/// Object plane of a right pixel that no left pixel fills: one below
/// [`tracer::NO_OBJECT`], so it is no sphere index in any scene of fewer than
/// `u32::MAX - 1` spheres. That is not checked, as no user can reach it: such a scene would
/// not fit in memory (over 4·10⁹ spheres), and even then a sphere of that index would only
/// be taken for a gap, so retraced: right, only slower.
pub(crate) const GAP_OBJECT: u32 = tracer::NO_OBJECT - 1;

/// Lights plane of a right pixel that no left pixel fills. Never decisive: a gap is itself
/// classified by its object plane, and a gap neighbour is skipped by the shadow test (it
/// makes an edge when edges are retraced).
pub(crate) const GAP_LIGHTS: u32 = 0;

/// The key planes of three consecutive right rows: the row classified and its neighbours
/// above and below (the row itself at the image's top or bottom edge), all the same width.
#[derive(Clone, Copy)]
pub(crate) struct KeyRows<'a> {
    /// Object ids (or [`GAP_OBJECT`]) of the rows above, at and below the row.
    pub object: [&'a [u32]; 3],
    /// Light bits of the rows above, at and below the row.
    pub lights: [&'a [u32]; 3],
    /// Keys `(object, lights)` of the row's neighbours beyond its first and its last pixel
    /// (see the module doc).
    pub beyond: [(u32, u32); 2],
}

/// Classifies one right row into `out`: [`PixelClass::RetracedGap`] where it has no source;
/// else [`PixelClass::RetracedEdge`] if `edges` and a neighbour is a gap or has another
/// object (of its eight if `shadows`, else of its four beside, above and below); else
/// [`PixelClass::RetracedShadow`] if `shadows` and a neighbour (of eight) that is not a gap
/// has other light bits; else [`PixelClass::Reprojected`]. Neighbours above or below
/// the image count as the pixel itself; those beyond the row's ends are `rows.beyond`.
pub(crate) fn classify_row(rows: KeyRows<'_>, edges: bool, shadows: bool, out: &mut [PixelClass]) {
    // One monomorphised loop per option pair, so that each does only its own tests.
    match (edges, shadows) {
        (false, false) => classify::<false, false>(rows, out),
        (true, false) => classify::<true, false>(rows, out),
        (false, true) => classify::<false, true>(rows, out),
        (true, true) => classify::<true, true>(rows, out),
    }
}

/// The neighbours beside, above and below a pixel, which come first in [`class_of`]'s
/// eight; the diagonal ones follow.
const SIDES: usize = 4;

/// The class of a pixel with key (`object`, `lights`) and its eight neighbours' keys: the
/// [`SIDES`] first, then the diagonal ones.
#[inline]
fn class_of<const EDGES: bool, const SHADOWS: bool>(
    object: u32,
    lights: u32,
    neighbours: [(u32, u32); 8],
) -> PixelClass {
    // No branches: the comparisons are side-effect free, so this compiles to lane-wise masks.
    let (mut same_object, mut same_lights) = (true, true);
    for (k, (o, l)) in neighbours.into_iter().enumerate() {
        // The diagonal neighbours count for the objects only where the light bits are read
        // too: in exact mode (module doc).
        same_object &= o == object || (!SHADOWS && k >= SIDES);
        // A gap neighbour is no shadow boundary: with edges retraced it makes this pixel an
        // edge (across a diagonal, in exact mode only).
        same_lights &= l == lights || o == GAP_OBJECT;
    }
    if object == GAP_OBJECT {
        PixelClass::RetracedGap
    } else if EDGES && !same_object {
        PixelClass::RetracedEdge
    } else if SHADOWS && !same_lights {
        PixelClass::RetracedShadow
    } else {
        PixelClass::Reprojected
    }
}

/// [`classify_row`] for one option pair.
fn classify<const EDGES: bool, const SHADOWS: bool>(rows: KeyRows<'_>, out: &mut [PixelClass]) {
    let w = out.len();
    let ([ao, ro, bo], [al, rl, bl], [before, after]) = (rows.object, rows.lights, rows.beyond);
    debug_assert!(
        [ao, ro, bo, al, rl, bl].iter().all(|p| p.len() == w),
        "key rows differ in width from the row classified"
    );
    let key = |i: usize| (ro[i], rl[i]);
    // An end pixel's diagonal neighbours beyond the row's end are the pixels above and
    // below it: the row beyond has no neighbours of its own.
    let at = |i: usize, left: (u32, u32), right: (u32, u32)| {
        let (up, down) = ((ao[i], al[i]), (bo[i], bl[i]));
        let diagonal = |o: &[u32], l: &[u32], c: Option<usize>, here: (u32, u32)| match c {
            Some(c) if c < w => (o[c], l[c]),
            _ => here,
        };
        let (before, after) = (i.checked_sub(1), Some(i + 1));
        let diagonals = [
            diagonal(ao, al, before, up),
            diagonal(ao, al, after, up),
            diagonal(bo, bl, before, down),
            diagonal(bo, bl, after, down),
        ];
        let [a, b, c, d] = diagonals;
        class_of::<EDGES, SHADOWS>(ro[i], rl[i], [left, right, up, down, a, b, c, d])
    };
    if w < 3 {
        for (i, class) in out.iter_mut().enumerate() {
            let left = if i == 0 { before } else { key(i - 1) };
            let right = if i + 1 == w { after } else { key(i + 1) };
            *class = at(i, left, right);
        }
        return;
    }
    out[0] = at(0, before, key(1));
    out[w - 1] = at(w - 1, key(w - 2), after);
    // The interior, over equal-length slices so that the loop has no bounds checks and
    // vectorises: pixel k + 1 with its left neighbours (beside, above, below) at k and its
    // right ones at k + 2.
    let n = w - 2;
    let (o_left, o_me, o_right, o_up, o_down) = (&ro[..n], &ro[1..=n], &ro[2..], &ao[1..=n], &bo[1..=n]);
    let (l_left, l_me, l_right, l_up, l_down) = (&rl[..n], &rl[1..=n], &rl[2..], &al[1..=n], &bl[1..=n]);
    let (o_up_left, o_up_right, o_down_left, o_down_right) = (&ao[..n], &ao[2..], &bo[..n], &bo[2..]);
    let (l_up_left, l_up_right, l_down_left, l_down_right) = (&al[..n], &al[2..], &bl[..n], &bl[2..]);
    for (k, class) in out[1..=n].iter_mut().enumerate() {
        let neighbours = [
            (o_left[k], l_left[k]),
            (o_right[k], l_right[k]),
            (o_up[k], l_up[k]),
            (o_down[k], l_down[k]),
            (o_up_left[k], l_up_left[k]),
            (o_up_right[k], l_up_right[k]),
            (o_down_left[k], l_down_left[k]),
            (o_down_right[k], l_down_right[k]),
        ];
        *class = class_of::<EDGES, SHADOWS>(o_me[k], l_me[k], neighbours);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GAP: (u32, u32) = (GAP_OBJECT, GAP_LIGHTS);

    /// The classes of the image of `keys`, `w` wide; beyond each row's ends, `beyond` (or the
    /// end pixel's own key).
    fn classes_beyond(
        keys: &[(u32, u32)],
        w: usize,
        (edges, shadows): (bool, bool),
        beyond: Option<[(u32, u32); 2]>,
    ) -> Vec<PixelClass> {
        let object: Vec<u32> = keys.iter().map(|k| k.0).collect();
        let lights: Vec<u32> = keys.iter().map(|k| k.1).collect();
        let h = keys.len() / w;
        let mut out = vec![PixelClass::Traced; keys.len()];
        for (j, row) in out.chunks_mut(w).enumerate() {
            let rows = [j.saturating_sub(1), j, (j + 1).min(h - 1)].map(|r| r * w..(r + 1) * w);
            let beyond = beyond.unwrap_or([keys[j * w], keys[j * w + w - 1]]);
            let rows = KeyRows { object: rows.clone().map(|r| &object[r]), lights: rows.map(|r| &lights[r]), beyond };
            classify_row(rows, edges, shadows, row);
        }
        out
    }

    fn classes(keys: &[(u32, u32)], w: usize, edges: bool, shadows: bool) -> Vec<PixelClass> {
        classes_beyond(keys, w, (edges, shadows), None)
    }

    #[test]
    fn edges_shadows_and_gaps() {
        use PixelClass::{Reprojected as P, RetracedEdge as E, RetracedGap as G, RetracedShadow as S};
        let (a, b, a_dark) = ((0, 1), (1, 1), (0, 0));
        // One row: a a b b | a a_dark a | gap a
        let keys = [a, a, b, b, a, a_dark, a, GAP, a];
        assert_eq!(classes(&keys, 9, true, true), vec![P, E, E, E, E, S, E, G, E]);
        assert_eq!(classes(&keys, 9, false, true), vec![P, P, P, P, S, S, S, G, P]);
        assert_eq!(classes(&keys, 9, false, false), vec![P, P, P, P, P, P, P, G, P]);
        // Vertical neighbours count too.
        let keys = [a, a, a, b, a, a];
        assert_eq!(classes(&keys, 3, true, false), vec![E, P, P, E, E, P]);
    }

    #[test]
    fn diagonal_neighbours_count_too() {
        use PixelClass::{Reprojected as P, RetracedEdge as E, RetracedShadow as S};
        // A shadow, or another object, touching the middle pixel only at a corner is found
        // across the diagonal as across a side where the light bits are read (exact mode);
        // without them, another object there is an edge only beside, above or below.
        let (a, b, a_dark) = ((0, 1), (1, 1), (0, 0));
        let corner = |key| [key, a, a, a, a, a, a, a, a];
        assert_eq!(classes(&corner(a_dark), 3, true, true), vec![S, S, P, S, S, P, P, P, P]);
        assert_eq!(classes(&corner(b), 3, true, true), vec![E, E, P, E, E, P, P, P, P]);
        assert_eq!(classes(&corner(b), 3, true, false), vec![E, E, P, E, P, P, P, P, P]);
        assert_eq!(classes(&corner(GAP), 3, true, true)[4], E);
        assert_eq!(classes(&corner(GAP), 3, false, true)[4], P);
        assert_eq!(classes(&corner(b), 3, false, true), vec![P; 9]);
        // Two pixels wide: each end's diagonals beyond the row are the pixels above and
        // below it, its other diagonal the pixel across.
        assert_eq!(classes(&[a, a, a, a, a, a_dark], 2, false, true), vec![P, P, S, S, S, S]);
    }

    #[test]
    fn misses_next_to_gaps() {
        use PixelClass::{Reprojected as P, RetracedEdge as E, RetracedGap as G, RetracedShadow as S};
        // A miss is not a gap, and a gap's light bits never make a shadow boundary.
        let (miss, lit) = ((tracer::NO_OBJECT, 0), (7, u32::MAX));
        assert_eq!(classes(&[miss, miss, GAP], 3, false, false), vec![P, P, G]);
        assert_eq!(classes(&[miss, miss, GAP, miss], 4, true, false), vec![P, E, G, E]);
        assert_eq!(classes(&[lit, lit, GAP, miss], 4, false, true), vec![P, P, G, P]);
        assert_eq!(classes(&[lit, lit, GAP, miss], 4, true, true), vec![P, E, G, E]);
        assert_eq!(classes(&[(7, 0), lit, lit], 3, false, true), vec![S, S, P]);
    }

    #[test]
    fn the_keys_beyond_a_row_are_its_end_pixels_neighbours() {
        use PixelClass::{Reprojected as P, RetracedEdge as E, RetracedShadow as S};
        let (a, b, a_dark) = ((0, 1), (1, 1), (0, 0));
        // Lit beyond the first pixel, another object beyond the last, a gap beyond both.
        let beyond = |ends| classes_beyond(&[a_dark, a_dark, a_dark, a], 4, (true, true), Some(ends));
        assert_eq!(beyond([a, a]), vec![S, P, S, S]);
        assert_eq!(beyond([a_dark, b]), vec![P, P, S, E]);
        assert_eq!(beyond([GAP, GAP]), vec![E, P, S, E]);
        // Without edges a gap beyond is no shadow boundary; rows of one and two pixels.
        assert_eq!(classes_beyond(&[a_dark, a_dark], 2, (false, true), Some([GAP, a])), vec![P, S]);
        assert_eq!(classes_beyond(&[a_dark], 1, (false, true), Some([a, a_dark])), vec![S]);
        assert_eq!(classes_beyond(&[a], 1, (true, false), Some([a, b])), vec![E]);
    }
}
