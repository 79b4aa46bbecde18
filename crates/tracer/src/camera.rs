//! The stereo camera: two parallel, off-axis eyes looking through one shared window.
//!
//! Head space follows Adelson & Hodges (1993) and the seed paper: left-handed, +z into the
//! scene, the shared view window on the plane z = 0 centred on the view axis, the eyes at
//! (∓e/2, 0, −d). The window is 2·d·tan(fov/2) wide, so changing `d` moves the
//! zero-parallax plane without zooming. The head pose (`position`, the midpoint between the
//! eyes, plus yaw and pitch) places head space in the world:
//! `world = position + R · (head + (0, 0, d))`, R = R_y(yaw) · R_x(−pitch).

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use std::ops::{Add, Div};

use fearless_simd::{dispatch, prelude::*, Simd};
use glam::{Mat3, Vec2, Vec3};

use crate::ray::Ray;
use crate::simd::{lane_index, F, U};

/// Which eye.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Eye {
    /// The eye at x = −e/2; traced fully.
    Left,
    /// The eye at x = +e/2; reprojected by `stereo`.
    Right,
}

impl Eye {
    /// −1 for the left eye, +1 for the right.
    #[must_use]
    pub fn sign(self) -> f32 {
        match self {
            Eye::Left => -1.0,
            Eye::Right => 1.0,
        }
    }
}

/// Head pose and stereo parameters, as in a scene file's `[camera]` table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Interpupillary distance e (world units), ≥ 0.
    pub ipd: f32,
    /// Distance d from the eyes to the zero-parallax window, > 0.
    pub distance: f32,
    /// Horizontal field of view in degrees, in (0, 180).
    pub fov_deg: f32,
    /// Midpoint between the eyes (world space).
    pub position: Vec3,
    /// Turn about +y in degrees; positive turns towards +x (right).
    pub yaw_deg: f32,
    /// Tilt in degrees; positive looks up.
    pub pitch_deg: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Self { ipd: 0.65, distance: 12.0, fov_deg: 45.0, position: Vec3::ZERO, yaw_deg: 0.0, pitch_deg: 0.0 }
    }
}

impl Camera {
    /// Width of the shared window at z = 0 (world units): 2·d·tan(fov/2).
    #[must_use]
    pub fn window_width(&self) -> f32 {
        2.0 * self.distance * (0.5 * self.fov_deg.to_radians()).tan()
    }

    /// Rotation taking head-space directions to world space.
    #[must_use]
    pub fn world_from_head(&self) -> Mat3 {
        Mat3::from_rotation_y(self.yaw_deg.to_radians()) * Mat3::from_rotation_x(-self.pitch_deg.to_radians())
    }

    /// World position of one eye.
    #[must_use]
    pub fn eye_position(&self, eye: Eye) -> Vec3 {
        self.position + self.world_from_head() * Vec3::new(eye.sign() * 0.5 * self.ipd, 0.0, 0.0)
    }

    /// Horizontal shift, in window units, from the left eye's window position of a point at
    /// head-space depth `z` to the right eye's: e·z/(d+z) ([`Disparity::at`]). A point at
    /// infinity (a miss) shifts by exactly e.
    #[must_use]
    pub fn disparity(&self, z: f32) -> f32 {
        Disparity { scale: self.ipd, distance: self.distance }.at(z)
    }

    /// The view of one eye for a `width` × `height` image.
    #[must_use]
    pub fn view(&self, eye: Eye, width: u32, height: u32) -> EyeView {
        self.view_with_margin(eye, width, height, (0, 0))
    }

