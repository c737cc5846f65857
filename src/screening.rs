//! Record screening for every excitation kind: dead and flat channels, identical records,
//! clipping, level outliers, double hits (impacts), and paired sets whose impedance is far from
//! the others'.
//!
//! A real test spoils some records without making them invalid: a hammer hit that did not
//! register leaves a force channel at zero, a file is passed twice, an amplifier overloads, a
//! gain is set wrong, a cable is swapped. Each goes straight into the coefficients (a dead
//! force channel in one record of sixteen scales `M` and `K` by `7/8`). This stage finds
//! them, per record and channel, and reports each as a typed [`Warning`] that names the record
//! and the channel with the numbers.
//!
//! # What is checked
//! On each record alone, as it arrives ([`Screener::push`]):
//! - **flat channel** ([`Warning::FlatChannel`]): every sample within [`FLAT_TOLERANCE`] of
//!   the channel's largest magnitude of one value (all zero, or a constant). Displacement
//!   channels always; force channels when *every* force channel of the record is flat (no
//!   excitation at all). A single flat force channel next to live ones is the undriven
//!   direction of a one-shaker test as often as a fault, so it is judged against its siblings
//!   (below) instead;
//! - **clipping** ([`Warning::Clipped`], [`quality::check_record`]): a run of
//!   [`Checks::clip_run`] samples at a channel's extreme, away from its mean, on every
//!   excitation;
//! - **double hit** ([`Warning::DoubleHit`]), with [`Checks::impact`] set, on impulsive
//!   records only (crest factor ≥ [`ImpactChecks::min_crest_factor`]);
//! - **identical records** ([`Warning::DuplicateRecord`]): a 64-bit hash of the bits of every
//!   sample of every channel (not the label) equal to an earlier record's.
//!
//! Across records, once all have arrived ([`Screener::across`]), each record against its
//! **siblings**, the records excited the same way: a record whose dominant force
//! ([`Record::dominant_force`]) has at least [`DOMINANCE`] times the RMS of every other force
//! channel is excited in that one direction (impacts, a shaker per direction) and its siblings
//! are the records excited in the same direction; the others (multi-input random) are
//! siblings of one another. A record with fewer than [`MIN_SIBLINGS`] siblings (itself
//! included) is judged against all records, for dead channels only (levels legitimately differ
//! between directions); with fewer than [`MIN_SIBLINGS`] records in all nothing is judged (a
//! median of two says nothing). Per channel `c` with sibling median RMS `m_c > 0` (RMS of the
//! mean-removed samples):
//! - **dead channel** ([`Warning::DeadChannel`]): `rms < `[`Checks::dead_ratio`]` · m_c`;
//! - **level outlier** ([`Warning::LevelOutlier`]): with `ℓ = ln rms` over the live siblings,
//!   `|ℓ − median ℓ| > max(`[`Checks::level_sigmas`]` · σ̂, ln `[`Checks::level_factor`]`)`,
//!   `σ̂ = 1.4826 · MAD(ℓ)`. The factor floor keeps records that agree to a fraction of a
//!   percent (simulated multisines of one RMS) from flagging each other over nothing.
//!
//! Per band line, paired sets ([`outlier_sets`]): at each line and element the median of the
//! sets' impedances (real and imaginary parts apart) and the MAD of the distances to it; a set
//! is *far* at a line when some element is more than [`Checks::set_sigmas`]` · σ̂` and more
//! than [`Checks::set_floor`] of the line's median impedance (Frobenius norm) away. A set far
//! at more than [`Checks::set_fraction`] of the tested lines is reported
//! ([`Warning::OutlierSet`]). Needs at least 3 sets. Cross-spectral estimators (H1, H2, Hv)
//! pool every record's cross-spectra line by line: their records are screened per record and
//! across siblings, not per line.
//!
//! Only small per-record summaries are kept ([`Summary`]: RMS per channel, hash, dominant
//! force), never the records.
//!
//! # Examples
//! The issue's case: a hammer hit that did not register (both force channels zero) in one of
//! sixteen impact records.
//! ```
//! use bearing_ident::screening::{Checks, Screener};
//! use bearing_ident::simulate::{ImpactTest, seed_rig};
//! use bearing_ident::{Record, Warning};
//! let mut records = ImpactTest { per_direction: 3, noise: 0.05, ..ImpactTest::seed_rig() }
//!     .run(&seed_rig())?;
//! let r = &records[1];
//! let zero = vec![0.0; r.len()];
//! records[1] = Record::new(r.label(), r.sample_rate(), vec![zero.clone(), zero],
//!     vec![r.displacement(0).to_vec(), r.displacement(1).to_vec()])?;
//! let mut screener = Screener::new(Checks::default());
//! let found: Vec<Vec<Warning>> = records.iter().map(|r| screener.push(r)).collect();
//! assert!(found[0].is_empty());
//! assert_eq!(found[1].len(), 2);
//! assert_eq!(
//!     found[1][0].to_string(),
//!     "record `impact-dof0-1`: force channel 0 is flat, every sample at 0.0000e0 \
//!      (a dead or disconnected sensor)"
//! );
//! # Ok::<(), bearing_ident::Error>(())
//! ```

