//! The measurement noise of the force and response channels as the records show it
//! ([`NoiseFloor`]), and H1 compensated for the force channels' share of it.
//!
//! # Why
//! With noise of power $N_f$ (per average, per line) on the force channels and $N_x$ on the
//! responses, the cross-spectral sums of `A` averages are, in expectation,
//! $S_{ff} = A(P + N_f)$, $S_{xf} = A\,G P$, $S_{xx} = A(G P G^H + N_x)$ for the forces' true
//! spectral matrix `P`. H1, $S_{xf} S_{ff}^{-1} = G P (P + N_f)^{-1}$, is unbiased for response
//! noise and biased by the force noise: its impedance is too stiff, too heavy and too damped by
//! the forces' noise-to-signal ratio. Coherence sees only the sum of the two noises; which
//! channel holds it decides whether H1 or H2 is right, and a bearing rig can have either (a
//! clean load cell and noisy probes, or the reverse). Two kinds of records show the split:
//!
//! - **Periods** ([`Segmentation::Periods`]): a steady periodic force repeats exactly, so the
//!   scatter of a channel's spectrum over the periods at an excited line is its noise. With `R`
//!   records of `P` periods, $N_c = (S_{cc} - \sum_r |\Sigma_p X_{c,rp}|^2 / P) / (R(P-1))$,
//!   with $R(P-1)$ complex degrees of freedom, line by line.
//! - **Welch segments** ([`Segmentation::Welch`]): the response left unexplained by the forces,
//!   $S_{xx\cdot f} = S_{xx} - S_{xf} S_{ff}^{-1} S_{fx}$, holds
//!   $(A - n)\,[N_x + G N_f G^H]$ to first order, plus the coherence the window's leakage costs
//!   where the flexibility changes fast, $\lambda \sum_j |\partial G_{ij}/\partial f|^2 P_j$
//!   ($\lambda \propto 1/T^2$ for segments of `T` seconds). Near a resonance `|G|²` is large and
//!   the force noise dominates; away from it the response noise does. With each channel's noise
//!   taken as flat over the band (white measurement noise), the three regressors per output
//!   channel (a constant, $|G_{ij}|^2$ per force channel, the leakage term) are fitted over the
//!   band's lines by weighted non-negative least squares (weights $1/m^2$ for the model value
//!   `m`, since each residual spectrum scatters by $m/\sqrt{A-n}$), then once more with `G`
//!   compensated. The standard errors come from the fit, scaled by its own reduced χ² when that
//!   is above 1 (noise that is not flat, overlapping segments).
//!
//! # Force measurement noise or an unmeasured excitation
//! The segments' force-side term is any noise that enters as the forces do: the force
//! channels' measurement noise, but equally an excitation they do not measure (a second force
//! on the rig, the distortion of a nonlinear element), which leaves H1 exact. Second-order
//! spectra cannot tell the two apart. Periods can: a measurement's noise scatters from period
//! to period, while a periodic drive, its distortion and the rig's response to them repeat.
//!
//! # Compensation
//! With the force measurement noise known, $G = S_{xf} (S_{ff} - A N_f)^{-1}$ is unbiased
//! for both noises: the diagonal of $S_{ff}$ loses the noise power the records show, and every
//! finish of the builder (the full data, the leave-one-out replicates, the band refits) uses
//! it ([`FrfBuilder::estimate_noise`]). Its uncertainty is what the noise estimate's standard
//! error moves the fit by (a finish compensated for the estimate raised by one
//! standard error). Periods are always compensated. Over segments the force-side noise is
//! compensated only when the user says it is the load cell's ([`ForceNoise::Measurement`]):
//! otherwise H1 is left as it is and what compensation would change is carried in the error
//! bars. On a clean load cell the force-side noise is near zero and nothing is carried: the
//! usual case of noisy probes, where the H1/H2 bracket would have carried the probes' noise
//! too.
//!
//! On 10 % force noise over white random forcing (noise-free responses) the segments' fit
//! found 100–104 % of the simulated force noise power, and 0.3 % of it on noise-free forces;
//! on a cubic spring driven by random forces it took the distortion for force-side noise of
//! about half the forces' power, as it must.