    /// The view of one eye for a `width` × `height` image traced with a guard band of
    /// `margin` = (mx, my) more pixels on each side: the view is (width + 2·mx) ×
    /// (height + 2·my) pixels, and its pixel (i, j) has the very ray (bit for bit) of pixel
    /// (i − mx, j − my) of [`Camera::view`]`(eye, width, height)`. A timewarp shows the
    /// `width` × `height` part, and turns the head into the band.
    #[must_use]
    pub fn view_with_margin(&self, eye: Eye, width: u32, height: u32, margin: (u32, u32)) -> EyeView {
        let window_width = self.window_width();
        let window_height = window_width * height as f32 / width as f32;
        let rot = self.world_from_head();
        EyeView {
            eye,
            width: width + 2 * margin.0,
            height: height + 2 * margin.1,
            margin,
            origin: self.eye_position(eye),
            eye_x: eye.sign() * 0.5 * self.ipd,
            distance: self.distance,
            window_width,
            window_height,
            inv_width: 1.0 / width as f32,
            inv_height: 1.0 / height as f32,
            world_from_head: rot,
            head_from_world: rot.transpose(),
            head_position: self.position,
        }
    }
}

/// The stereo pair's horizontal disparity (Adelson & Hodges 1993): a point at head-space
/// depth z seen at window position x by the left eye is at x + e·z/(d+z) for the right eye,
/// on the same scanline. `scale` is e in the unit x is measured in: window units, or pixels
/// (e·W/w, [`Disparity::in_pixels`]).
///
/// The formula is written once, in [`Disparity::shortfall`]: e·z/(d+z) = e − e·d/(d+z), and
/// e·d/(d+z) is how much less than a point at infinity (which shifts by exactly e) a point
/// at depth z shifts. Its users combine it in their own order, each the order it has always
/// had, so that every image stays bit for bit the same: the reprojection computes a left
/// pixel centre's landing place as (i + ½ + e) − e·d/(d+z), in SIMD lanes
/// ([`Disparity::shortfall_in`]), and [`Disparity::at`] gives e·(1 − d/(d+z)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disparity {
    /// e in the caller's unit: the shift of a point at infinity.
    pub scale: f32,
    /// d, the distance from the eyes to the zero-parallax window.
    pub distance: f32,
}

impl Disparity {
    /// The disparity between `camera`'s eyes in pixels of `view`: scale e·W/w.
    #[must_use]
    pub fn in_pixels(camera: &Camera, view: &EyeView) -> Self {
        Self { scale: camera.ipd * view.pixels_per_unit(), distance: camera.distance }
    }

    /// e·z/(d+z), the shift of a point at depth `z`, as e·(1 − d/(d+z)) so that z = +∞
    /// gives exactly e rather than ∞/∞. d/(d+z) is the shortfall of the unit disparity
    /// (1·d is d exactly).
    #[inline]
    #[must_use]
    pub fn at(self, z: f32) -> f32 {
        self.scale * (1.0 - Self { scale: 1.0, ..self }.shortfall(z))
    }

    /// e·d/(d+z): how much less than a point at infinity a point at depth `z` shifts (0 for
    /// z = +∞), in one lane: [`Disparity::shortfall_in`] of `f32`.
    #[inline]
    #[must_use]
    pub fn shortfall(self, z: f32) -> f32 {
        self.shortfall_in(z, |c| c)
    }

    /// [`Disparity::shortfall`] in any lanes: `f32`, or SIMD lanes, with `splat` making a
    /// lane value of a constant (`fearless_simd`'s splat needs its instruction-set token,
    /// so its vectors have no `From<f32>`). The same operations in the same order, so that
    /// a lane gives bit for bit the scalar answer.
    #[inline(always)]
    #[must_use]
    pub fn shortfall_in<T>(self, z: T, splat: impl Fn(f32) -> T) -> T
    where
        T: Add<Output = T> + Div<Output = T>,
    {
        splat(self.scale * self.distance) / (splat(self.distance) + z)
    }
}

/// One eye's precomputed view: generates primary rays and projects points to pixels.
#[derive(Clone, Copy, Debug)]
pub struct EyeView {
    /// Which eye this is.
    pub eye: Eye,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The guard band: pixels traced beyond the shown image on each side, (columns, rows)
    /// ([`Camera::view_with_margin`]); (0, 0) for a view without one.
    pub margin: (u32, u32),
    /// The eye's world position; every primary ray starts here.
    pub origin: Vec3,
    pub(crate) eye_x: f32,
    pub(crate) distance: f32,
    pub(crate) window_width: f32,
    pub(crate) window_height: f32,
    inv_width: f32,
    inv_height: f32,
    pub(crate) world_from_head: Mat3,
    pub(crate) head_from_world: Mat3,
    head_position: Vec3,
}

