//! Singular values of small complex matrices by one-sided (Hestenes) Jacobi rotations: one
//! matrix at a time ([`singular_values_in_place`]), and [`LANES`] independent matrices side by
//! side, one per SIMD lane ([`condition_numbers_in_lanes`]), for the condition numbers of the
//! thousands of per-line matrices of an FRF.
//!
//! One matrix's Jacobi is one long dependency chain (a square root and a division wait for
//! the inner product before them, the next rotation for them), so the core idles; eight
//! matrices in two AVX2 registers of four lanes each keep it busy (one register's chain still
//! left the divider and square-root unit half idle: 222 ns per 3 × 3 matrix with four
//! lanes, 131 ns with eight, 589 ns one at a time). Every lane runs the same
//! sweeps, and a rotation a lane's own run would skip is not applied to it (its columns and
//! norms are selected unchanged, not multiplied by an identity rotation, which could turn a
//! `-0.0` into `+0.0`): each lane's numbers are bit for bit those of
//! [`singular_values_in_place`] on its matrix, and a lane stops rotating at the sweep that
//! one-at-a-time run would have ended with.

use faer::c64;
use faer::traits::pulp::{Arch, Simd, WithSimd};

use super::Conditioner;

/// Sweeps after which the rotations stop, orthogonal or not (a handful suffice in practice:
/// Jacobi converges quadratically once the columns are nearly orthogonal).
const SWEEPS: usize = 64;

/// Singular values of the column-major `n × n` complex matrix in `a` (destroyed), written to
/// `out` in no particular order, by one-sided Jacobi (Hestenes) rotations: column pairs are
/// rotated until all are mutually orthogonal, when the singular values are the column norms.
/// Unitary column operations keep the singular values exact to rounding; no allocation.
///
/// The entries must be scaled to at most 1 in modulus (as [`Conditioner::condition_number`] does):
/// squares then neither overflow nor, for any matrix whose condition number is representable,
/// underflow, so moduli are `√(re² + im²)` rather than libm's `hypot`.
pub(super) fn singular_values_in_place(a: &mut [c64], n: usize, out: &mut [f64]) {
    let col_norm2 = |a: &[c64], p: usize| {
        a[p * n..(p + 1) * n]
            .iter()
            .map(|v| v.norm_sqr())
            .sum::<f64>()
    };
    // Squared column norms, kept up to date through the rotations (`out` is their home until
    // the end) and recomputed at each sweep's start so that rounding cannot accumulate.
    for _ in 0..SWEEPS {
        for (p, o) in out.iter_mut().enumerate().take(n) {
            *o = col_norm2(a, p);
        }
        let mut rotated = false;
        for p in 0..n {
            for q in p + 1..n {
                let (alpha, beta) = (out[p], out[q]);
                let (col_p, col_q) = {
                    let (left, right) = a.split_at_mut(q * n);
                    (&mut left[p * n..(p + 1) * n], &mut right[..n])
                };
                let mut gamma = c64::new(0.0, 0.0);
                for (x, y) in col_p.iter().zip(col_q.iter()) {
                    gamma += x.conj() * y;
                }
                let g = gamma.norm_sqr().sqrt();
                if g <= f64::EPSILON * (alpha * beta).sqrt() || g == 0.0 {
                    continue;
                }
                rotated = true;
                // Rotate a_p and e^{-iφ} a_q (γ = g e^{iφ}) by the real Jacobi rotation that
                // makes them orthogonal.
                let phase = c64::new(gamma.re / g, -gamma.im / g);
                let zeta = (beta - alpha) / (2.0 * g);
                let t = zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt());
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = c * t;
                for (x, y) in col_p.iter_mut().zip(col_q.iter_mut()) {
                    let ap = *x;
                    let aq = *y * phase;
                    *x = ap * c - aq * s;
                    *y = ap * s + aq * c;
                }
                // The rotation moves t·g of squared norm from column p to column q.
                out[p] = alpha - t * g;
                out[q] = beta + t * g;
            }
        }
        if !rotated {
            break;
        }
    }
    for (p, o) in out.iter_mut().enumerate().take(n) {
        *o = col_norm2(a, p).sqrt();
    }
}

