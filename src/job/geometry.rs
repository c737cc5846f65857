//! Sensor planes to the bearing plane: a rigid rotor whose motion near the bearing is a
//! conical mode about a pivot, measured by probes at other axial positions (and perhaps driven
//! at another plane), moved to the bearing plane before any spectrum is taken.

use crate::error::{Error, Parameter, Result};
use crate::records::{Record, conical_to_bearing};

/// Where the probes and forces sit along the shaft, and the bearing plane their channels are
/// moved to, for a rigid rotor tilting about a pivot (a conical mode). Positions in m from one
/// datum.
///
/// A probe at `z_s` sees `x_s = x_B (z_s − z_p)/(z_B − z_p)` of the bearing plane's `x_B`; a
/// force `F` at `z_f` does the virtual work of `F_B = F (z_f − z_p)/(z_B − z_p)` at the
/// bearing plane. So each response channel is scaled by `(z_B − z_p)/(z_s − z_p)` and each
/// force channel by `(z_f − z_p)/(z_B − z_p)`, and the impedance identified from the moved
/// channels is the bearing plane's.
///
/// # Examples
/// ```
/// use bearing_ident::Record;
/// use bearing_ident::job::Geometry;
/// // The seed rig: pivot at 0, damper at 151 mm, probes at 213 and 254 mm.
/// let g = Geometry::conical(0.0, 0.151, vec![0.213, 0.254], None)?;
/// let r = Record::new("hit", 100.0, vec![vec![2.0; 8]; 2], vec![vec![0.213; 8], vec![0.254; 8]])?;
/// let at_bearing = g.apply(r)?;
/// assert!((at_bearing.displacement(0)[0] - 0.151).abs() < 1e-15);
/// assert!((at_bearing.displacement(1)[5] - 0.151).abs() < 1e-15);
/// assert_eq!(at_bearing.force(0)[0], 2.0); // forces at the bearing plane: unchanged
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    pivot: f64,
    bearing: f64,
    probes: Vec<f64>,
    forces: Option<Vec<f64>>,
}

impl Geometry {
    /// A conical mode about `pivot`, moving the response channels measured at `probes` (one
    /// per response channel, in order) and the forces applied at `forces` (one per force
    /// channel; `None`: at the bearing plane) to the plane `bearing`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a position that is not finite, no probe, or a probe or
    /// force plane at the pivot, or a bearing plane at the pivot (nothing moves there).
    pub fn conical(
        pivot: f64,
        bearing: f64,
        probes: Vec<f64>,
        forces: Option<Vec<f64>>,
    ) -> Result<Self> {
        let bad = |name, value, expected| Error::InvalidParameter {
            name,
            value,
            expected,
        };
        for (name, z) in [
            (Parameter::GeometryPivot, pivot),
            (Parameter::GeometryBearing, bearing),
        ]
        .into_iter()
        .chain(probes.iter().map(|&z| (Parameter::GeometryProbes, z)))
        .chain(
            forces
                .iter()
                .flatten()
                .map(|&z| (Parameter::GeometryForces, z)),
        ) {
            if !z.is_finite() {
                return Err(bad(name, z, "a finite axial position (m)"));
            }
        }
        if probes.is_empty() {
            return Err(bad(
                Parameter::GeometryProbes,
                0.0,
                "one position per response channel",
            ));
        }
        let coincide = |a: f64, b: f64| (a - b).abs() < f64::MIN_POSITIVE;
        if coincide(bearing, pivot) {
            return Err(bad(
                Parameter::GeometryBearing,
                bearing,
                "a bearing plane away from the pivot (it does not move there)",
            ));
        }
        let at_pivot = |z: &&f64| coincide(**z, pivot);
        if let Some(&z) = probes.iter().find(at_pivot) {
            return Err(bad(
                Parameter::GeometryProbes,
                z,
                "probes away from the pivot (a probe there sees no motion)",
            ));
        }
        if let Some(&z) = forces.iter().flatten().find(at_pivot) {
            return Err(bad(
                Parameter::GeometryForces,
                z,
                "forces away from the pivot (a force there does no work)",
            ));
        }
        Ok(Self {
            pivot,
            bearing,
            probes,
            forces,
        })
    }

