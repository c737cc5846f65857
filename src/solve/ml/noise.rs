//! Noise models for records without repeated periods: impacts (whole records) and random
//! excitation (Welch segments). They give the maximum-likelihood fit the per-line noise
//! covariances that repeated periods give periodic records.
//!
//! # The residual noise model
//! Assumptions: the noise is in the displacements (output noise, as H1 assumes; forces from
//! load cells are clean by comparison, and gated for impacts), stationary over the test,
//! independent between records (and between Welch segments, up to their overlap), with a
//! spectrum smooth over a few lines; and the model fits, so that what is left over is noise.
//!
//! After the IVF start `Θ₀`, the residual of spectrum `s` at line `k` is
//! `r_s = x_s − G(ω_k; Θ₀) f_s`; its second moment, summed over the `S` spectra, is
//!
//! $$R_k = [I\;\; -G]\, \Big(\sum_s z_s z_s^H\Big) [I\;\; -G]^H, \qquad z = [x; f],$$
//!
//! so the records' second moments suffice (nothing per segment is kept). The noise
//! covariance of one spectrum is then
//!
//! $$\hat C_X(\omega_k) = \frac{D}{S\,(2h+1)} \sum_{|j-k| \le h} R_j,\qquad
//!   D = \frac{2LSn}{2LSn - 3n^2},$$
//!
//! pooled over `2h + 1` neighbouring lines until about
//! [`POOLED_NOISE_DOF`] real degrees of freedom (`2S` per
//! line, `2S/κ` for correlated Welch spectra, below; [`pooling_half_width`]), with `D` the degrees of freedom the `3n²` fitted coefficients took from the `L·S·n`
//! complex residuals. `C_F = C_XF = 0`.
//!
//! The likelihood depends on the spectra only through `Σ z zᴴ` (its cost is a trace against
//! it, its gradient and Fisher information bilinear in `z`), so each line's moments are
//! factored into at most `2n` columns `Z Zᴴ = Σ z zᴴ` and fitted as they are, whatever the
//! number of records or segments.
//!
//! Welch spectra are not independent: the Hann window makes neighbouring lines correlate
//! (by 2/3 and 1/6) and the 50 % overlap makes neighbouring segments correlate (by 1/6). The
//! likelihood treats them as independent (a quasi-likelihood); its estimate stays unbiased,
//! but its sums vary `κ` times as much as `F` says (`κ → 19/9` for Hann at 50 %; the frf
//! stage's `overlap_inflation` gives `κ` in closed form for any window and overlap), and the
//! covariance `F⁻¹` is multiplied by `κ`. Whole records with the rectangular window have
//! `κ = 1`; under an exponential window the neighbouring lines of a whole record correlate
//! too, which is not accounted for: on lightly damped impacts windowed to 1 % the estimate
//! was unbiased but its error bars 1.3–2.3 × too narrow (`tests/estimation/ml_records.rs`).
//!
//! When the assumptions fail: records that have not decayed (leakage) or a model that does
//! not fit leave a residual that is not noise; it is counted as noise, which widens the error
//! bars and weights the afflicted lines down, but the bias it causes stays (impacts on a rig
//! with ζ ≈ 0.8 % cut at 1.2 s, rectangular window: C +7.5 % and +12.5 % against a spread of
//! 0.7 % and error bars of 6.3 %; `tests/estimation/ml_records.rs`). Force noise breaks the
//! output-noise assumption too: the model then attributes it to the displacements.

use faer::{Mat, c64};

use super::MlData;
use crate::error::{Error, Result};
use crate::frf::RecordMoments;
use crate::model::Coefficients;
use crate::tolerance::{MOMENT_RANK, POOLED_NOISE_DOF};

/// Where the maximum-likelihood fit's noise covariances came from (the JSON's
/// `ml.noise_model`, by its [`Choice::name`](crate::Choice::name)).
///
/// # Examples
/// ```
/// use bearing_ident::Choice;
/// use bearing_ident::solve::ml::NoiseModel;
/// assert_eq!(NoiseModel::ImpactResiduals.name(), "impact_residuals");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize),
    serde(rename_all = "snake_case")
)]
#[non_exhaustive]
pub enum NoiseModel {
    /// Given by the caller ([`MlData::new`], [`MlData::planned`]).
    Given,
    /// The period-to-period scatter of periodic records.
    PeriodicRepeats,
    /// The residuals of whole records (impacts) about the IVF fit, pooled over records and
    /// neighbouring lines (module docs).
    ImpactResiduals,
    /// The residuals of Welch segments (random excitation) about the IVF fit, with the
    /// overlap's variance inflation (module docs).
    WelchResiduals,
}

