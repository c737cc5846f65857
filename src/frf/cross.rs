//! The cross-spectral family (MIMO H1, H2, Hv): every record and segment accumulated into
//! `S_ff = Σ F Fᴴ`, `S_xf = Σ X Fᴴ`, `S_xx = Σ X Xᴴ` per line, then per line a
//! [`LineEstimator`] turns the sums into `G` and `H`.
//!
//! Adding an estimator of this family: one file implementing [`LineEstimator`] (as
//! [`h1`](super::h1), [`h2`](super::h2), [`hv`](super::hv)), one [`Estimator`] arm and one arm
//! in [`line_estimator`].

use faer::c64;

use super::builder::{FrfBuilder, Plan};
use super::coherence::line_coherence;
use super::contribution::Contribution;
use super::h1::H1;
use super::h2::H2;
use super::hv::Hv;
use super::variance::h1_impedance_variance;
use super::{Estimator, Frf};
use crate::linalg;
use crate::spectra::Segmentation;

/// Band lines whose force power `tr S_ff` is below this fraction of the band's strongest line
/// are not excited (periodic segmentation): −20 dB, far above a broadband noise floor spread
/// over every line and far below the lines a multisine drives. A tuning constant of this
/// estimator, not a numerical tolerance.
pub const UNEXCITED_RATIO: f64 = 1e-2;

/// One line's accumulated cross-spectra, each `n × n` column-major (`sxx` holds `S_xx`, of
/// which the estimators use the diagonal or all).
#[derive(Debug, Clone, Copy)]
pub(crate) struct LineSums<'a> {
    /// Degrees of freedom `n`.
    pub(crate) n: usize,
    /// `S_ff = Σ F Fᴴ`.
    pub(crate) sff: &'a [c64],
    /// `S_ff⁻¹`.
    pub(crate) sff_inv: &'a [c64],
    /// `S_xf = Σ X Fᴴ`.
    pub(crate) sxf: &'a [c64],
    /// `S_xx = Σ X Xᴴ`.
    pub(crate) sxx: &'a [c64],
}

/// The buffers of one line's estimate: the flexibility `g` and impedance `h` it writes
/// (`n × n` column-major), a scratch matrix and an inverter.
#[derive(Debug)]
pub(crate) struct LineWork {
    pub(crate) g: Vec<c64>,
    pub(crate) h: Vec<c64>,
    pub(crate) scratch: Vec<c64>,
    pub(crate) inverter: linalg::Inverter,
}

impl LineWork {
    pub(crate) fn new(n: usize) -> Self {
        let zero = c64::new(0.0, 0.0);
        Self {
            g: vec![zero; n * n],
            h: vec![zero; n * n],
            scratch: vec![zero; n * n],
            inverter: linalg::Inverter::new(n),
        }
    }
}

/// A per-line estimator of the cross-spectral family: from one line's sums, the flexibility
/// `G` and the impedance `H = G⁻¹`.
pub(crate) trait LineEstimator {
    /// Writes `work.g` and `work.h`; `false` when either cannot be formed (a singular matrix,
    /// a degenerate eigenvector), and the line is dropped.
    fn estimate(&self, sums: &LineSums<'_>, work: &mut LineWork) -> bool;
}

/// The per-line estimator of a cross-spectral [`Estimator`] (H1 for paired sets, which never
/// reach it).
pub(crate) fn line_estimator(estimator: Estimator) -> &'static dyn LineEstimator {
    match estimator {
        Estimator::H2 => &H2,
        Estimator::Hv => &Hv,
        Estimator::PairedSets | Estimator::H1 => &H1,
    }
}

/// Cross-spectral sums `S_ff`, `S_xf`, `S_xx`, `[line][n × n]` column-major.
struct Cross {
    sff: Vec<c64>,
    sxf: Vec<c64>,
    sxx: Vec<c64>,
}

