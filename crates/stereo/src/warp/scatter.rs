//! Landing one source eye's pixels in a band of both target eyes' keys: the forward warp's
//! lane kernel.
//!
//! Each source pixel is mapped by [`WarpMap`] to its own eye's target in SIMD lanes (a
//! handful of multiplies and adds, one division), and from there to the other target eye
//! by the disparity ([`EyeShift`]: one multiply-add more, as both target eyes share the
//! head pose and the window). In each it lands on the pixel that contains its projected
//! centre (the floor of its continuous coordinates). What lands is a key of two words: the
//! first orders the keys, the second is the pixel's colour (`0x00RRGGBB`). The first word
//! is the bits of the target depth n_z = z_t + d_t (positive, so its bits order as the
//! floats do; +∞ for the background), with the sign bit flipped for the own eye's pixels:
//! as signed numbers, every own eye's word is negative, every other eye's positive, and
//! [`EMPTY`] (nothing landed) the largest. Each target pixel keeps the first key whose word
//! is smaller than the one there: any pixel of its own eye before any of the other eye
//! (whose pixels therefore show only in the holes the own eye left), then the nearest
//! surface, then, on a tie, the one that landed first. Pixels land in a fixed order (the
//! band's source rows from the top, left eye before right, pixels from the left), and the
//! bands share no target pixel, so the result is the same whatever the threads or the lane
//! width. The two words are kept in two planes, the first words in the band's [`Keys`] and
//! the colours in the band's rows of the target image itself, so that a vector of pixels
//! landing side by side is compared and stored as two vectors, and the winners' colours
//! are in place when the band is done.
//!
//! A pass lands only what falls in one band of target rows, whose keys stay in the core's
//! cache, and reads only the source rows that can reach the band
//! ([`WarpMap::rows_reached`]).

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{dispatch, prelude::*, Level, Simd};

use super::map::{EyeShift, WarpMap};

type F<S> = <S as Simd>::f32s;
type U<S> = <S as Simd>::u32s;
type I<S> = <S as Simd>::i32s;
type M<S> = <S as Simd>::mask32s;

/// The first key word of a target pixel no source pixel reached: larger than every one
/// that lands.
pub(crate) const EMPTY: i32 = i32::MAX;
/// The bits of a first key word that hold the depth's bits, in either eye's words.
pub(crate) const DEPTH: i32 = i32::MAX;
/// The colour bits of a pixel (`0x00RRGGBB`).
pub(crate) const COLOUR: u32 = 0x00ff_ffff;

/// A band's first key words ([`EMPTY`] where nothing landed), row-major.
#[derive(Clone, Debug, Default)]
pub(crate) struct Keys {
    /// The first words.
    pub depth: Vec<i32>,
}

impl Keys {
    /// `n` keys where nothing landed.
    pub fn reset(&mut self, n: usize) {
        self.depth.clear();
        self.depth.resize(n, EMPTY);
    }
}

/// A band's keys, to land in: its first words and its rows of the target image, which take
/// the colours (left as they were where nothing landed).
#[derive(Debug)]
pub(crate) struct KeysMut<'a> {
    /// The first words.
    pub depth: &'a mut [i32],
    /// The colours.
    pub colour: &'a mut [u32],
}

/// The target index of a lane that lands outside the target (no slot has it: the target
/// has fewer than `u32::MAX` pixels).
const OUTSIDE: u32 = u32::MAX;

/// One source eye as a pass reads it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Source<'a> {
    /// Its colours, rows of `width` pixels.
    pub rgb: &'a [u32],
    /// Its depth plane, rows of `width` pixels.
    pub z: &'a [f32],
    /// Its width in pixels.
    pub width: usize,
    /// The target rows each of its rows can reach, in either target eye
    /// ([`WarpMap::rows_reached`]).
    pub reach: &'a [Option<(u32, u32)>],
    /// Its map to its own eye's target.
    pub map: &'a WarpMap,
    /// From its own eye's target to the other's.
    pub shift: EyeShift,
}

/// A band of consecutive target rows, in both target eyes.
#[derive(Debug)]
pub(crate) struct Band<'a> {
    /// Its first target row.
    pub first: u32,
    /// The keys of the source's own eye's target, then of the other's, whole target rows.
    pub keys: [KeysMut<'a>; 2],
}

/// Lands every pixel of the `source` rows that can reach the band in both targets' keys,
/// at the SIMD `level`.
pub(crate) fn scatter(level: Level, source: Source<'_>, band: &mut Band<'_>) {
    if source.width == 0 || source.map.target_size.0 == 0 {
        return;
    }
    dispatch!(level, simd => simd.vectorize(
        #[inline(always)]
        || scatter_in(simd, source, band),
    ));
}

