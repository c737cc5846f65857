//! The string parsers of the command line: a matrix `a,b;c,d`, library names of options, the
//! default response column names. Their failures quote at most 80 characters of the input.
//! (A band `LO,HI` and a window are parsed by the library: `bearing_ident::job`.)

use bearing_ident::error::excerpt;
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

/// The library's option that a command-line value names: the value's name parsed by the
/// library's `FromStr` (so the tool and the library share one list of names; a bin test checks
/// every value parses).
pub fn library<T>(arg: impl clap::ValueEnum) -> Result<T, Failure>
where
    T: std::str::FromStr<Err = bearing_ident::Error>,
{
    let value = arg
        .to_possible_value()
        .expect("every command-line value has a name");
    Ok(value.get_name().parse()?)
}
