//! Time records of a nonlinear system: [`NonlinearSimulator`].

mod integrate;

use faer::Mat;

use super::expm::expm;
use super::sparse_rows::SparseRows;
use super::{AntiAlias, MAX_DOFS, MAX_SAMPLES, MAX_TOTAL_SAMPLES, at_most};
use crate::error::{Error, Result};
use crate::model::Coefficients;
use crate::nonlinear::{Regressor, Term};
use crate::records::{Record, Response, require_finite_positive};
use crate::tolerance::RK4_STABLE_STEP;

pub use integrate::SMOOTHING_BAND;

/// Default smoothing scale $v_s$ of the sign in dry friction, `10⁻⁵ m/s`: the friction force
/// is $F\tanh(\dot x/v_s)$. A thousandth of a typical velocity amplitude on a bearing rig
/// (`10⁻²` m/s), so the force is exact outside `10⁻⁴` m/s, a fraction `≈ 10⁻²` of the time,
/// and the identification sees the discontinuous law.
pub const DEFAULT_SMOOTHING: f64 = 1e-5;

/// Fewest RK4 steps per output sample when the simulator chooses the oversampling itself:
/// 16, so that the fastest signal in the records (the Nyquist frequency, `ωh = π/16`) is
/// integrated with a relative error `(ωh)⁴/120 ≈ 10⁻⁵` and the band of interest below `10⁻⁹`.
pub const DEFAULT_OVERSAMPLING: usize = 16;

/// Most RK4 steps per output sample a user may ask for.
pub const MAX_OVERSAMPLING: usize = 4096;

/// A simulation of `M ẍ + C ẋ + K x + Σ a_j y_j(x, ẋ) = f`, planned for one sampling rate and
/// record length.
///
/// The system is $M\ddot x + C\dot x + Kx + \sum_j a_j\,y_j(x, \dot x) = f(t)$ with the force
/// shapes $y_j$ of [`Term::force_shape`] (dry friction, cubic stiffness, quadratic damping).
/// No exact discretisation exists, so the structure is integrated by the classical fourth-order
/// Runge–Kutta method on a fine grid, `oversampling` steps per output sample (see
/// [`NonlinearSimulator::oversampling`]); the forces are held constant between output samples
/// (zero-order hold), as in [`Simulator::held_record`](super::Simulator::held_record), so the fine
/// steps never straddle a jump of the force.
///
/// # Dry friction
/// The sign of the velocity is smoothed to $\tanh(\dot x / v_s)$ ([`DEFAULT_SMOOTHING`]
/// `= 10⁻⁵ m/s`): a discontinuous right-hand side would cost RK4 its order. Inside the
/// smoothing band the law is a stiff damper of rate $F/(m v_s)$, far faster than anything else
/// in the system, and a velocity crosses the band in $\approx 2 v_s/\lvert\ddot x\rvert$, far less
/// than a fine step. A step whose velocity passes within [`SMOOTHING_BAND`]` · v_s` of zero is
/// therefore redone in substeps short enough to resolve the band and keep RK4 stable (see
/// [`NonlinearSimulator::oversampling`]); the steps elsewhere stay long. What remains is the
/// smoothing's own effect, in proportion to $v_s$: a free decay over four cycles departs from
/// the exact Coulomb decay by `5·10⁻⁶` of its amplitude at the default, `5·10⁻⁷` at
/// `v_s = 10⁻⁶ m/s` (`tests/nonlinear/simulate.rs`), whatever the oversampling.
///
/// # Acquisition
/// Every channel passes through the same analogue anti-alias filter as in the linear
/// [`Simulator`](super::Simulator): the force channels exactly (the filter's zero-order-hold
/// discretisation over one sample, the force being held), the response channels integrated with
/// the structure in the same RK4 steps (their input is the continuous displacement, velocity or
/// acceleration). The filter cancels in `X/F`; with all $a_j = 0$ the records agree with the
/// linear simulator's exact ones to `10⁻¹⁰` under forces in a band well below Nyquist, and to
/// `4·10⁻⁸` (16 steps per sample) or `3·10⁻⁹` (32) under white forces — RK4's `h⁴`.
///
/// # Examples
/// An SDOF with dry friction, released from 1 mm: each half cycle loses `2F/k` of amplitude.
/// ```
/// use bearing_ident::model::Coefficients;
/// use bearing_ident::nonlinear::{Regressor, Term};
/// use bearing_ident::simulate::{AntiAlias, NonlinearSimulator};
/// use faer::mat;
/// let (m, k, friction) = (1.0, 4.0e4, 2.0); // ω = 200 rad/s
/// let sdof = Coefficients::new(mat![[m]], mat![[0.0]], mat![[k]])?;
/// let coulomb = Term { regressor: Regressor::Coulomb, dof: Some(0) };
/// let mut sim = NonlinearSimulator::new(&sdof, 2000.0, 400, AntiAlias::None)?
///     .with_term(coulomb, friction)?;
/// let rec = sim.free_decay("decay", &[1e-3], &[0.0])?;
/// // After one period (2π/200 s ≈ 62.8 samples) the amplitude is 1 mm − 4F/k = 0.8 mm.
/// let peak = rec.displacement(0)[55..70].iter().cloned().fold(f64::MIN, f64::max);
/// assert!((peak - 0.8e-3).abs() < 1e-6);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct NonlinearSimulator {
    n: usize,
    sample_rate: f64,
    samples: usize,
    responses: Vec<Response>,
    smoothing: f64,
    oversampling: Option<usize>,
    /// `M⁻¹`, `M⁻¹C`, `M⁻¹K`, row-major.
    minv: Vec<f64>,
    mc: Vec<f64>,
    mk: Vec<f64>,
    /// Largest `|λ|` of the linear structure (1/s).
    linear_rate: f64,
    terms: Vec<(Term, f64)>,
    filter: Option<Filter>,
}

