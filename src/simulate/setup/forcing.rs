//! The forcing of a [`Setup`] and the records it makes: random forces on every direction at
//! once (white, or band-limited to `freqs`), a shaker driving one direction at a time or all at
//! once (`simultaneous`: multisine), stepped sines and sweeps, through the exact linear
//! simulator or, with nonlinear terms, the RK4 one.

use rand::SeedableRng;
use rand::rngs::StdRng;

use super::{Kind, Setup};
use crate::error::{Error, Result};
use crate::model::Coefficients;
use crate::records::Record;
use crate::simulate::{
    AntiAlias, MAX_RECORDS, MAX_SAMPLES, MAX_TOTAL_SAMPLES, NonlinearSimulator, Simulator,
    add_noise, at_most, band_noise, multisine, sample_count, sine, sweep,
};

/// Mixed into the seed for the measurement-noise generator of random and shaker records, so
/// that noise and forcing come from unrelated streams.
const NOISE_STREAM: u64 = 0x9E37_79B9_7F4A_7C15;

/// Mixed into the seed for band-limited random forces (the same role as the linear
/// simulator's own forcing stream).
const FORCE_STREAM: u64 = 0xD1B5_4A32_D192_ED03;

/// Spacing of the forcing seeds of successive records, so that the seeds of their directions
/// (`seed × stride + direction`) never coincide.
const MAX_DOFS_STRIDE: u64 = 1 << 8;

/// The simulator of one record length: the exact linear one, or the RK4 one when the system
/// has nonlinear terms.
#[derive(Clone)]
enum Engine {
    Linear(Simulator),
    Nonlinear(Box<NonlinearSimulator>),
}

impl Engine {
    fn new(setup: &Setup, system: &Coefficients, samples: usize) -> Result<Self> {
        Ok(if setup.nonlinear.any() {
            Engine::Nonlinear(Box::new(setup.nonlinear.simulator(
                system,
                setup.rate,
                samples,
                &setup.response,
            )?))
        } else {
            Engine::Linear(
                Simulator::with_states(
                    system,
                    &setup.states,
                    setup.rate,
                    samples,
                    AntiAlias::default(),
                )?
                .responding(&setup.response)?,
            )
        })
    }

    fn held_record(&mut self, label: String, forces: &[Vec<f64>]) -> Result<Record> {
        match self {
            Engine::Linear(sim) => sim.held_record(label, forces),
            Engine::Nonlinear(sim) => sim.held_record(label, forces),
        }
    }
}

/// Checks the size of a simulated test: at most [`MAX_RECORDS`] records and
/// [`MAX_TOTAL_SAMPLES`] samples in all.
pub(super) fn check_size(records: f64, samples: usize) -> Result<()> {
    at_most("records", records, MAX_RECORDS)?;
    at_most(
        "samples × records",
        records * samples as f64,
        MAX_TOTAL_SAMPLES,
    )
}

