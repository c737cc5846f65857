//! Random error of the measured impedance, `E|δH_ij|²` per line
//! ([`Frf::impedance_variance`](super::Frf::impedance_variance)): the scatter of the paired
//! sets' impedances, or the MIMO H1 random error of the cross-spectral estimators.

use faer::c64;

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

#[cfg(test)]
mod tests {
    use super::*;

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
