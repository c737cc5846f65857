//! Maximum likelihood (errors in variables), started from IVF, and the Cramér–Rao bound.
//!
//! Per line `k` and independent excitation (column) `j` the data are the mean spectra
//! `x̄_kj`, `f̄_kj` (`n`-vectors) with the noise covariances of those means, `C_X`, `C_F` and
//! `C_XF = E[δx δfᴴ]` (`n × n`, the same for every column of a line). The equation error
//! `e_kj = H(ω_k; Θ) x̄_kj − f̄_kj` then has covariance
//!
//! $$\Sigma_k(\Theta) = H C_X H^H + C_F - H C_{XF} - C_{XF}^H H^H,$$
//!
//! and the negative log-likelihood (up to constants) is the cost
//!
//! $$V(\Theta) = \sum_k \sum_j e_{kj}^H \,\Sigma_k^{-1} e_{kj}.$$
//!
//! With `u = Σ⁻¹e`, `w = C_X Hᴴu − C_XF u` and `∂H/∂θ = c E_ab` (`c = −ω², iω, 1` for an element
//! `ab` of `M`, `C`, `K`), its gradient is exact and cheap,
//! $\partial V/\partial\theta = 2\,\mathrm{Re}\big(\bar c\, u_a\, \overline{(x_b - w_b)}\big)$
//! summed over lines and columns, and its Gauss–Newton Hessian is the Fisher information
//! $F_{pq} = 2\,\mathrm{Re}\sum (\partial e/\partial\theta_p)^H \Sigma^{-1} (\partial e/\partial\theta_q)$.
//! Levenberg–Marquardt steps `(F + λ diag F) δ = −∇V` (Marquardt's scaling makes the step
//! independent of the units of `M`, `C`, `K`, as the column scaling of ls and IVF does) are
//! accepted only when they lower `V`, so the result never costs more than the IVF start. The
//! covariance of the estimate is `F⁻¹` at the solution, with `F` evaluated on the fitted
//! displacements `G(ω; Θ̂) f` (the noisy ones would count their noise power as information);
//! evaluated at the true system, `F⁻¹` is the Cramér–Rao lower bound ([`crlb`]).
//!
//! A small loop written out here, rather than a general optimisation crate: the problem has
//! 3n² parameters, an exact gradient and a Fisher matrix assembled line by line from `n × n`
//! blocks, and the one 3n² × 3n² solve per step goes through faer's LU — nothing to copy in or
//! out of another crate's matrix types.

use faer::linalg::solvers::Solve;
use faer::{Mat, c64};

use super::{Convergence, block_change, std_from};
use crate::error::{Error, Result};
use crate::linalg::Inverter;
use crate::model::Coefficients;

mod crlb;
mod data;
pub mod noise;

pub use crlb::crlb;
pub use data::MlData;
pub use noise::NoiseModel;

/// Settings of the Levenberg–Marquardt loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlOptions {
    /// Stop when a step changes every block `M`, `C`, `K` by less than this (relative,
    /// Frobenius), as IVF does. Default `1e-10`.
    pub tolerance: f64,
    /// Most steps tried (accepted or not). Default 100.
    pub max_iterations: usize,
}

impl MlOptions {
    /// Checks the tolerance. Zero iterations are allowed: [`fit`] then returns the start with
    /// its cost.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a tolerance outside `(0, 1)`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::MlOptions;
    /// assert!(MlOptions::default().check().is_ok());
    /// assert!(MlOptions { tolerance: 0.0, max_iterations: 10 }.check().is_err());
    /// ```
    pub fn check(&self) -> Result<()> {
        super::check_tolerance(self.tolerance, crate::Parameter::MlTolerance)
    }
}

impl Default for MlOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 100,
        }
    }
}

