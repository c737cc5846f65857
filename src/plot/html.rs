//! The static HTML report.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::significant as sig;
use super::{Figure, FigureOptions, coefficient_rows};
use crate::Choice;
use crate::error::{Error, Result};
use crate::identify::Identification;
use crate::model::Coefficients;
use crate::quality::ImpactChecks;
use crate::records::Record;

/// What a report shows besides the identification itself.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportOptions {
    /// Heading of the page. Default `"bearing-ident report"`.
    pub title: String,
    /// Lines about the run shown under the heading (files, excitation, …), as plain text.
    pub context: Vec<String>,
    /// A preformatted text report (the command-line tool's table), shown folded at the end.
    pub text: Option<String>,
    /// The true coefficients, when known (simulations): the table adds them and the error.
    pub truth: Option<Coefficients>,
    /// Screening of impact records: issues are marked on the record figure. Default
    /// `Some(ImpactChecks::default())`; `None` for records that are not impacts.
    pub checks: Option<ImpactChecks>,
    /// Records drawn at most (see [`report`]). Default 6.
    pub max_records: usize,
    /// Figure size and axis names.
    pub figure: FigureOptions,
}

impl Default for ReportOptions {
    fn default() -> Self {
        Self {
            title: "bearing-ident report".into(),
            context: Vec::new(),
            text: None,
            truth: None,
            checks: Some(ImpactChecks::default()),
            max_records: 6,
            figure: FigureOptions::default(),
        }
    }
}

/// Writes every figure of `id` as an SVG file into `dir` (created if missing) and an
/// `index.html` that shows them with the coefficient table, the diagnostics and the warnings;
/// returns the paths written, `index.html` last.
///
/// The page is static: no scripts, no style sheets or fonts from elsewhere. Each figure is
/// stored once, as its file beside the page: the page shows it as an image and links to it
/// (opened alone, a figure names each series on hover). The folder is the report. The files
/// are `flexibility.svg`, `impedance.svg`, `coherence.svg`, `per_frequency.svg`,
/// `records.svg` (only with `records`), `convergence.svg` and `residual.svg`. Their size does
/// not grow with the records' length or the number of lines: a series denser than the
/// plot's pixels is drawn by its extremes per pixel column, its error bars as a band.
///
/// The record figure draws at most [`ReportOptions::max_records`] of `records`: the first two
/// of each excitation direction (by [`Record::dominant_force`]), then those with an issue under
/// [`ReportOptions::checks`].
///
/// # Errors
/// [`Error::Io`] if the directory or a file cannot be written, or the directory holds an
/// `index.html` that is not an identification's report (another kind's report is not
/// overwritten); as the figure functions.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::plot::{self, ReportOptions};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let tmp = tempfile::tempdir().unwrap();
/// let dir = tmp.path().join("report");
/// let written = plot::report(&id, &records, &dir, &ReportOptions::default())?;
/// assert_eq!(written.len(), 8);
/// let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
/// assert!(html.contains("<img src=\"impedance.svg\"") && !html.contains("<svg"));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn report(
    id: &Identification,
    records: &[Record],
    dir: &Path,
    options: &ReportOptions,
) -> Result<Vec<PathBuf>> {
    create_dir(dir, Kind::Identification)?;
    let fig = &options.figure;
    let chosen: Vec<Record> = pick_records(records, options.checks.as_ref(), options.max_records)
        .into_iter()
        .map(|r| records[r].clone())
        .collect();
    let mut written = Vec::with_capacity(Figure::REPORT.len() + 1);
    let mut figures = Vec::with_capacity(Figure::REPORT.len());
    for &figure in Figure::REPORT {
        if let Some(svg) = figure.of_report(id, &chosen, options.checks.as_ref(), fig)? {
            written.push(write_file(&dir.join(format!("{figure}.svg")), &svg)?);
            figures.push(figure);
        }
    }
    let html = page(id, options, &figures, records.len(), chosen.len());
    written.push(write_file(&dir.join("index.html"), &html)?);
    Ok(written)
}

/// The window in words, saying that an exponential window's effect has been undone.
fn window_words(window: crate::Window) -> String {
    match window.decay_per_s() {
        Some(_) => format!("{} (coefficients corrected)", window.describe()),
        None => window.describe(),
    }
}