use faer::linalg::solvers::{DenseSolveCore, Solve};
use faer::{Mat, c64};

use super::builder::{FrfBuilder, Plan};
use crate::linalg;
use crate::spectra::Segmentation;

/// Where a [`NoiseFloor`] comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum NoiseSource {
    /// The scatter of repeated periods, line by line.
    Periods,
    /// The response left unexplained by the forces over Welch segments, fitted over the band.
    Segments,
}

impl NoiseSource {
    /// `"periods"` or `"segments"` (the JSON's `noise.source`).
    pub fn name(self) -> &'static str {
        match self {
            NoiseSource::Periods => "periods",
            NoiseSource::Segments => "segments",
        }
    }
}

/// What the noise the records show on the force side is taken for, and so whether H1 is
/// compensated for it ([`FrfBuilder::estimate_noise`]).
///
/// Noise on a force channel's measurement biases H1; an excitation the force channels do not
/// measure (another force on the rig, flow-induced forces, a nonlinear element's distortion)
/// leaves H1 exact (under random forcing, H1 is then the best linear approximation). Over
/// Welch segments the two give the same spectra, so the records cannot tell them apart;
/// repeated periods can (a measurement's noise scatters from period to period, a periodic
/// drive and its distortion repeat), and periods are always compensated.
///
/// # Examples
/// ```
/// use bearing_ident::frf::ForceNoise;
/// assert_eq!("measurement".parse::<ForceNoise>()?, ForceNoise::Measurement);
/// assert_eq!(ForceNoise::default(), ForceNoise::Auto);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum ForceNoise {
    /// Compensate where the records show the force channels' measurement noise for what it
    /// is (periods); over Welch segments compensate for nothing and carry in the error bars
    /// what compensation would change.
    #[default]
    Auto,
    /// The force-side noise of Welch segments is the force channels' measurement noise (a
    /// noisy load cell, no other force on the rig, a linear element): compensate for it too.
    Measurement,
}

impl crate::Choice for ForceNoise {
    const OPTION: &'static str = "force-noise";
    const ALL: &'static [ForceNoise] = &[ForceNoise::Auto, ForceNoise::Measurement];

    /// `"auto"` or `"measurement"` (the command line's `--force-noise` values).
    fn name(self) -> &'static str {
        match self {
            ForceNoise::Auto => "auto",
            ForceNoise::Measurement => "measurement",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            ForceNoise::Auto => {
                "compensate H1 for the force noise repeated periods show; over segments, carry it"
            }
            ForceNoise::Measurement => {
                "the force-side noise of segments is the load cell's: compensate H1 for it"
            }
        }
    }
}

crate::choice::choice_text!(ForceNoise);

/// The measurement noise of each force and response channel that the records show (see the
/// [module](self) docs): per band line and channel, the noise power per average, with its
/// standard error, and per channel the band's noise-to-signal power ratio for reports.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::frf::NoiseSource;
/// use bearing_ident::simulate::{AntiAlias, Simulator, add_noise, seed_rig};
/// use rand::SeedableRng;
/// let mut sim = Simulator::new(&seed_rig(), 500.0, 32_768, AntiAlias::default())?;
/// let mut rng = rand::rngs::StdRng::seed_from_u64(3);
/// let records: Vec<_> = (0..4)
///     .map(|r| add_noise(&sim.random_record(format!("r{r}"), 20.0, r)?, 0.05, &mut rng))
///     .collect::<Result<_, _>>()?;
/// let id = Identifier::new(8.0, 49.0)
///     .estimator(bearing_ident::Estimator::H1)
///     .segmentation(bearing_ident::Segmentation::Welch { len: 2048 })
///     .window(bearing_ident::Window::Hann)
///     .identify(&records)?;
/// let noise = id.noise_floor().expect("shown by the segments");
/// assert_eq!(noise.source(), NoiseSource::Segments);
/// // 5 % of each channel's RMS, spread to Nyquist: far below the forces' own power.
/// assert!(noise.force_ratio().iter().all(|r| *r < 0.01));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseFloor {
    source: NoiseSource,
    compensated: bool,
    n: usize,
    /// Per plan line `l`, `[l * n + c]`: the force channels' noise power per average.
    pub(crate) force: Vec<f64>,
    /// Its standard error.
    pub(crate) force_std: Vec<f64>,
    /// The response channels' noise power per average.
    response: Vec<f64>,
    /// Its standard error.
    response_std: Vec<f64>,
    force_ratio: Vec<f64>,
    force_ratio_std: Vec<f64>,
    response_ratio: Vec<f64>,
    response_ratio_std: Vec<f64>,
}