/// What the maximum-likelihood loop did.
///
/// Serialized (feature `serde`) as `iterations`, `converged` (from
/// [`MlReport::convergence`]), then the other fields by name.
#[derive(Debug, Clone, PartialEq)]
pub struct MlReport {
    /// How the loop ended, as every iterative fit reports it: converged, at its step limit
    /// (with the last accepted step's change), or fallen back to the start
    /// ([`Convergence::Diverged`] with `fallback_iteration` 0, the reason in
    /// [`MlReport::fell_back`]).
    pub convergence: Convergence,
    /// Cost `V` at the IVF start.
    pub start_cost: f64,
    /// Cost `V` at the result.
    pub cost: f64,
    /// `cost / expected cost` ([`MlData::expected_cost`]): about 1 when the model and the
    /// noise covariances fit the data, whatever the size of the coefficients — a
    /// goodness-of-fit test that, unlike `r²`, works for near-zero elements too. Sample
    /// covariances from few repeats inflate it somewhat.
    pub cost_ratio: f64,
    /// Why the IVF start was kept, if it was (the result then is IVF's).
    pub fell_back: Option<String>,
    /// Where the noise covariances came from (the JSON's `ml.noise_model`).
    pub noise_model: NoiseModel,
}

#[cfg(feature = "serde")]
impl serde::Serialize for MlReport {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(7))?;
        m.serialize_entry("iterations", &self.convergence.iterations())?;
        m.serialize_entry("converged", &self.convergence.is_converged())?;
        m.serialize_entry("start_cost", &self.start_cost)?;
        m.serialize_entry("cost", &self.cost)?;
        m.serialize_entry("cost_ratio", &self.cost_ratio)?;
        m.serialize_entry("fell_back", &self.fell_back)?;
        m.serialize_entry("noise_model", &self.noise_model)?;
        m.end()
    }
}

/// Per-parameter factors `c` of `∂H/∂θ = c E_ab`: `−ω²` (M), `iω` (C), `1` (K).
fn factors(w: f64) -> [c64; 3] {
    [c64::new(-w * w, 0.0), c64::new(0.0, w), c64::new(1.0, 0.0)]
}

/// Parameter `p = t·n² + a·n + b`: block `t` (M, C, K), element `(a, b)`.
fn to_params(c: &Coefficients) -> Vec<f64> {
    let n = c.dofs();
    let mut out = Vec::with_capacity(3 * n * n);
    for block in [c.mass(), c.damping(), c.stiffness()] {
        for a in 0..n {
            out.extend((0..n).map(|b| block[(a, b)]));
        }
    }
    out
}

fn from_params(theta: &[f64], n: usize) -> Result<Coefficients> {
    let block = |t: usize| Mat::from_fn(n, n, |a, b| theta[t * n * n + a * n + b]);
    Coefficients::new(block(0), block(1), block(2))
}

/// Cost, gradient and Fisher information at `theta`; `None` if some `Σ_k` is singular or a
/// value is not finite.
struct Evaluation {
    cost: f64,
    gradient: Vec<f64>,
    fisher: Mat<f64>,
}

