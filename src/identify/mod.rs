//! The façade: from records to an identification, through every stage in order.
//!
//! [`Identifier`] holds the settings as given (chained, infallible setters);
//! [`Identifier::check`] checks them once into [`Settings`]; the entry points
//! ([`Identifier::identify`], [`Identifier::identify_stream`],
//! [`Identifier::identify_stepped_sine`], [`Identifier::identify_batch`],
//! [`Identifier::identify_frf`]) check, then run records → spectra → frf → conditioning →
//! solve, and return an [`Identification`] that owns the coefficients and the diagnostics.
//!
//! | file | what lives there |
//! |---|---|
//! | `mod.rs` | [`Identifier`], its setters and [`Identifier::check`] |
//! | `settings.rs` | [`Settings`] (the checked settings), [`NonConvergence`], [`Screening`] |
//! | `pipeline.rs` | the entry points and the stages after the spectra |
//! | `spectra.rs` | an identification paused after its spectra, and a quick first fit on them |
//! | `screen.rs` | record screening and the force-gate check on the way to the spectra |
//! | `diagnostics.rs` | the flexibility `r²` and the warnings of a finished fit |
//! | `uncertainty/` | [`Uncertainty`]: sandwich, jackknife, bootstrap, Student's t; the [`Budget`] |
//! | `model_check.rs` | [`ModelCheck`]: the lack-of-fit test of every fit against the replicates' scatter |
//! | `calibration.rs` | [`Calibration`]: stated sensor gain uncertainties and their propagation |
//! | `derived.rs` | error bars of natural frequencies and damping ratios |
//! | `result.rs` | [`Identification`] and its accessors |
//! | `timings.rs` | [`Timings`]: wall time per stage |
//! | `baseline.rs` | [`Baseline`] and [`Identification::subtract_baseline`] |
//! | `serialize.rs` | the JSON form of an [`Identification`] (feature `serde`) |

mod baseline;
mod bias;
mod calibration;
mod derived;
mod diagnostics;
mod model_check;
mod periodic;
mod pipeline;
mod result;
mod screen;
#[cfg(feature = "serde")]
mod serialize;
mod settings;
mod spectra;
mod timings;
mod uncertainty;

pub use crate::solve::NonConvergence;
pub use baseline::Baseline;
pub use calibration::Calibration;
pub use model_check::{ModelCheck, Verdict};
pub use result::Identification;
pub use settings::{Screening, Settings};
pub(crate) use spectra::Spectra;
pub use timings::Timings;
pub use uncertainty::{Budget, MAX_BOOTSTRAP_DRAWS, Uncertainty};

use crate::conditioning::ConditionLimits;
use crate::element::ModelSpec;
use crate::error::Result;
use crate::frf::{Assignment, ChannelTransfers, Estimator, ForceNoise};
use crate::gate::FitGate;
use crate::solve::ml::MlOptions;
use crate::solve::{IvfOptions, Method};
use crate::spectra::{ForceGate, Segmentation, Window};

/// Settings of an identification. Build with [`Identifier::new`] and chained setters, then call
/// [`Identifier::identify`].
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let truth = seed_rig();
/// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&truth)?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let k = id.coefficients().stiffness()[(0, 0)];
/// assert!((k / 146.3e3 - 1.0).abs() < 1e-6);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Identifier {
    low_hz: f64,
    high_hz: f64,
    dofs: Option<usize>,
    estimator: Estimator,
    method: Method,
    assignment: Assignment,
    segmentation: Segmentation,
    window: Window,
    ivf: IvfOptions,
    ml: Option<MlOptions>,
    limits: ConditionLimits,
    non_convergence: NonConvergence,
    min_coherence: f64,
    uncertainty: Uncertainty,
    force_gate: Option<ForceGate>,
    screening: Screening,
    gate: FitGate,
    calibration: Calibration,
    transfers: ChannelTransfers,
    drop_periods: usize,
    force_noise: ForceNoise,
    model: ModelSpec,
}

