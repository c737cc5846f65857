//! [`Warning`]: what a user should know about a run that did not stop it, with the numbers.

use std::fmt;

use super::{Block, Channel};

/// Something a user should know about an identification that did not stop it.
///
/// Warnings travel with the result (see
/// [`Identification::warnings`](crate::identify::Identification::warnings)); each says what was
/// seen, with the numbers.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// Some lines have a condition number above the warning threshold.
    IllConditioned {
        /// Lines above the threshold.
        lines: usize,
        /// Lines in the band.
        of: usize,
        /// Frequency of the worst line (Hz).
        worst_hz: f64,
        /// Condition number of the worst line.
        worst: f64,
        /// The warning threshold.
        threshold: f64,
    },
    /// Lines were dropped because the multiple coherence of some output was below the
    /// threshold.
    LowCoherence {
        /// Lines dropped.
        lines: usize,
        /// The threshold.
        threshold: f64,
    },
    /// The jackknife had fewer than 3 replicates; the sandwich standard deviations are
    /// reported instead.
    FewReplicates {
        /// Replicates available (paired sets or records).
        replicates: usize,
    },
    /// Lines of the band were dropped because a matrix could not be inverted.
    DroppedLines {
        /// Frequencies of the dropped lines (Hz).
        freqs_hz: Vec<f64>,
    },
    /// Records left out of the paired sets (unequal counts per direction).
    UnpairedRecords {
        /// Labels of the records left out.
        records: Vec<String>,
    },
    /// An iterative fit stopped at its iteration limit before meeting its tolerance.
    NotConverged {
        /// Iterations run.
        iterations: usize,
        /// Block-wise relative change at the last iteration.
        change: f64,
    },
    /// An iterative fit diverged; the result is its best iterate.
    Diverged {
        /// Iterations run before divergence was detected.
        iterations: usize,
        /// The iterate returned (0 = the least-squares start).
        fallback_iteration: usize,
    },
    /// An impact record holds a second hammer pulse (see
    /// [`quality::check_record`](crate::quality::check_record)).
    DoubleHit {
        /// Label of the record.
        record: String,
        /// Time of the second pulse's peak (s from the record's first sample).
        second_s: f64,
        /// Its peak over the main peak.
        ratio: f64,
    },
    /// A channel of a record sits at its extreme value for several samples: the ADC or
    /// amplifier was overloaded (see [`quality::check_record`](crate::quality::check_record)).
    Clipped {
        /// Label of the record.
        record: String,
        /// The clipped channel.
        channel: Channel,
        /// The clipping level (N or m).
        value: f64,
    },
    /// A record was left out of the identification because it failed a quality check.
    Rejected {
        /// Label of the record.
        record: String,
        /// Why, in words (for example the issues found).
        reason: String,
    },
    /// Maximum likelihood kept its IVF start.
    MlFellBack {
        /// Why.
        reason: String,
    },
    /// Maximum likelihood on whole records under an exponential window: the window correlates
    /// neighbouring lines, which the residual noise model does not account for, so its error
    /// bars are too narrow (1.3–2.3 × in a simulated check; the estimate itself is fine).
    MlWindowedRecords {
        /// The window's decay rate (1/s).
        decay_per_s: f64,
    },
    // The fit gate (see `crate::gate`).
    /// The fitted model does not explain an element of the measured flexibility that carries
    /// signal (see [`gate::FitGate`](crate::gate::FitGate)).
    PoorFit {
        /// Row of the element.
        row: usize,
        /// Column of the element.
        col: usize,
        /// Its flexibility `r²`.
        r2: f64,
        /// The threshold.
        threshold: f64,
    },
    /// A diagonal entry of `M`, `C` or `K` is negative: not physical for a test system.
    NegativeDiagonal {
        /// The matrix.
        block: Block,
        /// The degree of freedom.
        dof: usize,
        /// The entry.
        value: f64,
    },
    /// The fitted model has a mode with negative damping.
    UnstableMode {
        /// Its natural frequency (Hz).
        frequency_hz: f64,
        /// Its damping ratio (negative).
        damping_ratio: f64,
    },
    /// Jackknife replicates gave the same fit: they carry the same data (records passed more
    /// than once?) and the error bars understate the error.
    DependentReplicates {
        /// Replicates (paired sets or records).
        replicates: usize,
        /// Distinct fits among them.
        distinct: usize,
    },
    /// Resampled standard deviations of diagonal entries are zero.
    ZeroSpread {
        /// Diagonal entries with zero spread.
        entries: usize,
        /// Diagonal entries in all.
        of: usize,
    },
    /// The exponential window decays faster than the lowest band frequency (see
    /// [`gate::window`](crate::gate::window)).
    WindowTooShort {
        /// The window's decay rate (1/s).
        decay_per_s: f64,
        /// $2\pi f_{low}$ (1/s).
        limit_per_s: f64,
    },
    /// The force gate closes before the force pulse has ended.
    ForceGateShort {
        /// Records whose pulse outlasts the gate.
        records: usize,
        /// Time the gate stays open (s).
        gate_s: f64,
        /// Latest end of a pulse (s from the record's start).
        pulse_end_s: f64,
    },
    /// Welch segments too short for a mode's half-power bandwidth (leakage bias at the peak).
    CoarseResolution {
        /// Line spacing (Hz).
        spacing_hz: f64,
        /// The mode's natural frequency (Hz).
        mode_hz: f64,
        /// Its half-power bandwidth `2ζ f_n` (Hz).
        half_power_hz: f64,
        /// Predicted relative peak bias `(Δf/B_r)²/3`.
        peak_bias: f64,
    },
    /// Few lines for the unknowns: little redundancy to average noise or show a misfit.
    FewLines {
        /// Lines fitted.
        lines: usize,
        /// Lines wanted.
        needed: usize,
    },
    // ---- Record screening (`crate::screening`) ----
    /// A channel holds one value throughout (no variation beyond rounding): a dead,
    /// disconnected or unpowered sensor (see [`screening`](crate::screening)).
    FlatChannel {
        /// Label of the record.
        record: String,
        /// The flat channel.
        channel: Channel,
        /// The value it holds (N or m).
        value: f64,
    },
    /// A channel's RMS (mean removed) is far below the same channel's median RMS in its
    /// sibling records (see [`screening`](crate::screening)).
    DeadChannel {
        /// Label of the record.
        record: String,
        /// The channel.
        channel: Channel,
        /// Its RMS (N or m).
        rms: f64,
        /// The median RMS of the same channel over the siblings (N or m).
        median_rms: f64,
    },
    /// A channel's level is an outlier among its sibling records: its log RMS is far from
    /// their median in robust standard deviations (see [`screening`](crate::screening)).
    LevelOutlier {
        /// Label of the record.
        record: String,
        /// The channel.
        channel: Channel,
        /// Its RMS (N or m).
        rms: f64,
        /// The median RMS of the same channel over the siblings (N or m).
        median_rms: f64,
        /// `|ln rms − median ln rms| / σ̂` with `σ̂ = 1.4826 · MAD` of the siblings' log RMS
        /// (infinite when the siblings agree exactly).
        sigmas: f64,
    },
    /// A record holds exactly the same samples as an earlier one (the same file passed twice,
    /// say, whatever the labels).
    DuplicateRecord {
        /// Label of the later record.
        record: String,
        /// Label of the earlier record with the same samples.
        of: String,
    },
    /// A paired set's impedance is far from the other sets' at most band lines (see
    /// [`screening::outlier_sets`](crate::screening::outlier_sets)).
    OutlierSet {
        /// Labels of the set's records, one per direction.
        records: Vec<String>,
        /// Lines where the set is far out.
        far_lines: usize,
        /// Lines tested.
        lines: usize,
    },
    // ---- end of record screening ----
    /// The model check of a nonlinear term failed: its $\hat A_j(\omega)$ is not real and
    /// flat over the band, so the regressor does not describe the element (the coefficient
    /// returned is still a number, but not the element's).
    NonlinearMisfit {
        /// The term ([`Term::label`](crate::nonlinear::Term::label)).
        term: String,
        /// Band average of `Im Â` over that of `Re Â`.
        imaginary_ratio: f64,
        /// Change of `Re Â` across the band relative to its average.
        slope: f64,
    },
    /// A dissipative nonlinear term (friction, quadratic damping) came out negative by more than
    /// [`NONLINEAR_CHECK_SIGMAS`](crate::tolerance::NONLINEAR_CHECK_SIGMAS) of its standard
    /// deviations: the element would feed energy into the motion. The regressor is not the
    /// element's — typically friction fitted where the element has quadratic damping or the
    /// reverse, the two being alike enough for the linear damping to absorb the difference.
    NegativeDissipation {
        /// The term ([`Term::label`](crate::nonlinear::Term::label)).
        term: String,
        /// Its identified coefficient.
        value: f64,
        /// Its standard deviation (`None` when none could be estimated).
        std: Option<f64>,
    },
    /// A nonlinear regressor is nearly a linear combination of the other inputs over the band
    /// (its multiple coherence on them is close to 1): its coefficient is poorly determined.
    CollinearRegressors {
        /// The term ([`Term::label`](crate::nonlinear::Term::label)).
        term: String,
        /// Median over the band of its multiple coherence on the other inputs.
        coherence: f64,
    },
    /// `field`: at some speeds the rotor model leaves a residual far beyond what the stated
    /// response noise explains (redundant probes only): the rotor model, the probe positions or
    /// the responses' phase convention do not fit the measurements.
    ModelResidual {
        /// Speeds (rad/s) where the residual is too large.
        speeds_rad_s: Vec<f64>,
        /// Largest ratio of `‖r‖²` to its expectation under the noise.
        worst_ratio: f64,
        /// The ratio above which a residual is too large.
        limit: f64,
    },
    /// Field identification: the added imbalance forces of the two tests are proportional
    /// (masses in one plane, whatever their angles): their responses are a rank-1 pair.
    DependentTests {
        /// `|⟨f¹, f²⟩| / (‖f¹‖ ‖f²‖)`, 1 for proportional forces.
        correlation: f64,
    },
    /// Field identification: at these speeds a bearing's pair of responses `[q¹ q²]` is
    /// singular (condition number above the limit); its `K`, `C` are not given there.
    SingularPair {
        /// Tag of the bearing.
        bearing: String,
        /// The speeds (rad/s).
        speeds_rad_s: Vec<f64>,
        /// The limit on the condition number.
        limit: f64,
    },
    /// Field identification: at these speeds a bearing's pair of responses is ill-conditioned
    /// (nearly circular orbits, or nearly dependent tests): noise is amplified by up to the
    /// condition number.
    IllConditionedPair {
        /// Tag of the bearing.
        bearing: String,
        /// The speeds (rad/s).
        speeds_rad_s: Vec<f64>,
        /// The largest condition number among them.
        worst: f64,
        /// The warning threshold.
        threshold: f64,
    },
    /// Field identification: at these speeds a bearing's `Z` amplifies relative response noise
    /// by more than the threshold (the first-order `‖δZ‖/‖Z‖` per unit relative noise).
    HighNoiseGain {
        /// Tag of the bearing.
        bearing: String,
        /// The speeds (rad/s).
        speeds_rad_s: Vec<f64>,
        /// The largest gain among them.
        worst: f64,
        /// The threshold.
        threshold: f64,
    },
    /// Field identification: a speed sits near a synchronous natural frequency of the rotor
    /// pinned at the probes, where the recovery of the unmeasured degrees of freedom amplifies
    /// noise.
    NearPinnedCritical {
        /// The test speed (rad/s).
        speed_rad_s: f64,
        /// The pinned rotor's critical speed (rad/s).
        critical_rad_s: f64,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::IllConditioned {
                lines,
                of,
                worst_hz,
                worst,
                threshold,
            } => write!(
                f,
                "{lines} of {of} lines have a condition number above {threshold:.3e} \
                 (worst {worst:.3e} at {worst_hz:.3} Hz): excitations close to dependent"
            ),
            Warning::LowCoherence { lines, threshold } => write!(
                f,
                "{lines} lines dropped with a multiple coherence below {threshold}"
            ),
            Warning::FewReplicates { replicates } => write!(
                f,
                "only {replicates} replicates for the jackknife (3 needed): sandwich standard deviations reported"
            ),
            Warning::DroppedLines { freqs_hz } => write!(
                f,
                "{} lines dropped (singular matrices) at {:?} Hz",
                freqs_hz.len(),
                freqs_hz
            ),
            Warning::UnpairedRecords { records } => write!(
                f,
                "{} records left out of the paired sets: {}",
                records.len(),
                records.join(", ")
            ),
            Warning::NotConverged { iterations, change } => write!(
                f,
                "not converged after {iterations} iterations (relative change {change:.3e})"
            ),
            Warning::Diverged {
                iterations,
                fallback_iteration,
            } => write!(
                f,
                "diverged after {iterations} iterations; returning iterate {fallback_iteration}"
            ),
            Warning::DoubleHit {
                record,
                second_s,
                ratio,
            } => write!(
                f,
                "record `{record}`: double hit, a second pulse at {second_s:.4} s of {ratio:.2} × the main peak"
            ),
            Warning::Clipped {
                record,
                channel,
                value,
            } => write!(f, "record `{record}`: {channel} clipped at {value:.4e}"),
            Warning::Rejected { record, reason } => {
                write!(f, "record `{record}` rejected: {reason}")
            }
            Warning::MlFellBack { reason } => {
                write!(f, "maximum likelihood kept the IVF result: {reason}")
            }
            Warning::MlWindowedRecords { decay_per_s } => write!(
                f,
                "maximum likelihood on whole records under an exponential window ({decay_per_s} 1/s): \
                 neighbouring lines correlate, so its error bars are too narrow (jackknife ones are safer)"
            ),
            Warning::PoorFit {
                row,
                col,
                r2,
                threshold,
            } => write!(
                f,
                "poor fit of flexibility element ({row},{col}): r² = {r2:.3} below {threshold}"
            ),
            Warning::NegativeDiagonal { block, dof, value } => write!(
                f,
                "{block}[{dof}][{dof}] = {value:.4e} is negative: not physical for a test system"
            ),
            Warning::UnstableMode {
                frequency_hz,
                damping_ratio,
            } => write!(
                f,
                "the fitted model is unstable: mode at {frequency_hz:.3} Hz with damping ratio {damping_ratio:.3}"
            ),
            Warning::DependentReplicates {
                replicates,
                distinct,
            } => write!(
                f,
                "only {distinct} of {replicates} replicates give distinct fits: records passed more than once? \
                 error bars understate the error"
            ),
            Warning::ZeroSpread { entries, of } => write!(
                f,
                "{entries} of {of} diagonal coefficients have zero resampled spread: the replicates are identical"
            ),
            Warning::WindowTooShort {
                decay_per_s,
                limit_per_s,
            } => write!(
                f,
                "exponential window decays at {decay_per_s:.4e} 1/s, faster than the lowest band frequency \
                 ({limit_per_s:.4e} rad/s): it leaves too little of the record"
            ),
            Warning::ForceGateShort {
                records,
                gate_s,
                pulse_end_s,
            } => write!(
                f,
                "force gate open {gate_s:.4e} s closes before the pulse ends (up to {pulse_end_s:.4} s) in {records} records"
            ),
            Warning::CoarseResolution {
                spacing_hz,
                mode_hz,
                half_power_hz,
                peak_bias,
            } => write!(
                f,
                "line spacing {spacing_hz:.4} Hz is coarse for the mode at {mode_hz:.3} Hz \
                 (half-power bandwidth {half_power_hz:.3} Hz): predicted peak bias {:.1} %",
                100.0 * peak_bias
            ),
            Warning::FewLines { lines, needed } => write!(
                f,
                "only {lines} lines in the band ({needed} wanted): little redundancy in the fit"
            ),
            // ---- Record screening ----
            Warning::FlatChannel {
                record,
                channel,
                value,
            } => write!(
                f,
                "record `{record}`: {channel} is flat, every sample at {value:.4e} \
                 (a dead or disconnected sensor)"
            ),
            Warning::DeadChannel {
                record,
                channel,
                rms,
                median_rms,
            } => write!(
                f,
                "record `{record}`: {channel} is dead, RMS {rms:.3e} is {:.1e} × the median \
                 {median_rms:.3e} of its sibling records",
                rms / median_rms
            ),
            Warning::LevelOutlier {
                record,
                channel,
                rms,
                median_rms,
                sigmas,
            } => write!(
                f,
                "record `{record}`: {channel} level is an outlier, RMS {rms:.3e} is {:.3} × the \
                 median {median_rms:.3e} of its sibling records ({sigmas:.1} robust σ)",
                rms / median_rms
            ),
            Warning::DuplicateRecord { record, of } if record == of => write!(
                f,
                "record `{record}` passed again: the same samples as its first copy"
            ),
            Warning::DuplicateRecord { record, of } => write!(
                f,
                "record `{record}` holds the same samples as record `{of}` (the same data twice)"
            ),
            Warning::OutlierSet {
                records,
                far_lines,
                lines,
            } => write!(
                f,
                "paired set ({}): impedance far from the other sets' at {far_lines} of {lines} lines",
                records.join(", ")
            ),
            Warning::NonlinearMisfit {
                term,
                imaginary_ratio,
                slope,
            } => write!(
                f,
                "nonlinear term {term} does not fit: its coefficient spectrum has Im/Re = \
                 {imaginary_ratio:.3} and changes by {:.1} % across the band (a right regressor \
                 gives a real constant); its value is not the element's",
                100.0 * slope
            ),
            Warning::NegativeDissipation { term, value, std } => write!(
                f,
                "nonlinear term {term} is dissipative but came out negative ({value:.4e}{}): \
                 the element would feed energy into the motion, so the regressor is not the \
                 element's",
                std.map_or(String::new(), |s| format!(" ± {s:.2e}"))
            ),
            Warning::CollinearRegressors { term, coherence } => write!(
                f,
                "nonlinear term {term} is nearly collinear with the other inputs (multiple \
                 coherence {coherence:.4} on them): its coefficient is poorly determined"
            ),
            // ---- Field identification ----
            Warning::ModelResidual {
                speeds_rad_s,
                worst_ratio,
                limit,
            } => write!(
                f,
                "the rotor model leaves a residual above {limit} times what the stated response \
                 noise explains at {} speed(s) from {:.4} rad/s (worst {worst_ratio:.3e}): the \
                 rotor model, the probe positions or the responses' phase convention do not fit \
                 the measurements, and K, C there are not the bearings'",
                speeds_rad_s.len(),
                speeds_rad_s.first().copied().unwrap_or(f64::NAN)
            ),
            Warning::DependentTests { correlation } => write!(
                f,
                "the two tests' added imbalance forces are proportional (1 − correlation = \
                 {:.1e}): masses in one plane give a rank-1 pair of responses whatever their \
                 angles",
                1.0 - correlation
            ),
            Warning::SingularPair {
                bearing,
                speeds_rad_s,
                limit,
            } => write!(
                f,
                "bearing `{bearing}`: responses of the two tests dependent (condition number \
                 above {limit:.0e}) at {} speed(s) from {:.4} rad/s; K and C not given there",
                speeds_rad_s.len(),
                speeds_rad_s.first().copied().unwrap_or(f64::NAN)
            ),
            Warning::IllConditionedPair {
                bearing,
                speeds_rad_s,
                worst,
                threshold,
            } => write!(
                f,
                "bearing `{bearing}`: responses of the two tests nearly dependent (condition \
                 number above {threshold:.0e}, worst {worst:.3e}) at {} speed(s): near a \
                 critical speed one mode dominates every test's response; away from one, nearly \
                 circular orbits or nearly dependent tests; either way noise is amplified",
                speeds_rad_s.len()
            ),
            Warning::HighNoiseGain {
                bearing,
                speeds_rad_s,
                worst,
                threshold,
            } => write!(
                f,
                "bearing `{bearing}`: relative response noise is amplified more than \
                 {threshold:.0}-fold in Z at {} speed(s) from {:.4} rad/s (worst {worst:.0}): \
                 1 % noise gives errors of that many percent",
                speeds_rad_s.len(),
                speeds_rad_s.first().copied().unwrap_or(f64::NAN)
            ),
            Warning::NearPinnedCritical {
                speed_rad_s,
                critical_rad_s,
            } => write!(
                f,
                "speed {speed_rad_s:.4} rad/s is near {critical_rad_s:.4} rad/s, a critical \
                 speed of the rotor pinned at the probes: noise is amplified there"
            ),
        }
    }
}