/// The records the report draws: the first two of each excitation direction (the records'
/// dominant force), then any record with an issue, at most `max` in all, in their order.
fn pick_records(records: &[Record], checks: Option<&ImpactChecks>, max: usize) -> Vec<usize> {
    let mut per_direction = std::collections::HashMap::new();
    let mut chosen: Vec<usize> = Vec::new();
    for (r, record) in records.iter().enumerate() {
        let count = per_direction
            .entry(record.dominant_force())
            .or_insert(0usize);
        if *count < 2 {
            *count += 1;
            chosen.push(r);
        }
    }
    if let Some(checks) = checks {
        for (r, record) in records.iter().enumerate() {
            if !chosen.contains(&r) && !crate::quality::check_record(record, checks).is_empty() {
                chosen.push(r);
            }
        }
    }
    chosen.sort_unstable();
    chosen.truncate(max);
    chosen
}

/// A figure of a report's page, stored once as `file` beside the page: an image of it that
/// links to it, under `heading` (if any), with `caption` (HTML, escaped by the caller) and the
/// file's name. The anchor is `fig-STEM`.
pub(super) fn figure_html(
    h: &mut String,
    stem: &str,
    heading: Option<&str>,
    file: &str,
    caption: &str,
) {
    let (stem, file, alt) = (esc(stem), esc(file), esc(heading.unwrap_or(stem)));
    let heading = heading.map_or(String::new(), |t| format!("<h2>{}</h2>\n", esc(t)));
    let _ = writeln!(
        h,
        "<figure id=\"fig-{stem}\">\n{heading}<a href=\"{file}\"><img src=\"{file}\" \
         alt=\"{alt}\"></a>\n<figcaption>{caption} (<a href=\"{file}\">{file}</a>)\
         </figcaption>\n</figure>"
    );
}

/// Every report's page up to its first section: the document head with the style and the
/// report's kind ([`Kind::MARK`]), the title, and the context lines.
pub(super) fn page_head(h: &mut String, options: &ReportOptions, kind: Kind) {
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         {mark}{kind}{end}\n<title>{0}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n\
         <h1>{0}</h1>\n",
        esc(&options.title),
        mark = Kind::MARK,
        kind = kind.name(),
        end = Kind::MARK_END,
    );
    for line in &options.context {
        let _ = writeln!(h, "<p>{}</p>", esc(line));
    }
}

/// Every report's page end: the text report folded (if any), and the closing tags.
pub(super) fn page_tail(h: &mut String, options: &ReportOptions) {
    if let Some(text) = &options.text {
        let _ = writeln!(
            h,
            "<details>\n<summary>Text report</summary>\n<pre>{}</pre>\n</details>",
            esc(text)
        );
    }
    let _ = writeln!(h, "</body>\n</html>");
}

/// The kind of a report. Its page says it in its head
/// (`<meta name="generator" content="bearing-ident KIND report">`), so that a folder holding
/// a report of another kind is refused rather than overwritten, its figures left beside the
/// new page.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// [`report`]: an identification.
    Identification,
    /// [`nonlinear_report`](super::nonlinear_report): a reverse-path identification.
    Nonlinear,
    /// [`field_report`](super::field_report): a field identification.
    Field,
    /// `campaign_report`: a campaign (each point's own report in `points/NAME/`).
    Campaign,
}

impl Kind {
    const ALL: [Kind; 4] = [
        Kind::Identification,
        Kind::Nonlinear,
        Kind::Field,
        Kind::Campaign,
    ];
    /// The page's mark of its kind, before the kind's name.
    const MARK: &'static str = "<meta name=\"generator\" content=\"bearing-ident ";
    /// The mark's end, after the kind's name.
    const MARK_END: &'static str = " report\">";

