//! `replay --plot`: two panels over the run's time, the resting part shaded and the head's
//! stop a dashed line. Above, each scored frame's PSNR against the converged picture at its
//! pose (a frame equal to it, an infinite PSNR, sits on a dotted ceiling, as in the other
//! figures); below, the age of the traced pair each presented frame shows, and the share the
//! warp guessed. Drawn with `cli/plot.rs`'s file, font, mesh and legend.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::record::Recording;
use super::report::Summary;
use super::score::Scored;
use crate::cli::plot::{ceiling_above, legend, mesh, panel, Drawing, Drawn, Entry, FAMILY};

/// The figure's size in pixels (SVG: user units).
pub const SIZE: (u32, u32) = (1000, 760);

/// Moving frames' colour.
const MOVING: RGBColor = RGBColor(31, 119, 180);
/// Resting frames' colour.
const RESTING: RGBColor = RGBColor(44, 160, 44);
/// The guessed share's colour.
const GUESSED: RGBColor = RGBColor(214, 39, 40);
/// The resting part's shade.
const SHADE: RGBColor = RGBColor(236, 244, 236);

/// What the figure shows.
pub struct Figure {
    title: String,
    /// When the head stopped, and the run's end, seconds.
    stop_s: f64,
    end_s: f64,
    /// Scored frames: (time, PSNR, moving).
    psnr: Vec<(f64, f64, bool)>,
    /// Presented frames: (time, age ms, guessed share, moving).
    age: Vec<(f64, f64, f64, bool)>,
    converge_s: Option<f64>,
}

impl Figure {
    pub fn new(summary: &Summary, recording: &Recording, scored: &Scored) -> Self {
        let frames = &recording.frames;
        let psnr = frames
            .iter()
            .zip(&scored.quality)
            .filter_map(|(f, q)| q.map(|q| (f.tick.t, q.psnr_db, f.tick.moving)))
            .collect();
        let age = frames.iter().map(|f| (f.tick.t, f.age_ms, f.guessed_share, f.tick.moving)).collect();
        let last = frames.last().map_or(0.0, |f| f.tick.t);
        Self {
            title: summary.title(),
            stop_s: recording.stop_s,
            end_s: last.max(recording.stop_s),
            psnr,
            age,
            converge_s: summary.converge_s,
        }
    }

    fn x_range(&self) -> std::ops::Range<f64> {
        -0.02 * self.end_s.max(0.1)..self.end_s.max(0.1) * 1.02
    }

    /// The resting part shaded, the stop marked, on a chart of `top` height.
    fn mark_rest<DB: DrawingBackend>(
        &self,
        chart: &mut ChartContext<
            DB,
            Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
        >,
        (bottom, top): (f64, f64),
    ) -> Drawn<DB> {
        let right = self.x_range().end;
        chart.draw_series(std::iter::once(Rectangle::new([(self.stop_s, bottom), (right, top)], SHADE.filled())))?;
        chart.draw_series(DashedLineSeries::new(
            [(self.stop_s, bottom), (self.stop_s, top)],
            6,
            4,
            BLACK.stroke_width(1),
        ))?;
        Ok(())
    }
}

impl Drawing for Figure {
    fn size(&self) -> (u32, u32) {
        SIZE
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let root = root.titled(&self.title, (FAMILY, 20))?;
        let (top, bottom) = root.split_vertically(SIZE.1 / 2 - 10);
        self.draw_psnr(&top)?;
        self.draw_age(&bottom)
    }
}

impl Figure {
    fn draw_psnr<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        let (chart_area, legend_area) = panel(area);
        let ceiling = ceiling_above(self.psnr.iter().map(|p| p.1));
        let low = self.psnr.iter().map(|p| p.1).filter(|p| p.is_finite()).fold(ceiling - 30.0, f64::min);
        let y0 = (10.0 * (low / 10.0).floor() - 5.0).max(0.0);
        let (y_lo, y_hi) = (y0, ceiling + 5.0);
        let mut chart = ChartBuilder::on(&chart_area)
            .caption("quality of the presented frame", (FAMILY, 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d(self.x_range(), y_lo..y_hi)?;
        let y_label = format!("PSNR vs the converged picture, dB (∞ at {ceiling:.0})");
        mesh(&mut chart, "time, s", &y_label, &|y| {
            if (*y - ceiling).abs() < 0.01 {
                "∞".into()
            } else {
                format!("{y:.0}")
            }
        })?;
        self.mark_rest(&mut chart, (y_lo, y_hi))?;
        let x = self.x_range();
        chart.draw_series(DashedLineSeries::new(
            [(x.start, ceiling), (x.end, ceiling)],
            2,
            4,
            BLACK.stroke_width(1),
        ))?;
        chart.draw_series(self.psnr.iter().map(|&(t, p, moving)| {
            let c = if moving { MOVING } else { RESTING };
            if p.is_finite() {
                EmptyElement::at((t, p)) + Circle::new((0, 0), 3, c.filled())
            } else {
                EmptyElement::at((t, ceiling)) + Circle::new((0, 0), 4, c.stroke_width(2))
            }
        }))?;
        let converged = self.converge_s.map_or("never converged".into(), |s| format!("converged {s:.2} s after"));
        let entries = [
            Entry::line("moving", MOVING.stroke_width(3)),
            Entry::line("resting (shaded)", RESTING.stroke_width(3)),
            Entry { ring: true, ..Entry::line("∞: converged", BLACK.stroke_width(1)) },
            Entry { dashed: true, ..Entry::line("the head stops", BLACK.stroke_width(1)) },
            Entry::line(format!("   {converged}"), WHITE.stroke_width(1)),
        ];
        legend(&legend_area, &entries)
    }

    fn draw_age<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        let (chart_area, legend_area) = panel(area);
        let top_age = self.age.iter().map(|a| a.1).fold(10.0f64, f64::max) * 1.08;
        let top_guess = self.age.iter().map(|a| 100.0 * a.2).fold(0.0f64, f64::max);
        // The guessed share in percent, drawn on the age axis scaled to fit beneath its top.
        let scale = if top_guess > 0.0 { 0.9 * top_age / top_guess } else { 1.0 };
        let mut chart = ChartBuilder::on(&chart_area)
            .caption("age of the traced pair shown, and the share guessed", (FAMILY, 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d(self.x_range(), 0.0..top_age)?;
        mesh(&mut chart, "time, s", "age, ms", &|y| format!("{y:.0}"))?;
        self.mark_rest(&mut chart, (0.0, top_age))?;
        chart.draw_series(
            self.age
                .iter()
                .map(|&(t, age, _, moving)| Circle::new((t, age), 2, if moving { MOVING } else { RESTING }.filled())),
        )?;
        chart.draw_series(LineSeries::new(
            self.age.iter().map(|&(t, _, g, _)| (t, 100.0 * g * scale)),
            GUESSED.mix(0.8).stroke_width(1),
        ))?;
        let entries = [
            Entry::line("age: moving", MOVING.stroke_width(3)),
            Entry::line("age: resting", RESTING.stroke_width(3)),
            Entry::line(format!("guessed, % (top {top_guess:.1} %)"), GUESSED.stroke_width(2)),
            Entry { dashed: true, ..Entry::line("the head stops", BLACK.stroke_width(1)) },
        ];
        legend(&legend_area, &entries)
    }
}
