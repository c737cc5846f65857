//! Edge: reading back the JSON of a saved identification (feature `json`).
//!
//! The command-line tool writes an [`Identification`](crate::Identification) as one flat JSON
//! object (`identify --json`, see its `Serialize` impl); [`Baseline::from_json`] reads the
//! parts a baseline subtraction needs back from it. Every problem is an
//! [`Error::BadBaseline`] that names the key and quotes at most
//! [`QUOTE_CHARS`](crate::error::QUOTE_CHARS) characters of the input.

use faer::Mat;
use serde_json::Value;

use crate::error::{Error, Result, excerpt};
use crate::frf::{Band, Estimator};
use crate::identify::Baseline;
use crate::model::Coefficients;
use crate::spectra::Window;

/// An [`Error::BadBaseline`] saying `message`, cut by [`excerpt`].
fn bad(message: impl AsRef<str>) -> Error {
    Error::BadBaseline {
        message: excerpt(message.as_ref()),
    }
}

impl Baseline {
    /// A baseline from the JSON of an identification saved earlier (`bearing-ident identify
    /// --json`): the keys `M`, `C`, `K` (square matrices as lists of rows, required),
    /// `M_std`, `C_std`, `K_std` (used when all three are present and not null), `band_hz`
    /// (`[LO, HI]`), `freqs_hz`, `estimator` (`paired`, `h1`, `h2`, `hv`) and `window`
    /// (`rect`, `hann`, or `exp` with `window_decay_per_s`). Other keys are ignored.
    ///
    /// # Errors
    /// [`Error::BadBaseline`] for text that is not JSON, a missing or mistyped key, a matrix
    /// that is not square or of another size than `M`, a NaN, infinite or (for the standard
    /// deviations) negative entry, an invalid band, non-finite lines, an unknown estimator or
    /// window, or a negative or non-finite window decay.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Baseline;
    /// let text = r#"{"M": [[2.0]], "C": [[30.0]], "K": [[4e4]], "band_hz": [5, 40],
    ///   "freqs_hz": [5, 10, 20, 40], "estimator": "paired", "window": "rect"}"#;
    /// let dry = Baseline::from_json(text)?;
    /// assert_eq!(dry.coefficients().stiffness()[(0, 0)], 4e4);
    /// let e = Baseline::from_json(r#"{"M": [[1, 2]]}"#).unwrap_err();
    /// assert_eq!(e.kind(), "bad_baseline");
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn from_json(text: &str) -> Result<Baseline> {
        // A UTF-8 byte order mark, as some editors write, is skipped as the CSV reader skips it.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let v: Value = serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
        if !v.is_object() {
            return Err(bad(
                "expected a JSON object (the output of `identify --json`)",
            ));
        }
        let matrix = |key: &str| -> Result<Option<Mat<f64>>> {
            let Some(rows) = v.get(key).filter(|r| !r.is_null()) else {
                return Ok(None);
            };
            let rows: Vec<Vec<f64>> =
                serde_json::from_value(rows.clone()).map_err(|e| bad(format!("`{key}`: {e}")))?;
            let n = rows.len();
            if n == 0 || rows.iter().any(|r| r.len() != n) {
                return Err(bad(format!(
                    "`{key}`: expected a square matrix (list of rows)"
                )));
            }
            Ok(Some(Mat::from_fn(n, n, |i, j| rows[i][j])))
        };
        let need = |key: &str| {
            let m = matrix(key)?.ok_or_else(|| bad(format!("no `{key}`")))?;
            // Finite is not enough: 1e308 overflows the first square or product it meets.
            let limit = crate::tolerance::COEFFICIENT_MAGNITUDE;
            for i in 0..m.nrows() {
                for j in 0..m.ncols() {
                    let within = m[(i, j)].abs() <= limit;
                    if !within {
                        return Err(bad(format!(
                            "`{key}`[{i}][{j}] = {:e} is past the largest coefficient \
                             magnitude accepted, {limit:e}",
                            m[(i, j)]
                        )));
                    }
                }
            }
            Ok(m)
        };
        let coefficients = Coefficients::new(need("M")?, need("C")?, need("K")?)
            .map_err(|e| bad(e.to_string()))?;
        let std = match (matrix("M_std")?, matrix("C_std")?, matrix("K_std")?) {
            (Some(m), Some(c), Some(k)) => {
                let std = Coefficients::new(m, c, k).map_err(|e| bad(e.to_string()))?;
                if std.dofs() != coefficients.dofs() {
                    return Err(bad(format!(
                        "`M_std`: {} degrees of freedom, `M` has {}",
                        std.dofs(),
                        coefficients.dofs()
                    )));
                }
                let negative = [std.mass(), std.damping(), std.stiffness()]
                    .iter()
                    .any(|m| (0..m.nrows()).any(|i| (0..m.ncols()).any(|j| m[(i, j)] < 0.0)));
                if negative {
                    return Err(bad("a standard deviation is negative"));
                }
                Some(std)
            }
            _ => None,
        };
        let band: Vec<f64> = v
            .get("band_hz")
            .and_then(|b| serde_json::from_value(b.clone()).ok())
            .filter(|b: &Vec<f64>| b.len() == 2)
            .ok_or_else(|| bad("no `band_hz` [LO, HI]"))?;
        let band = Band::new(band[0], band[1]).map_err(|e| bad(e.to_string()))?;
        let freqs: Vec<f64> = v
            .get("freqs_hz")
            .and_then(|b| serde_json::from_value(b.clone()).ok())
            .ok_or_else(|| bad("no `freqs_hz`"))?;
        if let Some(f) = freqs.iter().find(|f| !(f.is_finite() && **f >= 0.0)) {
            return Err(bad(format!("`freqs_hz`: {f} is not a frequency")));
        }
        let estimator = v
            .get("estimator")
            .and_then(Value::as_str)
            .ok_or_else(|| bad("no `estimator`"))?
            .parse::<Estimator>()
            .map_err(|e| bad(e.to_string()))?;
        let window = match v.get("window").and_then(Value::as_str) {
            // Before the window had a string form, an exponential window was `exp` and its
            // decay `window_decay_per_s`.
            Some("exp") => {
                let decay_per_s = v
                    .get("window_decay_per_s")
                    .and_then(Value::as_f64)
                    .ok_or_else(|| bad("no `window_decay_per_s` for the exponential window"))?;
                Window::exponential(decay_per_s).map_err(|_| {
                    bad(format!(
                        "`window_decay_per_s` {decay_per_s} is not a finite decay ≥ 0"
                    ))
                })?
            }
            Some(text) => text.parse::<Window>().map_err(|e| bad(e.to_string()))?,
            None => return Err(bad("no `window`")),
        };
        Ok(Baseline::new(
            coefficients,
            std,
            band,
            freqs,
            estimator,
            window,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"{"M": [[2.0]], "C": [[30.0]], "K": [[4e4]],
        "M_std": [[0.1]], "C_std": [[1.0]], "K_std": [[100.0]], "band_hz": [5, 40],
        "freqs_hz": [5, 10], "estimator": "h1", "window": "exp", "window_decay_per_s": 2.5}"#;

    #[test]
    fn reads_what_identify_json_writes() {
        let b = Baseline::from_json(GOOD).unwrap();
        assert!((b.coefficients().mass()[(0, 0)] - 2.0).abs() < 1e-15);
    }

    /// A UTF-8 byte order mark (as some editors write) is skipped, as the CSV reader skips it.
    #[test]
    fn a_byte_order_mark_is_skipped() {
        let b = Baseline::from_json(&format!("\u{feff}{GOOD}")).unwrap();
        assert!((b.coefficients().stiffness()[(0, 0)] - 4e4).abs() < 1e-9);
    }

    #[test]
    fn every_fault_is_bad_baseline() {
        let cases = [
            "not json".to_owned(),
            "[1, 2]".to_owned(),
            GOOD.replace(r#""M": [[2.0]], "#, ""),
            GOOD.replace(r#"[[0.1]]"#, "[[0.1, 0], [0, 0.1]]"),
            GOOD.replace(
                r#"[[0.1]], "C_std": [[1.0]], "K_std": [[100.0]]"#,
                "[[1, 0], [0, 1]], \"C_std\": [[1, 0], [0, 1]], \"K_std\": [[1, 0], [0, 1]]",
            ),
            GOOD.replace(r#"[[1.0]]"#, "[[-1.0]]"),
            GOOD.replace("[5, 40]", "[40, 5]"),
            GOOD.replace("[5, 10]", "[5, -10]"),
            GOOD.replace(r#""h1""#, r#""h9""#),
            GOOD.replace("2.5", "-2.5"),
            GOOD.replace(r#""exp""#, r#""kaiser""#),
            GOOD.replace("[[4e4]]", "[[1e308]]"),
            GOOD.replace("[[4e4]]", "[[-1e308]]"),
            GOOD.replace("[[2.0]]", "[[1e200]]"),
        ];
        for text in &cases {
            let e = Baseline::from_json(text).unwrap_err();
            assert!(matches!(e, Error::BadBaseline { .. }), "{text}: {e:?}");
            assert_eq!(e.kind(), "bad_baseline");
        }
    }

    #[test]
    fn long_input_is_not_echoed() {
        let long = "x".repeat(10_000);
        let text = GOOD.replace(r#""h1""#, &format!("\"{long}\""));
        let e = Baseline::from_json(&text).unwrap_err();
        assert!(e.to_string().chars().count() < 200, "{e}");
        let text = GOOD.replace("[[2.0]]", &format!("[[\"{long}\"]]"));
        let e = Baseline::from_json(&text).unwrap_err();
        assert!(e.to_string().chars().count() < 200, "{e}");
    }
}
