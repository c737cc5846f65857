//! The Cramér–Rao lower bound of the maximum-likelihood fit: the best any unbiased estimator
//! can do with the given excitation and noise, for planning tests.

use super::*;

/// The Cramér–Rao lower bound on the standard deviations of every coefficient of `system`
/// measured with `data`'s excitation and noise: `√diag(F⁻¹)` with the Fisher information
/// evaluated at the true system on noise-free displacements `x = G f̄`. No unbiased estimator
/// does better; [`fit`] reaches it.
///
/// # Errors
/// [`Error::InvalidParameter`] if `system` and `data` differ in size; [`Error::Singular`] if
/// the Fisher information or some `Σ_k` is singular (the data cannot determine every
/// coefficient, or carry no noise).
///
/// # Examples
/// How many impacts for ±1 % on `C_xx`? The bound falls as one over the square root of the
/// repeats: plan with one set, scale.
/// ```
/// use bearing_ident::simulate::seed_rig;
/// use bearing_ident::solve::ml::{MlData, crlb};
/// use faer::{Mat, c64};
/// let rig = seed_rig();
/// let freqs: Vec<f64> = (10..=48).map(f64::from).collect();
/// // One hit per direction, 0.64 N·s per line (a 500 N, 2 ms half-sine); noise spectral
/// // variances of 1e-4 (N·s)² and 1e-16 (m·s)².
/// let hits = vec![Mat::from_fn(2, 2, |i, j| c64::new(if i == j { 0.64 } else { 0.0 }, 0.0)); freqs.len()];
/// let one = crlb(&rig, &MlData::planned(&rig, freqs.clone(), &hits, 1e-4, 1e-16)?)?;
/// let sigma_c = one.damping()[(0, 0)];
/// let sets_needed = (sigma_c / (0.01 * 131.98)).powi(2).ceil();
/// assert!(sets_needed >= 1.0);
/// // Four sets: half the bound.
/// let four = crlb(&rig, &MlData::planned(&rig, freqs, &hits, 1e-4 / 4.0, 1e-16 / 4.0)?)?;
/// assert!((four.damping()[(0, 0)] / sigma_c - 0.5).abs() < 1e-9);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn crlb(system: &Coefficients, data: &MlData) -> Result<Coefficients> {
    let n = data.n;
    if system.dofs() != n {
        return Err(Error::InvalidParameter {
            name: "system size",
            value: system.dofs() as f64,
            expected: "the data's degrees of freedom",
        });
    }
    let x0 = model_displacements(data, system)?;
    let eval = evaluate(data, &to_params(system), Some(&x0)).ok_or(Error::Singular {
        what: "noise covariance Σ (noise-free data?)",
    })?;
    let cov = column_covariances(&eval.fisher, n, data.inflation).ok_or(Error::Singular {
        what: "Fisher information",
    })?;
    std_from(&cov)
}
