//! A simulated test as the `simulate` command describes one ([`Setup`]): the kind of
//! excitation, its sizes and frequencies, measurement noise, what the responses record, an
//! element's internal states, and optional nonlinear terms; [`Setup::run`] makes its records
//! for a given system. The command
//! line and the Python package both run this one description.

mod forcing;
mod terms;

use crate::error::{Error, Result, excerpt};
use crate::model::Coefficients;
use crate::records::{Record, Response};
use crate::simulate::{ElementStates, ImpactTest, MAX_SAMPLES};
use crate::tolerance::SIMULATED_DECAY_NEPERS;

pub use terms::NonlinearTerms;

/// The kind of a simulated test's excitation.
///
/// # Examples
/// ```
/// use bearing_ident::simulate::Kind;
/// let k: Kind = "stepped-sine".parse()?;
/// assert_eq!(k, Kind::SteppedSine);
/// assert_eq!(k.to_string(), "stepped-sine");
/// assert!("chirp".parse::<Kind>().is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kind {
    /// Half-sine hammer hits, `impacts` per degree of freedom.
    #[default]
    Impact,
    /// Gaussian forces on every degree of freedom at once, `records` records: white, or
    /// band-limited to `freqs` `LO,HI`.
    Random,
    /// Random-phase multisine on one direction per record (every direction at once with
    /// `simultaneous`, independent phases), lines in `freqs` `LO,HI`, period `period`,
    /// `records` records (per direction) of `periods` periods after 2 s of settling.
    Multisine,
    /// One sine per record and direction at `freqs` `LO,HI,COUNT` (evenly spaced), recorded
    /// for `duration` (default 1 s) after 1 s of settling.
    SteppedSine,
    /// Linear sweep over `freqs` `LO,HI` in `sweep_time`, then free decay, on one direction
    /// per record, `records` records per direction.
    Sweep,
}

impl crate::Choice for Kind {
    const OPTION: &'static str = "simulated test";
    const ALL: &'static [Kind] = &[
        Kind::Impact,
        Kind::Random,
        Kind::Multisine,
        Kind::SteppedSine,
        Kind::Sweep,
    ];

    /// `impact`, `random`, `multisine`, `stepped-sine` or `sweep`, in the order of the
    /// command's help.
    fn name(self) -> &'static str {
        match self {
            Kind::Impact => "impact",
            Kind::Random => "random",
            Kind::Multisine => "multisine",
            Kind::SteppedSine => "stepped-sine",
            Kind::Sweep => "sweep",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Kind::Impact => "half-sine hammer hits, `--impacts` per degree of freedom",
            Kind::Random => "Gaussian forces on every degree of freedom at once",
            Kind::Multisine => "random-phase multisine, one direction per record",
            Kind::SteppedSine => "one sine per record and direction at `--freqs LO,HI,COUNT`",
            Kind::Sweep => "linear sweep over `--freqs LO,HI`, then free decay",
        }
    }
}

crate::choice::choice_text!(Kind);

/// A simulated test, as the `simulate` command takes it: each field is the command's option of
/// the same long name (`_` for `-`), with its default ([`Setup::default`]).
///
/// # Examples
/// ```
/// use bearing_ident::simulate::{Setup, seed_rig};
/// let mut s = Setup::default();
/// s.set("kind", "stepped-sine")?;
/// s.set("freqs", "10,40,4")?;
/// s.set("rate", "1000")?;
/// let test = s.run(&seed_rig())?;
/// assert_eq!(test.records.len(), 8); // 4 frequencies × 2 directions
/// assert_eq!(test.records[0].label(), "sine-10.000Hz-d0");
/// assert_eq!(test.records[0].len(), 1000); // 1 s kept after 1 s of settling
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Setup {
    /// `kind`: the excitation; default impacts.
    pub kind: Kind,
    /// `simultaneous`: multisine on every direction at once in each record (independent
    /// phases) instead of one direction per record; random forcing is always simultaneous.
    pub simultaneous: bool,
    /// `records`: records of random forcing, multisine or sweep (per direction for the
    /// shaker kinds); default 4, at least 1.
    pub records: usize,
    /// `force-rms`: RMS of each random or shaker force (N); default 50.
    pub force_rms: f64,
    /// `impacts`: hammer hits per degree of freedom; default 8, at least 1.
    pub impacts: usize,
    /// `noise`: measurement noise, a fraction of each signal kind's RMS; default 0.
    pub noise: f64,
    /// `seed`: seed of the forcing and noise generators; default 1.
    pub seed: u64,
    /// `rate`: sampling rate (Hz); default 6700.
    pub rate: f64,
    /// `duration`: record length (s). Default: impacts and sweeps, long enough for the
    /// response (internal states included) to decay to 1e-7; random, 60 s; stepped sine, 1 s
    /// kept; multisine, `period × periods`.
    pub duration: Option<f64>,
    /// `pulse`: half-sine pulse duration (s); default 0.002.
    pub pulse: f64,
    /// `freqs`: frequencies (Hz), `LO,HI` for multisine lines, sweeps and band-limited random
    /// forces, `LO,HI,COUNT` for stepped sines (defaults 8,49 / 5,60 / 10,48,15; random:
    /// white).
    pub freqs: Option<Vec<f64>>,
    /// `period`: multisine period (s); default 1.
    pub period: f64,
    /// `periods`: multisine periods recorded per record; default 8, at least 1.
    pub periods: usize,
    /// `sweep-time`: sweep duration (s) before the free decay; default 1.
    pub sweep_time: f64,
    /// `response`: what the response channels record, one kind for all or one per degree of
    /// freedom; default (none) displacement.
    pub response: Vec<Response>,
    /// `states`: the element's internal states, `POLE_HZ:A11,A12;A21,A22|POLE_HZ:…` (see
    /// [`ElementStates`]), simulated exactly with the system (not with nonlinear terms);
    /// none by default.
    pub states: ElementStates,
    /// The nonlinear terms (`coulomb`, `coulomb-planar`, `cubic`, `quadratic-damping`,
    /// `smoothing`, `oversampling`); none by default.
    pub nonlinear: NonlinearTerms,
}

