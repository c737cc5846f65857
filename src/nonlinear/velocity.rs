//! Displacements and velocities of the records for the regressors: a frequency-domain
//! derivative (or integral) with a gain that keeps the excited band ([`Differentiation`]).
//!
//! The friction and quadratic-damping regressors $\operatorname{sign}(\dot x)$,
//! $\lvert\dot x\rvert\dot x$ are nonlinear in the velocity, so how the velocity is derived
//! from sampled records moves their coefficients: a low-pass just below the forcing band, none
//! at all, or a Savitzky–Golay derivative each bias them by several percent in simulation.
//! Here the whole record is transformed once, multiplied at every line by
//! $g_k\,(i\omega_k)^{1-p}$ for the velocity and $g_k\,(i\omega_k)^{-p}$ for the displacement
//! ($p$ the channel's [`Response::order`]), and transformed back; the gain $g_k$ is the choice:
//!
//! - [`Differentiation::Wiener`] (default): $g_k = \max\!\left(0,\; 1 - \beta N_0/\bar P_k\right)$,
//!   the Wiener gain $S/(S+N)$ written with the smoothed power $\bar P_k$ of the channel (a
//!   $\pm$[`WIENER_SMOOTHING_LINES`] moving average of $\lvert X_k\rvert^2$) and its noise floor
//!   $N_0$, the median of $\bar P_k$ above the band (the lowest decile of the whole spectrum
//!   when fewer than [`WIENER_MIN_FLOOR_LINES`] lines lie above it), over-subtracted by
//!   $\beta$ = [`WIENER_OVERSUBTRACTION`] so that lines of noise alone, whose smoothed power
//!   scatters about $N_0$, get a gain of zero. Where the excitation drives the system
//!   $\bar P_k \gg N_0$ and $g_k \to 1$: the excited band is kept whole, while the measurement
//!   noise that a derivative would amplify towards Nyquist is removed.
//! - [`Differentiation::Cutoff`]: $g_k = 1$ up to the cutoff, $0$ above (an ideal low-pass).
//!
//! DC is removed ($g_0 = 0$): displacements are taken about their mean, the equilibrium. The
//! record is one period to the DFT: periodic and multisine records are differentiated exactly;
//! a random record that ends away from where it starts rings over its first and last few
//! periods of the band's upper edge, where the Hann windows of the first and last Welch segments
//! give the regressors little weight. (Taking out the line through the ends was tried: it
//! breaks the exactness on periodic records and gains nothing measurable on random ones.)

use std::sync::Arc;

use faer::c64;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};

use crate::error::{Error, Result};
use crate::frf::Band;
use crate::records::Response;
use crate::statistics::quantile;
use crate::tolerance::{WIENER_MIN_FLOOR_LINES, WIENER_OVERSUBTRACTION, WIENER_SMOOTHING_LINES};

/// How velocities are derived from the records ([`crate::nonlinear::ReversePath::differentiation`]).
///
/// # Examples
/// ```
/// use bearing_ident::nonlinear::Differentiation;
/// assert_eq!(Differentiation::default(), Differentiation::Wiener);
/// assert_eq!(Differentiation::Cutoff(80.0).name(), "cutoff");
/// assert_eq!(Differentiation::Cutoff(80.0).cutoff_hz(), Some(80.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Differentiation {
    /// Frequency-domain derivative with the Wiener gain from the channel's noise floor: keeps
    /// the whole excited band (the default).
    #[default]
    Wiener,
    /// Frequency-domain derivative with an ideal low-pass at this frequency (Hz, finite,
    /// `> 0`; above Nyquist it keeps every line).
    Cutoff(f64),
}

