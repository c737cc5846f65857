//! [`ElementModel`]: the family chosen (or asked for), its fit, its check, the candidates
//! tried, and its `K(ω)`, `C(ω)` on the lines used ([`Curve`]).

use faer::{Mat, MatRef};

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

/// The effective coefficients of a 2-DOF model for forward whirl, per line of its curve, and
/// the crossover frequency where the effective damping changes sign
/// ([`ElementModel::effective`]): with the isotropic parts `K = (K_xx + K_yy)/2`,
/// `k = (K_xy − K_yx)/2`, `C = (C_xx + C_yy)/2`, `c = (C_xy − C_yx)/2` of the model's `K(ω)`,
/// `C(ω)`: $K_{eff} = K + \omega c$, $C_{eff} = C - k/\omega$.
#[derive(Debug, Clone, PartialEq)]
pub struct Effective {
    /// The lines (Hz).
    pub frequency_hz: Vec<f64>,
    /// `K_eff` per line (N/m).
    pub stiffness: Vec<f64>,
    /// `C_eff` per line (N·s/m).
    pub damping: Vec<f64>,
    /// Standard deviations of `K_eff` (the elements' in quadrature).
    pub stiffness_std: Vec<f64>,
    /// Standard deviations of `C_eff`.
    pub damping_std: Vec<f64>,
    /// The lowest frequency (Hz) from a third of the band's lower edge to three times its upper
    /// edge where `C_eff` changes sign, on the model; `None` when it does not.
    pub crossover_hz: Option<f64>,
    /// Its standard deviation: `σ(C_eff)` there over the slope of `C_eff`.
    pub crossover_hz_std: Option<f64>,
}

/// The element model of an identification ([`Identification::model`](crate::Identification::model)).
#[derive(Debug, Clone, PartialEq)]
pub struct ElementModel {
    pub(crate) fit: FamilyFit,
    pub(crate) check: ModelCheck,
    pub(crate) selection: Vec<Candidate>,
    pub(crate) curve: Curve,
    pub(crate) others: Vec<FamilyFit>,
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

    /// The fits of the other families the selection fitted, in its order (empty for a family
    /// asked for by name): what a figure draws beside the chosen model.
    pub fn other_fits(&self) -> &[FamilyFit] {
        &self.others
    }

    /// `K(ω)`, `C(ω)` of the model on the lines used.
    pub fn curve(&self) -> &Curve {
        &self.curve
    }

    /// `K(ω)`, `C(ω)` of the model, with standard deviations, at any frequencies `freqs_hz`
    /// (the curve of [`curve`](Self::curve) is this on the lines used). Off the band the model
    /// is extrapolated: its error bars say how far that can be trusted.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::element::ModelSpec;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).model(ModelSpec::Auto).identify(&records)?;
    /// let model = id.model().expect("a model was asked for");
    /// let curve = model.curve_at(&[10.0, 30.0]);
    /// // The seed rig is a constant K, C, M system: its K(ω) is the same at every frequency.
    /// let (k10, k30) = (curve.stiffness[0][(0, 0)], curve.stiffness[1][(0, 0)]);
    /// assert!((k10 / k30 - 1.0).abs() < 1e-6);
    /// assert!((k10 / 146.3e3 - 1.0).abs() < 1e-3);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn curve_at(&self, freqs_hz: &[f64]) -> Curve {
        Curve::of(
            &self.fit,
            freqs_hz,
            super::select::constant_mass(&self.fit).as_ref(),
        )
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
        // The mass's conditioning, as the constant part's own modes check it.
        constant.eigenvalues()?;
        let residues: Vec<Mat<f64>> = (0..poles.len()).map(|s| self.fit.matrix(3 + s)).collect();
        let eigen = constant.eigenvalues_with_states(&residues, &poles)?;
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

