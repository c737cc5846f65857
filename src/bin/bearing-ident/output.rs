//! What the tool writes: the result as a table or JSON on stdout, and the figures and HTML
//! report of `--plot DIR`.

use bearing_ident::quality::ImpactChecks;
use bearing_ident::{Coefficients, Identification, Record};

use crate::failure::{Failure, print_out};
use crate::report;

/// Writes the figures and `index.html` of `--plot DIR`; says where on stderr.
pub fn write_report(
    dir: &std::path::Path,
    id: &Identification,
    records: &[Record],
    context: &report::Context,
    truth: Option<&Coefficients>,
    checks: Option<ImpactChecks>,
) -> Result<(), Failure> {
    let mut lines = vec![format!(
        "{} records ({}), {} samples/s; excitation {}{}.",
        context.files.len(),
        summarize_files(&context.files),
        context.sample_rate,
        context.excitation,
        if context.excitation_auto {
            ", detected"
        } else {
            ""
        },
    )];
    lines.extend(report::stability_line(context));
    let options = bearing_ident::plot::ReportOptions {
        context: lines,
        text: Some(report::table(id, context, truth)),
        truth: truth.cloned(),
        checks,
        figure: bearing_ident::plot::FigureOptions {
            axes: context.axes.clone(),
            ..Default::default()
        },
        ..Default::default()
    };
    let written = bearing_ident::plot::report(id, records, dir, &options)?;
    crate::failure::print_err(format_args!(
        "bearing-ident: wrote {} figures and {}",
        written.len().saturating_sub(1),
        dir.join("index.html").display()
    ));
    Ok(())
}

/// The first few file names and how many more.
fn summarize_files(files: &[String]) -> String {
    let shown: Vec<&str> = files.iter().take(3).map(String::as_str).collect();
    if files.len() > shown.len() {
        format!("{}, … {} more", shown.join(", "), files.len() - shown.len())
    } else {
        shown.join(", ")
    }
}

pub fn emit(
    id: &Identification,
    context: &report::Context,
    truth: Option<&Coefficients>,
    json: bool,
) -> Result<(), Failure> {
    if json {
        let value = report::json(id, context).map_err(|e| Failure {
            kind: "io_error",
            message: e.to_string(),
        })?;
        print_out(format_args!("{value}\n"))?;
    } else {
        print_out(format_args!("{}", report::table(id, context, truth)))?;
    }
    Ok(())
}
