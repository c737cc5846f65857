//! How the standard deviations of the coefficients are estimated ([`Uncertainty`]): the
//! first-order sandwich (or, for ML, the inverse Fisher information) carried by the fit itself,
//! the jackknife (`jackknife.rs`) and the bootstrap (`bootstrap.rs`) over replicates,
//! with 95 % intervals from Student's t (`student_t.rs`).

mod bootstrap;
mod budget;
mod jackknife;

use faer::Mat;

use crate::error::{Error, Result, Warning};
use crate::frf::{Frf, FrfBuilder, Replicates};
use crate::gate;
use crate::model::Coefficients;
use crate::solve::{self, Fit, Method};

use super::{ModelCheck, Settings};
use crate::statistics::t975;
pub use budget::Budget;

/// How the standard deviations of the coefficients are estimated.
///
/// # Examples
/// ```
/// use bearing_ident::Uncertainty;
/// assert_eq!("jackknife".parse::<Uncertainty>()?, Uncertainty::Jackknife);
/// assert_eq!("bootstrap".parse::<Uncertainty>()?, Uncertainty::BOOTSTRAP);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Uncertainty {
    /// No error bars: nor does the fit form its first-order covariance ([`Fit::std_dev`] and
    /// [`Fit::covariance`] of [`Identification::fit`](crate::Identification::fit) are
    /// `None`, except for [`Method::Ml`]'s Fisher information).
    None,
    /// First-order covariance: the sandwich from the fit's own residuals (least squares and IVF;
    /// see [`Fit::std_dev`]), the inverse Fisher information for [`Method::Ml`] (JSON
    /// `"fisher"`). 95 % intervals use the normal quantile 1.96.
    #[default]
    Sandwich,
    /// Jackknife over records: the fit is repeated with each paired set (paired sets) or each
    /// record (H1) left out, and $\sigma^2 = \frac{R-1}{R}\sum_r (\theta_{(-r)} - \bar\theta)^2$.
    /// Needs at least 3 replicates (else the sandwich is used, with a warning). 95 % intervals
    /// use Student's t with `R − 1` degrees of freedom.
    Jackknife,
    /// Bootstrap over records: `replicates` refits, each on `R` paired sets (paired sets) or
    /// records (cross-spectral estimators) drawn with replacement by a generator seeded with
    /// `seed`; $\sigma^2 = \frac{R}{R-1}\,\mathrm{var}_b(\theta_b)$ (the factor corrects
    /// the resampling's small-`R` shrinkage). Needs at least 3 replicates (else the sandwich is
    /// used, with a warning). 95 % intervals use Student's t with `R − 1` degrees of freedom.
    Bootstrap {
        /// Number of bootstrap refits (≥ 20; 200 is usual; at most [`MAX_BOOTSTRAP_DRAWS`],
        /// past which [`Identifier::check`](crate::Identifier::check) fails with
        /// [`Error::TooLarge`]).
        replicates: usize,
        /// Seed of the resampling.
        seed: u64,
    },
    /// The jackknife when there are at least 3 replicates, else the sandwich (no warning);
    /// for periodic records the sandwich, whose noise the periods measure line by line (their
    /// scatter has many degrees of freedom at every line, a jackknife over a few records
    /// few). The result reports the one used.
    Auto,
}

/// Most bootstrap refits an identification runs (100 000).
pub const MAX_BOOTSTRAP_DRAWS: usize = 100_000;

impl Uncertainty {
    /// The bootstrap with 200 replicates and seed 0.
    pub const BOOTSTRAP: Uncertainty = Uncertainty::Bootstrap {
        replicates: 200,
        seed: 0,
    };

    /// Whether the replicates' own spectra must be kept.
    pub(crate) fn resamples(self) -> bool {
        matches!(
            self,
            Uncertainty::Jackknife | Uncertainty::Bootstrap { .. } | Uncertainty::Auto
        )
    }
}