// Index loops over the n × n blocks read as the formulas in the module docs.
#[allow(clippy::needless_range_loop)]
fn evaluate(data: &MlData, theta: &[f64], x_override: Option<&[c64]>) -> Option<Evaluation> {
    let n = data.n;
    let nn = n * n;
    let p = 3 * nn;
    let xs = x_override.unwrap_or(&data.x);
    let zero = c64::new(0.0, 0.0);
    let mut cost = 0.0;
    let mut gradient = vec![0.0; p];
    let mut fisher = Mat::<f64>::zeros(p, p);
    let mut inverter = Inverter::new(n);
    let (mut h, mut sigma, mut tmp) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
    let (mut e, mut u, mut v, mut wv) =
        (vec![zero; n], vec![zero; n], vec![zero; n], vec![zero; n]);
    for (k, &f_hz) in data.freqs_hz.iter().enumerate() {
        let w = 2.0 * std::f64::consts::PI * f_hz;
        let c = factors(w);
        for b in 0..n {
            for a in 0..n {
                h[a + b * n] = c[0] * theta[a * n + b]
                    + c[1] * theta[nn + a * n + b]
                    + c[2] * theta[2 * nn + a * n + b];
            }
        }
        let (cx, cf, cxf) = (
            &data.cx[k * nn..(k + 1) * nn],
            &data.cf[k * nn..(k + 1) * nn],
            &data.cxf[k * nn..(k + 1) * nn],
        );
        // Σ = H C_X Hᴴ + C_F − H C_XF − C_XFᴴ Hᴴ.
        for j in 0..n {
            for i in 0..n {
                let mut s = cf[i + j * n];
                for a in 0..n {
                    let mut hcx = zero;
                    for b in 0..n {
                        hcx += h[i + b * n] * cx[b + a * n];
                    }
                    s += hcx * h[j + a * n].conj();
                    s -= h[i + a * n] * cxf[a + j * n];
                    s -= cxf[a + i * n].conj() * h[j + a * n].conj();
                }
                sigma[i + j * n] = s;
            }
        }
        tmp.copy_from_slice(&sigma);
        if !inverter.invert(&mut tmp) {
            return None;
        }
        let s_inv = &tmp;
        for col in 0..data.columns {
            let base = (k * data.columns + col) * n;
            let (x, f) = (&xs[base..base + n], &data.f[base..base + n]);
            for i in 0..n {
                e[i] = (0..n).map(|b| h[i + b * n] * x[b]).sum::<c64>() - f[i];
            }
            for i in 0..n {
                u[i] = (0..n).map(|b| s_inv[i + b * n] * e[b]).sum();
            }
            cost += (0..n).map(|i| (e[i].conj() * u[i]).re).sum::<f64>();
            // v = Hᴴ u; w = C_X v − C_XF u.
            for i in 0..n {
                v[i] = (0..n).map(|a| h[a + i * n].conj() * u[a]).sum();
            }
            for i in 0..n {
                wv[i] = (0..n)
                    .map(|b| cx[i + b * n] * v[b] - cxf[i + b * n] * u[b])
                    .sum();
            }
            for (t, ct) in c.iter().enumerate() {
                for a in 0..n {
                    for b in 0..n {
                        let q = t * nn + a * n + b;
                        gradient[q] += 2.0 * (ct.conj() * u[a] * (x[b] - wv[b]).conj()).re;
                    }
                }
            }
            // F_pq = 2 Re(conj(c_t x_b) S_{a a'} c_t' x_b').
            for (t, ct) in c.iter().enumerate() {
                for a in 0..n {
                    for b in 0..n {
                        let row = t * nn + a * n + b;
                        let left = (*ct * x[b]).conj();
                        for (t2, ct2) in c.iter().enumerate() {
                            for a2 in 0..n {
                                let ls = left * s_inv[a + a2 * n];
                                for b2 in 0..n {
                                    let col2 = t2 * nn + a2 * n + b2;
                                    fisher[(row, col2)] += 2.0 * (ls * *ct2 * x[b2]).re;
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    (cost.is_finite() && gradient.iter().all(|g| g.is_finite())).then_some(Evaluation {
        cost,
        gradient,
        fisher,
    })
}

/// The displacements `G(ω; system) f` of every column: what the measured ones would be
/// without noise if `system` were true.
///
/// # Errors
/// [`Error::Singular`] if `H(ω)` is singular at a line.
fn model_displacements(data: &MlData, system: &Coefficients) -> Result<Vec<c64>> {
    let n = data.n;
    let mut x0 = vec![c64::new(0.0, 0.0); data.x.len()];
    for (k, &f) in data.freqs_hz.iter().enumerate() {
        let g = system.flexibility_at(f)?;
        for col in 0..data.columns {
            let base = (k * data.columns + col) * n;
            for i in 0..n {
                x0[base + i] = (0..n).map(|b| g[(i, b)] * data.f[base + b]).sum();
            }
        }
    }
    Ok(x0)
}

/// `inflation · F⁻¹` as per-column covariances of the stacked `Θ = [M; C; K]` (`3n × 3n`
/// each), as [`super::Fit::covariance`] holds them; `None` if `F` is singular.
fn column_covariances(fisher: &Mat<f64>, n: usize, inflation: f64) -> Option<Vec<Mat<f64>>> {
    let p = fisher.nrows();
    let inv = fisher.partial_piv_lu().solve(Mat::<f64>::identity(p, p));
    if !(0..p).all(|i| inv[(i, i)].is_finite() && inv[(i, i)] >= 0.0) {
        return None;
    }
    let nn = n * n;
    // Stacked row r = t·n + a of column b ↔ parameter t·n² + a·n + b.
    let param = |r: usize, b: usize| (r / n) * nn + (r % n) * n + b;
    Some(
        (0..n)
            .map(|b| {
                Mat::from_fn(3 * n, 3 * n, |r, s| {
                    inflation * inv[(param(r, b), param(s, b))]
                })
            })
            .collect(),
    )
}

/// The outcome of [`fit`].
#[derive(Debug, Clone, PartialEq)]
pub struct MlFit {
    /// The coefficients (the start's if the loop fell back).
    pub coefficients: Coefficients,
    /// Per-column covariances of `Θ = [M; C; K]` from `F⁻¹` (`None` after a fall-back).
    pub covariance: Option<Vec<Mat<f64>>>,
    /// What the loop did.
    pub report: MlReport,
}

/// Maximum-likelihood coefficients from `data`, by Levenberg–Marquardt from `start` (IVF's
/// result). Never returns a cost above the start's: if the start cannot be evaluated (a
/// singular `Σ_k`, e.g. noise-free data) or no step lowers the cost, the start is returned
/// with [`MlReport::fell_back`] saying why.
///
/// # Errors
/// [`Error::InvalidParameter`] if `start` and `data` differ in size or `options` are out of
/// range ([`MlOptions::check`]).
///
/// # Examples
/// ```
/// use bearing_ident::simulate::seed_rig;
/// use bearing_ident::solve::ml::{MlData, MlOptions, fit};
/// use bearing_ident::Coefficients;
/// use faer::{Mat, Scale, c64};
/// let rig = seed_rig();
/// let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
/// let forces = vec![Mat::<c64>::identity(2, 2); freqs.len()];
/// let data = MlData::planned(&rig, freqs, &forces, 1e-3, 1e-13)?;
/// // Start 10 % off in K: the likelihood pulls it back to the system that produced the data.
/// let start = Coefficients::new(rig.mass().to_owned(), rig.damping().to_owned(),
///     rig.stiffness() * Scale(1.1))?;
/// let out = fit(&data, &start, &MlOptions::default())?;
/// assert!(out.report.cost < 1e-12 * out.report.start_cost);
/// assert!((out.coefficients.stiffness()[(0, 0)] / 146.3e3 - 1.0).abs() < 1e-9);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn fit(data: &MlData, start: &Coefficients, options: &MlOptions) -> Result<MlFit> {
    options.check()?;
    let n = data.n;
    if start.dofs() != n {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::StartSize,
            value: start.dofs() as f64,
            expected: "the data's degrees of freedom",
        });
    }
    let fall_back = |reason: &str, start_cost: f64, iterations: usize| MlFit {
        coefficients: start.clone(),
        covariance: None,
        report: MlReport {
            convergence: Convergence::Diverged {
                iterations,
                fallback_iteration: 0,
            },
            start_cost,
            cost: start_cost,
            cost_ratio: start_cost / data.expected_cost(),
            fell_back: Some(reason.to_owned()),
            noise_model: data.noise_model,
        },
    };
    let mut theta = to_params(start);
    let Some(mut current) = evaluate(data, &theta, None) else {
        return Ok(fall_back(
            "the noise covariance Σ is singular at the start (noise-free or too few repeats)",
            f64::NAN,
            0,
        ));
    };
    let start_cost = current.cost;
    let p = theta.len();
    let mut lambda = 1e-3;
    let (mut iterations, mut converged, mut last_change) = (0, false, None);
    while iterations < options.max_iterations {
        iterations += 1;
        let mut a = current.fisher.clone();
        for i in 0..p {
            a[(i, i)] += lambda * current.fisher[(i, i)].max(f64::MIN_POSITIVE);
        }
        let rhs = Mat::from_fn(p, 1, |i, _| -current.gradient[i]);
        let step = a.partial_piv_lu().solve(rhs);
        let trial: Vec<f64> = (0..p).map(|i| theta[i] + step[(i, 0)]).collect();
        match evaluate(data, &trial, None) {
            Some(next) if next.cost <= current.cost => {
                let change = largest_change(&trial, &theta, n);
                last_change = Some(change);
                theta = trial;
                current = next;
                lambda = (lambda / 10.0).max(1e-12);
                if change < options.tolerance {
                    converged = true;
                    break;
                }
            }
            _ => {
                lambda *= 10.0;
                if lambda > 1e12 {
                    // No step lowers the cost: the current point is a minimum to rounding.
                    converged = true;
                    break;
                }
            }
        }
    }
    let coefficients = from_params(&theta, n)?;
    // The Fisher information on the fitted displacements `G(ω; Θ̂) f` rather than the noisy
    // ones, whose noise power would count as information (errors in variables).
    let fisher = model_displacements(data, &coefficients)
        .ok()
        .and_then(|x| evaluate(data, &theta, Some(&x)))
        .map_or(current.fisher, |e| e.fisher);
    let covariance = column_covariances(&fisher, n, data.inflation);
    if covariance.is_none() {
        return Ok(fall_back(
            "the Fisher information is singular at the result",
            start_cost,
            iterations,
        ));
    }
    Ok(MlFit {
        coefficients,
        covariance,
        report: MlReport {
            convergence: if converged {
                Convergence::Converged { iterations }
            } else {
                Convergence::IterationLimit {
                    iterations,
                    change: last_change,
                }
            },
            start_cost,
            cost: current.cost,
            cost_ratio: current.cost / data.expected_cost(),
            fell_back: None,
            noise_model: data.noise_model,
        },
    })
}

/// Largest [`block_change`] over `M`, `C`, `K` of the parameters `t·n² + a·n + b`.
fn largest_change(new: &[f64], old: &[f64], n: usize) -> f64 {
    let nn = n * n;
    (0..3)
        .map(|t| {
            let r = t * nn..(t + 1) * nn;
            block_change(new[r.clone()].iter().copied().zip(old[r].iter().copied()))
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::seed_rig;

    /// The analytic gradient against central differences of the cost.
    /// A NaN in the data (a noise model fed an overflowed spectrum) is `non_finite` naming
    /// the line (before: `invalid_argument` "parameter `ml data` = NaN").
    #[test]
    fn non_finite_data_name_the_line() {
        let one = Mat::<c64>::identity(1, 1);
        let mut x = vec![one.clone(); 3];
        x[1][(0, 0)] = c64::new(f64::NAN, 0.0);
        let (f, c) = (vec![one.clone(); 3], vec![one.clone(); 3]);
        let e = MlData::new(vec![10.0, 11.0, 12.0], &x, &f, &c, &c, &c).unwrap_err();
        assert_eq!(e.kind(), "non_finite");
        assert_eq!(
            e,
            Error::NonFiniteResult {
                stage: crate::error::Quantity::MlData,
                freq_hz: 11.0
            }
        );
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let rig = seed_rig();
        let freqs: Vec<f64> = vec![12.0, 25.0, 31.0, 44.0];
        let forces: Vec<Mat<c64>> = freqs
            .iter()
            .map(|&f| {
                Mat::from_fn(2, 3, |i, j| {
                    c64::new(1.0 + (i + 2 * j) as f64 * 0.3, f * 0.01 * j as f64)
                })
            })
            .collect();
        let mut data = MlData::planned(&rig, freqs, &forces, 1e-3, 1e-13).unwrap();
        // A correlated C_XF and unequal variances, to exercise every term.
        for k in 0..data.freqs_hz.len() {
            data.cxf[k * 4] = c64::new(2e-9, 1e-9);
            data.cx[k * 4 + 3] = c64::new(3e-13, 0.0);
        }
        let mut theta = to_params(&rig);
        for (i, t) in theta.iter_mut().enumerate() {
            *t *= 1.0 + 0.01 * (i as f64 - 5.0);
        }
        let e = evaluate(&data, &theta, None).unwrap();
        for q in 0..theta.len() {
            let h = 1e-6 * theta[q].abs().max(1e-3);
            let (mut up, mut down) = (theta.clone(), theta.clone());
            up[q] += h;
            down[q] -= h;
            let fd = (evaluate(&data, &up, None).unwrap().cost
                - evaluate(&data, &down, None).unwrap().cost)
                / (2.0 * h);
            let scale = e.gradient.iter().map(|g| g.abs()).fold(0.0, f64::max);
            assert!(
                (fd - e.gradient[q]).abs() < 1e-6 * scale,
                "param {q}: {fd} vs {}",
                e.gradient[q]
            );
        }
    }

    /// At the truth with exact displacements the residuals vanish, so the Hessian of the cost
    /// is exactly the Fisher matrix: check it against differences of the analytic gradient.
    #[test]
    fn fisher_is_the_hessian_at_the_truth() {
        let rig = seed_rig();
        let freqs: Vec<f64> = vec![9.0, 22.0, 30.0, 47.0];
        let forces = vec![Mat::<c64>::identity(2, 2); freqs.len()];
        let data = MlData::planned(&rig, freqs, &forces, 1e-3, 1e-13).unwrap();
        let theta = to_params(&rig);
        let e = evaluate(&data, &theta, None).unwrap();
        assert!(e.cost < 1e-20);
        for q in 0..theta.len() {
            let h = 1e-6 * theta[q].abs().max(1e-3);
            let (mut up, mut down) = (theta.clone(), theta.clone());
            up[q] += h;
            down[q] -= h;
            let (gu, gd) = (
                evaluate(&data, &up, None).unwrap().gradient,
                evaluate(&data, &down, None).unwrap().gradient,
            );
            for p in 0..theta.len() {
                let fd = (gu[p] - gd[p]) / (2.0 * h);
                let scale = (e.fisher[(p, p)] * e.fisher[(q, q)]).sqrt();
                assert!((fd - e.fisher[(p, q)]).abs() < 1e-5 * scale, "({p}, {q})");
            }
        }
    }

    /// From a start far off (M × 1.5, C × 0.5, K × 1.2) the loop finds the truth, and the
    /// cost never rises; with no steps allowed it returns the start.
    #[test]
    fn far_start_converges_and_cost_never_rises() {
        let rig = seed_rig();
        let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
        let forces = vec![Mat::<c64>::identity(2, 2); freqs.len()];
        let data = MlData::planned(&rig, freqs, &forces, 1e-3, 1e-13).unwrap();
        let start = Coefficients::new(
            rig.mass() * faer::Scale(1.5),
            rig.damping() * faer::Scale(0.5),
            rig.stiffness() * faer::Scale(1.2),
        )
        .unwrap();
        let out = fit(&data, &start, &MlOptions::default()).unwrap();
        assert!(out.report.convergence.is_converged() && out.report.fell_back.is_none());
        assert!(out.report.cost <= out.report.start_cost);
        let err =
            (out.coefficients.stiffness() - rig.stiffness()).norm_l2() / rig.stiffness().norm_l2();
        assert!(err < 1e-8, "{err}");
        let none = MlOptions {
            max_iterations: 0,
            ..MlOptions::default()
        };
        let kept = fit(&data, &start, &none).unwrap();
        assert_eq!(kept.coefficients, start);
        assert!(kept.report.cost.to_bits() == kept.report.start_cost.to_bits());
    }

    #[test]
    fn noise_free_data_fall_back_cleanly() {
        let rig = seed_rig();
        let freqs: Vec<f64> = (10..=20).map(f64::from).collect();
        let forces = vec![Mat::<c64>::identity(2, 2); freqs.len()];
        let data = MlData::planned(&rig, freqs, &forces, 0.0, 0.0).unwrap();
        let out = fit(&data, &rig, &MlOptions::default()).unwrap();
        assert!(out.report.fell_back.is_some());
        assert_eq!(out.coefficients, rig);
        assert!(crlb(&rig, &data).is_err());
    }
}
