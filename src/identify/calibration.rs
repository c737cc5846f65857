//! The stated calibration uncertainty of the sensors ([`Calibration`]) and what it does to
//! the coefficients.
//!
//! # The maths
//! A force channel `i` read with a gain off by a relative `δ_fᵢ` and a response channel `j` by
//! `δ_xⱼ` give the measured impedance $\tilde H = D_f H D_x^{-1}$ with
//! $D_f = \mathrm{diag}(1 + \delta_{f})$, $D_x = \mathrm{diag}(1 + \delta_x)$: row `i` of `H`
//! scales by `1 + δ_fᵢ`, column `j` by `1/(1 + δ_xⱼ)`, at every line alike. Since
//! $H(\omega) = K - \omega^2 M + i\omega C$ is linear in the coefficients, every fit returns
//! $\tilde P_{ij} = P_{ij}(1 + \delta_{f_i})/(1 + \delta_{x_j})$ for `P` = `M`, `C`, `K`,
//! exactly. With independent gains of relative standard uncertainty `u` (a calibration
//! sheet's 1σ), to first order
//! $$\sigma_{\mathrm{cal}}(P_{ij}) = |P_{ij}|\sqrt{u_{f_i}^2 + u_{x_j}^2},$$
//! whether the gain errors are shared between channels or not. The error is the same in every
//! record, so no replicate statistic sees it: only this stated budget does.
//!
//! # Which errors are shared
//! A kind-wide entry (`force=1%`) is one error common to every force channel it covers (one
//! calibration constant, one amplifier gain for the kind); a channel's own entry (`fx=0.5%`)
//! is an error of that channel alone, independent of every other
//! ([`Calibration::directions`]: one change of the coefficients per source). Per coefficient
//! both give the formula above. Neither moves a natural frequency or damping ratio: a gain
//! multiplies the impedance by a constant diagonal matrix from the left or the right, which
//! scales $\det Z(s)$ by a constant and leaves its roots, the modes, where they are. (A
//! stated delay or AC-coupling corner is not a constant: it does move them.)

use crate::error::{Error, Result};
use crate::model::Coefficients;

/// Relative standard (1σ) uncertainties of the sensor gains, per channel kind with per-channel
/// overrides, all zero by default.
///
/// # Examples
/// ```
/// use bearing_ident::identify::Calibration;
/// let cal = Calibration::default().force(0.01).response(0.02).response_channel(1, 0.005);
/// assert!((cal.force_uncertainty(0) - 0.01).abs() < 1e-15);
/// assert!((cal.response_uncertainty(1) - 0.005).abs() < 1e-15);
/// // The command line's form, with the channels' names.
/// let parsed = Calibration::parse("force=1%,x=2%", &["fx", "fy"], &["x", "y"])?;
/// assert!((parsed.response_uncertainty(0) - 0.02).abs() < 1e-15);
/// assert!(parsed.response_uncertainty(1).abs() < 1e-15);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Calibration {
    force: f64,
    response: f64,
    force_channels: Vec<(usize, f64)>,
    response_channels: Vec<(usize, f64)>,
}

impl Calibration {
    /// Every force channel's relative gain uncertainty (≥ 0; 0.01 for 1 %; default 0).
    pub fn force(mut self, u: f64) -> Self {
        self.force = u;
        self
    }

    /// Every response channel's relative gain uncertainty (≥ 0; default 0).
    pub fn response(mut self, u: f64) -> Self {
        self.response = u;
        self
    }

    /// Force channel `i`'s own relative gain uncertainty, in place of [`Calibration::force`].
    pub fn force_channel(mut self, i: usize, u: f64) -> Self {
        self.force_channels.retain(|c| c.0 != i);
        self.force_channels.push((i, u));
        self
    }

    /// Response channel `j`'s own relative gain uncertainty, in place of
    /// [`Calibration::response`].
    pub fn response_channel(mut self, j: usize, u: f64) -> Self {
        self.response_channels.retain(|c| c.0 != j);
        self.response_channels.push((j, u));
        self
    }

    /// Force channel `i`'s relative gain uncertainty.
    pub fn force_uncertainty(&self, i: usize) -> f64 {
        own(&self.force_channels, i).unwrap_or(self.force)
    }

    /// Response channel `j`'s relative gain uncertainty.
    pub fn response_uncertainty(&self, j: usize) -> f64 {
        own(&self.response_channels, j).unwrap_or(self.response)
    }

