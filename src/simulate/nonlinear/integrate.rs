//! The integration of [`NonlinearSimulator`]: the right-hand side, the RK4 step, the substeps
//! through the friction's smoothing band, and the sampling of the channels.

use super::{Filter, NonlinearSimulator};
use crate::error::{Error, Result};
use crate::nonlinear::Regressor;
use crate::records::{Record, Response};
use crate::tolerance::{RK4_STABLE_STEP, SMOOTHING_RESOLUTION};

/// Half-width of the friction's smoothing band, in units of the smoothing scale $v_s$: a step
/// whose velocity (per DOF, or the planar velocity vector) passes within `10 v_s` of zero is
/// redone in substeps. Outside the band the smoothed law differs from the sign by
/// `1 − tanh 10 ≈ 4·10⁻⁹` and its slope is `F sech²(10)/v_s ≈ 8·10⁻⁹ F/v_s`: nothing stiff left.
pub const SMOOTHING_BAND: f64 = 10.0;

/// Most substeps one fine step is cut into inside the smoothing band.
const MAX_SUBSTEPS: usize = 1 << 16;

/// Buffers of one run, allocated once (the stepping loop allocates nothing).
struct Work {
    state: Vec<f64>,
    trial: Vec<f64>,
    k: [Vec<f64>; 4],
    tmp: Vec<f64>,
    shape: Vec<f64>,
    residual: Vec<f64>,
}

impl NonlinearSimulator {
    /// Length of the integrated state: `x`, `v`, then the response channels' filters.
    fn state_len(&self) -> usize {
        2 * self.n + self.n * self.filter.as_ref().map_or(0, |f| f.order)
    }

    /// `ds = ṡ(s)` under the held force `f`: the structure, then the response filters.
    ///
    /// The innermost work of a simulation (four calls per RK4 step, and a friction's stick
    /// phases take thousands of substeps), written as indexed loops and plain slice loops: at
    /// the test profile's `opt-level = 1`, without cross-unit inlining, iterator adapters such
    /// as `zip` stay calls and made this twice as slow.
    fn derivative(&self, f: &[f64], s: &[f64], ds: &mut [f64], shape: &mut [f64], r: &mut [f64]) {
        let n = self.n;
        let (x, v) = (&s[..n], &s[n..2 * n]);
        r.copy_from_slice(f);
        for (term, a) in &self.terms {
            term.force_shape(x, v, Some(self.smoothing), shape);
            for i in 0..n {
                r[i] -= a * shape[i];
            }
        }
        ds[..n].copy_from_slice(v);
        for i in 0..n {
            let mut acc = 0.0;
            for j in 0..n {
                let k = i * n + j;
                acc += self.minv[k] * r[j] - self.mc[k] * v[j] - self.mk[k] * x[j];
            }
            ds[n + i] = acc;
        }
        if let Some(filter) = &self.filter {
            let o = filter.order;
            for c in 0..n {
                let input = match self.responses[c] {
                    Response::Displacement => s[c],
                    Response::Velocity => s[n + c],
                    Response::Acceleration => ds[n + c],
                };
                let base = 2 * n + c * o;
                for i in 0..o {
                    let mut acc = filter.b[i] * input;
                    for &(j, aij) in filter.a.row(i) {
                        acc += aij * s[base + j];
                    }
                    ds[base + i] = acc;
                }
            }
        }
    }

