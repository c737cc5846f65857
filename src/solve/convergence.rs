//! How an iterative fit ended ([`Convergence`], one type for IVF, maximum likelihood and the
//! reverse path's IVF) and what the caller does about it ([`NonConvergence`]): one judgement,
//! [`Convergence::judged`], turns an ending into nothing, a warning or an error.

use crate::error::{Error, Result, Warning};

use super::Method;

/// How an iterative fit ended.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Convergence {
    /// The method is not iterative (direct, least squares).
    NotIterative,
    /// The block-wise relative change fell below the tolerance.
    Converged {
        /// Iterations run.
        iterations: usize,
    },
    /// The iteration limit was reached first; the last iterate is returned.
    IterationLimit {
        /// Iterations run.
        iterations: usize,
        /// Block-wise relative change of the last iteration (`None` where the fit does not
        /// report one: maximum likelihood's limit).
        change: Option<f64>,
    },
    /// The change rose three times in a row (or the model became singular); the iterate with
    /// the smallest change is returned.
    Diverged {
        /// Iterations run.
        iterations: usize,
        /// The iterate returned (0 = the least-squares start).
        fallback_iteration: usize,
    },
    /// The next iteration met NaN or infinity (the model's impedance or its inverse at a
    /// line, or the normal equations); the iterate with the smallest change is returned.
    NonFinite {
        /// Iterations run before it (the one that met it is not counted).
        iterations: usize,
        /// The iterate returned (0 = the least-squares start).
        fallback_iteration: usize,
        /// The line where it met it (Hz); `None` for the normal equations of all lines.
        freq_hz: Option<f64>,
    },
}

impl Convergence {
    /// Short name: `"not_iterative"`, `"converged"`, `"iteration_limit"`, `"diverged"` or
    /// `"non_finite"`.
    pub fn name(self) -> &'static str {
        match self {
            Convergence::NotIterative => "not_iterative",
            Convergence::Converged { .. } => "converged",
            Convergence::IterationLimit { .. } => "iteration_limit",
            Convergence::Diverged { .. } => "diverged",
            Convergence::NonFinite { .. } => "non_finite",
        }
    }

    /// `true` for [`Convergence::NotIterative`] and [`Convergence::Converged`].
    pub fn is_converged(self) -> bool {
        matches!(
            self,
            Convergence::NotIterative | Convergence::Converged { .. }
        )
    }

    /// Number of iterations run (0 when not iterative).
    pub fn iterations(self) -> usize {
        match self {
            Convergence::NotIterative => 0,
            Convergence::Converged { iterations }
            | Convergence::IterationLimit { iterations, .. }
            | Convergence::Diverged { iterations, .. }
            | Convergence::NonFinite { iterations, .. } => iterations,
        }
    }
}

impl Convergence {
    /// The warning of an ending that is not a convergence: [`Warning::NotConverged`] at the
    /// iteration limit, [`Warning::Diverged`] for a divergence or NaN met (the fallback
    /// iterate is returned); `None` for a converged or non-iterative fit.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Convergence;
    /// assert!(Convergence::Converged { iterations: 4 }.warning().is_none());
    /// let limit = Convergence::IterationLimit { iterations: 50, change: Some(1e-3) };
    /// assert_eq!(limit.warning().unwrap().kind(), "not_converged");
    /// ```
    pub fn warning(self) -> Option<Warning> {
        match self {
            Convergence::IterationLimit { iterations, change } => {
                Some(Warning::NotConverged { iterations, change })
            }
            Convergence::Diverged {
                iterations,
                fallback_iteration,
            }
            | Convergence::NonFinite {
                iterations,
                fallback_iteration,
                ..
            } => Some(Warning::Diverged {
                iterations,
                fallback_iteration,
            }),
            Convergence::NotIterative | Convergence::Converged { .. } => None,
        }
    }

