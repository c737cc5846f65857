//! The entry points of [`Identifier`] and the stages they run: records (screened) →
//! spectra ([`FrfBuilder`]) → the stages after the spectra ([`Settings::conclude`]:
//! coherence selection, line count, conditioning, fit, diagnostics, error bars). Each entry
//! point checks the settings once ([`Identifier::check`]) and runs on the [`Settings`].

use std::borrow::Cow;
use std::time::Instant;

use crate::conditioning::Conditioning;
use crate::error::{Error, Result, Warning};
use crate::frf::{Assignment, Estimator, Frf, FrfBuilder};
use crate::records::Record;
use crate::screening::Screener;
use crate::solve::{self, Method};
use crate::spectra::Segmentation;
use crate::tolerance;

use super::derived::{mode_std, scaled_covariance};
use super::diagnostics::flexibility_r2;
use super::screen::{
    kept_records, observe, out_of_scale, reported, screen_batch, without_interference,
};
use super::timings::{Untimed, timed};
use super::{Budget, Identification, Identifier, ModelCheck, Settings, Timings};
#[cfg(doc)]
use super::{NonConvergence, Screening, Uncertainty};
use crate::element::{ModelSpec, select};

impl Identifier {
    /// Runs the identification.
    ///
    /// # Errors
    /// Every error of the stages: record shapes ([`Error::DofMismatch`],
    /// [`Error::SampleRateMismatch`], [`Error::RecordLengthMismatch`], [`Error::NoRecords`]),
    /// the band ([`Error::InvalidBand`], [`Error::BandAboveNyquist`], [`Error::TooFewLines`]
    /// when the band holds fewer lines than the fit needs, with the line spacing),
    /// [`Error::SpectrumOverflow`] and [`Error::NonFiniteResult`] when levels overflow f64,
    /// [`Error::DeadChannel`] naming a record with every force (or displacement) channel flat
    /// when the run cannot go on without it (instead of the rank, singularity or line-count
    /// error it causes), the assignment, [`Error::RankDeficient`], [`Error::SingularFit`],
    /// [`Error::InvalidParameter`] for out-of-range settings, and [`Error::NotConverged`] under
    /// [`NonConvergence::Fail`].
    pub fn identify(&self, records: &[Record]) -> Result<Identification> {
        self.check()?.identify(records)
    }

