//! [`Window`]: the weights applied to each segment before the DFT, one arm per window.

use crate::error::{Error, Result};
use crate::tolerance::BASELINE_DECAY;

#[cfg(doc)]
use super::SpectralEstimator;

/// Window applied to each segment before the DFT.
///
/// The enum is `#[non_exhaustive]`: more windows will come (the force gate is not one: it
/// multiplies the force channel only, [`ForceGate`](super::ForceGate)).
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

    /// Short name of the kind: `"rect"`, `"hann"` or `"exp"` (the string form without its
    /// parameter).
    pub fn name(self) -> &'static str {
        match self {
            Window::Rectangular => "rect",
            Window::Hann => "hann",
            Window::Exponential { .. } => "exp",
        }
    }

    /// The window in words, for reports: `"rectangular"`, `"Hann"` or
    /// `"exponential, a = 3.84 1/s"` (three significant digits).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Window;
    /// assert_eq!(Window::exponential(3.8376)?.describe(), "exponential, a = 3.84 1/s");
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn describe(self) -> String {
        match self {
            Window::Rectangular => "rectangular".to_owned(),
            Window::Hann => "Hann".to_owned(),
            Window::Exponential { decay_per_s } => {
                format!(
                    "exponential, a = {} 1/s",
                    crate::text::significant(decay_per_s, 3)
                )
            }
        }
    }

    /// Whether `other` is this window up to the rounding of a decay read back from text:
    /// the same kind, and decays within a relative [`BASELINE_DECAY`] (a baseline's window is
    /// checked so).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Window;
    /// let a = Window::exponential(2.5)?;
    /// assert!(a.matches(Window::exponential(2.5 * (1.0 + 1e-12))?));
    /// assert!(!a.matches(Window::exponential(2.6)?) && !a.matches(Window::Hann));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn matches(self, other: Window) -> bool {
        match (self.decay_per_s(), other.decay_per_s()) {
            (Some(a), Some(b)) => (a - b).abs() <= BASELINE_DECAY * a.abs().max(1e-12),
            _ => self == other,
        }
    }

    /// Whether the segment mean is removed before windowing.
    pub(super) fn removes_mean(self) -> bool {
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

impl std::fmt::Display for Window {
    /// The string form: `rect`, `hann` or `exp:A/s` with the decay `A` in 1/s at full
    /// precision (so that [`FromStr`](std::str::FromStr) reads the same window back).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Window::Exponential { decay_per_s } => write!(f, "exp:{decay_per_s}/s"),
            w => f.write_str(w.name()),
        }
    }
}

impl std::str::FromStr for Window {
    type Err = Error;

    /// Reads the string form `rect`, `hann` or `exp:A/s` (a decay `A ≥ 0` in 1/s); names
    /// under the one spelling rule of [`Choice`](crate::Choice).
    ///
    /// # Errors
    /// [`Error::UnknownName`] for any other text, [`Error::InvalidParameter`] for a decay that
    /// is negative or not finite.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Window;
    /// let w: Window = "exp:3.8376/s".parse()?;
    /// assert_eq!(w.decay_per_s(), Some(3.8376));
    /// assert_eq!(w.to_string(), "exp:3.8376/s");
    /// assert_eq!("HANN".parse::<Window>()?, Window::Hann);
    /// assert!("exp:0.01".parse::<Window>().is_err()); // a decay needs its unit
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    fn from_str(s: &str) -> Result<Window> {
        let bad = || Error::UnknownName {
            what: "window",
            given: s.to_owned(),
            expected: "rect, hann or exp:A/s (a decay in 1/s)".into(),
        };
        let (name, parameter) = match s.split_once(':') {
            Some((name, parameter)) => (name, Some(parameter.trim())),
            None => (s, None),
        };
        let named = |n: &str| crate::choice::same_name(n, name);
        match parameter {
            None if named("rect") => Ok(Window::Rectangular),
            None if named("hann") => Ok(Window::Hann),
            Some(decay) if named("exp") => {
                let decay: f64 = decay
                    .strip_suffix("/s")
                    .and_then(|a| a.trim().parse().ok())
                    .ok_or_else(bad)?;
                Window::exponential(decay)
            }
            _ => Err(bad()),
        }
    }
}
