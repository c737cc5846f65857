//! Stage 1: validated time records of forces and responses.
//!
//! A [`Record`] is one test: `n` force channels (N) and `n` response channels, sampled
//! together at one rate, one channel per degree of freedom. A response channel holds
//! displacement (m, the default), velocity (m/s) or acceleration (m/s²), its [`Response`];
//! the [`frf`](crate::frf) stage turns every response into displacement at its band lines.
//! Validation happens once, when the record is built: every later stage may assume equal
//! lengths and finite samples.
//!
//! What lives where: [`Record`] is here; a channel's samples, owned or shared with their
//! owner, in `records/samples.rs`; what the records of a test share and the crate-wide checks
//! of numbers in `records/shape.rs`, the probe geometry in `records/probes.rs`, what a
//! response channel measures in `records/response.rs`.

use std::ops::Range;

use crate::error::{Channel, Error, Result, Warning};
use crate::lanes;

mod probes;
mod response;
mod samples;
mod shape;
pub use probes::{conical_to_bearing, two_plane_to_bearing};
pub use response::Response;
pub(crate) use samples::Samples;
pub use samples::SharedSamples;
pub use shape::{Shape, common_shape, sample_rates_agree};
pub(crate) use shape::{check_against, finite_positive, require_finite_positive};

/// Smallest number of samples a record may have.
pub const MIN_SAMPLES: usize = 8;

pub use crate::tolerance::TIME_GRID_TOLERANCE;

/// One validated test record: forces and displacements for every degree of freedom.
///
/// Each channel's samples are either the record's own (the vectors [`Record::new`] takes, not
/// copied) or shared with an owner the record keeps alive ([`Record::from_shared`]: the Python
/// package's numpy arrays); a record never writes them, so cloning or cutting a record
/// ([`Record::trimmed`]) shares them too. The label names the record in every error and
/// warning (the CLI uses the file path).
///
/// # Examples
/// ```
/// use bearing_ident::records::Record;
/// let fx = vec![0.0, 1.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0];
/// let x = vec![0.0, 0.0, 1e-6, 2e-6, 1e-6, 0.0, 0.0, 0.0];
/// let r = Record::new("hit-x-1", 1000.0, vec![fx], vec![x])?;
/// assert_eq!(r.dofs(), 1);
/// assert_eq!(r.len(), 8);
/// assert!((r.duration() - 0.008).abs() < 1e-15);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    label: String,
    sample_rate: f64,
    forces: Vec<Samples>,
    displacements: Vec<Samples>,
    /// What each response channel measures.
    responses: Vec<Response>,
    /// The force channel with the largest energy about its mean ([`Record::dominant_force`]),
    /// found once when the record is built.
    dominant: usize,
    /// What its reader noticed and did not refuse ([`Record::warnings`]).
    warnings: Vec<Warning>,
}

impl Record {
    /// Builds a record from force and displacement channels sampled at `sample_rate` Hz.
    ///
    /// # Errors
    /// - [`Error::InvalidSampleRate`] unless `sample_rate` is finite and positive;
    /// - [`Error::ChannelCount`] unless there are `n ≥ 1` force and `n` displacement channels;
    /// - [`Error::ChannelLength`] if a channel's length differs from the first force channel's;
    /// - [`Error::RecordTooShort`] below [`MIN_SAMPLES`] samples;
    /// - [`Error::NonFinite`] for the first NaN or infinite sample, naming channel and index.
    pub fn new(
        label: impl Into<String>,
        sample_rate: f64,
        forces: Vec<Vec<f64>>,
        displacements: Vec<Vec<f64>>,
    ) -> Result<Self> {
        let own = |c: Vec<Vec<f64>>| c.into_iter().map(Samples::from).collect();
        Self::checked(
            label.into(),
            sample_rate,
            own(forces),
            own(displacements),
            true,
        )
    }

