//! The chart helpers the figures share: linear and logarithmic charts with their ticks, panel
//! titles, stacked plots, matrix grids, error bars, axis ranges with SI units, and phase curves
//! broken at their wraps.

use plotters::coord::combinators::{IntoLogRange, LogCoord};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::canvas::{Area, Boxed, Drawn, font};
use crate::plot::FigureOptions;

/// Pixels of the axis label areas.
pub(crate) const Y_LABELS: u32 = 78;
pub(crate) const X_LABELS: u32 = 46;

/// Points on a fitted model curve.
pub(crate) const MODEL_POINTS: usize = 400;

pub(crate) type Chart<'a, 'b, X, Y> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>;

/// A chart of linear `x` and `y` on `area`, its mesh drawn, x described only when `x_desc`
/// is given (stacked plots share it). The fine mesh is left out: white on the white
/// background, it would be a hundred invisible lines a plot.
pub(crate) fn linear_chart<'a, 'b>(
    area: &'a Area<'b>,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    x_desc: Option<&str>,
    y_desc: &str,
) -> std::result::Result<
    Chart<'a, 'b, plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    Boxed,
> {
    let mut chart = ChartBuilder::on(area)
        .margin(8)
        .margin_right(16)
        .x_label_area_size(if x_desc.is_some() { X_LABELS } else { 26 })
        .y_label_area_size(Y_LABELS)
        .build_cartesian_2d(x, y)?;
    chart
        .configure_mesh()
        .x_labels(7)
        .y_labels(6)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .x_desc(x_desc.unwrap_or(""))
        .y_desc(y_desc)
        .label_style(("sans-serif", font::TICK))
        .axis_desc_style(("sans-serif", font::DESC))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()?;
    Ok(chart)
}

/// As [`linear_chart`] with a logarithmic `y`, ticked at 1, 2, 5 × 10ᵏ (fewer over many
/// decades): plotters' own log ticks leave a plot spanning less than a decade with one label.
pub(crate) fn log_chart<'a, 'b>(
    area: &'a Area<'b>,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    x_desc: Option<&str>,
    y_desc: &str,
) -> std::result::Result<Chart<'a, 'b, plotters::coord::types::RangedCoordf64, LogCoord<f64>>, Boxed>
{
    let mut chart = ChartBuilder::on(area)
        .margin(8)
        .margin_right(16)
        .x_label_area_size(if x_desc.is_some() { X_LABELS } else { 26 })
        .y_label_area_size(Y_LABELS)
        .build_cartesian_2d(x.clone(), y.clone().log_scale())?;
    chart
        .configure_mesh()
        .x_labels(7)
        .y_labels(0)
        .disable_y_mesh()
        .x_label_formatter(&tick)
        .y_label_formatter(&|_| String::new())
        .x_desc(x_desc.unwrap_or(""))
        .y_desc(y_desc)
        .label_style(("sans-serif", font::TICK))
        .axis_desc_style(("sans-serif", font::DESC))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()?;
    for v in log_ticks(&y) {
        y_tick(&mut chart, &x, v, &log_tick(&v))?;
    }
    Ok(chart)
}

/// Tick values of a log axis over `y`: 1, 2, 5 × 10ᵏ below two decades, 1 and 3 × 10ᵏ below
/// four, powers of ten above (every other one above eight decades).
pub(crate) fn log_ticks(y: &std::ops::Range<f64>) -> Vec<f64> {
    let (lo, hi) = (y.start.log10(), y.end.log10());
    let decades = hi - lo;
    let mantissas: &[f64] = if decades < 2.0 {
        &[1.0, 2.0, 5.0]
    } else if decades < 4.0 {
        &[1.0, 3.0]
    } else {
        &[1.0]
    };
    let every = if decades > 8.0 { 2 } else { 1 };
    (lo.floor() as i32..=hi.ceil() as i32)
        .filter(|k| k.rem_euclid(every) == 0)
        .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
        .filter(|v| *v >= y.start && *v <= y.end)
        .collect()
}

/// A grid line across the chart at `y = v` and its label left of the axis.
pub(crate) fn y_tick<Y: Ranged<ValueType = f64>>(
    chart: &mut Chart<'_, '_, plotters::coord::types::RangedCoordf64, Y>,
    x: &std::ops::Range<f64>,
    v: f64,
    label: &str,
) -> Drawn {
    chart.draw_series(LineSeries::new(
        [(x.start, v), (x.end, v)],
        RGBColor(225, 225, 225),
    ))?;
    chart.draw_series([EmptyElement::at((x.start, v))
        + Text::new(
            label.to_string(),
            (-7, 0),
            TextStyle::from(("sans-serif", font::TICK).into_font())
                .pos(Pos::new(HPos::Right, VPos::Center)),
        )])?;
    Ok(())
}

