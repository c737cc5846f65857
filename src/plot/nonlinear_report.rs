//! The static HTML report of a nonlinear identification ([`nonlinear_report`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::html::{
    Kind, create_dir, esc, figure_html, page_head, page_tail, warnings_list, write_file,
};
use super::{ReportOptions, coefficient_rows, significant as sig};
use crate::Choice;
use crate::error::Result;
use crate::nonlinear::NonlinearIdentification;

/// Writes `nonlinear.svg` (the figure [`nonlinear`](super::nonlinear)) and an `index.html`
/// into `dir` (created if needed): the linear coefficients with their standard deviations,
/// the nonlinear terms with theirs and their model check, the velocity choice, the warnings,
/// the figure (shown from its file) and `options.text` folded at the end. Returns the files
/// written.
///
/// # Errors
/// [`Error::Io`](crate::Error::Io) if the directory or a file cannot be written, or the
/// directory holds an `index.html` that is not a nonlinear identification's report;
/// [`Error::Plot`](crate::Error::Plot) if a figure fails.
///
/// # Examples
/// ```
/// use bearing_ident::nonlinear::{Regressor, ReversePath};
/// use bearing_ident::plot::{ReportOptions, nonlinear_report};
/// use bearing_ident::Record;
/// let (fs, n) = (256.0, 4096);
/// let x: Vec<f64> = (0..n)
///     .map(|s| (5..=40).map(|hz| 1e-3 * ((hz as f64) * std::f64::consts::TAU * s as f64 / fs + hz as f64).sin()).sum())
///     .collect();
/// let f: Vec<f64> = x.iter().map(|x| 1e4 * x + 1e9 * x * x * x).collect();
/// let id = ReversePath::new(8.0, 36.0, &[Regressor::Cubic])
///     .segment_len(256)
///     .identify(&[Record::new("cubic", fs, vec![f], vec![x])?])?;
/// let tmp = tempfile::tempdir().unwrap();
/// let dir = tmp.path().join("report");
/// let written = nonlinear_report(&id, &dir, &ReportOptions::default())?;
/// assert_eq!(written.len(), 2);
/// let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
/// assert!(html.contains("cubic[0]") && html.contains("<img src=\"nonlinear.svg\""));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn nonlinear_report(
    id: &NonlinearIdentification,
    dir: &Path,
    options: &ReportOptions,
) -> Result<Vec<PathBuf>> {
    create_dir(dir, Kind::Nonlinear)?;
    let svg = super::nonlinear(id, &options.figure)?;
    let mut written = vec![write_file(&dir.join("nonlinear.svg"), &svg)?];
    let html = page(id, options);
    written.push(write_file(&dir.join("index.html"), &html)?);
    Ok(written)
}

fn page(id: &NonlinearIdentification, options: &ReportOptions) -> String {
    let mut h = String::new();
    let n = id.coefficients().dofs();
    let names = options.figure.axis_names(n);
    page_head(&mut h, options, Kind::Nonlinear);
    let freqs = id.freqs_hz();
    let _ = writeln!(
        h,
        "<h2 id=\"coefficients\">Linear coefficients</h2>\n<p>Reverse path (direct form), {} \
         lines {:.3}–{:.3} Hz, {} Welch averages of {} samples; linear part fitted by {}; \
         standard deviations by the jackknife over {} blocks of segments.</p>",
        freqs.len(),
        freqs.first().copied().unwrap_or(f64::NAN),
        freqs.last().copied().unwrap_or(f64::NAN),
        id.averages(),
        id.segment_len(),
        id.fit().method().name(),
        id.jackknife_blocks()
    );
    let _ = writeln!(
        h,
        "<table>\n<tr><th>coefficient</th><th>value</th><th>±1σ</th></tr>"
    );
    for row in coefficient_rows(id.coefficients(), id.std_dev(), None, None, &names) {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(&row.label),
            esc(&row.value),
            esc(&row.std_dev)
        );
    }
    let _ = writeln!(h, "</table>");
    let _ = writeln!(
        h,
        "<h2 id=\"terms\">Nonlinear terms</h2>\n<table>\n<tr><th>term</th><th>value</th>\
         <th>±1σ</th><th>unit</th><th>Im/Re</th><th>slope</th><th>input coherence</th>\
         <th>check</th></tr>"
    );
    for (t, c) in id.terms().iter().zip(id.checks()) {
        let verdict = if c.misfit {
            "<span class=\"warn\">does not fit</span>"
        } else if c.collinear {
            "<span class=\"warn\">collinear</span>"
        } else {
            "fits"
        };
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.4}</td><td>{:+.2} %</td>\
             <td>{:.4}</td><td>{verdict}</td></tr>",
            esc(&t.term.label()),
            sig(t.value, 6),
            t.std.map_or("—".to_string(), |s| sig(s, 3)),
            esc(t.unit()),
            c.imaginary_ratio,
            100.0 * c.slope,
            c.input_coherence
        );
    }
    let v = id.velocity();
    let sources: Vec<&str> = v.sources.iter().map(|r| r.name()).collect();
    let _ = writeln!(
        h,
        "</table>\n<p>Velocities: {} from {}{}.</p>",
        v.differentiation.name(),
        sources.join(", "),
        v.differentiation
            .cutoff_hz()
            .map_or(String::new(), |c| format!(", cutoff {c} Hz"))
    );
    let _ = writeln!(h, "<h2 id=\"diagnostics\">Diagnostics</h2>");
    let _ = writeln!(
        h,
        "<p>Smallest multiple coherence of a force on the inputs: {:.4}.</p>",
        id.min_output_coherence()
    );
    warnings_list(&mut h, id.warnings());
    let caption = format!(
        "Coefficient spectra Âⱼ(ω) per term, ± σ from {} Welch averages: a regressor that \
         describes the element gives a flat real part on the fitted constant and an imaginary \
         part about zero.",
        id.averages()
    );
    figure_html(&mut h, "nonlinear", None, "nonlinear.svg", &caption);
    page_tail(&mut h, options);
    h
}
