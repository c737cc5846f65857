//! Stage 3, for stepped-sine tests: impedance `H(ω)` and flexibility `G(ω)` at the drive
//! frequencies, from records each driven by one sine in one direction, in steady state.
//!
//! A stepped-sine test drives the element at one frequency at a time, in each direction in
//! turn, and records the steady state. Each record then holds one complex amplitude (phasor) per
//! channel at its drive frequency, found by a least-squares fit of a sine and an offset
//! ([`phasor`]); the drive frequency itself is estimated from the force ([`drive_frequency`]),
//! so the records need not carry it. Per frequency step and per set of `n` records, one per
//! direction, the seed's eq. 9 gives
//!
//! $$ H = [F^1 \cdots F^n]\,[X^1 \cdots X^n]^{-1}, $$
//!
//! averaged over the sets of the step, and `G = H⁻¹` ([`stepped_sine`]). Unlike a DFT line, the
//! least-squares phasor needs neither a whole number of periods nor a window: only the
//! transient must be gone (cut it off with [`Record::trimmed`]).
//!
//! # Phasor convention
//! A signal `x(t) = Re(P e^{iωt}) + offset`, with `t` counted from the record's first sample,
//! has phasor `P`. For `x = A cos(ωt + φ)`, `P = A e^{iφ}`. This is the crate's DFT convention
//! (`X(ω) = Σ x(t) e^{−iωt}` gives `X ≈ (N/2) P`), so `F = H X` holds between the phasors of
//! one record, and any common time shift of force and displacement cancels in `H`.
//!
//! What lives where: the FRF assembly ([`stepped_sine`]) is here; the phasor in `phasor.rs`,
//! the drive-frequency estimate in `drive.rs`, their small least-squares solver in
//! `least_squares.rs`.

mod drive;
mod least_squares;
mod phasor;

use std::f64::consts::PI;

use faer::c64;

use crate::Choice;
use crate::error::{Channel, Error, Result};
use crate::frf::{Assignment, Estimator, Frf, PairedKernel, Share};
use crate::records::Record;

use drive::DriveFrequency;
pub use drive::drive_frequency;
pub use phasor::phasor;

