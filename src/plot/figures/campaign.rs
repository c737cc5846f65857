//! The campaign figure: one block of coefficients (`K`, `C` or `M`) against a test condition,
//! one panel per element, one series per combination of the other conditions, with error bars
//! and the independent references.

use plotters::prelude::*;

use super::canvas::{Area, DARK, Drawn, Key, colour, header, render, series};
use super::chart::{bar_range, draw_points_with_bars, linear_chart, si_unit};
use crate::campaign::{Campaign, Value};
use crate::error::{Error, Result};
use crate::model::Coefficients;
use crate::plot::FigureOptions;

/// One block of a coefficient set.
type Pick = fn(&Coefficients) -> faer::MatRef<'_, f64>;

/// A series of the figure: its label and, per point, `(x, coefficients, std)`.
type Group<'c> = (
    String,
    Vec<(f64, &'c Coefficients, Option<&'c Coefficients>, usize)>,
);

/// The points of `campaign` with a number for condition `x`, grouped by the values of the
/// other conditions (in first-seen order).
fn groups(campaign: &Campaign, x: usize) -> Vec<Group<'_>> {
    let mut out: Vec<Group<'_>> = Vec::new();
    for (i, p) in campaign.points.iter().enumerate() {
        let (Some(xv), Ok(fit)) = (p.values[x].as_ref().and_then(Value::number), &p.result) else {
            continue;
        };
        let label = label(campaign, i, Some(x));
        let (c, s) = fit.reported();
        match out.iter_mut().find(|g| g.0 == label) {
            Some(g) => g.1.push((xv, c, s, i)),
            None => out.push((label, vec![(xv, c, s, i)])),
        }
    }
    for g in &mut out {
        g.1.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    out
}

/// The series label of point `i`: its values of the conditions other than `skip`, and what
/// is drawn (`system`, or `less NAME`: the system's coefficients and a bearing's own, less a
/// baseline point, are other quantities and never one series).
pub(super) fn label(campaign: &Campaign, i: usize, skip: Option<usize>) -> String {
    let what = match campaign.plan.points[i].baseline {
        Some(j) => format!("less {}", campaign.plan.points[j].name),
        None => "system".to_owned(),
    };
    campaign
        .plan
        .conditions
        .iter()
        .zip(&campaign.points[i].values)
        .enumerate()
        .filter(|(c, _)| Some(*c) != skip)
        .map(|(_, (c, v))| {
            format!(
                "{} = {}",
                c.name,
                v.as_ref().map_or("-".into(), Value::to_string)
            )
        })
        .chain([what])
        .collect::<Vec<_>>()
        .join(", ")
}

/// One block (`'K'`, `'C'` or `'M'`) of `campaign`'s points against condition `x` (an index
/// into the plan's conditions): `n × n` panels, one series per combination of the other
/// conditions and of what is drawn (`system`, or `less NAME`: the bearing's own, the
/// baseline point `NAME` subtracted), `±σ` bars when known, and each point's `expect`ed
/// references of that block as crosses with their own bars (series `reference`). Points without a number for `x` or without a
/// result are left out.
///
/// # Errors
/// [`Error::Plot`] if plotters fails; [`Error::InvalidOption`] (`x`) for a condition index
/// out of range or no point to draw.
pub fn campaign(
    campaign: &Campaign,
    block: char,
    x: usize,
    options: &FigureOptions,
) -> Result<String> {
    let Some(condition) = campaign.plan.conditions.get(x) else {
        return Err(Error::InvalidOption {
            option: "x",
            message: format!("--x: condition {x} of {}", campaign.plan.conditions.len()),
        });
    };
    let groups = groups(campaign, x);
    let Some(n) = groups.first().map(|g| g.1[0].1.dofs()) else {
        return Err(Error::InvalidOption {
            option: "x",
            message: format!(
                "--x {}: no identified point has a number for it",
                condition.name
            ),
        });
    };
    let (name, unit, pick): (&str, &str, Pick) = match block {
        'K' => ("stiffness K", "N/m", Coefficients::stiffness),
        'C' => ("damping C", "N·s/m", Coefficients::damping),
        _ => ("added mass M", "kg", Coefficients::mass),
    };
    let x_range = x_span(groups.iter().flat_map(|g| g.1.iter().map(|p| p.0)));
    let x_desc = format!("{} ({})", condition.name, condition.unit.name());
    let mut legend: Vec<(Key, &str)> = groups
        .iter()
        .enumerate()
        .map(|(g, (label, _))| (Key::Point(colour(g)), label.as_str()))
        .collect();
    let any_reference = campaign.points.iter().any(|p| {
        p.result
            .as_ref()
            .is_ok_and(|f| f.checks.iter().any(|c| c.coefficient.block == block))
    });
    if any_reference {
        legend.push((Key::Cross(DARK), "reference ± σ"));
    }
    let (w, h) = (options.panel_width.max(200), options.panel_height.max(160));
    let axes = crate::campaign::axis_names(n);
    render(
        crate::plot::Figure::Campaign,
        (w * n as u32 + 10, h * n as u32 + 80),
        |root| {
            let body = header(
                root,
                &format!("{name} against {} (± σ)", condition.name),
                &legend,
            )?;
            for (e, panel) in body.split_evenly((n, n)).iter().enumerate() {
                let (r, c) = (e / n, e % n);
                let element = format!("{block}_{}{}", axes[r], axes[c]);
                let per_group: Vec<Points> = groups
                    .iter()
                    .map(|g| {
                        g.1.iter()
                            .map(|&(xv, co, sd, _)| {
                                (xv, pick(co)[(r, c)], sd.map(|s| pick(s)[(r, c)]))
                            })
                            .collect()
                    })
                    .collect();
                let references: Points = groups
                    .iter()
                    .flat_map(|g| g.1.iter())
                    .flat_map(|&(xv, _, _, i)| {
                        campaign.points[i]
                            .result
                            .as_ref()
                            .map(|f| f.checks.as_slice())
                            .unwrap_or_default()
                            .iter()
                            .filter(|k| {
                                k.coefficient.block == block
                                    && k.coefficient.row == r
                                    && k.coefficient.col == c
                            })
                            .map(move |k| (xv, k.reference, Some(k.reference_std)))
                    })
                    .collect();
                let groups: Vec<(&str, Points)> =
                    groups.iter().map(|g| g.0.as_str()).zip(per_group).collect();
                let references = if references.is_empty() {
                    Vec::new()
                } else {
                    vec![(format!("{element} reference"), references)]
                };
                condition_panel(
                    panel,
                    (&x_range, &x_desc),
                    &element,
                    unit,
                    &groups,
                    &references,
                    false,
                )?;
            }
            Ok(())
        },
    )
}

