//! Multiple and ordinary coherence per line, for every estimator: from the accumulated
//! cross-spectra (H1, H2, Hv) or from the band-line spectra of all records (paired sets).

use faer::c64;

use crate::linalg::Inverter;

/// Multiple and ordinary coherences at one line from `S_ff`, its inverse, `S_xf` (all `n × n`
/// column-major) and the output auto-spectra `S_xᵢxᵢ`.
pub(super) fn line_coherence(
    n: usize,
    sff: &[c64],
    sff_inv: &[c64],
    sxf: &[c64],
    sxx: &[f64],
    multiple: &mut [f64],
    ordinary: &mut [f64],
) {
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
/// (each `n` values at this line): their cross-spectra are summed record by record, then as
/// [`line_coherence`]; zero when `S_ff` is singular. The buffers hold `n × n` (`sff`, `sxf`,
/// `inv`, `ordinary`) or `n` (`sxx`, `multiple`) values.
pub(super) struct SpectraCoherence {
    n: usize,
    sff: Vec<c64>,
    sxf: Vec<c64>,
    inv: Vec<c64>,
    sxx: Vec<f64>,
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
            multiple: vec![0.0; n],
            ordinary: vec![0.0; nn],
        }
    }

    /// Coherences of one line from every record's `(forces, displacements)` at it.
    pub(super) fn line<'a>(
        &mut self,
        records: impl IntoIterator<Item = (&'a [c64], &'a [c64])>,
        inverter: &mut Inverter,
    ) {
        let n = self.n;
        let zero = c64::new(0.0, 0.0);
        self.sff.fill(zero);
        self.sxf.fill(zero);
        self.sxx.fill(0.0);
        for (fl, xl) in records {
            for j in 0..n {
                let fj = fl[j].conj();
                for i in 0..n {
                    self.sff[i + j * n] += fl[i] * fj;
                    self.sxf[i + j * n] += xl[i] * fj;
                }
            }
            for (t, x) in self.sxx.iter_mut().zip(xl) {
                *t += x.norm_sqr();
            }
        }
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
