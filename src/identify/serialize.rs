//! The JSON form of an [`Identification`] (feature `serde`): one flat object whose field
//! names the command line's `--json` output and [`Baseline::from_json`](super::Baseline)
//! read back.

use crate::Choice;
use crate::error::Warning;
use crate::solve::Method;
use crate::spectra::Segmentation;

use super::{Budget, Identification, ModelCheck, Uncertainty, Verdict};

/// Serializes as one flat object, in SI units and Hz:
/// `method`, `estimator`, `window` (its string form: `rect`, `hann`, `exp:A/s`),
/// `window_decay_per_s` (the exponential window's `a`, null
/// otherwise), `segmentation` (`whole`, `welch`, `periods`), `segment_len`, `force_gate_s`
/// (the gate's open time, null without), `unexcited_lines` (periodic excitation), `n`, `band_hz`, `band_used_hz`, `n_freq`, `freqs_hz`, `M`, `C`, `K`,
/// `M_std`, `C_std`, `K_std` (null when not available), `uncertainty`, `M_ci95`, `C_ci95`,
/// `K_ci95` (half-widths of the 95 % intervals), `iterations`, `converged`,
/// `convergence`, `residual_norm`, `condition_number` (`min`, `median`, `max`),
/// `condition_numbers` (per line), `fit` (per-element flexibility `r²`),
/// `natural_frequencies_hz`, `damping_ratios`, `averages`, `coherence_min`, `warnings` (sentences), `warning_kinds` (their
/// [`Warning::kind`] names, in the same order), `history`
/// (IVF iterations), `predicted_bias` (`{source, M, C, K}`, absolute, or null; see
/// [`Identification::predicted_bias`]), `period` and `periods_dropped`; `model_check` (`statistic`, `expected`, `dof`, `p_value`, `runs_p_value`, `verdict`
/// `fits`/`misfit`/`untested`, `reason`), `budget` (`random`, `model`, `calibration`, each
/// with `M_std`, `C_std`, `K_std`; null without error bars; the top-level `*_std` are the
/// combined standard uncertainties), `noise` (H1 over periods or Welch segments: `source`
/// `periods`/`segments`, `compensated`, `force_ratio`, `force_ratio_std`, `response_ratio`,
/// `response_ratio_std`, each channel's noise over signal power in the band; null otherwise;
/// see [`Identification::noise_floor`]), `model` (the element model asked for, null for the
/// default: see [`ElementModel`](crate::element::ElementModel)'s serialization),
/// `natural_frequencies_hz_std`, `damping_ratios_std`.
impl serde::Serialize for Identification {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use crate::model::rows;
        use serde::ser::SerializeMap;
        let c = self.coefficients();
        let freqs = self.freqs_hz();
        let modes = self.modes().unwrap_or_default();
        let std = self.std_dev();
        let ci = self.interval_95();
        let cond = &self.conditioning;
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("method", self.method().name())?;
        m.serialize_entry("estimator", self.estimator.name())?;
        m.serialize_entry("window", &self.window.to_string())?;
        m.serialize_entry("window_decay_per_s", &self.window.decay_per_s())?;
        let (segments, segment_len) = match self.segmentation() {
            Segmentation::Welch { len } => ("welch", Some(len)),
            Segmentation::Periods { len } => ("periods", Some(len)),
            _ => ("whole", None),
        };
        m.serialize_entry("segmentation", segments)?;
        m.serialize_entry("segment_len", &segment_len)?;
        m.serialize_entry("force_gate_s", &self.force_gate.map(|g| g.open_s()))?;
        m.serialize_entry("unexcited_lines", &self.frf.unexcited_hz().len())?;
        m.serialize_entry("n", &c.dofs())?;
        m.serialize_entry("band_hz", &[self.band.low_hz(), self.band.high_hz()])?;
        m.serialize_entry("band_used_hz", &[freqs[0], freqs[freqs.len() - 1]])?;
        m.serialize_entry("n_freq", &freqs.len())?;
        m.serialize_entry("freqs_hz", freqs)?;
        m.serialize_entry("M", &rows(c.mass()))?;
        m.serialize_entry("C", &rows(c.damping()))?;
        m.serialize_entry("K", &rows(c.stiffness()))?;
        m.serialize_entry("M_std", &std.map(|s| rows(s.mass())))?;
        m.serialize_entry("C_std", &std.map(|s| rows(s.damping())))?;
        m.serialize_entry("K_std", &std.map(|s| rows(s.stiffness())))?;
        let uncertainty = match (self.uncertainty, self.method()) {
            (Uncertainty::Sandwich, Method::Ml) => "fisher",
            (u, _) => u.name(),
        };
        m.serialize_entry("uncertainty", uncertainty)?;
        m.serialize_entry("ml", &self.ml)?;
        m.serialize_entry("M_ci95", &ci.as_ref().map(|s| rows(s.mass())))?;
        m.serialize_entry("C_ci95", &ci.as_ref().map(|s| rows(s.damping())))?;
        m.serialize_entry("K_ci95", &ci.as_ref().map(|s| rows(s.stiffness())))?;
        m.serialize_entry("iterations", &self.iterations())?;
        m.serialize_entry("converged", &self.converged())?;
        m.serialize_entry("convergence", self.convergence().name())?;
        m.serialize_entry("residual_norm", &self.residual_norm())?;
        let summary: std::collections::BTreeMap<&str, f64> = [
            ("min", cond.best()),
            ("median", cond.median()),
            ("max", cond.worst()),
        ]
        .into();
        m.serialize_entry("condition_number", &summary)?;
        m.serialize_entry("condition_numbers", self.condition_numbers())?;
        m.serialize_entry("fit", &rows(self.fit_r2.as_ref()))?;
        let fns: Vec<f64> = modes.iter().map(|m| m.natural_frequency_hz).collect();
        let zetas: Vec<f64> = modes.iter().map(|m| m.damping_ratio).collect();
        m.serialize_entry("natural_frequencies_hz", &fns)?;
        m.serialize_entry("damping_ratios", &zetas)?;
        m.serialize_entry("averages", &self.frf.averages())?;
        m.serialize_entry("coherence_min", &self.min_coherence())?;
        let warnings: Vec<String> = self.warnings.iter().map(ToString::to_string).collect();
        m.serialize_entry("warnings", &warnings)?;
        let kinds: Vec<&str> = self.warnings.iter().map(Warning::kind).collect();
        m.serialize_entry("warning_kinds", &kinds)?;
        m.serialize_entry("history", self.history())?;
        // Periodic records (issue 25, item 5): the period (s) and the periods left out.
        m.serialize_entry("period", &self.period_s)?;
        m.serialize_entry("periods_dropped", &self.periods_dropped)?;
        // Predicted bias (issue 25, item 8): `{source, M, C, K}`, absolute, or null.
        let predicted = self.predicted_bias.as_ref().map(|p| {
            let b = &p.bias;
            let mut out = std::collections::BTreeMap::new();
            out.insert("M", rows(b.mass()));
            out.insert("C", rows(b.damping()));
            out.insert("K", rows(b.stiffness()));
            (p.source.name(), out)
        });
        match predicted {
            Some((source, matrices)) => {
                #[derive(serde::Serialize)]
                struct Predicted<'a, T> {
                    source: &'a str,
                    #[serde(flatten)]
                    matrices: T,
                }
                m.serialize_entry("predicted_bias", &Predicted { source, matrices })?;
            }
            None => m.serialize_entry("predicted_bias", &None::<()>)?,
        }
        // The model check, the uncertainty budget, the derived quantities' error bars.
        m.serialize_entry("model_check", &self.model_check)?;
        m.serialize_entry("budget", &self.budget)?;
        m.serialize_entry("noise", &self.noise_floor)?;
        m.serialize_entry("model", &self.model)?;
        m.serialize_entry(
            "natural_frequencies_hz_std",
            &self.natural_frequencies_hz_std(),
        )?;
        m.serialize_entry("damping_ratios_std", &self.damping_ratios_std())?;
        m.end()
    }
}

