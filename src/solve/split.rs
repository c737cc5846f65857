//! The IVF's per-line complex `n × n` kernels in split storage: a matrix is two column-major
//! slices, its real parts and its imaginary parts, so that a complex multiply-add down a
//! column is four real fused multiply-adds on whole SIMD registers (no shuffles). The kernels
//! are generic over faer's SIMD layer (`pulp`, reached as `faer::traits::pulp`) and run inside
//! one [`Arch::dispatch`] per pass over the lines, so they compile to AVX2 + FMA where the CPU
//! has it (with a scalar fallback); columns are vectorised, the rows past the last full
//! register are done in scalar.
//!
//! - [`impedance`]: $H = K - \omega^2 M + i\omega C$ from contiguous `M`, `C`, `K`;
//! - [`invert`]: Gauss–Jordan with partial pivoting, the algorithm (and pivot rule) of
//!   `linalg::Inverter`'s small-`n` path, `8n³` flops;
//! - [`invert3`]: the `3 × 3` inverse by cofactors, on the matrix scaled exactly by a power
//!   of two (the IVF's three-degree-of-freedom path);
//! - [`mul`]: $X Y$ or $X \bar Y$ column by column, `X`'s columns weighted by `Y`'s entries,
//!   the accumulators of up to four registers of a column held in registers, `8n³` flops.

pub(super) use faer::traits::pulp::{Arch, Simd, WithSimd};

use faer::c64;

use crate::linalg::{self, reciprocal};

/// `h = K − ω² M + iω C` (split, `n²` each) from the contiguous column-major blocks.
#[inline(always)]
pub(super) fn impedance<S: Simd>(
    simd: S,
    (h_re, h_im): (&mut [f64], &mut [f64]),
    (m, c, k): (&[f64], &[f64], &[f64]),
    w: f64,
) {
    let (w2, ww) = (simd.splat_f64s(-w * w), simd.splat_f64s(w));
    let (hr, hr_tail) = S::as_mut_simd_f64s(h_re);
    let (hi, hi_tail) = S::as_mut_simd_f64s(h_im);
    let (mv, m_tail) = S::as_simd_f64s(m);
    let (cv, c_tail) = S::as_simd_f64s(c);
    let (kv, k_tail) = S::as_simd_f64s(k);
    for ((((hr, hi), &m), &c), &k) in hr.iter_mut().zip(hi.iter_mut()).zip(mv).zip(cv).zip(kv) {
        *hr = simd.mul_add_f64s(m, w2, k);
        *hi = simd.mul_f64s(c, ww);
    }
    for ((((hr, hi), &m), &c), &k) in hr_tail
        .iter_mut()
        .zip(hi_tail.iter_mut())
        .zip(m_tail)
        .zip(c_tail)
        .zip(k_tail)
    {
        *hr = k - w * w * m;
        *hi = w * c;
    }
}

/// The `3 × 3` split matrix inverted in place by [`linalg::invert3`]'s cofactors (the same
/// operations): `None` (and `a` untouched) where its scale is not a normal number,
/// `Some(false)` if it is singular or the inverse is not finite.
#[inline(always)]
pub(super) fn invert3((re, im): (&mut [f64], &mut [f64])) -> Option<bool> {
    let (re, im) = (&mut re[..9], &mut im[..9]);
    let mut a: [c64; 9] = std::array::from_fn(|e| c64::new(re[e], im[e]));
    let regular = linalg::invert3(&mut a)?;
    for (e, z) in a.into_iter().enumerate() {
        (re[e], im[e]) = (z.re, z.im);
    }
    Some(regular)
}

