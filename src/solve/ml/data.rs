//! [`MlData`]: the mean spectra and noise covariances per line that the maximum-likelihood fit
//! and the Cramér–Rao bound read.

use faer::{Mat, c64};

use super::NoiseModel;
use crate::error::{Error, Quantity, Result};
use crate::frf::PeriodStatistics;
use crate::model::Coefficients;
use crate::records::finite_positive;

/// Mean spectra and their noise covariances per line: what the maximum-likelihood fit and the
/// Cramér–Rao bound need. Build with [`MlData::new`] (your own), [`MlData::planned`] (for test
/// planning) or from periodic records through [`crate::Identifier`] with
/// [`crate::Segmentation::Periods`].
#[derive(Debug, Clone, PartialEq)]
pub struct MlData {
    pub(super) n: usize,
    pub(super) columns: usize,
    pub(super) freqs_hz: Vec<f64>,
    /// `[line][column][i]`.
    pub(super) x: Vec<c64>,
    pub(super) f: Vec<c64>,
    /// `[line][n × n]`, column-major.
    pub(super) cx: Vec<c64>,
    pub(super) cf: Vec<c64>,
    pub(super) cxf: Vec<c64>,
    /// Spectra behind each line's columns (the columns themselves, unless they stand for a
    /// sum of second moments: [`noise`](super::noise)).
    pub(super) observations: usize,
    /// Factor on `F⁻¹` for observations that are not independent (overlapping Welch
    /// segments); 1 otherwise.
    pub(super) inflation: f64,
    pub(super) noise_model: NoiseModel,
}

impl MlData {
    /// From per-line data: `x[k]`, `f[k]` are `n × J` (column `j` = excitation `j`'s mean
    /// displacement and force spectra), `cx[k]`, `cf[k]`, `cxf[k]` the `n × n` noise
    /// covariances of one column's means.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for empty data, mismatched sizes, fewer columns than
    /// degrees of freedom, or a frequency that is not finite and positive;
    /// [`Error::NonFiniteResult`] naming the first line with a non-finite entry.
    pub fn new(
        freqs_hz: Vec<f64>,
        x: &[Mat<c64>],
        f: &[Mat<c64>],
        cx: &[Mat<c64>],
        cf: &[Mat<c64>],
        cxf: &[Mat<c64>],
    ) -> Result<Self> {
        let bad = |name, value: f64, expected| Error::InvalidParameter {
            name,
            value,
            expected,
        };
        let lines = freqs_hz.len();
        if lines == 0 || [x.len(), f.len(), cx.len(), cf.len(), cxf.len()] != [lines; 5] {
            return Err(bad(
                crate::Parameter::MlDataLines,
                lines as f64,
                "one x, f, C_X, C_F, C_XF per frequency, at least one line",
            ));
        }
        let (n, columns) = (x[0].nrows(), x[0].ncols());
        if n == 0 || columns < n {
            return Err(bad(
                crate::Parameter::MlDataColumns,
                columns as f64,
                "at least as many excitations as degrees of freedom",
            ));
        }
        let mut data = Self {
            n,
            columns,
            freqs_hz,
            x: Vec::with_capacity(lines * columns * n),
            f: Vec::with_capacity(lines * columns * n),
            cx: Vec::with_capacity(lines * n * n),
            cf: Vec::with_capacity(lines * n * n),
            cxf: Vec::with_capacity(lines * n * n),
            observations: columns,
            inflation: 1.0,
            noise_model: NoiseModel::Given,
        };
        for k in 0..lines {
            let w = data.freqs_hz[k];
            if !finite_positive(w) {
                return Err(bad(
                    crate::Parameter::Frequency,
                    w,
                    "finite and positive (Hz)",
                ));
            }
            let shapes_ok = [&x[k], &f[k]]
                .iter()
                .all(|m| m.nrows() == n && m.ncols() == columns)
                && [&cx[k], &cf[k], &cxf[k]]
                    .iter()
                    .all(|m| m.nrows() == n && m.ncols() == n);
            if !shapes_ok {
                return Err(bad(
                    crate::Parameter::MlDataShape,
                    k as f64,
                    "x, f n × J and covariances n × n on every line",
                ));
            }
            for (dst, m) in [(&mut data.x, &x[k]), (&mut data.f, &f[k])] {
                for j in 0..columns {
                    dst.extend((0..n).map(|i| m[(i, j)]));
                }
            }
            for (dst, m) in [
                (&mut data.cx, &cx[k]),
                (&mut data.cf, &cf[k]),
                (&mut data.cxf, &cxf[k]),
            ] {
                for j in 0..n {
                    dst.extend((0..n).map(|i| m[(i, j)]));
                }
            }
            // This line's entries, just added.
            let finite =
                |v: &[c64], per_line: usize| v[v.len() - per_line..].iter().all(|z| z.is_finite());
            let (xf, nn) = (columns * n, n * n);
            let all = finite(&data.x, xf)
                && finite(&data.f, xf)
                && [&data.cx, &data.cf, &data.cxf]
                    .iter()
                    .all(|v| finite(v, nn));
            if !all {
                return Err(Error::NonFiniteResult {
                    stage: Quantity::MlData,
                    freq_hz: w,
                });
            }
        }
        Ok(data)
    }

