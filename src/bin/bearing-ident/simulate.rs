//! `bearing-ident simulate`: records of a given system (impacts, random forcing, or a shaker:
//! multisine, stepped sine, sweep), with an element's optional internal states, or optional
//! nonlinear terms integrated by RK4, written as CSV, TDMS or MAT-files, one per record. The
//! test itself is the library's [`Setup`]: this file reads its options and writes what it
//! makes.

use bearing_ident::Choice;
use std::path::PathBuf;

use bearing_ident::io::{self, CsvLayout};
use bearing_ident::job::response_columns;
use bearing_ident::model::rows;
use bearing_ident::simulate::{Kind, NonlinearSimulator, Setup, seed_rig};
use bearing_ident::{Coefficients, Record};

use crate::failure::{Failure, print_out};
use crate::parse::{choice, parse_matrix};

/// The library's defaults, shown in the help.
fn defaults() -> Setup {
    Setup::default()
}

#[derive(Debug, Clone, clap::Args)]
pub struct NonlinearArgs {
    /// Dry friction per degree of freedom (N), `M ẍ + C ẋ + K x + F sign(ẋ) = f`: one value
    /// for every DOF or one per DOF, e.g. `20,15`. Makes the system nonlinear (integrated by
    /// RK4 on a fine grid).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    coulomb: Vec<f64>,
    /// Dry friction in the plane of the first two DOFs (N), opposing the velocity vector.
    #[arg(long, allow_negative_numbers = true)]
    coulomb_planar: Option<f64>,
    /// Cubic stiffness per DOF (N/m³), `k₃ x³`: one value or one per DOF.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    cubic: Vec<f64>,
    /// Quadratic damping per DOF (N·s²/m²), `q |ẋ| ẋ`: one value or one per DOF.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    quadratic_damping: Vec<f64>,
    /// Smoothing scale of the friction's sign (m/s): `F tanh(ẋ/V)`. Default 1e-5.
    #[arg(long)]
    smoothing: Option<f64>,
    /// RK4 steps per output sample. Default: at least 16, more if the system or the
    /// anti-alias filter needs them for a stable step.
    #[arg(long)]
    oversampling: Option<usize>,
}