impl Differentiation {
    /// `"wiener"` or `"cutoff"` (the JSON output's `velocity.method`).
    pub fn name(self) -> &'static str {
        match self {
            Differentiation::Wiener => "wiener",
            Differentiation::Cutoff(_) => "cutoff",
        }
    }

    /// The cutoff (Hz) of [`Differentiation::Cutoff`], `None` for the Wiener gain.
    pub fn cutoff_hz(self) -> Option<f64> {
        match self {
            Differentiation::Wiener => None,
            Differentiation::Cutoff(hz) => Some(hz),
        }
    }

    /// The same choice, checked.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a cutoff that is not finite and positive.
    pub fn check(self) -> Result<Self> {
        match self {
            Differentiation::Cutoff(hz) if !(hz.is_finite() && hz > 0.0) => {
                Err(Error::InvalidParameter {
                    name: crate::Parameter::VelocityCutoff,
                    value: hz,
                    expected: "finite and positive (Hz)",
                })
            }
            d => Ok(d),
        }
    }
}

/// What the velocities of an identification came from and how: reported with the result
/// ([`NonlinearIdentification::velocity`](crate::nonlinear::NonlinearIdentification::velocity)).
#[derive(Debug, Clone, PartialEq)]
pub struct VelocityChoice {
    /// The gain used.
    pub differentiation: Differentiation,
    /// The kinds of response channel the velocities were derived from, each once, in the
    /// order first met: `[Displacement]` when every channel measured displacement (the
    /// velocity is differentiated), `[Velocity]` when velocities were measured (used through
    /// the same gain, and integrated for the displacement).
    pub sources: Vec<Response>,
}

/// Displacement and velocity of single channels of one record length: plans its FFTs once
/// and reuses its buffers, so [`Differentiator::kinematics`] does not allocate.
///
/// # Examples
/// ```
/// use bearing_ident::frf::Band;
/// use bearing_ident::nonlinear::{Differentiation, Differentiator};
/// use bearing_ident::records::Response;
/// // x = 1e-3 sin(2π·8t) sampled at 256 Hz for 2 s: v = 2π·8·1e-3 cos(2π·8t).
/// let (fs, n) = (256.0, 512);
/// let w = 2.0 * std::f64::consts::PI * 8.0;
/// let x: Vec<f64> = (0..n).map(|m| 1e-3 * (w * m as f64 / fs).sin()).collect();
/// let mut d = Differentiator::new(n, fs, Differentiation::Cutoff(50.0), Band::new(5.0, 20.0)?)?;
/// let (mut xo, mut vo) = (vec![0.0; n], vec![0.0; n]);
/// d.kinematics(&x, Response::Displacement, &mut xo, &mut vo);
/// assert!((vo[0] - w * 1e-3).abs() < 1e-9);
/// assert!((xo[16] - x[16]).abs() < 1e-12);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub struct Differentiator {
    differentiation: Differentiation,
    sample_rate: f64,
    len: usize,
    /// Upper band edge (Hz): the noise floor is read above it.
    band_high_hz: f64,
    forward: Arc<dyn RealToComplex<f64>>,
    inverse: Arc<dyn ComplexToReal<f64>>,
    time: Vec<f64>,
    spectrum: Vec<c64>,
    work: Vec<c64>,
    power: Vec<f64>,
    smooth: Vec<f64>,
    sorted: Vec<f64>,
    scratch_forward: Vec<c64>,
    scratch_inverse: Vec<c64>,
    /// The Wiener floor of the last channel relative to its largest spectral component
    /// squared, and that component (floor 0 for a cutoff).
    floor: (f64, f64),
    /// Standard deviation of the noise left in the last velocity (see
    /// [`Differentiator::velocity_noise_std`]).
    velocity_noise_std: f64,
}

impl std::fmt::Debug for Differentiator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Differentiator")
            .field("differentiation", &self.differentiation)
            .field("sample_rate", &self.sample_rate)
            .field("len", &self.len)
            .finish_non_exhaustive()
    }
}

