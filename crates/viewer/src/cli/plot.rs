//! The sweep's figure, drawn with `plotters` (its bitmap backend for PNG, its SVG backend for
//! SVG): two panels against the swept parameter, a line per mode. What every figure shares
//! (the file, the font, the mesh, the legend, the ceiling infinite PSNRs are drawn on) is
//! here too, for `age_plot.rs`'s: a figure is a [`Drawing`].
//!
//! - **Cost**: the right eye over the left eye, in rays (solid) and in time (dashed). A full
//!   trace is 1 on both; the seed paper's §5.1 figure (13 % of all rays for the right eye) is
//!   a rays ratio of 0.15.
//! - **Quality**: the right eye's PSNR against a full trace. Identical images have an
//!   infinite PSNR; they are drawn on a ceiling above every finite value (a dotted line, named
//!   in the legend and on the axis), with a ring instead of a dot, each mode's ring of its own
//!   size so that coinciding modes stay told apart.
//!
//! Text is set in DejaVu Sans, embedded in the binary (`fonts/`, with its licence), so a plot
//! looks the same on every machine and needs no system font.

use std::path::Path;

use anyhow::{anyhow, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use viewer::{write_bytes, write_png};

use crate::setup::{check_output_dir, BadInput};

/// The embedded font (a subset of DejaVu Sans 2.37; see `fonts/README.md`).
static FONT: &[u8] = include_bytes!("../../fonts/DejaVuSans-subset.ttf");

/// The font family the figure's text asks for, which [`register_font`] provides.
pub(crate) const FAMILY: &str = "sans-serif";

/// The figure's size in pixels (SVG: user units).
pub const SIZE: (u32, u32) = (1000, 900);

/// One mode's measurements across the sweep, as (parameter, value) points in sweep order.
pub struct Line {
    /// The mode's name (`copy`, `reshade+edges`, …).
    pub name: &'static str,
    /// Right-eye rays over left-eye rays.
    pub rays: Vec<(f64, f64)>,
    /// Right-eye time over left-eye time.
    pub time: Vec<(f64, f64)>,
    /// PSNR of the right eye against a full trace, dB; +∞ when identical.
    pub psnr: Vec<(f64, f64)>,
}

/// What the figure shows.
pub struct Figure<'a> {
    /// The title above both panels.
    pub title: String,
    /// The parameter axis' label.
    pub x_label: &'a str,
    /// A line per mode.
    pub lines: &'a [Line],
}

/// A figure: its size and how it is drawn, on either backend.
pub trait Drawing {
    /// The figure's size in pixels (SVG: user units).
    fn size(&self) -> (u32, u32);

    /// Draws the figure on `root`, which is [`Drawing::size`] large.
    ///
    /// # Errors
    ///
    /// The backend's.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Drawn<DB>;
}

impl Drawing for Figure<'_> {
    fn size(&self) -> (u32, u32) {
        SIZE
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        draw(root, self)
    }
}

/// Writes the figure to `path`: SVG when its extension is `svg` (any case), else PNG.
/// The file appears whole or not at all.
pub fn write(path: &Path, fig: &impl Drawing) -> Result<()> {
    register_font()?;
    let failed = |e: String| anyhow!("cannot draw the plot {}: {e}", path.display());
    let size = fig.size();
    if is_svg(path) {
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
            fig.draw(&root).map_err(|e| failed(e.to_string()))?;
            root.present().map_err(|e| failed(e.to_string()))?;
        }
        write_bytes(path, svg.as_bytes())
    } else {
        let (w, h) = size;
        let mut rgb = vec![0u8; w as usize * h as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
            fig.draw(&root).map_err(|e| failed(e.to_string()))?;
            root.present().map_err(|e| failed(e.to_string()))?;
        }
        let pixels: Vec<u32> =
            rgb.chunks_exact(3).map(|c| (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2])).collect();
        write_png(path, w, h, &pixels)
    }
}

/// Whether `path` names an SVG file (else the plot is a PNG).
#[must_use]
pub fn is_svg(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("svg"))
}

/// Whether `path` names a PNG file.
#[must_use]
pub fn is_png(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

/// Makes the embedded font the figure's [`FAMILY`].
fn register_font() -> Result<()> {
    plotters::style::register_font(FAMILY, FontStyle::Normal, FONT)
        .map_err(|_| anyhow!("the embedded plot font does not parse"))
}

/// The height infinite PSNRs are drawn at: 10 dB above the highest finite value, rounded up
/// to a multiple of 10, and at least 60 dB.
#[must_use]
pub fn psnr_ceiling(lines: &[Line]) -> f64 {
    ceiling_above(finite_psnrs(lines))
}

/// [`psnr_ceiling`] of any PSNRs (the infinite ones are left out).
#[must_use]
pub fn ceiling_above(psnrs: impl Iterator<Item = f64>) -> f64 {
    let top = psnrs.filter(|p| p.is_finite()).fold(f64::NEG_INFINITY, f64::max);
    if top.is_finite() {
        (10.0 * (top / 10.0).ceil() + 10.0).max(60.0)
    } else {
        60.0
    }
}

fn finite_psnrs(lines: &[Line]) -> impl Iterator<Item = f64> + '_ {
    lines.iter().flat_map(|l| l.psnr.iter().map(|&(_, p)| p)).filter(|p| p.is_finite())
}

