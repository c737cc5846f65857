//! Wall time per stage of an identification, [`Timings`], measured with
//! [`std::time::Instant`] around each stage (a handful of clock reads per run, none inside a
//! per-line or per-sample loop).

use std::time::{Duration, Instant};

/// Wall time spent in each stage of one identification
/// ([`Identification::timings`](crate::Identification::timings)).
///
/// The stages, in the order data flows through them:
///
/// | field | what it covers |
/// |---|---|
/// | `screen` | record screening: flat channels, clipping, double hits, duplicates, outliers, the per-line test of paired sets |
/// | `spectra` | windows, gates and FFTs of the records, folded into band-line spectra or cross-spectra |
/// | `noise` | the noise the periods or segments show, for H1's compensation ([`NoiseFloor`](crate::frf::NoiseFloor)) |
/// | `frf` | impedance and flexibility per line (inversions, per-line products, coherence, and the per-line condition numbers the estimators compute as they go), coherence selection |
/// | `conditioning` | the verdict on the per-line condition numbers ([`Conditioning`](crate::conditioning::Conditioning)) |
/// | `solve` | the fit, the window correction and the diagnostics of the fit |
/// | `model_check` | the model check ([`ModelCheck`](crate::identify::ModelCheck)) |
/// | `uncertainty` | the error bars (sandwich, or every jackknife / bootstrap refit, the band refits of the budget) |
/// | `bias` | the processing bias predicted from the fit (leakage, truncation) and the refit that judges the noise compensation (or the H1/H2 bracket) |
/// | `total` | everything from the call to the result |
///
/// `total` is at least the sum of the others (the rest is bookkeeping between stages). Records
/// that arrive through an iterator ([`Identifier::identify_stream`](crate::Identifier::identify_stream))
/// are read while the clock runs: their reading counts in `total` but in no stage. A ready-made
/// FRF ([`Identifier::identify_frf`](crate::Identifier::identify_frf)) has zero `screen` and
/// `spectra`.
///
/// Timings are not part of a result's value: two [`Identification`](crate::Identification)s
/// that differ only in them compare equal.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let t = Identifier::new(8.0, 49.0).identify(&records)?.timings();
/// assert!(t.total >= t.stages().iter().map(|(_, d)| *d).sum());
/// assert_eq!(t.stages().len(), 9);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, Default)]
#[non_exhaustive]
pub struct Timings {
    /// Record screening.
    pub screen: Duration,
    /// Spectra of the records (FFTs).
    pub spectra: Duration,
    /// The noise the records show, for H1's compensation.
    pub noise: Duration,
    /// Impedance and flexibility per line.
    pub frf: Duration,
    /// The conditioning verdict.
    pub conditioning: Duration,
    /// The fit and its diagnostics.
    pub solve: Duration,
    /// The model check.
    pub model_check: Duration,
    /// The error bars.
    pub uncertainty: Duration,
    /// The predicted processing bias and the noise compensation's refit.
    pub bias: Duration,
    /// From the call to the result.
    pub total: Duration,
}

impl Timings {
    /// The stages by name, in pipeline order, without the total.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::identify::Timings;
    /// let names: Vec<&str> = Timings::default().stages().iter().map(|(n, _)| *n).collect();
    /// assert_eq!(
    ///     names,
    ///     ["screen", "spectra", "noise", "frf", "conditioning", "solve", "model_check",
    ///      "uncertainty", "bias"]
    /// );
    /// ```
    pub fn stages(&self) -> [(&'static str, Duration); 9] {
        [
            ("screen", self.screen),
            ("spectra", self.spectra),
            ("noise", self.noise),
            ("frf", self.frf),
            ("conditioning", self.conditioning),
            ("solve", self.solve),
            ("model_check", self.model_check),
            ("uncertainty", self.uncertainty),
            ("bias", self.bias),
        ]
    }
}

/// `f()`, its wall time added to `slot`.
pub(super) fn timed<T>(slot: &mut Duration, f: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = f();
    *slot += start.elapsed();
    out
}

/// [`Timings`] held by an [`Identification`](crate::Identification) without taking part in
/// its equality.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Untimed(pub(super) Timings);

impl PartialEq for Untimed {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timed_adds_up() {
        let mut slot = Duration::from_millis(2);
        let v = timed(&mut slot, || 7);
        assert_eq!(v, 7);
        assert!(slot >= Duration::from_millis(2));
    }

    #[test]
    fn timings_never_make_results_differ() {
        let a = Untimed(Timings {
            total: Duration::from_secs(1),
            ..Timings::default()
        });
        assert_eq!(a, Untimed::default());
    }
}
