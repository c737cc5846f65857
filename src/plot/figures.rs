//! The six figures.

use faer::{Mat, c64};
use plotters::coord::combinators::{IntoLogRange, LogCoord};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{
    ALERT, Area, Boxed, DARK, Drawn, FigureOptions, GREY, Key, MEASURED, MODEL, colour, font,
    freq_range, header, log_span, log_tick, message, model_freqs, render, series, si_unit, span,
    tick,
};
use crate::error::Result;
use crate::identify::Identification;
use crate::quality::{self, ImpactChecks, ImpactIssue};
use crate::records::Record;
use crate::spectra::Segmentation;
use crate::{Channel, Error};

/// Pixels of the axis label areas.
const Y_LABELS: u32 = 78;
const X_LABELS: u32 = 46;

/// Points on a fitted model curve.
const MODEL_POINTS: usize = 400;

type Chart<'a, 'b, X, Y> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>;

/// A chart of linear `x` and `y` on `area`, its mesh drawn, x described only when `x_desc`
/// is given (stacked plots share it).
fn linear_chart<'a, 'b>(
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
        .light_line_style(WHITE)
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()?;
    Ok(chart)
}

/// As [`linear_chart`] with a logarithmic `y`, ticked at 1, 2, 5 × 10ᵏ (fewer over many
/// decades): plotters' own log ticks leave a plot spanning less than a decade with one label.
fn log_chart<'a, 'b>(
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
        .light_line_style(WHITE)
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()?;
    for v in log_ticks(&y) {
        y_tick(&mut chart, &x, v, &log_tick(&v))?;
    }
    Ok(chart)
}

/// Tick values of a log axis over `y`: 1, 2, 5 × 10ᵏ below two decades, 1 and 3 × 10ᵏ below
/// four, powers of ten above (every other one above eight decades).
fn log_ticks(y: &std::ops::Range<f64>) -> Vec<f64> {
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
fn y_tick<Y: Ranged<ValueType = f64>>(
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
fn titled<'a>(panel: &Area<'a>, title: &str) -> std::result::Result<Area<'a>, Boxed> {
    Ok(panel.titled(
        title,
        ("sans-serif", font::PANEL)
            .into_font()
            .style(FontStyle::Bold),
    )?)
}

/// The two stacked plots of a matrix panel: upper 54 %, lower the rest.
fn stacked<'a>(area: &Area<'a>) -> (Area<'a>, Area<'a>) {
    let h = area.dim_in_pixel().1;
    area.split_vertically(h * 54 / 100)
}

/// Size of a matrix figure of `n × n` panels plus a header.
fn grid_size(options: &FigureOptions, n: usize) -> (u32, u32) {
    let (w, h) = options.panel();
    (w * n as u32 + 10, h * n as u32 + 80)
}

/// Points with symmetric error bars `±σ` (clamped to `y`), or plain points without `σ`.
fn draw_points_with_bars<Y>(
    chart: &mut Chart<'_, '_, plotters::coord::types::RangedCoordf64, Y>,
    points: &[(f64, f64, Option<f64>)],
    y: &std::ops::Range<f64>,
    color: RGBColor,
) -> Drawn
where
    Y: Ranged<ValueType = f64>,
{
    let clamp = |v: f64| v.clamp(y.start, y.end);
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
            .map(|&(f, v, _)| Circle::new((f, clamp(v)), 3, color.filled())),
    )?;
    Ok(())
}

