//! Wall time per stage of a [`Job`](super::Job)'s run ([`Timings`]): reading, detection, the
//! Welch choice, the identification's own stages and the baseline.

use std::time::Duration;

use crate::identify;

/// Wall time spent in each stage of a [`Job`](super::Job)'s run
/// ([`Outcome::timings`](super::Outcome::timings)), in the order the run goes through them:
///
/// | stage | what it covers |
/// |---|---|
/// | `read` | waiting for record files to be read and parsed (zero for records in memory) |
/// | `detect` | the kind of excitation from the records (the crest factor, tone, sweep and period of a force) and the settings it implies (a periodic force's period) |
/// | `welch_choice` | the Welch length chosen from a first fit (random records without a length given): its spectra, unless the choice keeps them for the identification, and the fit and predictions |
/// | the identification's ([`identify::Timings`]) | `screen`, `spectra`, `noise`, `frf`, `conditioning`, `solve`, `model_check`, `uncertainty`, `bias` |
/// | `baseline` | a dry-structure baseline read, identified and subtracted |
///
/// `compute` is the wall time of the run less `read`, and `total` their sum; the stages add up
/// to `total` but for the bookkeeping between them.
///
/// # Examples
/// ```
/// use bearing_ident::job::{Channels, Job, Options};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let outcome = Job::new(Options::new(8.0, 49.0), Channels::default()).run_records(records)?;
/// let t = outcome.timings();
/// let names: Vec<&str> = t.stages().iter().map(|(n, _)| *n).collect();
/// assert_eq!(&names[..3], ["read", "detect", "welch_choice"]);
/// assert_eq!(names.len(), 13);
/// assert!(t.stages().iter().map(|(_, d)| *d).sum::<std::time::Duration>() <= t.total());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, Default)]
#[non_exhaustive]
pub struct Timings {
    /// Waiting for the record files.
    pub read: Duration,
    /// Detection of the kind of excitation, and its settings.
    pub detect: Duration,
    /// The Welch length chosen from a first fit.
    pub welch_choice: Duration,
    /// The identification's stages.
    pub identification: identify::Timings,
    /// The baseline.
    pub baseline: Duration,
    /// Everything but `read`.
    pub compute: Duration,
}

impl Timings {
    /// The identification's `timings`, `read` and `compute` of a run that had no other stage.
    ///
    /// # Examples
    /// ```
    /// use std::time::Duration;
    /// use bearing_ident::identify::Timings as Stages;
    /// use bearing_ident::job::Timings;
    /// let t = Timings::new(Stages::default(), Duration::from_millis(3), Duration::from_millis(5));
    /// assert_eq!(t.total(), Duration::from_millis(8));
    /// ```
    pub fn new(identification: identify::Timings, read: Duration, compute: Duration) -> Self {
        Self {
            read,
            identification,
            compute,
            ..Self::default()
        }
    }

    /// The stages by name, in the order of the run, without the total: `read`, `detect`,
    /// `welch_choice`, the identification's ([`identify::Timings::stages`]), `baseline`.
    pub fn stages(&self) -> Vec<(&'static str, Duration)> {
        let mut stages = vec![
            ("read", self.read),
            ("detect", self.detect),
            ("welch_choice", self.welch_choice),
        ];
        stages.extend(self.identification.stages());
        stages.push(("baseline", self.baseline));
        stages
    }

    /// `read` plus `compute`: the whole run.
    pub fn total(&self) -> Duration {
        self.read + self.compute
    }
}