impl NoiseFloor {
    /// What showed the noise.
    pub fn source(&self) -> NoiseSource {
        self.source
    }

    /// Whether H1 was compensated for the force noise (see [`ForceNoise`]).
    pub fn compensated(&self) -> bool {
        self.compensated
    }

    /// Per force channel, the noise power over the signal power in the band (the median over
    /// its lines of $N_c / (S_{cc}/A - N_c)$).
    pub fn force_ratio(&self) -> &[f64] {
        &self.force_ratio
    }

    /// The standard errors of [`NoiseFloor::force_ratio`].
    pub fn force_ratio_std(&self) -> &[f64] {
        &self.force_ratio_std
    }

    /// Per response channel, the noise power over the signal power in the band.
    pub fn response_ratio(&self) -> &[f64] {
        &self.response_ratio
    }

    /// The standard errors of [`NoiseFloor::response_ratio`].
    pub fn response_ratio_std(&self) -> &[f64] {
        &self.response_ratio_std
    }

    /// The force noise raised by one standard error of what it moves the fit by, per line
    /// and channel: what the compensation's uncertainty is judged by. The segments' estimate
    /// is one number per channel, an error common to every line; the periods' are independent
    /// line by line, so a fit over `L` lines averages them and the common shift that moves it
    /// alike is $\sigma_l/\sqrt{L}$.
    pub(crate) fn force_raised(&self) -> Vec<f64> {
        let lines = (self.force.len() / self.n.max(1)).max(1) as f64;
        let scale = match self.source {
            NoiseSource::Segments => 1.0,
            NoiseSource::Periods => 1.0 / lines.sqrt(),
        };
        self.force
            .iter()
            .zip(&self.force_std)
            .map(|(n, s)| n + scale * s)
            .collect()
    }

    /// The ratios of `noise` (per line and channel) to the signal power of the auto-spectra
    /// `auto` (per line and channel, per average), with their standard errors: per channel,
    /// the median over the lines.
    fn ratios(n: usize, noise: &[f64], std: &[f64], auto: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let lines = noise.len() / n.max(1);
        (0..n)
            .map(|c| {
                let mut r: Vec<(f64, f64)> = (0..lines)
                    .filter_map(|l| {
                        let (v, s, a) = (noise[l * n + c], std[l * n + c], auto[l * n + c]);
                        let signal = a - v;
                        (signal > 0.0 && a.is_finite()).then(|| (v / signal, s / signal))
                    })
                    .collect();
                r.sort_by(|a, b| a.0.total_cmp(&b.0));
                r.get(r.len() / 2).copied().unwrap_or((f64::NAN, f64::NAN))
            })
            .unzip()
    }
}

impl FrfBuilder {
    /// The noise the records show ([`NoiseFloor`]), for H1 over periods (at least two) or
    /// Welch segments; `None` for other estimators or segmentations, before any record, or when
    /// the segments cannot show it (fewer than `2n + 8` averages, too few band lines, or a fit
    /// that is singular).
    pub fn noise_floor(&self) -> Option<NoiseFloor> {
        let (plan, _) = self.plan.as_ref()?;
        if self.sff.len() != plan.lines.len() * plan.n * plan.n {
            return None;
        }
        match self.segmentation {
            Segmentation::Periods { .. } => self.noise_from_periods(plan),
            Segmentation::Welch { .. } => self.noise_from_segments(plan),
            _ => None,
        }
    }

