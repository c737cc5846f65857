//! The record readers under attack: the CSV reader against a reference, bounded byte-fuzzing of
//! every reader, and the inputs fuzzing found. One test binary, with the `csv` feature.
#![cfg(feature = "csv")]

#[path = "../common/mod.rs"]
mod common;

mod csv_reader;
mod fuzz;
mod fuzz_regressions;
#[cfg(feature = "mat")]
mod mat;
#[cfg(feature = "cli")]
mod simulated;
#[cfg(feature = "cli")]
mod tdms;
