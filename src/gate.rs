//! The fit gate: checks of a finished fit and of the settings it was made with, each finding a
//! typed [`Warning`].
//!
//! A fit can be wrong without failing: a window that leaves almost nothing of the record, a force
//! gate that cuts the pulse, segments too short to resolve the modes, or records passed twice
//! all return numbers. The checks here look at the result and at the settings against the
//! records, and say what they see:
//!
//! | check | warning | rule |
//! |---|---|---|
//! | fit quality | [`Warning::PoorFit`] | flexibility $r^2_{ij}$ below [`FitGate::min_r2`] on an element that carries signal ([`significant_elements`]) |
//! | physics | [`Warning::NegativeDiagonal`] | a diagonal entry of `M`, `C` or `K` below zero |
//! | stability | [`Warning::UnstableMode`] | a mode of the fitted model with a negative damping ratio |
//! | error bars | [`Warning::DependentReplicates`] | two or more jackknife replicates give the same fit (to [`ALIKE`]) |
//! | error bars | [`Warning::ZeroSpread`] | a resampled standard deviation of a diagonal entry below [`ALIKE`] × its value |
//! | window | [`Warning::WindowTooShort`] | exponential decay rate $a > 2\pi f_{low}$ |
//! | force gate | [`Warning::ForceGateShort`] | the gate closes before the force pulse has ended ([`pulse_end_s`]) |
//! | resolution | [`Warning::CoarseResolution`] | Welch line spacing with a predicted peak bias $(\Delta f / B_r)^2/3$ above [`MAX_LEAKAGE_BIAS`] |
//! | redundancy | [`Warning::FewLines`] | fewer than [`MIN_REDUNDANCY`] equations per unknown |
//!
//! The checks are for the whole test system (rig plus element), where every diagonal entry and
//! every mode is physical; a bearing's own coefficients after baseline subtraction are not
//! gated.

use faer::{Mat, MatRef};

use crate::error::{Block, Error, Result, Warning};
use crate::frf::{Band, Frf};
use crate::model::Coefficients;
use crate::spectra::{ForceGate, Segmentation, Window};

pub use crate::tolerance::ALIKE;

mod bias;
mod causes;
pub(crate) use bias::worst_in;
pub use bias::{
    BiasSource, PredictedBias, leaked_flexibility, predicted_bias, truncated_flexibility,
};
pub use causes::{TRANSFER_FRACTION, negative_diagonal_causes};

/// An off-diagonal flexibility element carries signal when its RMS over the band is at least
/// this fraction of the geometric mean of the two diagonal elements' RMS; below it, its `r²`
/// measures noise about zero and says nothing of the fit.
pub const SIGNIFICANT_CROSS: f64 = 0.1;

/// Largest predicted relative peak bias of a Welch (Hann) estimate at a mode,
/// $\epsilon_b \approx (\Delta f / B_r)^2 / 3$ with $B_r = 2\zeta f_n$ (Bendat & Piersol), before
/// [`Warning::CoarseResolution`] is raised.
pub const MAX_LEAKAGE_BIAS: f64 = 0.05;

/// Fewest equations per unknown (`2n` real equations per line and column, `3n` unknowns per
/// column) below which [`Warning::FewLines`] is raised: the fit then has little redundancy to
/// average noise and to show a misfit.
pub const MIN_REDUNDANCY: f64 = 5.0;

/// Fraction of the force pulse's peak (above the record's median) that marks the pulse's end
/// in [`pulse_end_s`].
pub const PULSE_END_FRACTION: f64 = 0.1;

/// Settings of the fit gate.
///
/// # Examples
/// ```
/// use bearing_ident::gate::FitGate;
/// assert_eq!(FitGate::default().min_r2, 0.9);
/// assert!(FitGate { min_r2: 0.95 }.check().is_ok());
/// assert!(FitGate { min_r2: f64::NAN }.check().is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitGate {
    /// Smallest acceptable flexibility `r²` of an element that carries signal; default 0.9,
    /// any value ≤ 1 (`f64::NEG_INFINITY` turns the check off).
    pub min_r2: f64,
}

