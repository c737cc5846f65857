//! Periodic records checked against their stated period ([`PeriodCheck`]) and the period
//! found in the data ([`find_period`]).
//!
//! A steady periodic signal of period `L` samples repeats exactly from period to period: the
//! scatter of the periods about their mean is noise only, and by Parseval it is the energy
//! between the harmonic lines of the DFT over whole periods. The fraction
//! $q(L) = \sum_p \lVert x_p - \bar x \rVert^2 / \sum_p \lVert x_p \rVert^2$ of the dominant
//! force is small at the right period and near 1 at a wrong one; the period the data suggest
//! is the lag of the force's largest autocorrelation peak. The first period holds a
//! start-up transient when it differs from the mean of the others by more than their own
//! scatter predicts.

use std::cell::RefCell;

use faer::c64;
use realfft::RealFftPlanner;

use crate::error::Warning;
use crate::kept::with_kept;
use crate::records::Record;
use crate::tolerance::{
    PERIOD_MISMATCH, PERIOD_REPEATS, PERIODIC_CORRELATION, PERIODIC_CORRELATION_DOUBT,
    START_TRANSIENT, TRANSIENT_ENERGY,
};

thread_local! {
    /// The autocorrelation's FFT plans, kept per thread: records of one test share a length,
    /// and planning a transform costs about as much as running it.
    static PLANNER: RefCell<RealFftPlanner<f64>> = RefCell::new(RealFftPlanner::new());
    /// The autocorrelation's buffers, kept per thread ([`with_kept`]).
    static BUFFERS: RefCell<Buffers> = RefCell::new(Buffers::default());
}

/// The autocorrelation's buffers: the padded force, then its autocorrelation; the spectrum;
/// the transforms' scratch; the normalised autocorrelation at the lags read.
#[derive(Default)]
struct Buffers {
    signal: Vec<f64>,
    spectrum: Vec<c64>,
    scratch: Vec<c64>,
    rho: Vec<f64>,
}

/// The period of `record` (s), if its dominant force repeats: the lag `L ≥ 8` samples, at
/// most half the record, of the first autocorrelation peak within a few percent of the
/// largest, whose normalised autocorrelation $\rho(L) = r(L)/r(0) \cdot N/(N-L)$ exceeds
/// [`PERIODIC_CORRELATION`], refined between samples by a parabola through the peak; then,
/// where the record holds at least two periods, the whole lag within 3 samples
/// whose periods scatter least about their mean when it repeats better
/// than the refined one (noise moves a broad peak by a few samples, and a period one sample
/// off puts a long record's periods out of step: at 30 % noise on a multisine's force, one
/// record in forty was cut a sample short and its identification was off by 9 σ).
/// `None` for random forcing, impacts and flat forces.
///
/// # Examples
/// ```
/// use bearing_ident::Record;
/// use bearing_ident::screening::find_period;
/// use bearing_ident::simulate::multisine;
/// // A 250-sample multisine, 8 periods at 1000 S/s: 0.25 s.
/// let f = multisine(250, 3..=40, 1.0, 2000, 3)?;
/// let r = Record::new("ms", 1000.0, vec![f], vec![vec![0.0; 2000]])?;
/// assert!((find_period(&r).unwrap() / 0.25 - 1.0).abs() < 1e-3);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn find_period(record: &Record) -> Option<f64> {
    let (period_s, correlation, lag) = autocorrelation_peak(record)?;
    if correlation < PERIODIC_CORRELATION {
        return None;
    }
    let f = record.force(record.dominant_force());
    let rate = record.sample_rate();
    let scatter = |len: usize| match f.len() / len.max(1) {
        periods if len >= 8 && periods >= 2 => Some(between_lines(f, len, periods)),
        _ => None,
    };
    let rounded = (period_s * rate).round() as usize;
    let Some(at_rounded) = scatter(rounded) else {
        return Some(period_s);
    };
    let best = (lag.saturating_sub(LAG_SLACK)..=lag + LAG_SLACK)
        .filter_map(|len| scatter(len).map(|s| (len, s)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    Some(match best {
        Some((len, s)) if s < at_rounded => len as f64 / rate,
        _ => period_s,
    })
}

/// How a record's dominant force repeats: the lag of its autocorrelation's peak, whatever its
/// height, and how well the force repeats at it ([`repeat`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Repeat {
    /// The lag (s): the first autocorrelation peak within a few percent of the largest, as
    /// [`find_period`] picks it.
    pub(crate) period_s: f64,
    /// The normalised autocorrelation $\rho(L)$ at that lag.
    pub(crate) correlation: f64,
    /// The fraction of the force's energy between the harmonic lines of periods of the peak's
    /// whole lag, the first period left out when there are three or more; when that is above
    /// [`PERIOD_REPEATS`], the least over whole lags within [`LAG_SLACK`] of it. 1 when the
    /// record holds fewer than two such periods, or when the correlation is below
    /// [`PERIODIC_CORRELATION_DOUBT`] (not read: the force does not repeat).
    pub(crate) scatter: f64,
}

