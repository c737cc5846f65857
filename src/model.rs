//! The parametric model: mass, damping and stiffness matrices, and what follows from them.
//!
//! $$ M\ddot x + C\dot x + K x = f(t), \qquad H(\omega) = K - \omega^2 M + i\omega C,
//!    \qquad G(\omega) = H(\omega)^{-1}. $$
//!
//! [`Coefficients`] is the vocabulary shared by the fits (which produce it), the simulator
//! (which consumes it) and the identification result. Matrices are not assumed symmetric:
//! bearings have cross-coupled terms with `K_xy ≠ K_yx`.

use crate::error::Block;
use std::f64::consts::PI;

use faer::{Mat, MatRef, c64};

use crate::error::{Error, Result};
use crate::linalg;

/// Mass `M` (kg), damping `C` (N·s/m) and stiffness `K` (N/m) matrices, `n × n` each.
///
/// # Examples
/// ```
/// use bearing_ident::model::Coefficients;
/// use faer::mat;
/// // SDOF: 4.7 kg on 146.3 kN/m with 132 N·s/m.
/// let sdof = Coefficients::new(mat![[4.7]], mat![[132.0]], mat![[146.3e3]])?;
/// let mode = &sdof.modes()?[0];
/// assert!((mode.natural_frequency_hz - 28.08).abs() < 0.01);
/// assert!((mode.damping_ratio - 132.0 / (2.0 * (146.3e3_f64 * 4.7).sqrt())).abs() < 1e-12);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Coefficients {
    mass: Mat<f64>,
    damping: Mat<f64>,
    stiffness: Mat<f64>,
}

/// The rows of a matrix as a list of lists (the JSON layout of every matrix this crate writes).
///
/// # Examples
/// ```
/// let m = faer::mat![[1.0, 2.0], [3.0, 4.0]];
/// assert_eq!(bearing_ident::model::rows(m.as_ref()), vec![vec![1.0, 2.0], vec![3.0, 4.0]]);
/// ```
pub fn rows(m: MatRef<'_, f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

/// Serializes as `{"M": rows, "C": rows, "K": rows}` in SI units.
#[cfg(feature = "serde")]
impl serde::Serialize for Coefficients {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("Coefficients", 3)?;
        st.serialize_field("M", &rows(self.mass()))?;
        st.serialize_field("C", &rows(self.damping()))?;
        st.serialize_field("K", &rows(self.stiffness()))?;
        st.end()
    }
}

/// One vibration mode from the eigenvalues `λ = −ζω_n ± iω_n√(1−ζ²)` of the state matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Mode {
    /// Undamped natural frequency `|λ| / 2π` (Hz).
    pub natural_frequency_hz: f64,
    /// Damped natural frequency `Im λ / 2π` (Hz).
    pub damped_frequency_hz: f64,
    /// Damping ratio `ζ = −Re λ / |λ|`.
    pub damping_ratio: f64,
}

impl Coefficients {
    /// Bundles `M`, `C`, `K`.
    ///
    /// # Errors
    /// [`Error::CoefficientShape`] unless all three are square of one size `n ≥ 1`;
    /// [`Error::NonFiniteCoefficient`] for a NaN or infinite entry.
    pub fn new(mass: Mat<f64>, damping: Mat<f64>, stiffness: Mat<f64>) -> Result<Self> {
        let n = mass.nrows();
        let shape = |m: &Mat<f64>| (m.nrows(), m.ncols());
        if n == 0
            || [&mass, &damping, &stiffness]
                .iter()
                .any(|m| shape(m) != (n, n))
        {
            return Err(Error::CoefficientShape {
                mass: shape(&mass),
                damping: shape(&damping),
                stiffness: shape(&stiffness),
            });
        }
        for (name, m) in [
            (Block::Mass, &mass),
            (Block::Damping, &damping),
            (Block::Stiffness, &stiffness),
        ] {
            for j in 0..n {
                for i in 0..n {
                    if !m[(i, j)].is_finite() {
                        return Err(Error::NonFiniteCoefficient {
                            matrix: name,
                            row: i,
                            col: j,
                        });
                    }
                }
            }
        }
        Ok(Self {
            mass,
            damping,
            stiffness,
        })
    }