/// `{statistic, expected, dof, p_value, verdict, reason}`: null numbers and a `reason` when
/// untested, `reason` null otherwise.
impl serde::Serialize for ModelCheck {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(7))?;
        m.serialize_entry("statistic", &self.statistic)?;
        m.serialize_entry("expected", &self.expected)?;
        m.serialize_entry("dof", &self.dof)?;
        m.serialize_entry("p_value", &self.p_value)?;
        m.serialize_entry("runs_p_value", &self.runs_p_value)?;
        m.serialize_entry("verdict", self.verdict.name())?;
        let reason = match &self.verdict {
            Verdict::Untested { reason } => Some(reason.as_str()),
            _ => None,
        };
        m.serialize_entry("reason", &reason)?;
        m.end()
    }
}

/// `{random, model, calibration}`, each `{M_std, C_std, K_std}` (row-major matrices).
impl serde::Serialize for Budget {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use crate::model::{Coefficients, rows};
        use serde::ser::SerializeMap;
        let part = |c: &Coefficients| -> std::collections::BTreeMap<&str, Vec<Vec<f64>>> {
            [
                ("M_std", rows(c.mass())),
                ("C_std", rows(c.damping())),
                ("K_std", rows(c.stiffness())),
            ]
            .into()
        };
        let mut m = s.serialize_map(Some(3))?;
        m.serialize_entry("random", &part(&self.random))?;
        m.serialize_entry("model", &part(&self.model))?;
        m.serialize_entry("calibration", &part(&self.calibration))?;
        m.end()
    }
}