/// Samples either side of an autocorrelation peak's lag at which [`Repeat::scatter`] is also
/// read: noise moves a broad peak (a narrow-band force's, `T` samples per cycle) by about
/// $\sqrt{2\sigma_\rho / (\rho\,(2\pi/T)^2)}$ samples, with $\sigma_\rho \approx 1/\sqrt N$ the
/// autocorrelation's noise: 3 for a tone of 80 samples per cycle at 0.65 correlation over 8000
/// samples, and a lag off by one sample puts a long record's periods out of step.
const LAG_SLACK: usize = 3;

/// How `record`'s dominant force repeats ([`Repeat`]); `None` for a flat force, one shorter
/// than 32 samples or without an autocorrelation peak.
pub(crate) fn repeat(record: &Record) -> Option<Repeat> {
    let (period_s, correlation, lag) = autocorrelation_peak(record)?;
    let f = record.force(record.dominant_force());
    let scatter_at = |len: usize| {
        let periods = f.len() / len.max(1);
        if len >= 8 && periods >= 2 {
            let skip = usize::from(periods >= 3);
            between_lines(&f[skip * len..], len, periods - skip)
        } else {
            1.0
        }
    };
    let scatter = if correlation < PERIODIC_CORRELATION_DOUBT {
        1.0
    } else {
        let at_peak = scatter_at(lag);
        if at_peak <= PERIOD_REPEATS {
            at_peak
        } else {
            (lag.saturating_sub(LAG_SLACK)..=lag + LAG_SLACK)
                .filter(|&len| len != lag)
                .map(scatter_at)
                .fold(at_peak, f64::min)
        }
    };
    Some(Repeat {
        period_s,
        correlation,
        scatter,
    })
}

/// The lag (s) of the first autocorrelation peak of `record`'s dominant force within a few
/// percent of the largest, among lags of 9 samples up to half the record, refined between
/// samples by a parabola; the largest peak's normalised autocorrelation; the peak's lag in
/// whole samples.
fn autocorrelation_peak(record: &Record) -> Option<(f64, f64, usize)> {
    let f = record.force(record.dominant_force());
    let n = f.len();
    if n < 32 {
        return None;
    }
    let mean = f.iter().sum::<f64>() / n as f64;
    // Lags up to `n/2 + 1` are read: zero padding past `3n/2 + 1` keeps the circular
    // correlation's wrapped terms off them (a third less than padding to `2n`).
    let len = (3 * n / 2 + 2).next_power_of_two();
    let (forward, inverse) = PLANNER.with(|planner| {
        let mut planner = planner.borrow_mut();
        (planner.plan_fft_forward(len), planner.plan_fft_inverse(len))
    });
    with_kept(&BUFFERS, n, |buffers| {
        let Buffers {
            signal,
            spectrum,
            scratch,
            rho,
        } = buffers;
        signal.clear();
        signal.extend(f.iter().map(|v| v - mean));
        signal.resize(len, 0.0);
        spectrum.resize(len / 2 + 1, c64::ZERO);
        scratch.resize(
            forward.get_scratch_len().max(inverse.get_scratch_len()),
            c64::ZERO,
        );
        let transformed = forward
            .process_with_scratch(signal, spectrum, scratch)
            .is_ok()
            && {
                for z in spectrum.iter_mut() {
                    *z = c64::new(z.norm_sqr(), 0.0);
                }
                // The autocorrelation overwrites the padded force.
                inverse
                    .process_with_scratch(spectrum, signal, scratch)
                    .is_ok()
            };
        transformed.then(|| peak(record, signal, rho)).flatten()
    })
}

