//! Running a plan: each point's files found, its [`Job`] built from the shared options and its
//! own, the points identified in parallel (or taken from the cache), then baselines
//! subtracted and references checked.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use faer::Mat;
use serde_json::Value as Json;

use super::cache::Cache;
use super::plan::Plan;
use super::point::{Coefficient, Point, Setting, Value};
use crate::error::{Error, Result, excerpt};
use crate::identify::Baseline;
use crate::job::{Channels, Job, Options, Outcome};
use crate::model::Coefficients;
use crate::records::Response;

/// The options of `identify` that name channels rather than set the identification.
pub(super) const CHANNEL_NAMES: [&str; 5] = ["force", "disp", "resp", "response", "time"];

/// Whether `name` (with `-` between words) is an option a plan can set.
pub(super) fn is_setting(name: &str) -> bool {
    Options::NAMES.contains(&name) || CHANNEL_NAMES.contains(&name)
}

/// Every option a plan can set, for messages.
pub(super) fn setting_names() -> String {
    Options::NAMES
        .iter()
        .chain(&CHANNEL_NAMES)
        .copied()
        .collect::<Vec<_>>()
        .join(", ")
}

/// How a campaign runs (not what it identifies: that is the plan's).
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Points identified at once (at least 1).
    pub jobs: usize,
    /// A folder keeping each point's result by a digest of its files and settings; a rerun
    /// reuses what did not change.
    pub cache: Option<PathBuf>,
    /// Keep the per-line `K(ω)`, `C(ω)` in each point's JSON (for 2-D ROSS tables).
    pub per_frequency: bool,
}

impl Default for RunOptions {
    /// As many jobs as the machine has cores, no cache, no per-line coefficients.
    fn default() -> Self {
        Self {
            jobs: std::thread::available_parallelism().map_or(1, usize::from),
            cache: None,
            per_frequency: false,
        }
    }
}

/// A point's failure, as the command line reports it: the error's kind and message.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    /// The error's kind ([`Error::kind`]).
    pub kind: String,
    /// Its message.
    pub message: String,
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Self {
            kind: e.kind().as_str().to_owned(),
            message: e.to_string(),
        }
    }
}

/// An `expect` reference compared with the identified value: `z = (value − reference) /
/// √(std² + reference_std²)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// The coefficient.
    pub coefficient: Coefficient,
    /// The reference value.
    pub reference: f64,
    /// Its standard uncertainty.
    pub reference_std: f64,
    /// The identified value (the bearing's own when the point has a baseline).
    pub value: f64,
    /// Its standard deviation, if the identification has error bars.
    pub std: Option<f64>,
    /// The z-score; `None` when both uncertainties are zero.
    pub z: Option<f64>,
}

impl Check {
    /// Whether the reference and the value disagree: |z| > 3, or unequal with no
    /// uncertainty at all.
    pub fn mismatch(&self) -> bool {
        match self.z {
            Some(z) => z.abs() > 3.0,
            None => (self.value - self.reference).abs() > 0.0,
        }
    }
}

/// A point's identification: the JSON `identify --json` prints for its files and options
/// (with `bearing` when it has a baseline), and what the campaign reads from it.
#[derive(Debug, Clone)]
pub struct Fit {
    /// The point's result as `identify --json` prints it.
    pub json: Json,
    /// The system's coefficients.
    pub coefficients: Coefficients,
    /// Their standard deviations, if any.
    pub std_dev: Option<Coefficients>,
    /// The bearing's own (system less the baseline point) and their standard deviations.
    pub bearing: Option<(Coefficients, Option<Coefficients>)>,
    /// The kinds of the identification's warnings, then `reference_mismatch` for each
    /// failed check.
    pub warning_kinds: Vec<String>,
    /// The identification's warnings, then one per failed check.
    pub warnings: Vec<String>,
    /// The `expect` references compared.
    pub checks: Vec<Check>,
    /// Whether the result came from the cache.
    pub reused: bool,
    /// The run itself, for a point identified now (`None` when taken from the cache): its
    /// identification with the spectra, fit and diagnostics a report draws.
    pub outcome: Option<Box<Outcome>>,
}

