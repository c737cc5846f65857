//! The per-frequency figure: `K_ij(ω)` and `C_ij(ω)` line by line against the constant fit.

use plotters::prelude::*;

use super::canvas::{Key, MEASURED, MODEL, header, render, series};
use super::chart::{
    draw_points_with_bars, freq_range, grid_size, linear_chart, scaled_panel, stacked, titled,
};
use crate::error::Result;
use crate::identify::Identification;
use crate::plot::FigureOptions;

/// Frequency-dependent `K_ij(ω)` above `C_ij(ω)`, line by line with error bars, and the
/// constant fit, in an `n × n` grid.
///
/// From [`Identification::per_frequency`]: `K(ω) = Re H + ω²M`, `C(ω) = Im H/ω` with the
/// fitted `M` (and the exponential window's correction). Error bars `±σ` when the FRF
/// carries a variance. Lines denser than one per four pixel columns are drawn as a line
/// through their extremes per pixel column, over the band their error bars cover. Series, per element: `K ij(ω)`, `K ij fit`, `C ij(ω)`, `C ij fit`.
///
/// # Errors
/// As [`Identification::per_frequency`]; [`Error::Plot`](crate::Error::Plot) if plotters fails
/// to draw.
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
    render(
        crate::plot::Figure::PerFrequency,
        grid_size(options, n),
        |root| {
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
                    let panel = scaled_panel(points, &fit, unit);
                    let x_desc = (name == "C").then_some("frequency (Hz)");
                    let mut chart = linear_chart(
                        area,
                        x.clone(),
                        panel.y.clone(),
                        x_desc,
                        &format!("{name} ({})", panel.unit),
                    )?;
                    series(area, &format!("{name} {el}(ω)"), || {
                        draw_points_with_bars(&mut chart, &panel.points, &panel.y, MEASURED)
                    })?;
                    series(area, &format!("{name} {el} fit"), || {
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
