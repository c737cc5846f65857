//! `identify --delay` and `--highpass`: the channels' known transfer characteristics, each
//! `NAME=VALUE` with NAME a channel (a force or response column as `--force`/`--disp` name
//! them, or their defaults) or a kind (`force`, `response`: every channel of it), turned into the
//! library's [`ChannelTransfers`].

use bearing_ident::Channel;
use bearing_ident::error::excerpt;
use bearing_ident::frf::{ChannelTransfer, ChannelTransfers};

use crate::failure::{Failure, invalid};

/// The characteristics `--delay` (`NAME=0.25ms`; units `s`, `ms`, `us`; seconds if none) and
/// `--highpass` (`NAME=3Hz`, or `NAME=3Hz:2` for a second-order corner) give, for the force
/// channels `forces` and the response channels `responses` (names, one per degree of freedom).
///
/// # Errors
/// `invalid_argument` for an entry without `=`, a value that does not parse or is out of range
/// ([`ChannelTransfer::check`]); `unknown_name` for a channel that is none of the names.
pub fn transfers(
    delays: &[String],
    highpasses: &[String],
    forces: &[String],
    responses: &[String],
) -> Result<ChannelTransfers, Failure> {
    let mut out = ChannelTransfers::new();
    for (option, entries) in [("delay", delays), ("highpass", highpasses)] {
        for entry in entries {
            let bad = |what: &str| invalid(format!("--{option} `{}`: {what}", excerpt(entry)));
            let (name, value) = entry
                .split_once('=')
                .ok_or_else(|| bad("expected NAME=VALUE, e.g. x=0.25ms or response=3Hz"))?;
            let transfer = match option {
                "delay" => ChannelTransfer::delay(seconds(value.trim()).ok_or_else(|| {
                    bad("expected a delay with its unit, e.g. 0.25ms (s, ms, us)")
                })?),
                _ => corner(value.trim()).ok_or_else(|| {
                    bad("expected a corner in Hz, e.g. 3Hz, or 3Hz:2 for order 2")
                })?,
            };
            transfer.check().map_err(|e| bad(&e.to_string()))?;
            for channel in channels(name.trim(), forces, responses).ok_or_else(|| Failure {
                kind: "unknown_name",
                message: format!(
                    "--{option} `{}`: no channel of that name; expected force, response or one of {}",
                    excerpt(entry),
                    forces.iter().chain(responses).cloned().collect::<Vec<_>>().join(", ")
                ),
            })? {
                out = out.with(channel, transfer);
            }
        }
    }
    Ok(out)
}

/// The channels `name` stands for: every force or response channel for the kinds, else the
/// one channel of that name.
fn channels(name: &str, forces: &[String], responses: &[String]) -> Option<Vec<Channel>> {
    match name {
        "force" => Some((0..forces.len()).map(Channel::Force).collect()),
        "response" => Some((0..responses.len()).map(Channel::Displacement).collect()),
        _ => forces
            .iter()
            .position(|f| f == name)
            .map(Channel::Force)
            .or_else(|| {
                responses
                    .iter()
                    .position(|r| r == name)
                    .map(Channel::Displacement)
            })
            .map(|c| vec![c]),
    }
}

/// Seconds from `0.25ms`, `250us`, `2.5e-4s` or `2.5e-4`.
fn seconds(value: &str) -> Option<f64> {
    let (number, scale) = [("ms", 1e-3), ("us", 1e-6), ("µs", 1e-6), ("s", 1.0)]
        .iter()
        .find_map(|(unit, scale)| value.strip_suffix(unit).map(|v| (v, *scale)))
        .unwrap_or((value, 1.0));
    number.trim().parse::<f64>().ok().map(|v| v * scale)
}

/// A high-pass from `3Hz`, `3` or `3Hz:2` (order 2).
fn corner(value: &str) -> Option<ChannelTransfer> {
    let (corner, order) = match value.split_once(':') {
        Some((c, o)) => (c, o.trim().parse().ok()?),
        None => (value, 1),
    };
    let corner = corner.trim();
    let hz: f64 = corner
        .strip_suffix("Hz")
        .unwrap_or(corner)
        .trim()
        .parse()
        .ok()?;
    Some(ChannelTransfer::HighPass {
        corner_hz: hz,
        order,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn names_kinds_and_units_are_read() {
        let (f, x) = (names(&["fx", "fy"]), names(&["x", "y"]));
        let t = transfers(
            &names(&["x=0.25ms", "force=2us"]),
            &names(&["y=3Hz:2"]),
            &f,
            &x,
        )
        .ok()
        .expect("parses");
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
    }

    #[test]
    fn bad_entries_are_refused_with_their_kind() {
        let (f, x) = (names(&["fx"]), names(&["x"]));
        let kind = |d: &[&str], h: &[&str]| match transfers(&names(d), &names(h), &f, &x) {
            Err(e) => e.kind,
            Ok(_) => "ok",
        };
        assert_eq!(kind(&["z=1ms"], &[]), "unknown_name");
        assert_eq!(kind(&["x"], &[]), "invalid_argument");
        assert_eq!(kind(&["x=1 fortnight"], &[]), "invalid_argument");
        assert_eq!(kind(&["x=NaNms"], &[]), "invalid_argument");
        assert_eq!(kind(&[], &["x=-3Hz"]), "invalid_argument");
        assert_eq!(kind(&[], &["x=3Hz:0"]), "invalid_argument");
        assert_eq!(kind(&[], &["x=3Hz"]), "ok");
    }
}