/// A y range for `points` (values and error bars) and `model`: the bars are included unless
/// they would squeeze the values into a fifth of the axis (then they are clamped).
fn bar_range(points: &[(f64, f64, Option<f64>)], model: &[(f64, f64)]) -> std::ops::Range<f64> {
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

/// Breaks a phase curve (degrees, wrapped) where it jumps by more than 180°.
fn phase_segments(points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut segments: Vec<Vec<(f64, f64)>> = Vec::new();
    for &p in points {
        match segments.last_mut() {
            Some(seg) if seg.last().is_some_and(|q| (q.1 - p.1).abs() <= 180.0) => seg.push(p),
            _ => segments.push(vec![p]),
        }
    }
    segments
}

/// Flexibility `G_ij`: magnitude (log scale) over phase, measured points and fitted model.
///
/// The figure is an `n × n` grid, element `ij` in row `i`, column `j`; each panel holds
/// `|G_ij|` (m/N, logarithmic) above `∠G_ij` (degrees), the measured lines as points and the
/// fitted model `G(ω) = (K − ω²M + iωC)⁻¹` as a line. Series, per element:
/// `|G ij| measured`, `|G ij| model`, `∠G ij measured`, `∠G ij model`.
///
/// # Errors
/// [`Error::Plot`] if plotters fails to draw (not expected for an SVG held in memory).
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let svg = plot::flexibility(&id, &FigureOptions::default())?;
/// assert!(svg.starts_with("<svg") && svg.contains("|G xy| model"));
/// let path = std::env::temp_dir().join("bearing-ident-doc-flexibility.svg");
/// std::fs::write(&path, &svg).unwrap();
/// assert!(std::fs::read_to_string(&path).unwrap().ends_with("</svg>\n"));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn flexibility(id: &Identification, options: &FigureOptions) -> Result<String> {
    let n = id.coefficients().dofs();
    let names = options.axis_names(n);
    let freqs = id.freqs_hz();
    let x = freq_range(freqs);
    let model: Vec<(f64, Mat<c64>)> = model_freqs(&x, MODEL_POINTS)
        .into_iter()
        .filter_map(|f| id.coefficients().flexibility_at(f).ok().map(|g| (f, g)))
        .collect();
    let title = format!(
        "Flexibility G = H⁻¹: measured and fitted ({}, {} lines)",
        id.method().name(),
        freqs.len()
    );
    render("flexibility", grid_size(options, n), |root| {
        let body = header(
            root,
            &title,
            &[
                (Key::Point(MEASURED), "measured"),
                (Key::Line(MODEL), "fitted model"),
            ],
        )?;
        for (p, panel) in body.split_evenly((n, n)).iter().enumerate() {
            let (i, j) = (p / n, p % n);
            let el = format!("{}{}", names[i], names[j]);
            let panel = titled(panel, &format!("G {el}"))?;
            let (top, bottom) = stacked(&panel);
            let measured: Vec<(f64, c64)> = freqs
                .iter()
                .enumerate()
                .map(|(k, &f)| (f, id.frf().flexibility(k)[(i, j)]))
                .collect();
            let fitted: Vec<(f64, c64)> = model.iter().map(|(f, g)| (*f, g[(i, j)])).collect();
            let magnitude = |v: &[(f64, c64)]| -> Vec<(f64, f64)> {
                v.iter()
                    .map(|(f, g)| (*f, g.norm()))
                    .filter(|p| p.1 > 0.0 && p.1.is_finite())
                    .collect()
            };
            let phase = |v: &[(f64, c64)]| -> Vec<(f64, f64)> {
                v.iter()
                    .map(|(f, g)| (*f, g.arg().to_degrees()))
                    .filter(|p| p.1.is_finite())
                    .collect()
            };
            let (m_meas, m_fit) = (magnitude(&measured), magnitude(&fitted));
            let y = log_span(m_meas.iter().chain(&m_fit).map(|p| p.1));
            let mut chart = log_chart(&top, x.clone(), y, None, "|G| (m/N)")?;
            series(&top, &format!("|G {el}| measured"), || {
                chart.draw_series(m_meas.iter().map(|&p| Circle::new(p, 3, MEASURED.filled())))?;
                Ok(())
            })?;
            series(&top, &format!("|G {el}| model"), || {
                chart.draw_series(LineSeries::new(
                    m_fit.iter().copied(),
                    MODEL.stroke_width(2),
                ))?;
                Ok(())
            })?;
            let mut chart = ChartBuilder::on(&bottom)
                .margin(8)
                .margin_right(16)
                .x_label_area_size(X_LABELS)
                .y_label_area_size(Y_LABELS)
                .build_cartesian_2d(x.clone(), -200.0..200.0)?;
            chart
                .configure_mesh()
                .x_labels(7)
                .y_labels(0)
                .disable_y_mesh()
                .x_label_formatter(&tick)
                .x_desc("frequency (Hz)")
                .y_desc("∠G (°)")
                .label_style(("sans-serif", font::TICK))
                .axis_desc_style(("sans-serif", font::DESC))
                .light_line_style(WHITE)
                .bold_line_style(RGBColor(225, 225, 225))
                .draw()?;
            // Phase ticks at multiples of 90°, which plotters' automatic ticks do not hit.
            for deg in [-180.0, -90.0, 0.0, 90.0, 180.0] {
                y_tick(&mut chart, &x, deg, &format!("{deg:.0}"))?;
            }
            let (p_meas, p_fit) = (phase(&measured), phase(&fitted));
            series(&bottom, &format!("∠G {el} measured"), || {
                chart.draw_series(p_meas.iter().map(|&p| Circle::new(p, 3, MEASURED.filled())))?;
                Ok(())
            })?;
            series(&bottom, &format!("∠G {el} model"), || {
                for segment in phase_segments(&p_fit) {
                    chart.draw_series(LineSeries::new(segment, MODEL.stroke_width(2)))?;
                }
                Ok(())
            })?;
        }
        Ok(())
    })
}