    /// Splits a stacked parameter matrix `Θ = [M; C; K]` (`3n × n`).
    ///
    /// # Errors
    /// As [`Coefficients::new`]; [`Error::CoefficientShape`] if `Θ` is not `3n × n`.
    pub fn from_stacked(theta: MatRef<'_, f64>) -> Result<Self> {
        let n = theta.ncols();
        if theta.nrows() != 3 * n {
            let s = (theta.nrows(), n);
            return Err(Error::CoefficientShape {
                mass: s,
                damping: s,
                stiffness: s,
            });
        }
        Self::new(
            theta.subrows(0, n).to_owned(),
            theta.subrows(n, n).to_owned(),
            theta.subrows(2 * n, n).to_owned(),
        )
    }

    /// The stacked parameter matrix `Θ = [M; C; K]` (`3n × n`).
    pub fn stacked(&self) -> Mat<f64> {
        let n = self.dofs();
        Mat::from_fn(3 * n, n, |i, j| match i / n {
            0 => self.mass[(i, j)],
            1 => self.damping[(i - n, j)],
            _ => self.stiffness[(i - 2 * n, j)],
        })
    }

    /// Number of degrees of freedom `n`.
    pub fn dofs(&self) -> usize {
        self.mass.nrows()
    }

    /// Mass (added-mass, inertia) matrix `M` (kg).
    pub fn mass(&self) -> MatRef<'_, f64> {
        self.mass.as_ref()
    }

    /// Damping matrix `C` (N·s/m).
    pub fn damping(&self) -> MatRef<'_, f64> {
        self.damping.as_ref()
    }

    /// Stiffness matrix `K` (N/m).
    pub fn stiffness(&self) -> MatRef<'_, f64> {
        self.stiffness.as_ref()
    }

    /// Impedance (complex dynamic stiffness) `H = K − ω²M + iωC` at `freq_hz`, `ω = 2π f`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::model::Coefficients;
    /// use faer::mat;
    /// let c = Coefficients::new(mat![[2.0]], mat![[10.0]], mat![[8000.0]])?;
    /// let h = c.impedance_at(10.0);
    /// let w = 20.0 * std::f64::consts::PI;
    /// assert!((h[(0, 0)].re - (8000.0 - 2.0 * w * w)).abs() < 1e-9);
    /// assert!((h[(0, 0)].im - 10.0 * w).abs() < 1e-12);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn impedance_at(&self, freq_hz: f64) -> Mat<c64> {
        let w = 2.0 * PI * freq_hz;
        Mat::from_fn(self.dofs(), self.dofs(), |i, j| {
            c64::new(
                self.stiffness[(i, j)] - w * w * self.mass[(i, j)],
                w * self.damping[(i, j)],
            )
        })
    }

    /// Flexibility (receptance) `G = H⁻¹` at `freq_hz`.
    ///
    /// # Errors
    /// [`Error::Singular`] if `H` is singular at that frequency (undamped resonance).
    pub fn flexibility_at(&self, freq_hz: f64) -> Result<Mat<c64>> {
        let n = self.dofs();
        let mut g = vec![c64::new(0.0, 0.0); n * n];
        self.flexibility_into(freq_hz, &mut linalg::Inverter::new(n), &mut g)?;
        Ok(Mat::from_fn(n, n, |i, j| g[i + j * n]))
    }

    /// [`Coefficients::flexibility_at`] into `g` (column-major, `n²`) with the caller's
    /// `inverter` (of this model's size): the same numbers, without allocating.
    ///
    /// # Errors
    /// [`Error::Singular`] if `H` is singular at that frequency.
    pub(crate) fn flexibility_into(
        &self,
        freq_hz: f64,
        inverter: &mut linalg::Inverter,
        g: &mut [c64],
    ) -> Result<()> {
        let n = self.dofs();
        let w = 2.0 * PI * freq_hz;
        for j in 0..n {
            for i in 0..n {
                g[i + j * n] = c64::new(
                    self.stiffness[(i, j)] - w * w * self.mass[(i, j)],
                    w * self.damping[(i, j)],
                );
            }
        }
        if !inverter.invert(g) {
            return Err(Error::Singular { what: "impedance" });
        }
        Ok(())
    }

    /// Eigenvalues of the state matrix `[[0, I], [−M⁻¹K, −M⁻¹C]]` (rad/s), `2n` of them.
    ///
    /// # Errors
    /// [`Error::Singular`] if `M` is singular; [`Error::Decomposition`] if the eigenvalue
    /// iteration fails.
    pub fn eigenvalues(&self) -> Result<Vec<c64>> {
        let n = self.dofs();
        let mass: Vec<c64> = (0..n * n)
            .map(|k| c64::new(self.mass[(k % n, k / n)], 0.0))
            .collect();
        let cond = linalg::Conditioner::new(n).condition_number(&mass);
        if cond.is_nan() || cond > 1e14 {
            return Err(Error::Singular {
                what: "mass matrix",
            });
        }
        self.eigenvalues_with_states(&[], &[])
    }

    /// The eigenvalues of the system with an element's internal states: the state matrix of
    /// `[x, ẋ, w_1 … w_N]` with $\dot w_j = \dot x - p_j w_j$ and the force `Σ A_j w_j` on
    /// the structure, `A_j` the `residues` and `p_j` the `poles_rad` (rad/s); of dimension
    /// `2n + Nn`. The mass must have passed [`Coefficients::eigenvalues`]' conditioning check.
    pub(crate) fn eigenvalues_with_states(
        &self,
        residues: &[Mat<f64>],
        poles_rad: &[f64],
    ) -> Result<Vec<c64>> {
        use faer::prelude::Solve;
        let n = self.dofs();
        let size = 2 * n + poles_rad.len() * n;
        let lu = self.mass.partial_piv_lu();
        let mk = lu.solve(&self.stiffness);
        let mc = lu.solve(&self.damping);
        let mut a = Mat::<f64>::zeros(size, size);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
            for j in 0..n {
                a[(n + i, j)] = -mk[(i, j)];
                a[(n + i, n + j)] = -mc[(i, j)];
            }
        }
        for (s, (residue, &p)) in residues.iter().zip(poles_rad).enumerate() {
            let ma = lu.solve(residue);
            let w = 2 * n + s * n;
            for i in 0..n {
                a[(w + i, n + i)] = 1.0;
                a[(w + i, w + i)] = -p;
                for j in 0..n {
                    a[(n + i, w + j)] = -ma[(i, j)];
                }
            }
        }
        Ok(a.eigenvalues()?)
    }

    /// Oscillatory modes, one per complex-conjugate eigenvalue pair, by increasing natural
    /// frequency. Overdamped (real) eigenvalues have no mode and are left out.
    ///
    /// # Errors
    /// As [`Coefficients::eigenvalues`].
    pub fn modes(&self) -> Result<Vec<Mode>> {
        let mut modes: Vec<Mode> = self
            .eigenvalues()?
            .into_iter()
            .filter(|l| l.im > crate::tolerance::OSCILLATORY_ROOT * l.norm())
            .map(|l| Mode {
                natural_frequency_hz: l.norm() / (2.0 * PI),
                damped_frequency_hz: l.im / (2.0 * PI),
                damping_ratio: -l.re / l.norm(),
            })
            .collect();
        modes.sort_by(|a, b| a.natural_frequency_hz.total_cmp(&b.natural_frequency_hz));
        Ok(modes)
    }

    /// Every coefficient times `factor`.
    pub(crate) fn scaled(&self, factor: f64) -> Coefficients {
        Coefficients {
            mass: &self.mass * faer::Scale(factor),
            damping: &self.damping * faer::Scale(factor),
            stiffness: &self.stiffness * faer::Scale(factor),
        }
    }

    /// `self − baseline`, element by element: the bearing's coefficients from the lubricated
    /// system's and the dry structure's (`K_b = K_s − K_h`, `C_b = C_s − C_h`, `M_b = M_s − M_h`).
    ///
    /// # Errors
    /// [`Error::DofCountMismatch`] if the sizes differ; [`Error::NonFiniteCoefficient`] if a
    /// difference overflows (coefficients near `±f64::MAX`).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::model::Coefficients;
    /// use faer::mat;
    /// let system = Coefficients::new(mat![[4.7]], mat![[132.0]], mat![[150.0e3]])?;
    /// let dry = Coefficients::new(mat![[4.7]], mat![[22.3]], mat![[146.3e3]])?;
    /// let bearing = system.subtract(&dry)?;
    /// assert!((bearing.damping()[(0, 0)] - 109.7).abs() < 1e-9);
    /// assert_eq!(bearing.mass()[(0, 0)], 0.0);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn subtract(&self, baseline: &Coefficients) -> Result<Coefficients> {
        if self.dofs() != baseline.dofs() {
            return Err(Error::DofCountMismatch {
                left: self.dofs(),
                right: baseline.dofs(),
            });
        }
        Coefficients::new(
            &self.mass - &baseline.mass,
            &self.damping - &baseline.damping,
            &self.stiffness - &baseline.stiffness,
        )
    }
}

