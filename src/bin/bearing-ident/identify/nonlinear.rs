//! `identify --nonlinear TERMS`: linear M, C, K together with nonlinear terms by the reverse
//! path ([`ReversePath`]), its table, JSON and `--plot` report.
//!
//! JSON: `M`, `C`, `K` (and `*_std`) as the linear identification writes them, plus
//! `nonlinear` (one object per term: `term`, `dof` (null for `coulomb-planar`), `value`,
//! `std`, `unit`), `nonlinear_check` (per term: `imaginary_ratio`, `imaginary_sigmas`,
//! `slope`, `slope_sigmas`, `input_coherence`, `misfit`, `collinear`) and `velocity`
//! (`method`, `cutoff_hz`, `sources`).

use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

use bearing_ident::Choice;
use bearing_ident::excitation::{Excitation, deciding_record};
use bearing_ident::model::rows;
use bearing_ident::nonlinear::{Differentiation, NonlinearIdentification, Regressor, ReversePath};
use bearing_ident::plot::{FigureOptions, ReportOptions, coefficient_rows, significant as sig};
use bearing_ident::{Coefficients, IvfOptions, Method, Warning};
use serde_json::json;

use super::IdentifyArgs;
use crate::failure::{Failure, invalid, print_out};
use bearing_ident::job::{Channels, read_file, read_first};

/// The regressors of `--nonlinear` (a comma list of names).
pub(super) fn regressors(terms: &str) -> Result<Vec<Regressor>, Failure> {
    terms
        .split(',')
        .filter(|t| !t.trim().is_empty())
        .map(|t| t.parse::<Regressor>().map_err(Failure::from))
        .collect()
}

/// Refuses `--vel-cutoff` without `--nonlinear`.
pub(super) fn linear_only(args: &IdentifyArgs) -> Result<(), Failure> {
    match args.vel_cutoff {
        Some(_) => Err(invalid(
            "--vel-cutoff applies to --nonlinear only".to_string(),
        )),
        None => Ok(()),
    }
}

/// Runs the reverse path on every record of `args.files` and writes the result. The
/// excitation is the one given, or the one the first record with a force says
/// ([`Excitation::from_record`]).
pub(super) fn run(args: &IdentifyArgs, terms: &str, channels: &Channels) -> Result<(), Failure> {
    let start = Instant::now();
    let first = read_file(&args.files[0], channels)?;
    let excitation = match args.excitation {
        Some(kind) => kind,
        None => {
            let rest = args.files[1..]
                .iter()
                .map(|path| read_first(path, channels).map(std::borrow::Cow::Owned));
            let records = std::iter::once(Ok(std::borrow::Cow::Borrowed(&first[0]))).chain(rest);
            Excitation::from_record(&*deciding_record(records)?)?
        }
    };
    if !matches!(excitation, Excitation::Random | Excitation::Periodic) {
        return Err(invalid(format!(
            "--nonlinear needs random or multisine records (--excitation random); the records \
             are {}",
            excitation.name()
        )));
    }
    if args.baseline.is_some() || args.per_frequency {
        return Err(invalid(
            "--baseline and --per-frequency do not apply to --nonlinear".to_string(),
        ));
    }
    // The reverse path neither corrects channel transfers nor carries a calibration budget:
    // refused rather than read and dropped.
    if args.calibration.is_some() || !args.delay.is_empty() || !args.highpass.is_empty() {
        return Err(invalid(
            "--calibration, --delay and --highpass do not apply to --nonlinear (the reverse \
             path corrects no channel transfer and carries no calibration budget)"
                .to_string(),
        ));
    }
    let regressors = regressors(terms)?;
    let (lo, hi) = bearing_ident::job::parse_band(&args.band)?;
    let mut records = first;
    for path in &args.files[1..] {
        records.extend(read_file(path, channels)?);
    }
    let read_ms = start.elapsed().as_secs_f64() * 1e3;
    let method: Method = args.method;
    let mut path = ReversePath::new(lo, hi, &regressors)
        .method(method)
        .ivf_options(IvfOptions {
            tolerance: args.tolerance,
            max_iterations: args.max_iterations,
        })
        .differentiation(match args.vel_cutoff {
            Some(hz) => Differentiation::Cutoff(hz),
            None => Differentiation::Wiener,
        });
    if let Some(len) = args.nperseg {
        path = path.segment_len(len);
    }
    let compute = Instant::now();
    let id = path.identify(&records)?;
    let compute_ms = compute.elapsed().as_secs_f64() * 1e3;
    if !id.fit().convergence().is_converged() && !args.allow_unconverged {
        let change = id.fit().history().last().map(|h| h.change());
        return Err(bearing_ident::Error::NotConverged {
            method,
            iterations: id.fit().convergence().iterations(),
            change,
        }
        .into());
    }
    let axes = if args.disp.is_empty() {
        vec!["x".to_string(), "y".to_string()]
    } else {
        args.disp.clone()
    };
    let run = Run {
        excitation,
        sample_rate: records[0].sample_rate(),
        files: records.iter().map(|r| r.label().to_owned()).collect(),
        band: (lo, hi),
        read_ms,
        compute_ms,
        axes,
    };
    if let Some(dir) = &args.plot {
        write_report(dir, &id, &run)?;
    }
    if args.json {
        print_out(format_args!("{}\n", json(&id, &run)))
    } else {
        print_out(format_args!("{}", table(&id, &run, args.timings)))
    }
}