impl Identifier {
    /// An identifier over the band `low_hz ..= high_hz` (Hz, edges inclusive, DC excluded), with
    /// every other setting at its default: paired sets, IVF, dominant-force assignment, whole
    /// records, rectangular window.
    pub fn new(low_hz: f64, high_hz: f64) -> Self {
        Self {
            low_hz,
            high_hz,
            dofs: None,
            estimator: Estimator::default(),
            method: Method::default(),
            assignment: Assignment::default(),
            segmentation: Segmentation::default(),
            window: Window::default(),
            ivf: IvfOptions::default(),
            ml: None,
            limits: ConditionLimits::default(),
            non_convergence: NonConvergence::default(),
            min_coherence: 0.0,
            uncertainty: Uncertainty::default(),
            force_gate: None,
            screening: Screening::default(),
            gate: FitGate::default(),
            calibration: Calibration::default(),
            transfers: ChannelTransfers::new(),
            drop_periods: 0,
            force_noise: ForceNoise::default(),
            model: ModelSpec::default(),
        }
    }

    /// The band (Hz). Valid: finite `0 ≤ low < high ≤ f_s/2`.
    pub fn band(mut self, low_hz: f64, high_hz: f64) -> Self {
        self.low_hz = low_hz;
        self.high_hz = high_hz;
        self
    }

    /// The number of degrees of freedom the records must have. Default: that of the first
    /// record.
    pub fn dofs(mut self, n: usize) -> Self {
        self.dofs = Some(n);
        self
    }

    /// The impedance estimator. Default [`Estimator::PairedSets`].
    pub fn estimator(mut self, estimator: Estimator) -> Self {
        self.estimator = estimator;
        self
    }

    /// The fitting method. Default [`Method::Ivf`].
    pub fn method(mut self, method: Method) -> Self {
        self.method = method;
        self
    }

    /// How records are assigned to excitations for paired sets. Default
    /// [`Assignment::DominantForce`].
    pub fn assignment(mut self, assignment: Assignment) -> Self {
        self.assignment = assignment;
        self
    }

    /// Segmentation for H1 (paired sets always use whole records). Default
    /// [`Segmentation::WholeRecord`].
    pub fn segmentation(mut self, segmentation: Segmentation) -> Self {
        self.segmentation = segmentation;
        self
    }

    /// The window. Default [`Window::Rectangular`].
    pub fn window(mut self, window: Window) -> Self {
        self.window = window;
        self
    }

