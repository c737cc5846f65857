//! The model check of a nonlinear term ([`TermCheck`]): a right regressor has a coefficient
//! spectrum $\hat A_j(\omega)$ that is real and flat over the band; a wrong one still returns a
//! plausible number, and only this check shows it.
//!
//! With the weights $w_k = 1/\operatorname{Var}[\hat A_j(\omega_k)]$ of the band average,
//! each part of $\hat A_j$ carrying half the variance:
//!
//! - imaginary ratio $\rho = \overline{\operatorname{Im}\hat A}/\overline{\operatorname{Re}\hat A}$
//!   (weighted means), with $\sigma(\overline{\operatorname{Im}\hat A}) = (2\sum_k w_k)^{-1/2}$;
//! - slope: the weighted straight line $\operatorname{Re}\hat A_j \approx \alpha +
//!   \beta(f - \bar f)$, reported as the change across the band relative to the average,
//!   $s = \beta\,(f_{\max} - f_{\min})/\lvert\alpha\rvert$, with
//!   $\sigma(\beta) = \big(2\sum_k w_k (f_k - \bar f)^2\big)^{-1/2}$;
//! - the collinearity of the term's inputs with the other inputs (their multiple coherence).
//!
//! A term is a misfit when $\lvert\rho\rvert$ exceeds [`NONLINEAR_IMAGINARY_RATIO`] or
//! $\lvert s\rvert$ exceeds [`NONLINEAR_SLOPE`], that deviation being more than
//! [`NONLINEAR_CHECK_SIGMAS`] of its standard deviations from zero.

use faer::c64;

use crate::tolerance::{
    COLLINEAR_COHERENCE, NONLINEAR_CHECK_SIGMAS, NONLINEAR_IMAGINARY_RATIO, NONLINEAR_SLOPE,
};

use super::lines::weights;

/// The model check of one nonlinear term.
///
/// # Examples
/// ```
/// use bearing_ident::nonlinear::TermCheck;
/// use bearing_ident::faer::c64;
/// // A constant real spectrum fits; one that doubles across the band and turns complex does not.
/// let freqs = [10.0, 20.0, 30.0, 40.0];
/// let flat = [c64::new(0.8, 0.0); 4];
/// let ok = TermCheck::new(&freqs, &flat, &[1e-4; 4], 0.2);
/// assert!(!ok.misfit && ok.slope.abs() < 1e-12);
/// let bent: Vec<c64> = freqs.iter().map(|f| c64::new(f / 25.0, 0.3)).collect();
/// let bad = TermCheck::new(&freqs, &bent, &[1e-4; 4], 0.2);
/// assert!(bad.misfit && (bad.imaginary_ratio - 0.3).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TermCheck {
    /// Band average of `Im Â` over that of `Re Â`.
    pub imaginary_ratio: f64,
    /// How many of its standard deviations the band average of `Im Â` lies from zero.
    pub imaginary_sigmas: f64,
    /// Change of `Re Â` across the band (straight-line fit) relative to its band average.
    pub slope: f64,
    /// How many of its standard deviations the slope lies from zero.
    pub slope_sigmas: f64,
    /// Median over the band of the multiple coherence of the term's inputs on the other inputs.
    pub input_coherence: f64,
    /// Whether the term fails the check (the regressor does not describe the element).
    pub misfit: bool,
    /// Whether the term is collinear with the other inputs (coherence above
    /// [`COLLINEAR_COHERENCE`]).
    pub collinear: bool,
}

impl TermCheck {
    /// The check of a coefficient spectrum `spectrum` with per-line variances `var` at
    /// `freqs_hz`, and the term's input coherence on the other inputs.
    ///
    /// # Panics
    /// If the slices differ in length.
    pub fn new(freqs_hz: &[f64], spectrum: &[c64], var: &[f64], input_coherence: f64) -> Self {
        assert!(
            freqs_hz.len() == spectrum.len() && spectrum.len() == var.len(),
            "one value per line"
        );
        let w = weights(var);
        let total: f64 = w.iter().sum();
        let mean =
            |f: &dyn Fn(usize) -> f64| (0..w.len()).map(|k| w[k] * f(k)).sum::<f64>() / total;
        let re = mean(&|k| spectrum[k].re);
        let im = mean(&|k| spectrum[k].im);
        let f_mean = mean(&|k| freqs_hz[k]);
        let sxx: f64 = (0..w.len())
            .map(|k| w[k] * (freqs_hz[k] - f_mean).powi(2))
            .sum();
        let sxy: f64 = (0..w.len())
            .map(|k| w[k] * (freqs_hz[k] - f_mean) * (spectrum[k].re - re))
            .sum();
        let beta = if sxx > 0.0 { sxy / sxx } else { 0.0 };
        let span = freqs_hz.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - freqs_hz.iter().cloned().fold(f64::INFINITY, f64::min);
        // Standard deviations from the per-line variances; with equal weights (no variances)
        // every deviation counts as significant.
        let has_var = var.iter().all(|&v| v.is_finite() && v > 0.0);
        let sigmas = |value: f64, info: f64| {
            if has_var && info > 0.0 {
                value.abs() * (2.0 * info).sqrt()
            } else {
                f64::INFINITY
            }
        };
        let imaginary_ratio = im / re.abs();
        let slope = beta * span / re.abs();
        let imaginary_sigmas = sigmas(im, total);
        let slope_sigmas = sigmas(beta, sxx);
        let misfit = (imaginary_ratio.abs() > NONLINEAR_IMAGINARY_RATIO
            && imaginary_sigmas > NONLINEAR_CHECK_SIGMAS)
            || (slope.abs() > NONLINEAR_SLOPE && slope_sigmas > NONLINEAR_CHECK_SIGMAS);
        Self {
            imaginary_ratio,
            imaginary_sigmas,
            slope,
            slope_sigmas,
            input_coherence,
            misfit,
            collinear: input_coherence > COLLINEAR_COHERENCE,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_level_deviations_are_not_misfits() {
        // A term the system does not have: Re Â ≈ 0 ± noise, so the ratios are large, but
        // neither the imaginary part nor the slope stands out of the noise.
        let freqs = [10.0, 20.0, 30.0, 40.0];
        let spectrum = [
            c64::new(0.01, 0.03),
            c64::new(-0.01, 0.01),
            c64::new(0.02, 0.0),
            c64::new(-0.01, 0.0),
        ];
        let c = TermCheck::new(&freqs, &spectrum, &[1.0; 4], 0.3);
        assert!(c.imaginary_ratio.abs() > NONLINEAR_IMAGINARY_RATIO);
        assert!(!c.misfit && !c.collinear, "{c:?}");
        let c = TermCheck::new(&freqs, &spectrum, &[1.0; 4], 0.999);
        assert!(c.collinear);
    }
}
