//! [`Choice`]: an option chosen by name from a fixed list (a method, an estimator, an
//! excitation, …), with one spelling rule for every such option. The command-line tool builds
//! its `--help` values from [`Choice::ALL`], a campaign plan and Python keyword arguments parse
//! through [`FromStr`](std::str::FromStr), and JSON and reports print [`Choice::name`].
//!
//! Options that carry a parameter ([`Window`](crate::Window) `exp:3.8/s`,
//! [`Segmentation`](crate::Segmentation) `welch:4096`) are written `NAME:PARAMETER` and follow
//! the same rule for their `NAME`.

use std::borrow::Cow;

use crate::error::{Error, Result};

/// An option chosen by name from a fixed list.
///
/// Names are lower case, words joined by `-` (a few JSON-facing names keep `_`). Parsing
/// ([`Choice::parse`], and `FromStr` on every implementor) ignores case, surrounding spaces and
/// the difference between `-` and `_`, so `stepped-sine`, `Stepped_Sine` and `STEPPED-SINE`
/// name the same excitation.
///
/// # Examples
/// ```
/// use bearing_ident::{Choice, Excitation, Method};
/// assert_eq!(Method::parse("LS")?, Method::LeastSquares);
/// assert_eq!("stepped_sine".parse::<Excitation>()?, Excitation::SteppedSine);
/// assert_eq!(Method::ALL.len(), 4);
/// assert_eq!(Method::Ivf.to_string(), "ivf");
/// let e = Method::parse("newton").unwrap_err();
/// assert_eq!(e.to_string(), "method `newton` is not known: expected one of direct, ls, ivf, ml");
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub trait Choice: Copy + Sized + 'static {
    /// What the option is, as messages name it (`"method"`).
    const OPTION: &'static str;
    /// Every value, each once, in the order a help text lists them.
    const ALL: &'static [Self];

    /// Its name, as the command line, JSON and reports spell it.
    fn name(self) -> &'static str;

    /// One line saying what it is (the command line's `--help` shows it).
    fn describe(self) -> &'static str;

    /// The value named `text` under the one spelling rule (case, spaces and `-`/`_` ignored).
    ///
    /// # Errors
    /// [`Error::UnknownName`] quoting `text` and listing every name.
    fn parse(text: &str) -> Result<Self> {
        Self::ALL
            .iter()
            .copied()
            .find(|c| same_name(c.name(), text))
            .ok_or_else(|| Error::UnknownName {
                what: Self::OPTION,
                given: crate::error::excerpt(text),
                expected: Cow::Owned(format!("one of {}", names::<Self>().join(", "))),
            })
    }
}

/// Every name of `T`, in the order of [`Choice::ALL`].
///
/// # Examples
/// ```
/// use bearing_ident::{choice::names, Response};
/// assert_eq!(names::<Response>(), ["displacement", "velocity", "acceleration"]);
/// ```
pub fn names<T: Choice>() -> Vec<&'static str> {
    T::ALL.iter().map(|c| c.name()).collect()
}

/// Whether `given` spells `name` under the one rule: ASCII case, surrounding spaces and
/// `-`/`_` ignored.
///
/// # Examples
/// ```
/// use bearing_ident::choice::same_name;
/// assert!(same_name("per_frequency", " Per-Frequency "));
/// assert!(!same_name("h1", "h2"));
/// ```
pub fn same_name(name: &str, given: &str) -> bool {
    let fold = |b: u8| match b {
        b'_' => b'-',
        b => b.to_ascii_lowercase(),
    };
    let given = given.trim();
    name.len() == given.len()
        && name
            .bytes()
            .zip(given.bytes())
            .all(|(a, b)| fold(a) == fold(b))
}

/// Implements [`Display`](std::fmt::Display) (the [`Choice::name`]) and
/// [`FromStr`](std::str::FromStr) (by [`Choice::parse`]) for a [`Choice`].
macro_rules! choice_text {
    ($ty:ty) => {
        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str($crate::Choice::name(*self))
            }
        }

        impl std::str::FromStr for $ty {
            type Err = $crate::Error;

            /// Parses a [`Choice::name`](crate::Choice::name) under the one spelling rule.
            fn from_str(s: &str) -> $crate::Result<Self> {
                <$ty as $crate::Choice>::parse(s)
            }
        }
    };
}

pub(crate) use choice_text;

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Every name once, `Display` is the name, and every name (in any case, `_` for `-`)
    /// parses back to its value.
    pub(crate) fn round_trips<T>()
    where
        T: Choice + PartialEq + std::fmt::Debug + std::fmt::Display + std::str::FromStr,
    {
        let mut seen = names::<T>();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(
            seen.len(),
            T::ALL.len(),
            "{}: two values share a name",
            T::OPTION
        );
        for &c in T::ALL {
            assert_eq!(c.to_string(), c.name());
            assert!(
                !c.describe().is_empty(),
                "{}: {} undescribed",
                T::OPTION,
                c.name()
            );
            assert_eq!(T::parse(c.name()).unwrap(), c);
            let shouted = c.name().to_ascii_uppercase().replace('-', "_");
            assert_eq!(T::parse(&shouted).unwrap(), c);
            assert!(c.name().parse::<T>().is_ok());
        }
        let e = T::parse("no-such-value").unwrap_err();
        assert!(matches!(e, Error::UnknownName { what, .. } if what == T::OPTION));
        for &c in T::ALL {
            assert!(e.to_string().contains(c.name()));
        }
    }

    /// Every option of the crate chosen by name follows the rule.
    #[test]
    fn every_choice_round_trips() {
        round_trips::<crate::Method>();
        round_trips::<crate::Estimator>();
        round_trips::<crate::Uncertainty>();
        round_trips::<crate::Excitation>();
        round_trips::<crate::Response>();
        round_trips::<crate::nonlinear::Regressor>();
        round_trips::<crate::solve::ml::NoiseModel>();
        round_trips::<crate::identify::NonConvergence>();
        round_trips::<crate::simulate::Kind>();
        #[cfg(feature = "plot")]
        round_trips::<crate::plot::Figure>();
    }

    #[test]
    fn the_rule_folds_case_and_separators_only() {
        assert!(same_name("stepped-sine", "STEPPED_sine"));
        assert!(same_name("ivf", "  ivf\t"));
        assert!(!same_name("ivf", "iv"));
        assert!(!same_name("ivf", "ivf2"));
        assert!(!same_name("stepped-sine", "steppedsine"));
    }
}
