//! Stage 2: spectra of the time records.
//!
//! A [`SpectralEstimator`] is planned once for a segment length and then transforms any number
//! of channels and segments of that length. It owns its FFT plan, its window and its buffers, so
//! [`SpectralEstimator::transform`] never allocates.
//!
//! # Scaling
//! With `N` samples at spacing `Δt`, window `w` and the segment mean removed, line `k` is
//!
//! $$ X_k = \Delta t \sum_{m=0}^{N-1} w_m (x_m - \bar x)\, e^{-2\pi i k m / N},
//!    \qquad f_k = k\,\frac{f_s}{N},\quad k = 0,\dots,N/2 , $$
//!
//! the one-sided, `Δt`-scaled DFT: for a transient that starts and ends inside the record it
//! approximates the continuous Fourier transform $X(\omega) = \int x(t) e^{-i\omega t}\,dt$ (units
//! N·s and m·s). Transfer functions are ratios, so the scale cancels in them.
//!
//! What lives where: the estimator is here; the windows in `window.rs`, the force gate in
//! `gate.rs`, the cutting of records into segments in `segmentation.rs`.

mod gate;
mod segmentation;
mod window;

use std::cell::RefCell;
use std::sync::Arc;

use faer::c64;
use realfft::{RealFftPlanner, RealToComplex};

use crate::error::{Error, Result};
use crate::lanes;
use crate::records::require_finite_positive;

pub use gate::ForceGate;
pub use segmentation::Segmentation;
pub use window::Window;

/// A spectral estimator planned for one segment length: mean removal, window, real FFT.
///
/// # Examples
/// ```
/// use bearing_ident::spectra::{SpectralEstimator, Window};
/// // A 5 Hz cosine of amplitude 2 sampled at 64 Hz for 1 s.
/// let x: Vec<f64> = (0..64)
///     .map(|m| 2.0 * (2.0 * std::f64::consts::PI * 5.0 * m as f64 / 64.0).cos())
///     .collect();
/// let mut est = SpectralEstimator::new(64, 64.0, Window::Rectangular)?;
/// let spectrum = est.transform(&x);
/// // Line 5 holds amplitude · duration / 2 = 1.0 (Δt-scaled DFT).
/// assert!((spectrum[5].re - 1.0).abs() < 1e-12);
/// assert_eq!(est.frequency_hz(5), 5.0);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub struct SpectralEstimator {
    len: usize,
    sample_rate: f64,
    window: Window,
    weights: Arc<[f64]>,
    /// Window × gate weights for force channels, and the first closed sample, when gated.
    gate: Option<(ForceGate, Vec<f64>, usize)>,
    fft: Arc<dyn RealToComplex<f64>>,
    input: Vec<f64>,
    output: Vec<c64>,
    scratch: Vec<c64>,
}

thread_local! {
    /// The FFT plans, kept per thread: the records of a test share a segment length, and
    /// planning a transform (its twiddle factors) costs about as much as transforming a few
    /// channels.
    static PLANS: RefCell<RealFftPlanner<f64>> = RefCell::new(RealFftPlanner::new());
    /// The windows' weights of the last few estimators made on this thread, by window, length
    /// and sample spacing: the same numbers, computed once.
    static WEIGHTS: RefCell<Vec<(WeightsKey, Arc<[f64]>)>> = const { RefCell::new(Vec::new()) };
}

/// What a window's weights depend on: the window, the length and the bits of the sample
/// spacing.
type WeightsKey = (Window, usize, u64);

/// Windows [`SpectralEstimator::new`] keeps per thread.
const RECENT_WINDOWS: usize = 4;

impl std::fmt::Debug for SpectralEstimator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SpectralEstimator")
            .field("len", &self.len)
            .field("sample_rate", &self.sample_rate)
            .field("window", &self.window)
            .finish_non_exhaustive()
    }
}

/// A clone shares the FFT plan (and its twiddles) and gets buffers of its own: the cheap way
/// to give each worker thread an estimator.
impl Clone for SpectralEstimator {
    fn clone(&self) -> Self {
        Self {
            len: self.len,
            sample_rate: self.sample_rate,
            window: self.window,
            weights: Arc::clone(&self.weights),
            gate: self.gate.clone(),
            fft: Arc::clone(&self.fft),
            input: self.fft.make_input_vec(),
            output: self.fft.make_output_vec(),
            scratch: self.fft.make_scratch_vec(),
        }
    }
}

