//! The per-frequency figure: `K_ij(ω)` and `C_ij(ω)` line by line against the constant fit.

use plotters::prelude::*;

use super::canvas::{GREY, Key, MEASURED, MODEL, header, render, series};
use super::chart::{
    draw_points_with_bars, freq_range, grid_size, linear_chart, scaled_panel, stacked, titled,
};
use crate::element::Curve;
use crate::error::Result;
use crate::identify::Identification;
use crate::plot::FigureOptions;

/// The colours of the families a selection tried besides the chosen one.
const OTHERS: [RGBColor; 3] = [GREY, RGBColor(0, 150, 80), RGBColor(150, 0, 150)];

/// Frequency-dependent `K_ij(ω)` above `C_ij(ω)`, line by line with error bars, and the
/// constant fit (or the element model's curve and, dashed, every other family it tried), in
/// an `n × n` grid.
///
/// From [`Identification::per_frequency`]: `K(ω) = Re H + ω²M`, `C(ω) = Im H/ω` with the
/// fitted `M` (and the exponential window's correction). Error bars `±σ` when the FRF
/// carries a variance. Lines denser than one per four pixel columns are drawn as a line
/// through their extremes per pixel column, over the band their error bars cover. Series, per element: `K ij(ω)`, `K ij <family>` for each other family tried,
/// `K ij fit`, then the same for `C`.
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
    // The element model's curve (the constant fit without one) and the other families the
    // selection fitted, all with the mass of the per-line values so that they compare.
    let model = id.model();
    let curves: Vec<(String, Curve)> = model
        .map(|m| {
            let chosen = (format!("model {}", m.family()), m.curve().clone());
            let others = m
                .other_fits()
                .iter()
                .map(|fit| (fit.family().to_string(), Curve::of(fit, freqs, co.mass())));
            std::iter::once(chosen).chain(others).collect()
        })
        .unwrap_or_default();
    let mut legend: Vec<(Key, String)> = vec![(Key::Point(MEASURED), "per line".into())];
    match curves.split_first() {
        None => legend.push((Key::Line(MODEL), "constant fit".into())),
        Some(((chosen, _), others)) => {
            legend.push((Key::Line(MODEL), chosen.clone()));
            for (k, (name, _)) in others.iter().enumerate() {
                legend.push((Key::Dashed(OTHERS[k % OTHERS.len()]), name.clone()));
            }
        }
    }
    let legend: Vec<(Key, &str)> = legend.iter().map(|(k, s)| (*k, s.as_str())).collect();
    let title = format!(
        "Per-frequency stiffness K(ω) = Re H + ω²M and damping C(ω) = Im H/ω{}",
        if with_bars { " ± σ" } else { "" }
    );
    render(
        crate::plot::Figure::PerFrequency,
        grid_size(options, n),
        |root| {
            let body = header(root, &title, &legend)?;
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
                // A curve's element (i, j) of K (`stiffness`) or C over its lines.
                let trace = |c: &Curve, stiffness: bool| -> Vec<(f64, f64)> {
                    let blocks = if stiffness { &c.stiffness } else { &c.damping };
                    c.frequency_hz
                        .iter()
                        .zip(blocks)
                        .map(|(&f, m)| (f, m[(i, j)]))
                        .collect()
                };
                for (area, name, points, fitted, unit) in [
                    (&top, "K", &k_points, co.stiffness()[(i, j)], "N/m"),
                    (&bottom, "C", &c_points, co.damping()[(i, j)], "N·s/m"),
                ] {
                    let fit = match curves.first() {
                        Some((_, c)) => trace(c, name == "K"),
                        None => vec![(x.start, fitted), (x.end, fitted)],
                    };
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
                    // The other families, dashed, clipped to the panel's range.
                    for (k, (family, curve)) in curves.iter().skip(1).enumerate() {
                        let color = OTHERS[k % OTHERS.len()];
                        let y = &panel.y;
                        let line: Vec<(f64, f64)> = trace(curve, name == "K")
                            .into_iter()
                            .map(|(f, v)| (f, (v / panel.scale).clamp(y.start, y.end)))
                            .collect();
                        series(area, &format!("{name} {el} {family}"), || {
                            chart.draw_series(DashedLineSeries::new(
                                line,
                                8,
                                5,
                                color.stroke_width(2),
                            ))?;
                            Ok(())
                        })?;
                    }
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
