//! Nonlinear elements: the nonlinear simulator, the reverse path in the library, and
//! `simulate`/`identify --nonlinear` on the command line. One test binary.

#[path = "../common/mod.rs"]
mod common;

mod cli;
mod cli_simulate;
mod end_to_end;
mod reverse_path;
mod simulate;
