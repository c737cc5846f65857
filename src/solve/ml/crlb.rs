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
/// How many impacts for ±1 % on `C_xx`? The seed's test: 8040 samples at 6700 samples/s
/// (lines 0.83 Hz apart, 8.3–48.3 Hz), one 500 N, 2 ms half-sine hit per direction (0.64 N·s
/// per line), the force gated (clean), and a displacement noise floor of `σ = 0.1 mm` RMS per
/// sample (the response peaks near 0.8 mm): white, so each line's variance is `σ² N Δt²`
/// (this crate's DFT scaling) — what the residual noise model estimates from a real test
/// ([`super::noise`]). The bound falls as one over the square root of the hits: plan with
/// one, scale.
/// ```
/// use bearing_ident::simulate::seed_rig;
/// use bearing_ident::solve::ml::{MlData, crlb};
/// use faer::{Mat, c64};
/// let rig = seed_rig();
/// let (rate, samples) = (6700.0, 8040.0);
/// let freqs: Vec<f64> = (10..=58).map(|k| k as f64 * rate / samples).collect();
/// let hits = vec![Mat::from_fn(2, 2, |i, j| c64::new(if i == j { 0.64 } else { 0.0 }, 0.0)); freqs.len()];
/// let sigma = 1e-4;
/// let disp_var = sigma * sigma * samples / (rate * rate);
/// let one = crlb(&rig, &MlData::planned(&rig, freqs.clone(), &hits, 0.0, disp_var)?)?;
/// let sigma_c = one.damping()[(0, 0)];
/// let hits_needed = (sigma_c / (0.01 * 131.98)).powi(2).ceil();
/// assert_eq!(hits_needed, 4.0); // σ(C_xx) = 2.50 N·s/m (1.9 %) from one hit
/// // Four hits per direction: half the bound.
/// let four = crlb(&rig, &MlData::planned(&rig, freqs, &hits, 0.0, disp_var / 4.0)?)?;
/// assert!((four.damping()[(0, 0)] / sigma_c - 0.5).abs() < 1e-9);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn crlb(system: &Coefficients, data: &MlData) -> Result<Coefficients> {
    let n = data.n;
    if system.dofs() != n {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::SystemSize,
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
