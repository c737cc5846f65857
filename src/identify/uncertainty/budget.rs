//! The uncertainty budget of the coefficients ([`Budget`]): the random error the chosen
//! [`Uncertainty`] estimates, what the model misses, and the stated calibration, combined
//! into the standard deviations an [`Identification`](crate::Identification) reports.
//!
//! # Components
//! - **random**: the sandwich, Fisher, jackknife or bootstrap standard deviation `σ_r`.
//! - **model**: two parts in quadrature. The Birge part widens `σ_r` by the model check's
//!   ratio `F = χ²/expected` ([`ModelCheck`]): $\sigma_r\sqrt{\max(1, F) - 1}$, so that
//!   random and Birge parts together are $\sigma_r\sqrt{\max(1, F)}$ — residuals `√F` times
//!   the noise's size mean errors `√F` times the noise-only bars. The band part is the
//!   spread of refits with the band's edges moved inward by [`BAND_SHIFT_LINES`] lines (low
//!   edge, high edge, both): $\sigma_b^2 = \frac13\sum_r (\theta_r - \hat\theta)^2$. A fit
//!   that leans on lines the model does not describe moves when they go; a right model's
//!   moves by its random error alone, so the band part is carried only when the model
//!   check does not say the model fits (misfit, or untested for want of replicates).
//!   Maximum likelihood refits by IVF and takes the change of IVF's estimate. A bias the
//!   processing is predicted to add ([`PredictedBias`](crate::gate::PredictedBias): the
//!   leakage of Welch segments, the truncation of records that have not decayed) enters in
//!   quadrature too when it passes half a random standard deviation (the threshold of its
//!   warning, `leakage_bias` or `not_decayed`).
//! - **calibration**: the stated gain uncertainties ([`Calibration::std_dev`]).
//!
//! The combined standard uncertainty is
//! $\sigma = \sqrt{\sigma_r^2 + \sigma_m^2 + \sigma_c^2}$ (GUM: independent components add in
//! quadrature); the 95 % half-widths are the interval factor (1.96, or Student's t of the
//! resampling) times `σ`.

use faer::Mat;

use crate::error::Result;
use crate::frf::Frf;
use crate::model::Coefficients;
use crate::solve::{self, Method};
use crate::tolerance::BAND_SHIFT_LINES;

use super::super::model_check::Verdict;
use super::super::{Calibration, ModelCheck, Settings};
#[cfg(doc)]
use super::Uncertainty;

/// The components of the standard uncertainty of every coefficient (see the module docs).
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::identify::Calibration;
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 4, noise: 0.05, ..ImpactTest::seed_rig() }
///     .run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0)
///     .calibration(Calibration::default().force(0.02))
///     .identify(&records)?;
/// let b = id.budget().unwrap();
/// // 2 % of K_xx ≈ 146 kN/m from the calibration alone.
/// assert!((b.calibration.stiffness()[(0, 0)] / id.coefficients().stiffness()[(0, 0)] - 0.02).abs() < 1e-12);
/// let combined = id.std_dev().unwrap().stiffness()[(0, 0)];
/// let parts = [&b.random, &b.model, &b.calibration].map(|c| c.stiffness()[(0, 0)].powi(2));
/// assert!((combined - parts.iter().sum::<f64>().sqrt()).abs() < 1e-9 * combined);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Budget {
    /// The random component, as the chosen uncertainty estimates it.
    pub random: Coefficients,
    /// What the model misses: the Birge widening and the band sensitivity in quadrature.
    pub model: Coefficients,
    /// The stated calibration uncertainty.
    pub calibration: Coefficients,
}

impl Budget {
    /// The combined standard uncertainty, the three components in quadrature.
    ///
    /// # Errors
    /// None in practice (the components share one shape).
    pub fn combined(&self) -> Result<Coefficients> {
        quadrature(&[&self.random, &self.model, &self.calibration])
    }

    /// Random and model components in quadrature (what moves natural frequencies and damping
    /// ratios: a common calibration gain scales `M`, `C`, `K` alike and moves neither).
    ///
    /// # Errors
    /// None in practice (the components share one shape).
    pub fn random_and_model(&self) -> Result<Coefficients> {
        quadrature(&[&self.random, &self.model])
    }

