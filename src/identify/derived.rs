//! Standard deviations of the derived quantities, natural frequencies and damping ratios,
//! to first order from the coefficients' covariance.
//!
//! # The maths
//! The modes are the eigenvalues λ of $A = \begin{bmatrix}0 & I\\ -M^{-1}K & -M^{-1}C
//! \end{bmatrix}$; with right eigenvectors `v` (the columns of `V`) and left eigenvectors `w`
//! (the rows of `V⁻¹`), a change `dA` moves λ by $d\lambda = w\,dA\,v$. Only `A`'s lower block
//! row depends on the coefficients: with $\alpha_a = \sum_i w_{n+i}(M^{-1})_{ia}$ and the halves
//! `v = [v_x; v_v]` of `v`,
//! $$\frac{\partial\lambda}{\partial K_{aj}} = -\alpha_a v_{x,j},\quad
//! \frac{\partial\lambda}{\partial C_{aj}} = -\alpha_a v_{v,j},\quad
//! \frac{\partial\lambda}{\partial M_{aj}} = -\alpha_a \lambda\, v_{v,j}$$
//! (the last from $M^{-1}(K v_x + C v_v) = -\lambda v_v$). Then
//! $f_n = |\lambda|/2\pi$, $\zeta = -\mathrm{Re}\,\lambda/|\lambda|$,
//! $d|\lambda| = \mathrm{Re}(\bar\lambda\, d\lambda)/|\lambda|$ and
//! $d\zeta = -\mathrm{Re}\,d\lambda/|\lambda| + \mathrm{Re}\,\lambda\; d|\lambda|/|\lambda|^2$;
//! each variance is $g^\top \mathrm{Cov}\, g$ summed over the columns of `Θ`, whose
//! covariances are independent in the fits' first-order model, plus, for each systematic
//! source given as a change `d` of the whole of `Θ` (a stated calibration's), $(g\cdot d)^2$:
//! such a change moves every coefficient at once, so its effects add before they are squared.

use faer::linalg::solvers::DenseSolveCore;
use faer::prelude::Solve;
use faer::{Mat, c64};
use std::f64::consts::PI;

use crate::error::{Error, Result};
use crate::model::Coefficients;
use crate::tolerance::OSCILLATORY_ROOT;