    /// Parses the command line's form: comma-separated `NAME=VALUE` with NAME `force`,
    /// `response` or a channel's name from `force_names` / `response_names`, VALUE a
    /// percentage (`2%`) or a fraction (`0.02`).
    ///
    /// # Errors
    /// [`Error::UnknownName`] for a name that is none of these; [`Error::InvalidParameter`]
    /// for a value that is not a finite number ≥ 0; [`Error::InvalidSetting`] for an item
    /// without `=`.
    pub fn parse(
        spec: &str,
        force_names: &[impl AsRef<str>],
        response_names: &[impl AsRef<str>],
    ) -> Result<Self> {
        let mut out = Calibration::default();
        for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let Some((name, value)) = item.split_once('=') else {
                return Err(Error::InvalidSetting {
                    name: crate::Parameter::Calibration,
                    expected: "NAME=VALUE items such as force=1%,response=2%",
                });
            };
            let (name, value) = (name.trim(), value.trim());
            let u = match value.strip_suffix('%') {
                Some(percent) => percent.trim().parse::<f64>().map(|p| p / 100.0),
                None => value.parse::<f64>(),
            }
            .unwrap_or(f64::NAN);
            check_value(u)?;
            let position = |names: &[_]| names.iter().position(|c: &&str| *c == name);
            let forces: Vec<&str> = force_names.iter().map(AsRef::as_ref).collect();
            let responses: Vec<&str> = response_names.iter().map(AsRef::as_ref).collect();
            out = match name {
                "force" => out.force(u),
                "response" => out.response(u),
                _ => match (position(&forces), position(&responses)) {
                    (Some(i), _) => out.force_channel(i, u),
                    (None, Some(j)) => out.response_channel(j, u),
                    (None, None) => {
                        return Err(Error::UnknownName {
                            what: "calibration channel",
                            given: name.to_owned(),
                            expected: "force, response or a force or response channel's name"
                                .into(),
                        });
                    }
                },
            };
        }
        Ok(out)
    }

    /// Checks every value (finite, ≥ 0) and every channel index (`< dofs` when known).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first bad value or channel.
    pub(crate) fn check(&self, dofs: Option<usize>) -> Result<()> {
        for u in [self.force, self.response]
            .into_iter()
            .chain(self.force_channels.iter().map(|c| c.1))
            .chain(self.response_channels.iter().map(|c| c.1))
        {
            check_value(u)?;
        }
        if let Some(n) = dofs {
            let channels = self.force_channels.iter().chain(&self.response_channels);
            if let Some(&(i, _)) = channels.into_iter().find(|c| c.0 >= n) {
                return Err(Error::InvalidParameter {
                    name: crate::Parameter::CalibrationChannel,
                    value: i as f64,
                    expected: "a channel index below the number of degrees of freedom",
                });
            }
        }
        Ok(())
    }

    /// $\sigma_{\mathrm{cal}}(P_{ij}) = |P_{ij}|\sqrt{u_{f_i}^2 + u_{x_j}^2}$ for every
    /// coefficient of `c` (see the module docs).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a channel index at or above `c`'s degrees of freedom.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::identify::Calibration;
    /// use bearing_ident::simulate::seed_rig;
    /// let std = Calibration::default().force(0.03).response(0.04).std_dev(&seed_rig())?;
    /// // 3 % and 4 % in quadrature: 5 % of every coefficient.
    /// assert!((std.stiffness()[(0, 0)] / seed_rig().stiffness()[(0, 0)] - 0.05).abs() < 1e-12);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn std_dev(&self, c: &Coefficients) -> Result<Coefficients> {
        let n = c.dofs();
        self.check(Some(n))?;
        let scale = |p: faer::MatRef<'_, f64>| {
            faer::Mat::from_fn(n, n, |i, j| {
                p[(i, j)].abs()
                    * self
                        .force_uncertainty(i)
                        .hypot(self.response_uncertainty(j))
            })
        };
        Coefficients::new(scale(c.mass()), scale(c.damping()), scale(c.stiffness()))
    }

    /// One change of the stacked coefficients $\Theta = [M; C; K]$ (`3n × n`) per independent
    /// error source, each at one standard uncertainty: a kind-wide gain changes every row
    /// (force) or column (response) it covers, $dP_{ij} = \pm u P_{ij}$; a channel's own
    /// gain its row or column alone. Their squares sum to [`Calibration::std_dev`]'s
    /// variances.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a channel index at or above `c`'s degrees of freedom.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::identify::Calibration;
    /// use bearing_ident::simulate::seed_rig;
    /// let rig = seed_rig();
    /// // One common force gain and the first response channel's own gain: two sources.
    /// let d = Calibration::default().force(0.01).response_channel(0, 0.02).directions(&rig)?;
    /// assert_eq!(d.len(), 2);
    /// let k = rig.stiffness()[(1, 0)];
    /// // K_yx = K[1, 0]: row 1 (force y, common) and column 0 (response x, its own).
    /// assert!((d[0][(5, 0)] - 0.01 * k).abs() < 1e-9 * k.abs());
    /// assert!((d[1][(5, 0)] + 0.02 * k).abs() < 1e-9 * k.abs());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn directions(&self, c: &Coefficients) -> Result<Vec<faer::Mat<f64>>> {
        let n = c.dofs();
        self.check(Some(n))?;
        let theta = c.stacked();
        // (force side?, the channels covered, u): the kind-wide sources first.
        let kind_wide = |own: &[(usize, f64)]| -> Vec<usize> {
            (0..n).filter(|&i| !own.iter().any(|c| c.0 == i)).collect()
        };
        let mut sources: Vec<(bool, Vec<usize>, f64)> = vec![
            (true, kind_wide(&self.force_channels), self.force),
            (false, kind_wide(&self.response_channels), self.response),
        ];
        sources.extend(self.force_channels.iter().map(|&(i, u)| (true, vec![i], u)));
        sources.extend(
            self.response_channels
                .iter()
                .map(|&(j, u)| (false, vec![j], u)),
        );
        Ok(sources
            .into_iter()
            .filter(|(_, channels, u)| *u > 0.0 && !channels.is_empty())
            .map(|(force, channels, u)| {
                faer::Mat::from_fn(3 * n, n, |r, j| {
                    let (channel, sign) = if force { (r % n, 1.0) } else { (j, -1.0) };
                    if channels.contains(&channel) {
                        sign * u * theta[(r, j)]
                    } else {
                        0.0
                    }
                })
            })
            .collect())
    }
}

