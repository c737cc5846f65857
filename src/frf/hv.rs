//! Hv (total least squares) per output: the smallest eigenvector of the augmented
//! cross-spectral matrix, between H1 and H2 when force and displacement are both noisy.

use faer::{Mat, c64};

use super::cross::{LineEstimator, LineSums, LineWork};

/// The Hv line estimate ([`Estimator::Hv`](super::Estimator::Hv)).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Hv;

impl LineEstimator for Hv {
    fn estimate(&self, s: &LineSums<'_>, work: &mut LineWork) -> bool {
        hv_flexibility(s.n, s.sff, s.sxf, s.sxx, &mut work.g) && {
            work.h.copy_from_slice(&work.g);
            work.inverter.invert(&mut work.h)
        }
    }
}

/// Row by row Hv flexibility into `g` (column-major `n × n`) from one line's cross-spectra.
/// `false` if an augmented matrix is not finite or its smallest eigenvector has no output part.
fn hv_flexibility(n: usize, sff: &[c64], sxf: &[c64], sxx: &[c64], g: &mut [c64]) -> bool {
    let force_power = (0..n).map(|i| sff[i * (n + 1)].re).sum::<f64>() / n as f64;
    let mut aug = Mat::<c64>::zeros(n + 1, n + 1);
    for i in 0..n {
        let out_power = sxx[i * (n + 1)].re;
        if !(out_power > 0.0 && force_power > 0.0) {
            return false;
        }
        // Displacement scaled to the forces' mean power: x' = s x.
        let s = (force_power / out_power).sqrt();
        for b in 0..n {
            for a in 0..n {
                aug[(a, b)] = sff[a + b * n];
            }
            // S_{f x'} = s Σ F x̄_i = s conj(S_{x_i f}).
            aug[(b, n)] = sxf[i + b * n].conj() * s;
            aug[(n, b)] = sxf[i + b * n] * s;
        }
        aug[(n, n)] = c64::new(out_power * s * s, 0.0);
        let Ok(eig) = aug.self_adjoint_eigen(faer::Side::Lower) else {
            return false;
        };
        // Eigenvalues ascend: column 0 is the smallest. With u that eigenvector, the residual
        // x' − g' F is orthogonal-least-squares minimal for g'_b = −conj(u_b / u_n).
        let u = eig.U().col(0);
        let last = u[n];
        if last.norm() == 0.0 || !last.is_finite() {
            return false;
        }
        for b in 0..n {
            g[i + b * n] = -(u[b] / last).conj() / s;
        }
    }
    true
}