    /// Estimates the noise ([`FrfBuilder::noise_floor`]) for H1 and keeps it; when it is force
    /// measurement noise for what the records or `force_noise` say (periods always, Welch
    /// segments with [`ForceNoise::Measurement`]), every later H1 finish of this builder
    /// subtracts the force channels' share from `S_ff` (see the [module](self) docs). Records
    /// pushed or removed afterwards undo it.
    pub fn estimate_noise(&mut self, force_noise: ForceNoise) -> Option<&NoiseFloor> {
        if self.estimator != super::Estimator::H1 {
            return None;
        }
        let mut floor = self.noise_floor()?;
        floor.compensated =
            floor.source == NoiseSource::Periods || force_noise == ForceNoise::Measurement;
        self.noise = Some(floor);
        self.noise.as_ref()
    }

    /// The noise estimated by [`FrfBuilder::estimate_noise`], if any.
    pub(crate) fn noise(&self) -> Option<&NoiseFloor> {
        self.noise.as_ref()
    }

    /// The noise floor the H1 finishes are compensated for, if any.
    pub(crate) fn compensation(&self) -> Option<&NoiseFloor> {
        self.noise.as_ref().filter(|n| n.compensated)
    }

    /// Periods: the scatter of each channel's spectrum about its period mean, line by line.
    fn noise_from_periods(&self, plan: &Plan) -> Option<NoiseFloor> {
        let (n, nn) = (plan.n, plan.n * plan.n);
        let periods = self.segmentation.starts(plan.len).count();
        let records = self.gathered.len();
        if periods < 2 || records == 0 || self.period_means.len() != plan.lines.len() * 2 * n {
            return None;
        }
        let dof = (records * (periods - 1)) as f64;
        let averages = self.averages as f64;
        let lines = plan.lines.len();
        let (mut force, mut response) = (vec![0.0; lines * n], vec![0.0; lines * n]);
        let (mut force_auto, mut response_auto) = (vec![0.0; lines * n], vec![0.0; lines * n]);
        for l in 0..lines {
            for c in 0..n {
                let d = l * nn + c * (n + 1);
                let means = &self.period_means[l * 2 * n..(l + 1) * 2 * n];
                force[l * n + c] = ((self.sff[d].re - means[c]) / dof).max(0.0);
                response[l * n + c] = ((self.sxx[d].re - means[n + c]) / dof).max(0.0);
                force_auto[l * n + c] = self.sff[d].re / averages;
                response_auto[l * n + c] = self.sxx[d].re / averages;
            }
        }
        let relative = 1.0 / dof.sqrt();
        let force_std: Vec<f64> = force.iter().map(|v| v * relative).collect();
        let response_std: Vec<f64> = response.iter().map(|v| v * relative).collect();
        Some(NoiseFloor::new(
            NoiseSource::Periods,
            n,
            (force, force_std, &force_auto),
            (response, response_std, &response_auto),
        ))
    }

    /// Welch segments: the fit of the responses' unexplained spectra over the band (see the
    /// [module](self) docs), twice: with H1's `G`, then with `G` compensated by the first
    /// estimate.
    fn noise_from_segments(&self, plan: &Plan) -> Option<NoiseFloor> {
        let (n, lines) = (plan.n, plan.lines.len());
        let averages = self.averages as f64;
        let dof = averages - n as f64;
        if dof < (n + 8) as f64 || lines < 4 * (2 * n + 1) {
            return None;
        }
        let mut force_noise = vec![0.0; n];
        let mut fit = None;
        for _ in 0..2 {
            let residuals = Residuals::of(self, plan, &force_noise)?;
            let next = residuals.fit(dof)?;
            force_noise.clone_from(&next.force);
            fit = Some((next, residuals));
        }
        let (last, residuals) = fit?;
        let expand = |per_channel: &[f64]| -> Vec<f64> {
            (0..lines)
                .flat_map(|_| per_channel.iter().copied())
                .collect()
        };
        Some(NoiseFloor::new(
            NoiseSource::Segments,
            n,
            (
                expand(&force_noise),
                expand(&last.force_std),
                &residuals.force_auto,
            ),
            (
                expand(&last.response),
                expand(&last.response_std),
                &residuals.response_auto,
            ),
        ))
    }
}

