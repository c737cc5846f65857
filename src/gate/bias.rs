//! Bias the tool can predict from a fitted model ([`PredictedBias`]): the leakage of
//! Hann-windowed Welch segments ([`leaked_flexibility`]) and the truncation of impact records
//! whose response has not decayed by the record's end ([`truncated_flexibility`]).
//!
//! Each is predicted the same way: the flexibility the fitted model would show under that
//! processing is made at the lines of the fit, fitted as the data were, and compared with the
//! fit of the model's own flexibility at the same lines ([`predicted_bias`]). The prediction
//! is of every coefficient, the damping included, and needs no rule of thumb.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use faer::prelude::Solve;
use faer::{Mat, c64};

use crate::error::{Block, Error, Parameter, Result};
use crate::frf::Frf;
use crate::linalg;
use crate::model::Coefficients;
use crate::solve::{IvfOptions, Method};

/// What a [`PredictedBias`] comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum BiasSource {
    /// Leakage of Hann-windowed Welch segments: each line sees the flexibility smoothed by the
    /// window's spectral kernel.
    Leakage,
    /// Truncation of impact records whose response has not decayed by the record's end.
    Truncation,
}

impl BiasSource {
    /// Short name: `"leakage"` or `"truncation"` (the JSON's `predicted_bias.source`).
    pub fn name(self) -> &'static str {
        match self {
            BiasSource::Leakage => "leakage",
            BiasSource::Truncation => "truncation",
        }
    }
}

/// A bias of the coefficients predicted from the fitted model ([`predicted_bias`]): what the
/// processing adds to every coefficient (absolute, in the coefficients' units; estimate minus
/// truth).
#[derive(Debug, Clone, PartialEq)]
pub struct PredictedBias {
    /// Where the bias comes from.
    pub source: BiasSource,
    /// The predicted bias of `M`, `C`, `K`.
    pub bias: Coefficients,
}

impl PredictedBias {
    /// The element with the largest bias in standard deviations `std` (elements with a zero
    /// or non-finite standard deviation are skipped): its block, row, column and `|bias|/σ`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::gate::{BiasSource, PredictedBias};
    /// use bearing_ident::{Block, Coefficients};
    /// use faer::mat;
    /// let bias = PredictedBias {
    ///     source: BiasSource::Leakage,
    ///     bias: Coefficients::new(mat![[0.0]], mat![[2.0]], mat![[10.0]])?,
    /// };
    /// let std = Coefficients::new(mat![[0.1]], mat![[1.0]], mat![[100.0]])?;
    /// assert_eq!(bias.worst_in(&std), Some((Block::Damping, 0, 0, 2.0)));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn worst_in(&self, std: &Coefficients) -> Option<(Block, usize, usize, f64)> {
        worst_in(&self.bias, std)
    }
}

/// The element of `bias` largest in standard deviations `std` ([`PredictedBias::worst_in`]).
pub(crate) fn worst_in(
    bias: &Coefficients,
    std: &Coefficients,
) -> Option<(Block, usize, usize, f64)> {
    let n = bias.dofs();
    let blocks = [
        (Block::Mass, bias.mass(), std.mass()),
        (Block::Damping, bias.damping(), std.damping()),
        (Block::Stiffness, bias.stiffness(), std.stiffness()),
    ];
    let mut worst: Option<(Block, usize, usize, f64)> = None;
    for (block, b, s) in blocks {
        for i in 0..n {
            for j in 0..n {
                let sigma = s[(i, j)];
                if !(sigma.is_finite() && sigma > 0.0) {
                    continue;
                }
                let z = b[(i, j)].abs() / sigma;
                if z.is_finite() && worst.is_none_or(|w| z > w.3) {
                    worst = Some((block, i, j, z));
                }
            }
        }
    }
    worst
}

