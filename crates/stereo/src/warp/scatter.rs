//! Landing one source eye's pixels in a target's key buffer: the forward warp's lane kernel.
//!
//! Each source pixel is mapped by [`WarpMap`] in SIMD lanes (a handful of multiplies and
//! adds, one division), and lands on the target pixel that contains its projected centre
//! (the floor of its continuous coordinates). What lands is a 64-bit key: the target depth
//! n_z = z_t + d_t (positive, so its bits order as the floats do; +∞ for the background) in
//! the high half, the source pixel's index in the low 31 bits, and bit 31 set for the other
//! eye's pixels. Each target pixel keeps the smallest key it is given: the nearest surface,
//! and on a tie the smaller source index. A minimum does not depend on the order the
//! pixels come in, so the result is the same whatever the order, the lane width or the
//! threads.
//!
//! The other eye's pass writes only where bit 31 is set: target pixels still [`EMPTY`]
//! (holes of the own eye's pass, as `EMPTY` has every bit set) or already holding the
//! other eye's key. It never covers a pixel the own eye reached.

use fearless_simd::{dispatch, prelude::*, Level, Simd};

use super::map::WarpMap;

type F<S> = <S as Simd>::f32s;
type U<S> = <S as Simd>::u32s;
type M<S> = <S as Simd>::mask32s;

/// The key of a target pixel no source pixel reached: larger than every key that lands.
pub(crate) const EMPTY: u64 = u64::MAX;
/// The key bit of the other eye's pixels (set in [`EMPTY`] too).
pub(crate) const OTHER: u64 = 1 << 31;
/// The key bits holding the source pixel's index.
pub(crate) const INDEX: u64 = OTHER - 1;
/// The target index of a lane that lands outside the target (no slot has it: the target
/// has fewer than `u32::MAX` pixels).
const OUTSIDE: u32 = u32::MAX;

/// Which source eye a pass lands in a target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pass {
    /// The target's own eye: every landing pixel competes.
    Own,
    /// The other eye, after the own eye's pass: only the holes it left are written.
    Other,
}

/// Lands every pixel of a source whose depth plane is `z` (rows of `width` pixels) in
/// `keys` (the target's, row-major, of `map.target_size`), at the SIMD `level`.
pub(crate) fn scatter(level: Level, map: &WarpMap, z: &[f32], width: usize, keys: &mut [u64], pass: Pass) {
    debug_assert_eq!(keys.len(), map.target_size.0 as usize * map.target_size.1 as usize, "keys of the target's size");
    if width == 0 {
        return;
    }
    match pass {
        Pass::Own => dispatch!(level, simd => simd.vectorize(
            #[inline(always)]
            || scatter_in::<_, false>(simd, map, z, width, keys),
        )),
        Pass::Other => dispatch!(level, simd => simd.vectorize(
            #[inline(always)]
            || scatter_in::<_, true>(simd, map, z, width, keys),
        )),
    }
}

/// The map's numbers splatted across the lanes, once per pass.
struct Lanes<S: Simd> {
    g: [F<S>; 3],
    h_i: [F<S>; 3],
    distance: F<S>,
    size: (F<S>, F<S>),
    width: U<S>,
}

impl<S: Simd> Lanes<S> {
    #[expect(clippy::inline_always, reason = "inlined into the dispatched lane kernel, whose target features it needs")]
    #[inline(always)]
    fn new(simd: S, map: &WarpMap) -> Self {
        let splat3 = |v: [f32; 3]| [F::<S>::splat(simd, v[0]), F::<S>::splat(simd, v[1]), F::<S>::splat(simd, v[2])];
        let (w, h) = map.target_size;
        Self {
            g: splat3(map.g),
            h_i: splat3(map.h_i),
            distance: F::<S>::splat(simd, map.distance),
            size: (F::<S>::splat(simd, w as f32), F::<S>::splat(simd, h as f32)),
            width: U::<S>::splat(simd, w),
        }
    }
}

/// The pass over the source, row by row, a vector of pixels at a time.
#[expect(clippy::inline_always, reason = "inlined into the dispatched lane kernel, whose target features it needs")]
#[inline(always)]
fn scatter_in<S: Simd, const OTHER_EYE: bool>(simd: S, map: &WarpMap, z: &[f32], width: usize, keys: &mut [u64]) {
    let n = F::<S>::LEN;
    let lanes = Lanes::new(simd, map);
    let first_columns = F::<S>::float_from(lane_index(simd));
    let flag = if OTHER_EYE { OTHER } else { 0 };
    // The last, partial vector of a row, padded (its padding lanes land nowhere: they are
    // not emitted).
    let mut tail = [0.0_f32; 16];
    for (j, z_row) in z.chunks_exact(width).enumerate() {
        let h = map.row(j as u32);
        let h_row = [F::<S>::splat(simd, h[0]), F::<S>::splat(simd, h[1]), F::<S>::splat(simd, h[2])];
        let row_start = (j * width) as u64 | flag;
        for (k, chunk) in z_row.chunks(n).enumerate() {
            let i = k * n;
            let z = if chunk.len() == n {
                F::<S>::from_slice(simd, chunk)
            } else {
                tail[..chunk.len()].copy_from_slice(chunk);
                F::<S>::from_slice(simd, &tail[..n])
            };
            let columns = first_columns + F::<S>::splat(simd, i as f32);
            let (index, depth) = land(simd, &lanes, project(simd, &lanes, h_row, columns, z));
            emit::<OTHER_EYE>(keys, index.as_slice(), depth.as_slice(), row_start + i as u64, chunk.len());
        }
    }
}

