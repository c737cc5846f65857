//! Internal states of the element under test ([`ElementStates`]): the auxiliary-state model of
//! seals, tilting pads and magnetic bearings, whose stiffness and damping change with
//! frequency, in a form the exact simulator integrates.

use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

use faer::{Mat, c64};

use super::rig::check_mass;
use super::{MAX_STATE_POLES, at_most, finite_positive, require_finite_positive, slowest_decay};
use crate::error::{Error, Result, excerpt};
use crate::model::Coefficients;

/// Internal states of the element: `N` real poles $p_j = 2\pi f_j$ and their `n × n` residue
/// matrices $A_j$ (N/m, no symmetry assumed). Each pole adds `n` states $w_j$ to the system:
///
/// $$ M\ddot x + C\dot x + K x + \sum_{j=1}^N A_j w_j = f, \qquad \dot w_j = \dot x - p_j w_j, $$
///
/// so that in the frequency domain, $s = i\omega$, $W_j = \frac{s}{s + p_j} X$ and the
/// impedance is
///
/// $$ H(\omega) = K + sC + s^2 M + \sum_{j=1}^N A_j \frac{s}{s + p_j}. $$
///
/// Each state stiffens the element from `K` well below $p_j$ to $K + A_j$ well above it
/// ($\operatorname{Re} H = K - \omega^2 M + \sum_j A_j \omega^2/(\omega^2 + p_j^2)$), with a
/// damping $\operatorname{Im} H/\omega = C + \sum_j A_j p_j/(\omega^2 + p_j^2)$ that falls
/// from $C + A_j/p_j$ to `C` around it. The rig with the element is a linear system of state
/// `[x, ẋ, w_1 … w_N]`, dimension `2n + Nn` ([`ElementStates::eigenvalues`]), which
/// [`Simulator::with_states`](super::Simulator::with_states) integrates exactly.
///
/// As text ([`FromStr`], [`Display`](fmt::Display), the `simulate` command's `--states`):
/// one group `POLE_HZ:A` per pole, groups separated by `|`, the residue `A` in the
/// `--mass` matrix form (entries by `,`, rows by `;`), e.g. `12:3e4,0;0,2e4|35:1e4,0;0,1e4`;
/// empty text is no states.
///
/// # Examples
/// ```
/// use bearing_ident::simulate::{ElementStates, seed_rig};
/// let states: ElementStates = "20:4e4,0;0,3e4".parse()?;
/// assert_eq!(states.poles_hz(), &[20.0]);
/// // At the pole, s/(s + p) = (1 + i)/2: half of A is stiffness, half damping.
/// let h = states.impedance_at(&seed_rig(), 20.0)?;
/// let w = 2.0 * std::f64::consts::PI * 20.0;
/// assert!((h[(0, 0)].re - (146.3e3 - w * w * 4.7 + 2e4)).abs() < 1e-6);
/// assert!((h[(0, 0)].im - (131.98 * w + 2e4)).abs() < 1e-6);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ElementStates {
    /// The poles (Hz), each finite and positive.
    poles_hz: Vec<f64>,
    /// One square residue matrix per pole, all of one size, every entry finite.
    residues: Vec<Mat<f64>>,
}

