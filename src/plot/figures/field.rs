//! The field-identification figure: per bearing, `K(Ω)`, `C(Ω)` and the condition number of
//! the response pair against speed.

use plotters::prelude::*;

use super::canvas::{ALERT, GREY, Key, colour, header, render, series};
use super::chart::{bar_range, draw_points_with_bars, linear_chart, log_chart, log_span, si_unit};
use crate::error::Result;
use crate::field::FieldIdentification;
use crate::plot::FigureOptions;
use crate::tolerance::FIELD_ILL_CONDITIONED_PAIR;

/// Per bearing (one row each): the four elements of `K(Ω)`, of `C(Ω)` (points with `±σ`
/// error bars when known, one colour per element `xx, xy, yx, yy`) and the condition number
/// of the pair `[q¹ q²]` on a log scale with the warning threshold, against speed (rad/s).
/// Speeds where a pair is singular have no points. Series: `K xx brg0`, …, `C yy brg0`,
/// `cond brg0`.
///
/// # Errors
/// [`Error::Plot`](crate::Error::Plot) if plotters fails to draw.
///
/// # Examples
/// ```
/// # use bearing_ident::field::{self, *};
/// # let rotor = BeamRotor { element_lengths: vec![0.15; 6], diameter: 0.05, density: 7850.0,
/// #     young: 2.1e11, poisson: 0.3,
/// #     disks: vec![Disk { node: 2, mass: 15.0, polar: 0.12, diametral: 0.06 }],
/// #     bearings: vec![BearingSite::new("brg0", 0), BearingSite::new("brg1", 6)] }.model()?;
/// # let probes = [0, 6].into_iter()
/// #     .flat_map(|node| [Direction::X, Direction::Y].map(|dir| Probe { node, dir })).collect();
/// # let at = |node, phase_rad| vec![Imbalance { node, magnitude_kg_m: 1e-4, phase_rad }];
/// # let brg = |_b: usize, _w: f64| BearingCoefficients {
/// #     stiffness: [[2e7, 3e6], [-4e6, 3e7]], damping: [[2e4, 1e3], [-1e3, 3e4]] };
/// # let tests = ImbalanceRuns { speeds_rad_s: vec![100.0, 200.0, 300.0], probes,
/// #     residual: at(3, 1.0), added: [at(2, 0.0), at(5, 2.0)], noise: 0.0, repeats: 1, seed: 1 }
/// #     .simulate(&rotor, brg)?;
/// let id = field::identify(&rotor, &tests)?;
/// let svg = bearing_ident::plot::field(&id, &Default::default())?;
/// // Two bearings: four K, four C and one condition-number series each.
/// assert_eq!(svg.matches("class=\"series\"").count(), 2 * 9);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn field(id: &FieldIdentification, options: &FigureOptions) -> Result<String> {
    let (w, h) = (options.panel_width.max(200), options.panel_height.max(160));
    let nb = id.bearings().len();
    let speeds = id.speeds_rad_s();
    let (lo, hi) = (
        speeds.first().copied().unwrap_or(0.0),
        speeds.last().copied().unwrap_or(1.0),
    );
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.05 * hi.abs().max(1.0)
    };
    let x = (lo - pad)..(hi + pad);
    let with_bars = id
        .bearings()
        .iter()
        .flat_map(|b| b.coefficients.iter().flatten())
        .any(|c| c.stiffness_std.is_some());
    let title = format!(
        "Bearing coefficients K(Ω) = Re Z, C(Ω) = Im Z/Ω{} and condition numbers",
        if with_bars { " ± σ" } else { "" }
    );
    let elements = ["xx", "xy", "yx", "yy"];
    let legend: Vec<(Key, &str)> = elements
        .iter()
        .enumerate()
        .map(|(e, name)| (Key::Point(colour(e)), *name))
        .collect();
    render(
        crate::plot::Figure::Field,
        (3 * w + 10, h * nb as u32 + 80),
        |root| {
            let body = header(root, &title, &legend)?;
            for (b, row) in body.split_evenly((nb, 3)).chunks(3).enumerate() {
                let brg = &id.bearings()[b];
                for (panel, name, unit) in [(&row[0], "K", "N/m"), (&row[1], "C", "N·s/m")] {
                    let points: Vec<Vec<(f64, f64, Option<f64>)>> = (0..4)
                        .map(|e| {
                            let (i, j) = (e / 2, e % 2);
                            speeds
                                .iter()
                                .zip(&brg.coefficients)
                                .filter_map(|(&w, c)| {
                                    c.map(|c| match name {
                                        "K" => {
                                            (w, c.stiffness[i][j], c.stiffness_std.map(|s| s[i][j]))
                                        }
                                        _ => (w, c.damping[i][j], c.damping_std.map(|s| s[i][j])),
                                    })
                                })
                                .collect()
                        })
                        .collect();
                    let all: Vec<(f64, f64, Option<f64>)> = points.concat();
                    let range = if all.is_empty() {
                        -1.0..1.0
                    } else {
                        bar_range(&all, &[])
                    };
                    let (scale, unit) = si_unit(range.start.abs().max(range.end.abs()), unit);
                    let y = (range.start / scale)..(range.end / scale);
                    let mut chart = linear_chart(
                        panel,
                        x.clone(),
                        y.clone(),
                        Some("speed Ω (rad/s)"),
                        &format!("{} {name} ({unit})", brg.tag),
                    )?;
                    for (e, pts) in points.iter().enumerate() {
                        let scaled: Vec<(f64, f64, Option<f64>)> = pts
                            .iter()
                            .map(|&(w, v, s)| (w, v / scale, s.map(|s| s / scale)))
                            .collect();
                        series(
                            panel,
                            &format!("{name} {} {}", elements[e], brg.tag),
                            || {
                                draw_points_with_bars(&mut chart, &scaled, &y, colour(e))?;
                                chart.draw_series(LineSeries::new(
                                    scaled.iter().map(|&(w, v, _)| (w, v)),
                                    colour(e).mix(0.5).stroke_width(1),
                                ))?;
                                Ok(())
                            },
                        )?;
                    }
                }
                let conds: Vec<(f64, f64)> = speeds
                    .iter()
                    .zip(&brg.condition_number)
                    .filter(|(_, c)| c.is_finite())
                    .map(|(&w, &c)| (w, c))
                    .collect();
                let y = log_span(
                    conds
                        .iter()
                        .map(|p| p.1)
                        .chain([1.0, 2.0 * FIELD_ILL_CONDITIONED_PAIR]),
                );
                let panel = &row[2];
                let mut chart = log_chart(
                    panel,
                    x.clone(),
                    y,
                    Some("speed Ω (rad/s)"),
                    &format!("{} cond [q¹ q²]", brg.tag),
                )?;
                chart.draw_series(LineSeries::new(
                    [
                        (x.start, FIELD_ILL_CONDITIONED_PAIR),
                        (x.end, FIELD_ILL_CONDITIONED_PAIR),
                    ],
                    ALERT.mix(0.6).stroke_width(1),
                ))?;
                series(panel, &format!("cond {}", brg.tag), || {
                    chart.draw_series(LineSeries::new(conds.clone(), GREY.stroke_width(1)))?;
                    chart.draw_series(conds.iter().map(|&p| Circle::new(p, 3, GREY.filled())))?;
                    Ok(())
                })?;
            }
            Ok(())
        },
    )
}
