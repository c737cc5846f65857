//! The result of an identification, [`Identification`]: the coefficients and the evidence
//! to defend them, behind accessors.

use faer::Mat;

use crate::conditioning::Conditioning;
use crate::error::{Result, Warning};
use crate::frf::{Band, Estimator, Frf};
use crate::model::{Coefficients, Mode};
use crate::per_frequency::PerFrequency;
use crate::solve::ml::MlReport;
use crate::solve::{Convergence, Fit, Iteration, Method};
use crate::spectra::{ForceGate, Segmentation, Window};

use super::timings::Untimed;
use super::{Budget, ModelCheck, Timings, Uncertainty};

/// The result of an identification: coefficients and the evidence to defend them.
#[derive(Debug, Clone, PartialEq)]
pub struct Identification {
    pub(super) ml: Option<MlReport>,
    /// The element model asked for (`None` for the default constant coefficients).
    pub(super) model: Option<crate::element::ElementModel>,
    /// The noise the periods or segments showed for H1.
    pub(super) noise_floor: Option<crate::frf::NoiseFloor>,
    pub(super) band: Band,
    pub(super) window: Window,
    pub(super) segmentation: Segmentation,
    pub(super) force_gate: Option<ForceGate>,
    pub(super) uncertainty: Uncertainty,
    pub(super) std_dev: Option<Coefficients>,
    pub(super) budget: Option<Budget>,
    pub(super) model_check: ModelCheck,
    /// `(σ(f_n), σ(ζ))` per mode, in the order of [`Identification::modes`].
    pub(super) modes_std: Option<Vec<(f64, f64)>>,
    pub(super) interval_factor: f64,
    pub(super) estimator: Estimator,
    pub(super) frf: Frf,
    pub(super) conditioning: Conditioning,
    pub(super) fit: Fit,
    pub(super) fit_r2: Mat<f64>,
    pub(super) excitations: Vec<usize>,
    pub(super) warnings: Vec<Warning>,
    pub(super) timings: Untimed,
    /// A bias the processing adds and the fit cannot see, predicted from the fitted model
    /// when above half a standard deviation.
    pub(super) predicted_bias: Option<crate::gate::PredictedBias>,
    /// Periods left out at the start of every record ([`Identifier::drop_periods`](super::Identifier::drop_periods)).
    pub(super) periods_dropped: usize,
    /// The period of periodic records (s).
    pub(super) period_s: Option<f64>,
}

