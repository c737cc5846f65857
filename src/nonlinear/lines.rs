//! Per line, the direct form of the reverse path, and what follows from it: the linear part's
//! fit and each term's coefficient spectrum and band average.
//!
//! With the Welch sums of the forces $f$ ($n$) and the inputs $z = [x;\,u]$ ($q = n + p$), per
//! line
//! $$[\hat H\;\hat A] = S_{fz}\,S_{zz}^{-1},$$
//! the force treated as the noisy output (the direct form, not the H1-type variant on
//! conditioned spectra, which leaks more at the resonances with short segments). The multiple coherence of force $i$ on the inputs is
//! $\gamma^2_{i:z} = (S_{fz} S_{zz}^{-1} S_{zf})_{ii} / S_{f_if_i}$, and the random error of row
//! $i$ of the estimate, from $n_d$ averages,
//! $$\operatorname{Var}[\hat T_{ic}] = \frac{S_{f_if_i}(1-\gamma^2_{i:z})\,(S_{zz}^{-1})_{cc}}{n_d - q}$$
//! (Bendat & Piersol's MIMO H1 random error, with the roles of input and output as
//! here). The multiple coherence of input $c$ on the other inputs,
//! $1 - 1/\big((S_{zz})_{cc}(S_{zz}^{-1})_{cc}\big)$, says how collinear it is with them.
//!
//! Term $j$ acting on DOF $i$ through input $c$ has the coefficient spectrum
//! $\hat A_j(\omega) = \hat T_{i,n+c}$; the planar friction, two inputs, the mean of its two
//! entries. Its coefficient is the variance-weighted band average
//! $a_j = \sum_k w_k \operatorname{Re}\hat A_j(\omega_k) / \sum_k w_k$,
//! $w_k = 1/\operatorname{Var}[\hat A_j(\omega_k)]$ (equal weights when a variance is zero, as
//! for noise-free records).

use faer::c64;

use crate::error::{Error, Quantity, Result};
use crate::frf::{Estimator, Frf};
use crate::linalg::{Conditioner, Inverter};
use crate::solve::{self, Fit, IvfOptions, Method};
use crate::statistics::median;

use super::gather::{BlockSums, InputChannel};

/// The per-line estimates of the reverse path.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LineEstimates {
    pub n: usize,
    pub q: usize,
    pub freqs_hz: Vec<f64>,
    /// `[Ĥ Â]` per line, column-major `n × q`.
    pub t: Vec<c64>,
    /// `Var[T_ic]` per line, column-major `n × q`.
    pub var: Vec<f64>,
    /// Multiple coherence of each force on the inputs, per line (`n` each).
    pub output_coherence: Vec<f64>,
    /// Multiple coherence of each input on the other inputs, per line (`q` each).
    pub input_coherence: Vec<f64>,
    /// Condition number of `S_zz` per line.
    pub condition: Vec<f64>,
    /// Welch averages behind the estimates.
    pub averages: usize,
}