    /// One classical RK4 step of length `h` from `work.state` into `work.trial` (indexed
    /// loops, as in [`Self::derivative`]).
    fn rk4(&self, f: &[f64], h: f64, work: &mut Work) {
        let Work {
            state: src,
            trial: out,
            k,
            tmp,
            shape,
            residual,
        } = work;
        let [k1, k2, k3, k4] = k;
        let len = src.len();
        self.derivative(f, src, k1, shape, residual);
        for i in 0..len {
            tmp[i] = src[i] + 0.5 * h * k1[i];
        }
        self.derivative(f, tmp, k2, shape, residual);
        for i in 0..len {
            tmp[i] = src[i] + 0.5 * h * k2[i];
        }
        self.derivative(f, tmp, k3, shape, residual);
        for i in 0..len {
            tmp[i] = src[i] + h * k3[i];
        }
        self.derivative(f, tmp, k4, shape, residual);
        for i in 0..len {
            out[i] = src[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }

    /// Whether a step from velocities `v0` to `v1` passes within the smoothing band of zero
    /// for some friction term.
    fn crosses_band(&self, v0: &[f64], v1: &[f64]) -> bool {
        let band = SMOOTHING_BAND * self.smoothing;
        self.terms
            .iter()
            .any(|(term, _)| match (term.regressor, term.dof) {
                (Regressor::Coulomb, Some(i)) => {
                    v0[i].abs() < band || v1[i].abs() < band || v0[i].signum() != v1[i].signum()
                }
                (Regressor::CoulombPlanar, _) => {
                    // Distance from the origin of the segment v0 → v1 in the plane of DOFs 0, 1.
                    let (ax, ay) = (v0[0], v0[1]);
                    let (dx, dy) = (v1[0] - ax, v1[1] - ay);
                    let len2 = dx * dx + dy * dy;
                    let t = if len2 > 0.0 {
                        (-(ax * dx + ay * dy) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    (ax + t * dx).hypot(ay + t * dy) < band
                }
                _ => false,
            })
    }

    /// Substeps for a fine step `h` that crosses the smoothing band: enough that the friction's
    /// stiff rate inside the band, `|F| ‖M⁻¹‖∞ / v_s`, keeps RK4 stable, and that the velocity
    /// moves by at most [`SMOOTHING_RESOLUTION`]` · v_s` per substep at the acceleration
    /// `accel` seen at the step's start.
    fn substeps(&self, h: f64, accel: f64) -> usize {
        let minv_norm = (0..self.n)
            .map(|i| {
                self.minv[i * self.n..(i + 1) * self.n]
                    .iter()
                    .map(|m| m.abs())
                    .sum::<f64>()
            })
            .fold(0.0, f64::max);
        let friction: f64 = self
            .terms
            .iter()
            .filter(|(t, _)| matches!(t.regressor, Regressor::Coulomb | Regressor::CoulombPlanar))
            .map(|(_, a)| a.abs())
            .sum();
        let stiff = friction * minv_norm / self.smoothing * h / RK4_STABLE_STEP;
        let resolve = accel * h / (SMOOTHING_RESOLUTION * self.smoothing);
        let m = stiff.max(resolve).ceil();
        if m.is_finite() && m >= 1.0 {
            (m as usize).min(MAX_SUBSTEPS)
        } else {
            1
        }
    }

    /// Advances `work.state` by one fine step `h` under the held force `f`, in substeps where
    /// the step crosses the friction's smoothing band.
    fn step(&self, f: &[f64], h: f64, work: &mut Work, friction: bool) {
        self.rk4(f, h, work);
        let n = self.n;
        if !(friction && self.crosses_band(&work.state[n..2 * n], &work.trial[n..2 * n])) {
            std::mem::swap(&mut work.state, &mut work.trial);
            return;
        }
        // The trial step is discarded. The largest acceleration at the start sets the substep.
        let accel = work.k[0][n..2 * n]
            .iter()
            .chain(&work.k[3][n..2 * n])
            .fold(0.0_f64, |m, a| m.max(a.abs()));
        let m = self.substeps(h, accel);
        let hs = h / m as f64;
        for _ in 0..m {
            self.rk4(f, hs, work);
            std::mem::swap(&mut work.state, &mut work.trial);
        }
    }

    /// The sampled value of response channel `c` at the current state (filter output, or the
    /// structure's displacement, velocity or acceleration without a filter).
    fn sample_response(&self, c: usize, f: &[f64], work: &mut Work) -> f64 {
        let n = self.n;
        match (&self.filter, self.responses[c]) {
            (Some(filter), _) => work.state[2 * n + c * filter.order + filter.output],
            (None, Response::Displacement) => work.state[c],
            (None, Response::Velocity) => work.state[n + c],
            (None, Response::Acceleration) => {
                let Work {
                    state,
                    k,
                    shape,
                    residual,
                    ..
                } = work;
                self.derivative(f, state, &mut k[0], shape, residual);
                k[0][n + c]
            }
        }
    }

    /// The simulation: from `x0`, `v0` (filters settled on that state), under the held
    /// `forces` or none.
    pub(super) fn run(
        &mut self,
        label: String,
        forces: Option<&[Vec<f64>]>,
        x0: &[f64],
        v0: &[f64],
    ) -> Result<Record> {
        let steps = self.oversampling()?;
        let (n, samples) = (self.n, self.samples);
        let len = self.state_len();
        let mut work = Work {
            state: vec![0.0; len],
            trial: vec![0.0; len],
            k: std::array::from_fn(|_| vec![0.0; len]),
            tmp: vec![0.0; len],
            shape: vec![0.0; n],
            residual: vec![0.0; n],
        };
        work.state[..n].copy_from_slice(x0);
        work.state[n..2 * n].copy_from_slice(v0);
        let zero = vec![0.0; n];
        // Settle the response filters on their inputs' starting values (unit DC gain: every
        // section's output equals its input, derivatives zero).
        if let Some(filter) = &self.filter {
            let mut scratch = vec![0.0; len];
            let (mut shape, mut residual) = (zero.clone(), zero.clone());
            self.derivative(&zero, &work.state, &mut scratch, &mut shape, &mut residual);
            for (c, kind) in self.responses.iter().enumerate() {
                let start = match kind {
                    Response::Displacement => x0[c],
                    Response::Velocity => v0[c],
                    Response::Acceleration => scratch[n + c],
                };
                let base = 2 * n + c * filter.order;
                for sec in 0..filter.order / 2 {
                    work.state[base + 2 * sec] = start;
                }
            }
        }
        let mut force_filters = vec![0.0; n * self.filter.as_ref().map_or(0, |f| f.order)];
        let mut next_filter = force_filters.clone();
        let mut held = zero.clone();
        let mut out_f = vec![vec![0.0; samples]; n];
        let mut out_x = vec![vec![0.0; samples]; n];
        let h = 1.0 / (self.sample_rate * steps as f64);
        let friction = self
            .terms
            .iter()
            .any(|(t, _)| matches!(t.regressor, Regressor::Coulomb | Regressor::CoulombPlanar));
        for m in 0..samples {
            if let Some(forces) = forces {
                for (hc, fc) in held.iter_mut().zip(forces) {
                    *hc = fc[m];
                }
            }
            if work.state.iter().any(|s| !s.is_finite()) {
                return Err(Error::SimulationDiverged {
                    record: label,
                    sample: m,
                    step_s: h,
                });
            }
            for c in 0..n {
                out_f[c][m] = match &self.filter {
                    Some(filter) => force_filters[c * filter.order + filter.output],
                    None => held[c],
                };
                out_x[c][m] = self.sample_response(c, &held, &mut work);
            }
            if m + 1 == samples {
                break;
            }
            if let Some(filter) = &self.filter {
                advance_held(filter, &held, &mut force_filters, &mut next_filter);
            }
            for _ in 0..steps {
                self.step(&held, h, &mut work, friction);
            }
        }
        Record::new(label, self.sample_rate, out_f, out_x)?.with_responses(self.responses.clone())
    }
}

/// The force channels' filters over one sample under the held forces, exactly:
/// `s ← e^{AΔt} s + Γ f`.
fn advance_held(filter: &Filter, held: &[f64], states: &mut [f64], next: &mut [f64]) {
    let o = filter.order;
    for (c, &f) in held.iter().enumerate() {
        let s = &states[c * o..(c + 1) * o];
        for i in 0..o {
            let row = &filter.phi[i * o..(i + 1) * o];
            next[c * o + i] =
                row.iter().zip(s).map(|(p, v)| p * v).sum::<f64>() + filter.gamma[i] * f;
        }
    }
    states.copy_from_slice(next);
}