use std::collections::{BTreeMap, HashMap};
use std::hash::{DefaultHasher, Hash, Hasher};

use faer::{Mat, c64};

use crate::error::{Channel, Error, Result, Warning};
use crate::quality::{self, ImpactChecks};
use crate::records::Record;

/// A channel is flat when `max − min ≤ FLAT_TOLERANCE · max(|max|, |min|)`: one value up to
/// rounding (exactly zero for an all-zero channel).
pub const FLAT_TOLERANCE: f64 = 1e-12;

/// Sibling groups smaller than this are not judged across records.
pub const MIN_SIBLINGS: usize = 3;

/// A record is excited in one direction when its dominant force's RMS is at least this many
/// times every other force channel's.
pub const DOMINANCE: f64 = 3.0;

/// `1/Φ⁻¹(3/4)`: the MAD of Gaussian data times this is its standard deviation.
const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// Thresholds of the record screening (see the [module docs](self)).
///
/// # Examples
/// ```
/// use bearing_ident::screening::Checks;
/// let checks = Checks::default();
/// assert!(checks.impact.is_some());
/// assert_eq!(checks.clip_run, 3);
/// assert!((checks.dead_ratio - 0.01).abs() < 1e-15);
/// assert!(checks.validate().is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Checks {
    /// The double-hit check of impact records ([`quality::check_record`]); `None` skips it.
    /// Its `clip_run` is not used ([`Checks::clip_run`] is). It applies only to impulsive
    /// records (crest factor ≥ `min_crest_factor`), so leaving it on for other excitations is
    /// harmless. Default `Some(ImpactChecks::default())`.
    pub impact: Option<ImpactChecks>,
    /// This many consecutive samples at a channel's extreme count as clipping (see
    /// [`ImpactChecks::clip_run`]). Valid `≥ 2`; default `3`.
    pub clip_run: usize,
    /// A channel is dead when its RMS is below this fraction of the same channel's median RMS
    /// over its siblings. Valid `(0, 1)`; default `0.01`.
    pub dead_ratio: f64,
    /// A level is an outlier beyond this many robust standard deviations of the siblings' log
    /// RMS… Valid finite `> 0`; default `5`.
    pub level_sigmas: f64,
    /// …and beyond this factor of their median RMS (either way). Valid finite `> 1`; default
    /// `3`.
    pub level_factor: f64,
    /// A paired set is far from the others at a line when some element of its impedance is
    /// beyond this many robust standard deviations of the sets' distances to their median…
    /// Valid finite `> 0`; default `5`.
    pub set_sigmas: f64,
    /// …and beyond this fraction of the line's median impedance (Frobenius norm). Valid
    /// finite `≥ 0`; default `0.05`.
    pub set_floor: f64,
    /// A set far at more than this fraction of the lines tested is an outlier. Valid
    /// `(0, 1)`; default `0.5` (most lines).
    pub set_fraction: f64,
}

impl Default for Checks {
    fn default() -> Self {
        Self {
            impact: Some(ImpactChecks::default()),
            clip_run: 3,
            dead_ratio: 0.01,
            level_sigmas: 5.0,
            level_factor: 3.0,
            set_sigmas: 5.0,
            set_floor: 0.05,
            set_fraction: 0.5,
        }
    }
}