/// `freqs` checked for the kind: `LO,HI` (`LO,HI,COUNT` for stepped sines), or the kind's
/// default; `None` for random forcing without `freqs` (white forces).
fn frequencies(setup: &Setup) -> Result<Option<Vec<f64>>> {
    let freqs: Vec<f64> = match &setup.freqs {
        Some(f) => f.clone(),
        None => match setup.kind {
            Kind::Random | Kind::Impact => return Ok(None),
            Kind::Multisine => vec![8.0, 49.0],
            Kind::SteppedSine => vec![10.0, 48.0, 15.0],
            Kind::Sweep => vec![5.0, 60.0],
        },
    };
    let expected = if setup.kind == Kind::SteppedSine {
        "LO,HI,COUNT"
    } else {
        "LO,HI"
    };
    if freqs.len() != expected.split(',').count()
        || freqs.iter().any(|f| !f.is_finite())
        || !(freqs[0] > 0.0 && freqs[1] > freqs[0])
    {
        return Err(Error::InvalidOption {
            option: "freqs",
            message: format!("--freqs: expected {expected} with 0 < LO < HI, all finite"),
        });
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
/// Nyquist) or, with `freqs` `LO,HI`, band-limited to that band; with measurement noise.
pub(super) fn random_records(
    setup: &Setup,
    system: &Coefficients,
    samples: usize,
) -> Result<Vec<Record>> {
    let n = system.dofs();
    check_size(setup.records as f64, samples)?;
    let band = frequencies(setup)?;
    let engine = Engine::new(setup, system, samples)?;
    let mut rng = StdRng::seed_from_u64(setup.seed ^ NOISE_STREAM);
    let df = setup.rate / samples as f64;
    let (lo, hi) = match &band {
        Some(f) => (f[0], f[1]),
        None => (df, setup.rate / 2.0 - df),
    };
    let one = |engine: &mut Engine, r: usize| -> Result<Record> {
        let label = format!("random-{r}");
        let seed = setup.seed.wrapping_add(r as u64);
        match (engine, &band) {
            // The linear simulator's white staircase, as before band-limited forcing existed.
            (Engine::Linear(sim), None) => sim.random_record(label, setup.force_rms, seed),
            (engine, _) => {
                let forces = (0..n)
                    .map(|d| {
                        let stream = seed.wrapping_mul(MAX_DOFS_STRIDE).wrapping_add(d as u64);
                        let stream = stream ^ FORCE_STREAM;
                        band_noise(lo, hi, setup.force_rms, setup.rate, samples, stream)
                    })
                    .collect::<Result<Vec<_>>>()?;
                engine.held_record(label, &forces)
            }
        }
    };
    // The measurement noise is drawn from one stream, record after record, as it always was.
    let mut records = Vec::with_capacity(setup.records);
    for clean in each_record(setup.records, engine, one) {
        records.push(add_noise(&clean?, setup.noise, &mut rng)?);
    }
    Ok(records)
}

/// `one(engine, r)` for the records `r = 0, 1, …, count − 1`, in that order, up to the first
/// error. Each record is a function of its index alone, so with the `rayon` feature they are
/// simulated on worker threads, each with its own copy of the engine, and come out bit for
/// bit the same (all clean records are then held at once, before the noise is added).
fn each_record<F>(count: usize, mut engine: Engine, one: F) -> Vec<Result<Record>>
where
    F: Fn(&mut Engine, usize) -> Result<Record> + Sync,
{
    #[cfg(feature = "rayon")]
    if count > 1 {
        use rayon::prelude::*;
        return (0..count)
            .into_par_iter()
            .map_init(|| engine.clone(), |engine, r| one(engine, r))
            .collect();
    }
    let mut out = Vec::with_capacity(count);
    for r in 0..count {
        let record = one(&mut engine, r);
        let failed = record.is_err();
        out.push(record);
        if failed {
            break;
        }
    }
    out
}

/// Records of a shaker: multisine (one direction at a time, or every direction at once with
/// `simultaneous`), stepped sine or sweep (see [`Kind`]), with measurement noise; `decay_s`
/// is the time the slowest mode takes to decay (a sweep's default free decay).
pub(super) fn driven_records(
    setup: &Setup,
    system: &Coefficients,
    decay_s: f64,
) -> Result<Vec<Record>> {
    let Some(freqs) = frequencies(setup)? else {
        unreachable!("every shaker kind has default frequencies")
    };
    let drives = match setup.kind {
        Kind::Multisine => multisine_drives(setup, system.dofs(), &freqs)?,
        Kind::SteppedSine => stepped_drives(setup, system.dofs(), &freqs)?,
        _ => sweep_drives(setup, system.dofs(), &freqs, decay_s)?,
    };
    let mut rng = StdRng::seed_from_u64(setup.seed ^ NOISE_STREAM);
    let mut engines: Vec<(usize, Engine)> = Vec::new();
    drives
        .into_iter()
        .map(|drive| {
            let total = drive.forces[0].len();
            let at = match engines.iter().position(|(len, _)| *len == total) {
                Some(p) => p,
                None => {
                    engines.push((total, Engine::new(setup, system, total)?));
                    engines.len() - 1
                }
            };
            let clean = engines[at]
                .1
                .held_record(drive.label, &drive.forces)?
                .trimmed(total - drive.kept..total)?;
            add_noise(&clean, setup.noise, &mut rng)
        })
        .collect()
}

/// Random-phase multisines on lines `LO..=HI` of the period, after 2 s of settling.
fn multisine_drives(setup: &Setup, n: usize, freqs: &[f64]) -> Result<Vec<Drive>> {
    let samples = |s: f64| sample_count(s, setup.rate);
    let period = samples(setup.period)?;
    let kept = period.saturating_mul(setup.periods);
    at_most(
        "multisine samples kept per record",
        kept as f64,
        MAX_SAMPLES,
    )?;
    let settle = samples(2.0)?;
    let records = if setup.simultaneous { 1 } else { n } as f64 * setup.records as f64;
    check_size(records, settle + kept)?;
    let lines = (freqs[0] * setup.period).ceil() as usize..=(freqs[1] * setup.period) as usize;
    let drive = |d: usize, r: usize| {
        let seed = setup.seed.wrapping_add((d * setup.records + r) as u64);
        multisine(period, lines.clone(), setup.force_rms, settle + kept, seed)
    };
    let mut drives = Vec::new();
    for r in (0..setup.records).filter(|_| setup.simultaneous) {
        drives.push(Drive {
            label: format!("multisine-{r}"),
            forces: (0..n).map(|d| drive(d, r)).collect::<Result<_>>()?,
            kept,
        });
    }
    for d in (0..n).filter(|_| !setup.simultaneous) {
        for r in 0..setup.records {
            drives.push(Drive {
                label: format!("multisine-d{d}-{r}"),
                forces: one_direction(n, d, drive(d, r)?),
                kept,
            });
        }
    }
    Ok(drives)
}

/// One sine per record and direction at `COUNT` frequencies from `LO` to `HI`, kept for
/// `duration` (default 1 s) after 1 s of settling.
fn stepped_drives(setup: &Setup, n: usize, freqs: &[f64]) -> Result<Vec<Drive>> {
    if freqs[2] < 1.0 || freqs[2].fract() != 0.0 {
        return Err(Error::InvalidOption {
            option: "freqs",
            message: "--freqs: COUNT must be a whole number ≥ 1".into(),
        });
    }
    let samples = |s: f64| sample_count(s, setup.rate);
    let kept = samples(setup.duration.unwrap_or(1.0))?;
    let total = samples(1.0)? + kept;
    at_most("samples per record", total as f64, MAX_SAMPLES)?;
    check_size(freqs[2] * n as f64, total)?;
    // At most MAX_RECORDS, checked above.
    let count = freqs[2] as usize;
    let amplitude = setup.force_rms * std::f64::consts::SQRT_2;
    let mut drives = Vec::new();
    for s in 0..count {
        let f = if count == 1 {
            freqs[0]
        } else {
            freqs[0] + (freqs[1] - freqs[0]) * s as f64 / (count - 1) as f64
        };
        for d in 0..n {
            drives.push(Drive {
                label: format!("sine-{f:.3}Hz-d{d}"),
                forces: one_direction(n, d, sine(f, amplitude, setup.rate, total)?),
                kept,
            });
        }
    }
    Ok(drives)
}

/// Linear sweeps from `LO` to `HI` in `sweep_time`, then free decay (`decay_s` unless a
/// `duration` is given), `records` per direction.
fn sweep_drives(setup: &Setup, n: usize, freqs: &[f64], decay_s: f64) -> Result<Vec<Drive>> {
    let total = sample_count(
        setup.duration.unwrap_or(setup.sweep_time + decay_s),
        setup.rate,
    )?;
    check_size(n as f64 * setup.records as f64, total)?;
    let amplitude = setup.force_rms * std::f64::consts::SQRT_2;
    let mut drives = Vec::new();
    for d in 0..n {
        for r in 0..setup.records {
            let drive = sweep(
                freqs[0],
                freqs[1],
                setup.sweep_time,
                amplitude,
                setup.rate,
                total,
            )?;
            drives.push(Drive {
                label: format!("sweep-d{d}-{r}"),
                forces: one_direction(n, d, drive),
                kept: total,
            });
        }
    }
    Ok(drives)
}