impl FrfBuilder {
    /// The cross-spectral totals, or their sums over records weighted by `weights` (which needs
    /// the partials), with the number of averages they hold.
    fn cross_totals(&self, plan: &Plan, weights: Option<&[f64]>) -> (Cross, f64) {
        let segments = self.segmentation.starts(plan.len).count() as f64;
        let Some(weights) = weights else {
            let totals = Cross {
                sff: self.sff.clone(),
                sxf: self.sxf.clone(),
                sxx: self.sxx.clone(),
            };
            return (totals, self.averages as f64);
        };
        let zero = c64::new(0.0, 0.0);
        let mut totals = Cross {
            sff: vec![zero; self.sff.len()],
            sxf: vec![zero; self.sxf.len()],
            sxx: vec![zero; self.sxx.len()],
        };
        let mut averages = 0.0;
        for (g, &w) in self.gathered.iter().zip(weights) {
            if let Contribution::Cross { sff, sxf, sxx, .. } = &g.contribution {
                if w == 0.0 || sff.is_empty() {
                    continue;
                }
                averages += w * segments;
                let add = |t: &mut Vec<c64>, p: &Vec<c64>| {
                    t.iter_mut().zip(p).for_each(|(t, p)| *t += p * w);
                };
                add(&mut totals.sff, sff);
                add(&mut totals.sxf, sxf);
                add(&mut totals.sxx, sxx);
            }
        }
        (totals, averages)
    }

    /// The cross-spectral estimate from the totals (or weighted partials), line by line, H1
    /// compensated for the force noise ([`FrfBuilder::compensate_force_noise`]) if asked.
    pub(super) fn finish_cross(&self, plan: &Plan, weights: Option<&[f64]>) -> Frf {
        let compensation = self.compensation().map(|c| &c.force[..]);
        self.finish_cross_as(plan, weights, self.estimator, compensation)
    }

    /// [`FrfBuilder::finish_cross`] with another cross-spectral `estimator` on the same sums,
    /// and H1 compensated for the force noise `compensation` (per average, `[l * n + c]`).
    pub(super) fn finish_cross_as(
        &self,
        plan: &Plan,
        weights: Option<&[f64]>,
        estimator: Estimator,
        compensation: Option<&[f64]>,
    ) -> Frf {
        let compensation = compensation.filter(|_| estimator == Estimator::H1);
        let n = plan.n;
        let nn = n * n;
        let zero = c64::new(0.0, 0.0);
        let mut frf = Frf::empty(n, estimator);
        frf.spacing_hz = Some(plan.resolution_hz);
        let (Cross { sff, sxf, sxx }, averages) = self.cross_totals(plan, weights);
        frf.averages = averages.round() as usize;
        // Lines the excitation drives (periodic excitation leaves the others empty).
        let power = |l: usize| (0..n).map(|i| sff[l * nn + i * (n + 1)].re).sum::<f64>();
        let strongest = (0..plan.lines.len()).map(power).fold(0.0, f64::max);
        let periodic = matches!(self.segmentation, Segmentation::Periods { .. });
        let with_variance = weights.is_none() && averages > n as f64;
        let estimator = line_estimator(estimator);
        let mut work = LineWork::new(n);
        let (mut inv, mut conditioner) = (vec![zero; nn], linalg::Conditioner::new(n));
        let (mut compensated, mut compensated_inv) = (vec![zero; nn], vec![zero; nn]);
        let (mut multiple, mut ordinary) = (vec![0.0; n], vec![0.0; nn]);
        let (mut auto, mut variance, mut equation) = (vec![0.0; n], vec![0.0; nn], vec![0.0; nn]);
        for (l, &k) in plan.lines.iter().enumerate() {
            let freq = k as f64 * plan.resolution_hz;
            if periodic && power(l) < UNEXCITED_RATIO * strongest {
                frf.unexcited_hz.push(freq);
                continue;
            }
            let range = l * nn..(l + 1) * nn;
            let (sf, sx, ss) = (&sff[range.clone()], &sxf[range.clone()], &sxx[range]);
            let cond = conditioner.condition_number(sf);
            inv.copy_from_slice(sf);
            let ok = work.inverter.invert(&mut inv) && {
                let (sff, sff_inv) = match compensation {
                    Some(noise) => {
                        compensate(sf, &noise[l * n..(l + 1) * n], averages, &mut compensated);
                        compensated_inv.copy_from_slice(&compensated);
                        if !work.inverter.invert(&mut compensated_inv) {
                            frf.dropped_hz.push(freq);
                            continue;
                        }
                        (&compensated[..], &compensated_inv[..])
                    }
                    None => (sf, &inv[..]),
                };
                let sums = LineSums {
                    n,
                    sff,
                    sff_inv,
                    sxf: sx,
                    sxx: ss,
                };
                estimator.estimate(&sums, &mut work)
            };
            if !ok {
                frf.dropped_hz.push(freq);
                continue;
            }
            let (g, h) = (&work.g, &work.h);
            frf.push_line(freq, h, g, cond);
            for (i, a) in auto.iter_mut().enumerate() {
                *a = ss[i * (n + 1)].re;
            }
            line_coherence(n, sf, &inv, sx, &auto, &mut multiple, &mut ordinary);
            frf.push_coherence(&multiple, &ordinary);
            if with_variance {
                h1_impedance_variance(
                    n,
                    h,
                    &inv,
                    &auto,
                    &multiple,
                    averages,
                    &mut variance,
                    &mut equation,
                );
                frf.impedance_variance.extend_from_slice(&variance);
                frf.equation_variance.extend_from_slice(&equation);
            }
        }
        frf
    }
}

