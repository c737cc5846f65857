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

use std::sync::Arc;

use faer::c64;
use realfft::{RealFftPlanner, RealToComplex};

use crate::error::{Error, Result};
use crate::lanes;
use crate::records::require_finite_positive;

/// Window applied to each segment before the DFT.
///
/// The enum is `#[non_exhaustive]`: more windows (a force gate) will come.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[non_exhaustive]
pub enum Window {
    /// No window (`w = 1`). Right for transients that decay inside the record.
    #[default]
    Rectangular,
    /// Periodic Hann window `w_m = sin²(π m / N)`, for random excitation with Welch averaging.
    Hann,
    /// Exponential window $w(t) = e^{-a t}$, `t` from the segment's first sample, applied to
    /// force and response alike, for lightly damped records that do not decay inside the
    /// record. Windowed data belong to the system $Z(s + a)$: fitted coefficients are
    /// `M_w = M`, `C_w = C + 2aM`, `K_w = K + aC + a²M`, which
    /// [`Identifier`](crate::Identifier) undoes exactly (the fit's `corrected_for_window`,
    /// a later stage). The segment
    /// mean is **not** removed under this window (a removed constant would turn into a
    /// decaying exponential and leak into every line): remove offsets, e.g. the pre-trigger
    /// mean, before.
    Exponential {
        /// Decay rate `a` (1/s), `≥ 0`.
        decay_per_s: f64,
    },
}

impl Window {
    /// The exponential window $w(t) = e^{-a t}$ with decay `a = decay_per_s` (1/s).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless `decay_per_s` is finite and `≥ 0`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Window;
    /// let w = Window::exponential(3.0)?;
    /// assert_eq!(w.decay_per_s(), Some(3.0));
    /// assert!(Window::exponential(f64::NAN).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn exponential(decay_per_s: f64) -> Result<Window> {
        Window::Exponential { decay_per_s }.check()
    }

    /// The window itself if its parameters are valid (an exponential window's decay finite
    /// and `≥ 0`); the one check every user of a window ([`SpectralEstimator::new`], the
    /// identifier's settings) makes.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an exponential window's decay that is NaN, negative or
    /// infinite.
    pub(crate) fn check(self) -> Result<Window> {
        if let Some(a) = self.decay_per_s() {
            if !(a.is_finite() && a >= 0.0) {
                return Err(Error::InvalidParameter {
                    name: crate::Parameter::ExponentialWindowDecay,
                    value: a,
                    expected: "finite and ≥ 0 (1/s)",
                });
            }
        }
        Ok(self)
    }

    /// The exponential window that falls to `end_value` (e.g. 0.01) at `duration_s`:
    /// `a = −ln(end_value) / duration_s`. A decay that is not finite and `≥ 0` (an
    /// `end_value` outside `(0, 1]`, a `duration_s` of 0) is refused with
    /// [`Error::InvalidParameter`] where the window is used ([`SpectralEstimator::new`],
    /// `Identifier::check`); [`Window::exponential`] refuses it at once.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Window;
    /// let w = Window::exponential_to(0.01, 1.2);
    /// assert!((w.decay_per_s().unwrap() - 3.8376).abs() < 1e-4);
    /// ```
    pub fn exponential_to(end_value: f64, duration_s: f64) -> Window {
        Window::Exponential {
            decay_per_s: -end_value.ln() / duration_s,
        }
    }

    /// The decay rate `a` (1/s) of an exponential window, `None` for the others.
    pub fn decay_per_s(self) -> Option<f64> {
        match self {
            Window::Exponential { decay_per_s } => Some(decay_per_s),
            _ => None,
        }
    }

    /// Short name: `"rect"`, `"hann"` or `"exp"`.
    pub fn name(self) -> &'static str {
        match self {
            Window::Rectangular => "rect",
            Window::Hann => "hann",
            Window::Exponential { .. } => "exp",
        }
    }

    /// Whether the segment mean is removed before windowing.
    fn removes_mean(self) -> bool {
        !matches!(self, Window::Exponential { .. })
    }

    /// The window's weight at sample `m` of `len`, samples `dt` apart.
    pub(crate) fn weight(self, m: usize, len: usize, dt: f64) -> f64 {
        match self {
            Window::Rectangular => 1.0,
            Window::Hann => {
                let s = (std::f64::consts::PI * m as f64 / len as f64).sin();
                s * s
            }
            Window::Exponential { decay_per_s } => (-decay_per_s * m as f64 * dt).exp(),
        }
    }
}

