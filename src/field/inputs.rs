//! The imbalance tests and their measured responses ([`FieldTests`]), and their grouping by
//! speed, run and probe ([`Measurements`]).

use crate::error::FieldError;
use faer::c64;

use super::model::{Direction, RotorModel};
use crate::error::{Error, Result};

/// An imbalance `u = m·e` (kg·m) at a node and angle.
///
/// At speed `Ω` it applies $F_x = u\Omega^2\cos(\Omega t + \varphi)$,
/// $F_y = u\Omega^2\sin(\Omega t + \varphi)$ (rotation from x towards y), that is the phasors
/// $f_x = u\Omega^2 e^{i\varphi}$, $f_y = -i\,u\Omega^2 e^{i\varphi}$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Imbalance {
    /// The node it sits at.
    pub node: usize,
    /// Mass times radius (kg·m).
    pub magnitude_kg_m: f64,
    /// Angle (rad) from x towards y.
    pub phase_rad: f64,
}

impl Imbalance {
    /// The force phasors `(f_x, f_y)` at `speed_rad_s`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::field::Imbalance;
    /// let u = Imbalance { node: 0, magnitude_kg_m: 1e-4, phase_rad: 0.0 };
    /// let (fx, fy) = u.force(100.0);
    /// assert!((fx.re - 1.0).abs() < 1e-12 && (fy.im + 1.0).abs() < 1e-12);
    /// ```
    pub fn force(&self, speed_rad_s: f64) -> (c64, c64) {
        let f = c64::from_polar(
            self.magnitude_kg_m * speed_rad_s * speed_rad_s,
            self.phase_rad,
        );
        (f, f * c64::new(0.0, -1.0))
    }
}

/// A proximity probe: a node and a lateral direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Probe {
    /// The node it looks at.
    pub node: usize,
    /// The direction it measures.
    pub dir: Direction,
}

/// A run of a field test: the baseline (residual imbalance only) or one of the two tests with
/// added masses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Run {
    /// The machine as it is.
    Baseline,
    /// With the first set of added masses.
    First,
    /// With the second set of added masses.
    Second,
}

impl Run {
    /// The three runs in order.
    pub const ALL: [Run; 3] = [Run::Baseline, Run::First, Run::Second];

    /// `"baseline"`, `"1"` or `"2"`, the JSON spelling.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::field::Run;
    /// assert_eq!(Run::Second.name(), "2");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Run::Baseline => "baseline",
            Run::First => "1",
            Run::Second => "2",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// One measured synchronous response: `x(t) = Re(value · e^{iΩt})` in m at a probe, at a
/// speed, in a run; optionally with the standard deviation of each of its real and imaginary
/// parts (m). Several responses with the same speed, run and probe are repeats.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Response {
    /// The speed `Ω` (rad/s).
    pub speed_rad_s: f64,
    /// The run.
    pub run: Run,
    /// The probe.
    pub probe: Probe,
    /// The phasor (m).
    pub value: c64,
    /// Standard deviation of each of `Re value` and `Im value` (m), if stated.
    pub std: Option<f64>,
}

/// A field test: the added imbalances of the two tests (only the added masses, not the
/// residual imbalance) and every measured response.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldTests {
    /// Added imbalances of test 1 and test 2.
    pub imbalances: [Vec<Imbalance>; 2],
    /// The responses of all runs at all speeds.
    pub responses: Vec<Response>,
}

/// The responses grouped: ascending speeds, sorted probes, and per speed and run the mean
/// phasor per probe with the standard deviation of that mean (if every response has one).
#[derive(Debug, Clone)]
pub(crate) struct Measurements {
    pub speeds: Vec<f64>,
    pub probes: Vec<Probe>,
    /// `[speed][run][probe]`.
    pub values: Vec<[Vec<c64>; 3]>,
    /// Same layout; `None` when some response has no stated or repeat-derived deviation.
    pub std: Option<Vec<[Vec<f64>; 3]>>,
}