impl SpectralEstimator {
    /// Plans the FFT and allocates every buffer for segments of `len` samples at
    /// `sample_rate` Hz.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if `len < 2`, `sample_rate` is not finite and positive, or
    /// an exponential window's decay is not finite and `≥ 0`.
    pub fn new(len: usize, sample_rate: f64, window: Window) -> Result<Self> {
        if len < 2 {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::SpectralSegmentLength,
                value: len as f64,
                expected: "at least 2 samples",
            });
        }
        require_finite_positive(
            crate::Parameter::SampleRate,
            sample_rate,
            "finite and positive (Hz)",
        )?;
        let window = window.check()?;
        let fft = PLANS.with(|plans| plans.borrow_mut().plan_fft_forward(len));
        let dt = 1.0 / sample_rate;
        let weights = WEIGHTS.with(|recent| {
            let mut recent = recent.borrow_mut();
            let key = (window, len, dt.to_bits());
            if let Some((_, w)) = recent.iter().find(|(k, _)| *k == key) {
                return Arc::clone(w);
            }
            let w: Arc<[f64]> = (0..len).map(|m| window.weight(m, len, dt)).collect();
            if recent.len() == RECENT_WINDOWS {
                recent.remove(0);
            }
            recent.push((key, Arc::clone(&w)));
            w
        });
        let input = fft.make_input_vec();
        let output = fft.make_output_vec();
        let scratch = fft.make_scratch_vec();
        Ok(Self {
            len,
            sample_rate,
            window,
            weights,
            gate: None,
            fft,
            input,
            output,
            scratch,
        })
    }

    /// Segment length in samples.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always `false`: an estimator has at least 2 samples.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Number of one-sided lines, `len/2 + 1`.
    pub fn lines(&self) -> usize {
        self.len / 2 + 1
    }

    /// Line spacing `f_s / N` (Hz).
    pub fn resolution_hz(&self) -> f64 {
        self.sample_rate / self.len as f64
    }

    /// Frequency of line `k` (Hz).
    pub fn frequency_hz(&self, k: usize) -> f64 {
        k as f64 * self.resolution_hz()
    }

    /// The window in use.
    pub fn window(&self) -> Window {
        self.window
    }

    /// The same estimator with `gate` on the force channels ([`SpectralEstimator::transform_force`]).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::spectra::{ForceGate, SpectralEstimator, Window};
    /// // A 1 N offset, a unit pulse at sample 2, noise-like junk after the gate.
    /// let mut f = vec![1.0; 64];
    /// f[2] = 2.0;
    /// f[40] = 1.5;
    /// f[41] = 0.5;
    /// let gate = ForceGate::new(0.1, 0.0)?; // 6.4 samples at 64 Hz
    /// let mut est = SpectralEstimator::new(64, 64.0, Window::Rectangular)?.with_force_gate(gate);
    /// let spectrum = est.transform_force(&f);
    /// // Only the pulse is left (offset removed from the quiet part): |F| = 1 · Δt everywhere.
    /// assert!((spectrum[7].norm() - 1.0 / 64.0).abs() < 1e-12);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn with_force_gate(mut self, gate: ForceGate) -> Self {
        let dt = 1.0 / self.sample_rate;
        let weights = (0..self.len)
            .map(|m| self.weights[m] * gate.weight(m as f64 * dt))
            .collect();
        self.gate = Some((gate, weights, gate.closed_from(dt)));
        self
    }

    /// The force gate in use, if any.
    pub fn force_gate(&self) -> Option<ForceGate> {
        self.gate.as_ref().map(|g| g.0)
    }

    /// Sum of the squared window weights, `Σ w_m²` (for density scaling).
    pub fn window_power(&self) -> f64 {
        self.weights.iter().map(|w| w * w).sum()
    }

    /// One-sided spectrum of `signal` (mean removed, windowed, `Δt`-scaled), `len/2 + 1` lines,
    /// held in the estimator's own buffer until the next call. Does not allocate.
    ///
    /// # Panics
    /// If `signal.len() != self.len()`.
    pub fn transform(&mut self, signal: &[f64]) -> &[c64] {
        assert_eq!(
            signal.len(),
            self.len,
            "segment length differs from the plan"
        );
        let mean = if self.window.removes_mean() {
            lanes::sum(signal) / self.len as f64
        } else {
            0.0
        };
        for ((dst, &x), &w) in self.input.iter_mut().zip(signal).zip(self.weights.iter()) {
            *dst = w * (x - mean);
        }
        self.run_fft()
    }

    /// As [`SpectralEstimator::transform`] for a force channel: with a force gate
    /// ([`SpectralEstimator::with_force_gate`]) the offset is the mean of the samples after the
    /// gate has closed, and the gate multiplies the window. Without one, the same as
    /// [`SpectralEstimator::transform`]. Does not allocate.
    ///
    /// # Panics
    /// If `signal.len() != self.len()`.
    pub fn transform_force(&mut self, signal: &[f64]) -> &[c64] {
        let Some((_, weights, closed)) = &self.gate else {
            return self.transform(signal);
        };
        assert_eq!(
            signal.len(),
            self.len,
            "segment length differs from the plan"
        );
        let offset = match signal.get(*closed..) {
            Some(quiet) if !quiet.is_empty() => lanes::sum(quiet) / quiet.len() as f64,
            _ if self.window.removes_mean() => lanes::sum(signal) / self.len as f64,
            _ => 0.0,
        };
        for ((dst, &x), &w) in self.input.iter_mut().zip(signal).zip(weights) {
            *dst = w * (x - offset);
        }
        self.run_fft()
    }

    /// FFT of the prepared input, `Δt`-scaled, into the output buffer.
    fn run_fft(&mut self) -> &[c64] {
        // The buffers come from the plan itself, so their lengths always match.
        self.fft
            .process_with_scratch(&mut self.input, &mut self.output, &mut self.scratch)
            .expect("buffer lengths come from the plan");
        let dt = 1.0 / self.sample_rate;
        for v in &mut self.output {
            *v *= dt;
        }
        &self.output
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segmentation_round_trips_through_its_string_form() {
        for seg in [
            Segmentation::WholeRecord,
            Segmentation::Welch { len: 512 },
            Segmentation::Periods { len: 200 },
        ] {
            assert_eq!(seg.to_string().parse::<Segmentation>().unwrap(), seg);
            assert!(seg.to_string().starts_with(seg.name()));
        }
        for bad in ["", "welch", "whole:8", "periods:x", "hann", "welch:-1"] {
            let e = bad.parse::<Segmentation>().unwrap_err();
            assert_eq!(e.kind(), "invalid_argument", "{bad}");
        }
    }

    #[test]
    fn exponential_refuses_bad_decays() {
        for a in [f64::NAN, -1.0, f64::INFINITY] {
            let e = Window::exponential(a).unwrap_err();
            assert!(
                matches!(
                    e,
                    Error::InvalidParameter {
                        name: crate::Parameter::ExponentialWindowDecay,
                        ..
                    }
                ),
                "{a}"
            );
        }
        assert!(Window::exponential(0.0).is_ok());
    }

    #[test]
    fn new_refuses_bad_plans_with_errors() {
        for (len, fs, window) in [
            (1, 1.0, Window::Rectangular),
            (8, f64::NAN, Window::Rectangular),
            (8, 0.0, Window::Hann),
            (
                8,
                1.0,
                Window::Exponential {
                    decay_per_s: f64::NAN,
                },
            ),
            (8, 1.0, Window::Exponential { decay_per_s: -1.0 }),
            (
                8,
                1.0,
                Window::Exponential {
                    decay_per_s: f64::INFINITY,
                },
            ),
        ] {
            let e = SpectralEstimator::new(len, fs, window).unwrap_err();
            assert_eq!(e.kind(), "invalid_argument", "{len} {fs} {window:?}");
        }
    }

    #[test]
    fn matches_direct_dft_sum() {
        let n = 30;
        let fs = 10.0;
        let x: Vec<f64> = (0..n)
            .map(|m| ((m * m) % 7) as f64 - 0.3 * m as f64)
            .collect();
        let mean = x.iter().sum::<f64>() / n as f64;
        let mut est = SpectralEstimator::new(n, fs, Window::Rectangular).unwrap();
        let got = est.transform(&x).to_vec();
        for (k, g) in got.iter().enumerate() {
            let mut s = c64::new(0.0, 0.0);
            for (m, v) in x.iter().enumerate() {
                let ph = -2.0 * std::f64::consts::PI * (k * m) as f64 / n as f64;
                s += c64::new(ph.cos(), ph.sin()) * (v - mean);
            }
            assert!((g - s / fs).norm() < 1e-12, "line {k}");
        }
    }

    #[test]
    fn mean_is_removed() {
        let mut est = SpectralEstimator::new(16, 1.0, Window::Hann).unwrap();
        let x = vec![3.0; 16];
        assert!(est.transform(&x).iter().all(|v| v.norm() < 1e-12));
    }

    #[test]
    fn exponential_window_keeps_the_mean_and_decays() {
        let mut est =
            SpectralEstimator::new(100, 100.0, Window::exponential_to(0.01, 1.0)).unwrap();
        let x = vec![1.0; 100];
        // Σ e^{-a m Δt} Δt with a = ln 100: (1 − e^{-a})/(1 − e^{-aΔt}) · Δt.
        let a = 100f64.ln();
        let expect = (1.0 - (-a).exp()) / (1.0 - (-a * 0.01).exp()) * 0.01;
        assert!((est.transform(&x)[0].re - expect).abs() < 1e-12);
    }

    #[test]
    fn hann_weights_and_power() {
        let est = SpectralEstimator::new(8, 1.0, Window::Hann).unwrap();
        assert!((est.window_power() - 3.0).abs() < 1e-12); // Σ sin⁴(πm/8) = 3N/8
        assert_eq!(est.lines(), 5);
        assert_eq!(est.window(), Window::Hann);
    }

    #[test]
    fn welch_segment_length_is_checked() {
        assert_eq!(Segmentation::Welch { len: 16 }.segment_len(100), Ok(16));
        assert!(matches!(
            Segmentation::Welch { len: 200 }.segment_len(100),
            Err(Error::InvalidParameter { .. })
        ));
        assert_eq!(Segmentation::WholeRecord.segment_len(100), Ok(100));
    }
}