impl crate::Choice for Uncertainty {
    const OPTION: &'static str = "uncertainty";
    const ALL: &'static [Uncertainty] = &[
        Uncertainty::Auto,
        Uncertainty::None,
        Uncertainty::Sandwich,
        Uncertainty::Jackknife,
        Uncertainty::BOOTSTRAP,
    ];

    /// `"auto"`, `"none"`, `"sandwich"`, `"jackknife"` or `"bootstrap"` (the command line's
    /// `--uncertainty` values); `"bootstrap"` parses as [`Uncertainty::BOOTSTRAP`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Choice, Uncertainty};
    /// assert_eq!("bootstrap".parse::<Uncertainty>()?, Uncertainty::BOOTSTRAP);
    /// assert_eq!(Uncertainty::Bootstrap { replicates: 9, seed: 1 }.name(), "bootstrap");
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    fn name(self) -> &'static str {
        match self {
            Uncertainty::None => "none",
            Uncertainty::Sandwich => "sandwich",
            Uncertainty::Jackknife => "jackknife",
            Uncertainty::Bootstrap { .. } => "bootstrap",
            Uncertainty::Auto => "auto",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Uncertainty::Auto => {
                "the jackknife with at least 3 sets or records, else the sandwich; periods: the sandwich"
            }
            Uncertainty::None => "no error bars",
            Uncertainty::Sandwich => {
                "first order: the replicates' scatter (else the residuals) through the fit"
            }
            Uncertainty::Jackknife => "leave-one-out refits of the sets or records",
            Uncertainty::Bootstrap { .. } => "refits of resampled sets or records",
        }
    }
}

crate::choice::choice_text!(Uncertainty);

/// The error bars of a fit: the estimate used, the combined standard deviations, their
/// budget and the factor `q` of the 95 % half-widths `q · σ`.
pub(super) struct ErrorBars {
    pub(super) uncertainty: Uncertainty,
    pub(super) std_dev: Option<Coefficients>,
    pub(super) budget: Option<Budget>,
    pub(super) interval_factor: f64,
}

impl Settings {
    /// The error bars of `fit` (window-corrected) by the chosen [`Uncertainty`]: the
    /// resampling estimates refit the replicates of `builder` on the lines of `frf`; without
    /// `builder` or with fewer than 3 replicates, the sandwich. Warnings (few or dependent
    /// replicates, zero spread) are appended to `warnings`. The random part so estimated is
    /// combined with the model (from `check` and the band refits) and calibration parts of
    /// the [`Budget`].
    pub(super) fn error_bars(
        &self,
        fit: &Fit,
        frf: &Frf,
        builder: Option<&FrfBuilder>,
        check: &ModelCheck,
        warnings: &mut Vec<Warning>,
    ) -> Result<ErrorBars> {
        // Shared by every refit: per-set impedances (or per-record cross-spectra) on the
        // lines of `frf`, with their condition numbers; only the fit is repeated.
        let shared = match builder {
            Some(b) if self.resamples() && self.method != Method::Ml => {
                Some(b.replicates_on(&self.assignment, frf)?)
            }
            _ => None,
        };
        let replicates = shared.as_ref().map_or(0, Replicates::count);
        let mut uncertainty = match self.uncertainty {
            Uncertainty::Auto if self.method == Method::Ml || !self.resamples() => {
                Uncertainty::Sandwich
            }
            Uncertainty::Auto if replicates >= 3 => Uncertainty::Jackknife,
            Uncertainty::Auto => Uncertainty::Sandwich,
            Uncertainty::Jackknife | Uncertainty::Bootstrap { .. } if replicates < 3 => {
                warnings.push(Warning::FewReplicates { replicates });
                Uncertainty::Sandwich
            }
            chosen => chosen,
        };
        let (std_dev, interval_factor) = match (uncertainty, &shared) {
            (Uncertainty::Jackknife, Some(shared)) => {
                // A replicate that alone excites a direction (one x record among y records)
                // cannot be left out: the refit without it has no lines to fit.
                let (std, distinct) = match self.jackknife(shared) {
                    Err(
                        e @ (Error::TooFewLines { .. }
                        | Error::RankDeficient { .. }
                        | Error::Singular { .. }
                        | Error::SingularFit { .. }),
                    ) => {
                        warnings.push(Warning::JackknifeUnavailable {
                            reason: e.to_string(),
                        });
                        uncertainty = Uncertainty::Sandwich;
                        (None, 0)
                    }
                    Ok((std, distinct)) => (Some(std), distinct),
                    Err(e) => return Err(e),
                };
                match std {
                    // The sandwich the fit carries, with normal intervals.
                    None => (fit.std_dev().cloned(), t975(0)),
                    Some(std) => {
                        if distinct < replicates {
                            warnings.push(Warning::DependentReplicates {
                                replicates,
                                distinct,
                            });
                        } else {
                            warnings.extend(gate::zero_spread(&std, fit.coefficients()));
                        }
                        (Some(std), t975(replicates - 1))
                    }
                }
            }
            (
                Uncertainty::Bootstrap {
                    replicates: draws,
                    seed,
                },
                Some(shared),
            ) => {
                let std = self.bootstrap(shared, draws, seed)?;
                warnings.extend(gate::zero_spread(&std, fit.coefficients()));
                (Some(std), t975(replicates - 1))
            }
            (Uncertainty::None, _) => (None, 0.0),
            // The sandwich (or Fisher information) the fit carries, with normal intervals.
            _ => (fit.std_dev().cloned(), t975(0)),
        };
        let budget = std_dev
            .as_ref()
            .map(|random| self.budget(fit.coefficients(), random, check, frf))
            .transpose()?;
        Ok(ErrorBars {
            uncertainty,
            std_dev: budget.as_ref().map(Budget::combined).transpose()?,
            budget,
            interval_factor,
        })
    }

