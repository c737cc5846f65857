//! [`ElementModel`]: the family chosen (or asked for), its fit, its check, the candidates
//! tried, and its `K(ω)`, `C(ω)` on the lines used ([`Curve`]).

use faer::{Mat, c64};

use super::{Family, FamilyFit};
use crate::error::Result;
use crate::identify::{ModelCheck, Verdict};
use crate::model::{Coefficients, Mode};

/// One family tried by the selection ([`select`](super::select)).
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// The family.
    pub family: Family,
    /// The model check's statistic (`None` when the family could not be fitted or checked).
    pub statistic: Option<f64>,
    /// Its degrees of freedom.
    pub dof: Option<f64>,
    /// Its upper-tail probability.
    pub p_value: Option<f64>,
    /// The runs test's probability.
    pub runs_p_value: Option<f64>,
    /// BIC, `statistic + parameters · ln(2·terms)`: smaller is better.
    pub criterion: Option<f64>,
    /// `chosen`, `fits`, `misfit`, `unsupported` or `not_tried`.
    pub verdict: &'static str,
    /// Why a family is unsupported or could not be fitted; `None` otherwise.
    pub reason: Option<String>,
}

/// The chosen model's `K(ω) = Re H(ω) + ω²M` and `C(ω) = Im H(ω)/ω` on the lines used, with
/// standard deviations (first order through the fit's covariance), `M` the model's constant
/// mass: comparable with the per-line values of
/// [`Identification::per_frequency`](crate::Identification::per_frequency).
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// The lines (Hz).
    pub frequency_hz: Vec<f64>,
    /// `K(ω)` per line.
    pub stiffness: Vec<Mat<f64>>,
    /// `C(ω)` per line.
    pub damping: Vec<Mat<f64>>,
    /// Standard deviations of `K(ω)` per line (NaN where unknown).
    pub stiffness_std: Vec<Mat<f64>>,
    /// Standard deviations of `C(ω)` per line.
    pub damping_std: Vec<Mat<f64>>,
}

/// The element model of an identification ([`Identification::model`](crate::Identification::model)).
#[derive(Debug, Clone, PartialEq)]
pub struct ElementModel {
    pub(crate) fit: FamilyFit,
    pub(crate) check: ModelCheck,
    pub(crate) selection: Vec<Candidate>,
    pub(crate) curve: Curve,
}

impl ElementModel {
    /// The family of the model.
    pub fn family(&self) -> Family {
        self.fit.family()
    }

    /// The fit: coefficient matrices, poles, standard deviations (widened by the check's Birge
    /// ratio).
    pub fn fit(&self) -> &FamilyFit {
        &self.fit
    }

    /// The model check of this family.
    pub fn check(&self) -> &ModelCheck {
        &self.check
    }

    /// Every family tried, in order, with its statistic, criterion and verdict (one entry for a
    /// family asked for by name).
    pub fn selection(&self) -> &[Candidate] {
        &self.selection
    }

    /// `K(ω)`, `C(ω)` of the model on the lines used.
    pub fn curve(&self) -> &Curve {
        &self.curve
    }

    /// The poles (Hz).
    pub fn poles_hz(&self) -> Vec<f64> {
        self.fit
            .poles()
            .iter()
            .map(|p| p / (2.0 * std::f64::consts::PI))
            .collect()
    }

    /// The poles' standard deviations (Hz).
    pub fn poles_hz_std(&self) -> Option<Vec<f64>> {
        self.fit
            .pole_std()
            .map(|s| s.iter().map(|p| p / (2.0 * std::f64::consts::PI)).collect())
    }

    /// The model's constant part `M`, `C`, `K`: for `kc`, `M = 0`; for `poly:P`,
    /// `K = K₀`, `C = C₀`, `M = −K₂/ω₀²`.
    ///
    /// # Errors
    /// [`Error::NonFiniteCoefficient`](crate::Error::NonFiniteCoefficient) if a coefficient is
    /// not finite.
    pub fn constant_part(&self) -> Result<Coefficients> {
        let n = self.fit.dofs();
        let zero = Mat::zeros(n, n);
        match self.family() {
            Family::Kc => Coefficients::new(zero, self.fit.matrix(1), self.fit.matrix(0)),
            Family::Kcm | Family::States { .. } => {
                Coefficients::new(self.fit.matrix(2), self.fit.matrix(1), self.fit.matrix(0))
            }
            Family::Poly { degree } => {
                let m = if degree >= 2 {
                    let w0 = self.fit.omega0();
                    Mat::from_fn(n, n, |i, j| -self.fit.matrix(2)[(i, j)] / (w0 * w0))
                } else {
                    zero
                };
                Coefficients::new(m, self.fit.matrix(degree + 1), self.fit.matrix(0))
            }
        }
    }

