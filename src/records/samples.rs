//! A channel's samples, owned by the record or shared with an owner the record keeps alive.

use std::fmt;
use std::ops::Range;
use std::sync::Arc;

/// Samples a record shares with their owner instead of copying them: a numpy array's row
/// held by the Python package, a memory-mapped file, another record's channel. The record
/// keeps the owner alive (one reference count) and reads the samples through
/// [`AsRef::as_ref`], which must return the same samples every time.
///
/// # Examples
/// ```
/// use std::sync::Arc;
/// use bearing_ident::records::SharedSamples;
/// let owner: SharedSamples = Arc::new(vec![1.0, 2.0, 3.0]);
/// let again = Arc::clone(&owner); // a reference more, no samples copied
/// assert_eq!((*again).as_ref()[2], 3.0);
/// assert_eq!(Arc::strong_count(&owner), 2);
/// ```
pub type SharedSamples = Arc<dyn AsRef<[f64]> + Send + Sync>;

/// One channel: `range` of the samples of `owner`. A record built from owned vectors wraps
/// each in an `Arc` (no samples copied); a cut record ([`Record::trimmed`]) narrows the range;
/// a cloned record adds a reference count. Samples are never written once in a record, so
/// sharing needs no copy on write.
///
/// [`Record::trimmed`]: super::Record::trimmed
#[derive(Clone)]
pub(crate) struct Samples {
    owner: SharedSamples,
    range: Range<usize>,
}

impl Samples {
    /// All samples of `owner`.
    pub(crate) fn shared(owner: SharedSamples) -> Self {
        let len = (*owner).as_ref().len();
        Self {
            owner,
            range: 0..len,
        }
    }

    /// The samples.
    pub(crate) fn as_slice(&self) -> &[f64] {
        &(*self.owner).as_ref()[self.range.clone()]
    }

    /// Samples `range` of these (relative to their first), sharing the owner.
    ///
    /// # Panics
    /// If `range` ends beyond these samples or is reversed.
    pub(crate) fn cut(&self, range: Range<usize>) -> Self {
        assert!(range.start <= range.end && range.end <= self.range.len());
        let start = self.range.start;
        Self {
            owner: Arc::clone(&self.owner),
            range: start + range.start..start + range.end,
        }
    }
}

impl From<Vec<f64>> for Samples {
    fn from(samples: Vec<f64>) -> Self {
        Self::shared(Arc::new(samples))
    }
}

impl fmt::Debug for Samples {
    /// As the samples' slice: a record prints as it did when it owned `Vec<f64>` channels.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.as_slice().fmt(f)
    }
}

impl PartialEq for Samples {
    /// The same samples, whoever owns them.
    fn eq(&self, other: &Self) -> bool {
        self.as_slice() == other.as_slice()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cut_shares_the_owner_and_reads_its_range() {
        let s = Samples::from((0..10).map(f64::from).collect::<Vec<_>>());
        let cut = s.cut(2..7).cut(1..3);
        assert_eq!(cut.as_slice(), &[3.0, 4.0]);
        assert_eq!(cut.as_slice().as_ptr(), s.as_slice()[3..].as_ptr());
        assert_eq!(Arc::strong_count(&s.owner), 2);
        assert_eq!(format!("{cut:?}"), "[3.0, 4.0]");
        assert_eq!(cut, Samples::from(vec![3.0, 4.0]));
    }
}