#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// Kind of excitation (`--excitation` is the same flag). Random forcing: white, or
    /// band-limited to `--freqs LO,HI`, `--records` records; multisine: lines in `--freqs
    /// LO,HI`, period `--period`, `--periods` periods after 2 s of settling; stepped sine:
    /// `--duration` (1 s) after 1 s of settling; sweep: in `--sweep-time`.
    #[arg(long, value_parser = choice::<Kind>(), default_value_t = defaults().kind, alias = "excitation")]
    kind: Kind,
    /// Multisine: drive every direction at once in each record (independent phases) instead
    /// of one direction per record. Random forcing is always on every direction at once.
    #[arg(long)]
    simultaneous: bool,
    #[command(flatten)]
    nonlinear: NonlinearArgs,
    /// Records of random excitation, multisine or sweep (per direction for the shaker).
    #[arg(long, default_value_t = defaults().records)]
    records: usize,
    /// RMS of each random or shaker force (N).
    #[arg(long, default_value_t = defaults().force_rms)]
    force_rms: f64,
    /// Mass matrix (kg), rows separated by `;`, e.g. "4.7,0;0,4.8". Default: the 2-DOF test rig of
    /// Diaz & San Andrés (1999).
    #[arg(long, requires_all = ["damping", "stiffness"])]
    mass: Option<String>,
    /// Damping matrix (N·s/m), same form.
    #[arg(long, requires_all = ["mass", "stiffness"])]
    damping: Option<String>,
    /// Stiffness matrix (N/m), same form.
    #[arg(long, requires_all = ["mass", "damping"])]
    stiffness: Option<String>,
    /// Internal states of the element (a seal, tilting pads, a magnetic bearing), one
    /// `POLE_HZ:RESIDUE` per pole, poles separated by `|`, each residue matrix (N/m) in the
    /// `--mass` form, e.g. "12:3e4,0;0,2e4|35:1e4,0;0,1e4". A pole f adds states w,
    /// `ẇ = ẋ − 2πf w`, and the force `A w`: `H(ω) = K + iωC − ω²M + Σ A iω/(iω + 2πf)`,
    /// stiffness rising by A and a damping hump around f. Simulated exactly; not with
    /// nonlinear terms.
    #[arg(
        long,
        value_name = "POLE_HZ:A11,A12;A21,A22|…",
        allow_hyphen_values = true
    )]
    states: Option<String>,
    /// Impacts per degree of freedom.
    #[arg(long, default_value_t = defaults().impacts)]
    impacts: usize,
    /// Noise level (fraction of each signal kind's RMS).
    #[arg(long, default_value_t = defaults().noise)]
    noise: f64,
    /// Seed of the noise generator.
    #[arg(long, default_value_t = defaults().seed)]
    seed: u64,
    /// Sampling rate (Hz).
    #[arg(long, default_value_t = defaults().rate)]
    rate: f64,
    /// Record length (s); default for impacts: long enough for the response to decay to 1e-7;
    /// for random excitation: 60 s.
    #[arg(long)]
    duration: Option<f64>,
    /// Half-sine pulse duration (s).
    #[arg(long, default_value_t = defaults().pulse)]
    pulse: f64,
    /// Frequencies (Hz): `LO,HI` for multisine lines, sweeps and band-limited random forces,
    /// `LO,HI,COUNT` for stepped sines (defaults 8,49 / 5,60 / 10,48,15; random: white).
    #[arg(long)]
    freqs: Option<String>,
    /// Multisine period (s).
    #[arg(long, default_value_t = defaults().period)]
    period: f64,
    /// Multisine periods recorded per record.
    #[arg(long, default_value_t = defaults().periods)]
    periods: usize,
    /// Sweep duration (s), before the free decay.
    #[arg(long, default_value_t = defaults().sweep_time)]
    sweep_time: f64,
    /// What the response columns record: `displacement` (columns `x,y`), `velocity`
    /// (`vx,vy`, m/s) or `acceleration` (`ax,ay`, m/s²); one for all or one per degree of
    /// freedom (comma list). Read them back with `identify --response` the same.
    #[arg(long, value_delimiter = ',')]
    response: Vec<bearing_ident::Response>,
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// The files written, one per record: `csv` (`LABEL.csv`, columns `t,fx,fy,x,y`), `tdms`
    /// (`LABEL.tdms`: group `LABEL`, float64 channels `fx,fy,x,y` with `wf_increment` and
    /// `unit_string`) or `mat` (`LABEL.mat`, MAT-file level 5: double vectors `t,fx,fy,x,y`).
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    format: Format,
    /// Print what was written as JSON on stdout (and errors as `{"error": …}`).
    #[arg(long)]
    pub json: bool,
}

/// What `simulate` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Format {
    /// CSV files.
    Csv,
    /// TDMS files (NI LabVIEW).
    Tdms,
    /// MATLAB MAT-files, level 5.
    Mat,
}

impl Format {
    /// The files' extension.
    fn extension(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::Tdms => "tdms",
            Format::Mat => "mat",
        }
    }
}

/// The library's description of the test the arguments ask for.
fn setup(args: &SimulateArgs) -> Result<Setup, Failure> {
    let mut s = defaults();
    s.kind = args.kind;
    s.simultaneous = args.simultaneous;
    s.records = args.records;
    s.force_rms = args.force_rms;
    s.impacts = args.impacts;
    s.noise = args.noise;
    s.seed = args.seed;
    s.rate = args.rate;
    s.duration = args.duration;
    s.pulse = args.pulse;
    if let Some(freqs) = &args.freqs {
        s.set("freqs", freqs)?;
    }
    s.period = args.period;
    s.periods = args.periods;
    s.sweep_time = args.sweep_time;
    s.response.clone_from(&args.response);
    if let Some(states) = &args.states {
        s.set("states", states)?;
    }
    let n = &args.nonlinear;
    s.nonlinear.coulomb.clone_from(&n.coulomb);
    s.nonlinear.coulomb_planar = n.coulomb_planar;
    s.nonlinear.cubic.clone_from(&n.cubic);
    s.nonlinear
        .quadratic_damping
        .clone_from(&n.quadratic_damping);
    s.nonlinear.smoothing = n.smoothing;
    s.nonlinear.oversampling = n.oversampling;
    Ok(s)
}

