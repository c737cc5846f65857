//! Small dense kernels shared by the stages: allocation-free inversion and products of the
//! n×n complex matrices that appear once per frequency line, and condition numbers.
//!
//! The per-line matrices are tiny (n is the number of degrees of freedom, 1–32 in practice) and
//! there are thousands of them, so they live in flat column-major slices owned by the caller and
//! are inverted in place by Gauss–Jordan elimination with partial pivoting, without touching the
//! heap. Anything larger goes through faer.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor::{lu_in_place, lu_in_place_scratch};
use faer::linalg::lu::partial_pivoting::inverse::{inverse, inverse_scratch};
use faer::linalg::svd::{ComputeSvdVectors, svd, svd_scratch};
use faer::{ColMut, MatMut, MatRef, Par, c64};

mod cofactors;
mod jacobi;

pub(crate) use cofactors::{LANES as SPLIT3_LANES, Split3, invert3_lanes, right_divide3};
use jacobi::{condition_numbers_in_lanes, singular_values_in_place};

/// The inverse of the column-major `3 × 3` complex `a` in place by cofactors,
/// $A^{-1} = \operatorname{adj}(A) / \det A$, formed on `A / s` with `s` the power of two at
/// or below its largest real or imaginary part (an exact scaling), so that the cofactors and
/// the determinant stay in range whatever the units; about a third of the Gauss–Jordan work
/// at this size. `None` (and `a` untouched) where `s` or `1/s` is not a normal number (zero,
/// huge, infinite or NaN entries); `Some(false)` if the determinant is zero or the inverse is
/// not finite (`a` is then unspecified).
#[inline(always)]
pub(crate) fn invert3(a: &mut [c64; 9]) -> Option<bool> {
    let largest = a
        .iter()
        .fold(0.0_f64, |m, z| m.max(z.re.abs()).max(z.im.abs()));
    // The power of two at or below `largest`: its exponent bits alone.
    let scale = f64::from_bits(largest.to_bits() & 0x7ff0_0000_0000_0000);
    if !(scale.is_normal() && (1.0 / scale).is_normal()) {
        return None;
    }
    let down = 1.0 / scale;
    let at = |i: usize, j: usize| a[i + 3 * j] * down;
    let (a00, a10, a20) = (at(0, 0), at(1, 0), at(2, 0));
    let (a01, a11, a21) = (at(0, 1), at(1, 1), at(2, 1));
    let (a02, a12, a22) = (at(0, 2), at(1, 2), at(2, 2));
    // The adjugate, column-major.
    let adj = [
        a11 * a22 - a12 * a21,
        a12 * a20 - a10 * a22,
        a10 * a21 - a11 * a20,
        a02 * a21 - a01 * a22,
        a00 * a22 - a02 * a20,
        a01 * a20 - a00 * a21,
        a01 * a12 - a02 * a11,
        a02 * a10 - a00 * a12,
        a00 * a11 - a01 * a10,
    ];
    let det = a00 * adj[0] + a01 * adj[1] + a02 * adj[2];
    if det == c64::new(0.0, 0.0) {
        return Some(false);
    }
    // (A/s)⁻¹ = s A⁻¹: the inverse is (A/s)⁻¹ / s.
    let factor = reciprocal(det) * down;
    let mut finite = true;
    for (dst, z) in a.iter_mut().zip(adj) {
        *dst = z * factor;
        finite &= dst.re.is_finite() && dst.im.is_finite();
    }
    Some(finite)
}

/// `1 / z = z̄ / |z|²`, through the squared modulus (no libm `hypot`) while `|z|²` is a
/// normal number, else without forming `|z|²`, which overflows for `|z|` beyond `1.3e154` (and
/// underflows below `1e-154`) where `num_complex`'s `inv` would give 0 or infinity.
pub(crate) fn reciprocal(z: c64) -> c64 {
    let r2 = z.norm_sqr();
    if r2.is_finite() && r2 >= f64::MIN_POSITIVE {
        return c64::new(z.re / r2, -z.im / r2);
    }
    let r = z.norm();
    let unit = c64::new(z.re / r, z.im / r);
    unit.conj() * (1.0 / r)
}

/// Row of the largest-modulus entry of `col` at or below row `from`, and that modulus
/// squared (or the modulus itself if squares leave the normal range, when they no longer
/// order the entries); the pivot search of [`invert_in_place`], which needs only the order
/// of the moduli, so no square root or `hypot` in the usual case.
#[inline(always)]
fn pivot(col: &[c64], from: usize) -> (usize, f64) {
    let mut p = from;
    let mut best = col[from].norm_sqr();
    for (i, z) in col.iter().enumerate().skip(from + 1) {
        let v = z.norm_sqr();
        if v > best {
            best = v;
            p = i;
        }
    }
    if best.is_finite() && best >= f64::MIN_POSITIVE {
        return (p, best);
    }
    // An entry beyond 1.3e154 (square infinite) or all below 1.5e-154 (squares subnormal
    // or zero): compare the moduli.
    p = from;
    best = col[from].norm();
    for (i, z) in col.iter().enumerate().skip(from + 1) {
        let v = z.norm();
        if v > best {
            best = v;
            p = i;
        }
    }
    (p, best)
}