impl Fit {
    /// The coefficients the campaign reports: the bearing's own when the point has a
    /// baseline, else the system's; with their standard deviations.
    pub fn reported(&self) -> (&Coefficients, Option<&Coefficients>) {
        match &self.bearing {
            Some((c, s)) => (c, s.as_ref()),
            None => (&self.coefficients, self.std_dev.as_ref()),
        }
    }
}

/// One point's outcome.
#[derive(Debug, Clone)]
pub struct PointResult {
    /// The point's name.
    pub name: String,
    /// Its condition values, in the plan's order.
    pub values: Vec<Option<Value>>,
    /// The files its patterns matched.
    pub files: Vec<String>,
    /// The identification, or why there is none.
    pub result: std::result::Result<Fit, Failure>,
}

/// A campaign run: the plan and every point's outcome, in the plan's order.
#[derive(Debug, Clone)]
pub struct Campaign {
    /// The plan run.
    pub plan: Plan,
    /// The points, in the plan's order.
    pub points: Vec<PointResult>,
    /// Points taken from the cache.
    pub reused: usize,
    /// Whether the points carry per-line coefficients.
    pub per_frequency: bool,
}

impl Campaign {
    /// Whether any point failed.
    pub fn any_failed(&self) -> bool {
        self.points.iter().any(|p| p.result.is_err())
    }
}

/// A point ready to run: its job and files, or why it cannot run.
struct Prepared {
    job: Job,
    files: Vec<PathBuf>,
}

impl Plan {
    /// The options of `point`: the command's defaults, then the shared settings, then the
    /// point's own, in order; and its channel settings (name, text).
    ///
    /// # Errors
    /// [`Options::set`]'s, named with the plan's line; [`Error::Plan`] when no band is given.
    pub(super) fn options_of(&self, point: &Point) -> Result<(Options, Vec<Setting>)> {
        let mut o = Options::new(f64::NAN, f64::NAN);
        let mut channels = Vec::new();
        let mut band = false;
        for s in self.shared.iter().chain(&point.overrides) {
            if CHANNEL_NAMES.contains(&s.name.as_str()) {
                channels.push(s.clone());
                continue;
            }
            band |= s.name == "band";
            o.set(&s.name, &s.text).map_err(|e| Error::Plan {
                file: self.source.clone(),
                line: s.line,
                message: e.to_string(),
            })?;
        }
        if !band {
            return Err(Error::Plan {
                file: self.source.clone(),
                line: point.line,
                message: format!(
                    "point `{}` has no band: give `band = [LO, HI]` in [identify] or its own \
                     identify table",
                    excerpt(&point.name)
                ),
            });
        }
        Ok((o, channels))
    }

    /// The channels the point named `name` reads its files by (its channel settings and the
    /// plan's geometry).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a name that is no point; the channel settings' errors.
    pub fn channels_of(&self, name: &str) -> Result<Channels> {
        let point =
            self.points
                .iter()
                .find(|p| p.name == name)
                .ok_or_else(|| Error::InvalidOption {
                    option: "point",
                    message: format!("no point `{}` in the plan", excerpt(name)),
                })?;
        let (_, settings) = self.options_of(point)?;
        let files = self.files(point).unwrap_or_default();
        self.channels(&settings, &files)
    }

    /// The channels of a point from its channel settings, for `files`.
    pub(super) fn channels(&self, settings: &[Setting], files: &[PathBuf]) -> Result<Channels> {
        let list = |names: &[&str]| -> Vec<String> {
            settings
                .iter()
                .rev()
                .find(|s| names.contains(&s.name.as_str()))
                .map(|s| s.text.split(',').map(|c| c.trim().to_owned()).collect())
                .unwrap_or_default()
        };
        let responses = list(&["response"])
            .iter()
            .map(|r| r.parse::<Response>())
            .collect::<Result<Vec<_>>>()?;
        let time = list(&["time"]).pop().unwrap_or_else(|| "t".to_owned());
        let mut channels = Channels::named(
            &list(&["force"]),
            &list(&["disp", "resp"]),
            &responses,
            &time,
            files,
        )?;
        channels.geometry.clone_from(&self.geometry);
        Ok(channels)
    }