/// Impedance `H_ij`: `Re H_ij` with the fitted `K − ω²M` above `Im H_ij` with the fitted
/// `ωC`, in an `n × n` grid.
///
/// Units are N/m with an SI prefix chosen per plot. When the FRF carries a variance
/// ([`Frf::impedance_variance`](crate::Frf::impedance_variance)), every measured point has an
/// error bar of `±σ`, `σ² = E|δH_ij|²/2` (the real and imaginary parts each carry half).
/// Series, per element: `Re H ij measured`, `Re H ij model K − ω²M`, `Im H ij measured`,
/// `Im H ij model ωC`.
///
/// # Errors
/// [`Error::Plot`] if plotters fails to draw.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records =
///     ImpactTest { per_direction: 3, noise: 0.05, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let svg = plot::impedance(&id, &FigureOptions::default())?;
/// assert!(svg.contains("Re H xx model K − ω²M"));
/// assert!(svg.contains("Re H (kN/m)"));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn impedance(id: &Identification, options: &FigureOptions) -> Result<String> {
    let n = id.coefficients().dofs();
    let names = options.axis_names(n);
    let freqs = id.freqs_hz();
    let x = freq_range(freqs);
    let co = id.coefficients();
    let model_f = model_freqs(&x, MODEL_POINTS);
    let with_bars = (0..freqs.len()).all(|k| id.frf().impedance_variance(k).is_some());
    let title = format!(
        "Impedance H = K − ω²M + iωC: measured{} and fitted ({})",
        if with_bars { " ± σ" } else { "" },
        id.method().name()
    );
    render("impedance", grid_size(options, n), |root| {
        let body = header(
            root,
            &title,
            &[
                (Key::Point(MEASURED), "measured"),
                (Key::Line(MODEL), "fitted K − ω²M (Re), ωC (Im)"),
            ],
        )?;
        for (p, panel) in body.split_evenly((n, n)).iter().enumerate() {
            let (i, j) = (p / n, p % n);
            let el = format!("{}{}", names[i], names[j]);
            let panel = titled(panel, &format!("H {el}"))?;
            let (top, bottom) = stacked(&panel);
            let sigma = |k: usize| {
                id.frf()
                    .impedance_variance(k)
                    .map(|v| (v[(i, j)] / 2.0).max(0.0).sqrt())
            };
            let re: Vec<(f64, f64, Option<f64>)> = freqs
                .iter()
                .enumerate()
                .map(|(k, &f)| (f, id.frf().impedance(k)[(i, j)].re, sigma(k)))
                .collect();
            let im: Vec<(f64, f64, Option<f64>)> = freqs
                .iter()
                .enumerate()
                .map(|(k, &f)| (f, id.frf().impedance(k)[(i, j)].im, sigma(k)))
                .collect();
            let w = |f: f64| 2.0 * std::f64::consts::PI * f;
            let re_fit: Vec<(f64, f64)> = model_f
                .iter()
                .map(|&f| (f, co.stiffness()[(i, j)] - w(f) * w(f) * co.mass()[(i, j)]))
                .collect();
            let im_fit: Vec<(f64, f64)> = model_f
                .iter()
                .map(|&f| (f, w(f) * co.damping()[(i, j)]))
                .collect();
            for (area, part, points, fit, model_name) in [
                (&top, "Re", &re, &re_fit, "K − ω²M"),
                (&bottom, "Im", &im, &im_fit, "ωC"),
            ] {
                let range = bar_range(points, fit);
                let (scale, unit) = si_unit(range.start.abs().max(range.end.abs()), "N/m");
                let scaled: Vec<(f64, f64, Option<f64>)> = points
                    .iter()
                    .map(|&(f, v, s)| (f, v / scale, s.map(|s| s / scale)))
                    .collect();
                let fit: Vec<(f64, f64)> = fit.iter().map(|&(f, v)| (f, v / scale)).collect();
                let y = (range.start / scale)..(range.end / scale);
                let x_desc = (part == "Im").then_some("frequency (Hz)");
                let mut chart = linear_chart(
                    area,
                    x.clone(),
                    y.clone(),
                    x_desc,
                    &format!("{part} H ({unit})"),
                )?;
                series(area, &format!("{part} H {el} measured"), || {
                    draw_points_with_bars(&mut chart, &scaled, &y, MEASURED)
                })?;
                series(area, &format!("{part} H {el} model {model_name}"), || {
                    chart.draw_series(LineSeries::new(fit, MODEL.stroke_width(2)))?;
                    Ok(())
                })?;
            }
        }
        Ok(())
    })
}

