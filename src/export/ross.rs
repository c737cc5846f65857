//! A 2-DOF identification as a ROSS bearing element (feature `ross`).
//!
//! [ROSS](https://github.com/petrobras/ross) (rotordynamics in Python) loads a bearing from a
//! TOML or JSON file with `ross.BearingElement.load("brg.toml")`. The file holds one table,
//! `BearingElement_<tag>`, whose keys are the constructor's arguments:
//!
//! ```toml
//! [BearingElement_brg1]
//! n = 0
//! tag = "brg1"
//! frequency = [52.35987755982988, 92.36..., ...]     # rad/s, strictly increasing, ≥ 5 points
//! kxx = [146300.0, ...]                              # N/m
//! kxy = [...]
//! kyx = [...]
//! kyy = [...]
//! cxx = [...]                                        # N·s/m
//! # cxy, cyx, cyy, then mxx, mxy, myx, myy (kg)
//! ```
//!
//! `frequency` is ROSS 3.x's *excitation (whirl) frequency* axis: each coefficient is a table
//! over it, interpolated (PCHIP) between the points and extrapolated linearly from the end
//! slopes; ROSS warns below 5 points. Every one of the twelve terms is written, SI units
//! throughout. ROSS's matrices are `K = [[kxx, kxy], [kyx, kyy]]` with the force in `x` per the
//! displacement in `y` in `kxy`, as this crate's `(row, column)` = `(force, displacement)`.
//! Keys ROSS has defaults for (`n_link`: to ground, `scale_factor`, `color`, `kzz`, `czz`,
//! `mzz`: 0) are left out.
//!
//! Two tables ([`Table`]):
//! - [`Table::Constant`]: the fitted `M`, `C`, `K`, the same at 5 points evenly spread over the
//!   band asked for ([`Identification::band`]); or, when a frequency-dependent element model
//!   was fitted ([`Identification::model`]), that model's `K(ω)`, `C(ω)` at 21 points;
//! - [`Table::PerFrequency`]: `K(ω)`, `C(ω)` of [`Identification::per_frequency`] at every
//!   line used, with the fitted `M` (needs at least 5 lines).
//!
//! Numbers are written in Rust's shortest round-trip form (`146300.0`, `1e-7`), which TOML and
//! JSON read as floats, so a parser gets back every bit; no NaN or infinity is ever written.
//!
//! # Examples
//! ```
//! use bearing_ident::Identifier;
//! use bearing_ident::export::ross::{BearingElement, Table};
//! use bearing_ident::simulate::{ImpactTest, seed_rig};
//! let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
//! let id = Identifier::new(8.0, 49.0).identify(&records)?;
//! let brg = BearingElement::new(&id, 3, "brg1", Table::Constant)?;
//! assert_eq!(brg.frequency_rad_s().len(), 5);
//! assert!((brg.frequency_rad_s()[0] - 16.0 * std::f64::consts::PI).abs() < 1e-12);
//! assert!((brg.stiffness(0)[0][0] / 146.3e3 - 1.0).abs() < 1e-6);
//! let toml = brg.to_toml();
//! assert!(toml.contains("[BearingElement_brg1]\nn = 3\ntag = \"brg1\"\n"));
//! # Ok::<(), bearing_ident::Error>(())
//! ```

use std::fmt::Write as _;

use faer::MatRef;

use crate::element::ElementModel;
use crate::error::{Block, Error, Result};
use crate::frf::Band;
use crate::identify::Identification;
use crate::model::Coefficients;
use crate::per_frequency::PerFrequency;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// `[[m00, m01], [m10, m11]]` of a 2 × 2 matrix.
pub(crate) fn two(m: MatRef<'_, f64>) -> Matrix2 {
    [[m[(0, 0)], m[(0, 1)]], [m[(1, 0)], m[(1, 1)]]]
}

/// [`Error::ExportDofs`] unless `dofs` is 2.
fn check_dofs(dofs: usize) -> Result<()> {
    if dofs == 2 {
        Ok(())
    } else {
        Err(Error::ExportDofs {
            format: "a ROSS bearing element",
            dofs,
            expected: 2,
        })
    }
}