/// The peak [`autocorrelation_peak`] reads in the circular autocorrelation `r` of `record`'s
/// centred, zero-padded dominant force; `rho` is scratch for the normalised autocorrelation at
/// the lags read.
fn peak(record: &Record, r: &[f64], rho: &mut Vec<f64>) -> Option<(f64, f64, usize)> {
    let n = record.len();
    if !(r[0] > 0.0 && r[0].is_finite()) {
        return None;
    }
    let last = n / 2;
    // ρ at every lag read (8 up to `last + 1`), each computed once.
    rho.clear();
    rho.extend((8..=last + 1).map(|lag| r[lag] / r[0] * n as f64 / (n - lag) as f64));
    let rho = |lag: usize| rho[lag - 8];
    let peaks = (9..=last)
        .map(|lag| (lag, rho(lag)))
        .filter(|&(lag, v)| v >= rho(lag - 1) && v >= rho(lag + 1));
    let best = peaks.clone().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    let (lag, _) = peaks.clone().find(|p| p.1 > best - 0.05)?;
    let (a, b, c) = (rho(lag - 1), rho(lag), rho(lag + 1));
    let curvature = a - 2.0 * b + c;
    let shift = if curvature < 0.0 {
        0.5 * (a - c) / curvature
    } else {
        0.0
    };
    Some((
        (lag as f64 + shift.clamp(-0.5, 0.5)) / record.sample_rate(),
        best,
        lag,
    ))
}

/// Fraction of `x`'s energy (about its mean over the periods) in the scatter of its first
/// `periods` periods of `len` samples about their mean: the energy between the harmonic
/// lines of those periods' DFT.
fn between_lines(x: &[f64], len: usize, periods: usize) -> f64 {
    let used = &x[..len * periods];
    let mean = used.iter().sum::<f64>() / used.len() as f64;
    let (mut scatter, mut total) = (0.0, 0.0);
    for m in 0..len {
        let values = (0..periods).map(|p| used[p * len + m] - mean);
        let avg = values.clone().sum::<f64>() / periods as f64;
        for v in values {
            scatter += (v - avg).powi(2);
            total += v * v;
        }
    }
    if total > 0.0 { scatter / total } else { 0.0 }
}

/// How far the first of `periods` periods of `len` samples of `x` is from the mean of the
/// others, over what their scatter predicts: $d_1 / (s^2 (1 + 1/(P-1)))$ (0 when $d_1$ is
/// below [`TRANSIENT_ENERGY`] of the mean period's energy) with
/// $d_1 = \lVert x_1 - \bar x_{2..P} \rVert^2$ and
/// $s^2 = \sum_{p \ge 2} \lVert x_p - \bar x_{2..P} \rVert^2 / (P - 2)$; about 1 in a steady
/// state.
fn first_period_ratio(x: &[f64], len: usize, periods: usize) -> f64 {
    let (mut d1, mut s2, mut energy) = (0.0, 0.0, 0.0);
    for m in 0..len {
        let later = (1..periods).map(|p| x[p * len + m]);
        let avg = later.clone().sum::<f64>() / (periods - 1) as f64;
        d1 += (x[m] - avg).powi(2);
        s2 += later.map(|v| (v - avg).powi(2)).sum::<f64>();
        energy += avg * avg;
    }
    // A first period whose difference from the others holds a negligible part of the
    // signal is steady, however small the scatter (noise-free records).
    if d1 <= TRANSIENT_ENERGY * energy {
        return 0.0;
    }
    let s2 = s2 / (periods - 2) as f64;
    d1 / (s2 * (1.0 + 1.0 / (periods - 1) as f64))
}

