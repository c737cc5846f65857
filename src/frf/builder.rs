//! [`FrfBuilder`]: records in one at a time, each turned at once into what its estimator needs
//! (band-line spectra for paired sets, per-record cross-spectral sums otherwise) and merged into
//! running totals. The finishes live beside their estimators ([`paired`](super::paired),
//! [`cross`](super::cross)).

use std::sync::OnceLock;

use faer::c64;

use super::contribution::{
    Contribution, contribute, dead_channel, level_out_of_range, overflow_check,
};
use super::conversion::to_displacement;
use super::noise::NoiseFloor;
use super::sets::SetTable;
use super::transfer::ChannelTransfers;
use super::{Assignment, Band, Estimator, Frf};
use crate::error::{Channel, Error, Result, SpectrumKind};
use crate::records::{Record, check_against, common_shape};
use crate::spectra::{ForceGate, Segmentation, SpectralEstimator, Window};

/// Everything an [`FrfBuilder`] has gathered from one record.
#[derive(Debug, Clone)]
pub(super) struct Gathered {
    pub(super) label: String,
    pub(super) dominant: usize,
    pub(super) contribution: Contribution,
}

/// The fixed settings of a builder once the first record has fixed the shape.
#[derive(Debug, Clone)]
pub(super) struct Plan {
    pub(super) n: usize,
    pub(super) sample_rate: f64,
    pub(super) len: usize,
    pub(super) seg_len: usize,
    pub(super) lines: Vec<usize>,
    pub(super) resolution_hz: f64,
    /// Per band line, the factors $1/s^p$ that turn a response of order `p` (displacement,
    /// velocity, acceleration) into displacement ([`Response::to_displacement`]).
    pub(super) to_displacement: Vec<[Option<c64>; 3]>,
    /// Per band line, the known channel characteristics divided out, `[line][2n]` (forces,
    /// then responses; [`ChannelTransfers`]); empty when no channel is corrected.
    pub(super) corrections: Vec<c64>,
}

impl Plan {
    /// The band lines a finished FRF kept (lines can be dropped there): per line, its index
    /// `l` in the plan, its frequency and its index in `frf`. The FRF's frequencies are these
    /// very values (the same computation), so the lookup is exact.
    pub(super) fn lines_in<'a>(
        &'a self,
        frf: &'a Frf,
    ) -> impl Iterator<Item = (usize, f64, usize)> + 'a {
        self.lines.iter().enumerate().filter_map(|(l, &k)| {
            let freq = k as f64 * self.resolution_hz;
            let at = frf
                .freqs_hz()
                .binary_search_by(|u| u.total_cmp(&freq))
                .ok()?;
            Some((l, freq, at))
        })
    }
}

/// Adds one record's period means (its `n` channels' spectra summed over its `periods`
/// periods, `sf` and `sx`, `[l * n + c]`) to `means` (`[l * 2n + c]`, forces then responses):
/// nothing unless `means` is kept (periodic segmentation).
fn add_period_means(means: &mut [f64], sf: &[c64], sx: &[c64], n: usize, periods: usize) {
    if means.is_empty() || sf.len() * 2 != means.len() || periods == 0 {
        return;
    }
    let p = periods as f64;
    for (l, line) in means.chunks_exact_mut(2 * n).enumerate() {
        for c in 0..n {
            line[c] += sf[l * n + c].norm_sqr() / p;
            line[n + c] += sx[l * n + c].norm_sqr() / p;
        }
    }
}

