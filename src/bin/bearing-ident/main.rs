//! `bearing-ident`: identify bearing force coefficients from CSV records, simulate records, or
//! run the demo. Errors exit with status 2 and one line on stderr naming file, line and column;
//! with `--json` a `{"error": KIND, "message": …}` object is also printed on stdout — argument
//! errors included (`invalid_argument`). Messages quote at most 80 characters of any input.
//! A reader of stdout that goes away early (`… | head -1`) ends the tool quietly with status 0.
//!
//! This file parses the command line and dispatches; each subcommand lives in its own file
//! (`identify.rs`, `demo.rs`, `simulate.rs`, `inspect.rs`, `field.rs`, `campaign.rs`), with the string parsers in `parse.rs`, the
//! failure type and stdout in `failure.rs`, and the table, JSON and figures in `output.rs`
//! and `report.rs`.

mod campaign;
mod channels;
mod demo;
mod export;
mod failure;
mod field;
mod identify;
mod inspect;
mod output;
mod parse;
mod report;
mod simulate;

use std::process::ExitCode;

use bearing_ident::error::{bounded, excerpt};
use clap::{Parser, Subcommand};

use crate::campaign::{CampaignArgs, campaign};
use crate::demo::{DemoArgs, demo};
use crate::failure::{print_err, print_out};
use crate::field::{FieldArgs, field};
use crate::identify::{IdentifyArgs, identify};
use crate::inspect::{InspectArgs, inspect};
use crate::simulate::{SimulateArgs, simulate};

/// Dynamic force coefficients (M, C, K) of bearings, seals and dampers from test records.
#[derive(Debug, Parser)]
#[command(name = "bearing-ident", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Identify M, C, K from CSV records (one file per record) or Universal Files
    /// (`.uff`/`.unv`: a record per load case of their time histories).
    Identify(Box<IdentifyArgs>),
    /// Simulate the 2-DOF test rig of Diaz & San Andrés (1999) and identify it, as the quickstart
    /// example does.
    Demo(DemoArgs),
    /// Simulate records of a given system (linear, or with nonlinear terms) and write them as
    /// CSV files.
    Simulate(Box<SimulateArgs>),
    /// List the dataset 58 / 58b functions of Universal Files (`--json`: every value).
    Inspect(InspectArgs),
    /// Identify the bearings' K(Ω), C(Ω) of a running machine from imbalance responses and a
    /// model of its free rotor (`--rotor ROTOR.json --tests TESTS.json`).
    Field(Box<FieldArgs>),
    /// Identify every test point of a campaign plan (TOML) and tabulate M, C, K against the
    /// test conditions; figures, CSV, JSON and a ROSS table over rotor speed. Exit status 1
    /// when a point failed (after everything is written).
    Campaign(Box<CampaignArgs>),
}

fn main() -> ExitCode {
    // Known before parsing, so that argument errors, too, are JSON when it was asked for.
    let json = std::env::args_os().skip(1).any(|a| a == "--json");
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return argument_error(&e, json),
    };
    let json = match &cli.command {
        Command::Identify(a) => a.json,
        Command::Demo(a) => a.json,
        Command::Simulate(a) => a.json,
        Command::Inspect(a) => a.json,
        Command::Field(a) => a.json,
        Command::Campaign(a) => a.json,
    };
    let outcome = match cli.command {
        Command::Identify(args) => identify(&args),
        Command::Demo(args) => demo(&args),
        Command::Simulate(args) => simulate(&args),
        Command::Inspect(args) => inspect(&args),
        Command::Field(args) => field(&args),
        Command::Campaign(args) => match campaign(&args) {
            Ok(true) => Ok(()),
            // Every point is reported and every output written; the status says one failed.
            Ok(false) => return ExitCode::from(1),
            Err(f) => Err(f),
        },
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        // The reader of stdout went away: nothing more to say, to anyone.
        Err(f) if f.is_broken_pipe() => ExitCode::SUCCESS,
        Err(f) => {
            // Whatever the message quotes: control bytes escaped, no run past 80 characters.
            let message = bounded(&f.message);
            print_err(format_args!("bearing-ident: error: {message}"));
            if json {
                let v = serde_json::json!({ "error": f.kind, "message": message });
                // A closed stdout cannot take the JSON; stderr has the message.
                let _ = print_out(format_args!("{v}\n"));
            }
            ExitCode::from(2)
        }
    }
}

/// Longest message line printed for an argument error (the input in it is quoted by
/// [`excerpt`] already; this bounds the rest).
const MESSAGE_CHARS: usize = 400;

/// Reports an argument error of clap's: help and version as clap prints them; otherwise exit
/// status 2, with `{"error": "invalid_argument", "message": …}` on stdout under `--json` and
/// one line on stderr. The offending input is quoted by at most 80 characters.
fn argument_error(e: &clap::Error, json: bool) -> ExitCode {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        e.exit();
    }
    let rendered = e.render().to_string();
    let mut message = rendered
        .lines()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("invalid arguments")
        .trim_start_matches("error: ")
        .to_owned();
    for kind in [ContextKind::InvalidValue, ContextKind::InvalidArg] {
        if let Some(ContextValue::String(v)) = e.get(kind) {
            message = message.replace(v.as_str(), &excerpt(v));
        }
    }
    // clap lists what is missing on the lines after its first: the message names it.
    if e.kind() == ErrorKind::MissingRequiredArgument
        && let Some(ContextValue::Strings(missing)) = e.get(ContextKind::InvalidArg)
    {
        message = format!("{} {}", message.trim_end(), missing.join(", "));
    }
    let mut message = bounded(&message);
    if let Some((cut, _)) = message.char_indices().nth(MESSAGE_CHARS) {
        message.truncate(cut);
        message.push('…');
    }
    if json {
        let v = serde_json::json!({ "error": "invalid_argument", "message": message });
        let _ = print_out(format_args!("{v}\n"));
    } else if rendered.len() <= 4 * MESSAGE_CHARS {
        // Short enough to print as clap does, with its usage and tips.
        e.exit();
    }
    print_err(format_args!("bearing-ident: error: {message}"));
    ExitCode::from(2)
}
