//! [`Regressor`]: the kinds of nonlinear force term, and [`Term`]: one term with its degree of
//! freedom.

use crate::Choice;
use crate::error::{Error, Result};

/// A kind of nonlinear force term $a\,y(x, \dot x)$ on the left of
/// $M\ddot x + C\dot x + Kx + \sum_j a_j y_j = f$.
///
/// | regressor | force shape $y$ | coefficient unit | terms for $n$ DOFs |
/// |---|---|---|---|
/// | `coulomb` | $y_i = \operatorname{sign}(\dot x_i)$ on DOF $i$ | N | $n$ |
/// | `coulomb-planar` | $(y_0, y_1) = (\dot x_0, \dot x_1)/\lvert(\dot x_0, \dot x_1)\rvert$ | N | 1 (needs $n \ge 2$) |
/// | `cubic` | $y_i = x_i^3$ on DOF $i$ | N/m³ | $n$ |
/// | `quadratic-damping` | $y_i = \lvert\dot x_i\rvert\,\dot x_i$ on DOF $i$ | N·s²/m² | $n$ |
///
/// # Examples
/// ```
/// use bearing_ident::Choice;
/// use bearing_ident::nonlinear::Regressor;
/// let r: Regressor = "coulomb-planar".parse()?;
/// assert_eq!((r.name(), r.unit(), r.terms(2)?.len()), ("coulomb-planar", "N", 1));
/// assert_eq!(Regressor::Cubic.terms(3)?.len(), 3);
/// assert!(Regressor::CoulombPlanar.terms(1).is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Regressor {
    /// Dry friction per DOF: $y_i = \operatorname{sign}(\dot x_i)$, coefficient $F_i$ in N.
    Coulomb,
    /// Dry friction in the plane of the first two DOFs, opposing the velocity vector:
    /// $y = \dot x/\lvert\dot x\rvert$ over DOFs 0 and 1, one coefficient $F$ in N.
    CoulombPlanar,
    /// Cubic (hardening for $a > 0$) stiffness per DOF: $y_i = x_i^3$, in N/m³.
    Cubic,
    /// Quadratic damping per DOF: $y_i = \lvert\dot x_i\rvert\dot x_i$, in N·s²/m².
    QuadraticDamping,
}

impl Regressor {
    /// The SI unit of the coefficient: `"N"`, `"N/m³"` or `"N·s²/m²"`.
    pub fn unit(self) -> &'static str {
        match self {
            Regressor::Coulomb | Regressor::CoulombPlanar => "N",
            Regressor::Cubic => "N/m³",
            Regressor::QuadraticDamping => "N·s²/m²",
        }
    }

    /// Whether the force shape depends on the velocity (all but `cubic`).
    pub fn needs_velocity(self) -> bool {
        !matches!(self, Regressor::Cubic)
    }

    /// Whether the term dissipates energy for a positive coefficient (friction and quadratic
    /// damping: the force shape has the sign of the velocity, so $a_j\,y_j\,\dot x \ge 0$).
    /// A clearly negative coefficient of such a term would feed energy into the system: the
    /// regressor is not the element's ([`Warning::NegativeDissipation`](crate::Warning::NegativeDissipation)).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::nonlinear::Regressor;
    /// assert!(Regressor::Coulomb.dissipative() && !Regressor::Cubic.dissipative());
    /// ```
    pub fn dissipative(self) -> bool {
        self.needs_velocity()
    }

    /// The terms of this kind for a system of `dofs` degrees of freedom: one per DOF, or one
    /// planar term.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for `coulomb-planar` with fewer than two DOFs.
    pub fn terms(self, dofs: usize) -> Result<Vec<Term>> {
        match self {
            Regressor::CoulombPlanar if dofs < 2 => Err(Error::InvalidParameter {
                name: crate::Parameter::DegreesOfFreedomForCoulombPlanar,
                value: dofs as f64,
                expected: "at least 2",
            }),
            Regressor::CoulombPlanar => Ok(vec![Term {
                regressor: self,
                dof: None,
            }]),
            _ => Ok((0..dofs)
                .map(|i| Term {
                    regressor: self,
                    dof: Some(i),
                })
                .collect()),
        }
    }

    /// The terms of every kind in `kinds`, in order, for `dofs` degrees of freedom (a kind given
    /// twice is kept once).
    ///
    /// # Errors
    /// As [`Regressor::terms`].
    pub fn expand(kinds: &[Regressor], dofs: usize) -> Result<Vec<Term>> {
        let mut terms = Vec::new();
        for (k, &kind) in kinds.iter().enumerate() {
            if !kinds[..k].contains(&kind) {
                terms.extend(kind.terms(dofs)?);
            }
        }
        Ok(terms)
    }
}

impl crate::Choice for Regressor {
    const OPTION: &'static str = "nonlinear term";
    const ALL: &'static [Regressor] = &[
        Regressor::Coulomb,
        Regressor::CoulombPlanar,
        Regressor::Cubic,
        Regressor::QuadraticDamping,
    ];

    /// `"coulomb"`, `"coulomb-planar"`, `"cubic"` or `"quadratic-damping"` (the command
    /// line's `--nonlinear` values and the JSON's), in the order of the table above.
    fn name(self) -> &'static str {
        match self {
            Regressor::Coulomb => "coulomb",
            Regressor::CoulombPlanar => "coulomb-planar",
            Regressor::Cubic => "cubic",
            Regressor::QuadraticDamping => "quadratic-damping",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Regressor::Coulomb => "dry friction per DOF, sign of the velocity (N)",
            Regressor::CoulombPlanar => "dry friction opposing the velocity in the x-y plane (N)",
            Regressor::Cubic => "cubic stiffness per DOF, x³ (N/m³)",
            Regressor::QuadraticDamping => "quadratic damping per DOF, |v|·v (N·s²/m²)",
        }
    }
}

