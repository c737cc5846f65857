//! The bias the processing adds and the fit cannot see, predicted from the fitted model
//! ([`crate::gate::PredictedBias`]): Welch leakage of Hann segments, truncation of impact
//! records whose response has not decayed. Above half a standard deviation of some
//! coefficient it is kept on the result and carried in the error bars; it is named in a
//! warning when it is large against them or the user can remove it.

use crate::error::{NoiseBiasBasis, Warning};
#[cfg(doc)]
use crate::frf::NoiseFloor;
use crate::frf::{Frf, FrfBuilder};
use crate::gate::{
    BiasSource, PredictedBias, leaked_flexibility, predicted_bias, truncated_flexibility, worst_in,
};
use crate::model::Coefficients;
use crate::solve::{self, Fit, Method};
use crate::spectra::{Segmentation, Window};
use crate::tolerance::{BIAS_SIGMAS, BIAS_WARN_SIGMAS, DECAYED};

use super::Settings;

impl Settings {
    /// The predicted bias of `fit` (window-corrected) on the lines of `frf`, when some
    /// coefficient's exceeds [`BIAS_SIGMAS`] of its standard deviation `std`, with its warning
    /// pushed on `warnings` when it is news:
    /// - Welch (Hann) segments leak: carried, and [`Warning::LeakageBias`] only when it passes
    ///   [`BIAS_WARN_SIGMAS`] (the Welch length was chosen to keep it small).
    /// - Whole records under no window whose slowest mode keeps more than [`DECAYED`] of its
    ///   envelope at the record's end are truncated ([`Warning::NotDecayed`], which names the
    ///   window that removes it; the response taken to start at the force's peak, the median
    ///   over the records). Carried, never corrected.
    ///
    /// Nothing is predicted for a ready-made FRF, without standard deviations or when the
    /// prediction fails (it never fails the identification).
    pub(super) fn predicted_bias(
        &self,
        frf: &Frf,
        builder: Option<&FrfBuilder>,
        fit: &Fit,
        std: Option<&Coefficients>,
        warnings: &mut Vec<Warning>,
    ) -> Option<PredictedBias> {
        let builder = builder?;
        let (len, seg_len, rate) = builder.lengths()?;
        let std = std?;
        let model = fit.coefficients();
        let freqs = frf.freqs_hz();
        let slowest = model
            .modes()
            .ok()?
            .iter()
            .map(|m| m.damping_ratio * 2.0 * std::f64::consts::PI * m.natural_frequency_hz)
            .filter(|s| s.is_finite() && *s > 0.0)
            .fold(f64::INFINITY, f64::min);
        // An impact's response runs from the hit (the force's peak) to the record's end.
        let duration = len as f64 / rate - builder.force_peak_s().unwrap_or(0.0);
        let remaining = (-slowest * duration).exp();
        let (source, processed) = match (self.segmentation, self.window) {
            (Segmentation::Welch { .. }, Window::Hann) => (
                BiasSource::Leakage,
                leaked_flexibility(model, freqs, seg_len, rate).ok()?,
            ),
            (Segmentation::WholeRecord, Window::Rectangular) if remaining > DECAYED => (
                BiasSource::Truncation,
                truncated_flexibility(model, freqs, duration).ok()?,
            ),
            _ => return None,
        };
        let bias = predicted_bias(model, freqs, processed, self.method, &self.ivf, source).ok()?;
        let (block, row, col, sigmas) = bias.worst_in(std)?;
        if sigmas <= BIAS_SIGMAS {
            return None;
        }
        let value = |c: &Coefficients| element(c, block, row, col);
        let relative = value(&bias.bias) / value(model);
        // Leakage is budget unless large; a truncation the user can remove (an exponential
        // window) is named as soon as it is carried.
        if source == BiasSource::Leakage && !news(&bias.bias, std, fit) {
            return Some(bias);
        }
        warnings.push(match source {
            BiasSource::Leakage => Warning::LeakageBias {
                spacing_hz: rate / seg_len as f64,
                block,
                row,
                col,
                relative,
                sigmas,
            },
            BiasSource::Truncation => Warning::NotDecayed {
                remaining,
                block,
                row,
                col,
                relative,
                sigmas,
                window_end: (DECAYED / remaining).min(1.0),
            },
        });
        Some(bias)
    }

