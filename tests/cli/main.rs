//! The `bearing-ident` command-line tool, run as a user runs it: one test binary, a module per
//! command family.
#![cfg(feature = "cli")]

#[path = "../common/mod.rs"]
mod common;

mod campaign;
mod commands;
mod export;
mod field;
mod mat;
mod readme;
mod rotor;
