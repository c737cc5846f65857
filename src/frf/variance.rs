//! Random error of the measured impedance, `E|δH_ij|²` per line
//! ([`Frf::impedance_variance`](super::Frf::impedance_variance)): the scatter of the paired
//! sets' impedances, or the MIMO H1 random error of the cross-spectral estimators.

use faer::c64;
use faer::traits::pulp::{Arch, Simd, WithSimd};

use crate::lanes::LANES;

/// `E|δH_ij|²` at one line from the scatter of the `S` per-set impedances `per_set`
/// (`S × n²`, each column-major) about their mean `h`: $\sum_s |H_s - \bar H|^2 / (S(S-1))$.
pub(super) fn set_scatter(per_set: &[c64], h: &[c64], out: &mut [f64]) {
    let nn = h.len();
    let sets = (per_set.len() / nn) as f64;
    out.fill(0.0);
    for set in per_set.chunks_exact(nn) {
        for ((v, a), b) in out.iter_mut().zip(set).zip(h) {
            *v += (a - b).norm_sqr() / (sets * (sets - 1.0));
        }
    }
}

/// `E|δH_ij|²` at one line from the MIMO H1 random error (see [`Frf::impedance_variance`])
/// into `out`, and the equation error's `E|(δG H)_ij|² = ν_i q_j` into `equation`
/// ([`Frf::equation_variance`]): row `i` of `δG` has covariance `ν_i S_ff⁻¹` with
/// `ν_i = S_xᵢxᵢ (1 − γ²ᵢ:f)/(n_d − n)`, and `q_j = h_jᴴ S_ff⁻¹ h_j` for column `j` of `H`;
/// `δH = −H (δG H)`. `sff_inv = S_ff⁻¹`, `auto[i] = S_xᵢxᵢ`, `multiple[i] = γ²ᵢ:f`,
/// `averages = n_d`.
#[allow(clippy::too_many_arguments)]
pub(super) fn h1_impedance_variance(
    n: usize,
    h: &[c64],
    sff_inv: &[c64],
    auto: &[f64],
    multiple: &[f64],
    averages: f64,
    out: &mut [f64],
    equation: &mut [f64],
) {
    let dof = averages - n as f64;
    for j in 0..n {
        // q_j = h_jᴴ S_ff⁻¹ h_j (real: S_ff⁻¹ is Hermitian).
        let mut q = c64::new(0.0, 0.0);
        for b in 0..n {
            for a in 0..n {
                q += h[a + j * n].conj() * sff_inv[a + b * n] * h[b + j * n];
            }
        }
        let q = q.re.max(0.0);
        for a in 0..n {
            equation[a + j * n] = (auto[a] * (1.0 - multiple[a])).max(0.0) / dof * q;
        }
        for i in 0..n {
            out[i + j * n] = (0..n)
                .map(|a| h[i + a * n].norm_sqr() * equation[a + j * n])
                .sum::<f64>();
        }
    }
}

/// The equation error's variance `E|(δG H̄)_ij|²` at one line from the scatter of the `S`
/// per-set impedances `per_set` about their mean `h` (column-major `n × n` each), with
/// `g = h⁻¹`: to first order `G_s H̄ − I = −Ḡ (H_s − H̄)`, so
/// $\sum_s |[\bar G (H_s - \bar H)]_{ij}|^2 / (S(S-1))$ (see [`Frf::equation_variance`]).
/// Unrolled for `n ≤ 4` (the same operations in the same order).
pub(super) fn set_equation_scatter(per_set: &[c64], h: &[c64], g: &[c64], out: &mut [f64]) {
    match h.len() {
        1 => equation_scatter(per_set, h, g, out, 1),
        4 => equation_scatter(per_set, h, g, out, 2),
        9 => equation_scatter(per_set, h, g, out, 3),
        16 => equation_scatter(per_set, h, g, out, 4),
        nn => equation_scatter(per_set, h, g, out, (nn as f64).sqrt().round() as usize),
    }
}

/// [`set_equation_scatter`] for `n` degrees of freedom, inlined so that a constant `n`
/// unrolls it.
#[inline(always)]
fn equation_scatter(per_set: &[c64], h: &[c64], g: &[c64], out: &mut [f64], n: usize) {
    let nn = n * n;
    let (h, g, out) = (&h[..nn], &g[..nn], &mut out[..nn]);
    let sets = (per_set.len() / nn) as f64;
    out.fill(0.0);
    for set in per_set.chunks_exact(nn) {
        for j in 0..n {
            for i in 0..n {
                let mut e = c64::new(0.0, 0.0);
                for a in 0..n {
                    e += g[i + a * n] * (set[a + j * n] - h[a + j * n]);
                }
                out[i + j * n] += e.norm_sqr() / (sets * (sets - 1.0));
            }
        }
    }
}