impl ElementStates {
    /// Internal states of poles `poles_hz` (Hz) and residues `residues` (N/m, one per pole).
    /// No poles (both empty) is the element without states.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the `state pole` (not finite and positive), the
    /// `state residue count` (not one per pole), the `state residue size` (a matrix not
    /// square, or not of the first one's size) or a `state residue` entry that is not
    /// finite; [`Error::TooLarge`] for more than [`MAX_STATE_POLES`] poles.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::simulate::ElementStates;
    /// use faer::mat;
    /// let states = ElementStates::new(vec![12.0, 35.0], vec![mat![[3e4]], mat![[1e4]]])?;
    /// assert_eq!(states.len(), 2);
    /// assert_eq!(states.residues()[1][(0, 0)], 1e4);
    /// assert!(ElementStates::new(vec![-12.0], vec![mat![[3e4]]]).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn new(poles_hz: Vec<f64>, residues: Vec<Mat<f64>>) -> Result<Self> {
        at_most(
            "internal-state poles",
            poles_hz.len() as f64,
            MAX_STATE_POLES,
        )?;
        if residues.len() != poles_hz.len() {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::StateResidueCount,
                value: residues.len() as f64,
                expected: "one residue matrix per pole",
            });
        }
        for &pole in &poles_hz {
            require_finite_positive(
                crate::Parameter::StatePole,
                pole,
                "finite and positive (Hz)",
            )?;
        }
        let n = residues.first().map_or(0, Mat::nrows);
        for a in &residues {
            if a.nrows() != a.ncols() || a.nrows() != n || n == 0 {
                return Err(Error::InvalidParameter {
                    name: crate::Parameter::StateResidueSize,
                    value: a.ncols() as f64,
                    expected: "square, every residue of one size",
                });
            }
            let mut entries = (0..n).flat_map(|i| (0..n).map(move |j| a[(i, j)]));
            if let Some(value) = entries.find(|v| !v.is_finite()) {
                return Err(Error::InvalidParameter {
                    name: crate::Parameter::StateResidue,
                    value,
                    expected: "finite (N/m)",
                });
            }
        }
        Ok(Self { poles_hz, residues })
    }

    /// The poles $f_j = p_j / 2\pi$ (Hz), in the order given.
    pub fn poles_hz(&self) -> &[f64] {
        &self.poles_hz
    }

    /// The residue matrices $A_j$ (N/m), one per pole.
    pub fn residues(&self) -> &[Mat<f64>] {
        &self.residues
    }

    /// The number of poles `N`.
    pub fn len(&self) -> usize {
        self.poles_hz.len()
    }

    /// Whether there are no states (the element is `M`, `C`, `K` alone).
    pub fn is_empty(&self) -> bool {
        self.poles_hz.is_empty()
    }

    /// `Ok` if the residues are `n × n` (or there are none).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the `state residue size`.
    pub(super) fn check_dofs(&self, n: usize) -> Result<()> {
        match self.residues.first() {
            Some(a) if a.nrows() != n => Err(Error::InvalidParameter {
                name: crate::Parameter::StateResidueSize,
                value: a.nrows() as f64,
                expected: "one row and column per degree of freedom of the system",
            }),
            _ => Ok(()),
        }
    }

    /// The poles $p_j$ (rad/s).
    pub(super) fn poles_rad(&self) -> impl Iterator<Item = f64> + '_ {
        self.poles_hz.iter().map(|f| 2.0 * PI * f)
    }

    /// The impedance $H(\omega)$ of `system` with these states at `freq_hz`,
    /// $\omega = 2\pi f$ (the formula of [`ElementStates`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the `state residue size` if the residues are not
    /// `n × n` for the system's `n` degrees of freedom.
    pub fn impedance_at(&self, system: &Coefficients, freq_hz: f64) -> Result<Mat<c64>> {
        self.check_dofs(system.dofs())?;
        let s = c64::new(0.0, 2.0 * PI * freq_hz);
        let mut h = system.impedance_at(freq_hz);
        for (a, p) in self.residues.iter().zip(self.poles_rad()) {
            let g = s / (s + p);
            h += Mat::from_fn(a.nrows(), a.ncols(), |i, j| g * a[(i, j)]);
        }
        Ok(h)
    }

    /// The eigenvalues (rad/s) of `system` with these states: those of the state matrix of
    /// `[x, ẋ, w_1 … w_N]`,
    ///
    /// $$ \begin{bmatrix} 0 & I & 0 \\ -M^{-1}K & -M^{-1}C & -M^{-1}A_j \\ 0 & I & -p_j I
    ///    \end{bmatrix}, $$
    ///
    /// `2n + Nn` of them (the `2n` of [`Coefficients::eigenvalues`] without states).
    ///
    /// # Errors
    /// As [`ElementStates::impedance_at`]; [`Error::Singular`] if `M` is singular; the
    /// eigenvalue iteration's errors.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::model::Coefficients;
    /// use bearing_ident::simulate::ElementStates;
    /// use faer::mat;
    /// // No mass coupling to the state: with a zero residue it decays at its own pole.
    /// let sdof = Coefficients::new(mat![[1.0]], mat![[20.0]], mat![[4.0e4]])?;
    /// let states = ElementStates::new(vec![10.0], vec![mat![[0.0]]])?;
    /// let eig = states.eigenvalues(&sdof)?;
    /// assert_eq!(eig.len(), 3);
    /// let p = 2.0 * std::f64::consts::PI * 10.0;
    /// assert!(eig.iter().any(|l| (l.re + p).abs() < 1e-9 && l.im.abs() < 1e-9));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn eigenvalues(&self, system: &Coefficients) -> Result<Vec<c64>> {
        self.check_dofs(system.dofs())?;
        system.eigenvalues()?; // rejects a singular mass matrix
        let poles: Vec<f64> = self.poles_rad().collect();
        system.eigenvalues_with_states(&self.residues, &poles)
    }

    /// The slowest decay rate (1/s) of `system` with these states, `min(−Re λ)` over
    /// [`ElementStates::eigenvalues`], checked as [`slowest_decay`] checks a system alone
    /// (which it is without states): the mass's symmetric part positive definite and every
    /// mode decaying. The states may be what damps a mode (a system without `C` decays with
    /// them), or what drives one (a negative residue takes damping away).
    ///
    /// # Errors
    /// As [`slowest_decay`] without states; with states, as [`ElementStates::eigenvalues`],
    /// [`Error::InvalidParameter`] naming the `mass matrix` (not positive definite), a
    /// matrix as [`slowest_decay`] does if the system does not decay with nor without its
    /// states, or `decay with internal states` (value: the slowest rate) if only the states
    /// keep a mode from decaying.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::simulate::{ElementStates, seed_rig, slowest_decay};
    /// // A slow state (2 Hz) lengthens the decay of the seed's rig, 8 % damped at 27.5 Hz.
    /// let slow: ElementStates = "2:2e4,0;0,2e4".parse()?;
    /// let rate = slow.slowest_decay(&seed_rig())?;
    /// assert!(rate < 0.9 * slowest_decay(&seed_rig())?);
    /// assert!(rate > 0.0);
    /// let driving: ElementStates = "20:-6e4,0;0,-6e4".parse()?;
    /// assert!(driving.slowest_decay(&seed_rig()).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn slowest_decay(&self, system: &Coefficients) -> Result<f64> {
        if self.is_empty() {
            return slowest_decay(system);
        }
        self.check_dofs(system.dofs())?;
        check_mass(system)?;
        let slowest = self
            .eigenvalues(system)?
            .iter()
            .map(|l| -l.re)
            .fold(f64::INFINITY, f64::min);
        if finite_positive(slowest) {
            return Ok(slowest);
        }
        // A system that does not decay on its own either: name its matrix.
        slowest_decay(system)?;
        Err(Error::InvalidParameter {
            name: crate::Parameter::StateDecay,
            value: slowest + 0.0, // no "-0" in the message
            expected: "a decay rate > 0 for every mode of the system with its internal states \
                       (−Re λ, 1/s)",
        })
    }
}