/// Multiple coherence per output and condition number per line, with the thresholds.
///
/// Upper plot: the multiple coherence `γ²_{i:f}` of every output `i` (one series each,
/// `coherence x`, …; left out with a note when the spectra carry none, as for paired sets
/// with one record per excitation). Lower plot: the condition number per line (log scale,
/// series `condition number`) with the warning and refusal thresholds of the identification's
/// [`ConditionLimits`](crate::ConditionLimits) (series `warn limit`, `refuse limit`). On both,
/// the band asked for is shaded (series `band`) and lines dropped for low coherence are
/// marked (series `lines dropped`, only when there are some).
///
/// # Errors
/// [`Error::Plot`] if plotters fails to draw.
///
/// # Examples
/// ```
/// use bearing_ident::{Identifier, Estimator};
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records =
///     ImpactTest { per_direction: 2, noise: 0.05, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).estimator(Estimator::H1).identify(&records)?;
/// let svg = plot::coherence(&id, &FigureOptions::default())?;
/// assert!(svg.contains("data-series=\"coherence y\"") && svg.contains("refuse limit"));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn coherence(id: &Identification, options: &FigureOptions) -> Result<String> {
    let n = id.coefficients().dofs();
    let names = options.axis_names(n);
    let freqs = id.freqs_hz();
    let band = id.band();
    let dropped = id.frf().dropped_hz();
    let limits = id.conditioning().limits();
    let low = band.low_hz().min(freqs.first().copied().unwrap_or(0.0));
    let high = band.high_hz().max(freqs.last().copied().unwrap_or(1.0));
    let pad = 0.06 * (high - low).max(1.0);
    let x = (low - pad).max(0.0)..(high + pad);
    let coherence: Vec<Vec<(f64, f64)>> = (0..n)
        .map(|i| {
            freqs
                .iter()
                .enumerate()
                .filter_map(|(k, &f)| id.frf().multiple_coherence(k).map(|c| (f, c[i])))
                .collect()
        })
        .collect();
    let has_coherence = coherence.iter().any(|c| !c.is_empty());
    let (w, h) = options.panel();
    let size = (2 * w + 10, 2 * h * 85 / 100 + 80);
    let mut legend: Vec<(Key, String)> = (0..n)
        .filter(|_| has_coherence)
        .map(|i| (Key::Line(colour(i)), format!("γ² of {}", names[i])))
        .collect();
    legend.push((Key::Line(DARK), "condition number".into()));
    legend.push((Key::Dashed(RGBColor(230, 159, 0)), "warn".into()));
    legend.push((Key::Dashed(ALERT), "refuse".into()));
    legend.push((Key::Band(RGBColor(0, 114, 178)), "band used".into()));
    if !dropped.is_empty() {
        legend.push((Key::Cross(GREY), "dropped".into()));
    }
    render("coherence", size, |root| {
        let legend: Vec<(Key, &str)> = legend.iter().map(|(k, s)| (*k, s.as_str())).collect();
        let body = header(
            root,
            &format!(
                "Multiple coherence and conditioning, band {}–{} Hz",
                tick(&band.low_hz()),
                tick(&band.high_hz())
            ),
            &legend,
        )?;
        let (top, bottom) = body.split_vertically(body.dim_in_pixel().1 / 2);
        let shade = RGBColor(0, 114, 178).mix(0.08).filled();
        // Coherence, on 0–1 or zoomed to 0.9–1 (0.8–1, …) when it is all high.
        let lowest = coherence.iter().flatten().map(|p| p.1).fold(1.0, f64::min);
        let y = (((10.0 * lowest - 0.5).floor() / 10.0).clamp(0.0, 0.9))..1.02;
        let mut chart = linear_chart(&top, x.clone(), y.clone(), None, "multiple coherence γ²")?;
        series(&top, "band", || {
            chart.draw_series(std::iter::once(Rectangle::new(
                [(band.low_hz(), y.start), (band.high_hz(), y.end)],
                shade,
            )))?;
            Ok(())
        })?;
        if has_coherence {
            for (i, c) in coherence.iter().enumerate() {
                series(&top, &format!("coherence {}", names[i]), || {
                    chart.draw_series(LineSeries::new(
                        c.iter().copied(),
                        // Earlier outputs drawn wider, so coinciding curves all show.
                        colour(i).stroke_width(2 + 2 * (n - 1 - i) as u32),
                    ))?;
                    chart
                        .draw_series(c.iter().map(|&p| {
                            Circle::new(p, 2 + (n - 1 - i) as u32, colour(i).filled())
                        }))?;
                    Ok(())
                })?;
            }
        } else {
            message(
                &top,
                "no coherence: the spectra carry none (one record per excitation and set)",
            )?;
        }
        if !dropped.is_empty() {
            series(&top, "lines dropped", || {
                chart.draw_series(
                    dropped
                        .iter()
                        .map(|&f| Cross::new((f, 0.02), 5, GREY.stroke_width(2))),
                )?;
                Ok(())
            })?;
        }
        // Conditioning.
        let cond = id.condition_numbers();
        let y = log_span(
            cond.iter()
                .copied()
                .chain([1.0, limits.warn * 2.0, limits.refuse * 2.0]),
        );
        let y = 1.0_f64.min(y.start)..y.end;
        let mut chart = log_chart(
            &bottom,
            x.clone(),
            y.clone(),
            Some("frequency (Hz)"),
            "condition number (–)",
        )?;
        series(&bottom, "band", || {
            chart.draw_series(std::iter::once(Rectangle::new(
                [(band.low_hz(), y.start), (band.high_hz(), y.end)],
                shade,
            )))?;
            Ok(())
        })?;
        let points: Vec<(f64, f64)> = freqs.iter().copied().zip(cond.iter().copied()).collect();
        series(&bottom, "condition number", || {
            chart.draw_series(LineSeries::new(
                points.iter().copied(),
                DARK.stroke_width(2),
            ))?;
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 2, DARK.filled())))?;
            Ok(())
        })?;
        for (name, level, c) in [
            ("warn limit", limits.warn, RGBColor(230, 159, 0)),
            ("refuse limit", limits.refuse, ALERT),
        ] {
            series(&bottom, name, || {
                chart.draw_series(DashedLineSeries::new(
                    [(x.start, level), (x.end, level)],
                    8,
                    6,
                    c.stroke_width(2),
                ))?;
                Ok(())
            })?;
        }
        Ok(())
    })
}

