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

use fearless_simd::{dispatch, Simd};
use glam::Vec3;

use crate::accel::{skipped, Packet, PACKET};
use crate::camera::EyeView;
use crate::ray::{leaves_outwards, spawn_ray};
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
fn direction(n: Vec3, (t, b): (Vec3, Vec3), (u1, u2): (f32, f32)) -> Vec3 {
    let r = u1.sqrt();
    let (sin, cos) = (std::f32::consts::TAU * u2).sin_cos();
    t * (r * cos) + b * (r * sin) + n * (1.0 - u1).sqrt()
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

    /// The direction of occlusion ray `s`.
    pub(crate) fn get(self, s: u32) -> Vec3 {
        let (a, b) = sobol2(s);
        direction(self.n, self.basis, (unit(a ^ self.scramble.0), unit(b ^ self.scramble.1)))
    }
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
const HITS_MAX: usize = 16;

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
        for (h, &(object, (p, n), pixel)) in hits.iter().enumerate() {
            let directions = Directions::new(n, pixel);
            for s in 0..ao.samples {
                let dir = directions.get(s);
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