/// Inverts the column-major `n × n` matrix in `a` in place by Gauss–Jordan elimination with
/// partial pivoting; `pivots` is caller-owned scratch of length `n`. This is the small-`n`
/// path of [`Inverter`], through which every caller goes.
///
/// Returns `false` (leaving `a` in an unspecified state) if a pivot is zero or the result is
/// not finite.
///
/// For `n ≤ 4` (the bearings' 1 to 4 degrees of freedom, thousands of lines each) the one
/// elimination below is compiled once per size with `n` a constant, so its loops unroll and
/// its bounds checks go: bit for bit the same operations in the same order as the general
/// path ([`invert_general`]), in 0.6 of its instructions at n = 3.
fn invert_in_place(a: &mut [c64], n: usize, pivots: &mut [usize]) -> bool {
    match n {
        1 => gauss_jordan(a, 1, pivots),
        2 => gauss_jordan(a, 2, pivots),
        3 => gauss_jordan(a, 3, pivots),
        4 => gauss_jordan(a, 4, pivots),
        _ => invert_general(a, n, pivots),
    }
}

/// [`invert_in_place`] for any `n`, `n` a run-time value (the path of `n > 4`; the
/// reference the fixed sizes are tested against).
#[inline(never)]
fn invert_general(a: &mut [c64], n: usize, pivots: &mut [usize]) -> bool {
    gauss_jordan(a, n, pivots)
}

/// The elimination of [`invert_in_place`], inlined into each caller so that a constant `n`
/// unrolls it.
#[inline(always)]
fn gauss_jordan(a: &mut [c64], n: usize, pivots: &mut [usize]) -> bool {
    debug_assert_eq!(a.len(), n * n);
    debug_assert!(pivots.len() >= n);
    // Slices of the known lengths, so that the indexing below needs no checks when `n` is
    // a constant.
    let (a, pivots) = (&mut a[..n * n], &mut pivots[..n]);
    for k in 0..n {
        let (p, best) = pivot(&a[k * n..(k + 1) * n], k);
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        pivots[k] = p;
        if p != k {
            for j in 0..n {
                a.swap(k + j * n, p + j * n);
            }
        }
        let inv = reciprocal(a[k + k * n]);
        a[k + k * n] = c64::new(1.0, 0.0);
        for j in 0..n {
            a[k + j * n] *= inv;
        }
        // Eliminate column k from every other row, column by column so that the inner loop
        // runs down a contiguous column (row k is saved and restored rather than skipped, so
        // the loop has no branch); column k, which holds the multipliers, is done last.
        for j in 0..n {
            if j == k {
                continue;
            }
            let akj = a[k + j * n];
            if akj == c64::new(0.0, 0.0) {
                continue;
            }
            let (col_k, col_j) = if k < j {
                let (left, right) = a.split_at_mut(j * n);
                (&left[k * n..k * n + n], &mut right[..n])
            } else {
                let (left, right) = a.split_at_mut(k * n);
                (&right[..n], &mut left[j * n..j * n + n])
            };
            let keep = col_j[k];
            for (x, &m) in col_j.iter_mut().zip(col_k) {
                *x -= m * akj;
            }
            col_j[k] = keep;
        }
        // Column k: a[i,k] ← −a[i,k]·a[k,k] (a[k,k] now holds 1/pivot).
        let akk = a[k + k * n];
        for x in &mut a[k * n..(k + 1) * n] {
            *x = -*x * akk;
        }
        a[k + k * n] = akk;
    }
    for k in (0..n).rev() {
        let p = pivots[k];
        if p != k {
            let (lo, hi) = (k.min(p), k.max(p));
            let (left, right) = a.split_at_mut(hi * n);
            left[lo * n..lo * n + n].swap_with_slice(&mut right[..n]);
        }
    }
    a.iter().all(|v| v.re.is_finite() && v.im.is_finite())
}

/// Largest size inverted by [`invert_in_place`]; larger matrices go through faer's blocked,
/// SIMD LU (Gauss–Jordan is faster up to n = 16, faer at n = 32: `ivf_iteration` bench).
const GAUSS_JORDAN_MAX: usize = 16;

/// Workspace for inverting many `n × n` complex matrices without allocating: Gauss–Jordan for
/// small `n`, faer's in-place LU and inverse beyond [`GAUSS_JORDAN_MAX`].
pub(crate) struct Inverter {
    n: usize,
    lu: Vec<c64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    stack: MemBuffer,
}

impl std::fmt::Debug for Inverter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Inverter")
            .field("n", &self.n)
            .finish_non_exhaustive()
    }
}