    /// The files of `point`: each pattern matched (relative to the plan's folder), in
    /// sorted order within a pattern, patterns in the order given.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] (`files`) for a pattern that does not parse or matches no
    /// file.
    fn files(&self, point: &Point) -> Result<Vec<PathBuf>> {
        let mut out = Vec::new();
        for pattern in &point.files {
            let full = if Path::new(pattern).is_absolute() {
                PathBuf::from(pattern)
            } else {
                self.base.join(pattern)
            };
            let text = full.to_string_lossy();
            let bad = |message: String| Error::InvalidOption {
                option: "files",
                message,
            };
            let matches =
                glob::glob(&text).map_err(|e| bad(format!("files `{}`: {e}", excerpt(pattern))))?;
            let mut found: Vec<PathBuf> = matches.filter_map(std::result::Result::ok).collect();
            found.sort();
            if found.is_empty() {
                return Err(bad(format!(
                    "point `{}`: no file matches `{}`",
                    excerpt(&point.name),
                    excerpt(&text)
                )));
            }
            out.extend(found);
        }
        Ok(out)
    }

    /// The job of `point` and its files.
    fn prepare(&self, point: &Point) -> Result<Prepared> {
        let (options, channel_settings) = self.options_of(point)?;
        let files = self.files(point)?;
        let channels = self.channels(&channel_settings, &files)?;
        Ok(Prepared {
            job: Job::new(options, channels),
            files,
        })
    }

    /// Runs every point (see the [module docs](super)), telling `observe` of each point
    /// done (its index, and how many are done).
    ///
    /// A point that fails carries its [`Failure`]; the others complete. A point with a
    /// baseline fails when its baseline point does.
    ///
    /// # Errors
    /// Only the cache's: a folder that cannot be made or written ([`Error::Io`]).
    pub fn run(&self, run: &RunOptions, observe: impl Fn(usize, usize) + Sync) -> Result<Campaign> {
        let prepared: Vec<std::result::Result<Prepared, Failure>> = self
            .points
            .iter()
            .map(|p| self.prepare(p).map_err(Failure::from))
            .collect();
        let cache = run.cache.as_deref().map(Cache::open).transpose()?;
        // Each point's key: its settings, its files' bytes and its baseline's key.
        let keys: Vec<Option<String>> = match &cache {
            None => vec![None; self.points.len()],
            Some(_) => self.keys(&prepared, run.per_frequency),
        };
        let cached: Vec<Option<Json>> = keys
            .iter()
            .map(|k| k.as_ref().and_then(|k| cache.as_ref()?.load(k)))
            .collect();
        let reused = cached.iter().filter(|c| c.is_some()).count();
        let mut outcomes = self.identify(&prepared, &cached, run.jobs.max(1), &observe);
        // The systems' JSON (a point with a baseline gets its own below, once, unless another
        // point subtracts it), then the bearings of the points with baselines.
        let subtracted: Vec<bool> = (0..self.points.len())
            .map(|i| self.points.iter().any(|p| p.baseline == Some(i)))
            .collect();
        let mut json: Vec<std::result::Result<Json, Failure>> = outcomes
            .iter()
            .zip(&cached)
            .enumerate()
            .map(|(i, (o, c))| match (c, o) {
                (Some(c), _) => Ok(c.clone()),
                (None, Some(Ok(_))) if self.points[i].baseline.is_some() && !subtracted[i] => {
                    Ok(Json::Null)
                }
                (None, Some(Ok(o))) => o.to_json(run.per_frequency).map_err(Failure::from),
                (None, Some(Err(e))) => Err(e.clone()),
                (None, None) => unreachable!("every point not in the cache is identified"),
            })
            .collect();
        for (i, point) in self.points.iter().enumerate() {
            let (Some(j), None) = (point.baseline, &cached[i]) else {
                continue;
            };
            // The outcome is taken out, given its bearing and put back: never copied.
            let Some(Ok(mut outcome)) = outcomes[i].take() else {
                continue;
            };
            json[i] = match &json[j] {
                Err(e) => Err(Failure {
                    kind: e.kind.clone(),
                    message: format!(
                        "baseline point `{}` failed: {}",
                        excerpt(&self.points[j].name),
                        e.message
                    ),
                }),
                Ok(dry) => Baseline::from_json(&dry.to_string())
                    .and_then(|b| {
                        outcome.subtract_baseline(b, &format!("point {}", self.points[j].name))
                    })
                    .and_then(|()| outcome.to_json(run.per_frequency))
                    .map_err(Failure::from),
            };
            outcomes[i] = Some(Ok(outcome));
        }
        if let Some(cache) = &cache {
            for ((key, c), j) in keys.iter().zip(&cached).zip(&json) {
                if let (Some(key), None, Ok(j)) = (key, c, j) {
                    cache.store(key, j)?;
                }
            }
        }
        let points = self
            .points
            .iter()
            .zip(json)
            .zip(&prepared)
            .zip(&cached)
            .zip(outcomes)
            .map(|((((point, json), prepared), cached), outcome)| {
                let files = match prepared {
                    Ok(p) => p.files.iter().map(|f| f.display().to_string()).collect(),
                    Err(_) => Vec::new(),
                };
                PointResult {
                    name: point.name.clone(),
                    values: point.values.clone(),
                    files,
                    result: json
                        .and_then(|j| fit(point, j, cached.is_some()))
                        .map(|mut f| {
                            f.outcome = outcome.and_then(std::result::Result::ok).map(Box::new);
                            f
                        }),
                }
            })
            .collect();
        Ok(Campaign {
            plan: self.clone(),
            points,
            reused,
            per_frequency: run.per_frequency,
        })
    }

