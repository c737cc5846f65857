//! A dry-structure baseline ([`Baseline`]) and its subtraction from a lubricated system's
//! identification ([`Identification::subtract_baseline`]).

use crate::error::BaselineField;
use crate::error::{Error, Result};
use crate::frf::{Band, Estimator};
use crate::model::Coefficients;
use crate::spectra::Window;
use crate::tolerance;

use super::Identification;

/// What a baseline subtraction needs of a dry-structure identification: its coefficients,
/// standard deviations and the processing that produced them (to check they match). Made
/// from an [`Identification`] (`From`) or, for a result saved earlier, with
/// [`Baseline::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct Baseline {
    coefficients: Coefficients,
    std_dev: Option<Coefficients>,
    band: Band,
    freqs_hz: Vec<f64>,
    estimator: Estimator,
    window: Window,
}

impl Baseline {
    /// A baseline from its parts (read back from a saved result, say).
    pub fn new(
        coefficients: Coefficients,
        std_dev: Option<Coefficients>,
        band: Band,
        freqs_hz: Vec<f64>,
        estimator: Estimator,
        window: Window,
    ) -> Self {
        Self {
            coefficients,
            std_dev,
            band,
            freqs_hz,
            estimator,
            window,
        }
    }

    /// The dry structure's coefficients.
    pub fn coefficients(&self) -> &Coefficients {
        &self.coefficients
    }
}

impl From<&Identification> for Baseline {
    fn from(id: &Identification) -> Self {
        Baseline::new(
            id.coefficients().clone(),
            id.std_dev().cloned(),
            id.band,
            id.freqs_hz().to_vec(),
            id.estimator,
            id.window,
        )
    }
}

impl Identification {
    /// The bearing's own coefficients: this (lubricated) system minus a dry-structure
    /// `baseline` identified the same way, `K_b = K_s − K_h`, `C_b = C_s − C_h`,
    /// `M_b = M_s − M_h`; standard deviations add in quadrature (independent tests), `None`
    /// unless both carry them.
    ///
    /// `baseline` is an [`Identification`] (`&dry`) or a [`Baseline`] read back from a saved
    /// result.
    ///
    /// # Errors
    /// [`Error::BaselineMismatch`] if the two differ in degrees of freedom (the baseline's
    /// standard deviations included), band, lines used, estimator or window (an exponential
    /// window must have the same decay); [`Error::NonFiniteCoefficient`] if a difference
    /// overflows.
    pub fn subtract_baseline(
        &self,
        baseline: impl Into<Baseline>,
    ) -> Result<(Coefficients, Option<Coefficients>)> {
        let baseline: Baseline = baseline.into();
        let mismatch = |what| Err(Error::BaselineMismatch { what });
        let std_dofs = baseline.std_dev.as_ref().map(Coefficients::dofs);
        if self.coefficients().dofs() != baseline.coefficients.dofs()
            || std_dofs.is_some_and(|n| n != baseline.coefficients.dofs())
        {
            return mismatch(BaselineField::DegreesOfFreedom);
        }
        if self.band != baseline.band {
            return mismatch(BaselineField::Band);
        }
        let same_lines = self.freqs_hz().len() == baseline.freqs_hz.len()
            && self
                .freqs_hz()
                .iter()
                .zip(&baseline.freqs_hz)
                .all(|(a, b)| (a - b).abs() <= tolerance::BASELINE_LINE * a.abs().max(1.0));
        if !same_lines {
            return mismatch(BaselineField::FrequencyLines);
        }
        if self.estimator != baseline.estimator {
            return mismatch(BaselineField::Estimator);
        }
        if !self.window.matches(baseline.window) {
            return mismatch(BaselineField::Window);
        }
        let coefficients = self.coefficients().subtract(&baseline.coefficients)?;
        let std = match (self.std_dev(), baseline.std_dev.as_ref()) {
            (Some(a), Some(b)) => {
                let add = |x: faer::MatRef<'_, f64>, y: faer::MatRef<'_, f64>| {
                    faer::Mat::from_fn(x.nrows(), x.ncols(), |i, j| x[(i, j)].hypot(y[(i, j)]))
                };
                Some(Coefficients::new(
                    add(a.mass(), b.mass()),
                    add(a.damping(), b.damping()),
                    add(a.stiffness(), b.stiffness()),
                )?)
            }
            _ => None,
        };
        Ok((coefficients, std))
    }
}
