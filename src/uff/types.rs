//! The values of a dataset 58 block: [`Function`] and its enums.

use faer::c64;

/// What a function is (record 6, field 1).
///
/// # Examples
/// ```
/// use bearing_ident::uff::FunctionType;
/// assert_eq!(FunctionType::from_code(4), FunctionType::Frf);
/// assert_eq!(FunctionType::Frf.code(), 4);
/// assert_eq!(FunctionType::from_code(99).code(), 99);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum FunctionType {
    /// 0: general or unknown.
    General,
    /// 1: time response (a time history).
    TimeResponse,
    /// 2: auto-spectrum.
    AutoSpectrum,
    /// 3: cross-spectrum.
    CrossSpectrum,
    /// 4: frequency response function.
    Frf,
    /// 5: transmissibility.
    Transmissibility,
    /// 6: coherence.
    Coherence,
    /// 7: auto-correlation.
    AutoCorrelation,
    /// 8: cross-correlation.
    CrossCorrelation,
    /// 9: power spectral density.
    Psd,
    /// 10: energy spectral density.
    Esd,
    /// 11: probability density function.
    ProbabilityDensity,
    /// 12: spectrum.
    Spectrum,
    /// Any other code, kept as written.
    Other(i32),
}

impl FunctionType {
    /// The type of a record-6 code; codes without a name here are [`FunctionType::Other`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::FunctionType;
    /// assert_eq!(FunctionType::from_code(1), FunctionType::TimeResponse);
    /// ```
    pub fn from_code(code: i32) -> Self {
        match code {
            0 => Self::General,
            1 => Self::TimeResponse,
            2 => Self::AutoSpectrum,
            3 => Self::CrossSpectrum,
            4 => Self::Frf,
            5 => Self::Transmissibility,
            6 => Self::Coherence,
            7 => Self::AutoCorrelation,
            8 => Self::CrossCorrelation,
            9 => Self::Psd,
            10 => Self::Esd,
            11 => Self::ProbabilityDensity,
            12 => Self::Spectrum,
            other => Self::Other(other),
        }
    }

    /// The record-6 code.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::FunctionType;
    /// assert_eq!(FunctionType::Coherence.code(), 6);
    /// ```
    pub fn code(self) -> i32 {
        match self {
            Self::General => 0,
            Self::TimeResponse => 1,
            Self::AutoSpectrum => 2,
            Self::CrossSpectrum => 3,
            Self::Frf => 4,
            Self::Transmissibility => 5,
            Self::Coherence => 6,
            Self::AutoCorrelation => 7,
            Self::CrossCorrelation => 8,
            Self::Psd => 9,
            Self::Esd => 10,
            Self::ProbabilityDensity => 11,
            Self::Spectrum => 12,
            Self::Other(code) => code,
        }
    }
}

/// The physical quantity of an axis (records 8–11, field 1).
///
/// # Examples
/// ```
/// use bearing_ident::uff::DataType;
/// assert_eq!(DataType::from_code(13), DataType::ExcitationForce);
/// assert_eq!(DataType::Displacement.code(), 8);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum DataType {
    /// 0: unknown.
    Unknown,
    /// 1: general.
    General,
    /// 2: stress.
    Stress,
    /// 3: strain.
    Strain,
    /// 5: temperature.
    Temperature,
    /// 8: displacement (m).
    Displacement,
    /// 9: reaction force.
    ReactionForce,
    /// 11: velocity (m/s).
    Velocity,
    /// 12: acceleration (m/s²).
    Acceleration,
    /// 13: excitation force (N).
    ExcitationForce,
    /// 15: pressure.
    Pressure,
    /// 16: mass.
    Mass,
    /// 17: time (s).
    Time,
    /// 18: frequency (Hz).
    Frequency,
    /// 19: rpm.
    Rpm,
    /// 20: order.
    Order,
    /// 21: sound pressure.
    SoundPressure,
    /// Any other code, kept as written.
    Other(i32),
}

impl DataType {
    /// The data type of a code; codes without a name here are [`DataType::Other`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::DataType;
    /// assert_eq!(DataType::from_code(17), DataType::Time);
    /// ```
    pub fn from_code(code: i32) -> Self {
        match code {
            0 => Self::Unknown,
            1 => Self::General,
            2 => Self::Stress,
            3 => Self::Strain,
            5 => Self::Temperature,
            8 => Self::Displacement,
            9 => Self::ReactionForce,
            11 => Self::Velocity,
            12 => Self::Acceleration,
            13 => Self::ExcitationForce,
            15 => Self::Pressure,
            16 => Self::Mass,
            17 => Self::Time,
            18 => Self::Frequency,
            19 => Self::Rpm,
            20 => Self::Order,
            21 => Self::SoundPressure,
            other => Self::Other(other),
        }
    }