    /// What the noise on the channels leaves uncertain in an H1 (or H2) fit, with
    /// [`Warning::NoiseBias`] pushed on `warnings` when it passes [`BIAS_WARN_SIGMAS`] of the
    /// random standard deviation `random` on some coefficient; nothing for ML (whose noise model
    /// has both channels) or without error bars.
    ///
    /// Noise of power $N_f$ on the forces turns H1's impedance into $(I + N_f S_{ff}^{-1}) Z$,
    /// too stiff, too heavy and too damped by the forces' noise-to-signal ratio; noise on the
    /// responses biases H2 the other way. Neither the replicates' scatter nor the model check
    /// sees this (it is the same in every segment). By what the records show ([`NoiseFloor`]):
    /// - H1 compensated for the force measurement noise the periods (or, by the user's word,
    ///   the segments) show: the change of the fit when that noise is raised by one standard
    ///   error of its estimate, always carried ([`NoiseBiasBasis::Compensation`]).
    /// - Segments that show force-side noise, left uncompensated (it may be an excitation the
    ///   force channels do not measure): the change compensation for it would make, carried
    ///   past [`BIAS_SIGMAS`]
    ///   ([`NoiseBiasBasis::ForceSide`]); nothing when the force side shows no noise, the
    ///   usual clean load cell.
    /// - Otherwise (H2, whole records, too few averages or lines): the whole bracket, the
    ///   difference between the fits on H1 and on H2 of the same spectra, the bias of the
    ///   estimator in use were all the noise on the channel it assumes clean, carried past
    ///   [`BIAS_SIGMAS`] ([`NoiseBiasBasis::Bracket`]).
    ///
    /// The other fit is made on the same lines as `frf` (after the coherence selection) with
    /// the same method.
    pub(super) fn noise_bracket(
        &self,
        frf: &Frf,
        builder: Option<&FrfBuilder>,
        fit: &Fit,
        random: Option<&Coefficients>,
        warnings: &mut Vec<Warning>,
    ) -> Option<Coefficients> {
        // Without error bars nothing is judged or carried: no refit.
        let random = random?;
        let builder = builder?;
        if self.method == Method::Ml {
            return None;
        }
        let (other, basis) = match builder.noise() {
            Some(floor) if floor.compensated() => (
                builder.finish_compensated(&floor.force_raised())?,
                NoiseBiasBasis::Compensation,
            ),
            Some(floor) => (
                builder.finish_compensated(&floor.force)?,
                NoiseBiasBasis::ForceSide,
            ),
            None => (builder.finish_bracket()?, NoiseBiasBasis::Bracket),
        };
        let other = other.ok()?;
        let kept = frf.freqs_hz();
        let other = other.retain_lines(|k| {
            kept.binary_search_by(|f| f.total_cmp(&other.freqs_hz()[k]))
                .is_ok()
        });
        let refit = self
            .corrected(solve::fit_point(&other, self.method, &self.ivf).ok()?)
            .ok()?;
        let (a, b) = (fit.coefficients().stacked(), refit.coefficients().stacked());
        let bracket =
            faer::Mat::from_fn(a.nrows(), a.ncols(), |i, j| (b[(i, j)] - a[(i, j)]).abs());
        let bracket = Coefficients::from_stacked(bracket.as_ref()).ok()?;
        let (block, row, col, sigmas) = worst_in(&bracket, random)?;
        if basis != NoiseBiasBasis::Compensation && sigmas <= BIAS_SIGMAS {
            return None;
        }
        if news(&bracket, random, fit) {
            let value = |c: &Coefficients| element(c, block, row, col);
            warnings.push(Warning::NoiseBias {
                estimator: self.estimator,
                basis,
                block,
                row,
                col,
                relative: (value(refit.coefficients()) - value(fit.coefficients()))
                    / value(fit.coefficients()),
                sigmas,
            });
        }
        Some(bracket)
    }
}

