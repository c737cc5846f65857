//! One path from record files (or records in memory) to a result, as the `identify` command
//! takes it: the files read (ahead, on worker threads), the kind of excitation detected from
//! the records when not given, the estimator, segmentation and window that kind implies
//! (overridable), the Welch segment length chosen from a first fit for random records, the
//! identification (streamed, or all at once for stepped sine) and a dry-structure baseline
//! subtracted. The command-line tool, a campaign of test points and bindings to other languages
//! all call [`Job`], so a record is read and identified the same way whoever asks.
//!
//! | file | what lives there |
//! |---|---|
//! | `mod.rs` | [`Job`], the run |
//! | `outcome.rs` | [`Outcome`] and [`Bearing`]: what a run found |
//! | `timings.rs` | [`Timings`]: wall time per stage of a run |
//! | `options.rs` | [`Options`] and [`WindowChoice`], their defaults and names |
//! | `read.rs` | [`Channels`], [`read_file`], the read-ahead workers |
//! | `geometry.rs` | [`Geometry`]: probe and force planes moved to the bearing plane |
//! | `baseline.rs` | the baseline: a folder of records or a saved JSON result |
//! | `json.rs` | the JSON of a run, as `identify --json` prints it (feature `json`) |
//!
//! ```
//! use bearing_ident::Choice;
//! use bearing_ident::job::{Channels, Job, Options};
//! use bearing_ident::simulate::{ImpactTest, seed_rig};
//! let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
//! let outcome = Job::new(Options::new(8.0, 49.0), Channels::default()).run_records(records)?;
//! assert_eq!(outcome.excitation().name(), "impact"); // detected
//! assert_eq!(outcome.files().len(), 4);
//! let k = outcome.identification().coefficients().stiffness()[(0, 0)];
//! assert!((k / 146.3e3 - 1.0).abs() < 1e-6);
//! # Ok::<(), bearing_ident::Error>(())
//! ```

mod baseline;
mod geometry;
#[cfg(feature = "json")]
mod json;
mod options;
mod outcome;
mod read;
mod timings;

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

pub use geometry::Geometry;
#[cfg(feature = "json")]
pub use json::{Facts, json};
pub use options::{Options, WindowChoice, parse_band};
pub use outcome::{Bearing, Outcome};
pub use read::{Channels, is_tdms, is_uff, read_file, read_first, response_columns};
pub use timings::Timings;

use crate::Method;
use crate::error::{Error, Result, Warning};
use crate::excitation::{
    Evidence, Excitation, IMPACT_CREST_FACTOR, WelchChoice, choose_with_spectra, crest_factor,
    deciding_record, response_crest_factor,
};
use crate::frf::Assignment;
use crate::gate::FitGate;
use crate::identify::{Identification, Identifier, NonConvergence, Screening, Spectra};
use crate::records::Record;
use crate::spectra::{ForceGate, Segmentation};
use read::ReadAhead;

/// What a [`Job`] tells its observer while it reads files ([`Job::run_files_with`]).
#[derive(Debug, Clone, Copy)]
#[non_exhaustive]
pub enum Progress<'a> {
    /// File `index` of `total` is about to be waited for.
    Reading {
        /// Index in the file list.
        index: usize,
        /// Files in all.
        total: usize,
        /// The file.
        path: &'a Path,
    },
    /// File `index` of `total` is in.
    Read {
        /// Index in the file list.
        index: usize,
        /// Files in all.
        total: usize,
    },
}

/// An identification to run: the options, as the `identify` command takes them, and where the
/// forces and responses are in the files. Run it on files ([`Job::run_files`]) or on records
/// in memory ([`Job::run_records`]).
#[derive(Debug, Clone)]
pub struct Job {
    options: Options,
    channels: Channels,
}

/// Where the records come from: the first file's (read on the calling thread) followed by the
/// others, parsed ahead on worker threads; or all of them at hand.
enum Source<'a> {
    Streamed {
        first: Vec<Record>,
        ahead: ReadAhead,
        paths: &'a [PathBuf],
    },
    Read(Vec<Record>),
}

/// What the identification starts from: the records, or, once the Welch choice has
/// transformed them at the length it chose, their spectra (and their labels).
enum Start<'a> {
    Records(Source<'a>),
    Transformed {
        spectra: Box<Spectra>,
        labels: Vec<String>,
        warnings: Vec<Warning>,
    },
}

