//! The forcing of `simulate` and the records it makes: random forces on every direction at
//! once (white, or band-limited with `--freqs`), a shaker driving one direction at a time or
//! all at once (`--simultaneous`: multisine), stepped sines and sweeps, through the exact linear
//! simulator or, with nonlinear terms, the RK4 one.

use bearing_ident::error::excerpt;
use bearing_ident::simulate::{
    AntiAlias, MAX_RECORDS, MAX_SAMPLES, MAX_TOTAL_SAMPLES, NonlinearSimulator, Simulator,
    add_noise, band_noise, multisine, sample_count, sine, sweep,
};
use bearing_ident::{Coefficients, Record};
use rand::SeedableRng;
use rand::rngs::StdRng;

use super::{KindArg, SimulateArgs};
use crate::failure::{Failure, invalid};

/// Mixed into `--seed` for the measurement-noise generator of random records, so that noise
/// and forcing come from unrelated streams.
const NOISE_STREAM: u64 = 0x9E37_79B9_7F4A_7C15;

/// Mixed into `--seed` for band-limited random forces (the same role as the linear
/// simulator's own forcing stream).
const FORCE_STREAM: u64 = 0xD1B5_4A32_D192_ED03;

/// The simulator of one record length: the exact linear one, or the RK4 one when the system
/// has nonlinear terms.
enum Engine {
    Linear(Simulator),
    Nonlinear(Box<NonlinearSimulator>),
}

impl Engine {
    fn new(args: &SimulateArgs, system: &Coefficients, samples: usize) -> Result<Self, Failure> {
        Ok(if args.nonlinear.any() {
            Engine::Nonlinear(Box::new(args.nonlinear.simulator(
                system,
                args.rate,
                samples,
                &args.response,
            )?))
        } else {
            Engine::Linear(
                Simulator::new(system, args.rate, samples, AntiAlias::default())?
                    .responding(&args.response)?,
            )
        })
    }

    fn held_record(&mut self, label: String, forces: &[Vec<f64>]) -> bearing_ident::Result<Record> {
        match self {
            Engine::Linear(sim) => sim.held_record(label, forces),
            Engine::Nonlinear(sim) => sim.held_record(label, forces),
        }
    }
}

