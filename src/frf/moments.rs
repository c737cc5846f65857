//! [`RecordMoments`]: the second moments of the records' (segments') spectra per line, an
//! output of this stage for the maximum-likelihood fit on impact and random records, whose
//! noise model ([`crate::solve::ml::noise`]) is estimated from them.

use faer::{Mat, c64};

use super::Frf;
use super::builder::{Contribution, FrfBuilder};
use crate::error::{Error, Result};
use crate::spectra::Segmentation;

/// Per line, the sum over every record (and Welch segment) of `z zᴴ` with `z = [x; f]` the
/// `2n` displacement and force spectra, and what the spectra were cut from.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RecordMoments {
    /// Frequencies of the lines (Hz), those of the `Frf` given.
    pub(crate) freqs_hz: Vec<f64>,
    /// Per line, the `2n × 2n` sum `Σ z zᴴ`: blocks `S_xx`, `S_xf` / `S_fx`, `S_ff`.
    pub(crate) szz: Vec<Mat<c64>>,
    /// Spectra summed (records × segments per record).
    pub(crate) observations: usize,
    /// Whether the spectra are Welch segments (else whole records: impacts, transients).
    pub(crate) welch: bool,
    /// Variance inflation of a sum over one record's overlapping segments relative to as many
    /// independent ones ([`overlap_inflation`]); 1 for whole records.
    pub(crate) overlap_inflation: f64,
}

impl FrfBuilder {
    /// Whether the records are cut into periods ([`Segmentation::Periods`], a cross-spectral
    /// estimator): maximum likelihood then takes its noise from their scatter.
    pub(crate) fn is_periodic(&self) -> bool {
        self.estimator.is_cross_spectral()
            && matches!(self.segmentation, Segmentation::Periods { .. })
    }

    /// The second moments of every record's (segment's) spectra on the lines of `frf`, for
    /// the maximum-likelihood fit on records without repeated periods. Whole records (impacts,
    /// by paired sets or a cross-spectral estimator) and Welch segments both work.
    ///
    /// # Errors
    /// [`Error::NoRecords`] if nothing was pushed; [`Error::MlNeedsRepeats`] for periodic
    /// segmentation (those records use [`FrfBuilder::period_statistics`]) or when a record's
    /// own spectra were not kept.
    pub(crate) fn record_moments(&self, frf: &Frf) -> Result<RecordMoments> {
        let (plan, _) = self.plan.as_ref().ok_or(Error::NoRecords)?;
        if matches!(self.segmentation, Segmentation::Periods { .. }) {
            return Err(Error::MlNeedsRepeats);
        }
        let (n, nn) = (plan.n, plan.n * plan.n);
        let mut freqs = Vec::new();
        let mut szz = Vec::new();
        for (l, &k) in plan.lines.iter().enumerate() {
            let freq = k as f64 * plan.resolution_hz;
            // The FRF's lines are these very values (same computation): exact lookup.
            if frf
                .freqs_hz()
                .binary_search_by(|u| u.total_cmp(&freq))
                .is_err()
            {
                continue;
            }
            freqs.push(freq);
            let mut s = Mat::<c64>::zeros(2 * n, 2 * n);
            if self.estimator.is_cross_spectral() {
                for j in 0..n {
                    for i in 0..n {
                        let at = l * nn + i + j * n;
                        s[(i, j)] = self.sxx[at];
                        s[(i, n + j)] = self.sxf[at];
                        s[(n + j, i)] = self.sxf[at].conj();
                        s[(n + i, n + j)] = self.sff[at];
                    }
                }
            } else {
                for g in &self.gathered {
                    let Contribution::Spectra {
                        forces,
                        displacements,
                    } = &g.contribution
                    else {
                        return Err(Error::MlNeedsRepeats);
                    };
                    let z = |i: usize| {
                        if i < n {
                            displacements[l * n + i]
                        } else {
                            forces[l * n + i - n]
                        }
                    };
                    for j in 0..2 * n {
                        let zj = z(j).conj();
                        for i in 0..2 * n {
                            s[(i, j)] += z(i) * zj;
                        }
                    }
                }
            }
            szz.push(s);
        }
        let (welch, overlap_inflation) = match self.segmentation {
            Segmentation::Welch { len } => {
                let weights: Vec<f64> = (0..len)
                    .map(|m| self.window.weight(m, len, 1.0 / plan.sample_rate))
                    .collect();
                let segments = self.segmentation.starts(plan.len).count();
                (
                    true,
                    overlap_inflation(&weights, (len / 2).max(1), segments),
                )
            }
            _ => (false, 1.0),
        };
        Ok(RecordMoments {
            freqs_hz: freqs,
            szz,
            observations: self.averages,
            welch,
            overlap_inflation,
        })
    }
}

/// How much more a sum of products of `segments` overlapping segments (window `weights`,
/// `hop` samples apart) varies than one over as many independent segments, for a random
/// (broadband, stationary) signal and independent broadband noise:
///
/// $$\kappa = 1 + 2\sum_{\ell \ge 1} \rho_\ell^2 \,\frac{S - \ell}{S},\qquad
///   \rho_\ell = \frac{\sum_m w_m w_{m + \ell h}}{\sum_m w_m^2}.$$
///
/// `ρ_ℓ` is the correlation of one line's spectra of segments `ℓ` apart (signal or noise
/// alike); a product of signal and noise spectra (a term of the likelihood's gradient)
/// correlates by `ρ_ℓ²`. Hann at 50 % overlap: the overlapping halves give
/// `ρ₁ = Σ sin²cos² / Σ sin⁴ = (N/16)/(3N/8) = 1/6` (Harris's 16.7 %), so
/// `κ → 1 + 2/36 = 19/18` for many segments; rectangular at 50 %: `ρ₁ = 1/2`, `κ → 3/2`.
pub(crate) fn overlap_inflation(weights: &[f64], hop: usize, segments: usize) -> f64 {
    let power: f64 = weights.iter().map(|w| w * w).sum();
    if segments < 2 || power <= 0.0 || hop == 0 {
        return 1.0;
    }
    let s = segments as f64;
    let mut kappa = 1.0;
    let mut lag = 1;
    while lag < segments && lag * hop < weights.len() {
        let shift = lag * hop;
        let rho: f64 = weights[..weights.len() - shift]
            .iter()
            .zip(&weights[shift..])
            .map(|(a, b)| a * b)
            .sum::<f64>()
            / power;
        kappa += 2.0 * rho * rho * (s - lag as f64) / s;
        lag += 1;
    }
    kappa
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hann at 50 %: ρ₁ = 1/6 exactly (Σ sin²cos² over the overlapping half / Σ sin⁴ =
    /// (N/16)/(3N/8)), so κ = 1 + 2/36 (S − 1)/S; rectangular at 50 %: ρ₁ = 1/2; whole
    /// records: 1.
    #[test]
    fn overlap_inflation_closed_forms() {
        let len = 256;
        let hann: Vec<f64> = (0..len)
            .map(|m| (std::f64::consts::PI * m as f64 / len as f64).sin().powi(2))
            .collect();
        let k = overlap_inflation(&hann, len / 2, 10);
        assert!((k - (1.0 + 2.0 / 36.0 * 0.9)).abs() < 1e-12, "{k}");
        let rect = vec![1.0; len];
        let k = overlap_inflation(&rect, len / 2, 4);
        assert!((k - (1.0 + 0.5 * 0.75)).abs() < 1e-12, "{k}");
        assert!((overlap_inflation(&hann, len, 1) - 1.0).abs() < 1e-15);
    }
}