/// The panel title of element `ij`, e.g. `G xy`; returns the area below it.
pub(crate) fn titled<'a>(panel: &Area<'a>, title: &str) -> std::result::Result<Area<'a>, Boxed> {
    Ok(panel.titled(
        title,
        ("sans-serif", font::PANEL)
            .into_font()
            .style(FontStyle::Bold),
    )?)
}

/// The two stacked plots of a matrix panel: upper 54 %, lower the rest.
pub(crate) fn stacked<'a>(area: &Area<'a>) -> (Area<'a>, Area<'a>) {
    let h = area.dim_in_pixel().1;
    area.split_vertically(h * 54 / 100)
}

/// Size of a matrix figure of `n × n` panels plus a header.
pub(crate) fn grid_size(options: &FigureOptions, n: usize) -> (u32, u32) {
    let (w, h) = options.panel();
    (w * n as u32 + 10, h * n as u32 + 80)
}

/// A series is drawn point by point (a marker, an error bar each) while it has at most one
/// point per this many pixel columns of its plot; a denser one is drawn as its extremes per
/// pixel column ([`column_extremes`]) and its error bars as one band ([`column_band`]), so
/// that a figure's size does not grow with the lines it shows.
pub(crate) const PIXELS_PER_MARKER: usize = 4;

/// The width in pixels of `chart`'s plot.
pub(crate) fn columns<X: Ranged, Y: Ranged>(chart: &Chart<'_, '_, X, Y>) -> usize {
    chart.plotting_area().dim_in_pixel().0 as usize
}

/// Radius of a measured point's marker, in pixels.
pub(crate) const MARKER_RADIUS: u32 = 3;

/// Whether `count` points on a plot `columns` pixels wide are drawn one by one (see
/// [`PIXELS_PER_MARKER`]).
pub(crate) fn one_by_one(count: usize, columns: usize) -> bool {
    count.saturating_mul(PIXELS_PER_MARKER) <= columns
}

/// The pixel column, of `columns` over `x`, that `v` falls in (the edges clamped).
fn column(v: f64, x: &std::ops::Range<f64>, columns: usize) -> usize {
    let at = (v - x.start) / (x.end - x.start) * columns as f64;
    // `as` saturates: below the range (and NaN) column 0.
    (at as usize).min(columns.saturating_sub(1))
}

/// The finite `points` (in `x` order) reduced to the lowest and the highest of each pixel
/// column of a plot `columns` wide over `x`, in `x` order: a line through them draws every
/// excursion of a series of any length with at most two points per column.
pub(crate) fn column_extremes(
    points: impl IntoIterator<Item = (f64, f64)>,
    x: &std::ops::Range<f64>,
    columns: usize,
) -> Vec<(f64, f64)> {
    /// A pixel column being gathered: its index, its lowest and its highest point.
    type Gathered = (usize, (f64, f64), (f64, f64));
    let mut out = Vec::new();
    let mut open: Option<Gathered> = None;
    let flush = |out: &mut Vec<(f64, f64)>, (_, lo, hi): Gathered| {
        let (first, second) = if lo.0 <= hi.0 { (lo, hi) } else { (hi, lo) };
        out.push(first);
        if second != first {
            out.push(second);
        }
    };
    for p in points
        .into_iter()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
    {
        let c = column(p.0, x, columns);
        match &mut open {
            Some((at, lo, hi)) if *at == c => {
                if p.1 < lo.1 {
                    *lo = p;
                }
                if p.1 > hi.1 {
                    *hi = p;
                }
            }
            _ => {
                if let Some(done) = open.take() {
                    flush(&mut out, done);
                }
                open = Some((c, p, p));
            }
        }
    }
    if let Some(done) = open {
        flush(&mut out, done);
    }
    out
}

/// The error bars `v ± σ` of `points` (in `x` order) merged per pixel column of a plot
/// `columns` wide over `x`: per column that holds a bar, `(mean x, lowest v − σ, highest
/// v + σ)`, the outline of every bar of the column.
pub(crate) fn column_band(
    points: &[(f64, f64, Option<f64>)],
    x: &std::ops::Range<f64>,
    columns: usize,
) -> Vec<(f64, f64, f64)> {
    // Per column: its index, the sum of x and the count, the lowest and highest bar end.
    let mut sums: Vec<(usize, f64, f64, f64, f64)> = Vec::new();
    for &(f, v, s) in points {
        let Some(s) = s.filter(|s| s.is_finite() && f.is_finite() && v.is_finite()) else {
            continue;
        };
        let c = column(f, x, columns);
        match sums.last_mut() {
            Some(last) if last.0 == c => {
                last.1 += f;
                last.2 += 1.0;
                last.3 = last.3.min(v - s);
                last.4 = last.4.max(v + s);
            }
            _ => sums.push((c, f, 1.0, v - s, v + s)),
        }
    }
    sums.into_iter()
        .map(|(_, x, count, lo, hi)| (x / count, lo, hi))
        .collect()
}

