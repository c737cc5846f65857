//! Sensor planes to the bearing plane for a rigid rotor: a conical mode about a pivot,
//! measured by probes at other axial positions (and perhaps driven at another plane), or the
//! motion measured at two planes per direction and interpolated (or extrapolated) to the
//! bearing plane; moved there before any spectrum is taken.

use crate::Choice;
use std::borrow::Cow;

use crate::error::{Error, Parameter, Result};
use crate::io::CsvLayout;
use crate::records::{Record, conical_to_bearing, two_plane_to_bearing};

/// Where the probes (and forces) sit along the shaft, and the bearing plane their channels are
/// moved to, for a rigid rotor. Positions in m from one datum.
///
/// **Conical** ([`Geometry::conical`]): the rotor tilts about a pivot `z_p`. A probe at `z_s`
/// sees `x_s = x_B (z_s − z_p)/(z_B − z_p)` of the bearing plane's `x_B`; a force `F` at
/// `z_f` does the virtual work of `F_B = F (z_f − z_p)/(z_B − z_p)` at the bearing plane. So
/// each response channel is scaled by `(z_B − z_p)/(z_s − z_p)` and each force channel by
/// `(z_f − z_p)/(z_B − z_p)`, and the impedance identified from the moved channels is the
/// bearing plane's.
///
/// **Two-plane** ([`Geometry::two_plane`]): each direction is measured at two planes `z_1 ≠ z_2`
/// and a rigid shaft's motion is linear along its axis, so
/// `x_B = x_1 + (x_2 − x_1)(z_B − z_1)/(z_2 − z_1)` at any bearing plane, between the probes or
/// beyond them, with no pivot. The `2n` response channels (the first plane's `n` directions,
/// then the second's, as `--disp x1,y1,x2,y2`) become `n`; the forces act at the bearing plane.
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
    bearing: f64,
    probes: Vec<f64>,
    mode: Mode,
}

/// How the probes' planes reach the bearing plane.
#[derive(Debug, Clone, PartialEq)]
enum Mode {
    /// A conical mode about `pivot`, forces at `forces` (`None`: at the bearing plane).
    Conical {
        pivot: f64,
        forces: Option<Vec<f64>>,
    },
    /// Two planes per direction, interpolated linearly.
    TwoPlane,
}

/// [`Error::InvalidParameter`] naming a geometry key.
fn bad(name: Parameter, value: f64, expected: &'static str) -> Error {
    Error::InvalidParameter {
        name,
        value,
        expected,
    }
}

/// The first position that is not finite, refused naming its key.
fn finite(positions: impl IntoIterator<Item = (Parameter, f64)>) -> Result<()> {
    match positions.into_iter().find(|(_, z)| !z.is_finite()) {
        Some((name, z)) => Err(bad(name, z, "a finite axial position (m)")),
        None => Ok(()),
    }
}

