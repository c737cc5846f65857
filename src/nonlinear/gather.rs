//! The reverse path's inputs and their Welch sums: per record, the displacements and
//! velocities ([`Differentiator`]), the regressor time series $y_j(x, \dot x)$ of every term,
//! and per Welch segment (Hann, 50 % overlap, the planned FFTs of [`SpectralEstimator`]) the
//! cross-spectral sums of the forces $f$ and the inputs $z = [x;\, u]$ at the band lines.
//!
//! A term's force shape is an $n$-vector; each of its non-zero components is one scalar input
//! $u_c$ of the reverse path (one per DOF term, two for `coulomb-planar`), so that
//! $F = H X + \sum_c A_c U_c$ with $A_c$ an $n$-vector per line.
//!
//! The sums are kept per jackknife block: the segments of all records, in order, cut into at
//! most [`REVERSE_PATH_JACKKNIFE_BLOCKS`] contiguous blocks.

use faer::c64;

use crate::error::{Error, Result};
use crate::frf::Band;
use crate::records::{Record, Response, Shape};
use crate::spectra::{Segmentation, SpectralEstimator, Window};
use crate::tolerance::REVERSE_PATH_JACKKNIFE_BLOCKS;

use super::velocity::{Differentiation, Differentiator, VelocityChoice};
use super::{Regressor, Term};

/// One scalar input of the reverse path from a nonlinear term: component `dof` of the force
/// shape of term `term` (an index into the term list).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct InputChannel {
    pub term: usize,
    pub dof: usize,
}

/// The scalar inputs of `terms` for `n` DOFs, in term order.
pub(crate) fn input_channels(terms: &[Term]) -> Vec<InputChannel> {
    let mut out = Vec::new();
    for (j, t) in terms.iter().enumerate() {
        match t.dof {
            Some(i) => out.push(InputChannel { term: j, dof: i }),
            None => out.extend([0, 1].map(|i| InputChannel { term: j, dof: i })),
        }
    }
    out
}

/// Cross-spectral sums at the band lines, column-major per line: `zz` (`q × q`), `fz`
/// (`n × q`), `ff` (`n × n`), over `segments` Welch segments.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BlockSums {
    pub zz: Vec<c64>,
    pub fz: Vec<c64>,
    pub ff: Vec<c64>,
    pub segments: usize,
}

impl BlockSums {
    fn zeros(lines: usize, n: usize, q: usize) -> Self {
        let z = c64::new(0.0, 0.0);
        Self {
            zz: vec![z; lines * q * q],
            fz: vec![z; lines * n * q],
            ff: vec![z; lines * n * n],
            segments: 0,
        }
    }

    fn add(&mut self, other: &BlockSums, sign: f64) {
        for (a, b) in [
            (&mut self.zz, &other.zz),
            (&mut self.fz, &other.fz),
            (&mut self.ff, &other.ff),
        ] {
            a.iter_mut().zip(b).for_each(|(a, b)| *a += b * sign);
        }
    }
}

/// The Welch sums of an identification, per jackknife block, with what they were built from.
#[derive(Debug, Clone)]
pub(crate) struct Gathered {
    /// Degrees of freedom `n`.
    pub n: usize,
    /// Inputs `q = n + p` (displacements, then the regressor channels).
    pub q: usize,
    /// The regressor channels, in input order after the `n` displacements.
    pub channels: Vec<InputChannel>,
    /// Frequencies of the band lines (Hz).
    pub freqs_hz: Vec<f64>,
    /// Sums per block.
    pub blocks: Vec<BlockSums>,
    /// How the velocities were derived.
    pub velocity: VelocityChoice,
    /// Per DOF, the relative bias a plain sign of its noisy velocity would give a friction
    /// coefficient, averaged over the records ([`sign_noise`]); 0 without a noise
    /// estimate.
    pub sign_flip: Vec<f64>,
}

