//! [`ForceGate`]: the force channel kept for a while after the segment's start, then tapered to
//! zero, so the quiet force after an impact adds no noise.

use crate::error::{Error, Result};
use crate::records::require_finite_positive;

#[cfg(doc)]
use super::Window;

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
    pub(super) fn closed_from(self, dt: f64) -> usize {
        // `as` saturates: a gate longer than any record stays open over all of it.
        (((self.open_s + self.taper_s) / dt).floor() as usize).saturating_add(1)
    }
}