/// Whether the inclusive target rows `(lo, hi)` meet the `rows` rows from `first`.
fn meets((lo, hi): (u32, u32), first: u32, rows: u32) -> bool {
    lo < first + rows && hi >= first
}

/// The map's numbers splatted across the lanes, once per pass.
struct Lanes<S: Simd> {
    g: [F<S>; 3],
    h_i: [F<S>; 3],
    distance: F<S>,
    /// The target's width in pixels.
    width: F<S>,
}

impl<S: Simd> Lanes<S> {
    #[inline(always)]
    fn new(simd: S, map: &WarpMap) -> Self {
        let splat3 = |v: [f32; 3]| [F::<S>::splat(simd, v[0]), F::<S>::splat(simd, v[1]), F::<S>::splat(simd, v[2])];
        Self {
            g: splat3(map.g),
            h_i: splat3(map.h_i),
            distance: F::<S>::splat(simd, map.distance),
            width: F::<S>::splat(simd, map.target_size.0 as f32),
        }
    }
}

/// The pass over the source rows that reach the band, a vector of pixels at a time.
#[inline(always)]
fn scatter_in<S: Simd>(simd: S, source: Source<'_>, band: &mut Band<'_>) {
    let n = F::<S>::LEN;
    let lanes = Lanes::new(simd, source.map);
    let (shift, parallax) = (F::<S>::splat(simd, source.shift.shift), F::<S>::splat(simd, source.shift.parallax));
    let first_columns = F::<S>::float_from(lane_index(simd));
    let colour = U::<S>::splat(simd, COLOUR);
    let sign = U::<S>::splat(simd, 1 << 31);
    let target_width = source.map.target_size.0 as usize;
    let [own_keys, other_keys] = &mut band.keys;
    let len = own_keys.depth.len();
    let rows = (len / target_width) as u32;
    debug_assert!(len == rows as usize * target_width, "a band of whole rows");
    debug_assert!(
        [own_keys.colour.len(), other_keys.depth.len(), other_keys.colour.len()] == [len; 3],
        "both eyes' bands alike"
    );
    let first_row = F::<S>::splat(simd, band.first as f32);
    // The last, partial vector of a row, padded (its padding lanes land nowhere: they are
    // not emitted).
    let (mut z_tail, mut rgb_tail) = ([0.0_f32; 16], [0_u32; 16]);
    let rows_of = source.z.chunks_exact(source.width).zip(source.rgb.chunks_exact(source.width));
    for (j, ((z_row, rgb_row), reach)) in rows_of.zip(source.reach).enumerate() {
        let Some(reached) = *reach else { continue };
        if !meets(reached, band.first, rows) {
            continue;
        }
        let h = source.map.row(j as u32);
        let h_row = [F::<S>::splat(simd, h[0]), F::<S>::splat(simd, h[1]), F::<S>::splat(simd, h[2])];
        let at = RowMap { lanes: &lanes, h_row, first_row, shift, parallax, first_columns, colour };
        let lands = |k: usize, z: F<S>, rgb: U<S>| lands_vector(simd, &at, k, z, rgb);
        // Four vectors at a time, all landed before any is kept: more independent work
        // between the branches (12 % faster than one at a time; eight spill registers).
        let quads = z_row.chunks_exact(4 * n).zip(rgb_row.chunks_exact(4 * n));
        let done = quads.len() * 4 * n;
        for (k, (z, rgb)) in quads.enumerate() {
            let part = |q: usize| q * n..(q + 1) * n;
            let (z0, z1, z2, z3) = (&z[part(0)], &z[part(1)], &z[part(2)], &z[part(3)]);
            let (c0, c1, c2, c3) = (&rgb[part(0)], &rgb[part(1)], &rgb[part(2)], &rgb[part(3)]);
            let v = [
                lands(4 * k, F::<S>::from_slice(simd, z0), U::<S>::from_slice(simd, c0)),
                lands(4 * k + 1, F::<S>::from_slice(simd, z1), U::<S>::from_slice(simd, c1)),
                lands(4 * k + 2, F::<S>::from_slice(simd, z2), U::<S>::from_slice(simd, c2)),
                lands(4 * k + 3, F::<S>::from_slice(simd, z3), U::<S>::from_slice(simd, c3)),
            ];
            for v in v {
                emit(simd, own_keys, v.own, (v.depth ^ sign).bitcast(), v.colour, n);
                emit(simd, other_keys, v.there, v.depth.bitcast(), v.colour, n);
            }
        }
        for (k, (z, rgb)) in z_row[done..].chunks(n).zip(rgb_row[done..].chunks(n)).enumerate() {
            let count = z.len();
            let (z, rgb) = if count == n {
                (F::<S>::from_slice(simd, z), U::<S>::from_slice(simd, rgb))
            } else {
                z_tail[..count].copy_from_slice(z);
                rgb_tail[..count].copy_from_slice(rgb);
                (F::<S>::from_slice(simd, &z_tail[..n]), U::<S>::from_slice(simd, &rgb_tail[..n]))
            };
            let v = lands(done / n + k, z, rgb);
            emit(simd, own_keys, v.own, (v.depth ^ sign).bitcast(), v.colour, count);
            emit(simd, other_keys, v.there, v.depth.bitcast(), v.colour, count);
        }
    }
}

