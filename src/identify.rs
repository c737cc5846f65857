//! The façade: from records to an identification, through every stage in order.
//!
//! [`Identifier`] holds the settings (chained, infallible setters); [`Identifier::identify`]
//! validates them and the records once, runs records → spectra → frf → conditioning → solve,
//! and returns an [`Identification`] that owns the coefficients and the diagnostics.

use faer::{Mat, c64};

use crate::conditioning::{ConditionLimits, Conditioning};
use crate::error::{Error, Result, Warning};
use crate::frf::{Assignment, Band, Estimator, Frf, FrfBuilder};
use crate::gate::{self, FitGate, ForceGateCheck};
use crate::model::{Coefficients, Mode};
use crate::per_frequency::PerFrequency;
use crate::records::Record;
use crate::screening::{self, Checks, Screener};
use crate::solve::ml::{MlOptions, MlReport};
use crate::solve::{self, Convergence, Fit, Iteration, IvfOptions, Method};
use crate::spectra::{ForceGate, Segmentation, Window};

/// What to do when an iterative fit does not converge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum NonConvergence {
    /// Return the last (or, after divergence, the best) iterate with a [`Warning`].
    #[default]
    Warn,
    /// Return [`Error::NotConverged`].
    Fail,
}

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
    /// Report every fault found as a [`Warning`]; keep the record.
    Warn(Checks),
    /// Report every fault and leave the faulty records out ([`Warning::Rejected`], with the
    /// reason). A paired set far from the others is left out whole.
    Reject(Checks),
}

impl Default for Screening {
    fn default() -> Self {
        Screening::Warn(Checks::default())
    }
}

/// How the standard deviations of the coefficients are estimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Uncertainty {
    /// No error bars.
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
        /// past which identification fails with [`Error::TooLarge`]).
        replicates: usize,
        /// Seed of the resampling.
        seed: u64,
    },
    /// The jackknife when there are at least 3 replicates, else the sandwich (no warning).
    /// The result reports the one used.
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

    /// Short name: `"none"`, `"sandwich"`, `"jackknife"`, `"bootstrap"` or `"auto"`.
    pub fn name(self) -> &'static str {
        match self {
            Uncertainty::None => "none",
            Uncertainty::Sandwich => "sandwich",
            Uncertainty::Jackknife => "jackknife",
            Uncertainty::Bootstrap { .. } => "bootstrap",
            Uncertainty::Auto => "auto",
        }
    }

    /// Whether the replicates' own spectra must be kept.
    fn resamples(self) -> bool {
        matches!(
            self,
            Uncertainty::Jackknife | Uncertainty::Bootstrap { .. } | Uncertainty::Auto
        )
    }
}