impl From<ImpactChecks> for Checks {
    /// The default checks with `impact`'s double-hit settings and clip run.
    fn from(impact: ImpactChecks) -> Self {
        Self {
            impact: Some(impact),
            clip_run: impact.clip_run,
            ..Self::default()
        }
    }
}

impl Checks {
    /// The default checks without the double-hit check, for excitations that are not impacts.
    pub fn without_double_hits() -> Self {
        Self {
            impact: None,
            ..Self::default()
        }
    }

    /// Checks that every threshold is in its valid range.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first field out of range (the impact checks'
    /// own, see [`ImpactChecks::validate`]).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::screening::Checks;
    /// use bearing_ident::Error;
    /// let bad = Checks { dead_ratio: 1.5, ..Checks::default() };
    /// assert!(matches!(bad.validate(), Err(Error::InvalidParameter { name: "dead_ratio", .. })));
    /// ```
    pub fn validate(&self) -> Result<()> {
        if let Some(impact) = self.impact {
            impact.validate()?;
        }
        let fail = |name, value, expected| {
            Err(Error::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if self.clip_run < 2 {
            return fail("clip_run", self.clip_run as f64, "at least 2 samples");
        }
        if !(self.dead_ratio > 0.0 && self.dead_ratio < 1.0) {
            return fail("dead_ratio", self.dead_ratio, "0 < ratio < 1");
        }
        if !(self.level_sigmas > 0.0 && self.level_sigmas.is_finite()) {
            return fail("level_sigmas", self.level_sigmas, "finite and > 0");
        }
        if !(self.level_factor > 1.0 && self.level_factor.is_finite()) {
            return fail("level_factor", self.level_factor, "finite and > 1");
        }
        if !(self.set_sigmas > 0.0 && self.set_sigmas.is_finite()) {
            return fail("set_sigmas", self.set_sigmas, "finite and > 0");
        }
        if !(self.set_floor >= 0.0 && self.set_floor.is_finite()) {
            return fail("set_floor", self.set_floor, "finite and ≥ 0");
        }
        if !(self.set_fraction > 0.0 && self.set_fraction < 1.0) {
            return fail("set_fraction", self.set_fraction, "0 < fraction < 1");
        }
        Ok(())
    }
}

/// What the screening keeps of one record: RMS per channel (mean removed), a hash of its
/// samples, its dominant force.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    label: String,
    dominant: usize,
    force_rms: Vec<f64>,
    displacement_rms: Vec<f64>,
    hash: u64,
    /// Channels reported flat on arrival.
    flat: Vec<Channel>,
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
        let mut hasher = DefaultHasher::new();
        record.len().hash(&mut hasher);
        let n = record.dofs();
        for c in 0..n {
            for ch in [record.force(c), record.displacement(c)] {
                for v in ch {
                    v.to_bits().hash(&mut hasher);
                }
            }
        }
        Self {
            label: record.label().to_owned(),
            dominant: record.dominant_force(),
            force_rms: (0..n).map(|c| rms(record.force(c))).collect(),
            displacement_rms: (0..n).map(|c| rms(record.displacement(c))).collect(),
            hash: hasher.finish(),
            flat: Vec::new(),
        }
    }