/// Facts about the run beside the identification.
struct Run {
    excitation: Excitation,
    sample_rate: f64,
    files: Vec<String>,
    band: (f64, f64),
    read_ms: f64,
    compute_ms: f64,
    axes: Vec<String>,
}

/// The JSON object of a nonlinear identification.
fn json(id: &NonlinearIdentification, run: &Run) -> serde_json::Value {
    let c = id.coefficients();
    let std = id.std_dev();
    let block =
        |get: fn(&Coefficients) -> faer::MatRef<'_, f64>| (rows(get(c)), std.map(|s| rows(get(s))));
    let (m, m_std) = block(Coefficients::mass);
    let (cc, c_std) = block(Coefficients::damping);
    let (k, k_std) = block(Coefficients::stiffness);
    let freqs = id.freqs_hz();
    let modes = c.modes().unwrap_or_default();
    let terms: Vec<serde_json::Value> = id
        .terms()
        .iter()
        .map(|t| {
            json!({
                "term": t.term.regressor.name(),
                "dof": t.term.dof,
                "value": t.value,
                "std": t.std,
                "model_std": t.model_std,
                "unit": t.unit(),
            })
        })
        .collect();
    let checks: Vec<serde_json::Value> = id
        .terms()
        .iter()
        .zip(id.checks())
        .map(|(t, ch)| {
            json!({
                "term": t.term.regressor.name(),
                "dof": t.term.dof,
                "imaginary_ratio": ch.imaginary_ratio,
                "imaginary_sigmas": finite(ch.imaginary_sigmas),
                "slope": ch.slope,
                "slope_sigmas": finite(ch.slope_sigmas),
                "input_coherence": ch.input_coherence,
                "misfit": ch.misfit,
                "collinear": ch.collinear,
            })
        })
        .collect();
    let v = id.velocity();
    let timings: serde_json::Map<String, serde_json::Value> = id
        .timings()
        .stages()
        .iter()
        .map(|(name, d)| (name.to_string(), (d.as_secs_f64() * 1e3).into()))
        .chain([
            ("read".to_string(), run.read_ms.into()),
            ("total".to_string(), (run.read_ms + run.compute_ms).into()),
        ])
        .collect();
    json!({
        "method": id.fit().method().name(),
        "estimator": "reverse-path",
        "excitation": run.excitation.name(),
        "window": "hann",
        "segmentation": "welch",
        "segment_len": id.segment_len(),
        "nperseg": id.segment_len(),
        "n": c.dofs(),
        "fs": run.sample_rate,
        "n_records": run.files.len(),
        "files": run.files,
        "band_hz": [run.band.0, run.band.1],
        "band_used_hz": [freqs.first(), freqs.last()],
        "n_freq": freqs.len(),
        "freqs_hz": freqs,
        "M": m, "C": cc, "K": k,
        "M_std": m_std, "C_std": c_std, "K_std": k_std,
        "uncertainty": if id.jackknife_blocks() >= 3 { "jackknife" } else { "sandwich" },
        "jackknife_blocks": id.jackknife_blocks(),
        "averages": id.averages(),
        "iterations": id.fit().convergence().iterations(),
        "converged": id.fit().convergence().is_converged(),
        "convergence": id.fit().convergence().name(),
        "natural_frequencies_hz": modes.iter().map(|m| m.natural_frequency_hz).collect::<Vec<_>>(),
        "damping_ratios": modes.iter().map(|m| m.damping_ratio).collect::<Vec<_>>(),
        "coherence_min": id.min_output_coherence(),
        "nonlinear": terms,
        "nonlinear_check": checks,
        "velocity": {
            "method": v.differentiation.name(),
            "cutoff_hz": v.differentiation.cutoff_hz(),
            "sources": v.sources.iter().map(|r| r.name()).collect::<Vec<_>>(),
        },
        "warnings": id.warnings().iter().map(ToString::to_string).collect::<Vec<_>>(),
        "warning_kinds": id.warnings().iter().map(Warning::kind).collect::<Vec<_>>(),
        "compute_ms": run.compute_ms,
        "timings_ms": timings,
    })
}

