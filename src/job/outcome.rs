//! What a [`Job`](super::Job)(super::Job) found ([`Outcome`]), and a system less its dry-structure
//! baseline ([`Bearing`]).

use std::time::Duration;

use super::Timings;
use crate::excitation::{Excitation, WelchChoice};
use crate::identify::{Identification, Identifier};
use crate::model::Coefficients;

/// The system minus a dry-structure baseline ([`Options::baseline`](super::Options::baseline)).
#[derive(Debug, Clone)]
pub struct Bearing {
    /// `M`, `C`, `K` of the system less those of the baseline.
    pub coefficients: Coefficients,
    /// Their standard deviations (the variances add), when both have error bars.
    pub std_dev: Option<Coefficients>,
    /// Where the baseline came from (the path given).
    pub source: String,
}

/// What a [`Job`](super::Job) found: the identification, and the facts about the run that it does not
/// hold (the records used, the excitation and how it was decided, the Welch choice, times).
#[derive(Debug, Clone)]
pub struct Outcome {
    pub(super) identification: Identification,
    pub(super) identifier: Identifier,
    pub(super) files: Vec<String>,
    pub(super) excitation: Excitation,
    pub(super) detected: bool,
    pub(super) crest_factor: f64,
    pub(super) segment_len: Option<usize>,
    pub(super) welch_choice: Option<WelchChoice>,
    pub(super) sample_rate: f64,
    pub(super) timings: Timings,
    pub(super) bearing: Option<Bearing>,
    pub(super) conditions: crate::rotor::Conditions,
    pub(super) dimensionless: Option<crate::rotor::Dimensionless>,
    pub(super) stability: Option<crate::rotor::Stability>,
    pub(super) synchronous: Option<crate::rotor::Synchronous>,
}

impl Outcome {
    /// The identification.
    pub fn identification(&self) -> &Identification {
        &self.identification
    }

    /// The test's operating conditions ([`Options::conditions`](super::Options::conditions)).
    pub fn conditions(&self) -> &crate::rotor::Conditions {
        &self.conditions
    }

    /// The coefficients in dimensionless form (the bearing's own when a baseline was
    /// subtracted), when a clearance was given ([`crate::rotor::Dimensionless`]).
    pub fn dimensionless(&self) -> Option<&crate::rotor::Dimensionless> {
        self.dimensionless.as_ref()
    }

    /// The stability of a rigid rotor on the element (the bearing's own when a baseline was
    /// subtracted, its covariance then diagonal), when a speed or a load was given
    /// ([`crate::rotor::Stability`]).
    pub fn stability(&self) -> Option<&crate::rotor::Stability> {
        self.stability.as_ref()
    }

    /// `K(ω)`, `C(ω)` at the excitation frequency equal to the speed, when a speed was
    /// given and the lines span it ([`crate::rotor::Synchronous`]): the element model's where
    /// one other than `kcm` was fitted, else the per-line values interpolated. With a
    /// baseline subtracted, the bearing's own: less the dry structure's constant
    /// coefficients, their variances added.
    pub fn synchronous(&self) -> Option<&crate::rotor::Synchronous> {
        self.synchronous.as_ref()
    }

    /// Computes [`Outcome::dimensionless`], [`Outcome::stability`] and
    /// [`Outcome::synchronous`] from the coefficients reported and the conditions.
    ///
    /// # Errors
    /// As [`crate::rotor::Dimensionless::new`] (not for the conditions a job checked).
    pub(super) fn rotor(&mut self) -> crate::Result<()> {
        let (c, std) = self.reported();
        self.dimensionless = match self.conditions.clearance() {
            Some(_) => Some(crate::rotor::Dimensionless::new(c, std, &self.conditions)?),
            None => None,
        };
        let asked = self.conditions.speed().is_some() || self.conditions.load().is_some();
        self.stability = asked.then(|| match &self.bearing {
            Some(b) => crate::rotor::Stability::new(
                &b.coefficients,
                b.std_dev.as_ref().map(diagonal_covariance).as_ref(),
                None,
                &self.conditions,
            ),
            None => self.identification.stability(&self.conditions),
        });
        self.synchronous = self.synchronous_of()?;
        Ok(())
    }

