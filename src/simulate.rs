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
use std::ops::RangeInclusive;

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal, Uniform};

use crate::error::{Channel, Error, Result};
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

/// Most samples in one simulated record (or one drive signal): `2²⁴`, about 16.8 million
/// (42 minutes at 6.7 kHz). Larger requests are [`Error::TooLarge`], never an allocation.
pub const MAX_SAMPLES: usize = 1 << 24;

/// Most records one simulated test may produce ([`ImpactTest`], and the CLI's `simulate`).
pub const MAX_RECORDS: usize = 4096;

/// Most degrees of freedom a [`Simulator`] accepts (its state has `(5 + 2·order) n` entries).
pub const MAX_DOFS: usize = 16;

/// Most samples × records of one simulated test, `2²⁸`: bounds the time of a simulation.
pub const MAX_TOTAL_SAMPLES: usize = 1 << 28;

/// Most operations (samples × lines) in computing one multisine period, `2³²`.
const MAX_MULTISINE_WORK: usize = 1 << 32;

/// `Ok` if `value ≤ limit`, else [`Error::TooLarge`].
fn at_most(what: &'static str, value: f64, limit: usize) -> Result<()> {
    if value <= limit as f64 {
        Ok(())
    } else {
        Err(Error::TooLarge {
            what,
            value,
            limit: limit as f64,
        })
    }
}

/// Number of samples of a record `duration_s` long at `sample_rate`, `round(duration × rate)`,
/// checked: both finite and positive, and at most [`MAX_SAMPLES`].
///
/// # Errors
/// [`Error::InvalidParameter`] for a duration or rate that is not finite and positive;
/// [`Error::TooLarge`] past [`MAX_SAMPLES`].
///
/// # Examples
/// ```
/// use bearing_ident::simulate::sample_count;
/// assert_eq!(sample_count(1.2, 6700.0)?, 8040);
/// assert!(sample_count(1e30, 6700.0).is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn sample_count(duration_s: f64, sample_rate: f64) -> Result<usize> {
    if !(sample_rate.is_finite() && sample_rate > 0.0) {
        return Err(Error::InvalidParameter {
            name: "sample rate",
            value: sample_rate,
            expected: "finite and positive (Hz)",
        });
    }
    if !(duration_s.is_finite() && duration_s > 0.0) {
        return Err(Error::InvalidParameter {
            name: "record duration",
            value: duration_s,
            expected: "finite and positive (s)",
        });
    }
    let samples = (duration_s * sample_rate).round();
    at_most("samples per record", samples, MAX_SAMPLES)?;
    Ok(samples as usize)
}