/// The checks of periodic records against a stated period of `len` samples, one record at a
/// time ([`PeriodCheck::record`]), then [`PeriodCheck::warnings`]:
/// [`Warning::PeriodMismatch`] when the dominant force's energy between the harmonic lines of
/// the stated period is above [`PERIOD_MISMATCH`] and at least twice that at the period the
/// data suggest ([`find_period`]) — or when the data show no period; and
/// [`Warning::StartTransient`] for each record whose first period differs from the later ones
/// by more than [`START_TRANSIENT`] times what their scatter predicts on some channel (3
/// periods at least).
#[derive(Debug, Clone)]
pub struct PeriodCheck {
    len: usize,
    mismatch: Option<(f64, Option<f64>)>,
    transients: Vec<(String, f64)>,
}

impl PeriodCheck {
    /// A check against periods of `len` samples.
    pub fn new(len: usize) -> Self {
        Self {
            len,
            mismatch: None,
            transients: Vec::new(),
        }
    }

    /// Checks one record.
    pub fn record(&mut self, record: &Record) {
        let len = self.len;
        let periods = record.len() / len.max(1);
        if len == 0 || periods < 2 {
            return;
        }
        // The mismatch is judged without the first period when there are enough others, so
        // a start-up transient is not taken for a wrong period.
        let skip = usize::from(periods >= 3);
        let force = &record.force(record.dominant_force())[skip * len..];
        let q = between_lines(force, len, periods - skip);
        if self.mismatch.is_none() && q > PERIOD_MISMATCH {
            let found = find_period(record);
            let q_found = found.map(|p| {
                let l = (p * record.sample_rate()).round() as usize;
                let n = force.len() / l.max(1);
                if l >= 8 && n >= 2 {
                    between_lines(force, l, n)
                } else {
                    1.0
                }
            });
            if q_found.is_none_or(|qf| q > 2.0 * qf) {
                self.mismatch = Some((len as f64 / record.sample_rate(), found));
            }
        }
        if periods >= 3 {
            let worst = (0..record.dofs())
                .flat_map(|c| [record.force(c), record.displacement(c)])
                .map(|x| first_period_ratio(x, len, periods))
                .fold(0.0, f64::max);
            if worst > START_TRANSIENT {
                self.transients.push((record.label().to_owned(), worst));
            }
        }
    }

