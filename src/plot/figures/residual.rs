//! The model-check figure: the fit's residual over frequency against the pure-error band.

use plotters::prelude::*;

use super::canvas::{ALERT, DARK, Key, MEASURED, header, message, render, series};
use super::chart::{column_extremes, columns, freq_range, log_chart, log_span, one_by_one};
use crate::error::Result;
use crate::identify::{Identification, Verdict};
use crate::plot::FigureOptions;
use crate::statistics::chi2_upper_point;

/// The model check line by line: each line's residual over the noise measured without the
/// model ([`ModelCheck::line_ratios`](crate::identify::ModelCheck::line_ratios), about 1 where
/// the model fits) on a log scale, against the band a right model stays within at 95 %
/// (2.5 % and 97.5 % points of `χ²₂ₙ²/2n²`, series `pure-error band`). Lines far above the
/// band show where the model misses (marked in red; of lines denser than one per four pixel
/// columns, drawn as a line through their extremes per pixel column, only those are marked);
/// a run of lines above it, what it misses. Untested
/// checks (no replicates, or maximum likelihood's cost test) say so and hold no series.
///
/// # Errors
/// [`Error::Plot`](crate::Error::Plot) if plotters fails to draw.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records =
///     ImpactTest { per_direction: 4, noise: 0.05, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let svg = plot::residual(&id, &FigureOptions::default())?;
/// assert!(svg.contains("data-series=\"residual\"") && svg.contains("data-series=\"pure-error band\""));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn residual(id: &Identification, options: &FigureOptions) -> Result<String> {
    let check = id.model_check();
    let n = id.coefficients().dofs();
    let freqs = id.freqs_hz();
    let ratios = &check.line_ratios;
    let points: Vec<(f64, f64)> = freqs
        .iter()
        .zip(ratios)
        .filter_map(|(&f, r)| r.filter(|r| r.is_finite() && *r > 0.0).map(|r| (f, r)))
        .collect();
    let terms = (2 * n * n) as f64;
    let band = (
        chi2_upper_point(0.975, terms)? / terms,
        chi2_upper_point(0.025, terms)? / terms,
    );
    let (w, h) = options.panel();
    let size = (2 * w + 10, h + 120);
    let title = match (&check.verdict, check.ratio(), check.p_value) {
        (Verdict::Untested { reason }, ..) => format!("Model check: untested ({reason})"),
        (v, Some(r), Some(p)) => format!(
            "Model check: {}, χ²/expected = {r:.3}, p = {p:.2e}",
            v.name()
        ),
        (v, ..) => format!("Model check: {}", v.name()),
    };
    let legend = [
        (Key::Line(MEASURED), "residual / pure error, per line"),
        (Key::Line(DARK), "1 (noise only)"),
        (
            Key::Band(RGBColor(0, 158, 115)),
            "95 % band of a right model",
        ),
    ];
    render(crate::plot::Figure::Residual, size, |root| {
        let body = header(root, &title, if points.is_empty() { &[] } else { &legend })?;
        if points.is_empty() {
            let why = if check.line_ratios.is_empty() && check.p_value.is_some() {
                "the maximum-likelihood check tests the cost as a whole, not line by line"
            } else {
                "no pure error: the test needs replicates (sets, averages or periods)"
            };
            return message(&body, why);
        }
        let x = freq_range(freqs);
        let y = log_span(
            points
                .iter()
                .map(|p| p.1)
                .chain([band.0 * 0.8, band.1 * 1.25]),
        );
        let mut chart = log_chart(
            &body,
            x.clone(),
            y.clone(),
            Some("frequency (Hz)"),
            "residual² / pure-error variance (–)",
        )?;
        series(&body, "pure-error band", || {
            chart.draw_series(std::iter::once(Rectangle::new(
                [(x.start, band.0), (x.end, band.1)],
                RGBColor(0, 158, 115).mix(0.18).filled(),
            )))?;
            chart.draw_series(LineSeries::new(
                [(x.start, 1.0), (x.end, 1.0)],
                DARK.stroke_width(1),
            ))?;
            Ok(())
        })?;
        let columns = columns(&chart);
        series(&body, "residual", || {
            chart.draw_series(LineSeries::new(
                column_extremes(points.iter().copied(), &x, columns),
                MEASURED.stroke_width(2),
            ))?;
            if one_by_one(points.len(), columns) {
                chart.draw_series(points.iter().map(|&p| {
                    let colour = if p.1 > band.1 { ALERT } else { MEASURED };
                    Circle::new(p, 3, colour.filled())
                }))?;
            } else {
                // Dense lines: only those above the band marked, the highest per column.
                let above = points.iter().copied().filter(|p| p.1 > band.1);
                let marked = column_extremes(above, &x, columns);
                chart.draw_series(marked.iter().map(|&p| Circle::new(p, 3, ALERT.filled())))?;
            }
            Ok(())
        })?;
        Ok(())
    })
}