/// Collects records one at a time into what an estimator needs — band-line spectra for paired
/// sets, accumulated cross-spectra for H1 — and keeps no time data, so memory does not grow with
/// record length and, for H1, not with the number of records either.
///
/// # Examples
/// ```
/// use bearing_ident::frf::{Assignment, Band, Estimator, FrfBuilder};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// use bearing_ident::spectra::{Segmentation, Window};
/// let records = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let mut builder = FrfBuilder::new(
///     Estimator::PairedSets, Band::new(8.0, 49.0)?, Segmentation::WholeRecord, Window::Rectangular);
/// for r in &records {
///     builder.push(r)?; // each record may be dropped after this
/// }
/// let frf = builder.finish(&Assignment::DominantForce)?;
/// assert_eq!(frf.line_count(), 49);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug)]
pub struct FrfBuilder {
    pub(super) estimator: Estimator,
    pub(super) band: Band,
    pub(super) segmentation: Segmentation,
    pub(super) window: Window,
    pub(super) dofs: Option<usize>,
    pub(super) force_gate: Option<ForceGate>,
    pub(super) transfers: ChannelTransfers,
    /// Whether every record pushed had displacement responses only.
    pub(super) all_displacement: bool,
    /// Whole records: the time of each record's largest dominant-force sample (s), where an
    /// impact's response starts.
    pub(super) force_peaks_s: Vec<f64>,
    pub(super) plan: Option<(Plan, SpectralEstimator)>,
    pub(super) gathered: Vec<Gathered>,
    /// Cross-spectral totals, merged record by record.
    pub(super) sff: Vec<c64>,
    pub(super) sxf: Vec<c64>,
    pub(super) sxx: Vec<c64>,
    pub(super) averages: usize,
    /// Keep each H1 record's own sums too (for leave-one-out replicates).
    pub(super) keep_partials: bool,
    /// The first record with every force or every displacement channel flat.
    pub(super) dead: Option<Error>,
    /// The first record whose levels leave f64 in the spectra's squares and products.
    pub(super) level: Option<Error>,
    /// Paired sets: each set's `cond(X_s)` and `H_s` per line, once asked for
    /// ([`FrfBuilder::set_table`]); cleared when records come in or go out.
    pub(super) sets: OnceLock<SetTable>,
    /// Periods: per line, `[l * 2n + c]` each force channel's $\sum_r |\Sigma_p F_{c,rp}|^2 / P$,
    /// then each response channel's: the power of the period means, for the noise the periods
    /// show ([`FrfBuilder::noise_floor`]).
    pub(super) period_means: Vec<f64>,
    /// The noise the records show ([`FrfBuilder::estimate_noise`]); the H1 finishes take its
    /// force share off `S_ff` when it is [`NoiseFloor::compensated`]. Cleared when records come
    /// in or go out.
    pub(super) noise: Option<NoiseFloor>,
}

impl FrfBuilder {
    /// A builder for `estimator` over `band`. Paired sets always use whole records.
    pub fn new(
        estimator: Estimator,
        band: Band,
        segmentation: Segmentation,
        window: Window,
    ) -> Self {
        let segmentation = match estimator {
            Estimator::PairedSets => Segmentation::WholeRecord,
            _ => segmentation,
        };
        Self {
            estimator,
            band,
            segmentation,
            window,
            dofs: None,
            force_gate: None,
            transfers: ChannelTransfers::new(),
            all_displacement: true,
            force_peaks_s: Vec::new(),
            plan: None,
            gathered: Vec::new(),
            sff: Vec::new(),
            sxf: Vec::new(),
            sxx: Vec::new(),
            averages: 0,
            keep_partials: false,
            dead: None,
            level: None,
            sets: OnceLock::new(),
            period_means: Vec::new(),
            noise: None,
        }
    }

    /// Requires every record to have `n` degrees of freedom (default: the first record's).
    pub fn dofs(mut self, n: usize) -> Self {
        self.dofs = Some(n);
        self
    }

    /// Gates every force channel with `gate` ([`ForceGate`]) before its transform.
    pub fn force_gate(mut self, gate: ForceGate) -> Self {
        self.force_gate = Some(gate);
        self
    }

