//! Measurement noise added to a clean record: [`add_noise`].

use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

use crate::error::{Error, Result};
use crate::records::Record;

/// Adds white Gaussian noise to a record: on every force channel with standard deviation
/// `level × RMS` of the record's force channels taken together (about their means), and
/// likewise for the displacements. An unexcited channel thus gets the same absolute noise as
/// the excited one, as in a real test.
///
/// # Errors
/// [`Error::InvalidParameter`] unless `0 ≤ level` and finite.
///
/// # Examples
/// ```
/// use bearing_ident::records::Record;
/// use bearing_ident::simulate::add_noise;
/// use rand::SeedableRng;
/// let x: Vec<f64> = (0..1000).map(|m| (m as f64 * 0.1).sin()).collect();
/// let clean = Record::new("r", 100.0, vec![x.clone()], vec![x])?;
/// let mut rng = rand::rngs::StdRng::seed_from_u64(7);
/// let noisy = add_noise(&clean, 0.1, &mut rng)?;
/// let err: f64 = noisy.force(0).iter().zip(clean.force(0)).map(|(a, b)| (a - b).powi(2)).sum();
/// let rms = (err / 1000.0).sqrt();
/// assert!((rms / (0.5f64).sqrt() - 0.1).abs() < 0.01);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn add_noise(record: &Record, level: f64, rng: &mut StdRng) -> Result<Record> {
    if !(level >= 0.0 && level.is_finite()) {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::NoiseLevel,
            value: level,
            expected: "finite and ≥ 0",
        });
    }
    let n = record.dofs();
    let rms = |channels: Vec<&[f64]>| {
        let mut sum = 0.0;
        for ch in channels {
            let mean = ch.iter().sum::<f64>() / ch.len() as f64;
            sum += ch.iter().map(|v| (v - mean).powi(2)).sum::<f64>();
        }
        (sum / (n * record.len()) as f64).sqrt()
    };
    let sf = level * rms((0..n).map(|c| record.force(c)).collect());
    let sx = level * rms((0..n).map(|c| record.displacement(c)).collect());
    let mut noisy = |ch: &[f64], sigma: f64| -> Vec<f64> {
        match Normal::new(0.0, sigma) {
            Ok(dist) if sigma > 0.0 => ch.iter().map(|v| v + dist.sample(rng)).collect(),
            _ => ch.to_vec(),
        }
    };
    let forces = (0..n).map(|c| noisy(record.force(c), sf)).collect();
    let displacements = (0..n).map(|c| noisy(record.displacement(c), sx)).collect();
    Record::new(record.label(), record.sample_rate(), forces, displacements)?
        .with_responses(record.responses().to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::{AntiAlias, Simulator, seed_rig};
    use rand::SeedableRng;

    #[test]
    fn random_forcing_and_noise_with_one_seed_are_unrelated() {
        let mut sim = Simulator::new(&seed_rig(), 1000.0, 20_000, AntiAlias::None).unwrap();
        let rec = sim.random_record("r", 1.0, 5).unwrap();
        let mut rng = StdRng::seed_from_u64(5);
        let noisy = add_noise(&rec, 1.0, &mut rng).unwrap();
        let (f, nf) = (rec.force(0), noisy.force(0));
        let noise: Vec<f64> = nf.iter().zip(f).map(|(a, b)| a - b).collect();
        let dot: f64 = noise.iter().zip(f).map(|(a, b)| a * b).sum();
        let corr = dot
            / (noise.iter().map(|v| v * v).sum::<f64>() * f.iter().map(|v| v * v).sum::<f64>())
                .sqrt();
        // Independent streams: |ρ| ~ 1/√20000 ≈ 0.007.
        assert!(corr.abs() < 0.03, "correlation {corr}");
    }
}