/// What [`lands_vector`] needs of the pass and of one source row, in lanes.
struct RowMap<'a, S: Simd> {
    lanes: &'a Lanes<S>,
    h_row: [F<S>; 3],
    first_row: F<S>,
    shift: F<S>,
    parallax: F<S>,
    first_columns: F<S>,
    colour: U<S>,
}

/// Where a vector of pixels lands: its indices in the own eye's band and in the other's
/// (past their end for none), the bits of its depth (the other eye's first word; the own
/// eye's with the sign bit flipped), and its colour.
struct Landed<S: Simd> {
    own: U<S>,
    there: U<S>,
    depth: U<S>,
    colour: U<S>,
}

/// Where vector `k` of a row's pixels (depths `z`, colours `rgb`) lands.
#[inline(always)]
fn lands_vector<S: Simd>(simd: S, at: &RowMap<'_, S>, k: usize, z: F<S>, rgb: U<S>) -> Landed<S> {
    let n = F::<S>::LEN;
    let columns = at.first_columns + F::<S>::splat(simd, (k * n) as f32);
    let p = project(simd, at.lanes, at.h_row, columns, z);
    let depth = p.finite.select(p.nz, F::<S>::splat(simd, f32::INFINITY)).bitcast::<U<S>>();
    // The row (the same in both eyes), then the column in each. The band's own indices: a
    // lane that lands before the band wraps past its end, as does OUTSIDE (the target has
    // fewer than u32::MAX pixels).
    let row = land_row(simd, at.lanes, &p, at.first_row);
    let own = land(simd, at.lanes, &row, p.px);
    // The other eye, at the disparity: px + E·(1 − d/n_z); px + E for the background,
    // whose 1/n_z is 2⁻¹⁰⁰ times its direction's, too small to move px.
    let there = land(simd, at.lanes, &row, p.px + at.shift + at.parallax * p.inv);
    Landed { own, there, depth, colour: rgb & at.colour }
}

/// The w of a background pixel: 2¹⁰⁰, a power of two (so that w·h is exact) large enough
/// that g + w·h rounds to w·h, the point at infinity, and small enough not to overflow.
const FAR: f32 = (1_u128 << 100) as f32;

/// Where source pixels land, one per lane: continuous target coordinates (px, py), n_z
/// (the target depth plus d, > 0 in front of the target eye) and its reciprocal, and
/// whether the pixel is a surface (finite depth) rather than background.
struct Projected<S: Simd> {
    px: F<S>,
    py: F<S>,
    nz: F<S>,
    inv: F<S>,
    finite: M<S>,
}

/// Projects the source pixels (`columns`, row of `h_row`) of depth `z` to the target: n =
/// g + w·h, w = z + d; for the background w = [`FAR`], which makes px = h_x/h_z and
/// py = h_y/h_z bit for bit (scaling by a power of two is exact), the direction alone.
#[inline(always)]
fn project<S: Simd>(simd: S, lanes: &Lanes<S>, h_row: [F<S>; 3], columns: F<S>, z: F<S>) -> Projected<S> {
    let finite = z.simd_lt(F::<S>::splat(simd, f32::INFINITY));
    let w = finite.select(z + lanes.distance, F::<S>::splat(simd, FAR));
    let n = |a: usize| lanes.g[a] + w * (h_row[a] + columns * lanes.h_i[a]);
    let (nx, ny, nz) = (n(0), n(1), n(2));
    let inv = F::<S>::splat(simd, 1.0) / nz;
    Projected { px: nx * inv, py: ny * inv, nz, inv, finite }
}

/// The row part of each lane's landing: whether it lands in front of the target eye, and
/// the band-relative index of its row's first pixel, as a float (whole numbers, exact
/// below 2²⁴; far outside the band where they are not).
struct Row<S: Simd> {
    ahead: M<S>,
    first: F<S>,
}

