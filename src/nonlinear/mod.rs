//! Nonlinear elements: linear M, C, K together with known nonlinear force terms (dry friction,
//! cubic stiffness, quadratic damping), by the reverse path (Bendat 1990; Richards & Singh 1998; the repository's
//! `docs/method.md`, section 4).
//!
//! The model is
//! $$M\ddot x + C\dot x + Kx + \sum_j a_j\,y_j(x,\dot x) = f,$$
//! with **known** force shapes $y_j \in \mathbb R^n$ ([`Term::force_shape`]) and unknown scalar
//! coefficients $a_j$. A positive friction coefficient opposes the motion.
//!
//! | file | what lives there |
//! |---|---|
//! | `regressor.rs` | [`Regressor`] (the kinds of term) and [`Term`] (one term on one DOF) |
//! | `velocity.rs` | [`Differentiation`], [`Differentiator`]: velocities and displacements for the regressors |
//! | `gather.rs` | the regressor time series and the Welch sums of forces and inputs |
//! | `lines.rs` | per line $[\hat H\;\hat A] = S_{fz}S_{zz}^{-1}$, its variance and coherences; the linear fit and band averages |
//! | `check.rs` | [`TermCheck`]: is $\hat A_j(\omega)$ real and flat? |
//! | `reverse_path.rs` | [`ReversePath`]: settings and the run, with the jackknife |
//! | `result.rs` | [`NonlinearIdentification`], [`TermEstimate`] |

mod check;
mod gather;
mod lines;
mod regressor;
mod result;
mod reverse_path;
mod velocity;

pub use check::TermCheck;
pub use regressor::{Regressor, Term};
pub use result::{NonlinearIdentification, TermEstimate};
pub use reverse_path::ReversePath;
pub use velocity::{Differentiation, Differentiator, VelocityChoice};