/// Whether two positions are one plane.
fn coincide(a: f64, b: f64) -> bool {
    (a - b).abs() < f64::MIN_POSITIVE
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
        finite(
            [
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
            ),
        )?;
        if probes.is_empty() {
            return Err(bad(
                Parameter::GeometryProbes,
                0.0,
                "one position per response channel",
            ));
        }
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
            bearing,
            probes,
            mode: Mode::Conical { pivot, forces },
        })
    }

    /// Two measurement planes per direction, moved to the plane `bearing` by a rigid shaft's
    /// linear motion: `probes` holds one position per response channel, the first plane's `n`
    /// directions then the second's (as `--disp x1,y1,x2,y2` reads them), so direction `d` is
    /// measured at `probes[d]` and `probes[d + n]`. The forces act at the bearing plane.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming [`Parameter::GeometryBearing`] or
    /// [`Parameter::GeometryProbes`] for a position that is not finite, an odd or zero number
    /// of probes, or a direction whose two planes coincide.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Record;
    /// use bearing_ident::job::Geometry;
    /// // x and y at 213 and 254 mm, the damper at 151 mm: extrapolated past the nearer plane.
    /// let g = Geometry::two_plane(0.151, vec![0.213, 0.213, 0.254, 0.254])?;
    /// // A tilt about z = 0 (x = z) and a parallel shift of y by 1: x_B = 0.151, y_B = 1.
    /// let (x1, y1, x2, y2) = (vec![0.213; 8], vec![1.0; 8], vec![0.254; 8], vec![1.0; 8]);
    /// let r = Record::new("hit", 100.0, vec![vec![2.0; 8]; 4], vec![x1, y1, x2, y2])?;
    /// let at_bearing = g.apply(r)?;
    /// assert_eq!(at_bearing.dofs(), 2);
    /// assert!((at_bearing.displacement(0)[0] - 0.151).abs() < 1e-15);
    /// assert!((at_bearing.displacement(1)[3] - 1.0).abs() < 1e-15);
    /// assert!(Geometry::two_plane(0.151, vec![0.213, 0.22, 0.254, 0.26]).is_ok()); // y apart
    /// assert!(Geometry::two_plane(0.151, vec![0.213, 0.2, 0.213, 0.3]).is_err()); // x: one plane
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn two_plane(bearing: f64, probes: Vec<f64>) -> Result<Self> {
        finite(
            std::iter::once((Parameter::GeometryBearing, bearing))
                .chain(probes.iter().map(|&z| (Parameter::GeometryProbes, z))),
        )?;
        if probes.is_empty() || probes.len() % 2 != 0 {
            return Err(bad(
                Parameter::GeometryProbes,
                probes.len() as f64,
                "two positions per direction, an even count: the first plane's probes, then \
                 the second's, in response channel order",
            ));
        }
        let n = probes.len() / 2;
        if let Some(d) = (0..n).find(|&d| coincide(probes[d], probes[d + n])) {
            return Err(bad(
                Parameter::GeometryProbes,
                probes[d],
                "two distinct planes per direction (probes d and d + n coincide)",
            ));
        }
        Ok(Self {
            bearing,
            probes,
            mode: Mode::TwoPlane,
        })
    }

    /// Whether the geometry measures each direction at two planes ([`Geometry::two_plane`]).
    pub fn is_two_plane(&self) -> bool {
        self.mode == Mode::TwoPlane
    }

    /// The pivot (m) of a conical mode; `None` for two planes.
    pub fn pivot(&self) -> Option<f64> {
        match self.mode {
            Mode::Conical { pivot, .. } => Some(pivot),
            Mode::TwoPlane => None,
        }
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
        match &self.mode {
            Mode::Conical { forces, .. } => forces.as_deref(),
            Mode::TwoPlane => None,
        }
    }

    /// The weight of response channel `i` in its direction's motion at the bearing plane:
    /// conical, `(z_B − z_p)/(z_s − z_p)`; two-plane, `(z_2 − z_B)/(z_2 − z_1)` for a probe at
    /// the first plane `z_1` and `(z_B − z_1)/(z_2 − z_1)` for one at the second `z_2` (the
    /// two weights of a direction add to 1).
    pub fn response_factor(&self, i: usize) -> f64 {
        match self.mode {
            Mode::Conical { pivot, .. } => (self.bearing - pivot) / (self.probes[i] - pivot),
            Mode::TwoPlane => {
                let n = self.probes.len() / 2;
                let (z1, z2) = (self.probes[i % n], self.probes[i % n + n]);
                let to_second = (self.bearing - z1) / (z2 - z1);
                if i < n { 1.0 - to_second } else { to_second }
            }
        }
    }

    /// The factor force channel `i` is multiplied by: conical, `(z_f − z_p)/(z_B − z_p)`;
    /// 1 without force planes.
    pub fn force_factor(&self, i: usize) -> f64 {
        match &self.mode {
            Mode::Conical {
                pivot,
                forces: Some(f),
            } => (f[i] - pivot) / (self.bearing - pivot),
            _ => 1.0,
        }
    }

    /// The CSV columns to read for records this geometry moves: for two planes, each force
    /// column read twice, so that a record holds as many force channels as response channels
    /// ([`Geometry::apply`] keeps the first `n`); else `layout` itself.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for two planes when `layout` names other than two response
    /// columns per force column.
    pub fn reading_layout<'a>(&self, layout: &'a CsvLayout) -> Result<Cow<'a, CsvLayout>> {
        if !self.is_two_plane() {
            return Ok(Cow::Borrowed(layout));
        }
        let n = layout.forces.len();
        if layout.displacements.len() != 2 * n {
            return Err(Error::InvalidOption {
                option: "disp",
                message: format!(
                    "--force names {n} columns and --disp {}: two-plane geometry reads two \
                     response columns per force, the first plane's then the second's",
                    layout.displacements.len()
                ),
            });
        }
        let mut wide = layout.clone();
        wide.forces.extend_from_within(..);
        Ok(Cow::Owned(wide))
    }

    /// `record` with its channels moved to the bearing plane (label, rate and response kinds
    /// kept). For two planes the record holds `2n` channels of each kind: responses as
    /// [`Geometry::two_plane`] orders them, each force twice (channels `d` and `d + n`, as
    /// [`Geometry::reading_layout`] reads them); the result has `n`.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when the record has another number of response channels than
    /// probes, or of force channels than force planes, or for two planes a force channel
    /// `d + n` that is not channel `d`; [`Error::InvalidParameter`] for a moved sample that is
    /// not finite.
    pub fn apply(&self, record: Record) -> Result<Record> {
        let n = record.dofs();
        let refuse = |message: String| Error::InvalidOption {
            option: "geometry",
            message: format!(
                "record `{}`: {message}",
                crate::error::excerpt(record.label())
            ),
        };
        let counts = [
            (
                self.probes.len(),
                "geometry probes (one per response channel)",
            ),
            (
                self.forces().map_or(n, <[f64]>::len),
                "geometry forces (one per force channel)",
            ),
        ];
        for (count, what) in counts {
            if count != n {
                return Err(refuse(format!(
                    "{n} channels of each kind but {count} {what}"
                )));
            }
        }
        let kinds = record.responses().to_vec();
        if self.is_two_plane() {
            let n = n / 2;
            if let Some(d) = (0..n).find(|&d| record.force(d) != record.force(d + n)) {
                return Err(refuse(format!(
                    "two-plane records hold each force twice, channels {d} and {} (the reader \
                     reads each force column twice); they differ",
                    d + n
                )));
            }
            if let Some(d) = (0..n).find(|&d| kinds[d] != kinds[d + n]) {
                return Err(refuse(format!(
                    "direction {d} is measured as {} at one plane and {} at the other",
                    kinds[d].name(),
                    kinds[d + n].name()
                )));
            }
            let responses = (0..n)
                .map(|d| {
                    let (z1, z2) = (self.probes[d], self.probes[d + n]);
                    let (x1, x2) = (record.displacement(d), record.displacement(d + n));
                    two_plane_to_bearing(x1, x2, z1, z2, self.bearing)
                })
                .collect::<Result<Vec<_>>>()?;
            // The forces at the bearing plane: shared with the record read, not copied.
            let forces = (0..n).map(|d| record.force_samples(d)).collect();
            let responses = responses.into_iter().map(Into::into).collect();
            return Record::from_samples(
                record.label(),
                record.sample_rate(),
                forces,
                responses,
                kinds[..n].to_vec(),
            )
            .map(|r| r.with_warnings(record.warnings().to_vec()));
        }
        let Mode::Conical { pivot, .. } = self.mode else {
            unreachable!("two planes returned above")
        };
        let responses = (0..n)
            .map(|i| {
                conical_to_bearing(record.displacement(i), self.probes[i], pivot, self.bearing)
            })
            .collect::<Result<Vec<_>>>()?;
        // Forces measured at the bearing plane are shared, not copied.
        let at_bearing = matches!(self.mode, Mode::Conical { forces: None, .. });
        let forces = (0..n)
            .map(|i| {
                if at_bearing {
                    return record.force_samples(i);
                }
                let k = self.force_factor(i);
                record
                    .force(i)
                    .iter()
                    .map(|f| f * k)
                    .collect::<Vec<_>>()
                    .into()
            })
            .collect();
        let responses = responses.into_iter().map(Into::into).collect();
        Record::from_samples(
            record.label(),
            record.sample_rate(),
            forces,
            responses,
            kinds,
        )
        .map(|r| r.with_warnings(record.warnings().to_vec()))
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

    /// The seed's rig and two noise-free hits per direction on it, at its bearing plane.
    fn seed_hits() -> (crate::Coefficients, Vec<Record>) {
        use crate::simulate::{ImpactTest, seed_rig};
        let truth = seed_rig();
        let test = ImpactTest {
            per_direction: 2,
            ..ImpactTest::seed_rig()
        };
        let hits = test.run(&truth).unwrap();
        (truth, hits)
    }

    /// Noise-free hits on a known system, measured at probes beyond the bearing and driven at
    /// a force plane off it, come back to the bearing plane's coefficients: the lever arms
    /// undone exactly.
    #[test]
    fn the_bearing_plane_is_recovered() {
        use crate::job::{Channels, Job, Options};
        let (pivot, bearing) = (0.0, 0.151);
        let (probes, forces) = ([0.213, 0.254], [0.18, 0.12]);
        let g = Geometry::conical(pivot, bearing, probes.to_vec(), Some(forces.to_vec())).unwrap();
        let (truth, hits) = seed_hits();
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

    /// Two planes: the weights are the closed form `x_B = x_1 + (x_2 − x_1)(z_B − z_1)/(z_2 −
    /// z_1)`, between the planes and beyond them, and a rigid motion `x(z) = a + b z` comes
    /// back as `a + b z_B` exactly.
    #[test]
    fn two_planes_interpolate_and_extrapolate_a_rigid_motion() {
        for bearing in [0.151, 0.23, 0.3] {
            let g = Geometry::two_plane(bearing, vec![0.213, 0.2, 0.254, 0.26]).unwrap();
            let w = (bearing - 0.213) / (0.254 - 0.213);
            assert!((g.response_factor(0) - (1.0 - w)).abs() < 1e-15);
            assert!((g.response_factor(2) - w).abs() < 1e-15);
            assert!((g.response_factor(1) + g.response_factor(3) - 1.0).abs() < 1e-15);
            let line = |a: f64, b: f64, z: f64| vec![a + b * z; 16];
            let x = vec![
                line(1.0, -2.0, 0.213),
                line(0.5, 3.0, 0.2),
                line(1.0, -2.0, 0.254),
                line(0.5, 3.0, 0.26),
            ];
            let r = Record::new("r", 100.0, vec![vec![1.5; 16]; 4], x).unwrap();
            let at = g.apply(r).unwrap();
            assert_eq!(at.dofs(), 2);
            assert!((at.displacement(0)[7] - (1.0 - 2.0 * bearing)).abs() < 1e-14);
            assert!((at.displacement(1)[7] - (0.5 + 3.0 * bearing)).abs() < 1e-14);
            assert_eq!(at.force(1), [1.5; 16]);
        }
    }

    /// A rigid rotor measured at two planes per direction, tilting by an unrelated motion on
    /// top of the bearing plane's: the two-plane geometry gives back the bearing's M, C, K to
    /// the simulation's floor, from records in memory and from CSV files read as
    /// `--disp x1,y1,x2,y2`.
    #[test]
    fn two_plane_records_recover_the_bearing() {
        use crate::io::{CsvLayout, write_record};
        use crate::job::{Channels, Job, Options, read_file};
        let (bearing, planes) = (0.151, [0.213, 0.254]);
        let g =
            Geometry::two_plane(bearing, vec![planes[0], planes[0], planes[1], planes[1]]).unwrap();
        let (truth, hits) = seed_hits();
        // x(z) = x_B + θ (z − z_B), with a tilt θ unrelated to x_B: the other direction's
        // motion plus a 13 Hz wobble.
        let measured: Vec<Record> = hits
            .iter()
            .map(|r| {
                let tilt = |d: usize, m: usize| {
                    let t = m as f64 / r.sample_rate();
                    40.0 * r.displacement(1 - d)[m]
                        + 1e-4 * (2.0 * std::f64::consts::PI * 13.0 * t).sin()
                };
                let at = |z: f64, d: usize| -> Vec<f64> {
                    (0..r.len())
                        .map(|m| r.displacement(d)[m] + tilt(d, m) * (z - bearing))
                        .collect()
                };
                let x = vec![
                    at(planes[0], 0),
                    at(planes[0], 1),
                    at(planes[1], 0),
                    at(planes[1], 1),
                ];
                let f = (0..4).map(|i| r.force(i % 2).to_vec()).collect();
                Record::new(r.label(), r.sample_rate(), f, x).unwrap()
            })
            .collect();
        let worst = |id: &crate::job::Outcome| {
            let got = id.identification().coefficients();
            [
                (got.mass(), truth.mass()),
                (got.damping(), truth.damping()),
                (got.stiffness(), truth.stiffness()),
            ]
            .iter()
            .map(|(a, b)| (*a - *b).norm_l2() / b.norm_l2())
            .fold(0.0, f64::max)
        };
        let channels = Channels {
            geometry: Some(g),
            ..Channels::default()
        };
        let job = Job::new(Options::new(8.0, 49.0), channels.clone());
        let in_memory = worst(&job.run_records(measured.clone()).unwrap());
        assert!(in_memory < 1e-6, "{in_memory}");
        // The same records as files of 2 force and 4 response columns.
        let dir = tempfile::tempdir().unwrap();
        let layout = CsvLayout {
            time: "t".into(),
            forces: vec!["fx".into(), "fy".into()],
            displacements: ["x1", "y1", "x2", "y2"].map(String::from).to_vec(),
        };
        let mut paths = Vec::new();
        for (i, r) in measured.iter().enumerate() {
            // The record's second copy of the forces is written as fx2, fy2, which the
            // reader leaves: it reads fx and fy twice.
            let narrow = CsvLayout {
                forces: vec!["fx".into(), "fy".into(), "fx2".into(), "fy2".into()],
                ..layout.clone()
            };
            let path = dir.path().join(format!("hit-{i}.csv"));
            write_record(&path, r, &narrow).unwrap();
            paths.push(path);
        }
        let from_files = Channels {
            csv: layout,
            ..channels
        };
        let read = read_file(&paths[0], &from_files).unwrap();
        assert_eq!(read[0].dofs(), 2);
        let job = Job::new(Options::new(8.0, 49.0), from_files);
        let outcome = job.run_files(&paths).unwrap();
        let from_csv = worst(&outcome);
        assert!(from_csv < 1e-6, "{from_csv}");
        // Without the geometry, the probes' motion is not the bearing's.
        let plain = Job::new(Options::new(8.0, 49.0), Channels::default());
        let first_plane: Vec<Record> = measured
            .iter()
            .map(|r| {
                let f = (0..2).map(|i| r.force(i).to_vec()).collect();
                let x = (0..2).map(|i| r.displacement(i).to_vec()).collect();
                Record::new(r.label(), r.sample_rate(), f, x).unwrap()
            })
            .collect();
        assert!(worst(&plain.run_records(first_plane).unwrap()) > 0.05);
    }

    /// Bad two-plane geometry is refused naming the key; records that do not fit it too.
    #[test]
    fn bad_two_plane_geometry_is_refused() {
        let name = |e: Error| match e {
            Error::InvalidParameter { name, .. } => name,
            e => panic!("{e}"),
        };
        for probes in [
            vec![],
            vec![0.2, 0.3, 0.4],
            vec![0.2, 0.3, 0.2, 0.4],
            vec![0.2, f64::NAN],
        ] {
            assert_eq!(
                name(Geometry::two_plane(0.1, probes.clone()).unwrap_err()),
                Parameter::GeometryProbes,
                "{probes:?}"
            );
        }
        assert_eq!(
            name(Geometry::two_plane(f64::INFINITY, vec![0.2, 0.3]).unwrap_err()),
            Parameter::GeometryBearing
        );
        let g = Geometry::two_plane(0.1, vec![0.2, 0.2, 0.3, 0.3]).unwrap();
        assert_eq!(g.pivot(), None);
        assert!(g.forces().is_none());
        // Two channels of each kind for four probes.
        let r = Record::new("r", 10.0, vec![vec![1.0; 8]; 2], vec![vec![1.0; 8]; 2]).unwrap();
        assert_eq!(g.apply(r).unwrap_err().kind(), "invalid_argument");
        // The second copy of a force differs from the first.
        let f = vec![vec![1.0; 8], vec![1.0; 8], vec![2.0; 8], vec![1.0; 8]];
        let r = Record::new("r", 10.0, f, vec![vec![1.0; 8]; 4]).unwrap();
        assert!(
            g.apply(r)
                .unwrap_err()
                .to_string()
                .contains("each force twice")
        );
        // Reading: two response columns per force, no other count.
        let three = CsvLayout {
            time: "t".into(),
            forces: vec!["fx".into(), "fy".into()],
            displacements: vec!["x1".into(), "y1".into(), "x2".into()],
        };
        assert_eq!(
            g.reading_layout(&three).unwrap_err().kind(),
            "invalid_argument"
        );
        let four = CsvLayout {
            displacements: vec!["x1".into(), "y1".into(), "x2".into(), "y2".into()],
            ..three
        };
        assert_eq!(
            g.reading_layout(&four).unwrap().forces,
            ["fx", "fy", "fx", "fy"]
        );
    }
}
