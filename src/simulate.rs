//! Time records of a known system, for students and for the crate's own tests.
//!
//! The simulator integrates `M ẍ + C ẋ + K x = f(t)` **exactly** at the sample instants: the
//! structure, a half-sine pulse generator per degree of freedom and an optional analogue
//! anti-alias filter per channel form one linear autonomous system `ṡ = A s`, advanced from
//! sample to sample by the matrix exponential `Φ = e^{AΔt}` (and by `e^{Aδ}` over the partial
//! steps where a pulse starts or ends). No Euler steps: the records are the samples of the
//! continuous signals. Random forcing ([`Simulator::random_record`]) is a zero-order-hold
//! (staircase) force — a continuous signal in its own right, integrated just as exactly.
//!
//! # Aliasing and leakage
//! A half-sine pulse is not band-limited: its spectrum falls off only as `1/ω²`, so its raw
//! samples alias (by about `π²/(ω_s T)²` of the low-frequency level, 0.1–1 % for millisecond
//! pulses at a few kHz) and the ratio of sampled spectra would no longer be `G(ω)`. As a real
//! acquisition system does, the simulator passes every channel, force and displacement alike,
//! through the same analogue Butterworth filter before sampling ([`AntiAlias`]); the filter
//! cancels in `X/F` and suppresses the aliases. Records must also be long enough for the
//! response to decay, or the DFT leaks (see [`ImpactTest::run`], which checks this).

use std::f64::consts::PI;

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

use crate::error::{Error, Result};
use crate::model::Coefficients;
use crate::records::Record;

/// The analogue anti-alias filter applied to every channel before sampling.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum AntiAlias {
    /// Sample the continuous signals directly (pulses alias).
    None,
    /// Butterworth low-pass of even `order` with cutoff `cutoff_ratio × sample_rate`.
    Butterworth {
        /// Filter order, even, 2–16.
        order: usize,
        /// Cutoff as a fraction of the sampling rate, in `(0, 0.5)`.
        cutoff_ratio: f64,
    },
}

impl Default for AntiAlias {
    /// 8th-order Butterworth at a quarter of the sampling rate: at `f_s` it attenuates by
    /// `4⁻⁸ ≈ 1.5·10⁻⁵`.
    fn default() -> Self {
        AntiAlias::Butterworth {
            order: 8,
            cutoff_ratio: 0.25,
        }
    }
}

/// One half-sine force pulse `f(t) = peak · d · sin(π (t − start)/duration)` on
/// `start ≤ t ≤ start + duration`.
#[derive(Debug, Clone, PartialEq)]
pub struct Impact {
    /// Direction `d` (one entry per degree of freedom, not necessarily unit length).
    pub direction: Vec<f64>,
    /// Peak force (N).
    pub peak_n: f64,
    /// Pulse duration (s).
    pub duration_s: f64,
    /// Start time from the record's first sample (s).
    pub start_s: f64,
}

/// Mixed into the seed of [`Simulator::random_record`]'s forcing, so that measurement noise
/// seeded with the same number is an unrelated stream.
const FORCING_STREAM: u64 = 0xD1B5_4A32_D192_ED03;

