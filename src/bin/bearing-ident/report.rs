//! What the tool prints: an aligned table for people, JSON for scripts.

use std::fmt::Write as _;
use std::time::Duration;

use bearing_ident::Choice;
use bearing_ident::job::{Facts, Timings};
use bearing_ident::per_frequency::PerFrequency;
use bearing_ident::plot::{coefficient_rows, significant as sig};
use bearing_ident::text::{self, Align};
use bearing_ident::{Coefficients, Identification};

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
    /// Wall time per stage: reading the record files (0 for simulated records), the run after
    /// the data were in memory, and each stage of the run.
    pub timings: Timings,
    /// Print the stage timings in the table (`--timings`).
    pub show_timings: bool,
    /// Names of the degrees of freedom (the displacement columns).
    pub axes: Vec<String>,
    /// System minus baseline (coefficients, standard deviations) and where the baseline came
    /// from.
    pub bearing: Option<(Coefficients, Option<Coefficients>, String)>,
    /// Per-line coefficients, when asked for.
    pub per_frequency: Option<PerFrequency>,
    /// Print the coefficients in US customary units (lbm, lbf·s/in, lbf/in; `--units us`);
    /// the JSON keeps SI and adds them as `M_us`, `C_us`, `K_us`.
    pub us_units: bool,
    /// The JSON's `units` (null: none): the units the channels were given in (`force`,
    /// `response`) and those of the printed coefficients (`output`, `M`, `C`, `K`).
    pub units: serde_json::Value,
    /// The coefficients in dimensionless form, when a clearance was given.
    pub dimensionless: Option<bearing_ident::rotor::Dimensionless>,
    /// The stability of a rigid rotor on the element, when a speed or load was given.
    pub stability: Option<bearing_ident::rotor::Stability>,
    /// `K(ω)`, `C(ω)` at the excitation frequency equal to the speed.
    pub synchronous: Option<bearing_ident::rotor::Synchronous>,
}

impl Context {
    /// The context of a run of the library's `Job`: its excitation, Welch choice, files and
    /// times, the bearing less its baseline, and the per-line coefficients when asked for.
    pub fn of(
        outcome: &bearing_ident::job::Outcome,
        show_timings: bool,
        axes: Vec<String>,
        per_frequency: bool,
    ) -> Result<Self, crate::failure::Failure> {
        let id = outcome.identification();
        Ok(Context {
            excitation: outcome.excitation().name(),
            excitation_auto: outcome.excitation_detected(),
            crest_factor: outcome.crest_factor(),
            segment_len: outcome.segment_len(),
            welch_choice: outcome.welch_choice().copied(),
            sample_rate: outcome.sample_rate(),
            files: outcome.files().to_vec(),
            timings: outcome.timings(),
            show_timings,
            axes,
            bearing: outcome
                .bearing()
                .map(|b| (b.coefficients.clone(), b.std_dev.clone(), b.source.clone())),
            per_frequency: per_frequency.then(|| id.per_frequency()).transpose()?,
            us_units: false,
            units: serde_json::Value::Null,
            dimensionless: outcome.dimensionless().cloned(),
            stability: outcome.stability().cloned(),
            synchronous: outcome.synchronous().cloned(),
        })
    }
}

/// The library's JSON of `id` with the run's own fields ([`bearing_ident::job::json`]).
pub fn json(id: &Identification, c: &Context) -> serde_json::Result<serde_json::Value> {
    let facts = Facts {
        excitation: c.excitation,
        excitation_auto: c.excitation_auto,
        crest_factor: c.crest_factor,
        segment_len: c.segment_len,
        welch_choice: c.welch_choice,
        sample_rate: c.sample_rate,
        files: &c.files,
        timings: c.timings,
        bearing: c
            .bearing
            .as_ref()
            .map(|(b, std, source)| (b, std.as_ref(), source.as_str())),
        per_frequency: c.per_frequency.as_ref(),
        dimensionless: c.dimensionless.as_ref(),
        stability: c.stability.as_ref(),
        synchronous: c.synchronous.as_ref(),
    };
    let mut v = bearing_ident::job::json(id, &facts)?;
    if !c.units.is_null() {
        v["units"] = c.units.clone();
    }
    if c.us_units {
        let rows = |m: faer::MatRef<'_, f64>, k: f64| -> Vec<Vec<f64>> {
            (0..m.nrows())
                .map(|i| (0..m.ncols()).map(|j| m[(i, j)] * k).collect())
                .collect()
        };
        let [fm, fc, fk] = US.map(|(_, _, f)| f);
        let co = id.coefficients();
        v["M_us"] = serde_json::json!(rows(co.mass(), fm));
        v["C_us"] = serde_json::json!(rows(co.damping(), fc));
        v["K_us"] = serde_json::json!(rows(co.stiffness(), fk));
        if let Some(s) = id.std_dev() {
            v["M_std_us"] = serde_json::json!(rows(s.mass(), fm));
            v["C_std_us"] = serde_json::json!(rows(s.damping(), fc));
            v["K_std_us"] = serde_json::json!(rows(s.stiffness(), fk));
        }
    }
    Ok(v)
}