/// Frequency-dependent `K_ij(ω)` above `C_ij(ω)`, line by line with error bars, and the
/// constant fit, in an `n × n` grid.
///
/// From [`Identification::per_frequency`]: `K(ω) = Re H + ω²M`, `C(ω) = Im H/ω` with the
/// fitted `M` (and the exponential window's correction). Error bars `±σ` when the FRF
/// carries a variance. Series, per element: `K ij(ω)`, `K ij fit`, `C ij(ω)`, `C ij fit`.
///
/// # Errors
/// As [`Identification::per_frequency`]; [`Error::Plot`] if plotters fails to draw.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let svg = plot::per_frequency(&id, &FigureOptions::default())?;
/// assert_eq!(svg.matches("class=\"series\"").count(), 4 * 4);
/// assert!(svg.contains("C (N·s/m)"));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn per_frequency(id: &Identification, options: &FigureOptions) -> Result<String> {
    let pf = id.per_frequency()?;
    let n = id.coefficients().dofs();
    let names = options.axis_names(n);
    let freqs = pf.freqs_hz();
    let x = freq_range(freqs);
    let co = id.coefficients();
    let with_bars = (0..freqs.len()).all(|k| pf.stiffness_std(k).is_some());
    let title = format!(
        "Per-frequency stiffness K(ω) = Re H + ω²M and damping C(ω) = Im H/ω{}",
        if with_bars { " ± σ" } else { "" }
    );
    render("per_frequency", grid_size(options, n), |root| {
        let body = header(
            root,
            &title,
            &[
                (Key::Point(MEASURED), "per line"),
                (Key::Line(MODEL), "constant fit"),
            ],
        )?;
        for (p, panel) in body.split_evenly((n, n)).iter().enumerate() {
            let (i, j) = (p / n, p % n);
            let el = format!("{}{}", names[i], names[j]);
            let panel = titled(panel, &format!("K {el}, C {el}"))?;
            let (top, bottom) = stacked(&panel);
            let k_points: Vec<(f64, f64, Option<f64>)> = freqs
                .iter()
                .enumerate()
                .map(|(k, &f)| {
                    (
                        f,
                        pf.stiffness(k)[(i, j)],
                        pf.stiffness_std(k).map(|s| s[(i, j)]),
                    )
                })
                .collect();
            let c_points: Vec<(f64, f64, Option<f64>)> = freqs
                .iter()
                .enumerate()
                .map(|(k, &f)| {
                    (
                        f,
                        pf.damping(k)[(i, j)],
                        pf.damping_std(k).map(|s| s[(i, j)]),
                    )
                })
                .collect();
            for (area, name, points, fitted, unit) in [
                (&top, "K", &k_points, co.stiffness()[(i, j)], "N/m"),
                (&bottom, "C", &c_points, co.damping()[(i, j)], "N·s/m"),
            ] {
                let fit = [(x.start, fitted), (x.end, fitted)];
                let range = bar_range(points, &fit);
                let (scale, unit) = si_unit(range.start.abs().max(range.end.abs()), unit);
                let scaled: Vec<(f64, f64, Option<f64>)> = points
                    .iter()
                    .map(|&(f, v, s)| (f, v / scale, s.map(|s| s / scale)))
                    .collect();
                let y = (range.start / scale)..(range.end / scale);
                let x_desc = (name == "C").then_some("frequency (Hz)");
                let mut chart = linear_chart(
                    area,
                    x.clone(),
                    y.clone(),
                    x_desc,
                    &format!("{name} ({unit})"),
                )?;
                series(area, &format!("{name} {el}(ω)"), || {
                    draw_points_with_bars(&mut chart, &scaled, &y, MEASURED)
                })?;
                series(area, &format!("{name} {el} fit"), || {
                    chart.draw_series(LineSeries::new(
                        fit.iter().map(|&(f, v)| (f, v / scale)),
                        MODEL.stroke_width(2),
                    ))?;
                    Ok(())
                })?;
            }
        }
        Ok(())
    })
}

