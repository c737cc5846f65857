//! [`PeriodStatistics`]: the mean spectra of periodic records and the noise covariances of
//! those means, an output of this stage for the maximum-likelihood fit
//! (the fit receives them; this stage knows no solver).

use faer::{Mat, c64};

use super::Frf;
use super::builder::FrfBuilder;
use super::contribution::Contribution;
use crate::error::{Error, Result};
use crate::spectra::Segmentation;

/// Per line, each record's mean spectra over its periods and the pooled noise covariances of
/// those means ([`FrfBuilder::period_statistics`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PeriodStatistics {
    /// Frequencies of the lines (Hz), those of the `Frf` given.
    pub(crate) freqs_hz: Vec<f64>,
    /// Per line, `n × records`: column `r` is record `r`'s mean displacement spectrum.
    pub(crate) x: Vec<Mat<c64>>,
    /// Per line, `n × records`: column `r` is record `r`'s mean force spectrum.
    pub(crate) f: Vec<Mat<c64>>,
    /// Per line, the `n × n` noise covariance `C_X` of one column's mean displacements.
    pub(crate) cx: Vec<Mat<c64>>,
    /// Per line, the `n × n` noise covariance `C_F` of one column's mean forces.
    pub(crate) cf: Vec<Mat<c64>>,
    /// Per line, the `n × n` cross-covariance `C_XF = E[δx δfᴴ]`.
    pub(crate) cxf: Vec<Mat<c64>>,
}

impl FrfBuilder {
    /// Mean spectra of every record over its periods and the pooled noise covariances of
    /// those means, on the lines of `frf`: what the maximum-likelihood fit needs. Each record is one
    /// column (one independent excitation). Needs [`Segmentation::Periods`], at least 3
    /// periods per record, and [`FrfBuilder::keeping_partials`].
    ///
    /// With `P` periods, record `r`'s sample covariance of one period's spectra is
    /// `(Σ_p x_p x_pᴴ − P x̄ x̄ᴴ)/(P − 1)`; that of the mean is `1/P` of it; the records' are
    /// averaged (the noise is the same in every record).
    ///
    /// # Errors
    /// [`Error::NoRecords`] if nothing was pushed; [`Error::MlNeedsRepeats`] without
    /// [`Segmentation::Periods`], at least 3 periods and the records' own sums.
    pub(crate) fn period_statistics(&self, frf: &Frf) -> Result<PeriodStatistics> {
        let (plan, _) = self.plan.as_ref().ok_or(Error::NoRecords)?;
        let periods = self.segmentation.starts(plan.len).count();
        if !matches!(self.segmentation, Segmentation::Periods { .. })
            || periods < 3
            || !self.keep_partials
        {
            return Err(Error::MlNeedsRepeats);
        }
        let (n, nn) = (plan.n, plan.n * plan.n);
        let p = periods as f64;
        let records = self.gathered.len();
        let (mut x, mut f) = (Vec::new(), Vec::new());
        let (mut cx, mut cf, mut cxf) = (Vec::new(), Vec::new(), Vec::new());
        let mut freqs = Vec::new();
        for (l, freq, _) in plan.lines_in(frf) {
            freqs.push(freq);
            let mut xm = Mat::<c64>::zeros(n, records);
            let mut fm = Mat::<c64>::zeros(n, records);
            let mut covs = [Mat::<c64>::zeros(n, n), Mat::zeros(n, n), Mat::zeros(n, n)];
            for (r, g) in self.gathered.iter().enumerate() {
                let Contribution::Cross {
                    sff,
                    sxf,
                    sxx,
                    sf,
                    sx,
                } = &g.contribution
                else {
                    return Err(Error::MlNeedsRepeats);
                };
                let (mx, mf) = (&sx[l * n..(l + 1) * n], &sf[l * n..(l + 1) * n]);
                for i in 0..n {
                    xm[(i, r)] = mx[i] / p;
                    fm[(i, r)] = mf[i] / p;
                }
                let second = [&sxx, &sff, &sxf];
                let firsts = [(mx, mx), (mf, mf), (mx, mf)];
                for ((cov, s2), (a, b)) in covs.iter_mut().zip(second).zip(firsts) {
                    for j in 0..n {
                        for i in 0..n {
                            let centred = s2[l * nn + i + j * n] - a[i] * b[j].conj() / p;
                            cov[(i, j)] += centred / ((p - 1.0) * p * records as f64);
                        }
                    }
                }
            }
            x.push(xm);
            f.push(fm);
            let [a, b, c] = covs;
            cx.push(a);
            cf.push(b);
            cxf.push(c);
        }
        Ok(PeriodStatistics {
            freqs_hz: freqs,
            x,
            f,
            cx,
            cf,
            cxf,
        })
    }
}
