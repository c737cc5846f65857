//! MIMO H2: $G_2 = S_{xx} S_{fx}^{-1}$, i.e. $H = S_{fx} S_{xx}^{-1}$; unbiased under force
//! noise.

use super::cross::{LineEstimator, LineSums, LineWork};
use crate::linalg;

/// The H2 line estimate ([`Estimator::H2`](super::Estimator::H2)).
#[derive(Debug, Clone, Copy)]
pub(crate) struct H2;

impl LineEstimator for H2 {
    fn estimate(&self, s: &LineSums<'_>, work: &mut LineWork) -> bool {
        let n = s.n;
        // H = S_fx S_xx⁻¹ with S_fx = S_xfᴴ.
        work.scratch.copy_from_slice(s.sxx);
        work.inverter.invert(&mut work.scratch) && {
            for j in 0..n {
                for i in 0..n {
                    work.g[i + j * n] = s.sxf[j + i * n].conj();
                }
            }
            linalg::mul_into(&work.g, &work.scratch, &mut work.h, n);
            work.g.copy_from_slice(&work.h);
            work.inverter.invert(&mut work.g)
        }
    }
}
