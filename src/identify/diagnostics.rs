//! The diagnostics of a finished fit: the flexibility `r²`, the warnings of the data
//! (coherence selection, conditioning, dropped lines, unpaired records), the non-convergence
//! policy ([`NonConvergence`]) and the fit gate's findings ([`crate::gate`]).

use faer::{Mat, c64};

use crate::conditioning::Conditioning;
use crate::error::Warning;
use crate::frf::{Frf, FrfBuilder};
use crate::gate;
use crate::linalg::Inverter;
use crate::model::Coefficients;

use super::Settings;

impl Settings {
    /// The warnings of the data behind a fit, in order: lines dropped for low coherence
    /// (`low_coherence` of them), conditioning, lines dropped by the spectra, unpaired records.
    pub(super) fn data_warnings(
        &self,
        frf: &Frf,
        conditioning: &Conditioning,
        low_coherence: usize,
    ) -> Vec<Warning> {
        let mut warnings = Vec::new();
        if low_coherence > 0 {
            warnings.push(Warning::LowCoherence {
                lines: low_coherence,
                threshold: self.min_coherence,
            });
        }
        warnings.extend(conditioning.warning());
        if !frf.dropped_hz().is_empty() {
            warnings.push(Warning::DroppedLines {
                freqs_hz: frf.dropped_hz().to_vec(),
            });
        }
        if !frf.unpaired().is_empty() {
            warnings.push(Warning::UnpairedRecords {
                records: frf.unpaired().to_vec(),
            });
        }
        warnings
    }

    /// The fit gate's findings on a fit of `frf` (window-corrected `model`, `r2` of the
    /// windowed data); the resolution check only for spectra made here (`builder`).
    pub(super) fn gate_warnings(
        &self,
        frf: &Frf,
        r2: faer::MatRef<'_, f64>,
        model: &Coefficients,
        builder: Option<&FrfBuilder>,
    ) -> Vec<Warning> {
        let band = self.band;
        let mut out = self.gate.poor_fit(frf, r2);
        out.extend(gate::physics(model));
        out.extend(gate::negative_diagonal_causes(
            frf,
            model,
            self.method,
            &self.ivf,
            builder.is_some_and(FrfBuilder::all_displacement)
                && self.window.decay_per_s().is_none(),
        ));
        out.extend(gate::window(self.window, band));
        if builder.is_some() {
            if let Some(spacing) = line_spacing(frf.freqs_hz()) {
                out.extend(gate::resolution(self.segmentation, spacing, band, model));
            }
        }
        out.extend(gate::few_lines(frf.line_count(), frf.dofs()));
        out
    }
}

/// The smallest spacing of consecutive lines (Hz), if there are two.
fn line_spacing(freqs_hz: &[f64]) -> Option<f64> {
    freqs_hz
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .min_by(f64::total_cmp)
}

/// Per-element coefficient of determination between measured and fitted flexibility,
/// $r^2_{ij} = 1 - \sum_k |G_{ij,k} - \hat G_{ij,k}|^2 / \sum_k |G_{ij,k} - \bar G_{ij}|^2$.
pub(super) fn flexibility_r2(frf: &Frf, model: &Coefficients) -> Mat<f64> {
    let (n, lines) = (frf.dofs(), frf.line_count());
    let nn = n * n;
    let data = frf.flexibility_data();
    let zero = c64::new(0.0, 0.0);
    let mut mean = vec![zero; nn];
    for line in data.chunks_exact(nn) {
        for (m, g) in mean.iter_mut().zip(line) {
            *m += *g;
        }
    }
    let count = lines as f64;
    // One inverter and one buffer for every line's model flexibility.
    let mut inverter = Inverter::new(n);
    let mut fitted = vec![zero; nn];
    let (mut res, mut tot) = (vec![0.0; nn], vec![0.0; nn]);
    for (&f, measured) in frf.freqs_hz().iter().zip(data.chunks_exact(nn)) {
        // The model flexibility `(K − ω²M + iωC)⁻¹`, by cofactors for three degrees of freedom.
        let w = 2.0 * std::f64::consts::PI * f;
        let (m, c, k) = (model.mass(), model.damping(), model.stiffness());
        for j in 0..n {
            for i in 0..n {
                fitted[i + j * n] = c64::new(k[(i, j)] - w * w * m[(i, j)], w * c[(i, j)]);
            }
        }
        let regular = inverter.invert_by_cofactors(&mut fitted);
        for e in 0..nn {
            let g = measured[e];
            tot[e] += (g - mean[e] / count).norm_sqr();
            res[e] += if regular {
                (g - fitted[e]).norm_sqr()
            } else {
                f64::INFINITY
            };
        }
    }
    Mat::from_fn(n, n, |i, j| 1.0 - res[i + j * n] / tot[i + j * n])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_spacing_is_the_smallest_positive_step() {
        let d = line_spacing(&[1.0, 2.0, 2.5, 4.0]).unwrap();
        assert!((d - 0.5).abs() < 1e-15);
        assert!(line_spacing(&[1.0]).is_none());
    }
}
