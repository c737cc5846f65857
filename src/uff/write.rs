//! Writing dataset 58 (ASCII) and 58b (binary) blocks.

use std::io::Write;

use super::fortran::e_field;
use super::types::{Abscissa, Axis, Function, Ordinate, Precision};
use crate::error::{Error, Result};

/// Byte order of the values of a 58b block.
///
/// # Examples
/// ```
/// use bearing_ident::uff::ByteOrder;
/// assert_eq!(ByteOrder::Little.code(), 1);
/// assert_eq!(ByteOrder::Big.code(), 2);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ByteOrder {
    /// Little-endian (code 1; x86, ARM).
    Little,
    /// Big-endian (code 2).
    Big,
}

impl ByteOrder {
    /// The code written in the 58b dataset line.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::uff::ByteOrder;
    /// assert_eq!(ByteOrder::Big.code(), 2);
    /// ```
    pub fn code(self) -> i32 {
        match self {
            Self::Little => 1,
            Self::Big => 2,
        }
    }
}

/// Writes `functions` as ASCII dataset 58 blocks, in the Fortran formats of the
/// [module docs](super) (`E13.5` single, `E20.12` double; `x0`, `dx` and an uneven abscissa
/// `E13.5`). Text fields are cut to their widths (ID lines 80, entities 10, labels 20
/// characters) and characters outside ASCII become `?`, so that the columns hold.
///
/// # Errors
/// [`Error::InvalidParameter`] for a function whose abscissa and ordinate lengths differ, a
/// value that is not finite, or an integer too wide for its field; [`Error::Io`] if the writer
/// fails.
///
/// # Examples
/// ```
/// use bearing_ident::uff::{self, Function, Ordinate};
/// let f = Function::time_response(2, 1, 8, 0.0, 1e-3, vec![1e-6, -2e-6]);
/// let mut out = Vec::new();
/// uff::write(&mut out, &[f])?;
/// let text = String::from_utf8(out).unwrap();
/// assert!(text.contains("  1.000000000000E-06 -2.000000000000E-06"));
/// assert_eq!(uff::parse(text.as_bytes(), "mem")?[0].ordinate, Ordinate::Real(vec![1e-6, -2e-6]));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn write(w: &mut impl Write, functions: &[Function]) -> Result<()> {
    for f in functions {
        let header = header(f, "    58".into())?;
        let mut text = header;
        ascii_values(f, &mut text)?;
        text.push_str("    -1\n");
        w.write_all(text.as_bytes()).map_err(io)?;
    }
    w.flush().map_err(io)
}

