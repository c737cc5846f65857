//! What one record contributes to an estimator ([`Contribution`]): its band-line spectra
//! (paired sets) or its sums over segments of the cross-spectra (the cross-spectral
//! estimators), computed from the record alone so that records can be transformed in parallel
//! and merged in order ([`FrfBuilder`](super::FrfBuilder)); and the checks made on the way
//! (a dead channel, an overflowing spectrum).

use faer::c64;

use super::Estimator;
use super::builder::Plan;
use super::conversion::response_at_dc;
use crate::error::{Channel, Error, Result, SpectrumKind};
use crate::records::Record;
use crate::spectra::{Segmentation, SpectralEstimator};

/// What one record contributes to an estimator, computed independently of the others (so that
/// records can be transformed in parallel and merged in order, bit for bit the same).
#[derive(Debug, Clone)]
pub(super) enum Contribution {
    /// Band-line spectra `[line][channel]` for paired sets.
    Spectra {
        forces: Vec<c64>,
        displacements: Vec<c64>,
    },
    /// This record's sums over its segments of `F Fᴴ`, `X Fᴴ` and `X Xᴴ`, `[line][n × n]`,
    /// and of `F` and `X`, `[line][n]` (the first moments maximum likelihood needs).
    Cross {
        sff: Vec<c64>,
        sxf: Vec<c64>,
        sxx: Vec<c64>,
        sf: Vec<c64>,
        sx: Vec<c64>,
    },
}

/// One record's contribution: its band-line spectra (paired) or its segment sums (H1).
pub(super) fn contribute(
    estimator: Estimator,
    segmentation: Segmentation,
    plan: &Plan,
    spectral: &mut SpectralEstimator,
    record: &Record,
) -> Result<Contribution> {
    let (n, lines) = (plan.n, &plan.lines);
    let zero = c64::new(0.0, 0.0);
    let mut forces = vec![zero; lines.len() * n];
    let mut displacements = vec![zero; lines.len() * n];
    let mut transform = |start: usize, forces: &mut [c64], displacements: &mut [c64]| {
        let seg = start..start + plan.seg_len;
        for c in 0..n {
            let spec = spectral.transform_force(&record.force(c)[seg.clone()]);
            for (l, &k) in lines.iter().enumerate() {
                forces[l * n + c] = spec[k];
            }
            let spec = spectral.transform(&record.displacement(c)[seg.clone()]);
            let order = record.response(c).order() as usize;
            for (l, &k) in lines.iter().enumerate() {
                displacements[l * n + c] = match (order, plan.to_displacement[l][order]) {
                    (0, _) => spec[k],
                    (_, Some(factor)) => spec[k] * factor,
                    (_, None) => return Err(response_at_dc(record, plan, c, l)),
                };
            }
        }
        // The channels' known characteristics divided out, before any sum.
        for (l, correction) in plan.corrections.chunks_exact(2 * n).enumerate() {
            let (f, x) = correction.split_at(n);
            for c in 0..n {
                forces[l * n + c] *= f[c];
                displacements[l * n + c] *= x[c];
            }
        }
        for (values, channel) in [
            (&*forces, Channel::Force as fn(usize) -> Channel),
            (&*displacements, Channel::Displacement),
        ] {
            overflow_check(record, plan, SpectrumKind::Spectrum, values, n, channel)?;
        }
        Ok::<(), Error>(())
    };
    match estimator {
        Estimator::PairedSets => {
            transform(0, &mut forces, &mut displacements)?;
            Ok(Contribution::Spectra {
                forces,
                displacements,
            })
        }
        _ => {
            let nn = n * n;
            let mut sff = vec![zero; lines.len() * nn];
            let mut sxf = vec![zero; lines.len() * nn];
            let mut sxx = vec![zero; lines.len() * nn];
            let mut sf = vec![zero; lines.len() * n];
            let mut sx = vec![zero; lines.len() * n];
            for start in segmentation.starts(record.len()) {
                transform(start, &mut forces, &mut displacements)?;
                for (t, v) in sf.iter_mut().zip(&forces) {
                    *t += v;
                }
                for (t, v) in sx.iter_mut().zip(&displacements) {
                    *t += v;
                }
                for l in 0..lines.len() {
                    let (fl, xl) = (
                        &forces[l * n..(l + 1) * n],
                        &displacements[l * n..(l + 1) * n],
                    );
                    let (sf, sx, ss) = (
                        &mut sff[l * nn..(l + 1) * nn],
                        &mut sxf[l * nn..(l + 1) * nn],
                        &mut sxx[l * nn..(l + 1) * nn],
                    );
                    for j in 0..n {
                        let (fj, xj) = (fl[j].conj(), xl[j].conj());
                        for i in 0..n {
                            sf[i + j * n] += fl[i] * fj;
                            sx[i + j * n] += xl[i] * fj;
                            ss[i + j * n] += xl[i] * xj;
                        }
                    }
                }
            }
            for (values, channel) in [
                (&sff, Channel::Force as fn(usize) -> Channel),
                (&sxf, Channel::Displacement),
                (&sxx, Channel::Displacement),
            ] {
                overflow_check(
                    record,
                    plan,
                    SpectrumKind::CrossSpectrum,
                    values,
                    nn,
                    channel,
                )?;
            }
            Ok(Contribution::Cross {
                sff,
                sxf,
                sxx,
                sf,
                sx,
            })
        }
    }
}