fn own(channels: &[(usize, f64)], i: usize) -> Option<f64> {
    channels.iter().find(|c| c.0 == i).map(|c| c.1)
}

fn check_value(u: f64) -> Result<()> {
    if u.is_finite() && u >= 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: crate::Parameter::CalibrationUncertainty,
            value: u,
            expected: "a finite relative standard uncertainty ≥ 0 (2% or 0.02)",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Identifier;
    use crate::simulate::{ImpactTest, seed_rig};

    #[test]
    fn bad_values_and_names_are_refused() {
        let names = (["fx", "fy"], ["x", "y"]);
        for bad in ["force=-1%", "force=nan", "x=abc"] {
            assert!(
                matches!(
                    Calibration::parse(bad, &names.0, &names.1),
                    Err(Error::InvalidParameter { .. })
                ),
                "{bad}"
            );
        }
        let e = Calibration::parse("force", &names.0, &names.1).unwrap_err();
        assert!(matches!(e, Error::InvalidSetting { .. }), "{e:?}");
        assert_eq!(
            e.to_string(),
            "parameter `calibration` is invalid: expected NAME=VALUE items such as \
             force=1%,response=2%"
        );
        assert!(matches!(
            Calibration::parse("z=1%", &names.0, &names.1),
            Err(Error::UnknownName { .. })
        ));
        let cal = Calibration::parse("fy=0.5%, response=2%", &names.0, &names.1).unwrap();
        assert!((cal.force_uncertainty(1) - 0.005).abs() < 1e-15);
        assert!(cal.force_uncertainty(0).abs() < 1e-15);
        assert!((cal.response_uncertainty(0) - 0.02).abs() < 1e-15);
        assert!(
            Calibration::default()
                .response_channel(2, 0.01)
                .check(Some(2))
                .is_err()
        );
        let e = Identifier::new(8.0, 49.0)
            .calibration(Calibration::default().force(f64::NAN))
            .check();
        assert!(matches!(e, Err(Error::InvalidParameter { .. })));
    }

    /// A force gain error scales every coefficient's row, a response gain error its column,
    /// exactly: the fit of records with channel `fy` read 3 % high and `x` 2 % high returns
    /// `P_ij (1 + δ_fi)/(1 + δ_xj)` to rounding, which is what the budget's σ describes.
    #[test]
    fn gain_errors_scale_rows_and_columns_exactly() {
        let truth = seed_rig();
        let records = ImpactTest {
            per_direction: 1,
            ..ImpactTest::seed_rig()
        }
        .run(&truth)
        .unwrap();
        let (df, dx) = ([0.0, 0.03], [0.02, 0.0]);
        let scaled: Vec<_> = records
            .iter()
            .map(|r| {
                let f = (0..2)
                    .map(|i| r.force(i).iter().map(|v| v * (1.0 + df[i])).collect())
                    .collect();
                let x = (0..2)
                    .map(|j| {
                        r.displacement(j)
                            .iter()
                            .map(|v| v * (1.0 + dx[j]))
                            .collect()
                    })
                    .collect();
                crate::Record::new(r.label(), r.sample_rate(), f, x).unwrap()
            })
            .collect();
        let id = Identifier::new(8.0, 49.0);
        let (a, b) = (
            id.identify(&records).unwrap(),
            id.identify(&scaled).unwrap(),
        );
        for (pa, pb) in [
            (a.coefficients().mass(), b.coefficients().mass()),
            (a.coefficients().stiffness(), b.coefficients().stiffness()),
            (a.coefficients().damping(), b.coefficients().damping()),
        ] {
            // The fits converge block-wise (relative change of the whole block), so a zero
            // element is fitted to a fraction of its block's size, not of itself.
            let scale = (0..4).map(|k| pa[(k / 2, k % 2)].abs()).fold(0.0, f64::max);
            for i in 0..2 {
                for j in 0..2 {
                    let expected = pa[(i, j)] * (1.0 + df[i]) / (1.0 + dx[j]);
                    assert!(
                        (pb[(i, j)] - expected).abs() <= 1e-6 * scale,
                        "({i},{j}): {} vs {expected}",
                        pb[(i, j)]
                    );
                }
            }
        }
    }
}