/// Matrices processed side by side, one per SIMD lane: two AVX2 registers of four `f64`,
/// two independent chains of operations (sixteen, four registers, were no faster and
/// spill at n = 6).
pub(super) const LANES: usize = 8;

/// One number of each of the [`LANES`] matrices.
type Lanes = [f64; LANES];

/// [`LANES`] column-major `N × N` complex matrices as structure of arrays: `re[j][i][l]` and
/// `im[j][i][l]` are the parts of entry `(i, j)` of lane `l`'s matrix, so that an operation
/// on an entry is one SIMD operation on the matrices (two with AVX2).
struct Group<const N: usize> {
    re: [[Lanes; N]; N],
    im: [[Lanes; N]; N],
}

/// `Σᵢ |a_ip|²` of column `p` in every lane, summed down the column as
/// [`singular_values_in_place`] sums it.
#[inline(always)]
fn col_norm2<const N: usize>(re: &[Lanes; N], im: &[Lanes; N]) -> Lanes {
    let mut s = [0.0; LANES];
    for (r, i) in re.iter().zip(im) {
        for l in 0..LANES {
            s[l] += r[l] * r[l] + i[l] * i[l];
        }
    }
    s
}

/// `if mask { new } else { old }` lane by lane (a blend, which keeps `old`'s bits).
#[inline(always)]
fn select(mask: [bool; LANES], new: Lanes, old: Lanes) -> Lanes {
    let mut out = old;
    for l in 0..LANES {
        if mask[l] {
            out[l] = new[l];
        }
    }
    out
}

/// `x / d` lane by lane.
#[inline(always)]
fn divide(x: Lanes, d: Lanes) -> Lanes {
    let mut out = x;
    for l in 0..LANES {
        out[l] = x[l] / d[l];
    }
    out
}

/// Whether any lane's flag is set.
#[inline(always)]
fn any(mask: [bool; LANES]) -> bool {
    mask.iter().fold(false, |a, &m| a | m)
}