    fn synchronous_of(&self) -> crate::Result<Option<crate::rotor::Synchronous>> {
        use crate::rotor::Synchronous;
        let Some(omega) = self.conditions.speed() else {
            return Ok(None);
        };
        let f = omega / (2.0 * std::f64::consts::PI);
        let id = &self.identification;
        let system = match id.model().filter(|m| !m.is_kcm()) {
            Some(model) => Some(Synchronous::from_model(model, f)),
            None => Synchronous::from_lines(&id.per_frequency()?, f),
        };
        let (Some(system), Some(b)) = (system.clone(), &self.bearing) else {
            return Ok(system);
        };
        let own = id.coefficients();
        let minus = |x: faer::MatRef<'_, f64>, y: faer::MatRef<'_, f64>| {
            faer::Mat::from_fn(x.nrows(), x.ncols(), |i, j| x[(i, j)] - y[(i, j)])
        };
        let variance_left = |x: faer::MatRef<'_, f64>, y: faer::MatRef<'_, f64>| {
            faer::Mat::from_fn(x.nrows(), x.ncols(), |i, j| {
                (x[(i, j)].powi(2) - y[(i, j)].powi(2)).max(0.0).sqrt()
            })
        };
        let k = minus(own.stiffness(), b.coefficients.stiffness());
        let c = minus(own.damping(), b.coefficients.damping());
        let std = match (&b.std_dev, id.std_dev()) {
            (Some(bs), Some(ss)) => Some((
                variance_left(bs.stiffness(), ss.stiffness()),
                variance_left(bs.damping(), ss.damping()),
            )),
            _ => None,
        };
        Ok(Some(system.less(
            k.as_ref(),
            c.as_ref(),
            std.as_ref().map(|(k, c)| (k.as_ref(), c.as_ref())),
        )))
    }

    /// The coefficients reported: the bearing's own when a baseline was subtracted, else
    /// the system's; with their standard deviations.
    fn reported(&self) -> (&Coefficients, Option<&Coefficients>) {
        match &self.bearing {
            Some(b) => (&b.coefficients, b.std_dev.as_ref()),
            None => (
                self.identification.coefficients(),
                self.identification.std_dev(),
            ),
        }
    }

    /// The identification, taken out.
    pub fn into_identification(self) -> Identification {
        self.identification
    }

    /// The settings the records were identified with (after the excitation's defaults and the
    /// Welch choice).
    pub fn identifier(&self) -> &Identifier {
        &self.identifier
    }

    /// The labels of the records identified, in the order given: the file paths, or
    /// `path#load-case` for a Universal File of several load cases.
    pub fn files(&self) -> &[String] {
        &self.files
    }

    /// The kind of excitation the records were identified as.
    pub fn excitation(&self) -> Excitation {
        self.excitation
    }

    /// Whether the excitation was detected from the records rather than given.
    pub fn excitation_detected(&self) -> bool {
        self.detected
    }

    /// Crest factor of the first record with a force that is not flat
    /// ([`crate::excitation::crest_factor`]).
    pub fn crest_factor(&self) -> f64 {
        self.crest_factor
    }

    /// Samples per Welch segment or period, if the records were cut.
    pub fn segment_len(&self) -> Option<usize> {
        self.segment_len
    }

    /// How the Welch segment length was chosen from the data, if it was.
    pub fn welch_choice(&self) -> Option<&WelchChoice> {
        self.welch_choice.as_ref()
    }

    /// Sampling rate of the records (Hz).
    pub fn sample_rate(&self) -> f64 {
        self.sample_rate
    }

    /// Wall time spent waiting for files (zero for records in memory).
    pub fn read_time(&self) -> Duration {
        self.timings.read
    }

    /// Wall time of the rest: detection, settings, Welch choice, identification, baseline.
    pub fn compute_time(&self) -> Duration {
        self.timings.compute
    }

    /// Wall time per stage of the run ([`Timings`]).
    pub fn timings(&self) -> Timings {
        self.timings
    }

    /// The system minus the baseline, when one was given.
    pub fn bearing(&self) -> Option<&Bearing> {
        self.bearing.as_ref()
    }
}

/// A diagonal covariance of the stacked coefficients (in the order of
/// [`Identification::covariance`]) with the variances `std²`.
fn diagonal_covariance(std: &Coefficients) -> faer::Mat<f64> {
    let s = std.stacked();
    let rows = s.nrows();
    let p = rows * s.ncols();
    faer::Mat::from_fn(p, p, |a, b| {
        if a == b {
            s[(a % rows, a / rows)].powi(2)
        } else {
            0.0
        }
    })
}
