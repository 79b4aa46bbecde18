//! Where moving spheres can ever be: a conservative swept volume per orbit, and the test of
//! a ray segment against it. An `orbit` sphere of radius r revolving on a circle of radius R
//! sweeps a torus; its bound is the washer that holds it (the slab |y − c.y| ≤ r and the
//! annulus R − r ≤ ρ ≤ R + r), every limit widened by a margin far above the float error, so
//! rounding only makes the test say "meets" more often. [`Touch`] keeps the arc of the
//! ring's angle (in *diamond angles*, a monotone, division-only stand-in for `atan2`) that
//! a ray tree crosses; the sphere at one instant fills only a wedge of its washer
//! ([`SweptRing::wedge`]). A tree whose arc misses the wedges of two instants meets the
//! sphere at neither, and is the same tree at both: the ground of exact temporal reuse
//! (after Adelson & Hodges 1995). The construction and the lemma, with their proofs:
//! `docs/design/swept-volumes.md` and `docs/design/reuse-exactness.md`.

use glam::Vec3;

use crate::scene::Motion;

/// Relative size of the margin: against the largest coordinate involved, ~1700× the f32
/// epsilon, far above the few roundings in a centre from `Motion::center_at` or in a hit
/// point on the sphere.
const MARGIN: f32 = 1e-4;

/// The swept volume of one orbiting sphere: a washer about a vertical axis (see the module
/// doc), its limits already widened by the margin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptRing {
    /// Centre of the orbit.
    pub center: Vec3,
    /// Half-height of the slab: the sphere's radius plus the margin.
    pub half_height: f32,
    /// Inner radius of the annulus (R − r − margin, at least 0).
    pub inner: f32,
    /// Outer radius of the annulus (R + r + margin).
    pub outer: f32,
    /// The widening each limit has.
    pub margin: f32,
    /// The square of a radius about the centre that holds the washer, with room for
    /// rounding.
    ball2: f32,
    /// The sphere (its index in the scene) that moves in it.
    pub object: u32,
}

impl SweptRing {
    /// The bound of sphere `object`, of radius `radius`, moving as `motion`; `None` for a
    /// sphere that does not move.
    #[must_use]
    pub fn of(object: u32, radius: f32, motion: &Motion) -> Option<Self> {
        let Motion::Orbit { center, radius: ring, .. } = *motion else { return None };
        let margin = MARGIN * (1.0 + center.abs().max_element() + ring + radius);
        let (half_height, outer) = (radius + margin, ring + radius + margin);
        let ball = outer.hypot(half_height) + margin;
        Some(Self {
            center,
            half_height,
            inner: (ring - radius - margin).max(0.0),
            outer,
            margin,
            ball2: ball * ball,
            object,
        })
    }

    /// The ring's angle of the point `p`, in units of 2⁻³² turn (see [`Arc`]): growing
    /// with θ of `Motion::center_at`, 0 at θ = 0.
    #[must_use]
    pub fn angle_of(&self, p: Vec3) -> u32 {
        let q = p - self.center;
        units(diamond(q.x, -q.z))
    }

    /// The wedge of the washer that holds the sphere, of radius `r`, centred at `c`: every
    /// angle of a point of the sphere lies in the arc. The whole circle when the sphere
    /// reaches the axis.
    #[must_use]
    pub fn wedge(&self, c: Vec3, r: f32) -> Arc {
        let q = c - self.center;
        let (a, b) = (-q.z, q.x);
        let rho = a.hypot(b);
        let sine = (r + 2.0 * self.margin) / rho;
        if sine.is_nan() || sine >= 1.0 {
            return Arc::FULL;
        }
        // The centre's direction turned by ∓ the half-angle asin(sine) < π/2.
        let cosine = (1.0 - sine * sine).sqrt();
        let from = units(diamond(a * (-sine) + b * cosine, a * cosine + b * sine));
        let to = units(diamond(a * sine + b * cosine, a * cosine - b * sine));
        Arc::widened(from, to.wrapping_sub(from))
    }