impl crate::Choice for NoiseModel {
    const OPTION: &'static str = "noise model";
    const ALL: &'static [NoiseModel] = &[
        NoiseModel::Given,
        NoiseModel::PeriodicRepeats,
        NoiseModel::ImpactResiduals,
        NoiseModel::WelchResiduals,
    ];

    /// Short name: `given`, `periodic_repeats`, `impact_residuals`, `welch_residuals`.
    fn name(self) -> &'static str {
        match self {
            NoiseModel::Given => "given",
            NoiseModel::PeriodicRepeats => "periodic_repeats",
            NoiseModel::ImpactResiduals => "impact_residuals",
            NoiseModel::WelchResiduals => "welch_residuals",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            NoiseModel::Given => "covariances given by the caller",
            NoiseModel::PeriodicRepeats => "the scatter of repeated periods",
            NoiseModel::ImpactResiduals => "residuals of whole records about the IVF fit, pooled",
            NoiseModel::WelchResiduals => "residuals of Welch segments about the IVF fit, pooled",
        }
    }
}

crate::choice::choice_text!(NoiseModel);

/// Lines pooled on each side of a line so that `2h + 1` lines of `2S/κ` real degrees of
/// freedom each (`S` spectra per line, `κ ≥ 1` the correlation inflation of overlapping
/// windowed segments, 1 for independent spectra) reach
/// [`POOLED_NOISE_DOF`].
///
/// # Examples
/// ```
/// use bearing_ident::solve::ml::noise::pooling_half_width;
/// assert_eq!(pooling_half_width(16, 1.0), 4); // 16 impacts: 9 lines of 32
/// assert_eq!(pooling_half_width(15, 19.0 / 9.0), 10); // 15 Hann segments: 21 lines
/// ```
pub fn pooling_half_width(spectra: usize, inflation: f64) -> usize {
    let per_line = 2.0 * spectra.max(1) as f64 / inflation.max(1.0);
    let lines = POOLED_NOISE_DOF / per_line;
    ((lines - 1.0) / 2.0).ceil().max(0.0) as usize
}

/// The residual noise model (module docs) of `moments` about `start`, as [`MlData`].
///
/// # Errors
/// [`Error::Singular`] if `G(ω; start)` is singular at a line; as [`MlData::new`].
pub(crate) fn residual_data(moments: &RecordMoments, start: &Coefficients) -> Result<MlData> {
    let n = start.dofs();
    let lines = moments.freqs_hz.len();
    let spectra = moments.observations.max(1);
    if moments.szz.iter().any(|s| s.nrows() != 2 * n) {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::StartSize,
            value: n as f64,
            expected: "the records' degrees of freedom",
        });
    }
    let mut residual = Vec::with_capacity(lines);
    for (&f, s) in moments.freqs_hz.iter().zip(&moments.szz) {
        let g = start.flexibility_at(f)?;
        // [I  −G] S [I  −G]ᴴ.
        let p = Mat::from_fn(n, 2 * n, |i, j| {
            if j < n {
                c64::new(if i == j { 1.0 } else { 0.0 }, 0.0)
            } else {
                -g[(i, j - n)]
            }
        });
        residual.push(&p * s * p.adjoint());
    }
    let (l, sf, nf) = (lines as f64, spectra as f64, n as f64);
    let taken = 2.0 * l * sf * nf / (2.0 * l * sf * nf - 3.0 * nf * nf).max(1.0);
    let h = pooling_half_width(spectra, moments.overlap_inflation);
    let cx: Vec<Mat<c64>> = (0..lines)
        .map(|k| {
            let range = k.saturating_sub(h)..(k + h + 1).min(lines);
            let count = range.len() as f64;
            let mut c = Mat::<c64>::zeros(n, n);
            for r in &residual[range] {
                c += r;
            }
            // Hermitian by construction; average the halves against rounding.
            Mat::from_fn(n, n, |i, j| {
                (c[(i, j)] + c[(j, i)].conj()) * (0.5 * taken / (sf * count))
            })
        })
        .collect();
    let (x, f): (Vec<_>, Vec<_>) = moments.szz.iter().map(|s| columns(s, n)).unzip();
    let zeros = vec![Mat::zeros(n, n); lines];
    let mut data = MlData::new(moments.freqs_hz.clone(), &x, &f, &cx, &zeros, &zeros)?;
    data.observations = spectra;
    data.inflation = moments.overlap_inflation;
    data.noise_model = if moments.welch {
        NoiseModel::WelchResiduals
    } else {
        NoiseModel::ImpactResiduals
    };
    Ok(data)
}