impl EyeView {
    /// Pixels per window unit, horizontally (W / window width, W the shown width).
    #[must_use]
    pub fn pixels_per_unit(&self) -> f32 {
        (self.width - 2 * self.margin.0) as f32 / self.window_width
    }

    /// The shown image's size: the view's, less its guard band.
    #[must_use]
    pub fn shown_size(&self) -> (u32, u32) {
        (self.width - 2 * self.margin.0, self.height - 2 * self.margin.1)
    }

    /// The shared window's size (world units): the shown image's extent on the plane of
    /// zero parallax.
    #[must_use]
    pub fn window_size(&self) -> Vec2 {
        Vec2::new(self.window_width, self.window_height)
    }

    /// This eye's offset along the head's x axis from the midpoint of the eyes (∓e/2).
    #[must_use]
    pub fn eye_offset(&self) -> f32 {
        self.eye_x
    }

    /// The distance d from the eyes to the window.
    #[must_use]
    pub fn distance(&self) -> f32 {
        self.distance
    }

    /// The rotation taking head-space directions to world space.
    #[must_use]
    pub fn world_from_head(&self) -> Mat3 {
        self.world_from_head
    }

    /// The head's position: the midpoint of the eyes (world space).
    #[must_use]
    pub fn head_position(&self) -> Vec3 {
        self.head_position
    }

    /// The camera ray through the centre of pixel (i, j).
    ///
    /// The pixel centre lies on the window at x = ((i + ½)/W − ½)·width,
    /// y = (½ − (j + ½)/H)·height. Lane 0 of the primary-ray kernel (`EyeView::primary_dirs_rows`), so a ray made one
    /// at a time is bit-for-bit the one made a vector at a time.
    #[must_use]
    pub fn primary_ray(&self, i: u32, j: u32) -> Ray {
        fn lane0<S: Simd>(simd: S, view: &EyeView, i: u32, j: u32) -> Vec3 {
            let [x, y, z] = view.primary_dirs_at(simd, F::<S>::splat(simd, i as f32), j);
            Vec3::new(x.as_slice()[0], y.as_slice()[0], z.as_slice()[0])
        }
        let dir = dispatch!(crate::simd::level(), simd => lane0(simd, self, i, j));
        Ray::new(self.origin, dir)
    }

    /// The primary ray directions of pixels (i + l, j), l = 0..LEN, one per lane
    /// ([`EyeView::primary_dirs_rows`]).
    #[inline(always)]
    pub(crate) fn primary_dirs_lanes<S: Simd>(&self, simd: S, i: u32, j: u32) -> [F<S>; 3] {
        // (i + l) as f32, from whole lanes.
        let columns = F::<S>::float_from(U::<S>::splat(simd, i) + lane_index(simd));
        self.primary_dirs_at(simd, columns, j)
    }

    /// The primary ray directions of pixels (`columns[l]`, j), one per lane (each column a
    /// whole number, as f32).
    #[inline(always)]
    pub(crate) fn primary_dirs_at<S: Simd>(&self, simd: S, columns: F<S>, j: u32) -> [F<S>; 3] {
        self.primary_dirs_rows(simd, columns, F::<S>::splat(simd, j as f32))
    }