    /// Standard deviations of [`ElementModel::constant_part`], when known.
    pub fn constant_part_std(&self) -> Option<Coefficients> {
        let n = self.fit.dofs();
        let zero = Mat::zeros(n, n);
        let (m, c, k) = match self.family() {
            Family::Kc => (zero, self.fit.matrix_std(1)?, self.fit.matrix_std(0)?),
            Family::Kcm | Family::States { .. } => (
                self.fit.matrix_std(2)?,
                self.fit.matrix_std(1)?,
                self.fit.matrix_std(0)?,
            ),
            Family::Poly { degree } => {
                let m = if degree >= 2 {
                    let w0 = self.fit.omega0();
                    let s = self.fit.matrix_std(2)?;
                    Mat::from_fn(n, n, |i, j| s[(i, j)] / (w0 * w0))
                } else {
                    zero
                };
                (m, self.fit.matrix_std(degree + 1)?, self.fit.matrix_std(0)?)
            }
        };
        Coefficients::new(m, c, k).ok()
    }

    /// Natural frequencies and damping ratios of the rig with the element: the eigenvalues of
    /// the state-space model, for `states:N` of dimension `2n + Nn` (states
    /// `[x, ẋ, w_1 … w_N]`, $\dot w_j = \dot x - p_j w_j$, force `Σ A_j w_j`), otherwise of
    /// the constant part. Real eigenvalues of the internal states (overdamped) are left out;
    /// complex pairs are reported once, by ascending frequency.
    ///
    /// # Errors
    /// [`Error::Singular`](crate::Error::Singular) if the mass is singular.
    pub fn modes(&self) -> Result<Vec<Mode>> {
        let constant = self.constant_part()?;
        let poles = self.fit.poles().to_vec();
        if poles.is_empty() {
            return constant.modes();
        }
        let n = constant.dofs();
        let size = 2 * n + poles.len() * n;
        // The mass's conditioning, as the constant part's own modes check it.
        constant.eigenvalues()?;
        let lu = constant.mass().partial_piv_lu();
        use faer::linalg::solvers::Solve;
        let minv = |m: &Mat<f64>| lu.solve(m);
        let mk = minv(&constant.stiffness().to_owned());
        let mc = minv(&constant.damping().to_owned());
        let mut a = Mat::<f64>::zeros(size, size);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
            for j in 0..n {
                a[(n + i, j)] = -mk[(i, j)];
                a[(n + i, n + j)] = -mc[(i, j)];
            }
        }
        for (s, &p) in poles.iter().enumerate() {
            let ma = minv(&self.fit.matrix(3 + s));
            let base = 2 * n + s * n;
            for i in 0..n {
                // ẇ = ẋ − p w.
                a[(base + i, n + i)] = 1.0;
                a[(base + i, base + i)] = -p;
                for j in 0..n {
                    a[(n + i, base + j)] = -ma[(i, j)];
                }
            }
        }
        let eigen: Vec<c64> = a.eigenvalues()?;
        let mut modes: Vec<Mode> = eigen
            .iter()
            .filter(|l| l.im > crate::tolerance::OSCILLATORY_ROOT * l.norm())
            .map(|l| Mode {
                natural_frequency_hz: l.norm() / (2.0 * std::f64::consts::PI),
                damped_frequency_hz: l.im / (2.0 * std::f64::consts::PI),
                damping_ratio: -l.re / l.norm(),
            })
            .collect();
        modes.sort_by(|a, b| a.natural_frequency_hz.total_cmp(&b.natural_frequency_hz));
        Ok(modes)
    }

    /// Whether the model is the constant `K`, `C`, `M` of the default fit.
    pub fn is_kcm(&self) -> bool {
        self.family() == Family::Kcm
    }

    /// The verdict of the chosen family's check.
    pub fn verdict(&self) -> &Verdict {
        &self.check.verdict
    }
}

impl Curve {
    /// The curve of `fit` on `freqs_hz`, `M` the model's constant mass `mass`.
    pub(crate) fn of(fit: &FamilyFit, freqs_hz: &[f64], mass: &Mat<f64>) -> Curve {
        let n = fit.dofs();
        let mut curve = Curve {
            frequency_hz: freqs_hz.to_vec(),
            stiffness: Vec::with_capacity(freqs_hz.len()),
            damping: Vec::with_capacity(freqs_hz.len()),
            stiffness_std: Vec::with_capacity(freqs_hz.len()),
            damping_std: Vec::with_capacity(freqs_hz.len()),
        };
        for &f in freqs_hz {
            let w = 2.0 * std::f64::consts::PI * f;
            let (mut k, mut c) = (Mat::zeros(n, n), Mat::zeros(n, n));
            let (mut ks, mut cs) = (Mat::zeros(n, n), Mat::zeros(n, n));
            for j in 0..n {
                for i in 0..n {
                    // K(ω) = Re H + ω²M: the mass term of H cancels (its basis function is
                    // −ω² for kcm and states, −(ω/ω₀)²·ω₀²·M for polynomials).
                    let (h, std) = fit.element_with_std(w, i, j, true);
                    k[(i, j)] = h.re + w * w * mass[(i, j)];
                    c[(i, j)] = h.im / w;
                    let (sr, si) = std.unwrap_or((f64::NAN, f64::NAN));
                    ks[(i, j)] = sr;
                    cs[(i, j)] = si / w;
                }
            }
            curve.stiffness.push(k);
            curve.damping.push(c);
            curve.stiffness_std.push(ks);
            curve.damping_std.push(cs);
        }
        curve
    }
}
