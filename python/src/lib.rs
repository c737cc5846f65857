//! `bearing_ident._native`: the crate's `job` path from numpy arrays to a result, for the
//! Python package `bearing_ident` (whose `__init__.py` is the public face: records, options
//! by keyword, exceptions by kind). The crate's records read the rows of C-ordered float64
//! arrays in place (shared, not copied); other arrays (float32, any strides) are converted
//! once. The identification runs with the GIL released.

use bearing_ident::campaign::{Campaign, Plan, RunOptions, Value};
use bearing_ident::export::ross::{BearingElement, Table};
use bearing_ident::export::samples::{BearingSamples, COLUMNS};
use bearing_ident::job::{Channels, Job, Options, Outcome};
use bearing_ident::records::SharedSamples;
use bearing_ident::{Choice, Error, ErrorKind, Record, Response};
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use std::sync::Arc;

pyo3::create_exception!(
    _native,
    NativeError,
    PyException,
    "An error of the crate: args are (kind, message)."
);

/// A record as Python hands it over: `(force, response, fs, label, response_kinds)`.
type PyRecordIn<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    f64,
    String,
    Vec<String>,
);

/// A record as Python gets it back: `(force rows, response rows, fs, label, response_kinds)`.
type PyRecordOut = (Vec<Vec<f64>>, Vec<Vec<f64>>, f64, String, Vec<String>);

/// The crate's error as `NativeError(kind, message)`, which the package turns into the
/// exception class of that kind.
fn raise(e: &Error) -> PyErr {
    NativeError::new_err((e.kind().as_str(), e.to_string()))
}

/// An invalid argument of the binding itself (shapes, types).
fn invalid(message: String) -> PyErr {
    NativeError::new_err(("invalid_argument", message))
}

/// A row of a C-ordered float64 numpy array that a crate record reads in place.
struct NumpyRow {
    /// The array: this strong reference keeps it, and so its buffer, alive as long as a
    /// record (or a clone, or a cut of one) reads the row.
    _array: Py<PyAny>,
    /// The row's first sample, inside the array's buffer.
    start: *const f64,
    /// The row's length.
    len: usize,
}

// SAFETY: a `NumpyRow` is only ever read (`as_ref`), from any thread: the pointer is valid
// there for as long as the row lives (see `as_ref`), and the `Py` handle is itself `Send +
// Sync` (PyO3 defers its reference count's decrement when it is dropped without the GIL).
unsafe impl Send for NumpyRow {}
// SAFETY: as for `Send`: shared references only read the buffer.
unsafe impl Sync for NumpyRow {}

impl AsRef<[f64]> for NumpyRow {
    fn as_ref(&self) -> &[f64] {
        // SAFETY: `start..start + len` is one row of the slice numpy's crate gave for the
        // whole array (`PyReadonlyArray::as_slice`: aligned, contiguous, initialised f64s),
        // and `_array` keeps the array alive. numpy never moves or frees the buffer of a live
        // array: `ndarray.resize`, the one call that reallocates it in place, refuses while
        // other references to the array exist, unless told `refcheck=False`, which numpy
        // documents as unsafe. Nothing here writes the buffer, and the numpy crate's shared
        // borrow of the array is held for the whole call (`Borrows`), so no Rust code using
        // that crate gets it mutably meanwhile. Python code writing the array from another
        // thread while the crate reads it is a data race, as it is with numpy's own
        // functions that release the GIL: the package's `Record` and `identify` say so.
        unsafe { std::slice::from_raw_parts(self.start, self.len) }
    }
}

/// The numpy crate's shared borrows of the arrays whose rows records read in place, held
/// until the records are done with (the end of the call that built them).
type Borrows<'py> = Vec<PyReadonlyArray2<'py, f64>>;

