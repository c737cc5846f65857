//! The coefficients in the dimensionless form of test reports ([`Dimensionless`]).

use faer::Mat;

use super::Conditions;
use crate::error::Result;
use crate::model::Coefficients;

/// Dimensionless coefficients, with the radial clearance `c`, the static load `W` and the
/// rotor speed `Ω`:
///
/// $$\bar K = K\,\frac{c}{W},\qquad \bar C = C\,\frac{\Omega c}{W},\qquad
/// \bar M = M\,\frac{\Omega^2 c}{W},$$
///
/// and their standard deviations scaled alike (the conditions are taken as exact).
///
/// # Examples
/// ```
/// use bearing_ident::Coefficients;
/// use bearing_ident::faer::Mat;
/// use bearing_ident::rotor::{Conditions, Dimensionless};
/// let c = Coefficients::new(Mat::zeros(1, 1), Mat::from_fn(1, 1, |_, _| 2e4),
///     Mat::from_fn(1, 1, |_, _| 2e7))?;
/// let at = Conditions::default().clearance_m(100e-6).load_n(500.0).speed_rpm(3000.0);
/// let d = Dimensionless::new(&c, None, &at)?;
/// assert!((d.stiffness()[(0, 0)] - 4.0).abs() < 1e-12);
/// // 2e4 · 100π · 1e-4 / 500 = 0.4π.
/// assert!((d.damping()[(0, 0)] - 0.4 * std::f64::consts::PI).abs() < 1e-12);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Dimensionless {
    stiffness: Mat<f64>,
    damping: Mat<f64>,
    mass: Mat<f64>,
    std: Option<[Mat<f64>; 3]>,
    clearance_m: f64,
    load_n: f64,
    speed_rad_s: f64,
}

impl Dimensionless {
    /// The dimensionless form of `coefficients` (and of their standard deviations `std`)
    /// under `conditions`.
    ///
    /// # Errors
    /// [`Error::InvalidOption`](crate::Error::InvalidOption) naming `clearance`, `load` or
    /// `speed` when one is missing, or not finite and positive.
    pub fn new(
        coefficients: &Coefficients,
        std: Option<&Coefficients>,
        conditions: &Conditions,
    ) -> Result<Self> {
        let conditions = conditions.check()?;
        let what = "dimensionless coefficients";
        let c = conditions.needed_clearance(what)?;
        let w = conditions.needed_load(what)?;
        let omega = conditions.needed_speed(what)?;
        let factors = [c / w, omega * c / w, omega * omega * c / w];
        let scaled = |m: faer::MatRef<'_, f64>, f: f64| {
            Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)] * f)
        };
        let of = |x: &Coefficients| {
            [
                scaled(x.stiffness(), factors[0]),
                scaled(x.damping(), factors[1]),
                scaled(x.mass(), factors[2]),
            ]
        };
        let [stiffness, damping, mass] = of(coefficients);
        Ok(Self {
            stiffness,
            damping,
            mass,
            std: std.map(of),
            clearance_m: c,
            load_n: w,
            speed_rad_s: omega,
        })
    }

    /// `K̄ = K c / W`.
    pub fn stiffness(&self) -> faer::MatRef<'_, f64> {
        self.stiffness.as_ref()
    }

    /// `C̄ = C Ω c / W`.
    pub fn damping(&self) -> faer::MatRef<'_, f64> {
        self.damping.as_ref()
    }

    /// `M̄ = M Ω² c / W`.
    pub fn mass(&self) -> faer::MatRef<'_, f64> {
        self.mass.as_ref()
    }

    /// The standard deviations of `K̄`, `C̄`, `M̄`, in this order (`None` without error
    /// bars).
    pub fn std_dev(&self) -> Option<[faer::MatRef<'_, f64>; 3]> {
        self.std
            .as_ref()
            .map(|[k, c, m]| [k.as_ref(), c.as_ref(), m.as_ref()])
    }

    /// The radial clearance (m).
    pub fn clearance_m(&self) -> f64 {
        self.clearance_m
    }

    /// The static load (N).
    pub fn load_n(&self) -> f64 {
        self.load_n
    }

    /// The rotor speed (rad/s).
    pub fn speed_rad_s(&self) -> f64 {
        self.speed_rad_s
    }
}