/// US customary units of `M`, `C`, `K`: the SI unit as the table labels it, the US unit, and
/// one SI unit in US units (a pound is 0.453 592 37 kg; lbf and inch as in
/// `bearing_ident::units`).
const US: [(&str, &str, f64); 3] = [
    ("(kg)", "(lbm)", 1.0 / 0.453_592_37),
    (
        "(N·s/m)",
        "(lbf·s/in)",
        bearing_ident::units::INCH / bearing_ident::units::LBF,
    ),
    (
        "(N/m)",
        "(lbf/in)",
        bearing_ident::units::INCH / bearing_ident::units::LBF,
    ),
];

/// `c` in US customary units ([`US`]).
fn in_us(c: &Coefficients) -> Coefficients {
    let [fm, fc, fk] = US.map(|(_, _, f)| f);
    let scaled = |m: faer::MatRef<'_, f64>, k: f64| {
        faer::Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)] * k)
    };
    Coefficients::new(
        scaled(c.mass(), fm),
        scaled(c.damping(), fc),
        scaled(c.stiffness(), fk),
    )
    .unwrap_or_else(|_| c.clone())
}

/// One line per coefficient: name, value, standard deviation, and truth with error if known.
fn coefficient_lines(
    out: &mut String,
    axes: &[String],
    values: &Coefficients,
    std: Option<&Coefficients>,
    truth: Option<&Coefficients>,
    us: bool,
) {
    if us {
        let rows = coefficient_rows(
            &in_us(values),
            std.map(in_us).as_ref(),
            None,
            truth.map(in_us).as_ref(),
            axes,
        );
        return coefficient_table(out, rows, truth.is_some(), true);
    }
    coefficient_table(
        out,
        coefficient_rows(values, std, None, truth, axes),
        truth.is_some(),
        false,
    );
}

/// The lines of [`coefficient_lines`] from its rows, relabelled in US units if `us`.
fn coefficient_table(
    out: &mut String,
    rows: Vec<bearing_ident::plot::CoefficientRow>,
    truth: bool,
    us: bool,
) {
    let _ = write!(out, "  {:<16} {:>15} {:>11}", "coefficient", "value", "±1σ");
    if truth {
        let _ = write!(out, " {:>15} {:>10}", "true", "error");
    }
    let _ = writeln!(out);
    for row in rows {
        let mut label = row.label.clone();
        if us {
            for (si, us, _) in US {
                label = label.replace(si, us);
            }
        }
        let _ = write!(out, "  {:<16} {:>15} {:>11}", label, row.value, row.std_dev);
        if let (Some(truth), Some(error)) = (&row.truth, &row.error) {
            let _ = write!(out, " {truth:>15} {error:>10}");
        }
        let _ = writeln!(out);
    }
}

/// One line on the stability of a rigid rotor on the element, for the HTML report's head,
/// when a speed or load was given.
pub fn stability_line(c: &Context) -> Option<String> {
    let s = c.stability.as_ref()?;
    let pm = |v: Option<f64>, sd: Option<f64>, unit: &str| match (v, sd) {
        (Some(v), Some(sd)) => format!("{} ± {}{unit}", sig(v, 4), sig(sd, 2)),
        (Some(v), None) => format!("{}{unit}", sig(v, 4)),
        (None, _) => "—".into(),
    };
    let mut line = format!(
        "Stability of a rigid rotor on the element (Lund): whirl-frequency ratio {}, threshold \
         speed {}, C_eff crossover {}.",
        pm(s.whirl_frequency_ratio, s.whirl_frequency_ratio_std, ""),
        pm(s.threshold_speed_rpm, s.threshold_speed_rpm_std, " rpm"),
        pm(s.c_eff_crossover_hz, s.c_eff_crossover_hz_std, " Hz"),
    );
    if let Some(reason) = &s.reason {
        let _ = write!(line, " ({reason})");
    }
    Some(line)
}

