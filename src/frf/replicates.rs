//! [`Replicates`]: what the jackknife and the bootstrap share across their refits, computed
//! once from an [`FrfBuilder`], so that a replicate repeats only the weighted average (paired
//! sets) or the weighted sums (cross-spectral estimators) and the per-line `G`/`H`, never the
//! FFTs, the per-set impedances, the condition numbers or the coherences.
//!
//! A replicate counts replicate `r` (paired set `r`, or record `r` of a cross-spectral
//! estimator) `weights[r]` times: 0 leaves it out (jackknife), bootstrap counts resample. Its
//! `Frf` holds the lines of the full data's `Frf` (after any coherence selection) at which its
//! own `H` and `G` exist, each with the full data's condition number; no coherence or variance.
//!
//! A resampled replicate ([`Replicates::frf`], the bootstrap's) forms its sums again from the
//! stored per-set impedances (per-record cross-spectra) in the order of the full finish: it is
//! bit for bit the one [`FrfBuilder`] would finish from the same weights. A leave-one-out
//! replicate ([`Replicates::without`], the jackknife's) takes the left-out term from the sums
//! over every replicate ([`Replicates::totals`], formed once): one pass over the replicates for
//! all `R` refits rather than `R` passes, equal to the weighted finish up to the rounding of
//! the sums themselves (the summation order differs, nothing cancels).

use std::borrow::Cow;

use faer::c64;

use super::builder::{FrfBuilder, Plan};
use super::contribution::Contribution;
use super::cross::{LineSums, LineWork, UNEXCITED_RATIO, compensate, line_estimator};
use super::paired::Share;
use super::sets::SetTable;
use super::{Assignment, Estimator, Frf};
use crate::error::{Error, Result};
use crate::spectra::Segmentation;

/// The per-set impedances (paired sets) or a borrow of the per-record cross-spectra, on the
/// lines of one full-data [`Frf`]: built once by [`FrfBuilder::replicates_on`], then
/// [`Replicates::frf`] per refit.
#[derive(Debug)]
pub(crate) struct Replicates<'a> {
    builder: &'a FrfBuilder,
    plan: &'a Plan,
    /// `(plan line index, frequency in Hz, condition number)` of every line of the full `Frf`.
    lines: Vec<(usize, f64, f64)>,
    /// Paired sets: each set's `H_s` per line ([`FrfBuilder::set_table`]).
    sets: Option<Cow<'a, SetTable>>,
    count: usize,
}

impl FrfBuilder {
    /// What the replicates of this builder share, on the lines of `full` (this builder's own
    /// finish, possibly with lines left out since). Paired sets: each set's `H_s = F_s X_s⁻¹`
    /// at each of those lines, from the builder's [`SetTable`] (computed once, by the
    /// screening or the finish). Cross-spectral estimators need
    /// [`FrfBuilder::keeping_partials`] (no replicate without).
    ///
    /// # Errors
    /// [`Error::NoRecords`] if nothing was pushed; the assignment errors (paired sets).
    pub(crate) fn replicates_on(
        &self,
        assignment: &Assignment,
        full: &Frf,
    ) -> Result<Replicates<'_>> {
        let (plan, _) = self.plan.as_ref().ok_or(Error::NoRecords)?;
        let lines: Vec<(usize, f64, f64)> = plan
            .lines_in(full)
            .map(|(l, freq, at)| (l, freq, full.condition_numbers()[at]))
            .collect();
        let (count, sets) = match self.estimator {
            Estimator::PairedSets => {
                let sets = self.set_table(&self.excitations(assignment)?);
                for s in 0..sets.sets() {
                    // The full finish keeps a line only where every set is regular.
                    let singular = lines.iter().find(|l| sets.impedance(s, l.0).is_none());
                    if let Some(&(_, freq, _)) = singular {
                        return Err(Error::NonFiniteResult {
                            stage: crate::error::Quantity::Impedance,
                            freq_hz: freq,
                        });
                    }
                }
                (sets.sets(), Some(sets))
            }
            _ => (self.replicates(assignment)?, None),
        };
        Ok(Replicates {
            builder: self,
            plan,
            lines,
            sets,
            count,
        })
    }
}