    /// The primary ray directions of pixels (`columns[l]`, `rows[l]`), one per lane (each a
    /// whole number, as f32): **the primary-ray kernel**. The head-space direction
    /// (x − eye_x, y, d) is turned to world space and normalised with the operations, in the
    /// order, of glam's `Mat3 * Vec3` and `Vec3::normalize`.
    #[inline(always)]
    pub(crate) fn primary_dirs_rows<S: Simd>(&self, simd: S, columns: F<S>, rows: F<S>) -> [F<S>; 3] {
        let splat = |x: f32| F::<S>::splat(simd, x);
        // The shown image's column and row (exact: whole numbers; x − 0 is x).
        let (columns, rows) = (columns - splat(self.margin.0 as f32), rows - splat(self.margin.1 as f32));
        let x = ((columns + splat(0.5)) * splat(self.inv_width) - splat(0.5)) * splat(self.window_width);
        let y = (splat(0.5) - (rows + splat(0.5)) * splat(self.inv_height)) * splat(self.window_height);
        let (hx, hy, hz) = (x - splat(self.eye_x), y, splat(self.distance));
        let (a, b, c) = (self.world_from_head.x_axis, self.world_from_head.y_axis, self.world_from_head.z_axis);
        let wx = (hx * splat(a.x) + hy * splat(b.x)) + hz * splat(c.x);
        let wy = (hx * splat(a.y) + hy * splat(b.y)) + hz * splat(c.y);
        let wz = (hx * splat(a.z) + hy * splat(b.z)) + hz * splat(c.z);
        let recip = splat(1.0) / ((wx * wx + wy * wy) + wz * wz).sqrt();
        [wx * recip, wy * recip, wz * recip]
    }

    /// Head-space depth beyond the window (the paper's z) of a world point.
    #[inline]
    #[must_use]
    pub fn head_z(&self, p: Vec3) -> f32 {
        self.head_from_world.row(2).dot(p - self.head_position) - self.distance
    }