/// The bias the processing that turns the model's flexibility into `processed` (one matrix per
/// line of `freqs_hz`) adds to a fit by `method`: the fit of `processed` minus the fit of the
/// model's own flexibility at the same lines (so what the fit itself does at those lines
/// cancels). Maximum likelihood is predicted by its IVF start.
///
/// # Errors
/// [`Error::Singular`](crate::Error::Singular) if the model's impedance is singular at a line;
/// the errors of the two fits.
pub fn predicted_bias(
    model: &Coefficients,
    freqs_hz: &[f64],
    processed: Vec<Mat<c64>>,
    method: Method,
    options: &IvfOptions,
    source: BiasSource,
) -> Result<PredictedBias> {
    let method = if method == Method::Ml {
        Method::Ivf
    } else {
        method
    };
    let exact: Vec<Mat<c64>> = freqs_hz
        .iter()
        .map(|&f| model.flexibility_at(f))
        .collect::<Result<_>>()?;
    let fit = |g: &[Mat<c64>]| -> Result<Coefficients> {
        let frf = Frf::from_flexibility(freqs_hz.to_vec(), g)?;
        // The coefficients alone: without the sandwich covariance, which changes nothing
        // of them.
        Ok(crate::solve::fit_point(&frf, method, options)?
            .coefficients()
            .clone())
    };
    let (reference, biased) = (fit(&exact)?, fit(&processed)?);
    let n = model.dofs();
    let diff = |a: faer::MatRef<'_, f64>, b: faer::MatRef<'_, f64>| {
        Mat::from_fn(n, n, |i, j| a[(i, j)] - b[(i, j)])
    };
    let bias = Coefficients::new(
        diff(biased.mass(), reference.mass()),
        diff(biased.damping(), reference.damping()),
        diff(biased.stiffness(), reference.stiffness()),
    )?;
    Ok(PredictedBias { source, bias })
}

/// Most kernel points on each side of a line in [`leaked_flexibility`]: eight lines' width at
/// an eighth of a bandwidth as narrow as 1/64 of the line spacing.
const MAX_HALF_KERNEL: i64 = 8 * 8 * 64;

