//! The settings model: everything the user sets in the panel or with keys, the head's
//! movement and turning, and the render request the settings ask for.
//!
//! The panel (`ui.rs`) edits a [`Settings`] value and the keys (`input.rs`) toggle it; the
//! app turns it into a [`Request`] for the render worker every tick. Both eyes share the
//! head pose, so moving never breaks the reprojection.

use glam::Vec3;
use stereo::{Layout, Mode};
use tracer::{Camera, Scene};

use crate::window::present::Look;
use crate::window::worker::{Progressive, Request};

/// Largest interpupillary distance the slider offers, scene units.
pub const MAX_IPD: f32 = 2.0;

/// The range of the distance to the zero-parallax window, scene units.
pub const DISTANCE_RANGE: (f32, f32) = (1.0, 100.0);

/// Largest reflection depth the slider offers.
pub const MAX_REFLECTION_DEPTH: u32 = 8;

/// Smallest share of the on-screen eye size an eye is traced at.
pub const MIN_RENDER_SCALE: f32 = 0.25;

/// Largest render scale: 200 % traces 2 × 2 samples per pixel (supersampling).
pub const MAX_RENDER_SCALE: f32 = 2.0;

/// How far the light sliders reach from the origin on each axis.
pub const LIGHT_RANGE: f32 = 30.0;

/// Largest orbit-speed factor.
pub const MAX_ORBIT_SPEED: f32 = 4.0;

/// Head speed while a movement key is held, scene units per second.
pub const HEAD_SPEED: f32 = 2.0;

/// Head turn per pixel of mouse drag, degrees.
pub const TURN_PER_PIXEL: f32 = 0.2;

/// Pitch limit, degrees: the head never looks straight up or down.
pub const MAX_PITCH: f32 = 89.0;

/// The timewarp's guard band by default: each eye is traced this share of its width (and
/// height) beyond each side, so a turn of a few degrees during a trace shows no empty edge
/// (5 %: 40 × 30 pixels around an 800 × 600 eye, 21 % more pixels traced).
pub const DEFAULT_GUARD_BAND: f32 = 0.05;

/// Largest guard band, a share of the eye beyond each side.
pub const MAX_GUARD_BAND: f32 = 0.25;

/// Everything the user sets in the panel or with keys.
#[expect(
    clippy::struct_excessive_bools,
    reason = "each flag is an independent checkbox in the panel; an enum or bit set would only obscure that"
)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Interpupillary distance e, scene units (0..[`MAX_IPD`]).
    pub ipd: f32,
    /// Distance d from the eyes to the zero-parallax window ([`DISTANCE_RANGE`]).
    pub distance: f32,
    /// Reflection bounces (0..[`MAX_REFLECTION_DEPTH`]).
    pub depth: u32,
    /// How the right eye is made.
    pub mode: Mode,
    /// For copy and reshade: retrace object-edge pixels too.
    pub retrace_edges: bool,
    /// How the eyes are arranged.
    pub layout: Layout,
    /// Eyes are traced at this multiple of their on-screen size per axis
    /// ([`MIN_RENDER_SCALE`]..[`MAX_RENDER_SCALE`]): below 1 scaled up to the screen, above 1
    /// supersampled (anti-aliased) and filtered down to it, by a box filter in linear light
    /// (`stereo::downsample`); 2 traces 2 × 2 samples per pixel.
    pub render_scale: f32,
    /// Blend the debug mask over the right eye (key M).
    pub show_mask: bool,
    /// Measure the right eye against a full trace every frame.
    pub live_psnr: bool,
    /// Reuse a frame's unchanged pixels while only the scene time moves (the panel's
    /// "reuse" tick).
    pub reuse: bool,
    /// Scene time stands still (key Space).
    pub paused: bool,
    /// Exchange the eyes (key X).
    pub swap_eyes: bool,
    /// Head position (midpoint between the eyes), world space.
    pub position: Vec3,
    /// Head turn about +y, degrees.
    pub yaw_deg: f32,
    /// Head tilt, degrees, within ±[`MAX_PITCH`].
    pub pitch_deg: f32,
    /// Position of the scene's first light (the sliders reach ±[`LIGHT_RANGE`]); `None` when
    /// the scene has no lights.
    pub light: Option<Vec3>,
    /// Scene seconds per wall second for the revolving spheres (0..[`MAX_ORBIT_SPEED`]).
    pub orbit_speed: f32,
    /// The scene's size against the bundled scenes' (1 for scenes of spheres; a molecule in
    /// Ångström is larger): the IPD, distance and light sliders reach, and the head walks,
    /// this many times as far ([`Scene::head_speed`] over [`HEAD_SPEED`]).
    pub scale: f32,
    /// Every presented frame is the last traced frame warped to the head pose of that
    /// moment (the panel's "timewarp" tick; `--no-timewarp` starts with it off).
    pub timewarp: bool,
    /// The timewarp's guard band, a share of the eye traced beyond each side
    /// (0..=[`MAX_GUARD_BAND`]).
    pub guard_band: f32,
    /// The structures' colours and hidden atoms (the panel's colour section, key C).
    pub atoms: crate::window::look::AtomLook,
    /// The progressive policy the requests carry ([`Request::progressive`]), on by default;
    /// `None`: every frame at the render scale (`--no-progressive`, `replay --policy fixed`).
    pub progressive: Option<Progressive>,
}

