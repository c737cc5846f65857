//! Selection of the element of a given rank among many integer keys ([`select`]): the
//! double-hit check's two medians of a channel.

/// Keys sampled to bracket the rank.
const SAMPLE: usize = 512;

/// Sample ranks on each side of the target's in the bracket: about 3.5 standard deviations of
/// a sample quantile's rank (`√(S/4)` ≈ 11 for 512), so a bracket misses about once in
/// 2000 channels, when the plain selection runs instead.
const MARGIN: usize = 40;

/// Below this many keys [`select`] is the plain selection.
const SAMPLED_MIN: usize = 8 * SAMPLE;

/// The key of rank `k` (ascending) of `keys`, reordering them; the same key as
/// `keys.select_nth_unstable(k)` gives. `inside` is scratch, kept by the caller from one
/// selection to the next (grown to the keys' count once, never cleared).
///
/// From a strided sample of the keys, two sample quantiles bracket the rank; one pass counts
/// the keys below the bracket and gathers those inside it (a sixth or so), and the selection
/// runs among those only. When the bracket misses the rank (unusual data, or a periodic
/// pattern that the stride aliases), the plain selection runs on all keys.
///
/// # Panics
/// If `k ≥ keys.len()`.
pub(crate) fn select(keys: &mut [u64], k: usize, inside: &mut Vec<u64>) -> u64 {
    let n = keys.len();
    if n < SAMPLED_MIN {
        return *keys.select_nth_unstable(k).1;
    }
    let stride = n / SAMPLE;
    let mut sample = [0u64; SAMPLE];
    for (s, v) in sample.iter_mut().zip(keys.iter().step_by(stride)) {
        *s = *v;
    }
    let centre = k * SAMPLE / n;
    let (lo_rank, hi_rank) = (
        centre.saturating_sub(MARGIN),
        (centre + MARGIN).min(SAMPLE - 1),
    );
    let (_, &mut lo, above) = sample.select_nth_unstable(lo_rank);
    let hi = *above.select_nth_unstable(hi_rank - lo_rank - 1).1;
    // Keys inside [lo, hi], gathered without branches (a write at every key, the end moved on
    // only for those inside); one spare slot for the last write. Every slot read is written
    // first: what the scratch held before does not matter.
    if inside.len() <= n {
        inside.resize(n + 1, 0);
    }
    let (mut len, mut below) = (0, 0);
    for &v in keys.iter() {
        inside[len] = v;
        len += usize::from(v >= lo && v <= hi);
        below += usize::from(v < lo);
    }
    if below <= k && k < below + len {
        return *inside[..len].select_nth_unstable(k - below).1;
    }
    *keys.select_nth_unstable(k).1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against sorting, at ranks across the range, on data whose bracket holds, on ties, and
    /// on a pattern the stride aliases (the fallback).
    #[test]
    fn selection_is_the_sorted_key() {
        let mut seed = 5u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            seed >> 20
        };
        let n = 9001;
        let sets: Vec<Vec<u64>> = vec![
            (0..n).map(|_| next()).collect(),
            (0..n).map(|_| next() % 7).collect(),
            // Period equal to the stride: the sample sees one value only.
            (0..n)
                .map(|m| if m % (n / SAMPLE) == 0 { 5 } else { next() })
                .collect(),
            (0..n as u64).collect(),
            (0..n as u64).rev().collect(),
        ];
        // One scratch for all, as the double-hit check keeps it: left over from larger sets.
        let mut inside = vec![u64::MAX; 2 * n];
        for (i, set) in sets.iter().enumerate() {
            let mut sorted = set.clone();
            sorted.sort_unstable();
            for k in (0..n).step_by(97).chain([0, n / 2, n - 1]) {
                assert_eq!(
                    select(&mut set.clone(), k, &mut inside),
                    sorted[k],
                    "set {i} rank {k}"
                );
            }
        }
    }
}