    /// The arc of angles the segment `o + s·d`, 0 ≤ s ≤ `s_max`, crosses the washer in, if
    /// it meets it ([`SweptRing::meets`]). Conservative: the part of the segment between
    /// the slab's planes and inside the outer cylinder, hole and all, swept as seen from
    /// the axis.
    #[must_use]
    pub fn touch(&self, o: Vec3, d: Vec3, s_max: f32) -> Option<Arc> {
        let Crossing { q, mut lo, mut hi, a, b, k } = self.crossing(o, d, s_max)?;
        if a > 0.0 {
            // ρ²(s) ≤ outer²: between the roots of a·s² + 2b·s + (k − outer²).
            let disc = b * b - a * (k - self.outer * self.outer);
            if disc > 0.0 {
                let root = disc.sqrt();
                (lo, hi) = (lo.max((-b - root) / a), hi.min((-b + root) / a));
            }
        }
        if lo.is_nan() || hi.is_nan() || lo > hi || !hi.is_finite() {
            // Rounding at a tangent, or a ray along the axis: claim the whole circle.
            return Some(Arc::FULL);
        }
        let (pa, pb) = (q + lo * d, q + hi * d);
        // Seen from the axis, a straight segment sweeps less than half a turn, unless it
        // passes (nearly) through the axis.
        let near_axis = pa.x * pa.x + pa.z * pa.z < self.margin * self.margin
            || pb.x * pb.x + pb.z * pb.z < self.margin * self.margin;
        Some(Self::arc_between(diamond(pa.x, -pa.z), diamond(pb.x, -pb.z), near_axis))
    }

    /// The arc a straight segment sweeps, seen from the axis, between the diamond angles
    /// `fa` and `fb` of its ends: less than half a turn, the shorter way round, widened by
    /// the slack; the whole circle if `full` or if it is (nearly) half a turn, as when the
    /// segment passes through the axis.
    #[must_use]
    pub(crate) fn arc_between(fa: f32, fb: f32, full: bool) -> Arc {
        let (fa, fb) = (units(fa), units(fb));
        let sweep = fb.wrapping_sub(fa) as i32;
        if full || sweep.unsigned_abs() > (1 << 31) - SLACK_UNITS * 8 {
            return Arc::FULL;
        }
        let start = if sweep >= 0 { fa } else { fb };
        Arc::widened(start, sweep.unsigned_abs())
    }

    /// The square of the radius of [`SweptRing::crossing`]'s first, cheap test.
    pub(crate) fn ball2(&self) -> f32 {
        self.ball2
    }

    /// Radius of a ball about [`SweptRing::center`] that holds the washer.
    #[must_use]
    pub fn bounding_radius(&self) -> f32 {
        self.outer.hypot(self.half_height)
    }

    /// Whether the sphere of centre `c` and radius `r` lies in the washer. Every position of
    /// the orbit's sphere does, with the margin to spare; this is the invariant the reuse of
    /// frames rests on, asserted whenever a tracer places a moving sphere.
    #[must_use]
    pub fn holds(&self, c: Vec3, r: f32) -> bool {
        let q = c - self.center;
        let rho = q.x.hypot(q.z);
        q.y.abs() + r <= self.half_height && rho + r <= self.outer && (self.inner == 0.0 || rho - r >= self.inner)
    }

    /// Whether the segment `o + s·d`, 0 ≤ s ≤ `s_max` (+∞ for a ray), meets the washer.
    /// `d` need not be unit. Conservative: never `false` for a segment that meets it.
    #[must_use]
    pub fn meets(&self, o: Vec3, d: Vec3, s_max: f32) -> bool {
        self.crossing(o, d, s_max).is_some()
    }