    /// The points not in the cache identified on `jobs` threads, each point's outcome at its
    /// index (`None` for the cached).
    fn identify(
        &self,
        prepared: &[std::result::Result<Prepared, Failure>],
        cached: &[Option<Json>],
        jobs: usize,
        observe: &(impl Fn(usize, usize) + Sync),
    ) -> Vec<Option<std::result::Result<Outcome, Failure>>> {
        let todo: Vec<usize> = (0..prepared.len())
            .filter(|&i| cached[i].is_none())
            .collect();
        let slots: Vec<Mutex<Option<std::result::Result<Outcome, Failure>>>> =
            (0..prepared.len()).map(|_| Mutex::new(None)).collect();
        let next = AtomicUsize::new(0);
        let done = AtomicUsize::new(prepared.len() - todo.len());
        std::thread::scope(|scope| {
            for _ in 0..jobs.min(todo.len()) {
                scope.spawn(|| {
                    while let Some(&i) = todo.get(next.fetch_add(1, Ordering::Relaxed)) {
                        let outcome = match &prepared[i] {
                            Ok(p) => p.job.run_files(&p.files).map_err(Failure::from),
                            Err(e) => Err(e.clone()),
                        };
                        *slots[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(outcome);
                        observe(i, done.fetch_add(1, Ordering::Relaxed) + 1);
                    }
                });
            }
        });
        slots
            .into_iter()
            .map(|s| s.into_inner().unwrap_or_else(|e| e.into_inner()))
            .collect()
    }

    /// Each point's cache key (`None` for a point that cannot run), its baseline's chained
    /// in.
    fn keys(
        &self,
        prepared: &[std::result::Result<Prepared, Failure>],
        per_frequency: bool,
    ) -> Vec<Option<String>> {
        let own: Vec<Option<String>> = prepared
            .iter()
            .map(|p| {
                let p = p.as_ref().ok()?;
                super::cache::key(&p.job, &p.files, per_frequency).ok()
            })
            .collect();
        self.points
            .iter()
            .enumerate()
            .map(|(i, point)| {
                let mut key = own[i].clone()?;
                let mut at = point.baseline;
                // Plans refuse cycles, so the chain ends.
                while let Some(j) = at {
                    key = super::cache::chain(&key, own[j].as_deref()?);
                    at = self.points[j].baseline;
                }
                Some(key)
            })
            .collect()
    }
}

/// The fit of `point` from its JSON (`reused`: from the cache): coefficients, bearing,
/// warnings and the `expect` checks.
fn fit(point: &Point, json: Json, reused: bool) -> std::result::Result<Fit, Failure> {
    let bad = |what: &str| Failure {
        kind: "bad_baseline".into(),
        message: format!("point `{}`: its result has no valid `{what}`", point.name),
    };
    let coefficients = block_set(&json, "").ok_or_else(|| bad("M, C, K"))?;
    let std_dev = block_set(&json, "_std");
    let bearing = json.get("bearing").map(|b| {
        block_set(b, "")
            .map(|c| (c, block_set(b, "_std")))
            .ok_or_else(|| bad("bearing"))
    });
    let bearing = bearing.transpose()?;
    let strings = |key: &str| -> Vec<String> {
        json.get(key)
            .and_then(Json::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(|s| s.as_str().map(str::to_owned))
                    .collect()
            })
            .unwrap_or_default()
    };
    let mut fit = Fit {
        warning_kinds: strings("warning_kinds"),
        warnings: strings("warnings"),
        json,
        coefficients,
        std_dev,
        bearing,
        checks: Vec::new(),
        reused,
        outcome: None,
    };
    for e in &point.expect {
        let (c, s) = fit.reported();
        let c0 = e.coefficient;
        if c0.row >= c.dofs() || c0.col >= c.dofs() {
            return Err(Failure {
                kind: "invalid_input".into(),
                message: format!(
                    "point `{}`: expect {} is outside the {n} × {n} coefficients",
                    point.name,
                    c0.name(),
                    n = c.dofs()
                ),
            });
        }
        let pick = |set: &Coefficients| {
            let m = match c0.block {
                'M' => set.mass(),
                'C' => set.damping(),
                _ => set.stiffness(),
            };
            m[(c0.row, c0.col)]
        };
        let value = pick(c);
        let std = s.map(pick);
        let scale = std.unwrap_or(0.0).hypot(e.std);
        let check = Check {
            coefficient: c0,
            reference: e.reference,
            reference_std: e.std,
            value,
            std,
            z: (scale > 0.0).then(|| (value - e.reference) / scale),
        };
        if check.mismatch() {
            fit.warning_kinds.push("reference_mismatch".into());
            fit.warnings.push(format!(
                "{} = {value:.4e} is {} from the reference {:.4e} ± {:.2e}: check the \
                 reference, the band and the model",
                c0.name(),
                check.z.map_or("far".to_owned(), |z| format!("{z:+.1} σ")),
                e.reference,
                e.std
            ));
        }
        fit.checks.push(check);
    }
    Ok(fit)
}

/// `M{suffix}`, `C{suffix}`, `K{suffix}` of `json` as coefficients, if all three are square
/// matrices of one size.
fn block_set(json: &Json, suffix: &str) -> Option<Coefficients> {
    let matrix = |key: &str| -> Option<Mat<f64>> {
        let rows = json.get(format!("{key}{suffix}"))?.as_array()?;
        let n = rows.len();
        let rows: Vec<Vec<f64>> = rows
            .iter()
            .map(|r| r.as_array()?.iter().map(Json::as_f64).collect())
            .collect::<Option<_>>()?;
        if n == 0 || rows.iter().any(|r| r.len() != n) {
            return None;
        }
        Some(Mat::from_fn(n, n, |i, j| rows[i][j]))
    };
    Coefficients::new(matrix("M")?, matrix("C")?, matrix("K")?).ok()
}
