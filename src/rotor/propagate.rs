//! First-order propagation of the coefficients' covariance to a scalar derived from them.

use faer::Mat;

use crate::model::Coefficients;

/// The first-order standard deviation of `f(θ)`, `σ² = gᵀ Σ g` with `g = ∂f/∂θ` by central
/// differences, `θ` the stacked coefficients `[M; C; K]` (`3n × n`) read column by column
/// (index `j·3n + q` for row `q` of column `j`, the order of
/// [`Identification::covariance`](crate::Identification::covariance)) and `Σ` their
/// covariance. Each step is `10⁻⁶` of the coefficient's own magnitude, or of the largest
/// of its block (`M`, `C` or `K`) when it is zero. `None` when `f` is not finite at a step
/// or `Σ` is not of the size of `θ`.
///
/// # Examples
/// ```
/// use bearing_ident::Coefficients;
/// use bearing_ident::faer::Mat;
/// use bearing_ident::rotor::propagated_std;
/// let c = Coefficients::new(Mat::zeros(1, 1), Mat::from_fn(1, 1, |_, _| 10.0),
///     Mat::from_fn(1, 1, |_, _| 1e4))?;
/// // σ(C) = 1, σ(K) = 100, uncorrelated: K/C has σ = 1000·√(0.01² + 0.1²).
/// let cov = Mat::from_fn(3, 3, |a, b| if a != b { 0.0 } else { [0.0, 1.0, 1e4][a] });
/// let s = propagated_std(&c, &cov, |c| Some(c.stiffness()[(0, 0)] / c.damping()[(0, 0)]));
/// assert!((s.unwrap() / (1000.0 * (0.01f64.powi(2) + 0.1f64.powi(2)).sqrt()) - 1.0).abs() < 1e-6);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn propagated_std(
    coefficients: &Coefficients,
    covariance: &Mat<f64>,
    f: impl Fn(&Coefficients) -> Option<f64>,
) -> Option<f64> {
    let theta = coefficients.stacked();
    let (rows, n) = (theta.nrows(), theta.ncols());
    let p = rows * n;
    if covariance.nrows() != p || covariance.ncols() != p {
        return None;
    }
    let block_scale = |q: usize| {
        let block = q / n.max(1);
        (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| theta[(block * n + i, j)].abs())
            .fold(0.0, f64::max)
    };
    let at = |q: usize, j: usize, h: f64| {
        let mut moved = theta.clone();
        moved[(q, j)] += h;
        Coefficients::from_stacked(moved.as_ref())
            .ok()
            .and_then(|c| f(&c))
            .filter(|v| v.is_finite())
    };
    let mut gradient = vec![0.0; p];
    for j in 0..n {
        for q in 0..rows {
            let index = j * rows + q;
            if (0..p).all(|b| covariance[(index, b)] == 0.0) {
                continue;
            }
            let own = theta[(q, j)].abs();
            let scale = if own > 0.0 { own } else { block_scale(q) };
            let h = 1e-6 * if scale > 0.0 { scale } else { 1.0 };
            gradient[index] = (at(q, j, h)? - at(q, j, -h)?) / (2.0 * h);
        }
    }
    let variance: f64 = (0..p)
        .flat_map(|a| (0..p).map(move |b| (a, b)))
        .map(|(a, b)| gradient[a] * covariance[(a, b)] * gradient[b])
        .sum();
    Some(variance.max(0.0).sqrt())
}
