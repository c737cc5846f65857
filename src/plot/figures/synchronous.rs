//! The synchronous figure of a campaign: each point's `K`, `C` at its running speed against the
//! speed, with error bars and the predictions of the plan.

use plotters::prelude::*;
use serde_json::Value as Json;

use super::campaign::label;
use super::canvas::{DARK, Key, colour, header, render, series};
use super::chart::{bar_range, draw_points_with_bars, linear_chart, si_unit};
use crate::campaign::Campaign;
use crate::error::{Error, Result};
use crate::plot::FigureOptions;

/// One point of the figure: speed (rpm), its synchronous `K` and `C` with their σ (`n × n`,
/// rows), its index among the campaign's points.
struct Point {
    rpm: f64,
    values: [Vec<Vec<f64>>; 2],
    std: [Option<Vec<Vec<f64>>>; 2],
    index: usize,
}

/// A series: its label and its points by speed.
type Series = (String, Vec<Point>);

/// The `n × n` matrix `key` of a point's JSON `synchronous`.
fn matrix(sync: &Json, key: &str, n: usize) -> Option<Vec<Vec<f64>>> {
    let rows: Vec<Vec<f64>> = serde_json::from_value(sync.get(key)?.clone()).ok()?;
    (rows.len() == n && rows.iter().all(|r| r.len() == n)).then_some(rows)
}

/// The points with synchronous coefficients, grouped by the values of the conditions other
/// than `speed` (first-seen order), each group by speed.
fn groups(campaign: &Campaign) -> Vec<Series> {
    let speed = campaign
        .plan
        .conditions
        .iter()
        .position(|c| c.name == "speed");
    let mut out: Vec<Series> = Vec::new();
    for (index, p) in campaign.points.iter().enumerate() {
        let Ok(fit) = &p.result else { continue };
        let n = fit.coefficients.dofs();
        let Some(sync) = fit.json.get("synchronous").filter(|s| !s.is_null()) else {
            continue;
        };
        let (Some(hz), Some(k), Some(c)) = (
            sync.get("frequency_hz").and_then(Json::as_f64),
            matrix(sync, "K", n),
            matrix(sync, "C", n),
        ) else {
            continue;
        };
        let point = Point {
            rpm: 60.0 * hz,
            values: [k, c],
            std: [matrix(sync, "K_std", n), matrix(sync, "C_std", n)],
            index,
        };
        let name = label(campaign, index, speed);
        match out.iter_mut().find(|g| g.0 == name) {
            Some(g) => g.1.push(point),
            None => out.push((name, vec![point])),
        }
    }
    for g in &mut out {
        g.1.sort_by(|a, b| a.rpm.total_cmp(&b.rpm));
    }
    out
}

