//! [`Record`]s from dataset 58 time histories.

use super::types::{Abscissa, DataType, Function, FunctionType, Ordinate};
use crate::error::{Error, Result};
use crate::records::Record;

/// Builds one [`Record`] per load case from the time histories among `functions`; `label`
/// names the source (a file) in labels and errors.
///
/// # The rule
/// - Only time responses (function type 1) are used; FRFs, spectra and the rest are ignored.
/// - Time histories with the same load case (record 6) form one record, in the order of the
///   load cases' first appearance. A file whose time histories all carry one load case (0, as
///   most writers leave it) is one record.
/// - The ordinate numerator's data type assigns a channel: 13 (excitation force, N) a force,
///   8 (displacement, m) a displacement. Other quantities (velocity 11 and acceleration 12
///   included, for now) are ignored.
/// - Forces and displacements are each sorted by the absolute response direction
///   (1 X, 2 Y, 3 Z, …), then by response node: with `n` of each, degree of freedom `i` is the
///   `i`-th of each list. A negative direction (−X is −1) is a sensor pointing the other way;
///   its values are negated.
/// - Every channel of a record must be real, evenly spaced with one increment `dx` and one
///   length; the sampling rate is `1/dx`.
///
/// The record's label is `label` when there is one record, `label#lc` (the load case)
/// otherwise.
///
/// # Errors
/// [`Error::UffRecord`] naming the load case when no time history is a force or displacement,
/// when a channel's abscissa is uneven or its values complex, or when channels' increments
/// differ; and [`Record::new`]'s errors (unequal force and displacement counts, lengths, too
/// few samples, non-finite values).
///
/// # Examples
/// ```
/// use bearing_ident::uff::{self, Function};
/// let t: Vec<f64> = (0..16).map(|k| k as f64).collect();
/// let functions = [
///     Function::time_response(5, 2, 8, 0.0, 1e-3, t.iter().map(|v| 2.0 * v).collect()),
///     Function::time_response(5, 1, 13, 0.0, 1e-3, t.clone()),
///     Function::time_response(5, -1, 8, 0.0, 1e-3, t.clone()),
///     Function::time_response(5, 2, 13, 0.0, 1e-3, t.iter().map(|v| 3.0 * v).collect()),
/// ];
/// let records = uff::records(&functions, "rig.uff")?;
/// assert_eq!(records.len(), 1);
/// let r = &records[0];
/// assert_eq!(r.dofs(), 2);
/// assert!((r.sample_rate() - 1000.0).abs() < 1e-9);
/// assert_eq!(r.force(1)[1], 3.0); // +Y force
/// assert_eq!(r.displacement(0)[1], -1.0); // −X sensor, negated
/// assert_eq!(r.displacement(1)[1], 2.0);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn records(functions: &[Function], label: &str) -> Result<Vec<Record>> {
    let mut cases: Vec<i64> = Vec::new();
    for f in functions {
        if f.function_type == FunctionType::TimeResponse && !cases.contains(&f.load_case) {
            cases.push(f.load_case);
        }
    }
    if cases.is_empty() {
        return Err(Error::UffRecord {
            path: label.to_owned(),
            load_case: 0,
            message: "no time history (function type 1) in the file".into(),
        });
    }
    let single = cases.len() == 1;
    cases
        .iter()
        .map(|&lc| {
            let name = if single {
                label.to_owned()
            } else {
                format!("{label}#{lc}")
            };
            record_of_case(functions, lc, label, &name)
        })
        .collect()
}

/// The record of one load case's time histories, by the rule of [`records`], the records of
/// every other load case left out: one file per record.
///
/// # Errors
/// As [`records`]; [`Error::UffRecord`] also when the load case has no time history.
///
/// # Examples
/// ```
/// use bearing_ident::uff::{self, Function};
/// let mut f = Function::time_response(1, 1, 13, 0.0, 0.5, vec![1.0; 8]);
/// let mut x = Function::time_response(1, 1, 8, 0.0, 0.5, vec![2.0; 8]);
/// f.load_case = 3;
/// x.load_case = 3;
/// let r = uff::record(&[f, x], 3, "rig.uff")?;
/// assert_eq!(r.len(), 8);
/// assert!((r.sample_rate() - 2.0).abs() < 1e-12);
/// assert!(uff::record(&[], 3, "rig.uff").is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn record(functions: &[Function], load_case: i64, label: &str) -> Result<Record> {
    record_of_case(functions, load_case, label, label)
}

fn record_of_case(functions: &[Function], lc: i64, path: &str, name: &str) -> Result<Record> {
    let fail = |message: String| Error::UffRecord {
        path: path.to_owned(),
        load_case: lc,
        message,
    };
    let mut forces: Vec<(i64, i64, &Function)> = Vec::new();
    let mut displacements: Vec<(i64, i64, &Function)> = Vec::new();
    let mut others = 0;
    for f in functions
        .iter()
        .filter(|f| f.function_type == FunctionType::TimeResponse && f.load_case == lc)
    {
        let key = (f.response.direction.saturating_abs(), f.response.node, f);
        match f.numerator.data_type {
            DataType::ExcitationForce => forces.push(key),
            DataType::Displacement => displacements.push(key),
            _ => others += 1,
        }
    }
    if forces.is_empty() || displacements.is_empty() {
        return Err(fail(format!(
            "{} force (data type 13) and {} displacement (data type 8) time histories, \
             {others} of other quantities: a record needs both",
            forces.len(),
            displacements.len()
        )));
    }
    forces.sort_by_key(|&(d, n, _)| (d, n));
    displacements.sort_by_key(|&(d, n, _)| (d, n));
    let mut dx_common: Option<f64> = None;
    let mut channel = |f: &Function| -> Result<Vec<f64>> {
        let Abscissa::Even { dx, .. } = f.abscissa else {
            return Err(fail(format!(
                "the time history at node {} direction {} has an uneven abscissa",
                f.response.node, f.response.direction
            )));
        };
        match dx_common {
            None => dx_common = Some(dx),
            Some(d) if d.to_bits() == dx.to_bits() => {}
            Some(d) => {
                return Err(fail(format!(
                    "time increments differ: {d} s and {dx} s (node {} direction {})",
                    f.response.node, f.response.direction
                )));
            }
        }
        let Ordinate::Real(values) = &f.ordinate else {
            return Err(fail(format!(
                "the time history at node {} direction {} is complex",
                f.response.node, f.response.direction
            )));
        };
        Ok(if f.response.direction < 0 {
            values.iter().map(|v| -v).collect()
        } else {
            values.clone()
        })
    };
    let force_channels = forces
        .iter()
        .map(|&(_, _, f)| channel(f))
        .collect::<Result<Vec<_>>>()?;
    let displacement_channels = displacements
        .iter()
        .map(|&(_, _, f)| channel(f))
        .collect::<Result<Vec<_>>>()?;
    let dx = dx_common.unwrap_or(f64::NAN);
    Record::new(name, 1.0 / dx, force_channels, displacement_channels)
}
