//! The string parsers of the command line: a matrix `a,b;c,d`, the library's [`Choice`]s, the
//! default response column names. Their failures quote at most 80 characters of the input.
//! (A band `LO,HI` and a window are parsed by the library: `bearing_ident::job`.)

use std::ffi::OsStr;

use bearing_ident::Choice;
use bearing_ident::error::excerpt;
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Arg, Command, Error};
use faer::Mat;

use crate::failure::{Failure, invalid};

pub fn parse_matrix(name: &str, s: &str) -> Result<Mat<f64>, Failure> {
    let rows: Vec<Vec<f64>> = s
        .split(';')
        .map(|r| r.split(',').map(|v| v.trim().parse::<f64>()).collect())
        .collect::<Result<_, _>>()
        .map_err(|e| invalid(format!("--{name} `{}`: {e}", excerpt(s))))?;
    let n = rows.len();
    if rows.iter().any(|r| r.len() != n) {
        return Err(invalid(format!(
            "--{name} `{}`: expected a square matrix, rows separated by `;`",
            excerpt(s)
        )));
    }
    Ok(Mat::from_fn(n, n, |i, j| rows[i][j]))
}

/// The command-line values of a library [`Choice`]: `--help` lists [`Choice::ALL`] with each
/// value's [`Choice::describe`], and a value is read by the library's one spelling rule
/// ([`Choice::parse`]), so the tool keeps no copy of the library's lists. With `auto`, the
/// value `auto` (described so) comes first and reads as `None`.
#[derive(Clone)]
pub struct ChoiceParser<T> {
    auto: Option<&'static str>,
    of: std::marker::PhantomData<fn() -> T>,
}

/// The parser of a [`Choice`] option (`value_parser = choice::<Method>()`).
pub fn choice<T: Choice>() -> ChoiceParser<T> {
    ChoiceParser {
        auto: None,
        of: std::marker::PhantomData,
    }
}

/// The parser of a [`Choice`] option that also takes `auto` (read as `None`), described by
/// `describe`.
pub fn auto_or<T: Choice>(describe: &'static str) -> AutoOr<T> {
    AutoOr(ChoiceParser {
        auto: Some(describe),
        of: std::marker::PhantomData,
    })
}

/// A [`ChoiceParser`] that also takes `auto`, as `None`.
#[derive(Clone)]
pub struct AutoOr<T>(ChoiceParser<T>);

impl<T: Choice> ChoiceParser<T> {
    fn values(&self) -> impl Iterator<Item = PossibleValue> + '_ {
        let auto = self.auto.map(|d| PossibleValue::new("auto").help(d));
        auto.into_iter().chain(
            T::ALL
                .iter()
                .map(|c| PossibleValue::new(c.name()).help(c.describe())),
        )
    }

    /// The value of `text` under the library's rule; clap's own error (listing the values)
    /// when it names none.
    fn read(&self, cmd: &Command, arg: Option<&Arg>, text: &OsStr) -> Result<Option<T>, Error> {
        let named = text.to_str().map(|t| {
            if self.auto.is_some() && bearing_ident::choice::same_name("auto", t) {
                Ok(None)
            } else {
                T::parse(t).map(Some)
            }
        });
        match named {
            Some(Ok(value)) => Ok(value),
            _ => {
                let names: Vec<PossibleValue> = self.values().collect();
                PossibleValuesParser::new(names).parse_ref(cmd, arg, text)?;
                Err(Error::new(clap::error::ErrorKind::InvalidValue).with_cmd(cmd))
            }
        }
    }
}

impl<T: Choice + Send + Sync> TypedValueParser for ChoiceParser<T> {
    type Value = T;

    fn parse_ref(&self, cmd: &Command, arg: Option<&Arg>, text: &OsStr) -> Result<T, Error> {
        self.read(cmd, arg, text)?
            .ok_or_else(|| Error::new(clap::error::ErrorKind::InvalidValue).with_cmd(cmd))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(self.values()))
    }
}

impl<T: Choice + Send + Sync> TypedValueParser for AutoOr<T> {
    type Value = Option<T>;

    fn parse_ref(
        &self,
        cmd: &Command,
        arg: Option<&Arg>,
        text: &OsStr,
    ) -> Result<Option<T>, Error> {
        self.0.read(cmd, arg, text)
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        self.0.possible_values()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bearing_ident::{Excitation, Method};
    use clap::Parser;

    #[derive(Parser)]
    struct Args {
        #[arg(long, value_parser = choice::<Method>(), default_value = "ivf")]
        method: Method,
        #[arg(long, value_parser = auto_or::<Excitation>("detect"), default_value = "auto")]
        excitation: std::option::Option<Excitation>, // `auto` is `None`: a value, not an optional argument
    }

    /// The values read by the library's rule, `auto` as `None`, and `--help`'s list built from
    /// the library's.
    #[test]
    fn values_come_from_the_library() {
        let a = Args::try_parse_from(["x", "--method", "LS", "--excitation", "stepped_sine"])
            .expect("parses");
        assert_eq!(a.method, Method::LeastSquares);
        assert_eq!(a.excitation, Some(Excitation::SteppedSine));
        let a = Args::try_parse_from(["x"]).expect("defaults");
        assert_eq!((a.method, a.excitation), (Method::Ivf, None));
        let e = Args::try_parse_from(["x", "--method", "newton"])
            .err()
            .expect("refused");
        assert_eq!(e.kind(), clap::error::ErrorKind::InvalidValue);
        let text = e.to_string();
        assert!(
            text.contains("newton") && text.contains("direct, ls, ivf, ml"),
            "{text}"
        );
        let names: Vec<String> = auto_or::<Excitation>("detect")
            .possible_values()
            .expect("listed")
            .map(|v| v.get_name().to_owned())
            .collect();
        let mut expected = vec!["auto".to_owned()];
        expected.extend(Excitation::ALL.iter().map(|e| e.name().to_owned()));
        assert_eq!(names, expected);
    }
}