impl NoiseFloor {
    fn new(
        source: NoiseSource,
        n: usize,
        (force, force_std, force_auto): (Vec<f64>, Vec<f64>, &[f64]),
        (response, response_std, response_auto): (Vec<f64>, Vec<f64>, &[f64]),
    ) -> Self {
        let (force_ratio, force_ratio_std) = Self::ratios(n, &force, &force_std, force_auto);
        let (response_ratio, response_ratio_std) =
            Self::ratios(n, &response, &response_std, response_auto);
        NoiseFloor {
            source,
            compensated: false,
            n,
            force,
            force_std,
            response,
            response_std,
            force_ratio,
            force_ratio_std,
            response_ratio,
            response_ratio_std,
        }
    }
}

/// Per band line, what the segments' fit reads: each response channel's power unexplained by
/// the forces, the force noise's regressors, the leakage regressor, and the channels'
/// auto-spectra per average.
struct Residuals {
    n: usize,
    /// `[l * n + i]`: $[S_{xx} - S_{xf} S_{ff}^{-1} S_{fx}]_{ii}$.
    unexplained: Vec<f64>,
    /// `[(l * n + i) * n + j]`: what force channel `j`'s noise adds to it per unit noise
    /// power, $|G_{ij}|^2 (1 - N^0_j [S^{-1}]_{jj})$ with `G` compensated for the current
    /// estimate $N^0$ and `S` the forces' spectral matrix per average: the exact term is
    /// $G (N - N S^{-1} N) G^H$, linear in `N` with the second factor taken at $N^0$.
    gain: Vec<f64>,
    /// `[l * n + i]`: $\sum_j |\Delta G_{ij}/\Delta f|^2 P_j$.
    leakage: Vec<f64>,
    /// `[l * n + i]`: what response channel `i`'s (flat) noise becomes at the line, the
    /// square of the known channel characteristics divided out there (1 without any).
    floor: Vec<f64>,
    force_auto: Vec<f64>,
    response_auto: Vec<f64>,
}

/// One fit of the segments' noise: per channel, the response noise and the force noise, with
/// standard errors.
struct SegmentFit {
    response: Vec<f64>,
    response_std: Vec<f64>,
    force: Vec<f64>,
    force_std: Vec<f64>,
}

impl Residuals {
    /// The residual spectra of `builder`'s totals with `force_noise` (per channel, per
    /// average) taken off the forces' auto-spectra.
    fn of(builder: &FrfBuilder, plan: &Plan, force_noise: &[f64]) -> Option<Self> {
        let (n, nn, lines) = (plan.n, plan.n * plan.n, plan.lines.len());
        let averages = builder.averages as f64;
        let zero = c64::new(0.0, 0.0);
        let mut inverter = linalg::Inverter::new(n);
        let (mut sc, mut g, mut explained) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
        let (mut sfx, mut plain, mut g1) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
        let mut out = Residuals {
            n,
            unexplained: vec![0.0; lines * n],
            gain: vec![0.0; lines * nn],
            leakage: vec![0.0; lines * n],
            floor: vec![1.0; lines * n],
            force_auto: vec![0.0; lines * n],
            response_auto: vec![0.0; lines * n],
        };
        let mut gs: Vec<c64> = vec![zero; lines * nn];
        for l in 0..lines {
            let range = l * nn..(l + 1) * nn;
            let (sff, sxf, sxx) = (
                &builder.sff[range.clone()],
                &builder.sxf[range.clone()],
                &builder.sxx[range],
            );
            plain.copy_from_slice(sff);
            sc.copy_from_slice(sff);
            for c in 0..n {
                sc[c * (n + 1)] -= averages * force_noise[c];
            }
            if !(inverter.invert(&mut plain) && inverter.invert(&mut sc)) {
                return None;
            }
            // H1's explained power S_xf S_ff⁻¹ S_fx; G compensated, S_xf S_c⁻¹.
            linalg::mul_into(sxf, &plain, &mut g1, n);
            linalg::mul_into(sxf, &sc, &mut g, n);
            for j in 0..n {
                for i in 0..n {
                    sfx[i + j * n] = sxf[j + i * n].conj();
                }
            }
            linalg::mul_into(&g1, &sfx, &mut explained, n);
            for i in 0..n {
                let d = i * (n + 1);
                out.unexplained[l * n + i] = (sxx[d] - explained[d]).re.max(0.0);
                out.force_auto[l * n + i] = sff[d].re / averages;
                out.response_auto[l * n + i] = sxx[d].re / averages;
                // A force's flat noise, like a response's, is scaled at the line by the square
                // of the known characteristic divided out of its channel.
                let corrected = |c: usize| {
                    plan.corrections
                        .get(l * 2 * n + c)
                        .map_or(1.0, |z| z.norm_sqr())
                };
                out.floor[l * n + i] = corrected(n + i);
                for j in 0..n {
                    // [S⁻¹]_jj per average is A [S_ff⁻¹]_jj.
                    let kept = 1.0 - force_noise[j] * averages * plain[j * (n + 1)].re;
                    out.gain[(l * n + i) * n + j] =
                        g[i + j * n].norm_sqr() * kept.max(0.0) * corrected(j);
                }
            }
            gs[l * nn..(l + 1) * nn].copy_from_slice(&g);
        }
        // |∂G/∂f|² by central differences over the plan's evenly spaced lines (one-sided at
        // the ends), weighted by the forces' power per average.
        let df = plan.resolution_hz;
        for l in 0..lines {
            let (a, b) = (l.saturating_sub(1), (l + 1).min(lines - 1));
            let span = (b - a) as f64 * df;
            for i in 0..n {
                out.leakage[l * n + i] = (0..n)
                    .map(|j| {
                        let e = i + j * n;
                        let slope = (gs[b * nn + e] - gs[a * nn + e]) / span;
                        slope.norm_sqr() * out.force_auto[l * n + j]
                    })
                    .sum();
            }
        }
        Some(out)
    }

