//! An identification as Universal File dataset 58 functions (feature `uff`): the measured
//! impedances and flexibilities, the fitted model's, and the coherences, for modal software.
//!
//! # What is written
//! For `n` degrees of freedom, in this order, each block `i = 1…n` (response) then
//! `j = 1…n` (reference):
//!
//! | ID line 1 | function type | numerator / denominator | values |
//! |---|---|---|---|
//! | `Measured impedance H(i,j)` | 4 FRF | 13 force / 8 displacement (N/m) | `H_ij(ω_k)` of the FRF stage |
//! | `Model impedance H(i,j)` | 4 FRF | 13 force / 8 displacement (N/m) | `K − ω²M + iωC` of the fit |
//! | `Measured flexibility G(i,j)` | 4 FRF | 8 displacement / 13 force (m/N) | `G_ij(ω_k)` of the FRF stage |
//! | `Model flexibility G(i,j)` | 4 FRF | 8 displacement / 13 force (m/N) | `(K − ω²M + iωC)⁻¹` |
//! | `Ordinary coherence (i,j)` | 6 coherence | 1 general / 0 | `γ²_ij`, real, when the FRF has it |
//! | `Multiple coherence (i)` | 6 coherence | 1 general / 0 | `γ²_i:f`, real, reference node 0 direction 0, when the FRF has it |
//!
//! The FRFs are complex and double precision (ordinate type 6), the coherences real double
//! (type 4). The abscissa is the frequency (data type 18, Hz): evenly spaced (`x0`, `dx` in
//! record 7) when the lines are on one grid — every line within
//! [`BAND_EDGE_SLACK`] of a spacing of `x0 + k·dx` — otherwise every line given (uneven: a
//! stepped-sine test, lines dropped as singular or unexcited). Record 7 and an uneven abscissa
//! hold six significant digits ([module docs of `uff`](crate::uff#precision)); the values hold
//! thirteen in ASCII ([`uff::write`](crate::uff::write)) and every bit in binary
//! ([`uff::write_binary`](crate::uff::write_binary)).
//!
//! # Degrees of freedom
//! Degree of freedom `d = 1, 2, …` is node `node + (d − 1) / 6` in direction `(d − 1) mod 6 + 1`:
//! one node carries up to six (1 +X, 2 +Y, 3 +Z, 4–6 rotations about X, Y, Z), so a 2-DOF
//! bearing is `node` +X and +Y. Past six the next node continues at +X (a seventh degree of
//! freedom is `node + 1` +X): say in your model what they are. Response is output `i`,
//! reference input `j`: `H_ij` is the force at `i` per displacement at `j`, `G_ij` the
//! displacement at `i` per force at `j`. ID line 2 names the estimator, the fit and the window;
//! ID line 4 the two degrees of freedom (one-based).
//!
//! # Exponential window
//! Under [`Window::Exponential`] of decay `a` the measured functions are those of the windowed
//! data, the system at `s = a + iω`; the model's are evaluated at the same `s`,
//! `H(s) = K + sC + s²M` with the window-corrected coefficients, so that the two compare (ID
//! line 5 says so). Under every other window `s = iω`.

use crate::Choice;
use faer::{Mat, c64};

use crate::error::Result;
use crate::identify::Identification;
use crate::linalg::Inverter;
use crate::model::Coefficients;
use crate::spectra::Window;
use crate::tolerance::BAND_EDGE_SLACK;
use crate::uff::{Abscissa, Axis, DataType, Dof, Function, FunctionType, Ordinate, Precision};

