//! Probe geometry: displacements measured at sensor planes carried to the bearing plane of a
//! rigid shaft ([`two_plane_to_bearing`], [`conical_to_bearing`]).

use crate::error::{Error, Result};

/// Displacement at a bearing plane `z_b` from two sensor planes `z_1`, `z_2` on a rigid shaft:
/// $x_B = x_1 + (x_2 - x_1)\,\frac{z_B - z_1}{z_2 - z_1}$, sample by sample.
///
/// # Errors
/// [`Error::LengthMismatch`] if the channels differ in length; [`Error::InvalidParameter`] if a
/// plane position is not finite or `z_1 = z_2`, or a sample or the result is not finite.
///
/// # Examples
/// ```
/// use bearing_ident::records::two_plane_to_bearing;
/// let xb = two_plane_to_bearing(&[1.0, 2.0], &[3.0, 6.0], 0.0, 0.2, 0.1)?;
/// assert_eq!(xb, vec![2.0, 4.0]);
/// assert!(two_plane_to_bearing(&[1.0], &[3.0], 0.2, 0.2, 0.1).is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn two_plane_to_bearing(x1: &[f64], x2: &[f64], z1: f64, z2: f64, zb: f64) -> Result<Vec<f64>> {
    if x1.len() != x2.len() {
        return Err(Error::LengthMismatch {
            what: "sensor channels x1 and x2",
            expected: x1.len(),
            actual: x2.len(),
        });
    }
    let r = plane_ratio(zb - z1, z2 - z1, [z1, z2, zb], "sensor planes z1 ≠ z2")?;
    finite_samples(x1.iter().zip(x2).map(|(a, b)| a + (b - a) * r))
}

/// Displacement at a bearing plane `z_b` from one sensor plane `z_s` for a conical mode about
/// a pivot at `z_p`: $x_B = r\,x_S$ with $r = (z_B - z_p)/(z_S - z_p)$.
///
/// # Errors
/// [`Error::InvalidParameter`] if a position is not finite, `z_s = z_p`, or a sample or the
/// result is not finite.
///
/// # Examples
/// ```
/// use bearing_ident::records::conical_to_bearing;
/// // Sensor at the disk (0.3 m from the pivot), damper at 0.1 m: a third of the motion.
/// let xb = conical_to_bearing(&[3.0e-6], 0.3, 0.0, 0.1)?;
/// assert!((xb[0] - 1.0e-6).abs() < 1e-18);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn conical_to_bearing(xs: &[f64], zs: f64, zp: f64, zb: f64) -> Result<Vec<f64>> {
    let r = plane_ratio(zb - zp, zs - zp, [zs, zp, zb], "sensor plane zs ≠ pivot zp")?;
    finite_samples(xs.iter().map(|x| x * r))
}

/// `num / den` for plane positions `planes`, refused unless all are finite and `den ≠ 0`.
fn plane_ratio(num: f64, den: f64, planes: [f64; 3], expected: &'static str) -> Result<f64> {
    if let Some(&z) = planes.iter().find(|z| !z.is_finite()) {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::PlanePosition,
            value: z,
            expected: "finite (m)",
        });
    }
    let r = num / den;
    if !r.is_finite() {
        return Err(Error::InvalidParameter {
            name: crate::Parameter::DistanceBetweenThePlanes,
            value: den,
            expected,
        });
    }
    Ok(r)
}

/// Collects `samples`, refusing the first that is not finite.
fn finite_samples(samples: impl Iterator<Item = f64>) -> Result<Vec<f64>> {
    samples
        .map(|x| {
            if x.is_finite() {
                Ok(x)
            } else {
                Err(Error::InvalidParameter {
                    name: crate::Parameter::TransformedSample,
                    value: x,
                    expected: "finite: every sample and the plane ratio finite",
                })
            }
        })
        .collect()
}