/// The slowest decay rate of a system, `min(−Re λ)` over its eigenvalues (1/s), checked: a
/// mass matrix whose symmetric part is not positive definite, or a system with a mode that
/// does not decay, is an error naming the matrix.
///
/// # Errors
/// [`Error::InvalidParameter`] naming `"mass matrix"` (value: the smallest eigenvalue of its
/// symmetric part), `"stiffness matrix"` (likewise, when a mode does not decay and `K` is not
/// positive definite) or `"damping matrix"` (value: the slowest decay rate); the
/// [`Coefficients::eigenvalues`] errors.
///
/// # Examples
/// ```
/// use bearing_ident::simulate::{seed_rig, slowest_decay};
/// // The seed's rig: 8 % damping at about 27.5 Hz.
/// assert!((slowest_decay(&seed_rig())? - 13.9).abs() < 0.1);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn slowest_decay(system: &Coefficients) -> Result<f64> {
    let min_sym_eig = |a: faer::MatRef<'_, f64>| -> Result<f64> {
        let n = a.nrows();
        let sym = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
        let eig = sym.self_adjoint_eigenvalues(faer::Side::Lower)?;
        Ok(eig.iter().copied().fold(f64::INFINITY, f64::min))
    };
    let mass = min_sym_eig(system.mass().as_ref())?;
    if mass.is_nan() || mass <= 0.0 {
        return Err(Error::InvalidParameter {
            name: "mass matrix",
            value: mass,
            expected: "positive definite (smallest eigenvalue of its symmetric part > 0)",
        });
    }
    let slowest = system
        .eigenvalues()?
        .iter()
        .map(|l| -l.re)
        .fold(f64::INFINITY, f64::min);
    if !(slowest > 0.0 && slowest.is_finite()) {
        let stiffness = min_sym_eig(system.stiffness().as_ref())?;
        return Err(if stiffness > 0.0 {
            Error::InvalidParameter {
                name: "damping matrix",
                value: slowest + 0.0, // no "-0" in the message
                expected: "a decay rate > 0 for every mode (−Re λ, 1/s)",
            }
        } else {
            Error::InvalidParameter {
                name: "stiffness matrix",
                value: stiffness,
                expected: "positive definite, or every mode decays",
            }
        });
    }
    Ok(slowest)
}

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
    // 2^-squarings as f64: an integer power of two overflows past 31 squarings (a fast filter
    // at a high sampling rate).
    let scale = 0.5f64.powi(squarings.min(2000) as i32);
    let scaled = Mat::from_fn(d, d, |i, j| a[(i, j)] * scale);
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
    /// order or cutoff out of range; [`Error::TooLarge`] for more than [`MAX_SAMPLES`] samples
    /// or [`MAX_DOFS`] degrees of freedom; [`Error::Singular`] if `M` is singular.
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
        at_most("samples per record", samples as f64, MAX_SAMPLES)?;
        at_most("degrees of freedom", system.dofs() as f64, MAX_DOFS)?;
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

    /// A noise-free record of the response to user-given forces held constant between samples
    /// (zero-order hold), starting from rest: `forces[c][m]` acts on degree of freedom `c` from
    /// sample `m` to `m + 1`. The recorded force channels are that staircase passed through the
    /// same anti-alias filter as the displacements, so the ratio of their spectra is `G(ω)`.
    /// Build the samples with [`sine`], [`multisine`] or [`sweep`], or supply your own.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless there is one channel per degree of freedom, each
    /// exactly as long as the simulator's record; [`Error::NonFinite`] (naming the record, force
    /// channel and sample) for a NaN or infinite sample.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::model::Coefficients;
    /// use bearing_ident::simulate::{AntiAlias, Simulator, sine};
    /// use faer::mat;
    /// // A static load on an SDOF spring: 10 N on 1e4 N/m gives 1 mm once settled.
    /// let sdof = Coefficients::new(mat![[1.0]], mat![[40.0]], mat![[1.0e4]])?;
    /// let mut sim = Simulator::new(&sdof, 1000.0, 2000, AntiAlias::None)?;
    /// let rec = sim.held_record("static", &[vec![10.0; 2000]])?;
    /// assert!((rec.displacement(0)[1999] - 1.0e-3).abs() < 1e-12);
    /// // One channel per degree of freedom, each `samples` long.
    /// assert!(sim.held_record("short", &[sine(5.0, 1.0, 1000.0, 10)?]).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn held_record(&mut self, label: impl Into<String>, forces: &[Vec<f64>]) -> Result<Record> {
        let label = label.into();
        if forces.len() != self.n {
            return Err(Error::InvalidParameter {
                name: "held force channels",
                value: forces.len() as f64,
                expected: "one channel per degree of freedom",
            });
        }
        for (c, channel) in forces.iter().enumerate() {
            if channel.len() != self.samples {
                return Err(Error::InvalidParameter {
                    name: "held force length",
                    value: channel.len() as f64,
                    expected: "exactly the simulator's number of samples",
                });
            }
            if let Some((sample, &value)) = channel.iter().enumerate().find(|(_, v)| !v.is_finite())
            {
                return Err(Error::NonFinite {
                    record: label,
                    channel: Channel::Force(c),
                    sample,
                    value,
                });
            }
        }
        self.run(label, &[], forces)
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

/// Checks a sampling rate and a frequency strictly between DC and Nyquist.
fn check_frequency(name: &'static str, freq_hz: f64, sample_rate: f64) -> Result<()> {
    if !(sample_rate.is_finite() && sample_rate > 0.0) {
        return Err(Error::InvalidParameter {
            name: "sample rate",
            value: sample_rate,
            expected: "finite and positive (Hz)",
        });
    }
    if !(freq_hz.is_finite() && freq_hz > 0.0 && freq_hz < sample_rate / 2.0) {
        return Err(Error::InvalidParameter {
            name,
            value: freq_hz,
            expected: "0 < frequency < sample rate / 2 (Hz)",
        });
    }
    Ok(())
}

