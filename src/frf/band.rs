//! [`Band`]: the frequency band of an identification and the DFT lines inside it.

use crate::error::{Error, Result};
use crate::tolerance::BAND_EDGE_SLACK;

/// A frequency band in Hz, edges inclusive. DC is never used.
///
/// # Examples
/// ```
/// use bearing_ident::frf::Band;
/// let band = Band::new(8.0, 49.0)?;
/// // 6700 samples/s × 1.2 s: lines every 0.8333 Hz; 8.33 … 48.33 Hz.
/// let lines = band.lines(6700.0, 8040)?;
/// assert_eq!(lines.len(), 49);
/// assert_eq!(lines[0], 10);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    low_hz: f64,
    high_hz: f64,
}

impl Band {
    /// A band from `low_hz` to `high_hz`, both included.
    ///
    /// # Errors
    /// [`Error::InvalidBand`] unless `0 ≤ low_hz < high_hz` and both are finite.
    pub fn new(low_hz: f64, high_hz: f64) -> Result<Self> {
        if low_hz.is_finite() && high_hz.is_finite() && low_hz >= 0.0 && low_hz < high_hz {
            Ok(Self { low_hz, high_hz })
        } else {
            Err(Error::InvalidBand { low_hz, high_hz })
        }
    }

    /// Lower edge (Hz).
    pub fn low_hz(&self) -> f64 {
        self.low_hz
    }

    /// Upper edge (Hz).
    pub fn high_hz(&self) -> f64 {
        self.high_hz
    }

    /// Indices of the DFT lines in the band for segments of `segment_len` samples at
    /// `sample_rate` Hz. A line within [`BAND_EDGE_SLACK`] (`10⁻⁶`) of the spacing of an edge counts as
    /// inside; DC
    /// (line 0) is excluded.
    ///
    /// # Errors
    /// [`Error::BandAboveNyquist`] if the upper edge exceeds `sample_rate / 2`.
    pub fn lines(&self, sample_rate: f64, segment_len: usize) -> Result<Vec<usize>> {
        let df = sample_rate / segment_len as f64;
        let nyquist_hz = sample_rate / 2.0;
        let slack = BAND_EDGE_SLACK * df;
        if self.high_hz > nyquist_hz + slack {
            return Err(Error::BandAboveNyquist {
                high_hz: self.high_hz,
                nyquist_hz,
            });
        }
        let first = (((self.low_hz - slack) / df).ceil() as usize).max(1);
        let last = ((self.high_hz + slack) / df).floor() as usize;
        Ok((first..=last.min(segment_len / 2)).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_edges_are_inclusive_and_dc_excluded() {
        let band = Band::new(0.0, 4.0).unwrap();
        assert_eq!(band.lines(16.0, 16).unwrap(), vec![1, 2, 3, 4]);
        let band = Band::new(2.0 - 1e-9, 3.0 + 1e-9).unwrap();
        assert_eq!(band.lines(16.0, 16).unwrap(), vec![2, 3]);
    }

    #[test]
    fn invalid_band_is_refused() {
        assert!(matches!(
            Band::new(5.0, 5.0),
            Err(Error::InvalidBand { .. })
        ));
        assert!(matches!(
            Band::new(-1.0, 5.0),
            Err(Error::InvalidBand { .. })
        ));
        assert!(matches!(
            Band::new(1.0, f64::NAN),
            Err(Error::InvalidBand { .. })
        ));
    }

    #[test]
    fn band_above_nyquist_is_refused() {
        let e = Band::new(1.0, 40.0).unwrap().lines(64.0, 64).unwrap_err();
        assert_eq!(
            e,
            Error::BandAboveNyquist {
                high_hz: 40.0,
                nyquist_hz: 32.0
            }
        );
    }
}