impl FieldTests {
    /// Checks the tests against `rotor` and groups the responses.
    ///
    /// A probe's value at a speed and run is the mean of its repeats; the standard deviation
    /// of that mean is $\sqrt{\sum s_r^2}/n$ from stated `std`s, else
    /// $\sqrt{\sum |z_r - \bar z|^2 / (2(n-1))}/\sqrt n$ from `n ≥ 2` repeats, else none.
    pub(crate) fn measurements(&self, rotor: &RotorModel) -> Result<Measurements> {
        let bad = |message: String| Err(Error::Field(FieldError::Input { message }));
        for (t, set) in self.imbalances.iter().enumerate() {
            if set.is_empty() {
                return bad(format!("test {} adds no imbalance", t + 1));
            }
            for u in set {
                if !(u.magnitude_kg_m.is_finite() && u.phase_rad.is_finite()) {
                    return Err(Error::Field(FieldError::NonFinite {
                        what: format!("an imbalance of test {} at node {}", t + 1, u.node),
                    }));
                }
                if u.node >= rotor.nodes() {
                    return bad(format!(
                        "an imbalance of test {} at node {}, but the model has nodes 0–{}",
                        t + 1,
                        u.node,
                        rotor.nodes() - 1
                    ));
                }
            }
        }
        if self.responses.is_empty() {
            return bad("no responses are given".to_owned());
        }
        for (i, r) in self.responses.iter().enumerate() {
            let finite = r.speed_rad_s.is_finite()
                && r.value.re.is_finite()
                && r.value.im.is_finite()
                && r.std.is_none_or(f64::is_finite);
            if !finite {
                return Err(Error::Field(FieldError::NonFinite {
                    what: format!("response {i}"),
                }));
            }
            // Finite is not enough: the solve squares the responses and forms products of
            // them (the pair matrices and their condition numbers).
            let limit = crate::tolerance::FIELD_RESPONSE_MAGNITUDE;
            let size = r
                .value
                .re
                .abs()
                .max(r.value.im.abs())
                .max(r.std.unwrap_or(0.0));
            if size > limit {
                return bad(format!(
                    "response {i} (speed {} rad/s, test `{}`, node {}, direction {}): {} {:e} m \
                     is past {limit:e}: the solve squares the responses, so values that large \
                     leave f64 (a unit error? responses are in m)",
                    r.speed_rad_s,
                    r.run.name(),
                    r.probe.node,
                    r.probe.dir.name(),
                    if r.std.is_some_and(|s| s > limit) {
                        "std"
                    } else {
                        "value"
                    },
                    size
                ));
            }
            if r.speed_rad_s <= 0.0 {
                return bad(format!(
                    "response {i}: speed {} rad/s is not positive",
                    r.speed_rad_s
                ));
            }
            if r.std.is_some_and(|s| s < 0.0) {
                return bad(format!("response {i}: negative std"));
            }
            if r.probe.node >= rotor.nodes() {
                return bad(format!(
                    "response {i} at node {}, but the model has nodes 0–{}",
                    r.probe.node,
                    rotor.nodes() - 1
                ));
            }
        }
        let mut speeds: Vec<f64> = self.responses.iter().map(|r| r.speed_rad_s).collect();
        speeds.sort_by(f64::total_cmp);
        speeds.dedup_by(|a, b| a.total_cmp(b).is_eq());
        let mut probes: Vec<Probe> = self.responses.iter().map(|r| r.probe).collect();
        probes.sort();
        probes.dedup();
        let (ns, np) = (speeds.len(), probes.len());
        // Sums per [speed][run][probe]: Σz, Σ|z|², count, Σs², stated count.
        let cells = ns * 3 * np;
        let mut sum = vec![c64::new(0.0, 0.0); cells];
        let mut sq = vec![0.0; cells];
        let mut count = vec![0usize; cells];
        let mut var = vec![0.0; cells];
        let mut stated = vec![0usize; cells];
        for r in &self.responses {
            let s = speeds
                .binary_search_by(|v| v.total_cmp(&r.speed_rad_s))
                .unwrap_or_default();
            let p = probes.binary_search(&r.probe).unwrap_or_default();
            let c = (s * 3 + r.run.index()) * np + p;
            sum[c] += r.value;
            sq[c] += r.value.norm_sqr();
            count[c] += 1;
            if let Some(sd) = r.std {
                var[c] += sd * sd;
                stated[c] += 1;
            }
        }
        let mut values = Vec::with_capacity(ns);
        let mut std = Some(Vec::with_capacity(ns));
        for (s, &speed) in speeds.iter().enumerate() {
            let mut v: [Vec<c64>; 3] = Default::default();
            let mut d: [Vec<f64>; 3] = Default::default();
            for run in Run::ALL {
                for (p, probe) in probes.iter().enumerate() {
                    let c = (s * 3 + run.index()) * np + p;
                    let n = count[c];
                    if n == 0 {
                        return Err(Error::Field(FieldError::MissingResponse {
                            speed_rad_s: speed,
                            test: run.name(),
                            node: probe.node,
                            dir: probe.dir.name(),
                        }));
                    }
                    let nf = n as f64;
                    let mean = sum[c] / nf;
                    v[run.index()].push(mean);
                    let sd = if stated[c] == n {
                        Some(var[c].sqrt() / nf)
                    } else if n >= 2 {
                        // Σ|z − z̄|² = Σ|z|² − n|z̄|², split evenly over Re and Im.
                        let spread = (sq[c] - nf * mean.norm_sqr()).max(0.0);
                        Some((spread / (2.0 * (nf - 1.0))).sqrt() / nf.sqrt())
                    } else {
                        None
                    };
                    match sd {
                        Some(sd) => d[run.index()].push(sd),
                        None => std = None,
                    }
                }
            }
            values.push(v);
            if let Some(all) = std.as_mut() {
                all.push(d);
            }
        }
        Ok(Measurements {
            speeds,
            probes,
            values,
            std,
        })
    }
}