/// The direct-form estimates of every line from `sums`.
///
/// # Errors
/// [`Error::Singular`] when `S_zz` cannot be inverted at a line (an input that is identically
/// a combination of the others, or one that carries nothing);
/// [`Error::NonFiniteResult`] when an estimate is not finite.
pub(crate) fn estimate(
    sums: &BlockSums,
    n: usize,
    q: usize,
    freqs_hz: &[f64],
) -> Result<LineEstimates> {
    let l = freqs_hz.len();
    let zero = c64::new(0.0, 0.0);
    let mut out = LineEstimates {
        n,
        q,
        freqs_hz: freqs_hz.to_vec(),
        t: vec![zero; l * n * q],
        var: vec![0.0; l * n * q],
        output_coherence: vec![0.0; l * n],
        input_coherence: vec![0.0; l * q],
        condition: vec![0.0; l],
        averages: sums.segments,
    };
    let mut conditioner = Conditioner::new(q);
    let dof_free = sums.segments.saturating_sub(q).max(1) as f64;
    let mut inverter = Inverter::new(q);
    let mut inv = vec![zero; q * q];
    for (k, &freq_hz) in freqs_hz.iter().enumerate() {
        let zz = &sums.zz[k * q * q..(k + 1) * q * q];
        let fz = &sums.fz[k * n * q..(k + 1) * n * q];
        let ff = &sums.ff[k * n * n..(k + 1) * n * n];
        out.condition[k] = conditioner.condition_number(zz);
        inv.copy_from_slice(zz);
        if !inverter.invert(&mut inv) {
            return Err(Error::Singular {
                what: "the reverse path's input cross-spectral matrix S_zz (an input is a \
                       combination of the others, or zero, at a band line)",
            });
        }
        let t = &mut out.t[k * n * q..(k + 1) * n * q];
        for c in 0..q {
            for i in 0..n {
                t[i + c * n] = (0..q).map(|b| fz[i + b * n] * inv[b + c * q]).sum();
            }
        }
        for i in 0..n {
            let explained: f64 = (0..q)
                .map(|c| (t[i + c * n] * fz[i + c * n].conj()).re)
                .sum();
            let power = ff[i + i * n].re;
            let gamma = if power > 0.0 {
                (explained / power).clamp(0.0, 1.0)
            } else {
                0.0
            };
            out.output_coherence[k * n + i] = gamma;
            for c in 0..q {
                out.var[k * n * q + i + c * n] =
                    power * (1.0 - gamma) * inv[c + c * q].re.max(0.0) / dof_free;
            }
        }
        for c in 0..q {
            let product = zz[c + c * q].re * inv[c + c * q].re;
            out.input_coherence[k * q + c] = if product > 0.0 {
                (1.0 - 1.0 / product).clamp(0.0, 1.0)
            } else {
                0.0
            };
        }
        if t.iter().any(|z| !(z.re.is_finite() && z.im.is_finite())) {
            return Err(Error::NonFiniteResult {
                stage: Quantity::Impedance,
                freq_hz,
            });
        }
    }
    Ok(out)
}

impl LineEstimates {
    /// The linear part `Ĥ` of every line as an [`Frf`] (the per-line `G = Ĥ⁻¹`; lines where
    /// `Ĥ` is singular are dropped), ready for the fits of [`crate::solve`].
    pub fn frf(&self) -> Frf {
        let (n, q) = (self.n, self.q);
        Frf::from_impedance_lines(
            n,
            Estimator::H1,
            self.averages,
            Vec::new(),
            self.freqs_hz.iter().enumerate().map(|(k, &f)| {
                let h = &self.t[k * n * q..k * n * q + n * n];
                (f, Some(h), self.condition[k])
            }),
        )
    }

    /// Fits `M`, `C`, `K` to the linear part by `method` (with its first-order covariance when
    /// `with_covariance`).
    ///
    /// # Errors
    /// As [`solve::fit`].
    pub fn fit(&self, method: Method, ivf: &IvfOptions, with_covariance: bool) -> Result<Fit> {
        let frf = self.frf();
        if with_covariance {
            solve::fit(&frf, method, ivf)
        } else {
            solve::fit_point(&frf, method, ivf)
        }
    }

    /// The coefficient spectrum of term `j` and its variance per line.
    pub fn term_spectrum(&self, channels: &[InputChannel], j: usize) -> (Vec<c64>, Vec<f64>) {
        let (n, q) = (self.n, self.q);
        let mine: Vec<(usize, usize)> = channels
            .iter()
            .enumerate()
            .filter(|(_, ch)| ch.term == j)
            .map(|(c, ch)| (n + c, ch.dof))
            .collect();
        let count = mine.len().max(1) as f64;
        let mut spectrum = Vec::with_capacity(self.freqs_hz.len());
        let mut var = Vec::with_capacity(self.freqs_hz.len());
        for k in 0..self.freqs_hz.len() {
            let base = k * n * q;
            let sum: c64 = mine.iter().map(|&(c, i)| self.t[base + i + c * n]).sum();
            let v: f64 = mine.iter().map(|&(c, i)| self.var[base + i + c * n]).sum();
            spectrum.push(sum / count);
            var.push(v / (count * count));
        }
        (spectrum, var)
    }