/// `v`, or null when it is infinite (a check without variances).
fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

/// The table for people.
fn table(id: &NonlinearIdentification, run: &Run, timings: bool) -> String {
    let mut out = String::new();
    let c = id.coefficients();
    let n = c.dofs();
    let axes = crate::report::axis_labels(&run.axes, n);
    let freqs = id.freqs_hz();
    let _ = writeln!(
        out,
        "{} records, {} DOF, {} samples/s; excitation {}; reverse path (Welch, {} samples, \
         {} averages); linear part by {}",
        run.files.len(),
        n,
        run.sample_rate,
        run.excitation.name(),
        id.segment_len(),
        id.averages(),
        id.fit().method().name()
    );
    let _ = writeln!(
        out,
        "band {:.2}–{:.2} Hz: {} lines used, {:.3}–{:.3} Hz\n",
        run.band.0,
        run.band.1,
        freqs.len(),
        freqs.first().copied().unwrap_or(f64::NAN),
        freqs.last().copied().unwrap_or(f64::NAN),
    );
    let _ = writeln!(
        out,
        "Coefficients (± one standard deviation, jackknife over {} blocks)",
        id.jackknife_blocks()
    );
    let _ = writeln!(out, "  {:<16} {:>15} {:>11}", "coefficient", "value", "±1σ");
    for row in coefficient_rows(c, id.std_dev(), None, None, &axes) {
        let _ = writeln!(
            out,
            "  {:<16} {:>15} {:>11}",
            row.label, row.value, row.std_dev
        );
    }
    let _ = writeln!(out, "\nNonlinear terms");
    let _ = writeln!(
        out,
        "  {:<22} {:>13} {:>10} {:<9} {:>8} {:>8} {:>9}  check",
        "term", "value", "±1σ", "unit", "Im/Re", "slope", "coherence"
    );
    for (t, ch) in id.terms().iter().zip(id.checks()) {
        let _ = writeln!(
            out,
            "  {:<22} {:>13} {:>10} {:<9} {:>8.4} {:>7.2}% {:>9.4}  {}",
            t.term.label(),
            sig(t.value, 6),
            t.std.map_or("—".to_string(), |s| sig(s, 3)),
            t.unit(),
            ch.imaginary_ratio,
            100.0 * ch.slope,
            ch.input_coherence,
            if ch.misfit {
                "does not fit"
            } else if ch.collinear {
                "collinear"
            } else {
                "fits"
            }
        );
    }
    let v = id.velocity();
    let _ = writeln!(
        out,
        "\nVelocities: {}{} from {}",
        v.differentiation.name(),
        v.differentiation
            .cutoff_hz()
            .map_or(String::new(), |c| format!(" (cutoff {c} Hz)")),
        v.sources
            .iter()
            .map(|r| r.name())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(out, "\nModes");
    for (k, m) in c.modes().unwrap_or_default().iter().enumerate() {
        let _ = writeln!(
            out,
            "  {}: natural frequency {:8.3} Hz, damping ratio {:.4}",
            k + 1,
            m.natural_frequency_hz,
            m.damping_ratio
        );
    }
    let _ = writeln!(out, "\nDiagnostics");
    let _ = writeln!(
        out,
        "  multiple coherence of the forces on the inputs: min {:.4}; iterations {}, converged {}, compute {:.2} ms",
        id.min_output_coherence(),
        id.fit().convergence().iterations(),
        id.fit().convergence().is_converged(),
        run.compute_ms
    );
    if timings {
        let read = Duration::from_secs_f64(run.read_ms / 1e3);
        let mut stages = vec![("read", read)];
        stages.extend(id.timings().stages());
        let total = read + Duration::from_secs_f64(run.compute_ms / 1e3);
        crate::report::timings_line(&mut out, &stages, total);
    }
    for w in id.warnings() {
        let _ = writeln!(out, "  warning: {w}");
    }
    out
}

/// The figure and `index.html` of `--plot DIR`.
fn write_report(dir: &Path, id: &NonlinearIdentification, run: &Run) -> Result<(), Failure> {
    let options = ReportOptions {
        title: "bearing-ident report: nonlinear elements".into(),
        context: vec![format!(
            "{} records, {} samples/s; excitation {}.",
            run.files.len(),
            run.sample_rate,
            run.excitation.name()
        )],
        text: Some(table(id, run, false)),
        checks: None,
        figure: FigureOptions {
            axes: run.axes.clone(),
            ..Default::default()
        },
        ..Default::default()
    };
    let written = bearing_ident::plot::nonlinear_report(id, dir, &options)?;
    crate::failure::print_err(format_args!(
        "bearing-ident: wrote {} figure and {}",
        written.len().saturating_sub(1),
        dir.join("index.html").display()
    ));
    Ok(())
}
