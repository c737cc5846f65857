//! [`Assignment`]: which excitation (degree of freedom) each record belongs to.

use crate::error::{Error, Result};
use crate::records::Record;

/// Which excitation (degree of freedom) each record belongs to, for [`Estimator::PairedSets`](super::Estimator::PairedSets).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Assignment {
    /// Each record belongs to the degree of freedom of its strongest force channel
    /// ([`Record::dominant_force`]).
    #[default]
    DominantForce,
    /// Record `r` belongs to excitation `assignment[r]`.
    Explicit(Vec<usize>),
}

impl Assignment {
    /// The excitation index of every record.
    ///
    /// # Errors
    /// [`Error::AssignmentLength`] or [`Error::InvalidAssignment`] for an explicit assignment
    /// that does not fit the records.
    pub fn resolve(&self, records: &[Record], dofs: usize) -> Result<Vec<usize>> {
        let labels: Vec<&str> = records.iter().map(Record::label).collect();
        let dominant: Vec<usize> = records.iter().map(Record::dominant_force).collect();
        self.resolve_with(&labels, &dominant, dofs)
    }

    pub(super) fn resolve_with(
        &self,
        labels: &[&str],
        dominant: &[usize],
        dofs: usize,
    ) -> Result<Vec<usize>> {
        match self {
            Assignment::DominantForce => Ok(dominant.to_vec()),
            Assignment::Explicit(a) => {
                if a.len() != labels.len() {
                    return Err(Error::AssignmentLength {
                        expected: labels.len(),
                        actual: a.len(),
                    });
                }
                if let Some((r, &excitation)) = a.iter().enumerate().find(|(_, e)| **e >= dofs) {
                    return Err(Error::InvalidAssignment {
                        record: labels[r].to_owned(),
                        excitation,
                        dofs,
                    });
                }
                Ok(a.clone())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frf::tests::static_records;

    #[test]
    fn explicit_assignment_is_checked() {
        let recs = static_records([[1.0, 0.0], [0.0, 1.0]]);
        assert!(matches!(
            Assignment::Explicit(vec![0]).resolve(&recs, 2),
            Err(Error::AssignmentLength {
                expected: 2,
                actual: 1
            })
        ));
        assert!(matches!(
            Assignment::Explicit(vec![0, 2]).resolve(&recs, 2),
            Err(Error::InvalidAssignment { excitation: 2, .. })
        ));
        assert_eq!(
            Assignment::DominantForce.resolve(&recs, 2).unwrap(),
            vec![0, 1]
        );
    }
}