impl Default for FitGate {
    fn default() -> Self {
        Self { min_r2: 0.9 }
    }
}

impl FitGate {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when `min_r2` is NaN or above 1.
    pub fn check(&self) -> Result<()> {
        if self.min_r2.is_nan() || self.min_r2 > 1.0 {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::MinimumR2,
                value: self.min_r2,
                expected: "at most 1",
            });
        }
        Ok(())
    }

    /// [`Warning::PoorFit`] for every element of `r2` that carries signal in `frf`
    /// ([`significant_elements`]) with $r^2 <$ [`FitGate::min_r2`] (NaN counts as below).
    pub fn poor_fit(&self, frf: &Frf, r2: MatRef<'_, f64>) -> Vec<Warning> {
        let significant = significant_elements(frf);
        let n = r2.nrows();
        let mut out = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let r = r2[(i, j)];
                if significant[(i, j)] && (r.is_nan() || r < self.min_r2) {
                    out.push(Warning::PoorFit {
                        row: i,
                        col: j,
                        r2: r,
                        threshold: self.min_r2,
                    });
                }
            }
        }
        out
    }
}

/// Which flexibility elements carry signal: the diagonal always; an off-diagonal element when its
/// RMS over the band is at least [`SIGNIFICANT_CROSS`] times
/// $\sqrt{\mathrm{rms}(G_{ii})\,\mathrm{rms}(G_{jj})}$.
///
/// # Examples
/// ```
/// use bearing_ident::{Coefficients, Frf, gate::significant_elements};
/// use bearing_ident::faer::mat;
/// // An uncoupled rig: its cross flexibilities are zero, so only the diagonal counts.
/// let rig = Coefficients::new(mat![[4.7, 0.0], [0.0, 4.8]], mat![[132.0, 0.0], [0.0, 132.0]],
///     mat![[146.3e3, 0.0], [0.0, 169.1e3]])?;
/// let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
/// let g: Vec<_> = freqs.iter().map(|&f| rig.flexibility_at(f)).collect::<Result<_, _>>()?;
/// let s = significant_elements(&Frf::from_flexibility(freqs, &g)?);
/// assert!(s[(0, 0)] && s[(1, 1)] && !s[(0, 1)] && !s[(1, 0)]);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn significant_elements(frf: &Frf) -> Mat<bool> {
    let n = frf.dofs();
    let mut power = Mat::<f64>::zeros(n, n);
    for k in 0..frf.line_count() {
        let g = frf.flexibility(k);
        for j in 0..n {
            for i in 0..n {
                power[(i, j)] += g[(i, j)].norm_sqr();
            }
        }
    }
    Mat::from_fn(n, n, |i, j| {
        i == j
            || power[(i, j)].sqrt()
                >= SIGNIFICANT_CROSS * (power[(i, i)].sqrt() * power[(j, j)].sqrt()).sqrt()
    })
}

/// [`Warning::NegativeDiagonal`] for each diagonal entry of `M`, `C`, `K` below zero, and
/// [`Warning::UnstableMode`] for each eigenvalue $\lambda$ of the state matrix with
/// $\mathrm{Re}\,\lambda > 0$ (damping ratio $-\mathrm{Re}\,\lambda/|\lambda| < 0$).
pub fn physics(c: &Coefficients) -> Vec<Warning> {
    let mut out = Vec::new();
    for (block, m) in [
        (Block::Mass, c.mass()),
        (Block::Damping, c.damping()),
        (Block::Stiffness, c.stiffness()),
    ] {
        for i in 0..c.dofs() {
            if m[(i, i)] < 0.0 {
                out.push(Warning::NegativeDiagonal {
                    block,
                    dof: i,
                    value: m[(i, i)],
                });
            }
        }
    }
    // A singular mass matrix has no eigenvalues to judge. Of a conjugate pair, one is reported;
    // a real eigenvalue above zero (divergence) has damping ratio −1.
    for l in c.eigenvalues().unwrap_or_default() {
        if l.re > 0.0 && l.im >= 0.0 {
            out.push(Warning::UnstableMode {
                frequency_hz: l.norm() / (2.0 * std::f64::consts::PI),
                damping_ratio: -l.re / l.norm(),
            });
        }
    }
    out
}

