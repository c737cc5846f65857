//! The operating conditions of a test ([`Conditions`]) and their text with units
//! ([`parse_clearance`], [`parse_load`], [`parse_speed`]).

use crate::error::{Error, Result, excerpt};

/// Standard gravity (m/s²): a rotor of weight `W` has mass `W/g`.
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// The operating conditions of a test: the radial clearance `c` (m), the static load `W`
/// (N) and the rotor speed `Ω` (rad/s), each optional.
///
/// # Examples
/// ```
/// use bearing_ident::rotor::Conditions;
/// let c = Conditions::default().clearance_m(100e-6).load_n(500.0).speed_rpm(3000.0);
/// assert!((c.speed().unwrap() - 100.0 * std::f64::consts::PI).abs() < 1e-12);
/// assert_eq!(c.clearance().unwrap(), 100e-6);
/// assert!(Conditions::default().load().is_none());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Conditions {
    clearance_m: Option<f64>,
    load_n: Option<f64>,
    speed_rad_s: Option<f64>,
}

impl Conditions {
    /// The radial clearance (m). Valid: finite and > 0 (checked by [`Conditions::check`]).
    pub fn clearance_m(mut self, c: f64) -> Self {
        self.clearance_m = Some(c);
        self
    }

    /// The static load on the element (N). Valid: finite and > 0.
    pub fn load_n(mut self, w: f64) -> Self {
        self.load_n = Some(w);
        self
    }

    /// The rotor speed (rad/s). Valid: finite and > 0.
    pub fn speed_rad_s(mut self, omega: f64) -> Self {
        self.speed_rad_s = Some(omega);
        self
    }

    /// The rotor speed in revolutions per minute.
    pub fn speed_rpm(self, rpm: f64) -> Self {
        self.speed_rad_s(rpm * 2.0 * std::f64::consts::PI / 60.0)
    }

    /// The radial clearance (m), if given.
    pub fn clearance(&self) -> Option<f64> {
        self.clearance_m
    }

    /// The static load (N), if given.
    pub fn load(&self) -> Option<f64> {
        self.load_n
    }

    /// The rotor speed (rad/s), if given.
    pub fn speed(&self) -> Option<f64> {
        self.speed_rad_s
    }

    /// Whether none is given.
    pub fn is_empty(&self) -> bool {
        self == &Self::default()
    }

    /// The conditions, each given one finite and positive.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the option (`clearance`, `load`, `speed`) of a value
    /// that is not finite and positive.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::rotor::Conditions;
    /// let e = Conditions::default().load_n(0.0).check().unwrap_err();
    /// assert_eq!(e.kind(), "invalid_argument");
    /// assert!(e.to_string().contains("--load"));
    /// ```
    pub fn check(self) -> Result<Self> {
        for (option, value, unit) in [
            ("clearance", self.clearance_m, "m"),
            ("load", self.load_n, "N"),
            ("speed", self.speed_rad_s, "rad/s"),
        ] {
            if let Some(v) = value.filter(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(Error::InvalidOption {
                    option,
                    message: format!("--{option} {v} {unit}: expected a value > 0"),
                });
            }
        }
        Ok(self)
    }

    /// The clearance, or the error that names it missing for `what`.
    pub(crate) fn needed_clearance(&self, what: &str) -> Result<f64> {
        self.clearance_m.ok_or_else(|| missing("clearance", what))
    }

    /// The load, or the error that names it missing for `what`.
    pub(crate) fn needed_load(&self, what: &str) -> Result<f64> {
        self.load_n.ok_or_else(|| missing("load", what))
    }

    /// The speed, or the error that names it missing for `what`.
    pub(crate) fn needed_speed(&self, what: &str) -> Result<f64> {
        self.speed_rad_s.ok_or_else(|| missing("speed", what))
    }
}

fn missing(option: &'static str, what: &str) -> Error {
    Error::InvalidOption {
        option,
        message: format!("--{option} is needed for {what}"),
    }
}

/// A number followed by a unit of `units` (`(name, numerator, denominator)` of its factor
/// to SI, so that `100um` is exactly `100/10⁶`; names compared without case, spaces allowed
/// between), finite and > 0, in SI.
fn quantity(option: &'static str, text: &str, units: &[(&str, f64, f64)]) -> Result<f64> {
    let expected: Vec<&str> = units.iter().map(|u| u.0).collect();
    let bad = || Error::InvalidOption {
        option,
        message: format!(
            "--{option} `{}`: expected a number > 0 with its unit ({})",
            excerpt(text),
            expected.join(", ")
        ),
    };
    let t = text.trim();
    let split = t
        // No unit begins with `e`, which an exponent may hold.
        .find(|c: char| c.is_ascii_alphabetic() && c != 'e' && c != 'E')
        .ok_or_else(bad)?;
    let (number, unit) = t.split_at(split);
    let value: f64 = number.trim().parse().map_err(|_| bad())?;
    let (_, times, per) = units
        .iter()
        .find(|u| u.0.eq_ignore_ascii_case(unit.trim()))
        .ok_or_else(bad)?;
    let si = value * times / per;
    if si.is_finite() && si > 0.0 {
        Ok(si)
    } else {
        Err(bad())
    }
}

