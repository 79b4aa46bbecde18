//! The panel's figures: the live statistics, the frame-time plot and the masks' legends.

use egui::{Color32, RichText};
use stereo::{mask_color, KEPT_COLOR, KEPT_LEGEND, MASK_LEGEND};

use super::{mega, Readout, SERIES_COLORS};
use crate::window::frame_times::{FrameTimes, SERIES_NAMES};
use crate::window::settings::Settings;
use crate::window::timewarp::TIMEWARP_LEGEND;

pub(super) fn statistics(ui: &mut egui::Ui, s: &Settings, r: &Readout<'_>) {
    egui::Grid::new("stats").num_columns(2).spacing([12.0, 2.0]).show(ui, |ui| {
        let mut row = |name: &str, value: String| {
            ui.label(name);
            ui.label(RichText::new(value).monospace());
            ui.end_row();
        };
        row("fps", format!("{:.1} UI · {:.1} render", r.ui_fps, r.render_fps));
        let ms = |v: Option<f64>| v.map_or_else(|| "–".to_owned(), |v| format!("{v:.0} ms"));
        let m = &r.motion;
        row("new poses", format!("{:.1} /s · latency {}", m.pose_fps, ms(m.medians.latency_ms)));
        if let Some(w) = m.warp.filter(|_| s.timewarp) {
            let state = if w.fresh {
                "fresh: shown as traced".to_owned()
            } else {
                format!("warped · {:.1} ms · holes {:.2} %", w.ms, 100.0 * w.hole_share())
            };
            row("timewarp", state);
        }
        row("frame age", ms(m.medians.age_ms));
        let Some(f) = r.frame else {
            row("frame", "rendering…".to_owned());
            return;
        };
        let st = &f.stats;
        row("eye", format!("{} × {} · t {:.2} s", f.request.width, f.request.height, r.time));
        if f.request.progressive.is_some() {
            row("sampling", sampling(f.sampling, m.medians.age_ms));
        }
        if f.request.samples != (f.request.width, f.request.height) {
            let (w, h) = f.samples();
            let note = if f.samples() == f.request.samples { "" } else { " (no memory for more)" };
            row("samples", format!("{w} × {h}{note}"));
        }
        row("ms per eye", format!("L {:.1} · R {:.1}", st.left.ms, st.right.ms));
        row("rays per eye", format!("L {} · R {}", mega(st.left.rays.total()), mega(st.right.rays.total())));
        row("reprojected", format!("{:.1} %", 100.0 * st.pixels.reprojected_share()));
        let reuse = &st.reuse;
        row(
            "retraced",
            if reuse.reused {
                format!("{:.2} % (rest kept)", 100.0 * reuse.retraced_share())
            } else {
                "100 % (fresh frame)".to_owned()
            },
        );
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
/// The progressive policy's readout: "1/16 · 31 ms old" for a coarse frame (one sample per
/// 4 × 4 pixels), "4×4 · converged" at rest, "5 samples a pixel" while refining (and "16
/// samples a pixel" while orbiting spheres' samples are traced again).
pub(crate) fn sampling(s: crate::window::worker::Sampling, age_ms: Option<f64>) -> String {
    let old = age_ms.map_or_else(String::new, |a| format!(" · {a:.0} ms old"));
    if s.density > 1 {
        format!("1/{}{old}", s.density * s.density)
    } else if s.converged {
        let side = f64::from(s.spp).sqrt().round();
        format!("{side}×{side} · converged")
    } else if s.spp > 1 {
        format!("{} samples a pixel", s.spp)
    } else {
        format!("every pixel{old}")
    }
}

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
    for (series, &color) in SERIES_COLORS.iter().enumerate() {
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
        for (name, color) in SERIES_NAMES.into_iter().zip(SERIES_COLORS) {
            let (swatch, _) = ui.allocate_exact_size(egui::vec2(10.0, 3.0), egui::Sense::hover());
            ui.painter().rect_filled(swatch, 0.0, color);
            ui.label(RichText::new(name).small());
        }
    });
}

/// The timewarp mask's legend.
pub(super) fn timewarp_legend(ui: &mut egui::Ui) {
    ui.label(RichText::new("timewarp mask, blended 50 % over both eyes").small());
    for (colour, name) in TIMEWARP_LEGEND {
        swatch(ui, colour, name);
    }
}

/// A colour swatch and its name.
fn swatch(ui: &mut egui::Ui, colour: u32, name: &str) {
    ui.horizontal(|ui| {
        let [r, g, b] = tracer::unpack_rgb(colour);
        let (rect, _) = ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
        ui.painter().rect_filled(rect, 2.0, Color32::from_rgb(r, g, b));
        ui.label(name);
    });
}

pub(super) fn legend(ui: &mut egui::Ui) {
    ui.label(RichText::new("mask, blended 50 % over the right eye").small());
    let entries = MASK_LEGEND.map(|(class, name)| (mask_color(class), name));
    for (colour, name) in entries.into_iter().chain([(KEPT_COLOR, KEPT_LEGEND)]) {
        swatch(ui, colour, name);
    }
}
