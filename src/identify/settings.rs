//! The checked settings of an identification: [`Settings`], made once by
//! [`Identifier::check`] (in the manner of linfa's `ParamGuard::check`), and the option enums
//! only the façade uses ([`Screening`]).
//!
//! Every entry point of [`Identifier`] checks its settings here once, at the top; the stages
//! then receive checked values (a [`Band`] built once, a checked [`Window`], the IVF and ML
//! options, limits) and do not check them again.

use crate::conditioning::ConditionLimits;
use crate::element::ModelSpec;
use crate::error::{Error, Result};
use crate::frf::{Assignment, Band, ChannelTransfers, Estimator, ForceNoise, Frf, FrfBuilder};
use crate::gate::FitGate;
use crate::screening::Checks;
use crate::solve::ml::MlOptions;
use crate::solve::{Fit, Fitter, IvfOptions, Method, NonConvergence};
use crate::spectra::{ForceGate, Segmentation, Window};

use super::uncertainty::{MAX_BOOTSTRAP_DRAWS, Uncertainty};
use super::{Calibration, Identifier};

/// Whether records are screened for faults ([`crate::screening`]: flat and dead channels,
/// identical records, clipping, level outliers, double hits of impacts, paired sets far from
/// the others) on their way to the spectra.
///
/// The default is [`Screening::Warn`] with [`Checks::default`]: every finding is reported, no
/// record is left out. The checks are built not to fire on clean records of any excitation
/// (impact, random, multisine, sweep, stepped sine at 5 % noise), so warning costs nothing on
/// good data.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Screening {
    /// No screening.
    Off,
    /// Report every fault found as a [`Warning`](crate::Warning); keep the record.
    Warn(Checks),
    /// Report every fault and leave the faulty records out
    /// ([`Warning::Rejected`](crate::Warning::Rejected), with the reason). A paired set far
    /// from the others is left out whole.
    Reject(Checks),
}

impl Default for Screening {
    fn default() -> Self {
        Screening::Warn(Checks::default())
    }
}

/// The settings of an [`Identifier`], each checked once ([`Identifier::check`]): the band
/// as a [`Band`], a checked window, checked IVF and ML options, condition limits, coherence
/// threshold, uncertainty, force gate, screening checks and fit gate.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// let settings = Identifier::new(8.0, 49.0).check()?;
/// assert_eq!(settings.band().high_hz(), 49.0);
/// assert!(Identifier::new(49.0, 8.0).check().is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub(super) band: Band,
    pub(super) dofs: Option<usize>,
    pub(super) estimator: Estimator,
    pub(super) method: Method,
    pub(super) assignment: Assignment,
    pub(super) segmentation: Segmentation,
    pub(super) window: Window,
    pub(super) ivf: IvfOptions,
    pub(super) ml: MlOptions,
    pub(super) limits: ConditionLimits,
    pub(super) non_convergence: NonConvergence,
    pub(super) min_coherence: f64,
    pub(super) uncertainty: Uncertainty,
    pub(super) force_gate: Option<ForceGate>,
    /// The screening checks and whether faulty records are left out; `None` when off.
    pub(super) screening: Option<(Checks, bool)>,
    pub(super) gate: FitGate,
    pub(super) calibration: Calibration,
    pub(super) transfers: ChannelTransfers,
    pub(super) force_noise: ForceNoise,
    pub(super) model: ModelSpec,
    /// Periods left out at the start of every record (periodic records only; 0 otherwise).
    pub(super) drop_periods: usize,
}