/// The flexibility H1 gives on average at `freqs_hz` from Hann-windowed segments of `nperseg`
/// samples at `sample_rate`, under uncorrelated white forces of one level: the model's
/// flexibility smoothed by the window's spectral kernel,
/// $\bar G(f_k) = \int |W(\nu)|^2 G(f_k - \nu)\,d\nu \big/ \int |W(\nu)|^2 d\nu$, with
/// $W(\nu) = \sum_m w_m e^{-2\pi i \nu m / f_s}$, integrated over $\pm 8$ line spacings in
/// steps of the smaller of an eighth of the spacing and an eighth of the lightest mode's
/// half-power bandwidth.
///
/// # Errors
/// [`Error::Singular`](crate::Error::Singular) if the model's impedance is singular on the
/// grid; [`Error::InvalidParameter`] ([`Parameter::LightestBandwidth`]) for a mode whose
/// half-power bandwidth is below 1/64 of the line spacing (its kernel would grow without
/// bound; the `coarse_resolution` warning covers such a mode).
///
/// # Examples
/// ```
/// use bearing_ident::gate::leaked_flexibility;
/// use bearing_ident::Coefficients;
/// use faer::mat;
/// // One mode at 10 Hz, ζ = 1 %: 0.2 Hz half-power bandwidth, lines 0.49 Hz apart (1024
/// // samples at 500 S/s) flatten the peak.
/// let sdof = Coefficients::new(mat![[1.0]], mat![[1.2566]], mat![[3947.8]])?;
/// let leaked = leaked_flexibility(&sdof, &[10.0], 1024, 500.0)?;
/// let exact = sdof.flexibility_at(10.0)?;
/// assert!(leaked[0][(0, 0)].norm() < 0.6 * exact[(0, 0)].norm());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn leaked_flexibility(
    model: &Coefficients,
    freqs_hz: &[f64],
    nperseg: usize,
    sample_rate: f64,
) -> Result<Vec<Mat<c64>>> {
    let df = sample_rate / nperseg as f64;
    let lightest = model
        .modes()
        .unwrap_or_default()
        .iter()
        .map(|m| 2.0 * m.damping_ratio * m.natural_frequency_hz)
        .filter(|b| b.is_finite() && *b > 0.0)
        .fold(f64::INFINITY, f64::min);
    let step = (df / 8.0).min(lightest / 8.0);
    // The kernel resolves the lightest mode's bandwidth; a mode far lighter than the line
    // spacing would need a kernel of unbounded size (memory and time from data): such a mode
    // is not predicted here (the `coarse_resolution` warning names it).
    let half = (8.0 * df / step).ceil();
    if half.is_nan() || half > MAX_HALF_KERNEL as f64 {
        return Err(Error::InvalidParameter {
            name: Parameter::LightestBandwidth,
            value: lightest,
            expected: "at least 1/64 of the Welch line spacing for a leakage prediction",
        });
    }
    let half = half as i64;
    let kernel: Vec<(f64, f64)> = (-half..=half)
        .map(|j| {
            let nu = j as f64 * step;
            (nu, hann_power(nu, nperseg, sample_rate))
        })
        .collect();
    let total: f64 = kernel.iter().map(|(_, w)| w).sum();
    let weights: Vec<f64> = kernel.iter().map(|(_, w)| w / total).collect();
    let n = model.dofs();
    // Neighbouring lines share most of their kernel's frequencies (`f − ν` falls on the same
    // number when the step divides the line spacing): each is evaluated once. A point is
    // first matched, by its bits, against the point of the previous line that the line
    // spacing shifts onto it, and looked up among all the evaluations only when that misses.
    let mut flexibilities = Evaluated::new(n);
    // The previous line's and this line's points: each one's frequency bits and index.
    let mut previous: Vec<(u64, usize)> = Vec::with_capacity(kernel.len());
    let mut current: Vec<(u64, usize)> = Vec::with_capacity(kernel.len());
    let mut previous_f: Option<f64> = None;
    let mut leaked = Vec::with_capacity(freqs_hz.len());
    // Each point's flexibility (its index among the evaluations) and whether it lies below
    // 0 Hz, where the kernel of a real signal's one-sided spectrum reads the conjugate.
    let mut points: Vec<(usize, bool)> = Vec::with_capacity(kernel.len());
    for &f in freqs_hz {
        // Kernel points between this line and the previous one: point `j` here is point
        // `j − shift` there.
        let shift = previous_f
            .map(|p| ((f - p) / step).round())
            .filter(|s| s.is_finite() && *s >= 0.0 && *s < kernel.len() as f64)
            .map(|s| s as usize);
        current.clear();
        points.clear();
        for (j, &(nu, _)) in kernel.iter().enumerate() {
            let at = f - nu;
            let key = at.abs().to_bits();
            let matched = shift
                .and_then(|s| j.checked_sub(s))
                .and_then(|p| previous.get(p))
                .filter(|(bits, _)| *bits == key)
                .map(|&(_, k)| k);
            let k = match matched {
                Some(k) => k,
                None => flexibilities.index_of(model, at.abs())?,
            };
            current.push((key, k));
            points.push((k, at < 0.0));
        }
        let values = &flexibilities.values;
        let g = match n {
            1 => smoothed::<1>(values, &points, &weights).to_vec(),
            2 => smoothed::<4>(values, &points, &weights).to_vec(),
            3 => smoothed::<9>(values, &points, &weights).to_vec(),
            _ => smoothed_any(values, n * n, &points, &weights),
        };
        std::mem::swap(&mut previous, &mut current);
        previous_f = Some(f);
        leaked.push(Mat::from_fn(n, n, |i, j| g[i + j * n]));
    }
    Ok(leaked)
}

/// The kernel's weighted sum $\sum_j w_j G_j$ of the column-major `NN`-element matrices of
/// `values` at `points` (each one's index, and whether it is conjugated), each element summed
/// in the kernel's order: [`smoothed_any`] for a size known when compiling.
fn smoothed<const NN: usize>(
    values: &[c64],
    points: &[(usize, bool)],
    weights: &[f64],
) -> [c64; NN] {
    let mut g = [c64::new(0.0, 0.0); NN];
    for (&(k, conj), &w) in points.iter().zip(weights) {
        // Every index is an evaluation's: the chunk is always there.
        let Some(gf) = values.get(k * NN..).and_then(<[c64]>::first_chunk::<NN>) else {
            continue;
        };
        if conj {
            for (acc, v) in g.iter_mut().zip(gf) {
                *acc += v.conj() * w;
            }
        } else {
            for (acc, v) in g.iter_mut().zip(gf) {
                *acc += v * w;
            }
        }
    }
    g
}

