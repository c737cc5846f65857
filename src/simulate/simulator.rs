//! The exact discrete-time integration of one system: [`Simulator`].

use std::f64::consts::PI;

use faer::Mat;
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

use super::expm::expm;
use super::sparse_rows::SparseRows;
use super::{
    AntiAlias, ElementStates, Impact, MAX_DOFS, MAX_SAMPLES, at_most, finite_positive,
    require_finite_positive,
};
use crate::error::{Channel, Error, Result};
use crate::model::Coefficients;
use crate::records::{Record, Response};

/// Mixed into the seed of [`Simulator::random_record`]'s forcing, so that measurement noise
/// seeded with the same number is an unrelated stream.
const FORCING_STREAM: u64 = 0xD1B5_4A32_D192_ED03;

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
    /// What each response channel records.
    responses: Vec<Response>,
    /// Structure part of `A` without the pulse generators' frequency.
    base: Mat<f64>,
    dim: usize,
    /// Index of the first filter state: the structure's states (`x`, `v`, pulse generators,
    /// held forces, the element's internal states) come before it, `(5 + N) n` of them.
    structure: usize,
    /// `(duration, Φ)` for the pulse durations seen so far, `Φ` by rows of its nonzeros.
    cache: Vec<(f64, SparseRows)>,
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
        Self::plan(
            system,
            &ElementStates::default(),
            sample_rate,
            samples,
            anti_alias,
        )
    }

    /// Plans a simulation of `system` with an element's internal `states` (see
    /// [`ElementStates`]): `M ẍ + C ẋ + K x + Σ A_j w_j = f`, `ẇ_j = ẋ − p_j w_j`, from rest.
    /// Every record kind works as with [`Simulator::new`], which this is, bit for bit, without
    /// states; an acceleration response is $M^{-1}(f - C v - K x - \sum_j A_j w_j)$.
    ///
    /// # Errors
    /// As [`Simulator::new`]; with states, as [`ElementStates::slowest_decay`]: residues that
    /// are not `n × n`, a mass that is not positive definite, or a mode of the system with its
    /// states that does not decay ([`Error::InvalidParameter`] naming the matrix, or
    /// `decay with internal states`).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::model::Coefficients;
    /// use bearing_ident::simulate::{AntiAlias, ElementStates, Simulator};
    /// use faer::mat;
    /// // A static load: the states relax (w → 0), so only K carries it: 10 N on 1e4 N/m.
    /// let sdof = Coefficients::new(mat![[1.0]], mat![[40.0]], mat![[1.0e4]])?;
    /// let states: ElementStates = "5:2e4".parse()?;
    /// let mut sim = Simulator::with_states(&sdof, &states, 1000.0, 4000, AntiAlias::None)?;
    /// let rec = sim.held_record("static", &[vec![10.0; 4000]])?;
    /// assert!((rec.displacement(0)[3999] - 1.0e-3).abs() < 1e-12);
    /// // A state that takes the damping away is refused.
    /// let driving: ElementStates = "5:-2e4".parse()?;
    /// assert!(Simulator::with_states(&sdof, &driving, 1000.0, 4000, AntiAlias::None).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn with_states(
        system: &Coefficients,
        states: &ElementStates,
        sample_rate: f64,
        samples: usize,
        anti_alias: AntiAlias,
    ) -> Result<Self> {
        if !states.is_empty() {
            states.slowest_decay(system)?;
        }
        Self::plan(system, states, sample_rate, samples, anti_alias)
    }

    /// The simulator of [`Simulator::with_states`], its states checked.
    fn plan(
        system: &Coefficients,
        states: &ElementStates,
        sample_rate: f64,
        samples: usize,
        anti_alias: AntiAlias,
    ) -> Result<Self> {
        use faer::prelude::Solve;
        require_finite_positive(
            crate::Parameter::SampleRate,
            sample_rate,
            "finite and positive (Hz)",
        )?;
        at_most("samples per record", samples as f64, MAX_SAMPLES)?;
        at_most("degrees of freedom", system.dofs() as f64, MAX_DOFS)?;
        if samples < crate::records::MIN_SAMPLES {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::Samples,
                value: samples as f64,
                expected: "at least 8",
            });
        }
        let order = anti_alias.checked_order()?;
        system.eigenvalues()?; // rejects a singular mass matrix
        let n = system.dofs();
        let lu = system.mass().partial_piv_lu();
        let (mk, mc) = (lu.solve(system.stiffness()), lu.solve(system.damping()));
        let minv = lu.solve(Mat::<f64>::identity(n, n));
        // State: x (n), v (n), pulse generators (2 per dof), held forces (1 per dof, constant
        // between samples), the element's internal states (n per pole), filters (order per
        // channel).
        let structure = 5 * n + states.len() * n;
        let dim = structure + 2 * n * order;
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
        for (s, (residue, p)) in states.residues().iter().zip(states.poles_rad()).enumerate() {
            // ẇ = v − p w, and the force A w on the structure.
            let ma = lu.solve(residue);
            let w = 5 * n + s * n;
            for i in 0..n {
                a[(w + i, n + i)] = 1.0;
                a[(w + i, w + i)] = -p;
                for j in 0..n {
                    a[(n + i, w + j)] = -ma[(i, j)];
                }
            }
        }
        anti_alias.fill_state_matrix(&mut a, n, structure, sample_rate);
        Ok(Self {
            n,
            sample_rate,
            samples,
            anti_alias,
            responses: vec![Response::Displacement; n],
            base: a,
            dim,
            structure,
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

    /// Records velocity or acceleration instead of displacement on the response channels:
    /// `kinds` holds one [`Response`] for all channels or one per degree of freedom (none:
    /// displacement). Velocity is the state `v`; acceleration is
    /// $a = M^{-1}(f - C v - K x)$ (less $M^{-1} \sum_j A_j w_j$ with internal states) at the
    /// sample instant (with a held force, the force from
    /// that sample on). With an anti-alias filter the filter's input is that signal, so the
    /// recorded velocity is exactly the derivative of the filtered displacement. Records
    /// carry their kinds ([`Record::responses`]).
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] for a number of kinds other than 0, 1 or the degrees of
    /// freedom.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Response;
    /// use bearing_ident::model::Coefficients;
    /// use bearing_ident::simulate::{AntiAlias, Simulator};
    /// use faer::mat;
    /// // A static load on an SDOF spring: once settled, no velocity and no acceleration.
    /// let sdof = Coefficients::new(mat![[1.0]], mat![[40.0]], mat![[1.0e4]])?;
    /// let mut sim = Simulator::new(&sdof, 1000.0, 2000, AntiAlias::None)?
    ///     .responding(&[Response::Acceleration])?;
    /// let rec = sim.held_record("static", &[vec![10.0; 2000]])?;
    /// assert_eq!(rec.response(0), Response::Acceleration);
    /// assert!((rec.displacement(0)[0] - 10.0).abs() < 1e-12); // a(0) = f/m
    /// assert!(rec.displacement(0)[1999].abs() < 1e-9);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn responding(mut self, kinds: &[Response]) -> Result<Self> {
        self.responses = Response::per_channel(kinds, self.n)?;
        for c in 0..self.n {
            // The filter sees its input scaled to unit largest weight and the output is
            // scaled back: an acceleration's weights (K/M ≈ 10⁴–10⁵ 1/s²) times the filter's
            // ω_c² would otherwise inflate ‖A Δt‖ and the matrix exponential's rounding, which
            // showed as a 10⁻⁵ relative error of the filtered acceleration.
            let scale = self.input_scale(c);
            let inputs: Vec<(usize, f64)> = self
                .response_inputs(c)
                .into_iter()
                .map(|(u, w)| (u, w / scale))
                .collect();
            self.anti_alias.connect(
                &mut self.base,
                self.structure,
                self.sample_rate,
                self.n + c,
                &inputs,
            );
        }
        self.cache.clear();
        Ok(self)
    }

    /// What each response channel records.
    pub fn responses(&self) -> &[Response] {
        &self.responses
    }

    /// The structure's states and weights whose sum is response `c` before any filter:
    /// displacement `x_c`, velocity `v_c`, or acceleration, the row `n + c` of `A` over the
    /// structure's states (force generators and internal states included).
    fn response_inputs(&self, c: usize) -> Vec<(usize, f64)> {
        let n = self.n;
        match self.responses[c] {
            Response::Displacement => vec![(c, 1.0)],
            Response::Velocity => vec![(n + c, 1.0)],
            Response::Acceleration => (0..self.structure)
                .map(|u| (u, self.base[(n + c, u)]))
                .filter(|&(_, w)| w != 0.0)
                .collect(),
        }
    }

    /// The largest weight of response `c`'s inputs ([`Simulator::response_inputs`]); 1 for
    /// displacement and velocity.
    fn input_scale(&self, c: usize) -> f64 {
        match self.responses[c] {
            Response::Acceleration => self
                .response_inputs(c)
                .iter()
                .fold(0.0_f64, |m, &(_, w)| m.max(w.abs()))
                .max(f64::MIN_POSITIVE),
            _ => 1.0,
        }
    }

    /// The state entries and weights whose weighted sum is the sampled value of `channel`
    /// (forces first).
    fn output_indices(&self, channel: usize) -> Vec<(usize, f64)> {
        let n = self.n;
        match self.anti_alias {
            AntiAlias::Butterworth { order, .. } => {
                let scale = match channel.checked_sub(n) {
                    Some(c) => self.input_scale(c),
                    None => 1.0,
                };
                vec![(self.structure + channel * order + order - 2, scale)]
            }
            AntiAlias::None if channel < n => {
                vec![(2 * n + 2 * channel, 1.0), (4 * n + channel, 1.0)]
            }
            AntiAlias::None => self.response_inputs(channel - n),
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
            .filter(|_| finite_positive(force_rms))
            .ok_or(Error::InvalidParameter {
                name: crate::Parameter::ForceRms,
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
    /// Build the samples with [`sine`](super::sine), [`multisine`](super::multisine) or
    /// [`sweep`](super::sweep), or supply your own.
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
        check_held_forces(&label, forces, self.n, self.samples)?;
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
            require_finite_positive(
                crate::Parameter::PulseDuration,
                hit.duration_s,
                "finite and positive (s)",
            )?;
            if !(hit.peak_n.is_finite()) {
                return bad(crate::Parameter::PulsePeak, hit.peak_n, "finite (N)");
            }
            if hit.direction.len() != self.n || hit.direction.iter().any(|d| !d.is_finite()) {
                return bad(
                    crate::Parameter::PulseDirectionLength,
                    hit.direction.len() as f64,
                    "one finite entry per degree of freedom",
                );
            }
            if !(hit.start_s >= 0.0 && hit.start_s + hit.duration_s <= duration_total) {
                return bad(
                    crate::Parameter::PulseStart,
                    hit.start_s,
                    "pulse inside the record",
                );
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
                        name: crate::Parameter::PulseStart,
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
        let out_f: Vec<Vec<(usize, f64)>> = (0..self.n).map(|c| self.output_indices(c)).collect();
        let out_x: Vec<Vec<(usize, f64)>> = (0..self.n)
            .map(|c| self.output_indices(self.n + c))
            .collect();
        let sample = |state: &[f64], idx: &[(usize, f64)]| {
            idx.iter().map(|&(i, w)| w * state[i]).sum::<f64>()
        };
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
                SparseRows::new(&expm(&(&a * (te - t)))).propagate(&mut state, &mut next);
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
                SparseRows::new(&expm(&(&a * (t1 - t)))).propagate(&mut state, &mut next);
            } else {
                self.step_matrix(duration).propagate(&mut state, &mut next);
            }
        }
        Record::new(label, self.sample_rate, forces, displacements)?
            .with_responses(self.responses.clone())
    }

    fn step_matrix(&mut self, duration_s: f64) -> &SparseRows {
        #[allow(clippy::float_cmp)] // exact key lookup
        let pos = self.cache.iter().position(|(d, _)| *d == duration_s);
        let pos = match pos {
            Some(p) => p,
            None => {
                let a = self.system_matrix(duration_s);
                let phi = expm(&(&a * (1.0 / self.sample_rate)));
                self.cache.push((duration_s, SparseRows::new(&phi)));
                self.cache.len() - 1
            }
        };
        &self.cache[pos].1
    }
}

/// The held forces of a simulation: one channel per degree of freedom, each `samples` long, all
/// finite (shared by the linear and the nonlinear simulators).
pub(super) fn check_held_forces(
    label: &str,
    forces: &[Vec<f64>],
    n: usize,
    samples: usize,
) -> Result<()> {
    if forces.len() != n {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::HeldForceChannels,
            value: forces.len() as f64,
            expected: "one channel per degree of freedom",
        });
    }
    for (c, channel) in forces.iter().enumerate() {
        if channel.len() != samples {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::HeldForceLength,
                value: channel.len() as f64,
                expected: "exactly the simulator's number of samples",
            });
        }
        if let Some((sample, &value)) = channel.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::NonFinite {
                record: label.to_string(),
                channel: Channel::Force(c),
                sample,
                value,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::seed_rig;
    use faer::mat;

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
    fn held_record_refuses_bad_forces() {
        let mut sim = Simulator::new(&seed_rig(), 1000.0, 100, AntiAlias::None).unwrap();
        let ok = vec![0.0; 100];
        assert!(matches!(
            sim.held_record("r", std::slice::from_ref(&ok)),
            Err(Error::InvalidParameter {
                name: crate::Parameter::HeldForceChannels,
                ..
            })
        ));
        assert!(matches!(
            sim.held_record("r", &[ok.clone(), vec![0.0; 99]]),
            Err(Error::InvalidParameter {
                name: crate::Parameter::HeldForceLength,
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
    fn a_fast_filter_at_a_high_rate_integrates() {
        // ‖A Δt‖ ≈ 2.5e12: 42 squarings, past any u32 power of two.
        let mut sim = Simulator::new(&seed_rig(), 1e12, 64, AntiAlias::default()).unwrap();
        let rec = sim.random_record("fast", 1.0, 1).unwrap();
        assert!(rec.force(0).iter().all(|v| v.is_finite()));
    }
}
