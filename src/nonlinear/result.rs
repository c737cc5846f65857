//! [`NonlinearIdentification`]: the linear coefficients and the nonlinear terms identified by
//! the reverse path, with their error bars, spectra, model check and diagnostics.

use faer::c64;

use crate::error::Warning;
use crate::frf::Frf;
use crate::identify::Timings;
use crate::model::Coefficients;
use crate::solve::Fit;

use super::Term;
use super::check::TermCheck;
use super::velocity::VelocityChoice;

/// One identified nonlinear term: its coefficient and standard deviation.
///
/// # Examples
/// ```
/// use bearing_ident::nonlinear::{Regressor, Term, TermEstimate};
/// let t = TermEstimate {
///     term: Term { regressor: Regressor::Coulomb, dof: Some(0) },
///     value: 0.8,
///     std: Some(0.01),
///     model_std: 0.0,
/// };
/// assert_eq!((t.unit(), t.term.label().as_str()), ("N", "coulomb[0]"));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TermEstimate {
    /// The term.
    pub term: Term,
    /// Its coefficient $a_j$ in [`TermEstimate::unit`]: the weighted band average of
    /// $\operatorname{Re}\hat A_j$.
    pub value: f64,
    /// Its combined standard uncertainty: the random part (jackknife over blocks of Welch
    /// segments, or from the per-line variances with fewer than 3 blocks) and
    /// [`model_std`](TermEstimate::model_std) in quadrature; `None` when no random part is
    /// available.
    pub std: Option<f64>,
    /// The model part of its uncertainty, included in `std`: for dry friction, the bias a
    /// noisy velocity's sign would give it, $|F|\,\frac{2}{\pi}\arctan(\sigma_n/\sigma_v)$
    /// (velocity noise $\sigma_n$ against velocity $\sigma_v$, averaged over the records),
    /// which the expected-sign regressor removes only as far as the velocity is Gaussian;
    /// 0 for the other terms.
    pub model_std: f64,
}

impl TermEstimate {
    /// The coefficient's SI unit ([`Regressor::unit`](super::Regressor::unit)).
    pub fn unit(&self) -> &'static str {
        self.term.regressor.unit()
    }
}

/// The result of [`ReversePath::identify`](super::ReversePath::identify).
///
/// # Examples
/// See [`ReversePath`](super::ReversePath).
#[derive(Debug, Clone)]
pub struct NonlinearIdentification {
    pub(super) fit: Fit,
    pub(super) std: Option<Coefficients>,
    pub(super) terms: Vec<TermEstimate>,
    pub(super) spectra: Vec<Vec<c64>>,
    pub(super) spectra_var: Vec<Vec<f64>>,
    pub(super) checks: Vec<TermCheck>,
    pub(super) frf: Frf,
    pub(super) output_coherence: Vec<f64>,
    pub(super) velocity: VelocityChoice,
    pub(super) warnings: Vec<Warning>,
    pub(super) timings: Timings,
    pub(super) averages: usize,
    pub(super) blocks: usize,
    pub(super) segment_len: usize,
}

impl NonlinearIdentification {
    /// The linear `M`, `C`, `K`, fitted to the linear part $\hat H(\omega)$.
    pub fn coefficients(&self) -> &Coefficients {
        self.fit.coefficients()
    }

    /// Standard deviations of `M`, `C`, `K`: the jackknife over blocks of Welch segments (the
    /// fit's first-order sandwich with fewer than 3 blocks).
    pub fn std_dev(&self) -> Option<&Coefficients> {
        self.std.as_ref()
    }

    /// The linear fit itself (method, convergence, history).
    pub fn fit(&self) -> &Fit {
        &self.fit
    }

    /// The nonlinear terms, in the order of the regressors given, one per DOF or planar.
    pub fn terms(&self) -> &[TermEstimate] {
        &self.terms
    }

    /// The coefficient spectrum $\hat A_j(\omega)$ of term `j` at [`Self::freqs_hz`].
    ///
    /// # Panics
    /// If `j` is not below the number of terms.
    pub fn term_spectrum(&self, j: usize) -> &[c64] {
        &self.spectra[j]
    }

    /// The random-error variance $E\lvert\delta\hat A_j\rvert^2$ of term `j` per line.
    ///
    /// # Panics
    /// If `j` is not below the number of terms.
    pub fn term_variance(&self, j: usize) -> &[f64] {
        &self.spectra_var[j]
    }

    /// The model check of each term, in term order.
    pub fn checks(&self) -> &[TermCheck] {
        &self.checks
    }

    /// Frequencies of the band lines (Hz).
    pub fn freqs_hz(&self) -> &[f64] {
        self.frf.freqs_hz()
    }

    /// The linear part $\hat H(\omega)$ as an [`Frf`] (what the linear fit saw).
    pub fn frf(&self) -> &Frf {
        &self.frf
    }

    /// Multiple coherence of force `i` on all inputs (displacements and regressors) at line
    /// `k`: close to 1 when the model explains the force.
    ///
    /// # Panics
    /// If `k` or `i` is out of range.
    pub fn output_coherence(&self, k: usize, i: usize) -> f64 {
        let n = self.fit.coefficients().dofs();
        assert!(i < n, "DOF out of range");
        self.output_coherence[k * n + i]
    }

    /// The smallest multiple coherence of any force over the band.
    pub fn min_output_coherence(&self) -> f64 {
        self.output_coherence
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min)
    }

    /// How the velocities were derived.
    pub fn velocity(&self) -> &VelocityChoice {
        &self.velocity
    }

    /// What the user should know: failed model checks, collinear regressors, an IVF that did
    /// not converge, too few jackknife blocks.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// Wall time per stage: `spectra` covers the velocities, the regressors and the Welch
    /// sums; `frf` the per-line reverse path; `solve` the linear fit and the band averages;
    /// `conditioning` the model check; `uncertainty` the jackknife refits.
    pub fn timings(&self) -> Timings {
        self.timings
    }

    /// Welch segments over all records.
    pub fn averages(&self) -> usize {
        self.averages
    }

    /// Jackknife blocks the segments were cut into.
    pub fn jackknife_blocks(&self) -> usize {
        self.blocks
    }

    /// Welch segment length (samples).
    pub fn segment_len(&self) -> usize {
        self.segment_len
    }
}
