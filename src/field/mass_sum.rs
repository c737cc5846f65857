//! The mass-sum check ([`MassSum`]): the bearings' added masses summed against the rotor's
//! modelled mass (see [`MassSum`]).

use super::fit::ConstantFit;
use super::model::{Direction, RotorModel};
use crate::error::Warning;
use crate::tolerance::{FIELD_MASS_SUM_FRACTION, FIELD_MASS_SUM_SIGMAS};

/// The bearings' added masses summed per direction, against the rotor's modelled mass
/// (index 0 is `x`, 1 is `y`).
///
/// The free rotor's model carries the rotor's inertia, so the mass coefficients of the bearings'
/// constant fits ([`fit_constant`](super::fit_constant)) hold only what the measurements show
/// beyond the model: a fluid film's or a seal's own added mass, which is small against the
/// rotor's, and the speed trend of a fluid film's stiffness, which the constant fit's `M`
/// absorbs. Summed over the bearings per direction, `Σ_b M_b,dd`, it is set beside the rotor
/// model's translational mass `m_d = t_dᵀ M t_d` (`t_d` the rigid translation in direction
/// `d`: 1 on every node's `d`, 0 elsewhere), which is what "the rotor's modelled mass" means
/// here.
///
/// A rotor mass that the model gets wrong (a disk, a coupling half, an impeller left out or
/// mistyped) puts the missing inertia force `Ω² δm q` on the bearings. It does not come back as
/// `δm` in the sum: each bearing's `Z` divides its share of that force by its own orbits
/// (`[q¹ q²]⁻¹`), and the disk's orbits are not the bearings'. What it gives is a sum far from
/// anything a bearing carries: on the two-disk test rotor (58.3 kg), the 20 kg disk written as
/// 5 kg gives `ΣM_yy = −175 ± 54 kg` at 1 % response noise where the true rotor gives
/// `2.3 ± 1.0 kg` (truth 3 kg; `tests/estimation/field.rs`). The check is therefore a
/// plausibility test: a sum beyond [`FIELD_MASS_SUM_SIGMAS`] standard deviations **and**
/// above [`FIELD_MASS_SUM_FRACTION`] of the modelled mass is a warning.
///
/// $$ \Sigma_d = \sum_b M_{b,dd}, \qquad \sigma_{\Sigma_d} = \Big(\sum_b \sigma_{M_{b,dd}}^2\Big)^{1/2},
///    \qquad m_d = t_d^\top M\, t_d, $$
///
/// the standard deviation treating the bearings' fits as independent (each bearing's pair of
/// responses is its own; their common responses make the true spread differ somewhat).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassSum {
    /// `Σ_b M_b,xx` and `Σ_b M_b,yy` (kg), from the bearings' constant fits.
    pub sum: [f64; 2],
    /// Their standard deviations (kg).
    pub sum_std: [f64; 2],
    /// The rotor model's translational mass in `x` and `y`, `t_dᵀ M t_d` (kg).
    pub rotor_mass: [f64; 2],
}

impl MassSum {
    /// The sums of `fits` (one per bearing) against `rotor`'s mass; `None` when a bearing has
    /// no constant fit (fewer than 3 speeds identified).
    pub(super) fn of(rotor: &RotorModel, fits: &[Option<ConstantFit>]) -> Option<MassSum> {
        let fits: Vec<&ConstantFit> = fits.iter().map(Option::as_ref).collect::<Option<_>>()?;
        let mut out = MassSum {
            sum: [0.0; 2],
            sum_std: [0.0; 2],
            rotor_mass: [Direction::X, Direction::Y].map(|d| translational_mass(rotor, d)),
        };
        for d in 0..2 {
            out.sum[d] = fits.iter().map(|f| f.mass[d][d]).sum();
            out.sum_std[d] = fits
                .iter()
                .map(|f| f.mass_std[d][d].powi(2))
                .sum::<f64>()
                .sqrt();
        }
        Some(out)
    }

