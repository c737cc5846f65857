//! Synchronous coefficients ([`Synchronous`]): the frequency-dependent `K(ω)`, `C(ω)`
//! evaluated at the excitation frequency equal to the rotor speed.

use faer::Mat;

use crate::element::ElementModel;
use crate::per_frequency::PerFrequency;

/// Where synchronous coefficients come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum SyncSource {
    /// The per-line values, interpolated linearly between the two lines about the speed.
    Lines,
    /// The fitted element model's curve ([`ElementModel::curve_at`]).
    Model,
}

impl SyncSource {
    /// `lines` or `model`.
    pub fn name(self) -> &'static str {
        match self {
            SyncSource::Lines => "lines",
            SyncSource::Model => "model",
        }
    }
}

/// `K(ω)` and `C(ω)` at `ω = Ω`, the rotor speed, with their standard deviations.
///
/// From the per-line values ([`Synchronous::from_lines`]) between lines `f_a ≤ f ≤ f_b`,
/// `t = (f − f_a)/(f_b − f_a)`: `K = (1 − t) K_a + t K_b`, `σ² = (1 − t)² σ_a² + t² σ_b²`
/// (the lines' errors independent); on a line (within
/// [`SYNCHRONOUS_LINE`](crate::tolerance::SYNCHRONOUS_LINE) of a spacing), its own values. From an element model
/// ([`Synchronous::from_model`]): its curve at `f`.
#[derive(Debug, Clone, PartialEq)]
pub struct Synchronous {
    /// The excitation frequency (Hz), the speed in revolutions per second.
    pub frequency_hz: f64,
    /// `K(ω)` (N/m).
    pub stiffness: Mat<f64>,
    /// `C(ω)` (N·s/m).
    pub damping: Mat<f64>,
    /// The standard deviations of `K(ω)` (`None` where the lines carry none).
    pub stiffness_std: Option<Mat<f64>>,
    /// The standard deviations of `C(ω)`.
    pub damping_std: Option<Mat<f64>>,
    /// Where they come from.
    pub source: SyncSource,
}

impl Synchronous {
    /// The per-line values at `frequency_hz`, interpolated; `None` outside the lines' span.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::rotor::Synchronous;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 2, noise: 0.02, ..ImpactTest::seed_rig() }
    ///     .run(&seed_rig())?;
    /// let pf = Identifier::new(8.0, 49.0).identify(&records)?.per_frequency()?;
    /// let f = pf.freqs_hz()[10];
    /// let s = Synchronous::from_lines(&pf, f).unwrap();
    /// assert_eq!(s.stiffness[(0, 0)], pf.stiffness(10)[(0, 0)]);
    /// assert!(Synchronous::from_lines(&pf, 60.0).is_none());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn from_lines(pf: &PerFrequency, frequency_hz: f64) -> Option<Self> {
        let f = pf.freqs_hz();
        let (first, last) = (f[0], f[f.len() - 1]);
        let spacing = if f.len() > 1 {
            (last - first) / (f.len() - 1) as f64
        } else {
            0.0
        };
        let slack = crate::tolerance::SYNCHRONOUS_LINE * spacing;
        if !(frequency_hz >= first - slack && frequency_hz <= last + slack) {
            return None;
        }
        // The line at the speed, or the two about it.
        let (a, b, t) = match f.iter().position(|&x| (x - frequency_hz).abs() <= slack) {
            Some(k) => (k, k, 0.0),
            None => {
                let b = f.iter().position(|&x| x > frequency_hz)?;
                (b - 1, b, (frequency_hz - f[b - 1]) / (f[b] - f[b - 1]))
            }
        };
        let mix = |x: faer::MatRef<'_, f64>, y: faer::MatRef<'_, f64>| {
            Mat::from_fn(x.nrows(), x.ncols(), |i, j| {
                if t == 0.0 {
                    x[(i, j)]
                } else {
                    (1.0 - t) * x[(i, j)] + t * y[(i, j)]
                }
            })
        };
        let mix_std = |x: Option<faer::MatRef<'_, f64>>, y: Option<faer::MatRef<'_, f64>>| {
            let (x, y) = (x?, y?);
            Some(Mat::from_fn(x.nrows(), x.ncols(), |i, j| {
                if t == 0.0 {
                    x[(i, j)]
                } else {
                    ((1.0 - t).powi(2) * x[(i, j)].powi(2) + t * t * y[(i, j)].powi(2)).sqrt()
                }
            }))
        };
        Some(Self {
            frequency_hz,
            stiffness: mix(pf.stiffness(a), pf.stiffness(b)),
            damping: mix(pf.damping(a), pf.damping(b)),
            stiffness_std: mix_std(pf.stiffness_std(a), pf.stiffness_std(b)),
            damping_std: mix_std(pf.damping_std(a), pf.damping_std(b)),
            source: SyncSource::Lines,
        })
    }

    /// The element model's `K(ω)`, `C(ω)` at `frequency_hz`.
    pub fn from_model(model: &ElementModel, frequency_hz: f64) -> Self {
        let mut curve = model.curve_at(&[frequency_hz]);
        let finite = |m: Mat<f64>| {
            let all = (0..m.nrows()).all(|i| (0..m.ncols()).all(|j| m[(i, j)].is_finite()));
            all.then_some(m)
        };
        Self {
            frequency_hz,
            stiffness: curve.stiffness.remove(0),
            damping: curve.damping.remove(0),
            stiffness_std: finite(curve.stiffness_std.remove(0)),
            damping_std: finite(curve.damping_std.remove(0)),
            source: SyncSource::Model,
        }
    }

    /// These values less constant `stiffness` and `damping` (a dry structure's), whose
    /// standard deviations `stiffness_std`, `damping_std` add in quadrature.
    #[cfg(feature = "job")]
    pub(crate) fn less(
        mut self,
        stiffness: faer::MatRef<'_, f64>,
        damping: faer::MatRef<'_, f64>,
        std: Option<(faer::MatRef<'_, f64>, faer::MatRef<'_, f64>)>,
    ) -> Self {
        let n = self.stiffness.nrows();
        for i in 0..n {
            for j in 0..n {
                self.stiffness[(i, j)] -= stiffness[(i, j)];
                self.damping[(i, j)] -= damping[(i, j)];
            }
        }
        let add = |s: &mut Option<Mat<f64>>, extra: Option<faer::MatRef<'_, f64>>| {
            if let (Some(s), Some(e)) = (s.as_mut(), extra) {
                for i in 0..n {
                    for j in 0..n {
                        s[(i, j)] = s[(i, j)].hypot(e[(i, j)]);
                    }
                }
            }
        };
        add(&mut self.stiffness_std, std.map(|s| s.0));
        add(&mut self.damping_std, std.map(|s| s.1));
        self
    }
}

