//! Ray-traced ambient occlusion at a primary hit (pbrt-v4's `AOIntegrator`; Tachyon's and
//! ChimeraX's ambient shadows, QuteMol's per-atom occlusion made per pixel).
//!
//! At point p (unit outward normal n) of sphere k, hit by the primary ray of pixel (x, y)
//! of the traced view, ray s = 0..N leaves p as a shadow ray does ([`spawn_ray`]) along a
//! cosine-weighted direction about n (Malley's method), and asks the aggregate whether any
//! sphere lies within `distance` (an any-hit query, sphere k left out as for any ray that
//! leaves it outwards). The fraction that meet one estimates the cosine-weighted occluded
//! share of the hemisphere, and the ambient term is scaled by `1 − strength · share`.
//!
//! The directions are the first two dimensions of Sobol's (0, 2)-sequence, point s,
//! scrambled by a random digit scramble (an XOR; Kollig & Keller 2002) drawn from a hash
//! of (x, y): a function of the pixel and the sample index alone, never of threads, lanes,
//! batches or which other pixels are traced, so an image with occlusion is the same bytes
//! however it is made, and an eye traced in parts (exact mode, a progressive viewer) casts
//! the very rays of a whole one. Both shading paths call [`Tracer::ambient_factor`].

#![expect(
    clippy::inline_always,
    reason = "the packets are made and sent inside the dispatched lane kernel, whose target features they need"
)]

use fearless_simd::{dispatch, prelude::*, Simd};
use glam::Vec3;

use crate::accel::{skipped, Packet, PACKET};
use crate::camera::EyeView;
use crate::ray::{leaves_outwards, spawn_ray};
use crate::simd::{each3, F, U};
use crate::stats::RayCounts;
use crate::tracer::Tracer;

/// Where a batch's pixels lie: their row of the traced view, and the view's guard band, so
/// that a pixel is seeded by its place in the shown image: a view traced with a band (the
/// viewer's, for its timewarp) casts the rays of one without (`render`'s).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SeedRow {
    /// The row of the traced view.
    pub(crate) row: u32,
    /// The view's guard band, (columns, rows) ([`EyeView::margin`]).
    pub(crate) margin: (u32, u32),
}

impl SeedRow {
    /// Row `row` of `view`.
    pub(crate) fn of(view: &EyeView, row: u32) -> Self {
        Self { row, margin: view.margin }
    }

    /// The seed of the traced view's pixel (x, y): its place in the shown image (wrapping
    /// in the band above and left of it).
    pub(crate) fn shown(self, (x, y): (u32, u32)) -> (u32, u32) {
        (x.wrapping_sub(self.margin.0), y.wrapping_sub(self.margin.1))
    }
}

/// An integer hash with good avalanche (Wellons's "lowbias32").
fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

/// Pixel (x, y)'s scramble of each of the two dimensions.
pub(crate) fn scramble(x: u32, y: u32) -> (u32, u32) {
    let a = hash(x.wrapping_mul(0x9e37_79b9) ^ hash(y ^ 0x85eb_ca6b));
    (a, hash(a ^ 0x68e3_1da4))
}

