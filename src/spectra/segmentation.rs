//! [`Segmentation`]: how records are cut into segments (the whole record, Welch segments,
//! whole periods) before their spectra are taken.

use crate::error::{Error, Result};

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
            expected: "whole, welch:LEN or periods:LEN (samples)".into(),
        };
        let (name, len) = match s.split_once(':') {
            Some((name, len)) => (name, Some(len.parse::<usize>().map_err(|_| bad())?)),
            None => (s, None),
        };
        let named = |n: &str| crate::choice::same_name(n, name);
        match len {
            None if named("whole") => Ok(Segmentation::WholeRecord),
            Some(len) if named("welch") => Ok(Segmentation::Welch { len }),
            Some(len) if named("periods") => Ok(Segmentation::Periods { len }),
            _ => Err(bad()),
        }
    }
}