    /// How the record was excited: the dominant force channel when its RMS is at least
    /// [`DOMINANCE`] times every other force channel's (one direction at a time: impacts, a
    /// shaker per direction), else `n` (all inputs alike: multi-input random).
    fn pattern(&self) -> usize {
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

    /// The RMS of a channel about its mean (N or m).
    ///
    /// # Panics
    /// If the channel is not one of the record's.
    pub fn rms(&self, channel: Channel) -> f64 {
        match channel {
            Channel::Force(c) => self.force_rms[c],
            Channel::Displacement(c) => self.displacement_rms[c],
        }
    }

    fn channels(&self) -> impl Iterator<Item = Channel> + use<> {
        let n = self.force_rms.len();
        (0..n)
            .map(Channel::Force)
            .chain((0..n).map(Channel::Displacement))
    }
}

/// RMS of `x` about its mean.
fn rms(x: &[f64]) -> f64 {
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    (x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / x.len() as f64).sqrt()
}

/// The value of a flat channel, `None` if it varies.
fn flat(x: &[f64]) -> Option<f64> {
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    (hi - lo <= FLAT_TOLERANCE * hi.abs().max(lo.abs())).then_some(0.5 * (lo + hi))
}

/// Screens records one at a time, keeping only their [`Summary`], then across them.
///
/// # Examples
/// The same record passed twice under two labels:
/// ```
/// use bearing_ident::screening::{Checks, Screener};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// use bearing_ident::Warning;
/// let records = ImpactTest { per_direction: 1, noise: 0.05, ..ImpactTest::seed_rig() }
///     .run(&seed_rig())?;
/// let r = &records[0];
/// let copy = bearing_ident::Record::new("copy.csv", r.sample_rate(),
///     vec![r.force(0).to_vec(), r.force(1).to_vec()],
///     vec![r.displacement(0).to_vec(), r.displacement(1).to_vec()])?;
/// let mut screener = Screener::new(Checks::default());
/// assert!(screener.push(&records[0]).is_empty());
/// assert!(screener.push(&records[1]).is_empty());
/// assert_eq!(
///     screener.push(&copy),
///     vec![Warning::DuplicateRecord { record: "copy.csv".into(), of: "impact-dof0-0".into() }]
/// );
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Screener {
    checks: Checks,
    summaries: Vec<Summary>,
    first_with: HashMap<u64, usize>,
}

impl Screener {
    /// A screener with `checks` (validate them first: [`Checks::validate`]; invalid
    /// thresholds give meaningless findings, never a panic).
    pub fn new(checks: Checks) -> Self {
        Self {
            checks,
            summaries: Vec::new(),
            first_with: HashMap::new(),
        }
    }

    /// The summaries of the records pushed, in order.
    pub fn summaries(&self) -> &[Summary] {
        &self.summaries
    }

    /// Screens `record` on its own and against the earlier ones' hashes, and keeps its
    /// summary: flat channels, clipping, a double hit, a duplicate of an earlier record (in
    /// that order). Empty if it passes.
    pub fn push(&mut self, record: &Record) -> Vec<Warning> {
        let label = record.label();
        let mut found = Vec::new();
        let n = record.dofs();
        let forces_flat: Vec<Option<f64>> = (0..n).map(|c| flat(record.force(c))).collect();
        if forces_flat.iter().all(Option::is_some) {
            for (c, v) in forces_flat.iter().enumerate() {
                found.push(Warning::FlatChannel {
                    record: label.to_owned(),
                    channel: Channel::Force(c),
                    value: v.unwrap_or_default(),
                });
            }
        }
        for c in 0..n {
            if let Some(value) = flat(record.displacement(c)) {
                found.push(Warning::FlatChannel {
                    record: label.to_owned(),
                    channel: Channel::Displacement(c),
                    value,
                });
            }
        }
        // Clipping on every excitation; the double hit only with the impact checks (and even
        // then only on impulsive records).
        let impact = self.checks.impact.unwrap_or(ImpactChecks {
            min_crest_factor: f64::INFINITY,
            ..ImpactChecks::default()
        });
        let impact = ImpactChecks {
            clip_run: self.checks.clip_run,
            ..impact
        };
        let issues = quality::check_record(record, &impact);
        found.extend(quality::warnings(record, &issues));
        let mut summary = Summary::new(record);
        summary.flat = found
            .iter()
            .filter_map(|w| match w {
                Warning::FlatChannel { channel, .. } => Some(*channel),
                _ => None,
            })
            .collect();
        match self.first_with.get(&summary.hash) {
            Some(&first) => found.push(Warning::DuplicateRecord {
                record: label.to_owned(),
                of: self.summaries[first].label.clone(),
            }),
            None => {
                self.first_with.insert(summary.hash, self.summaries.len());
            }
        }
        self.summaries.push(summary);
        found
    }