/// [`Row`] of the projected lanes `p`, in the band from target row `first_row`.
#[inline(always)]
fn land_row<S: Simd>(simd: S, lanes: &Lanes<S>, p: &Projected<S>, first_row: F<S>) -> Row<S> {
    Row { ahead: p.nz.simd_gt(F::<S>::splat(simd, 0.0)), first: (floor(simd, p.py) - first_row) * lanes.width }
}

/// The pixel of the band each lane lands on, in the row `row` and at column coordinate
/// `px`: its index in the band's keys, past their end (as an unsigned number) for a lane
/// that lands outside the band, before it or after it, or outside the target.
#[inline(always)]
fn land<S: Simd>(simd: S, lanes: &Lanes<S>, row: &Row<S>, px: F<S>) -> U<S> {
    let inside = row.ahead & px.simd_ge(F::<S>::splat(simd, 0.0)) & px.simd_lt(lanes.width);
    // A row outside the band gives an index outside it, negative (a large unsigned number)
    // or past its end; a float out of the i32 range converts to i32::MIN (x86) or
    // saturates (aarch64), both outside.
    let index = I::<S>::truncate_from(row.first + floor(simd, px)).bitcast::<U<S>>();
    inside.select(index, U::<S>::splat(simd, OUTSIDE))
}

/// ⌊x⌋ in each lane, exact below 2³¹ (far outside any image; beyond, a large or negative
/// number, outside it too). SSE2 alone has no floor instruction, and `fearless_simd` then
/// floors lane by lane through libm: there it is a truncation, less one where that rounded
/// up. Both give the same bits.
#[inline(always)]
fn floor<S: Simd>(simd: S, x: F<S>) -> F<S> {
    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    let native = simd.level().as_sse4_2().is_some();
    #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
    let native = true;
    if native {
        x.floor()
    } else {
        let t = F::<S>::float_from(I::<S>::truncate_from(x));
        x.simd_lt(t).select(t - F::<S>::splat(simd, 1.0), t)
    }
}

/// Lands each of the first `count` lanes' keys (first words `word`, colours `colour`) on
/// its pixel of the band (`local`, its index in the band's keys), where its first word is
/// smaller than the one there. A whole vector landing on consecutive pixels (where the image
/// neither stretches nor folds) is compared and stored as two vectors.
#[inline(always)]
fn emit<S: Simd>(simd: S, keys: &mut KeysMut<'_>, local: U<S>, word: I<S>, colour: U<S>, count: usize) {
    let n = U::<S>::LEN;
    let len = keys.depth.len();
    let first = local.as_slice()[0] as usize;
    if count == n && first + n <= len {
        let at_first = local.simd_eq(U::<S>::splat(simd, first as u32) + lane_index(simd));
        if at_first.all_true() {
            emit_window(simd, keys, first, None, word, colour);
            return;
        }
        // Where the image stretches or folds by a pixel: the first lanes side by side from
        // the first lane's pixel, the others side by side up to the last lane's. Each part
        // lands as a vector, the first part first, so that a pixel two lanes reach sees them
        // in their order, as lane by lane.
        let last = local.as_slice()[n - 1];
        let base = last.wrapping_sub(n as u32 - 1) as usize;
        if base + n <= len {
            let at_base = local.simd_eq(U::<S>::splat(simd, base as u32) + lane_index(simd));
            let (head, tail) = (at_first.to_bitmask(), at_base.to_bitmask());
            if head & (head + 1) == 0 && head | tail == (1 << n) - 1 {
                emit_window(simd, keys, first, Some(at_first), word, colour);
                emit_window(simd, keys, base, Some(at_base), word, colour);
                return;
            }
        }
    }
    // Lanes that land outside the band (in the guard band's margin, or in the rows of
    // another band) wrap past its end.
    if local.simd_lt(U::<S>::splat(simd, len as u32)).any_true() {
        emit_lanes(keys, local.as_slice(), word.as_slice(), colour.as_slice(), count);
    }
}

/// Lands the lanes `lanes` (all if `None`) of a vector of keys on the band's pixels from
/// `first` on, lane l on pixel `first` + l, where their first words are smaller.
#[inline(always)]
fn emit_window<S: Simd>(simd: S, keys: &mut KeysMut<'_>, first: usize, lanes: Option<M<S>>, word: I<S>, colour: U<S>) {
    let n = U::<S>::LEN;
    let (there, there_colour) = (&mut keys.depth[first..first + n], &mut keys.colour[first..first + n]);
    let old = I::<S>::from_slice(simd, there);
    let nearer = word.simd_lt(old);
    let nearer = match lanes {
        Some(lanes) => nearer & lanes,
        None => nearer,
    };
    // The other eye's pixels mostly land where the own eye's are already.
    if nearer.any_true() {
        nearer.select(word, old).store_slice(there);
        nearer.select(colour, U::<S>::from_slice(simd, there_colour)).store_slice(there_colour);
    }
}

