//! Interference lines: a line of a force channel that stands far above its neighbours with no
//! response to match (mains hum picked up by the force transducer's cable or amplifier).
//!
//! A force the structure feels moves it: at a real force peak the responses rise with it and
//! the multiple coherence stays where its neighbours' is. Hum in the force *measurement* is not
//! felt: the force auto-spectrum rises at its line, the responses do not, and the coherence
//! drops. The test, per band line `k` of a cross-spectral estimate, with `r_c(k)` the ratio of
//! force channel `c`'s auto-spectrum `S_{f_c f_c}` to its median over the
//! [`INTERFERENCE_NEIGHBOURS`] lines on each side and `γ²(k)` the smallest multiple coherence of
//! the responses:
//!
//! $$\max_c r_c(k) \ge R \quad\text{and}\quad \gamma^2(k) < D \cdot \operatorname{median}_{\text{neighbours}} \gamma^2,$$
//!
//! `R` = [`INTERFERENCE_RATIO`], `D` =
//! [`INTERFERENCE_COHERENCE_DIP`]. The window
//! spreads a sine over adjacent lines: next to a line found, lines whose force ratio is still
//! above [`INTERFERENCE_SPREAD`] go with it, and
//! [`INTERFERENCE_GUARD`] lines beyond them on each side
//! (a sine's leakage there is below its random scatter, yet biased).

use crate::statistics::median;
use crate::tolerance::{
    INTERFERENCE_COHERENCE_DIP, INTERFERENCE_GUARD, INTERFERENCE_RATIO, INTERFERENCE_SPREAD,
};

/// Lines on each side of a line whose medians it is compared with.
pub const INTERFERENCE_NEIGHBOURS: usize = 8;

/// One run of adjacent interference lines.
#[derive(Debug, Clone, PartialEq)]
pub struct Interference {
    /// Index of the line where the force stands highest above its neighbours.
    pub peak: usize,
    /// The indices of every line of the run (the peak and the window's spread), ascending.
    pub lines: Vec<usize>,
    /// The force channel.
    pub channel: usize,
    /// Its auto-spectrum at the peak over the neighbours' median.
    pub ratio: f64,
}

/// The interference lines of a cross-spectral estimate: `force[k][c]` the auto-spectrum of
/// force channel `c` at line `k`, `coherence[k]` the smallest multiple coherence of the
/// responses there (see the module docs). Fewer than `2·`[`INTERFERENCE_NEIGHBOURS`]` + 1`
/// lines judge nothing.
///
/// # Examples
/// ```
/// use bearing_ident::frf::interference::interference_lines;
/// // A flat force with one line 100 × its neighbours and the coherence dropping there.
/// let force: Vec<Vec<f64>> = (0..40).map(|k| vec![if k == 20 { 100.0 } else { 1.0 }]).collect();
/// let coherence: Vec<f64> = (0..40).map(|k| if k == 20 { 0.05 } else { 0.95 }).collect();
/// let found = interference_lines(&force, &coherence);
/// assert_eq!(found.len(), 1);
/// assert_eq!((found[0].peak, found[0].ratio), (20, 100.0));
/// ```
pub fn interference_lines(force: &[Vec<f64>], coherence: &[f64]) -> Vec<Interference> {
    let lines = force.len().min(coherence.len());
    let w = INTERFERENCE_NEIGHBOURS;
    if lines < 2 * w + 1 {
        return Vec::new();
    }
    let channels = force.first().map_or(0, Vec::len);
    // Neighbours of k: w lines on each side, shifted inwards at the band's edges.
    let neighbours = |k: usize| {
        let start = k.saturating_sub(w).min(lines - 2 * w - 1);
        (start..start + 2 * w + 1).filter(move |&j| j != k)
    };
    let ratio = |k: usize, c: usize| -> f64 {
        let mut around: Vec<f64> = neighbours(k).map(|j| force[j][c]).collect();
        match median(&mut around) {
            Some(m) if m > 0.0 => force[k][c] / m,
            _ => 0.0,
        }
    };
    let best = |k: usize| -> (usize, f64) {
        (0..channels)
            .map(|c| (c, ratio(k, c)))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
    };
    let mut found: Vec<Interference> = Vec::new();
    for k in 0..lines {
        let (channel, r) = best(k);
        let stands_out = r >= INTERFERENCE_RATIO;
        if !stands_out {
            continue;
        }
        let mut around: Vec<f64> = neighbours(k).map(|j| coherence[j]).collect();
        let dips =
            median(&mut around).is_some_and(|m| coherence[k] < INTERFERENCE_COHERENCE_DIP * m);
        if !dips {
            continue;
        }
        if let Some(last) = found.last_mut()
            && last.lines.last().is_some_and(|&l| l + 1 >= k)
        {
            if r > last.ratio {
                (last.peak, last.channel, last.ratio) = (k, channel, r);
            }
            if !last.lines.contains(&k) {
                last.lines.push(k);
            }
            continue;
        }
        found.push(Interference {
            peak: k,
            lines: vec![k],
            channel,
            ratio: r,
        });
    }
    // The window's spread: adjacent lines still well above their neighbours go too.
    for run in &mut found {
        let spread = |k: usize| ratio(k, run.channel) >= INTERFERENCE_SPREAD;
        let mut lo = run.lines[0];
        while lo > 0 && spread(lo - 1) {
            lo -= 1;
        }
        let mut hi = *run.lines.last().unwrap_or(&lo);
        while hi + 1 < lines && spread(hi + 1) {
            hi += 1;
        }
        let lo = lo.saturating_sub(INTERFERENCE_GUARD);
        let hi = (hi + INTERFERENCE_GUARD).min(lines - 1);
        run.lines = (lo..=hi).collect();
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_force_peak_the_responses_follow_is_no_interference() {
        let force: Vec<Vec<f64>> = (0..40)
            .map(|k| vec![1.0, if k == 12 { 50.0 } else { 2.0 }])
            .collect();
        // The coherence does not dip: the structure felt the force.
        assert!(interference_lines(&force, &[0.9; 40]).is_empty());
        // Hum on channel 1, spread by the window to its neighbours at 5 × and 3 ×.
        let mut force = force;
        force[11][1] = 10.0;
        force[13][1] = 6.0;
        let coherence: Vec<f64> = (0..40).map(|k| if k == 12 { 0.1 } else { 0.9 }).collect();
        let found = interference_lines(&force, &coherence);
        assert_eq!(found.len(), 1);
        assert_eq!((found[0].peak, found[0].channel), (12, 1));
        let guard = INTERFERENCE_GUARD;
        assert_eq!(
            found[0].lines,
            (11 - guard..=13 + guard).collect::<Vec<_>>()
        );
        // Too few lines to judge.
        assert!(interference_lines(&force[..16], &coherence[..16]).is_empty());
    }
}