    /// The pivot (m).
    pub fn pivot(&self) -> f64 {
        self.pivot
    }

    /// The bearing plane (m).
    pub fn bearing(&self) -> f64 {
        self.bearing
    }

    /// The probes' planes (m), one per response channel.
    pub fn probes(&self) -> &[f64] {
        &self.probes
    }

    /// The forces' planes (m), one per force channel, if not at the bearing plane.
    pub fn forces(&self) -> Option<&[f64]> {
        self.forces.as_deref()
    }

    /// The factor response channel `i` is multiplied by: `(z_B − z_p)/(z_s − z_p)`.
    pub fn response_factor(&self, i: usize) -> f64 {
        (self.bearing - self.pivot) / (self.probes[i] - self.pivot)
    }

    /// The factor force channel `i` is multiplied by: `(z_f − z_p)/(z_B − z_p)` (1 without
    /// force planes).
    pub fn force_factor(&self, i: usize) -> f64 {
        self.forces
            .as_ref()
            .map_or(1.0, |f| (f[i] - self.pivot) / (self.bearing - self.pivot))
    }

    /// `record` with its channels moved to the bearing plane (label, rate and response kinds
    /// kept).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when the record has another number of response channels than
    /// probes, or of force channels than force planes; [`Error::InvalidParameter`] for a
    /// moved sample that is not finite.
    pub fn apply(&self, record: Record) -> Result<Record> {
        let n = record.dofs();
        let counts = [
            (
                self.probes.len(),
                "geometry probes (one per response channel)",
            ),
            (
                self.forces.as_ref().map_or(n, Vec::len),
                "geometry forces (one per force channel)",
            ),
        ];
        for (count, what) in counts {
            if count != n {
                return Err(Error::InvalidOption {
                    option: "geometry",
                    message: format!(
                        "record `{}` has {n} channels of each kind but {count} {what}",
                        crate::error::excerpt(record.label())
                    ),
                });
            }
        }
        let responses = (0..n)
            .map(|i| {
                conical_to_bearing(
                    record.displacement(i),
                    self.probes[i],
                    self.pivot,
                    self.bearing,
                )
            })
            .collect::<Result<Vec<_>>>()?;
        let forces = (0..n)
            .map(|i| {
                let k = self.force_factor(i);
                record.force(i).iter().map(|f| f * k).collect()
            })
            .collect();
        let kinds = record.responses().to_vec();
        Record::new(record.label(), record.sample_rate(), forces, responses)?.with_responses(kinds)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The impedance from the moved channels is the bearing plane's: a probe at twice the
    /// bearing's distance from the pivot and a force at three times it give
    /// `Z_B = Z_s · 3 · 2`.
    #[test]
    fn factors_follow_the_lever_arms() {
        let g = Geometry::conical(0.1, 0.2, vec![0.3, 0.3], Some(vec![0.4, 0.1 + 1e-3])).unwrap();
        assert!((g.response_factor(0) - 0.5).abs() < 1e-15);
        assert!((g.force_factor(0) - 3.0).abs() < 1e-12);
        let z_s = 1.0; // force over probe displacement
        let z_b = z_s * g.force_factor(0) / g.response_factor(0);
        assert!((z_b - 6.0).abs() < 1e-12);
    }

    /// Noise-free hits on a known system, measured at probes beyond the bearing and driven at
    /// a force plane off it, come back to the bearing plane's coefficients: the lever arms
    /// undone exactly.
    #[test]
    fn the_bearing_plane_is_recovered() {
        use crate::job::{Channels, Job, Options};
        use crate::simulate::{ImpactTest, seed_rig};
        let (pivot, bearing) = (0.0, 0.151);
        let (probes, forces) = ([0.213, 0.254], [0.18, 0.12]);
        let g = Geometry::conical(pivot, bearing, probes.to_vec(), Some(forces.to_vec())).unwrap();
        let truth = seed_rig();
        let hits = ImpactTest {
            per_direction: 2,
            ..ImpactTest::seed_rig()
        }
        .run(&truth)
        .unwrap();
        // As measured: the probe sees x_B (z_s − z_p)/(z_B − z_p); the hammer at z_f applies
        // F with F_B = F (z_f − z_p)/(z_B − z_p), so the force channel reads F_B over that.
        let measured: Vec<Record> = hits
            .iter()
            .map(|r| {
                let f = (0..2)
                    .map(|i| r.force(i).iter().map(|v| v / g.force_factor(i)).collect())
                    .collect();
                let x = (0..2)
                    .map(|i| {
                        r.displacement(i)
                            .iter()
                            .map(|v| v / g.response_factor(i))
                            .collect()
                    })
                    .collect();
                Record::new(r.label(), r.sample_rate(), f, x).unwrap()
            })
            .collect();
        let channels = Channels {
            geometry: Some(g),
            ..Channels::default()
        };
        let job = Job::new(Options::new(8.0, 49.0), channels);
        let id = job.run_records(measured.clone()).unwrap();
        let got = id.identification().coefficients();
        for (a, b) in [
            (got.mass(), truth.mass()),
            (got.damping(), truth.damping()),
            (got.stiffness(), truth.stiffness()),
        ] {
            for i in 0..2 {
                for j in 0..2 {
                    let scale = b[(i, i)].abs();
                    assert!(
                        (a[(i, j)] - b[(i, j)]).abs() < 1e-6 * scale,
                        "{i}{j}: {} vs {}",
                        a[(i, j)],
                        b[(i, j)]
                    );
                }
            }
        }
        // Without the geometry the probes' impedance is another: K_xx off by the lever arms.
        let plain = Job::new(Options::new(8.0, 49.0), Channels::default())
            .run_records(measured)
            .unwrap();
        let k = plain.identification().coefficients().stiffness()[(0, 0)];
        let arms = g_factor(0.213, 0.18);
        assert!(
            (k * arms / truth.stiffness()[(0, 0)] - 1.0).abs() < 1e-6,
            "{k}"
        );
    }

    /// `Z_B / Z_s` for a probe at `zs` and a force at `zf` (pivot 0, bearing 0.151).
    fn g_factor(zs: f64, zf: f64) -> f64 {
        (zf / 0.151) * (zs / 0.151)
    }

    /// Every bad geometry is refused naming the key; a record of the wrong width too.
    #[test]
    fn bad_geometry_is_refused() {
        let name = |e: Error| match e {
            Error::InvalidParameter { name, .. } => name,
            e => panic!("{e}"),
        };
        assert_eq!(
            name(Geometry::conical(0.0, 0.1, vec![0.0], None).unwrap_err()),
            Parameter::GeometryProbes
        );
        assert_eq!(
            name(Geometry::conical(0.0, 0.0, vec![0.2], None).unwrap_err()),
            Parameter::GeometryBearing
        );
        assert_eq!(
            name(Geometry::conical(f64::NAN, 0.1, vec![0.2], None).unwrap_err()),
            Parameter::GeometryPivot
        );
        assert_eq!(
            name(Geometry::conical(0.0, 0.1, vec![0.2], Some(vec![0.0])).unwrap_err()),
            Parameter::GeometryForces
        );
        assert_eq!(
            name(Geometry::conical(0.0, 0.1, vec![], None).unwrap_err()),
            Parameter::GeometryProbes
        );
        let g = Geometry::conical(0.0, 0.1, vec![0.2], None).unwrap();
        let r = Record::new("r", 10.0, vec![vec![1.0; 8]; 2], vec![vec![1.0; 8]; 2]).unwrap();
        assert_eq!(g.apply(r).unwrap_err().kind(), "invalid_argument");
    }
}
