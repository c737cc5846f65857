//! Every numerical tolerance of the library in one place, each with its reason (in the manner of
//! statrs' `prec`): when two numbers are "equal", when a value is "zero", how far a band edge or
//! a time stamp may stray. A tolerance used by more than one stage lives here and nowhere else.

// ---------------------------------------------------------------------------------------------
// Records, time grids, bands and spectra (records, spectra, frf, stepped, conditioning, solve).
// ---------------------------------------------------------------------------------------------

/// How far a sample's time may sit from its place on a uniform grid, as a fraction of one
/// sampling step: the CSV reader ([`io`], feature `csv`) accepts a time column whose every
/// sample is within this tolerance of the grid through its first and last time, and the same
/// tolerance decides when two records' sampling rates agree
/// ([`sample_rates_agree`](crate::records::sample_rates_agree)).
///
/// Why 1 %: data loggers stamp samples from one clock, so real jitter is far smaller; a
/// column off by more is not uniformly sampled (dropped or repeated samples). Over a record
/// the tolerance moves the highest band line by at most about 2 % of a line spacing, which the
/// spectra do not notice.
///
#[cfg_attr(feature = "csv", doc = "[`io`]: crate::io")]
#[cfg_attr(not(feature = "csv"), doc = "[`io`]: crate#feature-flags")]
pub const TIME_GRID_TOLERANCE: f64 = 0.01;

/// Relative slack added to the agreement of two sampling rates for the rounding of
/// `(N − 1)/(t_{N−1} − t_0)` ([`sample_rates_agree`](crate::records::sample_rates_agree)).
pub const RATE_ROUNDING: f64 = 1e-12;

/// A DFT line within this fraction of the line spacing of a band edge counts as inside
/// ([`Band::lines`](crate::frf::Band::lines)): edges typed in Hz rarely fall exactly on
/// `k · f_s / N` in floating point, and a line `10⁻⁶` of a spacing away is the edge.
pub const BAND_EDGE_SLACK: f64 = 1e-6;

/// A signal whose swing `max − min` is at most this fraction of its largest magnitude is flat
/// (a constant, or zero, up to rounding of its level) for
/// [`drive_frequency`](crate::stepped::drive_frequency).
pub const FLAT_SIGNAL: f64 = 1e-12;

/// A Gauss–Newton frequency step of [`drive_frequency`](crate::stepped::drive_frequency)
/// below this fraction of the frequency is rounding: the refinement stops.
pub const FREQUENCY_STEP: f64 = 1e-15;

/// An eigenvalue `λ` of the state matrix is an oscillatory root when `Im λ > 10⁻⁹ |λ|`
/// ([`Coefficients::modes`](crate::model::Coefficients::modes)): real roots come out of the
/// eigensolver with an imaginary part at rounding level, far below this.
pub const OSCILLATORY_ROOT: f64 = 1e-9;

// ---------------------------------------------------------------------------------------------
// Identification, screening, gates and quality checks (identify, screening, gate, quality).
// ---------------------------------------------------------------------------------------------

/// Relative agreement below which two fits, or a standard deviation and zero, are taken as the
/// same: far above the rounding of a fit (about 1e-13 relative) and far below any measured
/// scatter. Used for dependent jackknife replicates and zero spread
/// ([`gate::distinct_fits`](crate::gate::distinct_fits),
/// [`gate::zero_spread`](crate::gate::zero_spread)); also at its old path `gate::ALIKE`.
pub const ALIKE: f64 = 1e-9;

/// Slack, relative to the band's upper edge, by which a line of a ready-made FRF
/// ([`Identifier::identify_frf`](crate::Identifier::identify_frf)) may lie outside the band
/// and still be used: a frequency written in decimal or computed from a sample rate lands
/// within rounding (about 1e-15 relative) of the edge it was meant to be, far inside this,
/// while any real line spacing is far outside it.
pub const READY_FRF_BAND_EDGE: f64 = 1e-9;

