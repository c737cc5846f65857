//! `identify --uff OUT` and `identify --ross OUT.toml|OUT.json`: the result written for modal
//! software (Universal File dataset 58) and for ROSS (a bearing element).

use std::path::{Path, PathBuf};

use bearing_ident::export::ross::{BearingElement, Table};
use bearing_ident::export::samples::BearingSamples;
use bearing_ident::uff::ByteOrder;
use bearing_ident::{Coefficients, Identification};
use clap::ValueEnum;

use bearing_ident::error::excerpt;

use crate::failure::{Failure, invalid};

#[derive(Debug, Clone, Copy, PartialEq, ValueEnum)]
pub enum UffEncoding {
    /// Dataset 58, values in `E20.12` (13 significant digits).
    Ascii,
    /// Dataset 58b, values as little-endian `f64` (every bit).
    Binary,
}

/// The export flags of `identify`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// Write the measured impedances H and flexibilities G, the fitted model's H and G and the
    /// coherences as Universal File dataset 58 FRFs to OUT (DOF d at node 1 + (d−1)/6,
    /// direction (d−1) mod 6 + 1: 1 +X, 2 +Y, …).
    #[arg(long, value_name = "OUT")]
    uff: Option<PathBuf>,
    /// Encoding of `--uff`.
    #[arg(long, value_enum, default_value = "ascii", requires = "uff")]
    uff_encoding: UffEncoding,
    /// Write a ROSS 3.x bearing element to OUT (`.json`: JSON, else TOML), loadable with
    /// `ross.BearingElement.load(OUT)`: the fitted constant M, C, K at 5 points over the band
    /// (the bearing's own, system − baseline, with `--baseline`), a frequency-dependent
    /// `--model` at 21 points, or with `--per-frequency` K(ω), C(ω) at every line with the
    /// fitted M. 2-DOF results only.
    #[arg(long, value_name = "OUT")]
    ross: Option<PathBuf>,
    /// ROSS node of the bearing element (`n`).
    #[arg(long, default_value_t = 0, requires = "ross")]
    ross_node: usize,
    /// Tag of the bearing element (`tag`; the table is `BearingElement_<tag>`).
    #[arg(long, default_value = "brg1", requires = "ross")]
    ross_tag: String,
    /// Write N samples of the constant M, C, K drawn from their joint uncertainty (the full
    /// covariance of the error bars, the calibration's common sources among it; the bearing's
    /// own, uncorrelated, with `--baseline`) to FILE.csv: one row per sample, columns
    /// `sample,kxx,kxy,kyx,kyy,cxx,…,myy`, paired by index for a stochastic rotor model
    /// (ROSS's `ST_BearingElement`). 2-DOF results with error bars only.
    #[arg(long, num_args = 2, value_names = ["N", "FILE.csv"], allow_hyphen_values = true)]
    ross_samples: Vec<String>,
    /// Seed of `--ross-samples`' generator (a whole number ≥ 0).
    #[arg(
        long,
        default_value = "0",
        requires = "ross_samples",
        allow_hyphen_values = true
    )]
    ross_seed: String,
}

/// `--ross-samples N FILE` and `--ross-seed` checked: the count (≥ 1), the file, the seed.
fn samples_args(args: &ExportArgs) -> Result<Option<(usize, PathBuf, u64)>, Failure> {
    let [count, file] = args.ross_samples.as_slice() else {
        return Ok(None);
    };
    let (n, seed) = samples_count_and_seed(count, &args.ross_seed)?;
    Ok(Some((n, PathBuf::from(file), seed)))
}

/// The `N` of `--ross-samples N FILE` (≥ 1) and the `--ross-seed` (a whole number ≥ 0),
/// each refused as `invalid_argument` naming its option.
pub fn samples_count_and_seed(count: &str, seed: &str) -> Result<(usize, u64), Failure> {
    let n = count
        .trim()
        .parse::<usize>()
        .ok()
        .filter(|&n| n > 0)
        .ok_or_else(|| {
            invalid(format!(
                "--ross-samples `{}`: expected a number of samples ≥ 1",
                excerpt(count)
            ))
        })?;
    let seed = seed.trim().parse::<u64>().map_err(|_| {
        invalid(format!(
            "--ross-seed `{}`: expected a whole number ≥ 0",
            excerpt(seed)
        ))
    })?;
    Ok((n, seed))
}

