//! `bearing-ident`: identify bearing force coefficients from CSV records, simulate records, or
//! run the demo. Errors exit with status 2 and one line on stderr naming file, line and column;
//! with `--json` a `{"error": KIND, "message": …}` object is also printed on stdout — argument
//! errors included (`invalid_argument`). Messages quote at most 80 characters of any input.

mod report;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use bearing_ident::error::excerpt;
use bearing_ident::gate::FitGate;
use bearing_ident::io::{self, CsvLayout};
use bearing_ident::quality::ImpactChecks;
use bearing_ident::screening::Checks;
use bearing_ident::simulate::{
    AntiAlias, ImpactTest, MAX_RECORDS, MAX_SAMPLES, MAX_TOTAL_SAMPLES, Simulator, add_noise,
    sample_count, seed_rig, slowest_decay,
};
use bearing_ident::spectra::ForceGate;
use bearing_ident::{
    Assignment, Baseline, Channel, Coefficients, Error, Estimator, Identification, Identifier,
    Method, NonConvergence, Record, Screening, Segmentation, Uncertainty, Window,
};
use clap::{Parser, Subcommand, ValueEnum};
use faer::Mat;
use rand::SeedableRng;
use rand::rngs::StdRng;

/// Dynamic force coefficients (M, C, K) of bearings, seals and dampers from test records.
#[derive(Debug, Parser)]
#[command(name = "bearing-ident", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Identify M, C, K from CSV records (one file per record).
    Identify(IdentifyArgs),
    /// Simulate the seed's test rig and identify it, as the quickstart example does.
    Demo(DemoArgs),
    /// Simulate impact records of a given system and write them as CSV files.
    Simulate(SimulateArgs),
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum MethodArg {
    Direct,
    Ls,
    Ivf,
    /// Maximum likelihood from IVF; needs `--excitation periodic` (noise from the periods).
    Ml,
}