/// [`Warning::WindowTooShort`] when an exponential window decays faster than the lowest band
/// frequency, $a > 2\pi f_{low}$: the window then adds to every mode of the band a decay rate
/// above its own frequency, the windowed flexibility is nearly flat, and the exact correction
/// $C = C_w - 2aM_w$, $K = K_w - aC_w + a^2M_w$ subtracts large, nearly equal numbers.
///
/// # Examples
/// ```
/// use bearing_ident::{Band, Window, gate::window};
/// let band = Band::new(8.0, 49.0)?;
/// assert!(window(Window::exponential_to(0.01, 1.2), band).is_none());
/// assert!(window(Window::exponential_to(1e-300, 1.2), band).is_some());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn window(window: Window, band: Band) -> Option<Warning> {
    let a = window.decay_per_s()?;
    let limit = 2.0 * std::f64::consts::PI * band.low_hz();
    (a > limit).then_some(Warning::WindowTooShort {
        decay_per_s: a,
        limit_per_s: limit,
    })
}

/// Time (s from the first sample) at which the largest pulse of `force` has fallen back below
/// [`PULSE_END_FRACTION`] of its peak, both measured from the record's median; `None` for a
/// flat signal.
///
/// # Examples
/// ```
/// use bearing_ident::gate::pulse_end_s;
/// // A 2 ms half-sine at 1 kHz sampling after 5 ms of quiet.
/// let f: Vec<f64> = (0..100)
///     .map(|m| {
///         let t = m as f64 * 1e-3 - 0.005;
///         if (0.0..0.002).contains(&t) { (std::f64::consts::PI * t / 0.002).sin() } else { 0.0 }
///     })
///     .collect();
/// assert_eq!(pulse_end_s(&f, 1e-3), Some(0.007));
/// ```
pub fn pulse_end_s(force: &[f64], dt: f64) -> Option<f64> {
    let mut sorted: Vec<f64> = force.iter().copied().filter(|v| v.is_finite()).collect();
    if sorted.is_empty() {
        return None;
    }
    let mid = sorted.len() / 2;
    let median = *sorted.select_nth_unstable_by(mid, f64::total_cmp).1;
    let (peak_at, peak) = force
        .iter()
        .map(|v| (v - median).abs())
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    if peak.is_nan() || peak <= 0.0 {
        return None;
    }
    let end = force[peak_at..]
        .iter()
        .position(|v| (v - median).abs() < PULSE_END_FRACTION * peak)
        .map_or(force.len(), |p| peak_at + p);
    Some(end as f64 * dt)
}

/// The longest force pulse among records against a force gate: feed each record's pulse ends
/// with [`ForceGateCheck::record`], then [`ForceGateCheck::warning`].
#[derive(Debug, Clone, Copy)]
pub struct ForceGateCheck {
    gate: ForceGate,
    records: usize,
    longest_s: f64,
}

impl ForceGateCheck {
    /// A check of `gate`, nothing seen yet.
    pub fn new(gate: ForceGate) -> Self {
        Self {
            gate,
            records: 0,
            longest_s: 0.0,
        }
    }

