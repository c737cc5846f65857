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
//! Each line also carries the condition number the next stage judges: `cond([X¹…Xⁿ])` for paired
//! sets (the worst set), `cond(S_ff)` for H1. Lines whose matrices cannot be inverted are dropped
//! and listed in [`Frf::dropped_hz`].

use faer::{Mat, MatRef, c64};

use crate::error::{Error, Result};
use crate::linalg;
use crate::records::Record;
use crate::spectra::{Segmentation, SpectralEstimator, Window};

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
    /// MIMO H1 over all records and segments: `G = S_xf S_ff⁻¹`, `H = G⁻¹`.
    H1,
}

impl Estimator {
    /// Short name: `"paired"` or `"h1"`.
    pub fn name(self) -> &'static str {
        match self {
            Estimator::PairedSets => "paired",
            Estimator::H1 => "h1",
        }
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
        match self {
            Assignment::DominantForce => Ok(records.iter().map(Record::dominant_force).collect()),
            Assignment::Explicit(a) => {
                if a.len() != records.len() {
                    return Err(Error::AssignmentLength {
                        expected: records.len(),
                        actual: a.len(),
                    });
                }
                if let Some((r, &excitation)) = a.iter().enumerate().find(|(_, e)| **e >= dofs) {
                    return Err(Error::InvalidAssignment {
                        record: records[r].label().to_owned(),
                        excitation,
                        dofs,
                    });
                }
                Ok(a.clone())
            }
        }
    }
}

/// Relative difference below which two sampling rates are the same (rates read from CSV time
/// columns carry rounding).
pub const SAMPLE_RATE_TOLERANCE: f64 = 1e-6;

/// The common shape of a list of records: `(dofs, sample_rate, len)`.
///
/// # Errors
/// [`Error::NoRecords`], or [`Error::DofMismatch`], [`Error::SampleRateMismatch`] (beyond
/// [`SAMPLE_RATE_TOLERANCE`]),
/// [`Error::RecordLengthMismatch`] naming the first record that differs from the first one
/// (or from `dofs`, when given).
pub fn common_shape(records: &[Record], dofs: Option<usize>) -> Result<(usize, f64, usize)> {
    let first = records.first().ok_or(Error::NoRecords)?;
    let n = dofs.unwrap_or(first.dofs());
    for r in records {
        if r.dofs() != n {
            return Err(Error::DofMismatch {
                record: r.label().to_owned(),
                expected: n,
                actual: r.dofs(),
            });
        }
        if (r.sample_rate() / first.sample_rate() - 1.0).abs() > SAMPLE_RATE_TOLERANCE {
            return Err(Error::SampleRateMismatch {
                record: r.label().to_owned(),
                expected: first.sample_rate(),
                actual: r.sample_rate(),
            });
        }
        if r.len() != first.len() {
            return Err(Error::RecordLengthMismatch {
                record: r.label().to_owned(),
                expected: first.len(),
                actual: r.len(),
            });
        }
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
}

impl Frf {
    /// An `Frf` from flexibilities measured elsewhere (one `n × n` matrix per line), for fitting
    /// data that did not come through this crate's spectra. Condition numbers are those of `G`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for mismatched lengths, non-square or mismatched matrices, or
    /// a frequency that is not finite and positive; [`Error::NonFiniteCoefficient`] never; a line
    /// whose `G` is singular is dropped.
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
        let mut pivots = vec![0; n];
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
            let cond = linalg::condition_number(m.as_ref())?;
            let mut h = g.clone();
            if linalg::invert_in_place(&mut h, n, &mut pivots) {
                out.push_line(f, &h, &g, cond);
            } else {
                out.dropped_hz.push(f);
            }
        }
        out.averages = 1;
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
        }
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

    /// Labels of records left out of the paired sets (more records in one direction than in
    /// another).
    pub fn unpaired(&self) -> &[String] {
        &self.unpaired
    }
}

/// Band-limited spectra of every channel of a list of records: `[record][line][channel]`.
struct BandSpectra {
    lines: usize,
    n: usize,
    forces: Vec<c64>,
    displacements: Vec<c64>,
}

impl BandSpectra {
    fn at(&self, data: &[c64], record: usize, line: usize, channel: usize) -> c64 {
        data[(record * self.lines + line) * self.n + channel]
    }
}

fn band_spectra(
    records: &[Record],
    estimator: &mut SpectralEstimator,
    lines: &[usize],
    n: usize,
) -> BandSpectra {
    let mut out = BandSpectra {
        lines: lines.len(),
        n,
        forces: vec![c64::new(0.0, 0.0); records.len() * lines.len() * n],
        displacements: vec![c64::new(0.0, 0.0); records.len() * lines.len() * n],
    };
    for (r, rec) in records.iter().enumerate() {
        for c in 0..n {
            let spec = estimator.transform(rec.force(c));
            for (l, &k) in lines.iter().enumerate() {
                out.forces[(r * lines.len() + l) * n + c] = spec[k];
            }
            let spec = estimator.transform(rec.displacement(c));
            for (l, &k) in lines.iter().enumerate() {
                out.displacements[(r * lines.len() + l) * n + c] = spec[k];
            }
        }
    }
    out
}