impl FromStr for ElementStates {
    type Err = Error;

    /// Reads `POLE_HZ:A11,A12;A21,A22|POLE_HZ:…` (see [`ElementStates`]); empty text is no
    /// states.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming `states` for text not of that form (a group without
    /// `:`, a number that does not parse, a matrix that is not square); the errors of
    /// [`ElementStates::new`].
    fn from_str(text: &str) -> Result<Self> {
        if text.trim().is_empty() {
            return Ok(Self::default());
        }
        let invalid = |group: usize, what: &str| Error::InvalidOption {
            option: "states",
            message: format!(
                "--states `{}`: pole {}: {what}; expected POLE_HZ:A11,A12;A21,A22 per pole (the \
                 residue in the --mass matrix form), poles separated by `|`",
                excerpt(text),
                group + 1
            ),
        };
        let mut poles = Vec::new();
        let mut residues = Vec::new();
        for (g, group) in text.split('|').enumerate() {
            let Some((pole, matrix)) = group.split_once(':') else {
                return Err(invalid(g, "no `:` between the pole and its residue"));
            };
            let pole = pole.trim().parse::<f64>();
            poles.push(pole.map_err(|_| invalid(g, "the pole (Hz) is not a number"))?);
            let rows: Vec<Vec<f64>> = matrix
                .split(';')
                .map(|r| r.split(',').map(|v| v.trim().parse::<f64>()).collect())
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| invalid(g, "a residue entry is not a number"))?;
            let n = rows.len();
            if rows.iter().any(|r| r.len() != n) {
                return Err(invalid(g, "the residue is not a square matrix"));
            }
            residues.push(Mat::from_fn(n, n, |i, j| rows[i][j]));
        }
        Self::new(poles, residues)
    }
}

