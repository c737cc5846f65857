//! An identification paused after its spectra ([`Spectra`]): the records screened and
//! reduced to band-line spectra or cross-spectra, the stages after them still to run. A caller
//! that must look at a first fit before it settles the settings (the Welch length chosen from
//! the data, [`choose_welch`](crate::excitation::choose_welch)) fits quickly on them
//! ([`Spectra::quick_fit`]) and, when the settings stand, finishes on the same spectra
//! ([`Spectra::finish`]) instead of transforming the records again.
// Only the job's Welch choice finishes or recuts the spectra; without the `job` feature the
// quick fit alone is used.
#![cfg_attr(not(feature = "job"), allow(dead_code))]

use std::time::{Duration, Instant};

use crate::conditioning::Conditioning;
use crate::error::{Result, Warning};
use crate::frf::{Band, FrfBuilder};
use crate::model::Coefficients;
use crate::records::Record;
use crate::solve::Method;
use crate::spectra::Segmentation;

use super::pipeline::{Screened, require_lines};
use super::screen::without_interference;
use super::{Identification, Identifier, Settings, Timings, Uncertainty};

/// The records of an identification through the screening and the spectra, with the settings
/// that made them: what [`Identifier::identify`] has done before its FRF stage.
#[derive(Debug)]
pub(crate) struct Spectra {
    settings: Settings,
    builder: FrfBuilder,
    /// The screening's verdicts, which do not depend on the Welch length.
    screened: Screened,
    /// The screening's warnings, in the order the identification reports them.
    warnings: Vec<Warning>,
    /// The stages run so far (screen, spectra, frf for the paired sets' own impedances).
    timings: Timings,
    /// Wall time spent so far, from the call.
    elapsed: Duration,
}

/// What a quick fit on the spectra gives ([`Spectra::quick_fit`]).
#[derive(Debug, Clone)]
pub(crate) struct QuickFit {
    /// The band fitted.
    pub(crate) band: Band,
    /// The coefficients, corrected for the window as an identification's are.
    pub(crate) coefficients: Coefficients,
    /// The fit's own standard deviations (sandwich or Fisher): the random error an
    /// identification with [`Uncertainty::Sandwich`] reports as its budget's random part.
    pub(crate) random: Option<Coefficients>,
}

impl Identifier {
    /// The records through the screening and the spectra, as [`Identifier::identify`] runs
    /// them, the rest to come.
    ///
    /// # Errors
    /// The settings' errors ([`Identifier::check`]) and those of the screening and the spectra.
    pub(crate) fn spectra(&self, records: &[Record]) -> Result<Spectra> {
        self.check()?.spectra(records)
    }
}

impl Settings {
    /// [`Identifier::spectra`] on checked settings.
    fn spectra(&self, records: &[Record]) -> Result<Spectra> {
        let start = Instant::now();
        let (builder, warnings, timings, screened) = self.screened_spectra(records)?;
        Ok(Spectra {
            settings: self.clone(),
            builder,
            screened,
            warnings,
            timings,
            elapsed: start.elapsed(),
        })
    }
}

impl Spectra {
    /// The rest of the identification: bit for bit the [`Identification`] that
    /// [`Identifier::identify`] gives on the same records with the same settings, its timings
    /// those of both parts (the time between them left out).
    ///
    /// # Errors
    /// As [`Identifier::identify`] after the spectra.
    pub(crate) fn finish(self) -> Result<Identification> {
        let start = Instant::now()
            .checked_sub(self.elapsed)
            .unwrap_or_else(Instant::now);
        let Spectra {
            settings,
            mut builder,
            warnings,
            timings,
            ..
        } = self;
        settings.finish(&mut builder, warnings, timings, start)
    }

    /// The wall time spent on the records so far (screening and spectra).
    pub(crate) fn elapsed(&self) -> Duration {
        self.elapsed
    }

    /// The spectra of the same `records` cut into Welch segments of `len` samples, the
    /// settings otherwise these spectra's: bit for bit what [`Identifier::spectra`] gives with
    /// that length, without screening the records again (the screening does not depend on
    /// the Welch length; for other segmentations they are screened again).
    ///
    /// # Errors
    /// As [`Identifier::spectra`].
    pub(crate) fn welch_len(&self, records: &[Record], len: usize) -> Result<Spectra> {
        let settings = Settings {
            segmentation: Segmentation::Welch { len },
            ..self.settings.clone()
        };
        if !matches!(self.settings.segmentation, Segmentation::Welch { .. }) {
            return settings.spectra(records);
        }
        let start = Instant::now();
        // The screening is these spectra's, made once: its time is the new spectra's screen
        // stage, and part of the time they took.
        let mut timings = Timings {
            screen: self.timings.screen,
            ..Timings::default()
        };
        let steady = settings.steady_all(records)?;
        let (builder, warnings) =
            settings.spectra_screened(&steady, &self.screened, &mut timings)?;
        Ok(Spectra {
            settings,
            builder,
            screened: self.screened.clone(),
            warnings,
            timings,
            elapsed: start.elapsed() + self.timings.screen,
        })
    }