    /// Screens every record pushed against its siblings (see the [module docs](self)): dead
    /// channels and level outliers, as `(record index, warning)` in record order. Records
    /// with `excluded[r]` (left out already) are neither judged nor counted among siblings;
    /// `excluded` shorter than the records pushed excludes nothing beyond its end. Channels
    /// already reported flat are not judged again.
    pub fn across(&self, excluded: &[bool]) -> Vec<(usize, Warning)> {
        let included: Vec<usize> = (0..self.summaries.len())
            .filter(|&r| !excluded.get(r).copied().unwrap_or(false))
            .collect();
        let mut groups: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for &r in &included {
            groups
                .entry(self.summaries[r].pattern())
                .or_default()
                .push(r);
        }
        let mut found = Vec::new();
        let log_floor = self.checks.level_factor.ln();
        let mut cache: HashMap<(Option<usize>, Channel), Siblings> = HashMap::new();
        for &r in &included {
            let summary = &self.summaries[r];
            let key = summary.pattern();
            let (key, siblings, with_level) = match &groups[&key] {
                g if g.len() >= MIN_SIBLINGS => (Some(key), g, true),
                _ if included.len() >= MIN_SIBLINGS => (None, &included, false),
                _ => continue,
            };
            for channel in summary.channels() {
                if summary.flat.contains(&channel) {
                    continue;
                }
                let s = cache
                    .entry((key, channel))
                    .or_insert_with(|| self.siblings(siblings, channel));
                if s.median_rms <= 0.0 {
                    continue;
                }
                let rms = summary.rms(channel);
                let record = summary.label.clone();
                let median_rms = s.median_rms;
                if rms < self.checks.dead_ratio * median_rms {
                    found.push((
                        r,
                        Warning::DeadChannel {
                            record,
                            channel,
                            rms,
                            median_rms,
                        },
                    ));
                    continue;
                }
                let off = (rms.ln() - s.centre).abs();
                if with_level && off > log_floor && off > self.checks.level_sigmas * s.sigma {
                    found.push((
                        r,
                        Warning::LevelOutlier {
                            record,
                            channel,
                            rms,
                            median_rms,
                            sigmas: off / s.sigma,
                        },
                    ));
                }
            }
        }
        found
    }

    /// The statistics of `channel` over the records `siblings`.
    fn siblings(&self, siblings: &[usize], channel: Channel) -> Siblings {
        let values: Vec<f64> = siblings
            .iter()
            .map(|&r| self.summaries[r].rms(channel))
            .collect();
        let median_rms = median(&mut values.clone());
        let mut logs: Vec<f64> = values
            .iter()
            .filter(|&&v| v >= self.checks.dead_ratio * median_rms && v > 0.0)
            .map(|v| v.ln())
            .collect();
        let centre = median(&mut logs);
        logs.iter_mut().for_each(|l| *l = (*l - centre).abs());
        Siblings {
            median_rms,
            centre,
            sigma: MAD_TO_SIGMA * median(&mut logs),
        }
    }
}

/// A channel's level over a record's siblings.
#[derive(Debug, Clone, Copy)]
struct Siblings {
    /// Median RMS.
    median_rms: f64,
    /// Median log RMS of the live ones.
    centre: f64,
    /// `1.4826 · MAD` of their log RMS.
    sigma: f64,
}

/// The (upper) median of `values`, reordering them; NaN for none.
fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mid = values.len() / 2;
    *values.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// A paired set found far from the others by [`outlier_sets`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutlierSet {
    /// Index of the set.
    pub set: usize,
    /// Lines where it is far out.
    pub far_lines: usize,
    /// Lines tested (where at least 3 sets have an impedance).
    pub lines: usize,
}

