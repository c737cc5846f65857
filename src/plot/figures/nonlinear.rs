//! The nonlinear-term figure: each term's coefficient spectrum $\hat A_j(\omega)$ of the
//! reverse path, real and imaginary parts, against its fitted constant.

use plotters::prelude::*;

use super::canvas::{GREY, Key, MEASURED, MODEL, header, render, series};
use super::chart::{
    draw_points_with_bars, freq_range, linear_chart, scaled_panel, stacked, titled,
};
use crate::error::Result;
use crate::nonlinear::NonlinearIdentification;
use crate::plot::FigureOptions;

/// Per nonlinear term, `Re Âⱼ(ω)` with its fitted constant above `Im Âⱼ(ω)` with zero,
/// line by line with error bars `±σ` (`σ² = E|δÂⱼ|²/2` per part), terms in a grid of two
/// columns (lines denser than one per four pixel columns drawn as a line through their
/// extremes per pixel column, over the band of their error bars). A regressor that describes
/// the element gives a flat real part on its constant and an imaginary part about zero
/// ([`TermCheck`](crate::nonlinear::TermCheck)).
///
/// Series, per term `t` (its [`Term::label`](crate::nonlinear::Term::label)): `Re t`,
/// `t fit`, `Im t`, `Im t zero`.
///
/// # Errors
/// [`Error::Plot`](crate::Error::Plot) if plotters fails to draw.
///
/// # Examples
/// ```
/// use bearing_ident::nonlinear::{Regressor, ReversePath};
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::Record;
/// // A cubic spring under a prescribed multisine motion: f = k x + k₃ x³.
/// let (fs, n) = (256.0, 4096);
/// let x: Vec<f64> = (0..n)
///     .map(|s| (5..=40).map(|hz| 1e-3 * ((hz as f64) * std::f64::consts::TAU * s as f64 / fs + hz as f64).sin()).sum())
///     .collect();
/// let f: Vec<f64> = x.iter().map(|x| 1e4 * x + 1e9 * x * x * x).collect();
/// let id = ReversePath::new(8.0, 36.0, &[Regressor::Cubic])
///     .segment_len(256)
///     .identify(&[Record::new("cubic", fs, vec![f], vec![x])?])?;
/// assert!((id.terms()[0].value / 1e9 - 1.0).abs() < 1e-3);
/// let svg = plot::nonlinear(&id, &FigureOptions::default())?;
/// assert_eq!(svg.matches("class=\"series\"").count(), 4);
/// assert!(svg.contains("cubic[0] fit"));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn nonlinear(id: &NonlinearIdentification, options: &FigureOptions) -> Result<String> {
    let terms = id.terms();
    let count = terms.len().max(1);
    let columns = count.min(2);
    let rows = count.div_ceil(columns);
    let (w, h) = options.panel();
    let size = (w * columns as u32 + 10, h * rows as u32 + 80);
    let freqs = id.freqs_hz();
    let x = freq_range(freqs);
    render(crate::plot::Figure::Nonlinear, size, |root| {
        let body = header(
            root,
            "Nonlinear terms: coefficient spectra Âⱼ(ω) ± σ of the reverse path",
            &[
                (Key::Point(MEASURED), "per line"),
                (Key::Line(MODEL), "fitted constant"),
                (Key::Line(GREY), "zero"),
            ],
        )?;
        if terms.is_empty() {
            return super::canvas::message(&body, "no nonlinear terms");
        }
        for (j, (panel, t)) in body
            .split_evenly((rows, columns))
            .iter()
            .zip(terms)
            .enumerate()
        {
            let label = t.term.label();
            let check = id.checks()[j];
            let panel = titled(
                panel,
                &format!(
                    "{label} = {} {}; Im/Re {:.3}, slope {:+.1} %",
                    crate::plot::significant(t.value, 5),
                    t.unit(),
                    check.imaginary_ratio,
                    100.0 * check.slope
                ),
            )?;
            let (top, bottom) = stacked(&panel);
            let spectrum = id.term_spectrum(j);
            let var = id.term_variance(j);
            let bars =
                |k: usize| (var[k].is_finite() && var[k] > 0.0).then(|| (var[k] / 2.0).sqrt());
            let re: Vec<(f64, f64, Option<f64>)> = freqs
                .iter()
                .enumerate()
                .map(|(k, &f)| (f, spectrum[k].re, bars(k)))
                .collect();
            let im: Vec<(f64, f64, Option<f64>)> = freqs
                .iter()
                .enumerate()
                .map(|(k, &f)| (f, spectrum[k].im, bars(k)))
                .collect();
            for (area, part, points, level, line_name, colour) in [
                (&top, "Re", &re, t.value, format!("{label} fit"), MODEL),
                (&bottom, "Im", &im, 0.0, format!("Im {label} zero"), GREY),
            ] {
                let line = [(x.start, level), (x.end, level)];
                let panel = scaled_panel(points, &line, t.unit());
                let x_desc = (part == "Im").then_some("frequency (Hz)");
                let mut chart = linear_chart(
                    area,
                    x.clone(),
                    panel.y.clone(),
                    x_desc,
                    &format!("{part} Â ({})", panel.unit),
                )?;
                series(area, &format!("{part} {label}"), || {
                    draw_points_with_bars(&mut chart, &panel.points, &panel.y, MEASURED)
                })?;
                series(area, &line_name, || {
                    chart.draw_series(LineSeries::new(
                        panel.model.iter().copied(),
                        colour.stroke_width(2),
                    ))?;
                    Ok(())
                })?;
            }
        }
        Ok(())
    })
}
