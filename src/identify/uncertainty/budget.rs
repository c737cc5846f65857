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
//! - **calibration**: the stated gain uncertainties ([`Calibration::std_dev`]) and, in
//!   quadrature, those of the channels' stated transfer characteristics
//!   ([`ChannelTransfers::with_uncertainty`](crate::frf::ChannelTransfers::with_uncertainty)):
//!   for each, the half difference of two refits of the impedance perturbed to first order
//!   by plus and minus its standard uncertainty, $(\theta_+ - \theta_-)/2$ (exact to first
//!   order; maximum likelihood refits by IVF, as for the band part).
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

#[cfg(doc)]
use super::super::Calibration;
use super::super::model_check::Verdict;
use super::super::{ModelCheck, Settings};
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
    /// The calibration component's independent sources, one change of the stacked
    /// coefficients per source at one standard uncertainty ([`Calibration::directions`] and
    /// the transfer refits): what moves the derived quantities.
    calibration_directions: Vec<Mat<f64>>,
}

impl Budget {
    /// The combined standard uncertainty, the three components in quadrature.
    ///
    /// # Errors
    /// None in practice (the components share one shape).
    pub fn combined(&self) -> Result<Coefficients> {
        quadrature(&[&self.random, &self.model, &self.calibration])
    }

    /// Random and model components in quadrature: the part whose errors are taken as
    /// uncorrelated between coefficients (the calibration's are not: see
    /// [`Budget::calibration_directions`]).
    ///
    /// # Errors
    /// None in practice (the components share one shape).
    pub fn random_and_model(&self) -> Result<Coefficients> {
        quadrature(&[&self.random, &self.model])
    }

    /// The calibration component as its independent sources: one change of the stacked
    /// coefficients $[M; C; K]$ (`3n × n`) per source at one standard uncertainty. Their
    /// squares sum to [`Budget::calibration`]'s variances. A gain's moves no natural
    /// frequency or damping ratio; a stated delay's or corner's does, and the derived
    /// quantities' error bars carry it.
    pub fn calibration_directions(&self) -> &[Mat<f64>] {
        &self.calibration_directions
    }

    /// A budget of given components, the calibration's sources not known one by one.
    pub(in crate::identify) fn of_parts(
        random: Coefficients,
        model: Coefficients,
        calibration: Coefficients,
    ) -> Budget {
        Budget {
            random,
            model,
            calibration,
            calibration_directions: Vec::new(),
        }
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
        let calibration_directions = self.calibration_directions(fitted, frf)?;
        let theta = fitted.stacked();
        let calibration = Mat::from_fn(theta.nrows(), theta.ncols(), |i, j| {
            // A fold from +0.0: an empty `sum` of floats is −0.0, which JSON would show.
            calibration_directions
                .iter()
                .fold(0.0, |acc, d| acc + d[(i, j)].powi(2))
                .sqrt()
        });
        Ok(Budget {
            random: random.clone(),
            model: Coefficients::from_stacked(model.as_ref())?,
            calibration: Coefficients::from_stacked(calibration.as_ref())?,
            calibration_directions,
        })
    }