/// Matrix exponential by scaling and squaring with a 16-term Taylor series
/// (truncation below `10⁻²⁰` after scaling to norm ≤ 1/2).
fn expm(a: &Mat<f64>) -> Mat<f64> {
    let d = a.nrows();
    let norm = (0..d)
        .map(|i| (0..d).map(|j| a[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let squarings = if norm > 0.5 {
        (norm / 0.5).log2().ceil() as u32
    } else {
        0
    };
    let scaled = Mat::from_fn(d, d, |i, j| a[(i, j)] / f64::from(2u32.pow(squarings)));
    let mut result = Mat::<f64>::identity(d, d);
    let mut term = Mat::<f64>::identity(d, d);
    let mut next = Mat::<f64>::zeros(d, d);
    for k in 1..=16 {
        matmul(
            next.as_mut(),
            Accum::Replace,
            term.as_ref(),
            scaled.as_ref(),
            1.0 / k as f64,
            Par::Seq,
        );
        std::mem::swap(&mut term, &mut next);
        result += &term;
    }
    for _ in 0..squarings {
        matmul(
            next.as_mut(),
            Accum::Replace,
            result.as_ref(),
            result.as_ref(),
            1.0,
            Par::Seq,
        );
        std::mem::swap(&mut result, &mut next);
    }
    result
}

/// Exact sampled simulation of one system, planned for one sampling rate and record length.
///
/// # Examples
/// ```
/// use bearing_ident::model::Coefficients;
/// use bearing_ident::simulate::{AntiAlias, Impact, Simulator};
/// use faer::mat;
/// let sdof = Coefficients::new(mat![[1.0]], mat![[20.0]], mat![[4.0e4]])?;
/// let mut sim = Simulator::new(&sdof, 2000.0, 4000, AntiAlias::None)?;
/// let hit = Impact { direction: vec![1.0], peak_n: 100.0, duration_s: 0.001, start_s: 0.01 };
/// let rec = sim.record("hit", &[hit])?;
/// // Peak force is sampled at the pulse's middle; the response has decayed by the end.
/// assert!((rec.force(0)[21] - 100.0).abs() < 1e-9);
/// assert!(rec.displacement(0)[3999].abs() < 1e-12);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Simulator {
    n: usize,
    sample_rate: f64,
    samples: usize,
    anti_alias: AntiAlias,
    /// Structure part of `A` without the pulse generators' frequency.
    base: Mat<f64>,
    dim: usize,
    /// `(duration, Φ)` for the pulse durations seen so far.
    cache: Vec<(f64, Mat<f64>)>,
}

impl Simulator {
    /// Plans a simulation of `system` sampled at `sample_rate` Hz for `samples` samples.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive rate, fewer than 8 samples, or a filter
    /// order or cutoff out of range; [`Error::Singular`] if `M` is singular.
    pub fn new(
        system: &Coefficients,
        sample_rate: f64,
        samples: usize,
        anti_alias: AntiAlias,
    ) -> Result<Self> {
        use faer::prelude::Solve;
        if !(sample_rate.is_finite() && sample_rate > 0.0) {
            return Err(Error::InvalidParameter {
                name: "sample rate",
                value: sample_rate,
                expected: "finite and positive (Hz)",
            });
        }
        if samples < crate::records::MIN_SAMPLES {
            return Err(Error::InvalidParameter {
                name: "samples",
                value: samples as f64,
                expected: "at least 8",
            });
        }
        let order = match anti_alias {
            AntiAlias::None => 0,
            AntiAlias::Butterworth {
                order,
                cutoff_ratio,
            } => {
                if !(2..=16).contains(&order) || order % 2 != 0 {
                    return Err(Error::InvalidParameter {
                        name: "anti-alias order",
                        value: order as f64,
                        expected: "even, 2 to 16",
                    });
                }
                if !(cutoff_ratio > 0.0 && cutoff_ratio < 0.5) {
                    return Err(Error::InvalidParameter {
                        name: "anti-alias cutoff ratio",
                        value: cutoff_ratio,
                        expected: "0 < ratio < 0.5",
                    });
                }
                order
            }
        };
        system.eigenvalues()?; // rejects a singular mass matrix
        let n = system.dofs();
        let lu = system.mass().partial_piv_lu();
        let (mk, mc) = (lu.solve(system.stiffness()), lu.solve(system.damping()));
        let minv = lu.solve(Mat::<f64>::identity(n, n));
        // State: x (n), v (n), pulse generators (2 per dof), held forces (1 per dof, constant
        // between samples), filters (order per channel).
        let dim = 5 * n + 2 * n * order;
        let mut a = Mat::<f64>::zeros(dim, dim);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
            for j in 0..n {
                a[(n + i, j)] = -mk[(i, j)];
                a[(n + i, n + j)] = -mc[(i, j)];
                a[(n + i, 2 * n + 2 * j)] = minv[(i, j)];
                a[(n + i, 4 * n + j)] = minv[(i, j)];
            }
        }
        if let AntiAlias::Butterworth { cutoff_ratio, .. } = anti_alias {
            let wc = 2.0 * PI * cutoff_ratio * sample_rate;
            for c in 0..2 * n {
                // Channel input: force c (pulse generator plus held force) or displacement c − n.
                let inputs: &[usize] = if c < n {
                    &[2 * n + 2 * c, 4 * n + c]
                } else {
                    &[c - n]
                };
                for s in 0..order / 2 {
                    let q = 1.0 / (2.0 * (PI * (2 * s + 1) as f64 / (2 * order) as f64).cos());
                    let y = 5 * n + c * order + 2 * s;
                    if s == 0 {
                        for &u in inputs {
                            a[(y + 1, u)] += wc * wc;
                        }
                    } else {
                        a[(y + 1, y - 2)] += wc * wc;
                    }
                    a[(y, y + 1)] = 1.0;
                    a[(y + 1, y)] -= wc * wc;
                    a[(y + 1, y + 1)] = -wc / q;
                }
            }
        }
        Ok(Self {
            n,
            sample_rate,
            samples,
            anti_alias,
            base: a,
            dim,
            cache: Vec::new(),
        })
    }

    fn system_matrix(&self, duration_s: f64) -> Mat<f64> {
        let mut a = self.base.clone();
        let omega = PI / duration_s;
        for i in 0..self.n {
            let z = 2 * self.n + 2 * i;
            a[(z, z + 1)] = omega;
            a[(z + 1, z)] = -omega;
        }
        a
    }

    /// The state entries whose sum is the sampled value of `channel` (forces first).
    fn output_indices(&self, channel: usize) -> Vec<usize> {
        let n = self.n;
        match self.anti_alias {
            AntiAlias::Butterworth { order, .. } => vec![5 * n + channel * order + order - 2],
            AntiAlias::None if channel < n => vec![2 * n + 2 * channel, 4 * n + channel],
            AntiAlias::None => vec![channel - n],
        }
    }

    /// A noise-free record of the response to `impacts`, starting from rest.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a pulse with a non-positive duration or peak, a
    /// direction of the wrong length, a pulse outside the record, or pulses of different
    /// durations that overlap in time.
    pub fn record(&mut self, label: impl Into<String>, impacts: &[Impact]) -> Result<Record> {
        self.run(label.into(), impacts, &[])
    }

    /// A noise-free record of the response to independent white Gaussian forces on every
    /// degree of freedom (standard deviation `force_rms` N per sample, held constant between
    /// samples), starting from rest. The seed makes it reproducible.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless `force_rms` is finite and positive.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::simulate::{AntiAlias, Simulator, seed_rig};
    /// let mut sim = Simulator::new(&seed_rig(), 1000.0, 2000, AntiAlias::None)?;
    /// let rec = sim.random_record("shaker", 10.0, 3)?;
    /// let rms = (rec.force(1).iter().map(|f| f * f).sum::<f64>() / 2000.0).sqrt();
    /// assert!((rms / 10.0 - 1.0).abs() < 0.1);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn random_record(
        &mut self,
        label: impl Into<String>,
        force_rms: f64,
        seed: u64,
    ) -> Result<Record> {
        let dist = Normal::new(0.0, force_rms)
            .ok()
            .filter(|_| force_rms > 0.0 && force_rms.is_finite())
            .ok_or(Error::InvalidParameter {
                name: "force rms",
                value: force_rms,
                expected: "finite and positive (N)",
            })?;
        // A stream of its own: noise seeded with the same number must not copy the forcing.
        let mut rng = StdRng::seed_from_u64(seed ^ FORCING_STREAM);
        let hold: Vec<Vec<f64>> = (0..self.n)
            .map(|_| (0..self.samples).map(|_| dist.sample(&mut rng)).collect())
            .collect();
        self.run(label.into(), &[], &hold)
    }

    /// The simulation loop: `impacts` as pulse events and `hold[c][m]`, when given, as the
    /// force held on DOF `c` from sample `m` to `m + 1`.
    fn run(&mut self, label: String, impacts: &[Impact], hold: &[Vec<f64>]) -> Result<Record> {
        let duration_total = self.samples as f64 / self.sample_rate;
        debug_assert!(hold.is_empty() || hold.len() == self.n);
        for hit in impacts {
            let bad = |name, value, expected| {
                Err(Error::InvalidParameter {
                    name,
                    value,
                    expected,
                })
            };
            if !(hit.duration_s > 0.0 && hit.duration_s.is_finite()) {
                return bad("pulse duration", hit.duration_s, "finite and positive (s)");
            }
            if !(hit.peak_n.is_finite()) {
                return bad("pulse peak", hit.peak_n, "finite (N)");
            }
            if hit.direction.len() != self.n || hit.direction.iter().any(|d| !d.is_finite()) {
                return bad(
                    "pulse direction length",
                    hit.direction.len() as f64,
                    "one finite entry per degree of freedom",
                );
            }
            if !(hit.start_s >= 0.0 && hit.start_s + hit.duration_s <= duration_total) {
                return bad("pulse start", hit.start_s, "pulse inside the record");
            }
        }
        let mut events: Vec<(f64, usize, bool)> = impacts
            .iter()
            .enumerate()
            .flat_map(|(k, h)| [(h.start_s, k, true), (h.start_s + h.duration_s, k, false)])
            .collect();
        events.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
        let mut active: Option<usize> = None;
        for &(_, k, start) in &events {
            match (start, active) {
                (true, None) => active = Some(k),
                (false, Some(a)) if a == k => active = None,
                _ => {
                    return Err(Error::InvalidParameter {
                        name: "pulse start",
                        value: impacts[k].start_s,
                        expected: "pulses that do not overlap in time",
                    });
                }
            }
        }

        let dt = 1.0 / self.sample_rate;
        let dim = self.dim;
        let mut state = vec![0.0; dim];
        let mut next = vec![0.0; dim];
        let mut forces = vec![vec![0.0; self.samples]; self.n];
        let mut displacements = vec![vec![0.0; self.samples]; self.n];
        let out_f: Vec<Vec<usize>> = (0..self.n).map(|c| self.output_indices(c)).collect();
        let out_x: Vec<Vec<usize>> = (0..self.n)
            .map(|c| self.output_indices(self.n + c))
            .collect();
        let sample = |state: &[f64], idx: &[usize]| idx.iter().map(|&i| state[i]).sum::<f64>();
        let mut ev = 0;
        let mut current: Option<usize> = None;
        // Φ for "no pulse running" is any of them: generators are idle at zero state.
        let idle = impacts.first().map_or(1.0, |h| h.duration_s);
        for m in 0..self.samples {
            for (c, h) in hold.iter().enumerate() {
                state[4 * self.n + c] = h[m];
            }
            for c in 0..self.n {
                forces[c][m] = sample(&state, &out_f[c]);
                displacements[c][m] = sample(&state, &out_x[c]);
            }
            if m + 1 == self.samples {
                break;
            }
            let (t0, t1) = (m as f64 * dt, (m + 1) as f64 * dt);
            let mut t = t0;
            while ev < events.len() && events[ev].0 < t1 {
                let (te, k, start) = events[ev];
                let a = self.system_matrix(impacts[k].duration_s);
                propagate(&expm(&(&a * (te - t))), &mut state, &mut next);
                t = te;
                let hit = &impacts[k];
                for i in 0..self.n {
                    let z = 2 * self.n + 2 * i;
                    if start {
                        state[z] = 0.0;
                        state[z + 1] = hit.peak_n * hit.direction[i];
                    } else {
                        state[z] = 0.0;
                        state[z + 1] = 0.0;
                    }
                }
                current = start.then_some(k);
                ev += 1;
            }
            let duration = current.map_or(idle, |k| impacts[k].duration_s);
            if t > t0 {
                let a = self.system_matrix(duration);
                propagate(&expm(&(&a * (t1 - t))), &mut state, &mut next);
            } else {
                let phi = self.step_matrix(duration);
                propagate(phi, &mut state, &mut next);
            }
        }
        Record::new(label, self.sample_rate, forces, displacements)
    }

    fn step_matrix(&mut self, duration_s: f64) -> &Mat<f64> {
        #[allow(clippy::float_cmp)] // exact key lookup
        let pos = self.cache.iter().position(|(d, _)| *d == duration_s);
        let pos = match pos {
            Some(p) => p,
            None => {
                let a = self.system_matrix(duration_s);
                let phi = expm(&(&a * (1.0 / self.sample_rate)));
                self.cache.push((duration_s, phi));
                self.cache.len() - 1
            }
        };
        &self.cache[pos].1
    }
}

