//! Stage 6 (optional): frequency-dependent coefficients, line by line.
//!
//! A fluid film's stiffness and damping may change with frequency; the constant `M`, `C`, `K`
//! fit averages that away. Line by line, with the mass matrix `M` from the fit (or given),
//!
//! $$K(\omega_k) = \operatorname{Re} H_k + \omega_k^2 M, \qquad
//!   C(\omega_k) = \operatorname{Im} H_k / \omega_k,$$
//!
//! element by element. Under an exponential window of decay `a` the measured impedance is
//! `H(iω + a)`, and the same exact correction as for the fit applies line by line:
//! `C(ω) = Im H/ω − 2aM`, `K(ω) = Re H + ω²M − a Im H/ω + a²M`.
//!
//! Error bars come from the measured impedance's variance
//! ([`Frf::impedance_variance`]): `Re H` and `Im H` each carry half of `E|δH|²`, so
//! `σ_K = √(E|δH|²/2)` and `σ_C = σ_K / ω`. The uncertainty of `M` is **not** included: it moves
//! every line's `K(ω)` together by `ω² δM` and is reported with `M` itself.
//!
//! For an isotropic two-degree-of-freedom element (`K_xx ≈ K_yy`, `K_xy ≈ −K_yx`, likewise `C`)
//! whirling in a circular forward orbit at the excitation frequency, the forces reduce to an
//! effective stiffness and damping,
//!
//! $$K_\text{eff} = K + \omega c, \qquad C_\text{eff} = C - k/\omega,$$
//!
//! with the isotropic parts `K = (K_xx + K_yy)/2`, `k = (K_xy − K_yx)/2`,
//! `C = (C_xx + C_yy)/2`, `c = (C_xy − C_yx)/2`. A positive `C_eff` means the element damps
//! forward whirl; where it turns negative the element feeds it.

use faer::{Mat, MatRef};

use crate::error::{Error, Result};
use crate::frf::Frf;

/// Stiffness and damping per frequency line, with error bars when the FRF carries a variance.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let pf = id.per_frequency()?;
/// assert_eq!(pf.freqs_hz().len(), 49);
/// // The test system's coefficients do not depend on frequency: K(ω) = K on every line.
/// assert!((pf.stiffness(20)[(0, 0)] / 146.3e3 - 1.0).abs() < 1e-6);
/// assert!((pf.damping(20)[(1, 1)] / 131.98 - 1.0).abs() < 1e-6);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PerFrequency {
    freqs_hz: Vec<f64>,
    stiffness: Vec<Mat<f64>>,
    damping: Vec<Mat<f64>>,
    stiffness_std: Option<Vec<Mat<f64>>>,
    damping_std: Option<Vec<Mat<f64>>>,
}

/// Effective stiffness and damping of an isotropic element at one line (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Effective {
    /// Frequency (Hz).
    pub freq_hz: f64,
    /// `K_eff = K + ω c` (N/m).
    pub stiffness: f64,
    /// `C_eff = C − k/ω` (N·s/m).
    pub damping: f64,
    /// Standard deviation of `K_eff`, treating the elements' errors as independent.
    pub stiffness_std: Option<f64>,
    /// Standard deviation of `C_eff`, likewise.
    pub damping_std: Option<f64>,
}

