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
//! The sums are formed again from the stored per-set impedances (per-record cross-spectra) in
//! the order of the full finish, not by subtracting the left-out term from the total: every
//! replicate is then bit for bit the one [`FrfBuilder`] would finish from the same weights.

use std::borrow::Cow;

use faer::c64;

use super::builder::{FrfBuilder, Plan};
use super::contribution::Contribution;
use super::cross::{LineSums, LineWork, UNEXCITED_RATIO, line_estimator};
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
        let b = self.builder;
        let n = self.plan.n;
        let mut frf = Frf::empty(n, b.estimator);
        frf.spacing_hz = Some(self.plan.resolution_hz);
        match &self.sets {
            Some(sets) => self.paired(sets, weights, &mut frf),
            None => self.cross(weights, &mut frf),
        }
        frf
    }

    /// Paired sets: `H = Σ_s (w_s/Σw) H_s` over the sets with `w_s > 0`, in set order (as
    /// [`PairedKernel::average`] sums), then `G = H⁻¹`.
    fn paired(&self, sets: &SetTable, weights: &[f64], frf: &mut Frf) {
        let n = self.plan.n;
        let weight = |s: usize| weights.get(s).copied().unwrap_or(0.0);
        let used: Vec<usize> = (0..self.count).filter(|&s| weight(s) > 0.0).collect();
        let total_weight: f64 = used.iter().map(|&s| weight(s)).sum();
        frf.averages = used.len();
        let mut work = LineWork::new(n);
        for &(l, freq, cond) in &self.lines {
            work.h.fill(c64::new(0.0, 0.0));
            for &s in &used {
                let hs = sets.impedance(s, l).expect("checked by replicates_on");
                Share::Times(weight(s) / total_weight).add(&mut work.h, hs);
            }
            work.g.copy_from_slice(&work.h);
            if work.inverter.invert(&mut work.g) {
                frf.push_line(freq, &work.h, &work.g, cond);
            } else {
                frf.dropped_hz.push(freq);
            }
        }
    }

    /// Cross-spectral estimators: `S = Σ_r w_r S_r` over the records' partials, in record order
    /// (as the weighted finish sums), then the estimator's `G` and `H` per line.
    fn cross(&self, weights: &[f64], frf: &mut Frf) {
        let (b, plan) = (self.builder, self.plan);
        let n = plan.n;
        let nn = n * n;
        let zero = c64::new(0.0, 0.0);
        let partials = || {
            b.gathered
                .iter()
                .zip(weights)
                .filter_map(|(g, &w)| match &g.contribution {
                    Contribution::Cross { sff, sxf, sxx, .. } if w != 0.0 && !sff.is_empty() => {
                        Some((sff, sxf, sxx, w))
                    }
                    _ => None,
                })
        };
        let segments = b.segmentation.starts(plan.len).count() as f64;
        let averages: f64 = partials().map(|(.., w)| w * segments).sum();
        frf.averages = averages.round() as usize;
        // `tr S_ff` of a line, from the weighted partials' diagonals (the real part of a
        // complex sum is the sum of the real parts, bit for bit).
        let power = |l: usize| {
            (0..n)
                .map(|i| partials().fold(zero, |t, (sff, .., w)| t + sff[l * nn + i * (n + 1)] * w))
                .map(|z| z.re)
                .sum::<f64>()
        };
        let periodic = matches!(b.segmentation, Segmentation::Periods { .. });
        let strongest = if periodic {
            (0..plan.lines.len()).map(power).fold(0.0, f64::max)
        } else {
            0.0
        };
        let estimator = line_estimator(b.estimator);
        let mut work = LineWork::new(n);
        let (mut sf, mut sx, mut ss, mut inv) = (
            vec![zero; nn],
            vec![zero; nn],
            vec![zero; nn],
            vec![zero; nn],
        );
        for &(l, freq, cond) in &self.lines {
            for t in [&mut sf, &mut sx, &mut ss] {
                t.fill(zero);
            }
            let range = l * nn..(l + 1) * nn;
            for (pff, pxf, pxx, w) in partials() {
                for (t, p) in [(&mut sf, pff), (&mut sx, pxf), (&mut ss, pxx)] {
                    t.iter_mut()
                        .zip(&p[range.clone()])
                        .for_each(|(t, p)| *t += p * w);
                }
            }
            if periodic && power(l) < UNEXCITED_RATIO * strongest {
                frf.unexcited_hz.push(freq);
                continue;
            }
            inv.copy_from_slice(&sf);
            let ok = work.inverter.invert(&mut inv) && {
                let sums = LineSums {
                    n,
                    sff: &sf,
                    sff_inv: &inv,
                    sxf: &sx,
                    sxx: &ss,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frf::Band;
    use crate::simulate::{ImpactTest, seed_rig};
    use crate::spectra::Window;

    /// Bit for bit the weighted finish of the builder restricted to the full data's lines,
    /// for leave-one-out and resampling weights, paired sets and H1, with lines left out of
    /// the full data (as a coherence selection does).
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
        }
    }
}