    /// The code written in records 8–11.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::DataType;
    /// assert_eq!(DataType::Frequency.code(), 18);
    /// ```
    pub fn code(self) -> i32 {
        match self {
            Self::Unknown => 0,
            Self::General => 1,
            Self::Stress => 2,
            Self::Strain => 3,
            Self::Temperature => 5,
            Self::Displacement => 8,
            Self::ReactionForce => 9,
            Self::Velocity => 11,
            Self::Acceleration => 12,
            Self::ExcitationForce => 13,
            Self::Pressure => 15,
            Self::Mass => 16,
            Self::Time => 17,
            Self::Frequency => 18,
            Self::Rpm => 19,
            Self::Order => 20,
            Self::SoundPressure => 21,
            Self::Other(code) => code,
        }
    }
}

/// Precision of the ordinate values in the file: `E13.5` or `f32` (single), `E20.12` or `f64`
/// (double).
///
/// # Examples
/// ```
/// use bearing_ident::uff::Precision;
/// assert_ne!(Precision::Single, Precision::Double);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Precision {
    /// Single precision (ordinate types 2 and 5).
    Single,
    /// Double precision (ordinate types 4 and 6).
    Double,
}

/// A point of the model where a function is measured or excited (record 6).
///
/// # Examples
/// ```
/// use bearing_ident::uff::Dof;
/// let d = Dof { entity: "NONE".into(), node: 22, direction: 1 };
/// assert_eq!(d.node, 22);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct Dof {
    /// Entity name (at most 10 characters in the file).
    pub entity: String,
    /// Node number.
    pub node: i64,
    /// Direction: 0 scalar, 1 +X, 2 +Y, 3 +Z, 4–6 rotations about X, Y, Z; negative for the
    /// negative directions.
    pub direction: i64,
}

/// One axis's description (records 8–11).
///
/// # Examples
/// ```
/// use bearing_ident::uff::{Axis, DataType};
/// let a = Axis::new(DataType::Time, "Time", "s");
/// assert_eq!(a.data_type.code(), 17);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Axis {
    /// The quantity.
    pub data_type: DataType,
    /// Length units exponent.
    pub length_exponent: i32,
    /// Force units exponent.
    pub force_exponent: i32,
    /// Temperature units exponent.
    pub temperature_exponent: i32,
    /// Axis label (at most 20 characters in the file).
    pub label: String,
    /// Units label (at most 20 characters in the file).
    pub units: String,
}

impl Axis {
    /// An axis of the given quantity, label and units, all unit exponents zero.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::{Axis, DataType};
    /// let a = Axis::new(DataType::ExcitationForce, "Force", "N");
    /// assert_eq!(a.force_exponent, 0);
    /// assert_eq!(a.units, "N");
    /// ```
    pub fn new(data_type: DataType, label: &str, units: &str) -> Self {
        Self {
            data_type,
            length_exponent: 0,
            force_exponent: 0,
            temperature_exponent: 0,
            label: label.to_owned(),
            units: units.to_owned(),
        }
    }

    /// The empty axis (`0 0 0 0 NONE NONE`), for an unused denominator or z axis.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::{Axis, DataType};
    /// assert_eq!(Axis::none().data_type, DataType::Unknown);
    /// ```
    pub fn none() -> Self {
        Self::new(DataType::Unknown, "NONE", "NONE")
    }
}

/// The abscissa (`x`) values of a function.
///
/// # Examples
/// ```
/// use bearing_ident::uff::Abscissa;
/// let a = Abscissa::Even { x0: 10.0, dx: 0.25, n: 3 };
/// assert_eq!(a.values(), vec![10.0, 10.25, 10.5]);
/// assert_eq!(a.len(), 3);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub enum Abscissa {
    /// Evenly spaced: `x_k = x0 + k·dx`, `k = 0 … n−1`.
    Even {
        /// First abscissa value.
        x0: f64,
        /// Increment.
        dx: f64,
        /// Number of points.
        n: usize,
    },
    /// Every value given.
    Uneven(Vec<f64>),
}

impl Abscissa {
    /// The number of points.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::Abscissa;
    /// assert_eq!(Abscissa::Uneven(vec![1.0, 2.0]).len(), 2);
    /// ```
    pub fn len(&self) -> usize {
        match self {
            Self::Even { n, .. } => *n,
            Self::Uneven(x) => x.len(),
        }
    }

    /// Whether there are no points.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::Abscissa;
    /// assert!(Abscissa::Uneven(vec![]).is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every abscissa value.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::Abscissa;
    /// assert_eq!(Abscissa::Even { x0: 0.0, dx: 0.5, n: 2 }.values()[1], 0.5);
    /// ```
    pub fn values(&self) -> Vec<f64> {
        match self {
            Self::Even { x0, dx, n } => (0..*n).map(|k| x0 + k as f64 * dx).collect(),
            Self::Uneven(x) => x.clone(),
        }
    }
}

/// The ordinate (`y`) values of a function.
///
/// # Examples
/// ```
/// use bearing_ident::uff::Ordinate;
/// use bearing_ident::faer::c64;
/// let o = Ordinate::Complex(vec![c64::new(1.0, -2.0)]);
/// assert_eq!(o.len(), 1);
/// assert!(o.is_complex());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub enum Ordinate {
    /// Real values.
    Real(Vec<f64>),
    /// Complex values.
    Complex(Vec<c64>),
}

