//! Field identification: the bearings' `K(Ω)`, `C(Ω)` of a running machine from imbalance
//! responses and a model of its rotor (De Santiago & San Andrés 2004/2007).
//!
//! On a real machine there are no shakers: only the proximity probes near the bearings, a
//! finite-element model of the free rotor (no bearings) and a few runs with known imbalance
//! masses. The synchronous response to imbalance at speed `Ω`, `x(t) = Re(q e^{iΩt})`, obeys
//!
//! $$ D(\Omega)\, q = f_u + P_B f_B, \qquad D(\Omega) = K - \Omega^2 M + i\Omega\,(C + \Omega G), $$
//!
//! with `P_B` placing the bearing forces `f_B` at the bearings' `x, y`. An imbalance
//! `u = m·e` at angle `φ` gives $f_x = u\Omega^2 e^{i\varphi}$, $f_y = -i\,u\Omega^2 e^{i\varphi}$
//! (rotation from x towards y; [`Imbalance::force`]).
//!
//! 1. **Baseline subtraction.** Per speed, a baseline run (the unknown residual imbalance) and
//!    two runs with added masses; their differences `Δq = q¹ − q⁰`, `q² − q⁰` are driven by the
//!    added masses alone.
//! 2. **Least squares.** With the measured degrees of freedom `S` (the probes) and the others
//!    `U`, the rows of `D q = f_u + P_B f_B` read
//!    $$ [\,D_{:,U}\;\; -P_B\,] \begin{bmatrix} q_U \\ f_B \end{bmatrix} = f_u - D_{:,S}\,\Delta q_S, $$
//!    solved by QR after scaling every column to unit norm: the unknowns span ten orders of
//!    magnitude (forces against axial displacements) and an unscaled solve loses their digits.
//!    At least as many probes as bearing degrees of freedom are needed
//!    ([`FieldError::Underdetermined`]); the model residual
//!    `‖A x − b‖/‖b‖` is reported per speed.
//! 3. **Per bearing, 2×2.** $Z(\Omega) = -[f_B^1\; f_B^2]\,[q_B^1\; q_B^2]^{-1}$,
//!    `K(Ω) = Re Z`, `C(Ω) = Im Z / Ω`, with the condition number of `[q¹ q²]` per speed (above
//!    [`FIELD_SINGULAR_PAIR`] the pair is singular and
//!    `K`, `C` are not given).
//! 4. **Error bars** when the responses carry a standard deviation (stated, or from repeats;
//!    [`FieldTests`]): propagated to first order. Everything up to `Z` is complex-linear in the
//!    measured responses, `δZ = W (δΔ) Q⁻¹` with `W = −(L_f + Z L_q)` and `L` the sensitivities
//!    of the recovered `q_B`, `f_B` to `Δq_S` from the same QR; for circular noise of standard
//!    deviation `σ` on each of `Re`, `Im` of every response, `Re δZ_ij` and `Im δZ_ij` both have
//!    variance `Σ_k σ_k² |a_k|²` over the responses (baseline and tests, the baseline's noise
//!    entering both differences). In 400 simulated tests at 1 % noise the ±1.96σ intervals
//!    covered the truth in 95.1 % of the cases with probes at the bearings (`tests/estimation/field.rs`);
//!    where the noise gain is large (probes one node inboard, gains 16–290) first order no
//!    longer holds at 1 % noise (coverage 90 %), and holds again at 0.1 % (95.0 %).
//! 5. **Warnings.** Proportional added forces (masses in one plane: a rank-1 pair whatever
//!    their angles); singular or ill-conditioned pairs per bearing (isotropic supports give
//!    circular orbits and a singular pair; singular at every speed for every bearing is
//!    [`FieldError::RankDeficient`]); a speed within
//!    [`FIELD_NEAR_CRITICAL`] of a synchronous
//!    critical speed of the undamped rotor pinned at the probes, where noise is amplified; a
//!    noise gain (first-order `‖δZ‖/‖Z‖` per unit relative response noise, computed whether or
//!    not the responses carry deviations) above
//!    [`FIELD_NOISE_GAIN`].
//!    With more probes than the unknowns need and stated noise, the model residual is judged
//!    against the noise ([`FieldIdentification::residual_ratio`], about 1 when the model
//!    fits): above [`FIELD_RESIDUAL_RATIO`] the rotor
//!    model, the probe positions or the phase convention do not fit the measurements.
//! 6. **Constant fit** ([`fit_constant`]): `Re Z = K − Ω²M`, `Im Z = ΩC` over the speeds, which
//!    separates `K` and `M` (one speed cannot).
//! 7. **Mass-sum check** ([`MassSum`]): the bearings' added masses `M_dd` of the constant fits
//!    summed per direction, with σ, beside the rotor model's translational mass `t_dᵀ M t_d`.
//!    The model already carries the rotor's inertia, so the sum is what the measurements add
//!    to it, small for a sound model; a wrong rotor mass makes it large (not equal to the
//!    error). A sum beyond 3σ and 25 % of the modelled mass is a warning.
//!
//! The rotor model is read from JSON ([`RotorModel::from_json`], feature `json`): ROSS 3.x
//! users write it in a few lines (6 degrees of freedom per node, `x, y, z, alpha, beta, theta`;
//! `M0`, `K0`, `C0`, `G0` are ROSS 3.1's matrices without bearings, and a rotor built with ROSS
//! and ROSS's own unbalance responses give back the bearings to 5e-10 in `tests/estimation/field.rs`):
//!
//! ```python
//! import json, ross as rs
//! rotor = rs.Rotor.load("rotor.toml")            # or built in the script
//! to_list = lambda a: [[float(v) for v in row] for row in a]
//! json.dump({"dof_per_node": 6, "dof_names": ["x", "y", "z", "alpha", "beta", "theta"],
//!            "M": to_list(rotor.M0), "K": to_list(rotor.K0), "G": to_list(rotor.G0),
//!            "C": to_list(rotor.C0),
//!            "bearings": [{"tag": b.tag, "node": b.n} for b in rotor.bearing_elements]},
//!           open("ROTOR.json", "w"))
//! ```
//!
//! [`BeamRotor`] builds a small Euler–Bernoulli model for tests and examples, and
//! [`ImbalanceRuns::simulate`] the responses of a rotor on given bearings.
//!
//! # Examples
//! ```
//! use bearing_ident::field::{
//!     self, BeamRotor, BearingCoefficients, BearingSite, Direction, Disk, Imbalance,
//!     ImbalanceRuns, Probe,
//! };
//! let rotor = BeamRotor {
//!     element_lengths: vec![0.15; 6],
//!     diameter: 0.05, density: 7850.0, young: 2.1e11, poisson: 0.3,
//!     disks: vec![Disk { node: 2, mass: 15.0, polar: 0.12, diametral: 0.06 }],
//!     bearings: vec![BearingSite::new("brg0", 0), BearingSite::new("brg1", 6)],
//! }
//! .model()?;
//! let brg = |_b: usize, w: f64| BearingCoefficients {
//!     stiffness: [[2e7 + 1e4 * w, 3e6], [-4e6, 3e7]],
//!     damping: [[2e4, 1e3], [-1e3, 3e4]],
//! };
//! let probes = [0, 6]
//!     .into_iter()
//!     .flat_map(|node| [Direction::X, Direction::Y].map(|dir| Probe { node, dir }))
//!     .collect();
//! let at = |node, phase_rad| vec![Imbalance { node, magnitude_kg_m: 1e-4, phase_rad }];
//! let tests = ImbalanceRuns {
//!     speeds_rad_s: vec![100.0, 200.0],
//!     probes,
//!     residual: at(3, 1.0),
//!     added: [at(2, 0.0), at(5, 2.0)],
//!     noise: 0.0,
//!     repeats: 1,
//!     seed: 1,
//! }
//! .simulate(&rotor, brg)?;
//! let id = field::identify(&rotor, &tests)?;
//! let k = id.bearings()[0].coefficients[1].unwrap().stiffness;
//! assert!((k[0][0] / 2.2e7 - 1.0).abs() < 1e-8);
//! assert!((k[1][0] / -4e6 - 1.0).abs() < 1e-8);
//! # Ok::<(), bearing_ident::Error>(())
//! ```
//!
// Without feature `json`, the link goes to the crate's feature list.
#![cfg_attr(
    not(feature = "json"),
    doc = "[`RotorModel::from_json`]: crate#feature-flags"
)]