/// One Gauss–Jordan step on rows `row0 .. row0 + V·lanes` of every column `j ≠ k`:
/// `a[·, j] ← a[·, j] − a[·, k] a[k, j]`, with that part of column `k` held in registers
/// and row `k` left as it was.
#[inline(always)]
fn eliminate_rows<S: Simd, const V: usize>(
    simd: S,
    (re, im): (&mut [f64], &mut [f64]),
    n: usize,
    k: usize,
    row0: usize,
) {
    let width = V * S::F64_LANES;
    let mut xr = [simd.splat_f64s(0.0); V];
    let mut xi = [simd.splat_f64s(0.0); V];
    let col_k = k * n + row0..k * n + row0 + width;
    xr.copy_from_slice(S::as_simd_f64s(&re[col_k.clone()]).0);
    xi.copy_from_slice(S::as_simd_f64s(&im[col_k]).0);
    let holds_k = (row0..row0 + width).contains(&k);
    for j in (0..n).filter(|&j| j != k) {
        let akj = c64::new(re[k + j * n], im[k + j * n]);
        if akj == c64::new(0.0, 0.0) {
            continue;
        }
        let (nar, ai, nai) = (
            simd.splat_f64s(-akj.re),
            simd.splat_f64s(akj.im),
            simd.splat_f64s(-akj.im),
        );
        let col = j * n + row0..j * n + row0 + width;
        let (yr, _) = S::as_mut_simd_f64s(&mut re[col.clone()]);
        let (yi, _) = S::as_mut_simd_f64s(&mut im[col]);
        for (((yr, yi), &xr), &xi) in yr.iter_mut().zip(yi.iter_mut()).zip(&xr).zip(&xi) {
            *yr = simd.mul_add_f64s(xr, nar, simd.mul_add_f64s(xi, ai, *yr));
            *yi = simd.mul_add_f64s(xr, nai, simd.mul_add_f64s(xi, nar, *yi));
        }
        if holds_k {
            re[k + j * n] = akj.re;
            im[k + j * n] = akj.im;
        }
    }
}

/// `y ← y a` down one column, complex `a`.
#[inline(always)]
fn scale<S: Simd>(simd: S, (y_re, y_im): (&mut [f64], &mut [f64]), a: c64) {
    let (ar, ai, nai) = (
        simd.splat_f64s(a.re),
        simd.splat_f64s(a.im),
        simd.splat_f64s(-a.im),
    );
    let (yr, yr_tail) = S::as_mut_simd_f64s(y_re);
    let (yi, yi_tail) = S::as_mut_simd_f64s(y_im);
    for (yr, yi) in yr.iter_mut().zip(yi.iter_mut()) {
        let (r, i) = (*yr, *yi);
        *yr = simd.mul_add_f64s(i, nai, simd.mul_f64s(r, ar));
        *yi = simd.mul_add_f64s(i, ar, simd.mul_f64s(r, ai));
    }
    for (yr, yi) in yr_tail.iter_mut().zip(yi_tail.iter_mut()) {
        let z = c64::new(*yr, *yi) * a;
        (*yr, *yi) = (z.re, z.im);
    }
}

/// Row of the largest-modulus entry of column `k` at or below row `k` and that modulus
/// squared (the moduli themselves if squares leave the normal range): `linalg`'s pivot rule.
#[inline(always)]
fn pivot(re: &[f64], im: &[f64], k: usize) -> (usize, f64) {
    let mut p = k;
    let mut best = re[k] * re[k] + im[k] * im[k];
    for (i, (r, m)) in re.iter().zip(im).enumerate().skip(k + 1) {
        let v = r * r + m * m;
        if v > best {
            best = v;
            p = i;
        }
    }
    if best.is_finite() && best >= f64::MIN_POSITIVE {
        return (p, best);
    }
    p = k;
    best = re[k].hypot(im[k]);
    for (i, (r, m)) in re.iter().zip(im).enumerate().skip(k + 1) {
        let v = r.hypot(*m);
        if v > best {
            best = v;
            p = i;
        }
    }
    (p, best)
}