/// The fewest points of a coefficient table: ROSS 3.x warns below this
/// (`MIN_RECOMMENDED_AXIS_POINTS`), interpolating sparser tables poorly.
pub const MIN_POINTS: usize = 5;

/// The points of a table of a frequency-dependent element model ([`BearingElement::model`]):
/// enough that ROSS's interpolation between them follows the model's curve.
pub const MODEL_POINTS: usize = 21;

/// Which coefficients a [`BearingElement`] tabulates.
///
/// # Examples
/// ```
/// use bearing_ident::export::ross::Table;
/// assert_ne!(Table::Constant, Table::PerFrequency);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Table {
    /// The fitted `M`, `C`, `K` at [`MIN_POINTS`] points evenly spread over the band (default);
    /// when a frequency-dependent element model was fitted (`poly:P`, `states:N`), that model
    /// at [`MODEL_POINTS`] points ([`BearingElement::model`]).
    #[default]
    Constant,
    /// `K(ω) = Re H + ω²M` and `C(ω) = Im H/ω` at every line used, with the fitted `M`
    /// ([`PerFrequency`]).
    PerFrequency,
}

/// A 2 × 2 matrix, row-major: `[[xx, xy], [yx, yy]]`.
pub type Matrix2 = [[f64; 2]; 2];

/// A bearing element for ROSS 3.x: node, tag, and `K`, `C`, `M` tabulated over the excitation
/// frequency (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct BearingElement {
    node: usize,
    tag: String,
    frequency_rad_s: Vec<f64>,
    stiffness: Vec<Matrix2>,
    damping: Vec<Matrix2>,
    mass: Vec<Matrix2>,
}