impl Job {
    /// A job with `options`, reading files by `channels`.
    pub fn new(options: Options, channels: Channels) -> Self {
        Self { options, channels }
    }

    /// The options.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// The channels.
    pub fn channels(&self) -> &Channels {
        &self.channels
    }

    /// Identifies the records of `files` (CSV: one record each; Universal Files: one per load
    /// case), in the order given: streamed one file at a time (memory holds one record plus
    /// the band-line spectra, however many files), all together for stepped sine or when the
    /// Welch length is chosen from a first fit.
    ///
    /// # Errors
    /// [`Error::NoRecords`] for no files; [`Error::InvalidOption`] for a channel named twice
    /// ([`Channels::check`]), before any file is read; the readers' errors naming the file;
    /// those of [`Job::run_records`].
    pub fn run_files(&self, files: &[PathBuf]) -> Result<Outcome> {
        self.run_files_with(files, |_| {})
    }

    /// [`Job::run_files`], telling `observe` of each file waited for and read (a progress bar).
    ///
    /// # Errors
    /// As [`Job::run_files`].
    pub fn run_files_with(
        &self,
        files: &[PathBuf],
        mut observe: impl FnMut(Progress<'_>),
    ) -> Result<Outcome> {
        let Some(first_path) = files.first() else {
            return Err(Error::NoRecords);
        };
        self.channels.check()?;
        let start = Instant::now();
        std::thread::scope(|scope| {
            // The files after the first are parsed on worker threads from the start, while
            // this thread reads the first and settles the settings.
            let ahead = ReadAhead::spawn(scope, files, &self.channels);
            let first = read_file(first_path, &self.channels)?;
            let reading = start.elapsed();
            let source = Source::Streamed {
                first,
                ahead,
                paths: files,
            };
            self.run(source, start, reading, &mut observe)
        })
    }

    /// Identifies `records` (at least one) as [`Job::run_files`] identifies files: the same
    /// geometry ([`Channels::geometry`]), detection, settings, Welch choice and baseline.
    ///
    /// # Errors
    /// [`Error::NoRecords`] for none; [`Error::InvalidOption`] for options that do not fit the
    /// records (periodic records without a period, a period longer than the records); the
    /// errors of [`Identifier::identify_stream`], [`Identifier::identify_stepped_sine`] and
    /// [`crate::excitation::choose_welch`]; a baseline's errors.
    pub fn run_records(&self, records: Vec<Record>) -> Result<Outcome> {
        if records.is_empty() {
            return Err(Error::NoRecords);
        }
        self.check_conditions()?;
        // Records in memory are moved to the bearing plane as files are.
        let records = match &self.channels.geometry {
            Some(g) => records
                .into_iter()
                .map(|r| g.apply(r))
                .collect::<Result<_>>()?,
            None => records,
        };
        self.run(
            Source::Read(records),
            Instant::now(),
            Duration::ZERO,
            &mut |_| {},
        )
    }

    /// The kind of excitation of records whose first is `first`, with the crest factor of the
    /// record that decided it: the one given, or the one the first record with a force says
    /// ([`Excitation::from_record`]), reading `rest` only as far as that record. Also whether
    /// it was detected.
    ///
    /// # Errors
    /// The errors of `rest`; [`Error::DeadChannel`] if no record has a force;
    /// [`Error::UnclearExcitation`] when that record's force reads as more than one kind.
    pub fn excitation<'r>(
        &self,
        first: &'r Record,
        rest: impl Iterator<Item = Result<Cow<'r, Record>>>,
    ) -> Result<(Excitation, f64, bool)> {
        match self.options.excitation {
            Some(kind) => Ok((kind, crest_factor(first), false)),
            None => {
                // The first record's evidence holds its crest factor: when that is not 0
                // (a force), the first record decides, as `deciding_record` would say.
                let evidence = Evidence::of(first);
                if evidence.crest_factor > 0.0 {
                    let kind = Excitation::from_evidence(first, evidence)?;
                    return Ok((kind, evidence.crest_factor, true));
                }
                let deciding =
                    deciding_record(std::iter::once(Ok(Cow::Borrowed(first))).chain(rest))?;
                let evidence = Evidence::of(&deciding);
                let kind = Excitation::from_evidence(&deciding, evidence)?;
                Ok((kind, evidence.crest_factor, true))
            }
        }
    }