/// Whether a carried `bias` is news: past [`BIAS_WARN_SIGMAS`] of the random standard
/// deviation `random` on some coefficient, that deviation taken as at least the fit's own
/// first-order one (a jackknife over four records has three degrees of freedom: judged by it
/// alone, a bias a little under the threshold would be warned about on one seed in five).
fn news(bias: &Coefficients, random: &Coefficients, fit: &Fit) -> bool {
    let steadier = match fit.std_dev() {
        Some(first_order) => {
            let (a, b) = (random.stacked(), first_order.stacked());
            let max = faer::Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)].max(b[(i, j)]));
            Coefficients::from_stacked(max.as_ref()).unwrap_or_else(|_| random.clone())
        }
        None => random.clone(),
    };
    worst_in(bias, &steadier).is_some_and(|w| w.3 > BIAS_WARN_SIGMAS)
}

/// The element `[row][col]` of `block` of `c`.
fn element(c: &Coefficients, block: crate::Block, row: usize, col: usize) -> f64 {
    match block {
        crate::Block::Mass => c.mass()[(row, col)],
        crate::Block::Damping => c.damping()[(row, col)],
        crate::Block::Stiffness => c.stiffness()[(row, col)],
    }
}

#[cfg(test)]
mod tests {
    use crate::Identifier;
    use crate::simulate::{ImpactTest, seed_rig};

