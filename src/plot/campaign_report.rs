//! The static HTML report of a campaign ([`campaign_report`]): the figures of `K`, `C`, `M`
//! against a condition and the table of points.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::html::{Kind, create_dir, esc, figure_html, page_head, page_tail, write_file};
use super::{ReportOptions, significant as sig};
use crate::Choice;
use crate::campaign::{Campaign, Value};
use crate::error::{Error, Result, excerpt};

/// Writes `stiffness.svg`, `damping.svg`, `mass.svg` (the figure
/// [`campaign`](super::campaign) of each block against condition `x`, by name; the first
/// condition when `None`), `synchronous.svg` when points have synchronous coefficients (the
/// figure [`synchronous`](super::synchronous)) and an `index.html` into `dir` (created if needed): the figures
/// (shown from their files, each stored once), then per point its conditions, the diagonal
/// coefficients `± σ` (`K_xx`, …), the references checked with their z-scores, its warnings
/// or error, and a link to its own report: each
/// point identified in this run gets one under `points/NAME/` ([`report`](super::report),
/// its records read again); a point taken from a cache links its JSON (`NAME.json`, as
/// `campaign --out` writes it). Returns the files written, `index.html` last.
///
/// # Errors
/// [`Error::InvalidOption`] (`x`) for a condition the plan does not have or a plan without
/// conditions; [`Error::Io`] if a file cannot be written, or the directory holds an
/// `index.html` that is not a campaign's report; [`Error::Plot`] if a figure fails.
pub fn campaign_report(
    campaign: &Campaign,
    dir: &Path,
    x: Option<&str>,
    options: &ReportOptions,
) -> Result<Vec<PathBuf>> {
    let conditions = &campaign.plan.conditions;
    let x = match x {
        None if conditions.is_empty() => {
            return Err(Error::InvalidOption {
                option: "x",
                message: "the plan has no [conditions] to draw the coefficients against".into(),
            });
        }
        None => 0,
        Some(name) => conditions
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| Error::InvalidOption {
                option: "x",
                message: format!(
                    "--x `{}`: no such condition; expected one of {}",
                    excerpt(name),
                    conditions
                        .iter()
                        .map(|c| c.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            })?,
    };
    create_dir(dir, Kind::Campaign)?;
    let mut written = Vec::new();
    for (block, file, _) in BLOCKS {
        let svg = super::campaign(campaign, block, x, &options.figure)?;
        written.push(write_file(&dir.join(file), &svg)?);
    }
    let any_synchronous = campaign.points.iter().any(|p| {
        p.result
            .as_ref()
            .is_ok_and(|f| f.json.get("synchronous").is_some_and(|s| !s.is_null()))
    });
    let synchronous = if any_synchronous {
        Some(super::synchronous(campaign, &options.figure)?)
    } else {
        None
    };
    if let Some(svg) = &synchronous {
        written.push(write_file(&dir.join("synchronous.svg"), svg)?);
    }
    // Each point identified in this run (not taken from a cache) gets its own report.
    for p in &campaign.points {
        let Some(outcome) = p.result.as_ref().ok().and_then(|f| f.outcome.as_deref()) else {
            continue;
        };
        let channels = campaign.plan.channels_of(&p.name)?;
        let records = outcome
            .files()
            .iter()
            .map(Path::new)
            .filter(|f| f.exists())
            .take(options.max_records.max(1) * 4)
            .map(|f| crate::job::read_first(f, &channels))
            .collect::<Result<Vec<_>>>()?;
        let point_options = ReportOptions {
            title: format!("Test point {}", p.name),
            context: vec![format!(
                "{} records, excitation {}; part of the campaign ../../index.html.",
                outcome.files().len(),
                outcome.excitation().name()
            )],
            checks: (outcome.excitation() == crate::excitation::Excitation::Impact)
                .then(crate::quality::ImpactChecks::default),
            ..options.clone()
        };
        let folder = dir.join("points").join(point_folder(&p.name));
        written.extend(super::report(
            outcome.identification(),
            &records,
            &folder,
            &point_options,
        )?);
    }
    written.push(write_file(
        &dir.join("index.html"),
        &page(campaign, x, synchronous.is_some(), options),
    )?);
    Ok(written)
}

/// The folder of a point's own report under `points/`: its name as [`json_file_name`]
/// spells files, without the extension.
///
/// [`json_file_name`]: crate::campaign::json_file_name
fn point_folder(name: &str) -> String {
    crate::campaign::json_file_name(name)
        .trim_end_matches(".json")
        .to_owned()
}

/// The blocks drawn, their files and their captions' names.
const BLOCKS: [(char, &str, &str); 3] = [
    ('K', "stiffness.svg", "Stiffness K"),
    ('C', "damping.svg", "Damping C"),
    ('M', "mass.svg", "Added mass M"),
];

fn page(campaign: &Campaign, x: usize, synchronous: bool, options: &ReportOptions) -> String {
    let mut h = String::new();
    page_head(&mut h, options, Kind::Campaign);
    let conditions = &campaign.plan.conditions;
    let _ = writeln!(
        h,
        "<p>{} test points; coefficients against {} ({}). Points with a baseline show the \
         bearing's own (system less the baseline point, variances added).</p>",
        campaign.points.len(),
        esc(&conditions[x].name),
        esc(conditions[x].unit.name())
    );
    for (_, file, name) in BLOCKS {
        let caption = format!(
            "{name} per element against {} (± σ of each point's identification); crosses: \
             independent references ± σ.",
            esc(&conditions[x].name)
        );
        figure_html(&mut h, file.trim_end_matches(".svg"), None, file, &caption);
    }
    if synchronous {
        figure_html(
            &mut h,
            "synchronous",
            None,
            "synchronous.svg",
            "Synchronous K and C per element (each point's K(ω), C(ω) at ω equal to its speed, \
             ± σ) against speed; crosses on a dashed line: the plan's predictions ± σ.",
        );
    }
    let _ = write!(h, "<h2>Points</h2>\n<table>\n<tr><th>point</th>");
    for c in conditions {
        let _ = write!(h, "<th>{} ({})</th>", esc(&c.name), esc(c.unit.name()));
    }
    let _ = writeln!(
        h,
        "<th>diagonal K, C, M ± σ</th><th>references (z)</th><th>warnings</th></tr>"
    );
    for p in &campaign.points {
        // Its own report when it was identified in this run, else its JSON (`--out`).
        let link = match p.result.as_ref().ok().and_then(|f| f.outcome.as_ref()) {
            Some(_) => format!("points/{}/index.html", point_folder(&p.name)),
            None => crate::campaign::json_file_name(&p.name),
        };
        let _ = write!(
            h,
            "<tr><td><a href=\"{}\">{}</a></td>",
            esc(&link),
            esc(&p.name)
        );
        for v in &p.values {
            let _ = write!(
                h,
                "<td>{}</td>",
                esc(&v.as_ref().map_or("—".into(), Value::to_string))
            );
        }
        match &p.result {
            Err(e) => {
                let _ = write!(
                    h,
                    "<td colspan=\"3\" class=\"warn\">{}: {}</td>",
                    esc(&e.kind),
                    esc(&e.message)
                );
            }
            Ok(fit) => {
                let (c, s) = fit.reported();
                let axes = crate::campaign::axis_names(c.dofs());
                let mut cells = Vec::new();
                for (letter, block) in [
                    (
                        'K',
                        crate::Coefficients::stiffness
                            as fn(&crate::Coefficients) -> faer::MatRef<'_, f64>,
                    ),
                    ('C', crate::Coefficients::damping),
                    ('M', crate::Coefficients::mass),
                ] {
                    for (i, a) in axes.iter().enumerate() {
                        let v = block(c)[(i, i)];
                        cells.push(match s {
                            Some(s) => format!(
                                "{letter}_{a}{a} {} ± {}",
                                sig(v, 4),
                                sig(block(s)[(i, i)], 2)
                            ),
                            None => format!("{letter}_{a}{a} {}", sig(v, 4)),
                        });
                    }
                }
                let refs: Vec<String> = fit
                    .checks
                    .iter()
                    .map(|k| {
                        format!(
                            "{} {} ({})",
                            k.coefficient.name(),
                            sig(k.reference, 4),
                            k.z.map_or("—".into(), |z| format!("{z:+.1}"))
                        )
                    })
                    .collect();
                let _ = write!(
                    h,
                    "<td>{}</td><td>{}</td><td{}>{}</td>",
                    esc(&cells.join("; ")),
                    esc(&refs.join("; ")),
                    if fit.warning_kinds.is_empty() {
                        ""
                    } else {
                        " class=\"warn\""
                    },
                    esc(&fit.warnings.join(" | "))
                );
            }
        }
        let _ = writeln!(h, "</tr>");
    }
    let _ = writeln!(h, "</table>");
    page_tail(&mut h, options);
    h
}
