//! Stage 3: impedance `H(ω)` and flexibility `G(ω) = H(ω)⁻¹` per frequency line.
//!
//! Two estimators turn the spectra of the records into an [`Frf`]:
//!
//! - [`Estimator::PairedSets`] (the seed's eq. 9). Records are grouped into sets of `n`, one per
//!   linearly independent excitation; per set and line
//!   $H_k = [F^1 \cdots F^n]\,[X^1 \cdots X^n]^{-1}$, then `H` is averaged over the sets.
//! - [`Estimator::H1`] (MIMO H1). All records (and Welch segments) are accumulated into
//!   $S_{xf} = \sum_r X_r F_r^H$ and $S_{ff} = \sum_r F_r F_r^H$; then
//!   $G_1 = S_{xf} S_{ff}^{-1}$ and $H = G_1^{-1}$. No pairing is needed and `G₁` is unbiased
//!   under displacement noise.
//!
//! - [`Estimator::H2`]: $G_2 = S_{xx} S_{fx}^{-1}$, unbiased under force noise.
//! - [`Estimator::Hv`]: per output, the total-least-squares fit of force and displacement
//!   together (smallest eigenvector of the augmented cross-spectral matrix), between H1 and H2
//!   when both channels are noisy.
//!
//! Each line also carries the condition number the next stage judges: `cond([X¹…Xⁿ])` for paired
//! sets (the worst set), `cond(S_ff)` for H1. Lines whose matrices cannot be inverted are dropped
//! and listed in [`Frf::dropped_hz`].

use faer::{Mat, MatRef, c64};

use crate::error::{Channel, Error, Result};
use crate::linalg;
use crate::records::Record;
use crate::spectra::{ForceGate, Segmentation, SpectralEstimator, Window};

/// A frequency band in Hz, edges inclusive. DC is never used.
///
/// # Examples
/// ```
/// use bearing_ident::frf::Band;
/// let band = Band::new(8.0, 49.0)?;
/// // 6700 samples/s × 1.2 s: lines every 0.8333 Hz; 8.33 … 48.33 Hz.
/// let lines = band.lines(6700.0, 8040)?;
/// assert_eq!(lines.len(), 49);
/// assert_eq!(lines[0], 10);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    low_hz: f64,
    high_hz: f64,
}

impl Band {
    /// A band from `low_hz` to `high_hz`, both included.
    ///
    /// # Errors
    /// [`Error::InvalidBand`] unless `0 ≤ low_hz < high_hz` and both are finite.
    pub fn new(low_hz: f64, high_hz: f64) -> Result<Self> {
        if low_hz.is_finite() && high_hz.is_finite() && low_hz >= 0.0 && low_hz < high_hz {
            Ok(Self { low_hz, high_hz })
        } else {
            Err(Error::InvalidBand { low_hz, high_hz })
        }
    }

    /// Lower edge (Hz).
    pub fn low_hz(&self) -> f64 {
        self.low_hz
    }

    /// Upper edge (Hz).
    pub fn high_hz(&self) -> f64 {
        self.high_hz
    }

    /// Indices of the DFT lines in the band for segments of `segment_len` samples at
    /// `sample_rate` Hz. A line within `10⁻⁶` of the spacing of an edge counts as inside; DC
    /// (line 0) is excluded.
    ///
    /// # Errors
    /// [`Error::BandAboveNyquist`] if the upper edge exceeds `sample_rate / 2`.
    pub fn lines(&self, sample_rate: f64, segment_len: usize) -> Result<Vec<usize>> {
        let df = sample_rate / segment_len as f64;
        let nyquist_hz = sample_rate / 2.0;
        let slack = 1e-6 * df;
        if self.high_hz > nyquist_hz + slack {
            return Err(Error::BandAboveNyquist {
                high_hz: self.high_hz,
                nyquist_hz,
            });
        }
        let first = (((self.low_hz - slack) / df).ceil() as usize).max(1);
        let last = ((self.high_hz + slack) / df).floor() as usize;
        Ok((first..=last.min(segment_len / 2)).collect())
    }
}

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
    /// Short name: `"paired"`, `"h1"`, `"h2"` or `"hv"`.
    pub fn name(self) -> &'static str {
        match self {
            Estimator::PairedSets => "paired",
            Estimator::H1 => "h1",
            Estimator::H2 => "h2",
            Estimator::Hv => "hv",
        }
    }

    /// Whether the estimator works on accumulated cross-spectra (all but paired sets).
    pub fn is_cross_spectral(self) -> bool {
        !matches!(self, Estimator::PairedSets)
    }
}

/// Which excitation (degree of freedom) each record belongs to, for [`Estimator::PairedSets`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Assignment {
    /// Each record belongs to the degree of freedom of its strongest force channel
    /// ([`Record::dominant_force`]).
    #[default]
    DominantForce,
    /// Record `r` belongs to excitation `assignment[r]`.
    Explicit(Vec<usize>),
}

impl Assignment {
    /// The excitation index of every record.
    ///
    /// # Errors
    /// [`Error::AssignmentLength`] or [`Error::InvalidAssignment`] for an explicit assignment
    /// that does not fit the records.
    pub fn resolve(&self, records: &[Record], dofs: usize) -> Result<Vec<usize>> {
        let labels: Vec<&str> = records.iter().map(Record::label).collect();
        let dominant: Vec<usize> = records.iter().map(Record::dominant_force).collect();
        self.resolve_with(&labels, &dominant, dofs)
    }

    fn resolve_with(&self, labels: &[&str], dominant: &[usize], dofs: usize) -> Result<Vec<usize>> {
        match self {
            Assignment::DominantForce => Ok(dominant.to_vec()),
            Assignment::Explicit(a) => {
                if a.len() != labels.len() {
                    return Err(Error::AssignmentLength {
                        expected: labels.len(),
                        actual: a.len(),
                    });
                }
                if let Some((r, &excitation)) = a.iter().enumerate().find(|(_, e)| **e >= dofs) {
                    return Err(Error::InvalidAssignment {
                        record: labels[r].to_owned(),
                        excitation,
                        dofs,
                    });
                }
                Ok(a.clone())
            }
        }
    }
}

