//! The egui panel: the render settings the user controls and the live statistics.
//!
//! The panel is a small, semi-transparent, collapsible window anchored at the top-left corner,
//! so the eyes stay visible behind it. It only edits a [`Settings`] value and reports button
//! presses; the app turns the settings into render requests.

use egui::{Align2, Color32, RichText, Slider};
use glam::Vec3;
use stereo::{mask_color, FrameStats, Layout, Mode, MASK_LEGEND};
use tracer::{Camera, Scene};

use crate::worker::FrameInfo;

/// Largest reflection depth the slider offers.
pub const MAX_REFLECTION_DEPTH: u32 = 8;

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

/// The keys, as the panel lists them.
pub const HELP: &str = "W/↑ forward · ↓ back · A/← D/→ sideways · right-drag (or left-drag outside \
                        the panel) turns · R reset · 1 2 3 layout · X swap · M mask · Space pause · \
                        S save · Esc quit";

/// Everything the user sets in the panel or with keys.
// Each flag is an independent checkbox in the panel; an enum or bit set would only obscure that.
#[allow(clippy::struct_excessive_bools)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Interpupillary distance e, scene units (0..2).
    pub ipd: f32,
    /// Distance d from the eyes to the zero-parallax window (1..100).
    pub distance: f32,
    /// Reflection bounces (0..8).
    pub depth: u32,
    /// How the right eye is made.
    pub mode: Mode,
    /// For copy and reshade: retrace object-edge pixels too.
    pub retrace_edges: bool,
    /// How the eyes are arranged.
    pub layout: Layout,
    /// Eyes are traced at this fraction of their on-screen size (0.25..1) and scaled up.
    pub render_scale: f32,
    /// Blend the debug mask over the right eye (key M).
    pub show_mask: bool,
    /// Measure the right eye against a full trace every frame.
    pub live_psnr: bool,
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
    /// Scene seconds per wall second for the revolving spheres (0..4).
    pub orbit_speed: f32,
}