/// `2n` columns `Z = [X; F]` with `Z Zᴴ = s` (a Hermitian, positive semi-definite `2n × 2n`),
/// by a Cholesky factorisation with diagonal pivoting of `s` scaled to a unit diagonal
/// (displacements and forces differ by many orders of magnitude) that stops at the rank
/// ([`MOMENT_RANK`]); the columns past the rank are zero.
fn columns(s: &Mat<c64>, n: usize) -> (Mat<c64>, Mat<c64>) {
    let m = 2 * n;
    let scale: Vec<f64> = (0..m)
        .map(|i| {
            let d = s[(i, i)].re.sqrt();
            if d > 0.0 { d } else { 1.0 }
        })
        .collect();
    let mut a = Mat::from_fn(m, m, |i, j| s[(i, j)] / (scale[i] * scale[j]));
    let mut z = Mat::<c64>::zeros(m, m);
    for col in 0..m {
        let (p, d) = (0..m)
            .map(|i| (i, a[(i, i)].re))
            .fold((0, f64::NEG_INFINITY), |b, c| if c.1 > b.1 { c } else { b });
        if d.is_nan() || d <= MOMENT_RANK {
            break;
        }
        let root = d.sqrt();
        for i in 0..m {
            z[(i, col)] = a[(i, p)] / root;
        }
        for j in 0..m {
            let zj = z[(j, col)].conj();
            for i in 0..m {
                a[(i, j)] -= z[(i, col)] * zj;
            }
        }
    }
    (
        Mat::from_fn(n, m, |i, j| z[(i, j)] * scale[i]),
        Mat::from_fn(n, m, |i, j| z[(n + i, j)] * scale[n + i]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The columns reproduce the moments, full rank or not.
    #[test]
    fn columns_reproduce_the_moments() {
        // Rows of very different size, as displacements (m·s) and forces (N·s) are.
        let size = [1e-6, 3e-7, 0.5, 2.0];
        let z = Mat::from_fn(4, 6, |i, j| {
            c64::new(
                (i * 7 + j * 3) as f64 % 5.0 - 2.0,
                (i + 2 * j) as f64 % 3.0 - 1.0,
            ) * size[i]
        });
        for rank in [2, 6] {
            let zr = Mat::from_fn(4, rank, |i, j| z[(i, j)]);
            let s = &zr * zr.adjoint();
            let (x, f) = columns(&s, 2);
            let back = Mat::from_fn(4, 4, |i, j| {
                (0..4)
                    .map(|c| {
                        let a = if i < 2 { x[(i, c)] } else { f[(i - 2, c)] };
                        let b = if j < 2 { x[(j, c)] } else { f[(j - 2, c)] };
                        a * b.conj()
                    })
                    .sum::<c64>()
            });
            for i in 0..4 {
                for j in 0..4 {
                    let tol = 1e-12 * size[i] * size[j];
                    assert!(
                        (back[(i, j)] - s[(i, j)]).norm() < tol,
                        "rank {rank} ({i}, {j})"
                    );
                }
            }
        }
    }

    #[test]
    fn pooling_reaches_the_degrees_of_freedom() {
        assert_eq!(pooling_half_width(16, 1.0), 4); // 9 lines × 32 = 288
        assert_eq!(pooling_half_width(144, 1.0), 0);
        assert_eq!(pooling_half_width(4, 1.0), 18); // 37 lines × 8 ≥ 288
        assert_eq!(pooling_half_width(1000, 1.0), 0);
        assert_eq!(pooling_half_width(15, 2.0), 10); // 21 lines × 15 ≥ 288
    }
}