/// The two-sided 95 % quantile of Student's t with `dof` degrees of freedom (table to 30,
/// `1.96 + 2.4/dof` beyond, within 0.002 of the exact value; the normal 1.96 for `dof = 0`,
/// meaning "normal").
fn t975(dof: usize) -> f64 {
    const TABLE: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
        2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
        2.052, 2.048, 2.045, 2.042,
    ];
    match dof {
        0 => 1.96,
        1..=30 => TABLE[dof - 1],
        _ => 1.96 + 2.4 / dof as f64,
    }
}

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
    limits: ConditionLimits,
    non_convergence: NonConvergence,
    min_coherence: f64,
    uncertainty: Uncertainty,
    force_gate: Option<ForceGate>,
    screening: Screening,
    gate: FitGate,
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
            limits: ConditionLimits::default(),
            non_convergence: NonConvergence::default(),
            min_coherence: 0.0,
            uncertainty: Uncertainty::default(),
            force_gate: None,
            screening: Screening::default(),
            gate: FitGate::default(),
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

    /// Drops the lines where the multiple coherence of any output is below `threshold` before
    /// fitting, and reports how many with [`Warning::LowCoherence`]. Valid `[0, 1)`; default
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

    /// How records are screened for faults ([`Screening`]); default
    /// [`Screening::Warn`]`(`[`Checks::default`]`)`.
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
    /// settings against the records, each finding a [`Warning`] (see [`crate::gate`]).
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

    /// Runs the identification.
    ///
    /// # Errors
    /// Every error of the stages: record shapes ([`Error::DofMismatch`],
    /// [`Error::SampleRateMismatch`], [`Error::RecordLengthMismatch`], [`Error::NoRecords`]),
    /// the band ([`Error::InvalidBand`], [`Error::BandAboveNyquist`], [`Error::TooFewLines`]
    /// when the band holds fewer lines than the fit needs, with the line spacing),
    /// [`Error::SpectrumOverflow`] and [`Error::NonFiniteResult`] when levels overflow f64,
    /// [`Error::DeadChannel`] naming a record with every force (or displacement) channel flat
    /// when the run cannot go on without it (instead of the rank, singularity or line-count
    /// error it causes), the assignment, [`Error::RankDeficient`], [`Error::SingularFit`],
    /// [`Error::InvalidParameter`] for out-of-range settings, and [`Error::NotConverged`] under
    /// [`NonConvergence::Fail`].
    pub fn identify(&self, records: &[Record]) -> Result<Identification> {
        self.validate()?;
        let mut builder = self.builder();
        let pulses = self.pulse_warning(records);
        let Some((checks, reject)) = self.checks() else {
            builder.push_all(records)?;
            return self.finish(builder, pulses.into_iter().collect());
        };
        // Every record is at hand: decide all but the per-line test before the spectra.
        let (kept, mut warnings) = screen_batch(records, checks, reject);
        if kept.iter().all(|&k| k) {
            builder.push_all(records)?;
        } else {
            builder.push_all(&kept_records(records, &kept))?;
        }
        self.screen_sets(&mut builder, &checks, reject, &mut warnings)?;
        warnings.extend(pulses);
        self.finish(builder, warnings)
    }

    /// A check of the force gate against the pulses, when a gate is set on whole records.
    fn pulse_check(&self) -> Option<ForceGateCheck> {
        match (self.force_gate, self.segmentation) {
            (Some(g), Segmentation::WholeRecord) => Some(ForceGateCheck::new(g)),
            _ => None,
        }
    }

    /// Notes the force pulses of `record` for the force-gate check.
    fn observe(record: &Record, pulses: &mut Option<ForceGateCheck>) {
        if let Some(p) = pulses {
            let forces = (0..record.dofs()).map(|i| record.force(i));
            p.record(forces, 1.0 / record.sample_rate());
        }
    }

    /// [`Warning::ForceGateShort`] if the force gate closes on a pulse of `records`.
    fn pulse_warning(&self, records: &[Record]) -> Option<Warning> {
        let mut pulses = self.pulse_check();
        for r in records {
            Self::observe(r, &mut pulses);
        }
        pulses.and_then(|p| p.warning())
    }

    /// The screening checks and whether faulty records are left out; `None` when off.
    fn checks(&self) -> Option<(Checks, bool)> {
        match self.screening {
            Screening::Off => None,
            Screening::Warn(c) => Some((c, false)),
            Screening::Reject(c) => Some((c, true)),
        }
    }

    /// The per-line test of paired sets ([`screening::outlier_sets`]) on what `builder`
    /// holds; under `reject` the outlying sets' records are taken back out.
    fn screen_sets(
        &self,
        builder: &mut FrfBuilder,
        checks: &Checks,
        reject: bool,
        warnings: &mut Vec<Warning>,
    ) -> Result<()> {
        let sets = builder.set_impedances(&self.assignment)?;
        let mut out = Vec::new();
        for o in screening::outlier_sets(&sets.impedances, checks) {
            let members = &sets.records[o.set];
            let labels: Vec<String> = members
                .iter()
                .map(|&r| builder.label(r).to_owned())
                .collect();
            let warning = Warning::OutlierSet {
                records: labels.clone(),
                far_lines: o.far_lines,
                lines: o.lines,
            };
            if reject {
                let reason = screening::reason(&warning);
                out.extend(members.iter().copied());
                warnings.push(warning);
                warnings.extend(labels.into_iter().map(|record| Warning::Rejected {
                    record,
                    reason: reason.clone(),
                }));
            } else {
                warnings.push(warning);
            }
        }
        builder.remove(&out);
        Ok(())
    }

    /// [`Identifier::identify`] over records that arrive one at a time (read from files, say):
    /// each is reduced to its band-line spectra (paired sets) or folded into the cross-spectra
    /// (H1) and can be dropped at once, so memory does not grow with record length, nor, for
    /// H1, with the number of records.
    ///
    /// Screening ([`Screening`]) decides flat channels, clipping, double hits and duplicates of
    /// an earlier record on arrival; dead channels and level outliers (which need the
    /// siblings) and the per-line test of paired sets once all have arrived. Under
    /// [`Screening::Reject`] records found faulty late are taken back out: paired sets keep
    /// every record's band-line spectra anyway, and cross-spectral estimators then keep each
    /// record's own band-line cross-spectra too (`3n²` complex numbers per line and record),
    /// so the result is that of leaving the records out from the start.
    ///
    /// # Errors
    /// The first error of the iterator, then as [`Identifier::identify`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let test = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() };
    /// let records = test.run(&seed_rig())?;
    /// let streamed = Identifier::new(8.0, 49.0).identify_stream(records.clone().into_iter().map(Ok))?;
    /// let at_once = Identifier::new(8.0, 49.0).identify(&records)?;
    /// assert_eq!(streamed.coefficients(), at_once.coefficients());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn identify_stream(
        &self,
        records: impl IntoIterator<Item = Result<Record>>,
    ) -> Result<Identification> {
        self.validate()?;
        let mut builder = self.builder();
        let mut pulses = self.pulse_check();
        let Some((checks, reject)) = self.checks() else {
            for r in records {
                let r = r?;
                Self::observe(&r, &mut pulses);
                builder.push(&r)?;
            }
            return self.finish(
                builder,
                pulses.and_then(|p| p.warning()).into_iter().collect(),
            );
        };
        if reject {
            // Records found faulty only once all have arrived must come out again.
            builder = builder.keeping_partials();
        }
        let mut screener = Screener::new(checks);
        let (mut findings, mut pushed) = (Vec::new(), Vec::new());
        for r in records {
            let r = r?;
            Self::observe(&r, &mut pulses);
            let found = screener.push(&r);
            if reject && !found.is_empty() {
                pushed.push(None);
            } else {
                builder.push(&r)?;
                pushed.push(Some(builder.records() - 1));
            }
            findings.push(found);
        }
        let excluded: Vec<bool> = pushed.iter().map(Option::is_none).collect();
        let mut out = Vec::new();
        for (r, w) in screener.across(&excluded) {
            if let (true, Some(b)) = (reject, pushed[r]) {
                out.push(b);
            }
            findings[r].push(w);
        }
        builder.remove(&out);
        let mut warnings = reported(screener.summaries(), findings, reject);
        self.screen_sets(&mut builder, &checks, reject, &mut warnings)?;
        warnings.extend(pulses.and_then(|p| p.warning()));
        self.finish(builder, warnings)
    }

    /// Identifies a stepped-sine test ([`crate::stepped::stepped_sine`], steps grouped within
    /// `step_tolerance` Hz, records assigned by [`Identifier::assignment`]) with the record
    /// screening of [`Identifier::identify`] (per record and across siblings; no per-line
    /// test, each step being its own line), then as [`Identifier::identify_frf`].
    ///
    /// # Errors
    /// As [`crate::stepped::stepped_sine`] and [`Identifier::identify_frf`];
    /// [`Error::NoRecords`] if screening left none.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{AntiAlias, Simulator, seed_rig, sine};
    /// let mut sim = Simulator::new(&seed_rig(), 2000.0, 4000, AntiAlias::default())?;
    /// let mut records = Vec::new();
    /// for step in 0..8 {
    ///     let f = 10.0 + 5.0 * step as f64;
    ///     for dir in 0..2 {
    ///         let mut forces = vec![vec![0.0; 4000]; 2];
    ///         forces[dir] = sine(f, 50.0, 2000.0, 4000)?;
    ///         let r = sim.held_record(format!("{f}Hz-{dir}"), &forces)?;
    ///         records.push(r.trimmed(2000..4000)?);
    ///     }
    /// }
    /// let id = Identifier::new(8.0, 49.0).identify_stepped_sine(&records, 0.01)?;
    /// assert!(id.warnings().is_empty());
    /// assert!((id.coefficients().mass()[(0, 0)] / 4.7 - 1.0).abs() < 1e-4);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn identify_stepped_sine(
        &self,
        records: &[Record],
        step_tolerance: f64,
    ) -> Result<Identification> {
        self.validate()?;
        let (kept, warnings) = match self.checks() {
            None => (records.to_vec(), Vec::new()),
            Some((checks, reject)) => {
                let (kept, warnings) = screen_batch(records, checks, reject);
                (kept_records(records, &kept), warnings)
            }
        };
        if kept.is_empty() {
            return Err(Error::NoRecords);
        }
        let frf = crate::stepped::stepped_sine(&kept, &self.assignment, self.dofs, step_tolerance)?;
        let mut id = self.identify_frf(frf)?;
        id.warnings.splice(0..0, warnings);
        Ok(id)
    }

    /// Identifies many test conditions (operating points) with the same settings, one result
    /// per record set, in order. With the `rayon` feature the sets run in parallel.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let test = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() };
    /// let sets = vec![test.run(&seed_rig())?, test.run(&seed_rig())?];
    /// let results = Identifier::new(8.0, 49.0).identify_batch(&sets);
    /// assert_eq!(results.len(), 2);
    /// assert!(results.iter().all(|r| r.is_ok()));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn identify_batch(&self, sets: &[Vec<Record>]) -> Vec<Result<Identification>> {
        #[cfg(feature = "rayon")]
        {
            use rayon::prelude::*;
            sets.par_iter().map(|s| self.identify(s)).collect()
        }
        #[cfg(not(feature = "rayon"))]
        {
            sets.iter().map(|s| self.identify(s)).collect()
        }
    }

    fn validate(&self) -> Result<()> {
        Band::new(self.low_hz, self.high_hz)?;
        if self.method == Method::Ml
            && matches!(
                self.uncertainty,
                Uncertainty::Jackknife | Uncertainty::Bootstrap { .. }
            )
        {
            return Err(Error::InvalidParameter {
                name: "uncertainty with method ml",
                value: f64::NAN,
                expected: "none, sandwich or auto: ml's covariance is the inverse Fisher information",
            });
        }
        if let Uncertainty::Bootstrap { replicates, .. } = self.uncertainty {
            if replicates < 20 {
                return Err(Error::InvalidParameter {
                    name: "bootstrap replicates",
                    value: replicates as f64,
                    expected: "at least 20",
                });
            }
        }
        if !(0.0..1.0).contains(&self.min_coherence) {
            return Err(Error::InvalidParameter {
                name: "minimum coherence",
                value: self.min_coherence,
                expected: "0 ≤ threshold < 1",
            });
        }
        if let Some(a) = self.window.decay_per_s() {
            if !(a.is_finite() && a >= 0.0) {
                return Err(Error::InvalidParameter {
                    name: "exponential window decay",
                    value: a,
                    expected: "finite and ≥ 0 (1/s)",
                });
            }
        }
        self.ivf.validate()?;
        self.gate.check()?;
        if let Screening::Warn(c) | Screening::Reject(c) = self.screening {
            c.validate()?;
        }
        if !(self.limits.warn >= 1.0 && self.limits.refuse >= self.limits.warn) {
            return Err(Error::InvalidParameter {
                name: "condition limits",
                value: self.limits.warn,
                expected: "1 ≤ warn ≤ refuse",
            });
        }
        Ok(())
    }

    fn builder(&self) -> FrfBuilder {
        let band = Band::new(self.low_hz, self.high_hz).expect("validated");
        let mut builder = FrfBuilder::new(self.estimator, band, self.segmentation, self.window);
        if self.uncertainty.resamples() || self.method == Method::Ml {
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

    fn finish(&self, builder: FrfBuilder, screened: Vec<Warning>) -> Result<Identification> {
        if builder.records() == 0 {
            return Err(Error::NoRecords);
        }
        let outcome = builder.finish(&self.assignment).and_then(|frf| {
            let excitations = match self.estimator {
                Estimator::PairedSets => builder.excitations(&self.assignment)?,
                _ => builder.excitations(&Assignment::DominantForce)?,
            };
            self.conclude(frf, Some(&builder), excitations, screened)
        });
        // A record without force or without response shows up later as missing rank or a
        // singular fit: name the record instead. (A band with too few lines stays `bad_band`.)
        match outcome {
            Err(
                Error::RankDeficient { .. } | Error::Singular { .. } | Error::SingularFit { .. },
            ) => Err(builder
                .dead_channel()
                .unwrap_or_else(|| outcome.expect_err("matched"))),
            outcome => outcome,
        }
    }

    /// Fits an [`Frf`] measured some other way — stepped sine
    /// ([`crate::stepped::stepped_sine`]), or flexibilities from another tool
    /// ([`Frf::from_flexibility`]) — with every check and diagnostic of
    /// [`Identifier::identify`]. Lines outside the band are left out. Resampling uncertainties
    /// need the records, so the jackknife and bootstrap fall back to the sandwich here
    /// (silently under [`Uncertainty::Auto`], else with [`Warning::FewReplicates`]).
    ///
    /// # Errors
    /// As [`Identifier::identify`], after the record stages.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Frf, Identifier, simulate::seed_rig};
    /// let truth = seed_rig();
    /// let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
    /// let g: Vec<_> = freqs.iter().map(|&f| truth.flexibility_at(f)).collect::<Result<_, _>>()?;
    /// let id = Identifier::new(8.0, 49.0).identify_frf(Frf::from_flexibility(freqs, &g)?)?;
    /// assert!((id.coefficients().damping()[(0, 0)] / 131.98 - 1.0).abs() < 1e-8);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn identify_frf(&self, frf: Frf) -> Result<Identification> {
        self.validate()?;
        let band = Band::new(self.low_hz, self.high_hz)?;
        let tolerance = 1e-9 * band.high_hz();
        let inside = |f: f64| f >= band.low_hz() - tolerance && f <= band.high_hz() + tolerance;
        let frf = frf.retain_lines(|k| inside(frf.freqs_hz()[k]));
        self.conclude(frf, None, Vec::new(), Vec::new())
    }

    /// The stages after the spectra: coherence selection, conditioning, fit, correction,
    /// uncertainty. `builder` (with its replicates) is there unless the FRF came ready-made.
    fn conclude(
        &self,
        mut frf: Frf,
        builder: Option<&FrfBuilder>,
        excitations: Vec<usize>,
        mut warnings: Vec<Warning>,
    ) -> Result<Identification> {
        let band = Band::new(self.low_hz, self.high_hz)?;
        let mut low_coherence = 0;
        if self.min_coherence > 0.0 {
            let keep = |k: usize| {
                frf.multiple_coherence(k)
                    .is_none_or(|c| c.iter().all(|&g| g >= self.min_coherence))
            };
            low_coherence = (0..frf.lines()).filter(|&k| !keep(k)).count();
            if low_coherence > 0 {
                frf = frf.retain_lines(keep);
            }
        }
        // Too few lines in the band is the band's fault whether or not the lines are usable.
        let band_lines = frf.lines() + frf.dropped_hz().len();
        let required = solve::required_lines(frf.dofs());
        if band_lines < required {
            return Err(Error::TooFewLines {
                lines: band_lines,
                required,
                resolution_hz: frf.line_spacing_hz(),
            });
        }
        let conditioning = Conditioning::assess(&frf, self.limits)?;
        let (fit, ml) = match self.method {
            Method::Ml => {
                let data = builder.ok_or(Error::MlNeedsRepeats)?.ml_data(&frf)?;
                let start = solve::fit(&frf, Method::Ivf, &self.ivf)?;
                let options = MlOptions {
                    tolerance: self.ivf.tolerance.min(1e-10),
                    max_iterations: self.ivf.max_iterations.max(100),
                };
                let refined = solve::ml::fit(&data, start.coefficients(), &options)?;
                let fit = match (&refined.report.fell_back, refined.covariance) {
                    (None, Some(cov)) => {
                        let convergence = if refined.report.converged {
                            Convergence::Converged {
                                iterations: refined.report.iterations,
                            }
                        } else {
                            Convergence::IterationLimit {
                                iterations: refined.report.iterations,
                                change: f64::NAN,
                            }
                        };
                        Fit::refined_by_ml(&start, refined.coefficients, cov, convergence)?
                    }
                    (reason, _) => {
                        warnings.push(Warning::MlFellBack {
                            reason: reason.clone().unwrap_or_default(),
                        });
                        start
                    }
                };
                (fit, Some(refined.report))
            }
            method => (solve::fit(&frf, method, &self.ivf)?, None),
        };

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
        match fit.convergence() {
            Convergence::IterationLimit { iterations, change } => {
                if self.non_convergence == NonConvergence::Fail {
                    return Err(Error::NotConverged {
                        method: self.method.name(),
                        iterations,
                        change,
                    });
                }
                warnings.push(Warning::NotConverged { iterations, change });
            }
            Convergence::Diverged {
                iterations,
                fallback_iteration,
            } => {
                if self.non_convergence == NonConvergence::Fail {
                    let change = fit.history().last().map_or(f64::NAN, Iteration::change);
                    return Err(Error::NotConverged {
                        method: self.method.name(),
                        iterations,
                        change,
                    });
                }
                warnings.push(Warning::Diverged {
                    iterations,
                    fallback_iteration,
                });
            }
            _ => {}
        }
        // r² compares like with like: measured and fitted flexibility of the windowed data.
        let fit_r2 = flexibility_r2(&frf, fit.coefficients());
        let fit = self.corrected(fit)?;
        warnings.extend(self.gate_warnings(&frf, fit_r2.as_ref(), fit.coefficients(), builder));
        let replicates = match builder {
            Some(b) if self.uncertainty.resamples() => b.replicates(&self.assignment)?,
            _ => 0,
        };
        let uncertainty = match self.uncertainty {
            Uncertainty::Auto if self.method == Method::Ml => Uncertainty::Sandwich,
            Uncertainty::Auto if replicates >= 3 => Uncertainty::Jackknife,
            Uncertainty::Auto => Uncertainty::Sandwich,
            Uncertainty::Jackknife | Uncertainty::Bootstrap { .. } if replicates < 3 => {
                warnings.push(Warning::FewReplicates { replicates });
                Uncertainty::Sandwich
            }
            chosen => chosen,
        };
        let (std_dev, interval_factor) = match (uncertainty, builder) {
            (Uncertainty::Jackknife, Some(b)) => {
                let (std, distinct) = self.jackknife(b, &frf, replicates)?;
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
            (
                Uncertainty::Bootstrap {
                    replicates: draws,
                    seed,
                },
                Some(b),
            ) => {
                let std = self.bootstrap(b, &frf, replicates, draws, seed)?;
                warnings.extend(gate::zero_spread(&std, fit.coefficients()));
                (Some(std), t975(replicates - 1))
            }
            (Uncertainty::None, _) => (None, 0.0),
            _ => (fit.std_dev().cloned(), t975(0)),
        };
        Ok(Identification {
            ml,
            band,
            window: self.window,
            segmentation: if builder.is_some() {
                self.segmentation
            } else {
                Segmentation::WholeRecord
            },
            force_gate: self.force_gate.filter(|_| builder.is_some()),
            uncertainty,
            std_dev,
            interval_factor,
            estimator: self.estimator,
            frf,
            conditioning,
            fit,
            fit_r2,
            excitations,
            warnings,
        })
    }
}

impl Identifier {
    /// The fit mapped back through an exponential window's exact correction, if any.
    fn corrected(&self, fit: Fit) -> Result<Fit> {
        match self.window.decay_per_s() {
            Some(a) if a > 0.0 => fit.corrected_for_window(a),
            _ => Ok(fit),
        }
    }

    /// Jackknife standard deviations over `replicates` leave-one-out refits, each on the same
    /// lines as `frf` (the full data's, after any coherence selection), and the number of
    /// distinct refits ([`gate::distinct_fits`]).
    fn jackknife(
        &self,
        builder: &FrfBuilder,
        frf: &Frf,
        replicates: usize,
    ) -> Result<(Coefficients, usize)> {
        let mut weights = vec![1.0; replicates];
        let mut thetas = Vec::with_capacity(replicates);
        for r in 0..replicates {
            weights[r] = 0.0;
            thetas.push(self.refit(builder, frf, &weights)?);
            weights[r] = 1.0;
        }
        let r = replicates as f64;
        Ok((spread(&thetas, r - 1.0)?, gate::distinct_fits(&thetas)))
    }

    /// The fit gate's findings on a fit of `frf` (window-corrected `model`, `r2` of the
    /// windowed data); the resolution check only for spectra made here (`builder`).
    fn gate_warnings(
        &self,
        frf: &Frf,
        r2: faer::MatRef<'_, f64>,
        model: &Coefficients,
        builder: Option<&FrfBuilder>,
    ) -> Vec<Warning> {
        let band = Band::new(self.low_hz, self.high_hz).expect("validated");
        let mut out = self.gate.poor_fit(frf, r2);
        out.extend(gate::physics(model));
        out.extend(gate::window(self.window, band));
        if builder.is_some() {
            if let Some(spacing) = line_spacing(frf.freqs_hz()) {
                out.extend(gate::resolution(self.segmentation, spacing, band, model));
            }
        }
        out.extend(gate::few_lines(frf.lines(), frf.dofs()));
        out
    }

    /// Bootstrap standard deviations over `draws` refits, each on `replicates` replicates
    /// drawn with replacement (seeded). A draw that cannot be fitted (it may, rarely, miss a
    /// direction altogether) is redrawn, up to `draws` times in all.
    fn bootstrap(
        &self,
        builder: &FrfBuilder,
        frf: &Frf,
        replicates: usize,
        draws: usize,
        seed: u64,
    ) -> Result<Coefficients> {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        if draws > MAX_BOOTSTRAP_DRAWS {
            return Err(Error::TooLarge {
                what: "bootstrap draws",
                value: draws as f64,
                limit: MAX_BOOTSTRAP_DRAWS as f64,
            });
        }
        let mut weights = vec![0.0; replicates];
        let mut thetas = Vec::with_capacity(draws);
        let mut failures = 0;
        while thetas.len() < draws {
            weights.fill(0.0);
            for _ in 0..replicates {
                weights[rng.random_range(0..replicates)] += 1.0;
            }
            match self.refit(builder, frf, &weights) {
                Ok(theta) => thetas.push(theta),
                Err(e) if failures >= draws => return Err(e),
                Err(_) => failures += 1,
            }
        }
        let r = replicates as f64;
        spread(&thetas, r / (r - 1.0))
    }

    /// The corrected, stacked coefficients refitted with the replicates weighted by
    /// `weights`, on the same lines as `frf` (the full data's, after any coherence selection).
    fn refit(&self, builder: &FrfBuilder, frf: &Frf, weights: &[f64]) -> Result<Mat<f64>> {
        let used = frf.freqs_hz();
        let all = builder.finish_weighted(&self.assignment, weights)?;
        let same_lines = all.retain_lines(|k| {
            let f = all.freqs_hz()[k];
            used.binary_search_by(|u| u.total_cmp(&f)).is_ok()
        });
        let fit = self.corrected(solve::fit(&same_lines, self.method, &self.ivf)?)?;
        Ok(fit.coefficients().stacked())
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

/// Screens records that are all at hand: which to keep (all unless `reject`) and the warnings,
/// in record order (the per-line test of paired sets is separate, see
/// [`screening::outlier_sets`]).
fn screen_batch(records: &[Record], checks: Checks, reject: bool) -> (Vec<bool>, Vec<Warning>) {
    let mut screener = Screener::new(checks);
    let mut findings: Vec<Vec<Warning>> = records.iter().map(|r| screener.push(r)).collect();
    let excluded: Vec<bool> = findings.iter().map(|f| reject && !f.is_empty()).collect();
    for (r, w) in screener.across(&excluded) {
        findings[r].push(w);
    }
    let kept = findings.iter().map(|f| !reject || f.is_empty()).collect();
    (kept, reported(screener.summaries(), findings, reject))
}

/// The records marked in `kept`.
fn kept_records(records: &[Record], kept: &[bool]) -> Vec<Record> {
    records
        .iter()
        .zip(kept)
        .filter(|(_, k)| **k)
        .map(|(r, _)| r.clone())
        .collect()
}

/// The screening's warnings in record order, each faulty record's findings followed, under
/// `reject`, by its [`Warning::Rejected`].
fn reported(
    summaries: &[screening::Summary],
    findings: Vec<Vec<Warning>>,
    reject: bool,
) -> Vec<Warning> {
    let mut warnings = Vec::new();
    for (summary, found) in summaries.iter().zip(findings) {
        if found.is_empty() {
            continue;
        }
        let reason: Vec<String> = found.iter().map(screening::reason).collect();
        warnings.extend(found);
        if reject {
            warnings.push(Warning::Rejected {
                record: summary.label().to_owned(),
                reason: reason.join("; "),
            });
        }
    }
    warnings
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

/// Per-element coefficient of determination between measured and fitted flexibility,
/// $r^2_{ij} = 1 - \sum_k |G_{ij,k} - \hat G_{ij,k}|^2 / \sum_k |G_{ij,k} - \bar G_{ij}|^2$.
fn flexibility_r2(frf: &Frf, model: &Coefficients) -> Mat<f64> {
    let n = frf.dofs();
    let mut res = Mat::<f64>::zeros(n, n);
    let mut tot = Mat::<f64>::zeros(n, n);
    let mut mean = Mat::<c64>::zeros(n, n);
    for k in 0..frf.lines() {
        mean += frf.flexibility(k);
    }
    let lines = frf.lines() as f64;
    for (k, &f) in frf.freqs_hz().iter().enumerate() {
        let measured = frf.flexibility(k);
        let fitted = model.flexibility_at(f);
        for j in 0..n {
            for i in 0..n {
                let g = measured[(i, j)];
                tot[(i, j)] += (g - mean[(i, j)] / lines).norm_sqr();
                res[(i, j)] += match &fitted {
                    Ok(m) => (g - m[(i, j)]).norm_sqr(),
                    Err(_) => f64::INFINITY,
                };
            }
        }
    }
    Mat::from_fn(n, n, |i, j| 1.0 - res[(i, j)] / tot[(i, j)])
}

/// The result of an identification: coefficients and the evidence to defend them.
#[derive(Debug, Clone, PartialEq)]
pub struct Identification {
    ml: Option<MlReport>,
    band: Band,
    window: Window,
    segmentation: Segmentation,
    force_gate: Option<ForceGate>,
    uncertainty: Uncertainty,
    std_dev: Option<Coefficients>,
    interval_factor: f64,
    estimator: Estimator,
    frf: Frf,
    conditioning: Conditioning,
    fit: Fit,
    fit_r2: Mat<f64>,
    excitations: Vec<usize>,
    warnings: Vec<Warning>,
}

impl Identification {
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

    /// Standard deviations of the coefficients by the chosen [`Uncertainty`] (sandwich by
    /// default: least squares and IVF only; jackknife: any method).
    pub fn std_dev(&self) -> Option<&Coefficients> {
        self.std_dev.as_ref()
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

    /// Natural frequencies and damping ratios of the identified system.
    ///
    /// # Errors
    /// As [`Coefficients::modes`].
    pub fn modes(&self) -> Result<Vec<Mode>> {
        self.coefficients().modes()
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
    /// spectra carried none).
    pub fn coherence_min(&self) -> Option<f64> {
        (0..self.frf.lines())
            .filter_map(|k| self.frf.multiple_coherence(k))
            .flatten()
            .copied()
            .reduce(f64::min)
    }

    /// The bearing's own coefficients: this (lubricated) system minus a dry-structure
    /// `baseline` identified the same way, `K_b = K_s − K_h`, `C_b = C_s − C_h`,
    /// `M_b = M_s − M_h`; standard deviations add in quadrature (independent tests), `None`
    /// unless both carry them.
    ///
    /// `baseline` is an [`Identification`] (`&dry`) or a [`Baseline`] read back from a saved
    /// result.
    ///
    /// # Errors
    /// [`Error::BaselineMismatch`] if the two differ in degrees of freedom (the baseline's
    /// standard deviations included), band, lines used, estimator or window (an exponential
    /// window must have the same decay); [`Error::NonFiniteCoefficient`] if a difference
    /// overflows.
    pub fn subtract_baseline(
        &self,
        baseline: impl Into<Baseline>,
    ) -> Result<(Coefficients, Option<Coefficients>)> {
        let baseline: Baseline = baseline.into();
        let mismatch = |what| Err(Error::BaselineMismatch { what });
        let std_dofs = baseline.std_dev.as_ref().map(Coefficients::dofs);
        if self.coefficients().dofs() != baseline.coefficients.dofs()
            || std_dofs.is_some_and(|n| n != baseline.coefficients.dofs())
        {
            return mismatch("degrees of freedom");
        }
        if self.band != baseline.band {
            return mismatch("band");
        }
        let same_lines = self.freqs_hz().len() == baseline.freqs_hz.len()
            && self
                .freqs_hz()
                .iter()
                .zip(&baseline.freqs_hz)
                .all(|(a, b)| (a - b).abs() <= 1e-9 * a.abs().max(1.0));
        if !same_lines {
            return mismatch("frequency lines");
        }
        if self.estimator != baseline.estimator {
            return mismatch("estimator");
        }
        let same_window = match (self.window.decay_per_s(), baseline.window.decay_per_s()) {
            (Some(a), Some(b)) => (a - b).abs() <= 1e-9 * a.abs().max(1e-12),
            _ => self.window == baseline.window,
        };
        if !same_window {
            return mismatch("window");
        }
        let coefficients = self.coefficients().subtract(&baseline.coefficients)?;
        let std = match (self.std_dev(), baseline.std_dev.as_ref()) {
            (Some(a), Some(b)) => {
                let add = |x: faer::MatRef<'_, f64>, y: faer::MatRef<'_, f64>| {
                    faer::Mat::from_fn(x.nrows(), x.ncols(), |i, j| x[(i, j)].hypot(y[(i, j)]))
                };
                Some(Coefficients::new(
                    add(a.mass(), b.mass()),
                    add(a.damping(), b.damping()),
                    add(a.stiffness(), b.stiffness()),
                )?)
            }
            _ => None,
        };
        Ok((coefficients, std))
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

    /// What the user should know.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }
}

/// What a baseline subtraction needs of a dry-structure identification: its coefficients,
/// standard deviations and the processing that produced them (to check they match). Made
/// from an [`Identification`] (`From`) or, for a result saved earlier, with
/// [`Baseline::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct Baseline {
    coefficients: Coefficients,
    std_dev: Option<Coefficients>,
    band: Band,
    freqs_hz: Vec<f64>,
    estimator: Estimator,
    window: Window,
}

impl Baseline {
    /// A baseline from its parts (read back from a saved result, say).
    pub fn new(
        coefficients: Coefficients,
        std_dev: Option<Coefficients>,
        band: Band,
        freqs_hz: Vec<f64>,
        estimator: Estimator,
        window: Window,
    ) -> Self {
        Self {
            coefficients,
            std_dev,
            band,
            freqs_hz,
            estimator,
            window,
        }
    }

    /// The dry structure's coefficients.
    pub fn coefficients(&self) -> &Coefficients {
        &self.coefficients
    }
}

impl From<&Identification> for Baseline {
    fn from(id: &Identification) -> Self {
        Baseline::new(
            id.coefficients().clone(),
            id.std_dev().cloned(),
            id.band,
            id.freqs_hz().to_vec(),
            id.estimator,
            id.window,
        )
    }
}

/// Serializes as one flat object, in SI units and Hz:
/// `method`, `estimator`, `window`, `window_decay_per_s` (the exponential window's `a`, null
/// otherwise), `segmentation` (`whole`, `welch`, `periods`), `segment_len`, `force_gate_s`
/// (the gate's open time, null without), `unexcited_lines` (periodic excitation), `n`, `band_hz`, `band_used_hz`, `n_freq`, `freqs_hz`, `M`, `C`, `K`,
/// `M_std`, `C_std`, `K_std` (null when not available), `uncertainty`, `M_ci95`, `C_ci95`,
/// `K_ci95` (half-widths of the 95 % intervals), `iterations`, `converged`,
/// `convergence`, `residual_norm`, `condition_number` (`min`, `median`, `max`),
/// `condition_numbers` (per line), `fit` (per-element flexibility `r²`),
/// `natural_frequencies_hz`, `damping_ratios`, `averages`, `coherence_min`, `warnings` (sentences), `warning_kinds` (their
/// [`Warning::kind`] names, in the same order) and `history`
/// (IVF iterations).
#[cfg(feature = "serde")]
impl serde::Serialize for Identification {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use crate::model::rows;
        use serde::ser::SerializeMap;
        let c = self.coefficients();
        let freqs = self.freqs_hz();
        let modes = self.modes().unwrap_or_default();
        let std = self.std_dev();
        let ci = self.interval_95();
        let cond = &self.conditioning;
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("method", self.method().name())?;
        m.serialize_entry("estimator", self.estimator.name())?;
        m.serialize_entry("window", self.window.name())?;
        m.serialize_entry("window_decay_per_s", &self.window.decay_per_s())?;
        let (segments, segment_len) = match self.segmentation() {
            Segmentation::Welch { len } => ("welch", Some(len)),
            Segmentation::Periods { len } => ("periods", Some(len)),
            _ => ("whole", None),
        };
        m.serialize_entry("segmentation", segments)?;
        m.serialize_entry("segment_len", &segment_len)?;
        m.serialize_entry("force_gate_s", &self.force_gate.map(|g| g.open_s()))?;
        m.serialize_entry("unexcited_lines", &self.frf.unexcited_hz().len())?;
        m.serialize_entry("n", &c.dofs())?;
        m.serialize_entry("band_hz", &[self.band.low_hz(), self.band.high_hz()])?;
        m.serialize_entry("band_used_hz", &[freqs[0], freqs[freqs.len() - 1]])?;
        m.serialize_entry("n_freq", &freqs.len())?;
        m.serialize_entry("freqs_hz", freqs)?;
        m.serialize_entry("M", &rows(c.mass()))?;
        m.serialize_entry("C", &rows(c.damping()))?;
        m.serialize_entry("K", &rows(c.stiffness()))?;
        m.serialize_entry("M_std", &std.map(|s| rows(s.mass())))?;
        m.serialize_entry("C_std", &std.map(|s| rows(s.damping())))?;
        m.serialize_entry("K_std", &std.map(|s| rows(s.stiffness())))?;
        let uncertainty = match (self.uncertainty, self.method()) {
            (Uncertainty::Sandwich, Method::Ml) => "fisher",
            (u, _) => u.name(),
        };
        m.serialize_entry("uncertainty", uncertainty)?;
        m.serialize_entry("ml", &self.ml)?;
        m.serialize_entry("M_ci95", &ci.as_ref().map(|s| rows(s.mass())))?;
        m.serialize_entry("C_ci95", &ci.as_ref().map(|s| rows(s.damping())))?;
        m.serialize_entry("K_ci95", &ci.as_ref().map(|s| rows(s.stiffness())))?;
        m.serialize_entry("iterations", &self.iterations())?;
        m.serialize_entry("converged", &self.converged())?;
        m.serialize_entry("convergence", self.convergence().name())?;
        m.serialize_entry("residual_norm", &self.residual_norm())?;
        let summary: std::collections::BTreeMap<&str, f64> = [
            ("min", cond.best()),
            ("median", cond.median()),
            ("max", cond.worst()),
        ]
        .into();
        m.serialize_entry("condition_number", &summary)?;
        m.serialize_entry("condition_numbers", self.condition_numbers())?;
        m.serialize_entry("fit", &rows(self.fit_r2.as_ref()))?;
        let fns: Vec<f64> = modes.iter().map(|m| m.natural_frequency_hz).collect();
        let zetas: Vec<f64> = modes.iter().map(|m| m.damping_ratio).collect();
        m.serialize_entry("natural_frequencies_hz", &fns)?;
        m.serialize_entry("damping_ratios", &zetas)?;
        m.serialize_entry("averages", &self.frf.averages())?;
        m.serialize_entry("coherence_min", &self.coherence_min())?;
        let warnings: Vec<String> = self.warnings.iter().map(ToString::to_string).collect();
        m.serialize_entry("warnings", &warnings)?;
        let kinds: Vec<&str> = self.warnings.iter().map(Warning::kind).collect();
        m.serialize_entry("warning_kinds", &kinds)?;
        m.serialize_entry("history", self.history())?;
        m.end()
    }
}
