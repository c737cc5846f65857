//! Edge (feature `plot`): SVG figures of an identification and a static HTML report.
//!
//! Every figure is drawn with [plotters](https://docs.rs/plotters) into a self-contained SVG
//! string (no fonts, scripts or system libraries are needed: text is SVG `<text>` in the
//! viewer's sans-serif). Matrices are laid out as matrices: the panel in grid row `i`, column
//! `j` shows element `ij` (output `i` per input `j`), with the axis names of
//! [`FigureOptions::axes`].
//!
//! | function | shows |
//! | --- | --- |
//! | [`flexibility`] | `\|G_ij\|` (log scale, m/N) and `∠G_ij` (°) against frequency: the measured lines as points, the fitted model `G(ω) = (K − ω²M + iωC)⁻¹` as a line |
//! | [`impedance`] | `Re H_ij` with the fitted `K − ω²M` and `Im H_ij` with the fitted `ωC` (N/m), error bars `±σ` with `σ² = E|δH_ij|²/2` when the FRF carries a variance |
//! | [`coherence`] | the multiple coherence of every output and the condition number per line, the thresholds of [`ConditionLimits`](crate::ConditionLimits), the band shaded and the lines dropped marked |
//! | [`per_frequency`] | `K_ij(ω)` and `C_ij(ω)` line by line ([`PerFrequency`](crate::per_frequency::PerFrequency)) with error bars, and the constant fit |
//! | [`records`] | force (N) and displacement per record against time, the impact (peak of the dominant force) marked, double hits and clipping from [`check_record`](crate::quality::check_record) marked, the force gate shaded and an exponential window drawn |
//! | [`convergence`] | the IVF history: the block-wise relative changes of `M`, `C`, `K` per iteration (log scale) |
//!
//! [`report`] writes all of them as `.svg` files into a directory together with an `index.html`
//! that holds the coefficient table (with standard deviations and 95 % intervals), the
//! diagnostics, the warnings and every figure inline: one file to open or mail, no scripts, no
//! external assets.
//!
//! Every drawn series is an SVG group `<g class="series" data-series="…">` whose `<title>`
//! names it (a browser shows it on hover), so a figure can be checked or restyled by its
//! series.
//!
//! # Examples
//! ```
//! use bearing_ident::Identifier;
//! use bearing_ident::plot::{self, FigureOptions};
//! use bearing_ident::simulate::{ImpactTest, seed_rig};
//!
//! let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
//! let id = Identifier::new(8.0, 49.0).identify(&records)?;
//! let svg = plot::impedance(&id, &FigureOptions::default())?;
//! assert!(svg.starts_with("<svg"));
//! // Four series per element: Re H and Im H, measured and fitted.
//! assert_eq!(svg.matches("class=\"series\"").count(), 4 * 2 * 2);
//! # Ok::<(), bearing_ident::Error>(())
//! ```

mod figures;
mod html;

use std::path::{Path, PathBuf};

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::error::{Error, Result};
use crate::quality::ImpactChecks;
use crate::records::Record;

pub use figures::{coherence, convergence, flexibility, impedance, per_frequency, records};
pub use html::{ReportOptions, report};

/// `v` with `digits` significant digits: fixed-point for magnitudes from 10⁻³ to below 10⁶,
/// scientific otherwise (the format of every number in the report and the CLI's table).
///
/// # Examples
/// ```
/// use bearing_ident::plot::significant;
/// assert_eq!(significant(146_312.345, 7), "146312.3");
/// assert_eq!(significant(0.000_123_4, 3), "1.23e-4");
/// assert_eq!(significant(4.7, 3), "4.70");
/// ```
pub fn significant(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let exp = v.abs().log10().floor() as i32;
    if (-3..6).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.prec$e}", prec = digits.max(1) - 1)
    }
}

/// Size and labels of the figures.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureOptions {
    /// Width of one panel of a matrix grid, or of a single-panel figure's column, in pixels.
    /// Default 440; at least 200 is readable.
    pub panel_width: u32,
    /// Height of one panel (for the flexibility, impedance and per-frequency figures a panel
    /// holds two stacked plots), in pixels. Default 380.
    pub panel_height: u32,
    /// Names of the degrees of freedom, e.g. `["x", "y"]`; element `ij` is labelled
    /// `G xy`. Empty (the default), or of the wrong length, gives `x, y` for two degrees of
    /// freedom, `x, y, z` for three and `1, 2, …` otherwise.
    pub axes: Vec<String>,
}

