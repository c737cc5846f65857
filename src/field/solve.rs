//! The recovery per speed: the column-scaled least-squares solve for the unmeasured degrees of
//! freedom and the bearing forces, the 2×2 impedance per bearing, its condition number and its
//! first-order error bars; and the critical speeds of the rotor pinned at the probes.

use faer::prelude::{Solve, SolveLstsq};
use faer::{Mat, c64};

use super::inputs::{Imbalance, Measurements};
use super::model::{Direction, RotorModel};
use super::result::SpeedCoefficients;
use crate::tolerance::{FIELD_LS_RANK, FIELD_RESIDUAL_ROUNDING, FIELD_SINGULAR_PAIR};

/// Where the rotor's degrees of freedom go in the least-squares system: measured ones (their
/// probe index) and unknown ones (their column).
pub(super) struct Layout {
    /// Per degree of freedom: `Ok(probe)` if measured, `Err(column)` if unknown.
    place: Vec<std::result::Result<usize, usize>>,
    /// The measured degrees of freedom, in probe order.
    pub measured: Vec<usize>,
    /// The unknown degrees of freedom, in column order.
    pub unknown: Vec<usize>,
    /// Per bearing, its `x` and `y` degrees of freedom.
    bearing_dofs: Vec<[usize; 2]>,
}

impl Layout {
    pub fn new(rotor: &RotorModel, m: &Measurements) -> Layout {
        let n = rotor.dofs();
        let measured: Vec<usize> = m
            .probes
            .iter()
            .map(|p| rotor.lateral_dof(p.node, p.dir))
            .collect();
        let mut place = vec![Err(0); n];
        for (k, &d) in measured.iter().enumerate() {
            place[d] = Ok(k);
        }
        let mut unknown = Vec::with_capacity(n - measured.len());
        for (d, slot) in place.iter_mut().enumerate() {
            if slot.is_err() {
                *slot = Err(unknown.len());
                unknown.push(d);
            }
        }
        let bearing_dofs = rotor
            .bearings()
            .iter()
            .map(|b| {
                [
                    rotor.lateral_dof(b.node, Direction::X),
                    rotor.lateral_dof(b.node, Direction::Y),
                ]
            })
            .collect();
        Layout {
            place,
            measured,
            unknown,
            bearing_dofs,
        }
    }

    /// Columns of the least-squares system: the unknown degrees of freedom, then `x`, `y` of
    /// each bearing force.
    fn columns(&self) -> usize {
        self.unknown.len() + 2 * self.bearing_dofs.len()
    }
}

/// The result of one speed: the model residual and, per bearing, its condition number and
/// coefficients (`None` where the pair is singular). `None` altogether when the least-squares
/// system is rank-deficient at this speed.
pub(super) struct SpeedSolution {
    pub residual: f64,
    /// `‖r‖²` over what the stated response noise explains, `E‖r‖²` (see
    /// [`residual_ratio`]); `None` without standard deviations or without redundant probes.
    pub residual_ratio: Option<f64>,
    pub bearings: Vec<(f64, Option<SpeedCoefficients>)>,
}

/// The added imbalance forces of one test at `speed`, as a vector over all degrees of freedom.
pub(super) fn imbalance_forces(rotor: &RotorModel, set: &[Imbalance], speed: f64) -> Vec<c64> {
    let mut f = vec![c64::new(0.0, 0.0); rotor.dofs()];
    for u in set {
        let (fx, fy) = u.force(speed);
        f[rotor.lateral_dof(u.node, Direction::X)] += fx;
        f[rotor.lateral_dof(u.node, Direction::Y)] += fy;
    }
    f
}