/// The common shape of a list of records: `(dofs, sample_rate, len)`.
///
/// # Errors
/// [`Error::NoRecords`], or [`Error::DofMismatch`], [`Error::SampleRateMismatch`] (unless
/// [`sample_rates_agree`](crate::records::sample_rates_agree)),
/// [`Error::RecordLengthMismatch`] naming the first record that differs from the first one
/// (or from `dofs`, when given).
pub fn common_shape(records: &[Record], dofs: Option<usize>) -> Result<(usize, f64, usize)> {
    let first = records.first().ok_or(Error::NoRecords)?;
    let n = dofs.unwrap_or(first.dofs());
    for r in records {
        check_against(r, n, first.sample_rate(), first.len())?;
    }
    Ok((n, first.sample_rate(), first.len()))
}

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
                name: "flexibility lines",
                value: flexibility.len() as f64,
                expected: "one matrix per frequency, at least one",
            });
        }
        let n = flexibility[0].nrows();
        let mut out = Frf::empty(n, Estimator::H1);
        let mut g = vec![c64::new(0.0, 0.0); n * n];
        let mut inverter = linalg::Inverter::new(n);
        let mut h = vec![c64::new(0.0, 0.0); n * n];
        let (mut scratch, mut sigma) = (vec![c64::new(0.0, 0.0); n * n], vec![0.0; n]);
        for (&f, m) in freqs_hz.iter().zip(flexibility) {
            if m.nrows() != n || m.ncols() != n || n == 0 {
                return Err(Error::InvalidParameter {
                    name: "flexibility matrix size",
                    value: m.nrows() as f64,
                    expected: "square matrices of one size",
                });
            }
            if !(f.is_finite() && f > 0.0) {
                return Err(Error::InvalidParameter {
                    name: "frequency",
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
                    stage: "given flexibility",
                    freq_hz: f,
                });
            }
            let cond = linalg::condition_number_with(&g, n, &mut scratch, &mut sigma);
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

    fn empty(dofs: usize, estimator: Estimator) -> Self {
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
    fn check_finite(&self) -> Result<()> {
        let (n, nn) = (self.dofs, self.dofs * self.dofs);
        for (k, &freq_hz) in self.freqs_hz.iter().enumerate() {
            let finite = |v: &[c64]| v.iter().all(|z| z.re.is_finite() && z.im.is_finite());
            let stage = if !finite(&self.impedance[k * nn..(k + 1) * nn]) {
                "impedance"
            } else if !finite(&self.flexibility[k * nn..(k + 1) * nn]) {
                "flexibility"
            } else if self
                .multiple_coherence
                .get(k * n..(k + 1) * n)
                .is_some_and(|c| c.iter().any(|g| !g.is_finite()))
            {
                "coherence"
            } else {
                continue;
            };
            return Err(Error::NonFiniteResult { stage, freq_hz });
        }
        Ok(())
    }

    fn push_coherence(&mut self, multiple: &[f64], ordinary: &[f64]) {
        self.multiple_coherence.extend_from_slice(multiple);
        self.ordinary_coherence.extend_from_slice(ordinary);
    }

    fn push_line(&mut self, freq_hz: f64, h: &[c64], g: &[c64], condition: f64) {
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
    pub fn lines(&self) -> usize {
        self.freqs_hz.len()
    }

    /// Frequencies of the usable lines (Hz).
    pub fn freqs_hz(&self) -> &[f64] {
        &self.freqs_hz
    }

    /// Measured impedance `H` at line `k` (`n × n`).
    ///
    /// # Panics
    /// If `k >= self.lines()`.
    pub fn impedance(&self, k: usize) -> MatRef<'_, c64> {
        let nn = self.dofs * self.dofs;
        MatRef::from_column_major_slice(&self.impedance[k * nn..(k + 1) * nn], self.dofs, self.dofs)
    }

    /// Measured flexibility `G = H⁻¹` at line `k` (`n × n`).
    ///
    /// # Panics
    /// If `k >= self.lines()`.
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
    /// - Cross-spectral estimators: the MIMO H1 random error (METHOD.md §2). Row `a` of `G` has
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
        for k in 0..self.lines() {
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

/// Multiple and ordinary coherences at one line from `S_ff`, its inverse, `S_xf` (all `n × n`
/// column-major) and the output auto-spectra `S_xᵢxᵢ`.
fn line_coherence(
    n: usize,
    sff: &[c64],
    sff_inv: &[c64],
    sxf: &[c64],
    sxx: &[f64],
    multiple: &mut [f64],
    ordinary: &mut [f64],
) {
    for i in 0..n {
        let mut explained = c64::new(0.0, 0.0);
        for a in 0..n {
            for b in 0..n {
                explained += sxf[i + a * n] * sff_inv[a + b * n] * sxf[i + b * n].conj();
            }
        }
        multiple[i] = explained.re / sxx[i];
        for j in 0..n {
            ordinary[i + j * n] = sxf[i + j * n].norm_sqr() / (sxx[i] * sff[j + j * n].re);
        }
    }
}

/// What one record contributes to an estimator, computed independently of the others (so that
/// records can be transformed in parallel and merged in order, bit for bit the same).
#[derive(Debug, Clone)]
enum Contribution {
    /// Band-line spectra `[line][channel]` for paired sets.
    Spectra {
        forces: Vec<c64>,
        displacements: Vec<c64>,
    },
    /// This record's sums over its segments of `F Fᴴ`, `X Fᴴ` and `X Xᴴ`, `[line][n × n]`,
    /// and of `F` and `X`, `[line][n]` (the first moments maximum likelihood needs).
    Cross {
        sff: Vec<c64>,
        sxf: Vec<c64>,
        sxx: Vec<c64>,
        sf: Vec<c64>,
        sx: Vec<c64>,
    },
}

/// Everything an [`FrfBuilder`] has gathered from one record.
#[derive(Debug, Clone)]
struct Gathered {
    label: String,
    dominant: usize,
    contribution: Contribution,
}

/// Each paired set's own impedance per band line ([`FrfBuilder::set_impedances`]).
#[derive(Debug, Clone)]
pub(crate) struct SetImpedances {
    /// Records (push order) of each set, one per direction.
    pub(crate) records: Vec<Vec<usize>>,
    /// `[set][line]`: `H_s`, `None` where the set's displacements are singular.
    pub(crate) impedances: Vec<Vec<Option<Mat<c64>>>>,
}

/// The fixed settings of a builder once the first record has fixed the shape.
#[derive(Debug, Clone)]
struct Plan {
    n: usize,
    sample_rate: f64,
    len: usize,
    seg_len: usize,
    lines: Vec<usize>,
    resolution_hz: f64,
}

/// Collects records one at a time into what an estimator needs — band-line spectra for paired
/// sets, accumulated cross-spectra for H1 — and keeps no time data, so memory does not grow with
/// record length and, for H1, not with the number of records either.
///
/// # Examples
/// ```
/// use bearing_ident::frf::{Assignment, Band, Estimator, FrfBuilder};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// use bearing_ident::spectra::{Segmentation, Window};
/// let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let mut builder = FrfBuilder::new(
///     Estimator::PairedSets, Band::new(8.0, 49.0)?, Segmentation::WholeRecord, Window::Rectangular);
/// for r in &records {
///     builder.push(r)?; // each record may be dropped after this
/// }
/// let frf = builder.finish(&Assignment::DominantForce)?;
/// assert_eq!(frf.lines(), 49);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug)]
pub struct FrfBuilder {
    estimator: Estimator,
    band: Band,
    segmentation: Segmentation,
    window: Window,
    dofs: Option<usize>,
    force_gate: Option<ForceGate>,
    plan: Option<(Plan, SpectralEstimator)>,
    gathered: Vec<Gathered>,
    /// Cross-spectral totals, merged record by record.
    sff: Vec<c64>,
    sxf: Vec<c64>,
    sxx: Vec<c64>,
    averages: usize,
    /// Keep each H1 record's own sums too (for leave-one-out replicates).
    keep_partials: bool,
    /// The first record with every force or every displacement channel flat.
    dead: Option<Error>,
}

impl FrfBuilder {
    /// A builder for `estimator` over `band`. Paired sets always use whole records.
    pub fn new(
        estimator: Estimator,
        band: Band,
        segmentation: Segmentation,
        window: Window,
    ) -> Self {
        let segmentation = match estimator {
            Estimator::PairedSets => Segmentation::WholeRecord,
            _ => segmentation,
        };
        Self {
            estimator,
            band,
            segmentation,
            window,
            dofs: None,
            force_gate: None,
            plan: None,
            gathered: Vec::new(),
            sff: Vec::new(),
            sxf: Vec::new(),
            sxx: Vec::new(),
            averages: 0,
            keep_partials: false,
            dead: None,
        }
    }

    /// Requires every record to have `n` degrees of freedom (default: the first record's).
    pub fn dofs(mut self, n: usize) -> Self {
        self.dofs = Some(n);
        self
    }

    /// Gates every force channel with `gate` ([`ForceGate`]) before its transform.
    pub fn force_gate(mut self, gate: ForceGate) -> Self {
        self.force_gate = Some(gate);
        self
    }

    /// Keeps every H1 record's own cross-spectra as well as the totals, so that
    /// [`FrfBuilder::finish_leaving_out`] can drop one (memory then grows with the records).
    pub(crate) fn keeping_partials(mut self) -> Self {
        self.keep_partials = true;
        self
    }

    /// Number of leave-one-out replicates: paired sets (paired), records (H1, which needs
    /// [`FrfBuilder::keeping_partials`]; 0 without).
    pub(crate) fn replicates(&self, assignment: &Assignment) -> Result<usize> {
        match self.estimator {
            Estimator::PairedSets => {
                let n = self.plan.as_ref().map_or(0, |(p, _)| p.n);
                let excitation = self.excitations(assignment)?;
                Ok((0..n)
                    .map(|d| excitation.iter().filter(|&&e| e == d).count())
                    .min()
                    .unwrap_or(0))
            }
            _ if self.keep_partials => Ok(self.gathered.len()),
            _ => Ok(0),
        }
    }

    /// [`FrfBuilder::finish`] with replicate `r` (paired set `r`, or record `r` of a
    /// cross-spectral estimator, which needs [`FrfBuilder::keeping_partials`]) counted
    /// `weights[r]` times: 0 leaves it out (jackknife), bootstrap counts resample. No error
    /// bars are computed for weighted finishes.
    pub(crate) fn finish_weighted(&self, assignment: &Assignment, weights: &[f64]) -> Result<Frf> {
        let (plan, _) = self.plan.as_ref().ok_or(Error::NoRecords)?;
        if self.estimator == Estimator::PairedSets {
            self.finish_paired(plan, &self.excitations(assignment)?, Some(weights))
        } else {
            Ok(self.finish_cross(plan, Some(weights)))
        }
    }

    /// Mean spectra of every record over its periods and the pooled noise covariances of
    /// those means, on the lines of `frf` (see [`crate::solve::ml`]). Each record is one
    /// column (one independent excitation). Needs [`Segmentation::Periods`], at least 3
    /// periods per record, and [`FrfBuilder::keeping_partials`].
    ///
    /// With `P` periods, record `r`'s sample covariance of one period's spectra is
    /// `(Σ_p x_p x_pᴴ − P x̄ x̄ᴴ)/(P − 1)`; that of the mean is `1/P` of it; the records' are
    /// averaged (the noise is the same in every record).
    pub(crate) fn ml_data(&self, frf: &Frf) -> Result<crate::solve::ml::MlData> {
        let (plan, _) = self.plan.as_ref().ok_or(Error::NoRecords)?;
        let periods = self.segmentation.starts(plan.len).count();
        if !matches!(self.segmentation, Segmentation::Periods { .. })
            || periods < 3
            || !self.keep_partials
        {
            return Err(Error::MlNeedsRepeats);
        }
        let (n, nn) = (plan.n, plan.n * plan.n);
        let p = periods as f64;
        let records = self.gathered.len();
        let (mut x, mut f) = (Vec::new(), Vec::new());
        let (mut cx, mut cf, mut cxf) = (Vec::new(), Vec::new(), Vec::new());
        let mut freqs = Vec::new();
        for (l, &k) in plan.lines.iter().enumerate() {
            let freq = k as f64 * plan.resolution_hz;
            // The FRF's lines are these very values (same computation): exact lookup.
            if frf
                .freqs_hz()
                .binary_search_by(|u| u.total_cmp(&freq))
                .is_err()
            {
                continue;
            }
            freqs.push(freq);
            let mut xm = Mat::<c64>::zeros(n, records);
            let mut fm = Mat::<c64>::zeros(n, records);
            let mut covs = [Mat::<c64>::zeros(n, n), Mat::zeros(n, n), Mat::zeros(n, n)];
            for (r, g) in self.gathered.iter().enumerate() {
                let Contribution::Cross {
                    sff,
                    sxf,
                    sxx,
                    sf,
                    sx,
                } = &g.contribution
                else {
                    return Err(Error::MlNeedsRepeats);
                };
                let (mx, mf) = (&sx[l * n..(l + 1) * n], &sf[l * n..(l + 1) * n]);
                for i in 0..n {
                    xm[(i, r)] = mx[i] / p;
                    fm[(i, r)] = mf[i] / p;
                }
                let second = [&sxx, &sff, &sxf];
                let firsts = [(mx, mx), (mf, mf), (mx, mf)];
                for ((cov, s2), (a, b)) in covs.iter_mut().zip(second).zip(firsts) {
                    for j in 0..n {
                        for i in 0..n {
                            let centred = s2[l * nn + i + j * n] - a[i] * b[j].conj() / p;
                            cov[(i, j)] += centred / ((p - 1.0) * p * records as f64);
                        }
                    }
                }
            }
            x.push(xm);
            f.push(fm);
            let [a, b, c] = covs;
            cx.push(a);
            cf.push(b);
            cxf.push(c);
        }
        crate::solve::ml::MlData::new(freqs, &x, &f, &cx, &cf, &cxf)
    }

    /// Number of records pushed.
    pub fn records(&self) -> usize {
        self.gathered.len()
    }

    /// Label of record `index` (push order).
    pub(crate) fn label(&self, index: usize) -> &str {
        &self.gathered[index].label
    }

    /// Whether every record pushed can be taken out again by [`FrfBuilder::remove`]: always
    /// for paired sets (each record's spectra are kept), for cross-spectral estimators only
    /// with [`FrfBuilder::keeping_partials`].
    pub(crate) fn can_remove(&self) -> bool {
        !self.estimator.is_cross_spectral() || self.keep_partials
    }

    /// Takes the records at `indices` (push order) back out, as if they had never been pushed:
    /// cross-spectral totals are summed again from the remaining records' partials, in order,
    /// so the result is bit for bit that of pushing only the others. Does nothing unless
    /// [`FrfBuilder::can_remove`].
    pub(crate) fn remove(&mut self, indices: &[usize]) {
        if !self.can_remove() || indices.is_empty() {
            return;
        }
        let mut index = 0;
        self.gathered.retain(|_| {
            index += 1;
            !indices.contains(&(index - 1))
        });
        if !self.estimator.is_cross_spectral() {
            self.averages = self.gathered.len();
            return;
        }
        let Some((plan, _)) = self.plan.as_ref() else {
            return;
        };
        let segments = self.segmentation.starts(plan.len).count();
        let zero = c64::new(0.0, 0.0);
        for totals in [&mut self.sff, &mut self.sxf, &mut self.sxx] {
            totals.fill(zero);
        }
        for g in &self.gathered {
            if let Contribution::Cross { sff, sxf, sxx, .. } = &g.contribution {
                for (totals, part) in [
                    (&mut self.sff, sff),
                    (&mut self.sxf, sxf),
                    (&mut self.sxx, sxx),
                ] {
                    totals.iter_mut().zip(part).for_each(|(t, p)| *t += p);
                }
            }
        }
        self.averages = segments * self.gathered.len();
    }

    /// Each paired set's own impedance `H_s = F_s X_s⁻¹` on every band line, `None` where
    /// `X_s` is singular, with the records (push order) of each set, one per direction.
    /// Empty unless paired sets.
    ///
    /// # Errors
    /// As [`FrfBuilder::excitations`].
    pub(crate) fn set_impedances(&self, assignment: &Assignment) -> Result<SetImpedances> {
        let mut out = SetImpedances {
            records: Vec::new(),
            impedances: Vec::new(),
        };
        let Some((plan, _)) = self.plan.as_ref() else {
            return Ok(out);
        };
        if self.estimator != Estimator::PairedSets {
            return Ok(out);
        }
        let n = plan.n;
        let mut by_direction: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (r, &e) in self.excitations(assignment)?.iter().enumerate() {
            by_direction[e].push(r);
        }
        let sets = by_direction.iter().map(Vec::len).min().unwrap_or(0);
        let nn = n * n;
        let zero = c64::new(0.0, 0.0);
        let (mut x, mut f, mut h) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
        let mut inverter = linalg::Inverter::new(n);
        for s in 0..sets {
            let records: Vec<usize> = by_direction.iter().map(|d| d[s]).collect();
            let mut lines = Vec::with_capacity(plan.lines.len());
            for l in 0..plan.lines.len() {
                for (j, &r) in records.iter().enumerate() {
                    let Contribution::Spectra {
                        forces,
                        displacements,
                    } = &self.gathered[r].contribution
                    else {
                        return Ok(out);
                    };
                    x[j * n..(j + 1) * n].copy_from_slice(&displacements[l * n..(l + 1) * n]);
                    f[j * n..(j + 1) * n].copy_from_slice(&forces[l * n..(l + 1) * n]);
                }
                lines.push(inverter.invert(&mut x).then(|| {
                    linalg::mul_into(&f, &x, &mut h, n);
                    Mat::from_fn(n, n, |i, j| h[i + j * n])
                }));
            }
            out.records.push(records);
            out.impedances.push(lines);
        }
        Ok(out)
    }

    /// Checks `record` against the first one and fixes the plan on the first call.
    fn check(&mut self, record: &Record) -> Result<()> {
        match &self.plan {
            None => {
                let n = self.dofs.unwrap_or(record.dofs());
                common_shape(std::slice::from_ref(record), Some(n))?;
                let seg_len = self.segmentation.segment_len(record.len())?;
                let lines = self.band.lines(record.sample_rate(), seg_len)?;
                let spectral = SpectralEstimator::new(seg_len, record.sample_rate(), self.window)?;
                let plan = Plan {
                    n,
                    sample_rate: record.sample_rate(),
                    len: record.len(),
                    seg_len,
                    resolution_hz: spectral.resolution_hz(),
                    lines,
                };
                let size = plan.lines.len() * n * n;
                if self.estimator.is_cross_spectral() {
                    self.sff = vec![c64::new(0.0, 0.0); size];
                    self.sxf = vec![c64::new(0.0, 0.0); size];
                    self.sxx = vec![c64::new(0.0, 0.0); size];
                }
                let spectral = match self.force_gate {
                    Some(gate) => spectral.with_force_gate(gate),
                    None => spectral,
                };
                self.plan = Some((plan, spectral));
                Ok(())
            }
            Some((plan, _)) => check_against(record, plan.n, plan.sample_rate, plan.len),
        }
    }

    /// Adds one record.
    ///
    /// # Errors
    /// [`Error::DofMismatch`], [`Error::SampleRateMismatch`], [`Error::RecordLengthMismatch`]
    /// against the first record (rates compared by
    /// [`sample_rates_agree`](crate::records::sample_rates_agree)); on the first record,
    /// [`Error::BandAboveNyquist`] and [`Error::InvalidParameter`] for a bad Welch segment
    /// length; [`Error::SpectrumOverflow`] naming the record, channel and line when its
    /// spectra or cross-spectra (or the running totals) overflow.
    pub fn push(&mut self, record: &Record) -> Result<()> {
        self.check(record)?;
        let (plan, spectral) = self.plan.as_mut().expect("set by check");
        let contribution = contribute(self.estimator, self.segmentation, plan, spectral, record)?;
        self.merge(record, contribution)
    }

    /// Adds every record of a slice. With the `rayon` feature the records are transformed in
    /// parallel and merged in order: the result is bit for bit that of [`FrfBuilder::push`] in
    /// a loop.
    ///
    /// # Errors
    /// As [`FrfBuilder::push`], for the first record that fails.
    pub fn push_all(&mut self, records: &[Record]) -> Result<()> {
        let Some(first) = records.first() else {
            return Ok(());
        };
        self.check(first)?;
        for r in &records[1..] {
            self.check(r)?;
        }
        let (plan, spectral) = self.plan.as_mut().expect("set by check");
        let (estimator, segmentation) = (self.estimator, self.segmentation);
        #[cfg(feature = "rayon")]
        let contributions: Vec<Result<Contribution>> = {
            use rayon::prelude::*;
            let (plan, spectral) = (&*plan, &*spectral);
            records
                .par_iter()
                .map_init(
                    || spectral.clone(),
                    |est, r| contribute(estimator, segmentation, plan, est, r),
                )
                .collect()
        };
        #[cfg(not(feature = "rayon"))]
        let contributions: Vec<Result<Contribution>> = records
            .iter()
            .map(|r| contribute(estimator, segmentation, plan, spectral, r))
            .collect();
        for (r, c) in records.iter().zip(contributions) {
            self.merge(r, c?)?;
        }
        Ok(())
    }

    /// Adds `contribution` to what was gathered.
    ///
    /// # Errors
    /// [`Error::SpectrumOverflow`] when the accumulated cross-spectra overflow with this
    /// record; [`Error::DeadChannel`] is only noted here (see [`FrfBuilder::finish`]).
    fn merge(&mut self, record: &Record, contribution: Contribution) -> Result<()> {
        if self.dead.is_none() {
            self.dead = dead_channel(record);
        }
        let contribution = match contribution {
            Contribution::Cross {
                sff,
                sxf,
                sxx,
                sf,
                sx,
            } => {
                for (totals, part) in [
                    (&mut self.sff, &sff),
                    (&mut self.sxf, &sxf),
                    (&mut self.sxx, &sxx),
                ] {
                    totals.iter_mut().zip(part).for_each(|(t, p)| *t += p);
                }
                if let Some((plan, _)) = &self.plan {
                    let nn = plan.n * plan.n;
                    for (totals, channel) in [
                        (&self.sff, Channel::Force as fn(usize) -> Channel),
                        (&self.sxf, Channel::Displacement),
                        (&self.sxx, Channel::Displacement),
                    ] {
                        overflow_check(
                            record,
                            plan,
                            "accumulated cross-spectrum",
                            totals,
                            nn,
                            channel,
                        )?;
                    }
                }
                self.averages += self.segmentation.starts(record.len()).count();
                if self.keep_partials {
                    Contribution::Cross {
                        sff,
                        sxf,
                        sxx,
                        sf,
                        sx,
                    }
                } else {
                    // Only the totals are kept.
                    Contribution::Cross {
                        sff: Vec::new(),
                        sxf: Vec::new(),
                        sxx: Vec::new(),
                        sf: Vec::new(),
                        sx: Vec::new(),
                    }
                }
            }
            spectra => {
                self.averages += 1;
                spectra
            }
        };
        self.gathered.push(Gathered {
            label: record.label().to_owned(),
            dominant: record.dominant_force(),
            contribution,
        });
        Ok(())
    }

    /// The first record pushed whose force channels, or whose displacement channels, are all
    /// flat (constant over the whole record), as [`Error::DeadChannel`]: the true cause when
    /// an identification cannot go on (rank-deficient excitations or a singular fit).
    pub fn dead_channel(&self) -> Option<Error> {
        self.dead.clone()
    }

    /// The excitation of every record pushed, by `assignment`.
    ///
    /// # Errors
    /// As [`Assignment::resolve`].
    pub fn excitations(&self, assignment: &Assignment) -> Result<Vec<usize>> {
        let n = self.plan.as_ref().map_or(0, |(p, _)| p.n);
        let labels: Vec<&str> = self.gathered.iter().map(|g| g.label.as_str()).collect();
        let dominant: Vec<usize> = self.gathered.iter().map(|g| g.dominant).collect();
        assignment.resolve_with(&labels, &dominant, n)
    }

    /// Impedances and flexibilities from everything pushed.
    ///
    /// # Errors
    /// [`Error::NoRecords`] if nothing was pushed; for paired sets, the assignment errors and
    /// [`Error::RankDeficient`] when some direction has no record;
    /// [`Error::NonFiniteResult`] at the first line whose impedance, flexibility or coherence
    /// is not finite. (A record with all its forces or displacements flat is kept aside as
    /// [`FrfBuilder::dead_channel`] for the caller to report.)
    pub fn finish(&self, assignment: &Assignment) -> Result<Frf> {
        let (plan, _) = self.plan.as_ref().ok_or(Error::NoRecords)?;
        let frf = if self.estimator == Estimator::PairedSets {
            self.finish_paired(plan, &self.excitations(assignment)?, None)?
        } else {
            self.finish_cross(plan, None)
        };
        frf.check_finite()?;
        Ok(frf)
    }

    fn finish_paired(
        &self,
        plan: &Plan,
        excitation: &[usize],
        weights: Option<&[f64]>,
    ) -> Result<Frf> {
        let n = plan.n;
        let mut by_direction: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (r, &e) in excitation.iter().enumerate() {
            by_direction[e].push(r);
        }
        let rank = by_direction.iter().filter(|d| !d.is_empty()).count();
        if rank < n {
            return Err(Error::RankDeficient { rank, dofs: n });
        }
        let sets = by_direction.iter().map(Vec::len).min().unwrap_or(0);
        let mut frf = Frf::empty(n, Estimator::PairedSets);
        frf.spacing_hz = Some(plan.resolution_hz);
        let weight = |s: usize| weights.map_or(1.0, |w| w.get(s).copied().unwrap_or(0.0));
        let used: Vec<usize> = (0..sets).filter(|&s| weight(s) > 0.0).collect();
        let total_weight: f64 = used.iter().map(|&s| weight(s)).sum();
        frf.averages = used.len();
        frf.unpaired = by_direction
            .iter()
            .flat_map(|d| d[sets..].iter().map(|&r| self.gathered[r].label.clone()))
            .collect();
        let spectra = |r: usize| match &self.gathered[r].contribution {
            Contribution::Spectra {
                forces,
                displacements,
            } => (forces, displacements),
            Contribution::Cross { .. } => unreachable!("paired builders gather spectra"),
        };
        // Scatter of the per-set impedances, for the error bars of the unweighted finish.
        let with_variance = weights.is_none() && used.len() >= 2;
        let nn = n * n;
        let zero = c64::new(0.0, 0.0);
        let (mut x, mut f, mut hs) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
        let (mut h, mut g, mut scratch) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
        let (mut inverter, mut sigma) = (linalg::Inverter::new(n), vec![0.0; n]);
        let (mut sff, mut sxf, mut inv) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
        let (mut sxx, mut multiple, mut ordinary) = (vec![0.0; n], vec![0.0; n], vec![0.0; nn]);
        let mut per_set = vec![zero; if with_variance { used.len() * nn } else { 0 }];
        let mut variance = vec![0.0; nn];
        'line: for (l, &k) in plan.lines.iter().enumerate() {
            let freq = k as f64 * plan.resolution_hz;
            h.fill(zero);
            let mut worst = 0.0_f64;
            for (u, &s) in used.iter().enumerate() {
                for (j, dir) in by_direction.iter().enumerate() {
                    let (fr, xr) = spectra(dir[s]);
                    x[j * n..(j + 1) * n].copy_from_slice(&xr[l * n..(l + 1) * n]);
                    f[j * n..(j + 1) * n].copy_from_slice(&fr[l * n..(l + 1) * n]);
                }
                worst = worst.max(linalg::condition_number_with(
                    &x,
                    n,
                    &mut scratch,
                    &mut sigma,
                ));
                if !inverter.invert(&mut x) {
                    frf.dropped_hz.push(freq);
                    continue 'line;
                }
                linalg::mul_into(&f, &x, &mut hs, n);
                let w = weight(s) / total_weight;
                for (a, b) in h.iter_mut().zip(&hs) {
                    *a += b * w;
                }
                if with_variance {
                    per_set[u * nn..(u + 1) * nn].copy_from_slice(&hs);
                }
            }
            g.copy_from_slice(&h);
            if inverter.invert(&mut g) {
                frf.push_line(freq, &h, &g, worst);
                if with_variance {
                    let sets = used.len() as f64;
                    variance.fill(0.0);
                    for set in per_set.chunks_exact(nn) {
                        for ((v, a), b) in variance.iter_mut().zip(set).zip(&h) {
                            *v += (a - b).norm_sqr() / (sets * (sets - 1.0));
                        }
                    }
                    frf.impedance_variance.extend_from_slice(&variance);
                }
                // Coherence from the cross-spectra of all records at this line.
                sff.fill(zero);
                sxf.fill(zero);
                sxx.fill(0.0);
                for r in 0..self.gathered.len() {
                    let (fr, xr) = spectra(r);
                    let (fl, xl) = (&fr[l * n..(l + 1) * n], &xr[l * n..(l + 1) * n]);
                    for j in 0..n {
                        let fj = fl[j].conj();
                        for i in 0..n {
                            sff[i + j * n] += fl[i] * fj;
                            sxf[i + j * n] += xl[i] * fj;
                        }
                    }
                    for (t, x) in sxx.iter_mut().zip(xl) {
                        *t += x.norm_sqr();
                    }
                }
                inv.copy_from_slice(&sff);
                if inverter.invert(&mut inv) {
                    line_coherence(n, &sff, &inv, &sxf, &sxx, &mut multiple, &mut ordinary);
                } else {
                    multiple.fill(0.0);
                    ordinary.fill(0.0);
                }
                frf.push_coherence(&multiple, &ordinary);
            } else {
                frf.dropped_hz.push(freq);
            }
        }
        Ok(frf)
    }

    /// The cross-spectral totals, or their sums over records weighted by `weights` (which needs
    /// the partials), with the number of averages they hold.
    fn cross_totals(&self, plan: &Plan, weights: Option<&[f64]>) -> (Cross, f64) {
        let segments = self.segmentation.starts(plan.len).count() as f64;
        let Some(weights) = weights else {
            let totals = Cross {
                sff: self.sff.clone(),
                sxf: self.sxf.clone(),
                sxx: self.sxx.clone(),
            };
            return (totals, self.averages as f64);
        };
        let zero = c64::new(0.0, 0.0);
        let mut totals = Cross {
            sff: vec![zero; self.sff.len()],
            sxf: vec![zero; self.sxf.len()],
            sxx: vec![zero; self.sxx.len()],
        };
        let mut averages = 0.0;
        for (g, &w) in self.gathered.iter().zip(weights) {
            if let Contribution::Cross { sff, sxf, sxx, .. } = &g.contribution {
                if w == 0.0 || sff.is_empty() {
                    continue;
                }
                averages += w * segments;
                let add = |t: &mut Vec<c64>, p: &Vec<c64>| {
                    t.iter_mut().zip(p).for_each(|(t, p)| *t += p * w);
                };
                add(&mut totals.sff, sff);
                add(&mut totals.sxf, sxf);
                add(&mut totals.sxx, sxx);
            }
        }
        (totals, averages)
    }

    fn finish_cross(&self, plan: &Plan, weights: Option<&[f64]>) -> Frf {
        let n = plan.n;
        let nn = n * n;
        let zero = c64::new(0.0, 0.0);
        let mut frf = Frf::empty(n, self.estimator);
        frf.spacing_hz = Some(plan.resolution_hz);
        let (Cross { sff, sxf, sxx }, averages) = self.cross_totals(plan, weights);
        frf.averages = averages.round() as usize;
        // Lines the excitation drives (periodic excitation leaves the others empty).
        let power = |l: usize| (0..n).map(|i| sff[l * nn + i * (n + 1)].re).sum::<f64>();
        let strongest = (0..plan.lines.len()).map(power).fold(0.0, f64::max);
        let periodic = matches!(self.segmentation, Segmentation::Periods { .. });
        let with_variance = weights.is_none() && averages > n as f64;
        let (mut inv, mut g, mut h) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
        let (mut scratch, mut inverter, mut sigma) =
            (vec![zero; nn], linalg::Inverter::new(n), vec![0.0; n]);
        let (mut multiple, mut ordinary) = (vec![0.0; n], vec![0.0; nn]);
        let (mut auto, mut variance) = (vec![0.0; n], vec![0.0; nn]);
        for (l, &k) in plan.lines.iter().enumerate() {
            let freq = k as f64 * plan.resolution_hz;
            if periodic && power(l) < UNEXCITED_RATIO * strongest {
                frf.unexcited_hz.push(freq);
                continue;
            }
            let range = l * nn..(l + 1) * nn;
            let (sf, sx, ss) = (&sff[range.clone()], &sxf[range.clone()], &sxx[range]);
            let cond = linalg::condition_number_with(sf, n, &mut scratch, &mut sigma);
            inv.copy_from_slice(sf);
            let ok = inverter.invert(&mut inv)
                && match self.estimator {
                    Estimator::H2 => {
                        // H = S_fx S_xx⁻¹ with S_fx = S_xfᴴ.
                        scratch.copy_from_slice(ss);
                        inverter.invert(&mut scratch) && {
                            for j in 0..n {
                                for i in 0..n {
                                    g[i + j * n] = sx[j + i * n].conj();
                                }
                            }
                            linalg::mul_into(&g, &scratch, &mut h, n);
                            g.copy_from_slice(&h);
                            inverter.invert(&mut g)
                        }
                    }
                    Estimator::Hv => {
                        hv_flexibility(n, sf, sx, ss, &mut g) && {
                            h.copy_from_slice(&g);
                            inverter.invert(&mut h)
                        }
                    }
                    _ => {
                        linalg::mul_into(sx, &inv, &mut g, n);
                        h.copy_from_slice(&g);
                        inverter.invert(&mut h)
                    }
                };
            if !ok {
                frf.dropped_hz.push(freq);
                continue;
            }
            frf.push_line(freq, &h, &g, cond);
            for (i, a) in auto.iter_mut().enumerate() {
                *a = ss[i * (n + 1)].re;
            }
            line_coherence(n, sf, &inv, sx, &auto, &mut multiple, &mut ordinary);
            frf.push_coherence(&multiple, &ordinary);
            if with_variance {
                h1_impedance_variance(n, &h, &inv, &auto, &multiple, averages, &mut variance);
                frf.impedance_variance.extend_from_slice(&variance);
            }
        }
        frf
    }
}

/// Cross-spectral sums `S_ff`, `S_xf`, `S_xx`, `[line][n × n]` column-major.
struct Cross {
    sff: Vec<c64>,
    sxf: Vec<c64>,
    sxx: Vec<c64>,
}

/// Band lines whose force power `tr S_ff` is below this fraction of the band's strongest line
/// are not excited (periodic segmentation): −20 dB, far above a broadband noise floor spread
/// over every line and far below the lines a multisine drives.
pub const UNEXCITED_RATIO: f64 = 1e-2;

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

/// `E|δH_ij|²` at one line from the MIMO H1 random error (see [`Frf::impedance_variance`]):
/// `sff_inv = S_ff⁻¹`, `auto[i] = S_xᵢxᵢ`, `multiple[i] = γ²ᵢ:f`, `averages = n_d`.
fn h1_impedance_variance(
    n: usize,
    h: &[c64],
    sff_inv: &[c64],
    auto: &[f64],
    multiple: &[f64],
    averages: f64,
    out: &mut [f64],
) {
    let dof = averages - n as f64;
    for j in 0..n {
        // q_j = h_jᴴ S_ff⁻¹ h_j (real: S_ff⁻¹ is Hermitian).
        let mut q = c64::new(0.0, 0.0);
        for b in 0..n {
            for a in 0..n {
                q += h[a + j * n].conj() * sff_inv[a + b * n] * h[b + j * n];
            }
        }
        for i in 0..n {
            out[i + j * n] = (0..n)
                .map(|a| {
                    let noise = (auto[a] * (1.0 - multiple[a])).max(0.0) / dof;
                    h[i + a * n].norm_sqr() * noise
                })
                .sum::<f64>()
                * q.re.max(0.0);
        }
    }
}

/// `record` against the common shape `(n, sample_rate, len)`.
fn check_against(record: &Record, n: usize, sample_rate: f64, len: usize) -> Result<()> {
    if record.dofs() != n {
        return Err(Error::DofMismatch {
            record: record.label().to_owned(),
            expected: n,
            actual: record.dofs(),
        });
    }
    if !crate::records::sample_rates_agree(record.sample_rate(), sample_rate, len) {
        return Err(Error::SampleRateMismatch {
            record: record.label().to_owned(),
            expected: sample_rate,
            actual: record.sample_rate(),
        });
    }
    if record.len() != len {
        return Err(Error::RecordLengthMismatch {
            record: record.label().to_owned(),
            expected: len,
            actual: record.len(),
        });
    }
    Ok(())
}

/// One record's contribution: its band-line spectra (paired) or its segment sums (H1).
fn contribute(
    estimator: Estimator,
    segmentation: Segmentation,
    plan: &Plan,
    spectral: &mut SpectralEstimator,
    record: &Record,
) -> Result<Contribution> {
    let (n, lines) = (plan.n, &plan.lines);
    let zero = c64::new(0.0, 0.0);
    let mut forces = vec![zero; lines.len() * n];
    let mut displacements = vec![zero; lines.len() * n];
    let mut transform = |start: usize, forces: &mut [c64], displacements: &mut [c64]| {
        let seg = start..start + plan.seg_len;
        for c in 0..n {
            let spec = spectral.transform_force(&record.force(c)[seg.clone()]);
            for (l, &k) in lines.iter().enumerate() {
                forces[l * n + c] = spec[k];
            }
            let spec = spectral.transform(&record.displacement(c)[seg.clone()]);
            for (l, &k) in lines.iter().enumerate() {
                displacements[l * n + c] = spec[k];
            }
        }
        for (values, channel) in [
            (&*forces, Channel::Force as fn(usize) -> Channel),
            (&*displacements, Channel::Displacement),
        ] {
            overflow_check(record, plan, "spectrum", values, n, channel)?;
        }
        Ok::<(), Error>(())
    };
    match estimator {
        Estimator::PairedSets => {
            transform(0, &mut forces, &mut displacements)?;
            Ok(Contribution::Spectra {
                forces,
                displacements,
            })
        }
        _ => {
            let nn = n * n;
            let mut sff = vec![zero; lines.len() * nn];
            let mut sxf = vec![zero; lines.len() * nn];
            let mut sxx = vec![zero; lines.len() * nn];
            let mut sf = vec![zero; lines.len() * n];
            let mut sx = vec![zero; lines.len() * n];
            for start in segmentation.starts(record.len()) {
                transform(start, &mut forces, &mut displacements)?;
                for (t, v) in sf.iter_mut().zip(&forces) {
                    *t += v;
                }
                for (t, v) in sx.iter_mut().zip(&displacements) {
                    *t += v;
                }
                for l in 0..lines.len() {
                    let (fl, xl) = (
                        &forces[l * n..(l + 1) * n],
                        &displacements[l * n..(l + 1) * n],
                    );
                    let (sf, sx, ss) = (
                        &mut sff[l * nn..(l + 1) * nn],
                        &mut sxf[l * nn..(l + 1) * nn],
                        &mut sxx[l * nn..(l + 1) * nn],
                    );
                    for j in 0..n {
                        let (fj, xj) = (fl[j].conj(), xl[j].conj());
                        for i in 0..n {
                            sf[i + j * n] += fl[i] * fj;
                            sx[i + j * n] += xl[i] * fj;
                            ss[i + j * n] += xl[i] * xj;
                        }
                    }
                }
            }
            for (values, channel) in [
                (&sff, Channel::Force as fn(usize) -> Channel),
                (&sxf, Channel::Displacement),
                (&sxx, Channel::Displacement),
            ] {
                overflow_check(record, plan, "cross-spectrum", values, nn, channel)?;
            }
            Ok(Contribution::Cross {
                sff,
                sxf,
                sxx,
                sf,
                sx,
            })
        }
    }
}

/// [`Error::DeadChannel`] if every force channel, or every displacement channel, of `record`
/// is constant over the whole record.
fn dead_channel(record: &Record) -> Option<Error> {
    let flat = |v: &[f64]| v.iter().all(|x| (x - v[0]).abs() <= 0.0);
    let n = record.dofs();
    let forces = (0..n).all(|c| flat(record.force(c)));
    let displacements = (0..n).all(|c| flat(record.displacement(c)));
    let channel = match (forces, displacements) {
        (true, _) => Channel::Force(0),
        (false, true) => Channel::Displacement(0),
        (false, false) => return None,
    };
    let value = match channel {
        Channel::Force(c) => record.force(c)[0],
        Channel::Displacement(c) => record.displacement(c)[0],
    };
    Some(Error::DeadChannel {
        record: record.label().to_owned(),
        channel,
        value,
    })
}

/// [`Error::SpectrumOverflow`] at the first non-finite value of `values` (`[line][stride]`;
/// within a line, value `v` belongs to `channel(v % n)`, the row of an `n × n` matrix).
fn overflow_check(
    record: &Record,
    plan: &Plan,
    stage: &'static str,
    values: &[c64],
    stride: usize,
    channel: fn(usize) -> Channel,
) -> Result<()> {
    let Some(at) = values
        .iter()
        .position(|z| !(z.re.is_finite() && z.im.is_finite()))
    else {
        return Ok(());
    };
    let channel = channel(at % stride % plan.n);
    let samples = match channel {
        Channel::Force(c) => record.force(c),
        Channel::Displacement(c) => record.displacement(c),
    };
    Err(Error::SpectrumOverflow {
        record: record.label().to_owned(),
        stage,
        channel,
        freq_hz: plan.lines[at / stride] as f64 * plan.resolution_hz,
        peak: samples.iter().fold(0.0, |m, v| m.max(v.abs())),
    })
}

/// Impedance by paired sets (seed eq. 9): whole-record spectra, `H = F X⁻¹` per set, averaged.
///
/// `excitation[r]` is the excitation (degree of freedom) of record `r` (see
/// [`Assignment::resolve`]). Sets are formed in record order; when directions have unequal
/// counts the extra records are left out and listed in [`Frf::unpaired`].
///
/// # Errors
/// Shape errors from [`common_shape`]; [`Error::BandAboveNyquist`]; the assignment errors;
/// [`Error::RankDeficient`] when some direction has no record at all.
pub fn paired_sets(
    records: &[Record],
    excitation: &[usize],
    band: Band,
    window: Window,
) -> Result<Frf> {
    common_shape(records, None)?;
    let mut b = FrfBuilder::new(
        Estimator::PairedSets,
        band,
        Segmentation::WholeRecord,
        window,
    );
    b.push_all(records)?;
    b.finish(&Assignment::Explicit(excitation.to_vec()))
}

/// Impedance by the MIMO H1 estimator over all records and segments:
/// $G = S_{xf} S_{ff}^{-1}$, $H = G^{-1}$.
///
/// # Errors
/// Shape errors from [`common_shape`]; [`Error::InvalidParameter`] for a bad Welch segment
/// length; [`Error::BandAboveNyquist`].
pub fn h1(
    records: &[Record],
    band: Band,
    segmentation: Segmentation,
    window: Window,
) -> Result<Frf> {
    common_shape(records, None)?;
    let mut b = FrfBuilder::new(Estimator::H1, band, segmentation, window);
    b.push_all(records)?;
    b.finish(&Assignment::DominantForce)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_flexibilities_must_be_finite_and_keep_their_spacing() {
        let g = |v: f64| Mat::from_fn(1, 1, |_, _| c64::new(v, 0.0));
        let e = Frf::from_flexibility(vec![10.0, 20.0], &[g(1e-3), g(f64::NAN)]).unwrap_err();
        assert_eq!(
            e,
            Error::NonFiniteResult {
                stage: "given flexibility",
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
    fn static_records(g: [[f64; 2]; 2]) -> Vec<Record> {
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
        let mean: f64 = (0..frf.lines())
            .map(|k| frf.multiple_coherence(k).unwrap()[0])
            .sum::<f64>()
            / frf.lines() as f64;
        assert!((mean - 0.8).abs() < 0.01, "mean coherence {mean}");
        let ord = frf.ordinary_coherence(3).unwrap()[(0, 0)];
        assert!((ord - frf.multiple_coherence(3).unwrap()[0]).abs() < 1e-12); // SISO: equal
        // G stays unbiased under output noise (H1): 2 on average.
        let g: f64 = (0..frf.lines())
            .map(|k| frf.flexibility(k)[(0, 0)].re)
            .sum::<f64>()
            / frf.lines() as f64;
        assert!((g - 2.0).abs() < 0.01, "mean G {g}");
        // Keeping only some lines moves the rest to the dropped list.
        let kept = frf.retain_lines(|k| k % 2 == 0);
        assert_eq!(kept.lines() + kept.dropped_hz().len(), frf.lines());
        assert!(kept.multiple_coherence(0).is_some());
    }

    #[test]
    fn band_edges_are_inclusive_and_dc_excluded() {
        let band = Band::new(0.0, 4.0).unwrap();
        assert_eq!(band.lines(16.0, 16).unwrap(), vec![1, 2, 3, 4]);
        let band = Band::new(2.0 - 1e-9, 3.0 + 1e-9).unwrap();
        assert_eq!(band.lines(16.0, 16).unwrap(), vec![2, 3]);
    }

    #[test]
    fn invalid_band_is_refused() {
        assert!(matches!(
            Band::new(5.0, 5.0),
            Err(Error::InvalidBand { .. })
        ));
        assert!(matches!(
            Band::new(-1.0, 5.0),
            Err(Error::InvalidBand { .. })
        ));
        assert!(matches!(
            Band::new(1.0, f64::NAN),
            Err(Error::InvalidBand { .. })
        ));
    }

    #[test]
    fn band_above_nyquist_is_refused() {
        let e = Band::new(1.0, 40.0).unwrap().lines(64.0, 64).unwrap_err();
        assert_eq!(
            e,
            Error::BandAboveNyquist {
                high_hz: 40.0,
                nyquist_hz: 32.0
            }
        );
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
            assert_eq!(frf.lines(), 10);
            for k in 0..frf.lines() {
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
    fn explicit_assignment_is_checked() {
        let recs = static_records([[1.0, 0.0], [0.0, 1.0]]);
        assert!(matches!(
            Assignment::Explicit(vec![0]).resolve(&recs, 2),
            Err(Error::AssignmentLength {
                expected: 2,
                actual: 1
            })
        ));
        assert!(matches!(
            Assignment::Explicit(vec![0, 2]).resolve(&recs, 2),
            Err(Error::InvalidAssignment { excitation: 2, .. })
        ));
        assert_eq!(
            Assignment::DominantForce.resolve(&recs, 2).unwrap(),
            vec![0, 1]
        );
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