fn propagate(phi: &Mat<f64>, state: &mut Vec<f64>, next: &mut Vec<f64>) {
    let d = state.len();
    for (i, out) in next.iter_mut().enumerate() {
        let mut s = 0.0;
        for (j, v) in state.iter().enumerate().take(d) {
            s += phi[(i, j)] * v;
        }
        *out = s;
    }
    std::mem::swap(state, next);
}

/// Adds white Gaussian noise to a record: on every force channel with standard deviation
/// `level × RMS` of the record's force channels taken together (about their means), and
/// likewise for the displacements. An unexcited channel thus gets the same absolute noise as
/// the excited one, as in a real test.
///
/// # Errors
/// [`Error::InvalidParameter`] unless `0 ≤ level` and finite.
///
/// # Examples
/// ```
/// use bearing_ident::records::Record;
/// use bearing_ident::simulate::add_noise;
/// use rand::SeedableRng;
/// let x: Vec<f64> = (0..1000).map(|m| (m as f64 * 0.1).sin()).collect();
/// let clean = Record::new("r", 100.0, vec![x.clone()], vec![x])?;
/// let mut rng = rand::rngs::StdRng::seed_from_u64(7);
/// let noisy = add_noise(&clean, 0.1, &mut rng)?;
/// let err: f64 = noisy.force(0).iter().zip(clean.force(0)).map(|(a, b)| (a - b).powi(2)).sum();
/// let rms = (err / 1000.0).sqrt();
/// assert!((rms / (0.5f64).sqrt() - 0.1).abs() < 0.01);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn add_noise(record: &Record, level: f64, rng: &mut StdRng) -> Result<Record> {
    if !(level >= 0.0 && level.is_finite()) {
        return Err(Error::InvalidParameter {
            name: "noise level",
            value: level,
            expected: "finite and ≥ 0",
        });
    }
    let n = record.dofs();
    let rms = |channels: Vec<&[f64]>| {
        let mut sum = 0.0;
        for ch in channels {
            let mean = ch.iter().sum::<f64>() / ch.len() as f64;
            sum += ch.iter().map(|v| (v - mean).powi(2)).sum::<f64>();
        }
        (sum / (n * record.len()) as f64).sqrt()
    };
    let sf = level * rms((0..n).map(|c| record.force(c)).collect());
    let sx = level * rms((0..n).map(|c| record.displacement(c)).collect());
    let mut noisy = |ch: &[f64], sigma: f64| -> Vec<f64> {
        match Normal::new(0.0, sigma) {
            Ok(dist) if sigma > 0.0 => ch.iter().map(|v| v + dist.sample(rng)).collect(),
            _ => ch.to_vec(),
        }
    };
    let forces = (0..n).map(|c| noisy(record.force(c), sf)).collect();
    let displacements = (0..n).map(|c| noisy(record.displacement(c), sx)).collect();
    Record::new(record.label(), record.sample_rate(), forces, displacements)
}

