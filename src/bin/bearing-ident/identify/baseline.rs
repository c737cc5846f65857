//! `identify --baseline`: the dry structure's coefficients, identified from a directory of
//! CSV records with the same settings or read back from an earlier `identify --json` result.

use std::path::PathBuf;

use bearing_ident::excitation::Excitation;
use bearing_ident::{Baseline, Identifier};

use super::{Files, IdentifyArgs, layout, run};
use crate::failure::{Failure, invalid};
use crate::read::{ReadAhead, read_file};

/// The dry-structure baseline: identified from a directory of CSV records with the same
/// settings, or read back from an earlier `identify --json` result.
pub(super) fn baseline(
    args: &IdentifyArgs,
    identifier: &Identifier,
    excitation: Excitation,
    path: &std::path::Path,
) -> Result<Baseline, Failure> {
    let io_failure = |e: std::io::Error| Failure {
        kind: "io_error",
        message: format!("{}: {e}", path.display()),
    };
    if path.is_dir() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(io_failure)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "csv"))
            .collect();
        files.sort();
        if files.is_empty() {
            return Err(invalid(format!(
                "--baseline {}: no .csv records in the directory",
                path.display()
            )));
        }
        let layout = layout(args)?;
        let id = std::thread::scope(|scope| {
            let ahead = ReadAhead::spawn(scope, &files, &layout);
            let first = read_file(&files[0], &layout)?;
            let mut reading = std::time::Duration::ZERO;
            let streamed = Files::Streamed { first, ahead };
            run(
                args,
                identifier,
                excitation,
                &files,
                streamed,
                &mut reading,
                &mut Vec::new(),
            )
        })?;
        return Ok(Baseline::from(&id));
    }
    // Read at most the limit (a sparse file or /dev/zero must not fill memory).
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(
        &mut std::io::Read::take(
            std::fs::File::open(path).map_err(io_failure)?,
            MAX_BASELINE_BYTES + 1,
        ),
        &mut bytes,
    )
    .map_err(io_failure)?;
    if bytes.len() as u64 > MAX_BASELINE_BYTES {
        return Err(Failure {
            kind: "too_large",
            message: format!(
                "--baseline {}: longer than the limit of {MAX_BASELINE_BYTES} bytes for a JSON result",
                path.display()
            ),
        });
    }
    let text = String::from_utf8_lossy(&bytes);
    Baseline::from_json(&text).map_err(|e| Failure {
        kind: e.kind(),
        message: format!("--baseline {}: {e}", path.display()),
    })
}

/// Longest baseline JSON file read (16 MiB; a result is a few kilobytes).
const MAX_BASELINE_BYTES: u64 = 1 << 24;
