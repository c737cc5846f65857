//! [`drive_frequency`]: the frequency of the sine in a record, from the peak of its Hann
//! spectrum refined by Gauss–Newton steps on the least-squares sine fit.

use std::f64::consts::PI;

use crate::error::{Error, Result};
use crate::spectra::{SpectralEstimator, Window};
use crate::tolerance::{FLAT_SIGNAL, FREQUENCY_STEP};

use super::least_squares::{accumulate, fit_sine, solve_normal, symmetrise};
use super::phasor::{check_rate, check_signal};

/// Gauss–Newton refinements of the frequency at most, in [`drive_frequency`].
const NEWTON_STEPS: usize = 20;

/// The frequency (Hz) of the sine in `signal`, for records of a stepped-sine test.
///
/// The mean is removed and a Hann window applied; the largest line of the real FFT
/// (realfft) is refined by a parabola through the logarithms of it and its two neighbours
/// (exact for a Gaussian peak, within a few hundredths of a line for Hann), then by
/// Gauss–Newton steps on the nonlinear least-squares fit of `a cos ωt + b sin ωt + d`, each
/// accepted only if it lowers the residual. For a sine in white noise the result is the
/// maximum-likelihood frequency, far finer than the FFT's line spacing `f_s/N`.
///
/// # Errors
/// [`Error::InvalidParameter`] for fewer than 8 samples, a non-finite sample, a sampling rate
/// that is not finite and positive, or a flat signal (nothing but its mean).
///
/// # Examples
/// ```
/// use bearing_ident::stepped::drive_frequency;
/// // 17.77 Hz at 500 samples/s for 2 s: the FFT lines are 0.5 Hz apart.
/// let w = 2.0 * std::f64::consts::PI * 17.77;
/// let x: Vec<f64> = (0..1000).map(|m| (w * m as f64 / 500.0 + 1.0).sin() + 0.2).collect();
/// let f = drive_frequency(&x, 500.0)?;
/// assert!((f - 17.77).abs() < 1e-9);
/// assert!(drive_frequency(&vec![0.1; 1000], 500.0).is_err()); // flat
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn drive_frequency(signal: &[f64], sample_rate: f64) -> Result<f64> {
    DriveFrequency::default().estimate(signal, sample_rate)
}

/// [`drive_frequency`] for many records: the Hann-windowed FFT ([`SpectralEstimator`]) is
/// planned once per record length and sampling rate and reused while they stay the same.
#[derive(Debug, Default)]
pub(super) struct DriveFrequency {
    /// The plan and the sampling rate it was made for.
    spectral: Option<(f64, SpectralEstimator)>,
}

impl DriveFrequency {
    /// As [`drive_frequency`].
    pub(super) fn estimate(&mut self, signal: &[f64], sample_rate: f64) -> Result<f64> {
        check_rate(sample_rate)?;
        check_signal(signal)?;
        let len = signal.len();
        // Flat: no swing beyond rounding of its level (a constant, or zero).
        let flat = Error::InvalidParameter {
            name: crate::Parameter::Signal,
            value: 0.0,
            expected: "a sine drive, not a flat signal",
        };
        let (lo, hi) = signal
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        if hi - lo <= FLAT_SIGNAL * lo.abs().max(hi.abs()) {
            return Err(flat);
        }
        let planned = self
            .spectral
            .as_ref()
            .is_some_and(|(rate, e)| e.len() == len && rate.to_bits() == sample_rate.to_bits());
        if !planned {
            let spectral = SpectralEstimator::new(len, sample_rate, Window::Hann)?;
            self.spectral = Some((sample_rate, spectral));
        }
        let (_, spectral) = self.spectral.as_mut().expect("planned above");
        // Mean removed, Hann window, one-sided DFT.
        let power: Vec<f64> = spectral
            .transform(signal)
            .iter()
            .map(|v| v.norm_sqr())
            .collect();
        refine(signal, &power, sample_rate).ok_or(flat)
    }
}

/// The frequency (Hz) of the sine in `signal` from its windowed `power` spectrum: the peak
/// line refined by a parabola through the log powers, then by Gauss–Newton on the sine fit.
/// `None` for a spectrum with no power.
fn refine(signal: &[f64], power: &[f64], sample_rate: f64) -> Option<f64> {
    let len = signal.len();
    let (peak, &top) = power
        .iter()
        .enumerate()
        .skip(1)
        .max_by(|a, b| a.1.total_cmp(b.1))
        .unwrap_or((0, &0.0));
    if top <= 0.0 {
        return None;
    }
    // Parabola through the log powers of the peak and its neighbours.
    let mut line = peak as f64;
    if peak + 1 < power.len() {
        let (l, c, r) = (power[peak - 1].ln(), top.ln(), power[peak + 1].ln());
        let curvature = l - 2.0 * c + r;
        if curvature < 0.0 && l.is_finite() && r.is_finite() {
            line += (0.5 * (l - r) / curvature).clamp(-0.5, 0.5);
        }
    }
    let nyquist_w = PI;
    let mut w = 2.0 * PI * line / len as f64;
    let Some((mut coef, mut rss)) = fit_sine(signal, w) else {
        return Some(w * sample_rate / (2.0 * PI));
    };
    for _ in 0..NEWTON_STEPS {
        // Gauss–Newton on (a, b, d, w): Jacobian columns cos, sin, 1, m(−a sin + b cos).
        let mut gram = [0.0; 16];
        let mut rhs = [0.0; 4];
        for (m, &x) in signal.iter().enumerate() {
            let (s, c) = (w * m as f64).sin_cos();
            let u = [c, s, 1.0, m as f64 * (-coef[0] * s + coef[1] * c)];
            let r = x - coef[0] * c - coef[1] * s - coef[2];
            accumulate(&mut gram, &mut rhs, &u, r);
        }
        symmetrise(&mut gram, 4);
        if !solve_normal(&mut gram, &mut rhs, 4) {
            break;
        }
        let mut step = rhs[3];
        let mut accepted = false;
        // Halve the step until the residual drops (three tries).
        for _ in 0..3 {
            let trial = w + step;
            if trial > 0.0 && trial < nyquist_w {
                if let Some((c, r)) = fit_sine(signal, trial) {
                    if r <= rss {
                        (w, coef, rss, accepted) = (trial, c, r, true);
                        break;
                    }
                }
            }
            step *= 0.5;
        }
        if !accepted || step.abs() <= FREQUENCY_STEP * w {
            break;
        }
    }
    Some(w * sample_rate / (2.0 * PI))
}
