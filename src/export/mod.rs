//! Edge: an [`Identification`](crate::Identification) written for other tools (features `uff`
//! and `ross`).
//!
//! - [`uff`] (feature `uff`): the measured impedances and flexibilities, the fitted model's and
//!   the coherences as Universal File dataset 58 functions, for modal and data-acquisition
//!   software (and pyuff);
//! - [`ross`] (feature `ross`): the bearing element of a rotordynamic model in ROSS 3.x's TOML
//!   or JSON format, constant or per frequency.
//!
//! Both read a finished result only; nothing in the pipeline depends on them.

#[cfg(feature = "ross")]
pub mod ross;
#[cfg(feature = "uff")]
pub mod uff;
