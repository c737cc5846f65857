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
//!
//! # Elements with internal states
//! An element whose stiffness and damping change with frequency (a seal, tilting pads, a
//! magnetic bearing) is simulated with internal states ([`ElementStates`]): each pole `p_j`
//! adds states `w_j` with `ẇ_j = ẋ − p_j w_j` and a force `A_j w_j`, so that
//! `H(ω) = K + sC + s²M + Σ A_j s/(s + p_j)`, `s = iω`. They are states of the same linear
//! system, integrated just as exactly ([`Simulator::with_states`]; the `states` option of
//! [`Setup`]).

mod anti_alias;
pub(crate) mod expm;
mod impact;
mod noise;
mod nonlinear;
mod rig;
mod setup;
mod simulator;
mod sparse_rows;
mod states;
mod waveforms;

use crate::error::{Error, Result};

pub use anti_alias::AntiAlias;
pub use impact::{Impact, ImpactTest};
pub use noise::add_noise;
pub use nonlinear::{
    DEFAULT_OVERSAMPLING, DEFAULT_SMOOTHING, MAX_OVERSAMPLING, NonlinearSimulator, SMOOTHING_BAND,
};
pub use rig::{seed_rig, slowest_decay};
pub use setup::{Kind, NonlinearTerms, Setup, Simulated};
pub use simulator::Simulator;
pub use states::ElementStates;
pub use waveforms::{SWEEP_TAPER, band_noise, multisine, sine, sweep};

/// Most samples in one simulated record (or one drive signal): `2²⁴`, about 16.8 million
/// (42 minutes at 6.7 kHz). Larger requests are [`Error::TooLarge`], never an allocation.
pub const MAX_SAMPLES: usize = 1 << 24;

/// Most records one simulated test may produce ([`ImpactTest`], and the CLI's `simulate`).
pub const MAX_RECORDS: usize = 4096;

/// Most degrees of freedom a [`Simulator`] accepts (its state has `(5 + N + 2·order) n`
/// entries, with `N` internal-state poles).
pub const MAX_DOFS: usize = 16;

/// Most poles of an element's internal states ([`ElementStates`]): each adds `n` states to the
/// simulator's.
pub const MAX_STATE_POLES: usize = 8;

/// Most samples × records of one simulated test, `2²⁸`: bounds the time of a simulation.
pub const MAX_TOTAL_SAMPLES: usize = 1 << 28;

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

use crate::records::{finite_positive, require_finite_positive};

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
    require_finite_positive(
        crate::Parameter::SampleRate,
        sample_rate,
        "finite and positive (Hz)",
    )?;
    require_finite_positive(
        crate::Parameter::RecordDuration,
        duration_s,
        "finite and positive (s)",
    )?;
    let samples = (duration_s * sample_rate).round();
    at_most("samples per record", samples, MAX_SAMPLES)?;
    Ok(samples as usize)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Coefficients;
    use faer::Mat;
    use rand::SeedableRng;
    use rand::rngs::StdRng;

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
                name: crate::Parameter::RecordDuration,
                ..
            })
        ));
        let mut rng = StdRng::seed_from_u64(0);
        let rec = sim.record("r", &[hit(0.0)]).unwrap();
        assert!(add_noise(&rec, -1.0, &mut rng).is_err());
    }
}
