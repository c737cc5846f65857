//! `bearing-ident identify`: its arguments, turned into the library's [`Job`] (options and
//! channels), the progress bar while the files are read, and the report, figures, exports and
//! JSON written from the [`Outcome`]. The run itself (reading, detection, settings, the Welch
//! choice, the identification, the baseline) is the library's.

use std::path::PathBuf;

use bearing_ident::element::ModelSpec;
use bearing_ident::excitation::Excitation;
use bearing_ident::frf::ForceNoise;
use bearing_ident::io::CsvLayout;
use bearing_ident::job::{Channels, Job, Options, Outcome, Progress, read_first};
use bearing_ident::quality::ImpactChecks;
use bearing_ident::{Estimator, Method, Uncertainty};

use crate::failure::Failure;
use crate::output::{emit, write_report};
use crate::parse::{auto_or, choice};
use crate::report;

mod nonlinear;

/// What `--excitation auto` does.
const AUTO_EXCITATION: &str = "decide from the force of the first record with one: a steady \
     pure tone is a stepped sine, frequencies arriving in order a sweep, a crest factor of 8 or \
     more impacts, a force that repeats periodic (the period found too), else random; when it \
     cannot tell, it names the kinds and asks for --excitation";

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
    #[arg(long, value_parser = choice::<Method>(), default_value = "ivf")]
    method: Method,
    /// Frequency band LO,HI in Hz (edges inclusive).
    #[arg(long, allow_hyphen_values = true)]
    band: String,
    /// Kind of excitation in the records.
    #[arg(long, value_parser = auto_or::<Excitation>(AUTO_EXCITATION), default_value = "auto")]
    excitation: std::option::Option<Excitation>, // `auto` is `None`: a value, not an optional argument
    /// Override the impedance estimator chosen from the excitation.
    #[arg(long, value_parser = choice::<Estimator>())]
    estimator: Option<Estimator>,
    /// Window: `rect`, `hann`, `exp:END` (exponential on force and response, falling to END,
    /// e.g. 0.01, at the end of each record or segment) or `exp:A/s` (a fixed decay A in 1/s,
    /// the same for records of any length); under an exponential window the coefficients are
    /// corrected exactly. Default: `rect` for impacts, `hann` for random excitation.
    #[arg(long)]
    window: Option<String>,
    /// Error bars: `auto` is the jackknife over paired sets or records when there are at least
    /// 3 of them, else (and for periodic records) the first-order sandwich from the replicates'
    /// own scatter; `bootstrap` draws `--bootstrap-draws` resamples of the sets or records
    /// (seeded by `--seed`).
    #[arg(long, value_parser = choice::<Uncertainty>(), default_value = "auto")]
    uncertainty: Uncertainty,
    /// H1's force-side noise: `auto` compensates for the force measurement noise repeated
    /// periods show and, over Welch segments (which cannot tell the load cell's noise from a
    /// force it does not measure or a nonlinear distortion), carries what compensation would
    /// change; `measurement` says the segments' force-side noise is the load cell's and
    /// compensates for it too.
    #[arg(long, value_parser = choice::<ForceNoise>(), default_value = "auto")]
    force_noise: ForceNoise,
    /// Element model: `kcm` (constant K, C, M; the default), `kc`, `poly:P` (K(ω), C(ω)
    /// polynomials of degree P), `states:N` (K, C, M and N internal states, the model of seals,
    /// tilting pads, magnetic bearings), or `auto`: the smallest family the model check
    /// accepts (JSON `model`).
    #[arg(long, default_value = "kcm")]
    model: ModelSpec,
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
    /// Relative standard (1σ) uncertainty of the sensor gains, as a calibration sheet states
    /// it (not a correction): `force=1%,response=2%` per channel kind, or per channel by its
    /// name `fx=0.5%,x=2%` (percent or a fraction). It enters the JSON's
    /// `budget.calibration` and the combined `*_std`, `*_ci95`.
    #[arg(long, value_name = "SPEC")]
    calibration: Option<String>,
    /// Force channels, one per degree of freedom. CSV: column names (default `fx,fy`). TDMS:
    /// channels `GROUP/CHANNEL`, or `CHANNEL` when unique (default `fx,fy`).
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
    /// What the response channels measure, one for all or one per degree of freedom (comma
    /// list, for mixed rigs). Default:
    /// displacement for CSV; for Universal Files the data type (8, 11, 12) of each channel,
    /// which this overrides. Velocity and acceleration are turned into displacement at the
    /// band lines (X = V/(iω) = A/(−ω²); with `--window exp:…`, iω + a).
    #[arg(long, value_delimiter = ',', value_parser = choice::<bearing_ident::Response>())]
    response: Vec<bearing_ident::Response>,
    /// Time column (s). TDMS files: the time channel, read when the force and response
    /// channels have no `wf_increment` property. MAT-files: the time vector (`t`, `rec.t`);
    /// without one, a scalar `fs`, `Fs`, `rate` (Hz) or `dt` (s) beside the first force
    /// channel or at the top.
    #[arg(long, default_value = "t")]
    time: String,
    /// Units of the force channels, one for all or one per channel (comma list): N, kN, mN,
    /// lbf. Samples are converted to SI on reading. Default: N, or the unit a TDMS file
    /// states (`unit_string`).
    #[arg(long, value_delimiter = ',', value_name = "UNIT")]
    force_unit: Vec<String>,
    /// Units of the response channels, as `--force-unit`: m, mm, um, nm, in, mil (mils);
    /// m/s, mm/s, in/s; m/s^2, mm/s^2, in/s^2, g.
    #[arg(long, value_delimiter = ',', value_name = "UNIT")]
    disp_unit: Vec<String>,
    /// Units of the printed coefficients: `si` (kg, N·s/m, N/m) or `us` (lbm, lbf·s/in,
    /// lbf/in); the JSON keeps SI and adds `M_us`, `C_us`, `K_us` (and their `*_std_us`).
    #[arg(long, value_name = "si|us", default_value = "si", value_parser = ["si", "us"])]
    units: String,
    /// TDMS files: one record per file, or one per group holding the named channels.
    #[arg(long, value_name = "file|group", default_value = "file")]
    record_by: bearing_ident::tdms::RecordBy,
    /// Sample rate (Hz) of MAT-files that hold no time vector and no rate.
    #[arg(long, value_name = "HZ")]
    rate: Option<f64>,
    /// Move the responses (and forces) to the bearing plane before the spectra: a TOML file
    /// with the keys of a campaign plan's `[geometry]` (`mode = "conical"`, `pivot`,
    /// `bearing`, `probes` one per response channel, optional `forces`; m).
    #[arg(long, value_name = "FILE.toml")]
    geometry: Option<PathBuf>,
    /// Known delay of channels, divided out of their spectra before any average: `NAME=0.25ms`
    /// (units s, ms, us), NAME a `--force`/`--disp` column or `force`/`response` for every
    /// channel of that kind (e.g. a multiplexed acquisition's skew); comma list. A stated
    /// standard uncertainty after `±` or `+-` (`x=0.25ms±0.02ms`) enters `budget.calibration`.
    #[arg(long, value_delimiter = ',')]
    delay: Vec<String>,
    /// Known AC coupling of channels, divided out of their spectra before any average:
    /// `NAME=3Hz` (a first-order high-pass with that corner) or `NAME=3Hz:2` (order 2), NAME as
    /// for `--delay`; comma list. A stated standard uncertainty after `±` or `+-`
    /// (`x=3Hz±0.3Hz`) enters `budget.calibration`.
    #[arg(long, value_delimiter = ',')]
    highpass: Vec<String>,
    /// The test's radial clearance with its unit (m, mm, um, mil), e.g. `100um`: with
    /// `--load` and `--speed`, the dimensionless coefficients `K̄ = Kc/W`, `C̄ = CΩc/W`,
    /// `M̄ = MΩ²c/W` (JSON `dimensionless`).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    clearance: Option<String>,
    /// The static load on the element with its unit (N, kN, lbf), e.g. `500N`: with
    /// `--speed`, the threshold speed of a rigid rotor of weight W on the element (JSON
    /// `stability`).
    #[arg(long, value_name = "FORCE", allow_hyphen_values = true)]
    load: Option<String>,
    /// The rotor speed with its unit (rpm, Hz, rad/s), e.g. `3000rpm`: the whirl-frequency
    /// ratio (JSON `stability`).
    #[arg(long, value_name = "SPEED", allow_hyphen_values = true)]
    speed: Option<String>,
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
    /// then node; or the channels `--force`, `--disp` name; `--time` does not apply to them),
    /// or TDMS files `.tdms` (channels named `GROUP/CHANNEL`, or `CHANNEL` when unique; a
    /// record per file or per group, `--record-by`),
    /// or MATLAB MAT-files `.mat` (`-v6`, `-v7`, `-v7.3`: channels as variables `fx`, struct fields
    /// `rec.fx` or matrix columns `data:2`, counted from 1; a record per element of a struct
    /// or cell array on the way).
    #[arg(required = true)]
    files: Vec<PathBuf>,
}

