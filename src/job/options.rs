//! The options of a [`Job`](super::Job), as the `identify` command names them, with its
//! defaults; [`Options::set`] reads one by its long name (a campaign plan, keyword arguments).

use std::path::PathBuf;

use crate::element::ModelSpec;
use crate::error::{Error, Result, excerpt};
use crate::excitation::Excitation;
use crate::frf::{Estimator, ForceNoise};
use crate::identify::Uncertainty;
use crate::solve::Method;
use crate::spectra::Window;

/// The window as a user names it: a [`Window`] in its string form (`rect`, `hann`,
/// `exp:A/s` with the decay `A` in 1/s), or `exp:END`, an exponential on force and response
/// falling to `END` (`0 < END < 1`) at the end of each record or segment, whose decay depends
/// on the segment's duration, known once the records are ([`WindowChoice::window`]).
///
/// # Examples
/// ```
/// use bearing_ident::job::WindowChoice;
/// use bearing_ident::Window;
/// let w: WindowChoice = "exp:0.01".parse()?;
/// assert_eq!(w, WindowChoice::ExponentialTo(0.01));
/// assert!((w.window(1.2).decay_per_s().unwrap() - 3.8376).abs() < 1e-4);
/// assert_eq!(w.to_string(), "exp:0.01");
/// let fixed: WindowChoice = "exp:2.5/s".parse()?;
/// assert_eq!(fixed.window(1.2), Window::exponential(2.5)?);
/// assert_eq!("Hann".parse::<WindowChoice>()?, WindowChoice::Window(Window::Hann));
/// assert!("exp:1.5".parse::<WindowChoice>().is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum WindowChoice {
    /// This window, whatever the segments' duration.
    Window(Window),
    /// Exponential on force and response, falling to this value (`0 < END < 1`) at the end of
    /// each record or segment.
    ExponentialTo(f64),
}

impl WindowChoice {
    /// The window over segments of `segment_s` seconds.
    pub fn window(self, segment_s: f64) -> Window {
        match self {
            WindowChoice::Window(w) => w,
            WindowChoice::ExponentialTo(end) => Window::exponential_to(end, segment_s),
        }
    }
}

impl std::fmt::Display for WindowChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WindowChoice::Window(w) => w.fmt(f),
            WindowChoice::ExponentialTo(end) => write!(f, "exp:{end}"),
        }
    }
}

impl std::str::FromStr for WindowChoice {
    type Err = Error;

    /// `exp:END` with `0 < END < 1`, or a [`Window`]'s string form.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] quoting at most 80 characters of `s`.
    fn from_str(s: &str) -> Result<Self> {
        let bad = || Error::InvalidOption {
            option: "window",
            message: format!(
                "--window `{}`: expected rect, hann, exp:END with 0 < END < 1, or exp:A/s",
                excerpt(s)
            ),
        };
        let relative = s
            .split_once(':')
            .filter(|(name, end)| crate::choice::same_name("exp", name) && !end.contains('/'));
        match relative {
            Some((_, end)) => match end.trim().parse::<f64>() {
                Ok(end) if end > 0.0 && end < 1.0 => Ok(WindowChoice::ExponentialTo(end)),
                _ => Err(bad()),
            },
            None => s.parse().map(WindowChoice::Window).map_err(|_| bad()),
        }
    }
}

