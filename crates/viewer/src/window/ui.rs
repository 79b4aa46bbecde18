//! The egui panel: the render settings the user controls and the live statistics.
//!
//! The panel is a small, semi-transparent, collapsible window anchored at the top-left corner,
//! so the eyes stay visible behind it; it never grows past the window's bottom edge but
//! scrolls instead. It only draws: it edits a [`Settings`] value (the model, `settings.rs`)
//! and reports button presses; the app applies them and turns the settings into render
//! requests. Beside it are the key overlay ([`keys_overlay`], ? or F1) and the first-run hint
//! that Tab hides the UI ([`tab_hint`]); with the UI hidden the app draws neither the panel
//! nor the hint (the overlay only when asked for).

use std::path::PathBuf;

use egui::{Align2, Color32, RichText, Slider};
use glam::Vec3;
use stereo::{Layout, Mode};

use crate::window::frame_times::{FrameTimes, SERIES_LEN};
use crate::window::input::KEYS;
use crate::window::pose_meter::Medians;
use crate::window::settings::{
    Settings, MAX_GUARD_BAND, MAX_ORBIT_SPEED, MAX_REFLECTION_DEPTH, MAX_RENDER_SCALE, MIN_RENDER_SCALE,
};
use crate::window::timewarp::Warped;
use crate::window::worker::FrameInfo;
use figures::{legend, statistics, timewarp_legend};

/// The hint shown until Tab is first pressed.
pub const TAB_HINT: &str = "Tab hides the UI · ? lists the keys";

/// The colour of error text (a scene that did not load).
const ERROR_COLOR: Color32 = Color32::from_rgb(255, 120, 100);

/// The line colour of each series of the frame-time plot, in the order of
/// [`SERIES_NAMES`](crate::window::frame_times::SERIES_NAMES).
pub const SERIES_COLORS: [Color32; SERIES_LEN] = [
    Color32::from_rgb(200, 200, 200),
    Color32::from_rgb(255, 110, 90),
    Color32::from_rgb(90, 200, 255),
    Color32::from_rgb(120, 230, 110),
    Color32::from_rgb(240, 200, 60),
    Color32::from_rgb(210, 120, 255),
];

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
    /// The scene file and its neighbours.
    pub scene: SceneReadout<'a>,
    /// Whether the window is fullscreen.
    pub fullscreen: bool,
    /// What a moving head sees: new poses a second, input latency, frame age.
    pub motion: Motion,
}

/// The panel's timewarp figures.
#[derive(Clone, Copy, Debug, Default)]
pub struct Motion {
    /// Presented frames a second that showed a new head pose.
    pub pose_fps: f64,
    /// Median input latency and traced-frame age at present.
    pub medians: Medians,
    /// The last warp, when the timewarp is on.
    pub warp: Option<Warped>,
}

/// The scene file shown, why the last load failed, and the scenes beside it.
#[derive(Clone, Copy, Debug, Default)]
pub struct SceneReadout<'a> {
    /// The file's name.
    pub name: &'a str,
    /// Why the last load failed (the last good scene is still shown), if it did.
    pub error: Option<&'a str>,
    /// The `.toml` files in the scene's folder.
    pub files: &'a [PathBuf],
    /// Why the folder could not be listed, if it could not.
    pub folder_error: Option<&'a str>,
}