/// [`set_scatter`] and [`set_equation_scatter`] of many lines: line `m` has the per-set
/// impedances `per_set(k, m)` (`k < sets`, each `n²` values), the mean `h[m·n²..]` and its
/// inverse `g[m·n²..]`, and its scatters go to `variance[m·n²..]` and `equation[m·n²..]`.
/// For `2 ≤ n ≤ 4` the lines go [`LANES`] at a time, one per SIMD lane, each lane with the
/// operations of the one-line kernels in the same order (so the same bits); other sizes
/// line by line.
///
/// # Panics
/// If `h`, `g`, `variance` or `equation` do not hold `n²` values per line, or `per_set`
/// gives fewer than `n²` values.
pub(super) fn set_scatters<'a>(
    n: usize,
    sets: usize,
    per_set: impl Fn(usize, usize) -> &'a [c64] + Copy,
    (h, g): (&[c64], &[c64]),
    (variance, equation): (&mut [f64], &mut [f64]),
) {
    let nn = n * n;
    let lines = h.len() / nn.max(1);
    assert!(
        h.len() == lines * nn
            && g.len() == lines * nn
            && variance.len() == lines * nn
            && equation.len() == lines * nn,
        "{n} × {n} per line"
    );
    let scatters = Scatters {
        sets,
        per_set,
        h,
        g,
        variance,
        equation,
    };
    match n {
        2 => Arch::new().dispatch(InLanes::<_, 2>(scatters)),
        3 => Arch::new().dispatch(InLanes::<_, 3>(scatters)),
        4 => Arch::new().dispatch(InLanes::<_, 4>(scatters)),
        _ => {
            let mut per_line = Vec::with_capacity(sets * nn);
            for m in 0..lines {
                per_line.clear();
                (0..sets).for_each(|k| per_line.extend_from_slice(&per_set(k, m)[..nn]));
                let at = m * nn..(m + 1) * nn;
                set_scatter(&per_line, &h[at.clone()], &mut variance[at.clone()]);
                set_equation_scatter(&per_line, &h[at.clone()], &g[at.clone()], &mut equation[at]);
            }
        }
    }
}

/// The lines and buffers of [`set_scatters`].
struct Scatters<'b, F> {
    sets: usize,
    per_set: F,
    h: &'b [c64],
    g: &'b [c64],
    variance: &'b mut [f64],
    equation: &'b mut [f64],
}

/// [`set_scatters`] for `n = N` in lanes, as an operation of faer's SIMD dispatch (a named
/// type, so that the pass is compiled for the instruction set chosen).
struct InLanes<'b, F, const N: usize>(Scatters<'b, F>);

/// One number of each of the [`LANES`] lines.
type Lanes = [f64; LANES];

