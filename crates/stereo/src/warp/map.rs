//! The composite map from one traced view's pixels to another view's pixels, made once per
//! (source view, target view) pair and frame, so that landing a pixel costs a handful of
//! multiply-adds.
//!
//! A source pixel (i, j) of depth z (shown column c = i − mx, row r = j − my) has the window
//! point x_w = ((c + ½)/W − ½)·window_w, y_w = (½ − (r + ½)/H)·window_h, and the head-space
//! point P = (e_s, 0, −d_s) + k·(x_w − e_s, y_w, d_s), k = (z + d_s)/d_s: the point of the
//! pixel's primary ray at depth z. Write w = z + d_s (the depth from the eyes' plane) and
//! D(i, j) = (x_w − e_s, y_w, d_s)/d_s. Then, with M = R_tᵀ·R_s and T = R_tᵀ·(p_s − p_t)
//! (target-from-source rotation and translation), the point in the target's head space,
//! offset by the target's d so that its eyes' plane is z = 0, is
//!
//! Q = T + M·(e_s, 0, 0) + w·M·D(i, j),
//!
//! affine in w, with M·D(i, j) affine in i and j. `EyeView::project` is a projective map of
//! Q: px·Q_z = s_x·d_t·(Q_x − e_t) + (s_x·e_t + c_x)·Q_z and py·Q_z = −s_y·d_t·Q_y + c_y·Q_z
//! (s_x = W_t/window_w, c_x = W_t/2 + mx_t, likewise in y), a linear map L of (Q, 1).
//! Composed, the homogeneous target coordinates of the pixel are
//!
//! n = g + w·(h₀ + i·h_i + j·h_j),  px = n_x/n_z,  py = n_y/n_z,  n_z = Q_z = z_t + d_t,
//!
//! with g = L·(T + M·(e_s, 0, 0), 1) and h = L·M·D: nine numbers and three, made here in
//! f64 and rounded once. A background pixel (z = +∞) is a point at infinity: its n is h
//! alone (the rotation, no translation), and its depth is +∞.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{dispatch, prelude::*, Level, Simd};
use glam::{DMat3, DVec3};
use tracer::EyeView;

/// Where the pixels of one source view land in one target view (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WarpMap {
    /// The constant part of n: the source eye in the target's homogeneous pixel space.
    pub g: [f32; 3],
    /// The part of h that changes along a row: h_i, per source column.
    pub h_i: [f32; 3],
    /// h₀ + j·h_j is [`WarpMap::row`]'s, kept in f64.
    h_0: DVec3,
    h_j: DVec3,
    /// The source's d: w = z + d.
    pub distance: f32,
    /// The target's size in pixels (its guard band included).
    pub target_size: (u32, u32),
}

impl WarpMap {
    /// The map from `source`'s pixels (with its guard band, if any) to `target`'s.
    #[must_use]
    pub fn new(source: &EyeView, target: &EyeView) -> Self {
        let (rs, rt) = (source.world_from_head().as_dmat3(), target.world_from_head().as_dmat3());
        let m: DMat3 = rt.transpose() * rs;
        let t: DVec3 = rt.transpose() * (source.head_position() - target.head_position()).as_dvec3();
        // L, the target's projection of (Q, 1): rows for px·Q_z, py·Q_z and Q_z.
        let (wt, ht) = target.shown_size();
        let (wt, ht) = (f64::from(wt), f64::from(ht));
        let window_t = target.window_size().as_dvec2();
        let (e_t, d_t) = (f64::from(target.eye_offset()), f64::from(target.distance()));
        let (s_x, s_y) = (wt / window_t.x, ht / window_t.y);
        let c_x = 0.5 * wt + f64::from(target.margin.0);
        let c_y = 0.5 * ht + f64::from(target.margin.1);
        // Its linear part (glam's matrices are column-major: columns are the Q axes).
        let l = DMat3::from_cols(
            DVec3::new(s_x * d_t, 0.0, 0.0),
            DVec3::new(0.0, -s_y * d_t, 0.0),
            DVec3::new(s_x * e_t + c_x, c_y, 1.0),
        );
        let l_const = DVec3::new(-s_x * d_t * e_t, 0.0, 0.0);
        let lm = l * m;
        // The source's window: D(i, j) = (u₀ + i·u_i, v₀ + j·v_j, 1), pixel (i, j) of the
        // traced view (its shown pixel is (i − mx, j − my)).
        let (ws, hs) = source.shown_size();
        let (ws, hs) = (f64::from(ws), f64::from(hs));
        let window_s = source.window_size().as_dvec2();
        let (e_s, d_s) = (f64::from(source.eye_offset()), f64::from(source.distance()));
        let (mx, my) = (f64::from(source.margin.0), f64::from(source.margin.1));
        let u_i = window_s.x / (ws * d_s);
        let u_0 = (((0.5 - mx) / ws - 0.5) * window_s.x - e_s) / d_s;
        let v_j = -window_s.y / (hs * d_s);
        let v_0 = (0.5 - (0.5 - my) / hs) * window_s.y / d_s;
        let g = l * (t + m * DVec3::new(e_s, 0.0, 0.0)) + l_const;
        Self {
            g: g.as_vec3().to_array(),
            h_i: (lm.x_axis * u_i).as_vec3().to_array(),
            h_0: lm * DVec3::new(u_0, v_0, 1.0),
            h_j: lm.y_axis * v_j,
            distance: source.distance(),
            target_size: (target.width, target.height),
        }
    }

