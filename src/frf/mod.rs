//! Stage 3: impedance `H(ω)` and flexibility `G(ω) = H(ω)⁻¹` per frequency line.
//!
//! Two families of estimators turn the spectra of the records into an [`Frf`]: paired sets,
//! and the cross-spectral H1, H2 and Hv:
//!
//! - [`Estimator::PairedSets`] (the seed's eq. 9). Records are grouped into sets of `n`, one per
//!   linearly independent excitation; per set and line
//!   $H_k = [F^1 \cdots F^n]\,[X^1 \cdots X^n]^{-1}$, then `H` is averaged over the sets.
//! - [`Estimator::H1`] (MIMO H1). All records (and Welch segments) are accumulated into
//!   $S_{xf} = \sum_r X_r F_r^H$ and $S_{ff} = \sum_r F_r F_r^H$; then
//!   $G_1 = S_{xf} S_{ff}^{-1}$ and $H = G_1^{-1}$. No pairing is needed and `G₁` is unbiased
//!   under displacement noise.
//! - [`Estimator::H2`]: $G_2 = S_{xx} S_{fx}^{-1}$, unbiased under force noise.
//! - [`Estimator::Hv`]: per output, the total-least-squares fit of force and displacement
//!   together (smallest eigenvector of the augmented cross-spectral matrix), between H1 and H2
//!   when both channels are noisy.
//!
//! Each line also carries the condition number the next stage judges: `cond([X¹…Xⁿ])` for paired
//! sets (the worst set), `cond(S_ff)` for H1. Lines whose matrices cannot be inverted are dropped
//! and listed in [`Frf::dropped_hz`].
//!
//! # Layout
//! [`Frf`] (this file) is the result; [`Band`] (`band.rs`) and [`Assignment`]
//! (`assignment.rs`) say which lines and which records; [`FrfBuilder`] (`builder.rs`) gathers
//! the records; `paired.rs` holds the one paired-set kernel; `cross.rs` the cross-spectral
//! family behind a per-line estimator trait, one file per estimator (`h1.rs`, `h2.rs`,
//! `hv.rs`); `coherence.rs` and `variance.rs` the diagnostics of every estimator;
//! `statistics.rs` the per-period statistics maximum likelihood needs.

mod assignment;
mod band;
mod builder;
mod coherence;
mod contribution;
mod conversion;
mod cross;
mod h1;
mod h2;
mod hv;
pub mod interference;
mod moments;
pub mod noise;
mod paired;
mod replicates;
mod sets;
mod statistics;
mod transfer;
mod variance;

use crate::error::Quantity;
use faer::{Mat, MatRef, c64};

pub use crate::records::common_shape;
pub use assignment::Assignment;
pub use band::Band;
pub use builder::FrfBuilder;
pub use cross::UNEXCITED_RATIO;
pub use h1::h1;
pub(crate) use moments::RecordMoments;
pub use noise::{ForceNoise, NoiseFloor, NoiseSource};
pub use paired::paired_sets;
pub(crate) use paired::{PairedKernel, Share};
pub(crate) use replicates::Replicates;
pub(crate) use statistics::PeriodStatistics;
pub use transfer::{ChannelTransfer, ChannelTransfers, MAX_HIGH_PASS_ORDER};

use crate::error::{Error, Result};
use crate::linalg;
use crate::records::finite_positive;
#[cfg(doc)]
use crate::spectra::Segmentation;

/// How impedances are estimated from the records' spectra.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Estimator {
    /// Sets of `n` records, one per independent excitation; `H = F X⁻¹` per set, averaged over
    /// sets (the seed's eq. 9).
    #[default]
    PairedSets,
    /// MIMO H1 over all records and segments: `G = S_xf S_ff⁻¹`, `H = G⁻¹`. Unbiased under
    /// displacement noise; force noise biases `|G|` low (`H` high).
    H1,
    /// MIMO H2: `G = S_xx S_fx⁻¹`, i.e. `H = S_fx S_xx⁻¹`. Unbiased under force noise;
    /// displacement noise biases `|G|` high. Needs the records to excite all `n` directions.
    H2,
    /// Hv (total least squares) per output `i`: the eigenvector of the smallest eigenvalue of
    /// $\begin{bmatrix} S_{ff} & S_{fx_i} \\ S_{x_i f} & S_{x_i x_i}\end{bmatrix}$ gives row
    /// `i` of `G`. The displacement is first scaled to the forces' mean power, so the estimator
    /// assumes equal noise-to-signal ratios on force and displacement; between H1 and H2.
    Hv,
}