/// The options of an identification from files, with the `identify` command's defaults
/// ([`Options::new`]). Each field is the command's option of the same long name (`_` for `-`).
///
/// # Examples
/// ```
/// use bearing_ident::job::Options;
/// use bearing_ident::Method;
/// let mut o = Options::new(8.0, 49.0);
/// o.set("method", "ls")?;
/// o.set("min-r2", "0.8")?;
/// assert_eq!(o.method, Method::LeastSquares);
/// assert_eq!(o.min_r2, 0.8);
/// assert!(o.set("methd", "ls").is_err()); // unknown names are refused
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Options {
    /// `band`: the band (Hz), edges inclusive.
    pub band: (f64, f64),
    /// `method`: the fit; default IVF.
    pub method: Method,
    /// `excitation`: the kind of test; `None` (`auto`) detects it from the forces' crest factor.
    pub excitation: Option<Excitation>,
    /// `estimator`: overrides the estimator the excitation implies.
    pub estimator: Option<Estimator>,
    /// `window`: overrides the window the excitation implies (rectangular for impacts, Hann
    /// for random forcing).
    pub window: Option<WindowChoice>,
    /// `uncertainty`: the error bars; default [`Uncertainty::Auto`]. For the bootstrap, the
    /// draws and seed are [`Options::bootstrap_draws`] and [`Options::seed`].
    pub uncertainty: Uncertainty,
    /// `bootstrap-draws`: bootstrap resamples; default 200.
    pub bootstrap_draws: usize,
    /// `seed`: seed of the bootstrap's resampling; default 0.
    pub seed: u64,
    /// `force-gate`: the force channels open for this many seconds from each record's start,
    /// then a cosine taper over a fifth of that.
    pub force_gate_s: Option<f64>,
    /// `period`: the period (s) of periodic excitation.
    pub period_s: Option<f64>,
    /// `step-tolerance`: drive frequencies closer than this (Hz) are one step of a stepped-sine
    /// test; default 0.01.
    pub step_tolerance_hz: f64,
    /// `reject-bad-records`: leave out the records screening finds faulty (else warn only).
    pub reject_bad_records: bool,
    /// `force-noise`: what H1's force-side noise is taken for ([`ForceNoise`]); default auto.
    pub force_noise: ForceNoise,
    /// `model`: the element model ([`ModelSpec`]); default `kcm`.
    pub model: ModelSpec,
    /// `min-coherence`: drop lines where the multiple coherence of any output is below this;
    /// default 0.
    pub min_coherence: f64,
    /// `min-r2`: warn when the flexibility `r²` of an element that carries signal is below
    /// this; default 0.9.
    pub min_r2: f64,
    /// `nperseg`: the Welch segment length for random excitation (default: chosen from a
    /// first fit).
    pub nperseg: Option<usize>,
    /// `tolerance`: IVF's tolerance on the block-wise relative change; default 1e-8.
    pub tolerance: f64,
    /// `max-iterations`: IVF's iteration limit; default 50.
    pub max_iterations: usize,
    /// `allow-unconverged`: a non-converged fit is a warning, not an error.
    pub allow_unconverged: bool,
    /// `baseline`: a dry-structure baseline to subtract: a folder of its CSV records
    /// (identified with the same settings) or the JSON of an earlier identification.
    pub baseline: Option<PathBuf>,
    /// `calibration`: the relative standard (1σ) uncertainty of the sensor gains, as a
    /// calibration sheet states it: `force=1%,response=2%` per channel kind, or per channel
    /// by its name `fx=0.5%,x=2%` ([`crate::identify::Calibration::parse`]).
    pub calibration: Option<String>,
    /// `drop-periods`: periodic records: the first periods of every record left out (a
    /// start-up transient); default 0.
    pub drop_periods: usize,
    /// The channels' known transfer characteristics (a delay, an AC coupling), divided out of
    /// their spectra before any average, with channels by index; those of `delay` and
    /// `highpass` (by name) are added to them.
    pub channel_transfers: crate::frf::ChannelTransfers,
    /// `delay`: channels' known delays by name, `x=0.25ms` or with a stated standard
    /// uncertainty `x=0.25ms±0.02ms`, comma list
    /// ([`crate::frf::ChannelTransfers::parse_delays`]).
    pub delay: Option<String>,
    /// `highpass`: channels' known AC coupling by name, `x=3Hz`, `x=3Hz:2` or with a stated
    /// standard uncertainty `x=3Hz±0.3Hz`, comma list
    /// ([`crate::frf::ChannelTransfers::parse_high_passes`]).
    pub highpass: Option<String>,
    /// `clearance`, `load`, `speed`: the test's radial clearance, static load and rotor speed,
    /// each with its unit (`100um`, `500N`, `3000rpm`: [`crate::rotor::parse_clearance`],
    /// [`crate::rotor::parse_load`], [`crate::rotor::parse_speed`]), for the dimensionless
    /// coefficients and the stability of a rigid rotor on the element.
    pub conditions: crate::rotor::Conditions,
}