#[cfg(feature = "serde")]
/// `{frequency_hz, K, C, K_std, C_std, source}`, matrices as rows.
impl serde::Serialize for Synchronous {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use crate::model::rows;
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(6))?;
        m.serialize_entry("frequency_hz", &self.frequency_hz)?;
        m.serialize_entry("K", &rows(self.stiffness.as_ref()))?;
        m.serialize_entry("C", &rows(self.damping.as_ref()))?;
        m.serialize_entry(
            "K_std",
            &self.stiffness_std.as_ref().map(|x| rows(x.as_ref())),
        )?;
        m.serialize_entry(
            "C_std",
            &self.damping_std.as_ref().map(|x| rows(x.as_ref())),
        )?;
        m.serialize_entry("source", self.source.name())?;
        m.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Identifier;
    use crate::simulate::{ImpactTest, seed_rig};

    /// At a line, the line's own values and σ; halfway between two lines, their mean and
    /// `σ = ½√(σ_a² + σ_b²)`; outside the lines, none.
    #[test]
    fn lines_are_kept_and_interpolated() {
        let records = ImpactTest {
            per_direction: 2,
            noise: 0.02,
            ..ImpactTest::seed_rig()
        }
        .run(&seed_rig())
        .unwrap();
        let pf = Identifier::new(8.0, 49.0)
            .identify(&records)
            .unwrap()
            .per_frequency()
            .unwrap();
        let f = pf.freqs_hz();
        for k in [0, 17, f.len() - 1] {
            let s = Synchronous::from_lines(&pf, f[k]).unwrap();
            assert_eq!(s.stiffness, pf.stiffness(k).to_owned());
            assert_eq!(s.damping, pf.damping(k).to_owned());
            assert_eq!(
                s.damping_std.unwrap(),
                pf.damping_std(k).unwrap().to_owned()
            );
        }
        let mid = Synchronous::from_lines(&pf, 0.5 * (f[5] + f[6])).unwrap();
        let mean = 0.5 * (pf.stiffness(5)[(0, 1)] + pf.stiffness(6)[(0, 1)]);
        assert!((mid.stiffness[(0, 1)] - mean).abs() <= 1e-12 * mean.abs());
        let (a, b) = (
            pf.stiffness_std(5).unwrap()[(0, 1)],
            pf.stiffness_std(6).unwrap()[(0, 1)],
        );
        let s = mid.stiffness_std.unwrap()[(0, 1)];
        assert!((s - 0.5 * a.hypot(b)).abs() <= 1e-12 * s);
        assert!(Synchronous::from_lines(&pf, f[0] - 0.1).is_none());
        assert!(Synchronous::from_lines(&pf, f[f.len() - 1] + 0.1).is_none());
    }
}
