//! From coefficients to the rotor: the operating conditions of a test ([`Conditions`]:
//! radial clearance, static load, rotor speed), the coefficients in the dimensionless form
//! of test reports ([`Dimensionless`]) and the stability of a rigid rotor on the element
//! ([`Stability`]: Lund's whirl-frequency ratio and threshold speed, the sign change of the
//! effective damping), the coefficients at the excitation frequency equal to the speed
//! ([`Synchronous`]), each with its standard deviation propagated from the coefficients'
//! covariance ([`Identification::covariance`](crate::Identification::covariance)).
//!
//! The conditions are those of the test: the coefficients are taken as measured at the
//! speed and load given, and the dimensionless coefficients as the ones a rotor at another
//! speed would keep (Lund's assumption behind the threshold speed).

mod conditions;
mod dimensionless;
mod propagate;
mod stability;
mod synchronous;

pub use conditions::{Conditions, STANDARD_GRAVITY, parse_clearance, parse_load, parse_speed};
pub use dimensionless::Dimensionless;
pub use propagate::propagated_std;
pub use stability::{Lund, Stability, lund};
pub use synchronous::{SyncSource, Synchronous};