impl Settings {
    /// The scene's own camera and depth, exact mode, nothing else on.
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
            paused: false,
            swap_eyes: false,
            position: Vec3::ZERO,
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            light: scene.lights.first().map(|l| l.position),
            orbit_speed: 1.0,
        };
        s.reset_camera(scene);
        s
    }

    /// Restores the head pose, IPD, distance and reflection depth from the scene (clamped to
    /// the sliders' ranges).
    pub fn reset_camera(&mut self, scene: &Scene) {
        self.ipd = scene.camera.ipd.clamp(0.0, 2.0);
        self.distance = scene.camera.distance.clamp(1.0, 100.0);
        self.depth = scene.render.max_depth.min(MAX_REFLECTION_DEPTH);
        self.position = scene.camera.position;
        self.yaw_deg = scene.camera.yaw_deg;
        self.pitch_deg = scene.camera.pitch_deg.clamp(-MAX_PITCH, MAX_PITCH);
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

    /// Turns the head by a mouse drag of `dx`, `dy` pixels (right turns right, up looks up).
    pub fn turn_head(&mut self, dx: f32, dy: f32) {
        self.yaw_deg = (self.yaw_deg + dx * TURN_PER_PIXEL + 180.0).rem_euclid(360.0) - 180.0;
        self.pitch_deg = (self.pitch_deg - dy * TURN_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// The size to trace an eye at, for an eye of `width` × `height` on screen.
    #[must_use]
    pub fn render_size(&self, width: u32, height: u32) -> (u32, u32) {
        let scaled = |n: u32| ((n as f32 * self.render_scale.clamp(0.25, 1.0)).round() as u32).clamp(1, n.max(1));
        (scaled(width), scaled(height))
    }

    /// The render options these settings ask for.
    #[must_use]
    pub fn options(&self) -> stereo::Options {
        stereo::Options { mode: self.mode, retrace_edges: self.retrace_edges }
    }
}

/// The series of the frame-time plot: name and line colour.
pub const SERIES: [(&str, Color32); SERIES_LEN] = [
    ("frame", Color32::from_rgb(200, 200, 200)),
    ("left eye", Color32::from_rgb(255, 110, 90)),
    ("right eye", Color32::from_rgb(90, 200, 255)),
    ("reproject", Color32::from_rgb(120, 230, 110)),
    ("retrace", Color32::from_rgb(240, 200, 60)),
    ("reshade", Color32::from_rgb(210, 120, 255)),
];

/// Number of series in the frame-time plot.
pub const SERIES_LEN: usize = 6;

/// One frame's times, milliseconds, in [`SERIES`] order.
pub type Sample = [f32; SERIES_LEN];

/// The times of one frame in [`SERIES`] order: the whole job, each eye, and the right eye's
/// stages (the left eye's only stage is its trace).
#[must_use]
pub fn sample(wall_ms: f64, stats: &FrameStats) -> Sample {
    let st = &stats.stages;
    [wall_ms, stats.left.ms, stats.right.ms, st.reproject, st.retrace, st.reshade].map(|v| v as f32)
}

/// The last frames' times, for the plot (a fixed ring, no allocation).
#[derive(Clone, Debug)]
pub struct FrameTimes {
    ms: [Sample; Self::LEN],
    head: usize,
    len: usize,
}

impl Default for FrameTimes {
    fn default() -> Self {
        Self { ms: [[0.0; SERIES_LEN]; Self::LEN], head: 0, len: 0 }
    }
}

impl FrameTimes {
    /// How many frames the plot shows.
    pub const LEN: usize = 120;

    /// Records one frame's times.
    pub fn push(&mut self, ms: Sample) {
        self.ms[self.head] = ms;
        self.head = (self.head + 1) % Self::LEN;
        self.len = (self.len + 1).min(Self::LEN);
    }

    /// Oldest first.
    pub fn iter(&self) -> impl Iterator<Item = &Sample> + '_ {
        let start = (self.head + Self::LEN - self.len) % Self::LEN;
        (0..self.len).map(move |k| &self.ms[(start + k) % Self::LEN])
    }
}

/// What the panel shows but does not edit.
#[derive(Clone, Copy, Debug)]
pub struct Readout<'a> {
    /// Frames presented per second.
    pub ui_fps: f64,
    /// Stereo frames rendered per second.
    pub render_fps: f64,
    /// The frame on screen, if any.
    pub frame: Option<&'a FrameInfo>,
    /// Scene time, seconds.
    pub time: f32,
    /// Whether the scene has moving spheres (otherwise pausing means nothing).
    pub animated: bool,
    /// Recent frame times.
    pub history: &'a FrameTimes,
    /// What the last screenshot wrote, while it is recent.
    pub saved: Option<&'a str>,
}

/// Buttons pressed this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Actions {
    /// "reset camera" was clicked.
    pub reset: bool,
    /// "save pair (S)" was clicked.
    pub save: bool,
    /// "reset light" was clicked.
    pub reset_light: bool,
}

/// Formats a ray count as millions, e.g. "1.23 M".
#[must_use]
pub fn mega(n: u64) -> String {
    format!("{:.2} M", n as f64 / 1e6)
}

/// Sets the look once: dark, so the panel reads over the white seed scene.
pub fn setup_style(ctx: &egui::Context) {
    ctx.set_theme(egui::Theme::Dark);
}

/// Draws the panel and applies the user's edits to `settings` and the screenshot folder.
pub fn panel(ctx: &egui::Context, settings: &mut Settings, readout: &Readout<'_>, folder: &mut String) -> Actions {
    let mut actions = Actions::default();
    let frame = egui::Frame::window(&ctx.global_style()).fill(Color32::from_rgba_unmultiplied(24, 24, 28, 215));
    egui::Window::new("stereotrace")
        .anchor(Align2::LEFT_TOP, [8.0, 8.0])
        .collapsible(true)
        .resizable(false)
        .default_width(250.0)
        .frame(frame)
        // The scroll area may use the whole window height (egui clamps this minimum to the
        // screen); the panel itself still wraps its contents, and scrolls only when the window
        // is too short for them.
        .min_height(ctx.content_rect().height())
        .show(ctx, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                controls(ui, settings, readout, &mut actions);
                screenshots(ui, readout, folder);
                egui::CollapsingHeader::new("light").show(ui, |ui| light(ui, settings, readout, &mut actions));
                ui.separator();
                statistics(ui, settings, readout);
                if settings.show_mask {
                    ui.separator();
                    legend(ui);
                }
            });
        });
    actions
}

