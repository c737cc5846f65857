//! [`Fitter`]: a fitting method with every option it takes, the one seam between the
//! identification and the solvers. It fits an FRF and, for the methods that need more than the
//! FRF (maximum likelihood's noise model), the spectra kept per record.

use crate::error::{Error, Result, Warning};
use crate::frf::{Frf, FrfBuilder};
use crate::spectra::Window;

use super::ml::{self, MlData, MlOptions, MlReport};
use super::{Convergence, Fit, Iteration, IvfOptions, Method, NonConvergence};

/// A fitting method with its options: IVF's stopping rules (also the start of maximum
/// likelihood), maximum likelihood's, and what a fit that does not converge does.
///
/// # Examples
/// ```
/// use bearing_ident::solve::Fitter;
/// use bearing_ident::{Method, Identifier};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let fitted = Fitter::new(Method::LeastSquares).fit(id.frf(), None, Default::default())?;
/// assert!((fitted.fit.coefficients().mass()[(0, 0)] - 4.7).abs() < 0.05);
/// assert!(fitted.ml.is_none() && fitted.unconverged.is_none());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Fitter {
    /// The method.
    pub method: Method,
    /// IVF's tolerance and iteration limit (IVF, and the start of maximum likelihood).
    pub ivf: IvfOptions,
    /// Maximum likelihood's tolerance and step limit.
    pub ml: MlOptions,
    /// What a fit that does not converge does.
    pub non_convergence: NonConvergence,
    /// Whether least squares and IVF form their first-order (sandwich) covariance
    /// ([`Fit::std_dev`], [`Fit::covariance`]); `true` but for an identification under
    /// `Uncertainty::None`, which shows no error bars ([`Fitter::without_covariance`]).
    covariance: bool,
}

/// What a [`Fitter`] gives: the fit, maximum likelihood's report, and the warnings of the fit
/// (maximum likelihood's, then the convergence's).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Fitted {
    /// The fit (of the data as given: a window's correction is the caller's).
    pub fit: Fit,
    /// Maximum likelihood's report ([`Method::Ml`] only).
    pub ml: Option<MlReport>,
    /// Maximum likelihood's warnings: windowed records, a fallback to the IVF start.
    pub warnings: Vec<Warning>,
    /// The warning of a fit that did not converge, under [`NonConvergence::Warn`].
    pub unconverged: Option<Warning>,
}

impl Fitter {
    /// `method` with default options.
    pub fn new(method: Method) -> Self {
        Self {
            method,
            ivf: IvfOptions::default(),
            ml: MlOptions::default(),
            non_convergence: NonConvergence::default(),
            covariance: true,
        }
    }

    /// The fitter without the first-order covariance of least squares and IVF (no
    /// [`Fit::std_dev`], no [`Fit::covariance`]; maximum likelihood keeps its Fisher
    /// information): for an identification under `Uncertainty::None`, where the sandwich
    /// and its instruments cost as much as the IVF iterations themselves.
    pub(crate) fn without_covariance(mut self) -> Self {
        self.covariance = false;
        self
    }

    /// [`super::fit`], or [`super::fit_point`] without the covariance.
    fn fit_frf(&self, frf: &Frf, method: Method) -> Result<Fit> {
        if self.covariance {
            super::fit(frf, method, &self.ivf)
        } else {
            super::fit_point(frf, method, &self.ivf)
        }
    }

    /// Fits `frf`. Maximum likelihood also needs `records`, the spectra kept per record or
    /// period of the FRF's estimate (its noise model), and the `window` they were taken
    /// under; the other methods use neither.
    ///
    /// # Errors
    /// The method's errors; [`Error::MlNeedsRepeats`] for maximum likelihood without
    /// `records`; under [`NonConvergence::Fail`], those of [`Convergence::judged`].
    pub fn fit(&self, frf: &Frf, records: Option<&FrfBuilder>, window: Window) -> Result<Fitted> {
        let (fit, ml, warnings) = match self.method {
            Method::Ml => {
                let (fit, report, warnings) = self.maximum_likelihood(frf, records, window)?;
                (fit, Some(report), warnings)
            }
            method => (self.fit_frf(frf, method)?, None, Vec::new()),
        };
        let last_change = fit.history().last().map(Iteration::change);
        let unconverged =
            fit.convergence()
                .judged(self.method, self.non_convergence, last_change)?;
        Ok(Fitted {
            fit,
            ml,
            warnings,
            unconverged,
        })
    }

    /// Maximum likelihood: an IVF start refined with noise covariances from the periods'
    /// scatter (periodic records) or from the residuals of the records or Welch segments about
    /// the start ([`ml::noise`]); when the refinement falls back, the IVF start with
    /// [`Warning::MlFellBack`].
    fn maximum_likelihood(
        &self,
        frf: &Frf,
        records: Option<&FrfBuilder>,
        window: Window,
    ) -> Result<(Fit, MlReport, Vec<Warning>)> {
        let records = records.ok_or(Error::MlNeedsRepeats)?;
        let mut warnings = Vec::new();
        let start = self.fit_frf(frf, Method::Ivf)?;
        if let c @ Convergence::NonFinite { .. } = start.convergence() {
            // A start that met NaN: the error under `NonConvergence::Fail`, before the noise
            // model meets it too.
            c.judged(Method::Ivf, self.non_convergence, None)?;
        }
        let data = if records.is_periodic() {
            MlData::from_statistics(records.period_statistics(frf)?)?
        } else {
            let moments = records.record_moments(frf)?;
            if let (false, Some(decay_per_s)) = (moments.welch, window.decay_per_s()) {
                if decay_per_s > 0.0 {
                    warnings.push(Warning::MlWindowedRecords { decay_per_s });
                }
            }
            ml::noise::residual_data(&moments, start.coefficients())?
        };
        let refined = ml::fit(&data, start.coefficients(), &self.ml)?;
        let fit = match (&refined.report.fell_back, refined.covariance) {
            (None, Some(cov)) => Fit::refined_by_ml(
                &start,
                refined.coefficients,
                cov,
                refined.report.convergence,
            )?,
            (reason, _) => {
                warnings.push(Warning::MlFellBack {
                    reason: reason.clone().unwrap_or_default(),
                });
                start
            }
        };
        Ok((fit, refined.report, warnings))
    }
}