impl<'a, F: Fn(usize, usize) -> &'a [c64] + Copy, const N: usize> WithSimd for InLanes<'_, F, N> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) {
        let Scatters {
            sets,
            per_set,
            h,
            g,
            variance,
            equation,
        } = self.0;
        let nn = N * N;
        let lines = h.len() / nn;
        let count = sets as f64;
        let zero: Lanes = [0.0; LANES];
        // Entry `(i, j)` of lane `l`'s matrix at `[j][i][l]`, real and imaginary parts apart.
        let blank = || [[zero; N]; N];
        for start in (0..lines).step_by(LANES) {
            // The last group is padded by repeating its last line.
            let last = (lines - start).min(LANES) - 1;
            let line = |l: usize| start + l.min(last);
            let (mut hr, mut hi, mut gr, mut gi) = (blank(), blank(), blank(), blank());
            for l in 0..LANES {
                let (hm, gm) = (&h[line(l) * nn..][..nn], &g[line(l) * nn..][..nn]);
                for j in 0..N {
                    for i in 0..N {
                        (hr[j][i][l], hi[j][i][l]) = (hm[i + j * N].re, hm[i + j * N].im);
                        (gr[j][i][l], gi[j][i][l]) = (gm[i + j * N].re, gm[i + j * N].im);
                    }
                }
            }
            let (mut var, mut equ) = (blank(), blank());
            for k in 0..sets {
                // This set's deviations `H_s − H̄`.
                let (mut dr, mut di) = (blank(), blank());
                for l in 0..LANES {
                    let set = &per_set(k, line(l))[..nn];
                    for j in 0..N {
                        for i in 0..N {
                            dr[j][i][l] = set[i + j * N].re - hr[j][i][l];
                            di[j][i][l] = set[i + j * N].im - hi[j][i][l];
                        }
                    }
                }
                for j in 0..N {
                    for i in 0..N {
                        let (d, v) = ((dr[j][i], di[j][i]), &mut var[j][i]);
                        for (l, v) in v.iter_mut().enumerate() {
                            *v += (d.0[l] * d.0[l] + d.1[l] * d.1[l]) / (count * (count - 1.0));
                        }
                        // (Ḡ (H_s − H̄))_ij, summed over `a` from zero as a complex number.
                        let (mut er, mut ei) = (zero, zero);
                        for a in 0..N {
                            let (g_re, g_im) = (gr[a][i], gi[a][i]);
                            let (d_re, d_im) = (dr[j][a], di[j][a]);
                            for l in 0..LANES {
                                er[l] += g_re[l] * d_re[l] - g_im[l] * d_im[l];
                                ei[l] += g_re[l] * d_im[l] + g_im[l] * d_re[l];
                            }
                        }
                        let v = &mut equ[j][i];
                        for (l, v) in v.iter_mut().enumerate() {
                            *v += (er[l] * er[l] + ei[l] * ei[l]) / (count * (count - 1.0));
                        }
                    }
                }
            }
            for l in 0..=last {
                let m = start + l;
                for j in 0..N {
                    for i in 0..N {
                        variance[m * nn + i + j * N] = var[j][i][l];
                        equation[m * nn + i + j * N] = equ[j][i][l];
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`set_scatters`] (in lanes for 2 ≤ n ≤ 4) is the one-line kernels bit for bit, for
    /// every size and every number of lines (the padded last group too).
    #[test]
    fn scatters_of_many_lines_are_the_one_line_ones_bit_for_bit() {
        let z = |k: usize| c64::new((k as f64 * 0.71).sin(), (k as f64 * 0.29).cos() * 0.5);
        for n in 1..=5 {
            let nn = n * n;
            for sets in [2, 3, 6] {
                for lines in 0..11 {
                    let per_set: Vec<c64> = (0..lines * sets * nn)
                        .map(|k| z(k) * (1.0 + k as f64) + c64::new(3.0, 0.0))
                        .collect();
                    // Line `m`'s sets side by side, as the one-line kernels take them.
                    let line = |m: usize| &per_set[m * sets * nn..(m + 1) * sets * nn];
                    let h: Vec<c64> = (0..lines * nn).map(|k| z(k + 7) * 4.0).collect();
                    let g: Vec<c64> = (0..lines * nn).map(|k| z(k + 100)).collect();
                    let (mut variance, mut equation) =
                        (vec![0.0; lines * nn], vec![0.0; lines * nn]);
                    set_scatters(
                        n,
                        sets,
                        |k, m| &line(m)[k * nn..(k + 1) * nn],
                        (&h, &g),
                        (&mut variance, &mut equation),
                    );
                    for m in 0..lines {
                        let at = m * nn..(m + 1) * nn;
                        let (mut v, mut e) = (vec![0.0; nn], vec![0.0; nn]);
                        set_scatter(line(m), &h[at.clone()], &mut v);
                        set_equation_scatter(line(m), &h[at.clone()], &g[at.clone()], &mut e);
                        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                        assert_eq!(bits(&variance[at.clone()]), bits(&v), "n {n} line {m}");
                        assert_eq!(bits(&equation[at]), bits(&e), "n {n} line {m}");
                    }
                }
            }
        }
    }

    /// [`set_equation_scatter`] for every size, the unrolled ones (n ≤ 4) and the general
    /// one, against the formula written out with faer's products.
    #[test]
    fn equation_scatter_is_the_formula_for_every_size() {
        let z = |k: usize| c64::new((k as f64 * 0.71).sin(), (k as f64 * 0.29).cos() * 0.5);
        for n in 1..=5 {
            let nn = n * n;
            let sets = 4;
            let per_set: Vec<c64> = (0..sets * nn).map(|k| z(k) + c64::new(3.0, 0.0)).collect();
            let h: Vec<c64> = (0..nn)
                .map(|e| per_set.iter().skip(e).step_by(nn).sum::<c64>() / sets as f64)
                .collect();
            let g: Vec<c64> = (0..nn).map(|k| z(k + 100)).collect();
            let mut out = vec![0.0; nn];
            set_equation_scatter(&per_set, &h, &g, &mut out);
            let g = faer::MatRef::from_column_major_slice(&g, n, n);
            let h = faer::MatRef::from_column_major_slice(&h, n, n);
            let mut expect = faer::Mat::<f64>::zeros(n, n);
            for set in per_set.chunks_exact(nn) {
                let e = g * (faer::MatRef::from_column_major_slice(set, n, n) - h);
                for j in 0..n {
                    for i in 0..n {
                        expect[(i, j)] += e[(i, j)].norm_sqr() / (sets * (sets - 1)) as f64;
                    }
                }
            }
            for j in 0..n {
                for i in 0..n {
                    let (ours, theirs) = (out[i + j * n], expect[(i, j)]);
                    assert!(
                        (ours - theirs).abs() <= 1e-13 * theirs,
                        "n = {n}: {ours} vs {theirs}"
                    );
                }
            }
        }
    }
}