impl Default for Setup {
    /// The `simulate` command's defaults: 8 impacts per direction at 6700 Hz, no noise.
    fn default() -> Self {
        Self {
            kind: Kind::Impact,
            simultaneous: false,
            records: 4,
            force_rms: 50.0,
            impacts: 8,
            noise: 0.0,
            seed: 1,
            rate: 6700.0,
            duration: None,
            pulse: 0.002,
            freqs: None,
            period: 1.0,
            periods: 8,
            sweep_time: 1.0,
            response: Vec::new(),
            states: ElementStates::default(),
            nonlinear: NonlinearTerms::default(),
        }
    }
}

/// The records of a [`Setup`] and the record length it chose.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Simulated {
    /// The records, labelled as the command names their files.
    pub records: Vec<Record>,
    /// The record length (s) the setup asked for or derived.
    pub duration_s: f64,
}

impl Setup {
    /// The long names [`Setup::set`] takes, in the `simulate` command's spelling.
    pub const NAMES: [&'static str; 22] = [
        "kind",
        "simultaneous",
        "records",
        "force-rms",
        "impacts",
        "noise",
        "seed",
        "rate",
        "duration",
        "pulse",
        "freqs",
        "period",
        "periods",
        "sweep-time",
        "response",
        "states",
        "coulomb",
        "coulomb-planar",
        "cubic",
        "quadratic-damping",
        "smoothing",
        "oversampling",
    ];

    /// Sets the option of long name `name` (`-` or `_` between words; one of
    /// [`Setup::NAMES`]) from its text as the command line takes it: lists comma-separated,
    /// flags as `true`/`false`.
    ///
    /// # Errors
    /// [`Error::UnknownName`] for a name not among [`Setup::NAMES`], a kind or response not
    /// among their names; [`Error::InvalidOption`] for a value that does not parse;
    /// [`Error::InvalidParameter`] for `states` out of range ([`ElementStates::new`]).
    pub fn set(&mut self, name: &str, value: &str) -> Result<()> {
        let key = name.replace('_', "-");
        let Some(&option) = Self::NAMES.iter().find(|n| **n == key) else {
            return Err(Error::UnknownName {
                what: "option",
                given: excerpt(name),
                expected: "an option of `simulate`, by its long name".into(),
            });
        };
        let invalid = |expected: &str| Error::InvalidOption {
            option,
            message: format!("--{option} `{}`: expected {expected}", excerpt(value)),
        };
        let number = || value.trim().parse::<f64>().map_err(|_| invalid("a number"));
        let count = || {
            let c = value.trim().parse::<usize>();
            c.map_err(|_| invalid("a count"))
        };
        let numbers = || {
            let list = value.split(',').map(|v| v.trim().parse::<f64>());
            list.collect::<std::result::Result<Vec<_>, _>>()
                .map_err(|_| invalid("numbers separated by commas"))
        };
        let n = &mut self.nonlinear;
        match option {
            "kind" => self.kind = value.trim().parse()?,
            "simultaneous" => {
                let flag = value.trim().parse::<bool>();
                self.simultaneous = flag.map_err(|_| invalid("true or false"))?;
            }
            "records" => self.records = count()?,
            "force-rms" => self.force_rms = number()?,
            "impacts" => self.impacts = count()?,
            "noise" => self.noise = number()?,
            "seed" => self.seed = value.trim().parse().map_err(|_| invalid("a seed"))?,
            "rate" => self.rate = number()?,
            "duration" => self.duration = Some(number()?),
            "pulse" => self.pulse = number()?,
            "freqs" => self.freqs = Some(numbers()?),
            "period" => self.period = number()?,
            "periods" => self.periods = count()?,
            "sweep-time" => self.sweep_time = number()?,
            "response" => {
                let kinds = value.split(',').map(|k| k.trim().parse::<Response>());
                self.response = kinds.collect::<Result<_>>()?;
            }
            "states" => self.states = value.parse()?,
            "coulomb" => n.coulomb = numbers()?,
            "coulomb-planar" => n.coulomb_planar = Some(number()?),
            "cubic" => n.cubic = numbers()?,
            "quadratic-damping" => n.quadratic_damping = numbers()?,
            "smoothing" => n.smoothing = Some(number()?),
            "oversampling" => n.oversampling = Some(count()?),
            _ => unreachable!("every name of NAMES has its arm"),
        }
        Ok(())
    }

