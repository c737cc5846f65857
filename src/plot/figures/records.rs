//! The time-record figure: force and displacement per record, the impact, double hits,
//! clipping, the force gate and the exponential window marked.

use crate::Choice;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::canvas::{ALERT, GREY, Key, colour, font, header, render, series};
use super::chart::{linear_chart, si_unit, span, tick, titled};
use super::trace::{force_span, min_max};
use crate::error::Result;
use crate::identify::Identification;
use crate::plot::FigureOptions;
use crate::quality::{self, ImpactChecks, ImpactIssue};
use crate::records::Record;
use crate::spectra::Segmentation;
use crate::{Channel, Error};

/// Time records: force (left) and response (right: displacement, velocity or acceleration,
/// as the record says) per record, one row per record.
///
/// Channels are coloured by degree of freedom (series `RECORD force x`, …,
/// `RECORD displacement x`, …). On the force plot the impact is marked at the peak of the
/// dominant force channel (series `RECORD impact`); with `checks`, issues found by
/// [`quality::check_record`] are marked: a double hit by a cross at the second pulse
/// (`RECORD double hit`), a clipped channel by a red bar along the clipped run
/// (`RECORD clipped`). With `id`, its force gate is shaded (`RECORD force gate`) and an
/// exponential window over whole records is drawn, scaled to each plot's largest value
/// (`RECORD window`). Long records are reduced to the minimum and maximum per pixel column,
/// so peaks survive.
///
/// # Errors
/// [`Error::NoRecords`] for an empty slice; [`Error::Plot`] if plotters fails to draw.
///
/// # Examples
/// ```
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::quality::ImpactChecks;
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let svg = plot::records(&records, None, Some(&ImpactChecks::default()), &FigureOptions::default())?;
/// // Per record: two force channels, two displacement channels, the impact.
/// assert_eq!(svg.matches("class=\"series\"").count(), 2 * 5);
/// assert!(svg.contains("displacement (µm)"));
/// // Velocity records: the response panel says so, in its unit.
/// use bearing_ident::Response;
/// let test = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() };
/// let records = test.run_responding(&seed_rig(), &[Response::Velocity; 2])?;
/// let svg = plot::records(&records, None, None, &FigureOptions::default())?;
/// assert!(svg.contains("velocity (mm/s)") && !svg.contains("displacement ("));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn records(
    records: &[Record],
    id: Option<&Identification>,
    checks: Option<&ImpactChecks>,
    options: &FigureOptions,
) -> Result<String> {
    let first = records.first().ok_or(Error::NoRecords)?;
    let n = first.dofs();
    let names = options.axis_names(n);
    let (w, h) = options.panel();
    let (panel_w, row_h) = (w * 5 / 4, (h * 6 / 10).max(180));
    let size = (2 * panel_w + 10, row_h * records.len() as u32 + 80);
    let gate = id.and_then(Identification::force_gate);
    let decay = id
        .filter(|id| id.segmentation() == Segmentation::WholeRecord)
        .and_then(|id| id.window().decay_per_s());
    let issues: Vec<Vec<ImpactIssue>> = records
        .iter()
        .map(|r| checks.map_or_else(Vec::new, |c| quality::check_record(r, c)))
        .collect();
    let any_double = issues
        .iter()
        .flatten()
        .any(|i| matches!(i, ImpactIssue::DoubleHit { .. }));
    let any_clip = issues
        .iter()
        .flatten()
        .any(|i| matches!(i, ImpactIssue::Clipped { .. }));
    let mut legend: Vec<(Key, String)> = names
        .iter()
        .enumerate()
        .map(|(i, a)| (Key::Line(colour(i)), format!("channel {a}")))
        .collect();
    legend.push((Key::Point(ALERT), "impact (peak)".into()));
    if any_double {
        legend.push((Key::Cross(ALERT), "double hit".into()));
    }
    if any_clip {
        legend.push((Key::Line(ALERT), "clipped".into()));
    }
    if gate.is_some() {
        legend.push((Key::Band(RGBColor(0, 158, 115)), "force gate".into()));
    }
    if decay.is_some() {
        legend.push((Key::Dashed(GREY), "exp. window (scaled)".into()));
    }
    render(crate::plot::Figure::Records, size, |root| {
        let legend: Vec<(Key, &str)> = legend.iter().map(|(k, s)| (*k, s.as_str())).collect();
        let body = header(root, "Time records: force and displacement", &legend)?;
        let rows = body.split_evenly((records.len(), 1));
        for ((record, row), issues) in records.iter().zip(&rows).zip(&issues) {
            let label = record.label();
            let fs = record.sample_rate();
            let t_end = (record.len().saturating_sub(1) as f64 / fs).max(1.0 / fs);
            let force_end = force_span(record, gate, issues).min(t_end);
            let (left, right) = row.split_horizontally(panel_w);
            let buckets = (panel_w as usize).max(100);
            // The response panel is named after what its channels measure; a record mixing
            // kinds (e.g. velocity and acceleration) draws them in SI units, unscaled.
            let first = record.response(0);
            let uniform = record.responses().iter().all(|&r| r == first);
            let (response, response_unit) = if uniform {
                (first.name(), first.unit())
            } else {
                ("response", "SI")
            };
            for (area, kind, name, unit) in [
                (&left, "force", "force", "N"),
                (&right, "displacement", response, response_unit),
            ] {
                let channel = |c: usize| match kind {
                    "force" => record.force(c),
                    _ => record.displacement(c),
                };
                let x = 0.0..if kind == "force" { force_end } else { t_end };
                let shown = ((x.end * fs).round() as usize + 1).min(record.len());
                let channel = |c: usize| &channel(c)[..shown];
                let max = (0..n)
                    .flat_map(|c| channel(c).iter().map(|v| v.abs()))
                    .fold(0.0, f64::max);
                let (scale, unit) = if uniform || kind == "force" {
                    si_unit(max, unit)
                } else {
                    (1.0, unit.to_owned())
                };
                let y = span(
                    (0..n).flat_map(|c| channel(c).iter().map(|v| v / scale)),
                    0.08,
                );
                let title = if shown < record.len() {
                    format!("{label}: {name}, first {} s", tick(&x.end))
                } else {
                    format!("{label}: {name}")
                };
                let area = titled(area, &title)?;
                let mut chart = linear_chart(
                    &area,
                    x.clone(),
                    y.clone(),
                    Some("time (s)"),
                    &format!("{name} ({unit})"),
                )?;
                if kind == "force" {
                    if let Some(g) = gate {
                        series(&area, &format!("{label} force gate"), || {
                            let c = RGBColor(0, 158, 115);
                            chart.draw_series([
                                Rectangle::new(
                                    [(0.0, y.start), (g.open_s().min(x.end), y.end)],
                                    c.mix(0.15).filled(),
                                ),
                                Rectangle::new(
                                    [
                                        (g.open_s().min(x.end), y.start),
                                        ((g.open_s() + g.taper_s()).min(x.end), y.end),
                                    ],
                                    c.mix(0.07).filled(),
                                ),
                            ])?;
                            Ok(())
                        })?;
                    }
                }
                for (c, name) in names.iter().enumerate() {
                    let points = min_max(channel(c), fs, scale, buckets);
                    series(&area, &format!("{label} {kind} {name}"), || {
                        chart.draw_series(LineSeries::new(points, colour(c).stroke_width(1)))?;
                        Ok(())
                    })?;
                }
                if let Some(a) = decay {
                    let top = y.end.abs().max(y.start.abs()) / 1.08;
                    series(&area, &format!("{label} window"), || {
                        chart.draw_series(DashedLineSeries::new(
                            (0..=200).map(|k| {
                                let t = x.end * k as f64 / 200.0;
                                (t, top * (-a * t).exp())
                            }),
                            6,
                            4,
                            GREY.stroke_width(2),
                        ))?;
                        Ok(())
                    })?;
                }
                if kind == "force" {
                    let d = record.dominant_force();
                    let f = record.force(d);
                    if let Some((m, v)) = f
                        .iter()
                        .enumerate()
                        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
                    {
                        let peak = (m as f64 / fs, v / scale);
                        series(&area, &format!("{label} impact"), || {
                            chart.draw_series([Circle::new(peak, 5, ALERT.filled())])?;
                            chart.draw_series([EmptyElement::at(peak)
                                + Text::new(
                                    format!("{:.1} {unit} at {:.4} s", peak.1, peak.0),
                                    (10, 0),
                                    TextStyle::from(("sans-serif", font::NOTE).into_font())
                                        .pos(Pos::new(HPos::Left, VPos::Center)),
                                )])?;
                            Ok(())
                        })?;
                    }
                }
                for issue in issues {
                    match *issue {
                        ImpactIssue::DoubleHit {
                            channel,
                            second_s,
                            ratio,
                            ..
                        } if kind == "force" => {
                            let m = ((second_s * fs).round() as usize)
                                .min(record.len().saturating_sub(1));
                            let at = (second_s, record.force(channel)[m] / scale);
                            series(&area, &format!("{label} double hit"), || {
                                chart.draw_series([Cross::new(at, 7, ALERT.stroke_width(3))])?;
                                chart.draw_series([EmptyElement::at(at)
                                    + Text::new(
                                        format!("double hit ({ratio:.2} × peak)"),
                                        (10, -4),
                                        ("sans-serif", font::NOTE)
                                            .into_font()
                                            .color(&ALERT)
                                            .pos(Pos::new(HPos::Left, VPos::Bottom)),
                                    )])?;
                                Ok(())
                            })?;
                        }
                        ImpactIssue::Clipped {
                            channel,
                            value,
                            run,
                            at_s,
                        } if matches!(
                            (channel, kind),
                            (Channel::Force(_), "force")
                                | (Channel::Displacement(_), "displacement")
                        ) =>
                        {
                            // At least 4 % of the axis wide, so a short run shows past the
                            // impact marker.
                            let end = (at_s + (run as f64 / fs).max(0.04 * x.end)).min(x.end);
                            let at_s = at_s.min(x.end);
                            let level = (at_s, value / scale);
                            series(&area, &format!("{label} clipped"), || {
                                chart.draw_series(LineSeries::new(
                                    [level, (end, value / scale)],
                                    ALERT.stroke_width(5),
                                ))?;
                                chart.draw_series([EmptyElement::at(level)
                                    + Text::new(
                                        format!(
                                            "clipped: {run} samples at {} {unit}",
                                            tick(&level.1)
                                        ),
                                        (10, 12),
                                        ("sans-serif", font::NOTE)
                                            .into_font()
                                            .color(&ALERT)
                                            .pos(Pos::new(HPos::Left, VPos::Top)),
                                    )])?;
                                Ok(())
                            })?;
                        }
                        _ => {}
                    }
                }
            }
        }
        Ok(())
    })
}
