//! [`ReversePath`]: the settings of a nonlinear identification and its run, records →
//! velocities and regressors → Welch sums → per-line $[\hat H\;\hat A]$ → linear fit, band
//! averages, model check → jackknife.

use std::time::Instant;

use faer::Mat;

use crate::error::{Error, Result, Warning};
use crate::frf::Band;
use crate::identify::Timings;
use crate::model::Coefficients;
use crate::records::{Record, common_shape};
use crate::solve::{Convergence, IvfOptions, Method, NonConvergence};
use crate::spectra::Segmentation;
use crate::tolerance::{BIAS_SIGMAS, NONLINEAR_CHECK_SIGMAS, REVERSE_PATH_AVERAGES_PER_INPUT};

use super::check::TermCheck;
use super::gather::{Gathered, gather, input_channels, segment_count};
use super::lines::{LineEstimates, band_average, estimate};
use super::result::{NonlinearIdentification, TermEstimate};
use super::velocity::Differentiation;
use super::{Regressor, Term};

/// Settings of a nonlinear identification by the reverse path (Bendat 1990; Richards & Singh 1998): linear
/// $M, C, K$ together with the coefficients of known nonlinear terms, from records of random
/// or multisine forcing (any number of simultaneous forces).
///
/// Per line the forces are the outputs and the displacements and regressors the inputs,
/// $[\hat H\;\hat A] = S_{fz}S_{zz}^{-1}$ with $z = [x;\,y]$ (the direct form); `M`, `C`,
/// `K` are fitted to $\hat H(\omega)$ by least squares or IVF; each coefficient is the weighted
/// band average of $\operatorname{Re}\hat A_j(\omega)$ and is checked for being real and flat
/// ([`TermCheck`]). Error bars: the jackknife over at most 8 contiguous blocks of the Welch
/// segments of all records, for every coefficient.
///
/// This form treats the forces as the noisy channels: displacement noise biases it (about
/// 3 % low `M`, `K` at 20 % displacement noise, 0.03 % at 2 %, in simulation).
///
/// # Examples
/// A one-DOF element with dry friction, its displacement prescribed (a Schroeder-phased
/// multisine over 5–40 Hz on the 16 s record's grid, so that its derivatives are exact and
/// every Welch segment sees different motion) and its force computed exactly,
/// $f = m\ddot x + c\dot x + kx + F\operatorname{sign}\dot x$:
/// ```
/// use bearing_ident::nonlinear::{Regressor, ReversePath};
/// use bearing_ident::Record;
/// use std::f64::consts::PI;
/// let (fs, n) = (256.0, 4096); // 16 s, lines every 1/16 Hz
/// let (m, c, k, friction) = (2.0, 40.0, 8e4, 0.5);
/// let lines: Vec<f64> = (80..=640).map(|l| l as f64 / 16.0).collect();
/// let (mut x, mut f) = (vec![0.0; n], vec![0.0; n]);
/// for s in 0..n {
///     let t = s as f64 / fs;
///     let (mut xs, mut vs, mut acc) = (0.0, 0.0, 0.0);
///     for (l, hz) in lines.iter().enumerate() {
///         let (w, phase) = (2.0 * PI * hz, -PI * (l * l) as f64 / lines.len() as f64);
///         xs += 2e-6 * (w * t + phase).sin();
///         vs += 2e-6 * w * (w * t + phase).cos();
///         acc -= 2e-6 * w * w * (w * t + phase).sin();
///     }
///     x[s] = xs;
///     f[s] = m * acc + c * vs + k * xs + friction * vs.signum();
/// }
/// let record = Record::new("friction", fs, vec![f], vec![x])?;
/// let id = ReversePath::new(8.0, 36.0, &[Regressor::Coulomb])
///     .segment_len(256)
///     .identify(&[record])?;
/// let estimate = id.terms()[0];
/// assert!((estimate.value / friction - 1.0).abs() < 0.05);
/// assert!((id.coefficients().stiffness()[(0, 0)] / k - 1.0).abs() < 0.01);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ReversePath {
    low_hz: f64,
    high_hz: f64,
    regressors: Vec<Regressor>,
    segment_len: Option<usize>,
    method: Method,
    ivf: IvfOptions,
    differentiation: Differentiation,
}

