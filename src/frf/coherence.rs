//! Multiple and ordinary coherence per line, for every estimator: from the accumulated
//! cross-spectra (H1, H2, Hv) or from the band-line spectra of all records (paired sets).

use faer::c64;
use faer::traits::pulp::{Arch, Simd, WithSimd};

use crate::lanes::LANES;
use crate::linalg::Inverter;

/// Multiple and ordinary coherences at one line from `S_ff`, its inverse, `S_xf` (all `n × n`
/// column-major) and the output auto-spectra `S_xᵢxᵢ`; unrolled for `n ≤ 4` (the same
/// operations in the same order).
pub(super) fn line_coherence(
    n: usize,
    sff: &[c64],
    sff_inv: &[c64],
    sxf: &[c64],
    sxx: &[f64],
    multiple: &mut [f64],
    ordinary: &mut [f64],
) {
    let (spectra, out) = ((sff, sff_inv, sxf, sxx), (multiple, ordinary));
    match n {
        1 => coherences(1, spectra, out),
        2 => coherences(2, spectra, out),
        3 => coherences(3, spectra, out),
        4 => coherences(4, spectra, out),
        n => coherences(n, spectra, out),
    }
}

/// [`line_coherence`], inlined so that a constant `n` unrolls it.
#[inline(always)]
fn coherences(
    n: usize,
    (sff, sff_inv, sxf, sxx): (&[c64], &[c64], &[c64], &[f64]),
    (multiple, ordinary): (&mut [f64], &mut [f64]),
) {
    let nn = n * n;
    let (sff, sff_inv, sxf, sxx) = (&sff[..nn], &sff_inv[..nn], &sxf[..nn], &sxx[..n]);
    let (multiple, ordinary) = (&mut multiple[..n], &mut ordinary[..nn]);
    for i in 0..n {
        let mut explained = c64::new(0.0, 0.0);
        for a in 0..n {
            for b in 0..n {
                explained += sxf[i + a * n] * sff_inv[a + b * n] * sxf[i + b * n].conj();
            }
        }
        multiple[i] = explained.re / sxx[i];
        for j in 0..n {
            ordinary[i + j * n] = sxf[i + j * n].norm_sqr() / (sxx[i] * sff[j + j * n].re);
        }
    }
}

/// Coherences at one line from the band-line spectra `(forces, displacements)` of every record
/// (each `n` values at this line): their cross-spectra are summed over the records, then as
/// [`line_coherence`]; zero when `S_ff` is singular. The buffers hold `n × n` (`sff`, `sxf`,
/// `inv`, `ordinary`) or `n` (`sxx`, `multiple`) values.
///
/// The sums run over the records with the channels' real and imaginary parts apart
/// (`[part][channel][record]`), in [`LANES`] independent lanes and through faer's SIMD
/// dispatch: `S_{ab,ij} = Σ_r a_i b̄_j` as `Σ (a'b' + a''b'') + i Σ (a''b' − a'b'')`.
pub(super) struct SpectraCoherence {
    n: usize,
    sff: Vec<c64>,
    sxf: Vec<c64>,
    inv: Vec<c64>,
    sxx: Vec<f64>,
    /// The line's spectra, `4n` rows of one value per record (row `q` at
    /// `q · records..(q + 1) · records`): forces' real parts, forces' imaginary parts, then
    /// the same of the displacements.
    parts: Vec<f64>,
    /// Multiple coherence of every output at the last line.
    pub(super) multiple: Vec<f64>,
    /// Ordinary coherence at the last line, `n × n` column-major.
    pub(super) ordinary: Vec<f64>,
}

impl SpectraCoherence {
    pub(super) fn new(n: usize) -> Self {
        let (zero, nn) = (c64::new(0.0, 0.0), n * n);
        Self {
            n,
            sff: vec![zero; nn],
            sxf: vec![zero; nn],
            inv: vec![zero; nn],
            sxx: vec![0.0; n],
            parts: Vec::new(),
            multiple: vec![0.0; n],
            ordinary: vec![0.0; nn],
        }
    }

    /// Coherences of one line from every record's `(forces, displacements)` at it.
    pub(super) fn line<'a>(
        &mut self,
        records: impl IntoIterator<Item = (&'a [c64], &'a [c64]), IntoIter: ExactSizeIterator>,
        inverter: &mut Inverter,
    ) {
        let n = self.n;
        let records = records.into_iter();
        let count = records.len();
        self.parts.resize(4 * n * count, 0.0);
        let parts = &mut self.parts[..];
        match n {
            2 => gather(parts, 2, count, records),
            3 => gather(parts, 3, count, records),
            4 => gather(parts, 4, count, records),
            n => gather(parts, n, count, records),
        }
        Arch::new().dispatch(Sums {
            n,
            records: count,
            parts: &self.parts,
            sff: &mut self.sff,
            sxf: &mut self.sxf,
            sxx: &mut self.sxx,
        });
        self.inv.copy_from_slice(&self.sff);
        if inverter.invert(&mut self.inv) {
            line_coherence(
                n,
                &self.sff,
                &self.inv,
                &self.sxf,
                &self.sxx,
                &mut self.multiple,
                &mut self.ordinary,
            );
        } else {
            self.multiple.fill(0.0);
            self.ordinary.fill(0.0);
        }
    }
}

