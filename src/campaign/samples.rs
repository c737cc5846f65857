//! A campaign's bearing as index-aligned samples per speed ([`SpeedSamples`]), for a stochastic
//! rotor model over speed (ROSS's `ST_BearingElement`).

use std::fmt::Write as _;

use faer::Mat;
use serde_json::Value as Json;

use super::point::Value;
use super::run::{Campaign, Fit};
use crate::Coefficients;
use crate::error::{Error, Result};
use crate::export::samples::{BearingSamples, COLUMNS};

/// `N` samples of the bearing's coefficients at each speed of the campaign's ROSS speed table
/// ([`Campaign::ross_speed_table`]), the same `N` at every speed so that sample `i` over the
/// speeds is one stochastic bearing.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedSamples {
    /// The speeds (rad/s), increasing, as the speed table's.
    pub speed_rad_s: Vec<f64>,
    /// The points' names, in speed order.
    pub points: Vec<String>,
    /// The samples at each speed.
    pub samples: Vec<BearingSamples>,
    /// Whether they are drawn about the synchronous `K`, `C` (as the table holds them).
    pub synchronous: bool,
}

/// The covariance over the stacked `[M; C; K]` (column by column) with `std²` on its
/// diagonal.
fn diagonal(std: &Coefficients) -> Mat<f64> {
    let s = std.stacked();
    let rows = s.nrows();
    let p = rows * s.ncols();
    Mat::from_fn(p, p, |a, c| {
        if a == c {
            s[(a % rows, a / rows)].powi(2)
        } else {
            0.0
        }
    })
}

/// The `n × n` matrix `key` of a point's JSON object `sync`, as a faer matrix.
fn matrix(sync: &Json, key: &str, n: usize) -> Option<Mat<f64>> {
    let rows: Vec<Vec<f64>> = serde_json::from_value(sync.get(key)?.clone()).ok()?;
    (rows.len() == n && rows.iter().all(|r| r.len() == n))
        .then(|| Mat::from_fn(n, n, |i, j| rows[i][j]))
}

/// A point's synchronous coefficients and their standard deviations, the fitted `M` beside.
fn synchronous(fit: &Fit) -> Option<(Coefficients, Coefficients)> {
    let (c, std) = fit.reported();
    let n = c.dofs();
    let sync = fit.json.get("synchronous")?;
    let value = Coefficients::new(
        c.mass().to_owned(),
        matrix(sync, "C", n)?,
        matrix(sync, "K", n)?,
    )
    .ok()?;
    let sd = Coefficients::new(
        std?.mass().to_owned(),
        matrix(sync, "C_std", n)?,
        matrix(sync, "K_std", n)?,
    )
    .ok()?;
    Some((value, sd))
}

impl Campaign {
    /// `n` samples of the bearing at every speed of its ROSS speed table (the same points,
    /// slice and checks as [`Campaign::ross_speed_table`]; a 1-D table). At speed `k` the
    /// generator is seeded with `seed + k`, so the speeds' samples are independent, as the
    /// points' measurements are, and the whole set is reproducible.
    ///
    /// What is drawn is what the table holds. With synchronous coefficients: a normal about
    /// each point's synchronous `K`, `C` and fitted `M` with their standard deviations
    /// (uncorrelated: the synchronous values carry no covariance). Otherwise the constant
    /// `M`, `C`, `K`: for a point identified in this run without a baseline, the multivariate
    /// normal of the full covariance ([`BearingSamples::draw`]); for a bearing's own (less its
    /// baseline) or a point taken from the cache, uncorrelated normals of the standard
    /// deviations.
    ///
    /// # Errors
    /// As [`Campaign::ross_speed_table`]; [`Error::InvalidOption`] (`ross-samples`) for
    /// `n = 0`, with `--per-frequency` (a 2-D table), or a point without error bars.
    pub fn ross_samples(
        &self,
        slice: &[(String, Value)],
        n: usize,
        seed: u64,
    ) -> Result<SpeedSamples> {
        let invalid = |message: String| Error::InvalidOption {
            option: "ross-samples",
            message,
        };
        if self.per_frequency {
            return Err(invalid(
                "--ross-samples with --per-frequency: samples are of the 1-D speed table; drop \
                 --per-frequency"
                    .into(),
            ));
        }
        let table = self.ross_speed_table(0, "bearing", slice)?;
        let mut samples = Vec::with_capacity(table.points.len());
        for (k, name) in table.points.iter().enumerate() {
            let fit = self
                .points
                .iter()
                .find(|p| &p.name == name)
                .and_then(|p| p.result.as_ref().ok())
                .ok_or_else(|| invalid(format!("point `{name}` has no result")))?;
            let seed = seed.wrapping_add(k as u64);
            let no_bars = || invalid(format!("point `{name}` has no error bars to draw from"));
            let drawn = if table.synchronous {
                let (value, sd) = synchronous(fit).ok_or_else(no_bars)?;
                BearingSamples::from_covariance(&value, &diagonal(&sd), n, seed)?
            } else {
                match (&fit.outcome, &fit.bearing) {
                    (Some(outcome), None) => {
                        BearingSamples::draw(outcome.identification(), n, seed)?
                    }
                    _ => {
                        let (c, std) = fit.reported();
                        BearingSamples::from_covariance(
                            c,
                            &diagonal(std.ok_or_else(no_bars)?),
                            n,
                            seed,
                        )?
                    }
                }
            };
            samples.push(drawn);
        }
        Ok(SpeedSamples {
            speed_rad_s: table.speed_rad_s,
            points: table.points,
            samples,
            synchronous: table.synchronous,
        })
    }
}

impl SpeedSamples {
    /// CSV, one row per speed and sample: `speed_rpm,point,sample,kxx,…,myy` (SI but the
    /// speed), speeds in increasing order, samples `0 … N−1` at each; numbers in the shortest
    /// form that reads back every bit.
    pub fn to_csv(&self) -> String {
        let mut s = format!("speed_rpm,point,sample,{}\n", COLUMNS.join(","));
        for ((w, name), samples) in self.speed_rad_s.iter().zip(&self.points).zip(&self.samples) {
            let rpm = w * 30.0 / std::f64::consts::PI;
            for i in 0..samples.len() {
                let _ = write!(s, "{rpm:?},{},{i}", name.replace([',', '\n'], " "));
                for v in samples.row(i) {
                    let _ = write!(s, ",{v:?}");
                }
                s.push('\n');
            }
        }
        s
    }
}
