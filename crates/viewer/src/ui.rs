//! The egui panel: the render settings the user controls and the live statistics.
//!
//! The panel is a small, semi-transparent, collapsible window anchored at the top-left corner,
//! so the eyes stay visible behind it. It only edits a [`Settings`] value and reports button
//! presses; the app turns the settings into render requests.

use egui::{Align2, Color32, RichText, Slider};
use stereo::{mask_color, Layout, Mode, MASK_LEGEND};
use tracer::Scene;

use crate::worker::FrameInfo;

/// Largest reflection depth the slider offers.
pub const MAX_REFLECTION_DEPTH: u32 = 8;

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
        };
        s.reset_camera(scene);
        s
    }

    /// Restores IPD, distance and reflection depth from the scene (clamped to the sliders'
    /// ranges).
    pub fn reset_camera(&mut self, scene: &Scene) {
        self.ipd = scene.camera.ipd.clamp(0.0, 2.0);
        self.distance = scene.camera.distance.clamp(1.0, 100.0);
        self.depth = scene.render.max_depth.min(MAX_REFLECTION_DEPTH);
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

/// The last frame times, for the small plot (a fixed ring, no allocation).
#[derive(Clone, Debug)]
pub struct FrameTimes {
    ms: [f32; Self::LEN],
    head: usize,
    len: usize,
}

impl Default for FrameTimes {
    fn default() -> Self {
        Self { ms: [0.0; Self::LEN], head: 0, len: 0 }
    }
}

impl FrameTimes {
    /// How many frames the plot shows.
    pub const LEN: usize = 120;

    /// Records one frame's time.
    pub fn push(&mut self, ms: f32) {
        self.ms[self.head] = ms;
        self.head = (self.head + 1) % Self::LEN;
        self.len = (self.len + 1).min(Self::LEN);
    }

    /// Oldest first.
    pub fn iter(&self) -> impl Iterator<Item = f32> + '_ {
        let start = (self.head + Self::LEN - self.len) % Self::LEN;
        (0..self.len).map(move |k| self.ms[(start + k) % Self::LEN])
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
}

/// Buttons pressed this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Actions {
    /// "reset camera" was clicked.
    pub reset: bool,
    /// "save pair (S)" was clicked.
    pub save: bool,
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

/// Draws the panel and applies the user's edits to `settings`.
pub fn panel(ctx: &egui::Context, settings: &mut Settings, readout: &Readout<'_>) -> Actions {
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
        for l in Layout::ALL {
            ui.selectable_value(&mut s.layout, l, l.name());
        }
    });
    ui.horizontal(|ui| {
        ui.checkbox(&mut s.show_mask, "show mask (M)");
        ui.add_enabled(readout.animated, egui::Checkbox::new(&mut s.paused, "pause (Space)"));
    });
    ui.checkbox(&mut s.live_psnr, "live PSNR").on_hover_text("compare the right eye with a full trace each frame");
    ui.horizontal(|ui| {
        actions.reset = ui.button("reset camera").clicked();
        actions.save = ui.button("save pair (S)").clicked();
    });
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

/// A sparkline of recent frame times with the scale in the label.
fn frame_time_plot(ui: &mut egui::Ui, history: &FrameTimes) {
    let max = history.iter().fold(1.0_f32, f32::max);
    ui.label(RichText::new(format!("frame time, last {} frames (max {max:.0} ms)", FrameTimes::LEN)).small());
    let width = ui.available_width().max(100.0);
    let (response, painter) = ui.allocate_painter(egui::vec2(width, 36.0), egui::Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 2.0, Color32::from_black_alpha(90));
    let step = rect.width() / (FrameTimes::LEN - 1) as f32;
    let points: Vec<egui::Pos2> = history
        .iter()
        .enumerate()
        .map(|(k, ms)| egui::pos2(rect.left() + k as f32 * step, rect.bottom() - rect.height() * ms / max))
        .collect();
    painter.add(egui::Shape::line(points, egui::Stroke::new(1.0, Color32::from_rgb(120, 200, 255))));
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
            t.push(k as f32);
        }
        let v: Vec<f32> = t.iter().collect();
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
        let readout =
            Readout { ui_fps: 60.0, render_fps: 10.0, frame: None, time: 0.0, animated: true, history: &history };
        let panel_rect = |s: &mut Settings, height: f32| {
            for _ in 0..3 {
                let input = egui::RawInput {
                    screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1600.0, height))),
                    ..Default::default()
                };
                let _ = ctx.run_ui(input, |ui| {
                    let _ = panel(ui.ctx(), s, &readout);
                });
            }
            ctx.globally_used_rect()
        };
        let without = panel_rect(&mut s, 600.0);
        s.show_mask = true;
        let with = panel_rect(&mut s, 600.0);
        assert!(with.width() < 420.0, "the panel covers too much of the left eye: {with:?}");
        assert!(with.height() > without.height() + 60.0, "the legend should extend the panel: {with:?} vs {without:?}");
        assert!(with.height() < 560.0, "the panel should wrap its contents: {with:?}");
        let short = panel_rect(&mut s, 250.0);
        assert!(short.height() < 280.0, "a short window should scroll the panel: {short:?}");
        let again = panel_rect(&mut s, 600.0);
        assert_eq!(again.height(), with.height(), "the panel should grow back");
        assert_eq!(mega(1_234_567), "1.23 M");
    }
}