/// Samples of a sine force $f_m = A \sin(2\pi f\, m/f_s)$, `m = 0 … samples − 1`, for
/// [`Simulator::held_record`]. The drive starts at zero force; the response reaches its steady
/// state after the free vibration it starts has decayed (about `6 ln 10 / (ζ ω_n)` seconds for
/// `10⁻⁶`), which a test discards with [`Record::trimmed`].
///
/// # Errors
/// [`Error::InvalidParameter`] unless the sampling rate is finite and positive, `0 < f < f_s/2`,
/// and the amplitude is finite; [`Error::TooLarge`] for more than [`MAX_SAMPLES`] samples.
///
/// # Examples
/// ```
/// use bearing_ident::simulate::sine;
/// // 50 Hz at 1000 samples/s: a quarter period is 5 samples.
/// let f = sine(50.0, 20.0, 1000.0, 100)?;
/// assert!((f[5] - 20.0).abs() < 1e-12);
/// assert!(sine(600.0, 20.0, 1000.0, 100).is_err()); // above Nyquist
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn sine(freq_hz: f64, amplitude_n: f64, sample_rate: f64, samples: usize) -> Result<Vec<f64>> {
    check_frequency("sine frequency", freq_hz, sample_rate)?;
    at_most("samples per record", samples as f64, MAX_SAMPLES)?;
    if !amplitude_n.is_finite() {
        return Err(Error::InvalidParameter {
            name: "sine amplitude",
            value: amplitude_n,
            expected: "finite (N)",
        });
    }
    let w = 2.0 * PI * freq_hz / sample_rate;
    Ok((0..samples)
        .map(|m| amplitude_n * (w * m as f64).sin())
        .collect())
}

/// Samples of a random-phase multisine with period `period` samples: equal-amplitude cosines on
/// the DFT lines `k ∈ lines` of one period,
///
/// $$ f_m = a \sum_{k \in \text{lines}} \cos\!\left(\frac{2\pi k m}{P} + \varphi_k\right),
///    \qquad a = f_\text{rms}\sqrt{2/L}, $$
///
/// with `P = period`, `L` the number of lines and phases `φ_k` uniform on `[0, 2π)` drawn from a
/// `StdRng` seeded with `seed`. Over any whole period the RMS is exactly `rms_n` and the DFT is
/// nonzero on the excited lines only (line `k` lies at `k f_s / P` Hz), so records cut to whole
/// periods in steady state need no window and do not leak. The samples repeat with period `P`
/// over all `samples`.
///
/// # Errors
/// [`Error::InvalidParameter`] for a period below 8 samples, an empty range of lines, line 0
/// (DC) or a line at or above `P/2` (Nyquist), or an RMS that is not finite and positive;
/// [`Error::TooLarge`] for a period or record of more than [`MAX_SAMPLES`] samples, or more
/// than `2³²` period samples × lines.
///
/// # Examples
/// ```
/// use bearing_ident::simulate::multisine;
/// // 1 Hz lines at 1000 samples/s, 5–20 Hz, 3 N RMS, two periods.
/// let f = multisine(1000, 5..=20, 3.0, 2000, 7)?;
/// let rms = (f[..1000].iter().map(|v| v * v).sum::<f64>() / 1000.0).sqrt();
/// assert!((rms - 3.0).abs() < 1e-12);
/// assert!((f[1234] - f[234]).abs() < 1e-12); // periodic
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn multisine(
    period: usize,
    lines: RangeInclusive<usize>,
    rms_n: f64,
    samples: usize,
    seed: u64,
) -> Result<Vec<f64>> {
    if period < crate::records::MIN_SAMPLES {
        return Err(Error::InvalidParameter {
            name: "multisine period",
            value: period as f64,
            expected: "at least 8 samples",
        });
    }
    let (first, last) = (*lines.start(), *lines.end());
    if lines.is_empty() || first == 0 || 2 * last >= period {
        return Err(Error::InvalidParameter {
            name: "multisine lines",
            value: if first == 0 { 0.0 } else { last as f64 },
            expected: "a non-empty range of lines 1 ≤ k < period / 2",
        });
    }
    if !(rms_n.is_finite() && rms_n > 0.0) {
        return Err(Error::InvalidParameter {
            name: "multisine rms",
            value: rms_n,
            expected: "finite and positive (N)",
        });
    }
    at_most(
        "samples per record",
        samples.max(period) as f64,
        MAX_SAMPLES,
    )?;
    let count = last - first + 1;
    at_most(
        "multisine period × lines",
        period as f64 * count as f64,
        MAX_MULTISINE_WORK,
    )?;
    let a = rms_n * (2.0 / count as f64).sqrt();
    let mut rng = StdRng::seed_from_u64(seed);
    let uniform = Uniform::new(0.0, 2.0 * PI).expect("constant, valid range");
    let phases: Vec<f64> = (0..count).map(|_| uniform.sample(&mut rng)).collect();
    let one: Vec<f64> = (0..period)
        .map(|m| {
            phases
                .iter()
                .zip(first..=last)
                .map(|(phi, k)| {
                    // k·m reduced modulo the period keeps the argument small and exact.
                    let km = (k * m % period) as f64;
                    (2.0 * PI * km / period as f64 + phi).cos()
                })
                .sum::<f64>()
                * a
        })
        .collect();
    Ok((0..samples).map(|m| one[m % period]).collect())
}