/// The gather of [`SpectraCoherence::line`]: record `r`'s channel `c` into column `r` of rows
/// `c`, `n + c` (force, real and imaginary parts), `2n + c`, `3n + c` (displacement) of
/// `parts` (`4n` rows of `count` values); inlined so that a constant `n` unrolls it.
#[inline(always)]
fn gather<'a>(
    parts: &mut [f64],
    n: usize,
    count: usize,
    records: impl Iterator<Item = (&'a [c64], &'a [c64])>,
) {
    let (forces, displacements) = parts[..4 * n * count].split_at_mut(2 * n * count);
    let (f_re, f_im) = forces.split_at_mut(n * count);
    let (x_re, x_im) = displacements.split_at_mut(n * count);
    for (r, (fl, xl)) in records.take(count).enumerate() {
        let (fl, xl) = (&fl[..n], &xl[..n]);
        for c in 0..n {
            let at = c * count + r;
            f_re[at] = fl[c].re;
            f_im[at] = fl[c].im;
            x_re[at] = xl[c].re;
            x_im[at] = xl[c].im;
        }
    }
}

/// The sums of [`SpectraCoherence::line`] (a named operation, so that the SIMD dispatch
/// compiles its body for the processor's widest instructions).
struct Sums<'a> {
    n: usize,
    records: usize,
    parts: &'a [f64],
    sff: &'a mut [c64],
    sxf: &'a mut [c64],
    sxx: &'a mut [f64],
}

impl WithSimd for Sums<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) {
        // A constant `n` for the small systems unrolls the channel loops.
        match self.n {
            2 => self.sums(2),
            3 => self.sums(3),
            4 => self.sums(4),
            n => self.sums(n),
        }
    }
}

impl Sums<'_> {
    #[inline(always)]
    fn sums(self, n: usize) {
        let count = self.records;
        let row = |q: usize| &self.parts[q * count..(q + 1) * count];
        let (f_re, f_im) = (|c: usize| row(c), |c: usize| row(n + c));
        let (x_re, x_im) = (|c: usize| row(2 * n + c), |c: usize| row(3 * n + c));
        for j in 0..n {
            for i in 0..=j {
                let s = cross_sum(f_re(i), f_im(i), f_re(j), f_im(j));
                self.sff[i + j * n] = s;
                if i != j {
                    self.sff[j + i * n] = s.conj();
                }
            }
            for i in 0..n {
                self.sxf[i + j * n] = cross_sum(x_re(i), x_im(i), f_re(j), f_im(j));
            }
            self.sxx[j] = cross_sum(x_re(j), x_im(j), x_re(j), x_im(j)).re;
        }
    }
}