/// `(σ(f_n) in Hz, σ(ζ))` of every oscillatory mode of `c`, in the order of
/// [`Coefficients::modes`] (increasing natural frequency), from `covariance[j]`, the `3n × 3n`
/// covariance of column `j` of `Θ = [M; C; K]` (as [`Fit::covariance`](crate::Fit::covariance)),
/// and `directions`, each a `3n × n` change of the whole of `Θ` at one standard uncertainty of
/// an independent systematic source.
///
/// # Errors
/// [`Error::Singular`] if `M` or the eigenvector matrix is singular; [`Error::Decomposition`]
/// if the eigenvalue iteration fails.
pub(crate) fn mode_std(
    c: &Coefficients,
    covariance: &[Mat<f64>],
    directions: &[Mat<f64>],
) -> Result<Vec<(f64, f64)>> {
    let n = c.dofs();
    let lu = c.mass().partial_piv_lu();
    let minv = lu.inverse();
    if minv
        .col_iter()
        .flat_map(|c| c.iter())
        .any(|v| !v.is_finite())
    {
        return Err(Error::Singular {
            what: "mass matrix",
        });
    }
    let mk = lu.solve(c.stiffness());
    let mc = lu.solve(c.damping());
    let a = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(i == j - n)),
        (false, true) => -mk[(i - n, j)],
        (false, false) => -mc[(i - n, j - n)],
    });
    let eigen = a.eigen()?;
    let v = eigen.U().to_owned();
    let w = v.partial_piv_lu().inverse();
    if w.col_iter().flat_map(|c| c.iter()).any(|z| !z.is_finite()) {
        return Err(Error::Singular {
            what: "eigenvector matrix",
        });
    }
    let lambdas: Vec<c64> = eigen.S().column_vector().iter().copied().collect();
    let mut modes: Vec<usize> = (0..2 * n)
        .filter(|&k| lambdas[k].im > OSCILLATORY_ROOT * lambdas[k].norm())
        .collect();
    modes.sort_by(|&x, &y| lambdas[x].norm().total_cmp(&lambdas[y].norm()));
    Ok(modes
        .into_iter()
        .map(|k| {
            let l = lambdas[k];
            let r = l.norm();
            let alpha: Vec<c64> = (0..n)
                .map(|a| (0..n).map(|i| w[(k, n + i)] * minv[(i, a)]).sum())
                .collect();
            let (mut var_f, mut var_z) = (0.0, 0.0);
            // Each direction's first-order change of f_n and ζ, summed over the columns.
            let mut moved = vec![(0.0, 0.0); directions.len()];
            for (j, cov) in covariance.iter().enumerate() {
                // Gradients over column j's parameters M_aj, C_aj, K_aj (that order).
                let (mut gf, mut gz) = (vec![0.0; 3 * n], vec![0.0; 3 * n]);
                for a in 0..n {
                    let dl = [
                        -alpha[a] * l * v[(n + j, k)],
                        -alpha[a] * v[(n + j, k)],
                        -alpha[a] * v[(j, k)],
                    ];
                    for (t, d) in dl.into_iter().enumerate() {
                        let dr = (l.conj() * d).re / r;
                        gf[t * n + a] = dr / (2.0 * PI);
                        gz[t * n + a] = -d.re / r + l.re * dr / (r * r);
                    }
                }
                let quad = |g: &[f64]| {
                    (0..3 * n)
                        .flat_map(|p| (0..3 * n).map(move |q| (p, q)))
                        .map(|(p, q)| g[p] * cov[(p, q)] * g[q])
                        .sum::<f64>()
                };
                var_f += quad(&gf);
                var_z += quad(&gz);
                for (m, d) in moved.iter_mut().zip(directions) {
                    let dot = |g: &[f64]| (0..3 * n).map(|p| g[p] * d[(p, j)]).sum::<f64>();
                    m.0 += dot(&gf);
                    m.1 += dot(&gz);
                }
            }
            for (df, dz) in moved {
                var_f += df * df;
                var_z += dz * dz;
            }
            (var_f.max(0.0).sqrt(), var_z.max(0.0).sqrt())
        })
        .collect())
}