impl BearingElement {
    /// The bearing element of a 2-DOF (`x`, `y`) identification at ROSS node `node`, named
    /// `tag`, with the coefficients of `table`.
    ///
    /// # Errors
    /// As [`BearingElement::constant`] and [`BearingElement::per_frequency`]: the
    /// identification must have 2 degrees of freedom, and 5 lines or more for
    /// [`Table::PerFrequency`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::export::ross::{BearingElement, Table};
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).identify(&records)?;
    /// let brg = BearingElement::new(&id, 0, "brg1", Table::PerFrequency)?;
    /// // One point per line, 49 of them; the test system's K(ω) is its K on every line.
    /// assert_eq!(brg.frequency_rad_s().len(), 49);
    /// assert!((brg.stiffness(20)[0][0] / 146.3e3 - 1.0).abs() < 1e-6);
    /// assert_eq!(brg.mass(20), brg.mass(0));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn new(id: &Identification, node: usize, tag: &str, table: Table) -> Result<Self> {
        match table {
            Table::Constant => match id.model().filter(|m| m.family().is_frequency_dependent()) {
                Some(model) => Self::model(model, id.band(), None, node, tag),
                None => Self::constant(id.coefficients(), id.band(), node, tag),
            },
            Table::PerFrequency => {
                let pf = id.per_frequency()?;
                Self::per_frequency(&pf, id.coefficients().mass(), node, tag)
            }
        }
    }

    /// The constant coefficients `coefficients` (e.g. a bearing's own, system minus dry
    /// structure, [`Identification::subtract_baseline`]) at [`MIN_POINTS`] points evenly
    /// spread over `band`.
    ///
    /// # Errors
    /// [`Error::ExportDofs`] unless `coefficients` are 2 × 2.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Band, Coefficients};
    /// use bearing_ident::export::ross::BearingElement;
    /// use bearing_ident::faer::mat;
    /// let c = Coefficients::new(
    ///     mat![[0.5, 0.0], [0.0, 0.5]],
    ///     mat![[110.0, 5.0], [-5.0, 110.0]],
    ///     mat![[2e5, 1e4], [-1e4, 2e5]],
    /// )?;
    /// let brg = BearingElement::constant(&c, Band::new(10.0, 50.0)?, 4, "sfd")?;
    /// assert_eq!(brg.frequency_rad_s()[4], 100.0 * std::f64::consts::PI);
    /// assert_eq!(brg.stiffness(2)[1][0], -1e4);
    /// assert_eq!(brg.damping(4)[0][1], 5.0);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn constant(
        coefficients: &Coefficients,
        band: Band,
        node: usize,
        tag: &str,
    ) -> Result<Self> {
        check_dofs(coefficients.dofs())?;
        let (lo, hi) = (band.low_hz(), band.high_hz());
        let last = (MIN_POINTS - 1) as f64;
        let frequency_rad_s = (0..MIN_POINTS)
            .map(|p| TWO_PI * (lo + (hi - lo) * p as f64 / last))
            .collect();
        Self {
            node,
            tag: tag.to_owned(),
            frequency_rad_s,
            stiffness: vec![two(coefficients.stiffness()); MIN_POINTS],
            damping: vec![two(coefficients.damping()); MIN_POINTS],
            mass: vec![two(coefficients.mass()); MIN_POINTS],
        }
        .checked()
    }

    /// The element model's `K(ω)`, `C(ω)` ([`ElementModel::curve_at`]) at [`MODEL_POINTS`]
    /// points evenly spread over `band`, with the model's constant `M`; with `baseline` (the
    /// dry structure's constant `M`, `C`, `K`, as subtracted by
    /// [`Identification::subtract_baseline`]) the bearing's own: the baseline's terms taken
    /// off every point.
    ///
    /// # Errors
    /// [`Error::ExportDofs`] unless the model (and the baseline) are 2 × 2;
    /// [`Error::NonFiniteCoefficient`] for a term that is not finite.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::element::ModelSpec;
    /// use bearing_ident::export::ross::{BearingElement, MODEL_POINTS};
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).model(ModelSpec::Auto).identify(&records)?;
    /// let brg = BearingElement::model(id.model().unwrap(), id.band(), None, 0, "seal")?;
    /// assert_eq!(brg.frequency_rad_s().len(), MODEL_POINTS);
    /// assert!((brg.stiffness(10)[0][0] / 146.3e3 - 1.0).abs() < 1e-3);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn model(
        model: &ElementModel,
        band: Band,
        baseline: Option<&Coefficients>,
        node: usize,
        tag: &str,
    ) -> Result<Self> {
        check_dofs(model.fit().dofs())?;
        if let Some(b) = baseline {
            check_dofs(b.dofs())?;
        }
        let (lo, hi) = (band.low_hz(), band.high_hz());
        let last = (MODEL_POINTS - 1) as f64;
        let freqs: Vec<f64> = (0..MODEL_POINTS)
            .map(|p| lo + (hi - lo) * p as f64 / last)
            .collect();
        let curve = model.curve_at(&freqs);
        let mass = model.constant_part()?;
        let less = |m: Matrix2, base: Option<MatRef<'_, f64>>| match base {
            Some(b) => {
                let b = two(b);
                [
                    [m[0][0] - b[0][0], m[0][1] - b[0][1]],
                    [m[1][0] - b[1][0], m[1][1] - b[1][1]],
                ]
            }
            None => m,
        };
        Self {
            node,
            tag: tag.to_owned(),
            frequency_rad_s: freqs.iter().map(|f| TWO_PI * f).collect(),
            stiffness: curve
                .stiffness
                .iter()
                .map(|k| less(two(k.as_ref()), baseline.map(|b| b.stiffness())))
                .collect(),
            damping: curve
                .damping
                .iter()
                .map(|c| less(two(c.as_ref()), baseline.map(|b| b.damping())))
                .collect(),
            mass: vec![less(two(mass.mass()), baseline.map(|b| b.mass())); MODEL_POINTS],
        }
        .checked()
    }

    /// `K(ω)`, `C(ω)` of `per_frequency` at its every line, with the constant `mass`.
    ///
    /// # Errors
    /// [`Error::ExportDofs`] unless 2 × 2; [`Error::InvalidParameter`] for fewer than
    /// [`MIN_POINTS`] lines, lines not strictly increasing, or `mass` not 2 × 2;
    /// [`Error::NonFiniteCoefficient`] for a term that is not finite.
    pub fn per_frequency(
        per_frequency: &PerFrequency,
        mass: MatRef<'_, f64>,
        node: usize,
        tag: &str,
    ) -> Result<Self> {
        let freqs = per_frequency.freqs_hz();
        if let Some(k) = (!freqs.is_empty()).then(|| per_frequency.stiffness(0)) {
            check_dofs(k.nrows())?;
        }
        if mass.nrows() != 2 || mass.ncols() != 2 {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::MassMatrixSize,
                value: mass.nrows() as f64,
                expected: "2 × 2",
            });
        }
        if freqs.len() < MIN_POINTS || freqs.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::PerFrequencyLines,
                value: freqs.len() as f64,
                expected: "at least 5 lines, strictly increasing (ROSS tables)",
            });
        }
        let lines = 0..freqs.len();
        Self {
            node,
            tag: tag.to_owned(),
            frequency_rad_s: freqs.iter().map(|f| TWO_PI * f).collect(),
            stiffness: lines
                .clone()
                .map(|k| two(per_frequency.stiffness(k)))
                .collect(),
            damping: lines.map(|k| two(per_frequency.damping(k))).collect(),
            mass: vec![two(mass); freqs.len()],
        }
        .checked()
    }

    /// `self` if every term is finite, else [`Error::NonFiniteCoefficient`] at the first one
    /// that is not.
    fn checked(self) -> Result<Self> {
        self.check_finite()?;
        Ok(self)
    }

    /// [`Error::NonFiniteCoefficient`] at the first term that is not finite.
    fn check_finite(&self) -> Result<()> {
        for (block, table) in [
            (Block::Stiffness, &self.stiffness),
            (Block::Damping, &self.damping),
            (Block::Mass, &self.mass),
        ] {
            for m in table {
                for (row, col) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    if !m[row][col].is_finite() {
                        return Err(Error::NonFiniteCoefficient {
                            matrix: block,
                            row,
                            col,
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// The ROSS node the bearing sits at (`n`).
    pub fn node(&self) -> usize {
        self.node
    }

    /// The element's tag (`tag`, and the table's name `BearingElement_<tag>`).
    pub fn tag(&self) -> &str {
        &self.tag
    }

    /// The excitation-frequency axis (rad/s), strictly increasing.
    pub fn frequency_rad_s(&self) -> &[f64] {
        &self.frequency_rad_s
    }

    /// `[[kxx, kxy], [kyx, kyy]]` at point `p` (N/m).
    ///
    /// # Panics
    /// If `p >= self.frequency_rad_s().len()`.
    pub fn stiffness(&self, p: usize) -> Matrix2 {
        self.stiffness[p]
    }

    /// `[[cxx, cxy], [cyx, cyy]]` at point `p` (N·s/m).
    ///
    /// # Panics
    /// If `p >= self.frequency_rad_s().len()`.
    pub fn damping(&self, p: usize) -> Matrix2 {
        self.damping[p]
    }

    /// `[[mxx, mxy], [myx, myy]]` at point `p` (kg).
    ///
    /// # Panics
    /// If `p >= self.frequency_rad_s().len()`.
    pub fn mass(&self, p: usize) -> Matrix2 {
        self.mass[p]
    }

    /// The twelve terms by ROSS name, in the order written: `kxx kxy kyx kyy cxx … myy`.
    fn terms(&self) -> Vec<(String, Vec<f64>)> {
        let mut out = Vec::with_capacity(12);
        for (letter, table) in [
            ('k', &self.stiffness),
            ('c', &self.damping),
            ('m', &self.mass),
        ] {
            for (row, col, axes) in [(0, 0, "xx"), (0, 1, "xy"), (1, 0, "yx"), (1, 1, "yy")] {
                out.push((
                    format!("{letter}{axes}"),
                    table.iter().map(|m| m[row][col]).collect(),
                ));
            }
        }
        out
    }

    /// The element as a ROSS TOML file: a comment line, then the table
    /// `[BearingElement_<tag>]` with `n`, `tag`, `frequency` and the twelve terms, one array
    /// per line.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::export::ross::{BearingElement, Table};
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// let id = Identifier::new(10.0, 30.0).identify(&records)?;
    /// let toml = BearingElement::new(&id, 0, "brg1", Table::Constant)?.to_toml();
    /// // 10, 15, 20, 25, 30 Hz in rad/s.
    /// let w = |f: f64| format!("{:?}", 2.0 * std::f64::consts::PI * f);
    /// assert!(toml.contains(&format!("frequency = [{}, {}, {}", w(10.0), w(15.0), w(20.0))));
    /// assert_eq!(toml.lines().filter(|l| l.starts_with('m')).count(), 4);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn to_toml(&self) -> String {
        let mut s = String::with_capacity(4096);
        s.push_str(&format!(
            "# bearing-ident {}: ROSS 3.x bearing element; frequency in rad/s, k in N/m, c in N*s/m, m in kg\n",
            env!("CARGO_PKG_VERSION")
        ));
        let name = format!("BearingElement_{}", self.tag);
        let bare = !name.is_empty()
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        if bare {
            let _ = writeln!(s, "[{name}]");
        } else {
            let _ = writeln!(s, "[{}]", quoted(&name));
        }
        let _ = writeln!(s, "n = {}", self.node);
        let _ = writeln!(s, "tag = {}", quoted(&self.tag));
        let _ = writeln!(s, "frequency = {}", array(&self.frequency_rad_s, ", "));
        for (key, values) in self.terms() {
            let _ = writeln!(s, "{key} = {}", array(&values, ", "));
        }
        s
    }

    /// The element as a ROSS JSON file: `{"BearingElement_<tag>": {"n": …, "tag": …,
    /// "frequency": […], "kxx": […], …}}`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::export::ross::{BearingElement, Table};
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).identify(&records)?;
    /// let json = BearingElement::new(&id, 2, "brg \"A\"", Table::Constant)?.to_json();
    /// assert!(json.starts_with("{\n  \"BearingElement_brg \\\"A\\\"\": {\n    \"n\": 2,\n"));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn to_json(&self) -> String {
        let mut s = String::with_capacity(4096);
        let name = format!("BearingElement_{}", self.tag);
        let _ = writeln!(s, "{{\n  {}: {{", quoted(&name));
        let _ = writeln!(s, "    \"n\": {},", self.node);
        let _ = writeln!(s, "    \"tag\": {},", quoted(&self.tag));
        let _ = write!(
            s,
            "    \"frequency\": {}",
            array(&self.frequency_rad_s, ", ")
        );
        for (key, values) in self.terms() {
            let _ = write!(s, ",\n    \"{key}\": {}", array(&values, ", "));
        }
        s.push_str("\n  }\n}\n");
        s
    }
}

/// `[a, b, …]` in the shortest round-trip form of each value (`146300.0`, `1e-7`, never a
/// bare integer, which TOML would not mix with floats in one array).
pub(crate) fn array(values: &[f64], separator: &str) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("{v:?}")).collect();
    format!("[{}]", items.join(separator))
}

