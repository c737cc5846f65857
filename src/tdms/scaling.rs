//! NI's scaling properties of a channel: `NI_Scale[n]_Scale_Type` `Linear`
//! (`y = slope·x + intercept`) or `Polynomial` (`y = Σ cᵢ xⁱ`), the last scale applied to the
//! output of the scale its `Input_Source` names (a lower index) or to the raw values.

use super::{Property, Value, property};

/// Scales `values` in place by the scaling properties of a channel; `Err` says why they
/// cannot be (a scale type other than linear or polynomial, a property missing).
pub(super) fn scale(properties: &[Property], values: &mut [f64]) -> Result<(), String> {
    if let Some(Value::Text(status)) = property(properties, "NI_Scaling_Status")
        && status.eq_ignore_ascii_case("scaled")
    {
        return Ok(());
    }
    let last = match property(properties, "NI_Number_Of_Scales").and_then(Value::as_f64) {
        Some(n) if n >= 1.0 => Some(n as u64 - 1),
        _ => properties.iter().filter_map(|p| scale_index(&p.name)).max(),
    };
    let Some(last) = last else {
        return Ok(());
    };
    if property(properties, &format!("NI_Scale[{last}]_Scale_Type")).is_none() {
        return Ok(());
    }
    let chain = chain(properties, last)?;
    for v in values.iter_mut() {
        *v = chain.iter().fold(*v, |x, s| s.apply(x));
    }
    Ok(())
}

/// The index `n` of a property `NI_Scale[n]_Scale_Type`.
fn scale_index(name: &str) -> Option<u64> {
    name.strip_prefix("NI_Scale[")?
        .strip_suffix("]_Scale_Type")?
        .parse()
        .ok()
}

/// One scale.
enum Scale {
    Linear { slope: f64, intercept: f64 },
    Polynomial(Vec<f64>),
}

impl Scale {
    fn apply(&self, x: f64) -> f64 {
        match self {
            Scale::Linear { slope, intercept } => slope * x + intercept,
            Scale::Polynomial(c) => c.iter().rev().fold(0.0, |acc, &ci| acc * x + ci),
        }
    }
}

/// Most polynomial coefficients read.
const MAX_COEFFICIENTS: u64 = 64;

/// The scales from the raw values to scale `last`, first applied first.
fn chain(properties: &[Property], last: u64) -> Result<Vec<Scale>, String> {
    let number = |name: String| {
        property(properties, &name)
            .and_then(Value::as_f64)
            .ok_or_else(|| format!("its scaling property {name} is missing or not a number"))
    };
    let mut scales = Vec::new();
    let mut n = last;
    loop {
        let kind = match property(properties, &format!("NI_Scale[{n}]_Scale_Type")) {
            Some(Value::Text(t)) => t.clone(),
            _ => return Err(format!("its scale {n} has no NI_Scale[{n}]_Scale_Type")),
        };
        let (scale, source) = match kind.as_str() {
            "Linear" => (
                Scale::Linear {
                    slope: number(format!("NI_Scale[{n}]_Linear_Slope"))?,
                    intercept: number(format!("NI_Scale[{n}]_Linear_Y_Intercept")).unwrap_or(0.0),
                },
                format!("NI_Scale[{n}]_Linear_Input_Source"),
            ),
            "Polynomial" => {
                let size = number(format!("NI_Scale[{n}]_Polynomial_Coefficients_Size"))?;
                if !(0.0..=MAX_COEFFICIENTS as f64).contains(&size) {
                    return Err(format!(
                        "its polynomial scale {n} declares {size} coefficients"
                    ));
                }
                let c = (0..size as u64)
                    .map(|i| number(format!("NI_Scale[{n}]_Polynomial_Coefficients[{i}]")))
                    .collect::<Result<Vec<f64>, String>>()?;
                (
                    Scale::Polynomial(c),
                    format!("NI_Scale[{n}]_Polynomial_Input_Source"),
                )
            }
            other => {
                return Err(format!(
                    "its scale {n} is `{}`: only Linear and Polynomial scales are read",
                    crate::error::excerpt(other)
                ));
            }
        };
        scales.push(scale);
        // A source below this scale is another scale; anything else is the raw values.
        match property(properties, &source).and_then(Value::as_f64) {
            Some(s) if s >= 0.0 && (s as u64) < n => n = s as u64,
            _ => break,
        }
    }
    scales.reverse();
    Ok(scales)
}
