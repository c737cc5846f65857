//! Edge: an [`Identification`](crate::Identification) written for other tools (features `uff`
//! and `ross`).
//!
//! - [`uff`] (feature `uff`): the measured impedances and flexibilities, the fitted model's and
//!   the coherences as Universal File dataset 58 functions, for modal and data-acquisition
//!   software (and pyuff);
//! - [`ross`] (feature `ross`): the bearing element of a rotordynamic model in ROSS 3.x's TOML
//!   or JSON format, constant or per frequency;
//! - [`samples`] (feature `ross`): index-aligned samples of the coefficients drawn from their
//!   joint uncertainty, for stochastic rotor models.
//!
//! Both read a finished result only; nothing in the pipeline depends on them.
//!
// Without its feature, a link goes to the crate's feature list.
#![cfg_attr(not(feature = "uff"), doc = "[`uff`]: crate#feature-flags")]
#![cfg_attr(not(feature = "ross"), doc = "[`ross`]: crate#feature-flags")]
#![cfg_attr(not(feature = "ross"), doc = "[`samples`]: crate#feature-flags")]

#[cfg(feature = "ross")]
pub mod ross;
#[cfg(feature = "ross")]
pub mod samples;
#[cfg(feature = "uff")]
pub mod uff;
