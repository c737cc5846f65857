//! The small least-squares solver of stepped sine: normal equations of 3 or 4 unknowns,
//! Jacobi-scaled and solved by Gaussian elimination with partial pivoting, and the fit of a
//! sine and an offset at a known frequency ([`fit_sine`]).

use crate::records::finite_positive;

/// Smallest pivot of the Jacobi-scaled normal equations (a correlation matrix) accepted: below
/// it (a condition number above about `10⁸`) the sine, cosine and offset are too nearly
/// dependent over the record (frequency near DC or Nyquist, or far less than a period of data)
/// to be told apart.
const MIN_PIVOT: f64 = 1e-8;

/// Adds one row `u` (target `r`) to the normal equations: the upper triangle of the row-major
/// `k × k` Gram matrix gets `u uᵀ`, the right-hand side `u r`.
pub(super) fn accumulate(gram: &mut [f64], rhs: &mut [f64], u: &[f64], r: f64) {
    let k = u.len();
    for i in 0..k {
        for j in i..k {
            gram[i * k + j] += u[i] * u[j];
        }
        rhs[i] += u[i] * r;
    }
}

/// Copies the upper triangle of the row-major `k × k` matrix `a` into its lower triangle.
pub(super) fn symmetrise(a: &mut [f64], k: usize) {
    for i in 0..k {
        for j in 0..i {
            a[i * k + j] = a[j * k + i];
        }
    }
}

/// Solves the symmetric positive semi-definite `k × k` system `a x = b` (`a` row-major, both
/// destroyed, `x` left in `b`) after scaling it to unit diagonal; `false` if a pivot of the
/// scaled system falls below [`MIN_PIVOT`].
pub(super) fn solve_normal(a: &mut [f64], b: &mut [f64], k: usize) -> bool {
    let scale: Vec<f64> = (0..k).map(|i| a[i * k + i].sqrt()).collect();
    if scale.iter().any(|s| !finite_positive(*s)) {
        return false;
    }
    for i in 0..k {
        for j in 0..k {
            a[i * k + j] /= scale[i] * scale[j];
        }
        b[i] /= scale[i];
    }
    for c in 0..k {
        let p = (c..k)
            .max_by(|&i, &j| a[i * k + c].abs().total_cmp(&a[j * k + c].abs()))
            .unwrap_or(c);
        if a[p * k + c].abs() < MIN_PIVOT {
            return false;
        }
        if p != c {
            for j in 0..k {
                a.swap(p * k + j, c * k + j);
            }
            b.swap(p, c);
        }
        for i in c + 1..k {
            let factor = a[i * k + c] / a[c * k + c];
            for j in c..k {
                a[i * k + j] -= factor * a[c * k + j];
            }
            b[i] -= factor * b[c];
        }
    }
    for c in (0..k).rev() {
        let mut s = b[c];
        for j in c + 1..k {
            s -= a[c * k + j] * b[j];
        }
        b[c] = s / a[c * k + c];
    }
    for i in 0..k {
        b[i] /= scale[i];
    }
    b.iter().all(|v| v.is_finite())
}

/// Least-squares fit of `a cos(w m) + b sin(w m) + d` to `signal` (`w` in radians per sample):
/// `[a, b, d]` and the residual sum of squares, `None` if the three are not separable.
pub(super) fn fit_sine(signal: &[f64], w: f64) -> Option<([f64; 3], f64)> {
    let mut gram = [0.0; 9];
    let mut rhs = [0.0; 3];
    for (m, &x) in signal.iter().enumerate() {
        let (s, c) = (w * m as f64).sin_cos();
        accumulate(&mut gram, &mut rhs, &[c, s, 1.0], x);
    }
    symmetrise(&mut gram, 3);
    if !solve_normal(&mut gram, &mut rhs, 3) {
        return None;
    }
    let rss = signal
        .iter()
        .enumerate()
        .map(|(m, &x)| {
            let (s, c) = (w * m as f64).sin_cos();
            (x - rhs[0] * c - rhs[1] * s - rhs[2]).powi(2)
        })
        .sum();
    Some((rhs, rss))
}