/// Relative agreement (of the larger of `|f|` and 1 Hz) at which a baseline's line frequencies
/// count as the system's ([`Identification::subtract_baseline`](crate::Identification::subtract_baseline)):
/// lines read back from JSON carry at most a rounding of the printed value.
pub const BASELINE_LINE: f64 = 1e-9;

/// Relative agreement (of the larger of `|a|` and `1e-12` 1/s) at which a baseline's
/// exponential-window decay counts as the system's: the decay read back from JSON differs
/// from the one used by rounding only.
pub const BASELINE_DECAY: f64 = 1e-9;

/// A rotor speed within this fraction of the line spacing of a line is at that line for the
/// synchronous coefficients ([`Synchronous::from_lines`](crate::rotor::Synchronous::from_lines)):
/// a speed typed in rpm comes to Hz through `2π/60` and back by `1/2π`, which moves it by a
/// few ulps, and interpolating over `10⁻⁹` of a spacing would blur a line's own values with
/// its neighbour's by rounding only.
pub const SYNCHRONOUS_LINE: f64 = 1e-9;

/// A channel is flat when `max − min ≤ FLAT_CHANNEL · max(|max|, |min|)`: one value up to
/// rounding (exactly zero for an all-zero channel). Also at its old path
/// `screening::FLAT_TOLERANCE`.
pub const FLAT_CHANNEL: f64 = 1e-12;

/// Samples count as "at the extreme" when within this fraction of the channel's range
/// (`max − min`) of the channel's maximum or minimum (clipping). Also at its old path
/// `quality::CLIP_TOLERANCE`.
pub const CLIP_LEVEL: f64 = 1e-9;

/// Relative slack on the quantisation step when deciding that a clipped-looking run is a
/// smooth peak on its top code, flanked by samples one step below: the step and the
/// difference are computed from the same samples and differ by rounding only.
pub const QUANTISATION_STEP: f64 = 1e-9;

// ---------------------------------------------------------------------------------------------
// Simulation and figures (simulate, plot).
// ---------------------------------------------------------------------------------------------

/// How far the slowest mode of a simulated impact test must decay by the end of its records,
/// in nepers: `ln 10⁶`, i.e. to `10⁻⁶` of its amplitude. A response cut off earlier leaks in
/// the DFT of the whole record ([`ImpactTest::run`](crate::simulate::ImpactTest::run)).
pub const SIM_DECAY_NEPERS: f64 = 6.0 * std::f64::consts::LN_10;

/// Samples by which a [`sweep`](crate::simulate::sweep) may overrun its record and still
/// "fit": half a sample, since the sweep's sample count is `round(duration × rate)`.
pub const SWEEP_FIT_SAMPLES: f64 = 0.5;

/// Smallest width of a plotted axis range whose values are all equal (all zero): a range this
/// narrow about zero still draws, and nothing real is this small in SI units.
pub const PLOT_MIN_SPAN: f64 = 1e-30;

/// Floor of a relative change drawn on the IVF convergence figure's log axis: a change of
/// exactly zero (converged to the last bit) would have no logarithm; `10⁻¹⁷` lies below the
/// `f64` epsilon `2.2·10⁻¹⁶`, so any real change stays above it.
pub const PLOT_CHANGE_FLOOR: f64 = 1e-17;

// ---------------------------------------------------------------------------------------------
// Excitation detection and the command-line tool (excitation, bin).
// ---------------------------------------------------------------------------------------------

/// How far the slowest mode of a system decays over the records `bearing-ident simulate`
/// makes when no `--duration` is given (impacts, sweeps): `e^{-16.2} ≈ 9·10⁻⁸`, below `10⁻⁷`
/// of the mode's amplitude, so the whole-record DFT sees no leakage above the noise and the
/// `10⁻⁶` that [`ImpactTest::run_clean`](crate::simulate::ImpactTest::run_clean) requires is
/// met with margin. Record length `16.2 / min(−Re λ)` seconds after the excitation.
pub const SIMULATED_DECAY_NEPERS: f64 = 16.2;

