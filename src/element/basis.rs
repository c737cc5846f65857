//! [`Family`]: the model families and their basis functions, `H_ij(ω) = Σ_b θ_ij,b φ_b(ω)`.

use faer::c64;

use crate::error::{Error, Result, excerpt};

/// A family of element models (see the [module](super) docs for their impedances).
///
/// Written as the command line takes it: `kc`, `kcm`, `poly:P` (`P` from 1 to
/// [`Family::MAX_DEGREE`]), `states:N` (`N` from 1 to [`Family::MAX_POLES`]).
///
/// # Examples
/// ```
/// use bearing_ident::element::Family;
/// let f: Family = "states:2".parse()?;
/// assert_eq!(f, Family::States { poles: 2 });
/// assert_eq!(f.to_string(), "states:2");
/// // Per element: K, C, M and two residues.
/// assert_eq!(f.parameters_per_element(), 5);
/// assert!("poly:0".parse::<Family>().is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Family {
    /// `K + iωC`: no added mass.
    Kc,
    /// `K − ω²M + iωC`: the constant coefficients.
    Kcm,
    /// `K(ω) = Σ K_k (ω/ω₀)^k`, `C(ω) = Σ C_k (ω/ω₀)^k`, `k = 0 … degree`.
    Poly {
        /// The degree `P` of the polynomials.
        degree: usize,
    },
    /// `K − ω²M + iωC + Σ_j A_j iω/(iω + p_j)`, `j = 1 … poles`.
    States {
        /// The number `N` of internal states (real poles).
        poles: usize,
    },
}

impl Family {
    /// Highest polynomial degree `poly:P` takes.
    pub const MAX_DEGREE: usize = 6;
    /// Most internal states `states:N` takes.
    pub const MAX_POLES: usize = 4;

    /// Whether the family's `K(ω)`, `C(ω)` change with frequency (`poly:P` with `P ≥ 1`,
    /// `states:N`), so that constant `M`, `C`, `K` do not describe it.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::element::Family;
    /// assert!(!Family::Kcm.is_frequency_dependent());
    /// assert!(Family::States { poles: 1 }.is_frequency_dependent());
    /// ```
    pub fn is_frequency_dependent(self) -> bool {
        match self {
            Family::Kc | Family::Kcm => false,
            Family::Poly { degree } => degree >= 1,
            Family::States { poles } => poles >= 1,
        }
    }

    /// Real parameters per element of `H` (the poles, shared by every element, not counted).
    pub fn parameters_per_element(self) -> usize {
        match self {
            Family::Kc => 2,
            Family::Kcm => 3,
            Family::Poly { degree } => 2 * (degree + 1),
            Family::States { poles } => 3 + poles,
        }
    }

    /// Poles the family's fit searches for (shared by every element).
    pub fn poles(self) -> usize {
        match self {
            Family::States { poles } => poles,
            _ => 0,
        }
    }

    /// Every parameter of `n × n` elements and the poles: the size by which families are
    /// ordered.
    pub fn size(self, n: usize) -> usize {
        n * n * self.parameters_per_element() + self.poles()
    }

    /// The name of basis function `b` (the coefficient matrix it multiplies): `K`, `C`, `M`,
    /// `A1`…, or `K0`…, `C0`… for polynomials.
    pub fn parameter_name(self, b: usize) -> String {
        match self {
            Family::Kc => ["K", "C"][b].to_string(),
            Family::Kcm => ["K", "C", "M"][b].to_string(),
            Family::States { .. } => match b {
                0..=2 => ["K", "C", "M"][b].to_string(),
                _ => format!("A{}", b - 2),
            },
            Family::Poly { degree } => {
                if b <= degree {
                    format!("K{b}")
                } else {
                    format!("C{}", b - degree - 1)
                }
            }
        }
    }

    /// The basis functions `φ_b(ω)` at `omega` (rad/s) into `out` (length
    /// [`Family::parameters_per_element`]), with the poles `poles` (rad/s) and the reference
    /// `omega0` of the polynomials.
    pub(crate) fn basis(self, omega: f64, poles: &[f64], omega0: f64, out: &mut [c64]) {
        let s = c64::new(0.0, omega);
        match self {
            Family::Kc => {
                out[0] = c64::new(1.0, 0.0);
                out[1] = s;
            }
            Family::Kcm | Family::States { .. } => {
                out[0] = c64::new(1.0, 0.0);
                out[1] = s;
                out[2] = c64::new(-omega * omega, 0.0);
                for (j, &p) in poles.iter().enumerate() {
                    out[3 + j] = s / (s + p);
                }
            }
            Family::Poly { degree } => {
                let x = omega / omega0;
                let mut power = 1.0;
                for k in 0..=degree {
                    out[k] = c64::new(power, 0.0);
                    out[degree + 1 + k] = s * power;
                    power *= x;
                }
            }
        }
    }