    /// The segment's part in the slab, if it meets the washer there (see
    /// [`SweptRing::meets`]).
    #[inline]
    fn crossing(&self, o: Vec3, d: Vec3, s_max: f32) -> Option<Crossing> {
        // The segment is taken from its point nearest the centre: the origin, the end, or
        // the foot of the perpendicular. From there every square below is of a length about
        // the washer's size, not the camera's distance, so its rounding stays far under the
        // margin (from the origin, ρ²'s terms cancel to worse than the washer itself).
        let q = o - self.center;
        let (along, dd) = (-q.dot(d), d.length_squared());
        let s0 = if along <= 0.0 {
            0.0
        } else if along >= s_max * dd {
            s_max
        } else {
            along / dd
        };
        let q = q + s0 * d;
        // First the cheap test most segments fail: that point lies outside a ball that
        // holds the washer.
        if q.length_squared() > self.ball2 {
            return None;
        }
        // The slab: the part of the segment between the planes y = ±half_height, in s − s0.
        let (mut lo, mut hi) = (-s0, s_max - s0);
        if d.y == 0.0 {
            if q.y.abs() > self.half_height {
                return None;
            }
        } else {
            let inv = d.y.recip();
            let (a, b) = ((-self.half_height - q.y) * inv, (self.half_height - q.y) * inv);
            lo = lo.max(a.min(b));
            hi = hi.min(a.max(b));
            if lo.is_nan() || hi.is_nan() || lo > hi {
                return None;
            }
        }
        // The annulus: ρ²(s) = a·s² + 2b·s + k is convex, so over [lo, hi] it takes every
        // value between its least (at the vertex, clamped) and its greatest (at an end).
        let (a, b, k) = (d.x * d.x + d.z * d.z, q.x * d.x + q.z * d.z, q.x * q.x + q.z * q.z);
        let rho2 = |s: f32| if s.is_finite() { (a * s + 2.0 * b) * s + k } else { f32::INFINITY };
        let vertex = if a > 0.0 { (-b / a).clamp(lo, hi) } else { lo };
        let least = rho2(vertex);
        let greatest = if a > 0.0 { rho2(lo).max(rho2(hi)) } else { k };
        (least <= self.outer * self.outer && greatest >= self.inner * self.inner).then_some(Crossing {
            q,
            lo,
            hi,
            a,
            b,
            k,
        })
    }
}

/// A segment's part in a washer's slab: its point nearest the ring's centre, from that
/// centre, as `q`; its parameter range from that point; and ρ²(s) = a·s² + 2b·s + k.
#[derive(Clone, Copy, Debug)]
struct Crossing {
    q: Vec3,
    lo: f32,
    hi: f32,
    a: f32,
    b: f32,
    k: f32,
}

/// Widening of every arc, in units of 2⁻³² turn: 1e-4 of diamond angle (whose slope is at
/// most 1 per radian), far above the rounding of the points and of the division.
const SLACK_UNITS: u32 = 107_374;

/// The diamond angle of the direction (x, y): in [0, 4), growing with `atan2(y, x)` taken
/// in [0, 2π), a quarter turn per unit, exact at the axes.
#[inline]
fn diamond(y: f32, x: f32) -> f32 {
    // r = |y| / (|x| + |y|), the first quadrant's value, mirrored into the others (the
    // lanes of `reuse/lanes.rs` compute the same).
    let (ax, ay) = (x.abs(), y.abs());
    let sum = ax + ay;
    let r = if sum > 0.0 { ay / sum } else { 0.0 };
    match (y >= 0.0, x >= 0.0) {
        (true, true) => r,
        (true, false) => 2.0 - r,
        (false, false) => 2.0 + r,
        (false, true) => 4.0 - r,
    }
}

/// A diamond angle in units of 2⁻³² turn, so that angles wrap as `u32`s do.
#[inline]
fn units(diamond: f32) -> u32 {
    // Exact in f32: scaling by a power of two, and a diamond angle below 4 scales to an
    // integer below 2³². (4 itself, from rounding, wraps to 0 as the angle does.)
    (diamond * (1u32 << 30) as f32) as i64 as u32
}

/// An arc of a ring's angle: from `start`, `len` anticlockwise (as θ grows), in units of
/// 2⁻³² turn (a diamond angle times 2³⁰), so that angles wrap around as `u32`s do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Arc {
    /// First angle.
    pub start: u32,
    /// Length; `u32::MAX` is the whole circle.
    pub len: u32,
}

impl Arc {
    /// The whole circle.
    pub const FULL: Self = Self { start: 0, len: u32::MAX };

    /// The arc from `start`, `len` long, widened by the slack at both ends.
    fn widened(start: u32, len: u32) -> Self {
        match len.checked_add(2 * SLACK_UNITS) {
            Some(len) if len < u32::MAX => Self { start: start.wrapping_sub(SLACK_UNITS), len },
            _ => Self::FULL,
        }
    }

    /// Whether the two arcs share an angle.
    #[must_use]
    pub fn overlaps(self, other: Self) -> bool {
        other.start.wrapping_sub(self.start) <= self.len || self.start.wrapping_sub(other.start) <= other.len
    }