/// Impedance by paired sets (seed eq. 9): whole-record spectra, `H = F X⁻¹` per set, averaged.
///
/// `excitation[r]` is the excitation (degree of freedom) of record `r` (see
/// [`Assignment::resolve`]). Sets are formed in record order; when directions have unequal
/// counts the extra records are left out and listed in [`Frf::unpaired`].
///
/// # Errors
/// Shape errors from [`common_shape`]; [`Error::BandAboveNyquist`];
/// [`Error::RankDeficient`] when some direction has no record at all.
///
/// # Panics
/// If `excitation.len() != records.len()` or an entry is `≥ n`.
pub fn paired_sets(
    records: &[Record],
    excitation: &[usize],
    band: Band,
    window: Window,
) -> Result<Frf> {
    let (n, fs, len) = common_shape(records, None)?;
    assert_eq!(excitation.len(), records.len(), "one excitation per record");
    let mut by_direction: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (r, &e) in excitation.iter().enumerate() {
        by_direction[e].push(r);
    }
    let rank = by_direction.iter().filter(|d| !d.is_empty()).count();
    if rank < n {
        return Err(Error::RankDeficient { rank, dofs: n });
    }
    let sets = by_direction.iter().map(Vec::len).min().unwrap_or(0);
    let lines = band.lines(fs, len)?;
    let mut estimator = SpectralEstimator::new(len, fs, window);
    let spectra = band_spectra(records, &mut estimator, &lines, n);

    let mut frf = Frf::empty(n, Estimator::PairedSets);
    frf.averages = sets;
    frf.unpaired = by_direction
        .iter()
        .flat_map(|d| d[sets..].iter().map(|&r| records[r].label().to_owned()))
        .collect();
    let nn = n * n;
    let zero = c64::new(0.0, 0.0);
    let (mut x, mut f, mut hs) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
    let (mut h, mut g) = (vec![zero; nn], vec![zero; nn]);
    let mut pivots = vec![0; n];
    'line: for (l, &k) in lines.iter().enumerate() {
        h.fill(zero);
        let mut worst = 0.0_f64;
        for s in 0..sets {
            for (j, dir) in by_direction.iter().enumerate() {
                let r = dir[s];
                for i in 0..n {
                    x[i + j * n] = spectra.at(&spectra.displacements, r, l, i);
                    f[i + j * n] = spectra.at(&spectra.forces, r, l, i);
                }
            }
            worst = worst.max(linalg::condition_number(MatRef::from_column_major_slice(
                &x, n, n,
            ))?);
            if !linalg::invert_in_place(&mut x, n, &mut pivots) {
                frf.dropped_hz.push(estimator.frequency_hz(k));
                continue 'line;
            }
            linalg::mul_into(&f, &x, &mut hs, n);
            for (a, b) in h.iter_mut().zip(&hs) {
                *a += b / sets as f64;
            }
        }
        g.copy_from_slice(&h);
        if linalg::invert_in_place(&mut g, n, &mut pivots) {
            frf.push_line(estimator.frequency_hz(k), &h, &g, worst);
        } else {
            frf.dropped_hz.push(estimator.frequency_hz(k));
        }
    }
    Ok(frf)
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
    let (n, fs, len) = common_shape(records, None)?;
    let seg_len = segmentation.segment_len(len)?;
    let lines = band.lines(fs, seg_len)?;
    let mut estimator = SpectralEstimator::new(seg_len, fs, window);
    let nn = n * n;
    let zero = c64::new(0.0, 0.0);
    let mut sff = vec![zero; lines.len() * nn];
    let mut sxf = vec![zero; lines.len() * nn];
    let mut fspec = vec![zero; lines.len() * n];
    let mut xspec = vec![zero; lines.len() * n];
    let mut averages = 0;
    for rec in records {
        for start in segmentation.starts(len) {
            let seg = start..start + seg_len;
            for c in 0..n {
                let spec = estimator.transform(&rec.force(c)[seg.clone()]);
                for (l, &k) in lines.iter().enumerate() {
                    fspec[l * n + c] = spec[k];
                }
                let spec = estimator.transform(&rec.displacement(c)[seg.clone()]);
                for (l, &k) in lines.iter().enumerate() {
                    xspec[l * n + c] = spec[k];
                }
            }
            for l in 0..lines.len() {
                let (fl, xl) = (&fspec[l * n..(l + 1) * n], &xspec[l * n..(l + 1) * n]);
                let (sf, sx) = (
                    &mut sff[l * nn..(l + 1) * nn],
                    &mut sxf[l * nn..(l + 1) * nn],
                );
                for j in 0..n {
                    let fj = fl[j].conj();
                    for i in 0..n {
                        sf[i + j * n] += fl[i] * fj;
                        sx[i + j * n] += xl[i] * fj;
                    }
                }
            }
            averages += 1;
        }
    }
    let mut frf = Frf::empty(n, Estimator::H1);
    frf.averages = averages;
    let (mut inv, mut g, mut h) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
    let mut pivots = vec![0; n];
    for (l, &k) in lines.iter().enumerate() {
        let sf = &sff[l * nn..(l + 1) * nn];
        let cond = linalg::condition_number(MatRef::from_column_major_slice(sf, n, n))?;
        inv.copy_from_slice(sf);
        let ok = linalg::invert_in_place(&mut inv, n, &mut pivots) && {
            linalg::mul_into(&sxf[l * nn..(l + 1) * nn], &inv, &mut g, n);
            h.copy_from_slice(&g);
            linalg::invert_in_place(&mut h, n, &mut pivots)
        };
        if ok {
            frf.push_line(estimator.frequency_hz(k), &h, &g, cond);
        } else {
            frf.dropped_hz.push(estimator.frequency_hz(k));
        }
    }
    Ok(frf)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        for frf in [&paired, &h1] {
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
