//! Buffers kept per thread from one record to the next ([`with_kept`]): the excitation's
//! detection transforms one force of every run, and buffers allocated afresh each time are
//! handed back to the system by the allocator and faulted in again, page by page, for the
//! next record.

use std::cell::RefCell;
use std::thread::LocalKey;

/// Longest record whose buffers [`with_kept`] keeps for the next (131 072 samples: at most
/// about 12 MB per thread over the detection's two sets of buffers); a longer record's are
/// given back after use.
pub(crate) const KEPT_SAMPLES: usize = 1 << 17;

/// `work` on this thread's buffers in `key`, for a record of `samples` samples; the buffers
/// are given back to the allocator afterwards when the record is longer than
/// [`KEPT_SAMPLES`].
///
/// # Panics
/// If `work` reaches `key` again (its buffers are borrowed for the call).
pub(crate) fn with_kept<B: Default + 'static, R>(
    key: &'static LocalKey<RefCell<B>>,
    samples: usize,
    work: impl FnOnce(&mut B) -> R,
) -> R {
    key.with(|buffers| {
        let mut buffers = buffers.borrow_mut();
        let out = work(&mut buffers);
        if samples > KEPT_SAMPLES {
            *buffers = B::default();
        }
        out
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    thread_local! {
        static TEST: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
    }

    /// A short record's buffer is kept with its capacity; a long one's is given back.
    #[test]
    fn short_records_keep_their_buffers_long_ones_give_them_back() {
        let fill = |v: &mut Vec<f64>, n: usize| {
            v.clear();
            v.resize(n, 1.0);
            v.len()
        };
        assert_eq!(with_kept(&TEST, 1000, |v| fill(v, 1000)), 1000);
        assert!(TEST.with(|v| v.borrow().capacity()) >= 1000);
        let long = KEPT_SAMPLES + 1;
        assert_eq!(with_kept(&TEST, long, |v| fill(v, long)), long);
        assert_eq!(TEST.with(|v| v.borrow().capacity()), 0);
    }
}