/// Solves speed `s`: returns `None` when the column-scaled least-squares matrix is
/// rank-deficient there (ratio of the extreme diagonal entries of `R` above
/// [`FIELD_LS_RANK`]).
pub(super) fn solve_speed(
    rotor: &RotorModel,
    layout: &Layout,
    m: &Measurements,
    imbalances: &[Vec<Imbalance>; 2],
    s: usize,
) -> Option<SpeedSolution> {
    let speed = m.speeds[s];
    let n = rotor.dofs();
    let d = rotor.dynamic_stiffness(speed);
    let nu = layout.unknown.len();
    let ns = layout.measured.len();
    let cols = layout.columns();
    // A = [D_{:,U}  −P_B], columns scaled to unit norm.
    let mut a = Mat::<c64>::zeros(n, cols);
    for (j, &dof) in layout.unknown.iter().enumerate() {
        a.col_mut(j).copy_from(d.col(dof));
    }
    for (b, dofs) in layout.bearing_dofs.iter().enumerate() {
        for (k, &dof) in dofs.iter().enumerate() {
            a[(dof, nu + 2 * b + k)] = c64::new(-1.0, 0.0);
        }
    }
    let scale: Vec<f64> = (0..cols).map(|j| a.col(j).norm_l2()).collect();
    let scaled = Mat::from_fn(n, cols, |i, j| {
        if scale[j] > 0.0 {
            a[(i, j)] / scale[j]
        } else {
            a[(i, j)]
        }
    });
    let qr = scaled.qr();
    let r = qr.thin_R();
    let diag: Vec<f64> = (0..cols).map(|i| r[(i, i)].norm()).collect();
    let max = diag.iter().copied().fold(0.0, f64::max);
    let min = diag.iter().copied().fold(f64::INFINITY, f64::min);
    if !(min > 0.0 && max / min < FIELD_LS_RANK) {
        return None;
    }
    // Right-hand sides: the two tests, f_u − D_{:,S} Δq_S, then −D_{:,S} (sensitivities).
    let values = &m.values[s];
    let delta: [Vec<c64>; 2] = [1, 2].map(|t| {
        values[t]
            .iter()
            .zip(&values[0])
            .map(|(q, q0)| q - q0)
            .collect()
    });
    let mut rhs = Mat::<c64>::zeros(n, 2 + ns);
    for t in 0..2 {
        let f = imbalance_forces(rotor, &imbalances[t], speed);
        for i in 0..n {
            let mut v = f[i];
            for (k, &dof) in layout.measured.iter().enumerate() {
                v -= d[(i, dof)] * delta[t][k];
            }
            rhs[(i, t)] = v;
        }
    }
    for (k, &dof) in layout.measured.iter().enumerate() {
        for i in 0..n {
            rhs[(i, 2 + k)] = -d[(i, dof)];
        }
    }
    let mut x = qr.solve_lstsq(&rhs);
    for (j, &sc) in scale.iter().enumerate() {
        if sc > 0.0 {
            for c in 0..x.ncols() {
                x[(j, c)] /= sc;
            }
        }
    }
    // Model residual ‖A x − b‖ / ‖b‖ over both tests.
    let (mut res, mut norm) = (0.0, 0.0);
    for t in 0..2 {
        for i in 0..n {
            let mut v = -rhs[(i, t)];
            for j in 0..cols {
                v += a[(i, j)] * x[(j, t)];
            }
            res += v.norm_sqr();
            norm += rhs[(i, t)].norm_sqr();
        }
    }
    let residual = if norm > 0.0 { (res / norm).sqrt() } else { 0.0 };
    let residual_ratio = m
        .std
        .as_ref()
        .and_then(|sd| residual_ratio(&a, &x, &rhs, res, &sd[s]));
    // A displacement of degree of freedom `dof` in test `t` and its sensitivity row.
    let displacement = |dof: usize, t: usize| -> (c64, Vec<c64>) {
        match layout.place[dof] {
            Ok(k) => {
                let mut row = vec![c64::new(0.0, 0.0); ns];
                row[k] = c64::new(1.0, 0.0);
                (delta[t][k], row)
            }
            Err(j) => (x[(j, t)], (0..ns).map(|k| x[(j, 2 + k)]).collect()),
        }
    };
    let std = m.std.as_ref().map(|sd| &sd[s]);
    let bearings = (0..layout.bearing_dofs.len())
        .map(|b| {
            let dofs = layout.bearing_dofs[b];
            let mut q = [[c64::new(0.0, 0.0); 2]; 2];
            let mut f = [[c64::new(0.0, 0.0); 2]; 2];
            let mut lq: [Vec<c64>; 2] = Default::default();
            let mut lf: [Vec<c64>; 2] = Default::default();
            for dir in 0..2 {
                for t in 0..2 {
                    let (v, row) = displacement(dofs[dir], t);
                    q[dir][t] = v;
                    f[dir][t] = x[(nu + 2 * b + dir, t)];
                    if t == 0 {
                        lq[dir] = row;
                        lf[dir] = (0..ns).map(|k| x[(nu + 2 * b + dir, 2 + k)]).collect();
                    }
                }
            }
            let cond = condition_2x2(&q);
            if cond.is_nan() || cond > FIELD_SINGULAR_PAIR {
                return (cond, None);
            }
            let qinv = inverse_2x2(&q);
            // Z = −F Q⁻¹.
            let z: [[c64; 2]; 2] = std::array::from_fn(|i| {
                std::array::from_fn(|j| -(f[i][0] * qinv[0][j] + f[i][1] * qinv[1][j]))
            });
            let stiffness = z.map(|r| r.map(|v| v.re));
            let damping = z.map(|r| r.map(|v| v.im / speed));
            // δZ = W δΔ Q⁻¹ with W = −(L_f + Z L_q); δΔᵗ = δqᵗ − δq⁰.
            let w: [Vec<c64>; 2] = std::array::from_fn(|i| {
                (0..ns)
                    .map(|k| -(lf[i][k] + z[i][0] * lq[0][k] + z[i][1] * lq[1][k]))
                    .collect()
            });
            // Standard deviations of Z_ij (each of Re, Im) for per-response deviations `sd`.
            let propagate = |sd: &[Vec<f64>; 3]| -> [[f64; 2]; 2] {
                std::array::from_fn(|i| {
                    std::array::from_fn(|j| {
                        let (g1, g2) = (qinv[0][j], qinv[1][j]);
                        (0..ns)
                            .map(|k| {
                                w[i][k].norm_sqr()
                                    * (sd[1][k].powi(2) * g1.norm_sqr()
                                        + sd[2][k].powi(2) * g2.norm_sqr()
                                        + sd[0][k].powi(2) * (g1 + g2).norm_sqr())
                            })
                            .sum::<f64>()
                            .sqrt()
                    })
                })
            };
            let spread = std.map(propagate);
            // Noise gain: ‖σ_Z‖/‖Z‖ for a relative noise of 1 on every response.
            let unit: [Vec<f64>; 3] = std::array::from_fn(|r| {
                values[r]
                    .iter()
                    .map(|q| q.norm() / std::f64::consts::SQRT_2)
                    .collect()
            });
            let sz = propagate(&unit);
            let gain = (sz.iter().flatten().map(|v| 2.0 * v * v).sum::<f64>()
                / z.iter().flatten().map(|v| v.norm_sqr()).sum::<f64>())
            .sqrt();
            let coefficients = SpeedCoefficients {
                stiffness,
                damping,
                stiffness_std: spread,
                damping_std: spread.map(|s| s.map(|r| r.map(|v| v / speed))),
                noise_gain: gain,
            };
            let finite = stiffness
                .iter()
                .chain(&damping)
                .flatten()
                .all(|v| v.is_finite());
            (cond, finite.then_some(coefficients))
        })
        .collect();
    Some(SpeedSolution {
        residual,
        residual_ratio,
        bearings,
    })
}