impl Inverter {
    pub(crate) fn new(n: usize) -> Self {
        let big = n > GAUSS_JORDAN_MAX;
        let stack = if big {
            lu_in_place_scratch::<usize, c64>(n, n, Par::Seq, Default::default())
                .or(inverse_scratch::<usize, c64>(n, Par::Seq))
        } else {
            faer::dyn_stack::StackReq::EMPTY
        };
        Self {
            n,
            lu: vec![c64::new(0.0, 0.0); if big { n * n } else { 0 }],
            perm: vec![0; n],
            perm_inv: vec![0; n],
            stack: MemBuffer::new(stack),
        }
    }

    /// [`Inverter::invert`], by cofactors for `n = 3` ([`invert3`]) where the scale of `a`
    /// allows: the same inverse to rounding, not bit for bit.
    pub(crate) fn invert_by_cofactors(&mut self, a: &mut [c64]) -> bool {
        if let Ok(a3) = <&mut [c64; 9]>::try_from(&mut *a) {
            if self.n == 3 {
                if let Some(regular) = invert3(a3) {
                    return regular;
                }
            }
        }
        self.invert(a)
    }

    /// Inverts the column-major `n × n` matrix in `a` in place. `false` if it is singular or
    /// the result is not finite (`a` is then unspecified).
    pub(crate) fn invert(&mut self, a: &mut [c64]) -> bool {
        let n = self.n;
        if n <= GAUSS_JORDAN_MAX {
            return invert_in_place(a, n, &mut self.perm);
        }
        self.lu.copy_from_slice(a);
        let stack = MemStack::new(&mut self.stack);
        let (_, perm) = lu_in_place(
            MatMut::from_column_major_slice_mut(&mut self.lu, n, n),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            stack,
            Default::default(),
        );
        let lu = MatRef::from_column_major_slice(&self.lu, n, n);
        inverse(
            MatMut::from_column_major_slice_mut(a, n, n),
            lu,
            lu,
            perm,
            Par::Seq,
            stack,
        );
        a.iter().all(|v| v.re.is_finite() && v.im.is_finite())
    }
}

/// `out = a · b` for column-major `n × n` complex matrices; unrolled for `n ≤ 4` (the same
/// operations in the same order, as [`invert_in_place`]).
pub(crate) fn mul_into(a: &[c64], b: &[c64], out: &mut [c64], n: usize) {
    match n {
        1 => product(a, b, out, 1),
        2 => product(a, b, out, 2),
        3 => product(a, b, out, 3),
        4 => product(a, b, out, 4),
        _ => product(a, b, out, n),
    }
}

/// The product of [`mul_into`], inlined so that a constant `n` unrolls it.
#[inline(always)]
fn product(a: &[c64], b: &[c64], out: &mut [c64], n: usize) {
    let (a, b, out) = (&a[..n * n], &b[..n * n], &mut out[..n * n]);
    for j in 0..n {
        for i in 0..n {
            let mut s = c64::new(0.0, 0.0);
            for k in 0..n {
                s += a[i + k * n] * b[k + j * n];
            }
            out[i + j * n] = s;
        }
    }
}

/// Condition number `σ_max / σ_min` of the column-major 2 × 2 complex matrix `a` whose
/// largest entry has modulus 1, in closed form from the Hermitian Gram matrix
/// $G = A^H A = \begin{pmatrix} g_{11} & g_{12} \\ \bar g_{12} & g_{22} \end{pmatrix}$:
/// $\lambda_+ = \bigl(g_{11} + g_{22} + \sqrt{(g_{11} - g_{22})^2 + 4|g_{12}|^2}\bigr)/2$
/// (a sum of non-negative terms, so no cancellation), $\lambda_+\lambda_- = |\det A|^2$, and
/// $\kappa = \sqrt{\lambda_+/\lambda_-} = \lambda_+ / |\det A|$. Its relative error is that
/// of `det A`, `ε·κ`, as for any backward-stable SVD.
fn condition_number_2x2(a: &[c64]) -> f64 {
    let (a11, a21, a12, a22) = (a[0], a[1], a[2], a[3]);
    let g11 = a11.norm_sqr() + a21.norm_sqr();
    let g22 = a12.norm_sqr() + a22.norm_sqr();
    let g12 = a11.conj() * a12 + a21.conj() * a22;
    let diff = g11 - g22;
    let lambda = 0.5 * (g11 + g22 + (diff * diff + 4.0 * g12.norm_sqr()).sqrt());
    let det = (a11 * a22 - a12 * a21).norm_sqr().sqrt();
    if det > 0.0 {
        lambda / det
    } else {
        f64::INFINITY
    }
}

/// Smallest `n` whose condition number comes from faer's singular values (bidiagonalisation
/// and QR sweeps) rather than one-sided Jacobi. Measured per matrix (release, one core,
/// well-conditioned complex matrices, workspaces reused): Jacobi 1.17 µs vs faer 3.57 µs at
/// n = 3, 2.14 vs 3.59 at n = 4, 12.3 vs 8.3 at n = 8, 76.7 vs 35.2 at n = 16.
const FAER_SVD_MIN: usize = 8;

