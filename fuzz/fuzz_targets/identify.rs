//! `Identifier::identify` over arbitrary small records (1–3 degrees of freedom, 8–512 samples,
//! at most 6 records; values sane, extreme, NaN or infinite) and arbitrary settings.
//! Invariants: no panic, no hang (sizes and iterations bounded here), and an `Ok` result has
//! finite coefficients, standard deviations and intervals.
#![no_main]

use arbitrary::Arbitrary;
use bearing_ident::quality::ImpactChecks;
use bearing_ident::spectra::ForceGate;
use bearing_ident::{
    Coefficients, ConditionLimits, Estimator, Identifier, Method, NonConvergence, Record,
    Screening, Segmentation, Uncertainty, Window,
};
use libfuzzer_sys::fuzz_target;

/// A number: mostly ordinary, sometimes extreme or not finite.
#[derive(Debug, Clone, Copy, Arbitrary)]
enum Value {
    /// `m · 10^e` for small integers: the common case.
    Decimal(i8, i8),
    /// Any bit pattern: NaN, ±∞, subnormals, ±1e308.
    Raw(f64),
    Zero,
    Huge(bool),
    Tiny(bool),
}

impl Value {
    fn get(self) -> f64 {
        match self {
            Value::Decimal(m, e) => f64::from(m) * 10f64.powi(i32::from(e % 40)),
            Value::Raw(v) => v,
            Value::Zero => 0.0,
            Value::Huge(neg) => {
                if neg {
                    -1e308
                } else {
                    1e308
                }
            }
            Value::Tiny(neg) => {
                if neg {
                    -5e-324
                } else {
                    5e-324
                }
            }
        }
    }
}

/// One channel: a damped sine plus a repeated pattern of values.
#[derive(Debug, Arbitrary)]
struct Channel {
    amplitude: Value,
    cycles: u8,
    decay: u8,
    pattern: Vec<Value>,
}

impl Channel {
    fn samples(&self, len: usize) -> Vec<f64> {
        let a = self.amplitude.get();
        let w = 2.0 * std::f64::consts::PI * f64::from(self.cycles) / len as f64;
        let d = f64::from(self.decay) / len as f64;
        (0..len)
            .map(|m| {
                let t = m as f64;
                let p = if self.pattern.is_empty() {
                    0.0
                } else {
                    self.pattern[m % self.pattern.len()].get()
                };
                a * (w * t).sin() * (-d * t).exp() + p
            })
            .collect()
    }
}

#[derive(Debug, Arbitrary)]
struct RecordIn {
    forces: [Channel; 3],
    displacements: [Channel; 3],
    /// Another sampling rate than the first record's, sometimes.
    rate: Option<Value>,
    /// Another length, sometimes.
    len: Option<u16>,
}

#[derive(Debug, Arbitrary)]
enum Edge {
    /// `k/255` of the Nyquist frequency.
    Fraction(u8),
    Raw(Value),
}

#[derive(Debug, Arbitrary)]
enum WindowIn {
    Rectangular,
    Hann,
    Exponential(Value),
    /// Falling to `end` at the record's end.
    ExponentialTo(Value),
}

#[derive(Debug, Arbitrary)]
enum SegmentationIn {
    Whole,
    Welch(u16),
    Periods(u16),
}

#[derive(Debug, Arbitrary)]
enum UncertaintyIn {
    None,
    Sandwich,
    Jackknife,
    Bootstrap(u8, u64),
    Auto,
}

#[derive(Debug, Arbitrary)]
enum ScreeningIn {
    Off,
    Warn(Value, u8, Value),
    Reject(Value, u8, Value),
}

#[derive(Debug, Arbitrary)]
struct Input {
    dofs: u8,
    len: u16,
    rate: Value,
    records: Vec<RecordIn>,
    low: Edge,
    high: Edge,
    estimator: u8,
    method: u8,
    window: WindowIn,
    segmentation: SegmentationIn,
    gate: Option<(Value, Value)>,
    uncertainty: UncertaintyIn,
    min_coherence: Value,
    screening: ScreeningIn,
    tolerance: Value,
    max_iterations: u8,
    limits: Option<(Value, Value)>,
    fail_unconverged: bool,
    dofs_setting: Option<u8>,
}

/// At most this many records.
const MAX_RECORDS: usize = 6;

fn checks(ratio: Value, run: u8, crest: Value) -> ImpactChecks {
    ImpactChecks {
        double_hit_ratio: ratio.get(),
        clip_run: usize::from(run),
        min_crest_factor: crest.get(),
    }
}