fn controls(ui: &mut egui::Ui, s: &mut Settings, readout: &Readout<'_>, actions: &mut Actions) {
    ui.add(Slider::new(&mut s.ipd, 0.0..=2.0).text("IPD")).on_hover_text("interpupillary distance e, scene units");
    ui.add(Slider::new(&mut s.distance, 1.0..=100.0).logarithmic(true).text("depth d"))
        .on_hover_text("distance from the eyes to the zero-parallax window");
    ui.add(Slider::new(&mut s.depth, 0..=MAX_REFLECTION_DEPTH).text("reflections"))
        .on_hover_text("reflection depth (bounces)");
    ui.add(
        Slider::new(&mut s.render_scale, 0.25..=1.0)
            .text("render scale")
            .custom_formatter(|v, _| format!("{:.0} %", v * 100.0))
            .custom_parser(|t| t.trim().trim_end_matches('%').trim().parse::<f64>().ok().map(|v| v / 100.0)),
    )
    .on_hover_text("trace each eye at this share of its window size, then scale it up");
    ui.horizontal(|ui| {
        ui.label("mode");
        for m in Mode::ALL {
            ui.selectable_value(&mut s.mode, m, m.name());
        }
    });
    let edges_apply = matches!(s.mode, Mode::Copy | Mode::Reshade);
    ui.add_enabled(edges_apply, egui::Checkbox::new(&mut s.retrace_edges, "retrace edges"))
        .on_hover_text("copy and reshade: also retrace pixels on object silhouettes")
        .on_disabled_hover_text("exact always retraces edges; full traces everything");
    ui.horizontal(|ui| {
        ui.label("layout");
        for (k, l) in Layout::ALL.into_iter().enumerate() {
            ui.selectable_value(&mut s.layout, l, l.name()).on_hover_text(format!("key {}", k + 1));
        }
    });

    ui.horizontal(|ui| {
        ui.checkbox(&mut s.show_mask, "show mask (M)");
        ui.add_enabled(readout.animated, egui::Checkbox::new(&mut s.paused, "pause (Space)"));
    });
    ui.horizontal(|ui| {
        ui.checkbox(&mut s.swap_eyes, "swap eyes (X)").on_hover_text("exchange the left and right images");
        ui.checkbox(&mut s.live_psnr, "live PSNR").on_hover_text("compare the right eye with a full trace each frame");
    });
    ui.horizontal(|ui| {
        actions.reset = ui.button("reset camera (R)").clicked();
        actions.save = ui.button("save pair (S)").clicked();
    });
    ui.label(
        RichText::new(format!(
            "head at {:.1}, {:.1}, {:.1} · yaw {:.0}° · pitch {:.0}°",
            s.position.x, s.position.y, s.position.z, s.yaw_deg, s.pitch_deg
        ))
        .small(),
    );
    egui::CollapsingHeader::new("keys").show(ui, |ui| ui.label(RichText::new(HELP).small()));
}

fn screenshots(ui: &mut egui::Ui, r: &Readout<'_>, folder: &mut String) {
    ui.horizontal(|ui| {
        ui.label("folder");
        ui.add(egui::TextEdit::singleline(folder).desired_width(150.0))
            .on_hover_text("screenshots (S) go here; created if missing");
    });
    if let Some(saved) = r.saved {
        ui.label(RichText::new(saved).small().color(Color32::from_rgb(150, 230, 150)));
    }
}

