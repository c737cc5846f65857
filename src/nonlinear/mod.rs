//! Nonlinear elements: linear M, C, K together with known nonlinear force terms (dry friction,
//! cubic stiffness, quadratic damping), by the reverse path (METHOD.md §7).
//!
//! The model is
//! $$M\ddot x + C\dot x + Kx + \sum_j a_j\,y_j(x,\dot x) = f,$$
//! with **known** force shapes $y_j \in \mathbb R^n$ ([`Term::force_shape`]) and unknown scalar
//! coefficients $a_j$. A positive friction coefficient opposes the motion.

mod regressor;

pub use regressor::{Regressor, Term};