#[derive(Debug, Clone, Copy, PartialEq, ValueEnum)]
enum ExcitationArg {
    /// Decide from the force signals' crest factor.
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

#[derive(Debug, Clone, Copy, ValueEnum)]
enum UncertaintyArg {
    /// Jackknife with at least 3 paired sets or records, else the sandwich.
    Auto,
    None,
    Sandwich,
    Jackknife,
    Bootstrap,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum EstimatorArg {
    Paired,
    H1,
    H2,
    Hv,
}

#[derive(Debug, clap::Args)]
struct IdentifyArgs {
    /// Print the result as JSON on stdout.
    #[arg(long)]
    json: bool,
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
    /// Period of periodic excitation (s), for `--excitation periodic`.
    #[arg(long)]
    period: Option<f64>,
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
    /// Force columns, one per degree of freedom.
    #[arg(long, default_value = "fx,fy", value_delimiter = ',')]
    force: Vec<String>,
    /// Displacement columns, one per degree of freedom.
    #[arg(long, default_value = "x,y", value_delimiter = ',')]
    disp: Vec<String>,
    /// Time column (s).
    #[arg(long, default_value = "t")]
    time: String,
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
    /// Record files (CSV).
    #[arg(required = true)]
    files: Vec<PathBuf>,
}

#[derive(Debug, clap::Args)]
struct DemoArgs {
    /// Noise level (fraction of each signal kind's RMS).
    #[arg(long, default_value_t = 0.02)]
    noise: f64,
    /// Print the result as JSON on stdout.
    #[arg(long)]
    json: bool,
    /// Write figures (SVG) and a static `index.html` report into DIR.
    #[arg(long, value_name = "DIR")]
    plot: Option<PathBuf>,
}

#[derive(Debug, Clone, Copy, PartialEq, ValueEnum)]
enum KindArg {
    /// Half-sine hammer hits, `--impacts` per degree of freedom.
    Impact,
    /// White Gaussian forces on every degree of freedom at once, `--records` records.
    Random,
    /// Random-phase multisine on one direction per record, lines in `--freqs LO,HI`, period
    /// `--period`, `--records` records per direction of `--periods` periods after 2 s of
    /// settling.
    Multisine,
    /// One sine per record and direction at `--freqs LO,HI,COUNT` (evenly spaced), recorded
    /// for `--duration` (default 1 s) after 1 s of settling.
    SteppedSine,
    /// Linear sweep over `--freqs LO,HI` in `--sweep-time`, then free decay, on one direction
    /// per record, `--records` records per direction.
    Sweep,
}

#[derive(Debug, clap::Args)]
struct SimulateArgs {
    /// Kind of excitation.
    #[arg(long, value_enum, default_value = "impact")]
    kind: KindArg,
    /// Records of random excitation.
    #[arg(long, default_value_t = 4)]
    records: usize,
    /// RMS of each random force (N).
    #[arg(long, default_value_t = 50.0)]
    force_rms: f64,
    /// Mass matrix (kg), rows separated by `;`, e.g. "4.7,0;0,4.8". Default: the seed's rig.
    #[arg(long, requires_all = ["damping", "stiffness"])]
    mass: Option<String>,
    /// Damping matrix (N·s/m), same form.
    #[arg(long, requires_all = ["mass", "stiffness"])]
    damping: Option<String>,
    /// Stiffness matrix (N/m), same form.
    #[arg(long, requires_all = ["mass", "damping"])]
    stiffness: Option<String>,
    /// Impacts per degree of freedom.
    #[arg(long, default_value_t = 8)]
    impacts: usize,
    /// Noise level (fraction of each signal kind's RMS).
    #[arg(long, default_value_t = 0.0)]
    noise: f64,
    /// Seed of the noise generator.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Sampling rate (Hz).
    #[arg(long, default_value_t = 6700.0)]
    rate: f64,
    /// Record length (s); default for impacts: long enough for the response to decay to 1e-7;
    /// for random excitation: 60 s.
    #[arg(long)]
    duration: Option<f64>,
    /// Half-sine pulse duration (s).
    #[arg(long, default_value_t = 0.002)]
    pulse: f64,
    /// Frequencies (Hz): `LO,HI` for multisine lines and sweeps, `LO,HI,COUNT` for stepped
    /// sines (defaults 8,49 / 5,60 / 10,48,15).
    #[arg(long)]
    freqs: Option<String>,
    /// Multisine period (s).
    #[arg(long, default_value_t = 1.0)]
    period: f64,
    /// Multisine periods recorded per record.
    #[arg(long, default_value_t = 8)]
    periods: usize,
    /// Sweep duration (s), before the free decay.
    #[arg(long, default_value_t = 1.0)]
    sweep_time: f64,
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Print what was written as JSON on stdout (and errors as `{"error": …}`).
    #[arg(long)]
    json: bool,
}

/// A failure of the tool: a stable kind and a one-line message.
struct Failure {
    kind: &'static str,
    message: String,
}

impl From<bearing_ident::Error> for Failure {
    fn from(e: bearing_ident::Error) -> Self {
        Failure {
            kind: e.kind(),
            message: e.to_string(),
        }
    }
}

fn invalid(message: String) -> Failure {
    Failure {
        kind: "invalid_argument",
        message,
    }
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
    };
    let outcome = match cli.command {
        Command::Identify(args) => identify(&args),
        Command::Demo(args) => demo(&args),
        Command::Simulate(args) => simulate(&args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("bearing-ident: error: {}", f.message);
            if json {
                let v = serde_json::json!({ "error": f.kind, "message": f.message });
                println!("{v}");
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
    if let Some((cut, _)) = message.char_indices().nth(MESSAGE_CHARS) {
        message.truncate(cut);
        message.push('…');
    }
    if json {
        let v = serde_json::json!({ "error": "invalid_argument", "message": message });
        println!("{v}");
    } else if rendered.len() <= 4 * MESSAGE_CHARS {
        // Short enough to print as clap does, with its usage and tips.
        e.exit();
    }
    eprintln!("bearing-ident: error: {message}");
    ExitCode::from(2)
}

fn parse_band(s: &str) -> Result<(f64, f64), Failure> {
    let bad = || Failure {
        kind: "bad_band",
        message: format!("--band `{}`: expected LO,HI in Hz, e.g. 8,49", excerpt(s)),
    };
    let (lo, hi) = s.split_once(',').ok_or_else(bad)?;
    let lo: f64 = lo.trim().parse().map_err(|_| bad())?;
    let hi: f64 = hi.trim().parse().map_err(|_| bad())?;
    Ok((lo, hi))
}

/// Crest factor (peak / RMS about the mean) of a record's strongest force channel.
/// The force is scaled by its largest magnitude first, so huge forces do not overflow; a flat
/// force has crest factor 0.
fn crest_factor(record: &Record) -> f64 {
    let f = record.force(record.dominant_force());
    let scale = f.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
    if scale <= 0.0 || !scale.is_finite() {
        return 0.0;
    }
    let mean = f.iter().map(|v| v / scale).sum::<f64>() / f.len() as f64;
    let centred = |v: &f64| v / scale - mean;
    let rms = (f.iter().map(|v| centred(v).powi(2)).sum::<f64>() / f.len() as f64).sqrt();
    let peak = f.iter().map(|v| centred(v).abs()).fold(0.0, f64::max);
    if rms > 0.0 { peak / rms } else { 0.0 }
}

/// Impacts concentrate their force in a few samples: crest factors of 10–100. Random forcing
/// has Gaussian-like crest factors of 3–5. The median over the records is compared with 8.
const IMPACT_CREST: f64 = 8.0;

/// `rect`, `hann` or `exp:END` with `0 < END < 1`, over segments of `segment_s` seconds.
fn parse_window(s: &str, segment_s: f64) -> Result<Window, Failure> {
    let bad = || {
        invalid(format!(
            "--window `{}`: expected rect, hann or exp:END with 0 < END < 1",
            excerpt(s)
        ))
    };
    match s {
        "rect" => Ok(Window::Rectangular),
        "hann" => Ok(Window::Hann),
        _ => {
            let end: f64 = s
                .strip_prefix("exp:")
                .and_then(|e| e.parse().ok())
                .ok_or_else(bad)?;
            if end > 0.0 && end < 1.0 {
                Ok(Window::exponential_to(end, segment_s))
            } else {
                Err(bad())
            }
        }
    }
}

fn layout(args: &IdentifyArgs) -> Result<CsvLayout, Failure> {
    if args.force.len() != args.disp.len() {
        return Err(invalid(format!(
            "--force names {} columns and --disp {}: one of each per degree of freedom",
            args.force.len(),
            args.disp.len()
        )));
    }
    Ok(CsvLayout {
        time: args.time.clone(),
        forces: args.force.clone(),
        displacements: args.disp.clone(),
    })
}

/// The identifier and its processing for `excitation`, from the first record and the options;
/// also the Welch segment length, if any.
fn settings(
    args: &IdentifyArgs,
    excitation: ExcitationArg,
    first: &Record,
) -> Result<(Identifier, Option<usize>), Failure> {
    let (lo, hi) = parse_band(&args.band)?;
    let eighth = (first.len() / 8).max(8);
    let nperseg = args.nperseg.unwrap_or(if eighth.is_power_of_two() {
        eighth
    } else {
        eighth.next_power_of_two() / 2
    });
    let chosen = args.estimator.map(|e| match e {
        EstimatorArg::Paired => Estimator::PairedSets,
        EstimatorArg::H1 => Estimator::H1,
        EstimatorArg::H2 => Estimator::H2,
        EstimatorArg::Hv => Estimator::Hv,
    });
    let (estimator, segmentation, default_window) = match excitation {
        ExcitationArg::Random => match chosen {
            Some(Estimator::PairedSets) => (
                Estimator::PairedSets,
                Segmentation::WholeRecord,
                Window::Hann,
            ),
            e => (
                e.unwrap_or(Estimator::H1),
                Segmentation::Welch { len: nperseg },
                Window::Hann,
            ),
        },
        ExcitationArg::Periodic => {
            let period = args.period.ok_or_else(|| {
                invalid("--excitation periodic needs --period SECONDS".to_string())
            })?;
            let len = (period * first.sample_rate()).round();
            if !(len >= 8.0 && len <= first.len() as f64) {
                return Err(invalid(format!(
                    "--period {period}: {len} samples; expected 8 samples up to the record length"
                )));
            }
            let estimator = match chosen {
                None | Some(Estimator::PairedSets) => Estimator::H1,
                Some(e) => e,
            };
            let len = len as usize;
            (
                estimator,
                Segmentation::Periods { len },
                Window::Rectangular,
            )
        }
        _ => (
            chosen.unwrap_or(Estimator::PairedSets),
            Segmentation::WholeRecord,
            Window::Rectangular,
        ),
    };
    let segment_s = match segmentation {
        Segmentation::Welch { len } | Segmentation::Periods { len } => {
            len as f64 / first.sample_rate()
        }
        _ => first.duration(),
    };
    let window = match args.window.as_deref() {
        None => default_window,
        Some(w) => parse_window(w, segment_s)?,
    };
    let method = match args.method {
        MethodArg::Direct => Method::Direct,
        MethodArg::Ls => Method::LeastSquares,
        MethodArg::Ivf => Method::Ivf,
        MethodArg::Ml => Method::Ml,
    };
    let mut identifier = Identifier::new(lo, hi)
        .method(method)
        .estimator(estimator)
        .segmentation(segmentation)
        .window(window)
        .tolerance(args.tolerance)
        .max_iterations(args.max_iterations)
        .min_coherence(args.min_coherence)
        .fit_gate(FitGate {
            min_r2: args.min_r2,
        })
        .uncertainty(match args.uncertainty {
            UncertaintyArg::Auto => Uncertainty::Auto,
            UncertaintyArg::None => Uncertainty::None,
            UncertaintyArg::Sandwich => Uncertainty::Sandwich,
            UncertaintyArg::Jackknife => Uncertainty::Jackknife,
            UncertaintyArg::Bootstrap => Uncertainty::Bootstrap {
                replicates: args.bootstrap_draws,
                seed: args.seed,
            },
        })
        .on_non_convergence(if args.allow_unconverged {
            NonConvergence::Warn
        } else {
            NonConvergence::Fail
        });
    if let Some(open) = args.force_gate {
        identifier = identifier.force_gate(ForceGate::new(open, open / 5.0)?);
    }
    // Screening on every excitation; the double-hit check only for impacts.
    let checks = if excitation == ExcitationArg::Impact {
        Checks::default()
    } else {
        Checks::without_double_hits()
    };
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

/// Identifies the records of `files`, the first already read: streamed one at a time (memory
/// holds one record plus band-line spectra, however many files), or all together for a
/// stepped-sine test.
fn run(
    args: &IdentifyArgs,
    identifier: &Identifier,
    excitation: ExcitationArg,
    first: Record,
    files: &[PathBuf],
    reading: &mut std::time::Duration,
) -> Result<Identification, Failure> {
    let layout = layout(args)?;
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(files.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let rest = files[1..].iter().map(|path| {
        let t = Instant::now();
        bar.set_message(path.display().to_string());
        let record = io::read_record(path, &layout);
        bar.inc(1);
        *reading += t.elapsed();
        record
    });
    let records = std::iter::once(Ok(first)).chain(rest);
    let id = if excitation == ExcitationArg::SteppedSine {
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
    bar.finish_and_clear();
    Ok(id)
}

/// The dry-structure baseline: identified from a directory of CSV records with the same
/// settings, or read back from an earlier `identify --json` result.
fn baseline(
    args: &IdentifyArgs,
    identifier: &Identifier,
    excitation: ExcitationArg,
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
        let first = io::read_record(&files[0], &layout(args)?)?;
        let mut reading = std::time::Duration::ZERO;
        let id = run(args, identifier, excitation, first, &files, &mut reading)?;
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

/// Reads the record files and identifies them; the excitation kind is decided from the first
/// record with a force that is not flat.
fn identify(args: &IdentifyArgs) -> Result<(), Failure> {
    let layout = layout(args)?;
    let start = Instant::now();
    let first = io::read_record(&args.files[0], &layout)?;
    let mut crest = crest_factor(&first);
    if args.excitation == ExcitationArg::Auto && crest <= 0.0 {
        // A flat force (a hammer hit that did not register) says nothing of the excitation:
        // decide from the first record with a force; with none, say so.
        crest = args.files[1..]
            .iter()
            .map(|path| io::read_record(path, &layout).map(|r| crest_factor(&r)))
            .find(|c| !matches!(c, Ok(c) if *c <= 0.0))
            .transpose()?
            .ok_or_else(|| Error::DeadChannel {
                record: first.label().to_owned(),
                channel: Channel::Force(0),
                value: first.force(0)[0],
            })?;
    }
    let mut reading = start.elapsed();
    let excitation = match args.excitation {
        ExcitationArg::Auto if crest >= IMPACT_CREST => ExcitationArg::Impact,
        ExcitationArg::Auto => ExcitationArg::Random,
        chosen => chosen,
    };
    let (identifier, segment_len) = settings(args, excitation, &first)?;
    let sample_rate = first.sample_rate();
    let id = run(
        args,
        &identifier,
        excitation,
        first,
        &args.files,
        &mut reading,
    )?;
    let compute_ms = (start.elapsed().saturating_sub(reading)).as_secs_f64() * 1e3;
    let bearing = match &args.baseline {
        Some(path) => {
            let dry = baseline(args, &identifier, excitation, path)?;
            let (b, std) = id.subtract_baseline(dry)?;
            Some((b, std, path.display().to_string()))
        }
        None => None,
    };
    let context = report::Context {
        excitation: excitation_name(excitation),
        excitation_auto: args.excitation == ExcitationArg::Auto,
        crest_factor: crest,
        segment_len,
        sample_rate,
        files: args.files.iter().map(|p| p.display().to_string()).collect(),
        compute_ms,
        axes: args.disp.clone(),
        bearing,
        per_frequency: args.per_frequency.then(|| id.per_frequency()).transpose()?,
    };
    if let Some(dir) = &args.plot {
        // The records were streamed; read a few again for the record figure.
        let records = args
            .files
            .iter()
            .take(PLOTTED_FILES)
            .map(|path| io::read_record(path, &layout))
            .collect::<bearing_ident::Result<Vec<_>>>()?;
        let checks = (excitation == ExcitationArg::Impact).then(ImpactChecks::default);
        write_report(dir, &id, &records, &context, None, checks)?;
    }
    emit(&id, &context, None, args.json)
}

/// Files read again for the record figure of `identify --plot`.
const PLOTTED_FILES: usize = 32;

/// Writes the figures and `index.html` of `--plot DIR`; says where on stderr.
fn write_report(
    dir: &std::path::Path,
    id: &Identification,
    records: &[Record],
    context: &report::Context,
    truth: Option<&Coefficients>,
    checks: Option<ImpactChecks>,
) -> Result<(), Failure> {
    let options = bearing_ident::plot::ReportOptions {
        context: vec![format!(
            "{} records ({}), {} samples/s; excitation {}{}.",
            context.files.len(),
            summarize_files(&context.files),
            context.sample_rate,
            context.excitation,
            if context.excitation_auto {
                ", detected"
            } else {
                ""
            },
        )],
        text: Some(report::table(id, context, truth)),
        truth: truth.cloned(),
        checks,
        figure: bearing_ident::plot::FigureOptions {
            axes: context.axes.clone(),
            ..Default::default()
        },
        ..Default::default()
    };
    let written = bearing_ident::plot::report(id, records, dir, &options)?;
    eprintln!(
        "bearing-ident: wrote {} figures and {}",
        written.len().saturating_sub(1),
        dir.join("index.html").display()
    );
    Ok(())
}

/// The first few file names and how many more.
fn summarize_files(files: &[String]) -> String {
    let shown: Vec<&str> = files.iter().take(3).map(String::as_str).collect();
    if files.len() > shown.len() {
        format!("{}, … {} more", shown.join(", "), files.len() - shown.len())
    } else {
        shown.join(", ")
    }
}

fn excitation_name(excitation: ExcitationArg) -> &'static str {
    match excitation {
        ExcitationArg::Random => "random",
        ExcitationArg::Periodic => "periodic",
        ExcitationArg::SteppedSine => "stepped-sine",
        ExcitationArg::Sweep => "sweep",
        _ => "impact",
    }
}

fn emit(
    id: &Identification,
    context: &report::Context,
    truth: Option<&Coefficients>,
    json: bool,
) -> Result<(), Failure> {
    if json {
        let value = report::json(id, context).map_err(|e| Failure {
            kind: "io_error",
            message: e.to_string(),
        })?;
        println!("{value}");
    } else {
        print!("{}", report::table(id, context, truth));
    }
    Ok(())
}

fn demo(args: &DemoArgs) -> Result<(), Failure> {
    let truth = seed_rig();
    let test = ImpactTest {
        noise: args.noise,
        ..ImpactTest::seed_rig()
    };
    let records = test.run(&truth)?;
    let start = Instant::now();
    let id = Identifier::new(8.0, 49.0).identify(&records)?;
    let context = report::Context {
        excitation: "impact",
        excitation_auto: false,
        crest_factor: crest_factor(&records[0]),
        segment_len: None,
        sample_rate: test.sample_rate,
        files: records.iter().map(|r| r.label().to_owned()).collect(),
        compute_ms: start.elapsed().as_secs_f64() * 1e3,
        axes: vec!["x".into(), "y".into()],
        bearing: None,
        per_frequency: None,
    };
    if let Some(dir) = &args.plot {
        write_report(
            dir,
            &id,
            &records,
            &context,
            Some(&truth),
            Some(ImpactChecks::default()),
        )?;
    }
    if !args.json {
        println!(
            "Demo: the seed's rig (Diaz & San Andrés 1999), {} impacts per direction, {} samples/s \
             for {} s, noise {:.1} %, identified over 8–49 Hz by IVF.\n",
            test.per_direction,
            test.sample_rate,
            test.duration_s,
            100.0 * args.noise
        );
    }
    emit(&id, &context, Some(&truth), args.json)
}

fn parse_matrix(name: &str, s: &str) -> Result<Mat<f64>, Failure> {
    let rows: Vec<Vec<f64>> = s
        .split(';')
        .map(|r| r.split(',').map(|v| v.trim().parse::<f64>()).collect())
        .collect::<Result<_, _>>()
        .map_err(|e| invalid(format!("--{name} `{}`: {e}", excerpt(s))))?;
    let n = rows.len();
    if rows.iter().any(|r| r.len() != n) {
        return Err(invalid(format!(
            "--{name} `{}`: expected a square matrix, rows separated by `;`",
            excerpt(s)
        )));
    }
    Ok(Mat::from_fn(n, n, |i, j| rows[i][j]))
}

/// Records of a shaker driving one direction at a time: multisine, stepped sine or sweep
/// (see [`KindArg`]), with `--noise`.
fn driven_records(
    args: &SimulateArgs,
    system: &Coefficients,
    decay_s: f64,
) -> Result<Vec<Record>, Failure> {
    let n = system.dofs();
    let rate = args.rate;
    let freqs: Vec<f64> = match &args.freqs {
        Some(s) => s
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| invalid(format!("--freqs `{}`: {e}", excerpt(s))))?,
        None => match args.kind {
            KindArg::Multisine => vec![8.0, 49.0],
            KindArg::SteppedSine => vec![10.0, 48.0, 15.0],
            _ => vec![5.0, 60.0],
        },
    };
    let expected = if args.kind == KindArg::SteppedSine {
        3
    } else {
        2
    };
    if freqs.len() != expected
        || freqs.iter().any(|f| !f.is_finite())
        || !(freqs[0] > 0.0 && freqs[1] > freqs[0])
    {
        return Err(invalid(format!(
            "--freqs: expected {} with 0 < LO < HI, all finite",
            if expected == 3 {
                "LO,HI,COUNT"
            } else {
                "LO,HI"
            }
        )));
    }
    let samples = |s: f64| sample_count(s, rate);
    let amplitude = args.force_rms * std::f64::consts::SQRT_2;
    // (label, direction, drive samples, samples kept from the end)
    let mut drives: Vec<(String, usize, Vec<f64>, usize)> = Vec::new();
    match args.kind {
        KindArg::Multisine => {
            let period = samples(args.period)?;
            let kept = period.saturating_mul(args.periods);
            at_most(
                "multisine samples kept per record",
                kept as f64,
                MAX_SAMPLES,
            )?;
            let settle = samples(2.0)?;
            check_size(n as f64 * args.records as f64, settle + kept)?;
            let lines =
                (freqs[0] * args.period).ceil() as usize..=(freqs[1] * args.period) as usize;
            for d in 0..n {
                for r in 0..args.records {
                    let seed = args.seed.wrapping_add((d * args.records + r) as u64);
                    let drive = bearing_ident::simulate::multisine(
                        period,
                        lines.clone(),
                        args.force_rms,
                        settle + kept,
                        seed,
                    )?;
                    drives.push((format!("multisine-d{d}-{r}"), d, drive, kept));
                }
            }
        }
        KindArg::SteppedSine => {
            if freqs[2] < 1.0 || freqs[2].fract() != 0.0 {
                return Err(invalid("--freqs: COUNT must be a whole number ≥ 1".into()));
            }
            let kept = samples(args.duration.unwrap_or(1.0))?;
            let total = samples(1.0)? + kept;
            at_most("samples per record", total as f64, MAX_SAMPLES)?;
            check_size(freqs[2] * n as f64, total)?;
            // At most MAX_RECORDS, checked above.
            let count = freqs[2] as usize;
            for s in 0..count {
                let f = if count == 1 {
                    freqs[0]
                } else {
                    freqs[0] + (freqs[1] - freqs[0]) * s as f64 / (count - 1) as f64
                };
                for d in 0..n {
                    let drive = bearing_ident::simulate::sine(f, amplitude, rate, total)?;
                    drives.push((format!("sine-{f:.3}Hz-d{d}"), d, drive, kept));
                }
            }
        }
        _ => {
            let total = samples(args.duration.unwrap_or(args.sweep_time + decay_s))?;
            check_size(n as f64 * args.records as f64, total)?;
            for d in 0..n {
                for r in 0..args.records {
                    let drive = bearing_ident::simulate::sweep(
                        freqs[0],
                        freqs[1],
                        args.sweep_time,
                        amplitude,
                        rate,
                        total,
                    )?;
                    drives.push((format!("sweep-d{d}-{r}"), d, drive, total));
                }
            }
        }
    }
    let mut rng = StdRng::seed_from_u64(args.seed ^ NOISE_STREAM);
    let mut sims: Vec<(usize, Simulator)> = Vec::new();
    drives
        .into_iter()
        .map(|(label, d, drive, kept)| {
            let total = drive.len();
            let at = match sims.iter().position(|(len, _)| *len == total) {
                Some(p) => p,
                None => {
                    sims.push((
                        total,
                        Simulator::new(system, rate, total, AntiAlias::default())?,
                    ));
                    sims.len() - 1
                }
            };
            let mut forces = vec![vec![0.0; total]; n];
            forces[d] = drive;
            let clean = sims[at]
                .1
                .held_record(label, &forces)?
                .trimmed(total - kept..total)?;
            add_noise(&clean, args.noise, &mut rng)
        })
        .collect::<bearing_ident::Result<Vec<_>>>()
        .map_err(Failure::from)
}

/// `Ok` if `value ≤ limit`, else a `too_large` failure.
fn at_most(what: &'static str, value: f64, limit: usize) -> Result<(), Failure> {
    if value <= limit as f64 {
        Ok(())
    } else {
        Err(bearing_ident::Error::TooLarge {
            what,
            value,
            limit: limit as f64,
        }
        .into())
    }
}

/// Checks the size of a simulated test: at most `MAX_RECORDS` records and `MAX_TOTAL_SAMPLES`
/// samples in all.
fn check_size(records: f64, samples: usize) -> Result<(), Failure> {
    at_most("records", records, MAX_RECORDS)?;
    at_most(
        "samples × records",
        records * samples as f64,
        MAX_TOTAL_SAMPLES,
    )
}

/// Mixed into `--seed` for the measurement-noise generator of random records, so that noise
/// and forcing come from unrelated streams.
const NOISE_STREAM: u64 = 0x9E37_79B9_7F4A_7C15;

fn simulate(args: &SimulateArgs) -> Result<(), Failure> {
    let system = match (&args.mass, &args.damping, &args.stiffness) {
        (Some(m), Some(c), Some(k)) => Coefficients::new(
            parse_matrix("mass", m)?,
            parse_matrix("damping", c)?,
            parse_matrix("stiffness", k)?,
        )?,
        _ => seed_rig(),
    };
    let base = ImpactTest::seed_rig();
    // Time for the slowest mode to decay to 1e-7 (e^{-16.1}); a mass that is not positive
    // definite or a mode that does not decay is an error naming the matrix.
    let slowest = slowest_decay(&system)?;
    let decay_s = 16.2 / slowest;
    let decay_samples = decay_s * args.rate;
    let derived = args.duration.is_none() && matches!(args.kind, KindArg::Impact | KindArg::Sweep);
    if derived && (decay_samples.is_nan() || decay_samples > MAX_SAMPLES as f64) {
        return Err(Failure {
            kind: "too_large",
            message: format!(
                "the slowest mode decays at {slowest:.3e} 1/s: records must last {decay_s:.3e} s \
                 for it to decay to 1e-7, {decay_samples:.3e} samples at {} Hz, past the limit \
                 of {MAX_SAMPLES} samples per record (add damping or give --duration)",
                args.rate
            ),
        });
    }
    let duration_s = match (args.duration, args.kind) {
        (Some(d), _) => d,
        (None, KindArg::Random) => 60.0,
        (None, KindArg::SteppedSine) => 1.0,
        (None, KindArg::Multisine) => args.period * args.periods as f64,
        (None, KindArg::Sweep) => ((args.sweep_time + decay_s) * 10.0).ceil() / 10.0,
        (None, KindArg::Impact) => {
            let needed = base.pretrigger_s + args.pulse + decay_s;
            (needed * 10.0).ceil() / 10.0
        }
    };
    let test = ImpactTest {
        per_direction: args.impacts,
        sample_rate: args.rate,
        duration_s,
        pulse_s: args.pulse,
        noise: args.noise,
        seed: args.seed,
        ..base
    };
    let records = match args.kind {
        KindArg::Impact => test.run(&system)?,
        KindArg::Multisine | KindArg::SteppedSine | KindArg::Sweep => {
            driven_records(args, &system, decay_s)?
        }
        KindArg::Random => {
            let samples = test.samples()?;
            check_size(args.records as f64, samples)?;
            let mut sim = Simulator::new(&system, args.rate, samples, AntiAlias::default())?;
            // The noise stream must not be the forcing stream (seeded by `seed + r`).
            let mut rng = StdRng::seed_from_u64(args.seed ^ NOISE_STREAM);
            (0..args.records)
                .map(|r| {
                    let clean = sim.random_record(
                        format!("random-{r}"),
                        args.force_rms,
                        args.seed.wrapping_add(r as u64),
                    )?;
                    add_noise(&clean, args.noise, &mut rng)
                })
                .collect::<bearing_ident::Result<Vec<_>>>()?
        }
    };
    std::fs::create_dir_all(&args.out).map_err(|e| Failure {
        kind: "io_error",
        message: format!("{}: {e}", args.out.display()),
    })?;
    let layout = CsvLayout::for_dofs(system.dofs());
    for r in &records {
        io::write_record(args.out.join(format!("{}.csv", r.label())), r, &layout)?;
    }
    if args.json {
        let v = serde_json::json!({
            "records": records.len(),
            "samples": records.first().map_or(0, Record::len),
            "duration_s": duration_s,
            "sample_rate": args.rate,
            "out": args.out.display().to_string(),
            "columns": std::iter::once(&layout.time)
                .chain(&layout.forces)
                .chain(&layout.displacements)
                .collect::<Vec<_>>(),
        });
        println!("{v}");
        return Ok(());
    }
    println!(
        "wrote {} records of {} samples ({} s at {} samples/s) to {}, columns {},{},{}",
        records.len(),
        records.first().map_or(0, Record::len),
        duration_s,
        args.rate,
        args.out.display(),
        layout.time,
        layout.forces.join(","),
        layout.displacements.join(",")
    );
    Ok(())
}