/// The sets whose impedance is far from the others' at most lines (see the
/// [module docs](self)): `impedances[set][line]` is the set's own `n × n` impedance at a band
/// line (`None` where it could not be computed). Lines where fewer than 3 sets have one are
/// not tested.
///
/// # Examples
/// Four sets agree within 1 %, the fifth has its columns swapped:
/// ```
/// use bearing_ident::screening::{Checks, OutlierSet, outlier_sets};
/// use faer::{Mat, c64};
/// let h = |k: f64, swap: bool| -> Option<Mat<c64>> {
///     let m = [[146e3 * k, 22e3], [11e3, 169e3 * k]];
///     Some(Mat::from_fn(2, 2, |i, j| c64::new(m[i][if swap { 1 - j } else { j }], 800.0)))
/// };
/// let sets: Vec<Vec<Option<Mat<c64>>>> = (0..5)
///     .map(|s| (0..10).map(|l| h(1.0 + 0.002 * ((s * 3 + l) % 5) as f64, s == 4)).collect())
///     .collect();
/// assert_eq!(
///     outlier_sets(&sets, &Checks::default()),
///     vec![OutlierSet { set: 4, far_lines: 10, lines: 10 }]
/// );
/// ```
pub fn outlier_sets(impedances: &[Vec<Option<Mat<c64>>>], checks: &Checks) -> Vec<OutlierSet> {
    let sets = impedances.len();
    if sets < 3 {
        return Vec::new();
    }
    let lines = impedances.iter().map(Vec::len).min().unwrap_or(0);
    let (mut far, mut tested) = (vec![0; sets], vec![0; sets]);
    for l in 0..lines {
        let present: Vec<(usize, &Mat<c64>)> = impedances
            .iter()
            .enumerate()
            .filter_map(|(s, h)| h[l].as_ref().map(|h| (s, h)))
            .collect();
        if present.len() < 3 {
            continue;
        }
        let n = present[0].1.nrows();
        let centre = Mat::from_fn(n, n, |i, j| {
            let mut re: Vec<f64> = present.iter().map(|(_, h)| h[(i, j)].re).collect();
            let mut im: Vec<f64> = present.iter().map(|(_, h)| h[(i, j)].im).collect();
            c64::new(median(&mut re), median(&mut im))
        });
        let floor = checks.set_floor * centre.norm_l2();
        let mut far_here = vec![false; present.len()];
        for j in 0..n {
            for i in 0..n {
                let distances: Vec<f64> = present
                    .iter()
                    .map(|(_, h)| (h[(i, j)] - centre[(i, j)]).norm())
                    .collect();
                let sigma = MAD_TO_SIGMA * median(&mut distances.clone());
                for (f, d) in far_here.iter_mut().zip(&distances) {
                    *f |= *d > checks.set_sigmas * sigma && *d > floor;
                }
            }
        }
        for ((s, _), f) in present.iter().zip(far_here) {
            tested[*s] += 1;
            far[*s] += usize::from(f);
        }
    }
    (0..sets)
        .filter(|&s| tested[s] > 0 && far[s] as f64 > checks.set_fraction * tested[s] as f64)
        .map(|s| OutlierSet {
            set: s,
            far_lines: far[s],
            lines: tested[s],
        })
        .collect()
}