mod beam;
mod fit;
mod inputs;
#[cfg(feature = "json")]
mod json;
mod mass_sum;
mod model;
mod result;
mod simulate;
mod solve;

pub use beam::{BeamRotor, DOF_NAMES, Disk};
pub use fit::{ConstantFit, fit_constant};
pub use inputs::{FieldTests, Imbalance, Probe, Response, Run};
pub use mass_sum::MassSum;
pub use model::{BearingSite, Direction, RotorModel};
pub use result::{BearingIdentification, FieldIdentification, SpeedCoefficients};
pub use simulate::{BearingCoefficients, ImbalanceRuns};

use crate::error::FieldError;
use crate::error::{Error, Result, Warning};
use crate::tolerance::{
    FIELD_DEPENDENT_TESTS, FIELD_ILL_CONDITIONED_PAIR, FIELD_NEAR_CRITICAL, FIELD_NOISE_GAIN,
    FIELD_RESIDUAL_RATIO, FIELD_SINGULAR_PAIR,
};

/// Identifies the bearings of `rotor` from the imbalance tests `tests` (see the
/// [module](self) documentation for the method).
///
/// # Errors
/// [`FieldError::Input`] for tests that do not fit the rotor (nodes past its last, a test
/// without masses or with zero added force, no responses, speeds not positive);
/// [`FieldError::NonFinite`] for NaN or infinite values; [`FieldError::MissingResponse`] when a probe
/// lacks its response at a speed and run; [`FieldError::Underdetermined`] for fewer probes than
/// bearing degrees of freedom or a least-squares system singular at every speed;
/// [`FieldError::RankDeficient`] when every bearing's response pair is singular at every
/// speed.
///
/// # Examples
/// See the [module](self) documentation.
pub fn identify(rotor: &RotorModel, tests: &FieldTests) -> Result<FieldIdentification> {
    let m = tests.measurements(rotor)?;
    let nb = rotor.bearings().len();
    if m.probes.len() < 2 * nb {
        return Err(Error::Field(FieldError::Underdetermined {
            measured: m.probes.len(),
            bearing_dofs: 2 * nb,
            reason: "give at least x and y at (or near) every bearing",
        }));
    }
    let mut warnings = Vec::new();
    // Proportional added forces: the pair is rank 1 at every speed (Ω² cancels).
    let [f1, f2] = [0, 1].map(|t| solve::imbalance_forces(rotor, &tests.imbalances[t], 1.0));
    let norm = |f: &[faer::c64]| f.iter().map(|v| v.norm_sqr()).sum::<f64>().sqrt();
    let (n1, n2) = (norm(&f1), norm(&f2));
    if !(n1 > 0.0 && n2 > 0.0) {
        return Err(Error::Field(FieldError::Input {
            message: "a test's added imbalances sum to zero force".to_owned(),
        }));
    }
    let inner: faer::c64 = f1.iter().zip(&f2).map(|(a, b)| a.conj() * b).sum();
    let correlation = inner.norm() / (n1 * n2);
    if correlation > 1.0 - FIELD_DEPENDENT_TESTS {
        warnings.push(Warning::DependentTests { correlation });
    }
    let layout = solve::Layout::new(rotor, &m);
    let ns = m.speeds.len();
    let mut bearings: Vec<BearingIdentification> = rotor
        .bearings()
        .iter()
        .map(|b| BearingIdentification {
            tag: b.tag.clone(),
            node: b.node,
            coefficients: Vec::with_capacity(ns),
            condition_number: Vec::with_capacity(ns),
        })
        .collect();
    let mut model_residual = Vec::with_capacity(ns);
    let mut residual_ratio = Vec::with_capacity(ns);
    for s in 0..ns {
        match solve::solve_speed(rotor, &layout, &m, &tests.imbalances, s) {
            Some(sol) => {
                model_residual.push(Some(sol.residual));
                residual_ratio.push(sol.residual_ratio);
                for (b, (cond, c)) in sol.bearings.into_iter().enumerate() {
                    bearings[b].condition_number.push(cond);
                    bearings[b].coefficients.push(c);
                }
            }
            None => {
                model_residual.push(None);
                residual_ratio.push(None);
                for b in &mut bearings {
                    b.condition_number.push(f64::INFINITY);
                    b.coefficients.push(None);
                }
            }
        }
    }
    if model_residual.iter().all(Option::is_none) {
        return Err(Error::Field(FieldError::Underdetermined {
            measured: m.probes.len(),
            bearing_dofs: 2 * nb,
            reason: "the probes do not determine the bearing forces at any speed \
                     (probes too far from the bearings, or all on one side)",
        }));
    }
    if bearings
        .iter()
        .all(|b| b.coefficients.iter().all(Option::is_none))
    {
        let (bearing, worst) = bearings
            .iter()
            .map(|b| {
                let best = b
                    .condition_number
                    .iter()
                    .copied()
                    .fold(f64::INFINITY, f64::min);
                (b.tag.clone(), best)
            })
            .fold(
                (String::new(), 0.0),
                |acc, x| if x.1 >= acc.1 { x } else { acc },
            );
        return Err(Error::Field(FieldError::RankDeficient {
            bearing,
            worst,
            dependent_tests: warnings
                .iter()
                .any(|w| matches!(w, Warning::DependentTests { .. })),
        }));
    }
    for b in &bearings {
        let at = |keep: &dyn Fn(usize) -> bool| -> Vec<f64> {
            (0..ns).filter(|&s| keep(s)).map(|s| m.speeds[s]).collect()
        };
        let singular = at(&|s| model_residual[s].is_some() && b.coefficients[s].is_none());
        if !singular.is_empty() {
            warnings.push(Warning::SingularPair {
                bearing: b.tag.clone(),
                speeds_rad_s: singular,
                limit: FIELD_SINGULAR_PAIR,
            });
        }
        let ill = |s: usize| {
            b.coefficients[s].is_some() && b.condition_number[s] > FIELD_ILL_CONDITIONED_PAIR
        };
        let speeds = at(&ill);
        if !speeds.is_empty() {
            let worst = (0..ns)
                .filter(|&s| ill(s))
                .map(|s| b.condition_number[s])
                .fold(0.0, f64::max);
            warnings.push(Warning::IllConditionedPair {
                bearing: b.tag.clone(),
                speeds_rad_s: speeds,
                worst,
                threshold: FIELD_ILL_CONDITIONED_PAIR,
            });
        }
    }
    for b in &bearings {
        let noisy = |s: usize| b.coefficients[s].is_some_and(|c| c.noise_gain > FIELD_NOISE_GAIN);
        let speeds: Vec<f64> = (0..ns).filter(|&s| noisy(s)).map(|s| m.speeds[s]).collect();
        if !speeds.is_empty() {
            let worst = b
                .coefficients
                .iter()
                .flatten()
                .map(|c| c.noise_gain)
                .fold(0.0, f64::max);
            warnings.push(Warning::HighNoiseGain {
                bearing: b.tag.clone(),
                speeds_rad_s: speeds,
                worst,
                threshold: FIELD_NOISE_GAIN,
            });
        }
    }
    let pinned_critical_speeds = solve::pinned_critical_speeds(rotor, &layout);
    for &speed in &m.speeds {
        let near = pinned_critical_speeds
            .iter()
            .copied()
            .filter(|c| (speed - c).abs() <= FIELD_NEAR_CRITICAL * c)
            .min_by(|a, b| (speed - a).abs().total_cmp(&(speed - b).abs()));
        if let Some(critical_rad_s) = near {
            warnings.push(Warning::NearPinnedCritical {
                speed_rad_s: speed,
                critical_rad_s,
            });
        }
    }
    let misfit: Vec<(f64, f64)> = m
        .speeds
        .iter()
        .zip(&residual_ratio)
        .filter_map(|(&w, r)| r.filter(|&r| r > FIELD_RESIDUAL_RATIO).map(|r| (w, r)))
        .collect();
    if !misfit.is_empty() {
        warnings.push(Warning::ModelResidual {
            speeds_rad_s: misfit.iter().map(|p| p.0).collect(),
            worst_ratio: misfit.iter().map(|p| p.1).fold(0.0, f64::max),
            limit: FIELD_RESIDUAL_RATIO,
        });
    }
    let mut id = FieldIdentification {
        speeds: m.speeds,
        probes: m.probes,
        bearings,
        model_residual,
        residual_ratio,
        pinned_critical_speeds,
        mass_sum: None,
        warnings,
    };
    id.mass_sum = MassSum::of(rotor, &fit_constant(&id));
    if let Some(sum) = &id.mass_sum {
        id.warnings.extend(sum.warnings());
    }
    Ok(id)
}
