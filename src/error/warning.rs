//! [`Warning`]: what a user should know about a run that did not stop it, with the numbers.

use super::{Block, Channel};
use crate::frf::Estimator;

/// What a [`Warning::NoiseBias`] carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum NoiseBiasBasis {
    /// The difference between the fits on H1 and on H2 of the same spectra: the records do not
    /// show which channel is noisy, and the truth lies between the two.
    Bracket,
    /// Welch segments show noise entering as the forces do: were it the force channels'
    /// measurement noise, H1 would move by the difference; an excitation the force channels
    /// do not measure would leave it exact, and segments cannot tell the two apart.
    ForceSide,
    /// H1 was compensated for the force measurement noise the records show: the difference is
    /// what one standard error of that noise estimate moves the fit by.
    Compensation,
}

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
    /// A force channel's line stands far above its neighbours with no response to match (the
    /// coherence drops there): interference such as mains hum in the force measurement. The
    /// line and the window's spread of it were left out of the fit.
    InterferenceLine {
        /// Frequency of the line (Hz).
        freq_hz: f64,
        /// The force channel.
        channel: Channel,
        /// Its auto-spectrum there over the median of its neighbours.
        ratio: f64,
        /// Lines left out (the line and its spread).
        lines: usize,
    },
    /// The jackknife could not leave some replicate out (it alone excites a direction, e.g.
    /// the one x record among y records: the refit without it has nothing to fit); the
    /// sandwich standard deviations are reported instead.
    JackknifeUnavailable {
        /// Why the refit failed.
        reason: String,
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
        /// Block-wise relative change at the last iteration (`None` where the fit does not
        /// report one).
        change: Option<f64>,
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
    /// A channel's unit, as its file states it (a TDMS `unit_string`, a Universal File's units
    /// label), is not one this crate converts ([`Unit::named`](crate::units::Unit::named)):
    /// its samples were used as read, that is as SI (N for a force; m, m/s or m/s² for a
    /// response). A unit given by the user is never guessed: an unknown one is an error.
    UnknownUnit {
        /// Label of the record (the file, or `FILE:GROUP`).
        record: String,
        /// The channel, as the file or the user names it.
        channel: String,
        /// The unit as the file writes it.
        unit: String,
        /// Whether it is a force channel (else a response).
        force: bool,
    },
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
    /// Field identification: the bearings' added masses (their constant fits' `M_dd`) sum to a
    /// mass beyond its error bars and a fair fraction of the rotor's modelled mass: the rotor
    /// model's mass is off by about that much, or the bearings carry that inertia, or their
    /// stiffness changes with speed (see [`MassSum`](crate::field::MassSum)).
    MassSum {
        /// `"x"` or `"y"`.
        direction: &'static str,
        /// `Σ_b M_b,dd` (kg).
        sum_kg: f64,
        /// Its standard deviation (kg).
        std_kg: f64,
        /// The rotor model's translational mass in that direction (kg).
        rotor_mass_kg: f64,
    },
    // ---- Predicted bias (issue 25, item 8) ----
    /// Impact records whose response has not decayed by the record's end: the truncation
    /// biases the coefficients by more than half a standard deviation
    /// ([`crate::gate::truncated_flexibility`]); an exponential window removes it.
    NotDecayed {
        /// The slowest mode's envelope left at the record's end, relative to its start.
        remaining: f64,
        /// The coefficient most biased, in standard deviations: its block, row and column.
        block: Block,
        /// Row of that coefficient.
        row: usize,
        /// Column of that coefficient.
        col: usize,
        /// Its predicted bias relative to its value.
        relative: f64,
        /// Its predicted bias in standard deviations.
        sigmas: f64,
        /// The value at the record's end of an exponential window that leaves the remaining
        /// envelope at 1e-3 (`--window exp:END`; the coefficients are corrected exactly).
        window_end: f64,
    },
    /// Welch segments (Hann) leak: the predicted bias ([`crate::gate::leaked_flexibility`])
    /// of some coefficient is above half a standard deviation; longer segments remove it.
    LeakageBias {
        /// Line spacing of the segments (Hz).
        spacing_hz: f64,
        /// The coefficient most biased, in standard deviations: its block, row and column.
        block: Block,
        /// Row of that coefficient.
        row: usize,
        /// Column of that coefficient.
        col: usize,
        /// Its predicted bias relative to its value.
        relative: f64,
        /// Its predicted bias in standard deviations.
        sigmas: f64,
    },
    /// The noise on the channels leaves a coefficient uncertain by more than a random
    /// standard deviation, carried in the error bars. Noise on the force channels biases H1's
    /// impedance up by the forces' noise-to-signal ratio, noise on the responses biases H2's
    /// down; what is carried depends on what the records show ([`NoiseBiasBasis`]).
    NoiseBias {
        /// The estimator the coefficients come from ([`Estimator::H1`] or [`Estimator::H2`]).
        estimator: Estimator,
        /// What the carried difference is.
        basis: NoiseBiasBasis,
        /// The coefficient whose difference is largest in standard deviations.
        block: Block,
        /// Row of that coefficient.
        row: usize,
        /// Column of that coefficient.
        col: usize,
        /// The other fit minus this one, relative to this one's value.
        relative: f64,
        /// That difference in random standard deviations.
        sigmas: f64,
    },
    /// A dry-friction coefficient whose predicted sign bias (noise flipping the sign of the
    /// velocity near zero, [`TermEstimate::model_std`](crate::nonlinear::TermEstimate::model_std))
    /// is above half its random standard deviation: carried in its error bar.
    FrictionBias {
        /// The term ([`Term::label`](crate::nonlinear::Term::label)).
        term: String,
        /// The predicted bias (N), carried as a standard uncertainty.
        predicted: f64,
        /// The coefficient's random standard deviation (N), `None` when none could be
        /// estimated.
        random_std: Option<f64>,
    },
    // ---- end of predicted bias ----
    // ---- Periodic records (issue 25, item 5) ----
    /// The stated period does not fit periodic records: the dominant force's energy between
    /// the harmonic lines is large ([`crate::screening::PeriodCheck`]).
    PeriodMismatch {
        /// The stated period (s).
        stated_s: f64,
        /// The period the data suggest ([`crate::screening::find_period`]), if any.
        suggested_s: Option<f64>,
    },
    /// The first period of some periodic records differs from the later ones beyond their
    /// scatter: a start-up transient ([`crate::screening::PeriodCheck`]).
    StartTransient {
        /// The records.
        records: Vec<String>,
        /// The largest distance of a first period from the others, over what their scatter
        /// predicts (about 1 in a steady state).
        worst_ratio: f64,
    },
    // ---- end of periodic records ----
    // ---- Causes of negative diagonals (issue 25, item 6) ----
    /// A diagonal flexibility has a positive imaginary part at many lines: it is a transfer
    /// (non-drive-point) FRF, whose diagonal coefficients need not be positive.
    TransferFrf {
        /// The degree of freedom.
        dof: usize,
        /// Fraction of the lines where `Im G_ii > 0`.
        fraction: f64,
    },
    /// A negative diagonal mass from channels read as displacement, while the flexibility
    /// divided by `iω` or `−ω²` fits with every diagonal positive: the channels likely measure
    /// velocity or acceleration.
    ResponseKind {
        /// The response kind the data look like, by name
        /// ([`Response::name`](crate::records::Response): `"velocity"` or `"acceleration"`).
        suggested: &'static str,
        /// Relative residual of the fit read as that kind.
        residual: f64,
        /// Relative residual of the fit read as displacement.
        original: f64,
    },
    /// Negative diagonal coefficients, while the data read the other way round (the measured
    /// impedance as the flexibility) fit with every diagonal positive: the force and response
    /// columns are likely exchanged.
    SwappedChannels {
        /// Relative residual of the fit read the other way round.
        residual: f64,
        /// Relative residual of the fit as given.
        original: f64,
    },
    // ---- end of causes ----
    /// Field identification: a speed sits near a synchronous natural frequency of the rotor
    /// pinned at the probes, where the recovery of the unmeasured degrees of freedom amplifies
    /// noise.
    NearPinnedCritical {
        /// The test speed (rad/s).
        speed_rad_s: f64,
        /// The pinned rotor's critical speed (rad/s).
        critical_rad_s: f64,
    },
    // ---- Model check and uncertainty budget ----
    /// The model check ([`ModelCheck`](crate::identify::ModelCheck)) found residuals larger
    /// than the noise measured independently of the model explains: the model misses something.
    ModelMisfit {
        /// Observed statistic over its expectation under a right model (the Birge ratio²).
        ratio: f64,
        /// Probability of a ratio at least this large under a right model.
        p_value: f64,
        /// Line (Hz) where the residual stands furthest above the noise.
        worst_hz: f64,
        /// What the pure error came from: `"replicates"` (scatter of paired sets, records,
        /// segments or periods) or `"ml cost"` (the likelihood's own cost).
        source: &'static str,
    },
    /// The constant coefficients misfit, and a frequency-dependent family fits: the element's
    /// stiffness and damping change with frequency (`--model auto`).
    FrequencyDependent {
        /// The smallest family that fits (`states:1`, `poly:2`, …).
        family: String,
        /// Its poles (Hz), if any.
        poles_hz: Vec<f64>,
    },
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
            Warning::InterferenceLine { .. } => "interference_line",
            Warning::FewReplicates { .. } => "few_replicates",
            Warning::JackknifeUnavailable { .. } => "jackknife_unavailable",
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
            Warning::UnknownUnit { .. } => "unknown_unit",
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
            Warning::MassSum { .. } => "mass_sum",
            Warning::ModelMisfit { .. } => "model_misfit",
            Warning::FrequencyDependent { .. } => "frequency_dependent",
            Warning::NotDecayed { .. } => "not_decayed",
            Warning::LeakageBias { .. } => "leakage_bias",
            Warning::NoiseBias { .. } => "noise_bias",
            Warning::FrictionBias { .. } => "friction_bias",
            Warning::PeriodMismatch { .. } => "period_mismatch",
            Warning::StartTransient { .. } => "start_transient",
            Warning::TransferFrf { .. } => "transfer_frf",
            Warning::ResponseKind { .. } => "response_kind",
            Warning::SwappedChannels { .. } => "swapped_channels",
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_output_reference_lists_every_warning_kind() {
        let source = include_str!("warning.rs");
        let start = source.find("impl Warning {").expect("impl Warning");
        let body = &source[start..];
        let body = &body[body.find("pub fn kind(&self)").expect("kind")..];
        let body = &body[..body.find("\n}\n").expect("end of impl")];
        let kinds: Vec<&str> = body.split('"').skip(1).step_by(2).collect();
        assert!(kinds.len() >= 25, "found only {kinds:?}");
        let reference = include_str!("../../docs/guide/reference-output.md");
        let table = &reference[reference
            .find("| KIND | what was seen |")
            .expect("the output reference's warning table")..];
        // The table ends at a blank line or at the end of the file.
        let table = &table[..table.find("\n\n").unwrap_or(table.len())];
        for kind in kinds {
            assert!(
                table.contains(&format!("`{kind}`")),
                "the output reference's warning table lacks `{kind}`"
            );
        }
    }
}