/// Largest `ρ h` (fastest rate of the system times the step) of the nonlinear simulator's RK4
/// steps: the classical Runge–Kutta method is stable on the negative real axis up to
/// `ρh ≈ 2.785` and on the imaginary axis up to `2√2 ≈ 2.83`; `2` keeps a margin for the
/// rates between (a lightly damped filter section's poles lie near 45°).
pub const RK4_STABLE_STEP: f64 = 2.0;

/// Largest change of velocity per RK4 substep inside the friction's smoothing band, in units of
/// the smoothing scale `v_s`: `tanh` changes over `≈ v_s`, so a quarter of it per substep
/// resolves the law (a free Coulomb decay then matches its closed form to `10⁻⁶`).
pub const SMOOTHING_RESOLUTION: f64 = 0.25;
// ---------------------------------------------------------------------------------------------
// Nonlinear elements: the reverse path (nonlinear).
// ---------------------------------------------------------------------------------------------

/// Half-width (lines) of the moving average that smooths a channel's power before the Wiener
/// gain of the velocity ([`Differentiation::Wiener`](crate::nonlinear::Differentiation::Wiener)):
/// 65 lines average $\lvert X_k\rvert^2$ to a relative scatter of $1/\sqrt{65} \approx 12\,\%$,
/// so the gain $1 - N_0/\bar P$ is steady where the signal stands above the floor, while the
/// averaging width stays a small fraction of any band of a long record.
pub const WIENER_SMOOTHING_LINES: usize = 32;

/// Over-subtraction $\beta$ of the Wiener gain $1 - \beta N_0/\bar P$: the smoothed power of
/// lines of noise alone scatters about the floor $N_0$ by $1/\sqrt{65} \approx 12\,\%$ (see
/// [`WIENER_SMOOTHING_LINES`]); $\beta = 1 + 4/\sqrt{65} \approx 1.5$ puts four of those
/// scatters between them and a non-zero gain, so the noise is not let through at small gains
/// all the way to Nyquist (where a derivative multiplies it by $\omega$), while a line
/// 100 times above the floor keeps 98.5 % of its power.
pub const WIENER_OVERSUBTRACTION: f64 = 1.5;

/// Fewest lines above the band from which the Wiener gain's noise floor is read as their
/// median (the records' measurement noise, which the band-limited response lies under); with
/// fewer, the lowest decile of the whole spectrum is used. Four smoothing widths: the median
/// then rests on about four independent averages.
pub const WIENER_MIN_FLOOR_LINES: usize = 4 * (2 * WIENER_SMOOTHING_LINES + 1);

/// Welch averages the reverse path needs per input (linear and nonlinear together): the
/// input spectral matrix $S_{zz}$ of $q$ inputs is singular below $q$ averages, and the
/// random error of the estimate grows as $1/(n_d - q)$; twice as many averages as inputs keeps
/// that factor at most $1/q$ of the estimate's own variance.
pub const REVERSE_PATH_AVERAGES_PER_INPUT: usize = 2;

/// Most jackknife blocks of the reverse path: the Welch segments of all records, in order, are
/// cut into this many contiguous blocks (fewer when there are fewer segments), each left out
/// in turn. Eight replicates give the standard deviation to about ±25 % (χ² with 7 degrees of
/// freedom), at eight refits' cost.
pub const REVERSE_PATH_JACKKNIFE_BLOCKS: usize = 8;