    /// IVF tolerance on the block-wise relative change. Valid `(0, 1)`; default `1e-8`.
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.ivf.tolerance = tolerance;
        self
    }

    /// IVF iteration limit. Valid `≥ 1`; default `50`.
    pub fn max_iterations(mut self, max_iterations: usize) -> Self {
        self.ivf.max_iterations = max_iterations;
        self
    }

    /// Condition-number thresholds. Valid `1 ≤ warn ≤ refuse`; default `1e3` and `1e8`.
    pub fn condition_limits(mut self, limits: ConditionLimits) -> Self {
        self.limits = limits;
        self
    }

    /// What the force-side noise H1's records show is taken for ([`ForceNoise`]): the noise
    /// repeated periods show on the forces is their measurement noise and compensated for
    /// always; over Welch segments only with [`ForceNoise::Measurement`] (default
    /// [`ForceNoise::Auto`]: carried in the error bars).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::frf::ForceNoise;
    /// use bearing_ident::simulate::{AntiAlias, Simulator, add_noise, seed_rig};
    /// use bearing_ident::{Estimator, Identifier, Segmentation, Window};
    /// use rand::SeedableRng;
    /// let mut sim = Simulator::new(&seed_rig(), 500.0, 32_768, AntiAlias::default())?;
    /// let mut rng = rand::rngs::StdRng::seed_from_u64(3);
    /// let records: Vec<_> = (0..4)
    ///     .map(|r| add_noise(&sim.random_record(format!("r{r}"), 20.0, r)?, 0.05, &mut rng))
    ///     .collect::<Result<_, _>>()?;
    /// let id = Identifier::new(8.0, 49.0)
    ///     .estimator(Estimator::H1)
    ///     .segmentation(Segmentation::Welch { len: 2048 })
    ///     .window(Window::Hann);
    /// let auto = id.clone().identify(&records)?;
    /// assert!(!auto.noise_floor().unwrap().compensated());
    /// let told = id.force_noise(ForceNoise::Measurement).identify(&records)?;
    /// assert!(told.noise_floor().unwrap().compensated());
    /// // 5 % noise on a force white to 250 Hz: H1's mass 0.2 % heavier uncompensated.
    /// let m = |id: &bearing_ident::Identification| id.coefficients().mass()[(0, 0)];
    /// assert!(m(&auto) / m(&told) - 1.0 > 0.001);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn force_noise(mut self, force_noise: ForceNoise) -> Self {
        self.force_noise = force_noise;
        self
    }

    /// The element model fitted beside the constant coefficients ([`ModelSpec`]; default
    /// `kcm`, the constant `K`, `C`, `M` of the chosen method): a frequency-dependent family
    /// by name, or [`ModelSpec::Auto`], the smallest the model check accepts. The families are
    /// fitted by weighted least squares on the impedance ([`crate::element`]); when one other
    /// than `kcm` is chosen, [`Identification::coefficients`] are its constant part, with its
    /// standard deviations, model check and modes. Not with an exponential window, and only
    /// `kcm` with maximum likelihood.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::element::{Family, ModelSpec};
    /// use bearing_ident::{Identifier, simulate::{ImpactTest, seed_rig}};
    /// let records = ImpactTest { per_direction: 4, noise: 0.03, ..ImpactTest::seed_rig() }
    ///     .run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).model(ModelSpec::Auto).identify(&records)?;
    /// let model = id.model().expect("asked for");
    /// assert_eq!(model.family(), Family::Kcm);
    /// assert_eq!(model.selection()[0].family, Family::Kc); // tried first, refused
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn model(mut self, model: ModelSpec) -> Self {
        self.model = model;
        self
    }

    /// Drops the lines where the multiple coherence of any output is below `threshold` before
    /// fitting, and reports how many with [`Warning::LowCoherence`](crate::Warning::LowCoherence). Valid `[0, 1)`; default
    /// `0` (keep every line).
    pub fn min_coherence(mut self, threshold: f64) -> Self {
        self.min_coherence = threshold;
        self
    }

    /// How coefficient standard deviations are estimated. Default [`Uncertainty::Sandwich`].
    pub fn uncertainty(mut self, uncertainty: Uncertainty) -> Self {
        self.uncertainty = uncertainty;
        self
    }

    /// Gates every force channel ([`ForceGate`]): after an impact the force record holds only
    /// noise, which the gate keeps out of the spectra. The response is not gated.
    pub fn force_gate(mut self, gate: ForceGate) -> Self {
        self.force_gate = Some(gate);
        self
    }

    /// The channels' known transfer characteristics ([`ChannelTransfers`]: a delay such as a
    /// multiplexed acquisition's skew, an AC-coupling corner), divided out of every spectrum
    /// at the band lines before any average, so the fit sees the signals themselves. Default:
    /// none. Not applied to [`Identifier::identify_stepped_sine`] nor to a ready-made FRF.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::frf::{ChannelTransfer, ChannelTransfers};
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// use bearing_ident::{Channel, Identifier, Record};
    /// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// // The force channels sampled 3 samples late (whole-record DFT: a circular shift).
    /// let late: Vec<Record> = records.iter().map(|r| {
    ///     let shift = |x: &[f64]| [&x[x.len() - 3..], &x[..x.len() - 3]].concat();
    ///     Record::new(r.label(), r.sample_rate(), vec![shift(r.force(0)), shift(r.force(1))],
    ///         vec![r.displacement(0).to_vec(), r.displacement(1).to_vec()])
    /// }).collect::<Result<_, _>>()?;
    /// let tau = 3.0 / records[0].sample_rate();
    /// let transfers = (0..2).fold(ChannelTransfers::new(), |t, c| {
    ///     t.with(Channel::Force(c), ChannelTransfer::delay(tau))
    /// });
    /// let id = Identifier::new(8.0, 49.0).channel_transfers(transfers).identify(&late)?;
    /// assert!((id.coefficients().damping()[(0, 0)] / 131.98 - 1.0).abs() < 1e-3);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn channel_transfers(mut self, transfers: ChannelTransfers) -> Self {
        self.transfers = transfers;
        self
    }

    /// Periodic records ([`Segmentation::Periods`]): leaves the first `periods` periods of
    /// every record out (a start-up transient, [`Warning::StartTransient`](crate::Warning::StartTransient)).
    /// Default 0; ignored for other segmentations. With [`Segmentation::Periods`], the records
    /// are also checked against the period ([`PeriodCheck`](crate::screening::PeriodCheck):
    /// [`Warning::PeriodMismatch`](crate::Warning::PeriodMismatch), `StartTransient`).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::simulate::{AntiAlias, Simulator, multisine, seed_rig};
    /// use bearing_ident::{Estimator, Identifier, Segmentation};
    /// let mut sim = Simulator::new(&seed_rig(), 500.0, 3000, AntiAlias::default())?;
    /// // 6 periods of a 1 s multisine from rest on each axis in turn: the first is transient.
    /// let records = (0..2).map(|d| {
    ///     let f: Vec<Vec<f64>> = (0..2).map(|c| multisine(500, 8..=49, if c == d { 20.0 } else { 5.0 }, 3000, c as u64 + 1))
    ///         .collect::<Result<_, _>>()?;
    ///     sim.held_record(format!("ms{d}"), &f)
    /// }).collect::<Result<Vec<_>, _>>()?;
    /// let id = |drop| Identifier::new(8.0, 49.0).estimator(Estimator::H1)
    ///     .segmentation(Segmentation::Periods { len: 500 }).drop_periods(drop).identify(&records);
    /// assert!(id(0)?.warnings().iter().any(|w| w.kind() == "start_transient"));
    /// let steady = id(1)?;
    /// assert!(steady.warnings().iter().all(|w| w.kind() != "start_transient"));
    /// assert_eq!(steady.periods_dropped(), 1);
    /// assert!((steady.coefficients().stiffness()[(0, 0)] / 146.3e3 - 1.0).abs() < 1e-3);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn drop_periods(mut self, periods: usize) -> Self {
        self.drop_periods = periods;
        self
    }

    /// How records are screened for faults ([`Screening`]); default
    /// [`Screening::Warn`]`(`[`Checks::default`](crate::screening::Checks::default)`)`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::identify::{Identifier, Screening};
    /// use bearing_ident::screening::Checks;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let mut records = ImpactTest { per_direction: 3, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// // Overload the first record's force amplifier at 60 % of its peak.
    /// let r = &records[0];
    /// let limit = 0.6 * r.force(0).iter().cloned().fold(0.0, f64::max);
    /// let clipped: Vec<f64> = r.force(0).iter().map(|f| f.min(limit)).collect();
    /// records[0] = bearing_ident::Record::new(
    ///     "clipped", r.sample_rate(), vec![clipped, r.force(1).to_vec()],
    ///     vec![r.displacement(0).to_vec(), r.displacement(1).to_vec()])?;
    /// let id = Identifier::new(8.0, 49.0)
    ///     .screening(Screening::Reject(Checks::default()))
    ///     .identify(&records)?;
    /// assert!(id.warnings().iter().any(|w| w.to_string().contains("`clipped` rejected")));
    /// assert!((id.coefficients().stiffness()[(0, 0)] / 146.3e3 - 1.0).abs() < 1e-6);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn screening(mut self, screening: Screening) -> Self {
        self.screening = screening;
        self
    }

    /// The fit gate ([`FitGate`], default `r² ≥ 0.9`): the checks of the finished fit and of the
    /// settings against the records, each finding a [`Warning`](crate::Warning) (see [`crate::gate`]).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Identifier, Window, gate::FitGate};
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 2, noise: 0.05, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// // A window that falls to 1e-300 over the record leaves a few milliseconds of it.
    /// let id = Identifier::new(8.0, 49.0)
    ///     .window(Window::exponential_to(1e-300, 1.2))
    ///     .fit_gate(FitGate { min_r2: 0.95 })
    ///     .identify(&records)?;
    /// assert!(id.warnings().iter().any(|w| w.kind() == "window_too_short"));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn fit_gate(mut self, gate: FitGate) -> Self {
        self.gate = gate;
        self
    }

    /// What a non-converged IVF does. Default [`NonConvergence::Warn`].
    pub fn on_non_convergence(mut self, policy: NonConvergence) -> Self {
        self.non_convergence = policy;
        self
    }

    /// The sensors' stated relative gain uncertainties (1σ, as a calibration sheet gives
    /// them; each finite and ≥ 0, channels below the number of degrees of freedom). They enter
    /// [`Budget::calibration`] and the combined standard deviations. Default: none.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::identify::Calibration;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 4, noise: 0.05, ..ImpactTest::seed_rig() }
    ///     .run(&seed_rig())?;
    /// let plain = Identifier::new(8.0, 49.0).identify(&records)?;
    /// let stated = Identifier::new(8.0, 49.0)
    ///     .calibration(Calibration::default().force(0.01))
    ///     .identify(&records)?;
    /// let (a, b) = (plain.std_dev().unwrap().mass()[(0, 0)], stated.std_dev().unwrap().mass()[(0, 0)]);
    /// let m = plain.coefficients().mass()[(0, 0)];
    /// assert!((b * b - a * a - (0.01 * m).powi(2)).abs() < 1e-9 * b * b);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn calibration(mut self, calibration: Calibration) -> Self {
        self.calibration = calibration;
        self
    }

    /// Options of the maximum-likelihood refinement ([`Method::Ml`]): its tolerance (valid
    /// `(0, 1)`) and step limit (valid `≥ 1`). Default: derived from the IVF settings, the
    /// [`Identifier::tolerance`] capped at `1e-10` and the [`Identifier::max_iterations`]
    /// raised to at least 100 (with the IVF defaults, [`MlOptions::default`]).
    pub fn ml_options(mut self, options: MlOptions) -> Self {
        self.ml = Some(options);
        self
    }

    /// Checks every setting once and returns them checked ([`Settings`]); each entry point
    /// ([`Identifier::identify`] and the others) calls it first, so a bad setting is refused
    /// before any record is read.
    ///
    /// # Errors
    /// The first fault, in this order: [`Error::InvalidBand`](crate::Error::InvalidBand) for the band; then
    /// [`Error::InvalidSetting`](crate::Error::InvalidSetting) for an ML uncertainty other than none, sandwich or auto;
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) for fewer than 20 bootstrap replicates, a minimum coherence outside `[0, 1)`, an
    /// exponential window's decay not finite and `≥ 0`, the IVF tolerance and iteration limit,
    /// the fit gate ([`FitGate::check`]), the channel characteristics
    /// ([`ChannelTransfers::check`] against the [`Identifier::dofs`] if given), the screening checks ([`Checks::check`](crate::screening::Checks::check)) and the
    /// condition limits (`1 ≤ warn ≤ refuse`); [`Error::TooLarge`](crate::Error::TooLarge) for more than
    /// [`MAX_BOOTSTRAP_DRAWS`] bootstrap replicates; [`Error::InvalidParameter`](crate::Error::InvalidParameter) for ML
    /// options out of range.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Error, Identifier, Parameter};
    /// let e = Identifier::new(8.0, 49.0).min_coherence(1.5).check().unwrap_err();
    /// assert!(matches!(e, Error::InvalidParameter { name: Parameter::MinimumCoherence, .. }));
    /// ```
    pub fn check(&self) -> Result<Settings> {
        Settings::new(self)
    }
}