/// `text` as a double-quoted string that TOML and JSON both read: `"` and `\` escaped,
/// control characters (and DEL) as `\u00XX`.
pub(crate) fn quoted(text: &str) -> String {
    let mut s = String::with_capacity(text.len() + 2);
    s.push('"');
    for c in text.chars() {
        match c {
            '"' => s.push_str("\\\""),
            '\\' => s.push_str("\\\\"),
            c if c.is_control() => {
                let _ = write!(s, "\\u{:04X}", c as u32);
            }
            c => s.push(c),
        }
    }
    s.push('"');
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_are_escaped_for_toml_and_json() {
        assert_eq!(quoted("brg1"), "\"brg1\"");
        assert_eq!(quoted("a\"b\\c"), "\"a\\\"b\\\\c\"");
        assert_eq!(quoted("t\u{7f}\n"), "\"t\\u007F\\u000A\"");
        assert_eq!(quoted("é"), "\"é\"");
    }

    #[test]
    fn arrays_are_floats_to_the_last_bit() {
        let v = [146300.0, 1e-7, -2.5e20, 0.1, 1.0 / 3.0];
        let text = array(&v, ", ");
        assert_eq!(text, "[146300.0, 1e-7, -2.5e20, 0.1, 0.3333333333333333]");
        let back: Vec<f64> = text[1..text.len() - 1]
            .split(", ")
            .map(|x| x.parse().unwrap())
            .collect();
        assert_eq!(
            back.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            v.map(f64::to_bits)
        );
    }
}