    /// `K_eff`, `C_eff` for forward whirl and the crossover frequency ([`Effective`]), for two
    /// degrees of freedom (`x`, `y`); `None` otherwise.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::element::{Family, fit_family, ModelSpec, select};
    /// use bearing_ident::{Frf, simulate::seed_rig};
    /// # use faer::linalg::solvers::DenseSolveCore;
    /// // A cross-coupled element: k = 2e4 N/m, C = 130 N·s/m → C_eff crosses zero at
    /// // ω = k/C, 24.5 Hz (the seed rig's own cross terms shift it a little).
    /// let k = seed_rig();
    /// let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
    /// let g = freqs.iter().map(|&f| {
    ///     let mut h = k.impedance_at(f);
    ///     h[(0, 1)].re += 2e4;
    ///     h[(1, 0)].re -= 2e4;
    ///     h.partial_piv_lu().inverse()
    /// }).collect::<Vec<_>>();
    /// let frf = Frf::from_flexibility(freqs, &g)?;
    /// let (model, _) = select(&frf, ModelSpec::Family(Family::Kcm), 1, None)?;
    /// let eff = model.effective().unwrap();
    /// let c = &k.damping();
    /// let kk = 0.5 * (k.stiffness()[(0, 1)] - k.stiffness()[(1, 0)]) + 2e4;
    /// let cc = 0.5 * (c[(0, 0)] + c[(1, 1)]);
    /// let expected = kk / cc / (2.0 * std::f64::consts::PI);
    /// assert!((eff.crossover_hz.unwrap() / expected - 1.0).abs() < 1e-3);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn effective(&self) -> Option<Effective> {
        if self.fit.dofs() != 2 {
            return None;
        }
        let mass = self.constant_part().ok()?.mass().to_owned();
        let at = |omega: f64| -> (f64, f64, f64, f64) {
            let mut k = [[0.0; 2]; 2];
            let mut c = [[0.0; 2]; 2];
            let mut ks = [[0.0; 2]; 2];
            let mut cs = [[0.0; 2]; 2];
            for i in 0..2 {
                for j in 0..2 {
                    let (h, std) = self.fit.element_with_std(omega, i, j, true);
                    k[i][j] = h.re + omega * omega * mass[(i, j)];
                    c[i][j] = h.im / omega;
                    let (sr, si) = std.unwrap_or((f64::NAN, f64::NAN));
                    ks[i][j] = sr;
                    cs[i][j] = si / omega;
                }
            }
            let k_eff = 0.5 * (k[0][0] + k[1][1]) + omega * 0.5 * (c[0][1] - c[1][0]);
            let c_eff = 0.5 * (c[0][0] + c[1][1]) - 0.5 * (k[0][1] - k[1][0]) / omega;
            let k_std = 0.5
                * (ks[0][0].powi(2)
                    + ks[1][1].powi(2)
                    + (omega * cs[0][1]).powi(2)
                    + (omega * cs[1][0]).powi(2))
                .sqrt();
            let c_std = 0.5
                * (cs[0][0].powi(2)
                    + cs[1][1].powi(2)
                    + (ks[0][1] / omega).powi(2)
                    + (ks[1][0] / omega).powi(2))
                .sqrt();
            (k_eff, c_eff, k_std, c_std)
        };
        let two_pi = 2.0 * std::f64::consts::PI;
        let mut out = Effective {
            frequency_hz: self.curve.frequency_hz.clone(),
            stiffness: Vec::new(),
            damping: Vec::new(),
            stiffness_std: Vec::new(),
            damping_std: Vec::new(),
            crossover_hz: None,
            crossover_hz_std: None,
        };
        for &f in &self.curve.frequency_hz {
            let (k, c, ks, cs) = at(two_pi * f);
            out.stiffness.push(k);
            out.damping.push(c);
            out.stiffness_std.push(ks);
            out.damping_std.push(cs);
        }
        let freqs = &self.curve.frequency_hz;
        let (low, high) = (
            freqs.iter().copied().fold(f64::INFINITY, f64::min) / 3.0,
            freqs.iter().copied().fold(0.0, f64::max) * 3.0,
        );
        // The first sign change on a fine logarithmic grid, refined by bisection.
        let grid = 2000;
        let point = |i: usize| low * (high / low).powf(i as f64 / grid as f64);
        let c_at = |f: f64| at(two_pi * f).1;
        let mut previous = c_at(point(0));
        for i in 1..=grid {
            let current = c_at(point(i));
            if previous.signum() != current.signum() && previous.is_finite() && current.is_finite()
            {
                let (mut a, mut b) = (point(i - 1), point(i));
                for _ in 0..60 {
                    let m = 0.5 * (a + b);
                    if c_at(m).signum() == previous.signum() {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                let f = 0.5 * (a + b);
                let slope = (c_at(f * 1.001) - c_at(f * 0.999)) / (0.002 * f);
                let (_, _, _, c_std) = at(two_pi * f);
                out.crossover_hz = Some(f);
                out.crossover_hz_std = (slope != 0.0).then(|| c_std / slope.abs());
                break;
            }
            previous = current;
        }
        Some(out)
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
    pub(crate) fn of(fit: &FamilyFit, freqs_hz: &[f64], mass: MatRef<'_, f64>) -> Curve {
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