/// The points of one series in a panel: `(x, value, σ)`.
pub(super) type Points = Vec<(f64, f64, Option<f64>)>;

/// The x axis of a figure against a condition: the values' span padded by 6 % on each side
/// (half the value, or 1, about a single value).
pub(super) fn x_span(xs: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    let pad = if hi > lo {
        0.06 * (hi - lo)
    } else {
        0.5 * hi.abs().max(1.0)
    };
    (lo - pad)..(hi + pad)
}

/// One panel of a figure against a condition (`x`: its range and axis name), for the
/// coefficient `element` in `unit` (scaled to the SI prefix of the largest value):
/// `references`, each a named series of crosses with `±σ` bars drawn under the points (and
/// joined by a dashed line when `joined`: a prediction curve), then each of `groups` (label,
/// points) in its colour with `±σ` bars, joined in order.
pub(super) fn condition_panel(
    panel: &Area<'_>,
    x: (&std::ops::Range<f64>, &str),
    element: &str,
    unit: &str,
    groups: &[(&str, Points)],
    references: &[(String, Points)],
    joined: bool,
) -> Drawn {
    let all: Points = groups
        .iter()
        .map(|g| &g.1)
        .chain(references.iter().map(|r| &r.1))
        .flatten()
        .copied()
        .collect();
    let range = bar_range(&all, &[]);
    let (scale, unit) = si_unit(range.start.abs().max(range.end.abs()), unit);
    let y = (range.start / scale)..(range.end / scale);
    let mut chart = linear_chart(
        panel,
        x.0.clone(),
        y.clone(),
        Some(x.1),
        &format!("{element} ({unit})"),
    )?;
    let scaled = |pts: &[(f64, f64, Option<f64>)]| -> Points {
        pts.iter()
            .map(|&(xv, v, s)| (xv, v / scale, s.map(|s| s / scale)))
            .collect()
    };
    let clamp = |v: f64| v.clamp(y.start, y.end);
    // References under the points, so that a point on its reference shows.
    for (name, pts) in references.iter().filter(|r| !r.1.is_empty()) {
        let pts = scaled(pts);
        series(panel, name, || {
            if joined {
                chart.draw_series(DashedLineSeries::new(
                    pts.iter().map(|&(xv, v, _)| (xv, clamp(v))),
                    6,
                    4,
                    DARK.mix(0.7).stroke_width(1),
                ))?;
            }
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
            chart.draw_series(
                pts.iter()
                    .map(|&(xv, v, _)| Cross::new((xv, clamp(v)), 5, DARK.stroke_width(2))),
            )?;
            Ok(())
        })?;
    }
    for (g, (label, pts)) in groups.iter().enumerate() {
        let pts = scaled(pts);
        series(panel, &format!("{element} {label}"), || {
            draw_points_with_bars(&mut chart, &pts, &y, colour(g))?;
            chart.draw_series(LineSeries::new(
                pts.iter().map(|&(xv, v, _)| (xv, clamp(v))),
                colour(g).mix(0.5).stroke_width(1),
            ))?;
            Ok(())
        })?;
    }
    Ok(())
}
