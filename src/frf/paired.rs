//! Paired sets (the seed's eq. 9): per set of `n` records, one per independent excitation,
//! $H_s = [F^1 \cdots F^n]_s\,[X^1 \cdots X^n]_s^{-1}$, averaged over the sets.
//!
//! [`PairedKernel`] is the one place this product and average are computed: the DFT lines of
//! [`FrfBuilder`] and the drive frequencies of [`stepped_sine`](crate::stepped::stepped_sine)
//! both go through it.

use faer::c64;

use super::builder::{FrfBuilder, Plan};
use super::coherence::SpectraCoherence;
use super::contribution::Contribution;
use super::variance::set_scatters;
use super::{Assignment, Band, Estimator, Frf};
use crate::error::{Error, Result};
use crate::linalg;
use crate::records::{Record, common_shape};
use crate::spectra::{Segmentation, Window};

/// How one set's impedance enters the average `H = Σ_s share_s H_s`.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Share {
    /// `H_s · w` (a normalised weight, `1/S` for a plain mean).
    Times(f64),
    /// `H_s / d` (`d = S` for a plain mean).
    Over(f64),
}

impl Share {
    /// `h += share · hs`.
    pub(crate) fn add(self, h: &mut [c64], hs: &[c64]) {
        match self {
            Share::Times(w) => h.iter_mut().zip(hs).for_each(|(a, b)| *a += b * w),
            Share::Over(d) => h.iter_mut().zip(hs).for_each(|(a, b)| *a += b / d),
        }
    }
}

/// The paired-set kernel, with its buffers for `n` degrees of freedom: per set,
/// `cond(X_s)`, `X_s⁻¹` and `H_s = F_s X_s⁻¹`, and their average over the sets of a line.
#[derive(Debug)]
pub(crate) struct PairedKernel {
    n: usize,
    x: Vec<c64>,
    f: Vec<c64>,
    hs: Vec<c64>,
    conditioner: linalg::Conditioner,
    inverter: linalg::Inverter,
}

impl PairedKernel {
    pub(crate) fn new(n: usize) -> Self {
        let (zero, nn) = (c64::new(0.0, 0.0), n * n);
        Self {
            n,
            x: vec![zero; nn],
            f: vec![zero; nn],
            hs: vec![zero; nn],
            conditioner: linalg::Conditioner::new(n),
            inverter: linalg::Inverter::new(n),
        }
    }

    /// Loads one set: column `j` of `F_s` and `X_s` from `columns[j] = (forces, displacements)`
    /// of the record driving direction `j` (each `n` values).
    fn load<'a>(&mut self, columns: impl IntoIterator<Item = (&'a [c64], &'a [c64])>) {
        let n = self.n;
        for (j, (f, x)) in columns.into_iter().enumerate() {
            self.x[j * n..(j + 1) * n].copy_from_slice(x);
            self.f[j * n..(j + 1) * n].copy_from_slice(f);
        }
    }

    /// `H_s = F_s X_s⁻¹` of the loaded set, `None` when `X_s` is singular. Three degrees
    /// of freedom invert `X_s` by cofactors ([`linalg::Inverter::invert_by_cofactors`]), which
    /// [`linalg::right_divide3`] also does many lines at a time; the impedance is then the
    /// Gauss–Jordan one to rounding (relative changes of the identified `K`, `C`, `M` of
    /// 3e-13 or less on the three-degree-of-freedom impact test), not bit for bit.
    fn impedance(&mut self) -> Option<&[c64]> {
        if !self.inverter.invert_by_cofactors(&mut self.x) {
            return None;
        }
        linalg::mul_into(&self.f, &self.x, &mut self.hs, self.n);
        Some(&self.hs)
    }

    /// `H_s = F_s X_s⁻¹` of one set (columns as [`PairedKernel::average`]), `None` when `X_s`
    /// is singular.
    pub(crate) fn set_impedance<'a>(
        &mut self,
        columns: impl IntoIterator<Item = (&'a [c64], &'a [c64])>,
    ) -> Option<&[c64]> {
        self.load(columns);
        self.impedance()
    }

    /// The average `h = Σ_s share_s H_s` over `sets` at one line, each set given by its
    /// columns (`(forces, displacements)` per direction) and its [`Share`]; `each` sees every
    /// set's `H_s` in turn. Returns the worst `cond(X_s)`, or `None` (with `h` partly summed)
    /// as soon as some `X_s` is singular.
    pub(crate) fn average<'a, C>(
        &mut self,
        sets: impl IntoIterator<Item = (C, Share)>,
        h: &mut [c64],
        mut each: impl FnMut(&[c64]),
    ) -> Option<f64>
    where
        C: IntoIterator<Item = (&'a [c64], &'a [c64])>,
    {
        h.fill(c64::new(0.0, 0.0));
        let mut worst = 0.0_f64;
        for (columns, share) in sets {
            self.load(columns);
            worst = worst.max(self.conditioner.condition_number(&self.x));
            let hs = self.impedance()?;
            share.add(h, hs);
            each(hs);
        }
        Some(worst)
    }
}