/// The dataset 58 functions of an identification (see the [module docs](self)): measured and
/// model impedances `H` and flexibilities `G` for every pair of degrees of freedom, then the
/// ordinary and multiple coherences when the FRF carries them; degree of freedom `d` at node
/// `node + (d − 1) / 6`, direction `(d − 1) mod 6 + 1`.
///
/// Write them with [`uff::write`](crate::uff::write) (ASCII) or
/// [`uff::write_binary`](crate::uff::write_binary) (every bit kept).
///
/// # Errors
/// [`Error::Singular`](crate::Error::Singular) if the model's impedance is singular at a line
/// (an undamped resonance exactly on it). A node number too wide for its field is refused by
/// the writers.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::export::uff::functions;
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// use bearing_ident::uff::{Abscissa, FunctionType, Ordinate};
/// let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let f = functions(&id, 1)?;
/// // Four kinds of FRF for each of the 2 × 2 pairs, then 4 ordinary and 2 multiple coherences.
/// assert_eq!(f.len(), 16 + 4 + 2);
/// assert_eq!(f[16].function_type, FunctionType::Coherence);
/// assert_eq!(f[5].id[0], "Model impedance H(1,2)");
/// assert_eq!(f[5].function_type, FunctionType::Frf);
/// assert_eq!((f[5].response.direction, f[5].reference.direction), (1, 2));
/// // 49 lines, 1/1.2 s apart, from 8.33 Hz.
/// let Abscissa::Even { x0, dx, n } = f[0].abscissa else { panic!("uneven") };
/// assert_eq!(n, 49);
/// assert!((x0 - 10.0 / 1.2).abs() < 1e-12 && (dx - 1.0 / 1.2).abs() < 1e-12);
/// // The measured K_xx − ω²M_xx at the first line, 146.3 kN/m − (2π · 8.33 Hz)² · 4.7 kg.
/// let Ordinate::Complex(h) = &f[0].ordinate else { panic!("real") };
/// let w = 2.0 * std::f64::consts::PI * x0;
/// assert!((h[0].re / (146.3e3 - w * w * 4.7) - 1.0).abs() < 1e-6);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn functions(id: &Identification, node: i64) -> Result<Vec<Function>> {
    let frf = id.frf();
    let n = frf.dofs();
    let freqs = frf.freqs_hz();
    let lines = freqs.len();
    let abscissa = abscissa(freqs);
    let decay = id.window().decay_per_s();
    let mut model = Model::new(id.coefficients(), decay);
    let (mut model_h, mut model_g) = (Vec::with_capacity(lines), Vec::with_capacity(lines));
    for &f in freqs {
        let (h, g) = model.at(f)?;
        model_h.push(h);
        model_g.push(g);
    }
    let header = Header {
        n,
        node,
        abscissa,
        fit: format!(
            "bearing-ident {}: {} estimator, {} fit, {} averages",
            env!("CARGO_PKG_VERSION"),
            id.estimator().name(),
            id.method().name(),
            frf.averages()
        ),
        window: match (id.window(), decay) {
            (Window::Exponential { .. }, Some(a)) => {
                format!("exp window, decay {a} 1/s: functions at s = a + i w")
            }
            (w, _) => format!("{} window: functions at s = i w", w.name()),
        },
    };
    let mut out = Vec::new();
    let kinds: [(&str, Kind, &Element); 4] = [
        ("Measured impedance H", Kind::Impedance, &|k, i, j| {
            frf.impedance(k)[(i, j)]
        }),
        ("Model impedance H", Kind::Impedance, &|k, i, j| {
            model_h[k][(i, j)]
        }),
        ("Measured flexibility G", Kind::Flexibility, &|k, i, j| {
            frf.flexibility(k)[(i, j)]
        }),
        ("Model flexibility G", Kind::Flexibility, &|k, i, j| {
            model_g[k][(i, j)]
        }),
    ];
    for (what, kind, value) in kinds {
        for i in 0..n {
            for j in 0..n {
                let values = (0..lines).map(|k| value(k, i, j)).collect();
                out.push(header.function(
                    format!("{what}({},{})", i + 1, j + 1),
                    kind,
                    i,
                    Some(j),
                    Ordinate::Complex(values),
                ));
            }
        }
    }
    if lines > 0 && (0..lines).all(|k| frf.ordinary_coherence(k).is_some()) {
        for i in 0..n {
            for j in 0..n {
                let values = (0..lines)
                    .filter_map(|k| frf.ordinary_coherence(k).map(|c| c[(i, j)]))
                    .collect();
                out.push(header.function(
                    format!("Ordinary coherence ({},{})", i + 1, j + 1),
                    Kind::Coherence,
                    i,
                    Some(j),
                    Ordinate::Real(values),
                ));
            }
        }
    }
    if lines > 0 && (0..lines).all(|k| frf.multiple_coherence(k).is_some()) {
        for i in 0..n {
            let values = (0..lines)
                .filter_map(|k| frf.multiple_coherence(k).map(|c| c[i]))
                .collect();
            out.push(header.function(
                format!("Multiple coherence ({})", i + 1),
                Kind::Coherence,
                i,
                None,
                Ordinate::Real(values),
            ));
        }
    }
    for (number, f) in out.iter_mut().enumerate() {
        f.function_id = number as i64 + 1;
    }
    Ok(out)
}

