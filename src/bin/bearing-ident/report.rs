//! What the tool prints: an aligned table for people, JSON for scripts.

use std::fmt::Write as _;

use bearing_ident::model::rows;
use bearing_ident::per_frequency::PerFrequency;
use bearing_ident::plot::{coefficient_rows, significant as sig};
use bearing_ident::{Coefficients, Identification};
use faer::MatRef;

/// Facts about the run that the identification itself does not hold.
pub struct Context {
    /// `"impact"`, `"random"`, `"periodic"`, `"stepped-sine"` or `"sweep"`.
    pub excitation: &'static str,
    /// Whether the excitation was detected rather than given.
    pub excitation_auto: bool,
    /// Median crest factor of the records' strongest force channels.
    pub crest_factor: f64,
    /// Welch segment length, if any.
    pub segment_len: Option<usize>,
    /// How the Welch segment length was chosen from the data, if it was.
    pub welch_choice: Option<bearing_ident::excitation::WelchChoice>,
    /// Sampling rate (Hz).
    pub sample_rate: f64,
    /// The record files (or labels).
    pub files: Vec<String>,
    /// Wall time after the data were in memory (ms).
    pub compute_ms: f64,
    /// Wall time spent reading the record files (ms; 0 for simulated records).
    pub read_ms: f64,
    /// Print the stage timings in the table (`--timings`).
    pub show_timings: bool,
    /// Names of the degrees of freedom (the displacement columns).
    pub axes: Vec<String>,
    /// System minus baseline (coefficients, standard deviations) and where the baseline came
    /// from.
    pub bearing: Option<(Coefficients, Option<Coefficients>, String)>,
    /// Per-line coefficients, when asked for.
    pub per_frequency: Option<PerFrequency>,
}

/// The library's serialization of `id` plus the run's own fields.
pub fn json(id: &Identification, c: &Context) -> serde_json::Result<serde_json::Value> {
    let mut v = serde_json::to_value(id)?;
    if let Some(map) = v.as_object_mut() {
        map.insert("excitation".into(), c.excitation.into());
        map.insert("excitation_auto".into(), c.excitation_auto.into());
        map.insert("crest_factor".into(), c.crest_factor.into());
        map.insert("nperseg".into(), c.segment_len.into());
        map.insert("welch_choice".into(), serde_json::to_value(c.welch_choice)?);
        map.insert("fs".into(), c.sample_rate.into());
        map.insert("n_records".into(), c.files.len().into());
        map.insert("files".into(), c.files.clone().into());
        map.insert("compute_ms".into(), c.compute_ms.into());
        map.insert("timings_ms".into(), timings_ms(id, c));
        if let Some((b, std, source)) = &c.bearing {
            let block = |m: MatRef<'_, f64>| serde_json::Value::from(rows(m));
            let std_block = |get: Block| std.as_ref().map(|s| block(get(s)));
            let bearing = serde_json::json!({
                "baseline": source,
                "M": block(b.mass()),
                "C": block(b.damping()),
                "K": block(b.stiffness()),
                "M_std": std_block(Coefficients::mass),
                "C_std": std_block(Coefficients::damping),
                "K_std": std_block(Coefficients::stiffness),
            });
            map.insert("bearing".into(), bearing);
        }
        if let Some(pf) = &c.per_frequency {
            map.insert("per_frequency".into(), per_frequency_json(pf));
        }
    }
    Ok(v)
}

/// `read`, the library's stages ([`bearing_ident::identify::Timings`]) and `total` (reading
/// plus compute), in milliseconds.
fn timings_ms(id: &Identification, c: &Context) -> serde_json::Value {
    let mut map = serde_json::Map::new();
    map.insert("read".into(), c.read_ms.into());
    for (name, d) in id.timings().stages() {
        map.insert(name.into(), (d.as_secs_f64() * 1e3).into());
    }
    map.insert("total".into(), (c.read_ms + c.compute_ms).into());
    serde_json::Value::Object(map)
}