/// [`smoothed`] for matrices of `nn` elements.
fn smoothed_any(values: &[c64], nn: usize, points: &[(usize, bool)], weights: &[f64]) -> Vec<c64> {
    let mut g = vec![c64::new(0.0, 0.0); nn];
    for (&(k, conj), &w) in points.iter().zip(weights) {
        let gf = &values[k * nn..(k + 1) * nn];
        if conj {
            for (acc, v) in g.iter_mut().zip(gf) {
                *acc += v.conj() * w;
            }
        } else {
            for (acc, v) in g.iter_mut().zip(gf) {
                *acc += v * w;
            }
        }
    }
    g
}

/// A model's flexibilities at the frequencies asked for so far, each computed once: keyed by
/// the frequency's bits, so a value read back is the very one
/// [`Coefficients::flexibility_at`] gives.
struct Evaluated {
    n: usize,
    inverter: linalg::Inverter,
    /// Frequency bits to the index of its matrix in `values`.
    index: HashMap<u64, usize, BuildHasherDefault<BitsHasher>>,
    /// Column-major `n × n` flexibilities, one after another.
    values: Vec<c64>,
}

impl Evaluated {
    fn new(n: usize) -> Self {
        Self {
            n,
            inverter: linalg::Inverter::new(n),
            index: HashMap::default(),
            values: Vec::new(),
        }
    }

    /// The flexibility of `model` at `freq_hz`, column-major.
    ///
    /// # Errors
    /// [`Error::Singular`] if the model's impedance is singular there.
    #[cfg(test)]
    fn at(&mut self, model: &Coefficients, freq_hz: f64) -> Result<&[c64]> {
        let nn = self.n * self.n;
        let k = self.index_of(model, freq_hz)?;
        Ok(&self.values[k * nn..(k + 1) * nn])
    }

    /// The index (in matrices of `values`) of the flexibility of `model` at `freq_hz`, evaluated
    /// when it is asked for the first time.
    ///
    /// # Errors
    /// [`Error::Singular`] if the model's impedance is singular there.
    fn index_of(&mut self, model: &Coefficients, freq_hz: f64) -> Result<usize> {
        let nn = self.n * self.n;
        let next = self.values.len() / nn.max(1);
        let k = *self.index.entry(freq_hz.to_bits()).or_insert(next);
        if k == next {
            self.values.resize((next + 1) * nn, c64::new(0.0, 0.0));
            let g = &mut self.values[next * nn..];
            if let Err(e) = model.flexibility_into(freq_hz, &mut self.inverter, g) {
                self.index.remove(&freq_hz.to_bits());
                self.values.truncate(next * nn);
                return Err(e);
            }
        }
        Ok(k)
    }
}

/// The hasher of [`Evaluated`]'s keys, the bits of a frequency: one multiply-xorshift mix
/// (keys come from the program, not from an adversary).
#[derive(Default)]
struct BitsHasher(u64);

impl Hasher for BitsHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, bits: u64) {
        let h = (self.0 ^ bits ^ (bits >> 31)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        self.0 = h ^ (h >> 29);
    }
}

/// $|W(\nu)|^2$ of the periodic Hann window $w_m = \sin^2(\pi m / L)$ of `len` samples at
/// `sample_rate`, from its three shifted Dirichlet kernels.
fn hann_power(nu: f64, len: usize, sample_rate: f64) -> f64 {
    let l = len as f64;
    let dirichlet = |theta: f64| {
        let one = c64::new(1.0, 0.0);
        let den = one - c64::from_polar(1.0, -theta);
        if den.norm() < 1e-12 {
            c64::new(l, 0.0)
        } else {
            (one - c64::from_polar(1.0, -theta * l)) / den
        }
    };
    let theta = 2.0 * std::f64::consts::PI * nu / sample_rate;
    let shift = 2.0 * std::f64::consts::PI / l;
    let w = dirichlet(theta) * 0.5 - (dirichlet(theta - shift) + dirichlet(theta + shift)) * 0.25;
    w.norm_sqr()
}

