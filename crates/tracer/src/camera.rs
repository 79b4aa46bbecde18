//! The stereo camera: two parallel, off-axis eyes looking through one shared window.
//!
//! Head space follows Adelson & Hodges (1993) and the seed paper: left-handed, +z into the
//! scene, the shared view window on the plane z = 0 centred on the view axis, the eyes at
//! (∓e/2, 0, −d). The window is 2·d·tan(fov/2) wide, so changing `d` moves the
//! zero-parallax plane without zooming. The head pose (`position`, the midpoint between the
//! eyes, plus yaw and pitch) places head space in the world:
//! `world = position + R · (head + (0, 0, d))`, R = R_y(yaw) · R_x(−pitch).

use std::ops::{Add, Div};

use glam::{Mat3, Vec2, Vec3};
use wide::f32x4;

use crate::ray::Ray;

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
        let window_width = self.window_width();
        let window_height = window_width * height as f32 / width as f32;
        let rot = self.world_from_head();
        EyeView {
            eye,
            width,
            height,
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
/// pixel centre's landing place as (i + ½ + e) − e·d/(d+z), four lanes at a time, and
/// [`Disparity::at`] gives e·(1 − d/(d+z)).
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
    /// z = +∞), in one lane (`f32`) or in SIMD lanes (`f32x4`), with the same operations in
    /// the same order, so that a lane gives bit for bit the scalar answer.
    #[inline]
    #[must_use]
    pub fn shortfall<T>(self, z: T) -> T
    where
        T: From<f32> + Add<Output = T> + Div<Output = T>,
    {
        T::from(self.scale * self.distance) / (T::from(self.distance) + z)
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
    /// Pixels per window unit, horizontally (W / window width).
    #[must_use]
    pub fn pixels_per_unit(&self) -> f32 {
        self.width as f32 / self.window_width
    }

    /// The camera ray through the centre of pixel (i, j).
    ///
    /// The pixel centre lies on the window at x = ((i + ½)/W − ½)·width,
    /// y = (½ − (j + ½)/H)·height. Lane 0 of `EyeView::primary_dirs4`, so a ray made one
    /// at a time is bit-for-bit the one made four at a time.
    #[inline]
    #[must_use]
    pub fn primary_ray(&self, i: u32, j: u32) -> Ray {
        let [x, y, z] = self.primary_dirs4(i, j);
        Ray::new(self.origin, Vec3::new(x.as_array()[0], y.as_array()[0], z.as_array()[0]))
    }

    /// Unit world directions of the primary rays through pixels (i + k, j), k = 0..4, one
    /// per lane.
    ///
    /// The head-space direction (x − eye_x, y, d) is turned to world space and normalised
    /// with the operations, in the order, of glam's `Mat3 * Vec3` and `Vec3::normalize`.
    #[inline]
    #[must_use]
    pub(crate) fn primary_dirs4(&self, i: u32, j: u32) -> [f32x4; 3] {
        let lane = f32x4::new([i as f32, (i + 1) as f32, (i + 2) as f32, (i + 3) as f32]);
        let x = ((lane + 0.5) * self.inv_width - 0.5) * self.window_width;
        let y = (0.5 - (j as f32 + 0.5) * self.inv_height) * self.window_height;
        let (hx, hy, hz) = (x - self.eye_x, f32x4::splat(y), f32x4::splat(self.distance));
        let (a, b, c) = (self.world_from_head.x_axis, self.world_from_head.y_axis, self.world_from_head.z_axis);
        let wx = (hx * a.x + hy * b.x) + hz * c.x;
        let wy = (hx * a.y + hy * b.y) + hz * c.y;
        let wz = (hx * a.z + hy * b.z) + hz * c.z;
        let recip = f32x4::splat(1.0) / ((wx * wx + wy * wy) + wz * wz).sqrt();
        [wx * recip, wy * recip, wz * recip]
    }

    /// [`EyeView::primary_dirs4`] over the lanes of `simd`: pixels (i + l, j), l = 0..LEN,
    /// the same operations lane by lane, so bit-for-bit the same directions.
    #[inline(always)]
    pub(crate) fn primary_dirs_lanes<S: fearless_simd::Simd>(&self, simd: S, i: u32, j: u32) -> [crate::simd::F<S>; 3] {
        use crate::simd::F;
        use fearless_simd::prelude::*;
        // (i + l) as f32, from whole lanes.
        let columns = F::<S>::float_from(crate::simd::U::<S>::splat(simd, i) + crate::simd::lane_index(simd));
        self.primary_dirs_at(simd, columns, j)
    }

    /// The primary ray directions of pixels (`columns[l]`, j), one per lane (each column a
    /// whole number, as f32), by [`EyeView::primary_dirs4`]'s operations lane by lane.
    #[inline(always)]
    pub(crate) fn primary_dirs_at<S: fearless_simd::Simd>(
        &self,
        simd: S,
        columns: crate::simd::F<S>,
        j: u32,
    ) -> [crate::simd::F<S>; 3] {
        use crate::simd::F;
        use fearless_simd::prelude::*;
        self.primary_dirs_rows(simd, columns, F::<S>::splat(simd, j as f32))
    }

    /// The primary ray directions of pixels (`columns[l]`, `rows[l]`), one per lane (each a
    /// whole number, as f32), by [`EyeView::primary_dirs4`]'s operations lane by lane.
    #[inline(always)]
    pub(crate) fn primary_dirs_rows<S: fearless_simd::Simd>(
        &self,
        simd: S,
        columns: crate::simd::F<S>,
        rows: crate::simd::F<S>,
    ) -> [crate::simd::F<S>; 3] {
        use crate::simd::F;
        use fearless_simd::prelude::*;
        let splat = |x: f32| F::<S>::splat(simd, x);
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
        Some(Vec2::new(
            (x / self.window_width + 0.5) * self.width as f32,
            (0.5 - y / self.window_height) * self.height as f32,
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
    fn four_rays_at_a_time_are_glams_rays() {
        // The lanes reproduce glam's Mat3 * Vec3 and normalize bit for bit.
        let c = Camera { yaw_deg: 33.0, pitch_deg: -12.0, position: Vec3::new(1.0, 2.0, -3.0), ..camera() };
        let v = c.view(Eye::Right, 1280, 720);
        for (i, j) in [(0, 0), (17, 301), (640, 360), (1276, 719)] {
            let x = ((i as f32 + 0.5) * v.inv_width - 0.5) * v.window_width;
            let y = (0.5 - (j as f32 + 0.5) * v.inv_height) * v.window_height;
            let want = (v.world_from_head * Vec3::new(x - v.eye_x, y, v.distance)).normalize();
            assert_eq!(v.primary_ray(i, j).dir, want, "({i}, {j})");
            let [dx, dy, dz] = v.primary_dirs4(i - i % 4, j);
            let k = (i % 4) as usize;
            assert_eq!(Vec3::new(dx.as_array()[k], dy.as_array()[k], dz.as_array()[k]), want);
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