impl Warning {
    /// A stable snake_case name of the kind of warning, for scripts and logs (the CLI's JSON
    /// lists them as `warning_kinds`, in the order of `warnings`).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Warning;
    /// assert_eq!(Warning::FewReplicates { replicates: 2 }.kind(), "few_replicates");
    /// ```
    pub fn kind(&self) -> &'static str {
        match self {
            Warning::IllConditioned { .. } => "ill_conditioned",
            Warning::LowCoherence { .. } => "low_coherence",
            Warning::FewReplicates { .. } => "few_replicates",
            Warning::DroppedLines { .. } => "dropped_lines",
            Warning::UnpairedRecords { .. } => "unpaired_records",
            Warning::NotConverged { .. } => "not_converged",
            Warning::Diverged { .. } => "diverged",
            Warning::DoubleHit { .. } => "double_hit",
            Warning::Clipped { .. } => "clipped",
            Warning::Rejected { .. } => "rejected",
            Warning::MlFellBack { .. } => "ml_fell_back",
            Warning::MlWindowedRecords { .. } => "ml_windowed_records",
            Warning::PoorFit { .. } => "poor_fit",
            Warning::NegativeDiagonal { .. } => "negative_diagonal",
            Warning::UnstableMode { .. } => "unstable_mode",
            Warning::DependentReplicates { .. } => "dependent_replicates",
            Warning::ZeroSpread { .. } => "zero_spread",
            Warning::WindowTooShort { .. } => "window_too_short",
            Warning::ForceGateShort { .. } => "force_gate_short",
            Warning::CoarseResolution { .. } => "coarse_resolution",
            Warning::FewLines { .. } => "few_lines",
            Warning::FlatChannel { .. } => "flat_channel",
            Warning::DeadChannel { .. } => "dead_channel",
            Warning::LevelOutlier { .. } => "level_outlier",
            Warning::DuplicateRecord { .. } => "duplicate_record",
            Warning::OutlierSet { .. } => "outlier_set",
            Warning::NonlinearMisfit { .. } => "nonlinear_misfit",
            Warning::NegativeDissipation { .. } => "negative_dissipation",
            Warning::CollinearRegressors { .. } => "collinear_regressors",
            Warning::ModelResidual { .. } => "model_residual",
            Warning::DependentTests { .. } => "dependent_tests",
            Warning::SingularPair { .. } => "singular_pair",
            Warning::IllConditionedPair { .. } => "ill_conditioned_pair",
            Warning::NearPinnedCritical { .. } => "near_pinned_critical",
            Warning::HighNoiseGain { .. } => "high_noise_gain",
        }
    }
}
