//! The stability of a rigid rotor on the element ([`Stability`]): Lund's whirl-frequency
//! ratio and threshold speed ([`lund`]), and the sign change of the effective damping.

use faer::Mat;

use super::{Conditions, STANDARD_GRAVITY, propagated_std};
use crate::element::ElementModel;
use crate::model::Coefficients;

/// Lund's criterion for a rigid rotor on a 2 × 2 element ([`lund`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lund {
    /// The equivalent stiffness `K_eq` (N/m).
    pub equivalent_stiffness: f64,
    /// The whirl frequency `ν` at the threshold (rad/s).
    pub whirl_rad_s: f64,
}

/// Lund's rigid-rotor criterion from the stiffness `k` and damping `c` (rows `x`, `y`) of the
/// element at the test's speed. A rotor of mass `m` on the element, `m ẍ + C ẋ + K x = 0`, is
/// at its threshold when `s = iν` solves `det(K − ν² m I + iν C) = 0`; the imaginary part
/// and the real part of the determinant give
///
/// $$K_{eq} = m\nu^2 = \frac{K_{xx}C_{yy} + K_{yy}C_{xx} - K_{xy}C_{yx} - K_{yx}C_{xy}}
/// {C_{xx} + C_{yy}},\qquad
/// \nu^2 = \frac{(K_{xx} - K_{eq})(K_{yy} - K_{eq}) - K_{xy}K_{yx}}{C_{xx}C_{yy} - C_{xy}C_{yx}}.$$
///
/// With the dimensionless coefficients kept as measured (`C ∝ 1/Ω`), the whirl-frequency
/// ratio `γ = ν/Ω` is the same at every speed and the rotor is stable below
/// `Ω_th = √(K_eq/m) / γ`. The element's added mass is not part of the criterion (as in
/// Lund's and ROSS's).
///
/// # Errors
/// The reason, as text, when the criterion does not apply: `C_xx + C_yy ≤ 0`, no real whirl
/// frequency (`ν² ≤ 0`), or `K_eq ≤ 0` (no positive root for the threshold).
///
/// # Examples
/// ```
/// use bearing_ident::rotor::lund;
/// // Isotropic, cross-coupled: K_eq = K, ν = k/C = 5e6/2e4 = 250 rad/s.
/// let l = lund([[2e7, 5e6], [-5e6, 2e7]], [[2e4, 0.0], [0.0, 2e4]]).unwrap();
/// assert!((l.equivalent_stiffness - 2e7).abs() < 1e-6);
/// assert!((l.whirl_rad_s - 250.0).abs() < 1e-9);
/// assert!(lund([[2e7, 0.0], [0.0, 2e7]], [[2e4, 0.0], [0.0, 2e4]]).is_err());
/// ```
pub fn lund(k: [[f64; 2]; 2], c: [[f64; 2]; 2]) -> std::result::Result<Lund, String> {
    let direct = c[0][0] + c[1][1];
    if direct.is_nan() || direct <= 0.0 {
        return Err(format!(
            "C_xx + C_yy = {direct:.4e} N·s/m ≤ 0: Lund's criterion does not apply"
        ));
    }
    let k_eq =
        (k[0][0] * c[1][1] + k[1][1] * c[0][0] - k[0][1] * c[1][0] - k[1][0] * c[0][1]) / direct;
    let numerator = (k[0][0] - k_eq) * (k[1][1] - k_eq) - k[0][1] * k[1][0];
    let denominator = c[0][0] * c[1][1] - c[0][1] * c[1][0];
    let nu2 = numerator / denominator;
    if !(nu2 > 0.0 && nu2.is_finite()) {
        return Err(format!(
            "ν² = {nu2:.4e} (rad/s)² ≤ 0: no real whirl frequency, no threshold speed"
        ));
    }
    if k_eq.is_nan() || k_eq <= 0.0 {
        return Err(format!(
            "K_eq = {k_eq:.4e} N/m ≤ 0: no positive root for the threshold speed"
        ));
    }
    Ok(Lund {
        equivalent_stiffness: k_eq,
        whirl_rad_s: nu2.sqrt(),
    })
}