/// The JSON description of a nonlinear simulation: its terms, smoothing and steps.
fn nonlinear_json(sim: &NonlinearSimulator) -> serde_json::Value {
    let terms: Vec<serde_json::Value> = sim
        .terms()
        .iter()
        .map(|(t, value)| {
            serde_json::json!({
                "term": t.regressor.name(),
                "dof": t.dof,
                "value": value,
                "unit": t.regressor.unit(),
            })
        })
        .collect();
    serde_json::json!({
        "terms": terms,
        "smoothing": sim.smoothing(),
        "oversampling": sim.oversampling().ok(),
    })
}

pub fn simulate(args: &SimulateArgs) -> Result<(), Failure> {
    let system = match (&args.mass, &args.damping, &args.stiffness) {
        (Some(m), Some(c), Some(k)) => Coefficients::new(
            parse_matrix("mass", m)?,
            parse_matrix("damping", c)?,
            parse_matrix("stiffness", k)?,
        )?,
        _ => seed_rig(),
    };
    let setup = setup(args)?;
    let test = setup.run(&system)?;
    let records = &test.records;
    std::fs::create_dir_all(&args.out).map_err(|e| Failure {
        kind: "io_error",
        message: format!("{}: {e}", args.out.display()),
    })?;
    let mut layout = CsvLayout::for_dofs(system.dofs());
    layout.displacements = response_columns(&layout.displacements, &args.response);
    for r in records {
        let path = args
            .out
            .join(format!("{}.{}", r.label(), args.format.extension()));
        match args.format {
            Format::Csv => io::write_record(path, r, &layout)?,
            Format::Tdms => bearing_ident::tdms::write(
                path,
                std::slice::from_ref(r),
                &layout.forces,
                &layout.displacements,
            )?,
            Format::Mat => bearing_ident::mat::write(
                path,
                r,
                &layout.time,
                &layout.forces,
                &layout.displacements,
            )?,
        }
    }
    // A TDMS file holds no time channel: its channels carry their sample spacing.
    let time_column = (args.format != Format::Tdms).then_some(&layout.time);
    if args.json {
        let mut v = serde_json::json!({
            "records": records.len(),
            "samples": records.first().map_or(0, Record::len),
            "duration_s": test.duration_s,
            "sample_rate": args.rate,
            "out": args.out.display().to_string(),
            "format": args.format.extension(),
            "columns": time_column
                .iter()
                .copied()
                .chain(&layout.forces)
                .chain(&layout.displacements)
                .collect::<Vec<_>>(),
        });
        if !setup.states.is_empty() {
            let residues: Vec<_> = setup
                .states
                .residues()
                .iter()
                .map(|a| rows(a.as_ref()))
                .collect();
            v["states"] = serde_json::json!({
                "poles_hz": setup.states.poles_hz(),
                "residues": residues,
            });
        }
        if setup.nonlinear.any() {
            let sim = setup
                .nonlinear
                .simulator(&system, args.rate, 8, &args.response)?;
            v["nonlinear"] = nonlinear_json(&sim);
        }
        print_out(format_args!("{v}\n"))?;
        return Ok(());
    }
    print_out(format_args!(
        "wrote {} records of {} samples ({} s at {} samples/s) to {} as {} files, columns \
         {}{},{}\n",
        records.len(),
        records.first().map_or(0, Record::len),
        test.duration_s,
        args.rate,
        args.out.display(),
        args.format.extension().to_uppercase(),
        time_column.map_or(String::new(), |t| format!("{t},")),
        layout.forces.join(","),
        layout.displacements.join(",")
    ))
}
