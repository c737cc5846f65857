//! Element model families beyond constant `K`, `C`, `M`: the impedance `H(ω)` of a bearing,
//! seal or damper whose stiffness and damping change with frequency, fitted to the measured
//! impedance with error bars, and the smallest family the data support chosen by the model
//! check ([`ModelSpec::Auto`]).
//!
//! # The families
//! Each is linear in `n × n` coefficient matrices given its poles, with no symmetry assumed;
//! `s = iω`:
//!
//! | family | `H(ω)` | real parameters per element |
//! |---|---|---|
//! | [`Family::Kc`] | $K + sC$ | 2 |
//! | [`Family::Kcm`] | $K + sC + s^2 M$ (the constant coefficients) | 3 |
//! | [`Family::Poly`] `P` | $\sum_{k=0}^P K_k \hat\omega^k + s \sum_{k=0}^P C_k \hat\omega^k$, $\hat\omega = \omega/\omega_0$ | $2(P+1)$ |
//! | [`Family::States`] `N` | $K + sC + s^2 M + \sum_{j=1}^N A_j \dfrac{s}{s + p_j}$, real $p_j > 0$ | $3 + N$ (and `N` poles) |
//!
//! `Poly` gives `K(ω)`, `C(ω)` as polynomials of degree `P` in frequency (`ω₀` the band's
//! upper edge, so the coefficients keep the units of `K` and `C`); `kcm` is `Poly` 2 with
//! `K₁ = C₁ = C₂ = 0`. `States` is the internal-state (auxiliary-state) model of seals, tilting
//! pads and magnetic bearings: each pole adds a state `w_j` with $\dot w_j = \dot x - p_j w_j$
//! and the force $A_j w_j$, so stiffness rises from `K` below `p_j` to `K + A_j` above it, with
//! a damping hump $A_j p_j/(\omega^2 + p_j^2)$ around it; the rig with the element is a
//! state-space model of dimension `2n + Nn` and its eigenvalues, stability and time response
//! follow exactly ([`ElementModel::modes`]).
//!
//! # The fit
//! For fixed poles each element's impedance is a weighted linear least-squares problem in its
//! own parameters, weighted by the measured impedance's pure error (the replicates' scatter,
//! [`Frf::impedance_variance`]): the statistic the model check judges,
//! $\sum_k \nu \ln(1 + 2 t_k/\nu)$ with $t_k = |\bar H_k - H(\omega_k)|^2 / v_k$, minimised by
//! iteratively reweighted least squares. The poles are found by variable projection (Golub and
//! Pereyra): Levenberg–Marquardt on $\ln p_j$ over the residuals with every element's
//! coefficients solved at each step, from log-spaced starts across the band
//! ([`fit_family`]). The standard deviations come from the Gauss–Newton matrix of the whole
//! problem (coefficients and poles), widened by the model check's Birge ratio.
//!
//! # Choosing the family
//! [`select`] fits the families in order of size (`kc`, `kcm`, `states:1`, `states:2`,
//! `poly:2`, …) and chooses the smallest that the model check accepts; a model the data cannot
//! support is refused: more parameters per element than the lines allow, a pole beyond a third
//! of the band's lower edge or three times its upper edge (its term is a constant or a pure
//! `s` term there), or residues indistinguishable from zero. Among models of one size, BIC
//! breaks ties. KCM is chosen whenever it fits: a larger model is chosen only when the smaller
//! ones fail the check, which a right KCM model does at the check's own false-alarm rate.
//!
//! [`Frf::impedance_variance`]: crate::frf::Frf::impedance_variance

mod basis;
pub(crate) mod fit;
mod irls;
mod result;
mod select;

pub use basis::Family;
pub use fit::{FamilyFit, fit_family};
pub use result::{Candidate, Curve, Effective, ElementModel};
pub use select::{ModelSpec, select};
