//! `bearing-ident`: identify bearing force coefficients from CSV records, simulate records, or
//! run the demo. Errors exit with status 2 and one line on stderr naming file, line and column;
//! with `--json` a `{"error": KIND, "message": …}` object is also printed on stdout.

mod report;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use bearing_ident::io::{self, CsvLayout};
use bearing_ident::simulate::{AntiAlias, ImpactTest, Simulator, add_noise, seed_rig};
use bearing_ident::{
    Coefficients, Estimator, Identification, Identifier, Method, NonConvergence, Record,
    Segmentation, Uncertainty, Window,
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
}

#[derive(Debug, Clone, Copy, PartialEq, ValueEnum)]
enum ExcitationArg {
    /// Decide from the force signals' crest factor.
    Auto,
    /// Impacts: paired sets, whole-record DFT, no window.
    Impact,
    /// Random: MIMO H1 with Welch segments (Hann, 50 % overlap).
    Random,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum UncertaintyArg {
    None,
    Sandwich,
    Jackknife,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum EstimatorArg {
    Paired,
    H1,
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
    /// Error bars: jackknife over paired sets or records (falls back to the sandwich, with a
    /// warning, below 3 of them), first-order sandwich, or none.
    #[arg(long, value_enum, default_value = "jackknife")]
    uncertainty: UncertaintyArg,
    /// Drop lines where the multiple coherence of any output is below X (0 ≤ X < 1).
    #[arg(long, default_value_t = 0.0)]
    min_coherence: f64,
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
}

#[derive(Debug, Clone, Copy, PartialEq, ValueEnum)]
enum KindArg {
    /// Half-sine hammer hits, `--impacts` per degree of freedom.
    Impact,
    /// White Gaussian forces on every degree of freedom at once, `--records` records.
    Random,
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
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
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
    let cli = Cli::parse();
    let json = match &cli.command {
        Command::Identify(a) => a.json,
        Command::Demo(a) => a.json,
        Command::Simulate(_) => false,
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

fn parse_band(s: &str) -> Result<(f64, f64), Failure> {
    let bad = || Failure {
        kind: "bad_band",
        message: format!("--band `{s}`: expected LO,HI in Hz, e.g. 8,49"),
    };
    let (lo, hi) = s.split_once(',').ok_or_else(bad)?;
    let lo: f64 = lo.trim().parse().map_err(|_| bad())?;
    let hi: f64 = hi.trim().parse().map_err(|_| bad())?;
    Ok((lo, hi))
}

/// Crest factor (peak / RMS about the mean) of a record's strongest force channel.
fn crest_factor(record: &Record) -> f64 {
    let f = record.force(record.dominant_force());
    let mean = f.iter().sum::<f64>() / f.len() as f64;
    let rms = (f.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / f.len() as f64).sqrt();
    let peak = f.iter().map(|v| (v - mean).abs()).fold(0.0, f64::max);
    if rms > 0.0 { peak / rms } else { 0.0 }
}

/// Impacts concentrate their force in a few samples: crest factors of 10–100. Random forcing
/// has Gaussian-like crest factors of 3–5. The median over the records is compared with 8.
const IMPACT_CREST: f64 = 8.0;

/// `rect`, `hann` or `exp:END` with `0 < END < 1`, over segments of `segment_s` seconds.
fn parse_window(s: &str, segment_s: f64) -> Result<Window, Failure> {
    let bad = || {
        invalid(format!(
            "--window `{s}`: expected rect, hann or exp:END with 0 < END < 1"
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

/// Reads the record files one at a time and streams them into the identification, so memory
/// holds one record (plus band-line spectra) however many files there are. The excitation kind
/// is decided from the first record.
fn identify(args: &IdentifyArgs) -> Result<(), Failure> {
    let (lo, hi) = parse_band(&args.band)?;
    let layout = layout(args)?;
    let start = Instant::now();
    let first = io::read_record(&args.files[0], &layout)?;
    let mut reading = start.elapsed();
    let crest = crest_factor(&first);
    let excitation = match args.excitation {
        ExcitationArg::Auto if crest >= IMPACT_CREST => ExcitationArg::Impact,
        ExcitationArg::Auto => ExcitationArg::Random,
        chosen => chosen,
    };
    let eighth = (first.len() / 8).max(8);
    let nperseg = args.nperseg.unwrap_or(if eighth.is_power_of_two() {
        eighth
    } else {
        eighth.next_power_of_two() / 2
    });
    let (estimator, segmentation, default_window) = match (excitation, args.estimator) {
        (ExcitationArg::Random, Some(EstimatorArg::Paired)) => (
            Estimator::PairedSets,
            Segmentation::WholeRecord,
            Window::Hann,
        ),
        (ExcitationArg::Random, _) => (
            Estimator::H1,
            Segmentation::Welch { len: nperseg },
            Window::Hann,
        ),
        (_, Some(EstimatorArg::H1)) => (
            Estimator::H1,
            Segmentation::WholeRecord,
            Window::Rectangular,
        ),
        _ => (
            Estimator::PairedSets,
            Segmentation::WholeRecord,
            Window::Rectangular,
        ),
    };
    let segment_s = match segmentation {
        Segmentation::Welch { len } => len as f64 / first.sample_rate(),
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
    };
    let identifier = Identifier::new(lo, hi)
        .method(method)
        .estimator(estimator)
        .segmentation(segmentation)
        .window(window)
        .tolerance(args.tolerance)
        .max_iterations(args.max_iterations)
        .min_coherence(args.min_coherence)
        .uncertainty(match args.uncertainty {
            UncertaintyArg::None => Uncertainty::None,
            UncertaintyArg::Sandwich => Uncertainty::Sandwich,
            UncertaintyArg::Jackknife => Uncertainty::Jackknife,
        })
        .on_non_convergence(if args.allow_unconverged {
            NonConvergence::Warn
        } else {
            NonConvergence::Fail
        });
    let sample_rate = first.sample_rate();
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(args.files.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let rest = args.files[1..].iter().map(|path| {
        let t = Instant::now();
        bar.set_message(path.display().to_string());
        let record = io::read_record(path, &layout);
        bar.inc(1);
        reading += t.elapsed();
        record
    });
    let id = identifier.identify_stream(std::iter::once(Ok(first)).chain(rest))?;
    bar.finish_and_clear();
    let compute_ms = (start.elapsed().saturating_sub(reading)).as_secs_f64() * 1e3;
    let context = report::Context {
        excitation: match excitation {
            ExcitationArg::Random => "random",
            _ => "impact",
        },
        excitation_auto: args.excitation == ExcitationArg::Auto,
        crest_factor: crest,
        segment_len: match segmentation {
            Segmentation::Welch { len } => Some(len),
            _ => None,
        },
        sample_rate,
        files: args.files.iter().map(|p| p.display().to_string()).collect(),
        compute_ms,
        axes: args.disp.clone(),
    };
    emit(&id, &context, None, args.json)
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
    };
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
        .map_err(|e| invalid(format!("--{name} `{s}`: {e}")))?;
    let n = rows.len();
    if rows.iter().any(|r| r.len() != n) {
        return Err(invalid(format!(
            "--{name} `{s}`: expected a square matrix, rows separated by `;`"
        )));
    }
    Ok(Mat::from_fn(n, n, |i, j| rows[i][j]))
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
    let duration_s = match (args.duration, args.kind) {
        (Some(d), _) => d,
        (None, KindArg::Random) => 60.0,
        (None, KindArg::Impact) => {
            let slowest = system
                .eigenvalues()?
                .iter()
                .map(|l| -l.re)
                .fold(f64::INFINITY, f64::min);
            let needed = base.pretrigger_s + args.pulse + 16.2 / slowest;
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
        KindArg::Random => {
            let mut sim = Simulator::new(&system, args.rate, test.samples(), AntiAlias::default())?;
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
    println!(
        "wrote {} records of {} samples ({} s at {} samples/s) to {}, columns {},{},{}",
        records.len(),
        test.samples(),
        duration_s,
        args.rate,
        args.out.display(),
        layout.time,
        layout.forces.join(","),
        layout.displacements.join(",")
    );
    Ok(())
}
