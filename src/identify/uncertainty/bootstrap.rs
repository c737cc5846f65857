//! The bootstrap over replicates: refits on replicates drawn with replacement by a seeded
//! generator, $\sigma^2 = \frac{R}{R-1}\,\mathrm{var}_b(\theta_b)$.

use crate::error::Result;
use crate::frf::Replicates;
use crate::model::Coefficients;

use super::super::Settings;
use super::spread;

impl Settings {
    /// Bootstrap standard deviations over `draws` refits (at most
    /// [`MAX_BOOTSTRAP_DRAWS`](super::MAX_BOOTSTRAP_DRAWS), checked with the settings), each
    /// on as many replicates of `shared` as it holds, drawn with replacement (seeded). A draw that cannot be fitted
    /// (it may, rarely, miss a direction altogether) is redrawn, up to `draws` times in all.
    pub(super) fn bootstrap(
        &self,
        shared: &Replicates<'_>,
        draws: usize,
        seed: u64,
    ) -> Result<Coefficients> {
        use rand::{RngExt, SeedableRng};
        let replicates = shared.count();
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let mut weights = vec![0.0; replicates];
        let mut thetas = Vec::with_capacity(draws);
        let mut failures = 0;
        while thetas.len() < draws {
            weights.fill(0.0);
            for _ in 0..replicates {
                weights[rng.random_range(0..replicates)] += 1.0;
            }
            match self.refit(shared, &weights) {
                Ok(theta) => thetas.push(theta),
                Err(e) if failures >= draws => return Err(e),
                Err(_) => failures += 1,
            }
        }
        let r = replicates as f64;
        spread(&thetas, r / (r - 1.0))
    }
}