/// Buttons pressed this frame.
#[expect(
    clippy::struct_excessive_bools,
    reason = "each flag is one button's click this frame, independent of the others"
)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Actions {
    /// "reset camera" was clicked.
    pub reset: bool,
    /// "save pair (F12)" was clicked.
    pub save: bool,
    /// "reset light" was clicked.
    pub reset_light: bool,
    /// A scene of the list was picked: its index in [`SceneReadout::files`].
    pub open_scene: Option<usize>,
    /// The fullscreen checkbox was clicked.
    pub toggle_fullscreen: bool,
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
        .anchor(Align2::LEFT_TOP, [0.0, 0.0])
        .collapsible(true)
        .resizable(false)
        .default_width(250.0)
        // A long message (a scene's load error) wraps rather than widening the panel.
        .max_width(300.0)
        .frame(frame)
        // Kept inside the window, a margin from its edges (the anchor is that area's corner).
        // The scroll area may use the whole height (egui clamps this minimum to the area);
        // the panel itself still wraps its contents, and scrolls only when the window is too
        // short for them.
        .constrain_to(panel_bounds(ctx, frame))
        .min_height(ctx.content_rect().height())
        .show(ctx, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                scene(ui, &readout.scene, &mut actions);
                controls(ui, settings, readout, &mut actions);
                egui::CollapsingHeader::new("colour and hiding")
                    .show(ui, |ui| crate::window::look::look_ui(ui, &mut settings.atoms));
                screenshots(ui, readout, folder);
                egui::CollapsingHeader::new("light").show(ui, |ui| light(ui, settings, readout, &mut actions));
                ui.separator();
                statistics(ui, settings, readout);
                if settings.show_mask {
                    ui.separator();
                    // The warp's mask while the shown frame is warped; the stereo pair's
                    // (the seed paper's Fig. 2) while it is shown as traced.
                    if settings.timewarp && !readout.motion.warp.is_some_and(|w| w.fresh) {
                        timewarp_legend(ui);
                    } else {
                        legend(ui);
                    }
                }
            });
        });
    actions
}

/// The area the panel must stay in: the window less the anchor's margin on every side, and
/// less the frame's margins (egui caps a window's content at the area's height, not counting
/// the frame), so the whole panel, frame included, fits the window.
fn panel_bounds(ctx: &egui::Context, frame: egui::Frame) -> egui::Rect {
    let margin = frame.total_margin();
    let mut r = ctx.content_rect().shrink(PANEL_MARGIN);
    r.max.y -= margin.sum().y;
    r
}

/// The panel's distance from the window's edges, points.
const PANEL_MARGIN: f32 = 8.0;

/// The scene file: a list of the scenes beside it to switch to, and why the last save (or
/// drop) did not load.
fn scene(ui: &mut egui::Ui, r: &SceneReadout<'_>, actions: &mut Actions) {
    ui.horizontal(|ui| {
        ui.label("scene");
        egui::ComboBox::from_id_salt("scene file").selected_text(r.name).show_ui(ui, |ui| {
            for (k, path) in r.files.iter().enumerate() {
                let name = path.file_name().map_or_else(|| path.to_string_lossy(), |n| n.to_string_lossy());
                if ui.selectable_label(name == r.name, name).clicked() {
                    actions.open_scene = Some(k);
                }
            }
            if r.files.is_empty() {
                ui.label(RichText::new(r.folder_error.unwrap_or("no scene files beside this one")).small().weak());
            }
        });
    })
    .response
    .on_hover_text(
        "the scene files (.toml and structures) in the scene's folder; the file is reloaded when saved, and a dropped scene file opens",
    );
    if let Some(error) = r.error {
        ui.label(RichText::new("not loaded (still showing the last good scene):").small().color(ERROR_COLOR));
        ui.label(RichText::new(error).small().monospace().color(ERROR_COLOR));
    }
}