    /// Whether every angle of `other` lies in this arc.
    #[must_use]
    pub fn holds(self, other: Self) -> bool {
        self == Self::FULL
            || (other != Self::FULL
                && u64::from(other.start.wrapping_sub(self.start)) + u64::from(other.len) <= u64::from(self.len))
    }

    /// This arc with `by` more at both ends (the whole circle if that reaches round).
    #[must_use]
    pub fn grown(self, by: u32) -> Self {
        match u64::from(self.len) + 2 * u64::from(by) {
            len if len < u64::from(u32::MAX) => Self { start: self.start.wrapping_sub(by), len: len as u32 },
            _ => Self::FULL,
        }
    }

    /// The shortest arc holding both.
    #[must_use]
    pub fn hull(self, other: Self) -> Self {
        let reach =
            |a: Self, b: Self| u64::from(a.len).max(u64::from(b.start.wrapping_sub(a.start)) + u64::from(b.len));
        let (from_self, from_other) = (reach(self, other), reach(other, self));
        let (start, len) = if from_self <= from_other { (self.start, from_self) } else { (other.start, from_other) };
        if len >= u64::from(u32::MAX) {
            Self::FULL
        } else {
            Self { start, len: len as u32 }
        }
    }
}

/// Where a ray tree meets the moving spheres' swept volumes: nowhere, an arc of one ring,
/// or more than one ring (then it is taken to meet every wedge).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Touch {
    /// The ring (its index among the tracer's swept volumes), [`Touch::NONE_RING`] or
    /// [`Touch::MANY_RINGS`].
    pub ring: u32,
    /// The arc of that ring.
    pub arc: Arc,
}

impl Default for Touch {
    fn default() -> Self {
        Self::NONE
    }
}

impl Touch {
    /// `ring` of a tree that meets no swept volume.
    pub const NONE_RING: u32 = u32::MAX;
    /// `ring` of a tree that meets several.
    pub const MANY_RINGS: u32 = u32::MAX - 1;
    /// Meets nothing that moves.
    pub const NONE: Self = Self { ring: Self::NONE_RING, arc: Arc { start: 0, len: 0 } };

    /// Whether the tree meets any swept volume.
    #[must_use]
    pub fn is_some(self) -> bool {
        self.ring != Self::NONE_RING
    }

    /// Both trees' meetings together.
    #[must_use]
    pub fn union(self, other: Self) -> Self {
        match (self.ring, other.ring) {
            (Self::NONE_RING, _) => other,
            (_, Self::NONE_RING) => self,
            (a, b) if a == b && a != Self::MANY_RINGS => Self { ring: a, arc: self.arc.hull(other.arc) },
            _ => Self { ring: Self::MANY_RINGS, arc: Arc::FULL },
        }
    }

