//! The text form of channel transfers, as the command line, [`crate::job::Options::set`] and
//! a campaign plan take it: comma-separated `NAME=VALUE` items, NAME a channel's name or a kind
//! (`force`, `response`: every channel of it), VALUE the characteristic with an optional
//! stated standard uncertainty after `±` (or `+-`).

use super::{ChannelTransfer, ChannelTransfers};
use crate::error::{Channel, Error, Result, excerpt};

/// Which characteristic a text gives.
#[derive(Clone, Copy)]
enum Kind {
    Delay,
    HighPass,
}

impl Kind {
    /// The option's long name.
    fn option(self) -> &'static str {
        match self {
            Kind::Delay => "delay",
            Kind::HighPass => "highpass",
        }
    }

    /// What a value should look like.
    fn expected(self) -> &'static str {
        match self {
            Kind::Delay => {
                "expected NAME=DELAY with a unit (s, ms, us), e.g. x=0.25ms or x=0.25ms±0.02ms"
            }
            Kind::HighPass => {
                "expected NAME=CORNER in Hz, e.g. x=3Hz, x=3Hz:2 (order 2) or x=3Hz±0.3Hz"
            }
        }
    }

    /// The characteristic and the uncertainty of its parameter from `value`.
    fn read(self, value: &str) -> Option<(ChannelTransfer, f64)> {
        let (value, std) = match value.split_once('±').or_else(|| value.split_once("+-")) {
            Some((v, u)) => (v.trim(), Some(u.trim())),
            None => (value.trim(), None),
        };
        let (transfer, parameter, unit) = match self {
            Kind::Delay => {
                let (seconds, unit) = with_unit(
                    value,
                    &[("ms", 1e-3), ("us", 1e-6), ("µs", 1e-6), ("s", 1.0)],
                )?;
                (ChannelTransfer::delay(seconds), seconds, unit)
            }
            Kind::HighPass => {
                let (corner, order) = match value.split_once(':') {
                    Some((c, o)) => (c.trim(), o.trim().parse().ok()?),
                    None => (value, 1),
                };
                let (hz, unit) = with_unit(corner, &[("Hz", 1.0)])?;
                let t = ChannelTransfer::HighPass {
                    corner_hz: hz,
                    order,
                };
                (t, hz, unit)
            }
        };
        let std = match std {
            None => 0.0,
            Some(u) => match u.strip_suffix('%') {
                Some(percent) => percent.trim().parse::<f64>().ok()? / 100.0 * parameter.abs(),
                None => {
                    let units: &[(&str, f64)] = match self {
                        Kind::Delay => &[("ms", 1e-3), ("us", 1e-6), ("µs", 1e-6), ("s", 1.0)],
                        Kind::HighPass => &[("Hz", 1.0)],
                    };
                    // A bare number takes the value's unit.
                    match u.parse::<f64>() {
                        Ok(number) => number * unit,
                        Err(_) => with_unit(u, units)?.0,
                    }
                }
            },
        };
        Some((transfer, std))
    }
}

/// `(number × scale, scale)` of `text`, a number followed by one of `units` (scale 1 if none).
fn with_unit(text: &str, units: &[(&str, f64)]) -> Option<(f64, f64)> {
    let (number, scale) = units
        .iter()
        .find_map(|(unit, scale)| text.strip_suffix(unit).map(|v| (v, *scale)))
        .unwrap_or((text, 1.0));
    let v: f64 = number.trim().parse().ok()?;
    Some((v * scale, scale))
}