impl Estimator {
    /// Whether the estimator works on accumulated cross-spectra (all but paired sets).
    pub fn is_cross_spectral(self) -> bool {
        !matches!(self, Estimator::PairedSets)
    }
}

impl crate::Choice for Estimator {
    const OPTION: &'static str = "estimator";
    const ALL: &'static [Estimator] = &[
        Estimator::PairedSets,
        Estimator::H1,
        Estimator::H2,
        Estimator::Hv,
    ];

    /// `"paired"`, `"h1"`, `"h2"` or `"hv"` (the command line's `--estimator` values).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Choice, Estimator};
    /// assert_eq!("hv".parse::<Estimator>()?, Estimator::Hv);
    /// assert_eq!(Estimator::PairedSets.name(), "paired");
    /// assert!("h3".parse::<Estimator>().is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    fn name(self) -> &'static str {
        match self {
            Estimator::PairedSets => "paired",
            Estimator::H1 => "h1",
            Estimator::H2 => "h2",
            Estimator::Hv => "hv",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Estimator::PairedSets => "paired sets: one record per direction, impedance per set",
            Estimator::H1 => "MIMO H1, unbiased under response noise",
            Estimator::H2 => "MIMO H2, unbiased under force noise",
            Estimator::Hv => "Hv (total least squares), between H1 and H2",
        }
    }
}

crate::choice::choice_text!(Estimator);

/// Measured impedance and flexibility matrices over a set of frequency lines.
///
/// Matrices are `n × n`, indexed `[(output, input)]` = `[(displacement, force)]` for `G` and
/// `[(force, displacement)]` for `H`, so that `X = G F` and `F = H X`.
#[derive(Debug, Clone, PartialEq)]
pub struct Frf {
    dofs: usize,
    estimator: Estimator,
    freqs_hz: Vec<f64>,
    impedance: Vec<c64>,
    flexibility: Vec<c64>,
    condition: Vec<f64>,
    dropped_hz: Vec<f64>,
    averages: usize,
    unpaired: Vec<String>,
    /// Multiple coherence per line and output (`lines × n`); empty when unknown.
    multiple_coherence: Vec<f64>,
    /// Ordinary coherence per line, `n × n` column-major (output, input); empty when unknown.
    ordinary_coherence: Vec<f64>,
    /// `E|δH_ij|²` per line, `n × n` column-major; empty when unknown.
    impedance_variance: Vec<f64>,
    /// `E|(δG H)_ij|²` per line, `n × n` column-major: the variance of the identity `G H = I`
    /// the fits solve, at the true `H` (see [`Frf::equation_variance`]); empty when unknown.
    equation_variance: Vec<f64>,
    /// Band lines the excitation does not drive (periodic segmentation only).
    unexcited_hz: Vec<f64>,
    /// Spacing of the lines (Hz) when known.
    spacing_hz: Option<f64>,
}