impl<const N: usize> Group<N> {
    /// [`singular_values_in_place`] on the [`LANES`] matrices at once: the same operations in the
    /// same order, lane by lane, so the same bits in each lane. A lane's rotation of a pair is
    /// applied only where that lane's own test asks for it, and only while the lane is
    /// active: it stops at the end of its first sweep without a rotation, as the
    /// one-at-a-time loop does; the sweeps go on while any lane is active.
    #[inline(always)]
    fn singular_values(&mut self) -> [Lanes; N] {
        let (re, im) = (&mut self.re, &mut self.im);
        let mut norm2 = [[0.0; LANES]; N];
        let mut active = [true; LANES];
        for _ in 0..SWEEPS {
            for p in 0..N {
                norm2[p] = col_norm2(&re[p], &im[p]);
            }
            let mut rotated = [false; LANES];
            for p in 0..N {
                for q in p + 1..N {
                    let (alpha, beta) = (norm2[p], norm2[q]);
                    // γ = a_pᴴ a_q, as `x.conj() * y` summed from 0.
                    let (mut gr, mut gi) = ([0.0; LANES], [0.0; LANES]);
                    for i in 0..N {
                        for l in 0..LANES {
                            let (xr, xi) = (re[p][i][l], -im[p][i][l]);
                            let (yr, yi) = (re[q][i][l], im[q][i][l]);
                            gr[l] += xr * yr - xi * yi;
                            gi[l] += xr * yi + xi * yr;
                        }
                    }
                    let (mut g, mut rotate) = ([0.0; LANES], [false; LANES]);
                    for l in 0..LANES {
                        g[l] = (gr[l] * gr[l] + gi[l] * gi[l]).sqrt();
                        let skip =
                            g[l] <= f64::EPSILON * (alpha[l] * beta[l]).sqrt() || g[l] == 0.0;
                        rotate[l] = active[l] & !skip;
                    }
                    if !any(rotate) {
                        continue;
                    }
                    let (mut pr, mut pi) = ([0.0; LANES], [0.0; LANES]);
                    let (mut c, mut s, mut tg) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
                    for l in 0..LANES {
                        // Lanes that skip compute whatever their g (perhaps 0) gives, discarded.
                        pr[l] = gr[l] / g[l];
                        pi[l] = -gi[l] / g[l];
                        let zeta = (beta[l] - alpha[l]) / (2.0 * g[l]);
                        let t = zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt());
                        c[l] = 1.0 / (1.0 + t * t).sqrt();
                        s[l] = c[l] * t;
                        tg[l] = t * g[l];
                    }
                    for l in 0..LANES {
                        rotated[l] |= rotate[l];
                    }
                    for i in 0..N {
                        let (xr, xi) = (re[p][i], im[p][i]);
                        let (yr, yi) = (re[q][i], im[q][i]);
                        let (mut nxr, mut nxi) = ([0.0; LANES], [0.0; LANES]);
                        let (mut nyr, mut nyi) = ([0.0; LANES], [0.0; LANES]);
                        for l in 0..LANES {
                            // aq = y·phase; x ← ap·c − aq·s; y ← ap·s + aq·c.
                            let ar = yr[l] * pr[l] - yi[l] * pi[l];
                            let ai = yr[l] * pi[l] + yi[l] * pr[l];
                            nxr[l] = xr[l] * c[l] - ar * s[l];
                            nxi[l] = xi[l] * c[l] - ai * s[l];
                            nyr[l] = xr[l] * s[l] + ar * c[l];
                            nyi[l] = xi[l] * s[l] + ai * c[l];
                        }
                        re[p][i] = select(rotate, nxr, xr);
                        im[p][i] = select(rotate, nxi, xi);
                        re[q][i] = select(rotate, nyr, yr);
                        im[q][i] = select(rotate, nyi, yi);
                    }
                    let (mut from, mut to) = ([0.0; LANES], [0.0; LANES]);
                    for l in 0..LANES {
                        from[l] = alpha[l] - tg[l];
                        to[l] = beta[l] + tg[l];
                    }
                    norm2[p] = select(rotate, from, alpha);
                    norm2[q] = select(rotate, to, beta);
                }
            }
            active = rotated;
            if !any(active) {
                break;
            }
        }
        let mut sigma = [[0.0; LANES]; N];
        for p in 0..N {
            let s2 = col_norm2(&re[p], &im[p]);
            for l in 0..LANES {
                sigma[p][l] = s2[l].sqrt();
            }
        }
        sigma
    }
}

/// [`Conditioner::condition_numbers`] for `3 ≤ N < 8` as an operation of faer's SIMD
/// dispatch: a named type rather than a closure, so that the whole pass is inlined into the
/// instruction set chosen (a closure was not, and stayed SSE2).
struct Batch<'a, const N: usize> {
    conditioner: &'a mut Conditioner,
    a: &'a [c64],
    out: &'a mut [f64],
}

impl<const N: usize> WithSimd for Batch<'_, N> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) {
        let Self {
            conditioner,
            a,
            out,
        } = self;
        let nn = N * N;
        for (k, out) in out.chunks_mut(LANES).enumerate() {
            // The last group is padded by repeating its last matrix (no extra sweeps).
            let last = out.len() - 1;
            let matrix = |l: usize| {
                let m = k * LANES + l.min(last);
                &a[m * nn..(m + 1) * nn]
            };
            let mut group = Group::<N> {
                re: [[[0.0; LANES]; N]; N],
                im: [[[0.0; LANES]; N]; N],
            };
            for l in 0..LANES {
                let m = matrix(l);
                for j in 0..N {
                    for i in 0..N {
                        group.re[j][i][l] = m[i + j * N].re;
                        group.im[j][i][l] = m[i + j * N].im;
                    }
                }
            }
            let one_by_one = group.scale();
            let sigma = group.singular_values();
            for (l, o) in out.iter_mut().enumerate() {
                *o = if one_by_one[l] {
                    conditioner.condition_number(matrix(l))
                } else {
                    super::ratio((0..N).map(|p| sigma[p][l]))
                };
            }
        }
    }
}

