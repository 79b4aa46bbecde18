//! The timewarp's figure: the quality of each displayed frame against the age of the traced
//! frame it shows, a line per warp method (`timewarp --plot`).
//!
//! Every displayed frame is a faint dot at (age, PSNR against a trace at its own pose); the
//! line joins each age's median. A frame identical to the trace (infinite PSNR: a frame shown
//! at the pose it was traced for) sits on a dotted ceiling above every finite value, as in
//! the sweep's figure, and each method's median there is a ring of its own size, so that
//! coinciding methods stay told apart. Drawn with `plot.rs`'s file, font, mesh and legend.

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::cli::plot::{ceiling_above, legend, mesh, panel, Drawing, Drawn, Entry, FAMILY};

/// The figure's size in pixels (SVG: user units).
pub const SIZE: (u32, u32) = (900, 520);

/// One warp method's frames.
pub struct Series {
    /// The method's name (`none`, `rotation`, `depth`).
    pub name: &'static str,
    /// Every displayed frame: (age of the frame shown in ms, PSNR in dB; +∞ when identical).
    pub frames: Vec<(f64, f64)>,
    /// The median PSNR at each age, ages ascending.
    pub medians: Vec<(f64, f64)>,
}

/// What the figure shows.
pub struct AgeFigure<'a> {
    /// The title.
    pub title: String,
    /// One display frame, ms (the ages are whole frames).
    pub frame_ms: f64,
    /// A series per method.
    pub series: &'a [Series],
}

/// The method's colour: the stale frame red, the rotation-only warp blue, the depth warp
/// green.
fn color(name: &str) -> RGBColor {
    match name {
        "none" => RGBColor(214, 39, 40),
        "rotation" => RGBColor(31, 119, 180),
        "depth" => RGBColor(44, 160, 44),
        _ => RGBColor(148, 103, 189),
    }
}

impl Drawing for AgeFigure<'_> {
    fn size(&self) -> (u32, u32) {
        SIZE
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let root = root.titled(&self.title, (FAMILY, 20))?;
        let (chart_area, legend_area) = panel(&root);
        let psnrs = || self.series.iter().flat_map(|s| s.frames.iter().map(|&(_, p)| p));
        let ceiling = ceiling_above(psnrs());
        let low = psnrs().filter(|p| p.is_finite()).fold(ceiling - 30.0, f64::min);
        let y0 = (10.0 * (low / 10.0).floor() - 5.0).max(0.0);
        let ages = || self.series.iter().flat_map(|s| s.frames.iter().map(|&(a, _)| a));
        let top_age = ages().fold(0.0f64, f64::max);
        let step = ages().filter(|&a| a > 0.0).fold(f64::INFINITY, f64::min);
        let pad = if step.is_finite() { 0.5 * step } else { 1.0 };
        let mut chart = ChartBuilder::on(&chart_area)
            .caption("quality of the displayed frame", (FAMILY, 18))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(-pad..top_age + pad, y0..ceiling + 5.0)?;
        let y_label = format!("PSNR vs a trace at its pose, dB (∞ drawn at {ceiling:.0})");
        let x_label = format!("age of the traced frame shown, ms (a display frame: {:.1} ms)", self.frame_ms);
        mesh(&mut chart, &x_label, &y_label, &|y| {
            if *y > ceiling - 0.01 && *y < ceiling + 0.01 {
                "∞".into()
            } else {
                format!("{y:.0}")
            }
        })?;
        chart.draw_series(DashedLineSeries::new(
            [(-pad, ceiling), (top_age + pad, ceiling)],
            2,
            4,
            BLACK.stroke_width(1),
        ))?;
        let mut entries = Vec::new();
        let n = self.series.len();
        for (k, s) in self.series.iter().enumerate() {
            let c = color(s.name);
            // Every frame, faint; the medians over them, a line.
            chart.draw_series(
                s.frames.iter().map(|&(a, p)| Circle::new((a, p.min(ceiling)), 2, c.mix(0.25).filled())),
            )?;
            let line: Vec<(f64, f64)> = s.medians.iter().map(|&(a, p)| (a, p.min(ceiling))).collect();
            chart.draw_series(LineSeries::new(line.iter().copied(), c.stroke_width(2)))?;
            let ring = 3 + 2 * (n - 1 - k).min(4) as i32;
            chart.draw_series(s.medians.iter().map(|&(a, p)| {
                if p.is_finite() {
                    EmptyElement::at((a, p)) + Circle::new((0, 0), 3, c.filled())
                } else {
                    EmptyElement::at((a, ceiling)) + Circle::new((0, 0), ring, c.stroke_width(2))
                }
            }))?;
            entries.push(Entry::line(s.name, c.stroke_width(3)));
        }
        entries.push(Entry { ring: true, ..Entry::line("∞: identical", BLACK.stroke_width(1)) });
        entries.push(Entry::line(format!("   (drawn at {ceiling:.0} dB)"), WHITE.stroke_width(1)));
        entries.push(Entry::line("line: median", BLACK.stroke_width(2)));
        entries.push(Entry::line("dots: frames", WHITE.stroke_width(1)));
        legend(&legend_area, &entries)
    }
}
