//! MIMO H1: $G_1 = S_{xf} S_{ff}^{-1}$, $H = G_1^{-1}$; unbiased under displacement noise.

use super::cross::{LineEstimator, LineSums, LineWork};
use super::{Assignment, Band, Estimator, Frf, FrfBuilder};
use crate::error::Result;
use crate::linalg;
use crate::records::{Record, common_shape};
use crate::spectra::{Segmentation, Window};

/// The H1 line estimate ([`Estimator::H1`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct H1;

impl LineEstimator for H1 {
    fn estimate(&self, s: &LineSums<'_>, work: &mut LineWork) -> bool {
        linalg::mul_into(s.sxf, s.sff_inv, &mut work.g, s.n);
        work.h.copy_from_slice(&work.g);
        work.inverter.invert(&mut work.h)
    }
}

/// Impedance by the MIMO H1 estimator over all records and segments:
/// $G = S_{xf} S_{ff}^{-1}$, $H = G^{-1}$.
///
/// # Errors
/// Shape errors from [`common_shape`]; [`Error::InvalidParameter`](crate::Error::InvalidParameter) for a bad Welch segment
/// length; [`Error::BandAboveNyquist`](crate::Error::BandAboveNyquist).
pub fn h1(
    records: &[Record],
    band: Band,
    segmentation: Segmentation,
    window: Window,
) -> Result<Frf> {
    common_shape(records, None)?;
    let mut b = FrfBuilder::new(Estimator::H1, band, segmentation, window);
    b.push_all(records)?;
    b.finish(&Assignment::DominantForce)
}