impl Coefficients {
    /// The coefficients in other coordinates `q`, with the physical ones `x = T q`
    /// (`T` is `n × m`): `M_q = Tᵀ M T`, `C_q = Tᵀ C T`, `K_q = Tᵀ K T` (impedances transform
    /// as `Z_q = Tᵀ Z_x T`).
    ///
    /// # Errors
    /// [`Error::DofCountMismatch`] unless `T` has `n` rows.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::model::Coefficients;
    /// use faer::mat;
    /// // x and y swapped.
    /// let c = Coefficients::new(mat![[1.0, 0.0], [0.0, 2.0]], mat![[3.0, 0.5], [0.0, 4.0]],
    ///     mat![[5.0, 0.0], [0.0, 6.0]])?;
    /// let swapped = c.transform(mat![[0.0, 1.0], [1.0, 0.0]].as_ref())?;
    /// assert_eq!(swapped.mass()[(0, 0)], 2.0);
    /// assert_eq!(swapped.damping()[(1, 0)], 0.5);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn transform(&self, t: MatRef<'_, f64>) -> Result<Coefficients> {
        if t.nrows() != self.dofs() {
            return Err(Error::DofCountMismatch {
                left: self.dofs(),
                right: t.nrows(),
            });
        }
        let map = |m: &Mat<f64>| t.transpose() * m * t;
        Coefficients::new(map(&self.mass), map(&self.damping), map(&self.stiffness))
    }
}