    /// Adds a predicted bias (absolute, per coefficient) to the model component in
    /// quadrature: $\sigma_m \leftarrow \sqrt{\sigma_m^2 + b^2}$.
    ///
    /// # Errors
    /// None in practice (one shape).
    pub(in crate::identify) fn carry_bias(&mut self, bias: &Coefficients) -> Result<()> {
        self.model = quadrature(&[&self.model, bias])?;
        Ok(())
    }
}

fn quadrature(parts: &[&Coefficients]) -> Result<Coefficients> {
    let stacked: Vec<Mat<f64>> = parts.iter().map(|c| c.stacked()).collect();
    let (p, n) = (stacked[0].nrows(), stacked[0].ncols());
    let s = Mat::from_fn(p, n, |i, j| {
        stacked
            .iter()
            .map(|m| m[(i, j)].powi(2))
            .sum::<f64>()
            .sqrt()
    });
    Coefficients::from_stacked(s.as_ref())
}

impl Settings {
    /// The budget of `fitted` (window-corrected) with random part `random`, from the model
    /// check, the band refits on `frf` and the stated calibration.
    ///
    /// # Errors
    /// The calibration's channel check.
    pub(in crate::identify) fn budget(
        &self,
        fitted: &Coefficients,
        random: &Coefficients,
        check: &ModelCheck,
        frf: &Frf,
    ) -> Result<Budget> {
        let birge = check.birge_factor().powi(2) - 1.0;
        // The band sensitivity is carried only where the model is not shown to fit: moving
        // the edges of a right model's band moves the estimate by its random error alone
        // (for ML, by IVF's, twice ML's), which the random component already holds.
        let band = match check.verdict {
            Verdict::Fits => None,
            _ => self.band_spread(fitted, frf),
        };
        let r = random.stacked();
        let model = Mat::from_fn(r.nrows(), r.ncols(), |i, j| {
            let b = band.as_ref().map_or(0.0, |b| b[(i, j)]);
            (r[(i, j)].powi(2) * birge + b * b).sqrt()
        });
        Ok(Budget {
            random: random.clone(),
            model: Coefficients::from_stacked(model.as_ref())?,
            calibration: calibration_std(&self.calibration, fitted)?,
        })
    }

    /// The band-sensitivity spread (stacked), or `None` when the band is too short to move
    /// its edges or a refit fails (a refit that cannot be made says nothing of the model).
    fn band_spread(&self, fitted: &Coefficients, frf: &Frf) -> Option<Mat<f64>> {
        let lines = frf.line_count();
        let shift = BAND_SHIFT_LINES;
        if lines < solve::required_lines(frf.dofs()) + 2 * shift {
            return None;
        }
        // ML's refits are IVF's: its change with the band, from IVF's estimate on all lines.
        let method = match self.method {
            Method::Ml => Method::Ivf,
            m => m,
        };
        let refit = |keep: &dyn Fn(usize) -> bool| -> Option<Mat<f64>> {
            let sub = frf.retain_lines(keep);
            let fit = solve::fit_point(&sub, method, &self.ivf).ok()?;
            Some(self.corrected(fit).ok()?.coefficients().stacked())
        };
        let reference = match self.method {
            Method::Ml => refit(&|_| true)?,
            _ => fitted.stacked(),
        };
        let refits = [
            refit(&|k| k >= shift)?,
            refit(&|k| k < lines - shift)?,
            refit(&|k| k >= shift && k < lines - shift)?,
        ];
        Some(Mat::from_fn(
            reference.nrows(),
            reference.ncols(),
            |i, j| {
                let ss: f64 = refits
                    .iter()
                    .map(|t| (t[(i, j)] - reference[(i, j)]).powi(2))
                    .sum();
                (ss / refits.len() as f64).sqrt()
            },
        ))
    }
}

/// The calibration component, zero when nothing was stated.
fn calibration_std(calibration: &Calibration, fitted: &Coefficients) -> Result<Coefficients> {
    calibration.std_dev(fitted)
}