/// Time records: force (left) and displacement (right) per record, one row per record.
///
/// Channels are coloured by degree of freedom (series `RECORD force x`, …,
/// `RECORD displacement x`, …). On the force plot the impact is marked at the peak of the
/// dominant force channel (series `RECORD impact`); with `checks`, issues found by
/// [`quality::check_record`] are marked: a double hit by a cross at the second pulse
/// (`RECORD double hit`), a clipped channel by a red bar along the clipped run
/// (`RECORD clipped`). With `id`, its force gate is shaded (`RECORD force gate`) and an
/// exponential window over whole records is drawn, scaled to each plot's largest value
/// (`RECORD window`). Long records are reduced to the minimum and maximum per pixel column,
/// so peaks survive.
///
/// # Errors
/// [`Error::NoRecords`] for an empty slice; [`Error::Plot`] if plotters fails to draw.
///
/// # Examples
/// ```
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::quality::ImpactChecks;
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let svg = plot::records(&records, None, Some(&ImpactChecks::default()), &FigureOptions::default())?;
/// // Per record: two force channels, two displacement channels, the impact.
/// assert_eq!(svg.matches("class=\"series\"").count(), 2 * 5);
/// assert!(svg.contains("displacement (µm)"));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn records(
    records: &[Record],
    id: Option<&Identification>,
    checks: Option<&ImpactChecks>,
    options: &FigureOptions,
) -> Result<String> {
    let first = records.first().ok_or(Error::NoRecords)?;
    let n = first.dofs();
    let names = options.axis_names(n);
    let (w, h) = options.panel();
    let (panel_w, row_h) = (w * 5 / 4, (h * 6 / 10).max(180));
    let size = (2 * panel_w + 10, row_h * records.len() as u32 + 80);
    let gate = id.and_then(Identification::force_gate);
    let decay = id
        .filter(|id| id.segmentation() == Segmentation::WholeRecord)
        .and_then(|id| id.window().decay_per_s());
    let issues: Vec<Vec<ImpactIssue>> = records
        .iter()
        .map(|r| checks.map_or_else(Vec::new, |c| quality::check_record(r, c)))
        .collect();
    let any_double = issues
        .iter()
        .flatten()
        .any(|i| matches!(i, ImpactIssue::DoubleHit { .. }));
    let any_clip = issues
        .iter()
        .flatten()
        .any(|i| matches!(i, ImpactIssue::Clipped { .. }));
    let mut legend: Vec<(Key, String)> = names
        .iter()
        .enumerate()
        .map(|(i, a)| (Key::Line(colour(i)), format!("channel {a}")))
        .collect();
    legend.push((Key::Point(ALERT), "impact (peak)".into()));
    if any_double {
        legend.push((Key::Cross(ALERT), "double hit".into()));
    }
    if any_clip {
        legend.push((Key::Line(ALERT), "clipped".into()));
    }
    if gate.is_some() {
        legend.push((Key::Band(RGBColor(0, 158, 115)), "force gate".into()));
    }
    if decay.is_some() {
        legend.push((Key::Dashed(GREY), "exp. window (scaled)".into()));
    }
    render("records", size, |root| {
        let legend: Vec<(Key, &str)> = legend.iter().map(|(k, s)| (*k, s.as_str())).collect();
        let body = header(root, "Time records: force and displacement", &legend)?;
        let rows = body.split_evenly((records.len(), 1));
        for ((record, row), issues) in records.iter().zip(&rows).zip(&issues) {
            let label = record.label();
            let fs = record.sample_rate();
            let t_end = (record.len().saturating_sub(1) as f64 / fs).max(1.0 / fs);
            let force_end = force_span(record, gate, issues).min(t_end);
            let (left, right) = row.split_horizontally(panel_w);
            let buckets = (panel_w as usize).max(100);
            for (area, kind, unit) in [(&left, "force", "N"), (&right, "displacement", "m")] {
                let channel = |c: usize| match kind {
                    "force" => record.force(c),
                    _ => record.displacement(c),
                };
                let x = 0.0..if kind == "force" { force_end } else { t_end };
                let shown = ((x.end * fs).round() as usize + 1).min(record.len());
                let channel = |c: usize| &channel(c)[..shown];
                let max = (0..n)
                    .flat_map(|c| channel(c).iter().map(|v| v.abs()))
                    .fold(0.0, f64::max);
                let (scale, unit) = si_unit(max, unit);
                let y = span(
                    (0..n).flat_map(|c| channel(c).iter().map(|v| v / scale)),
                    0.08,
                );
                let title = if shown < record.len() {
                    format!("{label}: {kind}, first {} s", tick(&x.end))
                } else {
                    format!("{label}: {kind}")
                };
                let area = titled(area, &title)?;
                let mut chart = linear_chart(
                    &area,
                    x.clone(),
                    y.clone(),
                    Some("time (s)"),
                    &format!("{kind} ({unit})"),
                )?;
                if kind == "force" {
                    if let Some(g) = gate {
                        series(&area, &format!("{label} force gate"), || {
                            let c = RGBColor(0, 158, 115);
                            chart.draw_series([
                                Rectangle::new(
                                    [(0.0, y.start), (g.open_s().min(x.end), y.end)],
                                    c.mix(0.15).filled(),
                                ),
                                Rectangle::new(
                                    [
                                        (g.open_s().min(x.end), y.start),
                                        ((g.open_s() + g.taper_s()).min(x.end), y.end),
                                    ],
                                    c.mix(0.07).filled(),
                                ),
                            ])?;
                            Ok(())
                        })?;
                    }
                }
                for (c, name) in names.iter().enumerate() {
                    let points = min_max(channel(c), fs, scale, buckets);
                    series(&area, &format!("{label} {kind} {name}"), || {
                        chart.draw_series(LineSeries::new(points, colour(c).stroke_width(1)))?;
                        Ok(())
                    })?;
                }
                if let Some(a) = decay {
                    let top = y.end.abs().max(y.start.abs()) / 1.08;
                    series(&area, &format!("{label} window"), || {
                        chart.draw_series(DashedLineSeries::new(
                            (0..=200).map(|k| {
                                let t = x.end * k as f64 / 200.0;
                                (t, top * (-a * t).exp())
                            }),
                            6,
                            4,
                            GREY.stroke_width(2),
                        ))?;
                        Ok(())
                    })?;
                }
                if kind == "force" {
                    let d = record.dominant_force();
                    let f = record.force(d);
                    if let Some((m, v)) = f
                        .iter()
                        .enumerate()
                        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
                    {
                        let peak = (m as f64 / fs, v / scale);
                        series(&area, &format!("{label} impact"), || {
                            chart.draw_series([Circle::new(peak, 5, ALERT.filled())])?;
                            chart.draw_series([EmptyElement::at(peak)
                                + Text::new(
                                    format!("{:.1} {unit} at {:.4} s", peak.1, peak.0),
                                    (10, 0),
                                    TextStyle::from(("sans-serif", font::NOTE).into_font())
                                        .pos(Pos::new(HPos::Left, VPos::Center)),
                                )])?;
                            Ok(())
                        })?;
                    }
                }
                for issue in issues {
                    match *issue {
                        ImpactIssue::DoubleHit {
                            channel,
                            second_s,
                            ratio,
                            ..
                        } if kind == "force" => {
                            let m = ((second_s * fs).round() as usize)
                                .min(record.len().saturating_sub(1));
                            let at = (second_s, record.force(channel)[m] / scale);
                            series(&area, &format!("{label} double hit"), || {
                                chart.draw_series([Cross::new(at, 7, ALERT.stroke_width(3))])?;
                                chart.draw_series([EmptyElement::at(at)
                                    + Text::new(
                                        format!("double hit ({ratio:.2} × peak)"),
                                        (10, -4),
                                        ("sans-serif", font::NOTE)
                                            .into_font()
                                            .color(&ALERT)
                                            .pos(Pos::new(HPos::Left, VPos::Bottom)),
                                    )])?;
                                Ok(())
                            })?;
                        }
                        ImpactIssue::Clipped {
                            channel,
                            value,
                            run,
                            at_s,
                        } if matches!(
                            (channel, kind),
                            (Channel::Force(_), "force")
                                | (Channel::Displacement(_), "displacement")
                        ) =>
                        {
                            // At least 4 % of the axis wide, so a short run shows past the
                            // impact marker.
                            let end = (at_s + (run as f64 / fs).max(0.04 * x.end)).min(x.end);
                            let at_s = at_s.min(x.end);
                            let level = (at_s, value / scale);
                            series(&area, &format!("{label} clipped"), || {
                                chart.draw_series(LineSeries::new(
                                    [level, (end, value / scale)],
                                    ALERT.stroke_width(5),
                                ))?;
                                chart.draw_series([EmptyElement::at(level)
                                    + Text::new(
                                        format!(
                                            "clipped: {run} samples at {} {unit}",
                                            tick(&level.1)
                                        ),
                                        (10, 12),
                                        ("sans-serif", font::NOTE)
                                            .into_font()
                                            .color(&ALERT)
                                            .pos(Pos::new(HPos::Left, VPos::Top)),
                                    )])?;
                                Ok(())
                            })?;
                        }
                        _ => {}
                    }
                }
            }
        }
        Ok(())
    })
}

