//! `identify` on random records without `--nperseg`: the Welch segment length chosen from a
//! first fit ([`choose_welch`]), reported in the JSON as `welch_choice`.

use bearing_ident::excitation::{Excitation, WelchChoice, choose_welch};
use bearing_ident::records::Record;
use bearing_ident::{Identifier, Segmentation};

use super::IdentifyArgs;
use crate::failure::Failure;
use crate::read::{Layout, read_file};

/// For random excitation cut into Welch segments with no `--nperseg`: every record read (the
/// first file's are at hand), a first fit, and the identifier with the chosen segment length;
/// otherwise the identifier and segment length as they were, and no choice.
///
/// # Errors
/// Reading a file, and the first fit's errors.
pub fn choose(
    args: &IdentifyArgs,
    identifier: Identifier,
    segment_len: Option<usize>,
    excitation: Excitation,
    first_file: &[Record],
    layout: &Layout,
) -> Result<(Identifier, Option<usize>, Option<WelchChoice>), Failure> {
    // Random records are cut into Welch segments unless paired sets took whole records.
    if excitation != Excitation::Random || args.nperseg.is_some() || segment_len.is_none() {
        return Ok((identifier, segment_len, None));
    }
    let mut records = first_file.to_vec();
    for path in &args.files[1..] {
        records.extend(read_file(path, layout)?);
    }
    // The first fit is for the modes only: IVF, no resampled error bars.
    let first = identifier
        .clone()
        .method(bearing_ident::Method::Ivf)
        .uncertainty(bearing_ident::Uncertainty::Sandwich);
    let choice = choose_welch(&records, &first)?;
    let identifier = identifier.segmentation(Segmentation::Welch {
        len: choice.nperseg,
    });
    Ok((identifier, Some(choice.nperseg), Some(choice)))
}
