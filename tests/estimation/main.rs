//! The library's linear path against known truth: simulated records of every excitation through
//! screening, spectra, FRF estimators, fits (least squares, IVF, maximum likelihood), error bars,
//! figures and field identification. One test binary; the Monte-Carlo tests are `#[ignore]`d and
//! run in release (`.ci/run`).

#[path = "../common/mod.rs"]
mod common;

mod coverage;
mod errors;
mod estimators;
mod excitations;
mod field;
mod fit_gate;
mod honesty;
mod kinds;
mod ml;
mod ml_records;
mod parallel;
mod plots;
mod properties;
mod quality;
mod recovery;
mod responses;
mod screening;
mod seed_rig;
mod statistics;
mod timings;
mod welch_choice;
mod windows;