impl Default for FigureOptions {
    fn default() -> Self {
        Self {
            panel_width: 440,
            panel_height: 380,
            axes: Vec::new(),
        }
    }
}

impl FigureOptions {
    /// The names of `n` degrees of freedom (see [`FigureOptions::axes`]).
    fn axis_names(&self, n: usize) -> Vec<String> {
        if self.axes.len() == n {
            return self.axes.clone();
        }
        match n {
            2 => vec!["x".into(), "y".into()],
            3 => vec!["x".into(), "y".into(), "z".into()],
            _ => (1..=n).map(|i| i.to_string()).collect(),
        }
    }

    fn panel(&self) -> (u32, u32) {
        (self.panel_width.max(200), self.panel_height.max(160))
    }
}

/// The records the report draws: the first two of each excitation direction (the records'
/// dominant force), then any record with an issue, at most `max` in all, in their order.
fn pick_records(records: &[Record], checks: Option<&ImpactChecks>, max: usize) -> Vec<usize> {
    let mut per_direction = std::collections::HashMap::new();
    let mut chosen: Vec<usize> = Vec::new();
    for (r, record) in records.iter().enumerate() {
        let count = per_direction
            .entry(record.dominant_force())
            .or_insert(0usize);
        if *count < 2 {
            *count += 1;
            chosen.push(r);
        }
    }
    if let Some(checks) = checks {
        for (r, record) in records.iter().enumerate() {
            if !chosen.contains(&r) && !crate::quality::check_record(record, checks).is_empty() {
                chosen.push(r);
            }
        }
    }
    chosen.sort_unstable();
    chosen.truncate(max);
    chosen
}

/// Writes `contents` to `path`, mapping failures to [`Error::Io`].
fn write_file(path: &Path, contents: &str) -> Result<PathBuf> {
    std::fs::write(path, contents).map_err(|e| Error::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    Ok(path.to_path_buf())
}

// ---- drawing helpers shared by the figures -------------------------------------------------

/// The drawing area of an SVG held in a string.
type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

/// A plotters error, boxed.
type Boxed = Box<dyn std::error::Error>;

/// What a drawing closure returns.
type Drawn = std::result::Result<(), Boxed>;

/// Font sizes in plotters' units (the SVG backend writes `size / 1.24` px).
mod font {
    pub const TICK: f64 = 17.0;
    pub const DESC: f64 = 18.0;
    pub const PANEL: f64 = 20.0;
    pub const TITLE: f64 = 25.0;
    pub const NOTE: f64 = 17.0;
}

/// Text markers around a series; [`group_series`] turns them into `<g>` elements.
const BEGIN: &str = "@@series-begin@@";
const END: &str = "@@series-end@@";

/// Draws `figure` of `size` pixels into an SVG string, white background, series grouped.
fn render(
    figure: &'static str,
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Drawn,
) -> Result<String> {
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, size).into_drawing_area();
        let plot_error = |e: &dyn std::fmt::Display| Error::Plot {
            figure,
            message: e.to_string(),
        };
        root.fill(&WHITE).map_err(|e| plot_error(&e))?;
        draw(&root).map_err(|e| plot_error(&e))?;
        root.present().map_err(|e| plot_error(&e))?;
    }
    Ok(group_series(&buf))
}

/// Draws the series `name` with `draw`, marked so that it becomes one SVG group.
fn series(area: &Area<'_>, name: &str, draw: impl FnOnce() -> Drawn) -> Drawn {
    let marker = ("sans-serif", 1.0).into_font().color(&BLACK);
    area.draw(&Text::new(format!("{BEGIN}{name}"), (0, 0), marker.clone()))?;
    draw()?;
    area.draw(&Text::new(END.to_string(), (0, 0), marker))?;
    Ok(())
}

/// Replaces the marker texts of [`series`] by `<g class="series" data-series="NAME">` with a
/// `<title>`, and `</g>`. The name is already XML-escaped by the SVG backend.
fn group_series(svg: &str) -> String {
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg;
    while let Some(at) = rest.find("<text") {
        let (before, from) = rest.split_at(at);
        out.push_str(before);
        let Some(end) = from.find("</text>") else {
            out.push_str(from);
            return out;
        };
        let element = &from[..end + "</text>".len()];
        let content = element
            .split_once('>')
            .map_or("", |(_, c)| c.trim_end_matches("</text>").trim());
        if let Some(name) = content.strip_prefix(BEGIN) {
            out.push_str(&format!(
                "<g class=\"series\" data-series=\"{name}\">\n<title>{name}</title>"
            ));
        } else if content == END {
            out.push_str("</g>");
        } else {
            out.push_str(element);
        }
        rest = &from[end + "</text>".len()..];
    }
    out.push_str(rest);
    out
}