    /// The warnings found: at most one [`Warning::PeriodMismatch`] (the first record that
    /// showed it), then one [`Warning::StartTransient`] for all the records that showed one.
    pub fn warnings(&self) -> Vec<Warning> {
        let mut out = Vec::new();
        if let Some((stated_s, suggested_s)) = self.mismatch {
            out.push(Warning::PeriodMismatch {
                stated_s,
                suggested_s,
            });
        }
        if !self.transients.is_empty() {
            out.push(Warning::StartTransient {
                records: self.transients.iter().map(|t| t.0.clone()).collect(),
                worst_ratio: self.transients.iter().map(|t| t.1).fold(0.0, f64::max),
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::{AntiAlias, Simulator, add_noise, multisine, seed_rig};
    use rand::SeedableRng;

    const RATE: f64 = 500.0;
    const PERIOD: usize = 500;

    /// A multisine of `PERIOD` samples on both axes (different phases), 6 periods, from rest
    /// (the first period holds the start-up transient), with 2 % noise.
    fn records(seed: u64) -> Vec<Record> {
        let truth = seed_rig();
        let mut sim = Simulator::new(&truth, RATE, 6 * PERIOD, AntiAlias::default()).unwrap();
        (0..2)
            .map(|d| {
                let f: Vec<Vec<f64>> = (0..2)
                    .map(|c| {
                        let level = if c == d { 20.0 } else { 5.0 };
                        multisine(PERIOD, 8..=49, level, 6 * PERIOD, 10 * seed + c as u64).unwrap()
                    })
                    .collect();
                let r = sim.held_record(format!("ms{seed}-{d}"), &f).unwrap();
                let mut rng = rand::rngs::StdRng::seed_from_u64(100 + 10 * seed + d as u64);
                add_noise(&r, 0.02, &mut rng).unwrap()
            })
            .collect()
    }

    fn check(records: &[Record], len: usize) -> Vec<Warning> {
        let mut c = PeriodCheck::new(len);
        records.iter().for_each(|r| c.record(r));
        c.warnings()
    }

    /// In every seed: the right period raises no mismatch; 2 % short (490 samples) and 4 %
    /// long (520) raise `period_mismatch` naming the right one within 0.1 %; the first
    /// period of records that start from rest raises `start_transient`, the records with it
    /// dropped do not.
    #[test]
    fn wrong_periods_and_start_transients_are_found_in_every_seed() {
        for seed in 0..5 {
            let rs = records(seed);
            let kinds = |w: &[Warning]| w.iter().map(Warning::kind).collect::<Vec<_>>();
            let right = check(&rs, PERIOD);
            assert_eq!(kinds(&right), ["start_transient"], "seed {seed}: {right:?}");
            for wrong in [490, 520] {
                let w = check(&rs, wrong);
                match w.first() {
                    Some(Warning::PeriodMismatch {
                        suggested_s: Some(p),
                        ..
                    }) => assert!((p * RATE / PERIOD as f64 - 1.0).abs() < 1e-3, "{p}"),
                    other => panic!("seed {seed}, {wrong}: {other:?}"),
                }
            }
            let steady: Vec<Record> = rs
                .iter()
                .map(|r| r.trimmed(PERIOD..r.len()).unwrap())
                .collect();
            assert!(check(&steady, PERIOD).is_empty(), "seed {seed}");
            for r in &steady {
                let p = find_period(r).expect("periodic");
                assert!((p * RATE / PERIOD as f64 - 1.0).abs() < 1e-3, "{p}");
            }
        }
    }

    /// The F-16 ground vibration test (third-party, read when present): 9 periods of 8192
    /// samples at 400 S/s (20.48 s), the first transient. The period is found within 0.1 %;
    /// 20.0 s is a mismatch naming 20.48 s; the first period is a start-up transient.
    #[test]
    fn the_f16_multisine_period_is_found_and_checked() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../shared/fixtures/real/f16-gvt/F16Data_FullMSine_Level1.csv"
        );
        let Ok(text) = std::fs::read_to_string(path) else {
            println!("skipped: {path} absent (third-party data, not in the repository)");
            return;
        };
        let (mut force, mut accel) = (Vec::new(), Vec::new());
        for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
            let v: Vec<f64> = line
                .split(',')
                .take(3)
                .map(|x| x.trim().parse().unwrap())
                .collect();
            force.push(v[0]);
            accel.push(v[2]);
        }
        let r = Record::new("f16", 400.0, vec![force], vec![accel]).unwrap();
        let p = find_period(&r).expect("periodic");
        println!("F-16 period found: {p} s");
        assert!((p / 20.48 - 1.0).abs() < 1e-3, "{p}");
        let mut wrong = PeriodCheck::new(8000);
        wrong.record(&r);
        let w = wrong.warnings();
        println!("{}", w[0]);
        assert!(matches!(
            w[0],
            Warning::PeriodMismatch { suggested_s: Some(s), .. } if (s / 20.48 - 1.0).abs() < 1e-3
        ));
        let mut right = PeriodCheck::new(8192);
        right.record(&r);
        let kinds: Vec<_> = right.warnings().iter().map(Warning::kind).collect();
        println!("{:?}", right.warnings());
        assert_eq!(kinds, ["start_transient"]);
    }

    /// Random forcing has no period; one period of white noise repeated has exactly its own.
    #[test]
    fn random_forcing_has_no_period() {
        let mut sim = Simulator::new(&seed_rig(), RATE, 4000, AntiAlias::default()).unwrap();
        let r = sim.random_record("r", 20.0, 3).unwrap();
        assert_eq!(find_period(&r), None);
        let once = &r.force(0)[..731];
        let repeated: Vec<f64> = (0..4000).map(|m| once[m % 731]).collect();
        let r = Record::new("rep", RATE, vec![repeated], vec![vec![0.0; 4000]]).unwrap();
        assert!((find_period(&r).unwrap() * RATE - 731.0).abs() < 0.05);
    }
}