impl ReversePath {
    /// A reverse path over the band `low_hz ..= high_hz` (Hz, edges inclusive) with the terms
    /// of `regressors` (each kind once; an empty list is the linear-only fit of the same data),
    /// every other setting at its default.
    pub fn new(low_hz: f64, high_hz: f64, regressors: &[Regressor]) -> Self {
        Self {
            low_hz,
            high_hz,
            regressors: regressors.to_vec(),
            segment_len: None,
            method: Method::Ivf,
            ivf: IvfOptions::default(),
            differentiation: Differentiation::default(),
        }
    }

    /// Welch segment length (samples). Valid `8 ≤ len ≤` record length; default the largest
    /// power of two not above an eighth of the record (at least 8).
    pub fn segment_len(mut self, len: usize) -> Self {
        self.segment_len = Some(len);
        self
    }

    /// The fit of the linear part: [`Method::LeastSquares`], [`Method::Ivf`] (default) or
    /// [`Method::Direct`]; [`Method::Ml`] is refused (it needs periodic records).
    pub fn method(mut self, method: Method) -> Self {
        self.method = method;
        self
    }

    /// IVF options (tolerance in `(0, 1)`, iteration limit `≥ 1`). Default
    /// [`IvfOptions::default`].
    pub fn ivf_options(mut self, options: IvfOptions) -> Self {
        self.ivf = options;
        self
    }

    /// How velocities are derived. Default [`Differentiation::Wiener`].
    pub fn differentiation(mut self, differentiation: Differentiation) -> Self {
        self.differentiation = differentiation;
        self
    }

    /// Checks the settings that do not depend on the records: the band, the IVF options and
    /// the velocity cutoff. [`ReversePath::identify`] calls it first; what needs the records
    /// (the segment length against their length, the regressors against their degrees of
    /// freedom) is checked there.
    ///
    /// # Errors
    /// [`Error::InvalidBand`]; [`Error::InvalidParameter`] for the IVF options or a cutoff
    /// that is not finite and positive.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::nonlinear::{Differentiation, Regressor, ReversePath};
    /// assert!(ReversePath::new(5.0, 40.0, &[Regressor::Coulomb]).check().is_ok());
    /// let bad = ReversePath::new(5.0, 40.0, &[]).differentiation(Differentiation::Cutoff(-1.0));
    /// assert!(bad.check().is_err());
    /// assert!(ReversePath::new(40.0, 5.0, &[]).check().is_err());
    /// ```
    pub fn check(&self) -> Result<()> {
        Band::new(self.low_hz, self.high_hz)?;
        self.ivf.check()?;
        self.differentiation.check()?;
        Ok(())
    }

