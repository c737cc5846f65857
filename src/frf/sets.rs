//! [`SetTable`]: each paired set's own `cond(X_s)` and `H_s = F_s X_s⁻¹` (the seed's eq. 9
//! for one set) on every band line, computed once per builder and excitation and then read by
//! all three users: the per-line test of the sets (screening), the paired finish and the
//! replicates of the error bars. Before, each of them inverted every `X_s` again.

use std::borrow::Cow;

use faer::c64;

use super::Estimator;
use super::builder::FrfBuilder;
use super::paired::{PairedKernel, by_direction};
use crate::linalg;

/// Per paired set `s` and band line `l` (the builder's plan lines): `cond(X_s)` and
/// `H_s = F_s X_s⁻¹`, or nothing where `X_s` is singular.
///
/// Built by [`FrfBuilder::set_table`]; each value is the one [`PairedKernel`] computes for the
/// same set and line, bit for bit (the same condition number, the same inversion and product:
/// for three degrees of freedom the kernel's cofactors, run by [`linalg::right_divide3`] four
/// lines at a time).
#[derive(Debug, Clone)]
pub(crate) struct SetTable {
    /// The excitation (direction per record, push order) the sets were formed from.
    excitation: Vec<usize>,
    n: usize,
    lines: usize,
    /// Records (push order) of each set, one per direction.
    pub(crate) records: Vec<Vec<usize>>,
    /// `[set][line]`: `H_s`, column-major `n × n` (zeros where singular).
    impedance: Vec<c64>,
    /// `[set][line]`: whether `X_s` could be inverted.
    regular: Vec<bool>,
    /// `[set][line]`: `cond(X_s)`.
    condition: Vec<f64>,
}

impl SetTable {
    /// Number of complete sets (the fewest records over the directions).
    pub(crate) fn sets(&self) -> usize {
        self.records.len()
    }

    /// Number of band lines.
    pub(crate) fn lines(&self) -> usize {
        self.lines
    }

    /// Degrees of freedom.
    pub(crate) fn dofs(&self) -> usize {
        self.n
    }

    /// `H_s` of set `s` at line `l` (column-major), `None` where `X_s` is singular.
    pub(crate) fn impedance(&self, s: usize, l: usize) -> Option<&[c64]> {
        let at = s * self.lines + l;
        let nn = self.n * self.n;
        self.regular[at].then(|| &self.impedance[at * nn..(at + 1) * nn])
    }

    /// `cond(X_s)` of set `s` at line `l`.
    pub(crate) fn condition(&self, s: usize, l: usize) -> f64 {
        self.condition[s * self.lines + l]
    }
}

