//! Least squares on the stacked, column-scaled flexibility identity, by QR.

use faer::prelude::SolveLstsq;

use super::system::Stacked;
use super::{Convergence, Fit, Method, finish};
use crate::error::{Error, Result};
use crate::frf::Frf;

/// Largest accepted ratio of the extreme diagonal entries of `R` in the scaled QR.
const RANK_RATIO: f64 = 1e12;

/// Solves the scaled stacked system by QR; returns `(Θ, system)`.
pub(super) fn solve(frf: &Frf, method: Method) -> Result<(faer::Mat<f64>, Stacked)> {
    let sys = Stacked::new(frf, method)?;
    let qr = sys.a.qr();
    let r = qr.thin_R();
    let diag: Vec<f64> = (0..r.ncols()).map(|i| r[(i, i)].abs()).collect();
    let max = diag.iter().cloned().fold(0.0, f64::max);
    let min = diag.iter().cloned().fold(f64::INFINITY, f64::min);
    if !(min > 0.0 && max / min < RANK_RATIO) {
        return Err(Error::SingularFit { method });
    }
    let theta_s = qr.solve_lstsq(sys.rhs());
    let theta = sys.unscale(theta_s.as_ref());
    Ok((theta, sys))
}

/// Least squares without its covariance ([`super::fit_point`]).
pub(super) fn fit_point(frf: &Frf) -> Result<Fit> {
    fit_with(frf, false)
}

pub(super) fn fit(frf: &Frf) -> Result<Fit> {
    fit_with(frf, true)
}

/// The least-squares fit, with its sandwich covariance if `covariance`.
fn fit_with(frf: &Frf, covariance: bool) -> Result<Fit> {
    let (theta, sys) = solve(frf, Method::LeastSquares)?;
    let std = if covariance {
        sys.sandwich_covariance(theta.as_ref(), sys.a.as_ref())
    } else {
        None
    };
    finish(
        Method::LeastSquares,
        theta,
        &sys,
        Convergence::NotIterative,
        Vec::new(),
        std,
    )
}