    /// Notes the forces of one record sampled `dt` apart (the gate runs from the record's first
    /// sample).
    pub fn record<'a>(&mut self, forces: impl IntoIterator<Item = &'a [f64]>, dt: f64) {
        let end = forces
            .into_iter()
            .filter_map(|f| pulse_end_s(f, dt))
            .fold(0.0, f64::max);
        if end > self.gate.open_s() {
            self.records += 1;
            self.longest_s = self.longest_s.max(end);
        }
    }

    /// [`Warning::ForceGateShort`] if the gate closed on a pulse in any record.
    pub fn warning(&self) -> Option<Warning> {
        (self.records > 0).then_some(Warning::ForceGateShort {
            records: self.records,
            gate_s: self.gate.open_s(),
            pulse_end_s: self.longest_s,
        })
    }
}

/// [`Warning::CoarseResolution`] for each stable mode inside the band whose half-power
/// bandwidth $B_r = 2\zeta f_n$ is too narrow for the Welch line spacing $\Delta f$: the Hann
/// window's peak bias $\epsilon_b \approx (\Delta f / B_r)^2/3$ exceeds [`MAX_LEAKAGE_BIAS`].
/// Whole records and whole periods are not windowed segments and are not checked. `spacing_hz`
/// is the line spacing of the segments.
pub fn resolution(
    segmentation: Segmentation,
    spacing_hz: f64,
    band: Band,
    model: &Coefficients,
) -> Vec<Warning> {
    if !matches!(segmentation, Segmentation::Welch { .. }) {
        return Vec::new();
    }
    model
        .modes()
        .unwrap_or_default()
        .into_iter()
        .filter(|m| {
            m.damping_ratio > 0.0
                && m.natural_frequency_hz >= band.low_hz()
                && m.natural_frequency_hz <= band.high_hz()
        })
        .filter_map(|m| {
            let half_power_hz = 2.0 * m.damping_ratio * m.natural_frequency_hz;
            let bias = leakage_bias(spacing_hz, half_power_hz);
            (bias > MAX_LEAKAGE_BIAS).then_some(Warning::CoarseResolution {
                spacing_hz,
                mode_hz: m.natural_frequency_hz,
                half_power_hz,
                peak_bias: bias,
            })
        })
        .collect()
}

/// Predicted relative bias of a resonance peak of half-power bandwidth `B_r = 2ζf_n`
/// (`half_power_hz`) under Hann-windowed Welch segments of line spacing `Δf`
/// (`spacing_hz`): $\epsilon_b \approx (\Delta f / B_r)^2/3$ (Bendat & Piersol); the peak comes
/// out low and the mode's damping high by about as much.
///
/// # Examples
/// ```
/// use bearing_ident::gate::leakage_bias;
/// assert!((leakage_bias(0.5, 4.0) - 1.0 / 192.0).abs() < 1e-15);
/// ```
pub fn leakage_bias(spacing_hz: f64, half_power_hz: f64) -> f64 {
    (spacing_hz / half_power_hz).powi(2) / 3.0
}

/// [`Warning::FewLines`] when `lines` lines give fewer than [`MIN_REDUNDANCY`] equations per
/// unknown for `n` degrees of freedom ($2nN / 3n = 2N/3$).
///
/// # Examples
/// ```
/// use bearing_ident::gate::few_lines;
/// assert!(few_lines(7, 2).is_some());
/// assert!(few_lines(49, 2).is_none());
/// ```
pub fn few_lines(lines: usize, n: usize) -> Option<Warning> {
    let ratio = (2 * n * lines) as f64 / (3 * n) as f64;
    (ratio < MIN_REDUNDANCY).then_some(Warning::FewLines {
        lines,
        needed: (1.5 * MIN_REDUNDANCY).ceil() as usize,
    })
}

