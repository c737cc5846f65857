//! [`select`]: the smallest family the model check accepts ([`ModelSpec::Auto`]), or the one
//! asked for.

use super::fit::{Data, fit_data};
use super::{Candidate, Curve, ElementModel, Family};
use crate::error::{Error, Result, Warning, excerpt};
use crate::frf::Frf;
use crate::identify::{ModelCheck, Verdict};
use crate::model::Coefficients;

/// Which element model an identification fits ([`Identifier::model`](crate::Identifier::model)).
///
/// # Examples
/// ```
/// use bearing_ident::element::{Family, ModelSpec};
/// assert_eq!("auto".parse::<ModelSpec>()?, ModelSpec::Auto);
/// assert_eq!("states:1".parse::<ModelSpec>()?, ModelSpec::Family(Family::States { poles: 1 }));
/// assert_eq!(ModelSpec::default(), ModelSpec::Family(Family::Kcm));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ModelSpec {
    /// This family.
    Family(Family),
    /// The smallest family the model check accepts ([`select`]).
    Auto,
}

impl Default for ModelSpec {
    fn default() -> Self {
        ModelSpec::Family(Family::Kcm)
    }
}

impl std::fmt::Display for ModelSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModelSpec::Family(family) => family.fmt(f),
            ModelSpec::Auto => f.write_str("auto"),
        }
    }
}

impl std::str::FromStr for ModelSpec {
    type Err = Error;

    /// `auto` or a [`Family`]'s form.
    ///
    /// # Errors
    /// As [`Family`]'s.
    fn from_str(s: &str) -> Result<Self> {
        if s.trim().eq_ignore_ascii_case("auto") {
            return Ok(ModelSpec::Auto);
        }
        s.parse().map(ModelSpec::Family).map_err(|e| match e {
            Error::InvalidOption { option, .. } => Error::InvalidOption {
                option,
                message: format!(
                    "--model `{}`: expected auto, kc, kcm, poly:P (P from 1 to {}) or states:N \
                     (N from 1 to {})",
                    excerpt(s),
                    Family::MAX_DEGREE,
                    Family::MAX_POLES
                ),
            },
            e => e,
        })
    }
}

/// Most states [`ModelSpec::Auto`] tries.
pub const AUTO_MAX_POLES: usize = 3;

