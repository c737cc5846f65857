//! The dry-structure baseline of a [`Job`]: a folder of its CSV records, identified with the
//! same settings, or the JSON of an earlier identification read back; subtracted from the
//! system's coefficients.

use std::path::{Path, PathBuf};
use std::time::Duration;

use super::{Bearing, Job, Source, Start, identify, read::ReadAhead, read_file};
use crate::error::{Error, Result};
use crate::excitation::Excitation;
use crate::identify::{Baseline, Identification, Identifier};

impl Job {
    /// `system` less the baseline at `path`: a folder's CSV records identified with
    /// `identifier` as `excitation`, or a saved JSON result.
    pub(super) fn bearing(
        &self,
        system: &Identification,
        identifier: &Identifier,
        excitation: Excitation,
        path: &Path,
    ) -> Result<Bearing> {
        let dry = self.baseline(identifier, excitation, path)?;
        let (coefficients, std_dev) = system.subtract_baseline(dry)?;
        Ok(Bearing {
            coefficients,
            std_dev,
            source: path.display().to_string(),
        })
    }

    /// The dry structure's coefficients from `path`.
    fn baseline(
        &self,
        identifier: &Identifier,
        excitation: Excitation,
        path: &Path,
    ) -> Result<Baseline> {
        let io = |e: std::io::Error| Error::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        };
        if path.is_dir() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(path)
                .map_err(io)?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "csv"))
                .collect();
            files.sort();
            if files.is_empty() {
                return Err(Error::InvalidOption {
                    option: "baseline",
                    message: format!(
                        "--baseline {}: no .csv records in the directory",
                        path.display()
                    ),
                });
            }
            let mut waited = Duration::ZERO;
            let id = std::thread::scope(|scope| {
                let ahead = ReadAhead::spawn(scope, &files, &self.channels);
                let first = read_file(&files[0], &self.channels)?;
                let source = Source::Streamed {
                    first,
                    ahead,
                    paths: &files,
                };
                identify(
                    identifier,
                    excitation,
                    self.options.step_tolerance_hz,
                    Start::Records(source),
                    &mut waited,
                    &mut Vec::new(),
                    &mut |_| {},
                )
            })?;
            return Ok(Baseline::from(&id));
        }
        let within = |e: Error| Error::Baseline {
            path: path.display().to_string(),
            source: Box::new(e),
        };
        // At most the JSON readers' limit (a sparse file or /dev/zero must not fill memory);
        // a file that cannot be read is named as it is, anything else as the baseline's.
        let text = crate::limits::read_json_text(path).map_err(|e| match e {
            Error::Io { .. } => e,
            e => within(e),
        })?;
        from_json(&text).map_err(within)
    }
}

/// A baseline read back from the JSON of an identification.
#[cfg(feature = "json")]
fn from_json(text: &str) -> Result<Baseline> {
    Baseline::from_json(text)
}

/// Without the `json` feature a saved result cannot be read back.
#[cfg(not(feature = "json"))]
fn from_json(_: &str) -> Result<Baseline> {
    Err(Error::InvalidOption {
        option: "baseline",
        message: "a JSON baseline needs the `json` feature; give a folder of records".into(),
    })
}

impl super::Outcome {
    /// Subtracts `baseline` (named `source` in the result) from the system's coefficients,
    /// as [`super::Options::baseline`] would have: [`Outcome::bearing`](super::Outcome::bearing)
    /// then holds the difference, the variances adding. A campaign subtracts another point
    /// this way.
    ///
    /// # Errors
    /// [`Identification::subtract_baseline`]'s: a baseline of other degrees of freedom, band,
    /// lines, estimator or window.
    pub fn subtract_baseline(&mut self, baseline: Baseline, source: &str) -> Result<()> {
        let (coefficients, std_dev) = self.identification.subtract_baseline(baseline)?;
        self.bearing = Some(Bearing {
            coefficients,
            std_dev,
            source: source.to_owned(),
        });
        self.rotor()
    }
}
