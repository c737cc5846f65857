//! Drive signals for [`Simulator::held_record`](super::Simulator::held_record): [`sine`],
//! [`multisine`] and [`sweep`], with their checks.

use std::f64::consts::PI;
use std::ops::RangeInclusive;

use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Uniform};

use super::{MAX_SAMPLES, at_most, finite_positive, require_finite_positive};
use crate::error::{Error, Result};

/// Most operations (samples × lines) in computing one multisine period, `2³²`.
const MAX_MULTISINE_WORK: usize = 1 << 32;

/// Checks a sampling rate and a frequency strictly between DC and Nyquist.
fn check_frequency(name: crate::Parameter, freq_hz: f64, sample_rate: f64) -> Result<()> {
    require_finite_positive(
        crate::Parameter::SampleRate,
        sample_rate,
        "finite and positive (Hz)",
    )?;
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
/// [`Simulator::held_record`](super::Simulator::held_record). The drive starts at zero force;
/// the response reaches its steady state after the free vibration it starts has decayed (about
/// `6 ln 10 / (ζ ω_n)` seconds for `10⁻⁶`), which a test discards with
/// [`Record::trimmed`](crate::records::Record::trimmed).
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
    check_frequency(crate::Parameter::SineFrequency, freq_hz, sample_rate)?;
    at_most("samples per record", samples as f64, MAX_SAMPLES)?;
    if !amplitude_n.is_finite() {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::SineAmplitude,
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
            name: crate::Parameter::MultisinePeriod,
            value: period as f64,
            expected: "at least 8 samples",
        });
    }
    let (first, last) = (*lines.start(), *lines.end());
    if lines.is_empty() || first == 0 || 2 * last >= period {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::MultisineLines,
            value: if first == 0 { 0.0 } else { last as f64 },
            expected: "a non-empty range of lines 1 ≤ k < period / 2",
        });
    }
    require_finite_positive(
        crate::Parameter::MultisineRms,
        rms_n,
        "finite and positive (N)",
    )?;
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
    check_frequency(crate::Parameter::SweepStartFrequency, f0_hz, sample_rate)?;
    check_frequency(crate::Parameter::SweepEndFrequency, f1_hz, sample_rate)?;
    at_most("samples per record", samples as f64, MAX_SAMPLES)?;
    if !(finite_positive(sweep_s)
        && sweep_s * sample_rate <= samples as f64 + crate::tolerance::SWEEP_FIT_SAMPLES)
    {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::SweepDuration,
            value: sweep_s,
            expected: "finite, positive and within the record (s)",
        });
    }
    if !amplitude_n.is_finite() {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::SweepAmplitude,
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

/// Samples of Gaussian random noise band-limited to `[low_hz, high_hz]`: complex Gaussian
/// amplitudes on the DFT lines of the whole record inside the band, zero elsewhere, back to time
/// by an inverse real FFT and scaled to an RMS of exactly `rms_n`,
///
/// $$ f_m = s \,\mathrm{Re} \sum_{k:\, f_k \in [f_\text{lo}, f_\text{hi}]} (g_k + i h_k)\,
///    e^{2\pi i k m / N}, \qquad g_k, h_k \sim \mathcal N(0, 1), $$
///
/// with `f_k = k f_s / N`. The force of a random shaker test whose power stays in the band of
/// interest (white noise spends most of it above). Periodic over the record; its Welch segments
/// see a stationary Gaussian signal. Reproducible: the seed fixes the amplitudes.
///
/// # Errors
/// [`Error::InvalidParameter`] unless the sampling rate is finite and positive,
/// `0 < low < high < f_s/2`, at least one line lies in the band, the RMS is finite and
/// positive, and there are at least 8 samples; [`Error::TooLarge`] past [`MAX_SAMPLES`].
///
/// # Examples
/// ```
/// use bearing_ident::simulate::band_noise;
/// let f = band_noise(8.0, 49.0, 50.0, 2048.0, 8192, 3)?;
/// let rms = (f.iter().map(|v| v * v).sum::<f64>() / 8192.0).sqrt();
/// assert!((rms - 50.0).abs() < 1e-9);
/// assert!(band_noise(49.0, 8.0, 50.0, 2048.0, 8192, 3).is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn band_noise(
    low_hz: f64,
    high_hz: f64,
    rms_n: f64,
    sample_rate: f64,
    samples: usize,
    seed: u64,
) -> Result<Vec<f64>> {
    check_frequency(crate::Parameter::BandNoiseLowFrequency, low_hz, sample_rate)?;
    check_frequency(
        crate::Parameter::BandNoiseHighFrequency,
        high_hz,
        sample_rate,
    )?;
    require_finite_positive(
        crate::Parameter::BandNoiseRms,
        rms_n,
        "finite and positive (N)",
    )?;
    at_most("samples per record", samples as f64, MAX_SAMPLES)?;
    if samples < crate::records::MIN_SAMPLES {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::BandNoiseSamples,
            value: samples as f64,
            expected: "at least 8",
        });
    }
    let df = sample_rate / samples as f64;
    let first = (low_hz / df).ceil().max(1.0) as usize;
    let last = ((high_hz / df).floor() as usize).min((samples - 1) / 2);
    if low_hz >= high_hz || first > last {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::BandNoiseHighFrequency,
            value: high_hz,
            expected: "above the low frequency, with at least one DFT line of the record between",
        });
    }
    let mut rng = StdRng::seed_from_u64(seed);
    let normal = rand_distr::StandardNormal;
    let mut spectrum = vec![num_complex::Complex64::new(0.0, 0.0); samples / 2 + 1];
    for line in &mut spectrum[first..=last] {
        let (re, im): (f64, f64) = (normal.sample(&mut rng), normal.sample(&mut rng));
        *line = num_complex::Complex64::new(re, im);
    }
    let mut out = vec![0.0; samples];
    realfft::RealFftPlanner::<f64>::new()
        .plan_fft_inverse(samples)
        .process(&mut spectrum, &mut out)
        .expect("buffer lengths from the plan; DC and Nyquist lines are zero");
    let rms = (out.iter().map(|v| v * v).sum::<f64>() / samples as f64).sqrt();
    let scale = rms_n / rms;
    out.iter_mut().for_each(|v| *v *= scale);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Coefficients;
    use crate::simulate::{AntiAlias, Simulator};
    use faer::mat;

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
    fn band_noise_lives_in_its_band() {
        let (fs, n) = (1000.0, 4000);
        let f = band_noise(20.0, 60.0, 5.0, fs, n, 9).unwrap();
        let df = fs / n as f64;
        let total: f64 = (1..n / 2)
            .map(|k| dft_at(&f, k as f64 * df, fs).norm_sqr())
            .sum();
        let inside: f64 = (80..=240)
            .map(|k| dft_at(&f, k as f64 * df, fs).norm_sqr())
            .sum();
        assert!((inside / total - 1.0).abs() < 1e-12, "{}", inside / total);
        let rms = (f.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
        assert!((rms - 5.0).abs() < 1e-12);
        // Another seed, another signal; roughly Gaussian: kurtosis ≈ 3.
        let g = band_noise(20.0, 60.0, 5.0, fs, n, 10).unwrap();
        assert!(g.iter().zip(&f).any(|(a, b)| (a - b).abs() > 1e-3));
        let kurt = f.iter().map(|v| v.powi(4)).sum::<f64>() / n as f64 / 625.0;
        assert!((kurt - 3.0).abs() < 0.5, "kurtosis {kurt}");
        for bad in [
            band_noise(60.0, 20.0, 5.0, fs, n, 0),
            band_noise(20.0, 600.0, 5.0, fs, n, 0),
            band_noise(20.05, 20.2, 5.0, fs, n, 0),
            band_noise(20.0, 60.0, 0.0, fs, n, 0),
            band_noise(20.0, 60.0, 5.0, fs, 4, 0),
        ] {
            assert!(
                matches!(bad, Err(Error::InvalidParameter { .. })),
                "{bad:?}"
            );
        }
    }
}