/// The element model of `frf` for `spec`, with the model check of every family tried
/// (`runs_stride` as [`ModelCheck`]'s), `start` (the estimator's `K`, `C`, `M`) starting the
/// fits without poles:
/// - a family by name is fitted and checked;
/// - [`ModelSpec::Auto`] tries the families in order of size (`kc`, `kcm`, `states:1` …
///   `states:3`, `poly:2`), refuses those the data cannot support (too few lines, a pole
///   beyond a third of the band's lower edge or three times its upper edge, a pole
///   undetermined to within its own size, residues of a pole all within two standard
///   deviations of zero), and chooses the smallest that the check accepts; when none does,
///   the supported one of least BIC, its misfit warned.
///
/// The chosen fit's standard deviations are widened by the check's Birge factor
/// `√max(1, χ²/expected)`.
///
/// # Errors
/// Those of [`fit_family`](super::fit_family) for a family by name; with `Auto`, only when
/// no family can be fitted at all ([`Error::SingularFit`]).
///
/// # Examples
/// ```
/// use bearing_ident::element::{Family, ModelSpec, select};
/// use bearing_ident::{Identifier, simulate::{ImpactTest, seed_rig}};
/// let records = ImpactTest { per_direction: 4, noise: 0.03, ..ImpactTest::seed_rig() }
///     .run(&seed_rig())?;
/// let frf = Identifier::new(8.0, 49.0).identify(&records)?.frf().clone();
/// let (model, _) = select(&frf, ModelSpec::Auto, 1, None)?;
/// assert_eq!(model.family(), Family::Kcm); // a right KCM model is chosen
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn select(
    frf: &Frf,
    spec: ModelSpec,
    runs_stride: usize,
    start: Option<&Coefficients>,
) -> Result<(ElementModel, Vec<Warning>)> {
    let data = Data::of(frf);
    let families = match spec {
        ModelSpec::Family(family) => vec![family],
        ModelSpec::Auto => Family::candidates(AUTO_MAX_POLES),
    };
    let auto = spec == ModelSpec::Auto;
    let mut tried: Vec<(Candidate, Option<Tried>)> = Vec::new();
    let mut previous_poles: Vec<f64> = Vec::new();
    // A family of states asked for by name starts from the poles of the one a state smaller,
    // as `auto` does: a search from the band alone can merge two poles into one.
    if let ModelSpec::Family(Family::States { poles }) = spec {
        for smaller in 1..poles {
            let start_poles = cascade(&previous_poles, frf);
            let fit = fit_data(
                &data,
                Family::States { poles: smaller },
                Some(&start_poles),
                start,
            );
            match fit {
                Ok(fit) => previous_poles = fit.poles().to_vec(),
                Err(_) => break,
            }
        }
    }
    // The fitted families' statistics and sizes: a larger family's residues are supported
    // when its statistic falls below every smaller one's by more than chance would.
    let mut smaller_fits: Vec<(f64, usize)> = Vec::new();
    for family in families {
        let start_poles =
            (family.poles() == previous_poles.len() + 1).then(|| cascade(&previous_poles, frf));
        let fitted = fit_data(&data, family, start_poles.as_deref(), start);
        let (candidate, kept) = match fitted {
            Err(e) if auto => (refused(family, "unsupported", e.to_string()), None),
            Err(Error::TooFewLines { lines, .. }) => {
                return Err(Error::InvalidOption {
                    option: "model",
                    message: format!(
                        "--model {family}: {} parameters per element need more than {} lines; \
                         the band holds {lines}",
                        family.parameters_per_element(),
                        family.parameters_per_element() / 2,
                    ),
                });
            }
            Err(e) => return Err(e),
            Ok(fit) => {
                if family.poles() > 0 {
                    previous_poles = fit.poles().to_vec();
                }
                let (check, warning) =
                    ModelCheck::of_family(&data, &fit, frf.freqs_hz(), runs_stride)?;
                let (size, terms2) = (family.size(data.n), check.dof.unwrap_or(0.0));
                let needed = check.statistic.is_some_and(|now| {
                    smaller_fits.iter().all(|&(before, smaller)| {
                        let extra = size.saturating_sub(smaller).max(1) as f64;
                        crate::statistics::chi2_upper_tail((before - now).max(0.0), extra)
                            .is_ok_and(|p| p < LIKELIHOOD_RATIO_P)
                    })
                });
                if let Some(stat) = check.statistic {
                    smaller_fits.push((stat, size));
                }
                let unsupported = if auto {
                    unsupported(&fit, frf, needed)
                } else {
                    None
                };
                let criterion = check
                    .statistic
                    .map(|s| s + size as f64 * (terms2 + size as f64).max(1.0).ln());
                let verdict = match (&unsupported, &check.verdict) {
                    (Some(_), _) => "unsupported",
                    (None, Verdict::Misfit) => "misfit",
                    (None, _) => "fits",
                };
                let candidate = Candidate {
                    family,
                    statistic: check.statistic,
                    dof: check.dof,
                    p_value: check.p_value,
                    runs_p_value: check.runs_p_value,
                    criterion,
                    verdict,
                    reason: unsupported,
                };
                (candidate, Some((fit, check, warning.into_iter().collect())))
            }
        };
        tried.push((candidate, kept));
        // The smallest family that fits is the choice: larger ones are not fitted.
        if auto && tried.last().is_some_and(|(c, _)| c.verdict == "fits") {
            break;
        }
    }
    let chosen = tried
        .iter()
        .position(|(c, _)| c.verdict == "fits")
        .or_else(|| {
            tried
                .iter()
                .enumerate()
                .filter(|(_, (c, k))| c.verdict != "unsupported" && k.is_some())
                .min_by(|a, b| {
                    let key = |c: &Candidate| c.criterion.unwrap_or(f64::INFINITY);
                    key(&a.1.0).total_cmp(&key(&b.1.0))
                })
                .map(|(i, _)| i)
        })
        .ok_or(Error::SingularFit {
            method: crate::Method::LeastSquares,
        })?;
    let selection: Vec<Candidate> = tried
        .iter()
        .enumerate()
        .map(|(i, (c, _))| {
            let mut c = c.clone();
            if i == chosen {
                c.verdict = "chosen";
            }
            c
        })
        .collect();
    let (fit, check, warnings) = tried.remove(chosen).1.expect("chosen is fitted");
    let others = tried
        .into_iter()
        .filter_map(|(_, t)| t.map(|t| t.0))
        .collect();
    let fit = fit.widened(check.birge_factor());
    let mass = constant_mass(&fit);
    let curve = Curve::of(&fit, frf.freqs_hz(), mass.as_ref());
    Ok((
        ElementModel {
            fit,
            check,
            selection,
            curve,
            others,
        },
        warnings,
    ))
}

