//! The result of a field identification ([`FieldIdentification`]): per bearing and speed
//! `K(Ω)`, `C(Ω)` with error bars and the condition number of the response pair; the model
//! residual per speed; the warnings.

use super::inputs::Probe;
use super::mass_sum::MassSum;
use crate::error::Warning;

/// A bearing's coefficients at one speed: `K = Re Z`, `C = Im Z / Ω` (2×2, rows and columns
/// `x, y`), with their standard deviations when the responses carried them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedCoefficients {
    /// `[[k_xx, k_xy], [k_yx, k_yy]]` (N/m).
    pub stiffness: [[f64; 2]; 2],
    /// `[[c_xx, c_xy], [c_yx, c_yy]]` (N·s/m).
    pub damping: [[f64; 2]; 2],
    /// Standard deviations of `stiffness` (first order), if the responses had them.
    pub stiffness_std: Option<[[f64; 2]; 2]>,
    /// Standard deviations of `damping` (first order), if the responses had them.
    pub damping_std: Option<[[f64; 2]; 2]>,
    /// Noise gain: the relative error `‖δZ‖/‖Z‖` (first order, root mean square) per unit
    /// relative noise on every response (`E|δq|² = |q|²`); 1 % response noise gives about
    /// `noise_gain` % error in `Z`. It grows with the pair's condition number and, with probes
    /// away from the bearings, with the stiffness of the shaft between them.
    pub noise_gain: f64,
}

/// One bearing's identification over the speeds.
#[derive(Debug, Clone, PartialEq)]
pub struct BearingIdentification {
    /// The bearing's tag.
    pub tag: String,
    /// Its node.
    pub node: usize,
    /// Per speed, the coefficients; `None` where the response pair is singular (or the
    /// least-squares system is, at that speed).
    pub coefficients: Vec<Option<SpeedCoefficients>>,
    /// Per speed, the condition number of the pair `[q¹ q²]` of its responses (∞ where the
    /// least-squares system is singular).
    pub condition_number: Vec<f64>,
}

/// The result of [`identify`](super::identify).
#[derive(Debug, Clone, PartialEq)]
pub struct FieldIdentification {
    pub(super) speeds: Vec<f64>,
    pub(super) probes: Vec<Probe>,
    pub(super) bearings: Vec<BearingIdentification>,
    pub(super) model_residual: Vec<Option<f64>>,
    pub(super) residual_ratio: Vec<Option<f64>>,
    pub(super) pinned_critical_speeds: Vec<f64>,
    pub(super) mass_sum: Option<MassSum>,
    pub(super) warnings: Vec<Warning>,
}

impl FieldIdentification {
    /// The speeds (rad/s), ascending.
    pub fn speeds_rad_s(&self) -> &[f64] {
        &self.speeds
    }

    /// The measured degrees of freedom, sorted by node then direction.
    pub fn probes(&self) -> &[Probe] {
        &self.probes
    }

    /// Per bearing, in the rotor model's order.
    pub fn bearings(&self) -> &[BearingIdentification] {
        &self.bearings
    }

    /// Per speed, `‖A x − b‖ / ‖b‖` of the least-squares solve over both tests (0 up to
    /// rounding when there are exactly as many probes as bearing degrees of freedom; with more,
    /// it measures how well model and responses agree); `None` where the system is singular.
    pub fn model_residual(&self) -> &[Option<f64>] {
        &self.model_residual
    }

    /// Per speed, the model residual `‖r‖²` over what the stated response noise explains
    /// (about 1 when the rotor model fits; see [`FIELD_RESIDUAL_RATIO`](crate::tolerance::FIELD_RESIDUAL_RATIO));
    /// `None` without standard deviations, without redundant probes, or where the speed could
    /// not be solved.
    pub fn residual_ratio(&self) -> &[Option<f64>] {
        &self.residual_ratio
    }

    /// Synchronous critical speeds (rad/s) of the undamped rotor pinned at the probes.
    pub fn pinned_critical_speeds(&self) -> &[f64] {
        &self.pinned_critical_speeds
    }

    /// The bearings' added masses summed per direction against the rotor's modelled mass
    /// (see [`MassSum`]); `None` when a bearing has fewer than 3 speeds identified.
    ///
    /// # Examples
    /// ```
    /// # use bearing_ident::field::{self, *};
    /// # let rotor = BeamRotor { element_lengths: vec![0.15; 6], diameter: 0.05, density: 7850.0,
    /// #     young: 2.1e11, poisson: 0.3,
    /// #     disks: vec![Disk { node: 2, mass: 15.0, polar: 0.12, diametral: 0.06 }],
    /// #     bearings: vec![BearingSite::new("brg0", 0), BearingSite::new("brg1", 6)] }.model()?;
    /// # let probes = [0, 6].into_iter()
    /// #     .flat_map(|node| [Direction::X, Direction::Y].map(|dir| Probe { node, dir })).collect();
    /// # let at = |node, phase_rad| vec![Imbalance { node, magnitude_kg_m: 1e-4, phase_rad }];
    /// // Each bearing carries an added mass of 3 kg in x and none in y.
    /// let brg = |_b: usize, w: f64| BearingCoefficients {
    ///     stiffness: [[2e7 - 3.0 * w * w, 3e6], [-4e6, 3e7]],
    ///     damping: [[2e4, 1e3], [-1e3, 3e4]],
    /// };
    /// let tests = ImbalanceRuns { speeds_rad_s: vec![100.0, 200.0, 300.0], probes,
    ///     residual: at(3, 1.0), added: [at(2, 0.0), at(5, 2.0)], noise: 0.0, repeats: 1, seed: 1 }
    ///     .simulate(&rotor, brg)?;
    /// let sum = *field::identify(&rotor, &tests)?.mass_sum().unwrap();
    /// assert!((sum.sum[0] - 6.0).abs() < 1e-4 && sum.sum[1].abs() < 1e-4);
    /// // The shaft (0.9 m of 50 mm steel, 13.87 kg) and the 15 kg disk.
    /// assert!((sum.rotor_mass[0] - 28.87).abs() < 0.01);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn mass_sum(&self) -> Option<&MassSum> {
        self.mass_sum.as_ref()
    }

    /// What a user should know: dependent tests, singular or ill-conditioned pairs, speeds
    /// near a pinned critical speed, a mass sum off the model's.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }
}