/// [`emit`] lane by lane, for the vectors that do not land side by side: scalar code, kept
/// out of the kernel's loop.
#[cold]
#[inline(never)]
fn emit_lanes(keys: &mut KeysMut<'_>, local: &[u32], word: &[i32], colour: &[u32], count: usize) {
    let (local, word, colour) = (&local[..count], &word[..count], &colour[..count]);
    let depth = &mut *keys.depth;
    let colours = &mut keys.colour[..depth.len()];
    for l in 0..count {
        let t = local[l] as usize;
        if t < depth.len() && word[l] < depth[t] {
            (depth[t], colours[t]) = (word[l], colour[l]);
        }
    }
}

/// Lane l holds l.
#[inline(always)]
fn lane_index<S: Simd>(simd: S) -> U<S> {
    const INDEX: [u32; 16] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15];
    U::<S>::from_slice(simd, &INDEX[..U::<S>::LEN])
}

/// Where source pixel (i, j) of depth `z` lands in `map`'s target, by the kernel itself
/// (lane 0, at the process's level): its continuous coordinates and n_z = z_t + d_t (for
/// the background, of its direction only), or `None` behind the target eye.
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

#[cfg(test)]
mod tests {
    use fearless_simd::{dispatch, prelude::*, Simd};

    use super::{emit, emit_lanes, KeysMut, I, OUTSIDE, U};

    /// The keys `emit` leaves for the lanes' pixels `local`, first words `word` and
    /// colours `colour`, landed on `keys` (first words, colours).
    fn emitted<S: Simd>(
        simd: S,
        keys: &(Vec<i32>, Vec<u32>),
        local: &[u32],
        word: &[i32],
        colour: &[u32],
    ) -> (Vec<i32>, Vec<u32>) {
        let n = U::<S>::LEN;
        let (mut depth, mut colours) = keys.clone();
        let (local, word, colour) = (&local[..n], &word[..n], &colour[..n]);
        emit(
            simd,
            &mut KeysMut { depth: &mut depth, colour: &mut colours },
            U::<S>::from_slice(simd, local),
            I::<S>::from_slice(simd, word),
            U::<S>::from_slice(simd, colour),
            n,
        );
        (depth, colours)
    }

    /// The lane count of `S`.
    fn lanes<S: Simd>(_: S) -> usize {
        U::<S>::LEN
    }

    #[test]
    fn a_vector_lands_as_its_lanes_do_one_by_one() {
        // Side by side, stretched by a pixel, folded onto one, scattered, partly outside
        // the band, at its ends: the vector paths leave the keys lane by lane does, ties
        // to the first lane.
        let mut rng = tracer::testing::XorShift::new(0x2545_f491);
        let mut next = move |m: u32| rng.next_u32() % m;
        let len = 64_usize;
        for level in tracer::simd_levels() {
            let n = dispatch!(level, simd => lanes(simd));
            for trial in 0..20_000 {
                let keys: (Vec<i32>, Vec<u32>) =
                    ((0..len).map(|_| next(6) as i32 - 3).collect(), (0..len).map(|k| k as u32).collect());
                let first = next(len as u32 + 4);
                let cut = 1 + next(n as u32 - 1);
                let local: Vec<u32> = (0..n as u32)
                    .map(|l| match trial % 5 {
                        0 => first + l,
                        1 => first + l + u32::from(l >= cut),
                        2 => (first + l).wrapping_sub(u32::from(l >= cut)),
                        3 => next(len as u32 + 8),
                        _ => {
                            if l == cut {
                                OUTSIDE
                            } else {
                                first + l
                            }
                        }
                    })
                    .collect();
                let word: Vec<i32> = (0..n).map(|_| next(6) as i32 - 3).collect();
                let colour: Vec<u32> = (0..n as u32).map(|l| 1000 + l).collect();
                let vector = dispatch!(level, simd => emitted(simd, &keys, &local, &word, &colour));
                let mut lanes = keys.clone();
                emit_lanes(&mut KeysMut { depth: &mut lanes.0, colour: &mut lanes.1 }, &local, &word, &colour, n);
                assert_eq!(vector, lanes, "{level:?}, trial {trial}: pixels {local:?}, words {word:?}");
            }
        }
    }
}