/// Whether `a`'s elements can be read where they are: aligned, and every stride a whole
/// number of elements (the numpy crate's views assume both). The package's `Record` makes an
/// aligned copy of any other array, so only an array put in its place afterwards fails this.
fn aligned<T: numpy::Element>(a: &PyReadonlyArray2<'_, T>) -> bool {
    let size = std::mem::size_of::<T>() as isize;
    a.is_aligned() && a.strides().iter().all(|s| s % size == 0)
}

/// The rows of `array` for a record: shared with it in place for a C-ordered, aligned float64
/// array (its borrow added to `borrows`), else converted once (float32, any strides).
fn rows<'py>(
    array: &Bound<'py, PyAny>,
    what: &str,
    borrows: &mut Borrows<'py>,
) -> PyResult<Vec<SharedSamples>> {
    let owned = |rows: Vec<Vec<f64>>| {
        let share = |r: Vec<f64>| -> SharedSamples { Arc::new(r) };
        rows.into_iter().map(share).collect()
    };
    let unaligned = |strides: &[isize]| {
        invalid(format!(
            "{what}: an unaligned array (strides {strides:?} bytes): \
             numpy.require(array, requirements=\"A\") copies it aligned"
        ))
    };
    if let Ok(a) = array.extract::<PyReadonlyArray2<'py, f64>>() {
        if !aligned(&a) {
            return Err(unaligned(a.strides()));
        }
        let n = a.shape()[1];
        // `as_slice` is the buffer of an aligned array in memory order: rows for C order.
        let in_place = (a.is_c_contiguous() && n > 0)
            .then(|| a.as_slice().ok())
            .flatten()
            .map(|all| {
                let row = |row: &[f64]| -> SharedSamples {
                    Arc::new(NumpyRow {
                        _array: array.clone().unbind(),
                        start: row.as_ptr(),
                        len: row.len(),
                    })
                };
                all.chunks_exact(n).map(row).collect()
            });
        if let Some(rows) = in_place {
            borrows.push(a);
            return Ok(rows);
        }
        return Ok(owned(
            a.as_array()
                .rows()
                .into_iter()
                .map(|r| r.to_vec())
                .collect(),
        ));
    }
    if let Ok(a) = array.extract::<PyReadonlyArray2<'_, f32>>() {
        if !aligned(&a) {
            return Err(unaligned(a.strides()));
        }
        return Ok(owned(
            a.as_array()
                .rows()
                .into_iter()
                .map(|r| r.iter().map(|&v| f64::from(v)).collect())
                .collect(),
        ));
    }
    let shape = array
        .cast::<numpy::PyUntypedArray>()
        .map(|a| format!("{:?}", a.shape()))
        .unwrap_or_else(|_| "not an array".into());
    Err(invalid(format!(
        "{what}: expected a 2-D float array shaped (n_dof, n_samples), got {shape}"
    )))
}

/// One record from Python: force and response arrays, sampling rate, label, response kinds;
/// the borrows of the arrays it reads in place added to `borrows`.
fn record<'py>(
    (force, response, fs, label, kinds): &PyRecordIn<'py>,
    borrows: &mut Borrows<'py>,
) -> PyResult<Record> {
    let forces = rows(force, "force", borrows)?;
    let responses = rows(response, "response", borrows)?;
    if forces.len() != responses.len() {
        return Err(invalid(format!(
            "record `{label}`: force has {} rows and response {}: one of each per degree of freedom",
            forces.len(),
            responses.len()
        )));
    }
    let r = Record::from_shared(label.as_str(), *fs, forces, responses).map_err(|e| raise(&e))?;
    if kinds.is_empty() {
        return Ok(r);
    }
    let kinds = kinds
        .iter()
        .map(|k| k.parse::<Response>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| raise(&e))?;
    let kinds = Response::per_channel(&kinds, r.dofs()).map_err(|e| raise(&e))?;
    r.with_responses(kinds).map_err(|e| raise(&e))
}