/// The flexibility the whole-record DFT of an impact response cut at `duration_s` after the
/// hit gives at `freqs_hz`: $G_T(s) = G(s) - e^{-sT}\,[I\;0]\,(sI - A)^{-1} e^{AT} B$ with the
/// state matrix $A = [[0, I], [-M^{-1}K, -M^{-1}C]]$ and $B = [0; M^{-1}]$ (the response's
/// transform over `[0, T]` only).
///
/// # Errors
/// [`Error::Singular`](crate::Error::Singular) if `M` or the model's impedance is singular.
///
/// # Examples
/// ```
/// use bearing_ident::gate::truncated_flexibility;
/// use bearing_ident::Coefficients;
/// use faer::mat;
/// // One mode at 10 Hz, ζ = 1 %: the response decays as e^{-0.63 t}.
/// let sdof = Coefficients::new(mat![[1.0]], mat![[1.2566]], mat![[3947.8]])?;
/// let exact = sdof.flexibility_at(12.0)?[(0, 0)];
/// let long = truncated_flexibility(&sdof, &[12.0], 60.0)?[0][(0, 0)];
/// let short = truncated_flexibility(&sdof, &[12.0], 1.0)?[0][(0, 0)];
/// assert!((long - exact).norm() < 1e-12 * exact.norm());
/// assert!((short - exact).norm() > 0.1 * exact.norm());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn truncated_flexibility(
    model: &Coefficients,
    freqs_hz: &[f64],
    duration_s: f64,
) -> Result<Vec<Mat<c64>>> {
    let n = model.dofs();
    let minv = model
        .mass()
        .to_owned()
        .partial_piv_lu()
        .solve(Mat::<f64>::identity(n, n));
    if !minv.col_iter().all(|c| c.iter().all(|v| v.is_finite())) {
        return Err(crate::Error::Singular {
            what: "mass matrix",
        });
    }
    let mk = &minv * model.stiffness();
    let mc = &minv * model.damping();
    let (mk, mc): (Mat<f64>, Mat<f64>) = (mk, mc);
    let a = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(j - n == i)),
        (false, true) => -mk[(i - n, j)],
        (false, false) => -mc[(i - n, j - n)],
    });
    let scaled = Mat::from_fn(2 * n, 2 * n, |i, j| a[(i, j)] * duration_s);
    let eat = crate::simulate::expm::expm(&scaled);
    let b = Mat::from_fn(2 * n, n, |i, j| if i < n { 0.0 } else { minv[(i - n, j)] });
    let tail = &eat * &b;
    let tail = Mat::from_fn(2 * n, n, |i, j| c64::new(tail[(i, j)], 0.0));
    freqs_hz
        .iter()
        .map(|&f| {
            let w = 2.0 * std::f64::consts::PI * f;
            let s = c64::new(0.0, w);
            let si_a = Mat::from_fn(2 * n, 2 * n, |i, j| {
                let d = if i == j { s } else { c64::new(0.0, 0.0) };
                d - c64::new(a[(i, j)], 0.0)
            });
            let r = si_a.partial_piv_lu().solve(&tail);
            let phase = (-s * duration_s).exp();
            let g = model.flexibility_at(f)?;
            Ok(Mat::from_fn(n, n, |i, j| g[(i, j)] - phase * r[(i, j)]))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    /// The Hann kernel's power at the centre is `(L/2)²` and its first zeros are two line
    /// spacings out.
    #[test]
    fn hann_kernel_has_its_closed_form_values() {
        let (l, fs) = (64usize, 64.0);
        assert!((hann_power(0.0, l, fs) - 32.0f64.powi(2)).abs() < 1e-9);
        assert!(hann_power(2.0, l, fs) < 1e-20);
        // Against the direct sum at an arbitrary offset.
        let nu = 0.37;
        let direct: c64 = (0..l)
            .map(|m| {
                let w = (std::f64::consts::PI * m as f64 / l as f64).sin().powi(2);
                c64::from_polar(w, -2.0 * std::f64::consts::PI * nu * m as f64 / fs)
            })
            .sum();
        assert!((hann_power(nu, l, fs) - direct.norm_sqr()).abs() < 1e-9 * direct.norm_sqr());
    }

    /// The kernel's evaluations are each made once and read back as made: bit for bit the
    /// model's flexibility at every frequency asked for, asked again or not; a singular
    /// impedance is an error and leaves nothing behind.
    #[test]
    fn evaluations_are_the_model_s_flexibility() {
        let rig = crate::simulate::seed_rig();
        let mut evaluated = Evaluated::new(2);
        for f in [12.5, 28.125, 12.5, 0.0, 28.125, 40.0 - 1.0 / 3.0] {
            let direct = rig.flexibility_at(f).unwrap();
            let got = evaluated.at(&rig, f).unwrap();
            for j in 0..2 {
                for i in 0..2 {
                    assert_eq!(got[i + j * 2], direct[(i, j)], "{f}");
                }
            }
        }
        assert_eq!(evaluated.values.len(), 4 * 4);
        // No stiffness or damping: a zero impedance at 0 Hz.
        let free = Coefficients::new(mat![[1.0]], mat![[0.0]], mat![[0.0]]).unwrap();
        let mut evaluated = Evaluated::new(1);
        assert!(free.flexibility_at(0.0).is_err());
        assert!(evaluated.at(&free, 0.0).is_err());
        assert!(evaluated.values.is_empty() && evaluated.index.is_empty());
        assert!(evaluated.at(&free, 1.0).is_ok());
    }

    /// The leaked flexibility is bit for bit the kernel's sum of the model's own flexibilities
    /// evaluated point by point, whatever is shared between lines: 1 to 4 DOF, lines on the
    /// kernel's grid and off it, a kernel set by the line spacing and one set by a light mode,
    /// lines near 0 Hz whose kernel reaches the conjugate side.
    #[test]
    fn leaked_flexibility_is_the_kernel_sum_point_by_point() {
        let direct = |model: &Coefficients, freqs: &[f64], len: usize, rate: f64| {
            let df = rate / len as f64;
            let lightest = model
                .modes()
                .unwrap_or_default()
                .iter()
                .map(|m| 2.0 * m.damping_ratio * m.natural_frequency_hz)
                .filter(|b| b.is_finite() && *b > 0.0)
                .fold(f64::INFINITY, f64::min);
            let step = (df / 8.0).min(lightest / 8.0);
            let half = (8.0 * df / step).ceil() as i64;
            let kernel: Vec<(f64, f64)> = (-half..=half)
                .map(|j| (j as f64 * step, hann_power(j as f64 * step, len, rate)))
                .collect();
            let total: f64 = kernel.iter().map(|(_, w)| w).sum();
            let n = model.dofs();
            freqs
                .iter()
                .map(|&f| {
                    let mut g = Mat::<c64>::zeros(n, n);
                    for &(nu, w) in &kernel {
                        let at = f - nu;
                        let gf = model.flexibility_at(at.abs()).unwrap();
                        for j in 0..n {
                            for i in 0..n {
                                let v = if at < 0.0 {
                                    gf[(i, j)].conj()
                                } else {
                                    gf[(i, j)]
                                };
                                g[(i, j)] += v * (w / total);
                            }
                        }
                    }
                    g
                })
                .collect::<Vec<_>>()
        };
        let rig = crate::simulate::seed_rig();
        let diagonal = |n: usize, c: f64| {
            Coefficients::new(
                Mat::from_fn(
                    n,
                    n,
                    |i, j| if i == j { 1.0 + 0.1 * i as f64 } else { 0.05 },
                ),
                Mat::from_fn(n, n, |i, j| if i == j { c } else { -0.3 * c }),
                Mat::from_fn(n, n, |i, j| {
                    if i == j {
                        4000.0 * (1.0 + i as f64)
                    } else {
                        300.0
                    }
                }),
            )
            .unwrap()
        };
        let cases = [
            (diagonal(1, 2.0), 1024, 500.0),
            (rig.clone(), 4096, 6700.0),
            (rig, 512, 6700.0),
            (diagonal(3, 0.2), 1024, 500.0),
            (diagonal(4, 3.0), 256, 500.0),
        ];
        for (model, len, rate) in cases {
            let df = rate / len as f64;
            let on_grid: Vec<f64> = (1..40).map(|k| k as f64 * df).collect();
            let off_grid: Vec<f64> = (0..25).map(|k| 0.7 + 1.37 * k as f64).collect();
            for freqs in [on_grid, off_grid] {
                let got = leaked_flexibility(&model, &freqs, len, rate).unwrap();
                let want = direct(&model, &freqs, len, rate);
                for (g, w) in got.iter().zip(&want) {
                    for j in 0..model.dofs() {
                        for i in 0..model.dofs() {
                            assert_eq!(g[(i, j)], w[(i, j)], "{} DOF, {len}", model.dofs());
                        }
                    }
                }
            }
        }
    }

    /// An SDOF impulse response cut at T: the truncated transform against its closed form
    /// $\int_0^T h(t) e^{-i\omega t} dt$ with $h = e^{-\sigma t}\sin(\omega_d t)/(m\omega_d)$.
    #[test]
    fn truncated_flexibility_is_the_transform_over_the_record() {
        let (m, c, k) = (2.0, 3.0, 5000.0);
        let sdof = Coefficients::new(mat![[m]], mat![[c]], mat![[k]]).unwrap();
        let (sigma, wd) = (c / (2.0 * m), (k / m - (c / (2.0 * m)).powi(2)).sqrt());
        let t = 0.4;
        let f = 9.0;
        let w = 2.0 * std::f64::consts::PI * f;
        // ∫0^T e^{(p − iω)t} dt for p = −σ ± iω_d, combined into sin.
        let part = |p: c64| (((p - c64::new(0.0, w)) * t).exp() - 1.0) / (p - c64::new(0.0, w));
        let plus = part(c64::new(-sigma, wd));
        let minus = part(c64::new(-sigma, -wd));
        let closed = (plus - minus) / c64::new(0.0, 2.0 * m * wd);
        let got = truncated_flexibility(&sdof, &[f], t).unwrap()[0][(0, 0)];
        assert!(
            (got - closed).norm() < 1e-10 * closed.norm(),
            "{got} vs {closed}"
        );
    }

    /// Exact data processed by nothing predict no bias.
    #[test]
    fn unprocessed_flexibility_predicts_no_bias() {
        let model = crate::simulate::seed_rig();
        let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
        let g: Vec<Mat<c64>> = freqs
            .iter()
            .map(|&f| model.flexibility_at(f).unwrap())
            .collect();
        let b = predicted_bias(
            &model,
            &freqs,
            g,
            Method::Ivf,
            &IvfOptions::default(),
            BiasSource::Leakage,
        )
        .unwrap();
        assert!(b.bias.damping()[(0, 0)].abs() < 1e-9 * 131.98);
    }

    /// A mode far lighter than the line spacing is refused at once, not integrated on a grid
    /// sized by its bandwidth (a fuzzed input, ζ ≈ 1e-12 at 1e-4 S/s, took 8 GB and 111 s).
    #[test]
    fn a_mode_far_lighter_than_the_lines_is_not_predicted() {
        use faer::mat;
        let light = Coefficients::new(mat![[1.0]], mat![[1e-12]], mat![[3947.8]]).unwrap();
        let start = std::time::Instant::now();
        let e = super::leaked_flexibility(&light, &[10.0], 1024, 500.0).unwrap_err();
        assert!(matches!(
            e,
            Error::InvalidParameter {
                name: Parameter::LightestBandwidth,
                ..
            }
        ));
        assert!(start.elapsed().as_secs_f64() < 1.0);
        // At 1/32 of the spacing it is still predicted.
        let df = 500.0 / 1024.0;
        let c = 2.0 * std::f64::consts::PI * (df / 32.0); // bandwidth 2ζf_n = c/(2πm)
        let ok = Coefficients::new(mat![[1.0]], mat![[c]], mat![[3947.8]]).unwrap();
        assert!(super::leaked_flexibility(&ok, &[10.0], 1024, 500.0).is_ok());
    }
}
