//! `bearing-ident identify`: its arguments, the settings assembled from them and the
//! excitation ([`Excitation`]), the streamed run over the record files, the dry-structure
//! baseline, and the report, figures and JSON written at the end.

use std::borrow::Cow;
use std::path::PathBuf;
use std::time::Instant;

use bearing_ident::excitation::{Excitation, crest_factor, deciding_crest_factor};
use bearing_ident::gate::FitGate;
use bearing_ident::io::CsvLayout;
use bearing_ident::quality::ImpactChecks;
use bearing_ident::spectra::ForceGate;
use bearing_ident::uff::{UffChannel, UffLayout};
use bearing_ident::{
    Assignment, Error, Estimator, Identification, Identifier, Method, NonConvergence, Record,
    Screening, Segmentation, Uncertainty,
};
use clap::ValueEnum;

use crate::failure::{Failure, invalid};
use crate::output::{emit, write_report};
use crate::parse::{library, parse_band, parse_window, response_columns};
use crate::read::{Layout, ReadAhead, is_uff, read_file, read_record};
use crate::report;

mod baseline;
mod nonlinear;
mod welch;

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum MethodArg {
    Direct,
    Ls,
    Ivf,
    /// Maximum likelihood from IVF; needs `--excitation periodic` (noise from the periods).
    Ml,
}

#[derive(Debug, Clone, Copy, PartialEq, ValueEnum)]
pub enum ExcitationArg {
    /// Decide from the force signals: impacts by their crest factor, periodic records by their
    /// autocorrelation (the period found too), else random.
    Auto,
    /// Impacts: paired sets, whole-record DFT, no window.
    Impact,
    /// Random: MIMO H1 with Welch segments (Hann, 50 % overlap).
    Random,
    /// Periodic or multisine in steady state: MIMO H1 over whole periods (`--period`), no
    /// window, the excited lines only.
    Periodic,
    /// Stepped sine: one drive frequency per record; amplitude and phase at that frequency.
    SteppedSine,
    /// Sine sweep followed by free decay: as impacts (paired sets, whole record).
    Sweep,
}

