//! The matrix exponential that advances the simulator from sample to sample.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

/// Matrix exponential by scaling and squaring with a 16-term Taylor series
/// (truncation below `10⁻²⁰` after scaling to norm ≤ 1/2).
pub(crate) fn expm(a: &Mat<f64>) -> Mat<f64> {
    let d = a.nrows();
    let norm = (0..d)
        .map(|i| (0..d).map(|j| a[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let squarings = if norm > 0.5 {
        (norm / 0.5).log2().ceil() as u32
    } else {
        0
    };
    // 2^-squarings as f64: an integer power of two overflows past 31 squarings (a fast filter
    // at a high sampling rate).
    let scale = 0.5f64.powi(squarings.min(2000) as i32);
    let scaled = Mat::from_fn(d, d, |i, j| a[(i, j)] * scale);
    let mut result = Mat::<f64>::identity(d, d);
    let mut term = Mat::<f64>::identity(d, d);
    let mut next = Mat::<f64>::zeros(d, d);
    for k in 1..=16 {
        matmul(
            next.as_mut(),
            Accum::Replace,
            term.as_ref(),
            scaled.as_ref(),
            1.0 / k as f64,
            Par::Seq,
        );
        std::mem::swap(&mut term, &mut next);
        result += &term;
    }
    for _ in 0..squarings {
        matmul(
            next.as_mut(),
            Accum::Replace,
            result.as_ref(),
            result.as_ref(),
            1.0,
            Par::Seq,
        );
        std::mem::swap(&mut result, &mut next);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn expm_of_rotation_generator() {
        let a = mat![[0.0, 2.0], [-2.0, 0.0]];
        let e = expm(&a);
        assert!((e[(0, 0)] - 2f64.cos()).abs() < 1e-14);
        assert!((e[(0, 1)] - 2f64.sin()).abs() < 1e-14);
    }
}