/// An impact test campaign: `per_direction` hammer hits along each degree of freedom in turn.
///
/// # Examples
/// ```
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let test = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() };
/// let records = test.run(&seed_rig())?;
/// assert_eq!(records.len(), 2);
/// assert_eq!(records[0].len(), 8040);
/// assert_eq!(records[1].dominant_force(), 1);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ImpactTest {
    /// Hits per degree of freedom (records per direction).
    pub per_direction: usize,
    /// Sampling rate (Hz).
    pub sample_rate: f64,
    /// Record length (s).
    pub duration_s: f64,
    /// Half-sine pulse duration (s).
    pub pulse_s: f64,
    /// Nominal peak force (N); hits vary by ±10 % about it.
    pub peak_n: f64,
    /// Time before the pulse starts (s).
    pub pretrigger_s: f64,
    /// Off-axis force as a fraction of the on-axis one (a hammer is never perfectly aimed);
    /// it alternates in sign from hit to hit.
    pub off_axis: f64,
    /// Noise level, see [`add_noise`].
    pub noise: f64,
    /// Seed of the noise generator.
    pub seed: u64,
    /// Anti-alias filter of the simulated acquisition.
    pub anti_alias: AntiAlias,
}

impl ImpactTest {
    /// The seed's test: 8 hits per direction at 6700 samples/s for 1.2 s (8040 samples),
    /// 2 ms pulses of about 500 N, 20 ms pre-trigger, 5 % off-axis, no noise.
    pub fn seed_rig() -> Self {
        Self {
            per_direction: 8,
            sample_rate: 6700.0,
            duration_s: 1.2,
            pulse_s: 0.002,
            peak_n: 500.0,
            pretrigger_s: 0.02,
            off_axis: 0.05,
            noise: 0.0,
            seed: 1,
            anti_alias: AntiAlias::default(),
        }
    }