    /// Data for planning a test: the displacements `x = G(ω) f` of `system` under the force
    /// spectra `forces[k]` (`n × J`, one column per excitation), with white noise of spectral
    /// variance `force_var` on every force line and `disp_var` on every displacement line (the
    /// variance of a mean over `P` periods of `N` samples of white noise with standard deviation
    /// `σ`, sampled `Δt` apart, is `σ² N Δt² / P` in this crate's DFT scaling).
    ///
    /// # Errors
    /// As [`MlData::new`]; [`Error::Singular`] if `H(ω)` is singular at a line.
    pub fn planned(
        system: &Coefficients,
        freqs_hz: Vec<f64>,
        forces: &[Mat<c64>],
        force_var: f64,
        disp_var: f64,
    ) -> Result<Self> {
        let n = system.dofs();
        let x = freqs_hz
            .iter()
            .zip(forces)
            .map(|(&f, force)| Ok(system.flexibility_at(f)? * force))
            .collect::<Result<Vec<_>>>()?;
        let lines = freqs_hz.len();
        let diag = |v: f64| Mat::from_fn(n, n, |i, j| c64::new(if i == j { v } else { 0.0 }, 0.0));
        Self::new(
            freqs_hz,
            &x,
            forces,
            &vec![diag(disp_var); lines],
            &vec![diag(force_var); lines],
            &vec![Mat::zeros(n, n); lines],
        )
    }

    /// Number of degrees of freedom.
    pub fn dofs(&self) -> usize {
        self.n
    }

    /// Frequencies of the lines (Hz).
    pub fn freqs_hz(&self) -> &[f64] {
        &self.freqs_hz
    }

    /// Independent excitations (columns) per line.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// The cost expected at the minimum if the model and the noise covariances are right:
    /// one per complex residual less half a parameter each, `L·J·n − 3n²/2` (`J` the spectra
    /// per line, [`MlData::observations`]).
    pub fn expected_cost(&self) -> f64 {
        let n = self.n as f64;
        (self.freqs_hz.len() * self.observations * self.n) as f64 - 1.5 * n * n
    }

    /// Spectra (records, periods' means, Welch segments) behind each line: the columns, or
    /// the count whose second moments the columns carry ([`noise`](super::noise)).
    pub fn observations(&self) -> usize {
        self.observations
    }

    /// Where the noise covariances came from.
    pub fn noise_model(&self) -> NoiseModel {
        self.noise_model
    }
}

impl MlData {
    /// From the per-period statistics of periodic records, the frf stage's output
    /// ([`FrfBuilder`](crate::frf::FrfBuilder)).
    ///
    /// # Errors
    /// As [`MlData::new`].
    pub(crate) fn from_statistics(statistics: PeriodStatistics) -> Result<Self> {
        let PeriodStatistics {
            freqs_hz,
            x,
            f,
            cx,
            cf,
            cxf,
        } = statistics;
        let mut data = Self::new(freqs_hz, &x, &f, &cx, &cf, &cxf)?;
        data.noise_model = NoiseModel::PeriodicRepeats;
        Ok(data)
    }
}