    /// [`Identifier::identify`] over records that arrive one at a time (read from files, say):
    /// each is reduced to its band-line spectra (paired sets) or folded into the cross-spectra
    /// (H1) and can be dropped at once, so memory does not grow with record length, nor, for
    /// H1, with the number of records.
    ///
    /// Screening ([`Screening`]) decides flat channels, clipping, double hits and duplicates of
    /// an earlier record on arrival; dead channels and level outliers (which need the
    /// siblings) and the per-line test of paired sets once all have arrived. Under
    /// [`Screening::Reject`] records found faulty late are taken back out: paired sets keep
    /// every record's band-line spectra anyway, and cross-spectral estimators then keep each
    /// record's own band-line cross-spectra too (`3n²` complex numbers per line and record),
    /// so the result is that of leaving the records out from the start.
    ///
    /// # Errors
    /// The first error of the iterator, then as [`Identifier::identify`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let test = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() };
    /// let records = test.run(&seed_rig())?;
    /// let streamed = Identifier::new(8.0, 49.0).identify_stream(records.clone().into_iter().map(Ok))?;
    /// let at_once = Identifier::new(8.0, 49.0).identify(&records)?;
    /// assert_eq!(streamed.coefficients(), at_once.coefficients());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn identify_stream(
        &self,
        records: impl IntoIterator<Item = Result<Record>>,
    ) -> Result<Identification> {
        self.check()?.identify_stream(records)
    }

    /// Identifies a stepped-sine test ([`crate::stepped::stepped_sine`], steps grouped within
    /// `step_tolerance` Hz, records assigned by [`Identifier::assignment`]) with the record
    /// screening of [`Identifier::identify`] (per record and across siblings; no per-line
    /// test, each step being its own line), then as [`Identifier::identify_frf`].
    ///
    /// # Errors
    /// As [`crate::stepped::stepped_sine`] and [`Identifier::identify_frf`];
    /// [`Error::NoRecords`] if screening left none.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{AntiAlias, Simulator, seed_rig, sine};
    /// let mut sim = Simulator::new(&seed_rig(), 2000.0, 4000, AntiAlias::default())?;
    /// let mut records = Vec::new();
    /// for step in 0..8 {
    ///     let f = 10.0 + 5.0 * step as f64;
    ///     for dir in 0..2 {
    ///         let mut forces = vec![vec![0.0; 4000]; 2];
    ///         forces[dir] = sine(f, 50.0, 2000.0, 4000)?;
    ///         let r = sim.held_record(format!("{f}Hz-{dir}"), &forces)?;
    ///         records.push(r.trimmed(2000..4000)?);
    ///     }
    /// }
    /// let id = Identifier::new(8.0, 49.0).identify_stepped_sine(&records, 0.01)?;
    /// assert!(id.warnings().is_empty());
    /// assert!((id.coefficients().mass()[(0, 0)] / 4.7 - 1.0).abs() < 1e-4);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn identify_stepped_sine(
        &self,
        records: &[Record],
        step_tolerance: f64,
    ) -> Result<Identification> {
        self.check()?.identify_stepped_sine(records, step_tolerance)
    }

    /// Identifies many test conditions (operating points) with the same settings, one result
    /// per record set, in order. With the `rayon` feature the sets run in parallel. The
    /// settings are checked once; when they fail, every set gets the error.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let test = ImpactTest { per_direction: 1, ..ImpactTest::seed_rig() };
    /// let sets = vec![test.run(&seed_rig())?, test.run(&seed_rig())?];
    /// let results = Identifier::new(8.0, 49.0).identify_batch(&sets);
    /// assert_eq!(results.len(), 2);
    /// assert!(results.iter().all(|r| r.is_ok()));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn identify_batch(&self, sets: &[Vec<Record>]) -> Vec<Result<Identification>> {
        let settings = match self.check() {
            Ok(settings) => settings,
            Err(e) => return sets.iter().map(|_| Err(e.clone())).collect(),
        };
        #[cfg(feature = "rayon")]
        {
            use rayon::prelude::*;
            sets.par_iter().map(|s| settings.identify(s)).collect()
        }
        #[cfg(not(feature = "rayon"))]
        {
            sets.iter().map(|s| settings.identify(s)).collect()
        }
    }

    /// Fits an [`Frf`] measured some other way — stepped sine
    /// ([`crate::stepped::stepped_sine`]), or flexibilities from another tool
    /// ([`Frf::from_flexibility`]) — with every check and diagnostic of
    /// [`Identifier::identify`]. Lines outside the band are left out. Resampling uncertainties
    /// need the records, so the jackknife and bootstrap fall back to the sandwich here
    /// (silently under [`Uncertainty::Auto`], else with [`Warning::FewReplicates`]).
    ///
    /// # Errors
    /// As [`Identifier::identify`], after the record stages.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Frf, Identifier, simulate::seed_rig};
    /// let truth = seed_rig();
    /// let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
    /// let g: Vec<_> = freqs.iter().map(|&f| truth.flexibility_at(f)).collect::<Result<_, _>>()?;
    /// let id = Identifier::new(8.0, 49.0).identify_frf(Frf::from_flexibility(freqs, &g)?)?;
    /// assert!((id.coefficients().damping()[(0, 0)] / 131.98 - 1.0).abs() < 1e-8);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn identify_frf(&self, frf: Frf) -> Result<Identification> {
        self.check()?.identify_frf(frf)
    }
}

impl Settings {
    /// [`Identifier::identify`] on checked settings.
    fn identify(&self, records: &[Record]) -> Result<Identification> {
        let start = Instant::now();
        let (mut builder, warnings, t, _) = self.screened_spectra(records)?;
        self.finish(&mut builder, warnings, t, start)
    }

    /// The records of [`Identifier::identify`] through the screening and the spectra: the
    /// builder holding them, the screening's warnings and the stages' timings; and the
    /// screening's verdicts, which do not depend on how the records are cut
    /// ([`Settings::spectra_screened`] takes them again).
    pub(super) fn screened_spectra(
        &self,
        records: &[Record],
    ) -> Result<(FrfBuilder, Vec<Warning>, Timings, Screened)> {
        let mut t = Timings::default();
        let steady = self.steady_all(records)?;
        let screened = timed(&mut t.screen, || self.screen(&steady));
        let (builder, warnings) = self.spectra_screened(&steady, &screened, &mut t)?;
        Ok((builder, warnings, t, screened))
    }