/// Where the forces and responses are in the files, from `--force`, `--disp`, `--response`,
/// `--time`.
fn channels(args: &IdentifyArgs) -> Result<Channels, Failure> {
    let mut channels = Channels::named(
        &args.force,
        &args.disp,
        &args.response,
        &args.time,
        &args.files,
    )?;
    channels.mat.rate = args.rate;
    if let Some(path) = &args.geometry {
        channels.geometry = Some(bearing_ident::campaign::Plan::read_geometry(path)?);
    }
    channels.record_by = args.record_by;
    channels.force_units.clone_from(&args.force_unit);
    channels.response_units.clone_from(&args.disp_unit);
    Ok(channels)
}

/// The library's options from the command line (`channels`: the column names `--delay` and
/// `--highpass` name).
fn options(args: &IdentifyArgs, channels: &Channels) -> Result<Options, Failure> {
    let (lo, hi) = bearing_ident::job::parse_band(&args.band)?;
    let mut o = Options::new(lo, hi);
    o.method = args.method;
    o.excitation = args.excitation;
    o.estimator = args.estimator;
    o.window = args.window.as_deref().map(str::parse).transpose()?;
    o.uncertainty = args.uncertainty;
    o.force_noise = args.force_noise;
    o.model = args.model;
    o.bootstrap_draws = args.bootstrap_draws;
    o.seed = args.seed;
    o.force_gate_s = args.force_gate;
    o.period_s = args.period;
    o.step_tolerance_hz = args.step_tolerance;
    o.reject_bad_records = args.reject_bad_records;
    o.min_coherence = args.min_coherence;
    o.min_r2 = args.min_r2;
    o.nperseg = args.nperseg;
    o.tolerance = args.tolerance;
    o.max_iterations = args.max_iterations;
    o.allow_unconverged = args.allow_unconverged;
    o.baseline.clone_from(&args.baseline);
    o.calibration.clone_from(&args.calibration);
    o.drop_periods = args.drop_periods;
    for (name, value) in [
        ("clearance", &args.clearance),
        ("load", &args.load),
        ("speed", &args.speed),
    ] {
        if let Some(value) = value {
            o.set(name, value)?;
        }
    }
    o.channel_transfers = crate::channels::transfers(
        &args.delay,
        &args.highpass,
        &channels.csv.forces,
        &channels.csv.displacements,
    )?;
    Ok(o)
}