/// Writes `functions` as binary dataset 58b blocks in the given byte order: the ASCII header,
/// then the values as `f32` (single) or `f64` (double), an uneven abscissa as `f32`. Double
/// values round-trip exactly.
///
/// # Errors
/// As [`write()`].
///
/// # Examples
/// ```
/// use bearing_ident::uff::{self, ByteOrder, Function, Ordinate};
/// let f = Function::time_response(2, 1, 8, 0.0, 1e-3, vec![0.1, 1.0 / 3.0]);
/// let mut out = Vec::new();
/// uff::write_binary(&mut out, &[f], ByteOrder::Big)?;
/// let back = uff::parse(&out, "mem")?;
/// assert_eq!(back[0].ordinate, Ordinate::Real(vec![0.1, 1.0 / 3.0]));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn write_binary(w: &mut impl Write, functions: &[Function], order: ByteOrder) -> Result<()> {
    for f in functions {
        check(f)?;
        let mut bytes = Vec::new();
        let mut put32 = |bytes: &mut Vec<u8>, v: f64| {
            let v = v as f32;
            bytes.extend_from_slice(&match order {
                ByteOrder::Little => v.to_le_bytes(),
                ByteOrder::Big => v.to_be_bytes(),
            });
        };
        let put = |bytes: &mut Vec<u8>, v: f64, put32: &mut dyn FnMut(&mut Vec<u8>, f64)| match f
            .precision
        {
            Precision::Single => put32(bytes, v),
            Precision::Double => bytes.extend_from_slice(&match order {
                ByteOrder::Little => v.to_le_bytes(),
                ByteOrder::Big => v.to_be_bytes(),
            }),
        };
        let xs = match &f.abscissa {
            Abscissa::Uneven(x) => Some(x),
            Abscissa::Even { .. } => None,
        };
        for k in 0..f.ordinate.len() {
            if let Some(x) = xs {
                put32(&mut bytes, x[k]);
            }
            match &f.ordinate {
                Ordinate::Real(y) => put(&mut bytes, y[k], &mut put32),
                Ordinate::Complex(y) => {
                    put(&mut bytes, y[k].re, &mut put32);
                    put(&mut bytes, y[k].im, &mut put32);
                }
            }
        }
        let dataset = format!(
            "{:>6}b{:>6}{:>6}{:>12}{:>12}{:>6}{:>6}{:>12}{:>12}",
            58,
            order.code(),
            2,
            11,
            bytes.len(),
            0,
            0,
            0,
            0
        );
        let head = header(f, dataset)?;
        w.write_all(head.as_bytes()).map_err(io)?;
        w.write_all(&bytes).map_err(io)?;
        w.write_all(b"\n    -1\n").map_err(io)?;
    }
    w.flush().map_err(io)
}

fn io(e: std::io::Error) -> Error {
    Error::Io {
        path: "UFF output".into(),
        message: e.to_string(),
    }
}

fn invalid(name: crate::Parameter, value: f64, expected: &'static str) -> Error {
    Error::InvalidParameter {
        name,
        value,
        expected,
    }
}

/// Checks the lengths and finiteness of a function's values.
fn check(f: &Function) -> Result<()> {
    if f.abscissa.len() != f.ordinate.len() {
        return Err(invalid(
            crate::Parameter::AbscissaLength,
            f.abscissa.len() as f64,
            "the number of ordinate values",
        ));
    }
    let finite = match &f.ordinate {
        Ordinate::Real(y) => y.iter().all(|v| v.is_finite()),
        Ordinate::Complex(y) => y.iter().all(|v| v.re.is_finite() && v.im.is_finite()),
    } && match &f.abscissa {
        Abscissa::Even { x0, dx, .. } => x0.is_finite() && dx.is_finite(),
        Abscissa::Uneven(x) => x.iter().all(|v| v.is_finite()),
    } && f.z_value.is_finite();
    if !finite {
        return Err(invalid(
            crate::Parameter::UffValue,
            f64::NAN,
            "finite abscissa, ordinate and z values",
        ));
    }
    Ok(())
}

/// `s` cut to `width` characters, non-ASCII as `?`, padded to `width` when `pad`.
fn fixed(s: &str, width: usize) -> String {
    let s: String = s
        .chars()
        .map(|c| {
            if c.is_ascii() && !c.is_ascii_control() {
                c
            } else {
                '?'
            }
        })
        .take(width)
        .collect();
    format!("{s:<width$}")
}

/// An integer right-aligned in `width` characters.
fn int(v: i64, width: usize, name: crate::Parameter) -> Result<String> {
    let s = format!("{v:>width$}");
    if s.len() > width {
        return Err(invalid(name, v as f64, "an integer that fits its field"));
    }
    Ok(s)
}