impl<const N: usize> Group<N> {
    /// Divides each lane's entries by its largest modulus, as
    /// [`Conditioner::condition_number`] does when the squared moduli stay in the normal
    /// range. Lanes where they do not (an entry beyond 1e154, all below 1e-154, zero) or
    /// with an entry that is not finite are flagged for the one-at-a-time path and replaced
    /// by the identity, which no rotation touches. Returns the flags.
    #[inline(always)]
    fn scale(&mut self) -> [bool; LANES] {
        let mut largest2 = [0.0_f64; LANES];
        let mut finite = [true; LANES];
        for j in 0..N {
            for i in 0..N {
                let (r, m) = (self.re[j][i], self.im[j][i]);
                for l in 0..LANES {
                    finite[l] &= r[l].is_finite() & m[l].is_finite();
                    largest2[l] = largest2[l].max(r[l] * r[l] + m[l] * m[l]);
                }
            }
        }
        let mut one_by_one = [false; LANES];
        let mut largest = [1.0; LANES];
        for l in 0..LANES {
            let normal = largest2[l].is_finite() & (largest2[l] >= f64::MIN_POSITIVE);
            one_by_one[l] = !(finite[l] & normal);
            largest[l] = if one_by_one[l] {
                1.0
            } else {
                largest2[l].sqrt()
            };
        }
        if any(one_by_one) {
            for j in 0..N {
                for i in 0..N {
                    let unit = if i == j { 1.0 } else { 0.0 };
                    let zero = [0.0; LANES];
                    self.re[j][i] = select(one_by_one, [unit; LANES], self.re[j][i]);
                    self.im[j][i] = select(one_by_one, zero, self.im[j][i]);
                }
            }
        }
        for j in 0..N {
            for i in 0..N {
                self.re[j][i] = divide(self.re[j][i], largest);
                self.im[j][i] = divide(self.im[j][i], largest);
            }
        }
        one_by_one
    }
}

/// Condition numbers of the `out.len()` column-major `N × N` matrices back to back in `a`,
/// [`LANES`] at a time, compiled for the widest SIMD instructions of this processor.
pub(super) fn condition_numbers_in_lanes<const N: usize>(
    conditioner: &mut Conditioner,
    a: &[c64],
    out: &mut [f64],
) {
    Arch::new().dispatch(Batch::<N> {
        conditioner,
        a,
        out,
    });
}

#[cfg(test)]
mod tests {
    use super::super::tests::{with_condition, with_singular_values};
    use super::*;
    use rand::SeedableRng;
    use rand::rngs::StdRng;

    /// The batched condition numbers of the `n × n` matrices in `a` against
    /// [`Conditioner::condition_number`] on each, bit for bit.
    fn assert_same(a: &[c64], n: usize, what: &str) {
        let count = a.len() / (n * n);
        let mut batched = vec![-1.0; count];
        Conditioner::new(n).condition_numbers(a, &mut batched);
        let mut one = Conditioner::new(n);
        for (m, b) in batched.iter().enumerate() {
            let expected = one.condition_number(&a[m * n * n..(m + 1) * n * n]);
            assert_eq!(
                b.to_bits(),
                expected.to_bits(),
                "{what}: n = {n}, matrix {m} of {count}: {b:e} vs {expected:e}"
            );
        }
    }

    /// A complex matrix with independent standard normal parts.
    fn gaussian(n: usize, rng: &mut StdRng) -> Vec<c64> {
        use rand_distr::{Distribution, StandardNormal};
        let mut g = || -> f64 { StandardNormal.sample(&mut *rng) };
        (0..n * n).map(|_| c64::new(g(), g())).collect()
    }

    /// Random matrices whose condition numbers (and so sweep counts) differ from lane to
    /// lane, from κ = 1 to 1e12, and Gaussian ones.
    fn mixed(n: usize, count: usize, rng: &mut StdRng) -> Vec<c64> {
        let kappas = [1.0, 1e12, 1.5, 1e3, 1e8, 10.0, 1e6];
        (0..count)
            .flat_map(|m| {
                if m % 3 == 2 {
                    gaussian(n, rng)
                } else {
                    with_condition(n, kappas[m % kappas.len()], rng)
                }
            })
            .collect()
    }