/// The stability of a rigid rotor on the element, each value with its first-order standard
/// deviation ([`propagated_std`]); `None` with a `reason` where it does not apply:
///
/// - `whirl_frequency_ratio`, `γ = ν/Ω` of [`lund`] (needs the speed);
/// - `threshold_speed_rpm`, `Ω_th = √(K_eq/m)/γ` with the rotor's mass `m = W/g` on the
///   element (`g` = [`STANDARD_GRAVITY`]; needs the load too);
/// - `c_eff_crossover_hz`, where `C_eff(ω) = (C_xx + C_yy)/2 − (K_xy − K_yx)/(2ω)` changes
///   sign: `ω = (K_xy − K_yx)/(C_xx + C_yy)` for constant coefficients, the element model's
///   crossover ([`ElementModel::effective`]) where one is fitted (needs no condition).
///
/// For an isotropic element the crossover is the threshold's whirl frequency `ν`.
#[derive(Debug, Clone, PartialEq)]
pub struct Stability {
    /// `γ = ν/Ω`.
    pub whirl_frequency_ratio: Option<f64>,
    /// Its standard deviation.
    pub whirl_frequency_ratio_std: Option<f64>,
    /// `Ω_th` (rpm).
    pub threshold_speed_rpm: Option<f64>,
    /// Its standard deviation (rpm).
    pub threshold_speed_rpm_std: Option<f64>,
    /// The frequency where `C_eff` changes sign (Hz).
    pub c_eff_crossover_hz: Option<f64>,
    /// Its standard deviation (Hz).
    pub c_eff_crossover_hz_std: Option<f64>,
    /// Why a value is `None`, sentences joined by `; ` (`None` when every value is there).
    pub reason: Option<String>,
}

fn two(m: faer::MatRef<'_, f64>) -> [[f64; 2]; 2] {
    [[m[(0, 0)], m[(0, 1)]], [m[(1, 0)], m[(1, 1)]]]
}

/// `ω` (rad/s) where the constant coefficients' `C_eff` changes sign, if positive.
fn crossover_rad_s(c: &Coefficients) -> Option<f64> {
    let (k, d) = (two(c.stiffness()), two(c.damping()));
    let omega = (k[0][1] - k[1][0]) / (d[0][0] + d[1][1]);
    (omega.is_finite() && omega > 0.0).then_some(omega)
}

impl Stability {
    /// The stability of a rigid rotor on the element of `coefficients` (2 × 2) under
    /// `conditions`, the standard deviations from `covariance` (of the stacked coefficients
    /// in the order of [`propagated_std`]; `None` without error bars); the crossover from
    /// `model` when it is a family other than `kcm`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Coefficients;
    /// use bearing_ident::faer::Mat;
    /// use bearing_ident::rotor::{Conditions, Stability};
    /// let m = |v: [f64; 4]| Mat::from_fn(2, 2, |i, j| v[2 * i + j]);
    /// let c = Coefficients::new(Mat::zeros(2, 2), m([2e4, 0.0, 0.0, 2e4]),
    ///     m([2e7, 5e6, -5e6, 2e7]))?;
    /// let at = Conditions::default().load_n(500.0).speed_rpm(3000.0);
    /// let s = Stability::new(&c, None, None, &at);
    /// // γ = 250/(100π); Ω_th = √(2e7 g/500)/γ.
    /// let gamma = 250.0 / (100.0 * std::f64::consts::PI);
    /// assert!((s.whirl_frequency_ratio.unwrap() - gamma).abs() < 1e-12);
    /// let rpm = (2e7 * 9.80665 / 500.0f64).sqrt() / gamma * 60.0 / (2.0 * std::f64::consts::PI);
    /// assert!((s.threshold_speed_rpm.unwrap() / rpm - 1.0).abs() < 1e-12);
    /// assert!(s.reason.is_none());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn new(
        coefficients: &Coefficients,
        covariance: Option<&Mat<f64>>,
        model: Option<&ElementModel>,
        conditions: &Conditions,
    ) -> Self {
        let mut out = Stability {
            whirl_frequency_ratio: None,
            whirl_frequency_ratio_std: None,
            threshold_speed_rpm: None,
            threshold_speed_rpm_std: None,
            c_eff_crossover_hz: None,
            c_eff_crossover_hz_std: None,
            reason: None,
        };
        let mut reasons: Vec<String> = Vec::new();
        if coefficients.dofs() != 2 {
            out.reason = Some(format!(
                "a {0} × {0} element: the criteria are those of a 2 × 2 bearing",
                coefficients.dofs()
            ));
            return out;
        }
        let std = |f: &dyn Fn(&Coefficients) -> Option<f64>| {
            covariance.and_then(|cov| propagated_std(coefficients, cov, f))
        };
        let of = |c: &Coefficients| lund(two(c.stiffness()), two(c.damping()));
        let rpm = 60.0 / (2.0 * std::f64::consts::PI);
        let conditions = conditions.check().ok();
        let speed = conditions.and_then(|c| c.speed());
        let load = conditions.and_then(|c| c.load());
        match (of(coefficients), speed) {
            (Err(reason), _) => reasons.push(reason),
            (Ok(_), None) => reasons.push("no speed given: no whirl-frequency ratio".into()),
            (Ok(l), Some(omega)) => {
                out.whirl_frequency_ratio = Some(l.whirl_rad_s / omega);
                out.whirl_frequency_ratio_std = std(&|c| of(c).ok().map(|l| l.whirl_rad_s / omega));
                let threshold = |l: Lund, w: f64| {
                    (l.equivalent_stiffness * STANDARD_GRAVITY / w).sqrt() * omega / l.whirl_rad_s
                        * rpm
                };
                match load {
                    Some(w) => {
                        out.threshold_speed_rpm = Some(threshold(l, w));
                        out.threshold_speed_rpm_std = std(&|c| of(c).ok().map(|l| threshold(l, w)));
                    }
                    None => reasons.push("no load given: no threshold speed".into()),
                }
            }
        }
        let fitted = model
            .filter(|m| !m.is_kcm())
            .and_then(ElementModel::effective);
        let two_pi = 2.0 * std::f64::consts::PI;
        match fitted {
            Some(e) => {
                out.c_eff_crossover_hz = e.crossover_hz;
                out.c_eff_crossover_hz_std = e.crossover_hz_std;
            }
            None => {
                out.c_eff_crossover_hz = crossover_rad_s(coefficients).map(|w| w / two_pi);
                out.c_eff_crossover_hz_std = out
                    .c_eff_crossover_hz
                    .and_then(|_| std(&|c| crossover_rad_s(c).map(|w| w / two_pi)));
            }
        }
        if out.c_eff_crossover_hz.is_none() {
            reasons.push("C_eff keeps its sign: no crossover".into());
        }
        out.reason = (!reasons.is_empty()).then(|| reasons.join("; "));
        out
    }
}