/// The `-1` line, the dataset line and records 1–11, each ending in `\n`.
fn header(f: &Function, dataset: String) -> Result<String> {
    check(f)?;
    let mut s = String::with_capacity(1024);
    s.push_str("    -1\n");
    s.push_str(&dataset);
    s.push('\n');
    for line in &f.id {
        s.push_str(fixed(line, 80).trim_end());
        s.push('\n');
    }
    s.push_str(&format!(
        "{}{}{}{} {}{}{} {}{}{}\n",
        int(
            i64::from(f.function_type.code()),
            5,
            crate::Parameter::FunctionType
        )?,
        int(f.function_id, 10, crate::Parameter::FunctionId)?,
        int(f.version, 5, crate::Parameter::VersionNumber)?,
        int(f.load_case, 10, crate::Parameter::LoadCase)?,
        fixed(&f.response.entity, 10),
        int(f.response.node, 10, crate::Parameter::ResponseNode)?,
        int(f.response.direction, 4, crate::Parameter::ResponseDirection)?,
        fixed(&f.reference.entity, 10),
        int(f.reference.node, 10, crate::Parameter::ReferenceNode)?,
        int(
            f.reference.direction,
            4,
            crate::Parameter::ReferenceDirection
        )?,
    ));
    let (even, x0, dx) = match &f.abscissa {
        Abscissa::Even { x0, dx, .. } => (1, *x0, *dx),
        Abscissa::Uneven(x) => (0, x.first().copied().unwrap_or(0.0), 0.0),
    };
    s.push_str(&format!(
        "{}{}{:>10}{}{}{}\n",
        int(
            i64::from(f.ordinate_type()),
            10,
            crate::Parameter::OrdinateType
        )?,
        int(
            f.ordinate.len() as i64,
            10,
            crate::Parameter::NumberOfPoints
        )?,
        even,
        e_field(x0, 5, 13),
        e_field(dx, 5, 13),
        e_field(f.z_value, 5, 13),
    ));
    for axis in [&f.abscissa_axis, &f.numerator, &f.denominator, &f.z_axis] {
        s.push_str(&axis_line(axis)?);
    }
    Ok(s)
}

fn axis_line(a: &Axis) -> Result<String> {
    Ok(format!(
        "{}{}{}{} {} {}\n",
        int(
            i64::from(a.data_type.code()),
            10,
            crate::Parameter::DataType
        )?,
        int(
            i64::from(a.length_exponent),
            5,
            crate::Parameter::LengthExponent
        )?,
        int(
            i64::from(a.force_exponent),
            5,
            crate::Parameter::ForceExponent
        )?,
        int(
            i64::from(a.temperature_exponent),
            5,
            crate::Parameter::TemperatureExponent
        )?,
        fixed(&a.label, 20),
        fixed(&a.units, 20),
    ))
}

/// Record 12 in ASCII: the fields of one point, then lines of as many points as the format
/// holds.
fn ascii_values(f: &Function, s: &mut String) -> Result<()> {
    let (d, w) = match f.precision {
        Precision::Single => (5, 13),
        Precision::Double => (12, 20),
    };
    let xs = match &f.abscissa {
        Abscissa::Uneven(x) => Some(x),
        Abscissa::Even { .. } => None,
    };
    // Fields per line: 6 single; 4 double even; 2 points (real) or 1 point (complex) uneven.
    let fields_per_line = match (f.precision, xs.is_some(), f.ordinate.is_complex()) {
        (Precision::Single, _, _) => 6,
        (Precision::Double, false, _) => 4,
        (Precision::Double, true, false) => 4,
        (Precision::Double, true, true) => 3,
    };
    let mut on_line = 0;
    let mut field = |s: &mut String, text: String| {
        s.push_str(&text);
        on_line += 1;
        if on_line == fields_per_line {
            s.push('\n');
            on_line = 0;
        }
    };
    for k in 0..f.ordinate.len() {
        if let Some(x) = xs {
            field(s, e_field(x[k], 5, 13));
        }
        match &f.ordinate {
            Ordinate::Real(y) => field(s, e_field(y[k], d, w)),
            Ordinate::Complex(y) => {
                field(s, e_field(y[k].re, d, w));
                field(s, e_field(y[k].im, d, w));
            }
        }
    }
    if on_line != 0 {
        s.push('\n');
    }
    Ok(())
}