/// Records (push order) per direction.
pub(super) fn by_direction(excitation: &[usize], n: usize) -> Vec<Vec<usize>> {
    let mut by_direction: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (r, &e) in excitation.iter().enumerate() {
        by_direction[e].push(r);
    }
    by_direction
}

impl FrfBuilder {
    /// Band-line spectra `(forces, displacements)` of record `r` at line `l`.
    pub(super) fn spectra_at(&self, r: usize, l: usize, n: usize) -> Option<(&[c64], &[c64])> {
        self.spectra_of(r)
            .map(|(f, x)| (&f[l * n..(l + 1) * n], &x[l * n..(l + 1) * n]))
    }

    /// Band-line spectra `(forces, displacements)` of record `r` on every line, `n` values
    /// per line back to back.
    pub(super) fn spectra_of(&self, r: usize) -> Option<(&[c64], &[c64])> {
        match &self.gathered[r].contribution {
            Contribution::Spectra {
                forces,
                displacements,
            } => Some((forces, displacements)),
            Contribution::Cross { .. } => None,
        }
    }

    /// Paired sets from the gathered band-line spectra, replicate (set) `s` weighted by
    /// `weights[s]` when given.
    pub(super) fn finish_paired(
        &self,
        plan: &Plan,
        excitation: &[usize],
        weights: Option<&[f64]>,
    ) -> Result<Frf> {
        let n = plan.n;
        let by_direction = by_direction(excitation, n);
        let rank = by_direction.iter().filter(|d| !d.is_empty()).count();
        if rank < n {
            return Err(Error::RankDeficient { rank, dofs: n });
        }
        let sets = by_direction.iter().map(Vec::len).min().unwrap_or(0);
        let mut frf = Frf::empty(n, Estimator::PairedSets);
        frf.spacing_hz = Some(plan.resolution_hz);
        let weight = |s: usize| weights.map_or(1.0, |w| w.get(s).copied().unwrap_or(0.0));
        let used: Vec<usize> = (0..sets).filter(|&s| weight(s) > 0.0).collect();
        let total_weight: f64 = used.iter().map(|&s| weight(s)).sum();
        // Each used set's share `w_s/Σw`, formed once rather than on every line.
        let shares: Vec<f64> = used.iter().map(|&s| weight(s) / total_weight).collect();
        frf.averages = used.len();
        frf.unpaired = by_direction
            .iter()
            .flat_map(|d| d[sets..].iter().map(|&r| self.gathered[r].label.clone()))
            .collect();
        // Every record's spectra on all lines, looked up once.
        let spectra: Vec<(&[c64], &[c64])> = (0..self.gathered.len())
            .map(|r| self.spectra_of(r).expect("paired builders gather spectra"))
            .collect();
        let at_line = |l: usize| {
            let line = l * n..(l + 1) * n;
            spectra
                .iter()
                .map(move |(f, x)| (&f[line.clone()], &x[line.clone()]))
        };
        // Scatter of the per-set impedances, for the error bars of the unweighted finish.
        let with_variance = weights.is_none() && used.len() >= 2;
        frf.reserve_lines(plan.lines.len(), with_variance);
        let nn = n * n;
        let zero = c64::new(0.0, 0.0);
        let (mut h, mut g) = (vec![zero; nn], vec![zero; nn]);
        let table = self.set_table(excitation);
        let mut inverter = linalg::Inverter::new(n);
        let mut coherence = SpectraCoherence::new(n);
        // Band lines kept, in order: their scatters are computed together after the loop.
        let mut kept = Vec::with_capacity(if with_variance { plan.lines.len() } else { 0 });
        'lines: for (l, &k) in plan.lines.iter().enumerate() {
            let freq = k as f64 * plan.resolution_hz;
            // `H = Σ_s (w_s/Σw) H_s` in set order, and the worst `cond(X_s)`, as
            // [`PairedKernel::average`] forms them; no line where some `X_s` is singular.
            h.fill(zero);
            let mut worst = 0.0_f64;
            for (&s, &share) in used.iter().zip(&shares) {
                let Some(hs) = table.impedance(s, l) else {
                    frf.dropped_hz.push(freq);
                    continue 'lines;
                };
                worst = worst.max(table.condition(s, l));
                Share::Times(share).add(&mut h, hs);
            }
            g.copy_from_slice(&h);
            if inverter.invert(&mut g) {
                frf.push_line(freq, &h, &g, worst);
                if with_variance {
                    kept.push(l);
                }
                // Coherence from the cross-spectra of all records at this line.
                coherence.line(at_line(l), &mut inverter);
                frf.push_coherence(&coherence.multiple, &coherence.ordinary);
            } else {
                frf.dropped_hz.push(freq);
            }
        }
        if with_variance {
            // Every kept line's sets are regular (else it was dropped).
            let per_set = |k: usize, m: usize| {
                table
                    .impedance(used[k], kept[m])
                    .expect("kept lines have regular sets")
            };
            frf.impedance_variance.resize(kept.len() * nn, 0.0);
            frf.equation_variance.resize(kept.len() * nn, 0.0);
            set_scatters(
                n,
                used.len(),
                per_set,
                (&frf.impedance, &frf.flexibility),
                (&mut frf.impedance_variance, &mut frf.equation_variance),
            );
        }
        Ok(frf)
    }
}