/// The time span of the force plot: for an impulsive record (crest factor ≥ 8) the pulse
/// and what follows it closely — four times the peak's time, at least 80 ms past it, and the
/// force gate and any double hit with a quarter to spare; else the whole record.
fn force_span(
    record: &Record,
    gate: Option<crate::spectra::ForceGate>,
    issues: &[ImpactIssue],
) -> f64 {
    let fs = record.sample_rate();
    let whole = record.len() as f64 / fs;
    let f = record.force(record.dominant_force());
    let mean = f.iter().sum::<f64>() / f.len().max(1) as f64;
    let rms = (f.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / f.len().max(1) as f64).sqrt();
    let Some((m, peak)) = f
        .iter()
        .map(|v| (v - mean).abs())
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return whole;
    };
    if !(rms > 0.0 && peak / rms >= 8.0) {
        return whole;
    }
    let t_peak = m as f64 / fs;
    let mut end = (4.0 * t_peak).max(t_peak + 0.08);
    if let Some(g) = gate {
        end = end.max(1.25 * (g.open_s() + g.taper_s()));
    }
    for issue in issues {
        match *issue {
            ImpactIssue::DoubleHit { second_s, .. } => end = end.max(1.25 * second_s),
            ImpactIssue::Clipped {
                channel: Channel::Force(_),
                at_s,
                run,
                ..
            } => end = end.max(1.25 * (at_s + run as f64 / fs)),
            _ => {}
        }
    }
    // Two significant digits, rounded up: a readable span in the title.
    let step = 10f64.powf(end.log10().floor() - 1.0);
    ((end / step).ceil() * step).min(whole)
}