    /// The screening of [`Identifier::identify`] on records at hand (steady already): the
    /// pulses and periods checked, and the records screened one by one and against their
    /// siblings (all but the per-line test of paired sets, which needs their spectra).
    fn screen(&self, records: &[Record]) -> Screened {
        let mut pulses: Vec<Warning> = self.pulse_warning(records).into_iter().collect();
        pulses.extend(self.period_warnings(records));
        let batch = self
            .screening
            .map(|(checks, reject)| screen_batch(records, checks, reject));
        Screened { pulses, batch }
    }

    /// The spectra of `records` (steady already) screened as `screened` says, the per-line
    /// test of paired sets, and the warnings in the order the identification reports them.
    pub(super) fn spectra_screened(
        &self,
        records: &[Record],
        screened: &Screened,
        t: &mut Timings,
    ) -> Result<(FrfBuilder, Vec<Warning>)> {
        let mut builder = self.builder();
        let (Some((checks, reject)), Some((kept, found))) = (self.screening, &screened.batch)
        else {
            timed(&mut t.spectra, || builder.push_all(records))?;
            return Ok((builder, screened.pulses.clone()));
        };
        let mut warnings = found.clone();
        timed(&mut t.spectra, || {
            builder.push_all(&kept_records(records, kept))
        })?;
        self.screen_sets(&mut builder, &checks, reject, &mut warnings, t)?;
        warnings.extend(screened.pulses.iter().cloned());
        Ok((builder, warnings))
    }

    /// [`Identifier::identify_stream`] on checked settings.
    fn identify_stream(
        &self,
        records: impl IntoIterator<Item = Result<Record>>,
    ) -> Result<Identification> {
        let start = Instant::now();
        let mut t = Timings::default();
        let mut builder = self.builder();
        let mut pulses = self.pulse_check();
        let mut periods = self.period_check();
        let records = records
            .into_iter()
            .map(|r| r.and_then(|r| self.steady(r)))
            .inspect(|r| {
                if let (Ok(r), Some(p)) = (r, periods.as_mut()) {
                    p.record(r);
                }
            });
        let Some((checks, reject)) = self.screening else {
            for r in records {
                let r = r?;
                timed(&mut t.screen, || observe(&r, &mut pulses));
                timed(&mut t.spectra, || builder.push(&r))?;
            }
            let mut found: Vec<Warning> = pulses.and_then(|p| p.warning()).into_iter().collect();
            found.extend(periods.iter().flat_map(|p| p.warnings()));
            return self.finish(&mut builder, found, t, start);
        };
        if reject {
            // Records found faulty only once all have arrived must come out again.
            builder = builder.keeping_partials();
        }
        let mut screener = Screener::new(checks);
        let (mut findings, mut pushed) = (Vec::new(), Vec::new());
        for r in records {
            let r = r?;
            let found = timed(&mut t.screen, || {
                observe(&r, &mut pulses);
                screener.push(&r)
            });
            if reject && !found.is_empty() {
                pushed.push(None);
            } else {
                timed(&mut t.spectra, || builder.push(&r))?;
                pushed.push(Some(builder.records() - 1));
            }
            findings.push(found);
        }
        let screen_start = Instant::now();
        let excluded: Vec<bool> = pushed.iter().map(Option::is_none).collect();
        let mut out = Vec::new();
        for (r, w) in screener.across(&excluded) {
            if let (true, Some(b)) = (reject, pushed[r]) {
                out.push(b);
            }
            findings[r].push(w);
        }
        builder.remove(&out);
        let mut warnings = reported(screener.summaries(), findings, reject);
        t.screen += screen_start.elapsed();
        self.screen_sets(&mut builder, &checks, reject, &mut warnings, &mut t)?;
        warnings.extend(pulses.and_then(|p| p.warning()));
        warnings.extend(periods.iter().flat_map(|p| p.warnings()));
        self.finish(&mut builder, warnings, t, start)
    }

    /// [`Identifier::identify_stepped_sine`] on checked settings.
    fn identify_stepped_sine(
        &self,
        records: &[Record],
        step_tolerance: f64,
    ) -> Result<Identification> {
        let start = Instant::now();
        let mut t = Timings::default();
        let (kept, warnings) = timed(&mut t.screen, || match self.screening {
            None => (Cow::Borrowed(records), Vec::new()),
            Some((checks, reject)) => {
                let (kept, warnings) = screen_batch(records, checks, reject);
                (kept_records(records, &kept), warnings)
            }
        });
        if kept.is_empty() {
            return Err(Error::NoRecords);
        }
        // The stepped-sine estimate is a single-frequency DFT per record and step: spectra.
        let frf = timed(&mut t.spectra, || {
            crate::stepped::stepped_sine(&kept, &self.assignment, self.dofs, step_tolerance)
        })?;
        let mut id = self.identify_frf_timed(frf, t, start)?;
        id.warnings.splice(0..0, warnings);
        Ok(id)
    }