/// Fraction of a sweep's duration tapered by a raised cosine at each end (see [`sweep`]).
pub const SWEEP_TAPER: f64 = 0.05;

/// Samples of a linear sweep (chirp) from `f0` to `f1` Hz over `T = sweep_s` seconds, then zero
/// force for the rest of the record, so that the response can decay within it:
///
/// $$ f(t) = A\,w(t) \sin\!\left(2\pi\left(f_0 t + \frac{f_1 - f_0}{2T} t^2\right)\right),
///    \quad 0 \le t < T, \qquad f(t) = 0,\ t \ge T, $$
///
/// where `w` rises as a raised cosine over the first [`SWEEP_TAPER`]` · T` and falls likewise
/// over the last (a Tukey window): the abrupt ends of an untapered chirp ripple its spectrum.
/// The RMS over the sweep is close to $A\sqrt{(1 - \tfrac{5}{4}\,\text{SWEEP\_TAPER})/2}$. With
/// the response decayed by the end of the record, one DFT of the whole record gives `G(ω)`
/// without a window, as for impacts.
///
/// # Errors
/// [`Error::InvalidParameter`] unless the sampling rate is finite and positive, both
/// frequencies lie strictly between 0 and `f_s/2`, `sweep_s` is finite and positive and fits
/// in `samples`, and the amplitude is finite; [`Error::TooLarge`] for more than
/// [`MAX_SAMPLES`] samples.
///
/// # Examples
/// ```
/// use bearing_ident::simulate::sweep;
/// // 5 → 60 Hz in 1 s at 2000 samples/s, then 1.5 s of silence.
/// let f = sweep(5.0, 60.0, 1.0, 10.0, 2000.0, 5000)?;
/// let rms = (f[..2000].iter().map(|v| v * v).sum::<f64>() / 2000.0).sqrt();
/// assert!((rms / 6.847 - 1.0).abs() < 0.01);
/// assert!(f[2000..].iter().all(|&v| v == 0.0));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn sweep(
    f0_hz: f64,
    f1_hz: f64,
    sweep_s: f64,
    amplitude_n: f64,
    sample_rate: f64,
    samples: usize,
) -> Result<Vec<f64>> {
    check_frequency("sweep start frequency", f0_hz, sample_rate)?;
    check_frequency("sweep end frequency", f1_hz, sample_rate)?;
    at_most("samples per record", samples as f64, MAX_SAMPLES)?;
    if !(sweep_s.is_finite() && sweep_s > 0.0 && sweep_s * sample_rate <= samples as f64 + 0.5) {
        return Err(Error::InvalidParameter {
            name: "sweep duration",
            value: sweep_s,
            expected: "finite, positive and within the record (s)",
        });
    }
    if !amplitude_n.is_finite() {
        return Err(Error::InvalidParameter {
            name: "sweep amplitude",
            value: amplitude_n,
            expected: "finite (N)",
        });
    }
    let active = ((sweep_s * sample_rate).round() as usize).min(samples);
    let taper = SWEEP_TAPER * sweep_s;
    let rate = (f1_hz - f0_hz) / sweep_s;
    Ok((0..samples)
        .map(|m| {
            if m >= active {
                return 0.0;
            }
            let t = m as f64 / sample_rate;
            let edge = t.min(sweep_s - t);
            let w = if edge < taper {
                0.5 * (1.0 - (PI * edge / taper).cos())
            } else {
                1.0
            };
            amplitude_n * w * (2.0 * PI * (f0_hz * t + 0.5 * rate * t * t)).sin()
        })
        .collect())
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
    ///
    /// # Errors
    /// As [`sample_count`].
    pub fn samples(&self) -> Result<usize> {
        sample_count(self.duration_s, self.sample_rate)
    }

    /// Noise-free records of the test on `system`, hits along DOF 0 first, then DOF 1, ….
    ///
    /// # Errors
    /// As [`Simulator::new`], [`Simulator::record`], [`sample_count`] and [`slowest_decay`]
    /// (a mass that is not positive definite, a mode that does not decay);
    /// [`Error::InvalidParameter`] if the slowest mode has not decayed to `10⁻⁶` of its
    /// amplitude by the end of the record (the records would leak); [`Error::TooLarge`] for
    /// more than [`MAX_RECORDS`] records or [`MAX_TOTAL_SAMPLES`] samples in all.
    pub fn run_clean(&self, system: &Coefficients) -> Result<Vec<Record>> {
        let samples = self.samples()?;
        let n = system.dofs();
        let records = self.per_direction as f64 * n as f64;
        at_most("records", records, MAX_RECORDS)?;
        at_most(
            "samples × records",
            records * samples as f64,
            MAX_TOTAL_SAMPLES,
        )?;
        let slowest = slowest_decay(system)?;
        let decay_time = self.duration_s - self.pretrigger_s - self.pulse_s;
        let decays = slowest * decay_time >= 6.0 * std::f64::consts::LN_10;
        if !decays {
            return Err(Error::InvalidParameter {
                name: "record duration",
                value: self.duration_s,
                expected: "long enough for the slowest mode to decay to 1e-6",
            });
        }
        let mut sim = Simulator::new(system, self.sample_rate, samples, self.anti_alias)?;
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

    /// `Σ_m x_m e^{−iωm/f_s}` over a slice (a direct DFT at one frequency).
    fn dft_at(x: &[f64], freq_hz: f64, sample_rate: f64) -> num_complex::Complex64 {
        let w = 2.0 * PI * freq_hz / sample_rate;
        x.iter()
            .enumerate()
            .map(|(m, v)| num_complex::Complex64::from_polar(*v, -w * m as f64))
            .sum()
    }

    #[test]
    fn sine_drive_reaches_the_closed_form_steady_state() {
        // SDOF m = 1 kg, c = 20 N·s/m, k = 4e4 N/m (31.8 Hz, ζ = 5 %, decay 10 s⁻¹): after
        // 2 s the start-up transient is e⁻²⁰ ≈ 2e-9 of itself. The last second holds 10 whole
        // periods of 10 Hz, so the DFT at 10 Hz is exact and X/F = 1/(k − ω²m + iωc).
        let (m, c, k, f, fs) = (1.0, 20.0, 4.0e4, 10.0, 1000.0);
        let sys = Coefficients::new(mat![[m]], mat![[c]], mat![[k]]).unwrap();
        let mut sim = Simulator::new(&sys, fs, 3000, AntiAlias::default()).unwrap();
        let drive = sine(f, 5.0, fs, 3000).unwrap();
        let rec = sim.held_record("sine", &[drive]).unwrap();
        let steady = rec.trimmed(2000..3000).unwrap();
        let ratio = dft_at(steady.displacement(0), f, fs) / dft_at(steady.force(0), f, fs);
        let w = 2.0 * PI * f;
        let exact = num_complex::Complex64::new(k - w * w * m, w * c).inv();
        let err = (ratio / exact - 1.0).norm();
        assert!(err < 1e-6, "relative error {err:.3e}");
        // Amplitude and phase separately, for the record.
        assert!((ratio.norm() / exact.norm() - 1.0).abs() < 1e-6);
        assert!((ratio.arg() - exact.arg()).abs() < 1e-6);
    }

    #[test]
    fn multisine_spectrum_lives_on_its_lines_only() {
        let period = 256;
        let f = multisine(period, 5..=40, 2.0, 3 * period, 11).unwrap();
        // Any whole period, not only the first, has the same line spectrum.
        let one = &f[100..100 + period];
        let spectrum: Vec<f64> = (0..=period / 2)
            .map(|k| dft_at(one, k as f64, period as f64).norm())
            .collect();
        let peak = spectrum.iter().cloned().fold(0.0, f64::max);
        for (k, &a) in spectrum.iter().enumerate() {
            if (5..=40).contains(&k) {
                // Equal amplitudes a·P/2 with a = rms·√(2/L).
                let expected = 2.0 * (2.0 / 36.0_f64).sqrt() * period as f64 / 2.0;
                assert!((a / expected - 1.0).abs() < 1e-10, "line {k}: {a}");
            } else {
                assert!(a < 1e-10 * peak, "line {k}: {a:.3e}");
            }
        }
        let rms = (one.iter().map(|v| v * v).sum::<f64>() / period as f64).sqrt();
        assert!((rms - 2.0).abs() < 1e-12);
        // Another seed, other phases.
        let g = multisine(period, 5..=40, 2.0, period, 12).unwrap();
        assert!(g.iter().zip(&f).any(|(a, b)| (a - b).abs() > 1e-3));
        for bad in [
            multisine(4, 1..=1, 1.0, 10, 0),
            multisine(256, 0..=10, 1.0, 10, 0),
            multisine(256, 5..=128, 1.0, 10, 0),
            multisine(256, 5..=10, 0.0, 10, 0),
            multisine(256, 5..=10, f64::NAN, 10, 0),
        ] {
            assert!(matches!(bad, Err(Error::InvalidParameter { .. })));
        }
    }

    #[test]
    fn sweep_has_its_rms_extent_and_band() {
        let (fs, a) = (2000.0, 10.0);
        let f = sweep(5.0, 60.0, 1.0, a, fs, 5000).unwrap();
        assert_eq!(f.len(), 5000);
        let active = &f[..2000];
        let rms = (active.iter().map(|v| v * v).sum::<f64>() / 2000.0).sqrt();
        let expected = a * ((1.0 - 1.25 * SWEEP_TAPER) / 2.0).sqrt();
        assert!(
            (rms / expected - 1.0).abs() < 0.005,
            "rms {rms}, expected {expected}"
        );
        assert!(f[2000..].iter().all(|v| v.abs() < f64::MIN_POSITIVE));
        assert!(active.iter().all(|v| v.abs() <= a));
        // Tapered ends: the first and last samples are (nearly) zero.
        assert!(f[0].abs() < 1e-12 && f[1999].abs() < 0.01 * a);
        // The energy is in the swept band.
        let energy = |lo: f64, hi: f64| {
            let df = fs / 5000.0;
            let (k0, k1) = ((lo / df) as usize, (hi / df) as usize);
            (k0..=k1)
                .map(|k| dft_at(&f, k as f64 * df, fs).norm_sqr())
                .sum::<f64>()
        };
        let inside = energy(5.0, 60.0);
        // A chirp at 55 Hz/s spreads about √55 ≈ 7 Hz past its ends (Fresnel ripple): measured
        // 0.38 % of the energy in 0.4–3 Hz and 0.13 % in 66–120 Hz.
        assert!(energy(0.4, 3.0) < 0.01 * inside);
        assert!(energy(66.0, 120.0) < 0.01 * inside);
        assert!(energy(10.0, 55.0) > 0.8 * inside);
        for bad in [
            sweep(0.0, 60.0, 1.0, a, fs, 5000),
            sweep(5.0, 1000.0, 1.0, a, fs, 5000),
            sweep(5.0, 60.0, 3.0, a, fs, 5000),
            sweep(5.0, 60.0, -1.0, a, fs, 5000),
            sweep(5.0, 60.0, 1.0, f64::INFINITY, fs, 5000),
            sweep(5.0, 60.0, 1.0, a, 0.0, 5000),
        ] {
            assert!(matches!(bad, Err(Error::InvalidParameter { .. })));
        }
        assert!(sine(f64::NAN, 1.0, fs, 10).is_err());
        assert!(sine(10.0, f64::NAN, fs, 10).is_err());
    }

    #[test]
    fn held_record_refuses_bad_forces() {
        let mut sim = Simulator::new(&seed_rig(), 1000.0, 100, AntiAlias::None).unwrap();
        let ok = vec![0.0; 100];
        assert!(matches!(
            sim.held_record("r", std::slice::from_ref(&ok)),
            Err(Error::InvalidParameter {
                name: "held force channels",
                ..
            })
        ));
        assert!(matches!(
            sim.held_record("r", &[ok.clone(), vec![0.0; 99]]),
            Err(Error::InvalidParameter {
                name: "held force length",
                ..
            })
        ));
        let mut bad = ok.clone();
        bad[42] = f64::INFINITY;
        assert_eq!(
            sim.held_record("r", &[ok.clone(), bad]).unwrap_err(),
            Error::NonFinite {
                record: "r".into(),
                channel: Channel::Force(1),
                sample: 42,
                value: f64::INFINITY,
            }
        );
        assert!(sim.held_record("r", &[ok.clone(), ok]).is_ok());
    }

    #[test]
    fn sizes_past_the_limits_are_refused_without_allocating() {
        fn too_large<T>(r: Result<T>) -> bool {
            matches!(r, Err(Error::TooLarge { .. }))
        }
        assert!(too_large(sample_count(1e30, 6700.0)));
        assert!(too_large(sample_count(1e9, 6700.0)));
        assert!(matches!(
            sample_count(f64::NAN, 6700.0),
            Err(Error::InvalidParameter { .. })
        ));
        assert_eq!(sample_count(1.2, 6700.0), Ok(8040));
        let sys = seed_rig();
        assert!(too_large(
            Simulator::new(&sys, 1000.0, MAX_SAMPLES + 1, AntiAlias::None).map(|_| ())
        ));
        assert!(too_large(sine(10.0, 1.0, 1000.0, usize::MAX)));
        assert!(too_large(sweep(5.0, 60.0, 1.0, 1.0, 1000.0, usize::MAX)));
        assert!(too_large(multisine(256, 5..=10, 1.0, usize::MAX, 0)));
        assert!(too_large(multisine(
            MAX_SAMPLES,
            1..=MAX_SAMPLES / 2 - 1,
            1.0,
            8,
            0
        )));
        for test in [
            ImpactTest {
                per_direction: usize::MAX,
                ..ImpactTest::seed_rig()
            },
            ImpactTest {
                duration_s: 1e30,
                ..ImpactTest::seed_rig()
            },
            ImpactTest {
                sample_rate: 1e12,
                ..ImpactTest::seed_rig()
            },
        ] {
            assert!(too_large(test.run(&sys)), "{test:?}");
        }
        let big = Coefficients::new(
            Mat::identity(17, 17),
            Mat::identity(17, 17),
            Mat::identity(17, 17),
        )
        .unwrap();
        assert!(too_large(
            Simulator::new(&big, 1000.0, 100, AntiAlias::None).map(|_| ())
        ));
    }

    #[test]
    fn a_fast_filter_at_a_high_rate_integrates() {
        // ‖A Δt‖ ≈ 2.5e12: 42 squarings, past any u32 power of two.
        let mut sim = Simulator::new(&seed_rig(), 1e12, 64, AntiAlias::default()).unwrap();
        let rec = sim.random_record("fast", 1.0, 1).unwrap();
        assert!(rec.force(0).iter().all(|v| v.is_finite()));
    }

    #[test]
    fn matrices_without_decay_are_named() {
        let name = |m, c, k| match slowest_decay(&Coefficients::new(m, c, k).unwrap()) {
            Err(Error::InvalidParameter { name, .. }) => name,
            other => panic!("{other:?}"),
        };
        let (m, c, k) = (
            mat![[4.7, 0.0], [0.0, 4.8]],
            mat![[130.0, 0.0], [0.0, 130.0]],
            mat![[1.5e5, 0.0], [0.0, 1.7e5]],
        );
        assert_eq!(name(-&m, c.clone(), k.clone()), "mass matrix");
        assert_eq!(
            name(m.clone(), Mat::zeros(2, 2), k.clone()),
            "damping matrix"
        );
        assert_eq!(name(m.clone(), -&c, k.clone()), "damping matrix");
        assert_eq!(name(m.clone(), Mat::zeros(2, 2), -&k), "stiffness matrix");
        let slowest = slowest_decay(&Coefficients::new(m, c, k).unwrap()).unwrap();
        // Proportional damping: −Re λ = c / 2m for every mode, the slowest on the heavier mass.
        assert!((slowest - 130.0 / 9.6).abs() < 1e-9, "{slowest}");
        // The impact test names the matrix too, not the record duration.
        let undamped = Coefficients::new(
            mat![[4.7, 0.0], [0.0, 4.8]],
            Mat::zeros(2, 2),
            mat![[1.5e5, 0.0], [0.0, 1.7e5]],
        )
        .unwrap();
        assert!(matches!(
            ImpactTest::seed_rig().run(&undamped),
            Err(Error::InvalidParameter {
                name: "damping matrix",
                ..
            })
        ));
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