/// Replicate fits (stacked `[M; C; K]`) that agree element by element within [`ALIKE`] of the
/// largest magnitude of that element: the number of distinct fits. Fewer than `fits.len()`
/// means some replicates carry the same data (records passed twice), and the spread of the
/// fits understates the error.
pub fn distinct_fits(fits: &[Mat<f64>]) -> usize {
    let Some(first) = fits.first() else {
        return 0;
    };
    let scale = Mat::from_fn(first.nrows(), first.ncols(), |i, j| {
        fits.iter().map(|t| t[(i, j)].abs()).fold(0.0, f64::max)
    });
    let alike = |a: &Mat<f64>, b: &Mat<f64>| {
        (0..a.ncols())
            .all(|j| (0..a.nrows()).all(|i| (a[(i, j)] - b[(i, j)]).abs() <= ALIKE * scale[(i, j)]))
    };
    let mut representatives: Vec<&Mat<f64>> = Vec::new();
    for t in fits {
        if !representatives.iter().any(|r| alike(r, t)) {
            representatives.push(t);
        }
    }
    representatives.len()
}

/// [`Warning::ZeroSpread`] when a resampled standard deviation of a diagonal entry is below
/// [`ALIKE`] times the entry: the replicates all gave the same fit.
pub fn zero_spread(std: &Coefficients, value: &Coefficients) -> Option<Warning> {
    let n = value.dofs();
    let pairs = [
        (std.mass(), value.mass()),
        (std.damping(), value.damping()),
        (std.stiffness(), value.stiffness()),
    ];
    let zero = pairs
        .iter()
        .flat_map(|(s, v)| (0..n).map(move |i| (s[(i, i)], v[(i, i)])))
        .filter(|(s, v)| *s <= ALIKE * v.abs())
        .count();
    (zero > 0).then_some(Warning::ZeroSpread {
        entries: zero,
        of: 3 * n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::seed_rig;

    /// The seed's rig without its cross-coupled stiffness, a cross term of `noise_cross` × the
    /// direct one added.
    fn seed_frf(noise_cross: f64) -> Frf {
        let rig = seed_rig();
        let mut k = rig.stiffness().to_owned();
        k[(0, 1)] = 0.0;
        k[(1, 0)] = 0.0;
        let truth = Coefficients::new(rig.mass().to_owned(), rig.damping().to_owned(), k).unwrap();
        let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
        let g: Vec<_> = freqs
            .iter()
            .map(|&f| {
                let mut g = truth.flexibility_at(f).unwrap();
                let d = g[(0, 0)].norm();
                g[(0, 1)] += faer::c64::new(noise_cross * d, 0.0);
                g
            })
            .collect();
        Frf::from_flexibility(freqs, &g).unwrap()
    }

    #[test]
    fn r2_is_judged_only_where_there_is_signal() {
        let gate = FitGate::default();
        let frf = seed_frf(0.0);
        let mut r2 = Mat::from_fn(2, 2, |i, j| if i == j { 0.99 } else { -3.0 });
        assert!(gate.poor_fit(&frf, r2.as_ref()).is_empty());
        r2[(1, 1)] = 0.5;
        let w = gate.poor_fit(&frf, r2.as_ref());
        assert_eq!(
            w,
            vec![Warning::PoorFit {
                row: 1,
                col: 1,
                r2: 0.5,
                threshold: 0.9
            }]
        );
        // A cross term as large as the diagonal is judged.
        let frf = seed_frf(1.0);
        let w = gate.poor_fit(&frf, r2.as_ref());
        assert!(
            w.iter()
                .any(|w| matches!(w, Warning::PoorFit { row: 0, col: 1, .. }))
        );
        r2[(1, 1)] = f64::NAN;
        assert_eq!(gate.poor_fit(&seed_frf(0.0), r2.as_ref()).len(), 1);
    }

    #[test]
    fn negative_diagonals_and_unstable_modes_are_named() {
        let truth = seed_rig();
        assert!(physics(&truth).is_empty());
        let mut c = truth.damping().to_owned();
        c[(1, 1)] = -300.0;
        let bad =
            Coefficients::new(truth.mass().to_owned(), c, truth.stiffness().to_owned()).unwrap();
        let w = physics(&bad);
        assert!(w.contains(&Warning::NegativeDiagonal {
            block: Block::Damping,
            dof: 1,
            value: -300.0
        }));
        assert!(w.iter().any(
            |w| matches!(w, Warning::UnstableMode { damping_ratio, .. } if *damping_ratio < 0.0)
        ));
    }

    #[test]
    fn the_gate_must_cover_the_pulse() {
        let dt = 1.0 / 6700.0;
        let pulse: Vec<f64> = (0..8040)
            .map(|m| {
                let t = m as f64 * dt - 0.02;
                if (0.0..0.002).contains(&t) {
                    500.0 * (std::f64::consts::PI * t / 0.002).sin()
                } else {
                    0.0
                }
            })
            .collect();
        let end = pulse_end_s(&pulse, dt).unwrap();
        assert!((end - 0.022).abs() < 2.0 * dt, "{end}");
        let mut ok = ForceGateCheck::new(ForceGate::new(0.035, 0.007).unwrap());
        ok.record([pulse.as_slice()], dt);
        assert!(ok.warning().is_none());
        let mut short = ForceGateCheck::new(ForceGate::new(1e-9, 2e-10).unwrap());
        short.record([pulse.as_slice(), pulse.as_slice()], dt);
        short.record([pulse.as_slice()], dt);
        assert!(matches!(
            short.warning(),
            Some(Warning::ForceGateShort { records: 2, .. })
        ));
        assert_eq!(pulse_end_s(&[0.0; 16], dt), None);
        assert_eq!(pulse_end_s(&[f64::NAN; 4], dt), None);
    }

    #[test]
    fn welch_resolution_is_judged_against_the_half_power_bandwidth() {
        let band = Band::new(8.0, 49.0).unwrap();
        let welch = Segmentation::Welch { len: 1000 };
        // Seed rig: ζ ≈ 0.08 at 28 Hz, B_r ≈ 4.5 Hz.
        assert!(resolution(welch, 0.8, band, &seed_rig()).is_empty());
        let w = resolution(welch, 6.7, band, &seed_rig());
        assert!(!w.is_empty());
        assert!(resolution(Segmentation::WholeRecord, 6.7, band, &seed_rig()).is_empty());
    }

    #[test]
    fn distinct_fits_see_duplicates_through_rounding() {
        let a = Mat::from_fn(6, 2, |i, j| (i * 2 + j) as f64 * 1e3 + 1.0);
        let mut b = a.clone();
        b[(5, 1)] *= 1.0 + 1e-14;
        let mut c = a.clone();
        c[(0, 0)] *= 1.0 + 1e-6;
        assert_eq!(distinct_fits(&[a.clone(), b.clone()]), 1);
        assert_eq!(distinct_fits(&[a, b, c]), 2);
        assert_eq!(distinct_fits(&[]), 0);
    }

    #[test]
    fn zero_spread_is_reported_per_diagonal_entry() {
        let truth = seed_rig();
        let std = Coefficients::new(
            Mat::from_fn(2, 2, |_, _| 0.01),
            Mat::from_fn(2, 2, |_, _| 1.0),
            Mat::from_fn(2, 2, |_, _| 100.0),
        )
        .unwrap();
        assert!(zero_spread(&std, &truth).is_none());
        let zero = Coefficients::new(Mat::zeros(2, 2), Mat::zeros(2, 2), Mat::zeros(2, 2)).unwrap();
        assert_eq!(
            zero_spread(&zero, &truth),
            Some(Warning::ZeroSpread { entries: 6, of: 6 })
        );
    }

    #[test]
    fn settings_are_checked() {
        assert!(FitGate { min_r2: 1.5 }.check().is_err());
        assert!(
            FitGate {
                min_r2: f64::NEG_INFINITY
            }
            .check()
            .is_ok()
        );
        assert!(few_lines(6, 3).is_some());
        assert!(few_lines(8, 1).is_none());
    }
}
