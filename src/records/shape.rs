//! What records of one test share, and the crate-wide checks of numbers: [`Shape`] and
//! [`common_shape`], the one rule for "the same sampling rate" ([`sample_rates_agree`]), and
//! the finite-and-positive test of rates, frequencies, durations and scales.

use super::{MIN_SAMPLES, Record};
use crate::error::{Error, Result};
use crate::tolerance::{RATE_ROUNDING, TIME_GRID_TOLERANCE};

/// Whether sampling rates `a` and `b` (Hz) of records of `len` samples are the same rate.
///
/// A time column accepted under [`TIME_GRID_TOLERANCE`] fixes its rate
/// `(N − 1)/(t_{N−1} − t_0)` to within a relative `2τ/(N − 3)` (τ = the tolerance; both end
/// times may sit up to about τ steps off the true grid); two such rates agree within
/// `4τ/(N − 3)`, plus `10⁻¹²` for rounding. So what the reader accepts, the records accept
/// too, and a rate that differs by more is a different rate.
///
/// # Examples
/// ```
/// use bearing_ident::records::sample_rates_agree;
/// assert!(sample_rates_agree(6700.0, 6700.003, 8040));
/// assert!(!sample_rates_agree(6700.0, 6701.0, 8040));
/// // Short records: their rate is known less well.
/// assert!(sample_rates_agree(100.0, 100.4, 12));
/// ```
pub fn sample_rates_agree(a: f64, b: f64, len: usize) -> bool {
    let tolerance = 4.0 * TIME_GRID_TOLERANCE / (len.max(MIN_SAMPLES) - 3) as f64 + RATE_ROUNDING;
    (a / b - 1.0).abs() <= tolerance
}

/// Whether `value` is finite and positive: the one test of sampling rates, frequencies,
/// durations and scales throughout the crate.
pub(crate) fn finite_positive(value: f64) -> bool {
    value.is_finite() && value > 0.0
}

/// [`Error::InvalidParameter`] naming `name` unless `value` is [finite and
/// positive](finite_positive).
pub(crate) fn require_finite_positive(
    name: crate::Parameter,
    value: f64,
    expected: &'static str,
) -> Result<()> {
    if finite_positive(value) {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            expected,
        })
    }
}

/// The shape every record of a test shares: degrees of freedom, sampling rate and length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shape {
    /// Degrees of freedom `n` (force and displacement channels each).
    pub dofs: usize,
    /// Sampling rate (Hz) of the first record.
    pub sample_rate: f64,
    /// Samples per channel.
    pub len: usize,
}

impl Shape {
    /// Checks `record` against this shape.
    ///
    /// # Errors
    /// [`Error::DofMismatch`], [`Error::SampleRateMismatch`] (unless
    /// [`sample_rates_agree`]) or [`Error::RecordLengthMismatch`] naming `record`.
    pub fn check(&self, record: &Record) -> Result<()> {
        check_against(record, self.dofs, self.sample_rate, self.len)
    }
}

/// The common [`Shape`] of a list of records.
///
/// # Errors
/// [`Error::NoRecords`], or [`Error::DofMismatch`], [`Error::SampleRateMismatch`] (unless
/// [`sample_rates_agree`]), [`Error::RecordLengthMismatch`] naming the first record that
/// differs from the first one (or from `dofs`, when given).
///
/// # Examples
/// ```
/// use bearing_ident::records::{Record, common_shape};
/// let r = Record::new("a", 100.0, vec![vec![0.0, 1.0, 0.0, -1.0, 0.0, 1.0, 0.0, -1.0]],
///                     vec![vec![0.0; 8]])?;
/// let shape = common_shape(&[r], None)?;
/// assert_eq!((shape.dofs, shape.len), (1, 8));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn common_shape(records: &[Record], dofs: Option<usize>) -> Result<Shape> {
    let first = records.first().ok_or(Error::NoRecords)?;
    let n = dofs.unwrap_or(first.dofs());
    for r in records {
        check_against(r, n, first.sample_rate(), first.len())?;
    }
    Ok(Shape {
        dofs: n,
        sample_rate: first.sample_rate(),
        len: first.len(),
    })
}

/// `record` against the common shape `(n, sample_rate, len)`.
pub(crate) fn check_against(record: &Record, n: usize, sample_rate: f64, len: usize) -> Result<()> {
    if record.dofs() != n {
        return Err(Error::DofMismatch {
            record: record.label().to_owned(),
            expected: n,
            actual: record.dofs(),
        });
    }
    if !sample_rates_agree(record.sample_rate(), sample_rate, len) {
        return Err(Error::SampleRateMismatch {
            record: record.label().to_owned(),
            expected: sample_rate,
            actual: record.sample_rate(),
        });
    }
    if record.len() != len {
        return Err(Error::RecordLengthMismatch {
            record: record.label().to_owned(),
            expected: len,
            actual: record.len(),
        });
    }
    Ok(())
}