impl Settings {
    /// Checks every setting of `id`, in a fixed order (the first fault is the error).
    pub(super) fn new(id: &Identifier) -> Result<Self> {
        let band = Band::new(id.low_hz, id.high_hz)?;
        id.calibration.check(id.dofs)?;
        if id.method == Method::Ml
            && matches!(
                id.uncertainty,
                Uncertainty::Jackknife | Uncertainty::Bootstrap { .. }
            )
        {
            return Err(Error::InvalidSetting {
                name: crate::Parameter::UncertaintyWithMethodMl,
                expected: "none, sandwich or auto: ml's covariance is the inverse Fisher information",
            });
        }
        if let Uncertainty::Bootstrap { replicates, .. } = id.uncertainty {
            if replicates < 20 {
                return Err(Error::InvalidParameter {
                    name: crate::Parameter::BootstrapReplicates,
                    value: replicates as f64,
                    expected: "at least 20",
                });
            }
        }
        if !(0.0..1.0).contains(&id.min_coherence) {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::MinimumCoherence,
                value: id.min_coherence,
                expected: "0 ≤ threshold < 1",
            });
        }
        let window = id.window.check()?;
        if id.model != ModelSpec::default() {
            if window.decay_per_s().is_some_and(|a| a > 0.0) {
                return Err(Error::InvalidOption {
                    option: "model",
                    message: format!(
                        "--model {}: the families other than kcm are fitted to the records' own \
                         impedance, which an exponential window changes in a way they cannot \
                         follow; use the records without it",
                        id.model
                    ),
                });
            }
            if id.method == Method::Ml {
                return Err(Error::InvalidOption {
                    option: "model",
                    message: format!(
                        "--model {} with --method ml: maximum likelihood fits kcm only; the other \
                         families are fitted by weighted least squares on the impedance",
                        id.model
                    ),
                });
            }
        }
        id.ivf.check()?;
        id.gate.check()?;
        id.transfers.check(id.dofs)?;
        let screening = match id.screening {
            Screening::Off => None,
            Screening::Warn(c) => Some((c, false)),
            Screening::Reject(c) => Some((c, true)),
        };
        if let Some((c, _)) = screening {
            c.check()?;
        }
        id.limits.check()?;
        if let Uncertainty::Bootstrap { replicates, .. } = id.uncertainty {
            if replicates > MAX_BOOTSTRAP_DRAWS {
                return Err(Error::TooLarge {
                    what: "bootstrap draws",
                    value: replicates as f64,
                    limit: MAX_BOOTSTRAP_DRAWS as f64,
                });
            }
        }
        let ml = match id.ml {
            Some(options) => {
                options.check()?;
                options
            }
            None => derived_ml(&id.ivf),
        };
        Ok(Self {
            band,
            dofs: id.dofs,
            estimator: id.estimator,
            method: id.method,
            assignment: id.assignment.clone(),
            segmentation: id.segmentation,
            window,
            ivf: id.ivf,
            ml,
            limits: id.limits,
            non_convergence: id.non_convergence,
            min_coherence: id.min_coherence,
            uncertainty: id.uncertainty,
            force_gate: id.force_gate,
            screening,
            gate: id.gate,
            calibration: id.calibration.clone(),
            transfers: id.transfers.clone(),
            force_noise: id.force_noise,
            model: id.model,
            drop_periods: match id.segmentation {
                Segmentation::Periods { .. } => id.drop_periods,
                _ => 0,
            },
        })
    }

    /// The band, built once.
    pub fn band(&self) -> Band {
        self.band
    }

    /// The checked window.
    pub fn window(&self) -> Window {
        self.window
    }

    /// The fitting method.
    pub fn method(&self) -> Method {
        self.method
    }

    /// The options of the maximum-likelihood refinement ([`Identifier::ml_options`], or
    /// derived from the IVF settings when none were given).
    pub fn ml_options(&self) -> MlOptions {
        self.ml
    }

    /// The fitting method with its options, as the fit stage receives it.
    pub fn fitter(&self) -> Fitter {
        let mut fitter = Fitter::new(self.method);
        fitter.ivf = self.ivf;
        fitter.ml = self.ml;
        fitter.non_convergence = self.non_convergence;
        fitter
    }

    /// [`Settings::fitter`] for the identification itself: without the fit's first-order
    /// covariance under [`Uncertainty::None`], which shows no error bars.
    pub(super) fn identification_fitter(&self) -> Fitter {
        match self.uncertainty {
            Uncertainty::None => self.fitter().without_covariance(),
            _ => self.fitter(),
        }
    }

    /// The spectra's builder for these settings (replicates kept when the uncertainty
    /// resamples or the method is ML).
    pub(super) fn builder(&self) -> FrfBuilder {
        let mut builder =
            FrfBuilder::new(self.estimator, self.band, self.segmentation, self.window)
                .channel_transfers(self.transfers.clone());
        if self.resamples() || self.method == Method::Ml {
            builder = builder.keeping_partials();
        }
        if let Some(gate) = self.force_gate {
            builder = builder.force_gate(gate);
        }
        match self.dofs {
            Some(n) => builder.dofs(n),
            None => builder,
        }
    }

    /// The stride over lines of the model check's runs test: past the window's correlation of
    /// neighbouring lines (see `model_check`'s module docs): 1 without a window, 3 for Hann,
    /// `⌈1.56·a·T⌉` for an exponential window of decay `a` over segments of `T = 1/spacing`.
    pub(super) fn runs_stride(&self, frf: &Frf) -> usize {
        match self.window {
            Window::Rectangular => 1,
            Window::Hann => 3,
            Window::Exponential { decay_per_s } => match frf.line_spacing_hz() {
                Some(spacing) if spacing > 0.0 => {
                    let d = (1.56 * decay_per_s / spacing).ceil();
                    if d.is_finite() && d >= 1.0 {
                        d.min(frf.line_count() as f64 + 1.0) as usize
                    } else {
                        1
                    }
                }
                _ => usize::MAX,
            },
        }
    }

    /// Whether the error bars refit replicates, so that their spectra must be kept: the
    /// jackknife and the bootstrap, and [`Uncertainty::Auto`] unless the records are cut
    /// into periods (whose own scatter gives the sandwich its noise).
    pub(super) fn resamples(&self) -> bool {
        match self.uncertainty {
            Uncertainty::Auto => !matches!(self.segmentation, Segmentation::Periods { .. }),
            u => u.resamples(),
        }
    }

    /// The fit mapped back through an exponential window's exact correction, if any.
    pub(super) fn corrected(&self, fit: Fit) -> Result<Fit> {
        match self.window.decay_per_s() {
            Some(a) if a > 0.0 => fit.corrected_for_window(a),
            _ => Ok(fit),
        }
    }
}