    /// The order that [`select`](super::select) tries families in, up to `max_poles` states
    /// and polynomials of degree 2.
    pub(crate) fn candidates(max_poles: usize) -> Vec<Family> {
        let mut out = vec![Family::Kc, Family::Kcm];
        out.extend((1..=max_poles.min(Family::MAX_POLES)).map(|poles| Family::States { poles }));
        out.push(Family::Poly { degree: 2 });
        out
    }
}

impl std::fmt::Display for Family {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Family::Kc => f.write_str("kc"),
            Family::Kcm => f.write_str("kcm"),
            Family::Poly { degree } => write!(f, "poly:{degree}"),
            Family::States { poles } => write!(f, "states:{poles}"),
        }
    }
}

impl std::str::FromStr for Family {
    type Err = Error;

    /// `kc`, `kcm`, `poly:P` or `states:N` (case and spaces ignored).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the accepted forms, quoting at most 80 characters.
    fn from_str(s: &str) -> Result<Self> {
        let bad = || Error::InvalidOption {
            option: "model",
            message: format!(
                "--model `{}`: expected auto, kc, kcm, poly:P (P from 1 to {}) or states:N (N from \
                 1 to {})",
                excerpt(s),
                Family::MAX_DEGREE,
                Family::MAX_POLES
            ),
        };
        let text = s.trim().to_ascii_lowercase();
        let order = |rest: &str, max: usize| -> Result<usize> {
            match rest.trim().parse::<usize>() {
                Ok(k) if (1..=max).contains(&k) => Ok(k),
                _ => Err(bad()),
            }
        };
        match text.split_once(':') {
            None if text == "kc" => Ok(Family::Kc),
            None if text == "kcm" => Ok(Family::Kcm),
            Some(("poly", rest)) => Ok(Family::Poly {
                degree: order(rest, Family::MAX_DEGREE)?,
            }),
            Some(("states", rest)) => Ok(Family::States {
                poles: order(rest, Family::MAX_POLES)?,
            }),
            _ => Err(bad()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_bad_forms_are_refused() {
        for f in [
            Family::Kc,
            Family::Kcm,
            Family::Poly { degree: 3 },
            Family::States { poles: 4 },
        ] {
            assert_eq!(f.to_string().parse::<Family>().unwrap(), f);
        }
        assert_eq!(" KCM ".parse::<Family>().unwrap(), Family::Kcm);
        for bad in [
            "kcmx", "poly", "poly:0", "poly:7", "states:5", "states:x", "", "auto",
        ] {
            let e = bad.parse::<Family>().unwrap_err();
            assert!(e.to_string().contains("states:N"), "{bad}: {e}");
        }
    }

    /// The basis reproduces each family's impedance: `kcm` is `K − ω²M + iωC`, a state's term
    /// tends to `A` above its pole and to `A iω/p` below it.
    #[test]
    fn the_basis_is_each_familys_impedance() {
        let mut phi = vec![c64::new(0.0, 0.0); 5];
        Family::States { poles: 2 }.basis(10.0, &[1.0, 1000.0], 1.0, &mut phi);
        let (k, c, m, a1, a2) = (100.0, 2.0, 0.5, 7.0, 3.0);
        let h: c64 = [k, c, m, a1, a2]
            .iter()
            .zip(&phi)
            .map(|(t, p)| p * *t)
            .sum();
        let expected = c64::new(k - 100.0 * m, 10.0 * c)
            + c64::new(0.0, 10.0) / c64::new(1.0, 10.0) * a1
            + c64::new(0.0, 10.0) / c64::new(1000.0, 10.0) * a2;
        assert!((h - expected).norm() < 1e-12);
        let mut poly = vec![c64::new(0.0, 0.0); 6];
        Family::Poly { degree: 2 }.basis(20.0, &[], 10.0, &mut poly);
        assert_eq!(poly[2], c64::new(4.0, 0.0));
        assert_eq!(poly[5], c64::new(0.0, 80.0));
        assert_eq!(Family::Poly { degree: 2 }.parameter_name(4), "C1");
        assert_eq!(Family::States { poles: 2 }.parameter_name(4), "A2");
    }
}