    /// Builds a record whose channels share their samples with their owners instead of
    /// copying them: each owner is kept alive by the record (and its clones) and read in
    /// place. The checks are [`Record::new`]'s, on the owners' samples.
    ///
    /// # Errors
    /// As [`Record::new`].
    ///
    /// # Examples
    /// ```
    /// use std::sync::Arc;
    /// use bearing_ident::records::{Record, SharedSamples};
    /// let fx: SharedSamples = Arc::new(vec![0.0, 1.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0]);
    /// let x: SharedSamples = Arc::new(vec![0.0, 0.0, 1e-6, 2e-6, 1e-6, 0.0, 0.0, 0.0]);
    /// let r = Record::from_shared("hit", 1000.0, vec![fx.clone()], vec![x])?;
    /// assert_eq!(r.force(0)[1], 1.0);
    /// assert_eq!(r.force(0).as_ptr(), (*fx).as_ref().as_ptr()); // read in place
    /// assert_eq!(r.dominant_force(), 0);
    /// let mut bad = vec![0.0; 8];
    /// bad[3] = f64::NAN;
    /// let e = Record::from_shared("hit", 1000.0, vec![fx], vec![Arc::new(bad)]).unwrap_err();
    /// assert_eq!(e.to_string(), "record `hit`: displacement channel 0, sample 3: value NaN is not finite");
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn from_shared(
        label: impl Into<String>,
        sample_rate: f64,
        forces: Vec<SharedSamples>,
        displacements: Vec<SharedSamples>,
    ) -> Result<Self> {
        let share = |c: Vec<SharedSamples>| c.into_iter().map(Samples::shared).collect();
        Self::checked(
            label.into(),
            sample_rate,
            share(forces),
            share(displacements),
            true,
        )
    }

    /// A record of channels some of which another record shares (their samples not copied),
    /// with `responses`: [`Record::new`]'s checks, for the crate's own records built from
    /// records (the geometry of feature `job`).
    #[cfg(feature = "job")]
    pub(crate) fn from_samples(
        label: impl Into<String>,
        sample_rate: f64,
        forces: Vec<Samples>,
        displacements: Vec<Samples>,
        responses: Vec<Response>,
    ) -> Result<Self> {
        Self::checked(label.into(), sample_rate, forces, displacements, true)?
            .with_responses(responses)
    }

    /// [`Record::new`], the samples' finiteness checked when `check_finite` (else checked
    /// already by the caller).
    fn checked(
        label: String,
        sample_rate: f64,
        forces: Vec<Samples>,
        displacements: Vec<Samples>,
        check_finite: bool,
    ) -> Result<Self> {
        if !finite_positive(sample_rate) {
            return Err(Error::InvalidSampleRate {
                record: label,
                sample_rate,
            });
        }
        if forces.is_empty() || forces.len() != displacements.len() {
            return Err(Error::ChannelCount {
                record: label,
                forces: forces.len(),
                displacements: displacements.len(),
            });
        }
        let expected = forces[0].as_slice().len();
        let channels = forces
            .iter()
            .enumerate()
            .map(|(i, c)| (Channel::Force(i), c))
            .chain(
                displacements
                    .iter()
                    .enumerate()
                    .map(|(i, c)| (Channel::Displacement(i), c)),
            );
        for (channel, samples) in channels {
            let samples = samples.as_slice();
            if samples.len() != expected {
                return Err(Error::ChannelLength {
                    record: label,
                    channel,
                    expected,
                    actual: samples.len(),
                });
            }
            if check_finite && !lanes::all_finite(samples) {
                return Err(non_finite(&label, channel, samples, 0));
            }
        }
        if expected < MIN_SAMPLES {
            return Err(Error::RecordTooShort {
                record: label,
                samples: expected,
                minimum: MIN_SAMPLES,
            });
        }
        let responses = vec![Response::Displacement; forces.len()];
        let dominant = dominant(&forces);
        Ok(Self {
            label,
            sample_rate,
            forces,
            displacements,
            responses,
            dominant,
            warnings: Vec::new(),
        })
    }