impl Options {
    /// The long names [`Options::set`] takes, in the `identify` command's spelling.
    pub const NAMES: [&'static str; 28] = [
        "band",
        "method",
        "excitation",
        "estimator",
        "window",
        "uncertainty",
        "force-noise",
        "model",
        "bootstrap-draws",
        "seed",
        "force-gate",
        "period",
        "step-tolerance",
        "reject-bad-records",
        "min-coherence",
        "min-r2",
        "nperseg",
        "tolerance",
        "max-iterations",
        "allow-unconverged",
        "baseline",
        "calibration",
        "drop-periods",
        "delay",
        "highpass",
        "clearance",
        "load",
        "speed",
    ];

    /// The defaults of the `identify` command over the band `low_hz`–`high_hz`.
    pub fn new(low_hz: f64, high_hz: f64) -> Self {
        Self {
            band: (low_hz, high_hz),
            method: Method::Ivf,
            excitation: None,
            estimator: None,
            window: None,
            uncertainty: Uncertainty::Auto,
            force_noise: ForceNoise::Auto,
            model: ModelSpec::Family(crate::element::Family::Kcm),
            bootstrap_draws: 200,
            seed: 0,
            force_gate_s: None,
            period_s: None,
            step_tolerance_hz: 0.01,
            reject_bad_records: false,
            min_coherence: 0.0,
            min_r2: 0.9,
            nperseg: None,
            tolerance: 1e-8,
            max_iterations: 50,
            allow_unconverged: false,
            baseline: None,
            calibration: None,
            drop_periods: 0,
            channel_transfers: crate::frf::ChannelTransfers::new(),
            delay: None,
            highpass: None,
            conditions: crate::rotor::Conditions::default(),
        }
    }

    /// Sets the option of long name `name` (`-` or `_` between words; one of
    /// [`Options::NAMES`]) from its text as the command line takes it: `band` as `LO,HI`,
    /// choices by name (`auto` for the detected excitation), flags as `true`/`false`.
    ///
    /// # Errors
    /// [`Error::UnknownName`] for a name not among [`Options::NAMES`] or a choice not among
    /// its names; [`Error::InvalidOption`] for a value that does not parse.
    pub fn set(&mut self, name: &str, value: &str) -> Result<()> {
        let key = name.replace('_', "-");
        let Some(&option) = Self::NAMES.iter().find(|n| **n == key) else {
            return Err(Error::UnknownName {
                what: "option",
                given: name.to_owned(),
                expected: "an option of `identify`, by its long name".into(),
            });
        };
        let invalid = |expected: &str| Error::InvalidOption {
            option,
            message: format!("--{option} `{}`: expected {expected}", excerpt(value)),
        };
        let number = || value.trim().parse::<f64>().map_err(|_| invalid("a number"));
        let count = || {
            value
                .trim()
                .parse::<usize>()
                .map_err(|_| invalid("a count"))
        };
        let flag = || {
            value
                .trim()
                .parse::<bool>()
                .map_err(|_| invalid("true or false"))
        };
        match option {
            "band" => self.band = parse_band(value)?,
            "method" => self.method = value.parse()?,
            "excitation" => {
                self.excitation = match value {
                    v if crate::choice::same_name("auto", v) => None,
                    v => Some(v.parse()?),
                }
            }
            "estimator" => self.estimator = Some(value.parse()?),
            "window" => self.window = Some(value.parse()?),
            "uncertainty" => self.uncertainty = value.parse()?,
            "force-noise" => self.force_noise = value.parse()?,
            "model" => self.model = value.parse()?,
            "bootstrap-draws" => self.bootstrap_draws = count()?,
            "seed" => self.seed = value.trim().parse().map_err(|_| invalid("a seed"))?,
            "force-gate" => self.force_gate_s = Some(number()?),
            "period" => self.period_s = Some(number()?),
            "step-tolerance" => self.step_tolerance_hz = number()?,
            "reject-bad-records" => self.reject_bad_records = flag()?,
            "min-coherence" => self.min_coherence = number()?,
            "min-r2" => self.min_r2 = number()?,
            "nperseg" => self.nperseg = Some(count()?),
            "tolerance" => self.tolerance = number()?,
            "max-iterations" => self.max_iterations = count()?,
            "allow-unconverged" => self.allow_unconverged = flag()?,
            "baseline" => self.baseline = Some(PathBuf::from(value)),
            "calibration" => self.calibration = Some(value.to_owned()),
            "drop-periods" => self.drop_periods = count()?,
            "delay" => self.delay = Some(value.to_owned()),
            "highpass" => self.highpass = Some(value.to_owned()),
            "clearance" => {
                self.conditions = self
                    .conditions
                    .clearance_m(crate::rotor::parse_clearance(value)?);
            }
            "load" => self.conditions = self.conditions.load_n(crate::rotor::parse_load(value)?),
            "speed" => {
                self.conditions = self
                    .conditions
                    .speed_rad_s(crate::rotor::parse_speed(value)?);
            }
            _ => unreachable!("every name of NAMES has its arm"),
        }
        Ok(())
    }

