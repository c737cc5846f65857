//! `bearing-ident simulate`: records of a given system (impacts, random forcing, or a shaker:
//! multisine, stepped sine, sweep) written as CSV files; with nonlinear terms
//! (`--coulomb`, `--cubic`, …, in `nonlinear.rs`) integrated by RK4. The forcing and the
//! records are made in `records.rs`.

mod nonlinear;
mod records;

use std::path::PathBuf;

use bearing_ident::io::{self, CsvLayout};
use bearing_ident::simulate::{ImpactTest, MAX_SAMPLES, seed_rig, slowest_decay};
use bearing_ident::tolerance::SIMULATED_DECAY_NEPERS;
use bearing_ident::{Coefficients, Record};
use clap::ValueEnum;

use crate::failure::{Failure, invalid, print_out};
use crate::parse::parse_matrix;
use bearing_ident::job::response_columns;
use nonlinear::NonlinearArgs;
use records::{driven_records, random_records};

#[derive(Debug, Clone, Copy, PartialEq, ValueEnum)]
pub enum KindArg {
    /// Half-sine hammer hits, `--impacts` per degree of freedom.
    Impact,
    /// Gaussian forces on every degree of freedom at once, `--records` records: white, or
    /// band-limited to `--freqs LO,HI`.
    Random,
    /// Random-phase multisine on one direction per record (every direction at once with
    /// `--simultaneous`, independent phases), lines in `--freqs LO,HI`, period `--period`,
    /// `--records` records (per direction) of `--periods` periods after 2 s of settling.
    Multisine,
    /// One sine per record and direction at `--freqs LO,HI,COUNT` (evenly spaced), recorded
    /// for `--duration` (default 1 s) after 1 s of settling.
    SteppedSine,
    /// Linear sweep over `--freqs LO,HI` in `--sweep-time`, then free decay, on one direction
    /// per record, `--records` records per direction.
    Sweep,
}

#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// Kind of excitation (`--excitation` is the same flag).
    #[arg(long, value_enum, default_value = "impact", alias = "excitation")]
    kind: KindArg,
    /// Multisine: drive every direction at once in each record (independent phases) instead
    /// of one direction per record. Random forcing is always on every direction at once.
    #[arg(long)]
    simultaneous: bool,
    #[command(flatten)]
    nonlinear: NonlinearArgs,
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
    /// Frequencies (Hz): `LO,HI` for multisine lines, sweeps and band-limited random forces,
    /// `LO,HI,COUNT` for stepped sines (defaults 8,49 / 5,60 / 10,48,15; random: white).
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
    /// What the response columns record: `displacement` (columns `x,y`), `velocity`
    /// (`vx,vy`, m/s) or `acceleration` (`ax,ay`, m/s²); one for all or one per degree of
    /// freedom (comma list). Read them back with `identify --response` the same.
    #[arg(long, value_delimiter = ',')]
    response: Vec<bearing_ident::Response>,
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Print what was written as JSON on stdout (and errors as `{"error": …}`).
    #[arg(long)]
    pub json: bool,
}

/// Refuses, naming the flag, counts and a rate that would write nothing or fail later under
/// another name: `--impacts 0`, `--records 0`, `--periods 0`, a sampling rate that is not a
/// finite positive number.
fn check_counts(args: &SimulateArgs) -> Result<(), Failure> {
    if !(args.rate.is_finite() && args.rate > 0.0) {
        return Err(invalid(format!(
            "--rate {}: the sampling rate must be a finite positive number of samples/s",
            args.rate
        )));
    }
    let zero = match args.kind {
        KindArg::Impact => (args.impacts == 0).then_some("--impacts 0"),
        _ => (args.records == 0).then_some("--records 0"),
    };
    let zero =
        zero.or((args.kind == KindArg::Multisine && args.periods == 0).then_some("--periods 0"));
    if let Some(flag) = zero {
        return Err(invalid(format!(
            "{flag}: at least 1 is needed, or nothing would be written"
        )));
    }
    Ok(())
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
    if args.nonlinear.any() && args.kind == KindArg::Impact {
        return Err(invalid(
            "nonlinear terms need a forced test: --excitation random, multisine, \
             stepped-sine or sweep (impacts give too little time at each amplitude)"
                .into(),
        ));
    }
    if args.simultaneous && !matches!(args.kind, KindArg::Multisine | KindArg::Random) {
        return Err(invalid(
            "--simultaneous drives every direction at once with independent multisines: \
             it applies to --excitation multisine (random is simultaneous already)"
                .into(),
        ));
    }
    check_counts(args)?;
    let base = ImpactTest::seed_rig();
    // Time for the slowest mode to decay to 1e-7 (e^{-16.1}); a mass that is not positive
    // definite or a mode that does not decay is an error naming the matrix.
    let slowest = slowest_decay(&system)?;
    let decay_s = SIMULATED_DECAY_NEPERS / slowest;
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
        KindArg::Impact => test.run_responding(&system, &args.response)?,
        KindArg::Multisine | KindArg::SteppedSine | KindArg::Sweep => {
            driven_records(args, &system, decay_s)?
        }
        KindArg::Random => random_records(args, &system, test.samples()?)?,
    };
    std::fs::create_dir_all(&args.out).map_err(|e| Failure {
        kind: "io_error",
        message: format!("{}: {e}", args.out.display()),
    })?;
    let mut layout = CsvLayout::for_dofs(system.dofs());
    layout.displacements = response_columns(&layout.displacements, &args.response);
    for r in &records {
        io::write_record(args.out.join(format!("{}.csv", r.label())), r, &layout)?;
    }
    if args.json {
        let mut v = serde_json::json!({
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
        if args.nonlinear.any() {
            let sim = args
                .nonlinear
                .simulator(&system, args.rate, 8, &args.response)?;
            v["nonlinear"] = args.nonlinear.json(&sim);
        }
        print_out(format_args!("{v}\n"))?;
        return Ok(());
    }
    print_out(format_args!(
        "wrote {} records of {} samples ({} s at {} samples/s) to {}, columns {},{},{}\n",
        records.len(),
        records.first().map_or(0, Record::len),
        duration_s,
        args.rate,
        args.out.display(),
        layout.time,
        layout.forces.join(","),
        layout.displacements.join(",")
    ))
}