fn light(ui: &mut egui::Ui, s: &mut Settings, r: &Readout<'_>, actions: &mut Actions) {
    let range = -LIGHT_RANGE..=LIGHT_RANGE;
    if s.light.is_some() {
        ui.horizontal(|ui| {
            ui.label("first light's position");
            actions.reset_light = ui.small_button("reset").clicked();
        });
    } else {
        ui.label(RichText::new("the scene has no lights").small().weak());
    }
    let mut none = Vec3::ZERO;
    let enabled = s.light.is_some();
    let p = s.light.as_mut().unwrap_or(&mut none);
    for (value, axis) in [(&mut p.x, "x"), (&mut p.y, "y"), (&mut p.z, "z")] {
        // A scene light beyond the range keeps its place until the slider is moved.
        ui.add_enabled(enabled, Slider::new(value, range.clone()).clamping(egui::SliderClamping::Edits).text(axis));
    }
    ui.add_enabled(
        r.animated,
        Slider::new(&mut s.orbit_speed, 0.0..=MAX_ORBIT_SPEED)
            .text("orbit speed")
            .custom_formatter(|v, _| format!("{v:.2}×")),
    )
    .on_hover_text("scene time per wall second for the revolving spheres; 0 stands still");
}

fn statistics(ui: &mut egui::Ui, s: &Settings, r: &Readout<'_>) {
    egui::Grid::new("stats").num_columns(2).spacing([12.0, 2.0]).show(ui, |ui| {
        let mut row = |name: &str, value: String| {
            ui.label(name);
            ui.label(RichText::new(value).monospace());
            ui.end_row();
        };
        row("fps", format!("{:.1} UI · {:.1} render", r.ui_fps, r.render_fps));
        let Some(f) = r.frame else {
            row("frame", "rendering…".to_owned());
            return;
        };
        let st = &f.stats;
        row("eye", format!("{} × {} · t {:.2} s", f.request.width, f.request.height, r.time));
        row("ms per eye", format!("L {:.1} · R {:.1}", st.left.ms, st.right.ms));
        row("rays per eye", format!("L {} · R {}", mega(st.left.rays.total()), mega(st.right.rays.total())));
        row("reprojected", format!("{:.1} %", 100.0 * st.pixels.reprojected_share()));
        row("right / left", format!("rays {:.2} · time {:.2}", st.right_ray_ratio(), st.right_time_ratio()));
        if s.live_psnr {
            let q = match f.quality {
                Some(q) if q.psnr_db.is_infinite() => "identical · 100.00 % same".to_owned(),
                Some(q) => format!("{:.1} dB · {:.2} % same", q.psnr_db, 100.0 * q.share_identical()),
                None => "waiting…".to_owned(),
            };
            row("PSNR vs full", q);
        }
    });
    frame_time_plot(ui, r.history);
}

/// Recent frame times as lines, one per series, with the scale in the label and a legend.
fn frame_time_plot(ui: &mut egui::Ui, history: &FrameTimes) {
    let max = history.iter().flatten().fold(1.0_f32, |a, &b| a.max(b));
    ui.label(RichText::new(format!("ms per frame, last {} frames (top {max:.0} ms)", FrameTimes::LEN)).small());
    let width = ui.available_width().max(100.0);
    let (response, painter) = ui.allocate_painter(egui::vec2(width, 48.0), egui::Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 2.0, Color32::from_black_alpha(90));
    let step = rect.width() / (FrameTimes::LEN - 1) as f32;
    // Newest at the right edge.
    let skip = FrameTimes::LEN - history.iter().count();
    for (series, &(_, color)) in SERIES.iter().enumerate() {
        let points: Vec<egui::Pos2> = history
            .iter()
            .enumerate()
            .map(|(k, ms)| {
                let y = rect.bottom() - rect.height() * (ms[series] / max).clamp(0.0, 1.0);
                egui::pos2(rect.left() + (skip + k) as f32 * step, y)
            })
            .collect();
        if let [only] = points[..] {
            // A still scene renders once: show that frame as dots.
            painter.circle_filled(only, 2.0, color);
        } else {
            painter.add(egui::Shape::line(points, egui::Stroke::new(1.0, color)));
        }
    }
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 4.0;
        for (name, color) in SERIES {
            let (swatch, _) = ui.allocate_exact_size(egui::vec2(10.0, 3.0), egui::Sense::hover());
            ui.painter().rect_filled(swatch, 0.0, color);
            ui.label(RichText::new(name).small());
        }
    });
}