    /// Number of samples per record, `round(duration × rate)`.
    pub fn samples(&self) -> usize {
        (self.duration_s * self.sample_rate).round() as usize
    }

    /// Noise-free records of the test on `system`, hits along DOF 0 first, then DOF 1, ….
    ///
    /// # Errors
    /// As [`Simulator::new`] and [`Simulator::record`]; [`Error::InvalidParameter`] if the
    /// slowest mode has not decayed to `10⁻⁶` of its amplitude by the end of the record
    /// (the records would leak).
    pub fn run_clean(&self, system: &Coefficients) -> Result<Vec<Record>> {
        let slowest = system
            .eigenvalues()?
            .iter()
            .map(|l| -l.re)
            .fold(f64::INFINITY, f64::min);
        let decay_time = self.duration_s - self.pretrigger_s - self.pulse_s;
        let decays = slowest * decay_time >= 6.0 * std::f64::consts::LN_10;
        if !decays {
            return Err(Error::InvalidParameter {
                name: "record duration",
                value: self.duration_s,
                expected: "long enough for the slowest mode to decay to 1e-6",
            });
        }
        let n = system.dofs();
        let mut sim = Simulator::new(system, self.sample_rate, self.samples(), self.anti_alias)?;
        let mut out = Vec::with_capacity(n * self.per_direction);
        for dof in 0..n {
            for hit in 0..self.per_direction {
                let sign = if hit % 2 == 0 { 1.0 } else { -1.0 };
                let direction = (0..n)
                    .map(|i| {
                        if i == dof {
                            1.0
                        } else if i == (dof + 1) % n {
                            sign * self.off_axis
                        } else {
                            0.0
                        }
                    })
                    .collect();
                let impact = Impact {
                    direction,
                    peak_n: self.peak_n * (1.0 + 0.05 * ((hit * 7 % 5) as f64 - 2.0)),
                    duration_s: self.pulse_s,
                    start_s: self.pretrigger_s,
                };
                out.push(sim.record(format!("impact-dof{dof}-{hit}"), &[impact])?);
            }
        }
        Ok(out)
    }