/// Workspace for the condition numbers `σ_max / σ_min` of many `n × n` complex matrices
/// without allocating: n = 1 trivially, n = 2 in closed form from the eigenvalues of `AᴴA`,
/// `3 ≤ n < 8` by one-sided Jacobi, above by faer's SVD (singular values only) on a reused
/// [`MemBuffer`] (see [`FAER_SVD_MIN`] for the timings behind the split). No `hypot` in
/// any path for entries whose squares stay in the normal range.
pub(crate) struct Conditioner {
    n: usize,
    scratch: Vec<c64>,
    sigma: Vec<f64>,
    s: Vec<c64>,
    stack: MemBuffer,
}

impl std::fmt::Debug for Conditioner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Conditioner")
            .field("n", &self.n)
            .finish_non_exhaustive()
    }
}

impl Conditioner {
    pub(crate) fn new(n: usize) -> Self {
        let zero = c64::new(0.0, 0.0);
        let big = n >= FAER_SVD_MIN;
        let stack = if big {
            svd_scratch::<c64>(
                n,
                n,
                ComputeSvdVectors::No,
                ComputeSvdVectors::No,
                Par::Seq,
                Default::default(),
            )
        } else {
            faer::dyn_stack::StackReq::EMPTY
        };
        Self {
            n,
            scratch: vec![zero; n * n],
            sigma: vec![0.0; n],
            s: vec![zero; if big { n } else { 0 }],
            stack: MemBuffer::new(stack),
        }
    }

    /// Condition number `σ_max / σ_min` of the column-major `n × n` complex matrix `a` (`∞`
    /// when `σ_min = 0`, NaN if an entry is not finite or faer's SVD does not converge).
    pub(crate) fn condition_number(&mut self, a: &[c64]) -> f64 {
        let n = self.n;
        let a = &a[..n * n];
        // The condition number does not depend on scale; scaling to a largest entry of 1
        // keeps every square in range for entries anywhere in f64. The largest modulus comes
        // from the squared moduli (no `hypot`) unless those leave the normal range.
        let mut largest2 = 0.0_f64;
        let mut finite = true;
        for z in a {
            finite &= z.re.is_finite() && z.im.is_finite();
            largest2 = largest2.max(z.norm_sqr());
        }
        if !finite {
            return f64::NAN;
        }
        let largest = if largest2.is_finite() && largest2 >= f64::MIN_POSITIVE {
            largest2.sqrt()
        } else {
            // Entries beyond 1e154 or all below 1e-154: their squares leave the normal range.
            a.iter().fold(0.0, |m: f64, z| m.max(z.norm()))
        };
        if largest == 0.0 {
            return f64::INFINITY;
        }
        let scratch = &mut self.scratch[..n * n];
        for (dst, z) in scratch.iter_mut().zip(a) {
            *dst = c64::new(z.re / largest, z.im / largest);
        }
        let (max, min) = match n {
            1 => return 1.0,
            2 => return condition_number_2x2(scratch),
            _ if n < FAER_SVD_MIN => {
                let sigma = &mut self.sigma[..n];
                singular_values_in_place(scratch, n, sigma);
                return ratio(sigma.iter().copied());
            }
            _ => {
                let converged = svd(
                    MatRef::from_column_major_slice(scratch, n, n),
                    ColMut::from_slice_mut(&mut self.s).as_diagonal_mut(),
                    None,
                    None,
                    Par::Seq,
                    MemStack::new(&mut self.stack),
                    Default::default(),
                );
                if converged.is_err() {
                    return f64::NAN;
                }
                // Non-increasing, real and non-negative.
                (self.s[0].re, self.s[n - 1].re)
            }
        };
        extremes_ratio(max, min)
    }

    /// Condition numbers `σ_max / σ_min` of the `out.len()` column-major `n × n` complex
    /// matrices stored back to back in `a`, into `out`: each bit for bit what
    /// [`Conditioner::condition_number`] gives for it, faster. For `3 ≤ n < 8` the matrices go
    /// through one-sided Jacobi eight at a time, one per SIMD lane (see [`jacobi`]); matrices
    /// whose entries are not finite, or whose squared moduli leave the normal range, go one
    /// at a time. Other sizes loop over [`Conditioner::condition_number`]. No allocation.
    ///
    /// # Panics
    /// If `a.len() != out.len() · n²`.
    pub(crate) fn condition_numbers(&mut self, a: &[c64], out: &mut [f64]) {
        let n = self.n;
        assert_eq!(
            a.len(),
            out.len() * n * n,
            "{} matrices of {n} × {n} need {} entries",
            out.len(),
            out.len() * n * n
        );
        match n {
            3 => condition_numbers_in_lanes::<3>(self, a, out),
            4 => condition_numbers_in_lanes::<4>(self, a, out),
            5 => condition_numbers_in_lanes::<5>(self, a, out),
            6 => condition_numbers_in_lanes::<6>(self, a, out),
            7 => condition_numbers_in_lanes::<7>(self, a, out),
            _ => {
                for (m, o) in out.iter_mut().enumerate() {
                    *o = self.condition_number(&a[m * n * n..(m + 1) * n * n]);
                }
            }
        }
    }
}