/// The synchronous coefficients of `campaign`'s points against their speed: each point's
/// `K(ω)` and `C(ω)` at `ω` equal to its speed (JSON `synchronous`, see
/// [`Synchronous`](crate::rotor::Synchronous)) with `±σ` bars, `K` in the upper `n × n`
/// panels and `C` in the lower, one series per combination of the other conditions and of
/// what is drawn (`system` or `less NAME`), joined in speed order; each point's `expect`ed
/// reference of that element (its prediction at that speed) as a cross with its `±σ`, the
/// crosses of a series joined by a dashed line (the prediction curve). Points without a speed
/// (and so without synchronous coefficients) are left out.
///
/// # Errors
/// [`Error::InvalidOption`] (`speed`) when no point has synchronous coefficients (the plan
/// has no `speed` condition, or no point has per-line values or an element model there);
/// [`Error::Plot`] if plotters fails.
pub fn synchronous(campaign: &Campaign, options: &FigureOptions) -> Result<String> {
    let groups = groups(campaign);
    let Some(n) = groups.first().map(|g| g.1[0].values[0].len()) else {
        return Err(Error::InvalidOption {
            option: "speed",
            message: "no point has synchronous coefficients: give the plan a `speed` \
                      condition (and per-line values, `--per-frequency`, or an element model)"
                .into(),
        });
    };
    let speeds = groups.iter().flat_map(|g| g.1.iter().map(|p| p.rpm));
    let (lo, hi) = speeds.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    let pad = if hi > lo {
        0.06 * (hi - lo)
    } else {
        0.5 * hi.abs().max(1.0)
    };
    let x_range = (lo - pad)..(hi + pad);
    let mut legend: Vec<(Key, &str)> = groups
        .iter()
        .enumerate()
        .map(|(g, (name, _))| (Key::Point(colour(g)), name.as_str()))
        .collect();
    let any_prediction = groups.iter().flat_map(|g| &g.1).any(|p| {
        campaign.points[p.index]
            .result
            .as_ref()
            .is_ok_and(|f| f.checks.iter().any(|c| "KC".contains(c.coefficient.block)))
    });
    if any_prediction {
        legend.push((Key::Dashed(DARK), "prediction ± σ"));
    }
    let (w, h) = (options.panel_width.max(200), options.panel_height.max(160));
    let axes = crate::campaign::axis_names(n);
    render(
        crate::plot::Figure::Synchronous,
        (w * n as u32 + 10, 2 * h * n as u32 + 80),
        |root| {
            let body = header(root, "synchronous K, C against speed (± σ)", &legend)?;
            for (e, panel) in body.split_evenly((2 * n, n)).iter().enumerate() {
                let (block, r, c) = (e / (n * n), (e / n) % n, e % n);
                let (letter, unit) = [('K', "N/m"), ('C', "N·s/m")][block];
                let element = format!("{letter}_{}{} sync", axes[r], axes[c]);
                let per_group: Vec<Vec<(f64, f64, Option<f64>)>> = groups
                    .iter()
                    .map(|g| {
                        g.1.iter()
                            .map(|p| {
                                let sd = p.std[block].as_ref().map(|s| s[r][c]);
                                (p.rpm, p.values[block][r][c], sd)
                            })
                            .collect()
                    })
                    .collect();
                let predictions: Vec<Vec<(f64, f64, Option<f64>)>> = groups
                    .iter()
                    .map(|g| {
                        g.1.iter()
                            .flat_map(|p| {
                                campaign.points[p.index]
                                    .result
                                    .as_ref()
                                    .map(|f| f.checks.as_slice())
                                    .unwrap_or_default()
                                    .iter()
                                    .filter(|k| {
                                        k.coefficient.block == letter
                                            && k.coefficient.row == r
                                            && k.coefficient.col == c
                                    })
                                    .map(|k| (p.rpm, k.reference, Some(k.reference_std)))
                            })
                            .collect()
                    })
                    .collect();
                let all: Vec<(f64, f64, Option<f64>)> = per_group
                    .iter()
                    .chain(&predictions)
                    .flatten()
                    .copied()
                    .collect();
                let range = bar_range(&all, &[]);
                let (scale, unit) = si_unit(range.start.abs().max(range.end.abs()), unit);
                let y = (range.start / scale)..(range.end / scale);
                let mut chart = linear_chart(
                    panel,
                    x_range.clone(),
                    y.clone(),
                    Some("speed (rpm)"),
                    &format!("{element} ({unit})"),
                )?;
                let scaled = |pts: &[(f64, f64, Option<f64>)]| -> Vec<(f64, f64, Option<f64>)> {
                    pts.iter()
                        .map(|&(xv, v, s)| (xv, v / scale, s.map(|s| s / scale)))
                        .collect()
                };
                let clamp = |v: f64| v.clamp(y.start, y.end);
                // Predictions under the points, so that a point on its prediction shows.
                for (g, pts) in predictions.iter().enumerate() {
                    if pts.is_empty() {
                        continue;
                    }
                    let pts = scaled(pts);
                    series(
                        panel,
                        &format!("{element} prediction {}", groups[g].0),
                        || {
                            chart.draw_series(DashedLineSeries::new(
                                pts.iter().map(|&(xv, v, _)| (xv, clamp(v))),
                                6,
                                4,
                                DARK.mix(0.7).stroke_width(1),
                            ))?;
                            chart.draw_series(pts.iter().map(|&(xv, v, s)| {
                                let s = s.unwrap_or(0.0);
                                ErrorBar::new_vertical(
                                    xv,
                                    clamp(v - s),
                                    clamp(v),
                                    clamp(v + s),
                                    DARK.stroke_width(1),
                                    10,
                                )
                            }))?;
                            chart.draw_series(pts.iter().map(|&(xv, v, _)| {
                                Cross::new((xv, clamp(v)), 5, DARK.stroke_width(2))
                            }))?;
                            Ok(())
                        },
                    )?;
                }
                for (g, pts) in per_group.iter().enumerate() {
                    let pts = scaled(pts);
                    series(panel, &format!("{element} {}", groups[g].0), || {
                        draw_points_with_bars(&mut chart, &pts, &y, colour(g))?;
                        chart.draw_series(LineSeries::new(
                            pts.iter().map(|&(xv, v, _)| (xv, clamp(v))),
                            colour(g).mix(0.5).stroke_width(1),
                        ))?;
                        Ok(())
                    })?;
                }
            }
            Ok(())
        },
    )
}
