//! [`Response`]: what a response channel measures, and its conversion to displacement.

use faer::c64;

use crate::error::{Error, Result};

/// What a response channel measures: displacement, velocity or acceleration.
///
/// With the crate's DFT convention ($\dot x \to i\omega X$) the displacement spectrum follows
/// from the others at every line $\omega \ne 0$:
/// $X = V/(i\omega) = A/(-\omega^2)$. Under the exponential window $w(t) = e^{-\sigma t}$ the
/// windowed spectra belong to $s = \sigma + i\omega$ (a record from rest): $V_w = s\,X_w$,
/// $A_w = s^2 X_w$, so [`Response::to_displacement`] divides by $s^p$ with $p$ the
/// [`Response::order`], and the window's correction of the fitted coefficients then applies
/// unchanged.
///
/// # Examples
/// ```
/// use bearing_ident::Choice;
/// use bearing_ident::records::Response;
/// use bearing_ident::faer::c64;
/// let r: Response = "velocity".parse()?;
/// assert_eq!((r, r.name(), r.order()), (Response::Velocity, "velocity", 1));
/// // V = iω X: a velocity of 2π·10 i m/s·s at 10 Hz is a displacement of 1 m·s.
/// let w = 2.0 * std::f64::consts::PI * 10.0;
/// let x = r.to_displacement(c64::new(0.0, w), 0.0, w).unwrap();
/// assert!((x.re - 1.0).abs() < 1e-15 && x.im.abs() < 1e-15);
/// assert!(Response::Acceleration.to_displacement(c64::new(1.0, 0.0), 0.0, 0.0).is_none());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Response {
    /// Displacement (m): used as it is.
    #[default]
    Displacement,
    /// Velocity (m/s): $X = V/s$.
    Velocity,
    /// Acceleration (m/s²): $X = A/s^2$.
    Acceleration,
}

impl Response {
    /// The order `p` of the time derivative of displacement: 0, 1 or 2.
    pub fn order(self) -> i32 {
        match self {
            Response::Displacement => 0,
            Response::Velocity => 1,
            Response::Acceleration => 2,
        }
    }

    /// The SI unit of the channel: `"m"`, `"m/s"` or `"m/s²"`.
    pub fn unit(self) -> &'static str {
        match self {
            Response::Displacement => "m",
            Response::Velocity => "m/s",
            Response::Acceleration => "m/s²",
        }
    }

    /// The displacement spectrum $X = R/s^p$, $s = \sigma + i\omega$, of a response spectrum
    /// `value` at `omega` (rad/s) under an exponential window of decay `sigma` (1/s; 0 for
    /// every other window); `None` when $s^p$ is zero (a velocity or acceleration at DC with
    /// no window). Displacement is returned as it is.
    pub fn to_displacement(self, value: c64, sigma: f64, omega: f64) -> Option<c64> {
        match self {
            Response::Displacement => Some(value),
            _ => Some(value * self.divisor(sigma, omega)?),
        }
    }

    /// The factor $1/s^p$ that [`Response::to_displacement`] multiplies by; `None` when $s^p$
    /// is zero or its inverse is not finite.
    pub(crate) fn divisor(self, sigma: f64, omega: f64) -> Option<c64> {
        let s = c64::new(sigma, omega);
        let sp = match self {
            Response::Displacement => return Some(c64::new(1.0, 0.0)),
            Response::Velocity => s,
            Response::Acceleration => s * s,
        };
        let inv = c64::new(1.0, 0.0) / sp;
        (sp.norm() > 0.0 && inv.re.is_finite() && inv.im.is_finite()).then_some(inv)
    }

    /// The kind of every one of `n` response channels from a list: none (all displacement),
    /// one (the same for all) or `n` (one per channel).
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] for any other number.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::records::Response;
    /// assert_eq!(Response::per_channel(&[Response::Velocity], 2)?, vec![Response::Velocity; 2]);
    /// assert_eq!(Response::per_channel(&[], 1)?, vec![Response::Displacement]);
    /// assert!(Response::per_channel(&[Response::Velocity; 3], 2).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn per_channel(kinds: &[Response], n: usize) -> Result<Vec<Response>> {
        match kinds.len() {
            0 => Ok(vec![Response::Displacement; n]),
            1 => Ok(vec![kinds[0]; n]),
            len if len == n => Ok(kinds.to_vec()),
            len => Err(Error::LengthMismatch {
                what: "response kinds (one for all channels, or one per degree of freedom)",
                expected: n,
                actual: len,
            }),
        }
    }
}

impl crate::Choice for Response {
    const OPTION: &'static str = "response";
    const ALL: &'static [Response] = &[
        Response::Displacement,
        Response::Velocity,
        Response::Acceleration,
    ];

    /// `"displacement"`, `"velocity"` or `"acceleration"` (the command line's `--response`
    /// values), in the order of [`Response::order`].
    fn name(self) -> &'static str {
        match self {
            Response::Displacement => "displacement",
            Response::Velocity => "velocity",
            Response::Acceleration => "acceleration",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Response::Displacement => "displacement (m), used as it is",
            Response::Velocity => "velocity (m/s), divided by iω",
            Response::Acceleration => "acceleration (m/s²), divided by −ω²",
        }
    }
}

crate::choice::choice_text!(Response);