impl Differentiator {
    /// Plans the transforms for channels of `len` samples at `sample_rate` Hz, for an
    /// identification over `band` (its upper edge bounds the noise-floor search).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for fewer than 8 samples, a sample rate that is not finite
    /// and positive, or a bad cutoff ([`Differentiation::check`]).
    pub fn new(
        len: usize,
        sample_rate: f64,
        differentiation: Differentiation,
        band: Band,
    ) -> Result<Self> {
        if len < 8 {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::SamplesToDifferentiate,
                value: len as f64,
                expected: "at least 8",
            });
        }
        crate::records::require_finite_positive(
            crate::Parameter::SampleRate,
            sample_rate,
            "finite and positive (Hz)",
        )?;
        let differentiation = differentiation.check()?;
        let mut planner = RealFftPlanner::<f64>::new();
        let forward = planner.plan_fft_forward(len);
        let inverse = planner.plan_fft_inverse(len);
        let lines = len / 2 + 1;
        Ok(Self {
            differentiation,
            sample_rate,
            len,
            band_high_hz: band.high_hz(),
            time: forward.make_input_vec(),
            spectrum: forward.make_output_vec(),
            work: vec![c64::new(0.0, 0.0); lines],
            power: vec![0.0; lines],
            smooth: vec![0.0; lines],
            sorted: Vec::with_capacity(lines),
            scratch_forward: forward.make_scratch_vec(),
            scratch_inverse: inverse.make_scratch_vec(),
            floor: (0.0, 0.0),
            velocity_noise_std: 0.0,
            forward,
            inverse,
        })
    }

    /// Displacement (about its mean) into `x_out` and velocity into `v_out` of a channel
    /// `signal` that measures `response`, through the gain of the module docs. Returns the
    /// noise floor $N_0$ of the Wiener gain (power per line relative to the channel's largest
    /// spectral component squared; 0 for a cutoff). Does not allocate.
    ///
    /// # Panics
    /// If a slice's length differs from the planned one.
    pub fn kinematics(
        &mut self,
        signal: &[f64],
        response: Response,
        x_out: &mut [f64],
        v_out: &mut [f64],
    ) -> f64 {
        let n = self.len;
        assert!(
            signal.len() == n && x_out.len() == n && v_out.len() == n,
            "channel length differs from the plan"
        );
        self.time.copy_from_slice(signal);
        self.forward
            .process_with_scratch(
                &mut self.time,
                &mut self.spectrum,
                &mut self.scratch_forward,
            )
            .expect("buffer lengths come from the plan");
        let floor = self.gain();
        let dw = 2.0 * std::f64::consts::PI * self.sample_rate / n as f64;
        let p = response.order();
        // White noise of power N₀ per line through the gain and (iω)^(1−p): a one-sided sum,
        // each line standing for itself and its mirror.
        // Relative to the largest component, so that no square leaves f64's range.
        let (relative, largest) = self.floor;
        let sum: f64 = self
            .power
            .iter()
            .enumerate()
            .filter(|(_, g)| **g > 0.0)
            .map(|(k, g)| 2.0 * g * g * (dw * k as f64).powi(2 * (1 - p)) * relative)
            .sum();
        let std = sum.sqrt() * largest / n as f64;
        self.velocity_noise_std = if std.is_finite() { std } else { 0.0 };
        // Displacement: X̂ = g S / (iω)^p; velocity: V̂ = g S (iω)^(1−p). `power` holds g.
        for order_shift in [0, 1] {
            for (k, (dst, &s)) in self.work.iter_mut().zip(&self.spectrum).enumerate() {
                let g = self.power[k];
                *dst = if g == 0.0 {
                    c64::new(0.0, 0.0)
                } else {
                    s * g * c64::new(0.0, dw * k as f64).powi(order_shift - p)
                };
            }
            let out: &mut [f64] = if order_shift == 0 {
                &mut *x_out
            } else {
                &mut *v_out
            };
            self.inverse
                .process_with_scratch(&mut self.work, out, &mut self.scratch_inverse)
                .expect("buffer lengths come from the plan");
            let scale = 1.0 / n as f64;
            out.iter_mut().for_each(|v| *v *= scale);
        }
        floor
    }

    /// The standard deviation of the measurement noise left in the velocity of the last
    /// [`Differentiator::kinematics`], from its Wiener floor $N_0$ taken as white:
    /// $\sigma_n^2 = \frac{2}{N^2}\sum_k g_k^2\,\omega_k^{2(1-p)} N_0$ (0 for a cutoff,
    /// which reads no floor). It sets how often the sign of the velocity is wrong near its
    /// zero crossings, which biases dry friction low unless accounted for (see
    /// [`Regressor::Coulomb`](crate::nonlinear::Regressor::Coulomb)).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::frf::Band;
    /// use bearing_ident::nonlinear::{Differentiation, Differentiator};
    /// use bearing_ident::records::Response;
    /// let (fs, n) = (256.0, 512);
    /// let x: Vec<f64> = (0..n).map(|m| (2.0 * std::f64::consts::PI * 8.0 * m as f64 / fs).sin()).collect();
    /// let mut d = Differentiator::new(n, fs, Differentiation::Cutoff(50.0), Band::new(5.0, 20.0)?)?;
    /// let (mut xo, mut vo) = (vec![0.0; n], vec![0.0; n]);
    /// d.kinematics(&x, Response::Displacement, &mut xo, &mut vo);
    /// assert_eq!(d.velocity_noise_std(), 0.0);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn velocity_noise_std(&self) -> f64 {
        self.velocity_noise_std
    }

    /// The gain per line into `self.power` (DC and, for even lengths, Nyquist zero); returns
    /// the noise floor of the Wiener gain (0 for a cutoff).
    fn gain(&mut self) -> f64 {
        let lines = self.spectrum.len();
        let df = self.sample_rate / self.len as f64;
        let floor = match self.differentiation {
            Differentiation::Cutoff(hz) => {
                for (k, g) in self.power.iter_mut().enumerate() {
                    *g = if k as f64 * df <= hz { 1.0 } else { 0.0 };
                }
                self.floor = (0.0, 0.0);
                0.0
            }
            Differentiation::Wiener => {
                // Scaled to a largest component of 1: the gain is a ratio of powers, and the
                // squares of a channel's spectrum may leave f64's range.
                let largest = self
                    .spectrum
                    .iter()
                    .fold(0.0_f64, |m, s| m.max(s.re.abs()).max(s.im.abs()));
                let scale = if largest > 0.0 { 1.0 / largest } else { 1.0 };
                for (p, s) in self.power.iter_mut().zip(&self.spectrum) {
                    *p = (s * scale).norm_sqr();
                }
                moving_average(&self.power, WIENER_SMOOTHING_LINES, &mut self.smooth);
                let first_above = ((self.band_high_hz / df).floor() as usize + 1).min(lines);
                self.sorted.clear();
                let above = &self.smooth[first_above..];
                let floor = if above.len() >= WIENER_MIN_FLOOR_LINES {
                    self.sorted.extend_from_slice(above);
                    quantile(&mut self.sorted, 0.5)
                } else {
                    self.sorted.extend_from_slice(&self.smooth[1..]);
                    quantile(&mut self.sorted, 0.1)
                };
                // The noise level for the velocity's noise: the upper half of the lines above
                // the band, where a structure's own response to the harmonics of a
                // nonlinear force (falling with frequency) has died away and white noise has
                // not.
                let upper = &self.smooth[first_above + above.len() / 2..];
                let noise = if upper.len() >= WIENER_MIN_FLOOR_LINES {
                    self.sorted.clear();
                    self.sorted.extend_from_slice(upper);
                    quantile(&mut self.sorted, 0.5)
                } else {
                    floor
                };
                self.floor = (noise, largest);
                let floor_over = WIENER_OVERSUBTRACTION * floor;
                for (g, &p) in self.power.iter_mut().zip(&self.smooth) {
                    *g = if p > 0.0 {
                        (1.0 - floor_over / p).max(0.0)
                    } else {
                        0.0
                    };
                }
                floor
            }
        };
        self.power[0] = 0.0;
        if self.len % 2 == 0 {
            self.power[lines - 1] = 0.0;
        }
        floor
    }
}