    /// The warnings of the check: one per direction whose sum is beyond
    /// [`FIELD_MASS_SUM_SIGMAS`] standard deviations and [`FIELD_MASS_SUM_FRACTION`] of the
    /// modelled mass.
    pub(super) fn warnings(&self) -> Vec<Warning> {
        [Direction::X, Direction::Y]
            .into_iter()
            .enumerate()
            .filter(|&(d, _)| {
                let sum = self.sum[d].abs();
                sum > FIELD_MASS_SUM_SIGMAS * self.sum_std[d]
                    && sum > FIELD_MASS_SUM_FRACTION * self.rotor_mass[d]
            })
            .map(|(d, dir)| Warning::MassSum {
                direction: dir.name(),
                sum_kg: self.sum[d],
                std_kg: self.sum_std[d],
                rotor_mass_kg: self.rotor_mass[d],
            })
            .collect()
    }
}

/// `t_dᵀ M t_d`: the mass the model moves in a rigid translation in direction `d`.
fn translational_mass(rotor: &RotorModel, d: Direction) -> f64 {
    let dofs: Vec<usize> = (0..rotor.nodes())
        .map(|n| rotor.lateral_dof(n, d))
        .collect();
    dofs.iter()
        .map(|&i| dofs.iter().map(|&j| rotor.mass()[(i, j)]).sum::<f64>())
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::{BeamRotor, BearingSite, Disk};

    fn fit(mass: f64, std: f64) -> Option<ConstantFit> {
        Some(ConstantFit {
            stiffness: [[1e7, 0.0], [0.0, 1e7]],
            damping: [[1e3, 0.0], [0.0, 1e3]],
            mass: [[mass, 0.0], [0.0, -mass]],
            stiffness_std: [[0.0; 2]; 2],
            damping_std: [[0.0; 2]; 2],
            mass_std: [[std, 0.0], [0.0, std]],
            speeds: 5,
        })
    }

    /// A shaft of 0.8 m, 50 mm, steel (12.33 kg) with a 15 kg disk: 27.33 kg in each direction.
    fn rotor() -> RotorModel {
        BeamRotor {
            element_lengths: vec![0.2; 4],
            diameter: 0.05,
            density: 7850.0,
            young: 2.1e11,
            poisson: 0.3,
            disks: vec![Disk {
                node: 2,
                mass: 15.0,
                polar: 0.1,
                diametral: 0.05,
            }],
            bearings: vec![BearingSite::new("a", 0), BearingSite::new("b", 4)],
        }
        .model()
        .unwrap()
    }

    #[test]
    fn sums_per_direction_against_the_translational_mass() {
        let rotor = rotor();
        let shaft = 7850.0 * std::f64::consts::PI * 0.025f64.powi(2) * 0.8;
        let s = MassSum::of(&rotor, &[fit(5.0, 0.3), fit(3.0, 0.4)]).unwrap();
        assert!((s.rotor_mass[0] - (shaft + 15.0)).abs() < 1e-9, "{s:?}");
        assert!((s.rotor_mass[1] - (shaft + 15.0)).abs() < 1e-9, "{s:?}");
        assert!((s.sum[0] - 8.0).abs() < 1e-12 && (s.sum[1] + 8.0).abs() < 1e-12);
        assert!((s.sum_std[0] - 0.5).abs() < 1e-12);
        // 8 kg is 29 % of 27.3 kg and 16σ: both directions warn.
        let kinds: Vec<_> = s.warnings().iter().map(|w| w.kind()).collect();
        assert_eq!(kinds, ["mass_sum", "mass_sum"]);
        // Within 3σ: quiet.
        let s = MassSum::of(&rotor, &[fit(5.0, 2.0), fit(3.0, 2.0)]).unwrap();
        assert!(s.warnings().is_empty());
        // Significant but a small fraction of the rotor's mass: quiet.
        let s = MassSum::of(&rotor, &[fit(3.0, 0.01), fit(3.0, 0.01)]).unwrap();
        assert!(s.warnings().is_empty());
        // A bearing without a fit: no check.
        assert!(MassSum::of(&rotor, &[fit(2.0, 0.3), None]).is_none());
    }
}
