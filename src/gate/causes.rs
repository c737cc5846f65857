//! The likely causes of negative diagonal coefficients ([`negative_diagonal_causes`]): force
//! and response columns exchanged, a transfer (non-drive-point) FRF, whose diagonal terms need
//! not be positive, and response channels that measure velocity or acceleration read as
//! displacement.

use faer::{Mat, c64};

use crate::Choice;
use crate::error::Warning;
use crate::frf::Frf;
use crate::model::Coefficients;
use crate::records::Response;
use crate::solve::{IvfOptions, Method};

/// Fraction of the lines where a diagonal flexibility `G_ii` has a positive imaginary part
/// above which it is not a drive-point FRF: the receptance of a passive system at the point
/// of the force has $\mathrm{Im}\,G_{ii} = -\omega\, x^H C x / |\ldots|^2 \le 0$ at every line,
/// so noise alone puts only the lines far from resonance, where `Im G` is small, above zero.
pub const TRANSFER_FRACTION: f64 = 0.25;

/// With some diagonal entry of `M`, `C` or `K` of `model` (fitted to `frf` by `method`)
/// negative: [`Warning::SwappedChannels`] alone when the data read the other way round (the
/// measured impedance taken as the flexibility: force and response columns exchanged) fit
/// with every diagonal positive and a smaller relative residual; else [`Warning::TransferFrf`] for each diagonal flexibility whose imaginary part is
/// positive at more than [`TRANSFER_FRACTION`] of the lines; and, when every response channel
/// was read as displacement (`displacement`) and a diagonal of `M` is negative,
/// [`Warning::ResponseKind`] when the flexibility divided by $i\omega$ (velocity) or
/// $-\omega^2$ (acceleration) fits with every diagonal positive and a smaller relative
/// residual $\sum_k \lVert G_k - \hat G_k \rVert^2 / \sum_k \lVert G_k \rVert^2$.
///
/// # Examples
/// ```
/// use bearing_ident::gate::negative_diagonal_causes;
/// use bearing_ident::{Coefficients, Frf, Method};
/// use bearing_ident::solve::{IvfOptions, fit};
/// use bearing_ident::simulate::seed_rig;
/// // Accelerations read as displacements: A/F = −ω² G.
/// let truth = seed_rig();
/// let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
/// let g = freqs.iter().map(|&f| {
///     let (w, g) = (2.0 * std::f64::consts::PI * f, truth.flexibility_at(f)?);
///     Ok(faer::Mat::from_fn(2, 2, |i, j| g[(i, j)] * (-w * w)))
/// }).collect::<Result<Vec<_>, bearing_ident::Error>>()?;
/// let frf = Frf::from_flexibility(freqs, &g)?;
/// let model = fit(&frf, Method::Ivf, &IvfOptions::default())?.coefficients().clone();
/// let w = negative_diagonal_causes(&frf, &model, Method::Ivf, &IvfOptions::default(), true);
/// assert!(w.iter().any(|w| w.kind() == "response_kind"));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn negative_diagonal_causes(
    frf: &Frf,
    model: &Coefficients,
    method: Method,
    options: &IvfOptions,
    displacement: bool,
) -> Vec<Warning> {
    let n = model.dofs();
    let negative = |c: &Coefficients| {
        (0..n).any(|i| {
            c.mass()[(i, i)] < 0.0 || c.damping()[(i, i)] < 0.0 || c.stiffness()[(i, i)] < 0.0
        })
    };
    if !negative(model) {
        return Vec::new();
    }
    let method = if method == Method::Ml {
        Method::Ivf
    } else {
        method
    };
    let lines = frf.line_count();
    let freqs = frf.freqs_hz();
    let measured: Vec<Mat<c64>> = (0..lines).map(|k| frf.flexibility(k).to_owned()).collect();
    let residual = |g: &[Mat<c64>], c: &Coefficients| -> f64 {
        let (mut r, mut t) = (0.0, 0.0);
        for (k, &f) in freqs.iter().enumerate() {
            let Ok(fitted) = c.flexibility_at(f) else {
                return f64::INFINITY;
            };
            for j in 0..n {
                for i in 0..n {
                    r += (g[k][(i, j)] - fitted[(i, j)]).norm_sqr();
                    t += g[k][(i, j)].norm_sqr();
                }
            }
        }
        r / t
    };
    // A physical reading of the data as another quantity: its relative residual, if its fit
    // has every diagonal positive and fits better than the reading given.
    let original = residual(&measured, model);
    let reading = |g: Vec<Mat<c64>>| -> Option<f64> {
        let frf = Frf::from_flexibility(freqs.to_vec(), &g).ok()?;
        let fit = crate::solve::fit(&frf, method, options).ok()?;
        let r = residual(&g, fit.coefficients());
        (!negative(fit.coefficients()) && r < original).then_some(r)
    };
    // Force and response exchanged: the measured "flexibility" is the impedance, and the
    // measured impedance the flexibility, of a physical system.
    let impedances: Vec<Mat<c64>> = (0..lines).map(|k| frf.impedance(k).to_owned()).collect();
    if let Some(residual) = reading(impedances) {
        // Its Im G_ii > 0 at every line (ωC of the impedance) is no transfer FRF: not named so.
        return vec![Warning::SwappedChannels { residual, original }];
    }
    let mut out = Vec::new();
    for i in 0..n {
        let positive = (0..lines)
            .filter(|&k| frf.flexibility(k)[(i, i)].im > 0.0)
            .count();
        let fraction = positive as f64 / lines.max(1) as f64;
        if fraction > TRANSFER_FRACTION {
            out.push(Warning::TransferFrf { dof: i, fraction });
        }
    }
    if !displacement || !(0..n).any(|i| model.mass()[(i, i)] < 0.0) {
        return out;
    }
    let mut best: Option<(Response, f64)> = None;
    for kind in [Response::Velocity, Response::Acceleration] {
        let converted: Vec<Mat<c64>> = freqs
            .iter()
            .zip(&measured)
            .map(|(&f, g)| {
                let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
                let d = if kind == Response::Velocity { s } else { s * s };
                Mat::from_fn(n, n, |i, j| g[(i, j)] / d)
            })
            .collect();
        if let Some(r) = reading(converted) {
            if best.is_none_or(|b| r < b.1) {
                best = Some((kind, r));
            }
        }
    }
    if let Some((suggested, residual)) = best {
        out.push(Warning::ResponseKind {
            suggested: suggested.name(),
            residual,
            original,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::seed_rig;

    fn frf_of(g: impl Fn(f64) -> Mat<c64>) -> Frf {
        let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
        let gs: Vec<Mat<c64>> = freqs.iter().map(|&f| g(f)).collect();
        Frf::from_flexibility(freqs, &gs).unwrap()
    }

    fn causes(frf: &Frf, displacement: bool) -> Vec<Warning> {
        let options = IvfOptions::default();
        let model = crate::solve::fit(frf, Method::Ivf, &options)
            .unwrap()
            .coefficients()
            .clone();
        negative_diagonal_causes(frf, &model, Method::Ivf, &options, displacement)
    }

    fn kinds(frf: &Frf, displacement: bool) -> Vec<&'static str> {
        causes(frf, displacement)
            .iter()
            .map(Warning::kind)
            .collect()
    }

    /// Accelerations read as displacement (A/F = −ω²G) give a negative M and the hint;
    /// velocities (V/F = iωG) likewise; the true displacements give nothing; channels said
    /// to be converted already give no hint.
    #[test]
    fn the_response_kind_is_suggested_when_the_data_look_like_it() {
        let truth = seed_rig();
        let scaled = |p: i32| {
            let truth = truth.clone();
            move |f: f64| {
                let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f).powi(p);
                let g = truth.flexibility_at(f).unwrap();
                Mat::from_fn(2, 2, |i, j| g[(i, j)] * s)
            }
        };
        assert!(kinds(&frf_of(scaled(2)), true).contains(&"response_kind"));
        // The warning names the kind by its `--response` spelling.
        let hint = causes(&frf_of(scaled(2)), true)
            .into_iter()
            .find(|w| w.kind() == "response_kind")
            .unwrap();
        assert!(matches!(
            hint,
            Warning::ResponseKind {
                suggested: "acceleration",
                ..
            }
        ));
        assert!(
            hint.to_string()
                .contains("read as acceleration they fit with every diagonal positive")
                && hint.to_string().ends_with("try `--response acceleration`"),
            "{hint}"
        );
        assert!(kinds(&frf_of(scaled(0)), true).is_empty());
        assert!(!kinds(&frf_of(scaled(2)), false).contains(&"response_kind"));
        // A sign-reversed diagonal (the response measured away from the force, in antiphase)
        // has Im G_00 > 0 at every line and is named a transfer FRF.
        let reversed = frf_of(|f| {
            let g = truth.flexibility_at(f).unwrap();
            Mat::from_fn(2, 2, |i, j| {
                if i == 0 && j == 0 {
                    -g[(i, j)]
                } else {
                    g[(i, j)]
                }
            })
        });
        assert!(kinds(&reversed, true).contains(&"transfer_frf"));
    }

    /// Force and response columns exchanged: the measured flexibility is the rig's impedance.
    /// Before, it was named a transfer FRF on both diagonals (Im G_ii = ωC > 0 at every line).
    #[test]
    fn swapped_force_and_response_are_suggested() {
        let truth = seed_rig();
        let swapped = frf_of(|f| truth.impedance_at(f));
        assert_eq!(kinds(&swapped, true), ["swapped_channels"]);
        // The same data read the right way round: nothing to say.
        assert!(kinds(&frf_of(|f| truth.flexibility_at(f).unwrap()), true).is_empty());
    }
}
