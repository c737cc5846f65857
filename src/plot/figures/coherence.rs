//! The coherence and conditioning figure: multiple coherence per output, condition number per
//! line, their thresholds, the band and the lines dropped.

use plotters::prelude::*;

use super::canvas::{ALERT, DARK, GREY, Key, colour, header, message, render, series};
use super::chart::{column_extremes, columns, linear_chart, log_chart, log_span, one_by_one, tick};
use crate::error::Result;
use crate::identify::Identification;
use crate::plot::FigureOptions;

/// Multiple coherence per output and condition number per line, with the thresholds.
///
/// Upper plot: the multiple coherence `γ²_{i:f}` of every output `i` (one series each,
/// `coherence x`, …; left out with a note when the spectra carry none, as for paired sets
/// with one record per excitation). Lower plot: the condition number per line (log scale,
/// series `condition number`) with the warning and refusal thresholds of the identification's
/// [`ConditionLimits`](crate::ConditionLimits) (series `warn limit`, `refuse limit`). On both,
/// the band asked for is shaded (series `band`) and lines dropped for low coherence are
/// marked (series `lines dropped`, only when there are some). Lines denser than one per four
/// pixel columns are drawn without markers, through their extremes per pixel column.
///
/// # Errors
/// [`Error::Plot`](crate::Error::Plot) if plotters fails to draw.
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
    render(crate::plot::Figure::Coherence, size, |root| {
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
            let columns = columns(&chart);
            for (i, c) in coherence.iter().enumerate() {
                series(&top, &format!("coherence {}", names[i]), || {
                    chart.draw_series(LineSeries::new(
                        column_extremes(c.iter().copied(), &x, columns),
                        // Earlier outputs drawn wider, so coinciding curves all show.
                        colour(i).stroke_width(2 + 2 * (n - 1 - i) as u32),
                    ))?;
                    if one_by_one(c.len(), columns) {
                        chart.draw_series(c.iter().map(|&p| {
                            Circle::new(p, 2 + (n - 1 - i) as u32, colour(i).filled())
                        }))?;
                    }
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
        let columns = columns(&chart);
        series(&bottom, "condition number", || {
            chart.draw_series(LineSeries::new(
                column_extremes(points.iter().copied(), &x, columns),
                DARK.stroke_width(2),
            ))?;
            if one_by_one(points.len(), columns) {
                chart.draw_series(points.iter().map(|&p| Circle::new(p, 2, DARK.filled())))?;
            }
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