/// Node and direction of degree of freedom `dof` (zero-based): node `node + dof / 6`,
/// direction `dof mod 6 + 1` (1 +X, 2 +Y, 3 +Z, 4–6 rotations).
///
/// # Examples
/// ```
/// use bearing_ident::export::uff::dof;
/// assert_eq!((dof(10, 1).node, dof(10, 1).direction), (10, 2));
/// assert_eq!((dof(10, 6).node, dof(10, 6).direction), (11, 1));
/// ```
pub fn dof(node: i64, dof: usize) -> Dof {
    Dof {
        entity: "NONE".into(),
        node: node.saturating_add((dof / 6) as i64),
        direction: (dof % 6) as i64 + 1,
    }
}

/// The frequency abscissa: even when every line is within [`BAND_EDGE_SLACK`] of a spacing of
/// its place on the grid through the first and last line.
fn abscissa(freqs: &[f64]) -> Abscissa {
    let n = freqs.len();
    match freqs {
        [] => Abscissa::Even {
            x0: 0.0,
            dx: 0.0,
            n: 0,
        },
        [f] => Abscissa::Even { x0: *f, dx: 0.0, n },
        [first, .., last] => {
            let dx = (last - first) / (n - 1) as f64;
            let on_grid = dx > 0.0
                && freqs
                    .iter()
                    .enumerate()
                    .all(|(k, f)| (f - (first + k as f64 * dx)).abs() <= BAND_EDGE_SLACK * dx);
            if on_grid {
                Abscissa::Even { x0: *first, dx, n }
            } else {
                Abscissa::Uneven(freqs.to_vec())
            }
        }
    }
}

/// The fitted model at `s = a + iω` (`a` = 0 without an exponential window).
struct Model<'a> {
    coefficients: &'a Coefficients,
    decay: Option<f64>,
    inverter: Inverter,
    scratch: Vec<c64>,
}

impl<'a> Model<'a> {
    fn new(coefficients: &'a Coefficients, decay: Option<f64>) -> Self {
        let n = coefficients.dofs();
        Self {
            coefficients,
            decay,
            inverter: Inverter::new(n),
            scratch: vec![c64::new(0.0, 0.0); n * n],
        }
    }

    /// `H(s)` and `G(s) = H(s)⁻¹` at `freq_hz`: [`Coefficients::impedance_at`] and
    /// [`Coefficients::flexibility_at`] at `s = iω`, `K + sC + s²M` inverted at `s = a + iω`.
    fn at(&mut self, freq_hz: f64) -> Result<(Mat<c64>, Mat<c64>)> {
        let c = self.coefficients;
        let Some(a) = self.decay else {
            return Ok((c.impedance_at(freq_hz), c.flexibility_at(freq_hz)?));
        };
        let n = c.dofs();
        let s = c64::new(a, 2.0 * std::f64::consts::PI * freq_hz);
        let s2 = s * s;
        let h = Mat::from_fn(n, n, |i, j| {
            s2 * c.mass()[(i, j)] + s * c.damping()[(i, j)] + c.stiffness()[(i, j)]
        });
        for j in 0..n {
            for i in 0..n {
                self.scratch[i + j * n] = h[(i, j)];
            }
        }
        if !self.inverter.invert(&mut self.scratch) {
            return Err(crate::Error::Singular { what: "impedance" });
        }
        let g = Mat::from_fn(n, n, |i, j| self.scratch[i + j * n]);
        Ok((h, g))
    }
}

/// Element `(i, j)` at line `k` of one kind of function.
type Element<'a> = dyn Fn(usize, usize, usize) -> c64 + 'a;

/// Which quantity a function holds: its data types and units.
#[derive(Clone, Copy)]
enum Kind {
    /// Force per displacement (N/m).
    Impedance,
    /// Displacement per force (m/N).
    Flexibility,
    /// Coherence (dimensionless, real).
    Coherence,
}

/// What every function of one export shares.
struct Header {
    n: usize,
    node: i64,
    abscissa: Abscissa,
    fit: String,
    window: String,
}