/// Point `s` of the first two dimensions of Sobol's sequence, as 32-bit fractions: the
/// bit-reversed index (van der Corput), and the second dimension's generator (each
/// direction number the last XOR itself shifted right by one: Pascal's matrix mod 2).
pub(crate) fn sobol2(s: u32) -> (u32, u32) {
    let (mut second, mut v, mut i) = (0u32, 1u32 << 31, s);
    while i != 0 {
        if i & 1 != 0 {
            second ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    (s.reverse_bits(), second)
}

/// A 32-bit fraction's top 24 bits as an `f32` in [0, 1 − 2⁻²⁴].
fn unit(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// An orthonormal basis (t, b) of the plane normal to unit `n` (Duff et al. 2017,
/// "Building an orthonormal basis, revisited").
fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// The cosine-weighted direction about unit `n` (with its basis `(t, b)`, [`basis`]) of
/// the point (u1, u2) of the unit square: a uniform point of the unit disc (radius √u1,
/// angle 2π·u2) lifted to the hemisphere. u1 ≤ 1 − 2⁻²⁴ keeps it at least 2⁻¹² above the
/// horizon, so it leaves outwards.
#[cfg(test)]
fn direction(n: Vec3, (t, b): (Vec3, Vec3), (u1, u2): (f32, f32)) -> Vec3 {
    let r = u1.sqrt();
    let (cos, sin) = turn(u2);
    t * (r * cos) + b * (r * sin) + n * (1.0 - u1).sqrt()
}

/// (cos 2πu, sin 2πu) for u in [0, 1], within 10⁻⁶, in plain `f32` arithmetic (the same
/// bits on every machine, where `libm`'s `sin_cos` is a call, and may differ): the nearest
/// quarter turn q is split off exactly (4u is exact, and so is 4u − q), the rest, an angle
/// x in [−π/4, π/4], goes through Taylor polynomials (the first terms left out below
/// |x|¹¹/11! and |x|¹²/12!, under 10⁻⁸), and the quarter turns rotate the result.
#[cfg(test)]
pub(crate) fn turn(u: f32) -> (f32, f32) {
    let four = 4.0 * u;
    // The nearest quarter (a conversion, not `round`, which may be a call).
    #[expect(clippy::cast_possible_truncation, clippy::cast_sign_loss, reason = "4u + ½ is 0.5 to 4.5")]
    let q = (four + 0.5) as u32;
    let x = (four - q as f32) * std::f32::consts::FRAC_PI_2;
    let x2 = x * x;
    let sin = x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let cos =
        1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0 + x2 * (-1.0 / 3_628_800.0)))));
    match q & 3 {
        0 => (cos, sin),
        1 => (-sin, cos),
        2 => (-cos, -sin),
        _ => (sin, -cos),
    }
}

/// A point's occlusion directions: those of one pixel about one normal, the pixel's
/// scramble and the normal's basis made once for all its samples.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Directions {
    n: Vec3,
    basis: (Vec3, Vec3),
    scramble: (u32, u32),
}

impl Directions {
    /// The directions of pixel `pixel` about unit normal `n`.
    pub(crate) fn new(n: Vec3, pixel: (u32, u32)) -> Self {
        Self { n, basis: basis(n), scramble: scramble(pixel.0, pixel.1) }
    }

    /// The direction of occlusion ray `s`: the plain arithmetic that [`directions_in`]
    /// runs across lanes.
    #[cfg(test)]
    pub(crate) fn get(self, s: u32) -> Vec3 {
        let (a, b) = sobol2(s);
        direction(self.n, self.basis, (unit(a ^ self.scramble.0), unit(b ^ self.scramble.1)))
    }
}

/// Most samples a hit whose directions [`directions_in`] makes at once.
pub(super) const BLOCK: usize = 16;

/// The directions of samples `first..first + count` (`count` ≤ [`BLOCK`]) of each of
/// `points` (at most 16) into `out[h][k]`: [`Directions::get`]'s arithmetic, operation for
/// operation (so the same bits), across the lanes of a kernel, a lane a point.
#[inline(always)]
pub(super) fn directions_in<S: Simd>(
    simd: S,
    points: &[Directions],
    (first, count): (u32, usize),
    out: &mut [[Vec3; BLOCK]; HITS_MAX],
) {
    let lanes = F::<S>::LEN;
    for (c, chunk) in points.chunks(lanes).enumerate() {
        // Per lane: the normal and its basis, and the pixel's scramble.
        let mut frame = [[0f32; HITS_MAX]; 9];
        let mut scramble = [[0u32; HITS_MAX]; 2];
        for (l, d) in chunk.iter().enumerate() {
            for a in 0..3 {
                (frame[a][l], frame[3 + a][l], frame[6 + a][l]) = (d.n[a], d.basis.0[a], d.basis.1[a]);
            }
            (scramble[0][l], scramble[1][l]) = d.scramble;
        }
        let column = |x: &[f32; HITS_MAX]| F::<S>::from_slice(simd, &x[..lanes]);
        let (n, t, b) =
            (each3(|a| column(&frame[a])), each3(|a| column(&frame[3 + a])), each3(|a| column(&frame[6 + a])));
        for (k, s) in (first..).take(count).enumerate() {
            let (sa, sb) = sobol2(s);
            let mut square = [[0f32; HITS_MAX]; 2];
            for l in 0..chunk.len() {
                square[0][l] = unit(sa ^ scramble[0][l]);
                square[1][l] = unit(sb ^ scramble[1][l]);
            }
            let (u1, u2) = (column(&square[0]), column(&square[1]));
            let r = u1.sqrt();
            let (cos, sin) = turn_lanes(simd, u2);
            let up = (F::<S>::splat(simd, 1.0) - u1).sqrt();
            let (rc, rs) = (r * cos, r * sin);
            let mut dir = [[0f32; HITS_MAX]; 3];
            for a in 0..3 {
                (t[a] * rc + b[a] * rs + n[a] * up).store_slice(&mut dir[a][..lanes]);
            }
            for l in 0..chunk.len() {
                out[c * lanes + l][k] = Vec3::new(dir[0][l], dir[1][l], dir[2][l]);
            }
        }
    }
}