/// `&system - &structure` is [`Coefficients::subtract`]: a `Result`, since the sizes may differ.
///
/// # Examples
/// ```
/// use bearing_ident::model::Coefficients;
/// use faer::mat;
/// let a = Coefficients::new(mat![[2.0]], mat![[3.0]], mat![[4.0]])?;
/// let b = Coefficients::new(mat![[1.0]], mat![[1.0]], mat![[1.0]])?;
/// assert_eq!((&a - &b)?.stiffness()[(0, 0)], 3.0);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
impl std::ops::Sub for &Coefficients {
    type Output = Result<Coefficients>;

    fn sub(self, rhs: &Coefficients) -> Result<Coefficients> {
        self.subtract(rhs)
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are copied through, not computed
mod tests {
    use super::*;
    use faer::mat;

    fn two_dof() -> Coefficients {
        Coefficients::new(
            mat![[4.7, 0.0], [0.0, 4.8]],
            mat![[132.0, 5.0], [-3.0, 128.0]],
            mat![[146.3e3, 22.3e3], [11.5e3, 169.1e3]],
        )
        .unwrap()
    }

    #[test]
    fn flexibility_inverts_impedance() {
        let c = two_dof();
        let h = c.impedance_at(27.0);
        let g = c.flexibility_at(27.0).unwrap();
        let p = &h * &g;
        for i in 0..2 {
            for j in 0..2 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((p[(i, j)] - c64::new(e, 0.0)).norm() < 1e-12);
            }
        }
    }

    #[test]
    fn stacked_round_trip() {
        let c = two_dof();
        let back = Coefficients::from_stacked(c.stacked().as_ref()).unwrap();
        assert_eq!(back, c);
        assert!(matches!(
            Coefficients::from_stacked(Mat::<f64>::zeros(5, 2).as_ref()),
            Err(Error::CoefficientShape { .. })
        ));
    }

    #[test]
    fn shape_and_finiteness_are_checked() {
        let e =
            Coefficients::new(Mat::zeros(2, 2), Mat::zeros(2, 2), Mat::zeros(2, 3)).unwrap_err();
        assert!(matches!(e, Error::CoefficientShape { .. }));
        let e = Coefficients::new(mat![[1.0]], mat![[f64::NAN]], mat![[1.0]]).unwrap_err();
        assert_eq!(
            e,
            Error::NonFiniteCoefficient {
                matrix: Block::Damping,
                row: 0,
                col: 0
            }
        );
    }

    #[test]
    fn singular_mass_and_impedance_are_reported() {
        let c = Coefficients::new(mat![[0.0]], mat![[1.0]], mat![[1.0]]).unwrap();
        assert_eq!(
            c.modes().unwrap_err(),
            Error::Singular {
                what: "mass matrix"
            }
        );
        let undamped = Coefficients::new(mat![[1.0]], mat![[0.0]], mat![[4.0 * PI * PI]]).unwrap();
        assert_eq!(
            undamped.flexibility_at(1.0).unwrap_err(),
            Error::Singular { what: "impedance" }
        );
    }

    #[test]
    fn modes_of_uncoupled_two_dof_match_closed_form() {
        let c = Coefficients::new(
            mat![[4.7, 0.0], [0.0, 4.7]],
            mat![[50.0, 0.0], [0.0, 60.0]],
            mat![[146.3e3, 0.0], [0.0, 169.1e3]],
        )
        .unwrap();
        let modes = c.modes().unwrap();
        assert_eq!(modes.len(), 2);
        assert!((modes[0].natural_frequency_hz - 28.08).abs() < 5e-3);
        assert!((modes[1].natural_frequency_hz - 30.19).abs() < 5e-3);
        let zeta = 60.0 / (2.0 * (169.1e3_f64 * 4.7).sqrt());
        assert!((modes[1].damping_ratio - zeta).abs() < 1e-12);
    }

    #[test]
    fn transform_checks_sizes() {
        let e = two_dof()
            .transform(Mat::<f64>::zeros(3, 2).as_ref())
            .unwrap_err();
        assert_eq!(e, Error::DofCountMismatch { left: 2, right: 3 });
    }

    #[test]
    fn subtraction_checks_sizes() {
        let a = two_dof();
        let b = Coefficients::new(mat![[1.0]], mat![[1.0]], mat![[1.0]]).unwrap();
        assert_eq!(
            a.subtract(&b).unwrap_err(),
            Error::DofCountMismatch { left: 2, right: 1 }
        );
        let zero = (&a - &a).unwrap();
        assert_eq!(zero.stiffness()[(1, 0)], 0.0);
        assert!((&a - &b).is_err());
        // Differences that overflow are refused, not returned as infinity.
        let big = Coefficients::new(mat![[f64::MAX]], mat![[1.0]], mat![[1.0]]).unwrap();
        let neg = Coefficients::new(mat![[-f64::MAX]], mat![[1.0]], mat![[1.0]]).unwrap();
        assert_eq!(
            big.subtract(&neg).unwrap_err(),
            Error::NonFiniteCoefficient {
                matrix: Block::Mass,
                row: 0,
                col: 0
            }
        );
    }
}