/// The mode's colour: the reference grey, the paper's copy in reds, reshade in blues, exact
/// green.
fn color(name: &str) -> RGBColor {
    match name {
        "full" => RGBColor(90, 90, 90),
        "copy" => RGBColor(214, 39, 40),
        "copy+edges" => RGBColor(255, 127, 14),
        "reshade" => RGBColor(31, 119, 180),
        "reshade+edges" => RGBColor(23, 190, 207),
        "exact" => RGBColor(44, 160, 44),
        _ => RGBColor(148, 103, 189),
    }
}

/// The parameter's range, widened when it is a single value.
fn x_range(lines: &[Line]) -> (f64, f64) {
    let xs = || lines.iter().flat_map(|l| l.rays.iter().map(|&(x, _)| x));
    let lo = xs().fold(f64::INFINITY, f64::min);
    let hi = xs().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        (0.0, 1.0)
    } else if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, hi + 0.5)
    }
}

/// What drawing on a backend returns.
pub type Drawn<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// Width of a panel's legend column, pixels.
const LEGEND_WIDTH: u32 = 210;

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, fig: &Figure) -> Drawn<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(&fig.title, (FAMILY, 22))?;
    let (top, bottom) = root.split_vertically(SIZE.1 / 2 - 20);
    draw_cost(&top, fig)?;
    draw_quality(&bottom, fig)
}

/// One legend entry: a label and how its sample line is drawn.
pub(crate) struct Entry {
    pub(crate) label: String,
    pub(crate) style: ShapeStyle,
    pub(crate) dashed: bool,
    /// A hollow circle on the sample (the mark of an infinite PSNR).
    pub(crate) ring: bool,
}

impl Entry {
    pub(crate) fn line(label: impl Into<String>, style: ShapeStyle) -> Self {
        Self { label: label.into(), style, dashed: false, ring: false }
    }
}

/// A panel: the chart's area and its legend's column to the right.
pub(crate) fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
) -> (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>) {
    let (w, _) = area.dim_in_pixel();
    area.split_horizontally(w.saturating_sub(LEGEND_WIDTH))
}

/// Draws `entries` down the legend column, from below the panel's caption.
pub(crate) fn legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[Entry]) -> Drawn<DB> {
    let font = (FAMILY, 15).into_font().color(&BLACK);
    for (k, e) in entries.iter().enumerate() {
        let y = 60 + 24 * k as i32;
        if e.dashed {
            for a in [0, 11, 22] {
                area.draw(&PathElement::new(vec![(8 + a, y), (15 + a, y)], e.style))?;
            }
        } else {
            area.draw(&PathElement::new(vec![(8, y), (37, y)], e.style))?;
        }
        if e.ring {
            area.draw(&Circle::new((22, y), 5, e.style))?;
        }
        area.draw(&Text::new(e.label.as_str(), (46, y - 8), font.clone()))?;
    }
    Ok(())
}

/// The mesh: labelled axes, a light grid.
pub(crate) fn mesh<DB: DrawingBackend>(
    chart: &mut ChartContext<DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    x_label: &str,
    y_label: &str,
    y_format: &dyn Fn(&f64) -> String,
) -> Drawn<DB> {
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style((FAMILY, 14))
        .axis_desc_style((FAMILY, 15))
        .bold_line_style(RGBColor(215, 215, 215))
        .light_line_style(RGBColor(242, 242, 242))
        .y_label_formatter(y_format)
        .draw()
}

fn draw_cost<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, fig: &Figure) -> Drawn<DB> {
    let (chart_area, legend_area) = panel(area);
    let (x0, x1) = x_range(fig.lines);
    let y_max =
        fig.lines.iter().flat_map(|l| l.rays.iter().chain(&l.time).map(|&(_, y)| y)).fold(1.0f64, f64::max) * 1.08;
    let mut chart = ChartBuilder::on(&chart_area)
        .caption("cost of the right eye", (FAMILY, 18))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(x0..x1, 0.0..y_max)?;
    mesh(&mut chart, fig.x_label, "right eye / left eye", &|y| format!("{y:.1}"))?;
    let mut entries = Vec::new();
    for line in fig.lines {
        let c = color(line.name);
        chart.draw_series(LineSeries::new(line.rays.iter().copied(), c.stroke_width(2)))?;
        chart.draw_series(line.rays.iter().map(|&p| Circle::new(p, 3, c.filled())))?;
        chart.draw_series(DashedLineSeries::new(line.time.iter().copied(), 7, 5, c.stroke_width(2)))?;
        entries.push(Entry::line(line.name, c.stroke_width(3)));
    }
    entries.push(Entry::line("rays (solid)", BLACK.stroke_width(2)));
    entries.push(Entry { dashed: true, ..Entry::line("time (dashed)", BLACK.stroke_width(2)) });
    legend(&legend_area, &entries)
}