/// `Ok` if `value ≤ limit`, else a `too_large` failure.
pub fn at_most(what: &'static str, value: f64, limit: usize) -> Result<(), Failure> {
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
pub fn check_size(records: f64, samples: usize) -> Result<(), Failure> {
    at_most("records", records, MAX_RECORDS)?;
    at_most(
        "samples × records",
        records * samples as f64,
        MAX_TOTAL_SAMPLES,
    )
}

/// `--freqs` read as numbers: `LO,HI` (`LO,HI,COUNT` for stepped sines), or the kind's
/// default; `None` for random forcing without `--freqs` (white forces).
fn frequencies(args: &SimulateArgs) -> Result<Option<Vec<f64>>, Failure> {
    let freqs: Vec<f64> = match &args.freqs {
        Some(s) => s
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| invalid(format!("--freqs `{}`: {e}", excerpt(s))))?,
        None => match args.kind {
            KindArg::Random | KindArg::Impact => return Ok(None),
            KindArg::Multisine => vec![8.0, 49.0],
            KindArg::SteppedSine => vec![10.0, 48.0, 15.0],
            KindArg::Sweep => vec![5.0, 60.0],
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
    Ok(Some(freqs))
}

/// One record to make: its label, the held force on every DOF, and how many samples to keep
/// from its end.
struct Drive {
    label: String,
    forces: Vec<Vec<f64>>,
    kept: usize,
}

/// `drive` on direction `d` of `n`, the other directions unforced.
fn one_direction(n: usize, d: usize, drive: Vec<f64>) -> Vec<Vec<f64>> {
    let mut forces = vec![vec![0.0; drive.len()]; n];
    forces[d] = drive;
    forces
}

/// Records of random forces on every direction at once, `samples` long: white (the linear
/// simulator's own staircase, or for a nonlinear system Gaussian noise on every line below
/// Nyquist) or, with `--freqs LO,HI`, band-limited to that band; with `--noise`.
pub fn random_records(
    args: &SimulateArgs,
    system: &Coefficients,
    samples: usize,
) -> Result<Vec<Record>, Failure> {
    let n = system.dofs();
    check_size(args.records as f64, samples)?;
    let band = frequencies(args)?;
    let mut engine = Engine::new(args, system, samples)?;
    let mut rng = StdRng::seed_from_u64(args.seed ^ NOISE_STREAM);
    let df = args.rate / samples as f64;
    let (lo, hi) = match &band {
        Some(f) => (f[0], f[1]),
        None => (df, args.rate / 2.0 - df),
    };
    let mut records = Vec::with_capacity(args.records);
    for r in 0..args.records {
        let label = format!("random-{r}");
        let seed = args.seed.wrapping_add(r as u64);
        let clean = match (&mut engine, &band) {
            // The linear simulator's white staircase, as before band-limited forcing existed.
            (Engine::Linear(sim), None) => sim.random_record(label, args.force_rms, seed)?,
            (engine, _) => {
                let forces = (0..n)
                    .map(|d| {
                        let stream = seed.wrapping_mul(MAX_DOFS_STRIDE).wrapping_add(d as u64);
                        band_noise(
                            lo,
                            hi,
                            args.force_rms,
                            args.rate,
                            samples,
                            stream ^ FORCE_STREAM,
                        )
                    })
                    .collect::<bearing_ident::Result<Vec<_>>>()?;
                engine.held_record(label, &forces)?
            }
        };
        records.push(add_noise(&clean, args.noise, &mut rng)?);
    }
    Ok(records)
}

/// Spacing of the forcing seeds of successive records, so that the seeds of their directions
/// (`seed × stride + direction`) never coincide.
const MAX_DOFS_STRIDE: u64 = 1 << 8;

/// Records of a shaker: multisine (one direction at a time, or every direction at once with
/// `--simultaneous`), stepped sine or sweep (see [`KindArg`]), with `--noise`.
pub fn driven_records(
    args: &SimulateArgs,
    system: &Coefficients,
    decay_s: f64,
) -> Result<Vec<Record>, Failure> {
    let n = system.dofs();
    let rate = args.rate;
    let Some(freqs) = frequencies(args)? else {
        return Err(invalid("--freqs: expected LO,HI".into()));
    };
    let samples = |s: f64| sample_count(s, rate);
    let amplitude = args.force_rms * std::f64::consts::SQRT_2;
    let mut drives: Vec<Drive> = Vec::new();
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
            let records = if args.simultaneous { 1 } else { n } as f64 * args.records as f64;
            check_size(records, settle + kept)?;
            let lines =
                (freqs[0] * args.period).ceil() as usize..=(freqs[1] * args.period) as usize;
            let drive = |d: usize, r: usize| {
                let seed = args.seed.wrapping_add((d * args.records + r) as u64);
                multisine(period, lines.clone(), args.force_rms, settle + kept, seed)
            };
            for r in 0..args.records {
                if args.simultaneous {
                    drives.push(Drive {
                        label: format!("multisine-{r}"),
                        forces: (0..n).map(|d| drive(d, r)).collect::<Result<_, _>>()?,
                        kept,
                    });
                }
            }
            for d in (0..n).filter(|_| !args.simultaneous) {
                for r in 0..args.records {
                    drives.push(Drive {
                        label: format!("multisine-d{d}-{r}"),
                        forces: one_direction(n, d, drive(d, r)?),
                        kept,
                    });
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
                    drives.push(Drive {
                        label: format!("sine-{f:.3}Hz-d{d}"),
                        forces: one_direction(n, d, sine(f, amplitude, rate, total)?),
                        kept,
                    });
                }
            }
        }
        _ => {
            let total = samples(args.duration.unwrap_or(args.sweep_time + decay_s))?;
            check_size(n as f64 * args.records as f64, total)?;
            for d in 0..n {
                for r in 0..args.records {
                    let drive = sweep(freqs[0], freqs[1], args.sweep_time, amplitude, rate, total)?;
                    drives.push(Drive {
                        label: format!("sweep-d{d}-{r}"),
                        forces: one_direction(n, d, drive),
                        kept: total,
                    });
                }
            }
        }
    }
    let mut rng = StdRng::seed_from_u64(args.seed ^ NOISE_STREAM);
    let mut engines: Vec<(usize, Engine)> = Vec::new();
    drives
        .into_iter()
        .map(|drive| {
            let total = drive.forces[0].len();
            let at = match engines.iter().position(|(len, _)| *len == total) {
                Some(p) => p,
                None => {
                    engines.push((total, Engine::new(args, system, total)?));
                    engines.len() - 1
                }
            };
            let clean = engines[at]
                .1
                .held_record(drive.label, &drive.forces)?
                .trimmed(total - drive.kept..total)?;
            Ok(add_noise(&clean, args.noise, &mut rng)?)
        })
        .collect()
}
