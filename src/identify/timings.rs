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
/// | `frf` | impedance and flexibility per line (inversions, per-line products, coherence, and the per-line condition numbers the estimators compute as they go), coherence selection |
/// | `conditioning` | the verdict on the per-line condition numbers ([`Conditioning`](crate::conditioning::Conditioning)) |
/// | `solve` | the fit, the window correction and the diagnostics of the fit |
/// | `uncertainty` | the error bars (sandwich, or every jackknife / bootstrap refit) |
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
/// assert_eq!(t.stages().len(), 6);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, Default)]
#[non_exhaustive]
pub struct Timings {
    /// Record screening.
    pub screen: Duration,
    /// Spectra of the records (FFTs).
    pub spectra: Duration,
    /// Impedance and flexibility per line.
    pub frf: Duration,
    /// The conditioning verdict.
    pub conditioning: Duration,
    /// The fit and its diagnostics.
    pub solve: Duration,
    /// The error bars.
    pub uncertainty: Duration,
    /// From the call to the result.
    pub total: Duration,
}

impl Timings {
    /// The stages by name (`"screen"`, `"spectra"`, `"frf"`, `"conditioning"`, `"solve"`,
    /// `"uncertainty"`), in pipeline order, without the total.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::identify::Timings;
    /// let names: Vec<&str> = Timings::default().stages().iter().map(|(n, _)| *n).collect();
    /// assert_eq!(names, ["screen", "spectra", "frf", "conditioning", "solve", "uncertainty"]);
    /// ```
    pub fn stages(&self) -> [(&'static str, Duration); 6] {
        [
            ("screen", self.screen),
            ("spectra", self.spectra),
            ("frf", self.frf),
            ("conditioning", self.conditioning),
            ("solve", self.solve),
            ("uncertainty", self.uncertainty),
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
