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

/// `E|δH_ij|²` at one line from the MIMO H1 random error (see [`Frf::impedance_variance`]):
/// `sff_inv = S_ff⁻¹`, `auto[i] = S_xᵢxᵢ`, `multiple[i] = γ²ᵢ:f`, `averages = n_d`.
pub(super) fn h1_impedance_variance(
    n: usize,
    h: &[c64],
    sff_inv: &[c64],
    auto: &[f64],
    multiple: &[f64],
    averages: f64,
    out: &mut [f64],
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
        for i in 0..n {
            out[i + j * n] = (0..n)
                .map(|a| {
                    let noise = (auto[a] * (1.0 - multiple[a])).max(0.0) / dof;
                    h[i + a * n].norm_sqr() * noise
                })
                .sum::<f64>()
                * q.re.max(0.0);
        }
    }
}