/// A record handed back to Python, with what its responses measure.
fn record_out(r: &Record) -> PyRecordOut {
    let n = r.dofs();
    (
        (0..n).map(|i| r.force(i).to_vec()).collect(),
        (0..n).map(|i| r.displacement(i).to_vec()).collect(),
        r.sample_rate(),
        r.label().to_owned(),
        r.responses().iter().map(|k| k.name().to_owned()).collect(),
    )
}

/// The records from Python, the borrows of the arrays they read in place (to hold until the
/// records are done with) and the job of the options given by long name.
fn records_and_job<'py>(
    records: &[PyRecordIn<'py>],
    options: &[(String, String)],
) -> PyResult<(Vec<Record>, Borrows<'py>, Job)> {
    let mut borrows = Vec::new();
    let records = records
        .iter()
        .map(|r| record(r, &mut borrows))
        .collect::<PyResult<Vec<_>>>()?;
    let mut o = Options::new(f64::NAN, f64::NAN);
    for (name, value) in options {
        o.set(name, value).map_err(|e| raise(&e))?;
    }
    Ok((records, borrows, Job::new(o, Channels::default())))
}

/// A finished run: the crate's [`Outcome`] behind the package's `Identification`.
#[pyclass(frozen, module = "bearing_ident._native")]
struct NativeResult {
    outcome: Outcome,
    per_frequency: bool,
}

/// A coefficient set as rows of `M`, `C`, `K`.
type Blocks = (Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<f64>>);

/// `c`'s mass, damping and stiffness as rows.
fn blocks(c: &bearing_ident::Coefficients) -> Blocks {
    use bearing_ident::model::rows;
    (rows(c.mass()), rows(c.damping()), rows(c.stiffness()))
}

#[pymethods]
impl NativeResult {
    /// `M`, `C`, `K` as rows: the JSON's values, without writing the JSON.
    fn coefficients(&self) -> Blocks {
        blocks(self.outcome.identification().coefficients())
    }

    /// `M_std`, `C_std`, `K_std` as rows, or `None` without error bars (as the JSON's).
    fn std_dev(&self) -> Option<Blocks> {
        self.outcome.identification().std_dev().map(blocks)
    }

    /// The modes' natural frequencies (Hz) and damping ratios (as the JSON's).
    fn modes(&self) -> (Vec<f64>, Vec<f64>) {
        let modes = self.outcome.identification().modes().unwrap_or_default();
        modes
            .iter()
            .map(|m| (m.natural_frequency_hz, m.damping_ratio))
            .unzip()
    }

    /// The warnings as `(kind, sentence)` (as the JSON's `warning_kinds` and `warnings`).
    fn warnings(&self) -> Vec<(&'static str, String)> {
        self.outcome
            .identification()
            .warnings()
            .iter()
            .map(|w| (w.kind(), w.to_string()))
            .collect()
    }

    /// The JSON of the run, as `bearing-ident identify --json` prints it.
    fn json(&self) -> PyResult<String> {
        self.outcome
            .to_json(self.per_frequency)
            .map(|v| v.to_string())
            .map_err(|e| raise(&e))
    }

    /// `samples` draws of the constant coefficients from their joint uncertainty, seeded with
    /// `seed`: one list of `samples` values per column of
    /// [`bearing_ident::export::samples::COLUMNS`] (`kxx` … `myy`), paired by index.
    fn ross_samples(&self, samples: usize, seed: u64) -> PyResult<Vec<(&'static str, Vec<f64>)>> {
        let s = BearingSamples::draw(self.outcome.identification(), samples, seed)
            .map_err(|e| raise(&e))?;
        Ok(COLUMNS
            .iter()
            .enumerate()
            .map(|(c, name)| (*name, (0..s.len()).map(|i| s.row(i)[c]).collect()))
            .collect())
    }

    /// The identified bearing as a ROSS 3.x `BearingElement` TOML table at node `n`.
    #[pyo3(signature = (n, tag, per_frequency=false))]
    fn ross_toml(&self, n: usize, tag: &str, per_frequency: bool) -> PyResult<String> {
        let table = if per_frequency {
            Table::PerFrequency
        } else {
            Table::Constant
        };
        BearingElement::new(self.outcome.identification(), n, tag, table)
            .map(|b| b.to_toml())
            .map_err(|e| raise(&e))
    }
}