impl Gathered {
    /// The sums over every block but `leave_out` (all blocks for `None`).
    pub fn total(&self, leave_out: Option<usize>) -> BlockSums {
        let mut out = BlockSums::zeros(self.freqs_hz.len(), self.n, self.q);
        for (b, block) in self.blocks.iter().enumerate() {
            if Some(b) != leave_out {
                out.add(block, 1.0);
                out.segments += block.segments;
            }
        }
        out
    }
}

/// Welch segments of `records` (all of `shape`) with segments of `segment_len` samples.
pub(crate) fn segment_count(shape: &Shape, records: usize, segment_len: usize) -> usize {
    records
        * Segmentation::Welch { len: segment_len }
            .starts(shape.len)
            .count()
}

/// Gathers the Welch sums of `records` for `terms` over `band`.
///
/// # Errors
/// [`Error::NonFiniteRegressor`] for a regressor sample that is not finite; errors of
/// [`SpectralEstimator::new`], [`Differentiator::new`] and [`Band::lines`].
pub(crate) fn gather(
    records: &[Record],
    shape: &Shape,
    terms: &[Term],
    band: Band,
    segment_len: usize,
    differentiation: Differentiation,
) -> Result<Gathered> {
    let Shape {
        dofs: n,
        sample_rate: fs,
        len,
    } = *shape;
    let channels = input_channels(terms);
    let q = n + channels.len();
    let lines = band.lines(fs, segment_len)?;
    let mut estimator = SpectralEstimator::new(segment_len, fs, Window::Hann)?;
    let freqs_hz: Vec<f64> = lines.iter().map(|&k| estimator.frequency_hz(k)).collect();
    let needs_kinematics = !terms.is_empty();
    let mut diff = Differentiator::new(len, fs, differentiation, band)?;

    let per_record = Segmentation::Welch { len: segment_len }.starts(len).count();
    let total = per_record * records.len();
    let block_count = REVERSE_PATH_JACKKNIFE_BLOCKS.min(total).max(1);
    let mut blocks = vec![BlockSums::zeros(lines.len(), n, q); block_count];

    // Buffers, reused for every record.
    let mut x_hat = vec![vec![0.0; len]; n];
    let mut v_hat = vec![vec![0.0; len]; n];
    let mut inputs = vec![vec![0.0; len]; channels.len()];
    let (mut xs, mut vs, mut ys) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut sharpness = vec![0.0; n];
    let mut sign_flip = vec![0.0; n];
    let l = lines.len();
    let mut fbuf = vec![c64::new(0.0, 0.0); n * l];
    let mut zbuf = vec![c64::new(0.0, 0.0); q * l];
    let mut sources: Vec<Response> = Vec::new();

    for (r, record) in records.iter().enumerate() {
        for i in 0..n {
            let response = record.response(i);
            if !sources.contains(&response) {
                sources.push(response);
            }
            // Displacement is needed as an input: integrated from a velocity or acceleration.
            if needs_kinematics || response != Response::Displacement {
                diff.kinematics(
                    record.displacement(i),
                    response,
                    &mut x_hat[i],
                    &mut v_hat[i],
                );
                let (a, b) = sign_noise(&v_hat[i], diff.velocity_noise_std());
                sharpness[i] = a;
                sign_flip[i] += b / records.len() as f64;
            }
        }
        if needs_kinematics {
            let point = (&mut xs[..], &mut vs[..], &mut ys[..]);
            regressors(
                record,
                (terms, &channels, &sharpness),
                &x_hat,
                &v_hat,
                &mut inputs,
                point,
            )?;
        }
        let welch = Segmentation::Welch { len: segment_len };
        for (s, start) in welch.starts(len).enumerate() {
            let seg = start..start + segment_len;
            for i in 0..n {
                copy_lines(
                    &mut estimator,
                    &record.force(i)[seg.clone()],
                    &lines,
                    &mut fbuf[i * l..(i + 1) * l],
                );
                let x: &[f64] = if record.response(i) == Response::Displacement {
                    record.displacement(i)
                } else {
                    &x_hat[i]
                };
                copy_lines(
                    &mut estimator,
                    &x[seg.clone()],
                    &lines,
                    &mut zbuf[i * l..(i + 1) * l],
                );
            }
            for (c, u) in inputs.iter().enumerate() {
                let row = n + c;
                copy_lines(
                    &mut estimator,
                    &u[seg.clone()],
                    &lines,
                    &mut zbuf[row * l..(row + 1) * l],
                );
            }
            let global = r * per_record + s;
            let block = &mut blocks[global * block_count / total];
            accumulate(block, &fbuf, &zbuf, n, q, l);
            block.segments += 1;
        }
    }
    if sources.is_empty() {
        sources.push(Response::Displacement);
    }
    Ok(Gathered {
        n,
        q,
        channels,
        freqs_hz,
        blocks,
        velocity: VelocityChoice {
            differentiation: differentiation.check()?,
            sources,
        },
        sign_flip,
    })
}