/// Inverts the split column-major `n × n` matrix in place by Gauss–Jordan elimination with
/// partial pivoting (`pivots`: scratch of length `n`). `false` (the matrix then unspecified)
/// if a pivot is zero or the result is not finite.
#[inline(always)]
pub(super) fn invert<S: Simd>(
    simd: S,
    (re, im): (&mut [f64], &mut [f64]),
    n: usize,
    pivots: &mut [usize],
) -> bool {
    for k in 0..n {
        let (p, best) = pivot(&re[k * n..(k + 1) * n], &im[k * n..(k + 1) * n], k);
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        pivots[k] = p;
        if p != k {
            for j in 0..n {
                re.swap(k + j * n, p + j * n);
                im.swap(k + j * n, p + j * n);
            }
        }
        let inv = reciprocal(c64::new(re[k + k * n], im[k + k * n]));
        re[k + k * n] = 1.0;
        im[k + k * n] = 0.0;
        for j in 0..n {
            let z = c64::new(re[k + j * n], im[k + j * n]) * inv;
            re[k + j * n] = z.re;
            im[k + j * n] = z.im;
        }
        // Every other column j loses a[k, j] times column k (row k kept), a register block
        // of rows at a time, then the rows past the last full register; column k, the
        // multipliers, last.
        let (lanes, registers) = (S::F64_LANES, n / S::F64_LANES);
        let mut v = 0;
        while v < registers {
            let (a, row0) = ((&mut *re, &mut *im), v * lanes);
            match registers - v {
                1 => eliminate_rows::<S, 1>(simd, a, n, k, row0),
                2 => eliminate_rows::<S, 2>(simd, a, n, k, row0),
                3 => eliminate_rows::<S, 3>(simd, a, n, k, row0),
                _ => eliminate_rows::<S, 4>(simd, a, n, k, row0),
            }
            v += (registers - v).min(4);
        }
        for j in (0..n).filter(|&j| j != k) {
            let akj = c64::new(re[k + j * n], im[k + j * n]);
            for i in (registers * lanes..n).filter(|&i| i != k) {
                let z = c64::new(re[i + j * n], im[i + j * n])
                    - c64::new(re[i + k * n], im[i + k * n]) * akj;
                (re[i + j * n], im[i + j * n]) = (z.re, z.im);
            }
        }
        // Column k: a[i, k] ← −a[i, k] · a[k, k] (a[k, k] now holds 1 / pivot).
        let akk = c64::new(re[k + k * n], im[k + k * n]);
        scale(
            simd,
            (&mut re[k * n..(k + 1) * n], &mut im[k * n..(k + 1) * n]),
            -akk,
        );
        re[k + k * n] = akk.re;
        im[k + k * n] = akk.im;
    }
    for k in (0..n).rev() {
        let p = pivots[k];
        if p != k {
            let (lo, hi) = (k.min(p), k.max(p));
            for a in [&mut *re, &mut *im] {
                let (left, right) = a.split_at_mut(hi * n);
                left[lo * n..lo * n + n].swap_with_slice(&mut right[..n]);
            }
        }
    }
    all_finite(simd, re) && all_finite(simd, im)
}

/// Whether every entry is finite: `v − v` is 0 for a finite `v` and NaN otherwise, and NaN
/// survives the sum.
#[inline(always)]
fn all_finite<S: Simd>(simd: S, a: &[f64]) -> bool {
    let (v, tail) = S::as_simd_f64s(a);
    let mut acc = simd.splat_f64s(0.0);
    for &x in v {
        acc = simd.add_f64s(acc, simd.sub_f64s(x, x));
    }
    simd.reduce_sum_f64s(acc).is_finite() && tail.iter().all(|x| x.is_finite())
}

/// Rows `row0 .. row0 + V·lanes` of column `a` of `X Y`: `Σ_c X[·, c] y_c` with the
/// `2V` accumulators in registers (`y`: column `a` of `Y`, imaginary parts times `sign`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn mul_rows<S: Simd, const V: usize>(
    simd: S,
    (out_re, out_im): (&mut [f64], &mut [f64]),
    (x_re, x_im): (&[f64], &[f64]),
    (y_re, y_im): (&[f64], &[f64]),
    sign: f64,
    n: usize,
    row0: usize,
) {
    let width = V * S::F64_LANES;
    let mut acc_re = [simd.splat_f64s(0.0); V];
    let mut acc_im = [simd.splat_f64s(0.0); V];
    for (c, (&yr, &yi)) in y_re.iter().zip(y_im).enumerate() {
        let yi = sign * yi;
        let (br, bi, nbi) = (
            simd.splat_f64s(yr),
            simd.splat_f64s(yi),
            simd.splat_f64s(-yi),
        );
        let start = c * n + row0;
        let (xr, _) = S::as_simd_f64s(&x_re[start..start + width]);
        let (xi, _) = S::as_simd_f64s(&x_im[start..start + width]);
        for (((ar, ai), &xr), &xi) in acc_re.iter_mut().zip(acc_im.iter_mut()).zip(xr).zip(xi) {
            *ar = simd.mul_add_f64s(xr, br, simd.mul_add_f64s(xi, nbi, *ar));
            *ai = simd.mul_add_f64s(xr, bi, simd.mul_add_f64s(xi, br, *ai));
        }
    }
    let (or, _) = S::as_mut_simd_f64s(&mut out_re[row0..row0 + width]);
    or.copy_from_slice(&acc_re);
    let (oi, _) = S::as_mut_simd_f64s(&mut out_im[row0..row0 + width]);
    oi.copy_from_slice(&acc_im);
}