/// `points` (in `x` order) as filled markers of `radius`, or, denser than
/// [`PIXELS_PER_MARKER`], as a line as wide as a marker (less a pixel) through their extremes
/// per pixel column; a `wrapped` series (a phase in degrees) is broken where it jumps by more
/// than 180°.
pub(crate) fn draw_markers<Y>(
    chart: &mut Chart<'_, '_, plotters::coord::types::RangedCoordf64, Y>,
    points: &[(f64, f64)],
    radius: u32,
    color: RGBColor,
    wrapped: bool,
) -> Drawn
where
    Y: Ranged<ValueType = f64>,
{
    let columns = columns(chart);
    if one_by_one(points.len(), columns) {
        chart.draw_series(
            points
                .iter()
                .map(|&p| Circle::new(p, radius, color.filled())),
        )?;
        return Ok(());
    }
    let line = column_extremes(points.iter().copied(), &chart.x_range(), columns);
    let style = color.stroke_width((2 * radius).saturating_sub(1).max(1));
    if wrapped {
        for segment in phase_segments(&line) {
            chart.draw_series(LineSeries::new(segment, style))?;
        }
    } else {
        chart.draw_series(LineSeries::new(line, style))?;
    }
    Ok(())
}

/// Points with symmetric error bars `±σ` (clamped to `y`), or plain points without `σ`; a
/// series denser than [`PIXELS_PER_MARKER`] drawn as a line through its extremes per pixel
/// column over the band of its error bars.
pub(crate) fn draw_points_with_bars<Y>(
    chart: &mut Chart<'_, '_, plotters::coord::types::RangedCoordf64, Y>,
    points: &[(f64, f64, Option<f64>)],
    y: &std::ops::Range<f64>,
    color: RGBColor,
) -> Drawn
where
    Y: Ranged<ValueType = f64>,
{
    let clamp = |v: f64| v.clamp(y.start, y.end);
    let columns = columns(chart);
    let count = points.iter().filter(|p| p.1.is_finite()).count();
    if !one_by_one(count, columns) {
        let x = chart.x_range();
        let band = column_band(points, &x, columns);
        if !band.is_empty() {
            let outline: Vec<(f64, f64)> = band
                .iter()
                .map(|b| (b.0, clamp(b.2)))
                .chain(band.iter().rev().map(|b| (b.0, clamp(b.1))))
                .collect();
            chart.draw_series([Polygon::new(outline, color.mix(0.3).filled())])?;
        }
        // As wide as the markers (less a pixel), so that the fit drawn over it shows the
        // measured line on both sides.
        let line = column_extremes(points.iter().map(|p| (p.0, p.1)), &x, columns);
        chart.draw_series(LineSeries::new(
            line.into_iter().map(|(f, v)| (f, clamp(v))),
            color.stroke_width(2 * MARKER_RADIUS - 1),
        ))?;
        return Ok(());
    }
    chart.draw_series(
        points
            .iter()
            .filter_map(|&(f, v, s)| s.filter(|s| s.is_finite()).map(|s| (f, v, s)))
            .map(|(f, v, s)| {
                ErrorBar::new_vertical(
                    f,
                    clamp(v - s),
                    clamp(v),
                    clamp(v + s),
                    color.mix(0.7).stroke_width(1),
                    6,
                )
            }),
    )?;
    chart.draw_series(
        points
            .iter()
            .filter(|p| p.1.is_finite())
            .map(|&(f, v, _)| Circle::new((f, clamp(v)), MARKER_RADIUS, color.filled())),
    )?;
    Ok(())
}

/// A y range for `points` (values and error bars) and `model`: the bars are included unless
/// they would squeeze the values into a fifth of the axis (then they are clamped).
pub(crate) fn bar_range(
    points: &[(f64, f64, Option<f64>)],
    model: &[(f64, f64)],
) -> std::ops::Range<f64> {
    let values = || points.iter().map(|p| p.1).chain(model.iter().map(|p| p.1));
    let plain = span(values(), 0.12);
    let with_bars = span(
        values().chain(
            points
                .iter()
                .filter_map(|p| p.2.map(|s| [p.1 - s, p.1 + s]))
                .flatten(),
        ),
        0.08,
    );
    if with_bars.end - with_bars.start > 5.0 * (plain.end - plain.start) {
        plain
    } else {
        with_bars
    }
}

