//! The impedance figure: `Re H_ij` and `Im H_ij` with error bars, against the fitted
//! `K − ω²M` and `ωC`.

use crate::Choice;
use plotters::prelude::*;

use super::canvas::{Key, MEASURED, MODEL, header, render, series};
use super::chart::{
    MODEL_POINTS, draw_points_with_bars, freq_range, grid_size, linear_chart, model_freqs,
    scaled_panel, stacked, titled,
};
use crate::error::Result;
use crate::identify::Identification;
use crate::plot::FigureOptions;

/// Impedance `H_ij`: `Re H_ij` with the fitted `K − ω²M` above `Im H_ij` with the fitted
/// `ωC`, in an `n × n` grid.
///
/// Units are N/m with an SI prefix chosen per plot. When the FRF carries a variance
/// ([`Frf::impedance_variance`](crate::Frf::impedance_variance)), every measured point has an
/// error bar of `±σ`, `σ² = E|δH_ij|²/2` (the real and imaginary parts each carry half).
/// Lines denser than one per four pixel columns are drawn as a line through their extremes
/// per pixel column, over the band their error bars cover.
/// Series, per element: `Re H ij measured`, `Re H ij model K − ω²M`, `Im H ij measured`,
/// `Im H ij model ωC`.
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
    render(
        crate::plot::Figure::Impedance,
        grid_size(options, n),
        |root| {
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
                    let panel = scaled_panel(points, fit, "N/m");
                    let x_desc = (part == "Im").then_some("frequency (Hz)");
                    let mut chart = linear_chart(
                        area,
                        x.clone(),
                        panel.y.clone(),
                        x_desc,
                        &format!("{part} H ({})", panel.unit),
                    )?;
                    series(area, &format!("{part} H {el} measured"), || {
                        draw_points_with_bars(&mut chart, &panel.points, &panel.y, MEASURED)
                    })?;
                    series(area, &format!("{part} H {el} model {model_name}"), || {
                        chart.draw_series(LineSeries::new(
                            panel.model.iter().copied(),
                            MODEL.stroke_width(2),
                        ))?;
                        Ok(())
                    })?;
                }
            }
            Ok(())
        },
    )
}