/// One object per line: `freq_hz`, `K`, `C` (rows), `K_std`, `C_std` (null without an FRF
/// variance), and for n = 2 `K_eff`, `C_eff`, `K_eff_std`, `C_eff_std`.
fn per_frequency_json(pf: &PerFrequency) -> serde_json::Value {
    let effective = pf.effective();
    let lines: Vec<serde_json::Value> = pf
        .freqs_hz()
        .iter()
        .enumerate()
        .map(|(k, &f)| {
            let mut line = serde_json::json!({
                "freq_hz": f,
                "K": rows(pf.stiffness(k)),
                "C": rows(pf.damping(k)),
                "K_std": pf.stiffness_std(k).map(rows),
                "C_std": pf.damping_std(k).map(rows),
            });
            if let (Some(e), Some(map)) = (effective.as_ref().map(|e| e[k]), line.as_object_mut()) {
                map.insert("K_eff".into(), e.stiffness.into());
                map.insert("C_eff".into(), e.damping.into());
                map.insert("K_eff_std".into(), e.stiffness_std.into());
                map.insert("C_eff_std".into(), e.damping_std.into());
            }
            line
        })
        .collect();
    lines.into()
}

/// Picks one block (M, C or K) out of a coefficient set.
type Block = fn(&Coefficients) -> MatRef<'_, f64>;

/// One line per coefficient: name, value, standard deviation, and truth with error if known.
fn coefficient_lines(
    out: &mut String,
    axes: &[String],
    values: &Coefficients,
    std: Option<&Coefficients>,
    truth: Option<&Coefficients>,
) {
    let _ = write!(out, "  {:<16} {:>15} {:>11}", "coefficient", "value", "±1σ");
    if truth.is_some() {
        let _ = write!(out, " {:>15} {:>10}", "true", "error");
    }
    let _ = writeln!(out);
    for row in coefficient_rows(values, std, None, truth, axes) {
        let _ = write!(
            out,
            "  {:<16} {:>15} {:>11}",
            row.label, row.value, row.std_dev
        );
        if let (Some(truth), Some(error)) = (&row.truth, &row.error) {
            let _ = write!(out, " {truth:>15} {error:>10}");
        }
        let _ = writeln!(out);
    }
}

/// `  timings (ms): read …, <every stage>, total …`, a line of the table.
pub fn timings_line(
    out: &mut String,
    timings: &bearing_ident::identify::Timings,
    read_ms: f64,
    compute_ms: f64,
) {
    let stages: Vec<String> = timings
        .stages()
        .iter()
        .map(|(name, d)| format!("{name} {:.2}", d.as_secs_f64() * 1e3))
        .collect();
    let _ = writeln!(
        out,
        "  timings (ms): read {read_ms:.2}, {}, total {:.2}",
        stages.join(", "),
        read_ms + compute_ms
    );
}

/// The axes' names when there is one per degree of freedom, else `1`, `2`, ….
pub fn axis_labels(axes: &[String], n: usize) -> Vec<String> {
    if axes.len() == n {
        axes.to_vec()
    } else {
        (1..=n).map(|i| i.to_string()).collect()
    }
}