/// Model check of a nonlinear term: largest ratio of the band average of $\operatorname{Im}
/// \hat A_j$ to that of $\operatorname{Re} \hat A_j$ for a term that fits.
///
/// A right regressor has a real, constant $\hat A_j$ in theory; in records it does not quite.
/// Per-axis dry friction under random forces sticks part of the time (3 % of the samples on
/// the seed rig with 20 N against 50 N RMS), where $\operatorname{sign}\dot x$ is not the
/// friction force, and the anti-alias filter and the velocity's gain smooth the kinks of
/// $\dot x$ at its reversals, which moves the zero crossings: the right `coulomb` term then
/// shows ratios of 0.06 (noise-free), 0.10–0.14 (2 % noise) and 0.17 (a velocity cut off just
/// above the band), with its coefficient still within 2.5 %. Wrong regressors give 7–530
/// (`cubic` on friction, `coulomb` on cubic stiffness, `quadratic-damping` on cubic
/// stiffness, `cubic` on quadratic damping; `tests/nonlinear/end_to_end.rs`). 0.25 leaves the
/// right term a margin of 1.5 and the wrong ones a factor 30.
pub const NONLINEAR_IMAGINARY_RATIO: f64 = 0.25;

/// Model check of a nonlinear term: largest change of $\operatorname{Re}\hat A_j$ across the
/// band, relative to its band average (weighted straight-line fit), for a term that fits. The
/// right `coulomb` term shows up to 0.22 in magnitude for the reasons given at
/// [`NONLINEAR_IMAGINARY_RATIO`]; the imaginary ratio is the sharper test of the two.
pub const NONLINEAR_SLOPE: f64 = 0.3;

/// A model-check deviation (imaginary part, slope) counts only when it is this many of its own
/// standard deviations (from the per-line variances) away from zero, so that a term whose
/// coefficient is noise (a term the system does not have) is not called a misfit.
pub const NONLINEAR_CHECK_SIGMAS: f64 = 3.0;

/// A regressor is collinear with the other inputs when its multiple coherence on them (median
/// over the band) exceeds this: its coefficient is then determined by less than 1 % of its
/// own power, and scatter and bias grow by the factor $1/(1-\gamma^2) > 100$.
pub const COLLINEAR_COHERENCE: f64 = 0.99;

/// A pivot of the factorisation of a line's second moments `Σ z zᴴ` into columns
/// ([`noise`](crate::solve::ml::noise)), scaled to a unit diagonal, at most this large is
/// rounding: the moments have no more rank than that (noise-free spectra have rank `n`).
pub const MOMENT_RANK: f64 = 1e-13;

/// Real degrees of freedom the residual noise model pools per line
/// ([`noise`](crate::solve::ml::noise)): neighbouring lines are averaged until about this
/// many. Maximum likelihood with a noise covariance estimated from `ν` degrees of freedom
/// spreads more than with the exact one and its intervals cover less: on random records
/// (Monte-Carlo, `tests/estimation/ml_records.rs`) 96 left the spread 1.01–1.07 × the bound and one
/// coefficient's 95 % coverage at 0.927; 288 gives 0.99–1.04 × and 0.93–0.95. The price is
/// the assumption that the noise spectrum is smooth over the lines pooled (9 for 16 impacts,
/// about 21 for 15 Hann segments).
pub const POOLED_NOISE_DOF: f64 = 288.0;

// ---------------------------------------------------------------------------------------------
// Field identification from imbalance responses (field).
// ---------------------------------------------------------------------------------------------

/// A bearing's pair of responses `[q¹ q²]` is singular above this condition number
/// ([`field`](crate::field)): its `K`, `C` are not given at that speed. Rounding of the
/// recovered responses (about 1e-15 relative) times 1e10 leaves at most five correct digits;
/// dependent tests (masses in one plane, circular orbits) give 1e14 and more noise-free.
pub const FIELD_SINGULAR_PAIR: f64 = 1e10;

/// A bearing's pair of responses is ill-conditioned (a warning) above this condition number:
/// relative response noise is amplified up to this factor in `K`, `C`. Well-placed tests on
/// anisotropic supports give 1–30.
pub const FIELD_ILL_CONDITIONED_PAIR: f64 = 100.0;