/// Colours of channels and outputs, distinguishable in colour-blind palettes (Okabe–Ito).
const PALETTE: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
];

fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Measured points and the fitted model.
const MEASURED: RGBColor = RGBColor(0, 90, 160);
const MODEL: RGBColor = RGBColor(213, 60, 0);
const GREY: RGBColor = RGBColor(120, 120, 120);
const DARK: RGBColor = RGBColor(40, 40, 40);
const ALERT: RGBColor = RGBColor(200, 0, 0);

/// A title across the top of `area` and a legend under it; returns the area below.
fn header<'a>(
    area: &Area<'a>,
    title: &str,
    legend: &[(Key, &str)],
) -> std::result::Result<Area<'a>, Boxed> {
    let height = if legend.is_empty() { 44 } else { 78 };
    let (top, below) = area.split_vertically(height);
    let width = top.dim_in_pixel().0 as i32;
    top.draw(&Text::new(
        title.to_string(),
        (width / 2, 10),
        TextStyle::from(
            ("sans-serif", font::TITLE)
                .into_font()
                .style(FontStyle::Bold),
        )
        .pos(Pos::new(HPos::Center, VPos::Top)),
    ))?;
    draw_legend(&top, legend, 56)?;
    Ok(below)
}

/// How a legend entry is drawn.
#[derive(Clone, Copy)]
enum Key {
    Point(RGBColor),
    Line(RGBColor),
    Dashed(RGBColor),
    Band(RGBColor),
    Cross(RGBColor),
}

/// A legend centred on row `y` of `area`.
fn draw_legend(area: &Area<'_>, legend: &[(Key, &str)], y: i32) -> Drawn {
    if legend.is_empty() {
        return Ok(());
    }
    let style = TextStyle::from(("sans-serif", font::DESC).into_font());
    let gap = 28;
    let widths: Vec<i32> = legend
        .iter()
        .map(|(_, text)| {
            let w = area
                .estimate_text_size(text, &style)
                .map_or(8 * text.chars().count() as i32, |s| s.0 as i32);
            // The naive estimate counts bytes; non-ASCII letters are narrower than that.
            w.min(9 * text.chars().count() as i32) + 30
        })
        .collect();
    let total: i32 = widths.iter().sum::<i32>() + gap * (legend.len() as i32 - 1);
    let mut x = (area.dim_in_pixel().0 as i32 - total).max(0) / 2;
    for ((key, text), w) in legend.iter().zip(widths) {
        match *key {
            Key::Point(c) => area.draw(&Circle::new((x + 10, y), 4, c.filled()))?,
            Key::Line(c) => area.draw(&PathElement::new(
                vec![(x, y), (x + 22, y)],
                c.stroke_width(2),
            ))?,
            Key::Dashed(c) => {
                for k in 0..3 {
                    area.draw(&PathElement::new(
                        vec![(x + 8 * k, y), (x + 8 * k + 5, y)],
                        c.stroke_width(2),
                    ))?;
                }
            }
            Key::Band(c) => area.draw(&Rectangle::new(
                [(x, y - 7), (x + 22, y + 7)],
                c.mix(0.25).filled(),
            ))?,
            Key::Cross(c) => area.draw(&Cross::new((x + 10, y), 5, c.stroke_width(2)))?,
        }
        area.draw(&Text::new(
            text.to_string(),
            (x + 28, y),
            style.clone().pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        x += w + gap;
    }
    Ok(())
}

/// A message in the middle of an empty panel.
fn message(area: &Area<'_>, text: &str) -> Drawn {
    let (w, h) = area.dim_in_pixel();
    area.draw(&Text::new(
        text.to_string(),
        (w as i32 / 2, h as i32 / 2),
        ("sans-serif", font::NOTE)
            .into_font()
            .color(&GREY)
            .pos(Pos::new(HPos::Center, VPos::Center)),
    ))?;
    Ok(())
}

/// A scale for values up to `max` in `unit`: (divisor, unit with an SI prefix).
fn si_unit(max: f64, unit: &str) -> (f64, String) {
    let prefixes: [(f64, &str); 7] = [
        (1e9, "G"),
        (1e6, "M"),
        (1e3, "k"),
        (1.0, ""),
        (1e-3, "m"),
        (1e-6, "µ"),
        (1e-9, "n"),
    ];
    let max = max.abs();
    if !(max.is_finite() && max > 0.0) {
        return (1.0, unit.to_string());
    }
    let (scale, prefix) = prefixes
        .iter()
        .find(|(s, _)| max >= *s)
        .copied()
        .unwrap_or((1e-9, "n"));
    (scale, format!("{prefix}{unit}"))
}

/// A finite, non-empty range around `values` with `pad` of its span added on both sides.
fn span(values: impl IntoIterator<Item = f64>, pad: f64) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        return -1.0..1.0;
    }
    let width = hi - lo;
    let width = if width > 0.0 {
        width
    } else {
        lo.abs().max(1e-30)
    };
    (lo - pad * width)..(hi + pad * width)
}

