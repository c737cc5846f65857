//! Units of the channels of a record, as a file or the user states them: each recognised name
//! turned into its factor to SI (N, m, m/s, m/s²), so that records are converted to SI before
//! anything else reads them.

/// What a unit measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// A force (SI: N).
    Force,
    /// A displacement (SI: m).
    Displacement,
    /// A velocity (SI: m/s).
    Velocity,
    /// An acceleration (SI: m/s²).
    Acceleration,
}

/// A pound-force in newtons (exact: 0.453 592 37 kg × 9.806 65 m/s²).
pub const LBF: f64 = 4.448_221_615_260_5;
/// An inch in metres (exact).
pub const INCH: f64 = 0.0254;
/// Standard gravity in m/s² (exact).
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// The recognised units, by the names they are written with, and one of each in SI.
const UNITS: &[(&str, Quantity, f64)] = &[
    ("N", Quantity::Force, 1.0),
    ("kN", Quantity::Force, 1e3),
    ("mN", Quantity::Force, 1e-3),
    ("lbf", Quantity::Force, LBF),
    ("lb", Quantity::Force, LBF),
    ("m", Quantity::Displacement, 1.0),
    ("mm", Quantity::Displacement, 1e-3),
    ("um", Quantity::Displacement, 1e-6),
    ("µm", Quantity::Displacement, 1e-6),
    ("μm", Quantity::Displacement, 1e-6),
    ("nm", Quantity::Displacement, 1e-9),
    ("in", Quantity::Displacement, INCH),
    ("mil", Quantity::Displacement, 1e-3 * INCH),
    ("mils", Quantity::Displacement, 1e-3 * INCH),
    ("m/s", Quantity::Velocity, 1.0),
    ("mm/s", Quantity::Velocity, 1e-3),
    ("in/s", Quantity::Velocity, INCH),
    ("m/s^2", Quantity::Acceleration, 1.0),
    ("m/s2", Quantity::Acceleration, 1.0),
    ("m/s²", Quantity::Acceleration, 1.0),
    ("mm/s^2", Quantity::Acceleration, 1e-3),
    ("in/s^2", Quantity::Acceleration, INCH),
    ("g", Quantity::Acceleration, STANDARD_GRAVITY),
];

/// A recognised unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// Its name (`lbf`, `mil`).
    pub name: &'static str,
    /// What it measures.
    pub quantity: Quantity,
    /// One of it in SI.
    pub to_si: f64,
}

impl Unit {
    /// The unit written `name` (spaces around it ignored): `N`, `kN`, `mN`, `lbf`, `lb`; `m`,
    /// `mm`, `um`/`µm`, `nm`, `in`, `mil`/`mils`; `m/s`, `mm/s`, `in/s`; `m/s^2`, `mm/s^2`,
    /// `in/s^2`, `g`. `None` for any other.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::units::{Quantity, Unit};
    /// let mil = Unit::named(" mil ").unwrap();
    /// assert_eq!(mil.quantity, Quantity::Displacement);
    /// assert_eq!(mil.to_si, 2.54e-5);
    /// assert!(Unit::named("furlong").is_none());
    /// ```
    pub fn named(name: &str) -> Option<Unit> {
        let name = name.trim();
        UNITS
            .iter()
            .find(|(n, _, _)| *n == name)
            .map(|&(name, quantity, to_si)| Unit {
                name,
                quantity,
                to_si,
            })
    }

    /// Whether the unit can be that of a channel of `kind`: a force unit for a force, a
    /// displacement, velocity or acceleration unit for a response.
    pub fn fits(&self, force: bool) -> bool {
        (self.quantity == Quantity::Force) == force
    }
}

/// The unit of channel `i` of `count` among `given` (none, one for all, or one per channel).
///
/// # Examples
/// ```
/// let given = ["lbf".to_string()];
/// assert_eq!(bearing_ident::units::given(&given, 1, 2), Some("lbf"));
/// assert_eq!(bearing_ident::units::given(&[], 1, 2), None);
/// ```
pub fn given(given: &[String], i: usize, count: usize) -> Option<&str> {
    match given {
        [] => None,
        [one] => Some(one),
        many if many.len() == count => Some(&many[i]),
        _ => None,
    }
}