/// [`turn`] lane by lane, with the same operations (the quarter's rotation by selects).
#[inline(always)]
fn turn_lanes<S: Simd>(simd: S, u: F<S>) -> (F<S>, F<S>) {
    let k = |x: f32| F::<S>::splat(simd, x);
    let four = k(4.0) * u;
    let q = U::<S>::truncate_from(four + k(0.5));
    let x = (four - F::<S>::float_from(q)) * k(std::f32::consts::FRAC_PI_2);
    let x2 = x * x;
    let sin =
        x * (k(1.0) + x2 * (k(-1.0 / 6.0) + x2 * (k(1.0 / 120.0) + x2 * (k(-1.0 / 5040.0) + x2 * k(1.0 / 362_880.0)))));
    let cos = k(1.0)
        + x2 * (k(-0.5)
            + x2 * (k(1.0 / 24.0) + x2 * (k(-1.0 / 720.0) + x2 * (k(1.0 / 40_320.0) + x2 * k(-1.0 / 3_628_800.0)))));
    let bit = |b: u32| (q & U::<S>::splat(simd, b)).simd_eq(U::<S>::splat(simd, b));
    let (odd, half) = (bit(1), bit(2));
    let (c, s) = (odd.select(-sin, cos), odd.select(cos, sin));
    (half.select(-c, c), half.select(-s, s))
}

/// The direction of occlusion ray `s` of pixel `pixel` at a point of unit normal `n`.
#[cfg(test)]
pub(crate) fn sample_direction(n: Vec3, pixel: (u32, u32), s: u32) -> Vec3 {
    Directions::new(n, pixel).get(s)
}

/// A primary hit whose occlusion is wanted: its sphere, its point and unit outward normal,
/// and its pixel of the traced view (the seed).
pub(crate) type AoHit = (u32, (Vec3, Vec3), (u32, u32));

/// Most hits [`Tracer::occluded_shares_in`] takes at once: the widest lanes.
pub(super) const HITS_MAX: usize = 16;

/// Occlusion rays gathered into a packet: directions, and groups of one hit's rays that
/// leave to one side (one origin, one sphere left out), with the hit and side of each.
struct Gathered {
    dirs: [Vec3; PACKET],
    groups: [(Vec3, u32, u16); PACKET],
    owner: [(usize, bool); PACKET],
    rays: usize,
    group_count: usize,
}

impl Gathered {
    /// The group of the rays of hit and side `side` in the packet, opened (with the origin
    /// and sphere left out `spawn` gives) if it has none yet.
    #[inline(always)]
    fn group_of(&mut self, side: (usize, bool), spawn: impl FnOnce() -> (Vec3, u32)) -> usize {
        self.owner[..self.group_count].iter().rposition(|&o| o == side).unwrap_or_else(|| {
            let (g, (origin, skip)) = (self.group_count, spawn());
            (self.groups[g], self.owner[g]) = ((origin, skip, 0), side);
            self.group_count += 1;
            g
        })
    }

    /// Sends the packet down the BVH, adds each group's blocked rays to its hit's count in
    /// `blocked`, and empties it.
    #[inline(always)]
    fn flush<S: Simd>(&mut self, simd: S, tracer: &Tracer, t_max: f32, blocked: &mut [u32; HITS_MAX]) {
        let (dirs, groups) = (&self.dirs[..self.rays], &self.groups[..self.group_count]);
        let hit = tracer.accel.occluded_packet_in(simd, Packet { dirs, groups }, t_max);
        for (&(_, _, members), &(h, _)) in groups.iter().zip(&self.owner) {
            blocked[h] += (hit & members).count_ones();
        }
        (self.rays, self.group_count) = (0, 0);
    }
}