/// The minimum and maximum of `values` in each of `buckets` equal time slices, in time
/// order, divided by `scale`: a trace of any length drawn with a few points per pixel.
fn min_max(values: &[f64], fs: f64, scale: f64, buckets: usize) -> Vec<(f64, f64)> {
    let len = values.len();
    if len <= 2 * buckets {
        return values
            .iter()
            .enumerate()
            .map(|(m, v)| (m as f64 / fs, v / scale))
            .collect();
    }
    let mut out = Vec::with_capacity(2 * buckets);
    for b in 0..buckets {
        let (lo, hi) = (
            b * len / buckets,
            ((b + 1) * len / buckets).max(b * len / buckets + 1),
        );
        let slice = &values[lo..hi];
        let (mut imin, mut imax) = (0, 0);
        for (k, v) in slice.iter().enumerate() {
            if *v < slice[imin] {
                imin = k;
            }
            if *v > slice[imax] {
                imax = k;
            }
        }
        let (a, b) = (imin.min(imax), imin.max(imax));
        out.push(((lo + a) as f64 / fs, slice[a] / scale));
        if b != a {
            out.push(((lo + b) as f64 / fs, slice[b] / scale));
        }
    }
    out
}

/// IVF convergence: the block-wise relative changes `‖ΔM‖/‖M‖`, `‖ΔC‖/‖C‖`, `‖ΔK‖/‖K‖`
/// (Frobenius norms) per iteration on a log scale (series `mass change`, `damping change`,
/// `stiffness change`). For a method that does not iterate, the figure says so and holds no
/// series.
///
/// # Errors
/// [`Error::Plot`] if plotters fails to draw.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records =
///     ImpactTest { per_direction: 2, noise: 0.05, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let svg = plot::convergence(&id, &FigureOptions::default())?;
/// assert_eq!(svg.matches("class=\"series\"").count(), 3);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn convergence(id: &Identification, options: &FigureOptions) -> Result<String> {
    let history = id.history();
    let (w, h) = options.panel();
    let size = (2 * w + 10, h + 120);
    let floor = 1e-17;
    let blocks: [(&str, Vec<f64>); 3] = [
        ("mass", history.iter().map(|i| i.mass_change).collect()),
        (
            "damping",
            history.iter().map(|i| i.damping_change).collect(),
        ),
        (
            "stiffness",
            history.iter().map(|i| i.stiffness_change).collect(),
        ),
    ];
    let legend = [
        (Key::Line(colour(0)), "‖ΔM‖/‖M‖"),
        (Key::Line(colour(1)), "‖ΔC‖/‖C‖"),
        (Key::Line(colour(2)), "‖ΔK‖/‖K‖"),
    ];
    let title = format!(
        "IVF convergence: {} ({} iterations)",
        id.convergence().name().replace('_', " "),
        history.len()
    );
    render("convergence", size, |root| {
        let body = header(root, &title, if history.is_empty() { &[] } else { &legend })?;
        if history.is_empty() {
            return message(
                &body,
                &format!("method {} does not iterate", id.method().name()),
            );
        }
        let m = history.len();
        let x = 0.5..(m as f64 + 0.5);
        let y = log_span(blocks.iter().flat_map(|b| b.1.iter().map(|v| v.max(floor))));
        let mut chart = ChartBuilder::on(&body)
            .margin(8)
            .margin_right(24)
            .x_label_area_size(X_LABELS)
            .y_label_area_size(Y_LABELS)
            .build_cartesian_2d(x.clone(), y.clone().log_scale())?;
        // Whole iterations only.
        let every = m.div_ceil(12).max(1);
        chart
            .configure_mesh()
            .x_labels(0)
            .y_labels(0)
            .disable_mesh()
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .x_desc("iteration")
            .y_desc("relative change ‖ΔB‖/‖B‖ (Frobenius)")
            .axis_desc_style(("sans-serif", font::DESC))
            .draw()?;
        for v in log_ticks(&y) {
            y_tick(&mut chart, &x, v, &log_tick(&v))?;
        }
        for it in (1..=m).filter(|it| (it - 1) % every == 0) {
            chart.draw_series([EmptyElement::at((it as f64, y.start))
                + Text::new(
                    it.to_string(),
                    (0, 8),
                    TextStyle::from(("sans-serif", font::TICK).into_font())
                        .pos(Pos::new(HPos::Center, VPos::Top)),
                )])?;
        }
        for (c, (name, values)) in blocks.iter().enumerate() {
            let points: Vec<(f64, f64)> = values
                .iter()
                .enumerate()
                .map(|(m, v)| ((m + 1) as f64, v.max(floor)))
                .collect();
            series(&body, &format!("{name} change"), || {
                chart.draw_series(LineSeries::new(
                    points.iter().copied(),
                    // Wider first, so coinciding curves all show.
                    colour(c).stroke_width(2 + 2 * (2 - c) as u32),
                ))?;
                chart.draw_series(
                    points
                        .iter()
                        .map(|&p| Circle::new(p, 3 + (2 - c) as u32, colour(c).filled())),
                )?;
                Ok(())
            })?;
        }
        Ok(())
    })
}
