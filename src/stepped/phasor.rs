//! [`phasor`]: the complex amplitude of a record's channel at a known frequency, by least
//! squares, and the checks of a signal shared with the drive-frequency estimate.

use faer::c64;
use std::f64::consts::PI;

use crate::error::{Error, Result};
use crate::records::{MIN_SAMPLES, finite_positive, require_finite_positive};

use super::least_squares::fit_sine;

pub(super) fn check_rate(sample_rate: f64) -> Result<()> {
    require_finite_positive(
        crate::Parameter::SampleRate,
        sample_rate,
        "finite and positive (Hz)",
    )
}

pub(super) fn check_signal(signal: &[f64]) -> Result<()> {
    if signal.len() < MIN_SAMPLES {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::SignalLength,
            value: signal.len() as f64,
            expected: "at least 8 samples",
        });
    }
    match signal.iter().find(|v| !v.is_finite()) {
        Some(&value) => Err(Error::InvalidParameter {
            name: crate::Parameter::SignalSample,
            value,
            expected: "finite",
        }),
        None => Ok(()),
    }
}

/// The complex amplitude of `signal` at `freq_hz`: the least-squares fit
///
/// $$ x_m \approx a \cos\omega t_m + b \sin\omega t_m + d, \qquad t_m = m / f_s, $$
///
/// returned as the phasor $P = a - i b$, so that $x(t) \approx \operatorname{Re}(P e^{i\omega t}) + d$
/// (see the [module docs](crate::stepped) for the convention). The fit needs no whole number of periods
/// and no window; the offset `d` absorbs a sensor's DC level. For a stationary sine in white
/// noise it is the maximum-likelihood amplitude at a known frequency.
///
/// # Errors
/// [`Error::InvalidParameter`] for fewer than 8 samples, a non-finite sample, a sampling rate
/// that is not finite and positive, a frequency outside `0 < f < f_s/2`, or a record too short
/// (or a frequency too close to DC or Nyquist) for the sine, cosine and offset to be separated.
///
/// # Examples
/// ```
/// use bearing_ident::stepped::phasor;
/// // 3 cos(ωt + 0.5) + 1 at 12.3 Hz, 1000 samples/s, 0.37 s (not a whole number of periods).
/// let w = 2.0 * std::f64::consts::PI * 12.3;
/// let x: Vec<f64> = (0..370).map(|m| 3.0 * (w * m as f64 / 1000.0 + 0.5).cos() + 1.0).collect();
/// let p = phasor(&x, 12.3, 1000.0)?;
/// assert!((p.norm() - 3.0).abs() < 1e-12);
/// assert!((p.arg() - 0.5).abs() < 1e-12);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn phasor(signal: &[f64], freq_hz: f64, sample_rate: f64) -> Result<c64> {
    check_rate(sample_rate)?;
    check_signal(signal)?;
    if !(finite_positive(freq_hz) && freq_hz < sample_rate / 2.0) {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::PhasorFrequency,
            value: freq_hz,
            expected: "0 < frequency < sample rate / 2 (Hz)",
        });
    }
    let w = 2.0 * PI * freq_hz / sample_rate;
    let ([a, b, _], _) = fit_sine(signal, w).ok_or(Error::InvalidParameter {
        name: crate::Parameter::PhasorFrequency,
        value: freq_hz,
        expected: "a frequency the record resolves (about half a period or more, \
                   away from DC and Nyquist)",
    })?;
    Ok(c64::new(a, -b))
}
