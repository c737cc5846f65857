//! Every numerical tolerance of the library in one place, each with its reason (in the manner of
//! statrs' `prec`): when two numbers are "equal", when a value is "zero", how far a band edge or
//! a time stamp may stray. A tolerance used by more than one stage lives here and nowhere else.

// ---------------------------------------------------------------------------------------------
// Records, time grids, bands and spectra (records, spectra, frf, stepped, conditioning, solve).
// ---------------------------------------------------------------------------------------------

// ---------------------------------------------------------------------------------------------
// Identification, screening, gates and quality checks (identify, screening, gate, quality).
// ---------------------------------------------------------------------------------------------

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