/// Identifies `records` (tuples `(force, response, fs, label, response_kinds)`) with the
/// options given by long name, the GIL released while the crate works.
#[pyfunction]
#[pyo3(signature = (records, options, per_frequency=false))]
fn identify(
    py: Python<'_>,
    records: Vec<PyRecordIn<'_>>,
    options: Vec<(String, String)>,
    per_frequency: bool,
) -> PyResult<NativeResult> {
    let (records, borrows, job) = records_and_job(&records, &options)?;
    let outcome = py.detach(|| {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| job.run_records(records)))
    });
    // The records read the arrays in place until here.
    drop(borrows);
    let outcome = outcome
        .map_err(|_| NativeError::new_err(("internal", "the identification panicked")))?
        .map_err(|e| raise(&e))?;
    Ok(NativeResult {
        outcome,
        per_frequency,
    })
}

/// The records of CSV files (one each), Universal Files (one per load case) or TDMS files
/// (one per file or per group, `record_by`), as tuples
/// `(force, response, fs, label, response_kinds)` of nested lists.
#[pyfunction]
#[pyo3(signature = (paths, force, disp, time, response, record_by = "file"))]
fn read_files(
    paths: Vec<String>,
    force: Vec<String>,
    disp: Vec<String>,
    time: String,
    response: Vec<String>,
    record_by: &str,
) -> PyResult<Vec<PyRecordOut>> {
    let responses = response
        .iter()
        .map(|k| k.parse::<Response>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| raise(&e))?;
    let files: Vec<std::path::PathBuf> = paths.iter().map(Into::into).collect();
    let mut channels =
        Channels::named(&force, &disp, &responses, &time, &files).map_err(|e| raise(&e))?;
    channels.record_by = record_by.parse().map_err(invalid)?;
    let mut out = Vec::new();
    for path in &paths {
        let records =
            bearing_ident::job::read_file(path.as_ref(), &channels).map_err(|e| raise(&e))?;
        out.extend(records.iter().map(record_out));
    }
    Ok(out)
}

/// A campaign run: every point of a plan, as `bearing-ident campaign` reports them.
#[pyclass(frozen, module = "bearing_ident._native")]
struct NativeCampaign {
    campaign: Campaign,
}

#[pymethods]
impl NativeCampaign {
    /// The campaign's JSON, as `bearing-ident campaign --json` prints it.
    fn json(&self) -> String {
        self.campaign.to_json().to_string()
    }

    /// Each point's JSON, as `bearing-ident identify --json` prints it (`None` for a point
    /// that failed).
    fn point_json(&self) -> Vec<Option<String>> {
        self.campaign
            .points
            .iter()
            .map(|p| p.result.as_ref().ok().map(|f| f.json.to_string()))
            .collect()
    }

    /// The coefficients by point as CSV.
    fn csv(&self) -> String {
        self.campaign.to_csv()
    }

    /// The text table.
    fn table(&self) -> String {
        self.campaign.to_table()
    }