/// A family fitted and checked: its fit, its check and the check's warnings.
type Tried = (super::FamilyFit, ModelCheck, Vec<Warning>);

fn refused(family: Family, verdict: &'static str, reason: String) -> Candidate {
    Candidate {
        family,
        statistic: None,
        dof: None,
        p_value: None,
        runs_p_value: None,
        criterion: None,
        verdict,
        reason: Some(reason),
    }
}

/// Why the data cannot support `fit`'s poles, if they cannot.
/// Below this probability the fall of the model check's statistic from a smaller family to a
/// larger one is more than chance: the larger family's extra terms are needed.
const LIKELIHOOD_RATIO_P: f64 = 0.01;

/// The start of a search for one pole more than `previous`: those poles and one at the middle
/// of the band.
fn cascade(previous: &[f64], frf: &Frf) -> Vec<f64> {
    let mut p = previous.to_vec();
    p.push(2.0 * std::f64::consts::PI * frf.freqs_hz()[frf.line_count() / 2]);
    p
}

fn unsupported(fit: &super::FamilyFit, frf: &Frf, needed: bool) -> Option<String> {
    let freqs = frf.freqs_hz();
    let (low, high) = (
        freqs.iter().copied().fold(f64::INFINITY, f64::min),
        freqs.iter().copied().fold(0.0, f64::max),
    );
    let two_pi = 2.0 * std::f64::consts::PI;
    let std = fit.pole_std();
    for (j, &p) in fit.poles().iter().enumerate() {
        let hz = p / two_pi;
        if hz < low / 3.0 || hz > 3.0 * high {
            return Some(format!(
                "a pole at {hz:.3} Hz, beyond the band's reach ({:.3}–{:.3} Hz): its term is a \
                 constant or a pure damping there",
                low / 3.0,
                3.0 * high
            ));
        }
        match std.map(|s| s[j]) {
            Some(s) if s.is_finite() && s > 0.0 && s < p => {}
            Some(s) => {
                return Some(format!(
                    "the pole at {hz:.3} Hz is not determined (± {:.3} Hz)",
                    s / two_pi
                ));
            }
            None => return Some("the poles' covariance is singular".to_string()),
        }
        // Two poles closer than their combined standard deviation are one.
        if let Some(std) = std {
            for (k, &q) in fit.poles().iter().enumerate().skip(j + 1) {
                if (p - q).abs() < std[j].hypot(std[k]) {
                    return Some(format!(
                        "the poles at {hz:.3} and {:.3} Hz are not told apart",
                        q / two_pi
                    ));
                }
            }
        }
        if needed {
            // The statistic's fall from every smaller family is the residues' evidence, when
            // they are correlated with each other or with M, more than their one-by-one σ.
            continue;
        }
        let (a, sa) = (fit.matrix(3 + j), fit.matrix_std(3 + j)?);
        let n = fit.dofs();
        let significant = (0..n * n).any(|e| {
            let (i, k) = (e % n, e / n);
            a[(i, k)].abs() > 2.0 * sa[(i, k)]
        });
        if !significant {
            return Some(format!(
                "the residues of the pole at {hz:.3} Hz are all within two standard deviations of zero"
            ));
        }
    }
    None
}

