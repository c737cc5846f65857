//! The instrumental-variable filter (Fritzen 1985; Diaz & San Andrés 1999, eqs. 11–13).

use faer::linalg::matmul::matmul;
use faer::prelude::Solve;
use faer::{Accum, Mat, MatRef, Par, c64};

use super::{Convergence, Fit, Method, finish, ls};
use crate::error::{Error, Result};
use crate::frf::Frf;

/// Stopping rules of the IVF iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IvfOptions {
    /// Stop when the block-wise relative change
    /// $\max_{B \in \{M, C, K\}} \lVert \Delta B \rVert_F / \lVert B \rVert_F$ falls below
    /// this. Valid: `(0, 1)`. Default `1e-8`.
    pub tolerance: f64,
    /// Stop after this many iterations at the latest. Valid: `≥ 1`. Default `50`.
    pub max_iterations: usize,
}

impl Default for IvfOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 50,
        }
    }
}

impl IvfOptions {
    /// Checks the ranges.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a tolerance outside `(0, 1)` or zero iterations.
    pub fn validate(&self) -> Result<()> {
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(Error::InvalidParameter {
                name: "ivf tolerance",
                value: self.tolerance,
                expected: "0 < tolerance < 1",
            });
        }
        if self.max_iterations == 0 {
            return Err(Error::InvalidParameter {
                name: "ivf max iterations",
                value: 0.0,
                expected: "at least 1",
            });
        }
        Ok(())
    }
}

/// One IVF iteration: the block-wise relative changes from the previous iterate.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Iteration {
    /// `‖ΔM‖_F / ‖M‖_F`.
    pub mass_change: f64,
    /// `‖ΔC‖_F / ‖C‖_F`.
    pub damping_change: f64,
    /// `‖ΔK‖_F / ‖K‖_F`.
    pub stiffness_change: f64,
    /// Residual `‖A Θ − Ī‖_F` of the new iterate.
    pub residual_norm: f64,
}

impl Iteration {
    /// The largest of the three block changes: what the tolerance is compared with.
    pub fn change(&self) -> f64 {
        self.mass_change
            .max(self.damping_change)
            .max(self.stiffness_change)
    }
}

fn block_change(new: MatRef<'_, f64>, old: MatRef<'_, f64>, block: usize, n: usize) -> f64 {
    let (mut diff, mut norm) = (0.0, 0.0);
    for j in 0..n {
        for i in block * n..(block + 1) * n {
            diff += (new[(i, j)] - old[(i, j)]).powi(2);
            norm += new[(i, j)].powi(2);
        }
    }
    if norm > 0.0 {
        (diff / norm).sqrt()
    } else {
        diff.sqrt()
    }
}

/// Iteration workspace: owned once, reused by every iteration.
struct Workspace {
    w_s: Mat<f64>,
    normal: Mat<f64>,
    rhs: Mat<f64>,
    g: Vec<c64>,
    pivots: Vec<usize>,
}

pub(super) fn fit(frf: &Frf, options: &IvfOptions) -> Result<Fit> {
    options.validate()?;
    let (theta0, sys) = ls::solve(frf, "ivf")?;
    let n = sys.n;
    let p = 3 * n;
    let mut ws = Workspace {
        w_s: Mat::zeros(sys.a.nrows(), p),
        normal: Mat::zeros(p, p),
        rhs: Mat::zeros(p, n),
        g: vec![c64::new(0.0, 0.0); n * n],
        pivots: vec![0; n],
    };
    let mut theta = theta0.clone();
    let mut history: Vec<Iteration> = Vec::new();
    let mut best = (f64::INFINITY, 0, theta0);
    let mut rises = 0;
    let mut convergence = None;
    for it in 1..=options.max_iterations {
        if !sys.fill_instruments(theta.as_ref(), ws.w_s.as_mut(), &mut ws.g, &mut ws.pivots) {
            convergence = Some(Convergence::Diverged {
                iterations: it - 1,
                fallback_iteration: best.1,
            });
            break;
        }
        matmul(
            ws.normal.as_mut(),
            Accum::Replace,
            ws.w_s.transpose(),
            sys.a.as_ref(),
            1.0,
            Par::Seq,
        );
        sys.instrument_rhs(ws.w_s.as_ref(), ws.rhs.as_mut());
        let theta_s = ws.normal.partial_piv_lu().solve(&ws.rhs);
        let next = sys.unscale(theta_s.as_ref());
        if !next.col_iter().all(|c| c.iter().all(|v| v.is_finite())) {
            convergence = Some(Convergence::Diverged {
                iterations: it,
                fallback_iteration: best.1,
            });
            break;
        }
        let step = Iteration {
            mass_change: block_change(next.as_ref(), theta.as_ref(), 0, n),
            damping_change: block_change(next.as_ref(), theta.as_ref(), 1, n),
            stiffness_change: block_change(next.as_ref(), theta.as_ref(), 2, n),
            residual_norm: sys.residual_norm(next.as_ref()),
        };
        let change = step.change();
        if history.last().is_some_and(|prev| change > prev.change()) {
            rises += 1;
        } else {
            rises = 0;
        }
        history.push(step);
        theta = next;
        if change < best.0 {
            best = (change, it, theta.clone());
        }
        if change < options.tolerance {
            convergence = Some(Convergence::Converged { iterations: it });
            break;
        }
        if rises >= 3 {
            convergence = Some(Convergence::Diverged {
                iterations: it,
                fallback_iteration: best.1,
            });
            break;
        }
    }
    let convergence = convergence.unwrap_or(Convergence::IterationLimit {
        iterations: options.max_iterations,
        change: history.last().map_or(f64::NAN, Iteration::change),
    });
    if let Convergence::Diverged { .. } = convergence {
        theta = best.2;
    }
    // Instruments at the returned iterate, for the sandwich covariance.
    let std = sys
        .fill_instruments(theta.as_ref(), ws.w_s.as_mut(), &mut ws.g, &mut ws.pivots)
        .then(|| sys.sandwich_std(theta.as_ref(), ws.w_s.as_ref()))
        .flatten();
    finish(Method::Ivf, theta, &sys, convergence, history, std)
}