    /// Impacts cut at 0.2 s, before the response has decayed: `not_decayed`, and the predicted
    /// bias is the error the truncation makes on noise-free records (against the truth); a
    /// record of 1.2 s has decayed and raises nothing.
    #[test]
    fn impacts_cut_before_decay_warn_with_the_bias_they_make() {
        let truth = seed_rig();
        let test = ImpactTest {
            per_direction: 3,
            noise: 0.01,
            ..ImpactTest::seed_rig()
        };
        // 1340 samples: the first 0.2 s of each hit.
        let cut = |records: Vec<crate::Record>| -> Vec<crate::Record> {
            records
                .iter()
                .map(|r| r.trimmed(0..1340).unwrap())
                .collect()
        };
        let id = Identifier::new(5.0, 50.0)
            .identify(&cut(test.run(&truth).unwrap()))
            .unwrap();
        let warning = id
            .warnings()
            .iter()
            .find(|w| w.kind() == "not_decayed")
            .expect("not_decayed");
        println!("{warning}");
        let bias = id.predicted_bias().expect("predicted");
        // The bias is carried: the model component holds it, and the combined intervals
        // cover the truth on every element of K and C (the issue found K_xy +23 % at 86 σ).
        let budget = id.budget().expect("a budget");
        let std = id.std_dev().expect("error bars");
        for (b, m, sd, est, t) in [
            (
                bias.bias.stiffness(),
                budget.model.stiffness(),
                std.stiffness(),
                id.coefficients().stiffness(),
                truth.stiffness(),
            ),
            (
                bias.bias.damping(),
                budget.model.damping(),
                std.damping(),
                id.coefficients().damping(),
                truth.damping(),
            ),
        ] {
            for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                assert!(
                    m[(i, j)] >= b[(i, j)].abs(),
                    "model {} < bias {}",
                    m[(i, j)],
                    b[(i, j)]
                );
                let z = (est[(i, j)] - t[(i, j)]) / sd[(i, j)];
                println!("[{i}][{j}]: {z:+.2} combined σ");
                assert!(z.abs() < 2.5, "[{i}][{j}] {z} σ");
            }
        }
        // Noise-free, the error against the truth is the truncation's.
        let clean = ImpactTest { noise: 0.0, ..test };
        let exact = Identifier::new(5.0, 50.0)
            .identify(&cut(clean.run(&truth).unwrap()))
            .unwrap();
        let c = exact.coefficients();
        for (got, t, b) in [
            (c.stiffness(), truth.stiffness(), bias.bias.stiffness()),
            (c.damping(), truth.damping(), bias.bias.damping()),
        ] {
            for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let (error, predicted) = (got[(i, j)] - t[(i, j)], b[(i, j)]);
                println!("[{i}][{j}]: error {error:.4e}, predicted {predicted:.4e}");
                // Predicted from the noisy fit: within a third, or 0.3 % of the diagonal.
                let slack = 0.35 * error.abs() + 3e-3 * t[(i, i)].abs();
                assert!((predicted - error).abs() < slack, "{predicted} vs {error}");
            }
        }
        let id = Identifier::new(8.0, 49.0)
            .identify(&test.run(&truth).unwrap())
            .unwrap();
        assert!(id.predicted_bias().is_none());
        assert!(id.warnings().iter().all(|w| w.kind() != "not_decayed"));
    }

    /// Random records with noise on one side only. Noise on the forces (10 % of their RMS)
    /// biases H1's impedance up by the forces' noise-to-signal ratio in the band:
    /// `noise_bias` is raised, the bracket (H1 minus H2) holds the bias, and the combined
    /// error bars cover it.
    /// With the noise on the responses instead, H1 is unbiased within its random error.
    #[test]
    fn force_noise_is_bracketed_by_h1_and_h2() {
        use crate::simulate::{AntiAlias, Simulator, add_noise};
        use crate::{Estimator, Record, Window};
        use rand::SeedableRng;
        let truth = seed_rig();
        let mut sim = Simulator::new(&truth, 500.0, 32_768, AntiAlias::default()).unwrap();
        let mut rng = rand::rngs::StdRng::seed_from_u64(11);
        let (mut on_forces, mut on_responses) = (Vec::new(), Vec::new());
        for r in 0..4 {
            let clean = sim.random_record(format!("r{r}"), 20.0, 40 + r).unwrap();
            let noisy = add_noise(&clean, 0.1, &mut rng).unwrap();
            let side = |forces: &Record, responses: &Record| {
                Record::new(
                    format!("r{r}"),
                    500.0,
                    (0..2).map(|c| forces.force(c).to_vec()).collect(),
                    (0..2).map(|c| responses.displacement(c).to_vec()).collect(),
                )
                .unwrap()
            };
            on_forces.push(side(&noisy, &clean));
            on_responses.push(side(&clean, &noisy));
        }
        let id = |records: &[Record]| {
            Identifier::new(8.0, 49.0)
                .estimator(Estimator::H1)
                .window(Window::Hann)
                .identify(records)
                .unwrap()
        };
        let biased = id(&on_forces);
        assert!(
            biased.warnings().iter().any(|w| w.kind() == "noise_bias"),
            "{:?}",
            biased.warnings()
        );
        let (std, random) = (biased.std_dev().unwrap(), &biased.budget().unwrap().random);
        for i in 0..2 {
            let error = biased.coefficients().stiffness()[(i, i)] / truth.stiffness()[(i, i)] - 1.0;
            let (z_random, z) = (
                error * truth.stiffness()[(i, i)] / random.stiffness()[(i, i)],
                error * truth.stiffness()[(i, i)] / std.stiffness()[(i, i)],
            );
            println!(
                "K[{i}][{i}] {:+.3} %: {z_random:+.1} random σ, {z:+.2} combined σ",
                100.0 * error
            );
            // The bias stands out of the random error; the bracket (H2 is unbiased here, up to
            // its own random error) holds it, and the combined 95 % interval covers it.
            let bracket = biased.budget().unwrap().model.stiffness()[(i, i)];
            let sigma = random.stiffness()[(i, i)];
            assert!(z_random > 3.0, "{z_random}");
            assert!(
                bracket + 2.0 * sigma > error * truth.stiffness()[(i, i)],
                "{bracket} ± {sigma}"
            );
            assert!(z.abs() < 1.96, "{z}");
        }
        let clean = id(&on_responses);
        for i in 0..2 {
            let error = clean.coefficients().stiffness()[(i, i)] - truth.stiffness()[(i, i)];
            let z = error / clean.budget().unwrap().random.stiffness()[(i, i)];
            println!("responses noisy: K[{i}][{i}] {z:+.2} random σ");
            assert!(z.abs() < 3.0, "{z}");
        }
    }
}