    /// Divides the channels' known transfer characteristics ([`ChannelTransfers`]: a delay, AC
    /// coupling) out of every spectrum at the band lines, before any sum or average. Default:
    /// none. Checked against the first record (see [`FrfBuilder::push`]).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::frf::{Assignment, Band, ChannelTransfer, ChannelTransfers, Estimator, FrfBuilder};
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// use bearing_ident::spectra::{Segmentation, Window};
    /// use bearing_ident::{Channel, Record};
    /// let records = ImpactTest { per_direction: 1, noise: 0.0, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
    /// let frf = |records: &[Record], transfers: ChannelTransfers| {
    ///     let mut b = FrfBuilder::new(Estimator::PairedSets, Band::new(8.0, 49.0)?,
    ///         Segmentation::WholeRecord, Window::Rectangular).channel_transfers(transfers);
    ///     b.push_all(records)?;
    ///     b.finish(&Assignment::DominantForce)
    /// };
    /// // The responses delayed by 4 samples (a whole number: exact on the DFT), then corrected.
    /// let delayed: Vec<Record> = records.iter().map(|r| {
    ///     let shift = |x: &[f64]| [&x[x.len() - 4..], &x[..x.len() - 4]].concat();
    ///     Record::new(r.label(), r.sample_rate(), vec![r.force(0).to_vec(), r.force(1).to_vec()],
    ///         vec![shift(r.displacement(0)), shift(r.displacement(1))])
    /// }).collect::<Result<_, _>>()?;
    /// let tau = 4.0 / records[0].sample_rate();
    /// let t = ChannelTransfers::new()
    ///     .with(Channel::Displacement(0), ChannelTransfer::delay(tau))
    ///     .with(Channel::Displacement(1), ChannelTransfer::delay(tau));
    /// let (truth, corrected) = (frf(&records, ChannelTransfers::new())?, frf(&delayed, t)?);
    /// let (a, b) = (truth.impedance(10)[(0, 0)], corrected.impedance(10)[(0, 0)]);
    /// assert!((a - b).norm() < 1e-9 * a.norm());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn channel_transfers(mut self, transfers: ChannelTransfers) -> Self {
        self.transfers = transfers;
        self
    }

    /// Keeps every H1 record's own cross-spectra as well as the totals, so that
    /// [`FrfBuilder::finish_leaving_out`] can drop one (memory then grows with the records).
    pub(crate) fn keeping_partials(mut self) -> Self {
        self.keep_partials = true;
        self
    }

    /// Number of leave-one-out replicates: paired sets (paired), records (H1, which needs
    /// [`FrfBuilder::keeping_partials`]; 0 without).
    pub(crate) fn replicates(&self, assignment: &Assignment) -> Result<usize> {
        match self.estimator {
            Estimator::PairedSets => {
                let n = self.plan.as_ref().map_or(0, |(p, _)| p.n);
                let excitation = self.excitations(assignment)?;
                Ok((0..n)
                    .map(|d| excitation.iter().filter(|&&e| e == d).count())
                    .min()
                    .unwrap_or(0))
            }
            _ if self.keep_partials => Ok(self.gathered.len()),
            _ => Ok(0),
        }
    }

    /// [`FrfBuilder::finish`] with replicate `r` (paired set `r`, or record `r` of a
    /// cross-spectral estimator, which needs [`FrfBuilder::keeping_partials`]) counted
    /// `weights[r]` times: 0 leaves it out (jackknife), bootstrap counts resample. No error
    /// bars are computed for weighted finishes. The reference the shared replicates
    /// ([`FrfBuilder::replicates_on`]) are tested against.
    #[cfg(test)]
    pub(crate) fn finish_weighted(&self, assignment: &Assignment, weights: &[f64]) -> Result<Frf> {
        let (plan, _) = self.plan.as_ref().ok_or(Error::NoRecords)?;
        if self.estimator == Estimator::PairedSets {
            self.finish_paired(plan, &self.excitations(assignment)?, Some(weights))
        } else {
            Ok(self.finish_cross(plan, Some(weights)))
        }
    }

    /// The record length, segment length (samples) and sampling rate fixed by the first
    /// record; `None` before it.
    pub(crate) fn lengths(&self) -> Option<(usize, usize, f64)> {
        self.plan
            .as_ref()
            .map(|(p, _)| (p.len, p.seg_len, p.sample_rate))
    }

    /// Whole records: the median time of the records' largest dominant-force samples (s),
    /// where an impact's response starts; `None` for segmented records or none pushed.
    pub(crate) fn force_peak_s(&self) -> Option<f64> {
        let mut t = self.force_peaks_s.clone();
        t.sort_by(f64::total_cmp);
        t.get(t.len() / 2).copied()
    }

    /// Whether every record pushed had displacement responses only.
    pub(crate) fn all_displacement(&self) -> bool {
        self.all_displacement
    }

    /// Number of records pushed.
    pub fn records(&self) -> usize {
        self.gathered.len()
    }

    /// Label of record `index` (push order).
    pub(crate) fn label(&self, index: usize) -> &str {
        &self.gathered[index].label
    }

    /// Whether every record pushed can be taken out again by [`FrfBuilder::remove`]: always
    /// for paired sets (each record's spectra are kept), for cross-spectral estimators only
    /// with [`FrfBuilder::keeping_partials`].
    pub(crate) fn can_remove(&self) -> bool {
        !self.estimator.is_cross_spectral() || self.keep_partials
    }

    /// Takes the records at `indices` (push order) back out, as if they had never been pushed:
    /// cross-spectral totals are summed again from the remaining records' partials, in order,
    /// so the result is bit for bit that of pushing only the others. Does nothing unless
    /// [`FrfBuilder::can_remove`].
    pub(crate) fn remove(&mut self, indices: &[usize]) {
        if !self.can_remove() || indices.is_empty() {
            return;
        }
        self.sets.take();
        let mut index = 0;
        self.gathered.retain(|_| {
            index += 1;
            !indices.contains(&(index - 1))
        });
        if !self.estimator.is_cross_spectral() {
            self.averages = self.gathered.len();
            return;
        }
        let Some((plan, _)) = self.plan.as_ref() else {
            return;
        };
        let segments = self.segmentation.starts(plan.len).count();
        let zero = c64::new(0.0, 0.0);
        for totals in [&mut self.sff, &mut self.sxf, &mut self.sxx] {
            totals.fill(zero);
        }
        self.period_means.fill(0.0);
        self.noise = None;
        for g in &self.gathered {
            if let Contribution::Cross {
                sff,
                sxf,
                sxx,
                sf,
                sx,
            } = &g.contribution
            {
                for (totals, part) in [
                    (&mut self.sff, sff),
                    (&mut self.sxf, sxf),
                    (&mut self.sxx, sxx),
                ] {
                    totals.iter_mut().zip(part).for_each(|(t, p)| *t += p);
                }
                add_period_means(&mut self.period_means, sf, sx, plan.n, segments);
            }
        }
        self.averages = segments * self.gathered.len();
    }

    /// Checks `record` against the first one and fixes the plan on the first call.
    fn check(&mut self, record: &Record) -> Result<()> {
        match &self.plan {
            None => {
                let n = self.dofs.unwrap_or(record.dofs());
                common_shape(std::slice::from_ref(record), Some(n))?;
                let seg_len = self.segmentation.segment_len(record.len())?;
                let lines = self.band.lines(record.sample_rate(), seg_len)?;
                let spectral = SpectralEstimator::new(seg_len, record.sample_rate(), self.window)?;
                self.transfers.check(Some(n))?;
                let to_displacement =
                    to_displacement(&lines, spectral.resolution_hz(), self.window);
                let corrections =
                    self.transfers
                        .corrections(n, &lines, spectral.resolution_hz(), self.window);
                let plan = Plan {
                    n,
                    sample_rate: record.sample_rate(),
                    len: record.len(),
                    seg_len,
                    resolution_hz: spectral.resolution_hz(),
                    lines,
                    to_displacement,
                    corrections,
                };
                let size = plan.lines.len() * n * n;
                if self.estimator.is_cross_spectral() {
                    self.sff = vec![c64::new(0.0, 0.0); size];
                    self.sxf = vec![c64::new(0.0, 0.0); size];
                    self.sxx = vec![c64::new(0.0, 0.0); size];
                    if matches!(self.segmentation, Segmentation::Periods { .. }) {
                        self.period_means = vec![0.0; plan.lines.len() * 2 * n];
                    }
                }
                let spectral = match self.force_gate {
                    Some(gate) => spectral.with_force_gate(gate),
                    None => spectral,
                };
                self.plan = Some((plan, spectral));
                Ok(())
            }
            Some((plan, _)) => check_against(record, plan.n, plan.sample_rate, plan.len),
        }
    }

    /// Adds one record.
    ///
    /// # Errors
    /// [`Error::DofMismatch`], [`Error::SampleRateMismatch`], [`Error::RecordLengthMismatch`]
    /// against the first record (rates compared by
    /// [`sample_rates_agree`](crate::records::sample_rates_agree)); on the first record,
    /// [`Error::BandAboveNyquist`] and [`Error::InvalidParameter`] for a bad Welch segment
    /// length or channel characteristic ([`ChannelTransfers::check`]); [`Error::SpectrumOverflow`] naming the record, channel and line when its
    /// spectra or cross-spectra (or the running totals) overflow.
    pub fn push(&mut self, record: &Record) -> Result<()> {
        self.check(record)?;
        let (plan, spectral) = self.plan.as_mut().expect("set by check");
        let contribution = contribute(self.estimator, self.segmentation, plan, spectral, record)?;
        self.merge(record, contribution)
    }

    /// Adds every record of a slice. With the `rayon` feature the records are transformed in
    /// parallel and merged in order: the result is bit for bit that of [`FrfBuilder::push`] in
    /// a loop.
    ///
    /// # Errors
    /// As [`FrfBuilder::push`], for the first record that fails.
    pub fn push_all(&mut self, records: &[Record]) -> Result<()> {
        let Some(first) = records.first() else {
            return Ok(());
        };
        self.check(first)?;
        for r in &records[1..] {
            self.check(r)?;
        }
        let (plan, spectral) = self.plan.as_mut().expect("set by check");
        let (estimator, segmentation) = (self.estimator, self.segmentation);
        #[cfg(feature = "rayon")]
        let contributions: Vec<Result<Contribution>> = {
            use rayon::prelude::*;
            let (plan, spectral) = (&*plan, &*spectral);
            records
                .par_iter()
                .map_init(
                    || spectral.clone(),
                    |est, r| contribute(estimator, segmentation, plan, est, r),
                )
                .collect()
        };
        #[cfg(not(feature = "rayon"))]
        let contributions: Vec<Result<Contribution>> = records
            .iter()
            .map(|r| contribute(estimator, segmentation, plan, spectral, r))
            .collect();
        for (r, c) in records.iter().zip(contributions) {
            self.merge(r, c?)?;
        }
        Ok(())
    }

    /// Adds `contribution` to what was gathered.
    ///
    /// # Errors
    /// [`Error::SpectrumOverflow`] when the accumulated cross-spectra overflow with this
    /// record; [`Error::DeadChannel`] is only noted here (see [`FrfBuilder::finish`]).
    fn merge(&mut self, record: &Record, contribution: Contribution) -> Result<()> {
        if self.dead.is_none() {
            self.dead = dead_channel(record);
        }
        if self.level.is_none() {
            self.level = level_out_of_range(record);
        }
        self.all_displacement &= record.is_displacement();
        if self.segmentation == Segmentation::WholeRecord {
            // The first sample of the largest magnitude.
            let (peak, _) = crate::lanes::peak(record.force(record.dominant_force()), 0.0);
            self.force_peaks_s.push(peak as f64 / record.sample_rate());
        }
        let contribution = match contribution {
            Contribution::Cross {
                sff,
                sxf,
                sxx,
                sf,
                sx,
            } => {
                for (totals, part) in [
                    (&mut self.sff, &sff),
                    (&mut self.sxf, &sxf),
                    (&mut self.sxx, &sxx),
                ] {
                    totals.iter_mut().zip(part).for_each(|(t, p)| *t += p);
                }
                if let Some((plan, _)) = &self.plan {
                    let nn = plan.n * plan.n;
                    for (totals, channel) in [
                        (&self.sff, Channel::Force as fn(usize) -> Channel),
                        (&self.sxf, Channel::Displacement),
                        (&self.sxx, Channel::Displacement),
                    ] {
                        overflow_check(
                            record,
                            plan,
                            SpectrumKind::AccumulatedCrossSpectrum,
                            totals,
                            nn,
                            channel,
                        )?;
                    }
                }
                let segments = self.segmentation.starts(record.len()).count();
                self.averages += segments;
                let n = self.plan.as_ref().map_or(0, |(p, _)| p.n);
                add_period_means(&mut self.period_means, &sf, &sx, n, segments);
                if self.keep_partials {
                    Contribution::Cross {
                        sff,
                        sxf,
                        sxx,
                        sf,
                        sx,
                    }
                } else {
                    // Only the totals are kept.
                    Contribution::Cross {
                        sff: Vec::new(),
                        sxf: Vec::new(),
                        sxx: Vec::new(),
                        sf: Vec::new(),
                        sx: Vec::new(),
                    }
                }
            }
            spectra => {
                self.averages += 1;
                spectra
            }
        };
        self.sets.take();
        self.noise = None;
        self.gathered.push(Gathered {
            label: record.label().to_owned(),
            dominant: record.dominant_force(),
            contribution,
        });
        Ok(())
    }

    /// Per line of `frf` (one of this builder's finished estimates), the auto-spectra
    /// `S_{f_c f_c}` of the force channels from the accumulated cross-spectra; `None` unless a
    /// cross-spectral estimator gathered them.
    pub(crate) fn force_auto_spectra(&self, frf: &Frf) -> Option<Vec<Vec<f64>>> {
        let (plan, _) = self.plan.as_ref()?;
        let n = plan.n;
        if self.sff.len() != plan.lines.len() * n * n {
            return None;
        }
        let mut out = vec![Vec::new(); frf.line_count()];
        for (l, _, at) in plan.lines_in(frf) {
            out[at] = (0..n).map(|i| self.sff[(l * n + i) * n + i].re).collect();
        }
        out.iter().all(|v| v.len() == n).then_some(out)
    }

    /// The first record pushed whose force channels, or whose displacement channels, are all
    /// flat (constant over the whole record), as [`Error::DeadChannel`]: the true cause when
    /// an identification cannot go on (rank-deficient excitations or a singular fit).
    pub fn dead_channel(&self) -> Option<Error> {
        self.dead.clone()
    }

    /// The first record pushed whose levels leave f64 in the squares and products of its
    /// spectra, as [`Error::LevelOutOfRange`]: every force (or displacement) channel below
    /// about 1.5e-154 (subnormal samples far below), or a channel above about 1.3e154. The true
    /// cause when an identification then fails (rank, singularity, convergence, non-finite
    /// results).
    pub fn level_out_of_range(&self) -> Option<Error> {
        self.level.clone()
    }

    /// The excitation of every record pushed, by `assignment`.
    ///
    /// # Errors
    /// As [`Assignment::resolve`].
    pub fn excitations(&self, assignment: &Assignment) -> Result<Vec<usize>> {
        let n = self.plan.as_ref().map_or(0, |(p, _)| p.n);
        let labels: Vec<&str> = self.gathered.iter().map(|g| g.label.as_str()).collect();
        let dominant: Vec<usize> = self.gathered.iter().map(|g| g.dominant).collect();
        assignment.resolve_with(&labels, &dominant, n)
    }

    /// Impedances and flexibilities from everything pushed.
    ///
    /// # Errors
    /// [`Error::NoRecords`] if nothing was pushed; for paired sets, the assignment errors and
    /// [`Error::RankDeficient`] when some direction has no record;
    /// [`Error::NonFiniteResult`] at the first line whose impedance, flexibility or coherence
    /// is not finite. (A record with all its forces or displacements flat is kept aside as
    /// [`FrfBuilder::dead_channel`] for the caller to report.)
    pub fn finish(&self, assignment: &Assignment) -> Result<Frf> {
        let (plan, _) = self.plan.as_ref().ok_or(Error::NoRecords)?;
        let frf = if self.estimator == Estimator::PairedSets {
            self.finish_paired(plan, &self.excitations(assignment)?, None)?
        } else {
            self.finish_cross(plan, None)
        };
        frf.check_finite()?;
        Ok(frf)
    }

    /// The FRF the other one-sided estimator gives on the same cross-spectral sums: H2 for
    /// H1, H1 for H2 (`None` for paired sets and Hv, or before any record). Input noise
    /// biases H1's flexibility low and output noise H2's high, so the truth lies between the
    /// two: the pair brackets the bias of noise the estimator assumes away.
    pub(crate) fn finish_bracket(&self) -> Option<Result<Frf>> {
        let (plan, _) = self.plan.as_ref()?;
        let other = match self.estimator {
            Estimator::H1 => Estimator::H2,
            Estimator::H2 => Estimator::H1,
            Estimator::Hv | Estimator::PairedSets => return None,
        };
        let frf = self.finish_cross_as(plan, None, other, None);
        Some(frf.check_finite().map(|()| frf))
    }

    /// The H1 finish compensated for the force noise `force` (per average, `[l * n + c]` over
    /// the plan's lines) instead of the builder's own compensation; `None` for other
    /// estimators or before any record. The compensation's uncertainty is judged by it.
    pub(crate) fn finish_compensated(&self, force: &[f64]) -> Option<Result<Frf>> {
        let (plan, _) = self.plan.as_ref()?;
        if self.estimator != Estimator::H1 || force.len() != plan.lines.len() * plan.n {
            return None;
        }
        let frf = self.finish_cross_as(plan, None, Estimator::H1, Some(force));
        Some(frf.check_finite().map(|()| frf))
    }
}