    /// h₀ + j·h_j: the part of h that is constant along source row `j`.
    #[must_use]
    pub fn row(&self, j: u32) -> [f32; 3] {
        (self.h_0 + self.h_j * f64::from(j)).as_vec3().to_array()
    }
}

/// How far (in target rows) the lanes' f32 landings may stray from the exact ones that
/// [`WarpMap::rows_reached`] bounds: their rounding is below 10⁻³ of a pixel for any image under
/// 10⁵ pixels wide.
const SLACK: f64 = 1.0 / 64.0;

impl WarpMap {
    /// The target rows (first, last) that the pixels of source row `j` (`width` pixels) can
    /// land in, at any depth from `z_min` (the row's nearest, +∞ for a row of background)
    /// to +∞; `None` if none.
    ///
    /// Along a pixel's ray the target row n_y/n_z is a Möbius function of w (monotone while
    /// n_z keeps its sign), and along the row it is one of i: with n_z > 0 at the four
    /// corners (i ∈ {0, width − 1}, w ∈ {w_min, ∞}), n_z > 0 over the whole box (it is
    /// bilinear) and the rows reached lie between the corners'. Otherwise some pixel may
    /// pass by the target eye's plane, and the answer is every row. [`SLACK`] on each side
    /// covers the lanes' f32 rounding.
    #[must_use]
    pub fn rows_reached(&self, j: u32, width: u32, z_min: f32) -> Option<(u32, u32)> {
        if width == 0 || self.target_size.1 == 0 {
            return None;
        }
        let rows = f64::from(self.target_size.1);
        let every = Some((0, self.target_size.1 - 1));
        let w_min = f64::from(z_min) + f64::from(self.distance);
        if w_min <= 0.0 {
            return every;
        }
        let (g, h, h_i) = (
            DVec3::from(self.g.map(f64::from)),
            self.h_0 + self.h_j * f64::from(j),
            DVec3::from(self.h_i.map(f64::from)),
        );
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in [0, width - 1] {
            let direction = h + h_i * f64::from(i);
            let near = if w_min.is_finite() { g + direction * w_min } else { direction };
            for n in [direction, near] {
                if n.z.is_nan() || n.z <= 0.0 {
                    return every;
                }
                lo = lo.min(n.y / n.z);
                hi = hi.max(n.y / n.z);
            }
        }
        let (lo, hi) = ((lo - SLACK).floor(), (hi + SLACK).floor());
        (hi >= 0.0 && lo < rows).then(|| (lo.max(0.0) as u32, hi.min(rows - 1.0) as u32))
    }
}

/// The target rows each `width`-pixel row of the depth plane `z` can reach in either
/// target of `maps` ([`WarpMap::rows_reached`], from the row's nearest depth), into `out`,
/// at the SIMD `level`.
pub(crate) fn rows_reached(
    level: Level,
    maps: &[WarpMap; 2],
    z: &[f32],
    width: u32,
    out: &mut Vec<Option<(u32, u32)>>,
) {
    out.clear();
    if width == 0 {
        return;
    }
    out.extend(z.chunks_exact(width as usize).zip(0..).map(|(row, j)| {
        let z_min = dispatch!(level, simd => simd.vectorize(
            #[inline(always)]
            || nearest(simd, row),
        ));
        match maps.map(|map| map.rows_reached(j, width, z_min)) {
            [Some(a), Some(b)] => Some((a.0.min(b.0), a.1.max(b.1))),
            [a, b] => a.or(b),
        }
    }));
}

/// The nearest depth of `row` (NaN left out, as the kernel takes it for background), +∞
/// for a row of background.
#[inline(always)]
fn nearest<S: Simd>(simd: S, row: &[f32]) -> f32 {
    let n = S::f32s::LEN;
    let mut least = S::f32s::splat(simd, f32::INFINITY);
    let mut chunks = row.chunks_exact(n);
    for chunk in &mut chunks {
        let z = S::f32s::from_slice(simd, chunk);
        least = z.simd_lt(least).select(z, least);
    }
    let tail = chunks.remainder().iter().fold(f32::INFINITY, |m, &z| if z < m { z } else { m });
    least.as_slice().iter().fold(tail, |m, &z| if z < m { z } else { m })
}

/// From a pixel's landing in one target eye to its landing in the other eye of the same
/// head pose and window: the disparity in the target's pixels,
/// px' = px + shift + parallax/n_z = px + E·(1 − d/(d + z_t)) with E = (e' − e)·W/window,
/// and px' = px + shift for the background (the conventions' e·z/(d+z), `tracer::Disparity`).
/// The row does not change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EyeShift {
    /// The shift of a point at infinity (pixels): E.
    pub shift: f32,
    /// Times 1/n_z, for a point at finite depth: −E·d.
    pub parallax: f32,
}

impl EyeShift {
    /// From `from`'s pixels to `to`'s: two eyes of one head pose, one window and one size.
    #[must_use]
    pub fn between(from: &EyeView, to: &EyeView) -> Self {
        let per_unit = f64::from(from.shown_size().0) / f64::from(from.window_size().x);
        let eyes = (f64::from(to.eye_offset()) - f64::from(from.eye_offset())) * per_unit;
        let margins = f64::from(to.margin.0) - f64::from(from.margin.0);
        Self { shift: (eyes + margins) as f32, parallax: (-eyes * f64::from(from.distance())) as f32 }
    }
}
