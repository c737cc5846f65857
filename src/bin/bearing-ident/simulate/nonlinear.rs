//! `simulate`'s nonlinear terms: `--coulomb`, `--coulomb-planar`, `--cubic`,
//! `--quadratic-damping`, and the integration's `--smoothing` and `--oversampling`.

use bearing_ident::Choice;
use bearing_ident::Coefficients;
use bearing_ident::nonlinear::{Regressor, Term};
use bearing_ident::simulate::{AntiAlias, NonlinearSimulator};

use crate::failure::{Failure, invalid};

#[derive(Debug, Clone, clap::Args)]
pub struct NonlinearArgs {
    /// Dry friction per degree of freedom (N), `M ẍ + C ẋ + K x + F sign(ẋ) = f`: one value
    /// for every DOF or one per DOF, e.g. `20,15`. Makes the system nonlinear (integrated by
    /// RK4 on a fine grid).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    coulomb: Vec<f64>,
    /// Dry friction in the plane of the first two DOFs (N), opposing the velocity vector.
    #[arg(long, allow_negative_numbers = true)]
    coulomb_planar: Option<f64>,
    /// Cubic stiffness per DOF (N/m³), `k₃ x³`: one value or one per DOF.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    cubic: Vec<f64>,
    /// Quadratic damping per DOF (N·s²/m²), `q |ẋ| ẋ`: one value or one per DOF.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    quadratic_damping: Vec<f64>,
    /// Smoothing scale of the friction's sign (m/s): `F tanh(ẋ/V)`. Default 1e-5.
    #[arg(long)]
    smoothing: Option<f64>,
    /// RK4 steps per output sample. Default: at least 16, more if the system or the
    /// anti-alias filter needs them for a stable step.
    #[arg(long)]
    oversampling: Option<usize>,
}

impl NonlinearArgs {
    /// Whether any nonlinear term was given.
    pub fn any(&self) -> bool {
        !(self.coulomb.is_empty()
            && self.coulomb_planar.is_none()
            && self.cubic.is_empty()
            && self.quadratic_damping.is_empty())
    }

    /// The terms and coefficients for a system of `n` DOFs, in the order of the flags.
    pub fn terms(&self, n: usize) -> Result<Vec<(Term, f64)>, Failure> {
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
                    return Err(invalid(format!(
                        "--{}: {len} values for {n} degrees of freedom; give one for all or \
                         one per degree of freedom",
                        regressor.name()
                    )));
                }
            };
            // A friction force is a magnitude: a negative one would drive the motion.
            if regressor == Regressor::Coulomb
                && let Some(v) = per_dof.iter().find(|v| **v < 0.0)
            {
                return Err(invalid(format!(
                    "--coulomb {v}: a friction force is a magnitude (N), at least 0"
                )));
            }
            for (dof, value) in per_dof.into_iter().enumerate() {
                terms.push((
                    Term {
                        regressor,
                        dof: Some(dof),
                    },
                    value,
                ));
            }
        }
        if let Some(f) = self.coulomb_planar.filter(|f| *f < 0.0) {
            return Err(invalid(format!(
                "--coulomb-planar {f}: a friction force is a magnitude (N), at least 0"
            )));
        }
        if let Some(f) = self.coulomb_planar {
            terms.push((
                Term {
                    regressor: Regressor::CoulombPlanar,
                    dof: None,
                },
                f,
            ));
        }
        Ok(terms)
    }

    /// The simulator of `system` with the terms, smoothing and oversampling given.
    pub fn simulator(
        &self,
        system: &Coefficients,
        rate: f64,
        samples: usize,
        response: &[bearing_ident::Response],
    ) -> Result<NonlinearSimulator, Failure> {
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

    /// The JSON description of a nonlinear simulation: its terms, smoothing and steps.
    pub fn json(&self, sim: &NonlinearSimulator) -> serde_json::Value {
        let terms: Vec<serde_json::Value> = sim
            .terms()
            .iter()
            .map(|(t, value)| {
                serde_json::json!({
                    "term": t.regressor.name(),
                    "dof": t.dof,
                    "value": value,
                    "unit": t.regressor.unit(),
                })
            })
            .collect();
        serde_json::json!({
            "terms": terms,
            "smoothing": sim.smoothing(),
            "oversampling": sim.oversampling().ok(),
        })
    }
}