    /// The ROSS speed table (TOML) at node `n` with tag `tag`, over the points whose
    /// conditions equal `slice` (name, value) pairs.
    fn ross_toml(
        &self,
        n: usize,
        tag: &str,
        slice: Vec<(String, Bound<'_, PyAny>)>,
    ) -> PyResult<String> {
        let slice = slice
            .into_iter()
            .map(|(name, v)| {
                let value = match v.extract::<f64>() {
                    Ok(x) => Value::Number(x),
                    Err(_) => Value::Text(v.str()?.to_string()),
                };
                Ok((name, value))
            })
            .collect::<PyResult<Vec<_>>>()?;
        self.campaign
            .ross_speed_table(n, tag, &slice)
            .map(|t| t.to_toml())
            .map_err(|e| raise(&e))
    }

    /// Writes `coefficients.csv`, `campaign.json` and each point's JSON into `dir`.
    fn write(&self, dir: String) -> PyResult<()> {
        self.campaign.write(dir.as_ref()).map_err(|e| raise(&e))
    }
}

/// Runs the campaign plan at `plan` (TOML), the GIL released.
#[pyfunction]
#[pyo3(signature = (plan, jobs=None, cache=None, per_frequency=false))]
fn campaign(
    py: Python<'_>,
    plan: String,
    jobs: Option<usize>,
    cache: Option<String>,
    per_frequency: bool,
) -> PyResult<NativeCampaign> {
    if jobs == Some(0) {
        return Err(invalid("jobs = 0: expected at least 1".into()));
    }
    let plan = Plan::read(plan.as_ref()).map_err(|e| raise(&e))?;
    let mut run = RunOptions {
        cache: cache.map(Into::into),
        per_frequency,
        ..RunOptions::default()
    };
    if let Some(jobs) = jobs {
        run.jobs = jobs;
    }
    let campaign = py
        .detach(|| {
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| plan.run(&run, |_, _| {})))
        })
        .map_err(|_| NativeError::new_err(("internal", "the campaign panicked")))?
        .map_err(|e| raise(&e))?;
    Ok(NativeCampaign { campaign })
}

/// Field identification from the rotor model's and the tests' JSON texts (as `bearing-ident
/// field --rotor --tests` reads them), the GIL released; the result's JSON as `field --json`
/// prints it.
#[pyfunction]
fn field(py: Python<'_>, rotor: String, tests: String) -> PyResult<String> {
    use bearing_ident::field::{FieldTests, RotorModel, identify};
    let in_input =
        |what: &str, e: Error| NativeError::new_err((e.kind().as_str(), format!("{what}: {e}")));
    let rotor = RotorModel::from_json(&rotor).map_err(|e| in_input("rotor", e))?;
    let tests = FieldTests::from_json(&tests).map_err(|e| in_input("tests", e))?;
    let start = std::time::Instant::now();
    let id = py
        .detach(|| {
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| identify(&rotor, &tests)))
        })
        .map_err(|_| NativeError::new_err(("internal", "the field identification panicked")))?
        .map_err(|e| raise(&e))?;
    Ok(id.to_json(start.elapsed().as_secs_f64() * 1e3).to_string())
}

/// A square matrix from Python's rows, named by `what` when it is not one.
fn square(rows: &[Vec<f64>], what: &str) -> PyResult<bearing_ident::faer::Mat<f64>> {
    let n = rows.len();
    if n == 0 || rows.iter().any(|r| r.len() != n) {
        return Err(invalid(format!(
            "{what}: expected a square matrix (n_dof, n_dof), got {n} rows of lengths {:?}",
            rows.iter().map(Vec::len).collect::<Vec<_>>()
        )));
    }
    Ok(bearing_ident::faer::Mat::from_fn(n, n, |i, j| rows[i][j]))
}

/// Records of a simulated test, as `bearing-ident simulate` makes them
/// ([`bearing_ident::simulate::Setup`], options by long name) on the system `(M, C, K)` given
/// as rows, or the seed's rig; with the record length (s) the test chose.
#[pyfunction]
#[pyo3(signature = (options, system=None))]
fn simulate(
    py: Python<'_>,
    options: Vec<(String, String)>,
    system: Option<Blocks>,
) -> PyResult<(Vec<PyRecordOut>, f64)> {
    use bearing_ident::simulate::{Setup, seed_rig};
    let mut setup = Setup::default();
    for (name, value) in &options {
        setup.set(name, value).map_err(|e| raise(&e))?;
    }
    let system = match system {
        Some((m, c, k)) => bearing_ident::Coefficients::new(
            square(&m, "mass")?,
            square(&c, "damping")?,
            square(&k, "stiffness")?,
        )
        .map_err(|e| raise(&e))?,
        None => seed_rig(),
    };
    let test = py
        .detach(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| setup.run(&system))))
        .map_err(|_| NativeError::new_err(("internal", "the simulation panicked")))?
        .map_err(|e| raise(&e))?;
    Ok((
        test.records.iter().map(record_out).collect(),
        test.duration_s,
    ))
}