/// A speed within this fraction of a critical speed of the rotor pinned at the probes is
/// near it (a warning): the recovery of the unmeasured degrees of freedom divides by the
/// pinned rotor's dynamic stiffness, which vanishes there.
pub const FIELD_NEAR_CRITICAL: f64 = 0.05;

/// A bearing's noise gain (first-order `‖δZ‖/‖Z‖` per unit relative response noise) above this
/// is a warning: 1 % response noise then gives errors above 50 % in `Z`. Probes at the bearings
/// of the test rotor give 5–15 away from the pinned critical speeds.
pub const FIELD_NOISE_GAIN: f64 = 50.0;

/// The bearings' added masses summed per direction ([`MassSum`](crate::field::MassSum)) are a
/// warning beyond this many standard deviations (and [`FIELD_MASS_SUM_FRACTION`]): normal
/// noise passes 3σ with probability 0.27 % per direction.
pub const FIELD_MASS_SUM_SIGMAS: f64 = 3.0;

/// ... and above this fraction of the rotor's modelled translational mass. Below it a sum is
/// what a careful model's mass error, a fluid film's or a seal's added mass, or the speed trend
/// of a fluid film's stiffness give: the test rotor's speed-dependent bearings (stiffening
/// 10–20 % over the speeds) sum to −6.7 ± 1.5 kg in x and −7.6 ± 2.8 kg in y, 11–13 % of its
/// 58.3 kg, where a mistyped disk mass gives sums of 100 % and more
/// ([`MassSum`](crate::field::MassSum)).
pub const FIELD_MASS_SUM_FRACTION: f64 = 0.25;

/// Largest accepted ratio of the extreme diagonal entries of `R` in the column-scaled QR of the
/// field least-squares system: above it the probes do not determine the unknowns at that speed.
pub const FIELD_LS_RANK: f64 = 1e12;

/// Two imbalance force vectors are proportional when `|⟨f¹, f²⟩| / (‖f¹‖ ‖f²‖)` exceeds
/// `1 − FIELD_DEPENDENT_TESTS` (rounding of the forces is ~1e-16; any real second plane or angle
/// is far below).
pub const FIELD_DEPENDENT_TESTS: f64 = 1e-9;

/// The residuals of the measured responses' sensitivity columns, `Σ‖s_k‖²/Σ‖b_k‖²`, at most
/// this are rounding (relative residual `1e-10`): no probe is redundant and the model residual
/// cannot be judged against the noise ([`field`](crate::field)).
pub const FIELD_RESIDUAL_ROUNDING: f64 = 1e-20;

/// The model residual of a speed is too large (a warning) when `‖r‖²` exceeds this many times
/// what the stated response noise explains. The ratio is a weighted χ² over its mean: with as
/// few as 2 real degrees of freedom, noise alone passes 10 with probability `e⁻¹⁰ ≈ 5·10⁻⁵`
/// per speed, and a model error three times the noise's residual already gives 10.
pub const FIELD_RESIDUAL_RATIO: f64 = 10.0;

/// A rotor model's `M` and `K` are symmetric ([`RotorModel::new`](crate::field::RotorModel::new))
/// when every `|A_ij − A_ji|` is at most this fraction of the matrix's largest `|A_ij|`: a
/// finite-element model is symmetric up to rounding (1e-16) or to the digits a writer printed
/// (7 significant digits give 5e-8); a transposed block or a typed entry is far above, and a
/// field fit of an asymmetric model gave K off by 22 % and more.
pub const FIELD_SYMMETRY: f64 = 1e-6;

/// A rotor model's mass matrix is positive definite
/// ([`RotorModel::new`](crate::field::RotorModel::new)) when the smallest eigenvalue of its
/// symmetric part exceeds this fraction of the largest: every degree of freedom of a beam or
/// lumped model carries mass or inertia, while the eigenvalues of an indefinite or
/// negative-diagonal `M` are negative, and a massless DOF gives rounding (1e-16) only.
pub const FIELD_MASS_DEFINITE: f64 = 1e-12;