/// A radial clearance with its unit, `m`, `mm`, `um` (or `µm`), `mil`, in metres.
///
/// # Errors
/// [`Error::InvalidOption`] (`clearance`) for text that is not a number > 0 with one of the
/// units.
///
/// # Examples
/// ```
/// use bearing_ident::rotor::parse_clearance;
/// assert_eq!(parse_clearance("100um")?, 1e-4);
/// assert!((parse_clearance("4 mil")? - 1.016e-4).abs() < 1e-18);
/// assert!(parse_clearance("100").is_err());
/// assert!(parse_clearance("-1mm").is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn parse_clearance(text: &str) -> Result<f64> {
    let text = text.replace('µ', "u");
    quantity(
        "clearance",
        &text,
        &[
            ("m", 1.0, 1.0),
            ("mm", 1.0, 1e3),
            ("um", 1.0, 1e6),
            ("mil", 25.4, 1e6),
        ],
    )
}

/// A static load with its unit, `N`, `kN`, `lbf`, in newtons.
///
/// # Errors
/// [`Error::InvalidOption`] (`load`) for text that is not a number > 0 with one of the units.
///
/// # Examples
/// ```
/// use bearing_ident::rotor::parse_load;
/// assert_eq!(parse_load("500N")?, 500.0);
/// assert!((parse_load("100 lbf")? - 444.822_161_526_05).abs() < 1e-9);
/// assert!(parse_load("0N").is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn parse_load(text: &str) -> Result<f64> {
    quantity(
        "load",
        text,
        &[
            ("N", 1.0, 1.0),
            ("kN", 1e3, 1.0),
            ("lbf", 4.448_221_615_260_5, 1.0),
        ],
    )
}

/// A rotor speed with its unit, `rpm`, `Hz` (revolutions per second), `rad/s`, in rad/s.
///
/// # Errors
/// [`Error::InvalidOption`] (`speed`) for text that is not a number > 0 with one of the
/// units.
///
/// # Examples
/// ```
/// use bearing_ident::rotor::parse_speed;
/// let pi = std::f64::consts::PI;
/// assert!((parse_speed("3000rpm")? - 100.0 * pi).abs() < 1e-12);
/// assert!((parse_speed("50 Hz")? - 100.0 * pi).abs() < 1e-12);
/// assert_eq!(parse_speed("314 rad/s")?, 314.0);
/// assert!(parse_speed("fast").is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn parse_speed(text: &str) -> Result<f64> {
    let two_pi = 2.0 * std::f64::consts::PI;
    quantity(
        "speed",
        text,
        &[
            ("rpm", two_pi, 60.0),
            ("Hz", two_pi, 1.0),
            ("rad/s", 1.0, 1.0),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each unit converts; a missing unit, an unknown one, zero, a negative value and a
    /// non-finite one are refused naming the option.
    #[test]
    fn units_convert_and_bad_values_name_the_option() {
        assert!((parse_clearance("0.1 mm").unwrap() - 1e-4).abs() < 1e-18);
        assert!((parse_clearance("100µm").unwrap() - 1e-4).abs() < 1e-18);
        assert_eq!(
            parse_clearance("1e-4m").unwrap().to_bits(),
            1e-4f64.to_bits()
        );
        assert_eq!(parse_load("2kN").unwrap().to_bits(), 2000.0f64.to_bits());
        assert!((parse_speed("1rad/s").unwrap() - 1.0).abs() < 1e-15);
        for (option, result) in [
            ("clearance", parse_clearance("100")),
            ("clearance", parse_clearance("100 ft")),
            ("clearance", parse_clearance("0um")),
            ("load", parse_load("-5 N")),
            ("load", parse_load("inf N")),
            ("speed", parse_speed("rpm")),
        ] {
            let e = result.unwrap_err();
            assert_eq!(e.kind(), "invalid_argument");
            assert!(e.to_string().contains(&format!("--{option}")), "{e}");
        }
        let e = Conditions::default().needed_clearance("x").unwrap_err();
        assert!(e.to_string().contains("--clearance is needed"), "{e}");
        assert!(Conditions::default().clearance_m(f64::NAN).check().is_err());
    }
}