#[cfg(feature = "serde")]
/// `{K, C, M, K_std, C_std, M_std, clearance_m, load_n, speed_rpm}`, matrices as rows, the
/// `*_std` null without error bars.
impl serde::Serialize for Dimensionless {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use crate::model::rows;
        use serde::ser::SerializeMap;
        let std = self.std_dev();
        let mut m = s.serialize_map(Some(9))?;
        m.serialize_entry("K", &rows(self.stiffness()))?;
        m.serialize_entry("C", &rows(self.damping()))?;
        m.serialize_entry("M", &rows(self.mass()))?;
        m.serialize_entry("K_std", &std.map(|s| rows(s[0])))?;
        m.serialize_entry("C_std", &std.map(|s| rows(s[1])))?;
        m.serialize_entry("M_std", &std.map(|s| rows(s[2])))?;
        m.serialize_entry("clearance_m", &self.clearance_m)?;
        m.serialize_entry("load_n", &self.load_n)?;
        m.serialize_entry(
            "speed_rpm",
            &(self.speed_rad_s * 60.0 / (2.0 * std::f64::consts::PI)),
        )?;
        m.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The hand example: `K_xx = 2·10⁷ N/m`, `C_xx = 2·10⁴ N·s/m`, `M_xx = 10 kg` (σ 1 % each),
    /// `c = 100 µm`, `W = 500 N`, `Ω = 3000 rpm = 100π rad/s`: `K̄ = 2·10⁷·10⁻⁴/500 = 4`,
    /// `C̄ = 2·10⁴·100π·10⁻⁴/500 = 0.4π = 1.256 637`, `M̄ = 10·(100π)²·10⁻⁴/500 = 0.02π² =
    /// 0.197 392`, their σ 1 % of each.
    #[test]
    fn dimensionless_matches_the_hand_example() {
        let one = |v: f64| Mat::from_fn(1, 1, |_, _| v);
        let c = Coefficients::new(one(10.0), one(2e4), one(2e7)).unwrap();
        let s = Coefficients::new(one(0.1), one(2e2), one(2e5)).unwrap();
        let at = Conditions::default()
            .clearance_m(100e-6)
            .load_n(500.0)
            .speed_rpm(3000.0);
        let d = Dimensionless::new(&c, Some(&s), &at).unwrap();
        assert!((d.stiffness()[(0, 0)] - 4.0).abs() < 1e-12);
        assert!((d.damping()[(0, 0)] - 0.4 * PI).abs() < 1e-12);
        assert!((d.mass()[(0, 0)] - 0.02 * PI * PI).abs() < 1e-12);
        let [ks, cs, ms] = d.std_dev().unwrap();
        assert!((ks[(0, 0)] - 0.04).abs() < 1e-14);
        assert!((cs[(0, 0)] - 0.004 * PI).abs() < 1e-14);
        assert!((ms[(0, 0)] - 0.0002 * PI * PI).abs() < 1e-14);
        assert!((d.speed_rad_s() - 100.0 * PI).abs() < 1e-12);
    }

    /// A missing or non-positive condition is refused naming its option.
    #[test]
    fn a_missing_or_bad_condition_names_its_option() {
        let c = Coefficients::new(Mat::zeros(1, 1), Mat::zeros(1, 1), Mat::zeros(1, 1)).unwrap();
        let full = Conditions::default()
            .clearance_m(1e-4)
            .load_n(500.0)
            .speed_rpm(3000.0);
        for (option, at) in [
            ("clearance", full.clearance_m(0.0)),
            ("load", full.load_n(-1.0)),
            ("speed", full.speed_rad_s(f64::NAN)),
            (
                "load",
                Conditions::default().clearance_m(1e-4).speed_rpm(1.0),
            ),
            ("speed", Conditions::default().clearance_m(1e-4).load_n(1.0)),
            (
                "clearance",
                Conditions::default().load_n(1.0).speed_rpm(1.0),
            ),
        ] {
            let e = Dimensionless::new(&c, None, &at).unwrap_err();
            assert_eq!(e.kind(), "invalid_argument");
            assert!(e.to_string().contains(&format!("--{option}")), "{e}");
        }
    }
}