    /// [`Identifier::identify_frf`] on checked settings: the lines inside the band (to
    /// [`tolerance::READY_FRF_BAND_EDGE`] of its upper edge), then [`Settings::conclude`].
    fn identify_frf(&self, frf: Frf) -> Result<Identification> {
        self.identify_frf_timed(frf, Timings::default(), Instant::now())
    }

    /// [`Settings::identify_frf`] with the clock started at `start` and the stages before
    /// already in `t`.
    fn identify_frf_timed(
        &self,
        frf: Frf,
        mut t: Timings,
        start: Instant,
    ) -> Result<Identification> {
        let band = self.band;
        let slack = tolerance::READY_FRF_BAND_EDGE * band.high_hz();
        let inside = |f: f64| f >= band.low_hz() - slack && f <= band.high_hz() + slack;
        let frf = timed(&mut t.frf, || {
            frf.retain_lines(|k| inside(frf.freqs_hz()[k]))
        });
        self.conclude(frf, None, Vec::new(), Vec::new(), t, start)
    }

    /// The spectra of `builder`'s records, then [`Settings::conclude`]; a record without force
    /// or response is named ([`Error::DeadChannel`]) instead of the rank or singularity error
    /// it causes.
    pub(super) fn finish(
        &self,
        builder: &mut FrfBuilder,
        screened: Vec<Warning>,
        mut t: Timings,
        start: Instant,
    ) -> Result<Identification> {
        if builder.records() == 0 {
            return Err(Error::NoRecords);
        }
        // H1 from periods or Welch segments: the noise the records show, the force
        // measurement noise taken off where it is that (once: a first fit on the same spectra
        // may have estimated it already).
        if builder.noise().is_none() {
            timed(&mut t.noise, || {
                builder.estimate_noise(self.force_noise).is_some()
            });
        }
        let builder = &*builder;
        // Kept for the error: a record far out of scale that the screening found (and kept).
        let suspect = screened.iter().find_map(out_of_scale);
        let frf = timed(&mut t.frf, || {
            let frf = builder.finish(&self.assignment)?;
            let excitations = match self.estimator {
                Estimator::PairedSets => builder.excitations(&self.assignment)?,
                _ => builder.excitations(&Assignment::DominantForce)?,
            };
            Ok((frf, excitations))
        });
        let outcome = frf.and_then(|(frf, excitations)| {
            self.conclude(frf, Some(builder), excitations, screened, t, start)
        });
        // A record without force or without response, one far out of scale with its
        // siblings, or one whose levels leave f64 in the spectra's products, shows up later as
        // missing rank, a singular fit, a fit that cannot converge or values that are not
        // finite: name the record instead. (A band with too few lines stays `bad_band`.)
        match outcome {
            Err(
                e @ (Error::RankDeficient { .. }
                | Error::Singular { .. }
                | Error::SingularFit { .. }
                | Error::NotConverged { .. }
                | Error::NonFiniteResult { .. }
                | Error::IterationNonFinite { .. }
                | Error::ImpedanceScale { .. }),
            ) => Err(builder.dead_channel().unwrap_or_else(|| match suspect {
                Some((record, finding)) => Error::BadRecord {
                    record,
                    finding,
                    failure: e.to_string(),
                },
                None => builder.level_out_of_range().unwrap_or(e),
            })),
            outcome => outcome,
        }
    }

