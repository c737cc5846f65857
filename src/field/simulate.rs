//! The forward problem: synchronous imbalance responses of a rotor model on given bearings
//! ([`ImbalanceRuns::simulate`]), with noise, for tests and students.

use crate::error::FieldError;
use faer::prelude::Solve;
use faer::{Mat, c64};
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

use super::inputs::{FieldTests, Imbalance, Probe, Response, Run};
use super::model::{Direction, RotorModel};
use super::solve::imbalance_forces;
use crate::error::{Error, Result};

/// A bearing's 2×2 stiffness and damping at one speed (rows and columns `x, y`): the force on
/// the rotor is $f_B = -(K + i\Omega C)\,q_B$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BearingCoefficients {
    /// `[[k_xx, k_xy], [k_yx, k_yy]]` (N/m).
    pub stiffness: [[f64; 2]; 2],
    /// `[[c_xx, c_xy], [c_yx, c_yy]]` (N·s/m).
    pub damping: [[f64; 2]; 2],
}

impl BearingCoefficients {
    /// The impedance $Z = K + i\Omega C$ at `speed_rad_s`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::field::BearingCoefficients;
    /// let b = BearingCoefficients { stiffness: [[1e7, 0.0], [0.0, 2e7]], damping: [[1e3, 0.0], [0.0, 1e3]] };
    /// assert_eq!(b.impedance(100.0)[1][1].im, 1e5);
    /// ```
    pub fn impedance(&self, speed_rad_s: f64) -> [[c64; 2]; 2] {
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                c64::new(self.stiffness[i][j], speed_rad_s * self.damping[i][j])
            })
        })
    }
}

/// A simulated field test: the speeds, the probes, the machine's residual imbalance, the two
/// sets of added masses, and the response noise.
///
/// Each response `q` gets complex Gaussian noise with `E|δ|² = (noise·|q|)²`, that is standard
/// deviation `σ = noise·|q|/√2` on each of its real and imaginary parts, which is stated as the
/// response's `std` (none when `noise` is 0). `repeats` responses are drawn per speed, run and
/// probe (each with the noise; their mean is what identification uses).
#[derive(Debug, Clone, PartialEq)]
pub struct ImbalanceRuns {
    /// The speeds (rad/s).
    pub speeds_rad_s: Vec<f64>,
    /// The probes.
    pub probes: Vec<Probe>,
    /// The residual imbalance, present in every run.
    pub residual: Vec<Imbalance>,
    /// The added masses of test 1 and test 2.
    pub added: [Vec<Imbalance>; 2],
    /// Relative response noise (0.01 for 1 %).
    pub noise: f64,
    /// Responses per speed, run and probe (at least 1).
    pub repeats: usize,
    /// Seed of the noise.
    pub seed: u64,
}

impl ImbalanceRuns {
    /// The responses of `rotor` on bearings whose coefficients at speed `Ω` are
    /// `bearings(b, Ω)` (`b` indexes [`RotorModel::bearings`]): per speed,
    /// $(D(\Omega) + \sum_b P_b Z_b P_b^\mathsf{T})\, q = f_\text{residual} + f_\text{added}$,
    /// solved by LU.
    ///
    /// # Errors
    /// [`FieldError::Input`] for a noise that is negative or not finite, zero repeats, a speed
    /// that is not finite and positive, or a rotor with its bearings singular at a speed;
    /// [`FieldError::NonFinite`] for non-finite bearing coefficients.
    ///
    /// # Examples
    /// See the [module](super) documentation.
    pub fn simulate(
        &self,
        rotor: &RotorModel,
        bearings: impl Fn(usize, f64) -> BearingCoefficients,
    ) -> Result<FieldTests> {
        let bad = |message: String| Err(Error::Field(FieldError::Input { message }));
        if !(self.noise.is_finite() && self.noise >= 0.0) || self.repeats == 0 {
            return bad("noise must be finite and ≥ 0, repeats ≥ 1".to_owned());
        }
        let mut rng = StdRng::seed_from_u64(self.seed);
        let unit = Normal::new(0.0, 1.0).map_err(|e| {
            Error::Field(FieldError::Input {
                message: e.to_string(),
            })
        })?;
        let n = rotor.dofs();
        let mut responses = Vec::new();
        for &speed in &self.speeds_rad_s {
            if !(speed.is_finite() && speed > 0.0) {
                return bad(format!("speed {speed} rad/s is not finite and positive"));
            }
            let mut d = rotor.dynamic_stiffness(speed);
            for (b, site) in rotor.bearings().iter().enumerate() {
                let z = bearings(b, speed).impedance(speed);
                if !z
                    .iter()
                    .flatten()
                    .all(|v| v.re.is_finite() && v.im.is_finite())
                {
                    return Err(Error::Field(FieldError::NonFinite {
                        what: format!("bearing `{}` at {speed} rad/s", site.tag),
                    }));
                }
                let dofs =
                    [Direction::X, Direction::Y].map(|dir| rotor.lateral_dof(site.node, dir));
                for i in 0..2 {
                    for j in 0..2 {
                        d[(dofs[i], dofs[j])] += z[i][j];
                    }
                }
            }
            let residual = imbalance_forces(rotor, &self.residual, speed);
            let mut rhs = Mat::<c64>::zeros(n, 3);
            for (t, run) in Run::ALL.iter().enumerate() {
                let added = match run {
                    Run::Baseline => vec![c64::new(0.0, 0.0); n],
                    Run::First => imbalance_forces(rotor, &self.added[0], speed),
                    Run::Second => imbalance_forces(rotor, &self.added[1], speed),
                };
                for i in 0..n {
                    rhs[(i, t)] = residual[i] + added[i];
                }
            }
            let q = d.partial_piv_lu().solve(&rhs);
            for (t, &run) in Run::ALL.iter().enumerate() {
                for &probe in &self.probes {
                    let clean = q[(rotor.lateral_dof(probe.node, probe.dir), t)];
                    if !(clean.re.is_finite() && clean.im.is_finite()) {
                        return bad(format!(
                            "the rotor on its bearings is singular at {speed} rad/s"
                        ));
                    }
                    let sigma = self.noise * clean.norm() / std::f64::consts::SQRT_2;
                    for _ in 0..self.repeats {
                        let noise = c64::new(unit.sample(&mut rng), unit.sample(&mut rng)) * sigma;
                        responses.push(Response {
                            speed_rad_s: speed,
                            run,
                            probe,
                            value: clean + noise,
                            std: (self.noise > 0.0).then_some(sigma),
                        });
                    }
                }
            }
        }
        Ok(FieldTests {
            imbalances: self.added.clone(),
            responses,
        })
    }
}