/// Largest magnitude accepted for an entry of `M`, `C` or `K` read from a file (a baseline,
/// in SI units): no machine's coefficient comes near it, and it keeps the products and squares
/// that error bars and `H(ω) = K − ω²M + iωC` form finite (`1e150² = 1e300`).
pub const COEFFICIENT_MAGNITUDE: f64 = 1e150;

/// Largest magnitude accepted for a field test's response phasor or its standard deviation
/// ([`crate::field`], in m): vibration amplitudes are micrometres, and the solve's squares and
/// products of responses (`1e150² = 1e300`) stay finite below it; a value of 1e308 once passed
/// the finite check and was reported as the tests' responses being dependent.
pub const FIELD_RESPONSE_MAGNITUDE: f64 = 1e150;

/// Two records are copies up to rounding ([`DuplicateRecord`](crate::Warning::DuplicateRecord))
/// when every value of their fingerprints (a few samples, extremes, mean, RMS per channel)
/// agrees within this fraction of the channel's peak: a copy written with 8 significant
/// digits differs by at most `5·10⁻⁹`, with 7 by `5·10⁻⁸`; independent records of one test
/// differ by their noise, `10⁻⁴` of the peak and far more.
pub const NEAR_DUPLICATE: f64 = 1e-6;

/// A force line is interference ([`crate::frf::interference`]) when its auto-spectrum is at
/// least this many times the median of its neighbours': a random force's line over the median
/// of 16 neighbours follows `χ²(2n_d)/2n_d` and passes 10 with probability below 1e-7 for
/// `n_d ≥ 2` averages; a real force peak passes it too, but the responses follow it.
pub const INTERFERENCE_RATIO: f64 = 10.0;

/// ... and the smallest multiple coherence of the responses there is below this fraction of its
/// neighbours' median: hum of `R` times a line's force power leaves a coherence near `1/R`
/// where the structure felt none of it; a force the structure feels leaves the coherence as it
/// was.
pub const INTERFERENCE_COHERENCE_DIP: f64 = 0.5;

/// Lines next to an interference line whose force auto-spectrum is still this many times its
/// neighbours' median are the window's spread of the same sine (a Hann window puts a sine
/// between two lines into four) and are left out with it.
pub const INTERFERENCE_SPREAD: f64 = 1.5;

/// Lines left out beyond an interference line's spread on each side: there a sine's leakage
/// (a Hann window's third line: −31 dB, times a hum 30 times the force's line power, is 2 %
/// of it) is within the force's random scatter, so not seen, yet it biases the line.
pub const INTERFERENCE_GUARD: usize = 2;

/// The model check ([`ModelCheck`](crate::identify::ModelCheck)) calls a fit a misfit when
/// the lack-of-fit statistic has an upper-tail probability below this under a right model.
/// 1 % rather than 5 %: the statistic's reference distribution is exact only for independent
/// Gaussian line errors, and correlations between the elements of one line widen its spread;
/// at 1 % a right model stayed under the 1-in-20 rate the check promises (Monte-Carlo,
/// `monte_carlo_right_model_*` in `src/identify/model_check.rs`), while every misfit of those
/// tests lies many decades further out.
pub const MODEL_MISFIT_P: f64 = 0.01;

/// Most iterations of the model check's own fit of the model family (iteratively reweighted
/// least squares per element, see `identify::model_check`); it converges in a few from the
/// estimator's coefficients.
pub const FAMILY_FIT_ITERATIONS: usize = 20;

/// The model check's own fit stops when an element's model changes by less than this,
/// relative to its size (each coefficient's change weighted by its basis function's size in
/// the weighted normal equations): far below any noise the check judges.
pub const FAMILY_FIT_TOLERANCE: f64 = 1e-10;