fn legend(ui: &mut egui::Ui) {
    ui.label(RichText::new("mask, blended 50 % over the right eye").small());
    for (class, name) in MASK_LEGEND {
        ui.horizontal(|ui| {
            let [r, g, b] = tracer::unpack_rgb(mask_color(class));
            let (rect, _) = ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
            ui.painter().rect_filled(rect, 2.0, Color32::from_rgb(r, g, b));
            ui.label(name);
        });
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

    /// What the panel shows before the first frame arrives.
    fn idle_readout(history: &FrameTimes) -> Readout<'_> {
        Readout { ui_fps: 60.0, render_fps: 30.0, frame: None, time: 0.0, animated: true, history, saved: None }
    }

    #[test]
    fn reset_restores_the_scene_camera_within_the_slider_ranges() {
        let scene = scene();
        let mut s = Settings::from_scene(&scene);
        assert_eq!((s.ipd, s.distance, s.depth, s.mode), (0.5, 9.0, MAX_REFLECTION_DEPTH, Mode::Exact));
        s.ipd = 1.7;
        s.distance = 40.0;
        s.show_mask = true;
        s.reset_camera(&scene);
        assert_eq!((s.ipd, s.distance), (0.5, 9.0));
        assert!(s.show_mask, "reset touches only the camera values");
        assert_eq!(s.render_size(800, 600), (800, 600));
        s.render_scale = 0.5;
        assert_eq!(s.render_size(801, 600), (401, 300));
        s.render_scale = 0.0;
        assert_eq!(s.render_size(3, 1), (1, 1));
    }

    #[test]
    fn frame_times_keep_the_last_ones_in_order() {
        let mut t = FrameTimes::default();
        for k in 0..(FrameTimes::LEN + 3) {
            t.push([k as f32; SERIES_LEN]);
        }
        let v: Vec<f32> = t.iter().map(|s| s[2]).collect();
        assert_eq!(v.len(), FrameTimes::LEN);
        assert_eq!(v[0], 3.0);
        assert_eq!(*v.last().unwrap(), (FrameTimes::LEN + 2) as f32);
    }

    #[test]
    fn panel_wraps_its_contents_and_scrolls_only_when_short() {
        let ctx = egui::Context::default();
        setup_style(&ctx);
        let mut s = Settings::from_scene(&scene());
        s.live_psnr = true;
        let history = FrameTimes::default();
        let readout = idle_readout(&history);
        let mut folder = "./screenshots".to_owned();
        let mut panel_rect = |s: &mut Settings, height: f32| {
            for _ in 0..3 {
                let input = egui::RawInput {
                    screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1600.0, height))),
                    ..Default::default()
                };
                let _ = ctx.run_ui(input, |ui| {
                    let _ = panel(ui.ctx(), s, &readout, &mut folder);
                });
            }
            ctx.globally_used_rect()
        };
        // The window's default height is 600; with the mask legend and the sections open the
        // panel may scroll there, so it is measured in a taller one.
        let without = panel_rect(&mut s, 700.0);
        s.show_mask = true;
        let with = panel_rect(&mut s, 700.0);
        assert!(with.width() < 420.0, "the panel covers too much of the left eye: {with:?}");
        assert!(with.height() > without.height() + 60.0, "the legend should extend the panel: {with:?} vs {without:?}");
        assert!(with.height() < 660.0, "the panel should wrap its contents: {with:?}");
        let short = panel_rect(&mut s, 250.0);
        assert!(short.height() < 280.0, "a short window should scroll the panel: {short:?}");
        let again = panel_rect(&mut s, 700.0);
        assert_eq!(again.height(), with.height(), "the panel should grow back");
        assert_eq!(mega(1_234_567), "1.23 M");
    }

    /// The panel driven as a user would, through its accessibility tree (egui_kittest):
    /// widgets found by their labels, a slider moved with the keyboard, buttons clicked.
    #[test]
    fn panel_widgets_change_the_render_settings() {
        use egui::accesskit::Role;
        use egui_kittest::kittest::Queryable as _;
        use egui_kittest::Harness;

        struct State {
            settings: Settings,
            folder: String,
            actions: Actions,
        }
        let scene = scene();
        let history = FrameTimes::default();
        let readout = idle_readout(&history);
        let state = State {
            settings: Settings::from_scene(&scene),
            folder: "./screenshots".into(),
            actions: Actions::default(),
        };
        let mut harness = Harness::builder().with_size(egui::vec2(1600.0, 900.0)).build_ui_state(
            |ui, st: &mut State| {
                setup_style(ui.ctx());
                let actions = panel(ui.ctx(), &mut st.settings, &readout, &mut st.folder);
                st.actions.reset |= actions.reset;
                st.actions.save |= actions.save;
            },
            state,
        );
        harness.run();

        // The IPD slider: focused and nudged up with the arrow key.
        let ipd = harness.state().settings.ipd;
        harness.get_by_role_and_label(Role::Slider, "IPD").focus();
        harness.run();
        harness.key_press(egui::Key::ArrowRight);
        harness.run();
        let after = harness.state().settings.ipd;
        assert!(after > ipd, "IPD should grow: {ipd} -> {after}");
        assert!(after <= 2.0, "within the slider's range: {after}");

        // The mode buttons and the mask checkbox.
        harness.get_by_label("copy").click();
        harness.run();
        assert_eq!(harness.state().settings.mode, Mode::Copy);
        assert!(!harness.state().settings.show_mask);
        harness.get_by_label("show mask (M)").click();
        harness.run();
        assert!(harness.state().settings.show_mask);

        // Edge retracing applies to copy: its checkbox is enabled there.
        harness.get_by_label("retrace edges").click();
        harness.run();
        assert!(harness.state().settings.options().retrace_edges);

        // The buttons report their clicks to the app.
        harness.get_by_label("save pair (S)").click();
        harness.run();
        assert!(harness.state().actions.save);
        assert!(!harness.state().actions.reset);
    }

    #[test]
    fn the_light_starts_where_the_scene_puts_it_even_beyond_the_sliders() {
        let src = "[[lights]]\nposition = [40.0, 2.0, -3.0]\n[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n";
        let s = Settings::from_scene(&Scene::from_toml(src, "l.toml").unwrap());
        assert_eq!(s.light, Some(Vec3::new(40.0, 2.0, -3.0)));
        assert_eq!(s.orbit_speed, 1.0);
    }

    #[test]
    fn the_head_moves_along_its_own_axes_and_resets_to_the_scene() {
        let scene = scene();
        let mut s = Settings::from_scene(&scene);
        assert_eq!(s.light, None, "this scene has no lights");
        s.move_head(2.0, 0.0);
        assert!((s.position - Vec3::new(0.0, 0.0, 2.0)).length() < 1e-6, "forward is +z: {:?}", s.position);
        s.turn_head(90.0 / TURN_PER_PIXEL, 0.0);
        assert!((s.yaw_deg - 90.0).abs() < 1e-3);
        s.move_head(1.0, 0.0);
        assert!(
            (s.position - Vec3::new(1.0, 0.0, 2.0)).length() < 1e-5,
            "turned right, forward is +x: {:?}",
            s.position
        );
        s.move_head(0.0, 1.0);
        assert!((s.position - Vec3::new(1.0, 0.0, 1.0)).length() < 1e-5, "and right is -z: {:?}", s.position);
        s.turn_head(0.0, -1e6);
        assert_eq!(s.pitch_deg, MAX_PITCH, "dragging up looks up, clamped");
        let cam = s.camera(&scene.camera);
        assert_eq!((cam.position, cam.pitch_deg, cam.fov_deg), (s.position, MAX_PITCH, scene.camera.fov_deg));
        s.reset_camera(&scene);
        assert_eq!((s.position, s.yaw_deg, s.pitch_deg), (Vec3::ZERO, 0.0, 0.0));
    }
}