    /// The kind's name, as the page's mark and the messages say it.
    fn name(self) -> &'static str {
        match self {
            Kind::Identification => "identification",
            Kind::Nonlinear => "nonlinear identification",
            Kind::Field => "field identification",
            Kind::Campaign => "campaign",
        }
    }

    /// `a` or `an`, before [`Kind::name`].
    fn article(self) -> &'static str {
        match self {
            Kind::Identification => "an",
            _ => "a",
        }
    }

    /// The kind a page says it is, if it says one.
    fn of_page(head: &str) -> Option<Kind> {
        let after = &head[head.find(Self::MARK)? + Self::MARK.len()..];
        let name = &after[..after.find(Self::MARK_END)?];
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

/// Creates the folder of a report of `kind` (and its parents). A folder whose `index.html` is
/// not a report of that kind (another command's report, or a page this crate did not write) is
/// refused: writing there would mix two reports.
pub(super) fn create_dir(dir: &Path, kind: Kind) -> Result<()> {
    let refuse = |message: String| Error::Io {
        path: crate::error::excerpt(&dir.display().to_string()),
        message,
    };
    // Said in words: the system's "File exists" does not tell which is wrong.
    if dir.exists() && !dir.is_dir() {
        return Err(refuse("is a file, not a folder for the report".to_owned()));
    }
    let page = dir.join("index.html");
    if page.is_file() {
        use std::io::Read as _;
        let mut head = Vec::new();
        // The mark is in the page's first lines; a page's head is read, not the whole page.
        let read = std::fs::File::open(&page).and_then(|f| f.take(4096).read_to_end(&mut head));
        read.map_err(|e| refuse(format!("index.html: {e}")))?;
        let holds = match Kind::of_page(&String::from_utf8_lossy(&head)) {
            Some(found) if found == kind => None,
            Some(found) => Some(format!("{} {} report", found.article(), found.name())),
            None => Some("an index.html that is not a report of this tool".to_owned()),
        };
        if let Some(holds) = holds {
            return Err(refuse(format!(
                "holds {holds}; give the {} report another folder, or empty this one",
                kind.name()
            )));
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| refuse(e.to_string()))
}

/// The warnings of a result as a list (or that there are none), every report's same section.
pub(super) fn warnings_list(h: &mut String, warnings: &[crate::Warning]) {
    if warnings.is_empty() {
        let _ = writeln!(h, "<p>No warnings.</p>");
    } else {
        let _ = writeln!(h, "<h3>Warnings</h3>\n<ul class=\"warn\">");
        for w in warnings {
            let _ = writeln!(h, "<li>{}</li>", esc(&w.to_string()));
        }
        let _ = writeln!(h, "</ul>");
    }
}

/// Writes `contents` to `path`, mapping failures to [`Error::Io`].
pub(super) fn write_file(path: &Path, contents: &str) -> Result<PathBuf> {
    std::fs::write(path, contents).map_err(|e| Error::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    Ok(path.to_path_buf())
}

/// Escapes text for HTML.
pub(super) fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

pub(super) const STYLE: &str = "body{font-family:sans-serif;max-width:1400px;margin:1em auto;padding:0 1em;\
color:#222}table{border-collapse:collapse;margin:.5em 0}td,th{padding:.2em .7em;\
border-bottom:1px solid #ddd;text-align:right}th{background:#f3f3f3}td:first-child,\
th:first-child{text-align:left}figure{margin:1.5em 0}figure img{max-width:100%;height:auto}\
figcaption{color:#555;max-width:60em}.warn{color:#a00}pre{background:#f6f6f6;padding:1em;\
overflow-x:auto}";

fn page(
    id: &Identification,
    options: &ReportOptions,
    figures: &[Figure],
    total_records: usize,
    drawn_records: usize,
) -> String {
    let mut h = String::new();
    let co = id.coefficients();
    let n = co.dofs();
    let names = options.figure.axis_names(n);
    page_head(&mut h, options, Kind::Identification);
    // Contents.
    let _ = writeln!(
        h,
        "<p><a href=\"#coefficients\">Coefficients</a> · <a href=\"#model-check\">Model check</a>{} \
         · <a href=\"#diagnostics\">Diagnostics</a>",
        if id.model().is_some() {
            " · <a href=\"#element-model\">Element model</a>"
        } else {
            ""
        }
    );
    for figure in figures {
        let _ = write!(h, " · <a href=\"#fig-{figure}\">{}</a>", figure.heading());
    }
    let _ = writeln!(h, "</p>");
    // Coefficients.
    let _ = writeln!(
        h,
        "<h2 id=\"coefficients\">Coefficients</h2>\n<p>Method {}, estimator {}, window {}; \
         uncertainty: {}.</p>",
        id.method().name(),
        id.estimator().name(),
        esc(&window_words(id.window())),
        id.uncertainty().name()
    );
    let _ = write!(
        h,
        "<table>\n<tr><th>coefficient</th><th>value</th><th>±1σ</th><th>95 % interval</th>"
    );
    if options.truth.is_some() {
        let _ = write!(h, "<th>true</th><th>error</th>");
    }
    let _ = writeln!(h, "</tr>");
    let interval = id.interval_95();
    for row in coefficient_rows(
        co,
        id.std_dev(),
        interval.as_ref(),
        options.truth.as_ref(),
        &names,
    ) {
        // The block names and units need no escaping, the axis names may.
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td>",
            esc(&row.label),
            row.value,
            row.std_dev,
            row.interval
        );
        if let (Some(truth), Some(error)) = (&row.truth, &row.error) {
            let _ = write!(h, "<td>{truth}</td><td>{error}</td>");
        }
        let _ = writeln!(h, "</tr>");
    }
    let _ = writeln!(h, "</table>");
    // Modes.
    if let Ok(modes) = id.modes() {
        let _ = writeln!(
            h,
            "<table>\n<tr><th>mode</th><th>natural frequency (Hz)</th><th>±1σ</th>\
             <th>damping ratio</th><th>±1σ</th></tr>"
        );
        let (sf, sz) = (id.natural_frequencies_hz_std(), id.damping_ratios_std());
        let std = |s: &Option<Vec<f64>>, k: usize| {
            s.as_ref()
                .and_then(|s| s.get(k))
                .map_or("—".to_string(), |v| sig(*v, 3))
        };
        for (k, m) in modes.iter().enumerate() {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{:.3}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                k + 1,
                m.natural_frequency_hz,
                std(&sf, k),
                sig(m.damping_ratio, 3),
                std(&sz, k)
            );
        }
        let _ = writeln!(h, "</table>");
    }
    model_check_and_budget(&mut h, id, &names);
    if let Some(model) = id.model() {
        element_model(&mut h, model, &names);
    }
    // Diagnostics.
    let freqs = id.freqs_hz();
    let cond = id.conditioning();
    let limits = cond.limits();
    let _ = writeln!(h, "<h2 id=\"diagnostics\">Diagnostics</h2>\n<ul>");
    let _ = writeln!(
        h,
        "<li>band {}–{} Hz: {} lines used ({:.3}–{:.3} Hz), {} dropped; {} averages</li>",
        super::figures::tick(&id.band().low_hz()),
        super::figures::tick(&id.band().high_hz()),
        freqs.len(),
        freqs.first().copied().unwrap_or(f64::NAN),
        freqs.last().copied().unwrap_or(f64::NAN),
        id.frf().dropped_hz().len(),
        id.frf().averages()
    );
    let _ = writeln!(
        h,
        "<li>condition number: best {:.3}, median {:.3}, worst {:.3} (warn above {}, refuse \
         above {}); {} lines above the warning</li>",
        cond.best(),
        cond.median(),
        cond.worst(),
        sig(limits.warn, 3),
        sig(limits.refuse, 3),
        cond.lines_above_warning()
    );
    if let Some(c) = id.min_coherence() {
        let _ = writeln!(
            h,
            "<li>multiple coherence: min {c:.4} over the lines used</li>"
        );
    }
    let _ = writeln!(
        h,
        "<li>{} iterations, {}; residual ‖AΘ − Ī‖ = {:.4e}</li>",
        id.iterations(),
        id.convergence().name().replace('_', " "),
        id.residual_norm()
    );
    let r2 = id.fit_r2();
    let mut r2_text = String::new();
    for i in 0..n {
        for j in 0..n {
            let _ = write!(r2_text, " {}{} {:.4}", names[i], names[j], r2[(i, j)]);
        }
    }
    let _ = writeln!(h, "<li>flexibility fit r²:{}</li>", esc(&r2_text));
    if drawn_records < total_records {
        let _ = writeln!(
            h,
            "<li>records drawn: {drawn_records} of {total_records}</li>"
        );
    }
    let _ = writeln!(h, "</ul>");
    warnings_list(&mut h, id.warnings());
    // Figures.
    let averages = id.frf().averages();
    let bars = (0..freqs.len()).all(|k| id.frf().impedance_variance(k).is_some());
    for &figure in figures {
        let mut caption = esc(figure.caption());
        if bars && matches!(figure, Figure::Impedance | Figure::PerFrequency) {
            let _ = write!(
                caption,
                " Each error bar is {}.",
                if id.estimator() == crate::Estimator::PairedSets {
                    format!("the scatter of the {averages} paired sets at its line")
                } else {
                    format!("the random error of {averages} averages (records × segments)")
                }
            );
        }
        figure_html(
            &mut h,
            figure.name(),
            Some(figure.heading()),
            &format!("{figure}.svg"),
            &caption,
        );
    }
    page_tail(&mut h, options);
    h
}

/// The element model: its family, poles and residues' diagonal with σ, the crossover of
/// `C_eff`, and every family the selection tried with its numbers and verdict.
fn element_model(h: &mut String, model: &crate::element::ElementModel, names: &[String]) {
    let _ = writeln!(h, "<h2 id=\"element-model\">Element model</h2>");
    let poles = model.poles_hz();
    let poles_std = model.poles_hz_std().unwrap_or_default();
    let pole_words: Vec<String> = poles
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let s = poles_std.get(k).map_or("—".to_string(), |s| sig(*s, 2));
            format!("{} ± {s} Hz", sig(*p, 4))
        })
        .collect();
    let _ = writeln!(
        h,
        "<p>Chosen: <b>{}</b>{}; the coefficients above are its constant part, the \
         per-frequency figure draws its K(ω), C(ω) and the other families tried.</p>",
        model.family(),
        if pole_words.is_empty() {
            String::new()
        } else {
            format!(", poles {}", pole_words.join(", "))
        }
    );
    let family = model.family();
    let fit = model.fit();
    if family.poles() > 0 {
        let _ = writeln!(
            h,
            "<table>\n<tr><th>residue</th><th>value (N/m)</th><th>±1σ</th></tr>"
        );
        for b in 3..family.parameters_per_element() {
            let (a, sa) = (fit.matrix(b), fit.matrix_std(b));
            for (i, ax) in names.iter().enumerate() {
                let s = sa.as_ref().map_or("—".to_string(), |m| sig(m[(i, i)], 2));
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td>{}</td><td>{s}</td></tr>",
                    esc(&format!("{}_{ax}{ax}", family.parameter_name(b))),
                    sig(a[(i, i)], 5)
                );
            }
        }
        let _ = writeln!(h, "</table>");
    }
    if let Some(crossover) = model
        .effective()
        .and_then(|e| e.crossover_hz.map(|c| (c, e.crossover_hz_std)))
    {
        let (c, s) = crossover;
        let _ = writeln!(
            h,
            "<p>Effective damping C_eff changes sign at {} ± {} Hz.</p>",
            sig(c, 4),
            s.map_or("—".to_string(), |s| sig(s, 2))
        );
    }
    let _ = writeln!(
        h,
        "<table>\n<tr><th>family</th><th>χ²/expected</th><th>p</th><th>runs p</th>\
         <th>criterion (BIC)</th><th>verdict</th></tr>"
    );
    let num = |v: Option<f64>, digits: usize| v.map_or("—".to_string(), |v| sig(v, digits));
    for c in model.selection() {
        let ratio = c.statistic.zip(c.dof).map(|(s, d)| s / d);
        let verdict = match &c.reason {
            Some(reason) => format!("{}: {}", c.verdict, esc(reason)),
            None => c.verdict.to_string(),
        };
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{verdict}</td></tr>",
            c.family,
            num(ratio, 3),
            c.p_value.map_or("—".to_string(), |p| format!("{p:.2e}")),
            c.runs_p_value
                .map_or("—".to_string(), |p| format!("{p:.2e}")),
            num(c.criterion, 5),
        );
    }
    let _ = writeln!(h, "</table>");
}