    /// The same record with response channel `i` measuring `responses[i]` (velocity or
    /// acceleration records; [`Record::new`] makes every channel a displacement).
    ///
    /// # Errors
    /// [`Error::ResponseCount`] unless there is one kind per degree of freedom (see
    /// [`Response::per_channel`] for one kind for all).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::records::{Record, Response};
    /// let r = Record::new("a", 100.0, vec![vec![0.0; 8]; 2], vec![vec![0.0; 8]; 2])?
    ///     .with_responses(vec![Response::Acceleration, Response::Displacement])?;
    /// assert_eq!(r.response(0), Response::Acceleration);
    /// assert_eq!(r.responses(), &[Response::Acceleration, Response::Displacement]);
    /// assert!(r.clone().with_responses(vec![Response::Velocity]).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn with_responses(mut self, responses: Vec<Response>) -> Result<Self> {
        if responses.len() != self.dofs() {
            return Err(Error::ResponseCount {
                record: self.label,
                expected: self.forces.len(),
                actual: responses.len(),
            });
        }
        self.responses = responses;
        Ok(self)
    }

    /// The same record carrying `warnings`, in place of any it carried: what its reader
    /// noticed and did not refuse (a unit it does not convert, [`Warning::UnknownUnit`]). A
    /// [`Job`] reports them with its result's warnings.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Record, Warning};
    /// let w = Warning::UnknownUnit {
    ///     record: "run3.tdms".into(),
    ///     channel: "fx".into(),
    ///     unit: "kgf".into(),
    ///     force: true,
    /// };
    /// let r = Record::new("run3.tdms", 100.0, vec![vec![1.0; 16]], vec![vec![0.5; 16]])?
    ///     .with_warnings(vec![w]);
    /// assert_eq!(r.warnings()[0].kind(), "unknown_unit");
    /// assert_eq!(r.trimmed(2..16)?.warnings().len(), 1);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    ///
    #[cfg_attr(feature = "job", doc = "[`Job`]: crate::job::Job")]
    #[cfg_attr(not(feature = "job"), doc = "[`Job`]: crate#feature-flags")]
    #[must_use]
    pub fn with_warnings(mut self, warnings: Vec<Warning>) -> Self {
        self.warnings = warnings;
        self
    }

    /// What the record's reader noticed and did not refuse ([`Record::with_warnings`]);
    /// empty for a record built in memory.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// What response channel `i` measures.
    ///
    /// # Panics
    /// If `i >= self.dofs()`.
    pub fn response(&self, i: usize) -> Response {
        self.responses[i]
    }

    /// What every response channel measures, one per degree of freedom.
    pub fn responses(&self) -> &[Response] {
        &self.responses
    }

    /// Whether every response channel is a displacement.
    pub fn is_displacement(&self) -> bool {
        self.responses.iter().all(|&r| r == Response::Displacement)
    }

    /// The record's label, as used in errors and warnings.
    pub fn label(&self) -> &str {
        &self.label
    }

    /// Sampling rate (Hz).
    pub fn sample_rate(&self) -> f64 {
        self.sample_rate
    }

    /// Number of samples per channel.
    pub fn len(&self) -> usize {
        self.forces[0].as_slice().len()
    }

    /// Always `false`: a record holds at least [`MIN_SAMPLES`] samples.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Number of degrees of freedom `n` (force channels = displacement channels = `n`).
    pub fn dofs(&self) -> usize {
        self.forces.len()
    }

    /// Record length in seconds, `len / sample_rate`.
    pub fn duration(&self) -> f64 {
        self.len() as f64 / self.sample_rate
    }

    /// Force channel `i` (N).
    ///
    /// # Panics
    /// If `i >= self.dofs()`.
    pub fn force(&self, i: usize) -> &[f64] {
        self.forces[i].as_slice()
    }

    /// Force channel `i`'s samples, to share with another record.
    ///
    /// # Panics
    /// If `i >= self.dofs()`.
    #[cfg(feature = "job")]
    pub(crate) fn force_samples(&self, i: usize) -> Samples {
        self.forces[i].clone()
    }

    /// Response channel `i`: displacement (m) unless [`Record::response`] says it measures
    /// velocity (m/s) or acceleration (m/s²).
    ///
    /// # Panics
    /// If `i >= self.dofs()`.
    pub fn displacement(&self, i: usize) -> &[f64] {
        self.displacements[i].as_slice()
    }

    /// The samples `range` of every channel as a new record with the same label and rate
    /// (sharing this record's samples, none copied): to
    /// discard the transient before a periodic or sine response reaches its steady state, or to
    /// cut a record to a whole number of periods.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if the range is reversed or ends beyond the record;
    /// [`Error::RecordTooShort`] if it holds fewer than [`MIN_SAMPLES`] samples.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::records::Record;
    /// let ramp: Vec<f64> = (0..100).map(f64::from).collect();
    /// let r = Record::new("run-up", 100.0, vec![ramp.clone()], vec![ramp])?;
    /// let steady = r.trimmed(40..100)?;
    /// assert_eq!(steady.len(), 60);
    /// assert!((steady.force(0)[0] - 40.0).abs() < 1e-12);
    /// assert_eq!(steady.label(), "run-up");
    /// assert!(r.trimmed(40..101).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn trimmed(&self, range: Range<usize>) -> Result<Record> {
        if range.end > self.len() || range.start > range.end {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::TrimRangeEnd,
                value: range.end as f64,
                expected: "start ≤ end ≤ record length",
            });
        }
        let cut = |channels: &[Samples]| channels.iter().map(|c| c.cut(range.clone())).collect();
        // The samples were checked when this record was built.
        Self::checked(
            self.label.clone(),
            self.sample_rate,
            cut(&self.forces),
            cut(&self.displacements),
            false,
        )?
        .with_responses(self.responses.clone())
        .map(|r| r.with_warnings(self.warnings.clone()))
    }

    /// The force channel with the largest energy about its mean: the direction this record
    /// excites, for pairing impacts into sets.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::records::Record;
    /// let quiet = vec![0.0; 8];
    /// let mut hit = vec![0.0; 8];
    /// hit[2] = 50.0;
    /// let r = Record::new("hit-y", 1000.0, vec![quiet, hit], vec![vec![0.0; 8], vec![0.0; 8]])?;
    /// assert_eq!(r.dominant_force(), 1);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn dominant_force(&self) -> usize {
        self.dominant
    }
}