/// Impedances and flexibilities at the drive frequencies of a stepped-sine test.
///
/// Every record drives **one** direction (given by `assignment`, by default the strongest force
/// channel) at **one** frequency, in steady state. The drive frequency of each record is
/// estimated from its strongest force channel ([`drive_frequency`]); records are sorted by it and
/// grouped into steps, a record joining the current step when its frequency is within
/// `tolerance_hz` of the step's lowest. Per record, the phasors of all force and displacement
/// channels are taken at its own frequency ([`phasor`]). Per step, records are paired into sets
/// of one per direction, in the order given (extras are listed in [`Frf::unpaired`]), and
///
/// $$ H = \frac{1}{S}\sum_{s=1}^{S} [F^1 \cdots F^n]_s\,[X^1 \cdots X^n]_s^{-1}, \qquad G = H^{-1}, $$
///
/// at the mean frequency of the step's records. [`Frf::condition_numbers`] holds, per step, the
/// worst `cond([X¹…Xⁿ])` over its sets; a step whose displacement matrix cannot be inverted is
/// listed in [`Frf::dropped_hz`]. [`Frf::averages`] is the smallest number of sets of any step.
/// The lines come out sorted by frequency and carry no coherence (one phasor per record).
///
/// # Errors
/// [`Error::NoRecords`]; [`Error::DofMismatch`] for a record with other than `n` degrees of
/// freedom (`n` = `dofs`, or the first record's); [`Error::InvalidParameter`] for a tolerance
/// that is not finite and non-negative and as [`drive_frequency`] and [`phasor`] (a record with
/// flat forces, for instance); the errors of [`Assignment::resolve`]; [`Error::IncompleteStep`]
/// naming the first step with no record in some direction.
///
/// # Examples
/// ```
/// use bearing_ident::Assignment;
/// use bearing_ident::records::Record;
/// use bearing_ident::stepped::stepped_sine;
/// use std::f64::consts::PI;
/// // SDOF m = 2 kg, c = 30 N·s/m, k = 2e4 N/m in steady state at 5, 10 and 15 Hz.
/// let (m, c, k, fs) = (2.0, 30.0, 2.0e4, 1000.0);
/// let records: Vec<Record> = [5.0, 10.0, 15.0]
///     .iter()
///     .map(|&f: &f64| {
///         let w = 2.0 * PI * f;
///         let g = num_complex::Complex64::new(k - w * w * m, w * c).inv();
///         let t = |i: usize| i as f64 / fs;
///         let force: Vec<f64> = (0..700).map(|i| 10.0 * (w * t(i)).cos()).collect();
///         let disp: Vec<f64> = (0..700).map(|i| 10.0 * g.norm() * (w * t(i) + g.arg()).cos()).collect();
///         Record::new(format!("{f} Hz"), fs, vec![force], vec![disp])
///     })
///     .collect::<Result<_, _>>()?;
/// let frf = stepped_sine(&records, &Assignment::DominantForce, None, 0.01)?;
/// assert_eq!(frf.line_count(), 3);
/// let w = 2.0 * PI * frf.freqs_hz()[1];
/// assert!((frf.freqs_hz()[1] - 10.0).abs() < 1e-9);
/// assert!((frf.impedance(1)[(0, 0)].re - (k - w * w * m)).abs() < 1e-6);
/// assert!((frf.impedance(1)[(0, 0)].im / w - c).abs() < 1e-9);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn stepped_sine(
    records: &[Record],
    assignment: &Assignment,
    dofs: Option<usize>,
    tolerance_hz: f64,
) -> Result<Frf> {
    let first = records.first().ok_or(Error::NoRecords)?;
    let n = dofs.unwrap_or(first.dofs());
    if let Some(r) = records.iter().find(|r| r.dofs() != n) {
        return Err(Error::DofMismatch {
            record: r.label().to_owned(),
            expected: n,
            actual: r.dofs(),
        });
    }
    if !(tolerance_hz.is_finite() && tolerance_hz >= 0.0) {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::StepTolerance,
            value: tolerance_hz,
            expected: "finite and ≥ 0 (Hz)",
        });
    }
    let excitation = assignment.resolve(records, n)?;
    // Per record: drive frequency, then the phasors of every channel at it.
    struct Phasors {
        freq_hz: f64,
        forces: Vec<c64>,
        displacements: Vec<c64>,
    }
    let mut finder = DriveFrequency::default();
    let phasors: Vec<Phasors> = records
        .iter()
        .map(|r| {
            let fs = r.sample_rate();
            let freq_hz = finder.estimate(r.force(r.dominant_force()), fs)?;
            let at = |x: &[f64]| phasor(x, freq_hz, fs);
            Ok(Phasors {
                freq_hz,
                forces: (0..n).map(|c| at(r.force(c))).collect::<Result<_>>()?,
                displacements: (0..n)
                    .map(|c| {
                        let response = r.response(c);
                        let omega = 2.0 * PI * freq_hz;
                        let value = at(r.displacement(c))?;
                        response.to_displacement(value, 0.0, omega).ok_or_else(|| {
                            Error::ResponseAtZeroFrequency {
                                record: r.label().to_owned(),
                                channel: Channel::Displacement(c),
                                response: response.name(),
                                freq_hz,
                            }
                        })
                    })
                    .collect::<Result<_>>()?,
            })
        })
        .collect::<Result<_>>()?;

    let mut order: Vec<usize> = (0..records.len()).collect();
    order.sort_by(|&a, &b| {
        phasors[a]
            .freq_hz
            .total_cmp(&phasors[b].freq_hz)
            .then(a.cmp(&b))
    });
    let mut steps: Vec<Vec<usize>> = Vec::new();
    for r in order {
        match steps.last_mut() {
            Some(step) if phasors[r].freq_hz - phasors[step[0]].freq_hz <= tolerance_hz => {
                step.push(r);
            }
            _ => steps.push(vec![r]),
        }
    }

    let mut kernel = PairedKernel::new(n);
    let mut lines: Vec<(f64, Option<Vec<c64>>, f64)> = Vec::with_capacity(steps.len());
    let mut unpaired = Vec::new();
    let mut averages = usize::MAX;
    for step in &mut steps {
        step.sort_unstable();
        let freq_hz = step.iter().map(|&r| phasors[r].freq_hz).sum::<f64>() / step.len() as f64;
        let mut by_direction: Vec<Vec<usize>> = vec![Vec::new(); n];
        for &r in step.iter() {
            by_direction[excitation[r]].push(r);
        }
        if let Some(direction) = by_direction.iter().position(Vec::is_empty) {
            return Err(Error::IncompleteStep {
                freq_hz,
                direction,
                dofs: n,
            });
        }
        let sets = by_direction.iter().map(Vec::len).min().unwrap_or(0);
        averages = averages.min(sets);
        unpaired.extend(
            by_direction
                .iter()
                .flat_map(|d| d[sets..].iter().map(|&r| records[r].label().to_owned())),
        );
        let mut h = vec![c64::new(0.0, 0.0); n * n];
        let by_direction = &by_direction;
        let phasors = &phasors;
        let set_columns = (0..sets).map(|s| {
            let columns = by_direction.iter().map(move |dir| {
                let p = &phasors[dir[s]];
                (p.forces.as_slice(), p.displacements.as_slice())
            });
            (columns, Share::Over(sets as f64))
        });
        match kernel.average(set_columns, &mut h, |_| {}) {
            Some(worst) => lines.push((freq_hz, Some(h), worst)),
            None => lines.push((freq_hz, None, 0.0)),
        }
    }
    Ok(Frf::from_impedance_lines(
        n,
        Estimator::PairedSets,
        averages,
        unpaired,
        lines.iter().map(|(f, h, c)| (*f, h.as_deref(), *c)),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::{AntiAlias, Simulator, seed_rig, sine};

    fn tone(freq_hz: f64, sample_rate: f64, len: usize, p: c64, offset: f64) -> Vec<f64> {
        let w = 2.0 * PI * freq_hz / sample_rate;
        (0..len)
            .map(|m| (p * c64::from_polar(1.0, w * m as f64)).re + offset)
            .collect()
    }

    #[test]
    fn phasor_recovers_amplitude_phase_and_ignores_offset() {
        let p = c64::new(-1.5, 2.25);
        let x = tone(7.3, 200.0, 123, p, -4.0);
        let got = phasor(&x, 7.3, 200.0).unwrap();
        assert!((got - p).norm() < 1e-12 * p.norm(), "{got}");
    }

    #[test]
    fn phasor_matches_the_dft_convention() {
        // Whole periods: the DFT at the line is (N/2) P.
        let p = c64::new(0.3, -0.8);
        let x = tone(10.0, 100.0, 200, p, 0.0);
        let w = 2.0 * PI * 10.0 / 100.0;
        let dft: c64 = x
            .iter()
            .enumerate()
            .map(|(m, v)| c64::from_polar(*v, -w * m as f64))
            .sum();
        assert!((dft / 100.0 - p).norm() < 1e-12);
    }

    #[test]
    fn phasor_refuses_what_it_cannot_resolve() {
        let x = tone(5.0, 100.0, 100, c64::new(1.0, 0.0), 0.0);
        for (f, fs) in [(0.0, 100.0), (50.0, 100.0), (f64::NAN, 100.0), (5.0, 0.0)] {
            assert!(matches!(
                phasor(&x, f, fs),
                Err(Error::InvalidParameter { .. })
            ));
        }
        // A thousandth of a period in 10 samples: cosine and offset are one column.
        assert!(matches!(
            phasor(&x[..10], 0.01, 100.0),
            Err(Error::InvalidParameter {
                name: crate::Parameter::PhasorFrequency,
                ..
            })
        ));
        assert!(phasor(&x[..4], 5.0, 100.0).is_err());
        let mut bad = x.clone();
        bad[3] = f64::NAN;
        assert!(phasor(&bad, 5.0, 100.0).is_err());
    }

    #[test]
    fn drive_frequency_is_found_between_lines_and_in_noise() {
        for f in [3.3, 10.0, 27.123_456, 48.9] {
            let x = tone(f, 400.0, 900, c64::new(0.0, 2.0), 0.7);
            let got = drive_frequency(&x, 400.0).unwrap();
            assert!((got - f).abs() < 1e-9 * f, "{f}: {got}");
        }
        // In 10 % noise, far below the 0.44 Hz line spacing (CRLB ≈ 2e-4 Hz here).
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let noise = Normal::new(0.0, 0.1).unwrap();
        let x: Vec<f64> = tone(21.7, 400.0, 900, c64::new(1.0, 0.0), 0.0)
            .into_iter()
            .map(|v| v + noise.sample(&mut rng))
            .collect();
        let got = drive_frequency(&x, 400.0).unwrap();
        assert!((got - 21.7).abs() < 2e-3, "{got}");
        assert!(matches!(
            drive_frequency(&[0.0; 64], 400.0),
            Err(Error::InvalidParameter {
                name: crate::Parameter::Signal,
                ..
            })
        ));
        assert!(drive_frequency(&[1.0; 4], 400.0).is_err());
        assert!(drive_frequency(&x, -1.0).is_err());
    }

    fn rig_step(sim: &mut Simulator, f: f64, dir: usize, fs: f64, len: usize) -> Record {
        let drive = sine(f, 50.0, fs, len).unwrap();
        let mut forces = vec![vec![0.0; len]; 2];
        forces[dir] = drive;
        let rec = sim.held_record(format!("{f}-{dir}"), &forces).unwrap();
        rec.trimmed(len / 2..len).unwrap()
    }

    #[test]
    fn stepped_sine_gives_the_rig_impedance() {
        let (fs, len) = (1000.0, 2000);
        let truth = seed_rig();
        let mut sim = Simulator::new(&truth, fs, len, AntiAlias::default()).unwrap();
        let mut records = Vec::new();
        // Out of order, y before x at one step, and a repeat of 20 Hz in x.
        for (f, dir) in [(20.0, 1), (20.0, 0), (12.5, 0), (12.5, 1), (20.0, 0)] {
            records.push(rig_step(&mut sim, f, dir, fs, len));
        }
        let frf = stepped_sine(&records, &Assignment::DominantForce, None, 0.05).unwrap();
        assert_eq!(frf.line_count(), 2);
        assert_eq!(frf.averages(), 1);
        assert_eq!(frf.unpaired(), ["20-0"]);
        assert!(frf.multiple_coherence(0).is_none());
        for (k, f) in [12.5, 20.0].into_iter().enumerate() {
            assert!((frf.freqs_hz()[k] - f).abs() < 1e-9);
            let exact = truth.impedance_at(f);
            let scale = exact.norm_l2();
            for i in 0..2 {
                for j in 0..2 {
                    let err = (frf.impedance(k)[(i, j)] - exact[(i, j)]).norm() / scale;
                    assert!(err < 1e-6, "{f} Hz ({i},{j}): {err:.3e}");
                }
            }
            assert!(frf.condition_numbers()[k] >= 1.0);
        }
    }

    #[test]
    fn stepped_sine_errors_are_typed() {
        let (fs, len) = (1000.0, 400);
        let mut sim = Simulator::new(&seed_rig(), fs, len, AntiAlias::None).unwrap();
        let records = vec![
            rig_step(&mut sim, 15.0, 0, fs, len),
            rig_step(&mut sim, 15.0, 1, fs, len),
            rig_step(&mut sim, 30.0, 0, fs, len),
        ];
        match stepped_sine(&records, &Assignment::DominantForce, None, 0.1) {
            Err(e @ Error::IncompleteStep { .. }) => {
                assert_eq!(e.kind(), "rank_deficient");
                assert!(matches!(
                    e,
                    Error::IncompleteStep {
                        direction: 1,
                        dofs: 2,
                        ..
                    }
                ));
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(
            stepped_sine(&[], &Assignment::DominantForce, None, 0.1).unwrap_err(),
            Error::NoRecords
        );
        assert!(matches!(
            stepped_sine(&records, &Assignment::DominantForce, Some(3), 0.1),
            Err(Error::DofMismatch { .. })
        ));
        assert!(matches!(
            stepped_sine(&records[..2], &Assignment::DominantForce, None, -1.0),
            Err(Error::InvalidParameter { .. })
        ));
        assert!(matches!(
            stepped_sine(&records[..2], &Assignment::Explicit(vec![0]), None, 0.1),
            Err(Error::AssignmentLength { .. })
        ));
        let flat = Record::new("flat", fs, vec![vec![0.0; 64]; 2], vec![vec![0.0; 64]; 2]);
        assert!(matches!(
            stepped_sine(&[flat.unwrap()], &Assignment::DominantForce, None, 0.1),
            Err(Error::InvalidParameter {
                name: crate::Parameter::Signal,
                ..
            })
        ));
        // Both records drive x: the paired matrix is singular, so the step is dropped.
        let explicit = Assignment::Explicit(vec![0, 1]);
        let same = vec![records[0].clone(), records[0].clone()];
        let frf = stepped_sine(&same, &explicit, None, 0.1).unwrap();
        assert_eq!((frf.line_count(), frf.dropped_hz().len()), (0, 1));
    }
}