fn draw_quality<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, fig: &Figure) -> Drawn<DB> {
    let (chart_area, legend_area) = panel(area);
    let (x0, x1) = x_range(fig.lines);
    let ceiling = psnr_ceiling(fig.lines);
    let low = finite_psnrs(fig.lines).fold(ceiling - 30.0, f64::min);
    let y0 = (10.0 * (low / 10.0).floor() - 5.0).max(0.0);
    let mut chart = ChartBuilder::on(&chart_area)
        .caption("quality of the right eye", (FAMILY, 18))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(x0..x1, y0..ceiling + 5.0)?;
    let y_label = format!("PSNR vs full, dB (∞ drawn at {ceiling:.0})");
    mesh(&mut chart, fig.x_label, &y_label, &|y| {
        if *y > ceiling - 0.01 && *y < ceiling + 0.01 {
            "∞".into()
        } else {
            format!("{y:.0}")
        }
    })?;
    chart.draw_series(DashedLineSeries::new([(x0, ceiling), (x1, ceiling)], 2, 4, BLACK.stroke_width(1)))?;
    let mut entries = Vec::new();
    // Modes identical to full all sit on the ceiling: each marks it with a ring of its own
    // size (the first mode's the largest), so coinciding lines stay told apart.
    let n = fig.lines.len();
    for (k, line) in fig.lines.iter().enumerate() {
        let c = color(line.name);
        let ring = 3 + 2 * (n - 1 - k).min(4) as i32;
        let pts: Vec<(f64, f64)> = line.psnr.iter().map(|&(x, p)| (x, p.min(ceiling))).collect();
        chart.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?;
        chart.draw_series(line.psnr.iter().map(|&(x, p)| {
            if p.is_finite() {
                EmptyElement::at((x, p)) + Circle::new((0, 0), 3, c.filled())
            } else {
                EmptyElement::at((x, ceiling)) + Circle::new((0, 0), ring, c.stroke_width(2))
            }
        }))?;
        entries.push(Entry::line(line.name, c.stroke_width(3)));
    }
    entries.push(Entry { ring: true, ..Entry::line("∞: identical to full", BLACK.stroke_width(1)) });
    entries.push(Entry::line(format!("   (drawn at {ceiling:.0} dB)"), WHITE.stroke_width(1)));
    legend(&legend_area, &entries)
}

/// Fails before any work if a table command's `--plot` is neither a PNG nor an SVG, or
/// the directory of `--csv` or `--plot` is missing.
pub fn check_outputs(csv: Option<&Path>, plot: Option<&Path>) -> Result<()> {
    if let Some(p) = plot.filter(|p| !is_svg(p) && !is_png(p)) {
        return Err(BadInput(format!("--plot {}: the plot is a PNG (.png) or an SVG (.svg)", p.display())).into());
    }
    [csv, plot].into_iter().flatten().try_for_each(check_output_dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(psnr: &[f64]) -> Line {
        Line {
            name: "copy",
            rays: Vec::new(),
            time: Vec::new(),
            psnr: psnr.iter().enumerate().map(|(k, &p)| (k as f64, p)).collect(),
        }
    }

    #[test]
    fn infinite_psnr_is_drawn_above_every_finite_value() {
        assert_eq!(psnr_ceiling(&[line(&[f64::INFINITY])]), 60.0, "nothing finite: 60 dB");
        assert_eq!(psnr_ceiling(&[line(&[31.2, f64::INFINITY, 44.9])]), 60.0, "44.9 → 50 + 10");
        assert_eq!(psnr_ceiling(&[line(&[71.0]), line(&[f64::INFINITY])]), 90.0, "71 → 80 + 10");
        assert_eq!(psnr_ceiling(&[line(&[70.0])]), 80.0, "a multiple of 10 stays, + 10");
    }

    #[test]
    fn the_format_by_extension() {
        assert!(is_svg(Path::new("a/b.svg")) && is_svg(Path::new("B.SVG")), "svg, any case");
        assert!(!is_svg(Path::new("b.png")) && !is_svg(Path::new("svg")), "not an SVG");
        assert!(
            is_png(Path::new("b.PNG")) && !is_png(Path::new("b.jpg")) && !is_png(Path::new("png")),
            "PNG by extension"
        );
    }
}