/// The model residual of both tests, `res = ‖r¹‖² + ‖r²‖²`, over its expectation under the
/// stated response noise alone.
///
/// The residual of test `t` is linear in its measured differences `Δᵗ = qᵗ − q⁰`:
/// `rᵗ = r_f + Σ_k s_k Δᵗ_k` with `s_k = A x_k − b_k` the residual of the sensitivity
/// right-hand side `b_k = −D_{:,k}` (already solved). With independent circular noise of standard
/// deviation `σ` on each of `Re`, `Im` of every response (`E|δq|² = 2σ²`), an exact model gives
/// `E‖r¹‖² + E‖r²‖² = Σ_k ‖s_k‖² · 2 (σ¹_k² + σ²_k² + 2 σ⁰_k²)` (the baseline's noise enters both
/// differences). The ratio is about 1 when the model explains the measurements; it is `None`
/// when no probe is redundant (every `s_k = 0`: as many probes as the unknowns need, so the
/// residual is zero whatever the model).
fn residual_ratio(
    a: &Mat<c64>,
    x: &Mat<c64>,
    rhs: &Mat<c64>,
    res: f64,
    sd: &[Vec<f64>; 3],
) -> Option<f64> {
    let (n, cols) = (a.nrows(), a.ncols());
    let (mut expected, mut residuals, mut columns) = (0.0, 0.0, 0.0);
    for (k, ((s0, s1), s2)) in sd[0].iter().zip(&sd[1]).zip(&sd[2]).enumerate() {
        let c = 2 + k;
        let mut sk = 0.0;
        for i in 0..n {
            let mut v = -rhs[(i, c)];
            for j in 0..cols {
                v += a[(i, j)] * x[(j, c)];
            }
            sk += v.norm_sqr();
            columns += rhs[(i, c)].norm_sqr();
        }
        residuals += sk;
        expected += sk * 2.0 * (s1 * s1 + s2 * s2 + 2.0 * s0 * s0);
    }
    // Sensitivity residuals at rounding level: no probe is redundant, nothing to judge.
    let redundant = residuals > FIELD_RESIDUAL_ROUNDING * columns;
    (redundant && expected > 0.0).then(|| res / expected)
}

