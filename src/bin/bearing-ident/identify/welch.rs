//! `identify` on random records without `--nperseg`: the Welch segment length chosen from a
//! first fit ([`choose_welch`]), reported in the JSON as `welch_choice`.

use bearing_ident::excitation::{Excitation, WelchChoice, choose_welch};
use std::time::{Duration, Instant};

use bearing_ident::{Identifier, Segmentation};

use super::{Files, IdentifyArgs};
use crate::failure::Failure;

/// For random excitation cut into Welch segments with no `--nperseg`: every record read (the
/// first file's are at hand, the others taken from the workers, `reading` gathering the wait),
/// a first fit, and the identifier with the chosen segment length, and the records for the
/// identification (not read again); otherwise the identifier, segment length and files as they
/// were, and no choice.
///
/// # Errors
/// Reading a file, and the first fit's errors.
pub fn choose(
    args: &IdentifyArgs,
    identifier: Identifier,
    segment_len: Option<usize>,
    excitation: Excitation,
    files: Files,
    reading: &mut Duration,
) -> Result<(Identifier, Option<usize>, Option<WelchChoice>, Files), Failure> {
    // Random records are cut into Welch segments unless paired sets took whole records.
    let needed = excitation == Excitation::Random && args.nperseg.is_none();
    let (first, ahead) = match files {
        Files::Streamed { first, ahead } if needed && segment_len.is_some() => (first, ahead),
        files => return Ok((identifier, segment_len, None, files)),
    };
    let mut records = first;
    let t = Instant::now();
    for file in ahead {
        records.extend(file?);
    }
    *reading += t.elapsed();
    // The first fit is for the modes only: IVF, no resampled error bars.
    let first = identifier
        .clone()
        .method(bearing_ident::Method::Ivf)
        .uncertainty(bearing_ident::Uncertainty::Sandwich);
    let choice = choose_welch(&records, &first)?;
    let identifier = identifier.segmentation(Segmentation::Welch {
        len: choice.nperseg,
    });
    Ok((
        identifier,
        Some(choice.nperseg),
        Some(choice),
        Files::Read(records),
    ))
}