/// The Rust library's own time (ms) on the same records and options, `repeat` times: each run
/// builds the records from owned sample vectors (`Record::new`, as a Rust caller does) and
/// identifies them (`Job::run_records`); the vectors are cloned before the clock starts. The
/// reference of `benches/overhead.py`.
#[pyfunction]
fn _rust_reference_ms(
    py: Python<'_>,
    records: Vec<PyRecordIn<'_>>,
    options: Vec<(String, String)>,
    repeat: usize,
) -> PyResult<Vec<f64>> {
    let (records, borrows, job) = records_and_job(&records, &options)?;
    let owned = |r: &Record| {
        let n = r.dofs();
        (
            (0..n).map(|i| r.force(i).to_vec()).collect::<Vec<_>>(),
            (0..n)
                .map(|i| r.displacement(i).to_vec())
                .collect::<Vec<_>>(),
        )
    };
    let times = py.detach(|| {
        (0..repeat)
            .map(|_| {
                let data: Vec<_> = records.iter().map(owned).collect();
                let start = std::time::Instant::now();
                let built = records
                    .iter()
                    .zip(data)
                    .map(|(r, (f, x))| {
                        Record::new(r.label(), r.sample_rate(), f, x)?
                            .with_responses(r.responses().to_vec())
                    })
                    .collect::<bearing_ident::Result<Vec<_>>>()?;
                std::hint::black_box(job.run_records(built)?);
                Ok(start.elapsed().as_secs_f64() * 1e3)
            })
            .collect::<bearing_ident::Result<Vec<f64>>>()
    });
    drop(borrows);
    times.map_err(|e| raise(&e))
}

/// The address of each channel's first sample in the crate's record built from `record`
/// (as `identify` builds it): `(forces, responses)`, to show which arrays are read in place.
#[pyfunction]
fn _sample_addresses(record: PyRecordIn<'_>) -> PyResult<(Vec<usize>, Vec<usize>)> {
    let r = self::record(&record, &mut Vec::new())?;
    let first = |c: &[f64]| c.as_ptr() as usize;
    let n = r.dofs();
    Ok((
        (0..n).map(|i| first(r.force(i))).collect(),
        (0..n).map(|i| first(r.displacement(i))).collect(),
    ))
}

/// Panics inside the crate's call, to show that a panic becomes an exception.
#[pyfunction]
fn _panic_for_test(py: Python<'_>) -> PyResult<()> {
    py.detach(|| std::panic::catch_unwind(|| panic!("a test panic")))
        .map_err(|_| NativeError::new_err(("internal", "the call panicked")))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("NativeError", m.py().get_type::<NativeError>())?;
    // Every kind the crate names, and `internal` for a panic caught at the boundary.
    let mut kinds: Vec<&str> = ErrorKind::ALL.iter().map(|k| k.as_str()).collect();
    kinds.push("internal");
    m.add("ERROR_KINDS", kinds)?;
    m.add("OPTION_NAMES", Options::NAMES.to_vec())?;
    m.add(
        "SIMULATE_OPTION_NAMES",
        bearing_ident::simulate::Setup::NAMES.to_vec(),
    )?;
    m.add_class::<NativeResult>()?;
    m.add_class::<NativeCampaign>()?;
    m.add_function(wrap_pyfunction!(campaign, m)?)?;
    m.add_function(wrap_pyfunction!(field, m)?)?;
    m.add_function(wrap_pyfunction!(identify, m)?)?;
    m.add_function(wrap_pyfunction!(read_files, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    m.add_function(wrap_pyfunction!(_rust_reference_ms, m)?)?;
    m.add_function(wrap_pyfunction!(_sample_addresses, m)?)?;
    Ok(())
}