    /// The uncertainty with the bootstrap's draws and seed.
    pub(crate) fn uncertainty(&self) -> Uncertainty {
        match self.uncertainty {
            Uncertainty::Bootstrap { .. } => Uncertainty::Bootstrap {
                replicates: self.bootstrap_draws,
                seed: self.seed,
            },
            u => u,
        }
    }
}

/// A band `LO,HI` in Hz.
///
/// # Errors
/// [`Error::InvalidOption`] (kind `bad_band`) quoting at most 80 characters of `s`.
///
/// # Examples
/// ```
/// use bearing_ident::job::parse_band;
/// assert_eq!(parse_band("8, 49")?, (8.0, 49.0));
/// assert_eq!(parse_band("8-49").unwrap_err().kind(), "bad_band");
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn parse_band(s: &str) -> Result<(f64, f64)> {
    let bad = || Error::BandText { given: excerpt(s) };
    let (lo, hi) = s.split_once(',').ok_or_else(bad)?;
    let lo: f64 = lo.trim().parse().map_err(|_| bad())?;
    let hi: f64 = hi.trim().parse().map_err(|_| bad())?;
    Ok((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every name of `NAMES` is taken by `set`, with `_` for `-` too; an unknown name is
    /// refused, as is a value that does not parse.
    #[test]
    fn every_name_is_set() {
        let values = [
            ("band", "1,2"),
            ("method", "ml"),
            ("excitation", "random"),
            ("estimator", "h2"),
            ("window", "exp:0.1"),
            ("uncertainty", "bootstrap"),
            ("force-noise", "measurement"),
            ("model", "auto"),
            ("bootstrap-draws", "30"),
            ("seed", "7"),
            ("force-gate", "0.01"),
            ("period", "1.5"),
            ("step-tolerance", "0.5"),
            ("reject-bad-records", "true"),
            ("min-coherence", "0.5"),
            ("min-r2", "-1"),
            ("nperseg", "512"),
            ("tolerance", "1e-6"),
            ("max-iterations", "9"),
            ("allow-unconverged", "true"),
            ("baseline", "dry/"),
            ("calibration", "force=1%"),
            ("drop-periods", "1"),
            ("delay", "x=0.25ms±0.02ms"),
            ("highpass", "response=3Hz"),
            ("clearance", "100um"),
            ("load", "500N"),
            ("speed", "3000rpm"),
        ];
        assert_eq!(values.len(), Options::NAMES.len());
        let mut o = Options::new(8.0, 49.0);
        for (name, value) in values {
            let before = o.clone();
            o.set(&name.replace('-', "_"), value).unwrap();
            assert_ne!(o, before, "{name}");
        }
        assert_eq!(o.band, (1.0, 2.0));
        assert_eq!(
            o.uncertainty(),
            Uncertainty::Bootstrap {
                replicates: 30,
                seed: 7
            }
        );
        assert_eq!(o.window, Some(WindowChoice::ExponentialTo(0.1)));
        assert_eq!(
            o.set("bands", "1,2").unwrap_err().kind(),
            "invalid_argument"
        );
        assert_eq!(
            o.set("nperseg", "-1").unwrap_err().kind(),
            "invalid_argument"
        );
        assert_eq!(o.set("band", "1;2").unwrap_err().kind(), "bad_band");
        assert_eq!(o.conditions.load(), Some(500.0));
        for (name, value) in [("clearance", "0um"), ("load", "-1N"), ("speed", "3000")] {
            let e = o.set(name, value).unwrap_err();
            assert_eq!(e.kind(), "invalid_argument");
            assert!(e.to_string().contains(&format!("--{name}")), "{e}");
        }
        assert_eq!(
            o.set("method", "ivff").unwrap_err().kind(),
            "invalid_argument"
        );
        o.set("excitation", "auto").unwrap();
        assert_eq!(o.excitation, None);
    }
}