    #[test]
    fn random_matrices_match_one_at_a_time_bit_for_bit() {
        let mut rng = StdRng::seed_from_u64(21);
        for n in 3..=7 {
            let a = mixed(n, 203, &mut rng);
            assert_same(&a, n, "random");
        }
    }

    #[test]
    fn every_count_and_the_padding_match() {
        let mut rng = StdRng::seed_from_u64(22);
        for n in [3, 4, 5, 7] {
            for count in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 13, 15, 16, 17] {
                let a = mixed(n, count, &mut rng);
                assert_same(&a, n, &format!("{count} matrices"));
            }
        }
    }

    /// The lanes' columns after the sweeps and their singular values, bit for bit those of
    /// [`singular_values_in_place`], signed zeros included: a lane that skips a rotation its
    /// neighbours make keeps its `-0.0` (an identity rotation would turn `-0.0 - (-0.0)`
    /// into `+0.0`).
    #[test]
    fn lanes_hold_the_one_at_a_time_columns_bit_for_bit() {
        fn check<const N: usize>(rng: &mut StdRng) {
            // Lane 0: diagonal with signed zeros off it (never rotated); lane 1: its first
            // two columns orthogonal (that pair skipped, the others rotated); lanes 2, 3:
            // random, well and badly conditioned.
            let mut diagonal = vec![c64::new(-0.0, -0.0); N * N];
            for i in 0..N {
                diagonal[i + i * N] = c64::new(1.0 / (i + 1) as f64, -0.0);
            }
            let mut orthogonal = with_condition(N, 30.0, rng);
            for i in 0..N {
                orthogonal[i] = c64::new(-0.0, 0.0);
                orthogonal[i + N] = if i == 0 {
                    c64::new(0.0, -0.0)
                } else {
                    c64::new(-0.0, -0.0)
                };
            }
            orthogonal[0] = c64::new(0.5, -0.0);
            orthogonal[1 + N] = c64::new(-0.25, 0.0);
            let mut lanes = vec![diagonal, orthogonal];
            let kappas = [2.0, 1e9, 1.0, 1e3, 10.0, 1e12];
            lanes.extend((2..LANES).map(|l| with_condition(N, kappas[l % kappas.len()], rng)));
            let mut group = Group::<N> {
                re: [[[0.0; LANES]; N]; N],
                im: [[[0.0; LANES]; N]; N],
            };
            for (l, m) in lanes.iter().enumerate() {
                for j in 0..N {
                    for i in 0..N {
                        group.re[j][i][l] = m[i + j * N].re;
                        group.im[j][i][l] = m[i + j * N].im;
                    }
                }
            }
            let sigma = group.singular_values();
            for (l, m) in lanes.iter().enumerate() {
                let (mut one, mut expected) = (m.clone(), vec![0.0; N]);
                singular_values_in_place(&mut one, N, &mut expected);
                for p in 0..N {
                    assert_eq!(
                        sigma[p][l].to_bits(),
                        expected[p].to_bits(),
                        "N {N} lane {l}"
                    );
                    for i in 0..N {
                        let (ours, theirs) = (
                            (group.re[p][i][l], group.im[p][i][l]),
                            (one[i + p * N].re, one[i + p * N].im),
                        );
                        assert_eq!(
                            (ours.0.to_bits(), ours.1.to_bits()),
                            (theirs.0.to_bits(), theirs.1.to_bits()),
                            "N {N} lane {l} entry ({i}, {p}): {ours:?} vs {theirs:?}"
                        );
                    }
                }
            }
            // The diagonal lane was never rotated: its signed zeros are still there.
            assert!(group.re[1][0][0].is_sign_negative() && group.im[0][0][0].is_sign_negative());
        }
        let mut rng = StdRng::seed_from_u64(23);
        check::<3>(&mut rng);
        check::<4>(&mut rng);
        check::<5>(&mut rng);
        check::<7>(&mut rng);
    }

    #[test]
    fn ill_conditioned_and_clustered_singular_values_match() {
        let mut rng = StdRng::seed_from_u64(24);
        for n in [3, 4, 5, 7] {
            let mut a = Vec::new();
            for kappa in [1e9, 1e10, 1e11, 1e12, 1e13, 1e15] {
                a.extend(with_condition(n, kappa, &mut rng));
            }
            let spread = |first: f64, step: f64| -> Vec<f64> {
                (0..n).map(|i| first + step * i as f64).collect()
            };
            for sigma in [
                spread(1.0, 0.0),
                spread(1.0, 1e-15),
                spread(1.0, 1e-12),
                spread(1.0, 1e-8),
                spread(1e-6, 1e-20),
            ] {
                a.extend(with_singular_values(&sigma, &mut rng));
            }
            // Two clusters far apart.
            let two: Vec<f64> = (0..n)
                .map(|i| if i < n / 2 { 1.0 } else { 1e-7 } * (1.0 + 1e-13 * i as f64))
                .collect();
            a.extend(with_singular_values(&two, &mut rng));
            assert_same(&a, n, "ill-conditioned or clustered");
        }
    }

    /// Matrices the lanes hand to the one-at-a-time path (not finite, zero, squares out of
    /// the normal range) or whose rotations stop early (exactly singular), each in every lane
    /// position among random neighbours, which must come out unchanged.
    #[test]
    fn special_matrices_in_any_lane_match() {
        let mut rng = StdRng::seed_from_u64(25);
        for n in [3, 4, 5, 7] {
            let random = with_condition(n, 40.0, &mut rng);
            let scaled = |s: f64| -> Vec<c64> { random.iter().map(|z| z * s).collect() };
            let mut equal_columns = random.clone();
            equal_columns.copy_within(0..n, n);
            let mut zero_column = random.clone();
            zero_column[n..2 * n].fill(c64::new(0.0, 0.0));
            let mut nan = random.clone();
            nan[n + 1] = c64::new(f64::NAN, 0.0);
            let mut infinite = random.clone();
            infinite[0] = c64::new(0.0, f64::NEG_INFINITY);
            // One entry of order 1, the others' squares below the smallest normal number.
            let mut tiny_beside_one = scaled(1e-300);
            tiny_beside_one[n * n - 1] = c64::new(1.0, 0.0);
            let specials = [
                ("equal columns", equal_columns),
                ("zero column", zero_column),
                ("zero", vec![c64::new(0.0, 0.0); n * n]),
                ("negative zero", vec![c64::new(-0.0, -0.0); n * n]),
                ("NaN entry", nan),
                ("infinite entry", infinite),
                ("1e300", scaled(1e300)),
                ("1e160", scaled(1e160)),
                ("1e-160", scaled(1e-160)),
                ("1e-300", scaled(1e-300)),
                ("tiny beside 1", tiny_beside_one),
            ];
            for (what, special) in &specials {
                for count in [1, 2, 5, 6, 7, 9, 11] {
                    for at in 0..count {
                        let mut a = mixed(n, count, &mut rng);
                        a[at * n * n..(at + 1) * n * n].copy_from_slice(special);
                        assert_same(&a, n, &format!("{what} at {at} of {count}"));
                    }
                }
            }
            // The expected values themselves.
            let mut out = vec![0.0; 4];
            let a: Vec<c64> = [&specials[4].1, &specials[2].1, &specials[1].1, &random]
                .into_iter()
                .flatten()
                .copied()
                .collect();
            Conditioner::new(n).condition_numbers(&a, &mut out);
            assert!(out[0].is_nan() && out[1] == f64::INFINITY && out[2] == f64::INFINITY);
            assert!((out[3] / 40.0 - 1.0).abs() < 1e-12, "{}", out[3]);
        }
    }

    /// n = 1, 2 and n ≥ 8 loop over the one-at-a-time path.
    #[test]
    fn other_sizes_loop_over_one_at_a_time() {
        let mut rng = StdRng::seed_from_u64(26);
        for n in [1, 2, 8, 9] {
            for count in [0, 1, 5] {
                let a = mixed(n, count, &mut rng);
                assert_same(&a, n, "loop");
            }
        }
    }

    #[test]
    #[should_panic(expected = "3 matrices of 4 × 4 need 48 entries")]
    fn a_length_that_is_not_count_times_n_squared_panics() {
        let a = vec![c64::new(1.0, 0.0); 47];
        Conditioner::new(4).condition_numbers(&a, &mut [0.0; 3]);
    }
}
