//! What the screening keeps of a record ([`Summary`]: RMS per channel, hash, dominant force)
//! and the flat-channel test.

use std::hash::{DefaultHasher, Hash, Hasher};

use crate::error::Channel;
use crate::quality::Scan;
use crate::records::{Record, Response};

use super::{DOMINANCE, FLAT_TOLERANCE};
use crate::tolerance::NEAR_DUPLICATE;

/// Samples per channel in a record's fingerprint ([`Summary::copies`]), at even spacing from
/// the first to the last.
const FINGERPRINT_SAMPLES: usize = 16;

/// What the screening keeps of one record: RMS per channel (mean removed), a hash of its
/// samples, its dominant force.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    pub(super) label: String,
    pub(super) dominant: usize,
    pub(super) force_rms: Vec<f64>,
    pub(super) displacement_rms: Vec<f64>,
    /// What each response channel measures: levels are compared only between records whose
    /// channel measures the same quantity (m, m/s and m/s² differ by orders of magnitude).
    pub(super) responses: Vec<Response>,
    pub(super) hash: u64,
    /// Number of samples, and per channel (forces, then displacements) its peak `max |x|`
    /// and [`FINGERPRINT_SAMPLES`] samples at even spacing with its extremes, mean and RMS:
    /// what tells a copy rounded to a few digits from an independent record
    /// ([`Summary::copies`]).
    pub(super) len: usize,
    pub(super) peaks: Vec<f64>,
    pub(super) fingerprint: Vec<f64>,
    /// Channels reported flat on arrival.
    pub(super) flat: Vec<Channel>,
}

impl Summary {
    /// The summary of `record`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Record;
    /// use bearing_ident::screening::Summary;
    /// let f: Vec<f64> = (0..16).map(|m| if m % 2 == 0 { 3.0 } else { -1.0 }).collect();
    /// let r = Record::new("a", 1.0, vec![f.clone()], vec![f])?;
    /// assert!((Summary::new(&r).rms(bearing_ident::Channel::Force(0)) - 2.0).abs() < 1e-12);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn new(record: &Record) -> Self {
        let scans = Scan::channels(record);
        Self::scanned(record, record.dominant_force(), &scans)
    }

    /// The summary from the record's dominant force and the [`Scan`]s of its channels (forces,
    /// then displacements, their RMS included), done once and shared with the record checks.
    pub(super) fn scanned(record: &Record, dominant: usize, scans: &[Scan]) -> Self {
        let n = record.dofs();
        let mut hasher = DefaultHasher::new();
        record.len().hash(&mut hasher);
        for c in 0..n {
            scans[c].digest.hash(&mut hasher);
            scans[n + c].digest.hash(&mut hasher);
        }
        let len = record.len();
        let channels = (0..n)
            .map(|c| record.force(c))
            .chain((0..n).map(|c| record.displacement(c)));
        let mut fingerprint = Vec::with_capacity(2 * n * (FINGERPRINT_SAMPLES + 4));
        for (x, scan) in channels.zip(scans) {
            let at = |k: usize| x[k * (len - 1) / (FINGERPRINT_SAMPLES - 1)];
            fingerprint.extend((0..FINGERPRINT_SAMPLES).filter(|_| len > 0).map(at));
            fingerprint.extend([scan.lo, scan.hi, scan.mean, scan.rms]);
        }
        Self {
            len,
            peaks: scans.iter().map(|s| s.lo.abs().max(s.hi.abs())).collect(),
            fingerprint,
            label: record.label().to_owned(),
            dominant,
            force_rms: scans[..n].iter().map(|s| s.rms).collect(),
            displacement_rms: scans[n..].iter().map(|s| s.rms).collect(),
            responses: record.responses().to_vec(),
            hash: hasher.finish(),
            flat: Vec::new(),
        }
    }

    /// Whether `self` is a copy of `earlier` up to rounding: the same length and every value
    /// of the fingerprint within [`NEAR_DUPLICATE`] of its channel's peak in `earlier`, some
    /// channel not zero. Rounding every sample to 8 significant digits moves each value by
    /// at most `5·10⁻⁹` of its channel's peak; records of a test with their own noise differ
    /// by the noise (10⁻⁴ of the peak and more) in every sample.
    pub(super) fn copies(&self, earlier: &Summary) -> bool {
        let per = FINGERPRINT_SAMPLES + 4;
        self.len == earlier.len
            && self.fingerprint.len() == earlier.fingerprint.len()
            && earlier.peaks.iter().any(|&p| p > 0.0)
            && self
                .fingerprint
                .chunks(per)
                .zip(earlier.fingerprint.chunks(per))
                .zip(&earlier.peaks)
                .all(|((a, b), &peak)| {
                    a.iter()
                        .zip(b)
                        .all(|(x, y)| (x - y).abs() <= NEAR_DUPLICATE * peak)
                })
    }

    /// The sum of the channels' peaks. A copy's ([`Summary::copies`]) differs from the
    /// earlier record's by at most [`NEAR_DUPLICATE`] of it (each channel's extremes, hence
    /// its peak, move by at most that much of the channel's peak): copies need only be looked
    /// for among records of about the same sum.
    pub(super) fn peak_sum(&self) -> f64 {
        self.peaks.iter().sum()
    }

    /// How the record was excited: the dominant force channel when its RMS is at least
    /// [`DOMINANCE`] times every other force channel's (one direction at a time: impacts, a
    /// shaker per direction), else `n` (all inputs alike: multi-input random).
    pub(super) fn pattern(&self) -> usize {
        let d = self.dominant;
        let top = self.force_rms[d];
        let alone = self
            .force_rms
            .iter()
            .enumerate()
            .all(|(c, &v)| c == d || top >= DOMINANCE * v);
        if alone { d } else { self.force_rms.len() }
    }

    /// The record's label.
    pub fn label(&self) -> &str {
        &self.label
    }

    /// What a response channel measures; `None` for a force channel.
    pub(super) fn kind(&self, channel: Channel) -> Option<Response> {
        match channel {
            Channel::Force(_) => None,
            Channel::Displacement(c) => Some(self.responses[c]),
        }
    }

    /// The RMS of a channel about its mean (N; m, m/s or m/s² for a response).
    ///
    /// # Panics
    /// If the channel is not one of the record's.
    pub fn rms(&self, channel: Channel) -> f64 {
        match channel {
            Channel::Force(c) => self.force_rms[c],
            Channel::Displacement(c) => self.displacement_rms[c],
        }
    }

    pub(super) fn channels(&self) -> impl Iterator<Item = Channel> + use<> {
        let n = self.force_rms.len();
        (0..n)
            .map(Channel::Force)
            .chain((0..n).map(Channel::Displacement))
    }
}

/// The value of a flat channel (from its [`Scan`]), `None` if it varies.
pub(super) fn flat(scan: &Scan) -> Option<f64> {
    let (lo, hi) = (scan.lo, scan.hi);
    (hi - lo <= FLAT_TOLERANCE * hi.abs().max(lo.abs())).then_some(0.5 * (lo + hi))
}