/// The mass the curve's `K(ω) = Re H + ω²M` takes: the fit's constant mass.
pub(crate) fn constant_mass(fit: &super::FamilyFit) -> faer::Mat<f64> {
    let n = fit.dofs();
    match fit.family() {
        Family::Kc => faer::Mat::zeros(n, n),
        Family::Kcm | Family::States { .. } => fit.matrix(2),
        Family::Poly { degree } if degree >= 2 => {
            let w0 = fit.omega0();
            let k2 = fit.matrix(2);
            faer::Mat::from_fn(n, n, |i, j| -k2[(i, j)] / (w0 * w0))
        }
        Family::Poly { .. } => faer::Mat::zeros(n, n),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::identify::Identifier;
    use crate::records::Record;
    use crate::simulate::{add_noise, seed_rig};
    use crate::spectra::{Segmentation, Window};
    use faer::linalg::solvers::DenseSolveCore;
    use faer::{Mat, c64, mat};
    use rand::{RngExt, SeedableRng};
    use realfft::RealFftPlanner;

    /// Exact periodic records of the seed rig with internal states (poles in Hz, residues):
    /// random-phase multisines on lines 8–49 of a 1 s period at 1000 samples/s, one direction
    /// per record, three records per direction, 8 periods, the steady state computed at the
    /// lines (`X = H⁻¹ F`), then `noise` on every channel.
    pub(crate) fn states_records(
        poles_hz: &[f64],
        residues: &[Mat<f64>],
        noise: f64,
        seed: u64,
    ) -> Vec<Record> {
        let truth = seed_rig();
        let (rate, period, periods) = (1000.0, 1000usize, 8usize);
        let inverse = RealFftPlanner::<f64>::new().plan_fft_inverse(period);
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let mut records = Vec::new();
        for d in 0..2 {
            for r in 0..3 {
                let zero = c64::new(0.0, 0.0);
                let mut f = vec![zero; period / 2 + 1];
                let mut x = vec![vec![zero; period / 2 + 1]; 2];
                for k in 8..=49 {
                    let phase = rng.random::<f64>() * std::f64::consts::TAU;
                    f[k] = c64::new(phase.cos(), phase.sin()) * 5000.0;
                    let s = c64::new(0.0, std::f64::consts::TAU * k as f64);
                    let mut h = truth.impedance_at(k as f64);
                    for (p, a) in poles_hz.iter().zip(residues) {
                        let pole = std::f64::consts::TAU * p;
                        for i in 0..2 {
                            for j in 0..2 {
                                h[(i, j)] += s / (s + pole) * a[(i, j)];
                            }
                        }
                    }
                    let g = h.partial_piv_lu().inverse();
                    for i in 0..2 {
                        x[i][k] = g[(i, d)] * f[k];
                    }
                }
                let time = |spec: &[c64]| {
                    let (mut spec, mut out) = (spec.to_vec(), vec![0.0; period]);
                    inverse.process(&mut spec, &mut out).unwrap();
                    let one: Vec<f64> = out.iter().map(|v| v / period as f64).collect();
                    (0..periods).flat_map(|_| one.clone()).collect::<Vec<f64>>()
                };
                let mut forces = vec![vec![0.0; period * periods]; 2];
                forces[d] = time(&f);
                let clean = Record::new(
                    format!("ms-{d}-{r}"),
                    rate,
                    forces,
                    vec![time(&x[0]), time(&x[1])],
                )
                .unwrap();
                records.push(add_noise(&clean, noise, &mut rng).unwrap());
            }
        }
        records
    }

    fn identify(records: &[Record], spec: ModelSpec) -> crate::Identification {
        Identifier::new(8.0, 49.0)
            .estimator(crate::Estimator::H1)
            .segmentation(Segmentation::Periods { len: 1000 })
            .window(Window::Rectangular)
            .model(spec)
            .identify(records)
            .unwrap()
    }

    /// `auto` chooses the family the records were made with — `kcm`, one state, two states —
    /// and recovers its poles and residues within their error bars; the constant part is the
    /// rig's.
    #[test]
    fn auto_chooses_the_family_of_the_records() {
        let cases = [
            (vec![], vec![], Family::Kcm),
            (
                vec![20.0],
                vec![mat![[4e4, 0.0], [0.0, 3e4]]],
                Family::States { poles: 1 },
            ),
            (
                vec![12.0, 35.0],
                vec![mat![[3e4, 0.0], [0.0, 2e4]], mat![[2e4, -5e3], [0.0, 4e4]]],
                Family::States { poles: 2 },
            ),
        ];
        for (poles, residues, family) in cases {
            let id = identify(&states_records(&poles, &residues, 0.02, 3), ModelSpec::Auto);
            let model = id.model().unwrap();
            eprintln!(
                "{family}: chose {} poles {:?} ± {:?}",
                model.family(),
                model.poles_hz(),
                model.poles_hz_std()
            );
            assert_eq!(model.family(), family);
            let std = model.poles_hz_std().unwrap();
            for (j, p) in poles.iter().enumerate() {
                let z = (model.poles_hz()[j] - p) / std[j];
                assert!(z.abs() < 3.0, "pole {p}: {z} σ");
                let (a, sa) = (
                    model.fit().matrix(3 + j),
                    model.fit().matrix_std(3 + j).unwrap(),
                );
                for i in 0..2 {
                    let z = (a[(i, i)] - residues[j][(i, i)]) / sa[(i, i)];
                    assert!(z.abs() < 3.0, "A{}[{i}][{i}]: {z} σ", j + 1);
                }
            }
            let (c, s, t) = (
                id.coefficients().stiffness(),
                id.std_dev().unwrap().stiffness(),
                seed_rig(),
            );
            for i in 0..2 {
                let z = (c[(i, i)] - t.stiffness()[(i, i)]) / s[(i, i)];
                assert!(z.abs() < 3.0, "K[{i}][{i}]: {z} σ");
            }
            // Every family before the chosen one was tried and refused.
            let tried = model.selection();
            assert_eq!(tried.last().unwrap().verdict, "chosen");
            assert!(
                tried[..tried.len() - 1]
                    .iter()
                    .all(|c| c.verdict != "chosen")
            );
        }
    }

    /// With the default kcm, records of an element with a state are a misfit, and the warning
    /// names the family that fits.
    #[test]
    fn a_kcm_misfit_names_the_family_that_fits() {
        let records = states_records(&[20.0], &[mat![[4e4, 0.0], [0.0, 3e4]]], 0.02, 4);
        let id = identify(&records, ModelSpec::default());
        let kinds: Vec<&str> = id.warnings().iter().map(|w| w.kind()).collect();
        assert!(kinds.contains(&"model_misfit"), "{kinds:?}");
        let hint = id
            .warnings()
            .iter()
            .find(|w| w.kind() == "frequency_dependent")
            .expect("named");
        assert!(hint.to_string().contains("states:1"), "{hint}");
        assert!(id.model().is_none());
    }

    /// A family asked for by name is fitted even when it misfits; one with more parameters per
    /// element than the lines allow is refused, naming the counts.
    #[test]
    fn a_family_by_name_is_fitted_or_refused() {
        let records = states_records(&[20.0], &[mat![[4e4, 0.0], [0.0, 3e4]]], 0.02, 5);
        let id = identify(&records, ModelSpec::Family(Family::Kc));
        assert_eq!(id.model().unwrap().family(), Family::Kc);
        assert_eq!(id.model_check().verdict, Verdict::Misfit);
        assert_eq!(id.coefficients().mass()[(0, 0)].to_bits(), 0.0f64.to_bits());
        let e = Identifier::new(8.0, 14.0)
            .estimator(crate::Estimator::H1)
            .segmentation(Segmentation::Periods { len: 1000 })
            .model(ModelSpec::Family(Family::Poly { degree: 6 }))
            .identify(&records)
            .unwrap_err();
        assert!(e.to_string().contains("14 parameters per element"), "{e}");
        assert!(e.to_string().contains("the band holds 7"), "{e}");
    }
}