/// What the noise of a velocity estimate `v̂ = v + n` does to the sign of a dry friction, `n`
/// Gaussian of standard deviation `noise_std` ([`Differentiator::velocity_noise_std`]) and `v`
/// Gaussian too, with $\sigma_v^2 = \overline{\hat v^2} - \sigma_n^2$: `(a, b)`, both 0 when
/// there is no noise estimate.
///
/// `a` is the factor of the sign's expectation given the estimate,
/// $E[\operatorname{sign} v \mid \hat v] = \operatorname{erf}(a\hat v)$ with
/// $a = \sqrt{k}/(\sqrt2\,\sigma_n)$, since $v \mid \hat v \sim N(k\hat v,\, k\sigma_n^2)$,
/// $k = \sigma_v^2/\overline{\hat v^2}$. Why: near a zero crossing the noise flips the estimated
/// sign, and a regressor $\operatorname{sign}\hat v$ is then the true one plus an error that
/// does not depend on the force (errors in variables). Regressing on the conditional
/// expectation instead is unbiased (regression calibration): the force's own conditional mean
/// is the friction times it.
///
/// `b` is the relative bias the plain sign would give the coefficient,
/// $b = \frac{2}{\pi}\arctan(\sigma_n/\sigma_v)$ (twice the probability of a flip; about
/// $2\sigma_n/(\pi\sigma_v)$, 2–3 % at 2 % measurement noise). The expected sign removes it
/// when the velocity is Gaussian; how far it is removed depends on how long the velocity
/// dwells near zero (sticking), which the records do not resolve below the noise, so `b`
/// times the coefficient is what the reverse path carries as the friction's model
/// uncertainty.
fn sign_noise(v_hat: &[f64], noise_std: f64) -> (f64, f64) {
    if noise_std.is_nan() || noise_std <= 0.0 || v_hat.is_empty() {
        return (0.0, 0.0);
    }
    let power = v_hat.iter().map(|v| v * v).sum::<f64>() / v_hat.len() as f64;
    let variance_v = (power - noise_std * noise_std).max(0.0);
    let a = (variance_v / power).sqrt() / (std::f64::consts::SQRT_2 * noise_std);
    let b = std::f64::consts::FRAC_2_PI * noise_std.atan2(variance_v.sqrt());
    let finite = |x: f64| if x.is_finite() { x } else { 0.0 };
    (finite(a), finite(b))
}