impl PerFrequency {
    /// `K(ω)` and `C(ω)` on every line of `frf`, with the mass matrix `mass`, for spectra
    /// taken under an exponential window of decay `window_decay_per_s` (0 for any other
    /// window).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if `mass` is not `n × n` or not finite, or the decay is
    /// negative or not finite.
    pub fn new(frf: &Frf, mass: MatRef<'_, f64>, window_decay_per_s: f64) -> Result<Self> {
        let a = window_decay_per_s;
        if !(a.is_finite() && a >= 0.0) {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::ExponentialWindowDecay,
                value: a,
                expected: "finite and ≥ 0 (1/s)",
            });
        }
        let n = frf.dofs();
        if mass.nrows() != n || mass.ncols() != n {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::MassMatrixSize,
                value: mass.nrows() as f64,
                expected: "n × n, as the FRF",
            });
        }
        let entries = (0..n).flat_map(|j| (0..n).map(move |i| (i, j)));
        if let Some(value) = entries.map(|(i, j)| mass[(i, j)]).find(|v| !v.is_finite()) {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::MassMatrix,
                value,
                expected: "finite entries",
            });
        }
        let lines = frf.line_count();
        let mut stiffness = Vec::with_capacity(lines);
        let mut damping = Vec::with_capacity(lines);
        let with_std = (0..lines).all(|k| frf.impedance_variance(k).is_some()) && lines > 0;
        let (mut k_std, mut c_std) = (Vec::new(), Vec::new());
        for (k, &f) in frf.freqs_hz().iter().enumerate() {
            let w = 2.0 * std::f64::consts::PI * f;
            let h = frf.impedance(k);
            stiffness.push(Mat::from_fn(n, n, |i, j| {
                h[(i, j)].re + (w * w + a * a) * mass[(i, j)] - a * h[(i, j)].im / w
            }));
            damping.push(Mat::from_fn(n, n, |i, j| {
                h[(i, j)].im / w - 2.0 * a * mass[(i, j)]
            }));
            if let Some(v) = frf.impedance_variance(k).filter(|_| with_std) {
                // Re H and Im H each carry half of E|δH|².
                let s = Mat::from_fn(n, n, |i, j| (v[(i, j)] / 2.0).sqrt());
                c_std.push(Mat::from_fn(n, n, |i, j| s[(i, j)] / w));
                k_std.push(Mat::from_fn(n, n, |i, j| {
                    s[(i, j)] * (1.0 + a * a / (w * w)).sqrt()
                }));
            }
        }
        Ok(Self {
            freqs_hz: frf.freqs_hz().to_vec(),
            stiffness,
            damping,
            stiffness_std: with_std.then_some(k_std),
            damping_std: with_std.then_some(c_std),
        })
    }

    /// Frequencies of the lines (Hz).
    pub fn freqs_hz(&self) -> &[f64] {
        &self.freqs_hz
    }

    /// `K(ω)` at line `k` (N/m).
    ///
    /// # Panics
    /// If `k` is not a line index.
    pub fn stiffness(&self, k: usize) -> MatRef<'_, f64> {
        self.stiffness[k].as_ref()
    }

    /// `C(ω)` at line `k` (N·s/m).
    ///
    /// # Panics
    /// If `k` is not a line index.
    pub fn damping(&self, k: usize) -> MatRef<'_, f64> {
        self.damping[k].as_ref()
    }

    /// Standard deviation of `K(ω)` at line `k`, when the FRF carries a variance.
    pub fn stiffness_std(&self, k: usize) -> Option<MatRef<'_, f64>> {
        self.stiffness_std.as_ref()?.get(k).map(Mat::as_ref)
    }

    /// Standard deviation of `C(ω)` at line `k`, when the FRF carries a variance.
    pub fn damping_std(&self, k: usize) -> Option<MatRef<'_, f64>> {
        self.damping_std.as_ref()?.get(k).map(Mat::as_ref)
    }

    /// Effective coefficients of an isotropic two-degree-of-freedom element on every line
    /// (see the module docs); `None` unless `n = 2`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Frf;
    /// use bearing_ident::per_frequency::PerFrequency;
    /// use bearing_ident::model::Coefficients;
    /// use faer::mat;
    /// // Isotropic: K = 1e5, k = 2e4 (K_xy = −K_yx), C = 300, c = 50.
    /// let coeffs = Coefficients::new(
    ///     mat![[2.0, 0.0], [0.0, 2.0]],
    ///     mat![[300.0, 50.0], [-50.0, 300.0]],
    ///     mat![[1e5, 2e4], [-2e4, 1e5]],
    /// )?;
    /// let g = vec![coeffs.flexibility_at(10.0)?];
    /// let pf = PerFrequency::new(&Frf::from_flexibility(vec![10.0], &g)?, coeffs.mass(), 0.0)?;
    /// let eff = pf.effective().unwrap()[0];
    /// let w = 20.0 * std::f64::consts::PI;
    /// assert!((eff.stiffness - (1e5 + w * 50.0)).abs() < 1e-6);
    /// assert!((eff.damping - (300.0 - 2e4 / w)).abs() < 1e-9);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn effective(&self) -> Option<Vec<Effective>> {
        if self.stiffness.first()?.nrows() != 2 {
            return None;
        }
        let out = self
            .freqs_hz
            .iter()
            .enumerate()
            .map(|(l, &f)| {
                let w = 2.0 * std::f64::consts::PI * f;
                let (k, c) = (&self.stiffness[l], &self.damping[l]);
                let direct_k = 0.5 * (k[(0, 0)] + k[(1, 1)]);
                let cross_k = 0.5 * (k[(0, 1)] - k[(1, 0)]);
                let direct_c = 0.5 * (c[(0, 0)] + c[(1, 1)]);
                let cross_c = 0.5 * (c[(0, 1)] - c[(1, 0)]);
                // Half the root-sum-square of two elements' standard deviations.
                let half = |m: MatRef<'_, f64>, a: (usize, usize), b: (usize, usize)| {
                    0.5 * m[a].hypot(m[b])
                };
                let std = self
                    .stiffness_std(l)
                    .zip(self.damping_std(l))
                    .map(|(ks, cs)| {
                        let kd = half(ks, (0, 0), (1, 1));
                        let kc = half(ks, (0, 1), (1, 0));
                        let cd = half(cs, (0, 0), (1, 1));
                        let cc = half(cs, (0, 1), (1, 0));
                        (kd.hypot(w * cc), cd.hypot(kc / w))
                    });
                Effective {
                    freq_hz: f,
                    stiffness: direct_k + w * cross_c,
                    damping: direct_c - cross_k / w,
                    stiffness_std: std.map(|s| s.0),
                    damping_std: std.map(|s| s.1),
                }
            })
            .collect();
        Some(out)
    }
}