/// An aligned, human-readable report.
pub fn table(id: &Identification, c: &Context, truth: Option<&Coefficients>) -> String {
    let mut out = String::new();
    let co = id.coefficients();
    let n = co.dofs();
    let axes = axis_labels(&c.axes, n);
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
        match id.segmentation() {
            bearing_ident::Segmentation::Welch { len } => format!(" (Welch, {len} samples)"),
            bearing_ident::Segmentation::Periods { len } => format!(" (periods of {len} samples)"),
            _ => String::new(),
        },
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
        } + &id.force_gate().map_or(String::new(), |g| {
            format!("; force gate {} s + {} s taper", g.open_s(), g.taper_s())
        })
    );
    if !id.frf().unexcited_hz().is_empty() {
        let _ = writeln!(
            out,
            "{} band lines not excited (periodic excitation), left out\n",
            id.frf().unexcited_hz().len()
        );
    }
    let _ = writeln!(
        out,
        "Coefficients (± one standard deviation, {})",
        match (id.uncertainty(), id.method()) {
            (bearing_ident::Uncertainty::Sandwich, bearing_ident::Method::Ml) => "inverse Fisher",
            (u, _) => u.name(),
        }
    );
    coefficient_lines(&mut out, &axes, co, id.std_dev(), truth);
    let _ = writeln!(out);
    if let Some((b, std, source)) = &c.bearing {
        let _ = writeln!(out, "Bearing: system − baseline ({source})");
        coefficient_lines(&mut out, &axes, b, std.as_ref(), None);
        let _ = writeln!(out);
    }
    let _ = writeln!(out, "Modes (± one standard deviation)");
    let (sf, sz) = (id.natural_frequencies_hz_std(), id.damping_ratios_std());
    let pm = |s: &Option<Vec<f64>>, k: usize| {
        s.as_ref()
            .and_then(|s| s.get(k))
            .map_or(String::new(), |v| format!(" ± {}", sig(*v, 2)))
    };
    for (k, m) in id.modes().unwrap_or_default().iter().enumerate() {
        let _ = writeln!(
            out,
            "  {}: natural frequency {:8.3}{} Hz, damping ratio {}{}",
            k + 1,
            m.natural_frequency_hz,
            pm(&sf, k),
            sig(m.damping_ratio, 3),
            pm(&sz, k)
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
    if c.show_timings {
        timings_line(&mut out, &id.timings(), c.read_ms, c.compute_ms);
    }
    if let Some(ml) = id.ml() {
        let _ = writeln!(
            out,
            "  maximum likelihood: {} steps, cost {:.4e} (IVF start {:.4e}), cost / expected {:.3}{}",
            ml.iterations,
            ml.cost,
            ml.start_cost,
            ml.cost_ratio,
            ml.fell_back
                .as_ref()
                .map_or(String::new(), |r| format!("; kept IVF: {r}"))
        );
    }
    if let Some(c) = id.coherence_min() {
        let _ = writeln!(out, "  multiple coherence: min {c:.4} over the lines used");
    }
    model_check_lines(&mut out, id);
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
    if let Some(pf) = &c.per_frequency {
        per_frequency_lines(&mut out, &axes, pf);
    }
    out
}

/// The model check's verdict, with its ratio and p-value when tested.
fn model_check_lines(out: &mut String, id: &Identification) {
    let check = id.model_check();
    let _ = match (&check.verdict, check.ratio(), check.p_value) {
        (bearing_ident::identify::Verdict::Untested { reason }, ..) => {
            writeln!(out, "  model check: untested ({reason})")
        }
        (v, Some(r), Some(p)) => writeln!(
            out,
            "  model check: {}, χ²/expected {r:.3}, p = {p:.2e}",
            v.name()
        ),
        (v, ..) => writeln!(out, "  model check: {}", v.name()),
    };
}

/// The per-line diagonal coefficients as a table (the JSON has every element).
fn per_frequency_lines(out: &mut String, axes: &[String], pf: &PerFrequency) {
    let _ = writeln!(out, "\nPer frequency (diagonal; ± one standard deviation)");
    let _ = write!(out, "  {:>9}", "f (Hz)");
    for a in axes {
        let _ = write!(
            out,
            " {:>24} {:>22}",
            format!("K {a}{a} (N/m)"),
            format!("C {a}{a} (N·s/m)")
        );
    }
    let _ = writeln!(out);
    for (k, f) in pf.freqs_hz().iter().enumerate() {
        let _ = write!(out, "  {f:>9.3}");
        for i in 0..axes.len() {
            let pm = |v: f64, s: Option<f64>| match s {
                Some(s) => format!("{} ± {}", sig(v, 6), sig(s, 2)),
                None => sig(v, 6),
            };
            let ks = pf.stiffness_std(k).map(|s| s[(i, i)]);
            let cs = pf.damping_std(k).map(|s| s[(i, i)]);
            let _ = write!(
                out,
                " {:>24} {:>22}",
                pm(pf.stiffness(k)[(i, i)], ks),
                pm(pf.damping(k)[(i, i)], cs)
            );
        }
        let _ = writeln!(out);
    }
}