/// Reads the record files and identifies them ([`Job::run_files_with`], a progress bar on
/// stderr while the files stream in); `--nonlinear` takes the reverse path instead.
pub fn identify(args: &IdentifyArgs) -> Result<(), Failure> {
    let channels = channels(args)?;
    let inputs: Vec<&std::path::Path> = args
        .files
        .iter()
        .chain(&args.baseline)
        .map(PathBuf::as_path)
        .collect();
    crate::export::check(
        &args.export,
        args.baseline.is_some(),
        args.per_frequency,
        &inputs,
        args.plot.as_deref(),
    )?;
    if let Some(terms) = &args.nonlinear {
        return nonlinear::run(args, terms, &channels);
    }
    nonlinear::linear_only(args)?;
    let job = Job::new(options(args, &channels)?, channels);
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(args.files.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let outcome = job.run_files_with(&args.files, |p| match p {
        Progress::Reading { path, .. } => bar.set_message(path.display().to_string()),
        Progress::Read { .. } => bar.inc(1),
        _ => {}
    });
    bar.finish_and_clear();
    let outcome = outcome?;
    let id = outcome.identification();
    let context = context(args, &outcome)?;
    if let Some(dir) = &args.plot {
        // The records were streamed; read a few again for the record figure.
        let records = args
            .files
            .iter()
            .take(PLOTTED_FILES)
            .map(|path| read_first(path, job.channels()))
            .collect::<bearing_ident::Result<Vec<_>>>()?;
        let checks = (outcome.excitation() == Excitation::Impact).then(ImpactChecks::default);
        write_report(dir, id, &records, &context, None, checks)?;
    }
    let bearing = outcome
        .bearing()
        .map(|b| (&b.coefficients, b.std_dev.as_ref()));
    crate::export::write(&args.export, id, bearing, args.per_frequency)?;
    emit(id, &context, None, args.json)
}

/// What the report says of the run besides the identification.
fn context(args: &IdentifyArgs, outcome: &Outcome) -> Result<report::Context, Failure> {
    let axes = if args.disp.is_empty() {
        CsvLayout::default().displacements
    } else {
        args.disp.clone()
    };
    let mut context = report::Context::of(outcome, args.timings, axes, args.per_frequency)?;
    context.us_units = args.units == "us";
    let us = context.us_units;
    // Reported when units were given or US output asked for; the default JSON is SI as ever.
    if us || !args.force_unit.is_empty() || !args.disp_unit.is_empty() {
        context.units = serde_json::json!({
            "output": args.units,
            "M": if us { "lbm" } else { "kg" },
            "C": if us { "lbf·s/in" } else { "N·s/m" },
            "K": if us { "lbf/in" } else { "N/m" },
            "force": args.force_unit,
            "response": args.disp_unit,
        });
    }
    Ok(context)
}

/// Files read again for the record figure of `identify --plot`.
const PLOTTED_FILES: usize = 32;