    /// The stages after the spectra: coherence selection, line count, conditioning, fit,
    /// diagnostics, window correction, error bars. `builder` (with its replicates) is there
    /// unless the FRF came ready-made.
    fn conclude(
        &self,
        frf: Frf,
        builder: Option<&FrfBuilder>,
        excitations: Vec<usize>,
        mut warnings: Vec<Warning>,
        mut t: Timings,
        start: Instant,
    ) -> Result<Identification> {
        let (frf, low_coherence) = timed(&mut t.frf, || self.select_coherent(frf));
        // Lines left too few, or too few to span the directions, by the coherence minimum:
        // that minimum is the cause, not the band or the excitations.
        let coherence_cause = |e: Error| match e {
            Error::TooFewLines { .. } | Error::RankDeficient { .. } if low_coherence > 0 => {
                Error::InvalidParameter {
                    name: crate::Parameter::MinCoherence,
                    value: self.min_coherence,
                    expected: "a multiple coherence the records reach: the lines below it \
                               leave too few to fit",
                }
            }
            e => e,
        };
        let (frf, interference) = match builder {
            Some(b) => timed(&mut t.frf, || without_interference(frf, b)),
            None => (frf, Vec::new()),
        };
        warnings.extend(interference);
        require_lines(&frf).map_err(coherence_cause)?;
        let conditioning = timed(&mut t.conditioning, || {
            Conditioning::assess(&frf, self.limits)
        })
        .map_err(coherence_cause)?;
        let solve_start = Instant::now();
        // A fit that fails on an impedance whose squares leave f64: the units are the cause.
        let scale_cause = |e: Error| match e {
            Error::NotConverged { .. }
            | Error::IterationNonFinite { .. }
            | Error::SingularFit { .. }
            | Error::Singular { .. }
            | Error::NonFiniteResult { .. } => solve::impedance_out_of_range(&frf).unwrap_or(e),
            e => e,
        };
        let fitted = self
            .identification_fitter()
            .fit(&frf, builder, self.window)
            .map_err(scale_cause)?;
        let (fit, ml) = (fitted.fit, fitted.ml);
        warnings.extend(fitted.warnings);
        warnings.extend(self.data_warnings(&frf, &conditioning, low_coherence));
        warnings.extend(fitted.unconverged);
        // r² compares like with like: measured and fitted flexibility of the windowed data.
        let fit_r2 = flexibility_r2(&frf, fit.coefficients());
        // So does the model check: the windowed data against the windowed fit.
        t.solve += solve_start.elapsed();
        let (model_check, misfit) = timed(&mut t.model_check, || match &ml {
            Some(report) if fit.method() == Method::Ml => ModelCheck::ml(report, &frf),
            _ => ModelCheck::replicates(&frf, fit.coefficients(), self.runs_stride(&frf)),
        })?;
        warnings.extend(misfit);
        let solve_start = Instant::now();
        let windowed = fit.coefficients().clone();
        let fit = self.corrected(fit)?;
        warnings.extend(self.gate_warnings(&frf, fit_r2.as_ref(), fit.coefficients(), builder));
        t.solve += solve_start.elapsed();
        let mut bars = timed(&mut t.uncertainty, || {
            self.error_bars(&fit, &frf, builder, &model_check, &mut warnings)
        })?;
        // A bias is judged against the random error: the model component may already be
        // widened by the very misfit the bias makes.
        let bias_start = Instant::now();
        let random = bars.budget.as_ref().map(|b| &b.random);
        let predicted_bias = self.predicted_bias(
            &frf,
            builder,
            &fit,
            random.or(bars.std_dev.as_ref()),
            &mut warnings,
        );
        let bracket = self.noise_bracket(&frf, builder, &fit, random, &mut warnings);
        t.bias += bias_start.elapsed();
        // A bias past the threshold is carried by the model component, so the combined
        // intervals cover it.
        let carried = [predicted_bias.as_ref().map(|b| &b.bias), bracket.as_ref()];
        if let Some(budget) = bars
            .budget
            .as_mut()
            .filter(|_| carried.iter().any(Option::is_some))
        {
            for bias in carried.into_iter().flatten() {
                budget.carry_bias(bias)?;
            }
            bars.std_dev = Some(budget.combined()?);
        }
        // The calibration's sources move every coefficient at once (a common gain scales
        // M, C, K alike and moves no mode; a delay moves damping): carried as directions.
        let modes_std = timed(&mut t.uncertainty, || {
            bars.budget.as_ref().and_then(|b| {
                let cov = scaled_covariance(fit.covariance(), &b.random_and_model().ok()?);
                mode_std(fit.coefficients(), &cov, b.calibration_directions()).ok()
            })
        });
        // The element model: a family other than kcm asked for, or the smallest the model
        // check accepts; with the default kcm, a misfit that a frequency-dependent family
        // would explain is named.
        let (mut fit, mut model_check, mut modes_std) = (fit, model_check, modes_std);
        let element = if self.model != ModelSpec::default() {
            let (element, found) = timed(&mut t.model_check, || {
                select(&frf, self.model, self.runs_stride(&frf), Some(&windowed))
            })?;
            if !element.is_kcm() {
                let constant = element.constant_part()?;
                let std = element.constant_part_std();
                if let (Some(std), Some(_)) = (&std, bars.budget.as_ref()) {
                    let b = element.check().birge_factor();
                    let random = std.scaled(1.0 / b);
                    let model = std.scaled((1.0 - 1.0 / (b * b)).max(0.0).sqrt());
                    let calibration = self.calibration.std_dev(&constant)?;
                    let budget = Budget::of_parts(random, model, calibration);
                    bars.std_dev = Some(budget.combined()?);
                    bars.budget = Some(budget);
                    bars.interval_factor = crate::statistics::t975(0);
                    bars.uncertainty = super::Uncertainty::Sandwich;
                }
                fit = fit.replaced(constant, bars.std_dev.clone());
                model_check = element.check().clone();
                modes_std = None;
                // The constant part's checks give way to the model's: its misfit, and its
                // modes, those of the internal states' state space.
                warnings.retain(|w| {
                    !matches!(
                        w,
                        Warning::ModelMisfit { .. } | Warning::UnstableMode { .. }
                    )
                });
                warnings.extend(found);
                warnings.extend(element.modes().unwrap_or_default().iter().filter_map(|m| {
                    (m.damping_ratio < 0.0).then_some(Warning::UnstableMode {
                        frequency_hz: m.natural_frequency_hz,
                        damping_ratio: m.damping_ratio,
                    })
                }));
            }
            Some(element)
        } else {
            if model_check.verdict == super::model_check::Verdict::Misfit {
                let hint = timed(&mut t.model_check, || {
                    select(
                        &frf,
                        ModelSpec::Auto,
                        self.runs_stride(&frf),
                        Some(&windowed),
                    )
                });
                if let Some((element, _)) = hint.ok().filter(|(e, _)| {
                    !e.is_kcm() && e.check().verdict == super::model_check::Verdict::Fits
                }) {
                    warnings.push(Warning::FrequencyDependent {
                        family: element.family().to_string(),
                        poles_hz: element.poles_hz(),
                    });
                }
            }
            None
        };
        t.total = start.elapsed();
        Ok(Identification {
            ml,
            model: element,
            noise_floor: builder.and_then(|b| b.noise().cloned()),
            band: self.band,
            window: self.window,
            segmentation: if builder.is_some() {
                self.segmentation
            } else {
                Segmentation::WholeRecord
            },
            force_gate: self.force_gate.filter(|_| builder.is_some()),
            uncertainty: bars.uncertainty,
            std_dev: bars.std_dev,
            budget: bars.budget,
            model_check,
            modes_std,
            interval_factor: bars.interval_factor,
            estimator: self.estimator,
            frf,
            conditioning,
            fit,
            fit_r2,
            excitations,
            warnings,
            timings: Untimed(t),
            predicted_bias,
            period_s: match (self.segmentation, builder.and_then(FrfBuilder::lengths)) {
                (Segmentation::Periods { .. }, Some((_, len, rate))) => Some(len as f64 / rate),
                _ => None,
            },
            periods_dropped: if builder.is_some() {
                self.drop_periods
            } else {
                0
            },
        })
    }