impl Tracer {
    /// The share of occlusion rays from point `p` (unit outward normal `n`) of sphere
    /// `object`, hit by the primary ray of `pixel` of the traced view, that meet a sphere
    /// within the scene's distance: the cosine-weighted occluded share, estimated. Counts
    /// the rays as shadow rays (any-hit queries). 0 when occlusion is off.
    pub(crate) fn occluded_share(
        &self,
        object: u32,
        (p, n): (Vec3, Vec3),
        pixel: (u32, u32),
        counts: &mut RayCounts,
    ) -> f32 {
        let mut share = [0.0];
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.occluded_shares_in(simd, &[(object, (p, n), pixel)], &mut share, counts),
        ));
        share[0]
    }

    /// [`Tracer::occluded_share`] of each of `hits` (at most 16) into `shares`, inside a
    /// lane kernel: the hits' rays go down the BVH in packets of [`PACKET`], several hits'
    /// to a packet, each ray answered as on its own
    /// ([`crate::accel::Aggregate::occluded_packet_in`]).
    #[inline(always)]
    pub(crate) fn occluded_shares_in<S: Simd>(
        &self,
        simd: S,
        hits: &[AoHit],
        shares: &mut [f32],
        counts: &mut RayCounts,
    ) {
        debug_assert!(hits.len() <= HITS_MAX && shares.len() == hits.len(), "{} hits", hits.len());
        let ao = self.scene.settings.cues.ambient_occlusion;
        if !ao.is_on() {
            shares.fill(0.0);
            return;
        }
        let mut blocked = [0u32; HITS_MAX];
        let mut packet = Gathered {
            dirs: [Vec3::ZERO; PACKET],
            groups: [(Vec3::ZERO, 0, 0); PACKET],
            owner: [(0, false); PACKET],
            rays: 0,
            group_count: 0,
        };
        let mut points = [Directions { n: Vec3::Z, basis: (Vec3::X, Vec3::Y), scramble: (0, 0) }; HITS_MAX];
        for (d, &(_, (_, n), pixel)) in points.iter_mut().zip(hits) {
            *d = Directions::new(n, pixel);
        }
        let mut block = [[Vec3::ZERO; BLOCK]; HITS_MAX];
        for first in (0..ao.samples).step_by(BLOCK) {
            let count = BLOCK.min((ao.samples - first) as usize);
            directions_in(simd, &points[..hits.len()], (first, count), &mut block);
            for (h, &(object, (p, n), _)) in hits.iter().enumerate() {
                for &dir in &block[h][..count] {
                    let side = (h, leaves_outwards(n, dir));
                    let g = packet.group_of(side, || (spawn_ray(p, n, dir).origin, skipped(object, n, dir)));
                    packet.groups[g].2 |= 1 << packet.rays;
                    packet.dirs[packet.rays] = dir;
                    packet.rays += 1;
                    if packet.rays == PACKET {
                        packet.flush(simd, self, ao.distance, &mut blocked);
                    }
                }
            }
        }
        if packet.rays > 0 {
            packet.flush(simd, self, ao.distance, &mut blocked);
        }
        for (share, &blocked) in shares.iter_mut().zip(&blocked) {
            *share = blocked as f32 / ao.samples as f32;
        }
        counts.shadow += u64::from(ao.samples) * hits.len() as u64;
    }

    /// The ambient term at a primary hit: the scene's ambient scaled by
    /// `1 − strength · occluded share` ([`Tracer::occluded_share`]); the ambient itself when
    /// occlusion is off. The one formula of both shading paths.
    pub(crate) fn ambient_at(
        &self,
        object: u32,
        (p, n): (Vec3, Vec3),
        pixel: (u32, u32),
        counts: &mut RayCounts,
    ) -> f32 {
        if !self.scene.settings.cues.ambient_occlusion.is_on() {
            return self.scene.settings.ambient;
        }
        let share = self.occluded_share(object, (p, n), pixel, counts);
        self.ambient_of(share)
    }

    /// The ambient term of a primary hit whose occluded share is `share` (0 when occlusion
    /// is off): [`Tracer::ambient_at`]'s formula.
    pub(crate) fn ambient_of(&self, share: f32) -> f32 {
        let settings = &self.scene.settings;
        if !settings.cues.ambient_occlusion.is_on() {
            return settings.ambient;
        }
        settings.ambient * (1.0 - settings.cues.ambient_occlusion.strength * share)
    }
}