/// `out = X Y` (`conj = false`) or `X Ȳ` (`conj = true`), split column-major `n × n`:
/// column `a` of `out` is the columns of `X` weighted by column `a` of `Y`.
#[inline(always)]
pub(super) fn mul<S: Simd>(
    simd: S,
    (out_re, out_im): (&mut [f64], &mut [f64]),
    (x_re, x_im): (&[f64], &[f64]),
    (y_re, y_im): (&[f64], &[f64]),
    n: usize,
    conj: bool,
) {
    let sign = if conj { -1.0 } else { 1.0 };
    let lanes = S::F64_LANES;
    let registers = n / lanes;
    for a in 0..n {
        let col = a * n..(a + 1) * n;
        let out = (&mut out_re[col.clone()], &mut out_im[col.clone()]);
        let y = (&y_re[col.clone()], &y_im[col]);
        let mut v = 0;
        while v < registers {
            let row0 = v * lanes;
            let out = (&mut *out.0, &mut *out.1);
            match registers - v {
                1 => mul_rows::<S, 1>(simd, out, (x_re, x_im), y, sign, n, row0),
                2 => mul_rows::<S, 2>(simd, out, (x_re, x_im), y, sign, n, row0),
                3 => mul_rows::<S, 3>(simd, out, (x_re, x_im), y, sign, n, row0),
                _ => mul_rows::<S, 4>(simd, out, (x_re, x_im), y, sign, n, row0),
            }
            v += (registers - v).min(4);
        }
        for i in registers * lanes..n {
            let (mut sr, mut si) = (0.0, 0.0);
            for (c, (&yr, &yi)) in y.0.iter().zip(y.1).enumerate() {
                let (xr, xi, yi) = (x_re[i + c * n], x_im[i + c * n], sign * yi);
                sr += xr * yr - xi * yi;
                si += xr * yi + xi * yr;
            }
            out.0[i] = sr;
            out.1[i] = si;
        }
    }
}

/// `Σ |z|²` over a split slice pair.
#[inline(always)]
pub(super) fn norm_sqr<S: Simd>(simd: S, re: &[f64], im: &[f64]) -> f64 {
    let (rv, r_tail) = S::as_simd_f64s(re);
    let (iv, i_tail) = S::as_simd_f64s(im);
    let mut acc = simd.splat_f64s(0.0);
    for (&r, &i) in rv.iter().zip(iv) {
        acc = simd.mul_add_f64s(r, r, simd.mul_add_f64s(i, i, acc));
    }
    let mut sum = simd.reduce_sum_f64s(acc);
    for (r, i) in r_tail.iter().zip(i_tail) {
        sum += r * r + i * i;
    }
    sum
}