impl Replicates<'_> {
    /// Number of replicates: paired sets, or records (cross-spectral estimators keeping their
    /// partials; 0 without).
    pub(crate) fn count(&self) -> usize {
        self.count
    }

    /// The `Frf` of the data with replicate `r` counted `weights[r]` times (see the module
    /// docs), on the full data's lines.
    pub(crate) fn frf(&self, weights: &[f64]) -> Frf {
        let mut frf = self.empty_frf();
        match &self.sets {
            Some(sets) => self.paired(sets, weights, &mut frf),
            None => self.cross(weights, &mut frf),
        }
        frf
    }

    /// The sums over every replicate (each counted once), for [`Replicates::without`]: paired
    /// sets `Σ_s H_s` at each line of the full data, cross-spectral estimators `S_ff`, `S_xf`,
    /// `S_xx` at each line of the plan.
    pub(crate) fn totals(&self) -> Totals {
        let nn = self.plan.n * self.plan.n;
        let zero = c64::new(0.0, 0.0);
        match &self.sets {
            Some(sets) => {
                let mut sums = vec![zero; self.lines.len() * nn];
                for (sum, &(l, ..)) in sums.chunks_exact_mut(nn).zip(&self.lines) {
                    for s in 0..self.count {
                        let hs = sets.impedance(s, l).expect("checked by replicates_on");
                        sum.iter_mut().zip(hs).for_each(|(t, h)| *t += h);
                    }
                }
                Totals { sums }
            }
            None => {
                // Every line of the plan: periodic records judge a line against the
                // strongest of them all.
                let mut sums = vec![zero; self.plan.lines.len() * 3 * nn];
                for (l, sum) in sums.chunks_exact_mut(3 * nn).enumerate() {
                    for (pff, pxf, pxx) in self.partials() {
                        for (t, p) in sum.chunks_exact_mut(nn).zip([pff, pxf, pxx]) {
                            t.iter_mut()
                                .zip(&p[l * nn..(l + 1) * nn])
                                .for_each(|(t, p)| *t += p);
                        }
                    }
                }
                Totals { sums }
            }
        }
    }

    /// The `Frf` of the data without replicate `r` (the jackknife's refit): `totals` (of
    /// [`Replicates::totals`]) less replicate `r`'s own term, on the full data's lines.
    pub(crate) fn without(&self, totals: &Totals, r: usize) -> Frf {
        let n = self.plan.n;
        let nn = n * n;
        let mut frf = self.empty_frf();
        match &self.sets {
            Some(sets) => {
                let kept = self.count - 1;
                frf.averages = kept;
                self.finish_paired(&mut frf, |at, l, h| {
                    let hr = sets.impedance(r, l).expect("checked by replicates_on");
                    let total = &totals.sums[at * nn..(at + 1) * nn];
                    for ((h, t), hr) in h.iter_mut().zip(total).zip(hr) {
                        *h = (t - hr) / kept as f64;
                    }
                });
            }
            None => {
                let own = match &self.builder.gathered[r].contribution {
                    Contribution::Cross { sff, sxf, sxx, .. } if !sff.is_empty() => {
                        Some([sff, sxf, sxx])
                    }
                    _ => None,
                };
                let kept = self.partials().count() - usize::from(own.is_some());
                frf.averages = kept * self.segments();
                self.finish_cross(&mut frf, |l, sums| {
                    let total = &totals.sums[l * 3 * nn..(l + 1) * 3 * nn];
                    sums.copy_from_slice(total);
                    if let Some(own) = own {
                        for (t, p) in sums.chunks_exact_mut(nn).zip(own) {
                            t.iter_mut()
                                .zip(&p[l * nn..(l + 1) * nn])
                                .for_each(|(t, p)| *t -= p);
                        }
                    }
                });
            }
        }
        frf
    }

    /// An `Frf` with no lines yet, of the builder's estimator and resolution.
    fn empty_frf(&self) -> Frf {
        let mut frf = Frf::empty(self.plan.n, self.builder.estimator);
        frf.spacing_hz = Some(self.plan.resolution_hz);
        frf
    }

    /// Paired sets: `H = Σ_s (w_s/Σw) H_s` over the sets with `w_s > 0`, in set order (as
    /// [`PairedKernel::average`] sums), then `G = H⁻¹`.
    fn paired(&self, sets: &SetTable, weights: &[f64], frf: &mut Frf) {
        let weight = |s: usize| weights.get(s).copied().unwrap_or(0.0);
        let used: Vec<usize> = (0..self.count).filter(|&s| weight(s) > 0.0).collect();
        let total_weight: f64 = used.iter().map(|&s| weight(s)).sum();
        frf.averages = used.len();
        self.finish_paired(frf, |_, l, h| {
            for &s in &used {
                let hs = sets.impedance(s, l).expect("checked by replicates_on");
                Share::Times(weight(s) / total_weight).add(h, hs);
            }
        });
    }

    /// Paired sets, every line: `H` written by `average(line index, plan line, H)` into
    /// zeros, then `G = H⁻¹`; a line whose `H` is singular is dropped.
    fn finish_paired(&self, frf: &mut Frf, mut average: impl FnMut(usize, usize, &mut [c64])) {
        let mut work = LineWork::new(self.plan.n);
        for (at, &(l, freq, cond)) in self.lines.iter().enumerate() {
            work.h.fill(c64::new(0.0, 0.0));
            average(at, l, &mut work.h);
            work.g.copy_from_slice(&work.h);
            if work.inverter.invert(&mut work.g) {
                frf.push_line(freq, &work.h, &work.g, cond);
            } else {
                frf.dropped_hz.push(freq);
            }
        }
    }

    /// Cross-spectral estimators: the records' partials `(S_ff, S_xf, S_xx)` (those that
    /// hold any), in record order, with their weights when given.
    fn partials(&self) -> impl Iterator<Item = (&[c64], &[c64], &[c64])> + '_ {
        self.weighted_partials(None)
            .map(|(ff, xf, xx, _)| (ff, xf, xx))
    }

    /// As [`Replicates::partials`], each with its weight (1 without `weights`), those of
    /// weight 0 left out.
    fn weighted_partials<'w>(
        &'w self,
        weights: Option<&'w [f64]>,
    ) -> impl Iterator<Item = (&'w [c64], &'w [c64], &'w [c64], f64)> + 'w {
        self.builder
            .gathered
            .iter()
            .enumerate()
            .filter_map(move |(r, g)| {
                let w = weights.map_or(1.0, |w| w.get(r).copied().unwrap_or(0.0));
                match &g.contribution {
                    Contribution::Cross { sff, sxf, sxx, .. } if w != 0.0 && !sff.is_empty() => {
                        Some((sff.as_slice(), sxf.as_slice(), sxx.as_slice(), w))
                    }
                    _ => None,
                }
            })
    }

    /// Welch segments (or periods) per record.
    fn segments(&self) -> usize {
        self.builder.segmentation.starts(self.plan.len).count()
    }

    /// Cross-spectral estimators: `S = Σ_r w_r S_r` over the records' partials, in record order
    /// (as the weighted finish sums), then the estimator's `G` and `H` per line.
    fn cross(&self, weights: &[f64], frf: &mut Frf) {
        let nn = self.plan.n * self.plan.n;
        let segments = self.segments() as f64;
        let averages: f64 = self
            .weighted_partials(Some(weights))
            .map(|(.., w)| w * segments)
            .sum();
        frf.averages = averages.round() as usize;
        self.finish_cross(frf, |l, sums| {
            sums.fill(c64::new(0.0, 0.0));
            for (pff, pxf, pxx, w) in self.weighted_partials(Some(weights)) {
                for (t, p) in sums.chunks_exact_mut(nn).zip([pff, pxf, pxx]) {
                    t.iter_mut()
                        .zip(&p[l * nn..(l + 1) * nn])
                        .for_each(|(t, p)| *t += p * w);
                }
            }
        });
    }

    /// Cross-spectral estimators, every line of the full data: the sums
    /// `[S_ff | S_xf | S_xx]` written by `sum(plan line, sums)`, then the estimator's `G` and
    /// `H`. Periodic records leave out the lines whose `tr S_ff` is below [`UNEXCITED_RATIO`]
    /// of the strongest line's (of the whole plan); a line whose sums are singular is dropped.
    fn finish_cross(&self, frf: &mut Frf, mut sum: impl FnMut(usize, &mut [c64])) {
        let n = self.plan.n;
        let nn = n * n;
        let zero = c64::new(0.0, 0.0);
        let mut sums = vec![zero; 3 * nn];
        // `tr S_ff` of a line (the real part of a complex sum is the sum of the real parts).
        let power = |sums: &[c64]| (0..n).map(|i| sums[i * (n + 1)].re).sum::<f64>();
        let periodic = matches!(self.builder.segmentation, Segmentation::Periods { .. });
        let strongest = if periodic {
            (0..self.plan.lines.len()).fold(0.0, |top: f64, l| {
                sum(l, &mut sums);
                top.max(power(&sums))
            })
        } else {
            0.0
        };
        let estimator = line_estimator(self.builder.estimator);
        // H1 compensated for the force noise the full data showed, at this replicate's
        // number of averages.
        let compensation = self
            .builder
            .compensation()
            .filter(|_| self.builder.estimator == Estimator::H1)
            .map(|c| &c.force[..]);
        let averages = frf.averages as f64;
        let mut work = LineWork::new(n);
        let (mut inv, mut compensated) = (vec![zero; nn], vec![zero; nn]);
        for &(l, freq, cond) in &self.lines {
            sum(l, &mut sums);
            if periodic && power(&sums) < UNEXCITED_RATIO * strongest {
                frf.unexcited_hz.push(freq);
                continue;
            }
            let (sf, rest) = sums.split_at(nn);
            let (sx, ss) = rest.split_at(nn);
            let sf = match compensation {
                Some(noise) => {
                    compensate(sf, &noise[l * n..(l + 1) * n], averages, &mut compensated);
                    &compensated[..]
                }
                None => sf,
            };
            inv.copy_from_slice(sf);
            let ok = work.inverter.invert(&mut inv) && {
                let sums = LineSums {
                    n,
                    sff: sf,
                    sff_inv: &inv,
                    sxf: sx,
                    sxx: ss,
                };
                estimator.estimate(&sums, &mut work)
            };
            if ok {
                frf.push_line(freq, &work.h, &work.g, cond);
            } else {
                frf.dropped_hz.push(freq);
            }
        }
    }
}