impl Ordinate {
    /// The number of values.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::Ordinate;
    /// assert_eq!(Ordinate::Real(vec![1.0, 2.0]).len(), 2);
    /// ```
    pub fn len(&self) -> usize {
        match self {
            Self::Real(v) => v.len(),
            Self::Complex(v) => v.len(),
        }
    }

    /// Whether there are no values.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::Ordinate;
    /// assert!(Ordinate::Real(vec![]).is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the values are complex.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::Ordinate;
    /// assert!(!Ordinate::Real(vec![1.0]).is_complex());
    /// ```
    pub fn is_complex(&self) -> bool {
        matches!(self, Self::Complex(_))
    }
}

/// One dataset 58 block: a function (time history, FRF, coherence, spectrum, …) at a response
/// DOF per a reference DOF.
///
/// # Examples
/// ```
/// use bearing_ident::uff::{DataType, Function, FunctionType};
/// let f = Function::time_response(7, 2, 8, 0.0, 1e-3, vec![0.0; 16]);
/// assert_eq!(f.function_type, FunctionType::TimeResponse);
/// assert_eq!(f.numerator.data_type, DataType::Displacement);
/// assert_eq!(f.response.node, 7);
/// assert_eq!(f.ordinate_type(), 4);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Function {
    /// ID lines 1–5 (records 1–5), without trailing blanks.
    pub id: [String; 5],
    /// Function type (record 6).
    pub function_type: FunctionType,
    /// Function identification number (record 6).
    pub function_id: i64,
    /// Version or sequence number (record 6).
    pub version: i64,
    /// Load case identification number (record 6).
    pub load_case: i64,
    /// Response entity, node and direction (record 6).
    pub response: Dof,
    /// Reference entity, node and direction (record 6).
    pub reference: Dof,
    /// Precision of the ordinate values in the file (record 7).
    pub precision: Precision,
    /// Z-axis value (record 7).
    pub z_value: f64,
    /// Abscissa description (record 8).
    pub abscissa_axis: Axis,
    /// Ordinate numerator description (record 9).
    pub numerator: Axis,
    /// Ordinate denominator description (record 10).
    pub denominator: Axis,
    /// Z-axis description (record 11).
    pub z_axis: Axis,
    /// The abscissa values (record 7, or record 12 when uneven).
    pub abscissa: Abscissa,
    /// The ordinate values (record 12).
    pub ordinate: Ordinate,
}

impl Function {
    /// A real, double-precision, evenly sampled time history (function type 1) of the quantity
    /// with data-type code `data_type` (13 force in N, 8 displacement in m, …) at
    /// `node` in `direction` (1 +X, 2 +Y, …), starting at `t0` s every `dt` s; load case 0.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::{Abscissa, Function};
    /// let f = Function::time_response(1, 1, 13, 0.0, 0.5, vec![1.0, 2.0]);
    /// assert_eq!(f.abscissa, Abscissa::Even { x0: 0.0, dx: 0.5, n: 2 });
    /// assert_eq!(f.numerator.units, "N");
    /// ```
    pub fn time_response(
        node: i64,
        direction: i64,
        data_type: i32,
        t0: f64,
        dt: f64,
        values: Vec<f64>,
    ) -> Self {
        let data_type = DataType::from_code(data_type);
        let (label, units) = match data_type {
            DataType::ExcitationForce => ("Force", "N"),
            DataType::Displacement => ("Displacement", "m"),
            DataType::Velocity => ("Velocity", "m/s"),
            DataType::Acceleration => ("Acceleration", "m/s^2"),
            _ => ("NONE", "NONE"),
        };
        Self {
            id: [
                "Time Response".into(),
                "NONE".into(),
                "NONE".into(),
                "NONE".into(),
                "NONE".into(),
            ],
            function_type: FunctionType::TimeResponse,
            function_id: 0,
            version: 0,
            load_case: 0,
            response: Dof {
                entity: "NONE".into(),
                node,
                direction,
            },
            reference: Dof {
                entity: "NONE".into(),
                node: 0,
                direction: 0,
            },
            precision: Precision::Double,
            z_value: 0.0,
            abscissa_axis: Axis::new(DataType::Time, "Time", "s"),
            numerator: Axis::new(data_type, label, units),
            denominator: Axis::none(),
            z_axis: Axis::none(),
            abscissa: Abscissa::Even {
                x0: t0,
                dx: dt,
                n: values.len(),
            },
            ordinate: Ordinate::Real(values),
        }
    }

    /// The ordinate type code of record 7: 2 real single, 4 real double, 5 complex single,
    /// 6 complex double.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::{Function, Precision};
    /// let mut f = Function::time_response(1, 1, 13, 0.0, 0.5, vec![1.0]);
    /// f.precision = Precision::Single;
    /// assert_eq!(f.ordinate_type(), 2);
    /// ```
    pub fn ordinate_type(&self) -> i32 {
        match (self.ordinate.is_complex(), self.precision) {
            (false, Precision::Single) => 2,
            (false, Precision::Double) => 4,
            (true, Precision::Single) => 5,
            (true, Precision::Double) => 6,
        }
    }
}