impl ChannelTransfers {
    /// These characteristics and the delays `spec` gives: comma-separated `NAME=DELAY`, NAME
    /// a channel's name in `force_names` / `response_names` or `force` / `response` (every
    /// channel of that kind), DELAY with a unit (`0.25ms`, `250us`, `2.5e-4s`; seconds if
    /// none), optionally followed by its stated standard uncertainty after `±` or `+-`
    /// (`0.25ms±0.02ms`; a bare number takes the delay's unit, `10%` is relative), which
    /// enters the calibration part of the budget ([`ChannelTransfers::with_uncertainty`]).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] (option `delay`) for an item without `=`, a value that does not
    /// parse or is out of range ([`ChannelTransfer::check`], an uncertainty not finite and
    /// ≥ 0); [`Error::UnknownName`] for a NAME that is none of the channels.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::frf::{ChannelTransfer, ChannelTransfers};
    /// use bearing_ident::Channel;
    /// let t = ChannelTransfers::new().parse_delays("x=0.25ms±0.02ms", &["fx"], &["x"])?;
    /// assert_eq!(t.entries(), [(Channel::Displacement(0), ChannelTransfer::delay(2.5e-4))]);
    /// assert!((t.uncertainties()[0] - 2e-5).abs() < 1e-18);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn parse_delays(
        self,
        spec: &str,
        force_names: &[impl AsRef<str>],
        response_names: &[impl AsRef<str>],
    ) -> Result<Self> {
        self.parse(Kind::Delay, spec, force_names, response_names)
    }

    /// These characteristics and the AC couplings `spec` gives: comma-separated
    /// `NAME=CORNER`, NAME as for [`ChannelTransfers::parse_delays`], CORNER in Hz (`3Hz` or
    /// `3`; `3Hz:2` for order 2), optionally followed by its stated standard uncertainty after
    /// `±` or `+-` (`3Hz±0.3Hz`, `3Hz:2±0.3Hz`, `3Hz±10%`).
    ///
    /// # Errors
    /// As [`ChannelTransfers::parse_delays`] (option `highpass`).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::frf::{ChannelTransfer, ChannelTransfers};
    /// use bearing_ident::Channel;
    /// let t = ChannelTransfers::new().parse_high_passes("response=3Hz+-10%", &["fx", "fy"], &["x", "y"])?;
    /// assert_eq!(t.entries().len(), 2);
    /// assert_eq!(t.entries()[1], (Channel::Displacement(1), ChannelTransfer::high_pass(3.0)));
    /// assert!((t.uncertainties()[1] - 0.3).abs() < 1e-12);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn parse_high_passes(
        self,
        spec: &str,
        force_names: &[impl AsRef<str>],
        response_names: &[impl AsRef<str>],
    ) -> Result<Self> {
        self.parse(Kind::HighPass, spec, force_names, response_names)
    }

    fn parse(
        mut self,
        kind: Kind,
        spec: &str,
        force_names: &[impl AsRef<str>],
        response_names: &[impl AsRef<str>],
    ) -> Result<Self> {
        let forces: Vec<&str> = force_names.iter().map(AsRef::as_ref).collect();
        let responses: Vec<&str> = response_names.iter().map(AsRef::as_ref).collect();
        for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let bad = |what: &str| Error::InvalidOption {
                option: kind.option(),
                message: format!("--{} `{}`: {what}", kind.option(), excerpt(item)),
            };
            let (name, value) = item.split_once('=').ok_or_else(|| bad(kind.expected()))?;
            let (transfer, std) = kind.read(value).ok_or_else(|| bad(kind.expected()))?;
            let one = ChannelTransfers::new().with_uncertainty(Channel::Force(0), transfer, std);
            one.check(None).map_err(|e| bad(&e.to_string()))?;
            let channels =
                channels(name.trim(), &forces, &responses).ok_or_else(|| Error::UnknownName {
                    what: "corrected channel",
                    given: name.trim().to_owned(),
                    expected: "force, response or a force or response channel's name".into(),
                })?;
            for channel in channels {
                self = self.with_uncertainty(channel, transfer, std);
            }
        }
        Ok(self)
    }
}

/// The channels `name` stands for: every force or response channel for the kinds, else the
/// one channel of that name.
fn channels(name: &str, forces: &[&str], responses: &[&str]) -> Option<Vec<Channel>> {
    match name {
        "force" => Some((0..forces.len()).map(Channel::Force).collect()),
        "response" => Some((0..responses.len()).map(Channel::Displacement).collect()),
        _ => forces
            .iter()
            .position(|f| *f == name)
            .map(Channel::Force)
            .or_else(|| {
                responses
                    .iter()
                    .position(|r| *r == name)
                    .map(Channel::Displacement)
            })
            .map(|c| vec![c]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const F: [&str; 2] = ["fx", "fy"];
    const X: [&str; 2] = ["x", "y"];

    #[test]
    fn values_units_and_uncertainties_are_read() {
        let t = ChannelTransfers::new()
            .parse_delays("x=0.25ms±0.02ms, force=2us+-1", &F, &X)
            .unwrap()
            .parse_high_passes("y=3Hz:2±0.3Hz", &F, &X)
            .unwrap();
        assert_eq!(
            t.entries(),
            [
                (Channel::Displacement(0), ChannelTransfer::delay(0.25e-3)),
                (Channel::Force(0), ChannelTransfer::delay(2e-6)),
                (Channel::Force(1), ChannelTransfer::delay(2e-6)),
                (
                    Channel::Displacement(1),
                    ChannelTransfer::HighPass {
                        corner_hz: 3.0,
                        order: 2
                    }
                ),
            ]
        );
        let expected = [2e-5, 1e-6, 1e-6, 0.3];
        for (u, e) in t.uncertainties().iter().zip(expected) {
            assert!((u - e).abs() < 1e-12 * e, "{u} vs {e}");
        }
        let plain = ChannelTransfers::new()
            .parse_high_passes("x=3", &F, &X)
            .unwrap();
        assert_eq!(plain.uncertainties(), [0.0]);
    }

    #[test]
    fn bad_items_are_refused_by_kind() {
        let kind = |d: &str, h: &str| match ChannelTransfers::new()
            .parse_delays(d, &F, &X)
            .and_then(|t| t.parse_high_passes(h, &F, &X))
        {
            Err(Error::UnknownName { .. }) => "unknown",
            Err(Error::InvalidOption { option, .. }) => option,
            Err(e) => panic!("{e:?}"),
            Ok(_) => "ok",
        };
        assert_eq!(kind("z=1ms", ""), "unknown");
        assert_eq!(kind("x", ""), "delay");
        assert_eq!(kind("x=1 fortnight", ""), "delay");
        assert_eq!(kind("x=NaNms", ""), "delay");
        assert_eq!(kind("x=1ms±-0.1ms", ""), "delay");
        assert_eq!(kind("x=1ms±abc", ""), "delay");
        assert_eq!(kind("", "x=-3Hz"), "highpass");
        assert_eq!(kind("", "x=3Hz:0"), "highpass");
        assert_eq!(kind("", "x=3Hz±infHz"), "highpass");
        assert_eq!(kind("", "x=3Hz"), "ok");
        let e = ChannelTransfers::new()
            .parse_delays("x=1ms±-0.1ms", &F, &X)
            .unwrap_err();
        assert!(
            e.to_string().contains("channel transfer uncertainty"),
            "{e}"
        );
    }
}
