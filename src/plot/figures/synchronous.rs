//! The synchronous figure of a campaign: each point's `K`, `C` at its running speed against the
//! speed, with error bars and the predictions of the plan.

use serde_json::Value as Json;

use super::campaign::{Points, condition_panel, label, x_span};
use super::canvas::{DARK, Key, colour, header, render};
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
    let x_range = x_span(groups.iter().flat_map(|g| g.1.iter().map(|p| p.rpm)));
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
                let per_group: Vec<Points> = groups
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
                let predictions: Vec<Points> = groups
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
                let references: Vec<(String, Points)> = groups
                    .iter()
                    .map(|g| format!("{element} prediction {}", g.0))
                    .zip(predictions)
                    .collect();
                let groups: Vec<(&str, Points)> =
                    groups.iter().map(|g| g.0.as_str()).zip(per_group).collect();
                condition_panel(
                    panel,
                    (&x_range, "speed (rpm)"),
                    &element,
                    unit,
                    &groups,
                    &references,
                    true,
                )?;
            }
            Ok(())
        },
    )
}
