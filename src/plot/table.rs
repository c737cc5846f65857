//! The coefficient table, written once for the report page and the command-line tool.

use faer::MatRef;

use super::significant;
use crate::model::Coefficients;

/// One element of `M`, `C` or `K` as a row of the coefficient table, its numbers formatted:
/// the cells that [`report`](super::report)'s page and the command-line tool's text table
/// both show, each laying them out its own way.
#[derive(Debug, Clone, PartialEq)]
pub struct CoefficientRow {
    /// Block, element and unit, e.g. `K_xy (N/m)`: `M` in kg, `C` in N·s/m, `K` in N/m.
    pub label: String,
    /// The value to 7 significant digits ([`significant`]).
    pub value: String,
    /// One standard deviation to 3 significant digits, or `—` without one.
    pub std_dev: String,
    /// `value − q … value + q` to 5 significant digits from the half-widths `q` of a 95 %
    /// interval, or `—` without them.
    pub interval: String,
    /// The true value to 7 significant digits, when the truth is known.
    pub truth: Option<String>,
    /// The relative error against the truth, `+0.125 %`, or `—` where the truth is zero;
    /// present exactly when [`CoefficientRow::truth`] is.
    pub error: Option<String>,
}

/// Picks one block (M, C or K) out of a coefficient set.
type Block = fn(&Coefficients) -> MatRef<'_, f64>;

/// The rows of the coefficient table: `M`, then `C`, then `K`, each element by element in row
/// order (`xx`, `xy`, `yx`, `yy`), labelled with the names `axes` of the degrees of freedom
/// (one per degree of freedom). `std_dev`, `interval` (half-widths of a 95 % interval, as
/// [`Identification::interval_95`](crate::Identification::interval_95)) and `truth` fill
/// their cells when given.
///
/// # Panics
/// If `axes` has fewer names than `values` has degrees of freedom, or `std_dev`, `interval`
/// or `truth` are smaller than `values`.
///
/// # Examples
/// ```
/// use bearing_ident::plot::coefficient_rows;
/// use bearing_ident::simulate::seed_rig;
/// let truth = seed_rig();
/// let axes = ["x".to_string(), "y".to_string()];
/// let rows = coefficient_rows(&truth, None, None, Some(&truth), &axes);
/// assert_eq!(rows.len(), 3 * 4);
/// assert_eq!(rows[8].label, "K_xx (N/m)");
/// assert_eq!(rows[8].value, "146300.0");
/// assert_eq!(rows[8].std_dev, "—");
/// assert_eq!(rows[8].error.as_deref(), Some("+0.000 %"));
/// assert_eq!(rows[1].error.as_deref(), Some("—")); // M xy is zero
/// ```
pub fn coefficient_rows(
    values: &Coefficients,
    std_dev: Option<&Coefficients>,
    interval: Option<&Coefficients>,
    truth: Option<&Coefficients>,
    axes: &[String],
) -> Vec<CoefficientRow> {
    let n = values.dofs();
    let blocks: [(&str, &str, Block); 3] = [
        ("M", "kg", Coefficients::mass),
        ("C", "N·s/m", Coefficients::damping),
        ("K", "N/m", Coefficients::stiffness),
    ];
    let mut rows = Vec::with_capacity(3 * n * n);
    for (name, unit, get) in blocks {
        let value = get(values);
        for (i, ai) in axes[..n].iter().enumerate() {
            for (j, aj) in axes[..n].iter().enumerate() {
                let v = value[(i, j)];
                let t = truth.map(|t| get(t)[(i, j)]);
                rows.push(CoefficientRow {
                    label: format!("{name}_{ai}{aj} ({unit})"),
                    value: significant(v, 7),
                    std_dev: std_dev.map_or("—".to_string(), |s| significant(get(s)[(i, j)], 3)),
                    interval: interval.map_or("—".to_string(), |s| {
                        let q = get(s)[(i, j)];
                        format!("{} … {}", significant(v - q, 5), significant(v + q, 5))
                    }),
                    truth: t.map(|t| significant(t, 7)),
                    error: t.map(|t| {
                        if t == 0.0 {
                            "—".to_string()
                        } else {
                            format!("{:+.3} %", 100.0 * (v / t - 1.0))
                        }
                    }),
                });
            }
        }
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::seed_rig;

    #[test]
    fn every_cell_is_filled_when_given() {
        let rig = seed_rig();
        let axes = ["1".to_string(), "2".to_string()];
        let rows = coefficient_rows(&rig, Some(&rig), Some(&rig), None, &axes);
        assert_eq!(rows[4].label, "C_11 (N·s/m)");
        assert_eq!(rows[4].value, "131.9800");
        assert_eq!(rows[4].std_dev, "132");
        assert_eq!(rows[4].interval, "0 … 263.96");
        assert!(rows.iter().all(|r| r.truth.is_none() && r.error.is_none()));
    }
}
