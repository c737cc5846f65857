//! Impact tests: one half-sine pulse ([`Impact`]) and a campaign of them ([`ImpactTest`]).

use rand::SeedableRng;
use rand::rngs::StdRng;

use super::{
    AntiAlias, ElementStates, MAX_RECORDS, MAX_TOTAL_SAMPLES, Simulator, add_noise, at_most,
    sample_count,
};
use crate::error::{Error, Result};
use crate::model::Coefficients;
use crate::records::{Record, Response};

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
    /// As [`Simulator::new`], [`Simulator::responding`], [`Simulator::record`],
    /// [`sample_count`] and [`slowest_decay`](super::slowest_decay)
    /// (a mass that is not positive definite, a mode that does not decay);
    /// [`Error::InvalidParameter`] if the slowest mode has not decayed to `10⁻⁶` of its
    /// amplitude by the end of the record (the records would leak); [`Error::TooLarge`] for
    /// more than [`MAX_RECORDS`] records or [`MAX_TOTAL_SAMPLES`] samples in all.
    pub fn run_clean(&self, system: &Coefficients) -> Result<Vec<Record>> {
        self.clean(system, &ElementStates::default(), &[])
    }

    /// [`ImpactTest::run_clean`] of `system` with internal `states` ([`Simulator::with_states`];
    /// the slowest decay is the system's with them), response channels recording `responses`.
    fn clean(
        &self,
        system: &Coefficients,
        states: &ElementStates,
        responses: &[Response],
    ) -> Result<Vec<Record>> {
        let samples = self.samples()?;
        let n = system.dofs();
        let records = self.per_direction as f64 * n as f64;
        at_most("records", records, MAX_RECORDS)?;
        at_most(
            "samples × records",
            records * samples as f64,
            MAX_TOTAL_SAMPLES,
        )?;
        let slowest = states.slowest_decay(system)?;
        let decay_time = self.duration_s - self.pretrigger_s - self.pulse_s;
        let decays = slowest * decay_time >= crate::tolerance::SIM_DECAY_NEPERS;
        if !decays {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::RecordDuration,
                value: self.duration_s,
                expected: "long enough for the slowest mode to decay to 1e-6",
            });
        }
        let mut sim =
            Simulator::with_states(system, states, self.sample_rate, samples, self.anti_alias)?
                .responding(responses)?;
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
        self.run_responding(system, &[])
    }

    /// [`ImpactTest::run`] with the response channels recording velocity or acceleration:
    /// `responses` holds none (displacement), one kind for all, or one per degree of freedom
    /// (see [`Simulator::responding`]). The noise is [`ImpactTest::noise`] of each channel's
    /// own RMS.
    ///
    /// # Errors
    /// As [`ImpactTest::run`] and [`Simulator::responding`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Response;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let test = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() };
    /// let records = test.run_responding(&seed_rig(), &[Response::Acceleration])?;
    /// assert_eq!(records[0].responses(), &[Response::Acceleration; 2]);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn run_responding(
        &self,
        system: &Coefficients,
        responses: &[Response],
    ) -> Result<Vec<Record>> {
        self.run_with_states(system, &ElementStates::default(), responses)
    }

    /// [`ImpactTest::run_responding`] of `system` with internal `states`
    /// ([`Simulator::with_states`]), as [`Setup`](super::Setup) runs it.
    ///
    /// # Errors
    /// As [`ImpactTest::run_responding`] and [`ElementStates::slowest_decay`].
    pub(super) fn run_with_states(
        &self,
        system: &Coefficients,
        states: &ElementStates,
        responses: &[Response],
    ) -> Result<Vec<Record>> {
        let clean = self.clean(system, states, responses)?;
        let mut rng = StdRng::seed_from_u64(self.seed);
        clean
            .iter()
            .map(|r| add_noise(r, self.noise, &mut rng))
            .collect()
    }
}