/// Refuses, before any work, what [`write`] could not do: a per-frequency ROSS table of a
/// baseline-subtracted bearing; an output (`--uff`, `--ross`, `--plot`) that is one of the
/// `inputs` (compared as canonical paths, so links and `./` spellings are caught), which
/// would be overwritten.
pub fn check(
    args: &ExportArgs,
    baseline: bool,
    per_frequency: bool,
    inputs: &[&Path],
    plot: Option<&Path>,
) -> Result<(), Failure> {
    let samples = samples_args(args)?.map(|s| s.1);
    let outputs = [
        ("--uff", args.uff.as_deref()),
        ("--ross", args.ross.as_deref()),
        ("--ross-samples", samples.as_deref()),
        ("--plot", plot),
    ];
    for (flag, out) in outputs {
        let Some(out) = out else { continue };
        let quoted = || excerpt(&out.display().to_string());
        if flag == "--plot" && out.exists() && !out.is_dir() {
            return Err(invalid(format!(
                "--plot {}: is a file, not a folder for the report",
                quoted()
            )));
        }
        // An output that does not exist yet cannot be an input.
        let Ok(out_at) = out.canonicalize() else {
            continue;
        };
        if inputs
            .iter()
            .filter_map(|i| i.canonicalize().ok())
            .any(|i| i == out_at)
        {
            return Err(invalid(format!(
                "{flag} {}: is one of the input files; writing it would overwrite the input",
                quoted()
            )));
        }
    }
    if args.ross.is_some() && baseline && per_frequency {
        return Err(invalid(
            "--ross with --per-frequency and --baseline: per-frequency tables are of the whole \
             test system; drop --per-frequency to export the bearing's constant M, C, K"
                .into(),
        ));
    }
    Ok(())
}

/// Writes the files asked for. `bearing` is the bearing's own coefficients (and their
/// standard deviations) when a baseline was subtracted; `per_frequency` is `--per-frequency`.
pub fn write(
    args: &ExportArgs,
    id: &Identification,
    bearing: Option<(&Coefficients, Option<&Coefficients>)>,
    per_frequency: bool,
) -> Result<(), Failure> {
    if let Some((n, path, seed)) = samples_args(args)? {
        let samples = match bearing {
            None => BearingSamples::draw(id, n, seed)?,
            Some((b, std)) => {
                let std = std.ok_or_else(|| {
                    invalid("--ross-samples: the bearing has no error bars to draw from".into())
                })?;
                let s = std.stacked();
                let rows = s.nrows();
                let p = rows * s.ncols();
                let cov = faer::Mat::from_fn(p, p, |a, c| {
                    if a == c {
                        s[(a % rows, a / rows)].powi(2)
                    } else {
                        0.0
                    }
                });
                BearingSamples::from_covariance(b, &cov, n, seed)?
            }
        };
        save(&path, samples.to_csv().as_bytes())?;
    }
    let bearing = bearing.map(|b| b.0);
    if let Some(path) = &args.uff {
        let functions = bearing_ident::export::uff::functions(id, 1)?;
        let mut bytes = Vec::new();
        match args.uff_encoding {
            UffEncoding::Ascii => bearing_ident::uff::write(&mut bytes, &functions)?,
            UffEncoding::Binary => {
                bearing_ident::uff::write_binary(&mut bytes, &functions, ByteOrder::Little)?
            }
        }
        save(path, &bytes)?;
    }
    if let Some(path) = &args.ross {
        let (node, tag) = (args.ross_node, args.ross_tag.as_str());
        let model = id.model().filter(|m| m.family().is_frequency_dependent());
        let element = match (bearing, per_frequency, model) {
            (None, false, _) => BearingElement::new(id, node, tag, Table::Constant)?,
            (None, true, _) => BearingElement::new(id, node, tag, Table::PerFrequency)?,
            (Some(b), false, None) => BearingElement::constant(b, id.band(), node, tag)?,
            (Some(b), false, Some(model)) => {
                // The baseline's own: the system's constant part less the bearing's.
                let system = id.coefficients();
                let less = |a: faer::MatRef<'_, f64>, b: faer::MatRef<'_, f64>| {
                    faer::Mat::from_fn(2, 2, |i, j| a[(i, j)] - b[(i, j)])
                };
                let baseline = Coefficients::new(
                    less(system.mass(), b.mass()),
                    less(system.damping(), b.damping()),
                    less(system.stiffness(), b.stiffness()),
                )?;
                BearingElement::model(model, id.band(), Some(&baseline), node, tag)?
            }
            (Some(_), true, _) => return check(args, true, true, &[], None),
        };
        let json = path
            .extension()
            .and_then(|x| x.to_str())
            .is_some_and(|x| x.eq_ignore_ascii_case("json"));
        let text = if json {
            element.to_json()
        } else {
            element.to_toml()
        };
        save(path, text.as_bytes())?;
    }
    Ok(())
}

/// Writes `bytes` to `path`; an `io_error` naming the file otherwise.
fn save(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    std::fs::write(path, bytes).map_err(|e| Failure {
        kind: "io_error",
        message: format!("{}: {e}", path.display()),
    })
}