    /// The records of this test on `system`: noise-free samples of the exact linear response
    /// (or of the RK4 integration with nonlinear terms), then measurement noise; the same
    /// records, bit for bit, as `bearing-ident simulate` writes with the same options.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the option: a rate that is not finite and positive, a
    /// count of 0 (`impacts`, `records`, `periods`), nonlinear terms with impacts,
    /// `simultaneous` with a kind other than multisine or random, `freqs` that do not fit the
    /// kind, `states` with nonlinear terms; [`Error::TooLarge`] for sizes past [`MAX_SAMPLES`]
    /// and the simulator's other limits, or a mode too slow to decay within them; the
    /// simulators' own refusals (a mass that is not positive definite, a system that does not
    /// decay, with its internal states if any: [`ElementStates::slowest_decay`]).
    pub fn run(&self, system: &Coefficients) -> Result<Simulated> {
        self.check()?;
        let base = ImpactTest::seed_rig();
        // Time for the slowest mode (internal states included) to decay to 1e-7 (e^{-16.1}); a
        // mass that is not positive definite or a mode that does not decay is an error naming
        // the matrix (or the states).
        let decay_s = SIMULATED_DECAY_NEPERS / self.states.slowest_decay(system)?;
        let decay_samples = decay_s * self.rate;
        let derived = self.duration.is_none() && matches!(self.kind, Kind::Impact | Kind::Sweep);
        if derived && (decay_samples.is_nan() || decay_samples > MAX_SAMPLES as f64) {
            return Err(Error::TooLarge {
                what: "samples for the slowest mode to decay to 1e-7 (add damping or give a \
                       duration)",
                value: decay_samples,
                limit: MAX_SAMPLES as f64,
            });
        }
        let duration_s = match (self.duration, self.kind) {
            (Some(d), _) => d,
            (None, Kind::Random) => 60.0,
            (None, Kind::SteppedSine) => 1.0,
            (None, Kind::Multisine) => self.period * self.periods as f64,
            (None, Kind::Sweep) => ((self.sweep_time + decay_s) * 10.0).ceil() / 10.0,
            (None, Kind::Impact) => {
                ((base.pretrigger_s + self.pulse + decay_s) * 10.0).ceil() / 10.0
            }
        };
        let test = ImpactTest {
            per_direction: self.impacts,
            sample_rate: self.rate,
            duration_s,
            pulse_s: self.pulse,
            noise: self.noise,
            seed: self.seed,
            ..base
        };
        let records = match self.kind {
            Kind::Impact => test.run_with_states(system, &self.states, &self.response)?,
            Kind::Multisine | Kind::SteppedSine | Kind::Sweep => {
                forcing::driven_records(self, system, decay_s)?
            }
            Kind::Random => forcing::random_records(self, system, test.samples()?)?,
        };
        Ok(Simulated {
            records,
            duration_s,
        })
    }

    /// Refuses, naming the option, what would write nothing or fail later under another name:
    /// a count of 0, a rate that is not a finite positive number, nonlinear terms with impacts
    /// or with internal states, `simultaneous` with a kind it does not apply to.
    fn check(&self) -> Result<()> {
        let refuse = |option, message: String| Err(Error::InvalidOption { option, message });
        if !(self.rate.is_finite() && self.rate > 0.0) {
            let message = format!(
                "--rate {}: the sampling rate must be a finite positive number of samples/s",
                self.rate
            );
            return refuse("rate", message);
        }
        if self.nonlinear.any() && self.kind == Kind::Impact {
            let message = "nonlinear terms need a forced test: --excitation random, multisine, \
                           stepped-sine or sweep (impacts give too little time at each amplitude)";
            return refuse("kind", message.into());
        }
        if self.nonlinear.any() && !self.states.is_empty() {
            let message = "--states are integrated by the exact linear simulator: they do not \
                           combine with nonlinear terms";
            return refuse("states", message.into());
        }
        if self.simultaneous && !matches!(self.kind, Kind::Multisine | Kind::Random) {
            let message = "--simultaneous drives every direction at once with independent \
                           multisines: it applies to --excitation multisine (random is \
                           simultaneous already)";
            return refuse("simultaneous", message.into());
        }
        let zero = match self.kind {
            Kind::Impact => (self.impacts == 0).then_some("impacts"),
            _ => (self.records == 0).then_some("records"),
        };
        let zero =
            zero.or((self.kind == Kind::Multisine && self.periods == 0).then_some("periods"));
        match zero {
            Some(option) => refuse(
                option,
                format!("--{option} 0: at least 1 is needed, or nothing would be written"),
            ),
            None => Ok(()),
        }
    }
}