    /// The weighted non-negative least-squares fit of the unexplained spectra per degree of
    /// freedom: unknowns `N_x` (one per response), `N_f` (one per force), `λ` (leakage).
    fn fit(&self, dof: f64) -> Option<SegmentFit> {
        let n = self.n;
        let rows = self.unexplained.len();
        let k = 2 * n + 1;
        // The regressors, row-major (`[row * k + col]`), laid out once for every solve.
        let mut design = vec![0.0; rows * k];
        for (row, d) in design.chunks_exact_mut(k).enumerate() {
            for (c, v) in d[..n].iter_mut().enumerate() {
                *v = f64::from(u8::from(c == row % n)) * self.floor[row];
            }
            d[n..2 * n].copy_from_slice(&self.gain[row * n..(row + 1) * n]);
            d[2 * n] = self.leakage[row];
        }
        let regressor = |row: usize, col: usize| design[row * k + col];
        let y: Vec<f64> = self.unexplained.iter().map(|v| v / dof).collect();
        // Weights 1/m² from the observations first, then from the model.
        let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if !(scale > 0.0 && scale.is_finite()) {
            return None;
        }
        let tiny = scale * 1e-12;
        // The first weights from the observations smoothed over neighbouring lines (one
        // observation scatters by 1/√dof: a weight from it alone would follow its noise).
        let lines = rows / n;
        let smoothed: Vec<f64> = (0..rows)
            .map(|row| {
                let (l, i) = (row / n, row % n);
                let (a, b) = (l.saturating_sub(SMOOTHING), (l + SMOOTHING + 1).min(lines));
                (a..b).map(|m| y[m * n + i]).sum::<f64>() / (b - a) as f64
            })
            .collect();
        let mut weights: Vec<f64> = smoothed.iter().map(|v| 1.0 / v.max(tiny).powi(2)).collect();
        let mut active: Vec<bool> = vec![true; k];
        let (mut theta, mut diagonal) = (vec![0.0; k], vec![0.0; k]);
        for _ in 0..NOISE_FIT_ITERATIONS {
            // Non-negative; each reweighting starts again from every column.
            active.fill(true);
            loop {
                (theta, diagonal) = solve_weighted(&design, &y, &weights, &active, k)?;
                let negative = (0..k)
                    .filter(|&c| active[c] && theta[c] < 0.0)
                    .min_by(|&a, &b| theta[a].total_cmp(&theta[b]));
                match negative {
                    Some(c) => active[c] = false,
                    None => break,
                }
            }
            // 1/m² from the model, never more than a tenth of the smoothed observation's
            // square allows (a model near zero would let one line decide).
            for (row, w) in weights.iter_mut().enumerate() {
                let m: f64 = (0..k).map(|c| regressor(row, c) * theta[c]).sum();
                *w = 1.0 / m.max(0.1 * smoothed[row]).max(tiny).powi(2);
            }
        }
        // Standard errors from the weighted normal matrix, with each observation's relative
        // variance 1/dof, scaled by the fit's reduced χ² when above 1.
        let fitted = (0..rows)
            .map(|row| {
                let m: f64 = (0..k).map(|c| regressor(row, c) * theta[c]).sum();
                (y[row] - m).powi(2) * weights[row]
            })
            .sum::<f64>();
        let free = active.iter().filter(|&&a| a).count();
        let reduced = (fitted * dof / (rows - free).max(1) as f64).max(1.0);
        let std = |c: usize| (diagonal[c].max(0.0) * reduced / dof).sqrt();
        Some(SegmentFit {
            response: (0..n).map(|c| theta[c]).collect(),
            response_std: (0..n).map(std).collect(),
            force: (n..2 * n).map(|c| theta[c]).collect(),
            force_std: (n..2 * n).map(std).collect(),
        })
    }
}

