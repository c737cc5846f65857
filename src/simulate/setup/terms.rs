//! The nonlinear terms of a simulated test ([`NonlinearTerms`]): dry friction per degree of
//! freedom or in a plane, cubic stiffness, quadratic damping, and the RK4 integration's
//! smoothing and oversampling.

use crate::Choice;
use crate::error::{Error, Result};
use crate::model::Coefficients;
use crate::nonlinear::{Regressor, Term};
use crate::records::Response;
use crate::simulate::{AntiAlias, NonlinearSimulator};

/// Nonlinear terms added to `M ẍ + C ẋ + K x = f` in a simulated test, each given as the
/// `simulate` command's option of the same name (`_` for `-`): one value for every degree of
/// freedom, or one per degree of freedom.
///
/// With any term the records come from the RK4 simulator ([`NonlinearSimulator`]) instead of
/// the exact linear one.
///
/// # Examples
/// ```
/// use bearing_ident::simulate::{NonlinearTerms, seed_rig};
/// let mut t = NonlinearTerms::default();
/// assert!(!t.any());
/// t.coulomb = vec![20.0];
/// assert_eq!(t.terms(2)?.len(), 2); // one friction term per degree of freedom
/// t.coulomb = vec![-1.0];
/// assert!(t.terms(2).is_err()); // a friction force is a magnitude
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub struct NonlinearTerms {
    /// `coulomb`: dry friction per degree of freedom (N), `F sign(ẋ)`; at least 0.
    pub coulomb: Vec<f64>,
    /// `coulomb-planar`: dry friction in the plane of the first two degrees of freedom (N),
    /// opposing the velocity vector; at least 0.
    pub coulomb_planar: Option<f64>,
    /// `cubic`: cubic stiffness per degree of freedom (N/m³), `k₃ x³`.
    pub cubic: Vec<f64>,
    /// `quadratic-damping`: quadratic damping per degree of freedom (N·s²/m²), `q |ẋ| ẋ`.
    pub quadratic_damping: Vec<f64>,
    /// `smoothing`: the friction's sign smoothed as `tanh(ẋ/V)` (m/s); default
    /// [`DEFAULT_SMOOTHING`](crate::simulate::DEFAULT_SMOOTHING).
    pub smoothing: Option<f64>,
    /// `oversampling`: RK4 steps per output sample; default at least 16, more if the system
    /// or the anti-alias filter needs them for a stable step.
    pub oversampling: Option<usize>,
}

impl NonlinearTerms {
    /// Whether any nonlinear term is given.
    pub fn any(&self) -> bool {
        !(self.coulomb.is_empty()
            && self.coulomb_planar.is_none()
            && self.cubic.is_empty()
            && self.quadratic_damping.is_empty())
    }

    /// The terms and coefficients for a system of `n` degrees of freedom: Coulomb, cubic,
    /// quadratic damping (each per degree of freedom), then planar Coulomb.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a list that has neither one value nor `n`, or a negative
    /// friction force.
    pub fn terms(&self, n: usize) -> Result<Vec<(Term, f64)>> {
        let mut terms = Vec::new();
        for (regressor, values) in [
            (Regressor::Coulomb, &self.coulomb),
            (Regressor::Cubic, &self.cubic),
            (Regressor::QuadraticDamping, &self.quadratic_damping),
        ] {
            let per_dof: Vec<f64> = match values.len() {
                0 => continue,
                1 => vec![values[0]; n],
                len if len == n => values.clone(),
                len => {
                    return Err(Error::InvalidOption {
                        option: regressor.name(),
                        message: format!(
                            "--{}: {len} values for {n} degrees of freedom; give one for all \
                             or one per degree of freedom",
                            regressor.name()
                        ),
                    });
                }
            };
            // A friction force is a magnitude: a negative one would drive the motion.
            if regressor == Regressor::Coulomb
                && let Some(v) = per_dof.iter().find(|v| **v < 0.0)
            {
                return Err(negative_friction("coulomb", *v));
            }
            for (dof, value) in per_dof.into_iter().enumerate() {
                let dof = Some(dof);
                terms.push((Term { regressor, dof }, value));
            }
        }
        if let Some(f) = self.coulomb_planar {
            if f < 0.0 {
                return Err(negative_friction("coulomb-planar", f));
            }
            let regressor = Regressor::CoulombPlanar;
            terms.push((
                Term {
                    regressor,
                    dof: None,
                },
                f,
            ));
        }
        Ok(terms)
    }

    /// The RK4 simulator of `system` with these terms, smoothing and oversampling, for
    /// records of `samples` at `rate` whose responses record `response` (none: displacement).
    ///
    /// # Errors
    /// As [`NonlinearTerms::terms`], and [`NonlinearSimulator`]'s refusals (a coefficient
    /// that is not finite, a step too long for stability, sizes past the limits).
    pub fn simulator(
        &self,
        system: &Coefficients,
        rate: f64,
        samples: usize,
        response: &[Response],
    ) -> Result<NonlinearSimulator> {
        let mut sim = NonlinearSimulator::new(system, rate, samples, AntiAlias::default())?
            .responding(response)?;
        for (term, value) in self.terms(system.dofs())? {
            sim = sim.with_term(term, value)?;
        }
        if let Some(v) = self.smoothing {
            sim = sim.with_smoothing(v)?;
        }
        if let Some(s) = self.oversampling {
            sim = sim.with_oversampling(s)?;
        }
        sim.oversampling()?;
        Ok(sim)
    }
}

/// A negative friction force, refused naming its option.
fn negative_friction(option: &'static str, value: f64) -> Error {
    Error::InvalidOption {
        option,
        message: format!("--{option} {value}: a friction force is a magnitude (N), at least 0"),
    }
}