    /// Whether the tree may meet a sphere whose wedge of ring `ring` is `wedge`.
    #[must_use]
    pub fn meets_wedge(self, ring: u32, wedge: Arc) -> bool {
        self.ring == Self::MANY_RINGS || (self.ring == ring && self.arc.overlaps(wedge))
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    fn orbit(center: Vec3, radius: f32) -> Motion {
        Motion::Orbit { center, radius, period_s: 8.0, phase_deg: 30.0 }
    }

    #[test]
    fn units_in_f32_are_the_exact_f64_units() {
        let exact = |d: f32| (f64::from(d) * f64::from(1u32 << 30)) as u64 as u32;
        let four = 4.0f32.to_bits();
        for bits in (0..=four).step_by(997).chain([four, four - 1, 1, 0]) {
            let d = f32::from_bits(bits);
            assert_eq!(units(d), exact(d), "diamond angle {d:e}");
        }
        assert_eq!((units(f32::NAN), units(4.0)), (0, 0));
    }

    #[test]
    fn a_static_sphere_has_no_bound() {
        assert_eq!(SweptRing::of(0, 1.0, &Motion::Static(Vec3::ZERO)), None);
    }

    #[test]
    fn the_washer_leaves_out_the_middle_and_what_is_above() {
        // A ring of radius 2.5 about a sphere in its middle, swept by a sphere of 0.5.
        let ring = SweptRing::of(3, 0.5, &orbit(Vec3::new(0.0, 1.0, 15.0), 2.5)).unwrap();
        let down = Vec3::new(0.0, -1.0, 0.0);
        // Straight down through the centre (inside the hole) and down beside the ring.
        assert!(!ring.meets(Vec3::new(0.0, 10.0, 15.0), down, f32::INFINITY));
        assert!(!ring.meets(Vec3::new(3.5, 10.0, 15.0), down, f32::INFINITY));
        // Down through the ring itself, and a ray that ends just above it.
        assert!(ring.meets(Vec3::new(2.5, 10.0, 15.0), down, f32::INFINITY));
        assert!(!ring.meets(Vec3::new(2.5, 10.0, 15.0), down, 8.4));
        assert!(ring.meets(Vec3::new(2.5, 10.0, 15.0), down, 8.6));
        // Horizontal, above the slab and in it; a horizontal chord through the hole still
        // crosses the ring twice.
        let x = Vec3::X;
        assert!(!ring.meets(Vec3::new(-10.0, 1.6, 15.0), x, f32::INFINITY));
        assert!(ring.meets(Vec3::new(-10.0, 1.4, 15.0), x, f32::INFINITY));
        // A segment wholly inside the hole, and one wholly outside the ring.
        assert!(!ring.meets(Vec3::new(-1.0, 1.0, 15.0), x, 2.0));
        assert!(!ring.meets(Vec3::new(3.5, 1.0, 15.0), x, 5.0));
        // Pointing away.
        assert!(!ring.meets(Vec3::new(-10.0, 1.0, 15.0), -x, f32::INFINITY));
    }

    #[test]
    fn a_sphere_off_its_path_is_not_held() {
        let motion = orbit(Vec3::new(1.0, 2.0, 3.0), 2.0);
        let ring = SweptRing::of(0, 0.5, &motion).unwrap();
        let c = motion.center_at(1.3);
        assert!(ring.holds(c, 0.5));
        assert!(!ring.holds(c + Vec3::new(0.0, 2.0 * ring.margin, 0.0), 0.5), "raised out of the slab");
        assert!(!ring.holds(c + (c - Vec3::new(1.0, 2.0, 3.0)) * 0.01, 0.5), "pushed out of the annulus");
        assert!(!ring.holds(c, 0.5 + 2.0 * ring.margin), "grown");
    }

    #[test]
    fn the_diamond_angle_grows_with_the_angle() {
        let mut last = -1.0;
        for k in 0..4000 {
            let theta = k as f32 * std::f32::consts::TAU / 4000.0;
            let d = diamond(theta.sin(), theta.cos());
            assert!(d > last && (0.0..4.0).contains(&d), "θ = {theta}: {d} after {last}");
            // Opposite directions are half a turn apart.
            let opposite = diamond(-theta.sin(), -theta.cos());
            assert!((units(opposite).wrapping_sub(units(d)) as i64 - (1 << 31)).abs() < 1 << 12, "θ = {theta}");
            last = d;
        }
        assert_eq!(
            [diamond(0.0, 1.0), diamond(1.0, 0.0), diamond(0.0, -1.0), diamond(-1.0, 0.0)],
            [0.0, 1.0, 2.0, 3.0]
        );
    }

    #[test]
    fn arcs_overlap_and_join_across_the_seam() {
        // In diamond angle: 4 to the turn.
        let arc = |start: f32, len: f32| Arc { start: units(start), len: units(len) };
        let a = arc(3.8, 0.4); // across the seam at 4 ≡ 0
        let b = arc(0.1, 0.2);
        assert!(a.overlaps(b) && b.overlaps(a));
        assert!(!a.overlaps(arc(1.0, 1.0)));
        let h = a.hull(arc(0.5, 0.1));
        assert!(h.start == units(3.8) && h.len.abs_diff(units(0.8)) < 256, "{h:?}");
        assert_eq!(arc(0.0, 2.5).hull(arc(2.2, 2.0)), Arc::FULL);
        assert!(Arc::FULL.overlaps(b) && b.overlaps(Arc::FULL));
        let none = Touch::NONE;
        let one = Touch { ring: 0, arc: a };
        assert_eq!(none.union(one), one);
        assert!(one.meets_wedge(0, b) && !one.meets_wedge(1, b));
        assert_eq!(one.union(Touch { ring: 1, arc: a }).ring, Touch::MANY_RINGS);
    }

    #[test]
    fn the_sphere_lies_in_its_wedge_and_a_ray_to_it_touches_there() {
        let motion = orbit(Vec3::new(0.0, 1.2, 15.0), 3.6);
        let ring = SweptRing::of(0, 0.45, &motion).unwrap();
        let c = motion.center_at(2.0);
        let wedge = ring.wedge(c, 0.45);
        // asin(0.45 / 3.6) = 0.125 rad each side: between half and all of that in diamond
        // angle.
        assert!(wedge.len > units(0.125) && wedge.len < units(0.26), "{wedge:?}");
        // A ray from the camera to the sphere's centre crosses the washer where it is.
        let o = Vec3::ZERO;
        let touch = ring.touch(o, (c - o).normalize(), (c - o).length()).unwrap();
        assert!(touch.overlaps(wedge));
        // The sphere half a turn later is elsewhere.
        let far = ring.wedge(motion.center_at(6.0), 0.45);
        assert!(!wedge.overlaps(far));
    }

    /// A small orbit far from the segment's origin (CI's case, stop 46): measured from the
    /// origin, ρ²'s terms are ~10⁴ and cancel to an error larger than the washer's ~10⁻³,
    /// and the segment ending on the sphere was said to miss it.
    #[test]
    fn a_small_ring_far_away_is_met() {
        let motion = orbit(Vec3::new(42.707_893, 28.971_373, -28.842_712), 0.014_969_059);
        let r = 0.01;
        let bound = SweptRing::of(0, r, &motion).unwrap();
        let centre = motion.center_at(0.0);
        let p = centre - Vec3::Z * r;
        let o = Vec3::new(0.0, 0.0, 68.073_01);
        let d = (p - o).normalize();
        assert!(bound.meets(o, d, (p - o).length()), "the segment ending on the sphere");
        assert!(bound.meets(o, p - o, f32::INFINITY), "the ray through it");
        let wedge = bound.wedge(centre, r);
        assert!(bound.touch(o, d, (p - o).length()).is_some_and(|t| t.overlaps(wedge)));
        let lanes = crate::reuse::lanes::tests::lane0_of(&bound, (o, d, (p - o).length()));
        assert!(lanes.is_some_and(|t| t.overlaps(wedge)), "the lanes: {lanes:?}");
    }

    proptest! {
        /// Every position of the orbit is held, and every ray through a point of the moving
        /// sphere, or ending on it, meets the bound, in scalar code and in lanes.
        #[test]
        fn the_bound_holds_the_sphere_and_every_ray_to_it(
            c in prop::array::uniform3(-50.0f32..50.0),
            ring in 0.0f32..10.0,
            r in 0.01f32..3.0,
            t in -100.0f32..100.0,
            on in prop::array::uniform3(-1.0f32..1.0),
            from in prop::array::uniform3(-100.0f32..100.0),
        ) {
            let motion = orbit(Vec3::from(c), ring);
            let bound = SweptRing::of(0, r, &motion).unwrap();
            let centre = motion.center_at(t);
            prop_assert!(bound.holds(centre, r));
            let on = Vec3::from(on);
            prop_assume!(on.length() > 1e-3);
            let p = centre + r * on.normalize();
            let o = Vec3::from(from);
            let d = (p - o).normalize();
            prop_assert!(bound.meets(o, d, (p - o).length()), "a segment ending on the sphere");
            prop_assert!(bound.meets(o, p - o, f32::INFINITY), "a ray through the sphere");
            // ... and it crosses the washer in an arc that meets the sphere's wedge.
            let wedge = bound.wedge(centre, r);
            let touch = bound.touch(o, d, (p - o).length()).unwrap();
            prop_assert!(touch.overlaps(wedge), "{touch:?} misses {wedge:?}");
            prop_assert!(bound.touch(o, p - o, f32::INFINITY).unwrap().overlaps(wedge));
            // The lanes of `lanes.rs` too.
            let lanes = crate::reuse::lanes::tests::lane0_of(&bound, (o, d, (p - o).length()));
            prop_assert!(lanes.is_some_and(|t| t.overlaps(wedge)), "the lanes: {lanes:?} against {wedge:?}");
            // Every point of the sphere is in the wedge.
            prop_assert!(Arc { start: bound.angle_of(p), len: 0 }.overlaps(wedge), "{p} outside {wedge:?}");
        }
    }
}