/// A positive range around the positive finite `values` for a log axis, padded by a factor.
fn log_span(values: impl IntoIterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        return 1e-12..1e-11;
    }
    let (lo, hi) = if hi / lo < 10.0 {
        let mid = (lo * hi).sqrt();
        (mid / 3.3, mid * 3.3)
    } else {
        (lo / 1.6, hi * 1.6)
    };
    lo..hi
}

/// Tick label of a log axis: `1e-6`, `3e-7`, or plain for ordinary magnitudes.
fn log_tick(v: &f64) -> String {
    let e = v.abs().log10();
    if (-2.0..4.0).contains(&e) {
        let s = format!("{v:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

/// Tick label of a linear axis: at most four significant digits, no float noise.
fn tick(v: &f64) -> String {
    if *v == 0.0 {
        return "0".into();
    }
    let e = v.abs().log10().floor() as i32;
    if !(-3..6).contains(&e) {
        return format!("{v:.1e}");
    }
    let decimals = (3 - e).clamp(0, 6) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Frequency axis covering `freqs` with half a line spacing (or 2 % of the span) either side.
fn freq_range(freqs: &[f64]) -> std::ops::Range<f64> {
    let lo = freqs.first().copied().unwrap_or(0.0);
    let hi = freqs.last().copied().unwrap_or(1.0);
    let pad = if freqs.len() > 1 {
        (0.02 * (hi - lo)).max(0.5 * (freqs[1] - freqs[0]))
    } else {
        1.0
    };
    (lo - pad).max(0.0)..(hi + pad)
}

/// `count` frequencies evenly over `range`, for model curves.
fn model_freqs(range: &std::ops::Range<f64>, count: usize) -> Vec<f64> {
    let lo = range.start.max(1e-3);
    (0..count)
        .map(|k| lo + (range.end - lo) * k as f64 / (count - 1) as f64)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_replace_markers() {
        let svg = "<svg>\n<text x=\"0\">\n@@series-begin@@G xy &amp; z\n</text>\n<circle/>\n\
                   <text x=\"0\">\n@@series-end@@\n</text>\n<text x=\"1\">\nlabel\n</text>\n</svg>";
        let out = group_series(svg);
        assert!(out.contains("<g class=\"series\" data-series=\"G xy &amp; z\">"));
        assert!(out.contains("<title>G xy &amp; z</title>"));
        assert!(out.contains("</g>"));
        assert!(out.contains("label"));
        assert!(!out.contains("@@"));
    }

    #[test]
    fn si_units_pick_a_prefix() {
        assert_eq!(si_unit(146.3e3, "N/m"), (1e3, "kN/m".to_string()));
        assert_eq!(si_unit(2.5e-5, "m"), (1e-6, "µm".to_string()));
        assert_eq!(si_unit(0.0, "N"), (1.0, "N".to_string()));
    }

    #[test]
    fn ticks_are_short() {
        assert_eq!(tick(&0.30000000000000004), "0.3");
        assert_eq!(tick(&150.0), "150");
        assert_eq!(tick(&-2.5), "-2.5");
        assert_eq!(log_tick(&1e-6), "1e-6");
        assert_eq!(log_tick(&10.0), "10");
    }

    #[test]
    fn axis_names_default_by_size() {
        let o = FigureOptions::default();
        assert_eq!(o.axis_names(2), ["x", "y"]);
        assert_eq!(o.axis_names(4), ["1", "2", "3", "4"]);
        let o = FigureOptions {
            axes: vec!["u".into()],
            ..FigureOptions::default()
        };
        assert_eq!(o.axis_names(1), ["u"]);
    }

    #[test]
    fn write_failure_is_an_io_error() {
        let e = write_file(Path::new("/nonexistent-dir/x.svg"), "x").unwrap_err();
        assert_eq!(e.kind(), "io_error");
    }
}
