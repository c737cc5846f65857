//! Per-element fit of the impedance (seed eq. 10): `Re H_ij = K_ij − ω² M_ij`, `Im H_ij = ω C_ij`.

use faer::Mat;
use faer::prelude::SolveLstsq;

use super::system::{Stacked, check_lines};
use super::{Convergence, Fit, Method};
use crate::error::{Error, Result};
use crate::frf::Frf;
use crate::model::Coefficients;

/// Goodness of a direct fit, per element: the coefficient of determination
/// `r² = 1 − SS_res / SS_tot` of the real-part fit (`K − ω²M`) and of the imaginary-part fit
/// (`ωC`). Near 1 means the model shape fits; it says nothing for near-zero coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct DirectFit {
    /// `r²` of `Re H_ij` against `K_ij − ω² M_ij`.
    pub r2_real: Mat<f64>,
    /// `r²` of `Im H_ij` against `ω C_ij`.
    pub r2_imag: Mat<f64>,
}

fn r_squared(data: &[f64], fitted: impl Fn(usize) -> f64) -> f64 {
    let mean = data.iter().sum::<f64>() / data.len() as f64;
    let ss_tot: f64 = data.iter().map(|v| (v - mean).powi(2)).sum();
    let ss_res: f64 = data
        .iter()
        .enumerate()
        .map(|(k, v)| (v - fitted(k)).powi(2))
        .sum();
    if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        f64::NAN
    }
}

pub(super) fn fit(frf: &Frf) -> Result<Fit> {
    let n = frf.dofs();
    let lines = frf.line_count();
    check_lines(frf)?;
    let w: Vec<f64> = frf
        .freqs_hz()
        .iter()
        .map(|f| 2.0 * std::f64::consts::PI * f)
        .collect();
    // Real part: columns [1, −ω²], scaled to unit norm, one QR for all n² elements.
    let s0 = 1.0 / (lines as f64).sqrt();
    let s1 = 1.0 / w.iter().map(|w| w.powi(4)).sum::<f64>().sqrt();
    let basis = Mat::from_fn(lines, 2, |k, c| if c == 0 { s0 } else { -w[k] * w[k] * s1 });
    let qr = basis.qr();
    let re = Mat::from_fn(lines, n * n, |k, e| frf.impedance(k)[(e % n, e / n)].re);
    let sol = qr.solve_lstsq(&re);
    let sum_w2: f64 = w.iter().map(|w| w * w).sum();
    let mut mass = Mat::zeros(n, n);
    let mut damping = Mat::zeros(n, n);
    let mut stiffness = Mat::zeros(n, n);
    let mut r2_real = Mat::zeros(n, n);
    let mut r2_imag = Mat::zeros(n, n);
    for e in 0..n * n {
        let (i, j) = (e % n, e / n);
        let (k_ij, m_ij) = (sol[(0, e)] * s0, sol[(1, e)] * s1);
        let im: Vec<f64> = (0..lines).map(|k| frf.impedance(k)[(i, j)].im).collect();
        let c_ij = im.iter().zip(&w).map(|(h, w)| h * w).sum::<f64>() / sum_w2;
        let re_col: Vec<f64> = (0..lines).map(|k| re[(k, e)]).collect();
        r2_real[(i, j)] = r_squared(&re_col, |k| k_ij - w[k] * w[k] * m_ij);
        r2_imag[(i, j)] = r_squared(&im, |k| w[k] * c_ij);
        mass[(i, j)] = m_ij;
        damping[(i, j)] = c_ij;
        stiffness[(i, j)] = k_ij;
    }
    let coefficients =
        Coefficients::new(mass, damping, stiffness).map_err(|_| Error::SingularFit {
            method: Method::Direct,
        })?;
    let sys = Stacked::new(frf, Method::Direct)?;
    let residual_norm = sys.residual_norm(coefficients.stacked().as_ref());
    Ok(Fit {
        method: Method::Direct,
        coefficients,
        residual_norm,
        convergence: Convergence::NotIterative,
        history: Vec::new(),
        std_dev: None,
        covariance: None,
        direct: Some(DirectFit { r2_real, r2_imag }),
    })
}