impl Frf {
    /// An `Frf` from flexibilities measured elsewhere (one `n × n` matrix per line), for fitting
    /// data that did not come through this crate's spectra. Condition numbers are those of `G`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for mismatched lengths, non-square or mismatched matrices, or
    /// a frequency that is not finite and positive; [`Error::NonFiniteResult`] for a matrix
    /// holding NaN or infinity; a line whose `G` is singular is dropped.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::frf::Frf;
    /// use faer::{Mat, c64};
    /// // SDOF: m = 2 kg, c = 10 N·s/m, k = 8000 N/m.
    /// let freqs = vec![5.0, 10.0, 15.0];
    /// let g: Vec<Mat<c64>> = freqs
    ///     .iter()
    ///     .map(|f: &f64| {
    ///         let w = 2.0 * std::f64::consts::PI * f;
    ///         Mat::from_fn(1, 1, |_, _| c64::new(8000.0 - w * w * 2.0, w * 10.0).inv())
    ///     })
    ///     .collect();
    /// let frf = Frf::from_flexibility(freqs, &g)?;
    /// assert!((frf.impedance(0)[(0, 0)].re - (8000.0 - (10.0 * std::f64::consts::PI).powi(2) * 2.0)).abs() < 1e-9);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn from_flexibility(freqs_hz: Vec<f64>, flexibility: &[Mat<c64>]) -> Result<Self> {
        if freqs_hz.len() != flexibility.len() || flexibility.is_empty() {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::FlexibilityLines,
                value: flexibility.len() as f64,
                expected: "one matrix per frequency, at least one",
            });
        }
        let n = flexibility[0].nrows();
        let mut out = Frf::empty(n, Estimator::H1);
        let mut g = vec![c64::new(0.0, 0.0); n * n];
        let mut inverter = linalg::Inverter::new(n);
        let mut h = vec![c64::new(0.0, 0.0); n * n];
        let mut conditioner = linalg::Conditioner::new(n);
        for (&f, m) in freqs_hz.iter().zip(flexibility) {
            if m.nrows() != n || m.ncols() != n || n == 0 {
                return Err(Error::InvalidParameter {
                    name: crate::Parameter::FlexibilityMatrixSize,
                    value: m.nrows() as f64,
                    expected: "square matrices of one size",
                });
            }
            if !finite_positive(f) {
                return Err(Error::InvalidParameter {
                    name: crate::Parameter::Frequency,
                    value: f,
                    expected: "finite and positive (Hz)",
                });
            }
            for j in 0..n {
                for i in 0..n {
                    g[i + j * n] = m[(i, j)];
                }
            }
            if g.iter().any(|z| !(z.re.is_finite() && z.im.is_finite())) {
                return Err(Error::NonFiniteResult {
                    stage: Quantity::GivenFlexibility,
                    freq_hz: f,
                });
            }
            let cond = conditioner.condition_number(&g);
            h.copy_from_slice(&g);
            if inverter.invert(&mut h) {
                out.push_line(f, &h, &g, cond);
            } else {
                out.dropped_hz.push(f);
            }
        }
        out.averages = 1;
        out.spacing_hz = Frf::smallest_spacing(&freqs_hz);
        Ok(out)
    }

    pub(super) fn empty(dofs: usize, estimator: Estimator) -> Self {
        Self {
            dofs,
            estimator,
            freqs_hz: Vec::new(),
            impedance: Vec::new(),
            flexibility: Vec::new(),
            condition: Vec::new(),
            dropped_hz: Vec::new(),
            averages: 0,
            unpaired: Vec::new(),
            multiple_coherence: Vec::new(),
            ordinary_coherence: Vec::new(),
            impedance_variance: Vec::new(),
            equation_variance: Vec::new(),
            unexcited_hz: Vec::new(),
            spacing_hz: None,
        }
    }

    /// The smallest positive spacing of `freqs_hz` (Hz), `None` below two distinct lines.
    fn smallest_spacing(freqs_hz: &[f64]) -> Option<f64> {
        let mut sorted = freqs_hz.to_vec();
        sorted.sort_by(f64::total_cmp);
        sorted
            .windows(2)
            .map(|w| w[1] - w[0])
            .filter(|&d| d > 0.0)
            .min_by(f64::total_cmp)
    }

    /// [`Error::NonFiniteResult`] at the first line whose impedance, flexibility or coherence
    /// is not finite.
    pub(super) fn check_finite(&self) -> Result<()> {
        let (n, nn) = (self.dofs, self.dofs * self.dofs);
        for (k, &freq_hz) in self.freqs_hz.iter().enumerate() {
            let finite = |v: &[c64]| v.iter().all(|z| z.re.is_finite() && z.im.is_finite());
            let stage = if !finite(&self.impedance[k * nn..(k + 1) * nn]) {
                Quantity::Impedance
            } else if !finite(&self.flexibility[k * nn..(k + 1) * nn]) {
                Quantity::Flexibility
            } else if self
                .multiple_coherence
                .get(k * n..(k + 1) * n)
                .is_some_and(|c| c.iter().any(|g| !g.is_finite()))
            {
                Quantity::Coherence
            } else {
                continue;
            };
            return Err(Error::NonFiniteResult { stage, freq_hz });
        }
        Ok(())
    }

    pub(super) fn push_coherence(&mut self, multiple: &[f64], ordinary: &[f64]) {
        self.multiple_coherence.extend_from_slice(multiple);
        self.ordinary_coherence.extend_from_slice(ordinary);
    }

    /// Room for `lines` more lines (and their coherences, and their variances when
    /// `with_variance`), so that pushing them does not reallocate.
    pub(super) fn reserve_lines(&mut self, lines: usize, with_variance: bool) {
        let (n, nn) = (self.dofs, self.dofs * self.dofs);
        self.freqs_hz.reserve(lines);
        self.condition.reserve(lines);
        self.impedance.reserve(lines * nn);
        self.flexibility.reserve(lines * nn);
        self.multiple_coherence.reserve(lines * n);
        self.ordinary_coherence.reserve(lines * nn);
        if with_variance {
            self.impedance_variance.reserve(lines * nn);
            self.equation_variance.reserve(lines * nn);
        }
    }

    pub(super) fn push_line(&mut self, freq_hz: f64, h: &[c64], g: &[c64], condition: f64) {
        self.freqs_hz.push(freq_hz);
        self.impedance.extend_from_slice(h);
        self.flexibility.extend_from_slice(g);
        self.condition.push(condition);
    }

    /// Number of degrees of freedom `n`.
    pub fn dofs(&self) -> usize {
        self.dofs
    }

    /// The estimator that produced these matrices.
    pub fn estimator(&self) -> Estimator {
        self.estimator
    }

    /// Number of usable lines.
    pub fn line_count(&self) -> usize {
        self.freqs_hz.len()
    }

    /// Frequencies of the usable lines (Hz).
    pub fn freqs_hz(&self) -> &[f64] {
        &self.freqs_hz
    }

    /// Measured impedance `H` at line `k` (`n × n`).
    ///
    /// # Panics
    /// If `k >= self.line_count()`.
    pub fn impedance(&self, k: usize) -> MatRef<'_, c64> {
        let nn = self.dofs * self.dofs;
        MatRef::from_column_major_slice(&self.impedance[k * nn..(k + 1) * nn], self.dofs, self.dofs)
    }

    /// Measured flexibility `G = H⁻¹` at line `k` (`n × n`).
    ///
    /// # Panics
    /// If `k >= self.line_count()`.
    pub fn flexibility(&self, k: usize) -> MatRef<'_, c64> {
        let nn = self.dofs * self.dofs;
        MatRef::from_column_major_slice(
            &self.flexibility[k * nn..(k + 1) * nn],
            self.dofs,
            self.dofs,
        )
    }

    /// All flexibilities, line after line, each `n × n` column-major.
    pub(crate) fn flexibility_data(&self) -> &[c64] {
        &self.flexibility
    }

    /// Condition number per usable line: `cond([X¹…Xⁿ])` (worst set) for paired sets,
    /// `cond(S_ff)` for H1.
    pub fn condition_numbers(&self) -> &[f64] {
        &self.condition
    }

    /// Lines of the band that were dropped because a matrix could not be inverted (Hz).
    pub fn dropped_hz(&self) -> &[f64] {
        &self.dropped_hz
    }

    /// Number of averages: sets for paired sets, records × segments for H1.
    pub fn averages(&self) -> usize {
        self.averages
    }

    /// Multiple coherence of every output at line `k`,
    /// $\gamma^2_{i:f} = S_{x_i f} S_{ff}^{-1} S_{f x_i} / S_{x_i x_i}$: the fraction of output
    /// `i`'s power explained linearly by all the forces together (1 for noise-free linear data).
    /// `None` for an `Frf` built from external flexibilities.
    ///
    /// With as few averages as inputs it is 1 by construction; it says something only with
    /// more averages (records × segments) than degrees of freedom.
    pub fn multiple_coherence(&self, k: usize) -> Option<&[f64]> {
        let n = self.dofs;
        self.multiple_coherence.get(k * n..(k + 1) * n)
    }

    /// Ordinary coherence at line `k`, `γ²_ij = |S_xᵢfⱼ|² / (S_xᵢxᵢ S_fⱼfⱼ)`, column-major
    /// `n × n` (output `i`, input `j`). `None` when unknown.
    pub fn ordinary_coherence(&self, k: usize) -> Option<MatRef<'_, f64>> {
        let nn = self.dofs * self.dofs;
        self.ordinary_coherence
            .get(k * nn..(k + 1) * nn)
            .map(|s| MatRef::from_column_major_slice(s, self.dofs, self.dofs))
    }

    /// Variance of the measured impedance at line `k`, `E|δH_ij|²` (real and imaginary parts
    /// each carry half), column-major `n × n`; `None` when it cannot be estimated.
    ///
    /// - Paired sets: the scatter of the per-set impedances, $\sum_s |H_s - \bar H|^2 / (S(S-1))$
    ///   (needs 2 sets).
    /// - Cross-spectral estimators: the MIMO H1 random error (Bendat & Piersol). Row `a` of `G` has
    ///   covariance $\sigma_a^2 S_{ff}^{-1}$ with
    ///   $\sigma_a^2 = S_{x_a x_a}(1 - \gamma^2_{a:f}) / (n_d - n)$, and $\delta H = -H\,\delta G\,H$
    ///   gives $E|\delta H_{ij}|^2 = \sum_a |H_{ia}|^2 \sigma_a^2 \; h_j^H S_{ff}^{-1} h_j$
    ///   (`h_j` column `j` of `H`); needs more averages `n_d` than degrees of freedom. Welch
    ///   segments overlap and are not independent, so with Hann and 50 % overlap this is
    ///   somewhat optimistic.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let test = ImpactTest { per_direction: 4, noise: 0.1, ..ImpactTest::seed_rig() };
    /// let id = Identifier::new(8.0, 49.0).identify(&test.run(&seed_rig())?)?;
    /// // Four sets: the scatter of their impedances gives a variance on every line.
    /// let v = id.frf().impedance_variance(20).unwrap();
    /// let h = id.frf().impedance(20)[(0, 0)].norm();
    /// assert!(v[(0, 0)] > 0.0 && v[(0, 0)].sqrt() < 0.1 * h);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn impedance_variance(&self, k: usize) -> Option<MatRef<'_, f64>> {
        let nn = self.dofs * self.dofs;
        self.impedance_variance
            .get(k * nn..(k + 1) * nn)
            .map(|s| MatRef::from_column_major_slice(s, self.dofs, self.dofs))
    }

    /// The variance of the identity the fits solve at line `k`, `E|(δG\,H)_{ij}|²` (`n × n`):
    /// with the measured flexibility `G + δG` and the true impedance `H`, `(G + δG) H − I` is
    /// `δG H`, the equation error of a right model, whose correlations across the elements of
    /// a row of `δG` (H1's, `Cov(row i) ∝ S_ff⁻¹`) or of a set's impedance (paired sets) it
    /// keeps. `None` as for [`Frf::impedance_variance`].
    pub(crate) fn equation_variance(&self, k: usize) -> Option<MatRef<'_, f64>> {
        let nn = self.dofs * self.dofs;
        self.equation_variance
            .get(k * nn..(k + 1) * nn)
            .map(|s| MatRef::from_column_major_slice(s, self.dofs, self.dofs))
    }

    /// Lines of the band left out because the excitation does not drive them: with
    /// [`Segmentation::Periods`], lines whose force power `tr S_ff` is below
    /// [`UNEXCITED_RATIO`] of the band's strongest line.
    pub fn unexcited_hz(&self) -> &[f64] {
        &self.unexcited_hz
    }

    /// The same `Frf` restricted to the lines for which `keep(k)` holds; the others are added
    /// to [`Frf::dropped_hz`].
    pub fn retain_lines(&self, keep: impl Fn(usize) -> bool) -> Frf {
        let (n, nn) = (self.dofs, self.dofs * self.dofs);
        let mut out = Frf::empty(n, self.estimator);
        out.averages = self.averages;
        out.unpaired = self.unpaired.clone();
        out.dropped_hz = self.dropped_hz.clone();
        for k in 0..self.line_count() {
            if !keep(k) {
                out.dropped_hz.push(self.freqs_hz[k]);
                continue;
            }
            out.freqs_hz.push(self.freqs_hz[k]);
            out.impedance
                .extend_from_slice(&self.impedance[k * nn..(k + 1) * nn]);
            out.flexibility
                .extend_from_slice(&self.flexibility[k * nn..(k + 1) * nn]);
            out.condition.push(self.condition[k]);
            if let Some(c) = self.multiple_coherence.get(k * n..(k + 1) * n) {
                out.multiple_coherence.extend_from_slice(c);
            }
            if let Some(c) = self.ordinary_coherence.get(k * nn..(k + 1) * nn) {
                out.ordinary_coherence.extend_from_slice(c);
            }
            if let Some(v) = self.impedance_variance.get(k * nn..(k + 1) * nn) {
                out.impedance_variance.extend_from_slice(v);
            }
            if let Some(v) = self.equation_variance.get(k * nn..(k + 1) * nn) {
                out.equation_variance.extend_from_slice(v);
            }
        }
        out.unexcited_hz = self.unexcited_hz.clone();
        out.spacing_hz = self.spacing_hz;
        out.dropped_hz.sort_by(f64::total_cmp);
        out
    }

    /// Spacing of the frequency lines (Hz): the spectral resolution `fs / N` for an `Frf`
    /// built from records, the smallest spacing of the given lines otherwise; `None` for a
    /// ready-made `Frf` of fewer than two lines.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::frf::Frf;
    /// use faer::{Mat, c64};
    /// let g = vec![Mat::from_fn(1, 1, |_, _| c64::new(1e-3, 0.0)); 3];
    /// let frf = Frf::from_flexibility(vec![10.0, 12.5, 20.0], &g)?;
    /// assert_eq!(frf.line_spacing_hz(), Some(2.5));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn line_spacing_hz(&self) -> Option<f64> {
        self.spacing_hz
    }

    /// Labels of records left out of the paired sets (more records in one direction than in
    /// another).
    pub fn unpaired(&self) -> &[String] {
        &self.unpaired
    }

    /// An `Frf` from impedances computed elsewhere in the crate, one `(freq_hz, H, condition)`
    /// per line in the order given (`H` column-major `n × n`, `None` for a line already found
    /// singular); `G = H⁻¹`, and lines without an invertible `H` go to [`Frf::dropped_hz`].
    pub(crate) fn from_impedance_lines<'a>(
        n: usize,
        estimator: Estimator,
        averages: usize,
        unpaired: Vec<String>,
        lines: impl IntoIterator<Item = (f64, Option<&'a [c64]>, f64)>,
    ) -> Frf {
        let mut out = Frf::empty(n, estimator);
        (out.averages, out.unpaired) = (averages, unpaired);
        let mut all_hz = Vec::new();
        let (mut inverter, mut g) = (linalg::Inverter::new(n), vec![c64::new(0.0, 0.0); n * n]);
        for (freq, h, condition) in lines {
            all_hz.push(freq);
            let h = h.filter(|h| h.len() == n * n);
            let inverted = h.is_some_and(|h| {
                g.copy_from_slice(h);
                inverter.invert(&mut g)
            });
            match h {
                Some(h) if inverted => out.push_line(freq, h, &g, condition),
                _ => out.dropped_hz.push(freq),
            }
        }
        out.spacing_hz = Frf::smallest_spacing(&all_hz);
        out
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::Choice;
    use crate::records::Record;
    use crate::spectra::{Segmentation, Window};

    #[test]
    fn given_flexibilities_must_be_finite_and_keep_their_spacing() {
        let g = |v: f64| Mat::from_fn(1, 1, |_, _| c64::new(v, 0.0));
        let e = Frf::from_flexibility(vec![10.0, 20.0], &[g(1e-3), g(f64::NAN)]).unwrap_err();
        assert_eq!(
            e,
            Error::NonFiniteResult {
                stage: Quantity::GivenFlexibility,
                freq_hz: 20.0
            }
        );
        let one = Frf::from_flexibility(vec![10.0], &[g(1e-3)]).unwrap();
        assert_eq!(one.line_spacing_hz(), None);
        let kept = Frf::from_flexibility(vec![10.0, 20.0], &[g(1e-3), g(2e-3)])
            .unwrap()
            .retain_lines(|k| k == 0);
        assert_eq!(kept.line_spacing_hz(), Some(10.0));
        // Lines the band held but that were all dropped are not a band error.
        let none = kept.retain_lines(|_| false);
        let e = crate::conditioning::Conditioning::assess(&none, Default::default());
        assert!(matches!(e, Err(Error::RankDeficient { .. })), "{e:?}");
    }

    /// Records of a 2-DOF static "system" X = G F with a known constant G, driven by a pulse in
    /// x and one in y. A constant G is exact at every line whatever the signals.
    pub(crate) fn static_records(g: [[f64; 2]; 2]) -> Vec<Record> {
        let len = 64;
        let pulse = |m: usize| {
            if (3..6).contains(&m) {
                1.0 + m as f64
            } else {
                0.0
            }
        };
        (0..2)
            .map(|dir| {
                let f: Vec<Vec<f64>> = (0..2)
                    .map(|c| {
                        (0..len)
                            .map(|m| {
                                if c == dir {
                                    pulse(m)
                                } else {
                                    0.1 * pulse(m + 1)
                                }
                            })
                            .collect()
                    })
                    .collect();
                let x: Vec<Vec<f64>> = (0..2)
                    .map(|i| {
                        (0..len)
                            .map(|m| g[i][0] * f[0][m] + g[i][1] * f[1][m])
                            .collect()
                    })
                    .collect();
                Record::new(format!("dir{dir}"), 64.0, f, x).unwrap()
            })
            .collect()
    }

    #[test]
    fn siso_coherence_matches_signal_to_noise() {
        // x = 2 f + e with white f (σ = 1) and independent white e (σ = 1):
        // γ² = 4 / (4 + 1) = 0.8 at every line, up to the estimate's scatter.
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let mut rng = rand::rngs::StdRng::seed_from_u64(9);
        let normal = Normal::new(0.0, 1.0).unwrap();
        let len = 1 << 16;
        let f: Vec<f64> = (0..len).map(|_| normal.sample(&mut rng)).collect();
        let x: Vec<f64> = f
            .iter()
            .map(|v| 2.0 * v + normal.sample(&mut rng))
            .collect();
        let rec = Record::new("siso", 1000.0, vec![f], vec![x]).unwrap();
        let frf = h1(
            &[rec],
            Band::new(10.0, 400.0).unwrap(),
            Segmentation::Welch { len: 256 },
            Window::Hann,
        )
        .unwrap();
        let mean: f64 = (0..frf.line_count())
            .map(|k| frf.multiple_coherence(k).unwrap()[0])
            .sum::<f64>()
            / frf.line_count() as f64;
        assert!((mean - 0.8).abs() < 0.01, "mean coherence {mean}");
        let ord = frf.ordinary_coherence(3).unwrap()[(0, 0)];
        assert!((ord - frf.multiple_coherence(3).unwrap()[0]).abs() < 1e-12); // SISO: equal
        // G stays unbiased under output noise (H1): 2 on average.
        let g: f64 = (0..frf.line_count())
            .map(|k| frf.flexibility(k)[(0, 0)].re)
            .sum::<f64>()
            / frf.line_count() as f64;
        assert!((g - 2.0).abs() < 0.01, "mean G {g}");
        // Keeping only some lines moves the rest to the dropped list.
        let kept = frf.retain_lines(|k| k % 2 == 0);
        assert_eq!(
            kept.line_count() + kept.dropped_hz().len(),
            frf.line_count()
        );
        assert!(kept.multiple_coherence(0).is_some());
    }

    #[test]
    fn paired_and_h1_recover_a_constant_flexibility() {
        let g = [[2.0, 0.5], [-0.25, 1.0]];
        let recs = static_records(g);
        let band = Band::new(1.0, 10.0).unwrap();
        let paired = paired_sets(&recs, &[0, 1], band, Window::Rectangular).unwrap();
        let h1 = h1(&recs, band, Segmentation::WholeRecord, Window::Rectangular).unwrap();
        let cross = |e: Estimator| {
            let mut b = FrfBuilder::new(e, band, Segmentation::WholeRecord, Window::Rectangular);
            b.push_all(&recs).unwrap();
            b.finish(&Assignment::DominantForce).unwrap()
        };
        let (h2, hv) = (cross(Estimator::H2), cross(Estimator::Hv));
        assert_eq!(
            (h2.estimator(), hv.estimator()),
            (Estimator::H2, Estimator::Hv)
        );
        for frf in [&paired, &h1, &h2, &hv] {
            assert_eq!(frf.line_count(), 10);
            for k in 0..frf.line_count() {
                for (i, row) in g.iter().enumerate() {
                    for (j, &gij) in row.iter().enumerate() {
                        assert!((frf.flexibility(k)[(i, j)] - c64::new(gij, 0.0)).norm() < 1e-12);
                    }
                }
            }
        }
        assert_eq!(paired.averages(), 1);
        assert_eq!(h1.averages(), 2);
        // One set, two averages for two inputs: no variance can be estimated.
        assert!(paired.impedance_variance(0).is_none() && h1.impedance_variance(0).is_none());
    }

    #[test]
    fn one_direction_only_is_rank_deficient() {
        let recs = static_records([[1.0, 0.0], [0.0, 1.0]]);
        let e = paired_sets(
            &recs,
            &[0, 0],
            Band::new(1.0, 10.0).unwrap(),
            Window::Rectangular,
        )
        .unwrap_err();
        assert_eq!(e, Error::RankDeficient { rank: 1, dofs: 2 });
    }

    #[test]
    fn estimator_names_round_trip() {
        for e in [
            Estimator::PairedSets,
            Estimator::H1,
            Estimator::H2,
            Estimator::Hv,
        ] {
            assert_eq!(e.name().parse::<Estimator>(), Ok(e));
        }
        assert_eq!("H1".parse::<Estimator>(), Ok(Estimator::H1));
        assert!(matches!(
            "H3".parse::<Estimator>(),
            Err(Error::UnknownName {
                what: "estimator",
                ..
            })
        ));
    }

    #[test]
    fn common_shape_names_the_odd_record() {
        let mut recs = static_records([[1.0, 0.0], [0.0, 1.0]]);
        let r = &recs[1];
        let short: Vec<Vec<f64>> = (0..2).map(|c| r.force(c)[..32].to_vec()).collect();
        let shortx: Vec<Vec<f64>> = (0..2).map(|c| r.displacement(c)[..32].to_vec()).collect();
        recs.push(Record::new("short", 64.0, short.clone(), shortx.clone()).unwrap());
        assert!(
            matches!(common_shape(&recs, None), Err(Error::RecordLengthMismatch { ref record, .. }) if record == "short")
        );
        recs.pop();
        recs.push(
            Record::new(
                "slow",
                32.0,
                vec![recs[0].force(0).to_vec(), recs[0].force(1).to_vec()],
                vec![
                    recs[0].displacement(0).to_vec(),
                    recs[0].displacement(1).to_vec(),
                ],
            )
            .unwrap(),
        );
        assert!(matches!(
            common_shape(&recs, None),
            Err(Error::SampleRateMismatch { .. })
        ));
        assert!(matches!(
            common_shape(&recs[..1], Some(3)),
            Err(Error::DofMismatch { expected: 3, .. })
        ));
        assert_eq!(common_shape(&[], None), Err(Error::NoRecords));
    }
}