    /// The corrected, stacked coefficients refitted with the replicates weighted by
    /// `weights`, on the lines of the full data's `Frf` (after any coherence selection); no
    /// covariance is computed for a refit.
    fn refit(&self, shared: &Replicates<'_>, weights: &[f64]) -> Result<Mat<f64>> {
        self.fit_replicate(&shared.frf(weights))
    }

    /// The corrected, stacked coefficients fitted to a replicate's `frf`.
    fn fit_replicate(&self, frf: &Frf) -> Result<Mat<f64>> {
        let fit = self.corrected(solve::fit_point(frf, self.method, &self.ivf)?)?;
        Ok(fit.coefficients().stacked())
    }
}

/// Element-wise $\sqrt{s \cdot \mathrm{var}}$ over refits, with `var` the population variance
/// ($\frac1B\sum_b(\theta_b - \bar\theta)^2$) and `s` the estimator's factor.
fn spread(thetas: &[Mat<f64>], factor: f64) -> Result<Coefficients> {
    let (p, n) = (thetas[0].nrows(), thetas[0].ncols());
    let b = thetas.len() as f64;
    let std = Mat::from_fn(p, n, |i, j| {
        let mean = thetas.iter().map(|t| t[(i, j)]).sum::<f64>() / b;
        let var = thetas
            .iter()
            .map(|t| (t[(i, j)] - mean).powi(2))
            .sum::<f64>()
            / b;
        (factor * var).sqrt()
    });
    Coefficients::from_stacked(std.as_ref())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Choice;

    #[test]
    fn names_round_trip() {
        for u in [
            Uncertainty::None,
            Uncertainty::Sandwich,
            Uncertainty::Jackknife,
            Uncertainty::BOOTSTRAP,
            Uncertainty::Auto,
        ] {
            assert_eq!(u.name().parse::<Uncertainty>().unwrap(), u);
        }
        assert!(matches!(
            "fisher".parse::<Uncertainty>(),
            Err(Error::UnknownName {
                what: "uncertainty",
                ..
            })
        ));
    }

    #[test]
    fn spread_scales_the_population_variance() {
        let thetas: Vec<Mat<f64>> = [1.0, 3.0]
            .iter()
            .map(|&v| Mat::from_fn(3, 1, |_, _| v))
            .collect();
        let s = spread(&thetas, 4.0).unwrap();
        // Population variance 1, times 4, square root 2.
        assert!((s.mass()[(0, 0)] - 2.0).abs() < 1e-15);
    }
}