/// `σ_max / σ_min` of a complex 2×2 matrix: with `a = ‖Q‖_F²` and `d = |det Q|`,
/// `σ_max/σ_min + σ_min/σ_max = a/d`, so the ratio is `p + √(p² − 1)` with `p = a/(2d)`.
pub(super) fn condition_2x2(q: &[[c64; 2]; 2]) -> f64 {
    let a: f64 = q.iter().flatten().map(|v| v.norm_sqr()).sum();
    let det = (q[0][0] * q[1][1] - q[0][1] * q[1][0]).norm();
    if det.is_nan() || det <= 0.0 || !a.is_finite() {
        return f64::INFINITY;
    }
    let p = a / (2.0 * det);
    p + (p * p - 1.0).max(0.0).sqrt()
}

fn inverse_2x2(q: &[[c64; 2]; 2]) -> [[c64; 2]; 2] {
    let det = q[0][0] * q[1][1] - q[0][1] * q[1][0];
    [
        [q[1][1] / det, -q[0][1] / det],
        [-q[1][0] / det, q[0][0] / det],
    ]
}

/// Synchronous critical speeds (rad/s) of the undamped rotor pinned at the measured degrees of
/// freedom: `D_UU(Ω) = K_UU − Ω²(M_UU − iG_UU)` singular, so `Ω² = λ` with
/// `K_UU v = λ (M_UU − iG_UU) v`. Real positive `λ` only; damping is left out. Empty when the
/// pencil cannot be reduced (a singular `M_UU − iG_UU`) or the eigensolver fails.
pub(super) fn pinned_critical_speeds(rotor: &RotorModel, layout: &Layout) -> Vec<f64> {
    let u = &layout.unknown;
    let nu = u.len();
    if nu == 0 {
        return Vec::new();
    }
    let (m, k, g) = (rotor.mass(), rotor.stiffness(), rotor.gyroscopic());
    let b = Mat::from_fn(nu, nu, |i, j| c64::new(m[(u[i], u[j])], -g[(u[i], u[j])]));
    let kc = Mat::from_fn(nu, nu, |i, j| c64::new(k[(u[i], u[j])], 0.0));
    let a = b.partial_piv_lu().solve(&kc);
    if !(0..nu).all(|j| {
        a.col(j)
            .iter()
            .all(|v| v.re.is_finite() && v.im.is_finite())
    }) {
        return Vec::new();
    }
    let Ok(lambdas) = a.eigenvalues() else {
        return Vec::new();
    };
    // Rigid-body modes left free (axial, torsion) give λ = 0 up to rounding of the largest.
    let zero = 1e-12 * lambdas.iter().map(|l| l.norm()).fold(0.0, f64::max);
    let mut speeds: Vec<f64> = lambdas
        .into_iter()
        .filter(|l| l.re > zero && l.im.abs() <= 1e-6 * l.norm())
        .map(|l| l.re.sqrt())
        .collect();
    speeds.sort_by(f64::total_cmp);
    speeds
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn condition_of_2x2_matches_singular_values() {
        let q = [
            [c64::new(3.0, 0.0), c64::new(0.0, 0.0)],
            [c64::new(0.0, 0.0), c64::new(0.0, 0.5)],
        ];
        assert!((condition_2x2(&q) - 6.0).abs() < 1e-12);
        let circular = [
            [c64::new(1.0, 0.0), c64::new(2.0, 1.0)],
            [c64::new(0.0, -1.0), c64::new(1.0, -2.0)],
        ];
        assert!(condition_2x2(&circular).is_infinite() || condition_2x2(&circular) > 1e15);
    }
}