/// `S_ff` of `averages` averages with the force noise `noise` (per average, one per channel)
/// taken off its diagonal, into `out`; never below [`MIN_COMPENSATED`] of the diagonal (a line
/// whose force is mostly noise keeps a little of it rather than a matrix that is not
/// positive).
pub(super) fn compensate(sff: &[c64], noise: &[f64], averages: f64, out: &mut [c64]) {
    let n = noise.len();
    out.copy_from_slice(sff);
    for (c, &v) in noise.iter().enumerate() {
        let d = c * (n + 1);
        let kept = (sff[d].re - averages * v).max(MIN_COMPENSATED * sff[d].re);
        out[d] = c64::new(kept, 0.0);
    }
}

/// The least share of a force channel's auto-spectrum the compensation keeps.
const MIN_COMPENSATED: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    /// Noise-free cross-spectra of `x = G f` for a known 2 × 2 `G` and a Hermitian positive
    /// definite `S_ff`: `S_xf = G S_ff`, `S_xx = G S_ff Gᴴ`. Every estimator of the family must
    /// return `G` and `H = G⁻¹`.
    #[test]
    fn every_line_estimator_recovers_a_known_flexibility() {
        let n = 2;
        let c = c64::new;
        let g = [c(2.0, 0.5), c(-0.25, 0.1), c(0.5, -0.3), c(1.0, 0.2)]; // column-major
        let sff = [c(3.0, 0.0), c(0.5, -0.4), c(0.5, 0.4), c(2.0, 0.0)];
        let mut sxf = vec![c(0.0, 0.0); 4];
        linalg::mul_into(&g, &sff, &mut sxf, n);
        let gh: Vec<c64> = (0..4).map(|k| g[(k % 2) * 2 + k / 2].conj()).collect();
        let mut sxx = vec![c(0.0, 0.0); 4];
        linalg::mul_into(&sxf, &gh, &mut sxx, n);
        let mut inv = sff.to_vec();
        assert!(linalg::Inverter::new(n).invert(&mut inv));
        let sums = LineSums {
            n,
            sff: &sff,
            sff_inv: &inv,
            sxf: &sxf,
            sxx: &sxx,
        };
        for estimator in [Estimator::H1, Estimator::H2, Estimator::Hv] {
            let mut work = LineWork::new(n);
            assert!(line_estimator(estimator).estimate(&sums, &mut work));
            for (k, (a, b)) in work.g.iter().zip(&g).enumerate() {
                assert!((a - b).norm() < 1e-12, "{estimator:?} G[{k}]");
            }
            let mut gh = vec![c(0.0, 0.0); 4];
            linalg::mul_into(&work.g, &work.h, &mut gh, n);
            for (k, v) in gh.iter().enumerate() {
                let one = if k % 3 == 0 { 1.0 } else { 0.0 };
                assert!((v - c(one, 0.0)).norm() < 1e-12, "{estimator:?} GH[{k}]");
            }
        }
        // A singular S_xx: H2 cannot form H and says so.
        let zero = [c(0.0, 0.0); 4];
        let singular = LineSums { sxx: &zero, ..sums };
        assert!(!H2.estimate(&singular, &mut LineWork::new(n)));
    }
}