/// Points with error bars and a model line drawn on one axis, in the SI-prefixed unit of their
/// common range ([`bar_range`], [`si_unit`]): the values divided by the scale, the y range and
/// the unit.
pub(crate) struct ScaledPanel {
    /// `(x, value, error bar)` in the scaled unit.
    pub points: Vec<(f64, f64, Option<f64>)>,
    /// The model line in the scaled unit.
    pub model: Vec<(f64, f64)>,
    /// The y range in the scaled unit.
    pub y: std::ops::Range<f64>,
    /// `unit` with its SI prefix.
    pub unit: String,
    /// What the values were divided by.
    pub scale: f64,
}

/// `points` and `model` (in `unit`) scaled together ([`ScaledPanel`]).
pub(crate) fn scaled_panel(
    points: &[(f64, f64, Option<f64>)],
    model: &[(f64, f64)],
    unit: &str,
) -> ScaledPanel {
    let range = bar_range(points, model);
    let (scale, unit) = si_unit(range.start.abs().max(range.end.abs()), unit);
    ScaledPanel {
        points: points
            .iter()
            .map(|&(f, v, s)| (f, v / scale, s.map(|s| s / scale)))
            .collect(),
        model: model.iter().map(|&(f, v)| (f, v / scale)).collect(),
        y: (range.start / scale)..(range.end / scale),
        unit,
        scale,
    }
}

/// Breaks a phase curve (degrees, wrapped) where it jumps by more than 180°.
pub(crate) fn phase_segments(points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut segments: Vec<Vec<(f64, f64)>> = Vec::new();
    for &p in points {
        match segments.last_mut() {
            Some(seg) if seg.last().is_some_and(|q| (q.1 - p.1).abs() <= 180.0) => seg.push(p),
            _ => segments.push(vec![p]),
        }
    }
    segments
}

/// A scale for values up to `max` in `unit`: (divisor, unit with an SI prefix).
pub(crate) fn si_unit(max: f64, unit: &str) -> (f64, String) {
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
pub(crate) fn span(values: impl IntoIterator<Item = f64>, pad: f64) -> std::ops::Range<f64> {
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
        lo.abs().max(crate::tolerance::PLOT_MIN_SPAN)
    };
    (lo - pad * width)..(hi + pad * width)
}

/// A positive range around the positive finite `values` for a log axis, padded by a factor.
pub(crate) fn log_span(values: impl IntoIterator<Item = f64>) -> std::ops::Range<f64> {
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
pub(crate) fn log_tick(v: &f64) -> String {
    let e = v.abs().log10();
    if (-2.0..4.0).contains(&e) {
        let s = format!("{v:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

/// Tick label of a linear axis: at most four significant digits, no float noise.
pub(crate) fn tick(v: &f64) -> String {
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
pub(crate) fn freq_range(freqs: &[f64]) -> std::ops::Range<f64> {
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
pub(crate) fn model_freqs(range: &std::ops::Range<f64>, count: usize) -> Vec<f64> {
    let lo = range.start.max(1e-3);
    (0..count)
        .map(|k| lo + (range.end - lo) * k as f64 / (count - 1) as f64)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extremes_per_column_keep_every_excursion_in_order() {
        // Ten columns over 0..10; three points in column 0, one in column 5, two in 9.
        let points = [
            (0.1, 2.0),
            (0.5, -1.0),
            (0.9, 5.0),
            (5.5, 0.0),
            (9.2, f64::NAN),
            (9.3, 3.0),
            (9.9, 1.0),
        ];
        let out = column_extremes(points, &(0.0..10.0), 10);
        assert_eq!(
            out,
            [(0.5, -1.0), (0.9, 5.0), (5.5, 0.0), (9.3, 3.0), (9.9, 1.0)]
        );
        // The highest point before the lowest: still in x order.
        let out = column_extremes([(0.2, 9.0), (0.4, 1.0), (0.6, 4.0)], &(0.0..10.0), 10);
        assert_eq!(out, [(0.2, 9.0), (0.4, 1.0)]);
        // A million points on 300 columns: at most 600 drawn.
        let many = (0..1_000_000).map(|k| (k as f64 * 1e-5, (k as f64).sin()));
        assert!(column_extremes(many, &(0.0..10.0), 300).len() <= 600);
    }

    #[test]
    fn bands_outline_the_bars_of_a_column() {
        let points = [
            (0.2, 1.0, Some(0.5)),
            (0.6, 2.0, Some(0.1)),
            (0.8, 0.0, None),
            (3.5, 0.0, Some(1.0)),
        ];
        let band = column_band(&points, &(0.0..10.0), 10);
        assert_eq!(band, [(0.4, 0.5, 2.1), (3.5, -1.0, 1.0)]);
        assert!(one_by_one(100, 400) && !one_by_one(101, 400));
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
}