/// `out[k]` = mean of `values[k − h ..= k + h]` clipped to the slice, by a running sum.
fn moving_average(values: &[f64], h: usize, out: &mut [f64]) {
    let n = values.len();
    let mut sum: f64 = values[..(h + 1).min(n)].iter().sum();
    let mut count = (h + 1).min(n);
    for k in 0..n {
        out[k] = sum / count as f64;
        if k + h + 1 < n {
            sum += values[k + h + 1];
            count += 1;
        }
        if k >= h {
            sum -= values[k - h];
            count -= 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sine(n: usize, fs: f64, hz: f64, amp: f64) -> Vec<f64> {
        let w = 2.0 * std::f64::consts::PI * hz;
        (0..n).map(|m| amp * (w * m as f64 / fs).sin()).collect()
    }

    #[test]
    fn moving_average_clips_at_the_ends() {
        let mut out = [0.0; 5];
        moving_average(&[1.0, 2.0, 3.0, 4.0, 5.0], 1, &mut out);
        let expect = [1.5, 2.0, 3.0, 4.0, 4.5];
        assert!(out.iter().zip(expect).all(|(a, b)| (a - b).abs() < 1e-15));
    }

    #[test]
    fn wiener_keeps_the_band_and_removes_the_floor() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let (n, fs) = (8192, 1024.0);
        let w = 2.0 * std::f64::consts::PI * 20.0;
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        // A 20 Hz sine of 1 mm with 2 % white noise on top.
        let clean = sine(n, fs, 20.0, 1e-3);
        let noisy: Vec<f64> = clean
            .iter()
            .map(|c| c + Normal::new(0.0, 2e-5).unwrap().sample(&mut rng))
            .collect();
        let band = Band::new(10.0, 40.0).unwrap();
        let mut d = Differentiator::new(n, fs, Differentiation::Wiener, band).unwrap();
        let (mut x, mut v) = (vec![0.0; n], vec![0.0; n]);
        let floor = d.kinematics(&noisy, Response::Displacement, &mut x, &mut v);
        assert!(floor > 0.0);
        // True velocity 1e-3 ω cos: the error is a small fraction of its amplitude, where an
        // unfiltered derivative carries noise of 2e-5 · ω_Nyquist-ish.
        let amp = 1e-3 * w;
        let worst = (n / 8..7 * n / 8)
            .map(|m| (v[m] - amp * (w * m as f64 / fs).cos()).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 0.02 * amp,
            "worst velocity error {worst:e} of {amp:e}"
        );
        let mut raw = Differentiator::new(n, fs, Differentiation::Cutoff(fs), band).unwrap();
        raw.kinematics(&noisy, Response::Displacement, &mut x, &mut v);
        let worst_raw = (n / 8..7 * n / 8)
            .map(|m| (v[m] - amp * (w * m as f64 / fs).cos()).abs())
            .fold(0.0, f64::max);
        assert!(worst_raw > 5.0 * worst, "{worst_raw:e} vs {worst:e}");
    }

    #[test]
    fn a_measured_velocity_is_integrated_to_displacement() {
        let (n, fs) = (1024, 256.0);
        let w = 2.0 * std::f64::consts::PI * 8.0;
        // v = cos(ωt) → x = sin(ωt)/ω.
        let v_in: Vec<f64> = (0..n).map(|m| (w * m as f64 / fs).cos()).collect();
        let band = Band::new(5.0, 20.0).unwrap();
        let mut d = Differentiator::new(n, fs, Differentiation::Cutoff(50.0), band).unwrap();
        let (mut x, mut v) = (vec![0.0; n], vec![0.0; n]);
        d.kinematics(&v_in, Response::Velocity, &mut x, &mut v);
        for m in [0, 100, 517] {
            let t = m as f64 / fs;
            assert!(((x[m] - (w * t).sin() / w) * w).abs() < 1e-9, "{m}");
            assert!((v[m] - v_in[m]).abs() < 1e-9, "{m}");
        }
    }

    #[test]
    fn bad_plans_are_refused() {
        let band = Band::new(1.0, 2.0).unwrap();
        for (len, fs, d) in [
            (4, 10.0, Differentiation::Wiener),
            (64, f64::NAN, Differentiation::Wiener),
            (64, 10.0, Differentiation::Cutoff(f64::NAN)),
            (64, 10.0, Differentiation::Cutoff(-1.0)),
        ] {
            let e = Differentiator::new(len, fs, d, band).unwrap_err();
            assert_eq!(e.kind(), "invalid_argument", "{len} {fs} {d:?}");
        }
    }
}