/// A force gate: the force channel is kept as it is up to `open_s` after the segment's start,
/// falls to zero along a half cosine over `taper_s`, and is zero after, so that the noise of the
/// quiet force record after an impact does not enter the spectra. The response is not gated.
///
/// Weight at time `t` from the segment's start:
/// $g(t) = 1$ for $t \le t_o$, $\tfrac12\,(1 + \cos(\pi (t - t_o)/t_\tau))$ for
/// $t_o < t < t_o + t_\tau$, 0 after. The force's offset is taken as the mean of the samples
/// after the gate has closed (the quiet force), and removed before gating; with no such samples
/// the window's own rule applies. The gate multiplies whatever [`Window`] is in use.
///
/// # Examples
/// ```
/// use bearing_ident::spectra::ForceGate;
/// let gate = ForceGate::new(0.05, 0.01)?;
/// assert_eq!(gate.weight(0.02), 1.0);
/// assert!((gate.weight(0.055) - 0.5).abs() < 1e-12);
/// assert_eq!(gate.weight(0.07), 0.0);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceGate {
    open_s: f64,
    taper_s: f64,
}

impl ForceGate {
    /// A gate open for `open_s` seconds with a cosine taper of `taper_s` seconds.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless `open_s > 0` and `taper_s ≥ 0`, both finite.
    pub fn new(open_s: f64, taper_s: f64) -> Result<Self> {
        require_finite_positive(
            crate::Parameter::ForceGate,
            open_s,
            "finite and positive (s)",
        )?;
        if !(taper_s.is_finite() && taper_s >= 0.0) {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::ForceGateTaper,
                value: taper_s,
                expected: "finite and ≥ 0 (s)",
            });
        }
        Ok(Self { open_s, taper_s })
    }

    /// Time the gate stays fully open (s).
    pub fn open_s(self) -> f64 {
        self.open_s
    }

    /// Length of the cosine taper (s).
    pub fn taper_s(self) -> f64 {
        self.taper_s
    }

    /// The gate's weight at `t` seconds from the segment's start.
    pub fn weight(self, t: f64) -> f64 {
        if t <= self.open_s {
            1.0
        } else if t < self.open_s + self.taper_s {
            0.5 * (1.0 + (std::f64::consts::PI * (t - self.open_s) / self.taper_s).cos())
        } else {
            0.0
        }
    }

    /// First sample index at which the gate is closed, for segments sampled `dt` apart
    /// (saturating: a gate longer than any record closes at `usize::MAX`).
    fn closed_from(self, dt: f64) -> usize {
        // `as` saturates: a gate longer than any record stays open over all of it.
        (((self.open_s + self.taper_s) / dt).floor() as usize).saturating_add(1)
    }
}

/// How records are cut into segments before their spectra are taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Segmentation {
    /// One DFT over the whole record (impacts, transients).
    #[default]
    WholeRecord,
    /// Welch segments of `len` samples with 50 % overlap (random excitation). The number of
    /// segments per record is `⌊(N − len) / (len/2)⌋ + 1`.
    Welch {
        /// Samples per segment.
        len: usize,
    },
    /// Consecutive, non-overlapping segments of exactly one period of `len` samples, for
    /// periodic and multisine excitation in steady state (use the rectangular window). Every
    /// line on the period's grid is then leakage-free; lines the excitation does not drive are
    /// left out by the cross-spectral estimators (see [`crate::frf::Frf::unexcited_hz`]) and the
    /// period-to-period scatter is the noise the coherence and error bars see. Samples after
    /// the last whole period are not used.
    Periods {
        /// Samples per period.
        len: usize,
    },
}