    /// [`ImpactTest::run_clean`] plus noise at [`ImpactTest::noise`], seeded by
    /// [`ImpactTest::seed`].
    ///
    /// # Errors
    /// As [`ImpactTest::run_clean`] and [`add_noise`].
    pub fn run(&self, system: &Coefficients) -> Result<Vec<Record>> {
        let clean = self.run_clean(system)?;
        let mut rng = StdRng::seed_from_u64(self.seed);
        clean
            .iter()
            .map(|r| add_noise(r, self.noise, &mut rng))
            .collect()
    }
}

/// The seed's test rig (Diaz & San Andrés 1999) as a 2-DOF system: `M = diag(4.7, 4.8)` kg,
/// `K = [[146.3, 22.3], [11.5, 169.1]]` kN/m (their identified averages) and
/// `C = diag(131.98, 131.98)` N·s/m — the short-damper closed form 109.68 N·s/m
/// (`μ = 2.25 cP, D = 50.8 mm, L = 25.4 mm, c = 0.29 mm`) plus 22.3 N·s/m of dry structural
/// damping. Natural frequencies about 27.5 and 30.6 Hz, damping ratios about 8 %.
pub fn seed_rig() -> Coefficients {
    let m = faer::mat![[4.7, 0.0], [0.0, 4.8]];
    let c = faer::mat![[131.98, 0.0], [0.0, 131.98]];
    let k = faer::mat![[146.3e3, 22.3e3], [11.5e3, 169.1e3]];
    Coefficients::new(m, c, k).expect("constant, valid coefficients")
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn expm_of_rotation_generator() {
        let a = mat![[0.0, 2.0], [-2.0, 0.0]];
        let e = expm(&a);
        assert!((e[(0, 0)] - 2f64.cos()).abs() < 1e-14);
        assert!((e[(0, 1)] - 2f64.sin()).abs() < 1e-14);
    }

    #[test]
    fn sdof_response_matches_closed_form_without_filter() {
        // Undamped SDOF, ω_n = 2π·10, pulse 5 ms: after the pulse, free vibration with
        // amplitude from the exact Duhamel integral.
        let (m, k) = (1.0, (2.0 * PI * 10.0_f64).powi(2));
        let sys = Coefficients::new(mat![[m]], mat![[0.0]], mat![[k]]).unwrap();
        let mut sim = Simulator::new(&sys, 1000.0, 200, AntiAlias::None).unwrap();
        let (p, t_p) = (10.0, 0.005);
        let hit = Impact {
            direction: vec![1.0],
            peak_n: p,
            duration_s: t_p,
            start_s: 0.0,
        };
        let rec = sim.record("r", &[hit]).unwrap();
        let wn = (k / m).sqrt();
        let om = PI / t_p;
        // x(t) for t ≤ T: p/(k(1−r²)) (sin Ωt − r sin ωn t), r = Ω/ωn.
        let r = om / wn;
        for s in 0..5 {
            let t = s as f64 * 0.001;
            let exact = p / (k * (1.0 - r * r)) * ((om * t).sin() - r * (wn * t).sin());
            assert!(
                (rec.displacement(0)[s] - exact).abs() < 1e-12 * p / k,
                "sample {s}"
            );
        }
        assert!((rec.force(0)[2] - p * (om * 0.002).sin()).abs() < 1e-10);
    }

    #[test]
    fn random_forcing_and_noise_with_one_seed_are_unrelated() {
        let mut sim = Simulator::new(&seed_rig(), 1000.0, 20_000, AntiAlias::None).unwrap();
        let rec = sim.random_record("r", 1.0, 5).unwrap();
        let mut rng = StdRng::seed_from_u64(5);
        let noisy = add_noise(&rec, 1.0, &mut rng).unwrap();
        let (f, nf) = (rec.force(0), noisy.force(0));
        let noise: Vec<f64> = nf.iter().zip(f).map(|(a, b)| a - b).collect();
        let dot: f64 = noise.iter().zip(f).map(|(a, b)| a * b).sum();
        let corr = dot
            / (noise.iter().map(|v| v * v).sum::<f64>() * f.iter().map(|v| v * v).sum::<f64>())
                .sqrt();
        // Independent streams: |ρ| ~ 1/√20000 ≈ 0.007.
        assert!(corr.abs() < 0.03, "correlation {corr}");
    }

    #[test]
    fn invalid_parameters_are_refused() {
        let sys = seed_rig();
        assert!(Simulator::new(&sys, 0.0, 100, AntiAlias::None).is_err());
        assert!(Simulator::new(&sys, 100.0, 4, AntiAlias::None).is_err());
        let bad = AntiAlias::Butterworth {
            order: 3,
            cutoff_ratio: 0.25,
        };
        assert!(matches!(
            Simulator::new(&sys, 100.0, 100, bad),
            Err(Error::InvalidParameter { .. })
        ));
        let mut sim = Simulator::new(&sys, 1000.0, 100, AntiAlias::None).unwrap();
        let hit = |start_s| Impact {
            direction: vec![1.0, 0.0],
            peak_n: 1.0,
            duration_s: 0.01,
            start_s,
        };
        assert!(sim.record("r", &[hit(0.095)]).is_err());
        assert!(sim.record("r", &[hit(0.01), hit(0.015)]).is_err());
        assert!(
            sim.record(
                "r",
                &[Impact {
                    direction: vec![1.0],
                    ..hit(0.0)
                }]
            )
            .is_err()
        );
        let short = ImpactTest {
            duration_s: 0.1,
            ..ImpactTest::seed_rig()
        };
        assert!(matches!(
            short.run(&sys),
            Err(Error::InvalidParameter {
                name: "record duration",
                ..
            })
        ));
        let mut rng = StdRng::seed_from_u64(0);
        let rec = sim.record("r", &[hit(0.0)]).unwrap();
        assert!(add_noise(&rec, -1.0, &mut rng).is_err());
    }
}
