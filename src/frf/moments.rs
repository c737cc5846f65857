//! [`RecordMoments`]: the second moments of the records' (segments') spectra per line, an
//! output of this stage for the maximum-likelihood fit on impact and random records, whose
//! noise model ([`crate::solve::ml::noise`]) is estimated from them.

use faer::{Mat, c64};

use super::Frf;
use super::builder::FrfBuilder;
use super::contribution::Contribution;
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
    /// Variance inflation of the likelihood's sums over one record's overlapping, windowed
    /// segments and neighbouring lines relative to independent spectra
    /// ([`overlap_inflation`]); 1 for whole records.
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
        for (l, freq, _) in plan.lines_in(frf) {
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

/// How much more the likelihood's sums over `segments` Welch segments (window `weights`,
/// `hop` samples apart) and over neighbouring lines vary than the same sums over independent
/// spectra, for a random (broadband, stationary) signal and independent broadband noise:
///
/// $$\kappa = \sum_{|\ell| < S} \frac{S - |\ell|}{S}\, \sum_{q} |\rho_{\ell q}|^2
///   = \sum_{|\ell| < S} \frac{S - |\ell|}{S}\,
///     \frac{N \sum_m (w_m w_{m + |\ell| h})^2}{\big(\sum_m w_m^2\big)^2}.$$
///
/// `ρ_ℓq` is the correlation of the spectra at lines `q` apart in segments `ℓ` apart (signal
/// or noise alike); a term of the likelihood's gradient, a product of noise and signal
/// spectra, correlates by `|ρ_ℓq|²`, and Parseval sums those over `q` in closed form. A
/// window spreads a line over its neighbours and overlap shares samples between segments:
/// Hann at 50 % gives `35/18` within a segment (neighbouring lines correlate by `2/3` and
/// `1/6`) and `1/12` for each neighbouring segment, `κ → 19/9` for many segments; a
/// rectangular window on whole records or on non-overlapping periods gives 1.
pub(crate) fn overlap_inflation(weights: &[f64], hop: usize, segments: usize) -> f64 {
    let power: f64 = weights.iter().map(|w| w * w).sum();
    if segments == 0 || power <= 0.0 || hop == 0 {
        return 1.0;
    }
    let (s, len) = (segments as f64, weights.len() as f64);
    let mut kappa = 0.0;
    let mut lag = 0;
    while lag < segments && lag * hop < weights.len() {
        let shift = lag * hop;
        let fourth: f64 = weights[..weights.len() - shift]
            .iter()
            .zip(&weights[shift..])
            .map(|(a, b)| (a * b).powi(2))
            .sum();
        let sides = if lag == 0 { 1.0 } else { 2.0 };
        kappa += sides * (s - lag as f64) / s * len * fourth / (power * power);
        lag += 1;
    }
    kappa
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hann at 50 %: 35/18 + 2 · 1/12 · (S − 1)/S (Σ sin⁸ = 35N/128, Σ sin⁴cos⁴ over the
    /// overlapping half = 3N/256, Σ sin⁴ = 3N/8); rectangular at 50 %: 1 + 2 · 1/2 · (S −
    /// 1)/S; rectangular whole records: 1.
    #[test]
    fn overlap_inflation_closed_forms() {
        let len = 256;
        let hann: Vec<f64> = (0..len)
            .map(|m| (std::f64::consts::PI * m as f64 / len as f64).sin().powi(2))
            .collect();
        let k = overlap_inflation(&hann, len / 2, 10);
        assert!((k - (35.0 / 18.0 + 2.0 / 12.0 * 0.9)).abs() < 1e-12, "{k}");
        let rect = vec![1.0; len];
        let k = overlap_inflation(&rect, len / 2, 4);
        assert!((k - (1.0 + 2.0 * 0.5 * 0.75)).abs() < 1e-12, "{k}");
        assert!((overlap_inflation(&rect, len, 1) - 1.0).abs() < 1e-15);
    }
}
