//! The jackknife over replicates: each paired set (paired sets) or record (cross-spectral
//! estimators) left out in turn, $\sigma^2 = \frac{R-1}{R}\sum_r (\theta_{(-r)} - \bar\theta)^2$.

use crate::error::Result;
use crate::frf::{Frf, FrfBuilder};
use crate::gate;
use crate::model::Coefficients;

use super::super::Settings;
use super::spread;

impl Settings {
    /// Jackknife standard deviations over `replicates` leave-one-out refits, each on the same
    /// lines as `frf` (the full data's, after any coherence selection), and the number of
    /// distinct refits ([`gate::distinct_fits`]).
    pub(super) fn jackknife(
        &self,
        builder: &FrfBuilder,
        frf: &Frf,
        replicates: usize,
    ) -> Result<(Coefficients, usize)> {
        let mut weights = vec![1.0; replicates];
        let mut thetas = Vec::with_capacity(replicates);
        for r in 0..replicates {
            weights[r] = 0.0;
            thetas.push(self.refit(builder, frf, &weights)?);
            weights[r] = 1.0;
        }
        let r = replicates as f64;
        Ok((spread(&thetas, r - 1.0)?, gate::distinct_fits(&thetas)))
    }
}