/// The model check's verdict and numbers, then the uncertainty budget per coefficient.
fn model_check_and_budget(h: &mut String, id: &Identification, names: &[String]) {
    let check = id.model_check();
    let _ = writeln!(
        h,
        "<h2 id=\"model-check\">Model check and uncertainty budget</h2>"
    );
    let verdict = match (&check.verdict, check.statistic, check.dof, check.p_value) {
        (crate::identify::Verdict::Untested { reason }, ..) => {
            format!("untested: {}", esc(reason))
        }
        (v, Some(stat), Some(dof), Some(p)) => format!(
            "<b>{}</b>: χ² = {} on {} degrees of freedom (ratio {:.3}, p = {:.2e})",
            v.name(),
            sig(stat, 5),
            sig(dof, 5),
            stat / dof,
            p
        ),
        (v, ..) => v.name().to_string(),
    };
    let _ = writeln!(
        h,
        "<p>Residuals against the noise measured without the model: {verdict}.</p>"
    );
    let Some(budget) = id.budget() else {
        return;
    };
    let _ = writeln!(
        h,
        "<table>\n<tr><th>coefficient</th><th>random σ</th><th>model σ</th>\
         <th>calibration σ</th><th>combined σ</th></tr>"
    );
    let combined = id.std_dev();
    let parts = [
        Some(&budget.random),
        Some(&budget.model),
        Some(&budget.calibration),
        combined,
    ];
    let [random, model, calibration, combined] =
        parts.map(|p| coefficient_rows(id.coefficients(), p, None, None, names));
    for (((r, m), c), t) in random.iter().zip(&model).zip(&calibration).zip(&combined) {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(&r.label),
            r.std_dev,
            m.std_dev,
            c.std_dev,
            t.std_dev
        );
    }
    let _ = writeln!(h, "</table>");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup() {
        assert_eq!(esc("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
    }

    #[test]
    fn write_failure_is_an_io_error() {
        let e = write_file(Path::new("/nonexistent-dir/x.svg"), "x").unwrap_err();
        assert_eq!(e.kind(), "io_error");
    }

    #[test]
    fn a_page_says_its_kind_and_is_read_back() {
        for kind in Kind::ALL {
            let mut h = String::new();
            page_head(&mut h, &ReportOptions::default(), kind);
            assert_eq!(Kind::of_page(&h), Some(kind), "{h}");
        }
        assert_eq!(Kind::of_page("<html><title>mine</title>"), None);
        let unknown = format!("{}something else{}", Kind::MARK, Kind::MARK_END);
        assert_eq!(Kind::of_page(&unknown), None);
    }

    #[test]
    fn a_folder_with_another_kind_of_report_is_refused() {
        let dir = std::env::temp_dir().join(format!("html-kind-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        create_dir(&dir, Kind::Field).unwrap();
        let mut page = String::new();
        page_head(&mut page, &ReportOptions::default(), Kind::Field);
        write_file(&dir.join("index.html"), &page).unwrap();
        create_dir(&dir, Kind::Field).unwrap();
        let e = create_dir(&dir, Kind::Identification).unwrap_err();
        assert_eq!(e.kind(), "io_error");
        assert!(
            e.to_string().ends_with(
                "holds a field identification report; give the identification report another \
                 folder, or empty this one"
            ),
            "{e}"
        );
        write_file(&dir.join("index.html"), "<html>mine</html>").unwrap();
        let e = create_dir(&dir, Kind::Field).unwrap_err();
        assert!(e.to_string().contains("not a report of this tool"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// With `--model auto` the page has the element model's section with every family tried,
    /// and the per-frequency figure draws the chosen model's curve and, dashed, the others.
    #[test]
    fn an_element_model_has_its_section_and_curves() {
        use crate::Identifier;
        use crate::element::ModelSpec;
        use crate::simulate::{ImpactTest, seed_rig};
        let records = ImpactTest {
            per_direction: 2,
            ..ImpactTest::seed_rig()
        }
        .run(&seed_rig())
        .unwrap();
        let id = Identifier::new(8.0, 49.0)
            .model(ModelSpec::Auto)
            .identify(&records)
            .unwrap();
        let model = id.model().unwrap();
        let tried = model.selection().len();
        assert_eq!(model.other_fits().len(), tried - 1);
        let page = page(
            &id,
            &ReportOptions::default(),
            &[],
            records.len(),
            records.len(),
        );
        assert!(page.contains("<h2 id=\"element-model\">Element model</h2>"));
        assert!(page.contains("Chosen: <b>kcm</b>"));
        assert!(page.contains("<tr><td>kc</td>"), "{page}");
        let svg = crate::plot::per_frequency(&id, &Default::default()).unwrap();
        // Per element and block: the measured values, each other family, the chosen model.
        assert_eq!(svg.matches("class=\"series\"").count(), 4 * 2 * (tried + 1));
        assert!(svg.contains("model kcm"));
        assert!(svg.contains("K xx kc"));
    }

    #[test]
    fn significant_digits() {
        assert_eq!(sig(146300.0, 4), "146300");
        assert_eq!(sig(4.6997, 3), "4.70");
        assert_eq!(sig(1.5e-7, 2), "1.5e-7");
    }
}
