//! The analogue anti-alias filter of the simulated acquisition.

use std::f64::consts::PI;

use faer::Mat;

use crate::error::{Error, Result};

/// The analogue anti-alias filter applied to every channel before sampling.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum AntiAlias {
    /// Sample the continuous signals directly (pulses alias).
    None,
    /// Butterworth low-pass of even `order` with cutoff `cutoff_ratio × sample_rate`.
    Butterworth {
        /// Filter order, even, 2–16.
        order: usize,
        /// Cutoff as a fraction of the sampling rate, in `(0, 0.5)`.
        cutoff_ratio: f64,
    },
}

impl Default for AntiAlias {
    /// 8th-order Butterworth at a quarter of the sampling rate: at `f_s` it attenuates by
    /// `4⁻⁸ ≈ 1.5·10⁻⁵`.
    fn default() -> Self {
        AntiAlias::Butterworth {
            order: 8,
            cutoff_ratio: 0.25,
        }
    }
}

impl AntiAlias {
    /// The filter order, `0` for [`AntiAlias::None`], checked.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an order that is not even and 2–16, or a cutoff ratio
    /// outside `(0, 0.5)`.
    pub(super) fn checked_order(self) -> Result<usize> {
        Ok(match self {
            AntiAlias::None => 0,
            AntiAlias::Butterworth {
                order,
                cutoff_ratio,
            } => {
                if !(2..=16).contains(&order) || order % 2 != 0 {
                    return Err(Error::InvalidParameter {
                        name: crate::Parameter::AntiAliasOrder,
                        value: order as f64,
                        expected: "even, 2 to 16",
                    });
                }
                if !(cutoff_ratio > 0.0 && cutoff_ratio < 0.5) {
                    return Err(Error::InvalidParameter {
                        name: crate::Parameter::AntiAliasCutoffRatio,
                        value: cutoff_ratio,
                        expected: "0 < ratio < 0.5",
                    });
                }
                order
            }
        })
    }

    /// Writes the filters of the `2n` channels (forces first) into the simulator's state matrix
    /// `a`: per channel a cascade of `order / 2` second-order sections in companion form, the
    /// states from index `first + channel · order` on, after the structure's `first` states
    /// (see [`Simulator`](super::Simulator)). Each channel's input is force `c` (pulse
    /// generator plus held force) or displacement `c − n`; [`AntiAlias::connect`] changes it.
    pub(super) fn fill_state_matrix(
        self,
        a: &mut Mat<f64>,
        n: usize,
        first: usize,
        sample_rate: f64,
    ) {
        if let AntiAlias::Butterworth {
            order,
            cutoff_ratio,
        } = self
        {
            let wc = 2.0 * PI * cutoff_ratio * sample_rate;
            for c in 0..2 * n {
                for s in 0..order / 2 {
                    let q = 1.0 / (2.0 * (PI * (2 * s + 1) as f64 / (2 * order) as f64).cos());
                    let y = first + c * order + 2 * s;
                    if s > 0 {
                        a[(y + 1, y - 2)] += wc * wc;
                    }
                    a[(y, y + 1)] = 1.0;
                    a[(y + 1, y)] -= wc * wc;
                    a[(y + 1, y + 1)] = -wc / q;
                }
                let inputs: Vec<(usize, f64)> = if c < n {
                    vec![(2 * n + 2 * c, 1.0), (4 * n + c, 1.0)]
                } else {
                    vec![(c - n, 1.0)]
                };
                self.connect(a, first, sample_rate, c, &inputs);
            }
        }
    }

    /// One channel's filter on its own, `ṡ = A s + b u`, read off the state matrix the
    /// simulator builds ([`AntiAlias::fill_state_matrix`] for one degree of freedom): `A`
    /// (`order × order`, row-major), `b`, and the index of the state that is the filter's
    /// output. `None` for [`AntiAlias::None`]. Used by the nonlinear simulator, so that both
    /// simulators filter with the very same analogue filter.
    pub(super) fn channel_system(self, sample_rate: f64) -> Option<(Vec<f64>, Vec<f64>, usize)> {
        let AntiAlias::Butterworth { order, .. } = self else {
            return None;
        };
        let dim = 5 + 2 * order;
        let mut a = Mat::<f64>::zeros(dim, dim);
        self.fill_state_matrix(&mut a, 1, 5, sample_rate);
        // Channel 0 is the force channel of the one DOF: states 5 … 5 + order, input the held
        // force (state 4).
        let a_f = (0..order * order)
            .map(|k| a[(5 + k / order, 5 + k % order)])
            .collect();
        let b = (0..order).map(|i| a[(5 + i, 4)]).collect();
        Some((a_f, b, order - 2))
    }

    /// Makes the input of channel `channel`'s filter (forces first, then responses) the
    /// weighted sum `Σ w · s[u]` of the structure's states `inputs = [(u, w)]` (indices below
    /// `first`, where the filters' states begin): a response channel then filters
    /// displacement, velocity or acceleration, and the filtered velocity is the derivative of
    /// the filtered displacement (the filter is linear and starts from rest). Nothing for
    /// [`AntiAlias::None`].
    pub(super) fn connect(
        self,
        a: &mut Mat<f64>,
        first: usize,
        sample_rate: f64,
        channel: usize,
        inputs: &[(usize, f64)],
    ) {
        if let AntiAlias::Butterworth {
            order,
            cutoff_ratio,
        } = self
        {
            let wc = 2.0 * PI * cutoff_ratio * sample_rate;
            let row = first + channel * order + 1;
            for u in 0..first {
                a[(row, u)] = 0.0;
            }
            for &(u, w) in inputs {
                a[(row, u)] += wc * wc * w;
            }
        }
    }
}