    /// The calibration component's independent sources (see the module docs): the stated
    /// gains' ([`Calibration::directions`]) and, per stated transfer uncertainty, half the
    /// difference of the refits at plus and minus one standard uncertainty; none when nothing
    /// was stated.
    ///
    /// # Errors
    /// The calibration's channel check; a refit that fails.
    fn calibration_directions(&self, fitted: &Coefficients, frf: &Frf) -> Result<Vec<Mat<f64>>> {
        let mut directions = self.calibration.directions(fitted)?;
        let method = match self.method {
            Method::Ml => Method::Ivf,
            m => m,
        };
        let decay = self.window.decay_per_s().unwrap_or(0.0);
        let refit = |step: f64, entry: usize| -> Result<Mat<f64>> {
            let frf = self.transfers.perturbed(frf, entry, step, decay);
            let fit = self.corrected(solve::fit_point(&frf, method, &self.ivf)?)?;
            Ok(fit.coefficients().stacked())
        };
        for (entry, &u) in self.transfers.uncertainties().iter().enumerate() {
            if u > 0.0 {
                let (plus, minus) = (refit(u, entry)?, refit(-u, entry)?);
                directions.push(Mat::from_fn(plus.nrows(), plus.ncols(), |i, j| {
                    0.5 * (plus[(i, j)] - minus[(i, j)])
                }));
            }
        }
        Ok(directions)
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

#[cfg(test)]
mod tests {
    use faer::{Mat, c64};
    use std::f64::consts::PI;

    use crate::frf::{ChannelTransfer, ChannelTransfers, Frf};
    use crate::simulate::seed_rig;
    use crate::{Channel, Identifier, Method};

    /// A force channel late by `δ` more than stated leaves `H(1 − iωδ)` to first order; for
    /// `H = K + iωC` (no mass) that is `K + iω(C − δK) + ω²δC`, so a fit returns
    /// `C − δK` and `M = −δC`: a stated `u` on the delay is `σ(C) = K·u`, `σ(M) = C·u`,
    /// `σ(K) = 0`, exactly.
    #[test]
    fn a_stated_delay_uncertainty_is_carried_as_in_closed_form() {
        let (c, k, u) = (100.0, 1e5, 1e-4);
        let freqs: Vec<f64> = (5..=60).map(f64::from).collect();
        let g: Vec<Mat<c64>> = freqs
            .iter()
            .map(|f| Mat::from_fn(1, 1, |_, _| c64::new(k, 2.0 * PI * f * c).inv()))
            .collect();
        let frf = Frf::from_flexibility(freqs, &g).unwrap();
        let transfers = ChannelTransfers::new().with_uncertainty(
            Channel::Force(0),
            ChannelTransfer::delay(0.0),
            u,
        );
        let id = Identifier::new(5.0, 60.0)
            .method(Method::LeastSquares)
            .channel_transfers(transfers)
            .identify_frf(frf)
            .unwrap();
        let cal = &id.budget().unwrap().calibration;
        assert!((cal.damping()[(0, 0)] / (k * u) - 1.0).abs() < 1e-9);
        assert!((cal.mass()[(0, 0)] / (c * u) - 1.0).abs() < 1e-9);
        assert!(cal.stiffness()[(0, 0)] < 1e-9 * k);
    }

    /// A stated corner `3 ± 0.3 Hz` on response `x`: the calibration part of the budget is
    /// half the difference of the fits of exact data whose corner really was 3.3 and 2.7 Hz
    /// (divided by the stated 3 Hz), to second order in `u`.
    #[test]
    fn a_stated_corner_uncertainty_matches_refits_at_plus_and_minus_sigma() {
        let truth = seed_rig();
        let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
        let (corner, u) = (3.0, 0.3);
        // The corrected data when the true corner is `f`: column x of H times T(3)/T(f).
        let data = |f: f64| {
            let g: Vec<Mat<c64>> = freqs
                .iter()
                .map(|&hz| {
                    let s = c64::new(0.0, 2.0 * PI * hz);
                    let d = ChannelTransfer::high_pass(f).at(s)
                        / ChannelTransfer::high_pass(corner).at(s);
                    let mut g = truth.flexibility_at(hz).unwrap();
                    // G = H⁻¹: H's column x divided by d is G's row x times d.
                    for c in 0..2 {
                        g[(0, c)] *= d;
                    }
                    g
                })
                .collect();
            Frf::from_flexibility(freqs.clone(), &g).unwrap()
        };
        let id = Identifier::new(8.0, 49.0).method(Method::LeastSquares);
        let plus = id.identify_frf(data(corner + u)).unwrap();
        let minus = id.identify_frf(data(corner - u)).unwrap();
        let stated = ChannelTransfers::new().with_uncertainty(
            Channel::Displacement(0),
            ChannelTransfer::high_pass(corner),
            u,
        );
        let stated_id = id
            .channel_transfers(stated)
            .identify_frf(data(corner))
            .unwrap();
        let cal = stated_id.budget().unwrap().calibration.stacked();
        // The modes move with the corner too: the derived error bars (exact data, so the
        // calibration part alone) are half the difference of the refits' modes.
        let (fn_std, zeta_std) = (
            stated_id.natural_frequencies_hz_std().unwrap(),
            stated_id.damping_ratios_std().unwrap(),
        );
        let (mp, mm) = (
            plus.coefficients().modes().unwrap(),
            minus.coefficients().modes().unwrap(),
        );
        for k in 0..2 {
            let df = 0.5 * (mp[k].natural_frequency_hz - mm[k].natural_frequency_hz).abs();
            let dz = 0.5 * (mp[k].damping_ratio - mm[k].damping_ratio).abs();
            assert!(dz > 1e-6 * mp[k].damping_ratio, "mode {k}: ζ does not move");
            assert!(
                (fn_std[k] / df - 1.0).abs() < 0.05,
                "f_n {k}: {} vs {df}",
                fn_std[k]
            );
            assert!(
                (zeta_std[k] / dz - 1.0).abs() < 0.05,
                "ζ {k}: {} vs {dz}",
                zeta_std[k]
            );
        }
        let (p, m) = (
            plus.coefficients().stacked(),
            minus.coefficients().stacked(),
        );
        let mut checked = 0;
        for i in 0..6 {
            for j in 0..2 {
                let expected = 0.5 * (p[(i, j)] - m[(i, j)]).abs();
                if j == 0 && expected > 0.0 {
                    // Column x only moves; relative to its size, the second-order term.
                    assert!(
                        (cal[(i, j)] / expected - 1.0).abs() < 0.02,
                        "({i},{j}): {} vs {expected}",
                        cal[(i, j)]
                    );
                    checked += 1;
                } else {
                    assert!(cal[(i, j)] <= 1e-9 * p[(i, j)].abs().max(1.0), "({i},{j})");
                }
            }
        }
        assert_eq!(checked, 6);
    }
}