/// The dimensionless coefficients and the stability of a rigid rotor on the element, when
/// the conditions were given.
fn rotor_lines(out: &mut String, axes: &[String], c: &Context) {
    let pm = |v: Option<f64>, s: Option<f64>, digits: usize| match (v, s) {
        (Some(v), Some(s)) => format!("{} ± {}", sig(v, digits), sig(s, 2)),
        (Some(v), None) => sig(v, digits),
        (None, _) => "—".into(),
    };
    if let Some(d) = &c.dimensionless {
        let _ = writeln!(
            out,
            "Dimensionless (c = {} µm, W = {} N, Ω = {} rpm; K̄ = Kc/W, C̄ = CΩc/W, M̄ = MΩ²c/W)",
            sig(d.clearance_m() * 1e6, 4),
            sig(d.load_n(), 4),
            sig(d.speed_rad_s() * 60.0 / (2.0 * std::f64::consts::PI), 5)
        );
        let n = d.stiffness().nrows();
        let labels = axis_labels(axes, n);
        let std = d.std_dev();
        for (b, (name, m)) in [("K̄", d.stiffness()), ("C̄", d.damping()), ("M̄", d.mass())]
            .into_iter()
            .enumerate()
        {
            for i in 0..n {
                for j in 0..n {
                    let s = std.map(|s| s[b][(i, j)]);
                    let _ = writeln!(
                        out,
                        "  {:<16} {:>24}",
                        format!("{name}_{}{}", labels[i], labels[j]),
                        pm(Some(m[(i, j)]), s, 5)
                    );
                }
            }
        }
        let _ = writeln!(out);
    }
    if let Some(s) = &c.stability {
        let _ = writeln!(out, "Stability of a rigid rotor on the element (Lund)");
        let _ = writeln!(
            out,
            "  whirl-frequency ratio {}",
            pm(s.whirl_frequency_ratio, s.whirl_frequency_ratio_std, 4)
        );
        let _ = writeln!(
            out,
            "  threshold speed {} rpm",
            pm(s.threshold_speed_rpm, s.threshold_speed_rpm_std, 5)
        );
        let _ = writeln!(
            out,
            "  C_eff crossover {} Hz",
            pm(s.c_eff_crossover_hz, s.c_eff_crossover_hz_std, 5)
        );
        if let Some(reason) = &s.reason {
            out.push_str(&text::wrap("  ", reason, 4));
        }
        let _ = writeln!(out);
    }
}

