//! What the tool prints: an aligned table for people, JSON for scripts.

use std::fmt::Write as _;

use bearing_ident::{Coefficients, Identification};
use faer::MatRef;

/// Facts about the run that the identification itself does not hold.
pub struct Context {
    /// `"impact"` or `"random"`.
    pub excitation: &'static str,
    /// Whether the excitation was detected rather than given.
    pub excitation_auto: bool,
    /// Median crest factor of the records' strongest force channels.
    pub crest_factor: f64,
    /// Welch segment length, if any.
    pub segment_len: Option<usize>,
    /// Sampling rate (Hz).
    pub sample_rate: f64,
    /// The record files (or labels).
    pub files: Vec<String>,
    /// Wall time after the data were in memory (ms).
    pub compute_ms: f64,
    /// Names of the degrees of freedom (the displacement columns).
    pub axes: Vec<String>,
}

/// The library's serialization of `id` plus the run's own fields.
pub fn json(id: &Identification, c: &Context) -> serde_json::Result<serde_json::Value> {
    let mut v = serde_json::to_value(id)?;
    if let Some(map) = v.as_object_mut() {
        map.insert("excitation".into(), c.excitation.into());
        map.insert("excitation_auto".into(), c.excitation_auto.into());
        map.insert("crest_factor".into(), c.crest_factor.into());
        map.insert("nperseg".into(), c.segment_len.into());
        map.insert("fs".into(), c.sample_rate.into());
        map.insert("n_records".into(), c.files.len().into());
        map.insert("files".into(), c.files.clone().into());
        map.insert("compute_ms".into(), c.compute_ms.into());
    }
    Ok(v)
}

/// `v` with `digits` significant digits, fixed-point for ordinary magnitudes, scientific
/// otherwise.
fn sig(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let exp = v.abs().log10().floor() as i32;
    if (-3..6).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.prec$e}", prec = digits - 1)
    }
}

/// Picks one block (M, C or K) out of a coefficient set.
type Block = fn(&Coefficients) -> MatRef<'_, f64>;

/// One line per coefficient: name, value, standard deviation, and truth with error if known.
fn coefficient_lines(
    out: &mut String,
    axes: &[String],
    id: &Identification,
    truth: Option<&Coefficients>,
) {
    let blocks: [(&str, &str, Block); 3] = [
        ("M", "kg", Coefficients::mass),
        ("C", "N·s/m", Coefficients::damping),
        ("K", "N/m", Coefficients::stiffness),
    ];
    let std = id.std_dev();
    let _ = write!(out, "  {:<16} {:>15} {:>11}", "coefficient", "value", "±1σ");
    if truth.is_some() {
        let _ = write!(out, " {:>15} {:>10}", "true", "error");
    }
    let _ = writeln!(out);
    for (name, unit, get) in blocks {
        let value = get(id.coefficients());
        for (i, ai) in axes.iter().enumerate() {
            for (j, aj) in axes.iter().enumerate() {
                let label = format!("{name} {ai}{aj} ({unit})");
                let sd = std.map_or("—".to_string(), |s| sig(get(s)[(i, j)], 3));
                let _ = write!(out, "  {label:<16} {:>15} {sd:>11}", sig(value[(i, j)], 7));
                if let Some(t) = truth.map(get) {
                    let err = if t[(i, j)] == 0.0 {
                        "—".to_string()
                    } else {
                        format!("{:+.3} %", 100.0 * (value[(i, j)] / t[(i, j)] - 1.0))
                    };
                    let _ = write!(out, " {:>15} {err:>10}", sig(t[(i, j)], 7));
                }
                let _ = writeln!(out);
            }
        }
    }
}

/// An aligned, human-readable report.
pub fn table(id: &Identification, c: &Context, truth: Option<&Coefficients>) -> String {
    let mut out = String::new();
    let co = id.coefficients();
    let n = co.dofs();
    let axes: Vec<String> = if c.axes.len() == n {
        c.axes.clone()
    } else {
        (1..=n).map(|i| i.to_string()).collect()
    };
    let freqs = id.freqs_hz();
    let _ = writeln!(
        out,
        "{} records, {} DOF, {} samples/s; excitation {}{} (crest factor {:.1}); estimator {}{}; method {}",
        c.files.len(),
        n,
        c.sample_rate,
        c.excitation,
        if c.excitation_auto { ", detected" } else { "" },
        c.crest_factor,
        id.estimator().name(),
        c.segment_len
            .map_or(String::new(), |l| format!(" (Welch, {l} samples)")),
        id.method().name(),
    );
    let _ = writeln!(
        out,
        "band {:.2}–{:.2} Hz: {} lines used, {:.3}–{:.3} Hz; {} averages; window {}\n",
        id.band().low_hz(),
        id.band().high_hz(),
        freqs.len(),
        freqs[0],
        freqs[freqs.len() - 1],
        id.frf().averages(),
        match id.window().decay_per_s() {
            Some(a) => format!("exponential, a = {a:.4}/s, coefficients corrected"),
            None => id.window().name().to_string(),
        }
    );
    let _ = writeln!(
        out,
        "Coefficients (± one standard deviation, {})",
        id.uncertainty().name()
    );
    coefficient_lines(&mut out, &axes, id, truth);
    let _ = writeln!(out);
    let _ = writeln!(out, "Modes");
    for (k, m) in id.modes().unwrap_or_default().iter().enumerate() {
        let _ = writeln!(
            out,
            "  {}: natural frequency {:8.3} Hz, damping ratio {:.4}",
            k + 1,
            m.natural_frequency_hz,
            m.damping_ratio
        );
    }
    let cond = id.conditioning();
    let _ = writeln!(out, "\nDiagnostics");
    let _ = writeln!(
        out,
        "  condition number over the band: min {:.3}, median {:.3}, max {:.3}",
        cond.best(),
        cond.median(),
        cond.worst()
    );
    let _ = writeln!(
        out,
        "  iterations {}, converged {}, residual ‖AΘ − Ī‖ = {:.4e}, compute {:.2} ms",
        id.iterations(),
        id.converged(),
        id.residual_norm(),
        c.compute_ms
    );
    if let Some(c) = id.coherence_min() {
        let _ = writeln!(out, "  multiple coherence: min {c:.4} over the lines used");
    }
    let r2 = id.fit_r2();
    let _ = write!(out, "  flexibility fit r²:");
    for (i, ai) in axes.iter().enumerate() {
        for (j, aj) in axes.iter().enumerate() {
            let _ = write!(out, " {ai}{aj} {:.4}", r2[(i, j)]);
        }
    }
    let _ = writeln!(out);
    for w in id.warnings() {
        let _ = writeln!(out, "  warning: {w}");
    }
    out
}
