//! Universal File dataset 58 / 58b: reading other software's files, writing and reading back,
//! and velocity and acceleration records through Universal Files. One test binary.
#![cfg(feature = "uff")]

#[path = "../common/mod.rs"]
mod common;

mod datasets;
mod responses;
mod units;