    /// Continuous pixel coordinates (centre of pixel (i, j) is (i + ½, j + ½)) of a world
    /// point, or `None` if it is not in front of the eye.
    #[must_use]
    pub fn project(&self, p: Vec3) -> Option<Vec2> {
        let h = self.head_from_world * (p - self.head_position) - Vec3::new(0.0, 0.0, self.distance);
        let w = h.z + self.distance;
        if w <= 0.0 {
            return None;
        }
        let x = self.eye_x + (h.x - self.eye_x) * self.distance / w;
        let y = h.y * self.distance / w;
        let (w, h) = self.shown_size();
        Some(Vec2::new(
            (x / self.window_width + 0.5) * w as f32 + self.margin.0 as f32,
            (0.5 - y / self.window_height) * h as f32 + self.margin.1 as f32,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera { ipd: 0.65, distance: 12.0, fov_deg: 45.0, ..Camera::default() }
    }

    #[test]
    fn eyes_sit_at_plus_minus_half_ipd() {
        let c = camera();
        assert_eq!(c.eye_position(Eye::Left), Vec3::new(-0.325, 0.0, 0.0));
        assert_eq!(c.eye_position(Eye::Right), Vec3::new(0.325, 0.0, 0.0));
    }

    #[test]
    fn pixel_centre_ray_projects_back_to_the_pixel_centre() {
        let c = Camera { yaw_deg: 20.0, pitch_deg: -10.0, position: Vec3::new(1.0, 2.0, -3.0), ..camera() };
        for eye in [Eye::Left, Eye::Right] {
            let v = c.view(eye, 640, 360);
            for (i, j) in [(0, 0), (319, 180), (639, 359), (17, 301)] {
                let p = v.primary_ray(i, j).at(23.0);
                let px = v.project(p).unwrap();
                assert!((px - Vec2::new(i as f32 + 0.5, j as f32 + 0.5)).length() < 2e-3, "{eye:?} {i},{j}: {px}");
            }
        }
    }

    #[test]
    fn disparity_of_a_point_at_known_depth() {
        // x_r − x_l = e·z/(d+z) in window units, for points behind, on and in front of the window.
        let c = camera();
        let (w, h) = (1280, 720);
        let (l, r) = (c.view(Eye::Left, w, h), c.view(Eye::Right, w, h));
        for z in [8.0_f32, 3.0, 0.0, -2.0, -6.0] {
            let p = Vec3::new(0.7, -0.4, c.distance + z);
            let xl = l.project(p).unwrap();
            let xr = r.project(p).unwrap();
            let expected = c.ipd * z / (c.distance + z) * l.pixels_per_unit();
            assert!((xr.x - xl.x - expected).abs() < 1e-3, "z = {z}: {} vs {expected}", xr.x - xl.x);
            assert!((xr.y - xl.y).abs() < 1e-4);
            assert!((c.disparity(z) * l.pixels_per_unit() - expected).abs() < 1e-3);
        }
        assert_eq!(c.disparity(f32::INFINITY), c.ipd);
    }

    #[test]
    fn rays_in_lanes_are_glams_rays() {
        fn lane<S: Simd>(simd: S, v: &EyeView, i: u32, j: u32) -> Vec3 {
            let [dx, dy, dz] = v.primary_dirs_lanes(simd, i - i % 4, j);
            let k = (i % 4) as usize;
            Vec3::new(dx.as_slice()[k], dy.as_slice()[k], dz.as_slice()[k])
        }
        // The lanes reproduce glam's Mat3 * Vec3 and normalize bit for bit.
        let c = Camera { yaw_deg: 33.0, pitch_deg: -12.0, position: Vec3::new(1.0, 2.0, -3.0), ..camera() };
        let v = c.view(Eye::Right, 1280, 720);
        // A grid over the whole view, and its corners.
        let grid = (0..720).step_by(7).flat_map(|j| (0..1280).step_by(5).map(move |i| (i, j)));
        for (i, j) in grid.chain([(0, 0), (17, 301), (640, 360), (1276, 719), (1279, 719)]) {
            let x = ((i as f32 + 0.5) * v.inv_width - 0.5) * v.window_width;
            let y = (0.5 - (j as f32 + 0.5) * v.inv_height) * v.window_height;
            let want = (v.world_from_head * Vec3::new(x - v.eye_x, y, v.distance)).normalize();
            assert_eq!(v.primary_ray(i, j).dir, want, "({i}, {j})");
            assert_eq!(dispatch!(crate::simd::level(), simd => lane(simd, &v, i, j)), want, "({i}, {j}) in lanes");
        }
    }

    #[test]
    fn a_guard_band_keeps_every_shown_pixels_ray_and_projection() {
        let c = Camera { yaw_deg: 12.0, pitch_deg: 5.0, position: Vec3::new(0.5, -1.0, 2.0), ..camera() };
        for eye in [Eye::Left, Eye::Right] {
            let (plain, banded) = (c.view(eye, 160, 90), c.view_with_margin(eye, 160, 90, (24, 10)));
            assert_eq!((banded.width, banded.height, banded.shown_size()), (208, 110, (160, 90)));
            assert_eq!(banded.pixels_per_unit(), plain.pixels_per_unit(), "the same pitch");
            for j in 0..90 {
                for i in 0..160 {
                    let (a, b) = (plain.primary_ray(i, j), banded.primary_ray(i + 24, j + 10));
                    assert_eq!(a, b, "{eye:?} ({i}, {j}): the very ray");
                }
            }
            // A point projects to the same pixel, shifted by the band.
            let p = plain.primary_ray(37, 61).at(20.0);
            let (a, b) = (plain.project(p).unwrap(), banded.project(p).unwrap());
            assert!((b - a - Vec2::new(24.0, 10.0)).length() < 1e-3, "{a} and {b}");
            // And the band's own pixels look beyond the shown window.
            let outside = banded.project(banded.primary_ray(2, 3).at(20.0)).unwrap();
            assert!((outside - Vec2::new(2.5, 3.5)).length() < 2e-3, "{outside}");
        }
    }

    #[test]
    fn distance_moves_the_window_without_zooming() {
        // The central pixel's ray direction does not depend on d.
        let a = Camera { ipd: 0.0, distance: 5.0, ..camera() }.view(Eye::Left, 100, 50);
        let b = Camera { ipd: 0.0, distance: 50.0, ..camera() }.view(Eye::Left, 100, 50);
        assert!((a.primary_ray(10, 7).dir - b.primary_ray(10, 7).dir).length() < 1e-6);
    }
}