/// The force channel with the largest energy about its mean, `Σ (f − f̄)²` (the first of equals).
/// The forces are scaled by a power of two at or above the largest `|f|` of the record, so that
/// forces near `f64::MAX` compare rather than all overflow to infinity; a power of two scales
/// exactly, so the order is that of the unscaled energies.
fn dominant(forces: &[Samples]) -> usize {
    let peak = (forces.iter())
        .map(|c| lanes::max_abs(c.as_slice()))
        .fold(0.0, f64::max);
    // 2^e ≥ peak (up to the rounding of log2, which only halves or doubles the scale), e kept
    // where 2^-e is a normal number.
    let e = if peak > 0.0 {
        (peak.log2().floor() as i32 + 1).clamp(-1022, 1022)
    } else {
        0
    };
    let scale = f64::from_bits(((1023 - e) as u64) << 52);
    let mut best = (0, f64::NEG_INFINITY);
    for (i, c) in forces.iter().map(Samples::as_slice).enumerate() {
        let mean = lanes::sum_scaled(c, scale) / c.len() as f64;
        let energy = lanes::sum_sq_dev_scaled(c, scale, mean);
        if energy > best.1 {
            best = (i, energy);
        }
    }
    best.0
}

/// [`Error::NonFinite`] for the first sample of `samples` (which holds one) that is not
/// finite, `samples` starting at sample `offset` of `channel` of record `record`.
fn non_finite(record: &str, channel: Channel, samples: &[f64], offset: usize) -> Error {
    let (k, &value) = samples
        .iter()
        .enumerate()
        .find(|(_, v)| !v.is_finite())
        .expect("a sample is not finite");
    Error::NonFinite {
        record: record.to_owned(),
        channel,
        sample: offset + k,
        value,
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are copied through, not computed
mod tests {
    use super::*;

    #[test]
    fn plane_transforms_refuse_bad_geometry_with_errors() {
        let e = two_plane_to_bearing(&[1.0, 2.0], &[3.0], 0.0, 0.2, 0.1).unwrap_err();
        assert_eq!(
            e,
            Error::LengthMismatch {
                what: "sensor channels x1 and x2",
                expected: 2,
                actual: 1
            }
        );
        for (z1, z2, zb) in [
            (0.2, 0.2, 0.1),
            (f64::NAN, 0.2, 0.1),
            (0.0, 0.2, f64::INFINITY),
        ] {
            let e = two_plane_to_bearing(&[1.0], &[3.0], z1, z2, zb).unwrap_err();
            assert_eq!(e.kind(), "invalid_argument", "{z1} {z2} {zb}");
        }
        assert!(two_plane_to_bearing(&[f64::NAN], &[3.0], 0.0, 0.2, 0.1).is_err());
        // Planes 1e-310 apart: the ratio overflows.
        assert!(two_plane_to_bearing(&[1.0], &[3.0], 0.0, 1e-310, 0.1).is_err());
        for (zs, zp, zb) in [(0.3, 0.3, 0.1), (f64::NAN, 0.0, 0.1), (0.3, 0.0, f64::NAN)] {
            assert!(
                conical_to_bearing(&[1.0], zs, zp, zb).is_err(),
                "{zs} {zp} {zb}"
            );
        }
        assert!(conical_to_bearing(&[1e308], 1e-300, 0.0, 1.0).is_err());
    }

    fn ok_channel() -> Vec<f64> {
        vec![0.0; 16]
    }

    #[test]
    fn valid_record_reports_its_shape() {
        let r = Record::new("a", 100.0, vec![ok_channel(); 2], vec![ok_channel(); 2]).unwrap();
        assert_eq!((r.dofs(), r.len(), r.label()), (2, 16, "a"));
        assert_eq!(r.sample_rate(), 100.0);
        assert!(!r.is_empty());
    }

    #[test]
    fn rejects_bad_sample_rate() {
        for fs in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = Record::new("a", fs, vec![ok_channel()], vec![ok_channel()]).unwrap_err();
            assert!(matches!(e, Error::InvalidSampleRate { .. }), "{fs}");
        }
    }

    #[test]
    fn rejects_channel_count_mismatch() {
        let e = Record::new("a", 1.0, vec![ok_channel(); 2], vec![ok_channel()]).unwrap_err();
        assert_eq!(
            e,
            Error::ChannelCount {
                record: "a".into(),
                forces: 2,
                displacements: 1
            }
        );
        let e = Record::new("a", 1.0, vec![], vec![]).unwrap_err();
        assert!(matches!(e, Error::ChannelCount { forces: 0, .. }));
    }

    #[test]
    fn rejects_ragged_channels_naming_the_channel() {
        let e = Record::new("a", 1.0, vec![ok_channel()], vec![vec![0.0; 15]]).unwrap_err();
        assert_eq!(
            e,
            Error::ChannelLength {
                record: "a".into(),
                channel: Channel::Displacement(0),
                expected: 16,
                actual: 15
            }
        );
    }

    #[test]
    fn rejects_short_records() {
        let e = Record::new("a", 1.0, vec![vec![0.0; 4]], vec![vec![0.0; 4]]).unwrap_err();
        assert!(matches!(e, Error::RecordTooShort { samples: 4, .. }));
    }

    #[test]
    fn rejects_non_finite_naming_channel_and_sample() {
        let mut x = ok_channel();
        x[7] = f64::NAN;
        let e = Record::new(
            "r3",
            1.0,
            vec![ok_channel(), ok_channel()],
            vec![ok_channel(), x],
        )
        .unwrap_err();
        match e {
            Error::NonFinite {
                record,
                channel,
                sample,
                ..
            } => {
                assert_eq!(record, "r3");
                assert_eq!(channel, Channel::Displacement(1));
                assert_eq!(sample, 7);
            }
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn trimmed_keeps_label_and_refuses_bad_ranges() {
        let ramp: Vec<f64> = (0..16).map(f64::from).collect();
        let r = Record::new("a", 10.0, vec![ramp.clone()], vec![ramp]).unwrap();
        let t = r.trimmed(4..16).unwrap();
        assert_eq!((t.len(), t.label(), t.sample_rate()), (12, "a", 10.0));
        assert_eq!(t.displacement(0)[0], 4.0);
        assert!(matches!(
            r.trimmed(4..17),
            Err(Error::InvalidParameter { .. })
        ));
        #[allow(clippy::reversed_empty_ranges)]
        let reversed = 9..4;
        assert!(matches!(
            r.trimmed(reversed),
            Err(Error::InvalidParameter { .. })
        ));
        assert!(matches!(
            r.trimmed(10..16),
            Err(Error::RecordTooShort { samples: 6, .. })
        ));
    }

    #[test]
    fn dominant_force_compares_forces_near_the_largest_float() {
        let big =
            |a: f64| -> Vec<f64> { (0..16).map(|m| if m % 2 == 0 { a } else { -a }).collect() };
        for (a, b, expected) in [
            (1e308, 1.5e308, 1),
            (1.7e308, 1.5e308, 0),
            (3e-320, 5e-320, 1),
        ] {
            let r = Record::new("a", 1.0, vec![big(a), big(b)], vec![ok_channel(); 2]).unwrap();
            assert_eq!(r.dominant_force(), expected, "{a} vs {b}");
        }
    }

    #[test]
    fn dominant_force_ignores_offsets() {
        let offset = vec![100.0; 16];
        let mut hit = ok_channel();
        hit[3] = 1.0;
        let r = Record::new("a", 1.0, vec![offset, hit], vec![ok_channel(); 2]).unwrap();
        assert_eq!(r.dominant_force(), 1);
    }
}

/// Records that share their samples with an owner: one buffer of rows, as a C-ordered
/// numpy array holds a record's channels.
#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are read through, not computed
mod shared_tests {
    use std::sync::Arc;

    use super::*;
    use crate::simulate::{ImpactTest, seed_rig};

    /// Row `row` of a buffer of rows `len` long.
    struct Row {
        buffer: Arc<Vec<f64>>,
        row: usize,
        len: usize,
    }

    impl AsRef<[f64]> for Row {
        fn as_ref(&self) -> &[f64] {
            &self.buffer[self.row * self.len..(self.row + 1) * self.len]
        }
    }

    /// `channels` laid out as rows of one buffer, each shared as a row of it.
    fn rows_of(channels: &[&[f64]]) -> (Arc<Vec<f64>>, Vec<SharedSamples>) {
        let len = channels[0].len();
        let buffer = Arc::new(channels.concat());
        let rows = (0..channels.len())
            .map(|row| {
                let row = Row {
                    buffer: Arc::clone(&buffer),
                    row,
                    len,
                };
                Arc::new(row) as SharedSamples
            })
            .collect();
        (buffer, rows)
    }

    /// `r` rebuilt on shared rows of two buffers (forces, responses), and those buffers.
    fn shared(r: &Record) -> (Record, Arc<Vec<f64>>, Arc<Vec<f64>>) {
        let n = r.dofs();
        let f: Vec<&[f64]> = (0..n).map(|i| r.force(i)).collect();
        let x: Vec<&[f64]> = (0..n).map(|i| r.displacement(i)).collect();
        let ((fb, f), (xb, x)) = (rows_of(&f), rows_of(&x));
        let record = Record::from_shared(r.label(), r.sample_rate(), f, x).unwrap();
        (record, fb, xb)
    }

    #[test]
    fn shared_records_identify_as_owned_ones_and_read_in_place() {
        let test = ImpactTest {
            per_direction: 2,
            noise: 0.02,
            ..ImpactTest::seed_rig()
        };
        let owned = test.run(&seed_rig()).unwrap();
        let (shared, buffers): (Vec<_>, Vec<_>) = owned
            .iter()
            .map(|r| {
                let (s, fb, xb) = shared(r);
                (s, (fb, xb))
            })
            .unzip();
        // Read in place: the channels are the buffers' rows.
        let (s, (fb, xb)) = (&shared[1], &buffers[1]);
        assert_eq!(s.force(1).as_ptr(), fb[8040..].as_ptr());
        assert_eq!(s.displacement(0).as_ptr(), xb.as_ptr());
        assert_eq!(s, &owned[1]);
        assert_eq!(s.dominant_force(), owned[1].dominant_force());
        let identifier = crate::Identifier::new(8.0, 49.0);
        let a = identifier.identify(&owned).unwrap();
        let b = identifier.identify(&shared).unwrap();
        assert_eq!(a, b);
        let k = b.coefficients().stiffness();
        assert!((k[(0, 0)] / seed_rig().stiffness()[(0, 0)] - 1.0).abs() < 0.05);
    }

    #[test]
    fn a_non_finite_shared_sample_is_refused_naming_channel_and_sample() {
        let good: Vec<f64> = (0..64).map(|m| f64::from(m).sin()).collect();
        let mut bad = good.clone();
        bad[37] = f64::NAN;
        let (_, f) = rows_of(&[&good, &good]);
        let (_, x) = rows_of(&[&good, &bad]);
        let e = Record::from_shared("r", 100.0, f, x).unwrap_err();
        assert!(
            matches!(
                e,
                Error::NonFinite {
                    ref record,
                    channel: Channel::Displacement(1),
                    sample: 37,
                    ..
                } if record == "r"
            ),
            "{e:?}"
        );
        // And every shape fault as `new` names it.
        let (_, one) = rows_of(&[&good]);
        let (_, two) = rows_of(&[&good, &good]);
        let e = Record::from_shared("r", 100.0, one.clone(), two).unwrap_err();
        assert!(matches!(e, Error::ChannelCount { forces: 1, .. }), "{e:?}");
        let e = Record::from_shared("r", f64::NAN, one.clone(), one.clone()).unwrap_err();
        assert!(matches!(e, Error::InvalidSampleRate { .. }), "{e:?}");
        let (_, short) = rows_of(&[&good[..10]]);
        let e = Record::from_shared("r", 100.0, one, short).unwrap_err();
        assert!(
            matches!(e, Error::ChannelLength { actual: 10, .. }),
            "{e:?}"
        );
    }

    #[test]
    fn a_shared_record_is_send_and_sync_and_clones_and_cuts_without_copying() {
        fn send_sync<T: Send + Sync + Clone>() {}
        send_sync::<Record>();
        let ramp: Vec<f64> = (0..64).map(f64::from).collect();
        let (buffer, f) = rows_of(&[&ramp]);
        let (_, x) = rows_of(&[&ramp]);
        let r = Record::from_shared("r", 100.0, f, x).unwrap();
        let copy = r.clone();
        assert_eq!(copy.force(0).as_ptr(), buffer.as_ptr());
        let cut = copy.trimmed(16..48).unwrap();
        assert_eq!(cut.force(0).as_ptr(), buffer[16..].as_ptr());
        assert_eq!(cut.force(0)[0], 16.0);
        // The buffer lives as long as a record reads it: here, and two rows' owners.
        drop((r, copy));
        assert_eq!(Arc::strong_count(&buffer), 2);
        assert_eq!(cut.len(), 32);
    }
}