/// [`Error::DeadChannel`] if every force channel, or every displacement channel, of `record`
/// is constant over the whole record.
pub(super) fn dead_channel(record: &Record) -> Option<Error> {
    let flat = |v: &[f64]| v.iter().all(|x| (x - v[0]).abs() <= 0.0);
    let n = record.dofs();
    let forces = (0..n).all(|c| flat(record.force(c)));
    let displacements = (0..n).all(|c| flat(record.displacement(c)));
    let channel = match (forces, displacements) {
        (true, _) => Channel::Force(0),
        (false, true) => Channel::Displacement(0),
        (false, false) => return None,
    };
    let value = match channel {
        Channel::Force(c) => record.force(c)[0],
        Channel::Displacement(c) => record.displacement(c)[0],
    };
    Some(Error::DeadChannel {
        record: record.label().to_owned(),
        channel,
        value,
    })
}

/// [`Error::LevelOutOfRange`] if every force channel, or every displacement channel, of
/// `record` peaks below $\sqrt{\text{f64::MIN\_POSITIVE}} \approx 1.5 \cdot 10^{-154}$ (but
/// not at zero: that is [`dead_channel`]'s), so that the squares and products of its spectra
/// underflow (subnormal samples are far below); or if some channel peaks above
/// $\sqrt{\text{f64::MAX}} \approx 1.3 \cdot 10^{154}$, where they overflow. Not an error by
/// itself (a channel's products may still fit, and records far out of scale with their siblings
/// are the screening's): the cause to name when the fit then fails.
pub(super) fn level_out_of_range(record: &Record) -> Option<Error> {
    let low = f64::MIN_POSITIVE.sqrt();
    let high = f64::MAX.sqrt();
    // The largest magnitude, as `fold(0.0, |m, x| m.max(x.abs()))` gives it (samples are
    // finite), in SIMD lanes.
    let peak = crate::lanes::max_abs;
    let n = record.dofs();
    for forces in [true, false] {
        let (c, top) = (0..n)
            .map(|c| {
                let samples = if forces {
                    record.force(c)
                } else {
                    record.displacement(c)
                };
                (c, peak(samples))
            })
            .fold((0, 0.0), |b, (c, p)| if p > b.1 { (c, p) } else { b });
        if (top > 0.0 && top < low) || top > high {
            return Some(Error::LevelOutOfRange {
                record: record.label().to_owned(),
                channel: if forces {
                    Channel::Force(c)
                } else {
                    Channel::Displacement(c)
                },
                peak: top,
            });
        }
    }
    None
}

/// [`Error::SpectrumOverflow`] at the first non-finite value of `values` (`[line][stride]`;
/// within a line, value `v` belongs to `channel(v % n)`, the row of an `n × n` matrix).
pub(super) fn overflow_check(
    record: &Record,
    plan: &Plan,
    stage: SpectrumKind,
    values: &[c64],
    stride: usize,
    channel: fn(usize) -> Channel,
) -> Result<()> {
    let Some(at) = values
        .iter()
        .position(|z| !(z.re.is_finite() && z.im.is_finite()))
    else {
        return Ok(());
    };
    let channel = channel(at % stride % plan.n);
    let samples = match channel {
        Channel::Force(c) => record.force(c),
        Channel::Displacement(c) => record.displacement(c),
    };
    Err(Error::SpectrumOverflow {
        record: record.label().to_owned(),
        stage,
        channel,
        freq_hz: plan.lines[at / stride] as f64 * plan.resolution_hz,
        peak: samples.iter().fold(0.0, |m, v| m.max(v.abs())),
    })
}
