//! The views a stereo pair is traced through, kept with the pair as an OpenXR projection
//! layer (`XrCompositionLayerProjectionView`) carries the pose and field of view it was
//! rendered with: whoever warps or scores a traced pair reads its views from here, never
//! derives them again from a pose echoed back. This is the one place a pair's views are
//! made ([`tracer::Camera::view_with_margin`]), and the views a warp of it lands in.

use tracer::{Camera, Eye, EyeView};

/// A stereo pair's two eye views: the head pose and stereo parameters they come from, the
/// size each eye shows, and the guard band traced around it.
#[derive(Clone, Copy, Debug)]
pub struct StereoViews {
    /// The head pose and stereo parameters the pair was traced for.
    pub camera: Camera,
    /// The size each eye shows, without the guard band.
    pub shown: (u32, u32),
    /// The guard band, pixels traced beyond each side of the shown part (columns, rows).
    pub margin: (u32, u32),
    /// The left and the right eye's views as traced, guard band included.
    pub eyes: [EyeView; 2],
}

impl StereoViews {
    /// The views of `camera`'s eyes for a `shown` = (width, height) image each, traced with
    /// a guard band of `margin` = (mx, my) pixels each side: each view is (width + 2·mx) ×
    /// (height + 2·my), its shown part bit for bit the view without the band.
    #[must_use]
    pub fn new(camera: &Camera, shown: (u32, u32), margin: (u32, u32)) -> Self {
        let view = |eye| camera.view_with_margin(eye, shown.0, shown.1, margin);
        Self { camera: *camera, shown, margin, eyes: [view(Eye::Left), view(Eye::Right)] }
    }

    /// The left eye's view, as traced.
    #[must_use]
    pub fn left(&self) -> &EyeView {
        &self.eyes[0]
    }

    /// The right eye's view, as traced.
    #[must_use]
    pub fn right(&self) -> &EyeView {
        &self.eyes[1]
    }

    /// Pixels per traced eye, guard band included.
    #[must_use]
    pub fn traced_pixels(&self) -> usize {
        self.eyes[0].width as usize * self.eyes[0].height as usize
    }

    /// The views a warp of this pair to the head pose `pose` lands in: `pose`'s eyes at the
    /// shown size, without a band.
    #[must_use]
    pub fn warped_to(&self, pose: &Camera) -> [EyeView; 2] {
        Self::new(pose, self.shown, (0, 0)).eyes
    }
}

impl Default for StereoViews {
    /// The views of an empty frame: the default camera, no pixels.
    fn default() -> Self {
        Self::new(&Camera::default(), (0, 0), (0, 0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The views are the camera's: the shown part of a banded view has the very rays of
    /// the view without the band, and a warp lands in the unbanded views of its pose.
    #[test]
    fn a_pair_carries_its_cameras_banded_views_and_warps_to_unbanded_ones() {
        let camera = Camera { ipd: 1.0, yaw_deg: 10.0, ..Camera::default() };
        let views = StereoViews::new(&camera, (32, 24), (3, 2));
        assert_eq!((views.left().width, views.left().height, views.left().margin), (38, 28, (3, 2)));
        assert_eq!((views.left().eye, views.right().eye), (Eye::Left, Eye::Right));
        assert_eq!(views.traced_pixels(), 38 * 28);
        let plain = camera.view(Eye::Right, 32, 24);
        assert_eq!(views.right().origin, plain.origin);
        let turned = Camera { yaw_deg: 12.0, ..camera };
        let [l, r] = views.warped_to(&turned);
        assert_eq!((l.width, l.height, l.margin, r.eye), (32, 24, (0, 0), Eye::Right));
        assert_eq!(r.origin, turned.view(Eye::Right, 32, 24).origin);
        assert_ne!(r.origin, views.right().origin, "the pose the warp goes to, not the traced one");
    }
}