/// Impedance by paired sets (seed eq. 9): whole-record spectra, `H = F X⁻¹` per set, averaged.
///
/// `excitation[r]` is the excitation (degree of freedom) of record `r` (see
/// [`Assignment::resolve`]). Sets are formed in record order; when directions have unequal
/// counts the extra records are left out and listed in [`Frf::unpaired`].
///
/// # Errors
/// Shape errors from [`common_shape`]; [`Error::BandAboveNyquist`]; the assignment errors;
/// [`Error::RankDeficient`] when some direction has no record at all.
pub fn paired_sets(
    records: &[Record],
    excitation: &[usize],
    band: Band,
    window: Window,
) -> Result<Frf> {
    common_shape(records, None)?;
    let mut b = FrfBuilder::new(
        Estimator::PairedSets,
        band,
        Segmentation::WholeRecord,
        window,
    );
    b.push_all(records)?;
    b.finish(&Assignment::Explicit(excitation.to_vec()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frf::tests::static_records;

    /// The frf path (`H_s · (w/Σw)`) and the stepped-sine path (`H_s / S`) of the one kernel
    /// give bit for bit the same impedance and condition number when `S` is a power of two,
    /// and the same to rounding otherwise; and the builder's paired finish is that kernel.
    #[test]
    fn frf_and_stepped_shares_of_the_kernel_agree() {
        let n = 2;
        let c = |k: usize| c64::new((k as f64 * 0.37).sin() + 2.0, (k as f64 * 0.91).cos());
        let columns: Vec<(Vec<c64>, Vec<c64>)> = (0..8)
            .map(|r| {
                (
                    (0..n).map(|i| c(r * 7 + i)).collect(),
                    (0..n)
                        .map(|i| c(r * 5 + i + 1) * (1.0 + r as f64))
                        .collect(),
                )
            })
            .collect();
        let columns = &columns;
        for sets in 1..=4 {
            let run = |share: Share| {
                let mut h = vec![c64::new(0.0, 0.0); n * n];
                let sets_iter = (0..sets).map(|s| {
                    let set = (0..n).map(move |j| {
                        let (f, x) = &columns[s * n + j];
                        (f.as_slice(), x.as_slice())
                    });
                    (set, share)
                });
                let worst = PairedKernel::new(n).average(sets_iter, &mut h, |_| {});
                (h, worst.unwrap())
            };
            let (frf, cf) = run(Share::Times(1.0 / sets as f64));
            let (stepped, cs) = run(Share::Over(sets as f64));
            assert_eq!(cf.to_bits(), cs.to_bits());
            for (a, b) in frf.iter().zip(&stepped) {
                if sets.is_power_of_two() {
                    assert_eq!(
                        (a.re.to_bits(), a.im.to_bits()),
                        (b.re.to_bits(), b.im.to_bits())
                    );
                } else {
                    assert!((a - b).norm() <= 1e-14 * a.norm());
                }
            }
        }
        // End to end: the builder's paired finish is the kernel on its band-line spectra.
        let recs = static_records([[2.0, 0.5], [-0.25, 1.0]]);
        let band = Band::new(1.0, 10.0).unwrap();
        let frf = paired_sets(&recs, &[0, 1], band, Window::Rectangular).unwrap();
        let mut b = FrfBuilder::new(
            Estimator::PairedSets,
            band,
            Segmentation::WholeRecord,
            Window::Rectangular,
        );
        b.push_all(&recs).unwrap();
        let mut kernel = PairedKernel::new(n);
        for l in 0..frf.line_count() {
            let mut h = vec![c64::new(0.0, 0.0); n * n];
            let columns = (0..n).map(|r| b.spectra_at(r, l, n).unwrap());
            let worst = kernel.average([(columns, Share::Over(1.0))], &mut h, |_| {});
            assert_eq!(
                worst.unwrap().to_bits(),
                frf.condition_numbers()[l].to_bits()
            );
            let expect = frf.impedance(l);
            for j in 0..n {
                for i in 0..n {
                    assert_eq!(h[i + j * n], expect[(i, j)]);
                }
            }
        }
    }
}