    /// This ending of a `method` fit under `policy`: its [`Convergence::warning`] under
    /// [`NonConvergence::Warn`]; under [`NonConvergence::Fail`] the error instead.
    /// `last_change` is the block-wise change of the last iteration, which a divergence's
    /// error quotes.
    ///
    /// # Errors
    /// Under [`NonConvergence::Fail`]: [`Error::NotConverged`] at the limit or on a
    /// divergence, [`Error::IterationNonFinite`] for NaN or infinity met.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Convergence, Method, NonConvergence};
    /// let limit = Convergence::IterationLimit { iterations: 50, change: Some(1e-3) };
    /// assert!(limit.judged(Method::Ivf, NonConvergence::Warn, None)?.is_some());
    /// let e = limit.judged(Method::Ivf, NonConvergence::Fail, None).unwrap_err();
    /// assert_eq!(e.kind(), "not_converged");
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn judged(
        self,
        method: Method,
        policy: NonConvergence,
        last_change: Option<f64>,
    ) -> Result<Option<Warning>> {
        let warning = self.warning();
        if policy == NonConvergence::Warn || warning.is_none() {
            return Ok(warning);
        }
        Err(match self {
            Convergence::NonFinite {
                iterations,
                freq_hz,
                ..
            } => Error::IterationNonFinite {
                method: Method::Ivf,
                iteration: iterations + 1,
                freq_hz,
            },
            Convergence::IterationLimit { iterations, change } => Error::NotConverged {
                method,
                iterations,
                change,
            },
            c => Error::NotConverged {
                method,
                iterations: c.iterations(),
                change: last_change,
            },
        })
    }
}

/// What to do when an iterative fit does not converge.
///
/// # Examples
/// ```
/// use bearing_ident::NonConvergence;
/// assert_eq!("fail".parse::<NonConvergence>()?, NonConvergence::Fail);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum NonConvergence {
    /// Return the last (or, after divergence, the best) iterate with a [`Warning`](crate::Warning).
    #[default]
    Warn,
    /// Return [`Error::NotConverged`].
    Fail,
}

impl crate::Choice for NonConvergence {
    const OPTION: &'static str = "non-convergence policy";
    const ALL: &'static [NonConvergence] = &[NonConvergence::Warn, NonConvergence::Fail];

    /// Short name: `"warn"` or `"fail"`.
    fn name(self) -> &'static str {
        match self {
            NonConvergence::Warn => "warn",
            NonConvergence::Fail => "fail",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            NonConvergence::Warn => "keep the last iterate and warn",
            NonConvergence::Fail => "fail with not_converged",
        }
    }
}

crate::choice::choice_text!(NonConvergence);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Choice;
    use crate::solve::{Fitter, IvfOptions};

    /// An IVF that met NaN is `non_finite` naming the iteration under `Fail` (before:
    /// `not_converged` "in 0 iterations (last relative change NaN)"), a `diverged` warning
    /// under `Warn`; the fitter judges the same way.
    #[test]
    fn nan_inside_the_ivf_is_non_finite_not_unconverged() {
        let frf = crate::solve::tests::out_of_range_frf();
        let fit = crate::solve::fit(&frf, Method::Ivf, &IvfOptions::default()).unwrap();
        let c = fit.convergence();
        let e = c
            .judged(Method::Ivf, NonConvergence::Fail, None)
            .unwrap_err();
        assert_eq!(e.kind(), "non_finite");
        assert!(
            matches!(
                e,
                Error::IterationNonFinite {
                    method: Method::Ivf,
                    iteration: 1,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(
            e.to_string()
                .starts_with("ivf iteration 1 met NaN or infinity"),
            "{e}"
        );
        let w = c.judged(Method::Ivf, NonConvergence::Warn, None).unwrap();
        assert_eq!(w.map(|w| w.kind()), Some("diverged"));

        let mut fitter = Fitter::new(Method::Ivf);
        let fitted = fitter.fit(&frf, None, Default::default()).unwrap();
        assert_eq!(fitted.unconverged.map(|w| w.kind()), Some("diverged"));
        fitter.non_convergence = NonConvergence::Fail;
        let e = fitter.fit(&frf, None, Default::default()).unwrap_err();
        assert_eq!(e.kind(), "non_finite");
    }

    /// The limit and a divergence fail as `not_converged` quoting the change; converged and
    /// non-iterative fits pass under either policy.
    #[test]
    fn endings_are_judged_one_way() {
        let limit = Convergence::IterationLimit {
            iterations: 50,
            change: Some(2e-3),
        };
        let diverged = Convergence::Diverged {
            iterations: 7,
            fallback_iteration: 3,
        };
        for (c, change) in [(limit, Some(2e-3)), (diverged, Some(0.5))] {
            let e = c
                .judged(Method::Ml, NonConvergence::Fail, Some(0.5))
                .unwrap_err();
            assert_eq!(
                e,
                Error::NotConverged {
                    method: Method::Ml,
                    iterations: c.iterations(),
                    change,
                }
            );
        }
        for c in [
            Convergence::NotIterative,
            Convergence::Converged { iterations: 3 },
        ] {
            for policy in NonConvergence::ALL {
                assert_eq!(c.judged(Method::Ivf, *policy, None), Ok(None));
            }
        }
    }
}