    /// Median over the band of the largest multiple coherence, on the other inputs, of the
    /// inputs of term `j`.
    pub fn term_input_coherence(&self, channels: &[InputChannel], j: usize) -> f64 {
        let (n, q) = (self.n, self.q);
        let mut per_line: Vec<f64> = (0..self.freqs_hz.len())
            .map(|k| {
                channels
                    .iter()
                    .enumerate()
                    .filter(|(_, ch)| ch.term == j)
                    .map(|(c, _)| self.input_coherence[k * q + n + c])
                    .fold(0.0, f64::max)
            })
            .collect();
        median(&mut per_line).unwrap_or(0.0)
    }
}

/// Weights $1/\sigma_k^2$ of a band average, or equal weights when a variance is not finite
/// and positive (noise-free data).
pub(crate) fn weights(var: &[f64]) -> Vec<f64> {
    if var.iter().all(|&v| v.is_finite() && v > 0.0) {
        var.iter().map(|v| 1.0 / v).collect()
    } else {
        vec![1.0; var.len()]
    }
}

/// The weighted band average of `Re Â`.
pub(crate) fn band_average(spectrum: &[c64], var: &[f64]) -> f64 {
    let w = weights(var);
    let total: f64 = w.iter().sum();
    spectrum.iter().zip(&w).map(|(a, w)| a.re * w).sum::<f64>() / total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_line_of_known_spectra_is_solved_exactly() {
        // n = 1, one regressor: f = h x + a u with x, u uncorrelated unit inputs.
        let (h, a) = (c64::new(3.0, 2.0), c64::new(0.5, 0.0));
        let one = c64::new(1.0, 0.0);
        let zero = c64::new(0.0, 0.0);
        let sums = BlockSums {
            zz: vec![one * 4.0, zero, zero, one * 2.0],
            fz: vec![h * 4.0, a * 2.0],
            ff: vec![c64::new(h.norm_sqr() * 4.0 + a.norm_sqr() * 2.0, 0.0)],
            segments: 10,
        };
        let est = estimate(&sums, 1, 2, &[10.0]).unwrap();
        assert!((est.t[0] - h).norm() < 1e-14 && (est.t[1] - a).norm() < 1e-14);
        assert!((est.output_coherence[0] - 1.0).abs() < 1e-14);
        assert!(est.var.iter().all(|v| v.abs() < 1e-12));
        assert!(est.input_coherence.iter().all(|g| g.abs() < 1e-14));
        let ch = [InputChannel { term: 0, dof: 0 }];
        let (spectrum, var) = est.term_spectrum(&ch, 0);
        assert!((band_average(&spectrum, &var) - 0.5).abs() < 1e-14);
    }

    #[test]
    fn a_zero_input_is_singular() {
        let z = c64::new(0.0, 0.0);
        let sums = BlockSums {
            zz: vec![c64::new(1.0, 0.0), z, z, z],
            fz: vec![c64::new(1.0, 0.0), z],
            ff: vec![c64::new(1.0, 0.0)],
            segments: 10,
        };
        let e = estimate(&sums, 1, 2, &[10.0]).unwrap_err();
        assert_eq!(e.kind(), "singular");
    }

    #[test]
    fn weighted_average_and_median() {
        let s = [c64::new(1.0, 5.0), c64::new(3.0, 0.0)];
        assert!((band_average(&s, &[1.0, 3.0]) - 1.5).abs() < 1e-15);
        assert!((band_average(&s, &[0.0, 3.0]) - 2.0).abs() < 1e-15);
    }
}