/// Where source pixels land, one per lane: continuous target coordinates (px, py), n_z
/// (the target depth plus d, > 0 in front of the target eye), and whether the pixel is a
/// surface (finite depth) rather than background.
struct Projected<S: Simd> {
    px: F<S>,
    py: F<S>,
    nz: F<S>,
    finite: M<S>,
}

/// Projects the source pixels (`columns`, row of `h_row`) of depth `z` to the target.
#[expect(clippy::inline_always, reason = "inlined into the dispatched lane kernel, whose target features it needs")]
#[inline(always)]
fn project<S: Simd>(simd: S, lanes: &Lanes<S>, h_row: [F<S>; 3], columns: F<S>, z: F<S>) -> Projected<S> {
    let (zero, one) = (F::<S>::splat(simd, 0.0), F::<S>::splat(simd, 1.0));
    let finite = z.simd_lt(F::<S>::splat(simd, f32::INFINITY));
    // A background pixel is a direction: n = h, with no translation.
    let w = finite.select(z + lanes.distance, one);
    let n = |a: usize| finite.select(lanes.g[a], zero) + w * (h_row[a] + columns * lanes.h_i[a]);
    let (nx, ny, nz) = (n(0), n(1), n(2));
    let inv = one / nz;
    Projected { px: nx * inv, py: ny * inv, nz, finite }
}

/// The target pixel each lane lands on (row-major index, [`OUTSIDE`] for none) and its key
/// depth's bits.
#[expect(clippy::inline_always, reason = "inlined into the dispatched lane kernel, whose target features it needs")]
#[inline(always)]
fn land<S: Simd>(simd: S, lanes: &Lanes<S>, p: Projected<S>) -> (U<S>, U<S>) {
    let zero = F::<S>::splat(simd, 0.0);
    let inside = p.nz.simd_gt(zero)
        & p.px.simd_ge(zero)
        & p.px.simd_lt(lanes.size.0)
        & p.py.simd_ge(zero)
        & p.py.simd_lt(lanes.size.1);
    // In [0, size) the truncation is the floor.
    let column = U::<S>::truncate_from(inside.select(p.px, zero));
    let row = U::<S>::truncate_from(inside.select(p.py, zero));
    let index = inside.select(row * lanes.width + column, U::<S>::splat(simd, OUTSIDE));
    let depth = p.finite.select(p.nz, F::<S>::splat(simd, f32::INFINITY));
    (index, depth.bitcast())
}

/// Keeps each of the first `count` lanes' keys where it lands, if smaller; the other eye's
/// only in holes and over its own.
#[expect(clippy::inline_always, reason = "inlined into the dispatched lane kernel, whose target features it needs")]
#[inline(always)]
fn emit<const OTHER_EYE: bool>(keys: &mut [u64], index: &[u32], depth: &[u32], first: u64, count: usize) {
    for (l, (&t, &depth)) in index.iter().zip(depth).take(count).enumerate() {
        if let Some(slot) = keys.get_mut(t as usize) {
            let key = (u64::from(depth) << 32) | (first + l as u64);
            if !OTHER_EYE || *slot & OTHER != 0 {
                *slot = (*slot).min(key);
            }
        }
    }
}

/// Lane l holds l.
#[expect(clippy::inline_always, reason = "inlined into the dispatched lane kernel, whose target features it needs")]
#[inline(always)]
fn lane_index<S: Simd>(simd: S) -> U<S> {
    const INDEX: [u32; 16] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15];
    U::<S>::from_slice(simd, &INDEX[..U::<S>::LEN])
}

/// Where source pixel (i, j) of depth `z` lands in the target, by the kernel itself (lane
/// 0, at the process's level): its continuous coordinates and n_z = z_t + d_t (for the
/// background, of its direction only), or `None` behind the target eye.
#[cfg(test)]
pub(crate) fn land_one(map: &WarpMap, i: u32, j: u32, z: f32) -> Option<(glam::Vec2, f32)> {
    fn lane0<S: Simd>(simd: S, map: &WarpMap, i: u32, j: u32, z: f32) -> (f32, f32, f32) {
        let lanes = Lanes::new(simd, map);
        let h = map.row(j).map(|x| F::<S>::splat(simd, x));
        let p = project(simd, &lanes, h, F::<S>::splat(simd, i as f32), F::<S>::splat(simd, z));
        (p.px.as_slice()[0], p.py.as_slice()[0], p.nz.as_slice()[0])
    }
    let (px, py, nz) = dispatch!(tracer::simd_level(), simd => lane0(simd, map, i, j, z));
    (nz > 0.0).then(|| (glam::Vec2::new(px, py), nz))
}