impl Identification {
    /// The noise on the force and response channels that the records showed (repeated
    /// periods, or Welch segments fitted over the band) for H1, and whether H1 was compensated
    /// for the force channels' share ([`crate::frf::NoiseFloor`]); `None` for other
    /// estimators and segmentations, or when the records could not show it.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 2, noise: 0.02, ..ImpactTest::seed_rig() }
    ///     .run(&seed_rig())?;
    /// // Paired sets of impacts: no compensation.
    /// assert!(Identifier::new(8.0, 49.0).identify(&records)?.noise_floor().is_none());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn noise_floor(&self) -> Option<&crate::frf::NoiseFloor> {
        self.noise_floor.as_ref()
    }

    /// A bias of the coefficients predicted from the fitted model, when it exceeds half a
    /// standard deviation of some coefficient ([`PredictedBias`](crate::gate::PredictedBias),
    /// absolute, estimate minus truth, with its source): the Welch leakage of Hann segments
    /// ([`crate::gate::leaked_flexibility`]) or the truncation of impact records whose
    /// response has not decayed ([`crate::gate::truncated_flexibility`]). A warning names it
    /// too ([`Warning::LeakageBias`], [`Warning::NotDecayed`]). It is not removed from the
    /// coefficients: it enters the model component of the uncertainty budget in quadrature,
    /// so the combined standard deviations and intervals cover it, until the remedy the
    /// warning names removes it.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// // Records cut to their first 0.2 s: the response is still ringing at their end.
    /// let test = ImpactTest { per_direction: 3, noise: 0.02, ..ImpactTest::seed_rig() };
    /// let records = test.run(&seed_rig())?.iter().map(|r| r.trimmed(0..1340))
    ///     .collect::<Result<Vec<_>, _>>()?;
    /// let id = Identifier::new(5.0, 50.0).identify(&records)?;
    /// assert!(id.warnings().iter().any(|w| w.kind() == "not_decayed"));
    /// let bias = id.predicted_bias().expect("predicted");
    /// assert_eq!(bias.source.name(), "truncation");
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn predicted_bias(&self) -> Option<&crate::gate::PredictedBias> {
        self.predicted_bias.as_ref()
    }

    /// Periods left out at the start of every periodic record
    /// ([`Identifier::drop_periods`](super::Identifier::drop_periods)); 0 for other records.
    pub fn periods_dropped(&self) -> usize {
        self.periods_dropped
    }

    /// The window the spectra were taken with. Under [`Window::Exponential`] the
    /// coefficients, their standard deviations and the modes are already corrected back to
    /// the unwindowed system; the residual, history and `r²` are those of the windowed fit.
    pub fn window(&self) -> Window {
        self.window
    }

    /// How the records were cut into segments (paired sets always use whole records).
    pub fn segmentation(&self) -> Segmentation {
        match self.estimator {
            Estimator::PairedSets => Segmentation::WholeRecord,
            _ => self.segmentation,
        }
    }

    /// The force gate, if one was applied.
    pub fn force_gate(&self) -> Option<ForceGate> {
        self.force_gate
    }

    /// The identified `M`, `C`, `K` of the whole test system.
    pub fn coefficients(&self) -> &Coefficients {
        self.fit.coefficients()
    }

    /// Combined standard uncertainties of the coefficients: the random part by the chosen
    /// [`Uncertainty`] (sandwich by default: least squares and IVF only; jackknife: any
    /// method), the model part and the stated calibration in quadrature (see
    /// [`Identification::budget`]).
    pub fn std_dev(&self) -> Option<&Coefficients> {
        self.std_dev.as_ref()
    }

    /// The components of [`Identification::std_dev`]: random, model, calibration (`None`
    /// without error bars).
    pub fn budget(&self) -> Option<&Budget> {
        self.budget.as_ref()
    }

    /// The lack-of-fit test of the fit against the noise measured without the model.
    pub fn model_check(&self) -> &ModelCheck {
        &self.model_check
    }

    /// First-order standard deviations of the natural frequencies (Hz), one per mode of
    /// [`Identification::modes`], from the coefficients' covariance scaled to their random
    /// and model uncertainty (`None` without error bars).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 4, noise: 0.05, ..ImpactTest::seed_rig() }
    ///     .run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).identify(&records)?;
    /// let (f, s) = (id.modes()?, id.natural_frequencies_hz_std().unwrap());
    /// // The first mode, near 27.5 Hz, known to a fraction of a percent.
    /// assert!(s[0] > 0.0 && s[0] < 0.005 * f[0].natural_frequency_hz);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn natural_frequencies_hz_std(&self) -> Option<Vec<f64>> {
        Some(self.modes_std.as_ref()?.iter().map(|m| m.0).collect())
    }

    /// First-order standard deviations of the damping ratios, as
    /// [`Identification::natural_frequencies_hz_std`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 4, noise: 0.05, ..ImpactTest::seed_rig() }
    ///     .run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).identify(&records)?;
    /// let s = id.damping_ratios_std().unwrap();
    /// assert!(s[0] > 0.0 && s[0] < 0.1 * id.modes()?[0].damping_ratio);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn damping_ratios_std(&self) -> Option<Vec<f64>> {
        Some(self.modes_std.as_ref()?.iter().map(|m| m.1).collect())
    }

    /// How [`Identification::std_dev`] was estimated.
    pub fn uncertainty(&self) -> Uncertainty {
        self.uncertainty
    }

    /// Half-widths of the 95 % intervals, `q · σ`, with `q` = 1.96 for the sandwich and
    /// Student's `t(R − 1)` for the jackknife over `R` replicates.
    pub fn interval_95(&self) -> Option<Coefficients> {
        let s = self.std_dev.as_ref()?;
        let q = self.interval_factor;
        Coefficients::new(
            s.mass() * faer::Scale(q),
            s.damping() * faer::Scale(q),
            s.stiffness() * faer::Scale(q),
        )
        .ok()
    }

    /// Natural frequencies and damping ratios of the identified system: of its constant
    /// coefficients, or of the element model other than `kcm` when one was chosen
    /// ([`ElementModel::modes`](crate::element::ElementModel::modes): the internal states'
    /// state space).
    ///
    /// # Errors
    /// As [`Coefficients::modes`].
    pub fn modes(&self) -> Result<Vec<Mode>> {
        match self.model.as_ref().filter(|m| !m.is_kcm()) {
            Some(model) => model.modes(),
            None => self.coefficients().modes(),
        }
    }

    /// The element model: the family asked for with [`Identifier::model`](super::Identifier::model),
    /// or the one [`ModelSpec::Auto`](crate::element::ModelSpec::Auto) chose, with every
    /// family tried; `None` for the default constant coefficients. When its family is not
    /// `kcm`, [`Identification::coefficients`] are its constant part.
    pub fn model(&self) -> Option<&crate::element::ElementModel> {
        self.model.as_ref()
    }

    /// What the maximum-likelihood loop did (method ml only): iterations, the cost and its
    /// ratio to the expected value (a goodness-of-fit test), and whether it fell back to IVF.
    pub fn ml(&self) -> Option<&MlReport> {
        self.ml.as_ref()
    }

    /// The fitting method used.
    pub fn method(&self) -> Method {
        self.fit.method()
    }

    /// The impedance estimator used.
    pub fn estimator(&self) -> Estimator {
        self.estimator
    }

    /// The band asked for.
    pub fn band(&self) -> Band {
        self.band
    }

    /// Frequencies of the lines used (Hz).
    pub fn freqs_hz(&self) -> &[f64] {
        self.frf.freqs_hz()
    }

    /// Condition number per line used (see [`Frf::condition_numbers`]).
    pub fn condition_numbers(&self) -> &[f64] {
        self.frf.condition_numbers()
    }

    /// The conditioning verdict (worst, median, best).
    pub fn conditioning(&self) -> &Conditioning {
        &self.conditioning
    }

    /// Per-element goodness of fit between measured and fitted flexibility:
    /// $r^2_{ij} = 1 - \sum_k |G_{ij} - \hat G_{ij}|^2 / \sum_k |G_{ij} - \bar G_{ij}|^2$
    /// (1 is a perfect fit; small cross-coupled elements may score low or negative).
    pub fn fit_r2(&self) -> &Mat<f64> {
        &self.fit_r2
    }

    /// `‖A Θ − Ī‖_F`, the residual of the stacked flexibility identity.
    pub fn residual_norm(&self) -> f64 {
        self.fit.residual_norm()
    }

    /// How the fit ended.
    pub fn convergence(&self) -> Convergence {
        self.fit.convergence()
    }

    /// IVF iterations run (0 for direct and least squares).
    pub fn iterations(&self) -> usize {
        self.fit.convergence().iterations()
    }

    /// `true` unless an iterative fit stopped at its limit or diverged.
    pub fn converged(&self) -> bool {
        self.fit.convergence().is_converged()
    }

    /// The IVF iteration history.
    pub fn history(&self) -> &[Iteration] {
        self.fit.history()
    }

    /// The fit with all it carries (direct-fit `r²` among it).
    pub fn fit(&self) -> &Fit {
        &self.fit
    }

    /// The measured impedances and flexibilities.
    pub fn frf(&self) -> &Frf {
        &self.frf
    }

    /// The excitation (degree of freedom) each record was assigned to.
    pub fn excitations(&self) -> &[usize] {
        &self.excitations
    }

    /// The smallest multiple coherence over the lines used and the outputs (`None` when the
    /// spectra carried none): what [`Identifier::min_coherence`](crate::Identifier::min_coherence)
    /// compares with.
    pub fn min_coherence(&self) -> Option<f64> {
        (0..self.frf.line_count())
            .filter_map(|k| self.frf.multiple_coherence(k))
            .flatten()
            .copied()
            .reduce(f64::min)
    }

    /// Stiffness and damping line by line, `K(ω) = Re H + ω²M`, `C(ω) = Im H/ω`, with the
    /// fitted `M` (and the exponential window's exact correction), error bars from the FRF's
    /// variance when it has one; see [`PerFrequency`].
    ///
    /// # Errors
    /// As [`PerFrequency::new`] (not for a successful identification's own data).
    pub fn per_frequency(&self) -> Result<PerFrequency> {
        let decay = self.window.decay_per_s().unwrap_or(0.0);
        PerFrequency::new(&self.frf, self.coefficients().mass(), decay)
    }

    /// The covariance of the coefficients' combined uncertainty ([`Identification::std_dev`]),
    /// over the stacked `[M; C; K]` (`3n × n`) read column by column (index `j·3n + q` for
    /// row `q` of column `j`; `3n² × 3n²`): the fit's own covariance of each column rescaled
    /// to the random and model components (a diagonal one where the fit carries none),
    /// columns independent, plus the calibration's sources, which move every coefficient at
    /// once ([`Budget::calibration_directions`]). `None` without error bars.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 2, noise: 0.05, ..ImpactTest::seed_rig() }
    ///     .run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).identify(&records)?;
    /// let cov = id.covariance().unwrap();
    /// assert_eq!(cov.nrows(), 12);
    /// // Its diagonal is the combined variance: K_xx is row 4 of column 0.
    /// let s = id.std_dev().unwrap().stiffness()[(0, 0)];
    /// assert!((cov[(4, 4)].sqrt() / s - 1.0).abs() < 1e-9);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn covariance(&self) -> Option<Mat<f64>> {
        let budget = self.budget.as_ref()?;
        let columns = super::derived::scaled_covariance(
            self.fit.covariance(),
            &budget.random_and_model().ok()?,
        );
        let rows = columns.first()?.nrows();
        let p = rows * columns.len();
        let mut cov = Mat::zeros(p, p);
        for (j, block) in columns.iter().enumerate() {
            for a in 0..rows {
                for b in 0..rows {
                    cov[(j * rows + a, j * rows + b)] = block[(a, b)];
                }
            }
        }
        for d in budget.calibration_directions() {
            let v = |i: usize| d[(i % rows, i / rows)];
            for a in 0..p {
                for b in 0..p {
                    cov[(a, b)] += v(a) * v(b);
                }
            }
        }
        Some(cov)
    }

    /// The coefficients in dimensionless form under `conditions` ([`Dimensionless`](crate::rotor::Dimensionless)).
    ///
    /// # Errors
    /// As [`Dimensionless::new`](crate::rotor::Dimensionless::new).
    pub fn dimensionless(
        &self,
        conditions: &crate::rotor::Conditions,
    ) -> Result<crate::rotor::Dimensionless> {
        crate::rotor::Dimensionless::new(self.coefficients(), self.std_dev(), conditions)
    }

    /// The stability of a rigid rotor on the element under `conditions`
    /// ([`Stability`](crate::rotor::Stability)), with the standard deviations from
    /// [`Identification::covariance`] and the crossover of the element model where one is
    /// fitted.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::rotor::Conditions;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 2, noise: 0.05, ..ImpactTest::seed_rig() }
    ///     .run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).identify(&records)?;
    /// let s = id.stability(&Conditions::default().speed_rpm(3000.0).load_n(500.0));
    /// // The seed rig's element has no cross-coupling to drive a whirl.
    /// assert!(s.reason.is_some());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn stability(&self, conditions: &crate::rotor::Conditions) -> crate::rotor::Stability {
        crate::rotor::Stability::new(
            self.coefficients(),
            self.covariance().as_ref(),
            self.model.as_ref(),
            conditions,
        )
    }

    /// What the user should know.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The same result with `warnings` of its records' readers (a unit not converted) ahead of
    /// its own: the job reports what reading noticed with what the identification found.
    #[cfg(feature = "job")]
    pub(crate) fn with_read_warnings(mut self, warnings: Vec<Warning>) -> Self {
        self.warnings.splice(0..0, warnings);
        self
    }

    /// Wall time per stage of the run that produced this result ([`Timings`]; not part of
    /// the result's value, so not compared by `==` nor serialized).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// let t = Identifier::new(8.0, 49.0).identify(&records)?.timings();
    /// assert!(t.total >= t.spectra + t.frf + t.solve);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn timings(&self) -> Timings {
        self.timings.0
    }
}