/// `covariance` rescaled so that its standard deviations are `std` (correlations kept);
/// without a covariance, a diagonal one of `std²`.
pub(crate) fn scaled_covariance(
    covariance: Option<&[Mat<f64>]>,
    std: &Coefficients,
) -> Vec<Mat<f64>> {
    let s = std.stacked();
    let p = s.nrows();
    (0..s.ncols())
        .map(|j| match covariance {
            Some(cov) => {
                let own = |q: usize| cov[j][(q, q)].max(0.0).sqrt();
                let factor = |q: usize| {
                    if own(q) > 0.0 {
                        s[(q, j)] / own(q)
                    } else {
                        0.0
                    }
                };
                Mat::from_fn(p, p, |a, b| {
                    if a == b && own(a) <= 0.0 {
                        s[(a, j)].powi(2)
                    } else {
                        cov[j][(a, b)] * factor(a) * factor(b)
                    }
                })
            }
            None => Mat::from_fn(p, p, |a, b| if a == b { s[(a, j)].powi(2) } else { 0.0 }),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Identifier;
    use crate::simulate::{ImpactTest, seed_rig};
    use rand::SeedableRng;
    use rand::rngs::StdRng;
    use rand_distr::{Distribution, StandardNormal};

    /// A stated gain, common or a channel's own, moves no mode: it multiplies the impedance
    /// by a constant diagonal matrix from the left (forces) or the right (responses), which
    /// scales `det Z(s)` by a constant and leaves its roots where they are. The first-order
    /// propagation of the gains' directions gives zero to rounding, on a coupled element
    /// where the rows and columns really scale differently.
    #[test]
    fn calibration_gains_move_no_mode() {
        use crate::identify::Calibration;
        let m = |v: [f64; 4]| Mat::from_fn(2, 2, |i, j| v[2 * i + j]);
        let c = Coefficients::new(
            m([10.0, 1.0, 0.5, 12.0]),
            m([400.0, 50.0, -30.0, 600.0]),
            m([1.0e6, 2.0e5, -1.0e5, 1.5e6]),
        )
        .unwrap();
        let zero = vec![Mat::<f64>::zeros(6, 6); 2];
        let modes = c.modes().unwrap();
        for calibration in [
            Calibration::default().force(0.02).response(0.03),
            Calibration::default()
                .force_channel(0, 0.02)
                .response_channel(1, 0.03),
        ] {
            let directions = calibration.directions(&c).unwrap();
            assert!(!directions.is_empty());
            let moved = mode_std(&c, &zero, &directions).unwrap();
            for ((sf, sz), mode) in moved.iter().zip(&modes) {
                assert!(*sf < 1e-12 * mode.natural_frequency_hz, "{sf:e}");
                assert!(*sz < 1e-12 * mode.damping_ratio, "{sz:e}");
            }
        }
    }

    /// First order against sampling: θ drawn from the fit's own covariance (column by column,
    /// through its Cholesky factor), the modes of each draw computed exactly; the sample
    /// standard deviations of `f_n` and `ζ` over 400 draws agree with the first-order ones
    /// within the sampling error (σ of a sample σ over 400 draws is 3.5 %; 12 % allowed).
    #[test]
    fn first_order_matches_sampling_from_the_covariance() {
        let truth = seed_rig();
        let records = ImpactTest {
            per_direction: 4,
            noise: 0.1,
            ..ImpactTest::seed_rig()
        }
        .run(&truth)
        .unwrap();
        let id = Identifier::new(8.0, 49.0).identify(&records).unwrap();
        let c = id.coefficients();
        let cov = id.fit().covariance().unwrap();
        let first = mode_std(c, cov, &[]).unwrap();
        let n = c.dofs();
        let theta = c.stacked();
        let factors: Vec<Mat<f64>> = cov
            .iter()
            .map(|m| m.llt(faer::Side::Lower).unwrap().L().to_owned())
            .collect();
        let mut rng = StdRng::seed_from_u64(7);
        let draws = 400;
        let mut samples = vec![Vec::new(); 2 * n];
        for _ in 0..draws {
            let drawn = Mat::from_fn(3 * n, n, |_, _| 0.0);
            let mut drawn = drawn;
            for j in 0..n {
                let z: Vec<f64> = (0..3 * n)
                    .map(|_| StandardNormal.sample(&mut rng))
                    .collect();
                for q in 0..3 * n {
                    drawn[(q, j)] =
                        theta[(q, j)] + (0..=q).map(|r| factors[j][(q, r)] * z[r]).sum::<f64>();
                }
            }
            let modes = Coefficients::from_stacked(drawn.as_ref())
                .unwrap()
                .modes()
                .unwrap();
            for (m, mode) in modes.iter().enumerate() {
                samples[2 * m].push(mode.natural_frequency_hz);
                samples[2 * m + 1].push(mode.damping_ratio);
            }
        }
        let sd = |v: &[f64]| {
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
        };
        assert_eq!(first.len(), 2);
        for (m, (sf, sz)) in first.iter().enumerate() {
            for (ours, sampled) in [(sf, sd(&samples[2 * m])), (sz, sd(&samples[2 * m + 1]))] {
                assert!(
                    (ours / sampled - 1.0).abs() < 0.12,
                    "mode {m}: first order {ours:.4e}, sampled {sampled:.4e}"
                );
            }
        }
    }
}