fn assert_finite(what: &str, c: &Coefficients) {
    for (name, m) in [("M", c.mass()), ("C", c.damping()), ("K", c.stiffness())] {
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                assert!(
                    m[(i, j)].is_finite(),
                    "{what} {name}[{i}][{j}] = {}",
                    m[(i, j)]
                );
            }
        }
    }
}

fuzz_target!(|input: Input| {
    let n = usize::from(input.dofs % 3) + 1;
    let len = usize::from(input.len % 505) + 8;
    let rate = input.rate.get();
    let records: Vec<Record> = input
        .records
        .iter()
        .take(MAX_RECORDS)
        .enumerate()
        .filter_map(|(r, rec)| {
            let len = rec.len.map_or(len, |l| usize::from(l % 505) + 8);
            let forces = rec.forces[..n].iter().map(|c| c.samples(len)).collect();
            let disps = rec.displacements[..n]
                .iter()
                .map(|c| c.samples(len))
                .collect();
            let rate = rec.rate.map_or(rate, Value::get);
            Record::new(format!("r{r}"), rate, forces, disps).ok()
        })
        .collect();
    let nyquist = if rate.is_finite() { rate / 2.0 } else { 1.0 };
    let edge = |e: &Edge| match e {
        Edge::Fraction(k) => f64::from(*k) / 255.0 * nyquist,
        Edge::Raw(v) => v.get(),
    };
    let duration = len as f64 / rate;
    let window = match input.window {
        WindowIn::Rectangular => Window::Rectangular,
        WindowIn::Hann => Window::Hann,
        WindowIn::Exponential(a) => Window::Exponential {
            decay_per_s: a.get(),
        },
        WindowIn::ExponentialTo(end) => Window::exponential_to(end.get(), duration),
    };
    let segmentation = match input.segmentation {
        SegmentationIn::Whole => Segmentation::WholeRecord,
        SegmentationIn::Welch(l) => Segmentation::Welch {
            len: usize::from(l % 600),
        },
        SegmentationIn::Periods(l) => Segmentation::Periods {
            len: usize::from(l % 600),
        },
    };
    let uncertainty = match input.uncertainty {
        UncertaintyIn::None => Uncertainty::None,
        UncertaintyIn::Sandwich => Uncertainty::Sandwich,
        UncertaintyIn::Jackknife => Uncertainty::Jackknife,
        UncertaintyIn::Bootstrap(r, seed) => Uncertainty::Bootstrap {
            replicates: usize::from(r % 40),
            seed,
        },
        UncertaintyIn::Auto => Uncertainty::Auto,
    };
    let screening = match input.screening {
        ScreeningIn::Off => Screening::Off,
        ScreeningIn::Warn(a, b, c) => Screening::Warn(checks(a, b, c).into()),
        ScreeningIn::Reject(a, b, c) => Screening::Reject(checks(a, b, c).into()),
    };
    let estimator = [
        Estimator::PairedSets,
        Estimator::H1,
        Estimator::H2,
        Estimator::Hv,
    ][usize::from(input.estimator % 4)];
    let method = [
        Method::Direct,
        Method::LeastSquares,
        Method::Ivf,
        Method::Ml,
    ][usize::from(input.method % 4)];
    let mut identifier = Identifier::new(edge(&input.low), edge(&input.high))
        .estimator(estimator)
        .method(method)
        .window(window)
        .segmentation(segmentation)
        .uncertainty(uncertainty)
        .min_coherence(input.min_coherence.get())
        .screening(screening)
        .tolerance(input.tolerance.get())
        .max_iterations(usize::from(input.max_iterations % 60));
    if let Some((open, taper)) = input.gate {
        if let Ok(gate) = ForceGate::new(open.get(), taper.get()) {
            identifier = identifier.force_gate(gate);
        }
    }
    if let Some((warn, refuse)) = input.limits {
        identifier = identifier.condition_limits(ConditionLimits {
            warn: warn.get(),
            refuse: refuse.get(),
        });
    }
    if input.fail_unconverged {
        identifier = identifier.on_non_convergence(NonConvergence::Fail);
    }
    if let Some(d) = input.dofs_setting {
        identifier = identifier.dofs(usize::from(d % 4));
    }
    let Ok(id) = identifier.identify(&records) else {
        return;
    };
    assert_finite("coefficient", id.coefficients());
    if let Some(std) = id.std_dev() {
        assert_finite("standard deviation", std);
    }
    if let Some(ci) = id.interval_95() {
        assert_finite("95 % interval", &ci);
    }
    let _ = id.modes();
    let _ = id.per_frequency();
    let _ = id.min_coherence();
    for w in id.warnings() {
        let _ = (w.kind(), w.to_string());
    }
});
