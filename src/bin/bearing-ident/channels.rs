//! `identify --delay` and `--highpass`: the channels' known transfer characteristics, each
//! `NAME=VALUE[±STD]` with NAME a channel (a force or response column as `--force`/`--disp`
//! name them, or their defaults) or a kind (`force`, `response`: every channel of it), turned
//! into the library's [`ChannelTransfers`] by its own parser
//! ([`ChannelTransfers::parse_delays`], [`ChannelTransfers::parse_high_passes`]).

use bearing_ident::Error;
use bearing_ident::error::excerpt;
use bearing_ident::frf::ChannelTransfers;

use crate::failure::Failure;

/// The characteristics `--delay` (`NAME=0.25ms`; units `s`, `ms`, `us`; seconds if none) and
/// `--highpass` (`NAME=3Hz`, or `NAME=3Hz:2` for a second-order corner) give, each with an
/// optional stated standard uncertainty (`0.25ms±0.02ms`, `3Hz+-0.3Hz`), for the force
/// channels `forces` and the response channels `responses` (names, one per degree of freedom).
///
/// # Errors
/// `invalid_argument` for an entry without `=`, a value that does not parse or is out of range
/// ([`bearing_ident::frf::ChannelTransfer::check`]); `unknown_name` for a channel that is none
/// of the names.
pub fn transfers(
    delays: &[String],
    highpasses: &[String],
    forces: &[String],
    responses: &[String],
) -> Result<ChannelTransfers, Failure> {
    let unknown = |option: &str, entry: &str| Failure {
        kind: "unknown_name",
        message: format!(
            "--{option} `{}`: no channel of that name; expected force, response or one of {}",
            excerpt(entry),
            forces
                .iter()
                .chain(responses)
                .cloned()
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut out = ChannelTransfers::new();
    for entry in delays {
        out = match out.parse_delays(entry, forces, responses) {
            Err(Error::UnknownName { .. }) => return Err(unknown("delay", entry)),
            other => other?,
        };
    }
    for entry in highpasses {
        out = match out.parse_high_passes(entry, forces, responses) {
            Err(Error::UnknownName { .. }) => return Err(unknown("highpass", entry)),
            other => other?,
        };
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use bearing_ident::Channel;
    use bearing_ident::frf::ChannelTransfer;

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn names_kinds_units_and_uncertainties_are_read() {
        let (f, x) = (names(&["fx", "fy"]), names(&["x", "y"]));
        let t = transfers(
            &names(&["x=0.25ms±0.02ms", "force=2us"]),
            &names(&["y=3Hz:2+-0.3Hz"]),
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
        assert!((t.uncertainties()[0] - 2e-5).abs() < 1e-18);
        assert!((t.uncertainties()[3] - 0.3).abs() < 1e-15);
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
        assert_eq!(kind(&["x=1ms±-1us"], &[]), "invalid_argument");
        assert_eq!(kind(&[], &["x=-3Hz"]), "invalid_argument");
        assert_eq!(kind(&[], &["x=3Hz:0"]), "invalid_argument");
        assert_eq!(kind(&[], &["x=3Hz"]), "ok");
    }
}