    /// The run, from a source of records, the clock started at `start` and `reading` spent
    /// reading already.
    fn run(
        &self,
        source: Source<'_>,
        start: Instant,
        mut reading: Duration,
        observe: &mut dyn FnMut(Progress<'_>),
    ) -> Result<Outcome> {
        let mut timings = Timings::default();
        let detect_start = Instant::now();
        let first = match &source {
            Source::Streamed { first, .. } | Source::Read(first) => &first[0],
        };
        let (excitation, crest, detected) = match &source {
            // A flat force (a hammer hit that did not register) says nothing of the
            // excitation: the first record with a force decides, reading no further.
            Source::Streamed { paths, .. } => self.excitation(
                first,
                paths[1..]
                    .iter()
                    .map(|path| read_first(path, &self.channels).map(Cow::Owned)),
            )?,
            Source::Read(records) => {
                self.excitation(first, records[1..].iter().map(|r| Ok(Cow::Borrowed(r))))?
            }
        };
        let sample_rate = first.sample_rate();
        // Forces read as random whose responses look like a hammer's: the columns may be
        // exchanged, the likely cause if the run then fails. The responses' crest factor is
        // read only then, from the first record kept for it (a clone shares its samples).
        let suspect = (detected && excitation == Excitation::Random).then(|| first.clone());
        let swapped = |e: Error| {
            let fails = matches!(
                e,
                Error::TooFewLines { .. }
                    | Error::NotConverged { .. }
                    | Error::RankDeficient { .. }
                    | Error::Singular { .. }
                    | Error::SingularFit { .. }
            );
            match &suspect {
                Some(record) if fails => match response_crest_factor(record) {
                    response_crest if response_crest >= IMPACT_CREST_FACTOR => {
                        Error::LooksSwapped {
                            failure: Box::new(e),
                            force_crest: crest,
                            response_crest,
                        }
                    }
                    _ => e,
                },
                _ => e,
            }
        };
        let (identifier, segment_len) = self.identifier(excitation, first).map_err(swapped)?;
        timings.detect = detect_start.elapsed();
        let welch_start = Instant::now();
        let read_before = reading;
        let (identifier, segment_len, welch_choice, start_from) = self
            .welch(identifier, segment_len, excitation, source, &mut reading)
            .map_err(swapped)?;
        // The spectra the choice keeps are the identification's: counted in its stages.
        let kept = match &start_from {
            Start::Transformed { spectra, .. } => spectra.elapsed(),
            Start::Records(_) => Duration::ZERO,
        };
        timings.welch_choice = welch_start
            .elapsed()
            .saturating_sub(reading - read_before)
            .saturating_sub(kept);
        let mut files = Vec::new();
        let identification = identify(
            &identifier,
            excitation,
            self.options.step_tolerance_hz,
            start_from,
            &mut reading,
            &mut files,
            observe,
        )
        .map_err(swapped)?;
        let baseline_start = Instant::now();
        let bearing = match &self.options.baseline {
            Some(path) => Some(self.bearing(&identification, &identifier, excitation, path)?),
            None => None,
        };
        timings.baseline = baseline_start.elapsed();
        timings.read = reading;
        timings.compute = start.elapsed().saturating_sub(reading);
        timings.identification = identification.timings();
        let mut outcome = Outcome {
            identification,
            identifier,
            files,
            excitation,
            detected,
            crest_factor: crest,
            segment_len,
            welch_choice,
            sample_rate,
            timings,
            bearing,
            conditions: self.options.conditions,
            dimensionless: None,
            stability: None,
            synchronous: None,
        };
        outcome.rotor()?;
        Ok(outcome)
    }

    /// The operating conditions checked: each finite and positive, and a clearance only
    /// with the load and speed that the dimensionless coefficients it asks for need.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the option at fault.
    fn check_conditions(&self) -> Result<()> {
        let c = self.options.conditions.check()?;
        if c.clearance().is_some() {
            c.needed_load("dimensionless coefficients")?;
            c.needed_speed("dimensionless coefficients")?;
        }
        Ok(())
    }

    /// The identifier for `excitation`, from the first record and the options, and the
    /// segment length, if the records are cut. The excitation's defaults are the library's
    /// ([`Excitation::estimator`], [`Excitation::segmentation`], [`Excitation::window`],
    /// [`Excitation::checks`]); the options' estimator, segment length and window override
    /// them.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for periodic records without a period or with one that does
    /// not fit the records; [`ForceGate::new`]'s errors.
    pub fn identifier(
        &self,
        excitation: Excitation,
        first: &Record,
    ) -> Result<(Identifier, Option<usize>)> {
        let o = &self.options;
        let estimator = excitation.estimator(o.estimator);
        let segmentation = match excitation.segmentation(estimator, first, o.period_s) {
            Ok(Segmentation::Welch { len }) => Segmentation::Welch {
                len: o.nperseg.unwrap_or(len),
            },
            Ok(segmentation) => segmentation,
            Err(Error::InvalidParameter {
                name: crate::Parameter::Period,
                ..
            }) => {
                return Err(Error::InvalidOption {
                    option: "period",
                    message: match o.period_s {
                        None => "--excitation periodic: the first record's force does not \
                                 repeat within half its length; give --period SECONDS"
                            .to_string(),
                        Some(period) => format!(
                            "--period {period}: {} samples; expected 8 samples up to the record \
                             length",
                            (period * first.sample_rate()).round()
                        ),
                    },
                });
            }
            Err(e) => return Err(e),
        };
        let segment_s = match segmentation {
            Segmentation::Welch { len } | Segmentation::Periods { len } => {
                len as f64 / first.sample_rate()
            }
            _ => first.duration(),
        };
        let window = match o.window {
            None => excitation.window(),
            Some(w) => w.window(segment_s),
        };
        let mut identifier = Identifier::new(o.band.0, o.band.1)
            .method(o.method)
            .estimator(estimator)
            .segmentation(segmentation)
            .window(window)
            .tolerance(o.tolerance)
            .max_iterations(o.max_iterations)
            .min_coherence(o.min_coherence)
            .drop_periods(o.drop_periods)
            .fit_gate(FitGate { min_r2: o.min_r2 })
            .uncertainty(o.uncertainty())
            .force_noise(o.force_noise)
            .model(o.model)
            .on_non_convergence(if o.allow_unconverged {
                NonConvergence::Warn
            } else {
                NonConvergence::Fail
            });
        if let Some(open) = o.force_gate_s {
            identifier = identifier.force_gate(ForceGate::new(open, open / 5.0)?);
        }
        // Channels by the names of the files' columns (or the defaults for as many DOFs).
        let names = if self.channels.csv.forces.len() == first.dofs() {
            self.channels.csv.clone()
        } else {
            crate::io::CsvLayout::for_dofs(first.dofs())
        };
        if let Some(spec) = &o.calibration {
            identifier = identifier.calibration(crate::identify::Calibration::parse(
                spec,
                &names.forces,
                &names.displacements,
            )?);
        }
        let mut transfers = o.channel_transfers.clone();
        if let Some(spec) = &o.delay {
            transfers = transfers.parse_delays(spec, &names.forces, &names.displacements)?;
        }
        if let Some(spec) = &o.highpass {
            transfers = transfers.parse_high_passes(spec, &names.forces, &names.displacements)?;
        }
        identifier = identifier.channel_transfers(transfers);
        // Screening on every excitation; the double-hit check only for impacts.
        let checks = excitation.checks();
        identifier = identifier.screening(if o.reject_bad_records {
            Screening::Reject(checks)
        } else {
            Screening::Warn(checks)
        });
        let segment_len = match segmentation {
            Segmentation::Welch { len } | Segmentation::Periods { len } => Some(len),
            _ => None,
        };
        Ok((identifier, segment_len))
    }

    /// For random excitation cut into Welch segments with no length given: every record
    /// gathered (the files still to come taken from the workers, `reading` gathering the
    /// wait), a first fit ([`choose_welch`](crate::excitation::choose_welch), by IVF), and the
    /// identifier with the chosen length, with the records' spectra at that length (the first
    /// fit's when the choice keeps its length; the records screened once); otherwise
    /// everything as it was, and no choice.
    fn welch<'a>(
        &self,
        identifier: Identifier,
        segment_len: Option<usize>,
        excitation: Excitation,
        source: Source<'a>,
        reading: &mut Duration,
    ) -> Result<(Identifier, Option<usize>, Option<WelchChoice>, Start<'a>)> {
        // Random records are cut into Welch segments unless paired sets took whole records.
        let needed = excitation == Excitation::Random
            && self.options.nperseg.is_none()
            && segment_len.is_some();
        if !needed {
            return Ok((identifier, segment_len, None, Start::Records(source)));
        }
        let records = match source {
            Source::Read(records) => records,
            Source::Streamed {
                mut first, ahead, ..
            } => {
                let t = Instant::now();
                for file in ahead {
                    first.extend(file?);
                }
                *reading += t.elapsed();
                first
            }
        };
        // The first fit is for the modes only: IVF and its own standard deviations, on the
        // spectra the identification takes at the default length.
        let (choice, spectra) = choose_with_spectra(&records, &identifier, Method::Ivf)?;
        // The identification at the length chosen: on the first fit's spectra when it kept
        // the default, else on the records cut again (their screening kept).
        let len = choice.nperseg;
        let spectra = if segment_len == Some(len) {
            spectra
        } else {
            spectra.welch_len(&records, len)?
        };
        let start = Start::Transformed {
            spectra: Box::new(spectra),
            labels: records.iter().map(|r| r.label().to_owned()).collect(),
            warnings: read_warnings(&records),
        };
        let identifier = identifier.segmentation(Segmentation::Welch { len });
        Ok((identifier, Some(len), Some(choice), start))
    }
}