    /// Identifies the linear coefficients and the nonlinear terms from `records`.
    ///
    /// # Errors
    /// In the order checked: [`Error::InvalidBand`]; [`Error::InvalidParameter`] for the IVF
    /// options, a bad cutoff, `coulomb-planar` on fewer than 2 DOFs or a bad segment length;
    /// [`Error::NoRecords`] and the shape errors of [`common_shape`];
    /// [`Error::TooFewAverages`] when the records give fewer than
    /// [`REVERSE_PATH_AVERAGES_PER_INPUT`] Welch segments per input;
    /// [`Error::BandAboveNyquist`]; [`Error::NonFiniteRegressor`]; [`Error::Singular`] when the
    /// inputs are dependent at a line; [`Error::NonFiniteResult`];
    /// [`Error::IterationNonFinite`] when the IVF meets NaN or infinity; the errors of
    /// [`crate::solve::fit`] ([`Error::TooFewLines`], [`Error::SingularFit`],
    /// [`Error::MlNeedsRepeats`]).
    pub fn identify(&self, records: &[Record]) -> Result<NonlinearIdentification> {
        let start = Instant::now();
        let mut timings = Timings::default();
        self.check()?;
        let band = Band::new(self.low_hz, self.high_hz)?;
        let differentiation = self.differentiation;
        let shape = common_shape(records, None)?;
        let n = shape.dofs;
        let terms = Regressor::expand(&self.regressors, n)?;
        let segment_len = Segmentation::Welch {
            len: self
                .segment_len
                .unwrap_or_else(|| default_segment(shape.len)),
        }
        .segment_len(shape.len)?;
        let q = n + input_channels(&terms).len();
        let averages = segment_count(&shape, records.len(), segment_len);
        let required = REVERSE_PATH_AVERAGES_PER_INPUT * q;
        if averages < required {
            return Err(Error::TooFewAverages {
                averages,
                inputs: q,
                required,
            });
        }

        let clock = Instant::now();
        let gathered = gather(records, &shape, &terms, band, segment_len, differentiation)?;
        timings.spectra = clock.elapsed();

        let clock = Instant::now();
        let full = estimate(&gathered.total(None), n, q, &gathered.freqs_hz)?;
        timings.frf = clock.elapsed();

        let clock = Instant::now();
        let fit = full.fit(self.method, &self.ivf, true)?;
        // NaN or infinity inside the IVF is no slow convergence to warn of: name it.
        if let c @ Convergence::NonFinite { .. } = fit.convergence() {
            c.judged(Method::Ivf, NonConvergence::Fail, None)?;
        }
        let (spectra, spectra_var): (Vec<_>, Vec<_>) = (0..terms.len())
            .map(|j| full.term_spectrum(&gathered.channels, j))
            .unzip();
        let values: Vec<f64> = spectra
            .iter()
            .zip(&spectra_var)
            .map(|(s, v)| band_average(s, v))
            .collect();
        timings.solve = clock.elapsed();

        let clock = Instant::now();
        let checks: Vec<TermCheck> = (0..terms.len())
            .map(|j| {
                let coherence = full.term_input_coherence(&gathered.channels, j);
                TermCheck::new(&full.freqs_hz, &spectra[j], &spectra_var[j], coherence)
            })
            .collect();
        timings.conditioning = clock.elapsed();

        let clock = Instant::now();
        let mut warnings = Vec::new();
        let blocks = gathered.blocks.len();
        let (std, term_std): (Option<Coefficients>, Vec<Option<f64>>) = if blocks >= 3 {
            let (s, t) = self.jackknife(&gathered, &terms)?;
            (Some(s), t.into_iter().map(Some).collect())
        } else {
            warnings.push(Warning::FewReplicates { replicates: blocks });
            let per_line = spectra_var.iter().map(|v| per_line_std(v)).collect();
            (fit.std_dev().cloned(), per_line)
        };
        // Dry friction's sign bias, predicted from the velocity noise, joins its error bar.
        let model_std: Vec<f64> = terms
            .iter()
            .zip(&values)
            .map(|(term, value)| {
                let flip = &gathered.sign_flip;
                let b = match (term.regressor, term.dof) {
                    (Regressor::Coulomb, Some(d)) => flip[d],
                    (Regressor::CoulombPlanar, _) => 0.5 * (flip[0] + flip[1]),
                    _ => 0.0,
                };
                value.abs() * b
            })
            .collect();
        for ((term, &model), random) in terms.iter().zip(&model_std).zip(&term_std) {
            if random.is_none_or(|s| model > BIAS_SIGMAS * s) && model > 0.0 {
                warnings.push(Warning::FrictionBias {
                    term: term.label(),
                    predicted: model,
                    random_std: *random,
                });
            }
        }
        let term_std: Vec<Option<f64>> = term_std
            .iter()
            .zip(&model_std)
            .map(|(s, m)| s.map(|s| s.hypot(*m)))
            .collect();
        timings.uncertainty = clock.elapsed();

        warnings.extend(fit.convergence().warning());
        for (term, check) in terms.iter().zip(&checks) {
            if check.misfit {
                warnings.push(Warning::NonlinearMisfit {
                    term: term.label(),
                    imaginary_ratio: check.imaginary_ratio,
                    slope: check.slope,
                });
            }
            if check.collinear {
                warnings.push(Warning::CollinearRegressors {
                    term: term.label(),
                    coherence: check.input_coherence,
                });
            }
        }
        for ((term, &value), std) in terms.iter().zip(&values).zip(&term_std) {
            let clear = std.is_none_or(|s| value < -NONLINEAR_CHECK_SIGMAS * s);
            if term.regressor.dissipative() && value < 0.0 && clear {
                warnings.push(Warning::NegativeDissipation {
                    term: term.label(),
                    value,
                    std: *std,
                });
            }
        }
        let frf = full.frf();
        if !frf.dropped_hz().is_empty() {
            warnings.push(Warning::DroppedLines {
                freqs_hz: frf.dropped_hz().to_vec(),
            });
        }
        timings.total = start.elapsed();
        Ok(NonlinearIdentification {
            terms: terms
                .iter()
                .zip(values)
                .zip(term_std)
                .zip(model_std)
                .map(|(((&term, value), std), model_std)| TermEstimate {
                    term,
                    value,
                    std,
                    model_std,
                })
                .collect(),
            fit,
            std,
            spectra,
            spectra_var,
            checks,
            frf,
            output_coherence: full.output_coherence,
            velocity: gathered.velocity,
            warnings,
            timings,
            averages,
            blocks,
            segment_len,
        })
    }