/// One channel's anti-alias filter `ṡ = A s + b u`, and its exact zero-order-hold step.
#[derive(Debug, Clone)]
struct Filter {
    order: usize,
    /// `A`, by rows of its nonzero entries.
    a: SparseRows,
    /// `b`.
    b: Vec<f64>,
    /// The state that is the filter's output.
    output: usize,
    /// `e^{AΔt}` row-major, and `∫₀^Δt e^{Aτ} b dτ`, for a force held over one sample.
    phi: Vec<f64>,
    gamma: Vec<f64>,
    /// Cutoff (rad/s), the filter's fastest rate.
    cutoff: f64,
}

impl Filter {
    fn new(anti_alias: AntiAlias, sample_rate: f64) -> Option<Self> {
        let (a, b, output) = anti_alias.channel_system(sample_rate)?;
        let AntiAlias::Butterworth { cutoff_ratio, .. } = anti_alias else {
            return None;
        };
        let order = b.len();
        // [[A, b], [0, 0]] Δt: its exponential holds e^{AΔt} and the held input's Γ.
        let aug = Mat::from_fn(order + 1, order + 1, |i, j| match (i < order, j < order) {
            (true, true) => a[i * order + j] / sample_rate,
            (true, false) => b[i] / sample_rate,
            _ => 0.0,
        });
        let e = expm(&aug);
        Some(Filter {
            order,
            a: SparseRows::new(&Mat::from_fn(order, order, |i, j| a[i * order + j])),
            phi: (0..order * order)
                .map(|k| e[(k / order, k % order)])
                .collect(),
            gamma: (0..order).map(|i| e[(i, order)]).collect(),
            b,
            output,
            cutoff: 2.0 * std::f64::consts::PI * cutoff_ratio * sample_rate,
        })
    }
}

