//! The system under test: the seed's rig ([`seed_rig`]) and the slowest decay of any system
//! ([`slowest_decay`]), which bounds how long its records must be.

use faer::Mat;

use super::finite_positive;
use crate::error::{Error, Result};
use crate::model::Coefficients;

/// The slowest decay rate of a system, `min(−Re λ)` over its eigenvalues (1/s), checked: a
/// mass matrix whose symmetric part is not positive definite, or a system with a mode that
/// does not decay, is an error naming the matrix.
///
/// # Errors
/// [`Error::InvalidParameter`] naming `"mass matrix"` (value: the smallest eigenvalue of its
/// symmetric part), `"stiffness matrix"` (likewise, when a mode does not decay and `K` is not
/// positive definite) or `"damping matrix"` (value: the slowest decay rate); the
/// [`Coefficients::eigenvalues`] errors.
///
/// # Examples
/// ```
/// use bearing_ident::simulate::{seed_rig, slowest_decay};
/// // The seed's rig: 8 % damping at about 27.5 Hz.
/// assert!((slowest_decay(&seed_rig())? - 13.9).abs() < 0.1);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn slowest_decay(system: &Coefficients) -> Result<f64> {
    check_mass(system)?;
    let slowest = system
        .eigenvalues()?
        .iter()
        .map(|l| -l.re)
        .fold(f64::INFINITY, f64::min);
    if !finite_positive(slowest) {
        let stiffness = min_sym_eig(system.stiffness().as_ref())?;
        return Err(if stiffness > 0.0 {
            Error::InvalidParameter {
                name: crate::Parameter::DampingMatrix,
                value: slowest + 0.0, // no "-0" in the message
                expected: "a decay rate > 0 for every mode (−Re λ, 1/s)",
            }
        } else {
            Error::InvalidParameter {
                name: crate::Parameter::StiffnessMatrix,
                value: stiffness,
                expected: "positive definite, or every mode decays",
            }
        });
    }
    Ok(slowest)
}

/// The smallest eigenvalue of the symmetric part of `a`.
fn min_sym_eig(a: faer::MatRef<'_, f64>) -> Result<f64> {
    let n = a.nrows();
    let sym = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let eig = sym.self_adjoint_eigenvalues(faer::Side::Lower)?;
    Ok(eig.iter().copied().fold(f64::INFINITY, f64::min))
}

/// `Ok` if the symmetric part of the system's mass matrix is positive definite.
///
/// # Errors
/// [`Error::InvalidParameter`] naming `"mass matrix"`, its value the smallest eigenvalue of
/// the symmetric part; the eigenvalue iteration's errors.
pub(super) fn check_mass(system: &Coefficients) -> Result<()> {
    let mass = min_sym_eig(system.mass().as_ref())?;
    if mass.is_nan() || mass <= 0.0 {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::MassMatrix,
            value: mass,
            expected: "positive definite (smallest eigenvalue of its symmetric part > 0)",
        });
    }
    Ok(())
}

/// The seed's test rig (Diaz & San Andrés 1999) as a 2-DOF system: `M = diag(4.7, 4.8)` kg,
/// `K = [[146.3, 22.3], [11.5, 169.1]]` kN/m (their identified averages) and
/// `C = diag(131.98, 131.98)` N·s/m — the short-damper closed form 109.68 N·s/m
/// (`μ = 2.25 cP, D = 50.8 mm, L = 25.4 mm, c = 0.29 mm`) plus 22.3 N·s/m of dry structural
/// damping. Natural frequencies about 27.5 and 30.6 Hz, damping ratios about 8 %.
pub fn seed_rig() -> Coefficients {
    let m = faer::mat![[4.7, 0.0], [0.0, 4.8]];
    let c = faer::mat![[131.98, 0.0], [0.0, 131.98]];
    let k = faer::mat![[146.3e3, 22.3e3], [11.5e3, 169.1e3]];
    Coefficients::new(m, c, k).expect("constant, valid coefficients")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::ImpactTest;
    use faer::{Mat, mat};

    #[test]
    fn matrices_without_decay_are_named() {
        let name = |m, c, k| match slowest_decay(&Coefficients::new(m, c, k).unwrap()) {
            Err(Error::InvalidParameter { name, .. }) => name.as_str(),
            other => panic!("{other:?}"),
        };
        let (m, c, k) = (
            mat![[4.7, 0.0], [0.0, 4.8]],
            mat![[130.0, 0.0], [0.0, 130.0]],
            mat![[1.5e5, 0.0], [0.0, 1.7e5]],
        );
        assert_eq!(name(-&m, c.clone(), k.clone()), "mass matrix");
        assert_eq!(
            name(m.clone(), Mat::zeros(2, 2), k.clone()),
            "damping matrix"
        );
        assert_eq!(name(m.clone(), -&c, k.clone()), "damping matrix");
        assert_eq!(name(m.clone(), Mat::zeros(2, 2), -&k), "stiffness matrix");
        let slowest = slowest_decay(&Coefficients::new(m, c, k).unwrap()).unwrap();
        // Proportional damping: −Re λ = c / 2m for every mode, the slowest on the heavier mass.
        assert!((slowest - 130.0 / 9.6).abs() < 1e-9, "{slowest}");
        // The impact test names the matrix too, not the record duration.
        let undamped = Coefficients::new(
            mat![[4.7, 0.0], [0.0, 4.8]],
            Mat::zeros(2, 2),
            mat![[1.5e5, 0.0], [0.0, 1.7e5]],
        )
        .unwrap();
        assert!(matches!(
            ImpactTest::seed_rig().run(&undamped),
            Err(Error::InvalidParameter {
                name: crate::Parameter::DampingMatrix,
                ..
            })
        ));
    }
}