/// `{source, compensated, force_ratio, force_ratio_std, response_ratio, response_ratio_std}`.
impl serde::Serialize for crate::frf::NoiseFloor {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(6))?;
        m.serialize_entry("source", self.source().name())?;
        m.serialize_entry("compensated", &self.compensated())?;
        m.serialize_entry("force_ratio", self.force_ratio())?;
        m.serialize_entry("force_ratio_std", self.force_ratio_std())?;
        m.serialize_entry("response_ratio", self.response_ratio())?;
        m.serialize_entry("response_ratio_std", self.response_ratio_std())?;
        m.end()
    }
}

/// `{family, order, selection: [{model, statistic, dof, p_value, runs_p_value, criterion,
/// verdict, reason}], poles_hz, poles_hz_std, matrices: [{name, value, std}], residues (the
/// states' `A_j` among the matrices, empty for other families), modes: [{
/// natural_frequency_hz, damping_ratio}], verdict, effective (2 DOF: {frequency_hz, K_eff,
/// C_eff, K_eff_std, C_eff_std, crossover_hz, crossover_hz_std}, else null), curve:
/// {frequency_hz, K, C, K_std, C_std}}`, the
/// matrices as rows and the curve one matrix per line; `order` is the number of states or the
/// polynomial degree (0 for `kc`, `kcm`).
impl serde::Serialize for crate::element::ElementModel {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use crate::element::Family;
        use crate::model::rows;
        use serde::ser::SerializeMap;
        use serde_json_free::{Candidate, Matrix};
        let family = self.family();
        let per = family.parameters_per_element();
        let fit = self.fit();
        let matrices: Vec<Matrix> = (0..per)
            .map(|b| Matrix {
                name: family.parameter_name(b),
                value: rows(fit.matrix(b).as_ref()),
                std: fit.matrix_std(b).map(|m| rows(m.as_ref())),
            })
            .collect();
        let selection: Vec<Candidate> = self
            .selection()
            .iter()
            .map(|c| Candidate {
                model: c.family.to_string(),
                statistic: c.statistic,
                dof: c.dof,
                p_value: c.p_value,
                runs_p_value: c.runs_p_value,
                criterion: c.criterion,
                verdict: c.verdict,
                reason: c.reason.clone(),
            })
            .collect();
        let curve = self.curve();
        let per_line = |v: &[faer::Mat<f64>]| -> Vec<Vec<Vec<f64>>> {
            v.iter().map(|m| rows(m.as_ref())).collect()
        };
        let modes: Vec<crate::model::Mode> = self.modes().unwrap_or_default();
        let mut m = s.serialize_map(Some(12))?;
        m.serialize_entry("family", &family.to_string())?;
        m.serialize_entry(
            "order",
            &match family {
                Family::Poly { degree } => degree,
                Family::States { poles } => poles,
                _ => 0,
            },
        )?;
        m.serialize_entry("selection", &selection)?;
        m.serialize_entry("poles_hz", &self.poles_hz())?;
        m.serialize_entry("poles_hz_std", &self.poles_hz_std())?;
        m.serialize_entry("matrices", &matrices)?;
        let residues: Vec<&Matrix> = matrices
            .iter()
            .skip(3)
            .filter(|_| matches!(family, Family::States { .. }))
            .collect();
        m.serialize_entry("residues", &residues)?;
        m.serialize_entry("modes", &modes)?;
        m.serialize_entry("verdict", self.check().verdict.name())?;
        #[derive(serde::Serialize)]
        struct EffectiveOut {
            frequency_hz: Vec<f64>,
            #[serde(rename = "K_eff")]
            k: Vec<f64>,
            #[serde(rename = "C_eff")]
            c: Vec<f64>,
            #[serde(rename = "K_eff_std")]
            k_std: Vec<f64>,
            #[serde(rename = "C_eff_std")]
            c_std: Vec<f64>,
            crossover_hz: Option<f64>,
            crossover_hz_std: Option<f64>,
        }
        m.serialize_entry(
            "effective",
            &self.effective().map(|e| EffectiveOut {
                frequency_hz: e.frequency_hz,
                k: e.stiffness,
                c: e.damping,
                k_std: e.stiffness_std,
                c_std: e.damping_std,
                crossover_hz: e.crossover_hz,
                crossover_hz_std: e.crossover_hz_std,
            }),
        )?;
        #[derive(serde::Serialize)]
        struct CurveOut {
            frequency_hz: Vec<f64>,
            #[serde(rename = "K")]
            k: Vec<Vec<Vec<f64>>>,
            #[serde(rename = "C")]
            c: Vec<Vec<Vec<f64>>>,
            #[serde(rename = "K_std")]
            k_std: Vec<Vec<Vec<f64>>>,
            #[serde(rename = "C_std")]
            c_std: Vec<Vec<Vec<f64>>>,
        }
        m.serialize_entry(
            "curve",
            &CurveOut {
                frequency_hz: curve.frequency_hz.clone(),
                k: per_line(&curve.stiffness),
                c: per_line(&curve.damping),
                k_std: per_line(&curve.stiffness_std),
                c_std: per_line(&curve.damping_std),
            },
        )?;
        m.end()
    }
}

/// The serialized shapes of [`ElementModel`](crate::element::ElementModel)'s parts.
mod serde_json_free {
    /// One coefficient matrix by name.
    #[derive(serde::Serialize)]
    pub(super) struct Matrix {
        pub(super) name: String,
        pub(super) value: Vec<Vec<f64>>,
        pub(super) std: Option<Vec<Vec<f64>>>,
    }

    /// One family of the selection.
    #[derive(serde::Serialize)]
    pub(super) struct Candidate {
        pub(super) model: String,
        pub(super) statistic: Option<f64>,
        pub(super) dof: Option<f64>,
        pub(super) p_value: Option<f64>,
        pub(super) runs_p_value: Option<f64>,
        pub(super) criterion: Option<f64>,
        pub(super) verdict: &'static str,
        pub(super) reason: Option<String>,
    }
}