    /// `frf` without the lines where the multiple coherence of some output is below the
    /// minimum coherence, and how many were left out.
    pub(super) fn select_coherent(&self, frf: Frf) -> (Frf, usize) {
        if self.min_coherence <= 0.0 {
            return (frf, 0);
        }
        let keep = |k: usize| {
            frf.multiple_coherence(k)
                .is_none_or(|c| c.iter().all(|&g| g >= self.min_coherence))
        };
        let low_coherence = (0..frf.line_count()).filter(|&k| !keep(k)).count();
        if low_coherence > 0 {
            let kept = frf.retain_lines(keep);
            (kept, low_coherence)
        } else {
            (frf, 0)
        }
    }
}

/// What the screening of records at hand found, before their spectra: the pulse and period
/// warnings, and, when screening is on, which records to keep and the warnings of the records
/// one by one and against their siblings.
#[derive(Debug, Clone)]
pub(super) struct Screened {
    pulses: Vec<Warning>,
    batch: Option<(Vec<bool>, Vec<Warning>)>,
}

/// Too few lines in the band is the band's fault whether or not the lines are usable.
///
/// # Errors
/// [`Error::TooFewLines`] when the band's lines (used and dropped) are fewer than the fit
/// needs.
pub(super) fn require_lines(frf: &Frf) -> Result<()> {
    let band_lines = frf.line_count() + frf.dropped_hz().len();
    let required = solve::required_lines(frf.dofs());
    if band_lines < required {
        return Err(Error::TooFewLines {
            lines: band_lines,
            required,
            resolution_hz: frf.line_spacing_hz(),
        });
    }
    Ok(())
}