crate::choice::choice_text!(Regressor);

/// One nonlinear term: a [`Regressor`] acting on one DOF (`dof: Some(i)`) or, for
/// `coulomb-planar`, on the plane of DOFs 0 and 1 (`dof: None`).
///
/// # Examples
/// ```
/// use bearing_ident::nonlinear::{Regressor, Term};
/// let friction = Term { regressor: Regressor::Coulomb, dof: Some(1) };
/// let mut y = [0.0; 2];
/// friction.force_shape(&[0.0, 0.0], &[0.3, -0.2], None, &mut y);
/// assert_eq!(y, [0.0, -1.0]);
/// let planar = Term { regressor: Regressor::CoulombPlanar, dof: None };
/// planar.force_shape(&[0.0, 0.0], &[3.0, 4.0], None, &mut y);
/// assert!((y[0] - 0.6).abs() < 1e-15 && (y[1] - 0.8).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Term {
    /// The kind of term.
    pub regressor: Regressor,
    /// The DOF it acts on; `None` for the planar friction (DOFs 0 and 1).
    pub dof: Option<usize>,
}

impl Term {
    /// The force shape $y(x, \dot x)$ written into `out` (length $n$, zero where the term does
    /// not act), from displacements `x` and velocities `v` (length $n$).
    ///
    /// With `smoothing: Some(v_s)` (m/s, > 0) the sign is replaced by $\tanh(\dot x/v_s)$ and the
    /// planar unit vector by $\dot x\,\tanh(\lvert\dot x\rvert/v_s)/\lvert\dot x\rvert$ — the
    /// smooth law a fixed-step integrator needs; `None` is the exact law (sign(0) = 0).
    pub fn force_shape(&self, x: &[f64], v: &[f64], smoothing: Option<f64>, out: &mut [f64]) {
        out.fill(0.0);
        let sign = |u: f64| match smoothing {
            Some(s) => (u / s).tanh(),
            None if u > 0.0 => 1.0,
            None if u < 0.0 => -1.0,
            None => 0.0,
        };
        match (self.regressor, self.dof) {
            (Regressor::CoulombPlanar, _) => {
                let speed = v[0].hypot(v[1]);
                if speed > 0.0 {
                    let g = sign(speed) / speed;
                    out[0] = v[0] * g;
                    out[1] = v[1] * g;
                }
            }
            (_, None) => {}
            (Regressor::Coulomb, Some(i)) => out[i] = sign(v[i]),
            (Regressor::Cubic, Some(i)) => out[i] = x[i] * x[i] * x[i],
            (Regressor::QuadraticDamping, Some(i)) => out[i] = v[i].abs() * v[i],
        }
    }

    /// `"coulomb"` for DOF 0 as `coulomb[0]`, the planar term as `coulomb-planar`.
    pub fn label(&self) -> String {
        match self.dof {
            Some(i) => format!("{}[{i}]", self.regressor.name()),
            None => self.regressor.name().to_owned(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for r in Regressor::ALL {
            assert_eq!(r.name().parse::<Regressor>().unwrap(), *r);
        }
        assert_eq!(
            "quadratic_damping".parse::<Regressor>().unwrap(),
            Regressor::QuadraticDamping
        );
        let e = "friction".parse::<Regressor>().unwrap_err();
        assert_eq!(e.kind(), "invalid_argument");
    }

    #[test]
    fn expand_keeps_order_and_drops_repeats() {
        let t = Regressor::expand(
            &[Regressor::Cubic, Regressor::CoulombPlanar, Regressor::Cubic],
            2,
        )
        .unwrap();
        let labels: Vec<_> = t.iter().map(Term::label).collect();
        assert_eq!(labels, ["cubic[0]", "cubic[1]", "coulomb-planar"]);
    }

    #[test]
    // The laws give exact small integers at these points (sign, cube, v|v|): exact compare on purpose.
    #[allow(clippy::float_cmp)]
    fn force_shapes_match_their_laws() {
        let x = [0.5, -2.0];
        let v = [-3.0, 0.0];
        let mut y = [9.0; 2];
        let shape = |r, dof, s: Option<f64>, y: &mut [f64; 2]| {
            Term { regressor: r, dof }.force_shape(&x, &v, s, y);
            *y
        };
        assert_eq!(
            shape(Regressor::Coulomb, Some(0), None, &mut y),
            [-1.0, 0.0]
        );
        assert_eq!(shape(Regressor::Coulomb, Some(1), None, &mut y), [0.0, 0.0]);
        assert_eq!(shape(Regressor::Cubic, Some(1), None, &mut y), [0.0, -8.0]);
        assert_eq!(
            shape(Regressor::QuadraticDamping, Some(0), None, &mut y),
            [-9.0, 0.0]
        );
        let smooth = shape(Regressor::Coulomb, Some(0), Some(1.0), &mut y);
        assert!((smooth[0] + 3f64.tanh()).abs() < 1e-15);
        let planar = shape(Regressor::CoulombPlanar, None, None, &mut y);
        assert_eq!(planar, [-1.0, 0.0]);
    }
}