/// `  timings (ms): read …, <every stage>, total …`, a line of the table.
pub fn timings_line(out: &mut String, stages: &[(&str, Duration)], total: Duration) {
    let stages: Vec<String> = stages
        .iter()
        .map(|(name, d)| format!("{name} {:.2}", d.as_secs_f64() * 1e3))
        .collect();
    let _ = writeln!(
        out,
        "  timings (ms): {}, total {:.2}",
        stages.join(", "),
        total.as_secs_f64() * 1e3
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
    let run = format!(
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
    out.push_str(&text::wrap("", &run, 2));
    let band = format!(
        "band {:.2}–{:.2} Hz: {} lines used, {:.3}–{:.3} Hz; {} averages; window {}",
        id.band().low_hz(),
        id.band().high_hz(),
        freqs.len(),
        freqs[0],
        freqs[freqs.len() - 1],
        id.frf().averages(),
        id.window().describe()
            + if id.window().decay_per_s().is_some() {
                ", coefficients corrected"
            } else {
                ""
            }
            + &id.force_gate().map_or(String::new(), |g| {
                format!("; force gate {} s + {} s taper", g.open_s(), g.taper_s())
            })
    );
    out.push_str(&text::wrap("", &band, 2));
    out.push('\n');
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
    coefficient_lines(&mut out, &axes, co, id.std_dev(), truth, c.us_units);
    let _ = writeln!(out);
    if let Some((b, std, source)) = &c.bearing {
        let _ = writeln!(out, "Bearing: system − baseline ({source})");
        coefficient_lines(&mut out, &axes, b, std.as_ref(), None, c.us_units);
        let _ = writeln!(out);
    }
    rotor_lines(&mut out, &axes, c);
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
        c.timings.compute.as_secs_f64() * 1e3
    );
    if c.show_timings {
        timings_line(&mut out, &c.timings.stages(), c.timings.total());
    }
    if let Some(ml) = id.ml() {
        let _ = writeln!(
            out,
            "  maximum likelihood: {} steps, cost {:.4e} (IVF start {:.4e}), cost / expected {:.3}{}",
            ml.convergence.iterations(),
            ml.cost,
            ml.start_cost,
            ml.cost_ratio,
            ml.fell_back
                .as_ref()
                .map_or(String::new(), |r| format!("; kept IVF: {r}"))
        );
    }
    if let Some(c) = id.min_coherence() {
        let _ = writeln!(out, "  multiple coherence: min {c:.4} over the lines used");
    }
    model_check_lines(&mut out, id);
    if let Some(model) = id.model() {
        element_model_lines(&mut out, &axes, model);
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

/// The element model: its family and poles, the residues on the diagonal, and every family
/// tried with its verdict.
fn element_model_lines(
    out: &mut String,
    axes: &[String],
    model: &bearing_ident::element::ElementModel,
) {
    let poles: Vec<String> = model
        .poles_hz()
        .iter()
        .zip(
            model
                .poles_hz_std()
                .unwrap_or_default()
                .iter()
                .chain(std::iter::repeat(&f64::NAN)),
        )
        .map(|(p, s)| format!("{p:.3} ± {s:.3} Hz"))
        .collect();
    let _ = writeln!(
        out,
        "  element model: {}{} (the coefficients above are its constant part)",
        model.family(),
        if poles.is_empty() {
            String::new()
        } else {
            format!(", poles {}", poles.join(", "))
        }
    );
    let fit = model.fit();
    let family = model.family();
    for b in 3..family.parameters_per_element() {
        if !matches!(family, bearing_ident::element::Family::States { .. }) {
            break;
        }
        let (a, sa) = (fit.matrix(b), fit.matrix_std(b));
        let cells: Vec<String> = axes
            .iter()
            .enumerate()
            .map(|(i, ax)| {
                let s = sa.as_ref().map_or(f64::NAN, |m| m[(i, i)]);
                format!(
                    "{}_{ax}{ax} {} ± {}",
                    family.parameter_name(b),
                    sig(a[(i, i)], 5),
                    sig(s, 2)
                )
            })
            .collect();
        let _ = writeln!(out, "    {} N/m", cells.join(", "));
    }
    let _ = writeln!(out, "    families tried:");
    for c in model.selection() {
        let _ = match (c.statistic, c.dof) {
            (Some(s), Some(d)) => writeln!(
                out,
                "      {:<10} {} (χ²/expected {:.2})",
                c.family.to_string(),
                c.verdict,
                s / d
            ),
            _ => writeln!(out, "      {:<10} {}", c.family.to_string(), c.verdict),
        };
    }
}

/// The per-line diagonal coefficients as a table (the JSON has every element), split into
/// blocks of whole degrees of freedom when wider than
/// [`TABLE_WIDTH`](bearing_ident::text::TABLE_WIDTH).
fn per_frequency_lines(out: &mut String, axes: &[String], pf: &PerFrequency) {
    let _ = writeln!(out, "\nPer frequency (diagonal; ± one standard deviation)");
    let mut header = vec!["f (Hz)".to_owned()];
    for a in axes {
        header.push(format!("K_{a}{a} (N/m)"));
        header.push(format!("C_{a}{a} (N·s/m)"));
    }
    let mut rows = vec![header];
    let pm = |v: f64, s: Option<f64>| match s {
        Some(s) => format!("{} ± {}", sig(v, 6), sig(s, 2)),
        None => sig(v, 6),
    };
    for (k, f) in pf.freqs_hz().iter().enumerate() {
        let mut row = vec![format!("{f:.3}")];
        for i in 0..axes.len() {
            let ks = pf.stiffness_std(k).map(|s| s[(i, i)]);
            let cs = pf.damping_std(k).map(|s| s[(i, i)]);
            row.push(pm(pf.stiffness(k)[(i, i)], ks));
            row.push(pm(pf.damping(k)[(i, i)], cs));
        }
        rows.push(row);
    }
    let groups = vec![2; axes.len()];
    out.push_str(&text::table(&rows, 1, &groups, Align::Right, 2));
}
