//! The instrumental-variable filter (Fritzen 1985; Diaz & San Andrés 1999, eqs. 11–13).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor::{lu_in_place, lu_in_place_scratch};
use faer::linalg::lu::partial_pivoting::solve::{solve_in_place, solve_in_place_scratch};
use faer::{Mat, MatRef, Par, c64};

use super::system::{InstrumentWork, Stacked};
use super::{Convergence, Fit, Method, block_change, finish, ls};
#[cfg(doc)]
use crate::error::Error;
use crate::error::Result;
use crate::frf::Frf;
use crate::linalg::Inverter;
use crate::model::Coefficients;

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
    pub fn check(&self) -> Result<()> {
        super::check_tolerance(self.tolerance, crate::Parameter::IvfTolerance)?;
        if self.max_iterations == 0 {
            return Err(crate::Error::InvalidParameter {
                name: crate::Parameter::IvfMaxIterations,
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

/// [`block_change`] of block `block` (0: `M`, 1: `C`, 2: `K`) of the stacked `3n × n` `Θ`,
/// column by column.
fn stacked_change(new: MatRef<'_, f64>, old: MatRef<'_, f64>, block: usize, n: usize) -> f64 {
    block_change(
        (0..n).flat_map(|j| (block * n..(block + 1) * n).map(move |i| (new[(i, j)], old[(i, j)]))),
    )
}

/// The IVF iteration as a value: built once from an [`Frf`] (the least-squares start, the
/// scaled `A`, every buffer an iteration needs), then stepped with [`IvfSolver::iterate`],
/// which does not allocate, or run to the end with [`IvfSolver::solve`].
///
/// # Examples
/// ```
/// use bearing_ident::frf::Frf;
/// use bearing_ident::model::Coefficients;
/// use bearing_ident::solve::{IvfOptions, IvfSolver};
/// use faer::{Mat, c64, mat};
/// let truth = Coefficients::new(mat![[2.0]], mat![[10.0]], mat![[8.0e3]])?;
/// let freqs: Vec<f64> = (5..=15).map(f64::from).collect();
/// let g: Vec<Mat<c64>> = freqs.iter().map(|&f| truth.flexibility_at(f)).collect::<Result<_, _>>()?;
/// let mut solver = IvfSolver::new(&Frf::from_flexibility(freqs, &g)?, IvfOptions::default())?;
/// let step = solver.iterate().expect("a regular model");
/// assert!(step.change() < 1e-9); // exact data: least squares was already right
/// let fit = solver.solve()?;
/// assert!((fit.coefficients().stiffness()[(0, 0)] / 8.0e3 - 1.0).abs() < 1e-10);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub struct IvfSolver {
    sys: Stacked,
    options: IvfOptions,
    theta: Mat<f64>,
    next: Mat<f64>,
    history: Vec<Iteration>,
    normal: Mat<f64>,
    rhs: Mat<f64>,
    g: Vec<c64>,
    inverter: Inverter,
    work: InstrumentWork,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    stack: MemBuffer,
    /// The lines' frequencies (Hz), to name the one where an iteration meets NaN.
    freqs_hz: Vec<f64>,
    /// Why the last [`IvfSolver::iterate`] returned `None`, when it met NaN or infinity: the
    /// line (`Some(Hz)`) or the normal equations (`None`). `None` for a singular model.
    non_finite: Option<Option<f64>>,
}

impl std::fmt::Debug for IvfSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("IvfSolver")
            .field("options", &self.options)
            .field("theta", &self.theta)
            .field("history", &self.history)
            .finish_non_exhaustive()
    }
}

impl IvfSolver {
    /// Builds the stacked system, solves least squares for the start, and allocates every
    /// buffer of the iteration.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid options, and the least-squares errors
    /// ([`Error::TooFewLines`], [`Error::SingularFit`]).
    pub fn new(frf: &Frf, options: IvfOptions) -> Result<Self> {
        options.check()?;
        let (theta, sys) = ls::solve(frf, Method::Ivf)?;
        let n = sys.n;
        let p = 3 * n;
        let stack = MemBuffer::new(
            lu_in_place_scratch::<usize, f64>(p, p, Par::Seq, Default::default())
                .or(solve_in_place_scratch::<usize, f64>(p, n, Par::Seq)),
        );
        Ok(Self {
            options,
            next: theta.clone(),
            theta,
            // The limit is the user's: grown as iterations run, not reserved up front.
            history: Vec::with_capacity(options.max_iterations.min(64)),
            normal: Mat::zeros(p, p),
            rhs: Mat::zeros(p, n),
            g: vec![c64::new(0.0, 0.0); n * n],
            inverter: Inverter::new(n),
            work: InstrumentWork::new(n),
            perm: vec![0; p],
            perm_inv: vec![0; p],
            stack,
            sys,
            freqs_hz: frf.freqs_hz().to_vec(),
            non_finite: None,
        })
    }

    /// The current iterate `Θ = [M; C; K]` (`3n × n`).
    pub fn theta(&self) -> MatRef<'_, f64> {
        self.theta.as_ref()
    }

    /// The iterations run so far.
    pub fn history(&self) -> &[Iteration] {
        &self.history
    }

    /// One iteration, `Θ ← (W_sᵀ A_s)⁻¹ W_sᵀ Ī` with instruments from the current model,
    /// `W_sᵀ A_s` and `W_sᵀ Ī` formed line by line without `W` (`Stacked::instrument_normal`);
    /// no heap allocation. `None` (and no change) if the model impedance is singular at a
    /// line or the new iterate is not finite ([`IvfSolver::non_finite`] tells which).
    pub fn iterate(&mut self) -> Option<Iteration> {
        self.non_finite = None;
        let sys = &self.sys;
        if !sys.instrument_normal(
            self.theta.as_ref(),
            self.normal.as_mut(),
            self.rhs.as_mut(),
            &mut self.work,
        ) {
            self.non_finite = self.locate();
            return None;
        }
        let stack = MemStack::new(&mut self.stack);
        let (_, perm) = lu_in_place(
            self.normal.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            stack,
            Default::default(),
        );
        solve_in_place(
            self.normal.as_ref(),
            self.normal.as_ref(),
            perm,
            self.rhs.as_mut(),
            Par::Seq,
            stack,
        );
        sys.unscale_into(self.rhs.as_ref(), self.next.as_mut());
        if !self
            .next
            .col_iter()
            .all(|c| c.iter().all(|v| v.is_finite()))
        {
            // The iterate's model was regular at every line: the normal equations gave it.
            self.non_finite = Some(None);
            return None;
        }
        let n = sys.n;
        let step = Iteration {
            mass_change: stacked_change(self.next.as_ref(), self.theta.as_ref(), 0, n),
            damping_change: stacked_change(self.next.as_ref(), self.theta.as_ref(), 1, n),
            stiffness_change: stacked_change(self.next.as_ref(), self.theta.as_ref(), 2, n),
            residual_norm: sys.residual_norm_into(self.next.as_ref(), &mut self.work),
        };
        std::mem::swap(&mut self.theta, &mut self.next);
        self.history.push(step);
        Some(step)
    }

    /// After [`IvfSolver::iterate`] returned `None`: `Some` if it met NaN or infinity, with
    /// the line (Hz) where the model impedance or its inverse is not finite, or `None` for
    /// the normal equations of all lines together; `None` if the model is singular at a line.
    pub fn non_finite(&self) -> Option<Option<f64>> {
        self.non_finite
    }

    /// Why the instruments of the current iterate could not be formed (allocates; only on
    /// that failure): the first line where the model impedance or its inverse is not finite;
    /// `None` where the impedance is singular; the normal equations' sums otherwise.
    fn locate(&self) -> Option<Option<f64>> {
        let finite = |m: &Mat<c64>| m.col_iter().all(|c| c.iter().all(|z| z.is_finite()));
        let Ok(model) = Coefficients::from_stacked(self.theta.as_ref()) else {
            return Some(None);
        };
        for &f in &self.freqs_hz {
            if !finite(&model.impedance_at(f)) {
                return Some(Some(f));
            }
            match model.flexibility_at(f) {
                Ok(g) if !finite(&g) => return Some(Some(f)),
                Ok(_) => {}
                Err(_) => return None,
            }
        }
        Some(None)
    }

    /// Iterates until the block-wise change falls below the tolerance, the iteration limit,
    /// or divergence (the change rising three times in a row, or [`IvfSolver::iterate`]
    /// returning `None`), when the iterate with the smallest change is returned.
    ///
    /// # Errors
    /// [`Error::CoefficientShape`] never; kept for the uniform [`Fit`] constructor.
    pub fn solve(self) -> Result<Fit> {
        self.run(true)
    }

    /// [`IvfSolver::solve`], with the sandwich covariance only when `with_covariance`.
    pub(super) fn run(mut self, with_covariance: bool) -> Result<Fit> {
        let mut best = (f64::INFINITY, 0, self.theta.clone());
        let mut rises = 0;
        let mut convergence = None;
        while self.history.len() < self.options.max_iterations {
            let Some(step) = self.iterate() else {
                let (iterations, fallback_iteration) = (self.history.len(), best.1);
                convergence = Some(match self.non_finite {
                    Some(freq_hz) => Convergence::NonFinite {
                        iterations,
                        fallback_iteration,
                        freq_hz,
                    },
                    None => Convergence::Diverged {
                        iterations,
                        fallback_iteration,
                    },
                });
                break;
            };
            let it = self.history.len();
            let change = step.change();
            if it > 1 && change > self.history[it - 2].change() {
                rises += 1;
            } else {
                rises = 0;
            }
            if change < best.0 {
                best.0 = change;
                best.1 = it;
                best.2.copy_from(&self.theta);
            }
            if change < self.options.tolerance {
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
            iterations: self.options.max_iterations,
            change: self.history.last().map(Iteration::change),
        });
        if let Convergence::Diverged { .. } | Convergence::NonFinite { .. } = convergence {
            self.theta = best.2;
        }
        // Instruments at the returned iterate, for the sandwich covariance.
        let sys = &self.sys;
        let std = with_covariance
            .then(|| {
                // The instruments only here: a fit without its covariance never forms them.
                let mut w_s = Mat::zeros(sys.a.nrows(), sys.a.ncols());
                sys.fill_instruments(
                    self.theta.as_ref(),
                    w_s.as_mut(),
                    &mut self.g,
                    &mut self.inverter,
                )
                .then(|| sys.sandwich_covariance(self.theta.as_ref(), w_s.as_ref()))
                .flatten()
            })
            .flatten();
        finish(Method::Ivf, self.theta, sys, convergence, self.history, std)
    }
}

pub(super) fn fit(frf: &Frf, options: &IvfOptions) -> Result<Fit> {
    IvfSolver::new(frf, *options)?.solve()
}