    /// A fit by `method` that is only what a first look at the system needs: the FRF with its
    /// force-noise compensation, coherence selection and interference lines as the
    /// identification makes them, the conditioning verdict, the fit corrected for the window
    /// and its own standard deviations; no model check, error bars, budget or predicted bias.
    /// Its coefficients and standard deviations are bit for bit those of
    /// [`Identifier::identify`] by `method` with [`Uncertainty::Sandwich`] on the same records
    /// (its coefficients and its budget's random part).
    ///
    /// # Errors
    /// The error that identification gives: when a stage fails here, the identification is
    /// run to its end, so that the error is named as it names it.
    pub(crate) fn quick_fit(&mut self, method: Method) -> Result<QuickFit> {
        let settings = Settings {
            method,
            uncertainty: Uncertainty::Sandwich,
            ..self.settings.clone()
        };
        match quick(&settings, &mut self.builder) {
            Ok(fit) => Ok(fit),
            Err(_) => {
                let id = settings.finish(
                    &mut self.builder,
                    Vec::new(),
                    Timings::default(),
                    Instant::now(),
                )?;
                // The quick fit failed where the whole identification did not: its result.
                Ok(QuickFit {
                    band: id.band(),
                    coefficients: id.coefficients().clone(),
                    random: id.budget().map(|b| b.random.clone()),
                })
            }
        }
    }
}

/// [`Spectra::quick_fit`]'s stages, by `settings`, on `builder`.
fn quick(settings: &Settings, builder: &mut FrfBuilder) -> Result<QuickFit> {
    if builder.noise().is_none() {
        builder.estimate_noise(settings.force_noise);
    }
    let frf = builder.finish(&settings.assignment)?;
    let (frf, _) = settings.select_coherent(frf);
    let (frf, _) = without_interference(frf, builder);
    require_lines(&frf)?;
    Conditioning::assess(&frf, settings.limits)?;
    let fitted = settings
        .fitter()
        .fit(&frf, Some(builder), settings.window)?;
    let fit = settings.corrected(fitted.fit)?;
    Ok(QuickFit {
        band: settings.band,
        random: fit.std_dev().cloned(),
        coefficients: fit.coefficients().clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frf::Estimator;
    use crate::simulate::{AntiAlias, Simulator, add_noise, seed_rig};
    use crate::spectra::{Segmentation, Window};
    use rand::SeedableRng;

    /// On random records with force noise (H1 compensated for it), whatever the uncertainty
    /// the spectra were made for: the quick fit is bit for bit the fit and random error of the
    /// identification by that method with the sandwich, and the finish is the identification.
    #[test]
    fn quick_fit_and_finish_are_the_identification_s() {
        let mut sim = Simulator::new(&seed_rig(), 500.0, 16_384, AntiAlias::default()).unwrap();
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let records: Vec<Record> = (0..3)
            .map(|r| {
                let clean = sim.random_record(format!("r{r}"), 20.0, r).unwrap();
                add_noise(&clean, 0.05, &mut rng).unwrap()
            })
            .collect();
        let id = Identifier::new(8.0, 49.0)
            .estimator(Estimator::H1)
            .segmentation(Segmentation::Welch { len: 2048 })
            .window(Window::Hann);
        for uncertainty in [Uncertainty::Sandwich, Uncertainty::Auto, Uncertainty::None] {
            for method in [Method::Ivf, Method::LeastSquares] {
                let id = id.clone().uncertainty(uncertainty);
                let mut spectra = id.spectra(&records).unwrap();
                let quick = spectra.quick_fit(method).unwrap();
                let full = id
                    .clone()
                    .method(method)
                    .uncertainty(Uncertainty::Sandwich)
                    .identify(&records)
                    .unwrap();
                assert!(full.noise_floor().is_some());
                assert_eq!(&quick.coefficients, full.coefficients());
                assert_eq!(quick.random.as_ref(), full.budget().map(|b| &b.random));
                assert_eq!(quick.band, full.band());
                let longer = spectra.welch_len(&records, 4096).unwrap();
                assert_eq!(spectra.finish().unwrap(), id.identify(&records).unwrap());
                let cut = id.clone().segmentation(Segmentation::Welch { len: 4096 });
                assert_eq!(longer.finish().unwrap(), cut.identify(&records).unwrap());
            }
        }
    }

    /// Records the screening rejects (a copy of another) stay out when the spectra are cut
    /// again at another Welch length, as when the records are identified at that length.
    #[test]
    fn another_welch_length_keeps_the_screening() {
        let mut sim = Simulator::new(&seed_rig(), 500.0, 16_384, AntiAlias::default()).unwrap();
        let mut records: Vec<Record> = (0..3)
            .map(|r| sim.random_record(format!("r{r}"), 20.0, r).unwrap())
            .collect();
        let copy = records[1].clone();
        records.push(copy);
        let id = Identifier::new(8.0, 49.0)
            .estimator(Estimator::H1)
            .segmentation(Segmentation::Welch { len: 2048 })
            .window(Window::Hann)
            .screening(crate::Screening::Reject(crate::screening::Checks::default()));
        let spectra = id.spectra(&records).unwrap();
        let longer = spectra.welch_len(&records, 4096).unwrap().finish().unwrap();
        let cut = id.segmentation(Segmentation::Welch { len: 4096 });
        let direct = cut.identify(&records).unwrap();
        assert_eq!(longer, direct);
        assert!(
            direct
                .warnings()
                .iter()
                .any(|w| matches!(w, crate::Warning::Rejected { .. }))
        );
    }

    /// A first fit that cannot be made fails with the identification's error.
    #[test]
    fn quick_fit_fails_as_the_identification_does() {
        let mut sim = Simulator::new(&seed_rig(), 500.0, 4096, AntiAlias::default()).unwrap();
        let records = vec![sim.random_record("r", 20.0, 1).unwrap()];
        // Lines 0.98 Hz apart: four in 8–11 Hz, fewer than a 2-DOF fit of M, C, K needs.
        let id = Identifier::new(8.0, 11.0)
            .estimator(Estimator::H1)
            .segmentation(Segmentation::Welch { len: 512 })
            .window(Window::Hann);
        let full = id.identify(&records).unwrap_err();
        let quick = id
            .spectra(&records)
            .unwrap()
            .quick_fit(Method::Ivf)
            .unwrap_err();
        assert_eq!(quick.to_string(), full.to_string());
    }
}
