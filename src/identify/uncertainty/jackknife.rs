//! The jackknife over replicates: each paired set (paired sets) or record (cross-spectral
//! estimators) left out in turn, $\sigma^2 = \frac{R-1}{R}\sum_r (\theta_{(-r)} - \bar\theta)^2$.

use crate::error::Result;
use crate::frf::Replicates;
use crate::gate;
use crate::model::Coefficients;

use super::super::Settings;
use super::spread;

impl Settings {
    /// Jackknife standard deviations over the leave-one-out refits of `shared`, each on the
    /// full data's lines (after any coherence selection), and the number of distinct refits
    /// ([`gate::distinct_fits`]).
    /// Each refit's data are the sums over every replicate less the one left out
    /// ([`Replicates::without`]), so that the `R` refits cost one pass over the replicates, not
    /// `R`.
    pub(super) fn jackknife(&self, shared: &Replicates<'_>) -> Result<(Coefficients, usize)> {
        let replicates = shared.count();
        let totals = shared.totals();
        let thetas = (0..replicates)
            .map(|r| self.fit_replicate(&shared.without(&totals, r)))
            .collect::<Result<Vec<_>>>()?;
        let r = replicates as f64;
        Ok((spread(&thetas, r - 1.0)?, gate::distinct_fits(&thetas)))
    }
}