/// The ML options when none were given: the IVF tolerance, at most `1e-10`, and the IVF
/// iteration limit, at least 100 (so the defaults are [`MlOptions::default`]). Valid whenever
/// the (checked) IVF options are.
fn derived_ml(ivf: &IvfOptions) -> MlOptions {
    MlOptions {
        tolerance: ivf.tolerance.min(1e-10),
        max_iterations: ivf.max_iterations.max(100),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Choice;

    fn invalid(id: Identifier) -> &'static str {
        match id.check() {
            Err(Error::InvalidParameter { name, .. } | Error::InvalidSetting { name, .. }) => {
                name.as_str()
            }
            other => panic!("expected InvalidParameter or InvalidSetting, got {other:?}"),
        }
    }

    #[test]
    fn defaults_check_and_keep_todays_ml_options() {
        let s = Identifier::new(8.0, 49.0).check().unwrap();
        assert_eq!(s.band(), Band::new(8.0, 49.0).unwrap());
        assert_eq!(s.ml_options(), MlOptions::default());
        let s = Identifier::new(8.0, 49.0)
            .tolerance(1e-6)
            .max_iterations(500)
            .check()
            .unwrap();
        assert_eq!(s.ml_options().max_iterations, 500);
        assert!((s.ml_options().tolerance - 1e-10).abs() < 1e-25);
        let own = MlOptions {
            tolerance: 1e-7,
            max_iterations: 7,
        };
        let s = Identifier::new(8.0, 49.0).ml_options(own).check().unwrap();
        assert_eq!(s.ml_options(), own);
    }

    #[test]
    fn every_setting_is_checked() {
        let id = || Identifier::new(8.0, 49.0);
        assert!(matches!(
            Identifier::new(49.0, 8.0).check(),
            Err(Error::InvalidBand { .. })
        ));
        assert_eq!(
            invalid(id().method(Method::Ml).uncertainty(Uncertainty::Jackknife)),
            "uncertainty with method ml"
        );
        let boot = |replicates| Uncertainty::Bootstrap {
            replicates,
            seed: 0,
        };
        assert_eq!(invalid(id().uncertainty(boot(19))), "bootstrap replicates");
        assert!(matches!(
            id().uncertainty(boot(MAX_BOOTSTRAP_DRAWS + 1)).check(),
            Err(Error::TooLarge { .. })
        ));
        assert!(id().uncertainty(boot(MAX_BOOTSTRAP_DRAWS)).check().is_ok());
        assert_eq!(invalid(id().min_coherence(1.0)), "minimum coherence");
        assert_eq!(invalid(id().min_coherence(f64::NAN)), "minimum coherence");
        let nan = Window::Exponential {
            decay_per_s: f64::NAN,
        };
        assert_eq!(invalid(id().window(nan)), "exponential window decay");
        assert_eq!(invalid(id().tolerance(0.0)), "ivf tolerance");
        assert_eq!(invalid(id().max_iterations(0)), "ivf max iterations");
        assert_eq!(
            invalid(id().fit_gate(FitGate { min_r2: 2.0 })),
            "minimum r²"
        );
        let bad = Checks {
            dead_ratio: 2.0,
            ..Checks::default()
        };
        assert_eq!(
            invalid(id().screening(Screening::Reject(bad))),
            "dead_ratio"
        );
        assert!(id().screening(Screening::Off).check().is_ok());
        let limits = ConditionLimits {
            warn: 10.0,
            refuse: 5.0,
        };
        assert_eq!(invalid(id().condition_limits(limits)), "condition limits");
        let ml = |tolerance, max_iterations| MlOptions {
            tolerance,
            max_iterations,
        };
        assert_eq!(invalid(id().ml_options(ml(1.0, 10))), "ml tolerance");
        // Zero ML iterations are legal, as for `solve::ml::fit`: the start is kept.
        assert!(id().ml_options(ml(1e-9, 0)).check().is_ok());
    }

    #[test]
    fn the_first_fault_is_the_error() {
        let id = Identifier::new(8.0, 49.0).min_coherence(2.0).tolerance(0.0);
        assert_eq!(invalid(id), "minimum coherence");
    }

    #[test]
    fn non_convergence_names_round_trip() {
        for v in [NonConvergence::Warn, NonConvergence::Fail] {
            assert_eq!(v.name().parse::<NonConvergence>().unwrap(), v);
        }
        assert!(matches!(
            "stop".parse::<NonConvergence>(),
            Err(Error::UnknownName { .. })
        ));
    }
}