impl ExcitationArg {
    /// The library's kind; `None` for `auto` (detected from the records).
    fn kind(self) -> Option<Excitation> {
        match self {
            ExcitationArg::Auto => None,
            ExcitationArg::Impact => Some(Excitation::Impact),
            ExcitationArg::Random => Some(Excitation::Random),
            ExcitationArg::Periodic => Some(Excitation::Periodic),
            ExcitationArg::SteppedSine => Some(Excitation::SteppedSine),
            ExcitationArg::Sweep => Some(Excitation::Sweep),
        }
    }
}

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum UncertaintyArg {
    /// Jackknife with at least 3 paired sets or records, else the sandwich.
    Auto,
    None,
    Sandwich,
    Jackknife,
    Bootstrap,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum EstimatorArg {
    Paired,
    H1,
    H2,
    Hv,
}

#[derive(Debug, clap::Args)]
pub struct IdentifyArgs {
    /// Print the result as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Print the wall time of each stage (read, screen, spectra, frf, conditioning, solve,
    /// uncertainty, total) in the table output; the JSON output always carries `timings_ms`.
    #[arg(long)]
    timings: bool,
    /// Fitting method.
    #[arg(long, value_enum, default_value = "ivf")]
    method: MethodArg,
    /// Frequency band LO,HI in Hz (edges inclusive).
    #[arg(long, allow_hyphen_values = true)]
    band: String,
    /// Kind of excitation in the records.
    #[arg(long, value_enum, default_value = "auto")]
    excitation: ExcitationArg,
    /// Override the impedance estimator chosen from the excitation.
    #[arg(long, value_enum)]
    estimator: Option<EstimatorArg>,
    /// Window: `rect`, `hann`, or `exp:END` (exponential on force and response, falling to END,
    /// e.g. 0.01, at the end of each record or segment; the coefficients are corrected
    /// exactly). Default: `rect` for impacts, `hann` for random excitation.
    #[arg(long)]
    window: Option<String>,
    /// Error bars: `auto` is the jackknife over paired sets or records when there are at least
    /// 3 of them, else the first-order sandwich; `bootstrap` draws `--bootstrap-draws`
    /// resamples of the sets or records (seeded by `--seed`).
    #[arg(long, value_enum, default_value = "auto")]
    uncertainty: UncertaintyArg,
    /// Bootstrap resamples.
    #[arg(long, default_value_t = 200)]
    bootstrap_draws: usize,
    /// Seed of the bootstrap's resampling.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Gate the force channels: open for SECONDS from each record's start, then a cosine
    /// taper over a fifth of that; the quiet force after an impact is noise only.
    #[arg(long)]
    force_gate: Option<f64>,
    /// Period of periodic excitation (s), for `--excitation periodic`; found in the records
    /// when not given (and with `--excitation auto`, which recognises periodic records).
    #[arg(long)]
    period: Option<f64>,
    /// Periodic excitation: leave the first N periods of every record out (a start-up
    /// transient; JSON `periods_dropped`).
    #[arg(long, default_value_t = 0)]
    drop_periods: usize,
    /// Drive frequencies closer than this (Hz) are one step of a stepped-sine test.
    #[arg(long, default_value_t = 0.01)]
    step_tolerance: f64,
    /// Leave out the records that screening finds faulty: flat or dead channels, identical
    /// records, clipping, level outliers, double hits (impacts), paired sets far from the
    /// others (they are always reported as warnings).
    #[arg(long, alias = "reject-bad-impacts")]
    reject_bad_records: bool,
    /// Subtract a dry-structure baseline: a directory of its CSV records (identified here with
    /// the same settings) or the JSON result of an earlier `identify --json`. The JSON output
    /// then carries `bearing` (`M`, `C`, `K` and their `*_std`: system − baseline).
    #[arg(long)]
    baseline: Option<PathBuf>,
    /// Add per-line `K(ω) = Re H + ω²M`, `C(ω) = Im H/ω` with error bars (and, for n = 2, the
    /// isotropic effective coefficients) to the output (JSON `per_frequency`).
    #[arg(long)]
    per_frequency: bool,
    /// Drop lines where the multiple coherence of any output is below X (0 ≤ X < 1).
    #[arg(long, default_value_t = 0.0)]
    min_coherence: f64,
    /// Warn (`poor_fit`) when the flexibility r² of an element that carries signal is below X
    /// (X ≤ 1; `-inf` turns the check off).
    #[arg(long, default_value_t = 0.9, allow_negative_numbers = true)]
    min_r2: f64,
    /// Welch segment length for random excitation (default: the largest power of two not above
    /// an eighth of the record).
    #[arg(long)]
    nperseg: Option<usize>,
    /// Force channels, one per degree of freedom. CSV: column names (default `fx,fy`).
    /// Universal Files: `NODE+DIR`/`NODE-DIR` (DIR: X, Y, Z, RX, RY, RZ or 1–6; matches the
    /// response node and signed direction exactly) or `id:TEXT` (the first ID line, trimmed,
    /// equal to TEXT); default: every time history of data type 13.
    #[arg(long, value_delimiter = ',')]
    force: Vec<String>,
    /// Response channels (displacement, or what `--response` says), one per degree of
    /// freedom. CSV: column names (default `x,y`; `vx,vy` for velocity and `ax,ay` for
    /// acceleration, as `simulate --response` writes). Universal Files: as `--force`; default:
    /// every time history of data type 8, 11 or 12.
    #[arg(long, visible_alias = "resp", value_delimiter = ',')]
    disp: Vec<String>,
    /// What the response channels measure: `displacement`, `velocity` or `acceleration`, one
    /// for all or one per degree of freedom (comma list, for mixed rigs). Default:
    /// displacement for CSV; for Universal Files the data type (8, 11, 12) of each channel,
    /// which this overrides. Velocity and acceleration are turned into displacement at the
    /// band lines (X = V/(iω) = A/(−ω²); with `--window exp:…`, iω + a).
    #[arg(long, value_delimiter = ',')]
    response: Vec<bearing_ident::Response>,
    /// Time column (s).
    #[arg(long, default_value = "t")]
    time: String,
    /// Known delay of channels, divided out of their spectra before any average: `NAME=0.25ms`
    /// (units s, ms, us), NAME a `--force`/`--disp` column or `force`/`response` for every
    /// channel of that kind (e.g. a multiplexed acquisition's skew); comma list.
    #[arg(long, value_delimiter = ',')]
    delay: Vec<String>,
    /// Known AC coupling of channels, divided out of their spectra before any average:
    /// `NAME=3Hz` (a first-order high-pass with that corner) or `NAME=3Hz:2` (order 2), NAME as
    /// for `--delay`; comma list.
    #[arg(long, value_delimiter = ',')]
    highpass: Vec<String>,
    /// IVF tolerance on the block-wise relative change.
    #[arg(long, default_value_t = 1e-8)]
    tolerance: f64,
    /// IVF iteration limit.
    #[arg(long, default_value_t = 50)]
    max_iterations: usize,
    /// Report a non-converged IVF with a warning instead of failing with `not_converged`.
    #[arg(long)]
    allow_unconverged: bool,
    /// Write figures (SVG) and a static `index.html` report into DIR. The record figure
    /// draws a few of the first 32 files (read again for it).
    #[arg(long, value_name = "DIR")]
    plot: Option<PathBuf>,
    /// Identify nonlinear terms with M, C, K by the reverse path (random or multisine
    /// records): a comma list of `coulomb`, `coulomb-planar`, `cubic`, `quadratic-damping`.
    #[arg(long, value_name = "TERMS")]
    nonlinear: Option<String>,
    /// With `--nonlinear`: velocities through an ideal low-pass at HZ instead of the default
    /// Wiener gain from the displacement's noise floor.
    #[arg(long, value_name = "HZ")]
    vel_cutoff: Option<f64>,
    #[command(flatten)]
    export: crate::export::ExportArgs,
    /// Record files: CSV (one record each), or Universal Files `.uff`/`.unv` (a record per load
    /// case of their dataset 58 time histories: force channels of data type 13, responses of
    /// data types 8, 11, 12 (displacement, velocity, acceleration), each sorted by direction,
    /// then node; or the channels `--force`, `--disp` name; `--time` does not apply to them).
    #[arg(required = true)]
    files: Vec<PathBuf>,
}

fn layout(args: &IdentifyArgs) -> Result<Layout, Failure> {
    let defaults = CsvLayout::default();
    let pick = |given: &[String], default: Vec<String>| {
        if given.is_empty() {
            default
        } else {
            given.to_vec()
        }
    };
    let csv = CsvLayout {
        time: args.time.clone(),
        forces: pick(&args.force, defaults.forces),
        displacements: pick(
            &args.disp,
            response_columns(&defaults.displacements, &args.response),
        ),
    };
    if csv.forces.len() != csv.displacements.len() {
        return Err(invalid(format!(
            "--force names {} columns and --disp {}: one of each per degree of freedom",
            csv.forces.len(),
            csv.displacements.len()
        )));
    }
    let uff = if args.files.iter().any(|f| is_uff(f)) {
        let channels = |given: &[String], option: &str| {
            given
                .iter()
                .map(|c| {
                    c.parse::<UffChannel>()
                        .map_err(|e| invalid(format!("--{option}: {e}")))
                })
                .collect::<Result<Vec<_>, Failure>>()
        };
        UffLayout {
            forces: channels(&args.force, "force")?,
            responses: channels(&args.disp, "disp")?,
            kinds: args.response.clone(),
        }
    } else {
        UffLayout::default()
    };
    if !args.response.is_empty()
        && args.response.len() != 1
        && args.response.len() != csv.displacements.len()
        && !args.files.iter().all(|f| is_uff(f))
    {
        return Err(invalid(format!(
            "--response names {} kinds for {} response columns: give one for all or one per \
             degree of freedom",
            args.response.len(),
            csv.displacements.len()
        )));
    }
    Ok(Layout {
        csv,
        uff,
        responses: args.response.clone(),
    })
}

/// The identifier and its processing for `excitation`, from the first record and the options;
/// also the Welch segment length, if any. The excitation's defaults are the library's
/// ([`Excitation::estimator`], [`Excitation::segmentation`], [`Excitation::window`],
/// [`Excitation::checks`]); `--estimator`, `--nperseg` and `--window` override them.
fn settings(
    args: &IdentifyArgs,
    excitation: Excitation,
    first: &Record,
) -> Result<(Identifier, Option<usize>), Failure> {
    let (lo, hi) = parse_band(&args.band)?;
    let chosen: Option<Estimator> = args.estimator.map(library).transpose()?;
    let estimator = excitation.estimator(chosen);
    let segmentation = match excitation.segmentation(estimator, first, args.period) {
        Ok(Segmentation::Welch { len }) => Segmentation::Welch {
            len: args.nperseg.unwrap_or(len),
        },
        Ok(segmentation) => segmentation,
        Err(Error::InvalidParameter { name: "period", .. }) => {
            return Err(invalid(match args.period {
                None => "--excitation periodic needs --period SECONDS".to_string(),
                Some(period) => format!(
                    "--period {period}: {} samples; expected 8 samples up to the record length",
                    (period * first.sample_rate()).round()
                ),
            }));
        }
        Err(e) => return Err(e.into()),
    };
    let segment_s = match segmentation {
        Segmentation::Welch { len } | Segmentation::Periods { len } => {
            len as f64 / first.sample_rate()
        }
        _ => first.duration(),
    };
    let window = match args.window.as_deref() {
        None => excitation.window(),
        Some(w) => parse_window(w, segment_s)?,
    };
    let method: Method = library(args.method)?;
    let mut identifier = Identifier::new(lo, hi)
        .method(method)
        .estimator(estimator)
        .segmentation(segmentation)
        .window(window)
        .tolerance(args.tolerance)
        .max_iterations(args.max_iterations)
        .min_coherence(args.min_coherence)
        .drop_periods(args.drop_periods)
        .fit_gate(FitGate {
            min_r2: args.min_r2,
        })
        .uncertainty(match library(args.uncertainty)? {
            Uncertainty::Bootstrap { .. } => Uncertainty::Bootstrap {
                replicates: args.bootstrap_draws,
                seed: args.seed,
            },
            uncertainty => uncertainty,
        })
        .on_non_convergence(if args.allow_unconverged {
            NonConvergence::Warn
        } else {
            NonConvergence::Fail
        });
    if let Some(open) = args.force_gate {
        identifier = identifier.force_gate(ForceGate::new(open, open / 5.0)?);
    }
    let names = layout(args)?.csv;
    identifier = identifier.channel_transfers(crate::channels::transfers(
        &args.delay,
        &args.highpass,
        &names.forces,
        &names.displacements,
    )?);
    // Screening on every excitation; the double-hit check only for impacts.
    let checks = excitation.checks();
    identifier = identifier.screening(if args.reject_bad_records {
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

/// The records to identify: the first file's (read on this thread) followed by the others,
/// parsed ahead on worker threads; or every file's, read already (for the Welch choice).
pub(crate) enum Files {
    Streamed {
        first: Vec<Record>,
        ahead: ReadAhead,
    },
    Read(Vec<Record>),
}

/// Identifies the records of `files` (read from `paths`): streamed one at a time (memory holds one record plus
/// band-line spectra, however many files), or all together for a stepped-sine test.
/// `reading` gathers the time spent waiting for files.
fn run(
    args: &IdentifyArgs,
    identifier: &Identifier,
    excitation: Excitation,
    paths: &[PathBuf],
    files: Files,
    reading: &mut std::time::Duration,
    labels: &mut Vec<String>,
) -> Result<Identification, Failure> {
    let (first, mut ahead) = match files {
        Files::Read(records) => {
            labels.extend(records.iter().map(|r| r.label().to_owned()));
            let records = records.into_iter().map(Ok);
            return identify_records(args, identifier, excitation, records);
        }
        Files::Streamed { first, ahead } => (first, ahead),
    };
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(paths.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    // The first file is read already (a Universal File may hold several records, one per
    // load case); the others are taken in order, each once.
    bar.inc(1);
    let rest = std::iter::from_fn(|| {
        let t = Instant::now();
        if let Some(path) = paths.get(ahead.position()) {
            bar.set_message(path.display().to_string());
        }
        let file = ahead.next()?;
        bar.inc(1);
        *reading += t.elapsed();
        Some(match file {
            Ok(r) => r.into_iter().map(Ok).collect(),
            Err(e) => vec![Err(e)],
        })
    })
    .flatten();
    let records = first.into_iter().map(Ok).chain(rest).inspect(|r| {
        if let Ok(r) = r {
            labels.push(r.label().to_owned());
        }
    });
    identify_records(args, identifier, excitation, records).inspect(|_| bar.finish_and_clear())
}

/// Identifies `records` as they arrive, or all together for a stepped-sine test.
fn identify_records(
    args: &IdentifyArgs,
    identifier: &Identifier,
    excitation: Excitation,
    records: impl Iterator<Item = bearing_ident::Result<Record>>,
) -> Result<Identification, Failure> {
    let id = if excitation == Excitation::SteppedSine {
        let records: Vec<Record> = records.collect::<bearing_ident::Result<_>>()?;
        let dofs = records[0].dofs();
        identifier
            .clone()
            .dofs(dofs)
            .assignment(Assignment::DominantForce)
            .identify_stepped_sine(&records, args.step_tolerance)?
    } else {
        identifier.identify_stream(records)?
    };
    Ok(id)
}

/// Reads the record files and identifies them; the excitation kind is decided from the first
/// record with a force that is not flat (as [`Excitation::detect`] does, reading the files
/// one at a time).
pub fn identify(args: &IdentifyArgs) -> Result<(), Failure> {
    let layout = layout(args)?;
    crate::export::check(&args.export, args.baseline.is_some(), args.per_frequency)?;
    let start = Instant::now();
    std::thread::scope(|scope| {
        // The files after the first are parsed on worker threads from the start, while this
        // thread reads the first and settles the settings (`--nonlinear` reads its own).
        let ahead = args
            .nonlinear
            .is_none()
            .then(|| ReadAhead::spawn(scope, &args.files, &layout));
        identify_files(args, &layout, start, ahead)
    })
}

/// [`identify`] once the workers (if any) are parsing.
fn identify_files(
    args: &IdentifyArgs,
    layout: &Layout,
    start: Instant,
    ahead: Option<ReadAhead>,
) -> Result<(), Failure> {
    let first_file = read_file(&args.files[0], layout)?;
    let first = &first_file[0];
    let crest = if args.excitation == ExcitationArg::Auto {
        // A flat force (a hammer hit that did not register) says nothing of the excitation:
        // the library decides from the first record with a force, reading no further.
        let rest = args.files[1..]
            .iter()
            .map(|path| read_record(path, layout).map(Cow::Owned));
        deciding_crest_factor(std::iter::once(Ok(Cow::Borrowed(first))).chain(rest))?
    } else {
        crest_factor(first)
    };
    let mut reading = start.elapsed();
    let excitation = args
        .excitation
        .kind()
        .unwrap_or_else(|| Excitation::from_record(crest, first));
    let Some(ahead) = ahead else {
        let terms = args
            .nonlinear
            .as_ref()
            .expect("no workers only for --nonlinear");
        return nonlinear::run(args, terms, layout, excitation, first_file);
    };
    nonlinear::linear_only(args)?;
    let (identifier, segment_len) = settings(args, excitation, first)?;
    let sample_rate = first.sample_rate();
    let files = Files::Streamed {
        first: first_file,
        ahead,
    };
    let (identifier, segment_len, welch_choice, files) = welch::choose(
        args,
        identifier,
        segment_len,
        excitation,
        files,
        &mut reading,
    )?;
    // The labels of the records identified: the files, or a file's load cases for a UFF.
    let mut labels = Vec::new();
    let id = run(
        args,
        &identifier,
        excitation,
        &args.files,
        files,
        &mut reading,
        &mut labels,
    )?;
    let compute_ms = (start.elapsed().saturating_sub(reading)).as_secs_f64() * 1e3;
    let bearing = match &args.baseline {
        Some(path) => {
            let dry = baseline::baseline(args, &identifier, excitation, path)?;
            let (b, std) = id.subtract_baseline(dry)?;
            Some((b, std, path.display().to_string()))
        }
        None => None,
    };
    let context = report::Context {
        excitation: excitation.name(),
        excitation_auto: args.excitation == ExcitationArg::Auto,
        crest_factor: crest,
        segment_len,
        welch_choice,
        sample_rate,
        files: labels,
        compute_ms,
        read_ms: reading.as_secs_f64() * 1e3,
        show_timings: args.timings,
        axes: if args.disp.is_empty() {
            CsvLayout::default().displacements
        } else {
            args.disp.clone()
        },
        bearing,
        per_frequency: args.per_frequency.then(|| id.per_frequency()).transpose()?,
    };
    if let Some(dir) = &args.plot {
        // The records were streamed; read a few again for the record figure.
        let records = args
            .files
            .iter()
            .take(PLOTTED_FILES)
            .map(|path| read_record(path, layout))
            .collect::<bearing_ident::Result<Vec<_>>>()?;
        let checks = (excitation == Excitation::Impact).then(ImpactChecks::default);
        write_report(dir, &id, &records, &context, None, checks)?;
    }
    let bearing = context.bearing.as_ref().map(|(b, _, _)| b);
    crate::export::write(&args.export, &id, bearing, args.per_frequency)?;
    emit(&id, &context, None, args.json)
}

/// Files read again for the record figure of `identify --plot`.
const PLOTTED_FILES: usize = 32;

#[cfg(test)]
mod tests {
    use super::*;

    /// `--excitation` spells every kind as the library's [`Excitation::name`] does.
    #[test]
    fn excitation_values_are_the_library_names() {
        let mut kinds = Vec::new();
        for v in ExcitationArg::value_variants() {
            let name = v
                .to_possible_value()
                .expect("a value")
                .get_name()
                .to_owned();
            match v.kind() {
                Some(kind) => {
                    assert_eq!(name, kind.name());
                    assert_eq!(name.parse::<Excitation>().expect("parses"), kind);
                    kinds.push(kind);
                }
                None => assert_eq!(name, "auto"),
            }
        }
        assert_eq!(kinds, Excitation::ALL);
    }

    /// Every `--method`, `--estimator` and `--uncertainty` value is a name the library parses,
    /// and each names a different choice.
    #[test]
    fn option_values_parse_as_library_names() {
        let methods: Vec<Method> = MethodArg::value_variants()
            .iter()
            .map(|&v| library(v).ok().expect("a method"))
            .collect();
        assert_eq!(
            methods,
            [
                Method::Direct,
                Method::LeastSquares,
                Method::Ivf,
                Method::Ml
            ]
        );
        let estimators: Vec<Estimator> = EstimatorArg::value_variants()
            .iter()
            .map(|&v| library(v).ok().expect("an estimator"))
            .collect();
        assert_eq!(
            estimators,
            [
                Estimator::PairedSets,
                Estimator::H1,
                Estimator::H2,
                Estimator::Hv
            ]
        );
        let uncertainties: Vec<Uncertainty> = UncertaintyArg::value_variants()
            .iter()
            .map(|&v| library(v).ok().expect("an uncertainty"))
            .collect();
        assert_eq!(uncertainties.len(), 5);
        assert!(uncertainties.contains(&Uncertainty::BOOTSTRAP));
    }
}
