//! What a plan names: the conditions and their units, a condition's value at a point, a
//! coefficient and an independent reference for it, an `identify` setting, and a point.

/// A unit of a test condition, as the plan states it.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Unit {
    /// Revolutions per minute (a speed).
    Rpm,
    /// Radians per second (a speed).
    RadPerS,
    /// Hertz (a speed, revolutions per second).
    Hz,
    /// Newtons (a load).
    Newton,
    /// Kilonewtons (a load).
    Kilonewton,
    /// Pounds-force (a load).
    PoundForce,
    /// Anything else, as written (`"1"`, `"°C"`, `"bar"`).
    Other(String),
}

impl Unit {
    /// The unit of `text`: `rpm`, `rad/s`, `Hz`, `N`, `kN`, `lbf` (any case), else
    /// [`Unit::Other`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::campaign::Unit;
    /// assert_eq!(Unit::parse("RPM"), Unit::Rpm);
    /// assert_eq!(Unit::parse("1").name(), "1");
    /// assert!((Unit::Rpm.to_rad_per_s(60.0).unwrap() - 2.0 * std::f64::consts::PI).abs() < 1e-15);
    /// ```
    pub fn parse(text: &str) -> Self {
        match text.trim().to_ascii_lowercase().as_str() {
            "rpm" => Unit::Rpm,
            "rad/s" => Unit::RadPerS,
            "hz" => Unit::Hz,
            "n" => Unit::Newton,
            "kn" => Unit::Kilonewton,
            "lbf" => Unit::PoundForce,
            _ => Unit::Other(text.to_owned()),
        }
    }

    /// The unit as written in outputs.
    pub fn name(&self) -> &str {
        match self {
            Unit::Rpm => "rpm",
            Unit::RadPerS => "rad/s",
            Unit::Hz => "Hz",
            Unit::Newton => "N",
            Unit::Kilonewton => "kN",
            Unit::PoundForce => "lbf",
            Unit::Other(s) => s,
        }
    }

    /// A speed `value` in this unit as rad/s; `None` unless the unit is a speed.
    pub fn to_rad_per_s(&self, value: f64) -> Option<f64> {
        let two_pi = 2.0 * std::f64::consts::PI;
        match self {
            Unit::Rpm => Some(value * two_pi / 60.0),
            Unit::RadPerS => Some(value),
            Unit::Hz => Some(value * two_pi),
            _ => None,
        }
    }
}

/// A test variable of the campaign (`[conditions]`): its name and unit.
#[derive(Debug, Clone, PartialEq)]
pub struct Condition {
    /// The name, as the points use it (`speed`, `air_fraction`).
    pub name: String,
    /// The unit.
    pub unit: Unit,
}

/// The value of a condition at a point: a number, or text (a lubricant's name).
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A number in the condition's unit.
    Number(f64),
    /// Text.
    Text(String),
}

impl Value {
    /// The number, if it is one.
    pub fn number(&self) -> Option<f64> {
        match self {
            Value::Number(x) => Some(*x),
            Value::Text(_) => None,
        }
    }
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Number(x) => write!(f, "{x}"),
            Value::Text(s) => f.write_str(s),
        }
    }
}

/// One coefficient of an `n × n` block: `M_xx`, `C_xy`, `K_yy` for up to three degrees of
/// freedom (`x`, `y`, `z`), or `K_12` (rows and columns from 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Coefficient {
    /// `'M'`, `'C'` or `'K'`.
    pub block: char,
    /// Row (force), from 0.
    pub row: usize,
    /// Column (displacement), from 0.
    pub col: usize,
}

impl Coefficient {
    /// The coefficient named `text` (`K_xy`, `m_yy`, `C_12`).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::campaign::Coefficient;
    /// let k = Coefficient::parse("K_xy").unwrap();
    /// assert_eq!((k.block, k.row, k.col), ('K', 0, 1));
    /// assert_eq!(Coefficient::parse("C_21").unwrap().row, 1);
    /// assert_eq!(k.name(), "K_xy");
    /// assert!(Coefficient::parse("Q_xx").is_none());
    /// ```
    pub fn parse(text: &str) -> Option<Self> {
        let (block, axes) = text.split_once('_')?;
        let block = match block {
            "M" | "m" => 'M',
            "C" | "c" => 'C',
            "K" | "k" => 'K',
            _ => return None,
        };
        let index = |c: char| match c {
            'x' => Some(0),
            'y' => Some(1),
            'z' => Some(2),
            '1'..='9' => Some(c as usize - '1' as usize),
            _ => None,
        };
        let mut chars = axes.chars();
        let (r, c) = (chars.next()?, chars.next()?);
        if chars.next().is_some() {
            return None;
        }
        Some(Self {
            block,
            row: index(r)?,
            col: index(c)?,
        })
    }

    /// The name, `K_xy` style for up to three degrees of freedom, else `K_12`.
    pub fn name(&self) -> String {
        let axis = |i: usize| match i {
            0 => 'x',
            1 => 'y',
            2 => 'z',
            _ => '?',
        };
        if self.row < 3 && self.col < 3 {
            format!("{}_{}{}", self.block, axis(self.row), axis(self.col))
        } else {
            format!("{}_{}{}", self.block, self.row + 1, self.col + 1)
        }
    }
}

/// An independent reference for a coefficient (`[point.expect]`): a value and its standard
/// uncertainty.
#[derive(Debug, Clone, PartialEq)]
pub struct Expectation {
    /// The coefficient.
    pub coefficient: Coefficient,
    /// The reference value (SI).
    pub reference: f64,
    /// Its standard uncertainty (SI, ≥ 0).
    pub std: f64,
}

/// An option of `identify` as the plan gives it: its long name, its text as the command line
/// takes it, and the plan's line.
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// The long name (`band`, `method`, `force`).
    pub name: String,
    /// The value as the command line takes it (`8,49`, `ivf`).
    pub text: String,
    /// The plan's line (from 1).
    pub line: usize,
}

/// One test point (`[[point]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Its name, unique in the plan.
    pub name: String,
    /// Its line in the plan.
    pub line: usize,
    /// File patterns (globs), relative to the plan's folder unless absolute.
    pub files: Vec<String>,
    /// The value of each condition of the plan, in the plan's order (`None`: not given).
    pub values: Vec<Option<Value>>,
    /// The point whose coefficients are subtracted (an index into the plan's points).
    pub baseline: Option<usize>,
    /// Independent references.
    pub expect: Vec<Expectation>,
    /// Options that override the shared ones for this point.
    pub overrides: Vec<Setting>,
}

/// The axis letters of an `n`-DOF system in tables and figures: `x`, `y`, `z` up to three
/// degrees of freedom, else `1`, `2`, ….
pub(crate) fn axis_names(n: usize) -> Vec<String> {
    if n <= 3 {
        ["x", "y", "z"][..n]
            .iter()
            .map(|s| (*s).to_owned())
            .collect()
    } else {
        (1..=n).map(|i| i.to_string()).collect()
    }
}