/// The regressor time series of `record` into `inputs`, one per input channel; a dry
/// friction's sign taken as its expectation given the noisy velocity where `sharpness` (per
/// DOF, [`sign_noise`]) is above 0.
fn regressors(
    record: &Record,
    (terms, channels, sharpness): (&[Term], &[InputChannel], &[f64]),
    x_hat: &[Vec<f64>],
    v_hat: &[Vec<f64>],
    inputs: &mut [Vec<f64>],
    (xs, vs, ys): (&mut [f64], &mut [f64], &mut [f64]),
) -> Result<()> {
    let len = record.len();
    for m in 0..len {
        for i in 0..xs.len() {
            xs[i] = x_hat[i][m];
            vs[i] = v_hat[i][m];
        }
        let mut c = 0;
        for (j, term) in terms.iter().enumerate() {
            term.force_shape(xs, vs, None, ys);
            while c < channels.len() && channels[c].term == j {
                let dof = channels[c].dof;
                let y = match term.regressor {
                    Regressor::Coulomb if sharpness[dof] > 0.0 => {
                        statrs::function::erf::erf(sharpness[dof] * vs[dof])
                    }
                    _ => ys[dof],
                };
                if !y.is_finite() {
                    return Err(Error::NonFiniteRegressor {
                        record: record.label().to_owned(),
                        term: term.label(),
                        sample: m,
                    });
                }
                inputs[c][m] = y;
                c += 1;
            }
        }
    }
    Ok(())
}

/// The band lines of the spectrum of `segment` into `out`.
fn copy_lines(est: &mut SpectralEstimator, segment: &[f64], lines: &[usize], out: &mut [c64]) {
    let spectrum = est.transform(segment);
    for (o, &k) in out.iter_mut().zip(lines) {
        *o = spectrum[k];
    }
}

/// Adds one segment's outer products per line: `zz += z zᴴ`, `fz += f zᴴ`, `ff += f fᴴ`.
fn accumulate(block: &mut BlockSums, f: &[c64], z: &[c64], n: usize, q: usize, l: usize) {
    for k in 0..l {
        let zz = &mut block.zz[k * q * q..(k + 1) * q * q];
        for b in 0..q {
            let zb = z[b * l + k].conj();
            for a in 0..q {
                zz[a + b * q] += z[a * l + k] * zb;
            }
        }
        let fz = &mut block.fz[k * n * q..(k + 1) * n * q];
        for b in 0..q {
            let zb = z[b * l + k].conj();
            for i in 0..n {
                fz[i + b * n] += f[i * l + k] * zb;
            }
        }
        let ff = &mut block.ff[k * n * n..(k + 1) * n * n];
        for j in 0..n {
            let fj = f[j * l + k].conj();
            for i in 0..n {
                ff[i + j * n] += f[i * l + k] * fj;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nonlinear::Regressor;

    #[test]
    fn planar_terms_give_two_inputs() {
        let terms = Regressor::expand(&[Regressor::Cubic, Regressor::CoulombPlanar], 2).unwrap();
        let ch = input_channels(&terms);
        assert_eq!(
            ch,
            [
                InputChannel { term: 0, dof: 0 },
                InputChannel { term: 1, dof: 1 },
                InputChannel { term: 2, dof: 0 },
                InputChannel { term: 2, dof: 1 },
            ]
        );
    }

    #[test]
    fn a_cube_beyond_f64_is_a_typed_error() {
        let x: Vec<f64> = (0..256).map(|m| 1e120 * (m as f64 * 0.3).sin()).collect();
        let f: Vec<f64> = (0..256).map(|m| (m as f64 * 0.7).cos()).collect();
        let r = Record::new("huge", 100.0, vec![f], vec![x]).unwrap();
        let shape = crate::records::common_shape(std::slice::from_ref(&r), None).unwrap();
        let terms = Regressor::Cubic.terms(1).unwrap();
        let e = gather(
            &[r],
            &shape,
            &terms,
            Band::new(5.0, 20.0).unwrap(),
            64,
            Differentiation::Wiener,
        )
        .unwrap_err();
        assert!(
            matches!(&e, Error::NonFiniteRegressor { record, term, .. } if record == "huge" && term == "cubic[0]"),
            "{e:?}"
        );
        assert_eq!(e.kind(), "non_finite");
    }
}
