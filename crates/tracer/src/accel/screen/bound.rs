//! Where on an eye's screen a sphere's primary hits can be: the screen bins' bound
//! (`screen.rs`), also the reuse observer's rectangle of a moved sphere.
//!
//! **The bound.** In the eye's head frame (x right, y up, z forward) a primary ray has
//! direction ∝ (u, v, 1). Projecting the ray and the sphere (centre (a, b, c), radius r)
//! onto the xz-plane, a hit needs the line x = u·z to meet the disc of radius r about
//! (a, c): u lies between the slopes of the two tangents from the origin,
//!
//! ```text
//! u = (a·c ∓ r·√(a² + c² − r²)) / (c² − r²)          (needs c > r),
//! ```
//!
//! and likewise v from (b, c) in the yz-plane. The pair of intervals is a conservative
//! screen rectangle: exact in each axis, loose only in the corners. A sphere that reaches
//! the eye's plane (c ≤ r) could be anywhere ahead and goes in every tile; one wholly
//! behind it (c ≤ −r) is in none.
//!
//! **Exactness.** Binning only decides which spheres to *test*; the test itself is the
//! BVH's lane arithmetic on the same values, so a listed sphere yields bit-for-bit the `t`
//! it would in the BVH (`simd.rs`'s `nearest_root`), and the rays are bit-for-bit
//! [`EyeView::primary_ray`]'s. For the result to equal `Tracer::trace_pixel`'s, the
//! bound must never miss a sphere the f32 test would report. It is computed in f64 with
//! the radius grown by 10⁻⁴ of the distance (the f32 test's perpendicular distance is good
//! to a few 10⁻⁷ of it) and then widened by one pixel on each side; a test compares the
//! two paths over the scenes.

use glam::{DVec3, Vec3};

use super::TILE;
use crate::camera::EyeView;

/// Growth of a sphere's radius for the bound, relative to its distance from the eye.
const RADIUS_MARGIN: f64 = 1e-4;

/// The tile rectangle of a sphere no primary ray can hit.
pub(super) const NO_RECT: [u16; 4] = [u16::MAX; 4];

/// Inclusive range of slopes u = x/z of the lines from the origin that meet the disc of
/// radius `r` about (a, c), for c > r.
fn tangent_slopes(a: f64, c: f64, r: f64) -> (f64, f64) {
    let root = r * (a * a + c * c - r * r).sqrt();
    let den = c * c - r * r;
    ((a * c - root) / den, (a * c + root) / den)
}

/// Where on screen a sphere's primary hits can be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Bound {
    /// Behind the eye: no primary ray reaches it.
    Nowhere,
    /// Reaches the eye's plane: any primary ray may hit it.
    Everywhere,
    /// Only pixels (i, j) with `i0 ≤ i ≤ i1` and `j0 ≤ j ≤ j1`: `[i0, j0, i1, j1]`, in
    /// continuous pixel indices (pixel i's centre ray is at index i), unclipped.
    Pixels([f64; 4]),
}

/// The screen bound of the sphere (`center`, `radius` grown by `margin` of its distance).
pub(super) fn screen_bound(view: &EyeView, center: Vec3, radius: f32, margin: f64) -> Bound {
    let to_head = view.head_from_world.as_dmat3();
    let p: DVec3 = to_head * (center.as_dvec3() - view.origin.as_dvec3());
    let r = f64::from(radius) * (1.0 + margin) + margin * p.length();
    if !p.is_finite() || !r.is_finite() {
        return Bound::Everywhere;
    }
    if p.z <= -r {
        return Bound::Nowhere;
    }
    if p.z <= r {
        return Bound::Everywhere;
    }
    // Slopes to window coordinates to continuous pixel indices of the ray through a
    // pixel centre: x = eye_x + u·d, i + ½ = (x/width + ½)·W (and j grows downwards).
    let d = f64::from(view.distance);
    let (u0, u1) = tangent_slopes(p.x, p.z, r);
    let (v0, v1) = tangent_slopes(p.y, p.z, r);
    let (w, h) = view.shown_size();
    let (w, h, mx, my) = (f64::from(w), f64::from(h), f64::from(view.margin.0), f64::from(view.margin.1));
    let column = |u: f64| ((f64::from(view.eye_x) + u * d) / f64::from(view.window_width) + 0.5) * w - 0.5 + mx;
    let row = |v: f64| (0.5 - v * d / f64::from(view.window_height)) * h - 0.5 + my;
    Bound::Pixels([column(u0), row(v1), column(u1), row(v0)])
}

/// The inclusive pixel rectangle `[i0, j0, i1, j1]` a sphere's primary hits can fall in,
/// if any.
pub(crate) fn pixel_rect(view: &EyeView, center: Vec3, radius: f32) -> Option<[u32; 4]> {
    let (w, h) = (view.width, view.height);
    if w == 0 || h == 0 {
        return None;
    }
    let [i0, j0, i1, j1] = match screen_bound(view, center, radius, RADIUS_MARGIN) {
        Bound::Nowhere => return None,
        Bound::Everywhere => return Some([0, 0, w - 1, h - 1]),
        Bound::Pixels(b) => b,
    };
    // One pixel of slack on each side for rounding in the rays themselves.
    let (i0, j0, i1, j1) = (i0.floor() - 1.0, j0.floor() - 1.0, i1.ceil() + 1.0, j1.ceil() + 1.0);
    if i1 < 0.0 || j1 < 0.0 || i0 >= f64::from(w) || j0 >= f64::from(h) {
        return None;
    }
    let clip = |x: f64, n: u32| x.clamp(0.0, f64::from(n - 1)) as u32;
    Some([clip(i0, w), clip(j0, h), clip(i1, w), clip(j1, h)])
}

/// The inclusive tile rectangle a sphere's primary hits can fall in, or [`NO_RECT`].
pub(super) fn tile_rect(view: &EyeView, center: Vec3, radius: f32) -> [u16; 4] {
    pixel_rect(view, center, radius).map_or(NO_RECT, |r| r.map(|x| (x / TILE) as u16))
}