/// `σ_max / σ_min` from singular values in any order (folded from 0 and from `∞`).
fn ratio(sigma: impl Iterator<Item = f64> + Clone) -> f64 {
    let max = sigma.clone().fold(0.0, f64::max);
    let min = sigma.fold(f64::INFINITY, f64::min);
    extremes_ratio(max, min)
}

/// `max / min`, `∞` when `min = 0` (and `max` finite), NaN otherwise.
fn extremes_ratio(max: f64, min: f64) -> f64 {
    if min > 0.0 {
        max / min
    } else if max.is_finite() {
        f64::INFINITY
    } else {
        f64::NAN
    }
}

/// Condition number `σ_max / σ_min` of a complex matrix by faer's singular values (`∞` when
/// `σ_min = 0`): the reference the Jacobi version is tested against.
#[cfg(test)]
fn condition_number(m: MatRef<'_, c64>) -> f64 {
    let s = m
        .singular_values()
        .expect("SVD converges on the test matrices");
    let (max, min) = (s[0], s[s.len() - 1]);
    if min > 0.0 { max / min } else { f64::INFINITY }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reciprocal_holds_over_the_whole_range() {
        for scale in [1e-300, 1e-160, 1.0, 1e160, 1e300] {
            let z = c64::new(3.0 * scale, -4.0 * scale);
            let w = reciprocal(z);
            let expected = c64::new(3.0, 4.0) / 25.0;
            assert!((w * scale - expected).norm() < 1e-15, "{scale:e}: {w}");
        }
    }
    use faer::Mat;

    /// The cofactor path is the Gauss–Jordan inverse to rounding for `n = 3`, at impedance
    /// scales and far beyond; other sizes, and a scale out of range, take Gauss–Jordan itself.
    #[test]
    fn cofactor_inverse_is_the_gauss_jordan_inverse() {
        for n in [2, 3, 4] {
            for scale in [1e-200, 1.0, 4e5, 1e200] {
                let a: Vec<c64> = (0..n * n)
                    .map(|q| {
                        let (i, j) = (q % n, q / n);
                        let d = if (i + 1) % n == j { 5.0 } else { 0.0 };
                        c64::new(
                            d + ((i * 7 + j * 3) % 11) as f64 * 0.1,
                            (i + j) as f64 * 0.2,
                        ) * scale
                    })
                    .collect();
                let (mut reference, mut fast) = (a.clone(), a.clone());
                assert!(Inverter::new(n).invert(&mut reference));
                assert!(Inverter::new(n).invert_by_cofactors(&mut fast));
                let largest = reference.iter().map(|z| z.norm()).fold(0.0, f64::max);
                let err = reference
                    .iter()
                    .zip(&fast)
                    .map(|(r, f)| (r - f).norm() / largest)
                    .fold(0.0, f64::max);
                assert!(err < 1e-14, "n = {n}, scale {scale:e}: {err:e}");
                if n != 3 {
                    assert_eq!(fast, reference);
                }
            }
        }
        let mut singular = [c64::new(1.0, 0.0); 9];
        assert!(!Inverter::new(3).invert_by_cofactors(&mut singular));
        let mut huge = [c64::new(f64::MAX, 0.0); 9];
        assert_eq!(invert3(&mut huge.clone()), None);
        assert!(!Inverter::new(3).invert_by_cofactors(&mut huge));
    }

    #[test]
    fn inverse_times_matrix_is_identity() {
        let n = 4;
        let m = Mat::<c64>::from_fn(n, n, |i, j| {
            c64::new(
                ((i * 7 + j * 3) % 5) as f64 - 1.5,
                (i as f64 - j as f64) * 0.3,
            )
        });
        let mut a: Vec<c64> = (0..n * n).map(|k| m[(k % n, k / n)]).collect();
        let mut piv = vec![0; n];
        assert!(invert_in_place(&mut a, n, &mut piv));
        let orig: Vec<c64> = (0..n * n).map(|k| m[(k % n, k / n)]).collect();
        let mut prod = vec![c64::new(0.0, 0.0); n * n];
        mul_into(&orig, &a, &mut prod, n);
        for i in 0..n {
            for j in 0..n {
                let expect = if i == j { 1.0 } else { 0.0 };
                assert!((prod[i + j * n] - c64::new(expect, 0.0)).norm() < 1e-12);
            }
        }
    }

    #[test]
    fn inverter_agrees_with_gauss_jordan_for_every_size() {
        for n in [1, 2, 5, 16, 17, 20, 32] {
            let a: Vec<c64> = (0..n * n)
                .map(|k| {
                    let (i, j) = (k % n, k / n);
                    let d = if i == j { 4.0 + i as f64 } else { 0.0 };
                    c64::new(
                        d + ((i * 7 + j * 3) % 5) as f64 * 0.3,
                        (i as f64 - j as f64) * 0.1,
                    )
                })
                .collect();
            let mut gj = a.clone();
            assert!(invert_in_place(&mut gj, n, &mut vec![0; n]));
            let mut inv = Inverter::new(n);
            let mut ours = a.clone();
            assert!(inv.invert(&mut ours));
            let err = gj
                .iter()
                .zip(&ours)
                .map(|(x, y)| (x - y).norm())
                .fold(0.0, f64::max);
            assert!(err < 1e-12, "n = {n}: {err:e}");
        }
        let mut singular = vec![c64::new(1.0, 0.0); 17 * 17];
        assert!(!Inverter::new(17).invert(&mut singular));
    }

    #[test]
    fn singular_matrix_is_refused() {
        let mut a = vec![
            c64::new(1.0, 0.0),
            c64::new(2.0, 0.0),
            c64::new(2.0, 0.0),
            c64::new(4.0, 0.0),
        ];
        assert!(!invert_in_place(&mut a, 2, &mut [0, 0]));
    }

    #[test]
    fn jacobi_singular_values_match_faer() {
        for n in 1..=6 {
            let m = Mat::<c64>::from_fn(n, n, |i, j| {
                c64::new(
                    ((i * 7 + j * 3 + n) % 5) as f64 - 1.7,
                    ((i + 2 * j) % 3) as f64 * 0.4 - 0.2,
                )
            });
            let a: Vec<c64> = (0..n * n).map(|k| m[(k % n, k / n)]).collect();
            let ours = Conditioner::new(n).condition_number(&a);
            let theirs = condition_number(m.as_ref());
            assert!(
                (ours / theirs - 1.0).abs() < 1e-10,
                "n = {n}: {ours} vs {theirs}"
            );
        }
        // Rank-deficient: two equal columns.
        let a = vec![
            c64::new(1.0, 1.0),
            c64::new(2.0, 0.0),
            c64::new(1.0, 1.0),
            c64::new(2.0, 0.0),
        ];
        let c = Conditioner::new(2).condition_number(&a);
        assert!(c > 1e15);
    }

    /// A random complex matrix `U diag(σ) Vᴴ` with condition number about `kappa` (singular
    /// values spaced geometrically from 1 to `1/kappa`), column-major.
    pub(super) fn with_condition(n: usize, kappa: f64, rng: &mut impl rand::Rng) -> Vec<c64> {
        let sigma: Vec<f64> = (0..n)
            .map(|i| {
                let exponent = if n > 1 {
                    i as f64 / (n - 1) as f64
                } else {
                    0.0
                };
                kappa.powf(-exponent)
            })
            .collect();
        with_singular_values(&sigma, rng)
    }

    /// A random complex matrix `U diag(σ) Vᴴ` from random unitary `U`, `V` (QR of Gaussian
    /// matrices), column-major.
    pub(super) fn with_singular_values(sigma: &[f64], rng: &mut impl rand::Rng) -> Vec<c64> {
        use rand_distr::{Distribution, StandardNormal};
        let n = sigma.len();
        let mut gaussian = || -> f64 { StandardNormal.sample(&mut *rng) };
        let mut unitary = || {
            let g = Mat::<c64>::from_fn(n, n, |_, _| c64::new(gaussian(), gaussian()));
            g.qr().compute_Q()
        };
        let (u, v) = (unitary(), unitary());
        let s = Mat::<c64>::from_fn(n, n, |i, j| {
            c64::new(if i == j { sigma[i] } else { 0.0 }, 0.0)
        });
        let a = &u * &s * v.adjoint();
        (0..n * n).map(|k| a[(k % n, k / n)]).collect()
    }

    fn ours(a: &[c64], n: usize) -> f64 {
        Conditioner::new(n).condition_number(a)
    }

    fn faer_condition(a: &[c64], n: usize) -> f64 {
        condition_number(MatRef::from_column_major_slice(a, n, n))
    }

    #[test]
    fn closed_form_and_jacobi_match_faer_svd_on_random_matrices() {
        use rand::SeedableRng;
        let mut rng = rand::rngs::StdRng::seed_from_u64(12);
        for n in 1..=6 {
            for kappa in [1.0, 1.5, 10.0, 1e3] {
                for _ in 0..50 {
                    let a = with_condition(n, kappa, &mut rng);
                    let (ours, theirs) = (ours(&a, n), faer_condition(&a, n));
                    assert!(
                        (ours / theirs - 1.0).abs() < 1e-12,
                        "n = {n}, κ ≈ {kappa:e}: {ours} vs {theirs}"
                    );
                }
            }
        }
    }

    /// The faer path (n ≥ 8) against the Jacobi routine on the same matrices and against the
    /// condition number they were built with.
    #[test]
    fn faer_path_matches_jacobi_and_the_constructed_condition() {
        use rand::SeedableRng;
        let mut rng = rand::rngs::StdRng::seed_from_u64(15);
        for n in [8, 11, 16, 24] {
            let mut jacobi = vec![0.0; n];
            for kappa in [1.0, 10.0, 1e3] {
                for _ in 0..10 {
                    let a = with_condition(n, kappa, &mut rng);
                    let ours = ours(&a, n);
                    let mut scratch = a.clone();
                    singular_values_in_place(&mut scratch, n, &mut jacobi);
                    let max = jacobi.iter().cloned().fold(0.0, f64::max);
                    let min = jacobi.iter().cloned().fold(f64::INFINITY, f64::min);
                    assert!(
                        (ours / (max / min) - 1.0).abs() < 1e-12,
                        "n = {n}, κ ≈ {kappa:e}: {ours} vs Jacobi {}",
                        max / min
                    );
                    assert!(
                        (ours / kappa - 1.0).abs() < 1e-12,
                        "n = {n}: {ours} vs constructed {kappa}"
                    );
                }
            }
            // Rank-deficient (two equal columns), zero and non-finite.
            let mut a = with_condition(n, 3.0, &mut rng);
            let (first, rest) = a.split_at_mut(n);
            rest[..n].copy_from_slice(first);
            assert!(ours(&a, n) > 1e14, "n = {n}: {}", ours(&a, n));
            assert!(ours(&vec![c64::new(0.0, 0.0); n * n], n).is_infinite());
            a[n * n - 1] = c64::new(f64::NAN, 0.0);
            assert!(ours(&a, n).is_nan());
            a[n * n - 1] = c64::new(f64::INFINITY, 0.0);
            assert!(ours(&a, n).is_nan());
        }
    }

    /// The pivot search compares squared moduli, and the moduli when squares leave the normal
    /// range: the inverse of `s·A` is `A⁻¹/s` over the whole exponent range.
    #[test]
    fn inversion_is_scale_free_over_the_whole_range() {
        let n = 4;
        let a: Vec<c64> = (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                c64::new(
                    ((i * 7 + j * 3) % 5) as f64 - 1.5,
                    (i as f64 - j as f64) * 0.3,
                )
            })
            .collect();
        let mut reference = a.clone();
        assert!(invert_in_place(&mut reference, n, &mut vec![0; n]));
        for scale in [1e-300, 1e-160, 1e-150, 1e150, 1e160, 1e300] {
            let mut scaled: Vec<c64> = a.iter().map(|z| z * scale).collect();
            assert!(
                invert_in_place(&mut scaled, n, &mut vec![0; n]),
                "{scale:e}"
            );
            let err = scaled
                .iter()
                .zip(&reference)
                .map(|(x, y)| (x * scale - y).norm() / y.norm().max(1.0))
                .fold(0.0, f64::max);
            assert!(err < 1e-13, "{scale:e}: {err:e}");
        }
    }

    /// The unrolled sizes (n ≤ 4) are the general elimination and product bit for bit, on
    /// random well- and ill-conditioned matrices.
    #[test]
    fn fixed_sizes_are_the_general_kernels_bit_for_bit() {
        use rand::SeedableRng;
        let mut rng = rand::rngs::StdRng::seed_from_u64(16);
        let bits = |m: &[c64]| -> Vec<(u64, u64)> {
            m.iter().map(|z| (z.re.to_bits(), z.im.to_bits())).collect()
        };
        for n in 1..=4 {
            for kappa in [1.0, 10.0, 1e8, 1e12] {
                for _ in 0..20 {
                    let a = with_condition(n, kappa, &mut rng);
                    let (mut fixed, mut general) = (a.clone(), a.clone());
                    assert!(invert_in_place(&mut fixed, n, &mut vec![0; n]));
                    assert!(invert_general(&mut general, n, &mut vec![0; n]));
                    assert_eq!(bits(&fixed), bits(&general), "n = {n}, κ ≈ {kappa:e}");
                    let b = with_condition(n, 3.0, &mut rng);
                    let zero = c64::new(0.0, 0.0);
                    let (mut ours, mut reference) = (vec![zero; n * n], vec![zero; n * n]);
                    mul_into(&a, &b, &mut ours, n);
                    // The general product: `n` not known to the compiler.
                    product(&a, &b, &mut reference, std::hint::black_box(n));
                    assert_eq!(bits(&ours), bits(&reference), "n = {n}");
                }
            }
        }
    }

    /// The unrolled inverses against faer's LU inverse: to a few ε·κ relative to `‖A⁻¹‖`.
    #[test]
    fn fixed_size_inverses_match_faer() {
        use faer::linalg::solvers::DenseSolveCore;
        use rand::SeedableRng;
        let mut rng = rand::rngs::StdRng::seed_from_u64(17);
        for n in 1..=4 {
            for kappa in [1.0, 1.5, 10.0, 1e3, 1e8, 1e12] {
                for _ in 0..20 {
                    let a = with_condition(n, kappa, &mut rng);
                    let mut ours = a.clone();
                    assert!(Inverter::new(n).invert(&mut ours));
                    let theirs = MatRef::from_column_major_slice(&a, n, n)
                        .partial_piv_lu()
                        .inverse();
                    let ours = MatRef::from_column_major_slice(&ours, n, n);
                    let err = (ours - &theirs).norm_l2() / theirs.norm_l2();
                    let bound = 64.0 * f64::EPSILON * kappa;
                    assert!(err < bound, "n = {n}, κ ≈ {kappa:e}: {err:e}");
                }
            }
        }
    }

    /// Singular and non-finite matrices are refused at every unrolled size, as before.
    #[test]
    fn fixed_sizes_refuse_singular_and_non_finite_matrices() {
        use rand::SeedableRng;
        let mut rng = rand::rngs::StdRng::seed_from_u64(18);
        let zero = c64::new(0.0, 0.0);
        for n in 1..=4 {
            let mut inverter = Inverter::new(n);
            assert!(!inverter.invert(&mut vec![zero; n * n]), "n = {n}: zero");
            for column in 0..n {
                // A zero column: exactly singular, whichever step meets it.
                let mut a = with_condition(n, 2.0, &mut rng);
                a[column * n..(column + 1) * n].fill(zero);
                let mut general = a.clone();
                assert!(!inverter.invert(&mut a), "n = {n}: column {column} zero");
                assert!(!invert_general(&mut general, n, &mut vec![0; n]));
            }
            // Exactly dependent columns (small integers: the elimination is exact).
            let mut a: Vec<c64> = (0..n * n)
                .map(|k| c64::new(((k % n) * 2 + 1) as f64, 0.0))
                .collect();
            assert!(n == 1 || !inverter.invert(&mut a), "n = {n}: equal columns");
            for bad in [f64::NAN, f64::INFINITY] {
                let mut a = with_condition(n, 2.0, &mut rng);
                a[n * n - 1] = c64::new(bad, 0.0);
                assert!(!inverter.invert(&mut a), "n = {n}: {bad}");
            }
        }
    }

    #[test]
    fn ill_conditioned_matrices_are_within_rounding_of_faer() {
        use rand::SeedableRng;
        let mut rng = rand::rngs::StdRng::seed_from_u64(13);
        for n in 2..=4 {
            for kappa in [1e8, 1e12] {
                for _ in 0..20 {
                    let a = with_condition(n, kappa, &mut rng);
                    let (ours, theirs) = (ours(&a, n), faer_condition(&a, n));
                    // Both carry a relative error of order ε·κ (the smallest singular value
                    // is known to ε·σ_max only).
                    let bound = 64.0 * f64::EPSILON * kappa;
                    assert!(
                        (ours / theirs - 1.0).abs() < bound,
                        "n = {n}, κ ≈ {kappa:e}: {ours} vs {theirs}"
                    );
                }
            }
        }
    }

    #[test]
    fn scale_does_not_matter_and_bad_input_is_flagged() {
        use rand::SeedableRng;
        let mut rng = rand::rngs::StdRng::seed_from_u64(14);
        for n in 1..=4 {
            let a = with_condition(n, 7.0, &mut rng);
            let reference = ours(&a, n);
            for scale in [1e-300, 1e-160, 1e160, 1e300] {
                let scaled: Vec<c64> = a.iter().map(|z| z * scale).collect();
                let c = ours(&scaled, n);
                assert!(
                    (c / reference - 1.0).abs() < 1e-12,
                    "n = {n}, {scale:e}: {c}"
                );
            }
            let zero = vec![c64::new(0.0, 0.0); n * n];
            assert!(ours(&zero, n).is_infinite());
            let mut bad = a.clone();
            bad[n * n - 1] = c64::new(f64::NAN, 0.0);
            assert!(ours(&bad, n).is_nan());
            bad[n * n - 1] = c64::new(0.0, f64::INFINITY);
            assert!(ours(&bad, n).is_nan());
        }
        // Exactly dependent columns: σ_min = 0.
        let a = [
            c64::new(1.0, 1.0),
            c64::new(2.0, 0.0),
            c64::new(2.0, 2.0),
            c64::new(4.0, 0.0),
        ];
        assert!(ours(&a, 2).is_infinite());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]
        #[test]
        fn two_by_two_closed_form_matches_faer(
            entries in proptest::collection::vec(-1.0e3..1.0e3_f64, 8),
        ) {
            let a: Vec<c64> = entries.chunks(2).map(|p| c64::new(p[0], p[1])).collect();
            let (ours, theirs) = (ours(&a, 2), faer_condition(&a, 2));
            let bound = 64.0 * f64::EPSILON * theirs.max(1.0);
            proptest::prop_assert!((ours / theirs - 1.0).abs() < bound, "{} vs {}", ours, theirs);
        }
    }

    #[test]
    fn condition_number_of_diagonal() {
        let m = Mat::<c64>::from_fn(2, 2, |i, j| {
            if i == j {
                c64::new(if i == 0 { 10.0 } else { 0.5 }, 0.0)
            } else {
                c64::new(0.0, 0.0)
            }
        });
        assert!((condition_number(m.as_ref()) - 20.0).abs() < 1e-12);
    }
}