impl Header {
    /// One function: `what` on ID line 1, response degree of freedom `i`, reference `j`
    /// (`None`: node 0, direction 0, all inputs).
    fn function(
        &self,
        what: String,
        kind: Kind,
        i: usize,
        j: Option<usize>,
        ordinate: Ordinate,
    ) -> Function {
        let force = Axis {
            force_exponent: 1,
            ..Axis::new(DataType::ExcitationForce, "Force", "N")
        };
        let displacement = Axis {
            length_exponent: 1,
            ..Axis::new(DataType::Displacement, "Displacement", "m")
        };
        let (function_type, numerator, denominator) = match kind {
            Kind::Impedance => (FunctionType::Frf, force, displacement),
            Kind::Flexibility => (FunctionType::Frf, displacement, force),
            Kind::Coherence => (
                FunctionType::Coherence,
                Axis::new(DataType::General, "Coherence", "NONE"),
                Axis::none(),
            ),
        };
        let response = dof(self.node, i);
        let (reference, dofs) = match j {
            Some(j) => {
                let r = dof(self.node, j);
                let text = format!(
                    "response DOF {} (node {} dir {}) of {}, reference DOF {} (node {} dir {})",
                    i + 1,
                    response.node,
                    response.direction,
                    self.n,
                    j + 1,
                    r.node,
                    r.direction
                );
                (r, text)
            }
            None => (
                Dof {
                    entity: "NONE".into(),
                    node: 0,
                    direction: 0,
                },
                format!(
                    "response DOF {} (node {} dir {}) of {}, all inputs",
                    i + 1,
                    response.node,
                    response.direction,
                    self.n
                ),
            ),
        };
        Function {
            id: [
                what,
                self.fit.clone(),
                "NONE".into(),
                dofs,
                self.window.clone(),
            ],
            function_type,
            function_id: 0,
            version: 0,
            load_case: 0,
            response,
            reference,
            precision: Precision::Double,
            z_value: 0.0,
            abscissa_axis: Axis::new(DataType::Frequency, "Frequency", "Hz"),
            numerator,
            denominator,
            z_axis: Axis::none(),
            abscissa: self.abscissa.clone(),
            ordinate,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn even_lines_give_an_even_abscissa() {
        let f: Vec<f64> = (10..20).map(|k| k as f64 * 0.1).collect();
        let Abscissa::Even { x0, dx, n } = abscissa(&f) else {
            panic!("uneven")
        };
        assert_eq!(n, 10);
        assert!((x0 - 1.0).abs() < 1e-15 && (dx - 0.1).abs() < 1e-15);
    }

    #[test]
    fn a_gap_gives_every_line() {
        let f = vec![1.0, 2.0, 4.0];
        assert_eq!(abscissa(&f), Abscissa::Uneven(f));
    }

    #[test]
    fn one_line_is_even_with_no_spacing() {
        assert_eq!(
            abscissa(&[5.0]),
            Abscissa::Even {
                x0: 5.0,
                dx: 0.0,
                n: 1
            }
        );
    }

    #[test]
    fn dofs_past_six_move_to_the_next_node() {
        let d: Vec<(i64, i64)> = (0..8)
            .map(|k| {
                let d = dof(3, k);
                (d.node, d.direction)
            })
            .collect();
        assert_eq!(d[0], (3, 1));
        assert_eq!(d[5], (3, 6));
        assert_eq!(d[7], (4, 2));
    }

    #[test]
    fn the_shifted_model_inverts_at_s() -> Result<()> {
        use faer::mat;
        // SDOF m = 2, c = 10, k = 8000 at s = a + iω: H = k + s c + s² m.
        let c = Coefficients::new(mat![[2.0]], mat![[10.0]], mat![[8000.0]])?;
        let mut model = Model::new(&c, Some(3.0));
        let (h, g) = model.at(5.0)?;
        let s = c64::new(3.0, 10.0 * std::f64::consts::PI);
        let expected = s * s * 2.0 + s * 10.0 + 8000.0;
        assert!((h[(0, 0)] - expected).norm() < 1e-12 * expected.norm());
        assert!((g[(0, 0)] * h[(0, 0)] - c64::new(1.0, 0.0)).norm() < 1e-14);
        Ok(())
    }

    #[test]
    fn an_undamped_resonance_on_a_line_is_singular() -> Result<()> {
        use faer::mat;
        // m = 1, k = (2π · 5)², c = 0: H(i · 2π · 5) = 0.
        let k = (10.0 * std::f64::consts::PI).powi(2);
        let c = Coefficients::new(mat![[1.0]], mat![[0.0]], mat![[k]])?;
        let err = Model::new(&c, Some(0.0)).at(5.0).unwrap_err();
        assert_eq!(err.kind(), "singular");
        Ok(())
    }
}
