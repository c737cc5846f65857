//! The crate's statistics, in one place: the reference distributions of its statistical tests
//! (upper tails of χ² and F, from `statrs`, used by the model check of a fit,
//! [`ModelCheck`](crate::identify::ModelCheck)), and inside the crate the medians, the median
//! absolute deviation's scale and quantiles of samples (`median.rs`), the medians of every
//! column of a small table at once (`column_median.rs`), the selection of a rank
//! among integer keys (`select.rs`) and the Student-t quantiles of the error bars'
//! intervals (`student_t.rs`).
//!
//! An upper tail `Q(x) = P(X > x)` is the p-value of an observed statistic `x`: small means the
//! observation is unlikely under the reference distribution.

mod column_median;
mod median;
pub(crate) mod select;
mod student_t;

use statrs::distribution::{ChiSquared, ContinuousCDF, FisherSnedecor};

pub(crate) use column_median::ColumnMedians;
pub(crate) use median::{MAD_TO_SIGMA, median, quantile, upper_median};
pub(crate) use student_t::t975;

use crate::error::{Error, Result};

/// Upper tail $Q(x) = P(\chi^2_\nu > x)$ of the χ² distribution with `dof` = ν degrees of
/// freedom; 1 for `x ≤ 0`.
///
/// # Errors
/// [`Error::InvalidParameter`] unless `dof` is finite and positive, or if `x` is NaN.
///
/// # Examples
/// ```
/// use bearing_ident::statistics::chi2_upper_tail;
/// // χ²₂ is exponential with mean 2: Q(x) = e^{−x/2}.
/// assert!((chi2_upper_tail(3.0, 2.0)? - (-1.5f64).exp()).abs() < 1e-12);
/// // The 95 % point of χ²₁₀ is 18.307.
/// assert!((chi2_upper_tail(18.307, 10.0)? - 0.05).abs() < 1e-4);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn chi2_upper_tail(x: f64, dof: f64) -> Result<f64> {
    check(x, dof, crate::Parameter::ChiSquaredDegreesOfFreedom)?;
    if x <= 0.0 {
        return Ok(1.0);
    }
    let d = ChiSquared::new(dof)
        .map_err(|_| invalid(crate::Parameter::ChiSquaredDegreesOfFreedom, dof))?;
    Ok(d.sf(x))
}

/// Upper tail $Q(x) = P(F_{\nu_1,\nu_2} > x)$ of Fisher's F distribution; 1 for `x ≤ 0`.
///
/// # Errors
/// [`Error::InvalidParameter`] unless both degrees of freedom are finite and positive, or if
/// `x` is NaN.
///
/// # Examples
/// ```
/// use bearing_ident::statistics::f_upper_tail;
/// // F(2, ν) has the closed tail (1 + 2x/ν)^(−ν/2).
/// let (x, nu) = (1.7, 6.0);
/// assert!((f_upper_tail(x, 2.0, nu)? - (1.0 + 2.0 * x / nu).powf(-nu / 2.0)).abs() < 1e-12);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn f_upper_tail(x: f64, dof1: f64, dof2: f64) -> Result<f64> {
    check(x, dof1, crate::Parameter::FNumeratorDegreesOfFreedom)?;
    check(x, dof2, crate::Parameter::FDenominatorDegreesOfFreedom)?;
    if x <= 0.0 {
        return Ok(1.0);
    }
    let d = FisherSnedecor::new(dof1, dof2)
        .map_err(|_| invalid(crate::Parameter::FDegreesOfFreedom, dof1))?;
    Ok(d.sf(x))
}

/// The `x` with upper tail `q` of the χ² distribution with `dof` degrees of freedom (its
/// `1 − q` quantile).
///
/// # Errors
/// [`Error::InvalidParameter`] unless `dof` is finite and positive and `0 < q < 1`.
///
/// # Examples
/// ```
/// use bearing_ident::statistics::chi2_upper_point;
/// assert!((chi2_upper_point(0.05, 10.0)? - 18.307).abs() < 1e-3);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn chi2_upper_point(q: f64, dof: f64) -> Result<f64> {
    if !(q > 0.0 && q < 1.0) {
        return Err(invalid(crate::Parameter::TailProbability, q));
    }
    check(1.0, dof, crate::Parameter::ChiSquaredDegreesOfFreedom)?;
    let d = ChiSquared::new(dof)
        .map_err(|_| invalid(crate::Parameter::ChiSquaredDegreesOfFreedom, dof))?;
    Ok(d.inverse_cdf(1.0 - q))
}

fn check(x: f64, dof: f64, name: crate::Parameter) -> Result<()> {
    if !(dof.is_finite() && dof > 0.0) {
        return Err(invalid(name, dof));
    }
    if x.is_nan() {
        return Err(invalid(crate::Parameter::TestStatistic, x));
    }
    Ok(())
}

fn invalid(name: crate::Parameter, value: f64) -> Error {
    Error::InvalidParameter {
        name,
        value,
        expected: "finite and positive",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tails_match_closed_forms_and_reject_bad_arguments() {
        // χ²₄: Q(x) = e^{−x/2}(1 + x/2).
        let x = 5.0_f64;
        let exact = (-x / 2.0).exp() * (1.0 + x / 2.0);
        assert!((chi2_upper_tail(x, 4.0).unwrap() - exact).abs() < 1e-12);
        assert!((chi2_upper_tail(-1.0, 4.0).unwrap() - 1.0).abs() < 1e-15);
        assert!(chi2_upper_tail(1.0, 0.0).is_err());
        assert!(chi2_upper_tail(f64::NAN, 3.0).is_err());
        assert!(f_upper_tail(1.0, f64::INFINITY, 3.0).is_err());
        assert!(chi2_upper_point(1.5, 3.0).is_err());
        let p = chi2_upper_point(0.01, 380.0).unwrap();
        assert!((chi2_upper_tail(p, 380.0).unwrap() - 0.01).abs() < 1e-9);
    }
}