/// `dst += w · src`.
#[inline(always)]
pub(super) fn add_scaled<S: Simd>(simd: S, dst: &mut [f64], src: &[f64], w: f64) {
    let ww = simd.splat_f64s(w);
    let (dv, d_tail) = S::as_mut_simd_f64s(dst);
    let (sv, s_tail) = S::as_simd_f64s(src);
    for (d, &s) in dv.iter_mut().zip(sv) {
        *d = simd.mul_add_f64s(s, ww, *d);
    }
    for (d, s) in d_tail.iter_mut().zip(s_tail) {
        *d += w * s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Inverter;

    /// A complex test matrix with a dominant diagonal off by a row shift, so pivoting swaps.
    fn sample(n: usize) -> Vec<c64> {
        (0..n * n)
            .map(|q| {
                let (i, j) = (q % n, q / n);
                let d = if (i + 1) % n == j { 5.0 } else { 0.0 };
                c64::new(
                    d + ((i * 7 + j * 3) % 11) as f64 * 0.1,
                    ((i * 5 + j) % 7) as f64 * 0.1,
                )
            })
            .collect()
    }

    fn split(z: &[c64]) -> (Vec<f64>, Vec<f64>) {
        (
            z.iter().map(|v| v.re).collect(),
            z.iter().map(|v| v.im).collect(),
        )
    }

    struct Check(usize);

    impl WithSimd for Check {
        type Output = ();
        #[inline(always)]
        fn with_simd<S: Simd>(self, simd: S) {
            let n = self.0;
            let a = sample(n);
            // The inverse is linalg's Gauss–Jordan inverse to rounding.
            let mut reference = a.clone();
            assert!(Inverter::new(n).invert(&mut reference));
            let (mut re, mut im) = split(&a);
            assert!(invert(simd, (&mut re, &mut im), n, &mut vec![0; n]));
            let scale = reference.iter().map(|z| z.norm()).fold(0.0, f64::max);
            for (q, z) in reference.iter().enumerate() {
                let err = (c64::new(re[q], im[q]) - z).norm() / scale;
                assert!(err < 1e-14, "n = {n}: inverse entry {q}: {err:e}");
            }
            // X Y and X Ȳ against the direct sums.
            let b: Vec<c64> = sample(n).iter().map(|z| z * c64::new(0.3, -1.1)).collect();
            let (x, y) = (split(&a), split(&b));
            for conj in [false, true] {
                let (mut o_re, mut o_im) = (vec![0.0; n * n], vec![0.0; n * n]);
                mul(
                    simd,
                    (&mut o_re, &mut o_im),
                    (&x.0, &x.1),
                    (&y.0, &y.1),
                    n,
                    conj,
                );
                for i in 0..n {
                    for j in 0..n {
                        let direct: c64 = (0..n)
                            .map(|c| {
                                let yv = b[c + j * n];
                                a[i + c * n] * if conj { yv.conj() } else { yv }
                            })
                            .sum();
                        let got = c64::new(o_re[i + j * n], o_im[i + j * n]);
                        assert!((got - direct).norm() < 1e-13 * (1.0 + direct.norm()));
                    }
                }
            }
        }
    }

    /// Every register-count arm of `mul` and the scalar tail rows, both conjugations, and
    /// the inverse, for sizes around the register width: on this CPU's SIMD and on pulp's
    /// scalar fallback (one lane, what a CPU without AVX2 runs).
    #[test]
    fn kernels_match_the_direct_forms() {
        for n in [1, 2, 3, 4, 5, 7, 8, 12, 16, 17, 19, 32, 33] {
            Arch::new().dispatch(Check(n));
            Check(n).with_simd(faer::traits::pulp::Scalar::new());
        }
    }

    /// `all_finite` sees an infinity or a NaN in the registers and in the tail.
    #[test]
    fn non_finite_entries_are_seen() {
        struct Finite(Vec<f64>);
        impl WithSimd for Finite {
            type Output = bool;
            #[inline(always)]
            fn with_simd<S: Simd>(self, simd: S) -> bool {
                all_finite(simd, &self.0)
            }
        }
        let a: Vec<f64> = (0..11).map(|i| i as f64 - 5.0).collect();
        assert!(Arch::new().dispatch(Finite(a.clone())));
        for (at, bad) in [(0, f64::INFINITY), (3, f64::NAN), (10, f64::NEG_INFINITY)] {
            let mut b = a.clone();
            b[at] = bad;
            assert!(!Arch::new().dispatch(Finite(b)), "{bad} at {at}");
        }
    }

    /// A singular matrix is refused.
    #[test]
    fn singular_is_refused() {
        struct Singular;
        impl WithSimd for Singular {
            type Output = bool;
            #[inline(always)]
            fn with_simd<S: Simd>(self, simd: S) -> bool {
                let (mut re, mut im) = (vec![1.0, 2.0, 2.0, 4.0], vec![0.0; 4]);
                invert(simd, (&mut re, &mut im), 2, &mut [0; 2])
            }
        }
        assert!(!Arch::new().dispatch(Singular));
    }

    /// The cofactor inverse of a 3 × 3 is linalg's Gauss–Jordan inverse to rounding at every
    /// scale an impedance may have, refuses a singular matrix, and leaves a scale outside the
    /// normal range (and zero) to Gauss–Jordan.
    #[test]
    fn cofactor_inverse_matches_gauss_jordan() {
        for scale in [1e-250, 1e-8, 1.0, 3e5, 1e250] {
            let a: Vec<c64> = sample(3).iter().map(|z| z * scale).collect();
            let mut reference = a.clone();
            assert!(Inverter::new(3).invert(&mut reference));
            let (mut re, mut im) = split(&a);
            assert_eq!(invert3((&mut re, &mut im)), Some(true), "{scale:e}");
            let largest = reference.iter().map(|z| z.norm()).fold(0.0, f64::max);
            for (q, z) in reference.iter().enumerate() {
                let err = (c64::new(re[q], im[q]) - z).norm() / largest;
                assert!(err < 1e-14, "{scale:e}: inverse entry {q}: {err:e}");
            }
        }
        // Rank 2: the third column is the sum of the first two.
        let (mut re, mut im) = (
            vec![1.0, 2.0, 0.5, -1.0, 0.25, 3.0, 0.0, 2.25, 3.5],
            vec![0.0; 9],
        );
        assert_eq!(invert3((&mut re, &mut im)), Some(false));
        for out_of_range in [0.0, f64::MAX, f64::INFINITY] {
            let (mut re, mut im) = (vec![out_of_range; 9], vec![0.0; 9]);
            assert_eq!(invert3((&mut re, &mut im)), None, "{out_of_range:e}");
        }
    }
}