/// The sums over every replicate ([`Replicates::totals`]): paired sets `Σ_s H_s`, `n × n`
/// per line of the full data; cross-spectral estimators `S_ff`, `S_xf`, `S_xx`, `3 n × n` per
/// line of the plan.
#[derive(Debug)]
pub(crate) struct Totals {
    sums: Vec<c64>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frf::Band;
    use crate::simulate::{ImpactTest, seed_rig};
    use crate::spectra::Window;

    /// Bit for bit the weighted finish of the builder restricted to the full data's lines,
    /// for leave-one-out and resampling weights, paired sets and H1, with lines left out of
    /// the full data (as a coherence selection does); the leave-one-out replicates taken from
    /// the totals equal to it up to the rounding of the sums.
    #[test]
    fn replicates_are_the_weighted_finish_bit_for_bit() {
        let records = ImpactTest {
            per_direction: 4,
            noise: 0.05,
            ..ImpactTest::seed_rig()
        }
        .run(&seed_rig())
        .unwrap();
        let band = Band::new(8.0, 49.0).unwrap();
        let assignment = Assignment::DominantForce;
        for estimator in [Estimator::PairedSets, Estimator::H1, Estimator::Hv] {
            let mut builder = FrfBuilder::new(
                estimator,
                band,
                Segmentation::WholeRecord,
                Window::Rectangular,
            )
            .keeping_partials();
            builder.push_all(&records).unwrap();
            let full = builder.finish(&assignment).unwrap();
            let full = full.retain_lines(|k| k % 3 != 1);
            let shared = builder.replicates_on(&assignment, &full).unwrap();
            let count = shared.count();
            assert_eq!(
                count,
                if estimator == Estimator::PairedSets {
                    4
                } else {
                    8
                }
            );
            let mut all_weights: Vec<Vec<f64>> = (0..count)
                .map(|r| (0..count).map(|s| f64::from(u8::from(s != r))).collect())
                .collect();
            all_weights.push((0..count).map(|s| (s % 3) as f64).collect());
            for weights in &all_weights {
                let ours = shared.frf(weights);
                let reference = builder.finish_weighted(&assignment, weights).unwrap();
                let reference = reference.retain_lines(|k| {
                    let f = reference.freqs_hz()[k];
                    full.freqs_hz()
                        .binary_search_by(|u| u.total_cmp(&f))
                        .is_ok()
                });
                assert_eq!(ours.freqs_hz(), reference.freqs_hz(), "{estimator:?}");
                assert_eq!(ours.freqs_hz(), full.freqs_hz());
                assert_eq!(ours.averages(), reference.averages());
                for k in 0..ours.line_count() {
                    for (a, b) in [
                        (ours.impedance(k), reference.impedance(k)),
                        (ours.flexibility(k), reference.flexibility(k)),
                    ] {
                        for j in 0..2 {
                            for i in 0..2 {
                                let (a, b) = (a[(i, j)], b[(i, j)]);
                                assert_eq!(
                                    (a.re.to_bits(), a.im.to_bits()),
                                    (b.re.to_bits(), b.im.to_bits()),
                                    "{estimator:?} line {k}"
                                );
                            }
                        }
                    }
                }
                // The condition numbers are the full data's, not recomputed.
                assert_eq!(ours.condition_numbers(), full.condition_numbers());
            }
            // Leave-one-out from the totals: the same lines and averages, the same matrices
            // to the rounding of the sums.
            let totals = shared.totals();
            for (r, weights) in all_weights[..count].iter().enumerate() {
                let ours = shared.without(&totals, r);
                let reference = builder.finish_weighted(&assignment, weights).unwrap();
                assert_eq!(ours.freqs_hz(), full.freqs_hz(), "{estimator:?}");
                assert_eq!(ours.averages(), reference.averages(), "{estimator:?}");
                for k in 0..ours.line_count() {
                    let at = reference
                        .freqs_hz()
                        .iter()
                        .position(|f| f.to_bits() == ours.freqs_hz()[k].to_bits())
                        .unwrap();
                    for (a, b) in [
                        (ours.impedance(k), reference.impedance(at)),
                        (ours.flexibility(k), reference.flexibility(at)),
                    ] {
                        let scale = (0..4).map(|e| b[(e / 2, e % 2)].norm()).fold(0.0, f64::max);
                        for e in 0..4 {
                            let (a, b) = (a[(e / 2, e % 2)], b[(e / 2, e % 2)]);
                            assert!(
                                (a - b).norm() <= SUM_ROUNDING * scale,
                                "{estimator:?} without {r}, line {k}: {a} against {b}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// Leave-one-out sums taken from the totals against sums formed afresh: a few rounding
    /// errors of the largest term (8 replicates here), far below it.
    const SUM_ROUNDING: f64 = 1e-13;
}