impl Segmentation {
    /// Segment length for a record of `record_len` samples.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if a Welch segment or a period is shorter than 8 samples or
    /// longer than the record.
    pub fn segment_len(self, record_len: usize) -> Result<usize> {
        match self {
            Segmentation::WholeRecord => Ok(record_len),
            Segmentation::Welch { len } | Segmentation::Periods { len }
                if (8..=record_len).contains(&len) =>
            {
                Ok(len)
            }
            Segmentation::Welch { len } | Segmentation::Periods { len } => {
                Err(Error::InvalidParameter {
                    name: crate::Parameter::SegmentLength,
                    value: len as f64,
                    expected: "8 ≤ segment (period) length ≤ record length",
                })
            }
        }
    }

    /// Start indices of the segments of a record of `record_len` samples.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::spectra::Segmentation;
    /// let starts: Vec<usize> = Segmentation::Welch { len: 8 }.starts(20).collect();
    /// assert_eq!(starts, vec![0, 4, 8, 12]);
    /// assert_eq!(Segmentation::WholeRecord.starts(20).count(), 1);
    /// let periods: Vec<usize> = Segmentation::Periods { len: 8 }.starts(20).collect();
    /// assert_eq!(periods, vec![0, 8]);
    /// ```
    pub fn starts(self, record_len: usize) -> impl Iterator<Item = usize> {
        let (len, hop) = match self {
            Segmentation::WholeRecord => (record_len, record_len.max(1)),
            Segmentation::Welch { len } => (len, (len / 2).max(1)),
            Segmentation::Periods { len } => (len, len.max(1)),
        };
        let count = if len == 0 || len > record_len {
            0
        } else {
            (record_len - len) / hop + 1
        };
        (0..count).map(move |s| s * hop)
    }
}

impl Segmentation {
    /// Short name: `"whole"`, `"welch"` or `"periods"` (the JSON output's `segmentation`).
    pub fn name(self) -> &'static str {
        match self {
            Segmentation::WholeRecord => "whole",
            Segmentation::Welch { .. } => "welch",
            Segmentation::Periods { .. } => "periods",
        }
    }
}

/// `whole`, `welch:LEN` or `periods:LEN` (samples per segment), the form
/// [`Segmentation::from_str`](std::str::FromStr::from_str) reads.
impl std::fmt::Display for Segmentation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Segmentation::WholeRecord => f.write_str("whole"),
            Segmentation::Welch { len } | Segmentation::Periods { len } => {
                write!(f, "{}:{len}", self.name())
            }
        }
    }
}

impl std::str::FromStr for Segmentation {
    type Err = Error;

    /// Parses `whole`, `welch:LEN` or `periods:LEN` (a [`Segmentation::name`], with the
    /// segment length in samples after a colon for the segmented ones), as printed by
    /// `Display`. The length is checked against a record by [`Segmentation::segment_len`].
    ///
    /// # Errors
    /// [`Error::UnknownName`] quoting the name given and listing the accepted ones.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Segmentation;
    /// assert_eq!("welch:512".parse::<Segmentation>()?, Segmentation::Welch { len: 512 });
    /// assert_eq!("whole".parse::<Segmentation>()?, Segmentation::WholeRecord);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    fn from_str(s: &str) -> Result<Self> {
        let bad = || Error::UnknownName {
            what: "segmentation",
            given: s.to_owned(),
            expected: "whole, welch:LEN or periods:LEN (samples)",
        };
        let (name, len) = match s.split_once(':') {
            Some((name, len)) => (name, Some(len.parse::<usize>().map_err(|_| bad())?)),
            None => (s, None),
        };
        match (name, len) {
            ("whole", None) => Ok(Segmentation::WholeRecord),
            ("welch", Some(len)) => Ok(Segmentation::Welch { len }),
            ("periods", Some(len)) => Ok(Segmentation::Periods { len }),
            _ => Err(bad()),
        }
    }
}

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
    weights: Vec<f64>,
    /// Window × gate weights for force channels, and the first closed sample, when gated.
    gate: Option<(ForceGate, Vec<f64>, usize)>,
    fft: Arc<dyn RealToComplex<f64>>,
    input: Vec<f64>,
    output: Vec<c64>,
    scratch: Vec<c64>,
}

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
            weights: self.weights.clone(),
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
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(len);
        let dt = 1.0 / sample_rate;
        let weights = (0..len).map(|m| window.weight(m, len, dt)).collect();
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
        for ((dst, &x), &w) in self.input.iter_mut().zip(signal).zip(&self.weights) {
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