/// `Σ_r a_r b̄_r` of two channels given by their real and imaginary parts, in [`LANES`] lanes
/// (the remainder folded into lanes `0..`), combined as `(l₀ + l₁) + (l₂ + l₃)`.
#[inline(always)]
fn cross_sum(a_re: &[f64], a_im: &[f64], b_re: &[f64], b_im: &[f64]) -> c64 {
    let (mut re, mut im) = ([0.0; LANES], [0.0; LANES]);
    let len = a_re.len();
    let (a_re, a_im, b_re, b_im) = (a_re, &a_im[..len], &b_re[..len], &b_im[..len]);
    // Whole groups of LANES as fixed-size arrays, so that the lanes are one vector.
    for (((ar, ai), br), bi) in a_re
        .chunks_exact(LANES)
        .zip(a_im.chunks_exact(LANES))
        .zip(b_re.chunks_exact(LANES))
        .zip(b_im.chunks_exact(LANES))
    {
        for k in 0..LANES {
            re[k] += ar[k] * br[k] + ai[k] * bi[k];
            im[k] += ai[k] * br[k] - ar[k] * bi[k];
        }
    }
    let whole = len - len % LANES;
    for (k, r) in (whole..len).enumerate() {
        re[k] += a_re[r] * b_re[r] + a_im[r] * b_im[r];
        im[k] += a_im[r] * b_re[r] - a_re[r] * b_im[r];
    }
    c64::new(
        (re[0] + re[1]) + (re[2] + re[3]),
        (im[0] + im[1]) + (im[2] + im[3]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lane-wise sums are the record-by-record complex sums to rounding, for record
    /// counts on and off the lanes, with `S_ff` Hermitian exactly.
    #[test]
    fn sums_match_the_record_by_record_sums() {
        let n = 3;
        let z = |k: usize| c64::new((k as f64 * 0.61).sin() * 3.0, (k as f64 * 1.37).cos());
        let mut coherence = SpectraCoherence::new(n);
        let mut inverter = Inverter::new(n);
        for records in 1..=9 {
            let spectra: Vec<(Vec<c64>, Vec<c64>)> = (0..records)
                .map(|r| {
                    let f = (0..n).map(|i| z(r * 11 + i)).collect();
                    let x = (0..n).map(|i| z(r * 7 + i + 100) * 1e-6).collect();
                    (f, x)
                })
                .collect();
            coherence.line(
                spectra.iter().map(|(f, x)| (f.as_slice(), x.as_slice())),
                &mut inverter,
            );
            for j in 0..n {
                for i in 0..n {
                    let (mut sff, mut sxf) = (c64::new(0.0, 0.0), c64::new(0.0, 0.0));
                    for (f, x) in &spectra {
                        sff += f[i] * f[j].conj();
                        sxf += x[i] * f[j].conj();
                    }
                    let ours = coherence.sff[i + j * n];
                    assert!(
                        (ours - sff).norm() <= 1e-14 * records as f64 * 10.0,
                        "{ours} {sff}"
                    );
                    let ours = coherence.sxf[i + j * n];
                    assert!(
                        (ours - sxf).norm() <= 1e-20 * records as f64 * 10.0,
                        "{ours} {sxf}"
                    );
                    let mirror = coherence.sff[j + i * n].conj();
                    assert_eq!(coherence.sff[i + j * n], mirror);
                }
                let sxx: f64 = spectra.iter().map(|(_, x)| x[j].norm_sqr()).sum();
                assert!((coherence.sxx[j] - sxx).abs() <= 1e-26 * records as f64);
            }
            // Multiple coherence within [0, 1] (one record: every output fully explained).
            for &m in &coherence.multiple {
                assert!((0.0..=1.0 + 1e-12).contains(&m), "{records}: {m}");
            }
        }
    }

    /// Every size, the unrolled ones (n ≤ 4) and the general one: the sums are the
    /// record-by-record sums, and the multiple coherence is $s_i^H S_{ff}^{-1} s_i / S_{x_ix_i}$
    /// from faer's inverse, to rounding.
    #[test]
    fn every_size_gives_the_direct_sums_and_coherence() {
        use faer::linalg::solvers::DenseSolveCore;
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let mut z = |_: usize| c64::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        for n in 1..=5 {
            let mut coherence = SpectraCoherence::new(n);
            let mut inverter = Inverter::new(n);
            for records in [n + 1, 2 * n + 3] {
                let spectra: Vec<(Vec<c64>, Vec<c64>)> = (0..records)
                    .map(|r| {
                        let f = (0..n).map(|i| z(r * 13 + i)).collect();
                        let x = (0..n).map(|i| z(r * 5 + 3 * i + 50)).collect();
                        (f, x)
                    })
                    .collect();
                coherence.line(
                    spectra.iter().map(|(f, x)| (f.as_slice(), x.as_slice())),
                    &mut inverter,
                );
                let cross = |a: &dyn Fn(usize) -> c64, b: &dyn Fn(usize) -> c64| {
                    (0..records).fold(c64::new(0.0, 0.0), |s, r| s + a(r) * b(r).conj())
                };
                let sff = faer::Mat::from_fn(n, n, |i, j| {
                    cross(&|r| spectra[r].0[i], &|r| spectra[r].0[j])
                });
                let sff_inv = sff.partial_piv_lu().inverse();
                for i in 0..n {
                    let sxf: Vec<c64> = (0..n)
                        .map(|j| cross(&|r| spectra[r].1[i], &|r| spectra[r].0[j]))
                        .collect();
                    let sxx = cross(&|r| spectra[r].1[i], &|r| spectra[r].1[i]).re;
                    let mut explained = c64::new(0.0, 0.0);
                    for a in 0..n {
                        assert!((coherence.sxf[i + a * n] - sxf[a]).norm() < 1e-12);
                        assert!((coherence.sff[i + a * n] - sff[(i, a)]).norm() < 1e-12);
                        for b in 0..n {
                            explained += sxf[a] * sff_inv[(a, b)] * sxf[b].conj();
                        }
                    }
                    assert!((coherence.sxx[i] - sxx).abs() < 1e-12 * sxx);
                    let multiple = explained.re / sxx;
                    assert!(
                        (coherence.multiple[i] - multiple).abs() < 1e-10,
                        "n = {n}, {records} records: {} vs {multiple}",
                        coherence.multiple[i]
                    );
                    for j in 0..n {
                        let ordinary = sxf[j].norm_sqr() / (sxx * sff[(j, j)].re);
                        assert!((coherence.ordinary[i + j * n] - ordinary).abs() < 1e-12);
                    }
                }
            }
        }
    }
}
