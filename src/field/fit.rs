//! The constant fit over speeds ([`fit_constant`]): `K`, `C`, `M` of a bearing from its
//! `K(Ω)`, `C(Ω)`.

use super::result::{FieldIdentification, SpeedCoefficients};

/// Constant coefficients of one bearing fitted over the speeds (rows and columns `x, y`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantFit {
    /// `K` (N/m).
    pub stiffness: [[f64; 2]; 2],
    /// `C` (N·s/m).
    pub damping: [[f64; 2]; 2],
    /// `M` (kg): the synchronous `Re Z = K − Ω²M` seen across speeds.
    pub mass: [[f64; 2]; 2],
    /// Standard deviations of `stiffness`, `damping`, `mass` (see [`fit_constant`]).
    pub stiffness_std: [[f64; 2]; 2],
    /// Standard deviation of `damping`.
    pub damping_std: [[f64; 2]; 2],
    /// Standard deviation of `mass`.
    pub mass_std: [[f64; 2]; 2],
    /// Speeds used.
    pub speeds: usize,
}

/// Per bearing, the fit of constant `K`, `C`, `M` to its `K(Ω)`, `C(Ω)`:
/// $\operatorname{Re} Z_{ij}(\Omega) = K_{ij} - \Omega^2 M_{ij}$ by least squares and
/// $C_{ij}$ the mean of $C_{ij}(\Omega)$, each speed weighted by $1/\sigma^2$ when the
/// coefficients carry standard deviations (unweighted otherwise). `None` for a bearing with
/// fewer than 3 speeds identified (two unknowns and one degree of freedom to spare).
///
/// A bearing whose coefficients depend on speed (a fluid-film bearing's do) is not a constant
/// `K`, `C`, `M`: the fit is then a summary, and `M` absorbs the trend of `K(Ω)`.
///
/// Standard deviations: weighted, $(X^\top W X)^{-1}$ scaled by the reduced
/// $\chi^2 = \sum_s w_s r_s^2/(S - p)$ when it exceeds 1 (the scatter about the constant model is
/// more than the per-speed error bars explain: a speed-dependent bearing, whose trend then
/// counts as error); unweighted, $(X^\top X)^{-1}\, \mathrm{RSS}/(S - p)$. $S$ speeds, $p = 2$
/// for `K`, `M` and $1$ for `C`.
///
/// # Examples
/// ```
/// # use bearing_ident::field::{self, *};
/// # let rotor = BeamRotor { element_lengths: vec![0.15; 6], diameter: 0.05, density: 7850.0,
/// #     young: 2.1e11, poisson: 0.3,
/// #     disks: vec![Disk { node: 2, mass: 15.0, polar: 0.12, diametral: 0.06 }],
/// #     bearings: vec![BearingSite::new("brg0", 0), BearingSite::new("brg1", 6)] }.model()?;
/// # let probes = [0, 6].into_iter()
/// #     .flat_map(|node| [Direction::X, Direction::Y].map(|dir| Probe { node, dir })).collect();
/// # let at = |node, phase_rad| vec![Imbalance { node, magnitude_kg_m: 1e-4, phase_rad }];
/// // Bearings with a constant K, C and an added mass of 3 kg in x.
/// let brg = |_b: usize, w: f64| BearingCoefficients {
///     stiffness: [[2e7 - 3.0 * w * w, 3e6], [-4e6, 3e7]],
///     damping: [[2e4, 1e3], [-1e3, 3e4]],
/// };
/// let tests = ImbalanceRuns { speeds_rad_s: vec![100.0, 200.0, 300.0], probes,
///     residual: at(3, 1.0), added: [at(2, 0.0), at(5, 2.0)], noise: 0.0, repeats: 1, seed: 1 }
///     .simulate(&rotor, brg)?;
/// let fits = field::fit_constant(&field::identify(&rotor, &tests)?);
/// let fit = fits[0].unwrap();
/// assert!((fit.mass[0][0] - 3.0).abs() < 1e-5 && (fit.stiffness[0][0] / 2e7 - 1.0).abs() < 1e-9);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn fit_constant(id: &FieldIdentification) -> Vec<Option<ConstantFit>> {
    id.bearings()
        .iter()
        .map(|b| {
            let points: Vec<_> = id
                .speeds_rad_s()
                .iter()
                .zip(&b.coefficients)
                .filter_map(|(&w, c)| c.map(|c| (w, c)))
                .collect();
            if points.len() < 3 {
                return None;
            }
            let weighted = points.iter().all(|(_, c)| c.stiffness_std.is_some());
            let mut fit = ConstantFit {
                stiffness: [[0.0; 2]; 2],
                damping: [[0.0; 2]; 2],
                mass: [[0.0; 2]; 2],
                stiffness_std: [[0.0; 2]; 2],
                damping_std: [[0.0; 2]; 2],
                mass_std: [[0.0; 2]; 2],
                speeds: points.len(),
            };
            for i in 0..2 {
                for j in 0..2 {
                    // Weighted normal equations of k − Ω² m, and the weighted mean of c.
                    let weights = |c: &SpeedCoefficients| match (c.stiffness_std, c.damping_std) {
                        (Some(sk), Some(sc)) if weighted => (
                            1.0 / sk[i][j].powi(2).max(f64::MIN_POSITIVE),
                            1.0 / sc[i][j].powi(2).max(f64::MIN_POSITIVE),
                        ),
                        _ => (1.0, 1.0),
                    };
                    let (mut s, mut sx, mut sxx, mut sy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
                    let (mut cw, mut cs) = (0.0, 0.0);
                    for (w, c) in &points {
                        let (wk, wc) = weights(c);
                        let x = -w * w;
                        let y = c.stiffness[i][j];
                        s += wk;
                        sx += wk * x;
                        sxx += wk * x * x;
                        sy += wk * y;
                        sxy += wk * x * y;
                        cw += wc;
                        cs += wc * c.damping[i][j];
                    }
                    let det = s * sxx - sx * sx;
                    let (m, k, cm) = (
                        (s * sxy - sx * sy) / det,
                        (sxx * sy - sx * sxy) / det,
                        cs / cw,
                    );
                    // Weighted residual sums of both fits.
                    let (mut rk, mut rc) = (0.0, 0.0);
                    for (w, c) in &points {
                        let (wk, wc) = weights(c);
                        rk += wk * (c.stiffness[i][j] - (k - w * w * m)).powi(2);
                        rc += wc * (c.damping[i][j] - cm).powi(2);
                    }
                    let n = points.len() as f64;
                    let scale = |chi2: f64, dof: f64| {
                        let reduced = chi2 / dof;
                        if weighted { reduced.max(1.0) } else { reduced }
                    };
                    let (sk2, sc2) = (scale(rk, n - 2.0), scale(rc, n - 1.0));
                    fit.mass[i][j] = m;
                    fit.stiffness[i][j] = k;
                    fit.damping[i][j] = cm;
                    fit.mass_std[i][j] = (s / det * sk2).sqrt();
                    fit.stiffness_std[i][j] = (sxx / det * sk2).sqrt();
                    fit.damping_std[i][j] = (sc2 / cw).sqrt();
                }
            }
            let finite = [
                fit.stiffness,
                fit.damping,
                fit.mass,
                fit.stiffness_std,
                fit.damping_std,
                fit.mass_std,
            ]
            .iter()
            .flatten()
            .flatten()
            .all(|v| v.is_finite());
            finite.then_some(fit)
        })
        .collect()
}
