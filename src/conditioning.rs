//! Stage 4: is the excitation good enough to identify from?
//!
//! The seed calls the conditioning of the displacement matrix `[X¹…Xⁿ]` the "MOST important"
//! check: nearly dependent excitations (impacts all in one direction, circular orbits on a
//! nearly isotropic element) give impedances that look plausible and are wrong. This stage
//! reads the per-line condition numbers of an [`Frf`], warns above one threshold, and refuses
//! with [`Error::RankDeficient`] when every line of the band is beyond a second one.

use crate::error::{Error, Result, Warning};
use crate::frf::Frf;

/// `true` if `value` is above `limit` or not a number (an undefined condition is not good).
fn exceeds(value: f64, limit: f64) -> bool {
    !matches!(
        value.partial_cmp(&limit),
        Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
    )
}

/// Thresholds on the per-line condition number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConditionLimits {
    /// Warn when a line's condition number exceeds this. Default `1e3`.
    pub warn: f64,
    /// Refuse the identification when every line exceeds this. Default `1e8`.
    pub refuse: f64,
}

impl ConditionLimits {
    /// Checks the limits: $1 \le \text{warn} \le \text{refuse}$ (a condition number is at
    /// least 1, and refusing below the warning would refuse without warning).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `condition limits` (with the warning limit as its
    /// value) otherwise, NaN included.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::ConditionLimits;
    /// assert!(ConditionLimits::default().check().is_ok());
    /// assert!(ConditionLimits { warn: 1e6, refuse: 1e3 }.check().is_err());
    /// assert!(ConditionLimits { warn: f64::NAN, refuse: 1e3 }.check().is_err());
    /// ```
    pub fn check(&self) -> Result<()> {
        if self.warn >= 1.0 && self.refuse >= self.warn {
            Ok(())
        } else {
            Err(Error::InvalidParameter {
                name: crate::Parameter::ConditionLimits,
                value: self.warn,
                expected: "1 ≤ warn ≤ refuse",
            })
        }
    }
}

impl Default for ConditionLimits {
    fn default() -> Self {
        Self {
            warn: 1e3,
            refuse: 1e8,
        }
    }
}

/// The verdict on an [`Frf`]'s conditioning.
///
/// # Examples
/// ```
/// use bearing_ident::conditioning::{Conditioning, ConditionLimits};
/// use bearing_ident::frf::Frf;
/// use faer::{Mat, c64};
/// let g: Vec<Mat<c64>> = (0..3)
///     .map(|k| Mat::from_fn(2, 2, |i, j| c64::new(if i == j { 1.0 + k as f64 } else { 0.0 }, 0.0)))
///     .collect();
/// let frf = Frf::from_flexibility(vec![1.0, 2.0, 3.0], &g)?;
/// let c = Conditioning::assess(&frf, ConditionLimits::default())?;
/// assert_eq!(c.worst(), 1.0);
/// assert!(c.warning().is_none());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Conditioning {
    limits: ConditionLimits,
    lines: usize,
    above_warn: usize,
    worst: f64,
    worst_hz: f64,
    median: f64,
    best: f64,
}

impl Conditioning {
    /// Judges the condition numbers of `frf`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for limits that fail [`ConditionLimits::check`];
    /// [`Error::TooFewLines`] if `frf` holds no line at all; [`Error::RankDeficient`] if every
    /// line was dropped as singular or every line's condition number exceeds `limits.refuse`.
    pub fn assess(frf: &Frf, limits: ConditionLimits) -> Result<Self> {
        limits.check()?;
        let cond = frf.condition_numbers();
        let n = frf.dofs();
        if cond.is_empty() && frf.dropped_hz().is_empty() {
            return Err(Error::TooFewLines {
                lines: 0,
                required: 1,
                resolution_hz: frf.line_spacing_hz(),
            });
        }
        if cond.is_empty() || cond.iter().all(|&c| exceeds(c, limits.refuse)) {
            return Err(Error::RankDeficient {
                rank: n.saturating_sub(1),
                dofs: n,
            });
        }
        let mut sorted = cond.to_vec();
        sorted.sort_by(f64::total_cmp);
        let (worst_line, &worst) = cond
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .expect("non-empty");
        Ok(Self {
            limits,
            lines: cond.len(),
            above_warn: cond.iter().filter(|&&c| exceeds(c, limits.warn)).count(),
            worst,
            worst_hz: frf.freqs_hz()[worst_line],
            median: sorted[sorted.len() / 2],
            best: sorted[0],
        })
    }

    /// The thresholds the lines were judged against.
    pub fn limits(&self) -> ConditionLimits {
        self.limits
    }

    /// Largest condition number over the band.
    pub fn worst(&self) -> f64 {
        self.worst
    }

    /// Median condition number over the band.
    pub fn median(&self) -> f64 {
        self.median
    }

    /// Smallest condition number over the band.
    pub fn best(&self) -> f64 {
        self.best
    }

    /// Number of lines above the warning threshold.
    pub fn lines_above_warning(&self) -> usize {
        self.above_warn
    }

    /// A warning if any line is above the warning threshold.
    pub fn warning(&self) -> Option<Warning> {
        (self.above_warn > 0).then_some(Warning::IllConditioned {
            lines: self.above_warn,
            of: self.lines,
            worst_hz: self.worst_hz,
            worst: self.worst,
            threshold: self.limits.warn,
        })
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are copied through, not computed
mod tests {
    use super::*;
    use faer::{Mat, c64};

    fn frf_with_conditions(conds: &[f64]) -> Frf {
        let g: Vec<Mat<c64>> = conds
            .iter()
            .map(|&c| {
                Mat::from_fn(2, 2, |i, j| {
                    c64::new(
                        if i != j {
                            0.0
                        } else if i == 0 {
                            c
                        } else {
                            1.0
                        },
                        0.0,
                    )
                })
            })
            .collect();
        Frf::from_flexibility((1..=conds.len()).map(|k| k as f64).collect(), &g).unwrap()
    }

    #[test]
    fn warns_above_threshold() {
        let c = Conditioning::assess(
            &frf_with_conditions(&[2.0, 5e3, 3.0]),
            ConditionLimits::default(),
        )
        .unwrap();
        assert_eq!(c.lines_above_warning(), 1);
        assert_eq!(c.median(), 3.0);
        assert_eq!(c.best(), 2.0);
        match c.warning() {
            Some(Warning::IllConditioned {
                worst_hz,
                lines: 1,
                of: 3,
                ..
            }) => assert_eq!(worst_hz, 2.0),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn refuses_when_every_line_is_beyond_the_limit() {
        let e = Conditioning::assess(
            &frf_with_conditions(&[1e9, 1e10]),
            ConditionLimits::default(),
        )
        .unwrap_err();
        assert_eq!(e, Error::RankDeficient { rank: 1, dofs: 2 });
    }
}