fn controls(ui: &mut egui::Ui, s: &mut Settings, readout: &Readout<'_>, actions: &mut Actions) {
    let max_ipd = s.max_ipd();
    ui.add(Slider::new(&mut s.ipd, 0.0..=max_ipd).text("IPD")).on_hover_text("interpupillary distance e, scene units");
    let (near, far) = s.distance_range();
    ui.add(Slider::new(&mut s.distance, near..=far).logarithmic(true).text("depth d"))
        .on_hover_text("distance from the eyes to the zero-parallax window");
    ui.add(Slider::new(&mut s.depth, 0..=MAX_REFLECTION_DEPTH).text("reflections"))
        .on_hover_text("reflection depth (bounces)");
    ui.add(
        Slider::new(&mut s.render_scale, MIN_RENDER_SCALE..=MAX_RENDER_SCALE)
            .text("render scale")
            .custom_formatter(|v, _| format!("{:.0} %", v * 100.0))
            .custom_parser(|t| t.trim().trim_end_matches('%').trim().parse::<f64>().ok().map(|v| v / 100.0)),
    )
    .on_hover_text(
        "trace each eye at this multiple of its window size: below 100 % scaled up; above it \
         supersampled (anti-aliased) and box-filtered down, 200 % = 2 × 2 samples per pixel",
    );
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
        ui.checkbox(&mut s.reuse, "reuse").on_hover_text(
            "while only the orbit moves, retrace only the pixels that can change (the image is the same)",
        );
    });
    ui.horizontal(|ui| {
        ui.checkbox(&mut s.timewarp, "timewarp (T)").on_hover_text(
            "show every frame warped to the head pose of that moment, by its depth, while the \
             tracer catches up",
        );
        ui.add_enabled(
            s.timewarp,
            Slider::new(&mut s.guard_band, 0.0..=MAX_GUARD_BAND)
                .text("guard")
                .custom_formatter(|v, _| format!("{:.0} %", v * 100.0))
                .custom_parser(|t| t.trim().trim_end_matches('%').trim().parse::<f64>().ok().map(|v| v / 100.0)),
        )
        .on_hover_text("trace this share of each eye beyond each side, for the timewarp to turn into");
    });
    ui.horizontal(|ui| {
        actions.reset = ui.button("reset camera (R)").clicked();
        actions.save = ui.button("save pair (F12)").clicked();
    });
    let mut fullscreen = readout.fullscreen;
    actions.toggle_fullscreen = ui.checkbox(&mut fullscreen, "fullscreen (F11)").clicked();
    ui.label(
        RichText::new(format!(
            "head at {:.1}, {:.1}, {:.1} · yaw {:.0}° · pitch {:.0}°",
            s.position.x, s.position.y, s.position.z, s.yaw_deg, s.pitch_deg
        ))
        .small(),
    );
    egui::CollapsingHeader::new("keys").show(ui, |ui| {
        // One wrapped line a key: the panel stays narrow (the overlay has the table).
        for (key, action) in KEYS {
            ui.label(RichText::new(format!("{key}: {action}")).small());
        }
    });
}

/// Every key and what it does, in two columns.
fn key_grid(ui: &mut egui::Ui) {
    egui::Grid::new(ui.next_auto_id()).num_columns(2).spacing([12.0, 2.0]).show(ui, |ui| {
        for (key, action) in KEYS {
            ui.label(RichText::new(key).strong());
            ui.label(action);
            ui.end_row();
        }
    });
}

/// The key overlay (? or F1): every key, in a window at the centre. Closing it with its
/// button clears `open`.
pub fn keys_overlay(ctx: &egui::Context, open: &mut bool) {
    egui::Window::new("keys")
        .open(open)
        .anchor(Align2::CENTER_CENTER, [0.0, 0.0])
        .collapsible(false)
        .resizable(false)
        .frame(egui::Frame::window(&ctx.global_style()).fill(Color32::from_rgba_unmultiplied(24, 24, 28, 235)))
        .show(ctx, |ui| {
            key_grid(ui);
            ui.label(RichText::new("? or F1 or Esc closes this").small().weak());
        });
}

/// The hint that Tab hides the UI, at the bottom centre of the window.
pub fn tab_hint(ctx: &egui::Context) {
    egui::Area::new(egui::Id::new("tab hint")).anchor(Align2::CENTER_BOTTOM, [0.0, -12.0]).interactable(false).show(
        ctx,
        |ui| {
            egui::Frame::popup(&ctx.global_style()).show(ui, |ui| ui.label(TAB_HINT));
        },
    );
}

/// A progress note in the middle of the window (a scene being read or built).
pub fn progress(ctx: &egui::Context, note: &str) {
    egui::Area::new(egui::Id::new("progress")).anchor(Align2::CENTER_CENTER, [0.0, 0.0]).interactable(false).show(
        ctx,
        |ui| {
            // No spinner: it would repaint at the tick's rate, taking the cores from the build;
            // the note's seconds move at the idle redraws.
            egui::Frame::popup(&ctx.global_style()).show(ui, |ui| ui.label(RichText::new(note).size(16.0)));
        },
    );
}

fn screenshots(ui: &mut egui::Ui, r: &Readout<'_>, folder: &mut String) {
    ui.horizontal(|ui| {
        ui.label("folder");
        ui.add(egui::TextEdit::singleline(folder).desired_width(150.0))
            .on_hover_text("screenshots (F12 or P) go here; created if missing");
    });
    if let Some(saved) = r.saved {
        ui.label(RichText::new(saved).small().color(Color32::from_rgb(150, 230, 150)));
    }
}

fn light(ui: &mut egui::Ui, s: &mut Settings, r: &Readout<'_>, actions: &mut Actions) {
    let range = -s.light_range()..=s.light_range();
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

mod figures;
#[cfg(test)]
mod tests;