    /// Jackknife standard deviations of `M`, `C`, `K` and of each term's coefficient over the
    /// blocks of `gathered`, $\sigma^2 = \frac{B-1}{B}\sum_b(\theta_{(-b)} - \bar\theta)^2$.
    fn jackknife(&self, gathered: &Gathered, terms: &[Term]) -> Result<(Coefficients, Vec<f64>)> {
        let b = gathered.blocks.len();
        let (n, q) = (gathered.n, gathered.q);
        let mut thetas: Vec<Mat<f64>> = Vec::with_capacity(b);
        let mut values: Vec<Vec<f64>> = Vec::with_capacity(b);
        for leave_out in 0..b {
            let est: LineEstimates =
                estimate(&gathered.total(Some(leave_out)), n, q, &gathered.freqs_hz)?;
            thetas.push(
                est.fit(self.method, &self.ivf, false)?
                    .coefficients()
                    .stacked(),
            );
            values.push(
                (0..terms.len())
                    .map(|j| {
                        let (s, v) = est.term_spectrum(&gathered.channels, j);
                        band_average(&s, &v)
                    })
                    .collect(),
            );
        }
        let factor = (b as f64 - 1.0) / b as f64;
        let spread = |vals: &mut dyn Iterator<Item = f64>| {
            let v: Vec<f64> = vals.collect();
            let mean = v.iter().sum::<f64>() / b as f64;
            (factor * v.iter().map(|x| (x - mean).powi(2)).sum::<f64>()).sqrt()
        };
        let (p, cols) = (thetas[0].nrows(), thetas[0].ncols());
        let std = Mat::from_fn(p, cols, |i, j| {
            spread(&mut thetas.iter().map(|t| t[(i, j)]))
        });
        let term_std = (0..terms.len())
            .map(|j| spread(&mut values.iter().map(|v| v[j])))
            .collect();
        Ok((Coefficients::from_stacked(std.as_ref())?, term_std))
    }
}

/// The largest power of two not above an eighth of `len` samples (at least 8).
fn default_segment(len: usize) -> usize {
    let eighth = (len / 8).max(8);
    1 << eighth.ilog2()
}

/// The standard deviation of a weighted band average from per-line variances of `Â`
/// (half of each in the real part): $(2\sum_k 1/\sigma_k^2)^{-1/2}$; `None` without variances.
fn per_line_std(var: &[f64]) -> Option<f64> {
    let ok = var.iter().all(|&v| v.is_finite() && v > 0.0) && !var.is_empty();
    ok.then(|| {
        (2.0 * var.iter().map(|v| 1.0 / v).sum::<f64>())
            .sqrt()
            .recip()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_segments_are_powers_of_two() {
        assert_eq!(default_segment(60 * 2048), 8192);
        assert_eq!(default_segment(100), 8);
        assert_eq!(default_segment(8040), 512);
    }

    #[test]
    fn per_line_std_needs_variances() {
        assert!(per_line_std(&[0.0, 1.0]).is_none());
        let s = per_line_std(&[2.0, 2.0]).unwrap();
        assert!((s - 0.5f64.sqrt()).abs() < 1e-15);
    }
}