impl Settings {
    /// The scene's own camera, depth and light, exact mode, nothing else on.
    #[must_use]
    pub fn from_scene(scene: &Scene) -> Self {
        let mut s = Self {
            ipd: 0.0,
            distance: 1.0,
            depth: 0,
            mode: Mode::Exact,
            retrace_edges: false,
            layout: Layout::SideBySide,
            render_scale: 1.0,
            show_mask: false,
            live_psnr: false,
            reuse: true,
            paused: false,
            swap_eyes: false,
            position: Vec3::ZERO,
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            light: None,
            orbit_speed: 1.0,
            scale: scene.head_speed() / HEAD_SPEED,
            timewarp: true,
            guard_band: DEFAULT_GUARD_BAND,
            atoms: crate::window::look::AtomLook::default(),
            progressive: Some(Progressive::default()),
        };
        s.reset_camera(scene);
        s.reset_light(scene);
        s
    }

    /// Takes another scene's scale, camera and light (a new file opened).
    pub fn adopt_scene(&mut self, scene: &Scene) {
        self.scale = scene.head_speed() / HEAD_SPEED;
        self.reset_camera(scene);
        self.reset_light(scene);
    }

    /// Restores the head pose, IPD, distance and reflection depth from the scene (clamped to
    /// the sliders' ranges).
    pub fn reset_camera(&mut self, scene: &Scene) {
        let (max_ipd, (near, far)) = (self.max_ipd(), self.distance_range());
        self.ipd = scene.camera.ipd.clamp(0.0, max_ipd);
        self.distance = scene.camera.distance.clamp(near, far);
        self.depth = scene.render.max_depth.min(MAX_REFLECTION_DEPTH);
        self.position = scene.camera.position;
        self.yaw_deg = scene.camera.yaw_deg;
        self.pitch_deg = scene.camera.pitch_deg.clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// The IPD slider's top, scene units: [`MAX_IPD`] at the scene's scale.
    #[must_use]
    pub fn max_ipd(&self) -> f32 {
        MAX_IPD * self.scale
    }

    /// The distance slider's range, scene units: [`DISTANCE_RANGE`] at the scene's scale.
    #[must_use]
    pub fn distance_range(&self) -> (f32, f32) {
        (DISTANCE_RANGE.0 * self.scale, DISTANCE_RANGE.1 * self.scale)
    }

    /// How far the light sliders reach, scene units: [`LIGHT_RANGE`] at the scene's scale.
    #[must_use]
    pub fn light_range(&self) -> f32 {
        LIGHT_RANGE * self.scale
    }

    /// Puts the first light back where the scene has it (even beyond the sliders' reach).
    pub fn reset_light(&mut self, scene: &Scene) {
        self.light = scene.lights.first().map(|l| l.position);
    }

    /// The camera these settings ask for: `base` (the scene's) with the head pose, IPD and
    /// distance set here.
    #[must_use]
    pub fn camera(&self, base: &Camera) -> Camera {
        Camera {
            ipd: self.ipd,
            distance: self.distance,
            position: self.position,
            yaw_deg: self.yaw_deg,
            pitch_deg: self.pitch_deg,
            ..*base
        }
    }

    /// Moves the head (both eyes together) by `forward` and `right` scene units along its own
    /// axes (forward follows the pitch too).
    pub fn move_head(&mut self, forward: f32, right: f32) {
        let rot = self.camera(&Camera::default()).world_from_head();
        self.position += rot * Vec3::new(right, 0.0, forward);
    }

    /// Walks the head for `seconds` at [`HEAD_SPEED`] (at the scene's scale) in the direction (`forward`, `right`,
    /// `up`), each −1..=1 (movement keys held): forward and right along the head's own axes,
    /// up straight along world +y (Q and E, as in a fly camera).
    pub fn walk(&mut self, (forward, right, up): (f32, f32, f32), seconds: f32) {
        if forward != 0.0 || right != 0.0 || up != 0.0 {
            let step = HEAD_SPEED * self.scale * seconds;
            self.move_head(forward * step, right * step);
            self.position.y += up * step;
        }
    }

    /// Follows a reload of the same scene file from `old` to `new`: what the file changed
    /// (a camera value, the reflection depth, the first light) takes the file's new value;
    /// everything else — above all the head pose the user walked to, and the sliders —
    /// stays as it is.
    pub fn follow_reload(&mut self, old: &Scene, new: &Scene) {
        self.scale = new.head_speed() / HEAD_SPEED;
        let mut from_file = *self;
        from_file.reset_camera(new);
        from_file.reset_light(new);
        let (o, n) = (&old.camera, &new.camera);
        if o.ipd != n.ipd {
            self.ipd = from_file.ipd;
        }
        if o.distance != n.distance {
            self.distance = from_file.distance;
        }
        if old.render.max_depth != new.render.max_depth {
            self.depth = from_file.depth;
        }
        if (o.position, o.yaw_deg, o.pitch_deg) != (n.position, n.yaw_deg, n.pitch_deg) {
            (self.position, self.yaw_deg, self.pitch_deg) =
                (from_file.position, from_file.yaw_deg, from_file.pitch_deg);
        }
        if old.lights.first().map(|l| l.position) != new.lights.first().map(|l| l.position) {
            self.light = from_file.light;
        }
    }

    /// Turns the head by a mouse drag of `dx`, `dy` pixels (right turns right, up looks up).
    pub fn turn_head(&mut self, dx: f32, dy: f32) {
        self.yaw_deg = (self.yaw_deg + dx * TURN_PER_PIXEL + 180.0).rem_euclid(360.0) - 180.0;
        self.pitch_deg = (self.pitch_deg - dy * TURN_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// The size to trace an eye at, for an eye of `width` × `height` on screen: smaller
    /// below 100 %, larger (the samples) above it.
    #[must_use]
    pub fn render_size(&self, width: u32, height: u32) -> (u32, u32) {
        let scale = self.render_scale.clamp(MIN_RENDER_SCALE, MAX_RENDER_SCALE);
        let scaled = |n: u32| ((n as f32 * scale).round() as u32).max(1);
        (scaled(width), scaled(height))
    }

    /// The render options these settings ask for.
    #[must_use]
    pub fn options(&self) -> stereo::Options {
        stereo::Options { mode: self.mode, retrace_edges: self.retrace_edges }
    }

    /// How the eyes are shown.
    #[must_use]
    pub fn look(&self) -> Look {
        Look { layout: self.layout, swap: self.swap_eyes, show_mask: self.show_mask }
    }

    /// The render request these settings ask for, for `scene` at scene time `time` (a still
    /// scene is always rendered at 0) and an eye of `width` × `height` on screen.
    #[must_use]
    pub fn request(&self, scene: &Scene, time: f32, width: u32, height: u32) -> Request {
        let samples = self.render_size(width, height);
        // Below 100 % the images are the traced size (the window scales them up); above it,
        // the eye size the samples are filtered down to.
        let (width, height) = (samples.0.min(width), samples.1.min(height));
        let anaglyph = self.layout == Layout::Anaglyph;
        Request {
            camera: self.camera(&scene.camera),
            depth: self.depth,
            opts: self.options(),
            time: if scene.is_animated() { time } else { 0.0 },
            width,
            height,
            samples,
            psnr: self.live_psnr,
            reuse: self.reuse,
            anaglyph,
            overlay: self.show_mask,
            swap: anaglyph && self.swap_eyes,
            light: self.light,
            timewarp: self.timewarp,
            guard: if self.timewarp { self.guard(samples) } else { (0, 0) },
            atoms: self.atoms,
            progressive: self.progressive,
            moving: false,
        }
    }

    /// The guard band around `samples` (the traced size), samples beyond each side.
    #[must_use]
    pub fn guard(&self, samples: (u32, u32)) -> (u32, u32) {
        crate::setup::guard_band(samples, self.guard_band.clamp(0.0, MAX_GUARD_BAND))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        let src = "[camera]\nipd = 0.5\ndistance = 9.0\n[render]\nmax_depth = 12\n\
                   [[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n";
        Scene::from_toml(src, "s.toml").unwrap()
    }

    #[test]
    fn reset_restores_the_scene_camera_within_the_slider_ranges() {
        let scene = scene();
        let mut s = Settings::from_scene(&scene);
        assert_eq!(
            (s.ipd, s.distance, s.depth, s.mode),
            (0.5, 9.0, MAX_REFLECTION_DEPTH, Mode::Exact),
            "the scene's camera, its depth clamped"
        );
        s.ipd = 1.7;
        s.distance = 40.0;
        s.show_mask = true;
        s.reset_camera(&scene);
        assert_eq!((s.ipd, s.distance), (0.5, 9.0), "reset restores the scene's IPD and distance");
        assert!(s.show_mask, "reset touches only the camera values");
        assert_eq!(s.render_size(800, 600), (800, 600), "full scale traces the eye size");
        s.render_scale = 0.5;
        assert_eq!(s.render_size(801, 600), (401, 300), "half scale, rounded");
        s.render_scale = 0.0;
        assert_eq!(s.render_size(3, 1), (1, 1), "never below one pixel");
        s.render_scale = MAX_RENDER_SCALE;
        assert_eq!(s.render_size(801, 600), (1602, 1200), "200 %: 2 × 2 samples per pixel");
        s.render_scale = 9.0;
        assert_eq!(s.render_size(801, 600), (1602, 1200), "never above 200 %");
        s.render_scale = 1.5;
        assert_eq!(s.render_size(801, 600), (1202, 900), "150 %, rounded");
    }

    #[test]
    fn the_light_starts_where_the_scene_puts_it_even_beyond_the_sliders() {
        let src = "[[lights]]\nposition = [40.0, 2.0, -3.0]\n[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n";
        let scene = Scene::from_toml(src, "l.toml").unwrap();
        let mut s = Settings::from_scene(&scene);
        assert_eq!(s.light, Some(Vec3::new(40.0, 2.0, -3.0)), "the scene's first light");
        assert_eq!(s.orbit_speed, 1.0, "the orbit at its own speed");
        s.light = Some(Vec3::ZERO);
        s.reset_light(&scene);
        assert_eq!(s.light, Some(Vec3::new(40.0, 2.0, -3.0)), "reset puts it back");
    }

    #[test]
    fn the_head_moves_along_its_own_axes_and_resets_to_the_scene() {
        let scene = scene();
        let mut s = Settings::from_scene(&scene);
        assert_eq!(s.light, None, "this scene has no lights");
        s.move_head(2.0, 0.0);
        assert!((s.position - Vec3::new(0.0, 0.0, 2.0)).length() < 1e-6, "forward is +z: {:?}", s.position);
        s.turn_head(90.0 / TURN_PER_PIXEL, 0.0);
        assert!((s.yaw_deg - 90.0).abs() < 1e-3, "dragging right turns right: {}", s.yaw_deg);
        s.move_head(1.0, 0.0);
        assert!(
            (s.position - Vec3::new(1.0, 0.0, 2.0)).length() < 1e-5,
            "turned right, forward is +x: {:?}",
            s.position
        );
        s.move_head(0.0, 1.0);
        assert!((s.position - Vec3::new(1.0, 0.0, 1.0)).length() < 1e-5, "and right is -z: {:?}", s.position);
        s.walk((-1.0, 0.0, 0.0), 0.25);
        let walked = Vec3::new(1.0 - 0.25 * HEAD_SPEED, 0.0, 1.0);
        assert!((s.position - walked).length() < 1e-5, "walking back at the head speed: {:?}", s.position);
        s.walk((0.0, 0.0, 1.0), 0.5);
        let risen = walked + Vec3::Y * 0.5 * HEAD_SPEED;
        assert!((s.position - risen).length() < 1e-5, "E rises straight up: {:?}", s.position);
        s.walk((0.0, 0.0, -1.0), 0.5);
        assert!((s.position - walked).length() < 1e-5, "Q sinks back: {:?}", s.position);
        s.turn_head(0.0, -1e6);
        assert_eq!(s.pitch_deg, MAX_PITCH, "dragging up looks up, clamped");
        let cam = s.camera(&scene.camera);
        assert_eq!(
            (cam.position, cam.pitch_deg, cam.fov_deg),
            (s.position, MAX_PITCH, scene.camera.fov_deg),
            "the head pose over the scene's camera"
        );
        s.reset_camera(&scene);
        assert_eq!((s.position, s.yaw_deg, s.pitch_deg), (Vec3::ZERO, 0.0, 0.0), "reset puts the head back");
    }

    #[test]
    fn a_reload_keeps_the_head_and_sliders_and_takes_what_the_file_changed() {
        let old = scene();
        let mut s = Settings::from_scene(&old);
        s.move_head(3.0, 1.0);
        s.turn_head(50.0, 20.0);
        s.ipd = 1.2;
        s.mode = Mode::Copy;
        let walked = s;
        // A sphere added: nothing of the settings changes.
        let mut new = old.clone();
        new.spheres.push(new.spheres[0]);
        s.follow_reload(&old, &new);
        assert_eq!(s, walked, "the head pose and the sliders are kept");
        // The file's IPD changed: that one value follows the file.
        new.camera.ipd = 0.3;
        s.follow_reload(&old, &new);
        assert_eq!(s, Settings { ipd: 0.3, ..walked }, "only the IPD follows the file");
        // The file's camera pose changed: the head goes where the file now puts it.
        let mut moved = new.clone();
        moved.camera.position = Vec3::new(0.0, 1.0, -2.0);
        s.follow_reload(&new, &moved);
        assert_eq!((s.position, s.yaw_deg, s.pitch_deg), (moved.camera.position, 0.0, 0.0), "the file's new pose");
        assert_eq!((s.ipd, s.mode), (0.3, Mode::Copy), "the rest stays");
    }

    #[test]
    fn the_request_follows_the_settings() {
        let scene = scene();
        let mut s = Settings::from_scene(&scene);
        s.render_scale = 0.5;
        s.swap_eyes = true;
        let r = s.request(&scene, 3.0, 400, 300);
        assert_eq!((r.width, r.height, r.samples), (200, 150, (200, 150)), "traced at the render scale");
        s.render_scale = 2.0;
        let r = s.request(&scene, 3.0, 400, 300);
        assert_eq!((r.width, r.height, r.samples), (400, 300, (800, 600)), "supersampled, shown at the eye size");
        s.render_scale = 0.5;
        assert_eq!(r.time, 0.0, "a still scene is rendered at time 0");
        assert!(!r.anaglyph && !r.swap, "side by side swaps on screen, not in the worker");
        assert_eq!((r.camera.ipd, r.depth, r.opts), (0.5, MAX_REFLECTION_DEPTH, s.options()), "the settings' camera");
        s.layout = Layout::Anaglyph;
        let r = s.request(&scene, 3.0, 400, 300);
        assert!(r.anaglyph && r.swap, "the worker makes the anaglyph, swapped");
        let orbit = "[[spheres]]\norbit = { center = [0.0, 0.0, 10.0], radius = 2.0, period_s = 4.0 }\nradius = 1.0\n";
        let animated = Scene::from_toml(orbit, "o.toml").unwrap();
        assert_eq!(s.request(&animated, 3.0, 400, 300).time, 3.0, "a moving scene at the clock's time");
        assert_eq!(
            s.request(&scene, 3.0, 400, 300).progressive,
            Some(Progressive::default()),
            "progressive by default"
        );
        s.progressive = None;
        assert_eq!(s.request(&scene, 3.0, 400, 300).progressive, None, "--no-progressive");
        s.progressive = Some(Progressive { target_age_ms: 20.0, max_supersample: 2 });
        assert_eq!(s.request(&scene, 3.0, 400, 300).progressive, s.progressive, "the policy rides on the request");
    }
}