impl FrfBuilder {
    /// The [`SetTable`] of the records pushed, their sets formed by `excitation` (as
    /// [`FrfBuilder::excitations`] resolves it). Computed on the first call and kept until the
    /// next [`FrfBuilder::push`] or [`FrfBuilder::remove`]; a call with another excitation
    /// computes a table of its own. Empty (no set) unless paired sets.
    pub(crate) fn set_table(&self, excitation: &[usize]) -> Cow<'_, SetTable> {
        if let Some(table) = self.sets.get() {
            if table.excitation == excitation {
                return Cow::Borrowed(table);
            }
            return Cow::Owned(self.compute_set_table(excitation));
        }
        // A racing first call would compute the same table; the first stored is kept.
        Cow::Borrowed(self.sets.get_or_init(|| self.compute_set_table(excitation)))
    }

    fn compute_set_table(&self, excitation: &[usize]) -> SetTable {
        let (n, lines) = match &self.plan {
            Some((plan, _)) if self.estimator == Estimator::PairedSets => {
                (plan.n, plan.lines.len())
            }
            _ => (0, 0),
        };
        let mut table = SetTable {
            excitation: excitation.to_vec(),
            n,
            lines,
            records: Vec::new(),
            impedance: Vec::new(),
            regular: Vec::new(),
            condition: Vec::new(),
        };
        if n == 0 {
            return table;
        }
        let nn = n * n;
        let by_direction = by_direction(excitation, n);
        let sets = by_direction.iter().map(Vec::len).min().unwrap_or(0);
        let zero = c64::new(0.0, 0.0);
        // Filled in order, set by set and line by line (no zeroing pass first).
        table.impedance = Vec::with_capacity(sets * lines * nn);
        table.regular = Vec::with_capacity(sets * lines);
        table.condition = vec![0.0; sets * lines];
        // One set's displacement matrices on every line side by side: their condition numbers
        // are computed together, and for three degrees of freedom their quotients `F_s X_s⁻¹`
        // too, several lines at a time ([`linalg::right_divide3`], the kernel's operations).
        let mut xs = vec![zero; lines * nn];
        let lanes = n == 3;
        let mut fs = vec![zero; if lanes { lines * nn } else { 0 }];
        let mut conditioner = linalg::Conditioner::new(n);
        let mut inverter = linalg::Inverter::new(n);
        let mut kernel = PairedKernel::new(n);
        for s in 0..sets {
            let records: Vec<usize> = by_direction.iter().map(|d| d[s]).collect();
            let columns = |l: usize| {
                records.iter().map(move |&r| {
                    self.spectra_at(r, l, n)
                        .expect("paired builders gather spectra")
                })
            };
            // Column `j` of line `l`'s matrices: record `j`'s values at that line.
            for (j, &r) in records.iter().enumerate() {
                let (f, x) = self.spectra_of(r).expect("paired builders gather spectra");
                for (xl, xr) in xs.chunks_exact_mut(nn).zip(x.chunks_exact(n)) {
                    xl[j * n..(j + 1) * n].copy_from_slice(xr);
                }
                if lanes {
                    for (fl, fr) in fs.chunks_exact_mut(nn).zip(f.chunks_exact(n)) {
                        fl[j * n..(j + 1) * n].copy_from_slice(fr);
                    }
                }
            }
            let at = s * lines;
            conditioner.condition_numbers(&xs, &mut table.condition[at..at + lines]);
            if lanes {
                linalg::right_divide3(
                    &mut inverter,
                    &fs,
                    &xs,
                    &mut table.impedance,
                    &mut table.regular,
                );
            } else {
                for l in 0..lines {
                    let h = kernel.set_impedance(columns(l));
                    table.regular.push(h.is_some());
                    match h {
                        Some(h) => table.impedance.extend_from_slice(h),
                        None => table.impedance.extend(std::iter::repeat_n(zero, nn)),
                    }
                }
            }
            table.records.push(records);
        }
        table
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frf::{Assignment, Band};
    use crate::records::Record;
    use crate::simulate::{ImpactTest, seed_rig};
    use crate::spectra::{Segmentation, Window};

    fn builder(records: &[Record]) -> FrfBuilder {
        let band = Band::new(8.0, 49.0).unwrap();
        let mut b = FrfBuilder::new(
            Estimator::PairedSets,
            band,
            Segmentation::WholeRecord,
            Window::Rectangular,
        );
        b.push_all(records).unwrap();
        b
    }

    fn bits(frf: &super::super::Frf) -> Vec<u64> {
        let mut out: Vec<u64> = frf
            .condition_numbers()
            .iter()
            .map(|c| c.to_bits())
            .collect();
        for k in 0..frf.line_count() {
            let h = frf.impedance(k);
            for j in 0..2 {
                for i in 0..2 {
                    out.extend([h[(i, j)].re.to_bits(), h[(i, j)].im.to_bits()]);
                }
            }
        }
        out
    }

    /// Three degrees of freedom, where the table's quotients come from
    /// [`linalg::right_divide3`]'s lanes: every value is still the kernel's bit for bit, and
    /// within rounding (`ε·κ`) of the Gauss–Jordan quotient the kernel used before.
    #[test]
    fn three_dof_table_is_the_kernel_and_gauss_jordan_to_rounding() {
        let system = crate::model::Coefficients::new(
            faer::mat![[2.0, 0.1, 0.0], [0.1, 2.5, 0.2], [0.0, 0.2, 3.0]],
            faer::mat![[60.0, 8.0, -3.0], [-5.0, 70.0, 4.0], [2.0, -6.0, 80.0]],
            faer::mat![[4e5, 6e4, -1e4], [2e4, 6e5, 5e4], [-2e4, 1e4, 9e5]],
        )
        .unwrap();
        let records = ImpactTest {
            per_direction: 2,
            sample_rate: 4096.0,
            duration_s: 2.0,
            noise: 0.03,
            seed: 5,
            ..ImpactTest::seed_rig()
        }
        .run(&system)
        .unwrap();
        let mut b = FrfBuilder::new(
            Estimator::PairedSets,
            Band::new(20.0, 250.0).unwrap(),
            Segmentation::WholeRecord,
            Window::Rectangular,
        );
        b.push_all(&records).unwrap();
        let excitation = b.excitations(&Assignment::DominantForce).unwrap();
        let table = b.set_table(&excitation);
        assert_eq!((table.sets(), table.dofs()), (2, 3));
        let (n, nn) = (3, 9);
        let mut kernel = PairedKernel::new(n);
        let mut conditioner = linalg::Conditioner::new(n);
        let mut inverter = linalg::Inverter::new(n);
        let zero = c64::new(0.0, 0.0);
        let (mut x, mut f, mut gj) = (vec![zero; nn], vec![zero; nn], vec![zero; nn]);
        for s in 0..table.sets() {
            for l in 0..table.lines() {
                let columns = || {
                    table.records[s]
                        .iter()
                        .map(|&r| b.spectra_at(r, l, n).unwrap())
                };
                for (j, (fr, xr)) in columns().enumerate() {
                    x[j * n..(j + 1) * n].copy_from_slice(xr);
                    f[j * n..(j + 1) * n].copy_from_slice(fr);
                }
                let cond = conditioner.condition_number(&x);
                assert_eq!(table.condition(s, l).to_bits(), cond.to_bits());
                let h = table.impedance(s, l).unwrap();
                assert_eq!(h, kernel.set_impedance(columns()).unwrap());
                assert!(inverter.invert(&mut x));
                linalg::mul_into(&f, &x, &mut gj, n);
                let norm = |m: &[c64]| m.iter().fold(0.0_f64, |a, z| a.max(z.norm()));
                let diff: Vec<c64> = h.iter().zip(&gj).map(|(a, b)| a - b).collect();
                assert!(
                    norm(&diff) <= 100.0 * f64::EPSILON * cond * norm(&gj),
                    "set {s} line {l}: {} vs {}",
                    norm(&diff),
                    norm(&gj)
                );
            }
        }
    }

    /// The table holds the kernel's values, is computed once, and is computed again after
    /// records go out: the finish is then that of a builder that never had them.
    #[test]
    fn table_is_the_kernel_kept_until_the_records_change() {
        let records = ImpactTest {
            per_direction: 4,
            noise: 0.05,
            ..ImpactTest::seed_rig()
        }
        .run(&seed_rig())
        .unwrap();
        let mut b = builder(&records);
        let excitation = b.excitations(&Assignment::DominantForce).unwrap();
        let table = b.set_table(&excitation);
        assert!(matches!(table, Cow::Borrowed(_)));
        assert_eq!((table.sets(), table.dofs()), (4, 2));
        let again = b.set_table(&excitation);
        assert!(std::ptr::eq(&*table, &*again));
        // Every value is the kernel's, bit for bit.
        let mut kernel = PairedKernel::new(2);
        let mut conditioner = linalg::Conditioner::new(2);
        let mut x = vec![c64::new(0.0, 0.0); 4];
        for s in 0..table.sets() {
            for l in 0..table.lines() {
                let columns = || {
                    table.records[s]
                        .iter()
                        .map(|&r| b.spectra_at(r, l, 2).unwrap())
                };
                for (j, (_, xr)) in columns().enumerate() {
                    x[j * 2..(j + 1) * 2].copy_from_slice(xr);
                }
                let cond = conditioner.condition_number(&x);
                assert_eq!(table.condition(s, l).to_bits(), cond.to_bits());
                let h = kernel.set_impedance(columns()).unwrap();
                assert_eq!(table.impedance(s, l).unwrap(), h);
            }
        }
        // Another excitation: a table of its own, the kept one untouched.
        let swapped: Vec<usize> = excitation.iter().map(|&e| 1 - e).collect();
        assert!(matches!(b.set_table(&swapped), Cow::Owned(_)));
        assert!(std::ptr::eq(&*b.set_table(&excitation), &*table));
        // Take the second set out: the finish is that of the records without it.
        let out = table.records[1].clone();
        drop((table, again));
        b.remove(&out);
        let kept: Vec<Record> = records
            .iter()
            .enumerate()
            .filter(|(r, _)| !out.contains(r))
            .map(|(_, r)| r.clone())
            .collect();
        let fresh = builder(&kept).finish(&Assignment::DominantForce).unwrap();
        let after = b.finish(&Assignment::DominantForce).unwrap();
        assert_eq!(after.averages(), 3);
        assert_eq!(bits(&after), bits(&fresh));
    }
}
