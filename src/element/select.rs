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
    let mut tried: Vec<(
        Candidate,
        Option<(super::FamilyFit, ModelCheck, Vec<Warning>)>,
    )> = Vec::new();
    let mut previous_poles: Vec<f64> = Vec::new();
    for family in families {
        let start_poles = (family.poles() == previous_poles.len() + 1).then(|| {
            let mut p = previous_poles.clone();
            p.push(2.0 * std::f64::consts::PI * frf.freqs_hz()[frf.line_count() / 2]);
            p
        });
        let fitted = fit_data(&data, family, start_poles.as_deref(), start);
        let (candidate, kept) = match fitted {
            Err(e) if auto => (refused(family, "unsupported", e.to_string()), None),
            Err(e) => return Err(e),
            Ok(fit) => {
                if family.poles() > 0 {
                    previous_poles = fit.poles().to_vec();
                }
                let (check, warning) =
                    ModelCheck::of_family(&data, &fit, frf.freqs_hz(), runs_stride)?;
                let unsupported = if auto { unsupported(&fit, frf) } else { None };
                let (size, terms2) = (family.size(data.n), check.dof.unwrap_or(0.0));
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
    let (fit, check, warnings) = tried.swap_remove(chosen).1.expect("chosen is fitted");
    let fit = fit.widened(check.birge_factor());
    let mass = constant_mass(&fit);
    let curve = Curve::of(&fit, frf.freqs_hz(), &mass);
    Ok((
        ElementModel {
            fit,
            check,
            selection,
            curve,
        },
        warnings,
    ))
}

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
fn unsupported(fit: &super::FamilyFit, frf: &Frf) -> Option<String> {
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
            Some(s) if s.is_finite() && s < p => {}
            Some(s) => {
                return Some(format!(
                    "the pole at {hz:.3} Hz is not determined (± {:.3} Hz)",
                    s / two_pi
                ));
            }
            None => return Some("the poles' covariance is singular".to_string()),
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
fn constant_mass(fit: &super::FamilyFit) -> faer::Mat<f64> {
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
