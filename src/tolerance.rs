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

// ---------------------------------------------------------------------------------------------
// Excitation detection and the command-line tool (excitation, bin).
// ---------------------------------------------------------------------------------------------

/// How far the slowest mode of a system decays over the records `bearing-ident simulate`
/// makes when no `--duration` is given (impacts, sweeps): `e^{-16.2} ≈ 9·10⁻⁸`, below `10⁻⁷`
/// of the mode's amplitude, so the whole-record DFT sees no leakage above the noise and the
/// `10⁻⁶` that [`ImpactTest::run_clean`](crate::simulate::ImpactTest::run_clean) requires is
/// met with margin. Record length `16.2 / min(−Re λ)` seconds after the excitation.
pub const SIMULATED_DECAY_NEPERS: f64 = 16.2;