#[cfg(feature = "serde")]
/// `{whirl_frequency_ratio, whirl_frequency_ratio_std, threshold_speed_rpm,
/// threshold_speed_rpm_std, c_eff_crossover_hz, c_eff_crossover_hz_std, reason}`.
impl serde::Serialize for Stability {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(7))?;
        m.serialize_entry("whirl_frequency_ratio", &self.whirl_frequency_ratio)?;
        m.serialize_entry("whirl_frequency_ratio_std", &self.whirl_frequency_ratio_std)?;
        m.serialize_entry("threshold_speed_rpm", &self.threshold_speed_rpm)?;
        m.serialize_entry("threshold_speed_rpm_std", &self.threshold_speed_rpm_std)?;
        m.serialize_entry("c_eff_crossover_hz", &self.c_eff_crossover_hz)?;
        m.serialize_entry("c_eff_crossover_hz_std", &self.c_eff_crossover_hz_std)?;
        m.serialize_entry("reason", &self.reason)?;
        m.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn two_by_two(v: [f64; 4]) -> Mat<f64> {
        Mat::from_fn(2, 2, |i, j| v[2 * i + j])
    }

    fn element(k: [f64; 4], c: [f64; 4]) -> Coefficients {
        Coefficients::new(Mat::zeros(2, 2), two_by_two(c), two_by_two(k)).unwrap()
    }

    /// The hand example: an isotropic element, `K_xx = K_yy = K = 2·10⁷ N/m`, cross-coupled
    /// `K_xy = −K_yx = k = 5·10⁶ N/m`, `C_xx = C_yy = C = 2·10⁴ N·s/m`, under `W = 500 N` at
    /// `Ω = 3000 rpm = 100π rad/s`. The closed form, from `det(K − mν²I + iνC) = 0`:
    /// the imaginary part gives `K_eq = K`, the real part `(K − K_eq)² + k² = ν²C²`, so
    /// `ν = k/C = 250 rad/s`, `γ = ν/Ω = 2.5/π = 0.795 774 7`; the rotor's mass
    /// `m = W/g = 50.985 kg` is at its threshold when `mν² = K_eq` with `ν = γΩ_th`:
    /// `Ω_th = √(Kg/W)/γ = 787.04 rad/s = 7515.737 rpm`. `C_eff(ω) = C − k/ω` changes sign
    /// at `ω = k/C = ν`: 39.788 736 Hz.
    #[test]
    fn lund_matches_the_closed_form_on_a_hand_example() {
        let c = element([2e7, 5e6, -5e6, 2e7], [2e4, 0.0, 0.0, 2e4]);
        let at = Conditions::default().load_n(500.0).speed_rpm(3000.0);
        let s = Stability::new(&c, None, None, &at);
        let gamma = 2.5 / PI;
        let threshold_rpm = (2e7 * STANDARD_GRAVITY / 500.0).sqrt() / gamma * 30.0 / PI;
        assert!((s.whirl_frequency_ratio.unwrap() - gamma).abs() < 1e-14);
        assert!((s.threshold_speed_rpm.unwrap() - threshold_rpm).abs() < 1e-9);
        assert!((threshold_rpm - 7515.737).abs() < 1e-3);
        assert!((s.c_eff_crossover_hz.unwrap() - 125.0 / PI).abs() < 1e-12);
        assert_eq!(s.reason, None);
        assert_eq!(s.whirl_frequency_ratio_std, None);
    }

    /// An anisotropic element (`K = [3, 1.5; −1, 5]·10⁷ N/m`, `C = [4, 0.3; 0.2, 6]·10⁴ N·s/m`,
    /// `W = 800 N`, `Ω = 4000 rpm`; closed form `K_eq = 3.8·10⁷ N/m`, `ν = 150.19 rad/s`,
    /// `γ = 0.358 55`, `Ω_th = 18 177.4 rpm`) against the eigenvalues of the rigid rotor
    /// `m ẍ + (Ω/Ω') C ẋ + K x = 0` at speeds `Ω'` about the threshold (the dimensionless
    /// damping kept): the least damped mode has zero damping at `Ω_th`, whirling at `γΩ_th`,
    /// and is damped 1 % below, undamped 1 % above. Its damping ratio changes by 0.085 per
    /// unit relative speed here, and the eigenvalues of this stiff state matrix are good to
    /// about 10⁻¹¹ of their modulus: `|ζ| < 10⁻⁹` places the threshold within 1.2·10⁻⁸ of
    /// `Ω_th` (numpy's eigenvalues at the same speed give `ζ = 3·10⁻¹⁷`).
    #[test]
    fn threshold_is_where_the_rigid_rotor_loses_its_damping() {
        let (k, c) = ([3e7, 1.5e7, -1e7, 5e7], [4e4, 3e3, 2e3, 6e4]);
        let (w, omega) = (800.0, 4000.0 * PI / 30.0);
        let s = Stability::new(
            &element(k, c),
            None,
            None,
            &Conditions::default().load_n(w).speed_rad_s(omega),
        );
        let gamma = s.whirl_frequency_ratio.unwrap();
        let threshold = s.threshold_speed_rpm.unwrap() * PI / 30.0;
        assert!((gamma - 0.358_547_086).abs() < 1e-8, "{gamma}");
        assert!((threshold * 30.0 / PI - 18_177.423_6).abs() < 1e-3);
        let mass = w / STANDARD_GRAVITY;
        let least_damped = |speed: f64| {
            let scaled = c.map(|v| v * omega / speed);
            let rotor = Coefficients::new(
                Mat::from_fn(2, 2, |i, j| if i == j { mass } else { 0.0 }),
                two_by_two(scaled),
                two_by_two(k),
            )
            .unwrap();
            rotor
                .modes()
                .unwrap()
                .into_iter()
                .min_by(|a, b| a.damping_ratio.total_cmp(&b.damping_ratio))
                .unwrap()
        };
        let at = least_damped(threshold);
        assert!(at.damping_ratio.abs() < 1e-9, "{}", at.damping_ratio);
        assert!((2.0 * PI * at.damped_frequency_hz / (gamma * threshold) - 1.0).abs() < 1e-9);
        assert!(least_damped(0.99 * threshold).damping_ratio > 1e-5);
        assert!(least_damped(1.01 * threshold).damping_ratio < -1e-5);
    }

    /// Where the criteria do not apply, `None` and the reason: no cross-coupling (no real
    /// whirl frequency), no speed, no load, negative direct damping, three degrees of freedom.
    #[test]
    fn where_it_does_not_apply_the_reason_says_why() {
        let at = Conditions::default().load_n(500.0).speed_rpm(3000.0);
        let plain = Stability::new(
            &element([2e7, 0.0, 0.0, 2e7], [2e4, 0.0, 0.0, 2e4]),
            None,
            None,
            &at,
        );
        assert_eq!(plain.whirl_frequency_ratio, None);
        assert!(
            plain
                .reason
                .as_deref()
                .unwrap()
                .contains("no real whirl frequency")
        );
        assert!(plain.reason.as_deref().unwrap().contains("no crossover"));
        let coupled = element([2e7, 5e6, -5e6, 2e7], [2e4, 0.0, 0.0, 2e4]);
        let no_load = Stability::new(&coupled, None, None, &Conditions::default().speed_rpm(3e3));
        assert!(no_load.whirl_frequency_ratio.is_some());
        assert_eq!(no_load.threshold_speed_rpm, None);
        assert_eq!(
            no_load.reason.as_deref(),
            Some("no load given: no threshold speed")
        );
        let no_speed = Stability::new(&coupled, None, None, &Conditions::default().load_n(1.0));
        assert_eq!(no_speed.whirl_frequency_ratio, None);
        assert!(no_speed.c_eff_crossover_hz.is_some());
        let negative = element([2e7, 5e6, -5e6, 2e7], [-2e4, 0.0, 0.0, -2e4]);
        let s = Stability::new(&negative, None, None, &at);
        assert!(s.reason.unwrap().contains("C_xx + C_yy"));
        let three =
            Coefficients::new(Mat::zeros(3, 3), Mat::identity(3, 3), Mat::identity(3, 3)).unwrap();
        assert!(
            Stability::new(&three, None, None, &at)
                .reason
                .unwrap()
                .contains("2 × 2")
        );
    }

    /// The first-order σ of γ, Ω_th and the crossover against their scatter over 4000 draws
    /// of the coefficients from a covariance of 1 % (K) and 2 % (C) with a correlation: within
    /// the sampling error of a σ over 4000 draws (1.1 %; 5 % allowed).
    #[test]
    fn first_order_std_matches_sampling() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, StandardNormal};
        let c = element([3e7, 1.5e7, -1e7, 5e7], [4e4, 3e3, 2e3, 6e4]);
        let theta = c.stacked();
        let (rows, p) = (theta.nrows(), theta.nrows() * theta.ncols());
        // Independent σ per coefficient, and K_xy, K_yx correlated +0.5.
        let sd = |i: usize| {
            let v = theta[(i % rows, i / rows)].abs();
            match i % rows {
                0 | 1 => 0.0,
                2 | 3 => 0.02 * v,
                _ => 0.01 * v,
            }
        };
        let (kxy, kyx) = (rows + 4, 5);
        let cov = Mat::from_fn(p, p, |a, b| match (a, b) {
            _ if a == b => sd(a).powi(2),
            (a, b) if (a, b) == (kxy, kyx) || (a, b) == (kyx, kxy) => 0.5 * sd(a) * sd(b),
            _ => 0.0,
        });
        let at = Conditions::default().load_n(800.0).speed_rpm(4000.0);
        let ours = Stability::new(&c, Some(&cov), None, &at);
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let mut draws: [Vec<f64>; 3] = Default::default();
        for _ in 0..4000 {
            let z: Vec<f64> = (0..p).map(|_| StandardNormal.sample(&mut rng)).collect();
            let moved = Mat::from_fn(rows, 2, |q, j| {
                let i = j * rows + q;
                let noise = if i == kyx {
                    sd(i) * (0.5 * z[kxy] + 0.75f64.sqrt() * z[i])
                } else {
                    sd(i) * z[i]
                };
                theta[(q, j)] + noise
            });
            let s = Stability::new(
                &Coefficients::from_stacked(moved.as_ref()).unwrap(),
                None,
                None,
                &at,
            );
            draws[0].push(s.whirl_frequency_ratio.unwrap());
            draws[1].push(s.threshold_speed_rpm.unwrap());
            draws[2].push(s.c_eff_crossover_hz.unwrap());
        }
        let spread = |v: &[f64]| {
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
        };
        for (first, sampled) in [
            (ours.whirl_frequency_ratio_std, spread(&draws[0])),
            (ours.threshold_speed_rpm_std, spread(&draws[1])),
            (ours.c_eff_crossover_hz_std, spread(&draws[2])),
        ] {
            let first = first.unwrap();
            assert!(
                (first / sampled - 1.0).abs() < 0.05,
                "{first:e} vs {sampled:e}"
            );
        }
    }
}
