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
