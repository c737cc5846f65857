//! The result of a field identification ([`FieldIdentification`]): per bearing and speed
//! `K(Ω)`, `C(Ω)` with error bars and the condition number of the response pair; the model
//! residual per speed; the warnings.

use super::inputs::Probe;
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

    /// What a user should know: dependent tests, singular or ill-conditioned pairs, speeds
    /// near a pinned critical speed.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }
}
