//! `bearing-ident simulate`: records of a given system (impacts, random forcing, or a shaker
//! driving one direction at a time: multisine, stepped sine, sweep) written as CSV files.

use std::path::PathBuf;

use bearing_ident::error::excerpt;
use bearing_ident::io::{self, CsvLayout};
use bearing_ident::simulate::{
    AntiAlias, ImpactTest, MAX_RECORDS, MAX_SAMPLES, MAX_TOTAL_SAMPLES, Simulator, add_noise,
    sample_count, seed_rig, slowest_decay,
};
use bearing_ident::tolerance::SIMULATED_DECAY_NEPERS;
use bearing_ident::{Coefficients, Record};
use clap::ValueEnum;
use rand::SeedableRng;
use rand::rngs::StdRng;

use crate::failure::{Failure, invalid, print_out};
use crate::parse::{parse_matrix, response_columns};

#[derive(Debug, Clone, Copy, PartialEq, ValueEnum)]
pub enum KindArg {
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
pub struct SimulateArgs {
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
                        Simulator::new(system, rate, total, AntiAlias::default())?
                            .responding(&args.response)?,
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

pub fn simulate(args: &SimulateArgs) -> Result<(), Failure> {
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
        KindArg::Random => {
            let samples = test.samples()?;
            check_size(args.records as f64, samples)?;
            let mut sim = Simulator::new(&system, args.rate, samples, AntiAlias::default())?
                .responding(&args.response)?;
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
    let mut layout = CsvLayout::for_dofs(system.dofs());
    layout.displacements = response_columns(&layout.displacements, &args.response);
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
