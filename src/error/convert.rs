//! Other crates' errors into [`Error`].

use super::{Error, Factorization};

// faer 0.24's decomposition errors do not implement `std::error::Error`, so they are mapped here
// by hand.
impl From<faer::linalg::solvers::SvdError> for Error {
    fn from(_: faer::linalg::solvers::SvdError) -> Self {
        Error::Decomposition {
            what: Factorization::SingularValue,
        }
    }
}

impl From<faer::linalg::solvers::EvdError> for Error {
    fn from(_: faer::linalg::solvers::EvdError) -> Self {
        Error::Decomposition {
            what: Factorization::Eigenvalue,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faer_errors_convert() {
        let e: Error = faer::linalg::solvers::SvdError::NoConvergence.into();
        assert!(matches!(e, Error::Decomposition { .. }));
        let e: Error = faer::linalg::solvers::EvdError::NoConvergence.into();
        assert!(matches!(e, Error::Decomposition { .. }));
    }
}