/// Iterations of the reweighting of the segments' noise fit.
const NOISE_FIT_ITERATIONS: usize = 5;

/// Lines on either side over which the segments' noise fit smooths its observations for its
/// first weights.
const SMOOTHING: usize = 5;

/// The weighted least-squares solution of `y` by the `k` columns of the row-major `design`
/// over the `active` columns (the others zero), with the
/// diagonal of the inverse of the weighted normal matrix (0 for inactive columns); `None`
/// when it is singular.
fn solve_weighted(
    design: &[f64],
    y: &[f64],
    weights: &[f64],
    active: &[bool],
    k: usize,
) -> Option<(Vec<f64>, Vec<f64>)> {
    let rows = y.len();
    let regressor = |r: usize, c: usize| design[r * k + c];
    // Columns scaled to unit weighted norm: the regressors differ by many orders.
    let norms: Vec<f64> = (0..k)
        .map(|c| match active[c] {
            true => (0..rows)
                .map(|r| weights[r] * regressor(r, c).powi(2))
                .sum::<f64>()
                .sqrt(),
            false => 0.0,
        })
        .collect();
    let used: Vec<usize> = (0..k).filter(|&c| norms[c] > 0.0).collect();
    let u = used.len();
    // The sums over the rows among the used columns (`[a * u + b]`, `[a]`), each in the
    // rows' order; the unused columns' rows and columns of the normal matrix are the
    // identity's.
    let (mut sums, mut rhs_sums) = (vec![0.0; u * u], vec![0.0; u]);
    let (mut x, mut wx) = (vec![0.0; u], vec![0.0; u]);
    for r in 0..rows {
        for (x, &c) in x.iter_mut().zip(&used) {
            *x = regressor(r, c) / norms[c];
        }
        for (wx, x) in wx.iter_mut().zip(&x) {
            *wx = weights[r] * x;
        }
        for a in 0..u {
            rhs_sums[a] += wx[a] * y[r];
            for (s, xb) in sums[a * u..(a + 1) * u].iter_mut().zip(&x) {
                *s += wx[a] * xb;
            }
        }
    }
    let mut rhs = Mat::<f64>::zeros(k, 1);
    let mut normal = Mat::<f64>::identity(k, k);
    for (i, &a) in used.iter().enumerate() {
        rhs[(a, 0)] = rhs_sums[i];
        for (j, &b) in used.iter().enumerate() {
            normal[(a, b)] = sums[i * u + j];
        }
    }
    let lu = normal.partial_piv_lu();
    let (solved, inverse) = (lu.solve(&rhs), lu.inverse());
    let (mut theta, mut diagonal) = (vec![0.0; k], vec![0.0; k]);
    for &c in &used {
        // Back to the unscaled columns: N⁻¹ = D⁻¹ Ñ⁻¹ D⁻¹, D = diag(norms).
        theta[c] = solved[(c, 0)] / norms[c];
        diagonal[c] = inverse[(c, c)] / (norms[c] * norms[c]);
    }
    (theta.iter().chain(&diagonal).all(|t: &f64| t.is_finite())).then_some((theta, diagonal))
}