impl NonlinearSimulator {
    /// Plans a simulation of the linear part `system` sampled at `sample_rate` Hz for `samples`
    /// samples, with no nonlinear term yet ([`NonlinearSimulator::with_term`] adds them), the
    /// [`DEFAULT_SMOOTHING`] and an automatic oversampling.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a rate that is not finite and positive, fewer than 8
    /// samples, or a filter order or cutoff out of range; [`Error::TooLarge`] past
    /// [`MAX_SAMPLES`] samples or [`MAX_DOFS`] degrees of freedom; [`Error::Singular`] if `M` is
    /// singular.
    pub fn new(
        system: &Coefficients,
        sample_rate: f64,
        samples: usize,
        anti_alias: AntiAlias,
    ) -> Result<Self> {
        use faer::prelude::Solve;
        require_finite_positive(
            crate::Parameter::SampleRate,
            sample_rate,
            "finite and positive (Hz)",
        )?;
        at_most("samples per record", samples as f64, MAX_SAMPLES)?;
        at_most("degrees of freedom", system.dofs() as f64, MAX_DOFS)?;
        if samples < crate::records::MIN_SAMPLES {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::Samples,
                value: samples as f64,
                expected: "at least 8",
            });
        }
        anti_alias.checked_order()?;
        let linear_rate = system
            .eigenvalues()? // rejects a singular mass matrix
            .iter()
            .fold(0.0_f64, |r, l| r.max(l.norm()));
        let n = system.dofs();
        let lu = system.mass().partial_piv_lu();
        let row_major = |m: Mat<f64>| (0..n * n).map(|k| m[(k / n, k % n)]).collect::<Vec<_>>();
        Ok(Self {
            n,
            sample_rate,
            samples,
            responses: vec![Response::Displacement; n],
            smoothing: DEFAULT_SMOOTHING,
            oversampling: None,
            minv: row_major(lu.solve(Mat::<f64>::identity(n, n))),
            mc: row_major(lu.solve(system.damping())),
            mk: row_major(lu.solve(system.stiffness())),
            linear_rate,
            terms: Vec::new(),
            filter: Filter::new(anti_alias, sample_rate),
        })
    }

    /// Adds the term $a\,y(x, \dot x)$ to the left-hand side (a positive friction coefficient
    /// opposes the motion; a negative cubic coefficient softens). Terms add up, the same term
    /// given twice included.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a coefficient that is not finite, a DOF outside the
    /// system, a per-DOF regressor without a DOF, or `coulomb-planar` on fewer than two DOFs.
    pub fn with_term(mut self, term: Term, coefficient: f64) -> Result<Self> {
        if !coefficient.is_finite() {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::NonlinearCoefficient,
                value: coefficient,
                expected: "finite",
            });
        }
        let fits = match (term.regressor, term.dof) {
            (Regressor::CoulombPlanar, _) => self.n >= 2,
            (_, Some(dof)) => dof < self.n,
            (_, None) => false,
        };
        if !fits {
            let name = crate::Parameter::NonlinearTermDegreeOfFreedom;
            let expected = "a DOF of the system (coulomb-planar: a system of at least 2 DOFs)";
            return Err(match term.dof {
                Some(dof) => Error::InvalidParameter {
                    name,
                    value: dof as f64,
                    expected,
                },
                None => Error::InvalidSetting { name, expected },
            });
        }
        self.terms.push((term, coefficient));
        Ok(self)
    }

    /// Sets the smoothing scale $v_s$ of the friction's sign (m/s, default
    /// [`DEFAULT_SMOOTHING`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless finite and positive.
    pub fn with_smoothing(mut self, smoothing: f64) -> Result<Self> {
        require_finite_positive(
            crate::Parameter::FrictionSmoothing,
            smoothing,
            "finite and positive (m/s)",
        )?;
        self.smoothing = smoothing;
        Ok(self)
    }

    /// Sets the number of RK4 steps per output sample (1 to [`MAX_OVERSAMPLING`]; default:
    /// chosen by [`NonlinearSimulator::oversampling`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] outside `1 ..= MAX_OVERSAMPLING`. A factor too small for the
    /// system is refused when the records are made.
    pub fn with_oversampling(mut self, steps: usize) -> Result<Self> {
        if !(1..=MAX_OVERSAMPLING).contains(&steps) {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::Oversampling,
                value: steps as f64,
                expected: "1 to 4096 RK4 steps per sample",
            });
        }
        self.oversampling = Some(steps);
        Ok(self)
    }

    /// Records velocity or acceleration instead of displacement on the response channels: one
    /// [`Response`] for all channels or one per DOF (none: displacement), as
    /// [`Simulator::responding`](super::Simulator::responding).
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] for a number of kinds other than 0, 1 or the DOFs.
    pub fn responding(mut self, kinds: &[Response]) -> Result<Self> {
        self.responses = Response::per_channel(kinds, self.n)?;
        Ok(self)
    }

    /// The nonlinear terms and their coefficients, in the order given.
    pub fn terms(&self) -> &[(Term, f64)] {
        &self.terms
    }

    /// The smoothing scale of the friction (m/s).
    pub fn smoothing(&self) -> f64 {
        self.smoothing
    }

    /// The RK4 steps per output sample: the one set, or else the smallest factor of at least
    /// [`DEFAULT_OVERSAMPLING`] for which `ρ h ≤` [`RK4_STABLE_STEP`], `ρ` the fastest rate of
    /// the linear structure and of the anti-alias filter, `h` the step. (The friction's rate
    /// inside its smoothing band is handled by substeps, not here.)
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if the factor set is too small for a stable step;
    /// [`Error::TooLarge`] if the factor needed passes [`MAX_OVERSAMPLING`] or the fine steps
    /// of a record pass [`MAX_TOTAL_SAMPLES`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::model::Coefficients;
    /// use bearing_ident::simulate::{AntiAlias, NonlinearSimulator, seed_rig};
    /// use faer::mat;
    /// let rig = NonlinearSimulator::new(&seed_rig(), 2048.0, 1024, AntiAlias::default())?;
    /// assert_eq!(rig.oversampling()?, 16); // the default: ρh ≤ 2 needs only 1
    /// // A stiff SDOF, |λ| = 10⁵ rad/s: ⌈10⁵/(2 · 2048)⌉ = 25 steps per sample.
    /// let stiff = Coefficients::new(mat![[1.0]], mat![[0.0]], mat![[1e10]])?;
    /// let sim = NonlinearSimulator::new(&stiff, 2048.0, 1024, AntiAlias::default())?;
    /// assert_eq!(sim.oversampling()?, 25);
    /// assert!(sim.with_oversampling(16)?.oversampling().is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn oversampling(&self) -> Result<usize> {
        let rate = self
            .linear_rate
            .max(self.filter.as_ref().map_or(0.0, |f| f.cutoff));
        let needed = (rate / (RK4_STABLE_STEP * self.sample_rate)).ceil();
        at_most("RK4 steps per sample", needed, MAX_OVERSAMPLING)?;
        let needed = needed as usize;
        let steps = match self.oversampling {
            Some(s) if s < needed => {
                return Err(Error::InvalidParameter {
                    name: crate::Parameter::Oversampling,
                    value: s as f64,
                    expected: "enough RK4 steps per sample for a stable step (ρh ≤ 2, ρ the \
                               fastest rate of the structure and the anti-alias filter)",
                });
            }
            Some(s) => s,
            None => needed.max(DEFAULT_OVERSAMPLING),
        };
        at_most(
            "RK4 steps per record",
            steps as f64 * self.samples as f64,
            MAX_TOTAL_SAMPLES,
        )?;
        Ok(steps)
    }

    /// A noise-free record of the response to forces held constant between samples
    /// (`forces[c][m]` acts on DOF `c` from sample `m` to `m + 1`), starting from rest.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless there is one channel per DOF, each exactly as long as
    /// the record; [`Error::NonFinite`] naming the record, force channel and sample of a NaN or
    /// infinite force; [`Error::SimulationDiverged`] if the state stops being finite; the
    /// errors of [`NonlinearSimulator::oversampling`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::model::Coefficients;
    /// use bearing_ident::nonlinear::{Regressor, Term};
    /// use bearing_ident::simulate::{AntiAlias, NonlinearSimulator};
    /// use faer::mat;
    /// // A static load on a hardening spring: k x + k₃ x³ = f settles at x = 1 mm.
    /// let (k, k3) = (1.0e4, 1.0e10); // k₃ x³ = 10 N at 1 mm
    /// let sdof = Coefficients::new(mat![[1.0]], mat![[60.0]], mat![[k]])?;
    /// let cubic = Term { regressor: Regressor::Cubic, dof: Some(0) };
    /// let mut sim = NonlinearSimulator::new(&sdof, 1000.0, 2000, AntiAlias::None)?
    ///     .with_term(cubic, k3)?;
    /// let rec = sim.held_record("static", &[vec![20.0; 2000]])?;
    /// assert!((rec.displacement(0)[1999] - 1.0e-3).abs() < 1e-12);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn held_record(&mut self, label: impl Into<String>, forces: &[Vec<f64>]) -> Result<Record> {
        let label = label.into();
        super::simulator::check_held_forces(&label, forces, self.n, self.samples)?;
        let zeros = vec![0.0; self.n];
        self.run(label, Some(forces), &zeros, &zeros)
    }

    /// A noise-free record of the free vibration from displacement `x0` (m) and velocity `v0`
    /// (m/s), no force. The response filters start settled on `x0` (as if the system had been
    /// held there), so the records show no filter transient.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless `x0` and `v0` have one finite entry per DOF;
    /// otherwise as [`NonlinearSimulator::held_record`].
    pub fn free_decay(
        &mut self,
        label: impl Into<String>,
        x0: &[f64],
        v0: &[f64],
    ) -> Result<Record> {
        for (name, start) in [
            (crate::Parameter::InitialDisplacement, x0),
            (crate::Parameter::InitialVelocity, v0),
        ] {
            if start.len() != self.n || start.iter().any(|v| !v.is_finite()) {
                return Err(Error::InvalidParameter {
                    name,
                    value: start.len() as f64,
                    expected: "one finite entry per degree of freedom",
                });
            }
        }
        self.run(label.into(), None, x0, v0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::seed_rig;

    #[test]
    fn bad_terms_and_settings_are_refused() {
        let sim = NonlinearSimulator::new(&seed_rig(), 1000.0, 100, AntiAlias::None).unwrap();
        let term = |regressor, dof| Term { regressor, dof };
        let bad = [
            sim.clone()
                .with_term(term(Regressor::Coulomb, Some(2)), 1.0),
            sim.clone().with_term(term(Regressor::Cubic, None), 1.0),
            sim.clone()
                .with_term(term(Regressor::Coulomb, Some(0)), f64::NAN),
            sim.clone().with_smoothing(0.0),
            sim.clone().with_smoothing(f64::INFINITY),
            sim.clone().with_oversampling(0),
            sim.clone().with_oversampling(MAX_OVERSAMPLING + 1),
        ];
        for b in bad {
            assert!(
                matches!(
                    b,
                    Err(Error::InvalidParameter { .. } | Error::InvalidSetting { .. })
                ),
                "{b:?}"
            );
        }
        let sdof =
            Coefficients::new(faer::mat![[1.0]], faer::mat![[1.0]], faer::mat![[1.0]]).unwrap();
        let one = NonlinearSimulator::new(&sdof, 1000.0, 100, AntiAlias::None).unwrap();
        assert!(
            one.with_term(term(Regressor::CoulombPlanar, None), 1.0)
                .is_err()
        );
        assert!(matches!(
            NonlinearSimulator::new(&seed_rig(), 1000.0, 4, AntiAlias::None),
            Err(Error::InvalidParameter { .. })
        ));
        assert!(matches!(
            NonlinearSimulator::new(&seed_rig(), 1000.0, MAX_SAMPLES + 1, AntiAlias::None),
            Err(Error::TooLarge { .. })
        ));
    }
}