impl fmt::Display for ElementStates {
    /// The text [`FromStr`] reads, every number in its shortest exact form.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (s, (pole, a)) in self.poles_hz.iter().zip(&self.residues).enumerate() {
            let bar = if s > 0 { "|" } else { "" };
            write!(f, "{bar}{pole}:")?;
            for i in 0..a.nrows() {
                let semicolon = if i > 0 { ";" } else { "" };
                f.write_str(semicolon)?;
                for j in 0..a.ncols() {
                    let comma = if j > 0 { "," } else { "" };
                    write!(f, "{comma}{}", a[(i, j)])?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::seed_rig;
    use faer::mat;

    fn parameter(r: Result<ElementStates>) -> crate::Parameter {
        match r {
            Err(Error::InvalidParameter { name, .. }) => name,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn bad_poles_and_residues_are_named() {
        let a = || mat![[4e4, 0.0], [0.0, 3e4]];
        for pole in [-20.0, 0.0, f64::NAN, f64::INFINITY] {
            assert_eq!(
                parameter(ElementStates::new(vec![pole], vec![a()])),
                crate::Parameter::StatePole
            );
        }
        assert_eq!(
            parameter(ElementStates::new(vec![20.0, 30.0], vec![a()])),
            crate::Parameter::StateResidueCount
        );
        let size = crate::Parameter::StateResidueSize;
        let wide = Mat::<f64>::zeros(2, 3);
        assert_eq!(parameter(ElementStates::new(vec![20.0], vec![wide])), size);
        let mixed = vec![a(), mat![[1.0]]];
        assert_eq!(parameter(ElementStates::new(vec![20.0, 30.0], mixed)), size);
        let empty = Mat::<f64>::zeros(0, 0);
        assert_eq!(parameter(ElementStates::new(vec![20.0], vec![empty])), size);
        let mut nan = a();
        nan[(1, 0)] = f64::NAN;
        assert_eq!(
            parameter(ElementStates::new(vec![20.0], vec![nan])),
            crate::Parameter::StateResidue
        );
        let many = MAX_STATE_POLES + 1;
        assert!(matches!(
            ElementStates::new(vec![20.0; many], vec![a(); many]),
            Err(Error::TooLarge { .. })
        ));
        // A residue of the wrong size for the system.
        let sdof = ElementStates::new(vec![20.0], vec![mat![[4e4]]]).unwrap();
        assert!(matches!(
            sdof.impedance_at(&seed_rig(), 10.0),
            Err(Error::InvalidParameter { name, .. }) if name == size
        ));
        assert!(matches!(
            sdof.slowest_decay(&seed_rig()),
            Err(Error::InvalidParameter { name, .. }) if name == size
        ));
    }

    #[test]
    fn text_round_trips_and_bad_text_is_refused() {
        let text = "12:30000,5000;-2000,25000|35.5:0.125,0;0,1e-300";
        let states: ElementStates = text.parse().unwrap();
        assert_eq!(states.poles_hz(), &[12.0, 35.5]);
        assert_eq!(
            states.residues()[0][(1, 0)].to_bits(),
            (-2000.0_f64).to_bits()
        );
        assert_eq!(states.to_string().parse::<ElementStates>(), Ok(states));
        assert_eq!(" ".parse::<ElementStates>(), Ok(ElementStates::default()));
        for bad in ["20", "20:1,2", "x:1", "20:1,a;0,1", "20:1|30", "20:1,0;0"] {
            match bad.parse::<ElementStates>() {
                Err(Error::InvalidOption { option, message }) => {
                    assert_eq!(option, "states");
                    assert!(message.contains(bad), "{message}");
                }
                other => panic!("{bad}: {other:?}"),
            }
        }
        assert_eq!(
            parameter("-20:1".parse()),
            crate::Parameter::StatePole,
            "a value out of range is named as the library names it"
        );
    }

    #[test]
    fn decay_with_states() {
        let rig = seed_rig();
        // Negative residues take damping away: A p/(ω² + p²) = −6e4 · 126/(173² + 126²) ≈ −165
        // N·s/m at the modes, more than C = 132 N·s/m.
        let driving: ElementStates = "20:-6e4,0;0,-6e4".parse().unwrap();
        match driving.slowest_decay(&rig) {
            Err(Error::InvalidParameter { name, value, .. }) => {
                assert_eq!(name, crate::Parameter::StateDecay);
                assert!(value < 0.0, "{value}");
            }
            other => panic!("{other:?}"),
        }
        // States damp a system without damping of its own.
        let undamped = Coefficients::new(
            rig.mass().to_owned(),
            Mat::zeros(2, 2),
            rig.stiffness().to_owned(),
        )
        .unwrap();
        let damping: ElementStates = "20:4e4,0;0,3e4".parse().unwrap();
        assert!(slowest_decay(&undamped).is_err());
        assert!(damping.slowest_decay(&undamped).unwrap() > 1.0);
        // …but do not hide a system that is unstable with and without them: its matrix is named.
        let negative =
            Coefficients::new(rig.mass().to_owned(), -rig.damping(), -rig.stiffness()).unwrap();
        assert_eq!(
            match damping.slowest_decay(&negative) {
                Err(Error::InvalidParameter { name, .. }) => name,
                other => panic!("{other:?}"),
            },
            crate::Parameter::StiffnessMatrix
        );
        // Without states, the system's own decay.
        assert_eq!(
            ElementStates::default().slowest_decay(&rig),
            slowest_decay(&rig)
        );
    }
}