/// Fewest lines the runs test of the model check's residual signs counts over (its normal
/// approximation wants about ten of each sign); shorter sequences are left out of it.
pub const MIN_RUNS_LINES: usize = 20;

/// Smallest `χ²/expected` of the model check at which runs of residual signs count as a
/// misfit. Below it the residuals are far smaller than the replicates' scatter says the
/// noise is, so that scatter is not the residuals' noise (a multisine cut into Welch
/// segments: leakage inflates the scatter and shapes the residuals alike); a pattern in
/// residuals that small is no misfit of consequence.
pub const RUNS_MIN_RATIO: f64 = 0.5;

/// Lines by which the band-sensitivity refits move each band edge inward
/// ([`Budget`](crate::identify::Budget)): a few lines, enough to move a fit that leans on its
/// edges, few enough to leave a right model's estimate within a fraction of its σ.
pub const BAND_SHIFT_LINES: usize = 3;

/// Smallest pure-error standard deviation the model check
/// ([`ModelCheck`](crate::identify::ModelCheck)) credits at a line, relative to the line's
/// impedance norm `‖H_k‖_F`: replicates that agree better than this (noise-free or nearly
/// noise-free data) leave the model judged at this precision, the level to which the
/// simulator and the fits reproduce an exact model (a direct fit of noise-free records is
/// off by ~1e-7), not at rounding. Any measured noise (16-bit converters give ~1e-5) is above.
pub const MODEL_CHECK_FLOOR: f64 = 1e-6;
// ---- Predicted bias (issue 25, item 8) ----

/// A predicted bias ([`crate::gate::PredictedBias`]) is kept on the result and carried in the
/// error bars above this many standard deviations of the coefficient it biases (named in a
/// warning above [`BIAS_WARN_SIGMAS`], or here already when the user can remove it: impacts
/// cut before the response decayed, `not_decayed`): below it, it
/// widens a 95 % interval by under 12 % (the interval of `N(b, σ)` for `b = σ/2` covers as
/// one of width `1.96 σ · 1.12` about the truth).
pub const BIAS_SIGMAS: f64 = 0.5;

/// A carried bias or noise uncertainty is news, a warning, only above this many random
/// standard deviations of the coefficient it moves: it then makes at least half the variance of
/// that coefficient's combined error bar. Below it, it is budget: carried in the combined
/// error bars (above [`BIAS_SIGMAS`]) and listed in the budget, not warned about.
pub const BIAS_WARN_SIGMAS: f64 = 1.0;

/// A response is decayed when its slowest mode's envelope at the record's end is below this
/// fraction of its start: the truncation of what is left is then predicted no more (its bias
/// is below a thousandth of the coefficients'), and the exponential window that
/// [`crate::Warning::NotDecayed`] names brings the envelope down to it.
pub const DECAYED: f64 = 1e-3;

// ---- Periodic records (issue 25, item 5) ----

/// Normalised autocorrelation of the dominant force above which a record is periodic
/// ([`crate::screening::find_period`]): a steady periodic force gives `1/(1 + 1/SNR)` at its
/// period (0.8 at 6 dB), white or random forcing about `1/√N` at any lag.
pub const PERIODIC_CORRELATION: f64 = 0.8;

/// Fraction of the dominant force's energy between the harmonic lines of the stated period
/// above which it may not fit ([`crate::Warning::PeriodMismatch`], raised when the period the
/// data suggest also halves it): a steady force at 13 dB signal to noise stays below it, a
/// period off by a line's width puts most of the energy there.
pub const PERIOD_MISMATCH: f64 = 0.05;

/// The first period is a start-up transient ([`crate::Warning::StartTransient`]) when its
/// distance from the mean of the later periods is more than this many times what their own
/// scatter predicts: in a steady state the ratio is an F variate about 1 with thousands of
/// degrees of freedom (a few hundred after the anti-alias filter), so 3 is never reached by
/// noise.
pub const START_TRANSIENT: f64 = 3.0;