/// A short phrase for `warning` as the reason a record was rejected.
pub(crate) fn reason(warning: &Warning) -> String {
    match warning {
        Warning::FlatChannel { channel, .. } => format!("{channel} flat"),
        Warning::DeadChannel { channel, .. } => format!("{channel} dead"),
        Warning::LevelOutlier { channel, .. } => format!("{channel} level outlier"),
        Warning::DuplicateRecord { of, .. } => format!("same samples as `{of}`"),
        Warning::OutlierSet { .. } => "impedance far from the other paired sets'".to_owned(),
        Warning::Clipped { channel, .. } => format!("{channel} clipped"),
        Warning::DoubleHit { .. } => "double hit".to_owned(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(label: &str, f: [Vec<f64>; 2], x: [Vec<f64>; 2]) -> Record {
        let [f0, f1] = f;
        let [x0, x1] = x;
        Record::new(label, 100.0, vec![f0, f1], vec![x0, x1]).unwrap()
    }

    fn wave(amplitude: f64, phase: f64) -> Vec<f64> {
        (0..64)
            .map(|m| amplitude * (0.37 * m as f64 + phase).sin())
            .collect()
    }

    #[test]
    fn each_invalid_setting_is_named() {
        let d = Checks::default();
        let cases = [
            (Checks { clip_run: 1, ..d }, "clip_run"),
            (
                Checks {
                    dead_ratio: 0.0,
                    ..d
                },
                "dead_ratio",
            ),
            (
                Checks {
                    level_sigmas: f64::NAN,
                    ..d
                },
                "level_sigmas",
            ),
            (
                Checks {
                    level_factor: 1.0,
                    ..d
                },
                "level_factor",
            ),
            (
                Checks {
                    set_sigmas: -1.0,
                    ..d
                },
                "set_sigmas",
            ),
            (
                Checks {
                    set_floor: f64::INFINITY,
                    ..d
                },
                "set_floor",
            ),
            (
                Checks {
                    set_fraction: 1.0,
                    ..d
                },
                "set_fraction",
            ),
            (
                Checks {
                    impact: Some(ImpactChecks {
                        double_hit_ratio: 2.0,
                        ..ImpactChecks::default()
                    }),
                    ..d
                },
                "double_hit_ratio",
            ),
        ];
        for (checks, field) in cases {
            let e = checks.validate().unwrap_err();
            assert!(
                matches!(e, Error::InvalidParameter { name, .. } if name == field),
                "{checks:?}: {e:?}"
            );
        }
        assert_eq!(Checks::without_double_hits().validate(), Ok(()));
    }

    #[test]
    fn a_single_flat_force_is_left_to_the_siblings() {
        let mut s = Screener::new(Checks::default());
        let r = record(
            "one-shaker",
            [wave(10.0, 0.0), vec![0.0; 64]],
            [wave(1e-6, 0.3), wave(1e-7, 0.1)],
        );
        assert_eq!(s.push(&r), vec![]);
        let r = record(
            "probe-off",
            [wave(10.0, 0.0), wave(1.0, 0.2)],
            [vec![2.5e-4; 64], wave(1e-7, 0.1)],
        );
        assert_eq!(
            s.push(&r),
            vec![Warning::FlatChannel {
                record: "probe-off".into(),
                channel: Channel::Displacement(0),
                value: 2.5e-4
            }]
        );
    }

    #[test]
    fn siblings_judge_dead_channels_and_levels() {
        let mut s = Screener::new(Checks::without_double_hits());
        let levels = [1.0, 1.1, 0.95, 1.05, 1.0, 1.02];
        for (k, a) in levels.iter().enumerate() {
            let p = k as f64;
            let f1 = if k == 2 {
                wave(1e-3, p)
            } else {
                wave(2.0 * a, p)
            };
            let x0 = if k == 4 {
                wave(10e-6 * a, p)
            } else {
                wave(1e-6 * a, p)
            };
            let r = record(
                &format!("r{k}"),
                [wave(10.0 * a, p), f1],
                [x0, wave(1e-7, p)],
            );
            assert_eq!(s.push(&r), vec![]);
        }
        let found = s.across(&[]);
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(matches!(
            &found[0],
            (
                2,
                Warning::DeadChannel {
                    channel: Channel::Force(1),
                    ..
                }
            )
        ));
        assert!(matches!(
            &found[1],
            (4, Warning::LevelOutlier { channel: Channel::Displacement(0), rms, median_rms, .. })
                if (rms / median_rms - 10.0).abs() < 0.5
        ));
        // Left out, a record neither is judged nor counts.
        let found = s.across(&[false, false, true, false, true]);
        assert_eq!(found, vec![]);
    }

    #[test]
    fn fewer_than_three_siblings_are_not_judged() {
        let mut s = Screener::new(Checks::default());
        for k in 0..2 {
            let f1 = if k == 1 {
                wave(1e-6, 0.0)
            } else {
                wave(2.0, 0.0)
            };
            let r = record(
                &format!("r{k}"),
                [wave(10.0, 0.0), f1],
                [wave(1e-6, 0.1), wave(1e-6, 0.2)],
            );
            s.push(&r);
        }
        assert_eq!(s.across(&[]), vec![]);
    }

    #[test]
    fn outlier_sets_need_three() {
        let h = Some(Mat::<c64>::identity(2, 2));
        let two = vec![vec![h.clone()], vec![Some(Mat::zeros(2, 2))]];
        assert_eq!(outlier_sets(&two, &Checks::default()), vec![]);
        let three = vec![vec![h.clone()], vec![h.clone()], vec![None]];
        assert_eq!(outlier_sets(&three, &Checks::default()), vec![]);
    }
}
