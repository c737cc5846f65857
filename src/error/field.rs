//! [`FieldError`]: what field identification ([`field`](crate::field)) refuses, nested in
//! [`Error::Field`](super::Error::Field), with its messages and kinds.

use std::fmt;

use super::ErrorKind;
use super::message::rank_deficient_advice;

/// What field identification refuses: its inputs, or probes that cannot determine the
/// bearings.
///
/// # Examples
/// ```
/// use bearing_ident::error::FieldError;
/// use bearing_ident::Error;
/// let e: Error = FieldError::NonFinite { what: "M[0][1]".into() }.into();
/// assert_eq!(e.kind(), "non_finite");
/// assert_eq!(e.to_string(), "M[0][1] is not finite");
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum FieldError {
    /// A rotor model or test set that is not
    /// well formed (shapes, names, nodes, speeds, masses); the message names the key or record.
    Input {
        /// What is wrong, naming the key or record (input quoted by at most 80 characters).
        message: String,
    },
    /// A NaN or infinite value in a rotor model or a test set.
    NonFinite {
        /// The matrix entry or response holding the value.
        what: String,
    },
    /// A measured degree of freedom lacks its response at a speed and
    /// run (every speed and run needs the same probes).
    MissingResponse {
        /// The speed (rad/s).
        speed_rad_s: f64,
        /// The run: `baseline`, `1` or `2`.
        test: &'static str,
        /// The probe's node.
        node: usize,
        /// The probe's direction, `x` or `y`.
        dir: &'static str,
    },
    /// The probes cannot determine the bearing forces — fewer measured
    /// degrees of freedom than bearing degrees of freedom, or a least-squares system singular
    /// at every speed.
    Underdetermined {
        /// Measured degrees of freedom (probes).
        measured: usize,
        /// Bearing degrees of freedom (x and y per bearing).
        bearing_dofs: usize,
        /// Why the system is underdetermined.
        reason: &'static str,
    },
    /// At every speed the responses of the two tests at a bearing are
    /// dependent (masses in one plane, or isotropic supports and circular orbits).
    RankDeficient {
        /// Tag of the bearing.
        bearing: String,
        /// Smallest condition number of its response pair over the speeds.
        worst: f64,
        /// Whether the two tests' added forces are proportional (masses in one plane).
        dependent_tests: bool,
    },
}

impl FieldError {
    /// The kind of error, as [`Error::kind`](super::Error::kind) reports it.
    pub fn kind(&self) -> ErrorKind {
        match self {
            FieldError::Input { .. } => ErrorKind::InvalidInput,
            FieldError::NonFinite { .. } => ErrorKind::NonFinite,
            FieldError::MissingResponse { .. } => ErrorKind::MissingResponse,
            FieldError::Underdetermined { .. } => ErrorKind::Underdetermined,
            FieldError::RankDeficient { .. } => ErrorKind::RankDeficient,
        }
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FieldError::Input { message } => write!(f, "{message}"),
            FieldError::NonFinite { what } => write!(f, "{what} is not finite"),
            FieldError::MissingResponse {
                speed_rad_s,
                test,
                node,
                dir,
            } => write!(
                f,
                "no response at {speed_rad_s} rad/s, test `{test}`, node {node}, direction {dir}: \
                 every speed and test needs every probe"
            ),
            FieldError::Underdetermined {
                measured,
                bearing_dofs,
                reason,
            } => write!(
                f,
                "{measured} measured degrees of freedom for {bearing_dofs} bearing degrees of \
                 freedom: {reason}"
            ),
            FieldError::RankDeficient {
                bearing,
                worst,
                dependent_tests,
            } => write!(
                f,
                "bearing `{bearing}`: the two tests' responses are dependent at every speed \
                 (smallest condition number {worst:.3e}): {}",
                rank_deficient_advice(*dependent_tests)
            ),
        }
    }
}

impl std::error::Error for FieldError {}

impl From<FieldError> for super::Error {
    fn from(e: FieldError) -> Self {
        super::Error::Field(e)
    }
}