/// Identifies the records of `start` with `identifier`: streamed as they arrive, or all
/// together for a stepped-sine test, or from the spectra the Welch choice kept; the labels of
/// the records pushed onto `files`.
fn identify(
    identifier: &Identifier,
    excitation: Excitation,
    step_tolerance_hz: f64,
    start: Start<'_>,
    reading: &mut Duration,
    files: &mut Vec<String>,
    observe: &mut dyn FnMut(Progress<'_>),
) -> Result<Identification> {
    let source = match start {
        Start::Transformed {
            spectra,
            labels,
            warnings,
        } => {
            files.extend(labels);
            return Ok(spectra.finish()?.with_read_warnings(warnings));
        }
        Start::Records(source) => source,
    };
    let (first, mut ahead, paths) = match source {
        Source::Read(records) => {
            files.extend(records.iter().map(|r| r.label().to_owned()));
            let warnings = read_warnings(&records);
            return Ok(identify_records(
                identifier,
                excitation,
                step_tolerance_hz,
                records.into_iter().map(Ok),
            )?
            .with_read_warnings(warnings));
        }
        Source::Streamed {
            first,
            ahead,
            paths,
        } => (first, ahead, paths),
    };
    let total = paths.len();
    observe(Progress::Read { index: 0, total });
    // The first file is read already (a Universal File may hold several records, one per load
    // case); the others are taken in order, each once.
    let rest = std::iter::from_fn(|| {
        let t = Instant::now();
        let index = ahead.position();
        if let Some(path) = paths.get(index) {
            observe(Progress::Reading { index, total, path });
        }
        let file = ahead.next()?;
        observe(Progress::Read { index, total });
        *reading += t.elapsed();
        Some(match file {
            Ok(r) => r.into_iter().map(Ok).collect(),
            Err(e) => vec![Err(e)],
        })
    })
    .flatten();
    let mut warnings = Vec::new();
    let records = first.into_iter().map(Ok).chain(rest).inspect(|r| {
        if let Ok(r) = r {
            files.push(r.label().to_owned());
            warnings.extend_from_slice(r.warnings());
        }
    });
    let identification = identify_records(identifier, excitation, step_tolerance_hz, records)?;
    Ok(identification.with_read_warnings(warnings))
}

/// What the readers of `records` noticed ([`Record::warnings`]), in record order.
fn read_warnings(records: &[Record]) -> Vec<Warning> {
    records.iter().flat_map(|r| r.warnings()).cloned().collect()
}

/// Identifies `records` as they arrive, or all together for a stepped-sine test (each record
/// assigned to its dominant force).
fn identify_records(
    identifier: &Identifier,
    excitation: Excitation,
    step_tolerance_hz: f64,
    records: impl Iterator<Item = Result<Record>>,
) -> Result<Identification> {
    if excitation == Excitation::SteppedSine {
        let records: Vec<Record> = records.collect::<Result<_>>()?;
        let dofs = records.first().ok_or(Error::NoRecords)?.dofs();
        identifier
            .clone()
            .dofs(dofs)
            .assignment(Assignment::DominantForce)
            .identify_stepped_sine(&records, step_tolerance_hz)
    } else {
        identifier.identify_stream(records)
    }
}

#[cfg(test)]
mod tests;