/// A first period whose distance from the later ones holds less than this fraction of the
/// mean period's energy is steady whatever their scatter (noise-free records): its amplitude
/// is a thousandth of the signal's, below any bias worth a warning.
pub const TRANSIENT_ENERGY: f64 = 1e-6;

// ---- Excitation detection (issue 40, item 2) ----

/// Fraction of a record's force power in one spectral peak ([`crate::excitation::Evidence`]'s
/// `tone`) at and above which a steady force is a stepped sine's pure tone: a sine holds over
/// 0.9999 of its Hann-windowed power within three lines of its peak, and noise at a fraction
/// `ε` of the RMS takes `ε²/(1 + ε²)` of it (0.0025 at 5 %), so only noise at half the tone's
/// RMS comes down to 0.8; a multisine of `K` equal lines holds about `1/K` there (0.024 for
/// 42 lines), a sweep the few lines near its top frequency (0.2 for 5–60 Hz in 1 s).
pub const TONE_FRACTION: f64 = 0.8;

/// Below [`TONE_FRACTION`] and at or above this, a steady force may or may not be a tone (two
/// tones, strong harmonics or noise as strong as the tone): detection says it cannot tell.
pub const TONE_FRACTION_DOUBT: f64 = 0.5;

/// A force is steady when the mean power of its weaker half is at least this fraction of its
/// stronger half's: a sine with at least three quarters of a cycle in each half gives 0.4 or
/// more, a ring-down that decays within the record or a sweep followed by free decay almost 0.
/// A tone that is not steady is not a stepped sine (a lightly damped response to a hit, read
/// with the columns exchanged, holds half its power in one peak).
pub const STEADY_POWER: f64 = 0.25;

/// Rank correlation between frequency and the force's group delay (`sweep` of
/// [`crate::excitation::Evidence`]) at and above which the force is a sweep: its frequencies
/// arrive one after another. Simulated sweeps (5–60 Hz or 20–30 Hz in 1 s, 5–60 Hz in 4 s,
/// 5 % noise) give 0.97 to 1.0; random forcing 0.01; a 42-line random-phase multisine up to
/// 0.37 (the rank correlation of `n` unrelated values has a standard deviation
/// `1/√(n − 1)`, 0.16 here, so 0.9 is 5.5 of them); a hammer hit 0.07.
pub const SWEEP_MONOTONY: f64 = 0.9;

/// Below [`SWEEP_MONOTONY`] and at or above this, the force may or may not be a sweep:
/// detection says it cannot tell.
pub const SWEEP_MONOTONY_DOUBT: f64 = 0.7;

/// Fraction of a record's force energy between the harmonic lines of the period found (its
/// scatter from period to period) at and below which the force repeats: a steady periodic
/// force at the [`PERIODIC_CORRELATION`] threshold (6 dB) scatters 0.2, a sine whose period is
/// not a whole number of samples drifts by up to 0.15 over 48 periods; narrow-band random
/// forcing, which resembles itself one cycle later (autocorrelation 0.95 for a 5 Hz band) but
/// not over many, scatters 0.98.
pub const PERIOD_REPEATS: f64 = 0.5;

/// Above [`PERIOD_REPEATS`] and at or below this, or with an autocorrelation from
/// [`PERIODIC_CORRELATION_DOUBT`] up to [`PERIODIC_CORRELATION`], the force may or may not be
/// periodic: detection says it cannot tell.
pub const PERIOD_REPEATS_DOUBT: f64 = 0.8;

/// Normalised autocorrelation from which, below [`PERIODIC_CORRELATION`], a force that
/// repeats may be periodic at a poor signal to noise ratio (0.6 is 1.8 dB).
pub const PERIODIC_CORRELATION_DOUBT: f64 = 0.6;
