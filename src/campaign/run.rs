//! Running a plan: each point's files found, its [`Job`] built from the shared options and its
//! own, the points (and the baselines to identify again at a point's settings) identified in
//! parallel or taken from the cache, then baselines subtracted and references checked.

use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use faer::Mat;
use serde_json::Value as Json;

use super::baseline::{self, Again, Settings, Use};
use super::cache::{self, Cache};
use super::plan::Plan;
use super::point::{Coefficient, Point, Value};
use crate::error::{Error, Result, excerpt};
use crate::identify::Baseline;
use crate::job::{Job, Outcome};
use crate::model::Coefficients;

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
    /// The bearing's own (the system less its baseline point's, identified at this point's
    /// settings) and their standard deviations.
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

/// One identification of a run: a point's, or a baseline point's files at another point's
/// settings (an index into the baselines identified again).
#[derive(Debug, Clone, Copy)]
enum Work {
    Point(usize),
    Again(usize),
}

/// Outcomes of a run's identifications, at the index of what they identified (`None`: not
/// identified now).
type Outcomes = Vec<Option<std::result::Result<Outcome, Failure>>>;

impl Plan {
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
    /// baseline fails when its baseline point does, or when the baseline point's files, at
    /// this point's settings, do.
    ///
    /// # Errors
    /// Only the cache's: a folder that cannot be made or written ([`Error::Io`]).
    pub fn run(&self, run: &RunOptions, observe: impl Fn(usize, usize) + Sync) -> Result<Campaign> {
        let pf = run.per_frequency;
        let prepared: Vec<std::result::Result<Prepared, Failure>> = self
            .points
            .iter()
            .map(|p| self.prepare(p).map_err(Failure::from))
            .collect();
        let baselines: Vec<Option<usize>> = self.points.iter().map(|p| p.baseline).collect();
        let work_of: Vec<Option<(&Job, &[PathBuf])>> = prepared
            .iter()
            .map(|p| p.as_ref().ok().map(|p| (&p.job, p.files.as_slice())))
            .collect();
        let (uses, again) = baseline::uses(&baselines, &work_of);
        let cache = run.cache.as_deref().map(Cache::open).transpose()?;
        // Each point's key: its settings, its files' bytes and its baseline's key; each
        // baseline identified again, its own.
        let (keys, again_keys) = match &cache {
            None => (vec![None; self.points.len()], vec![None; again.len()]),
            Some(_) => keys(&work_of, &uses, &again, pf),
        };
        let load = |key: &Option<String>| key.as_ref().and_then(|k| cache.as_ref()?.load(k));
        let cached: Vec<Option<Json>> = keys.iter().map(load).collect();
        let reused = cached.iter().filter(|c| c.is_some()).count();
        // A baseline identified again is wanted while a point using it is not in the cache.
        let wanted: Vec<bool> = (0..again.len())
            .map(|k| {
                uses.iter()
                    .zip(&cached)
                    .any(|(u, c)| c.is_none() && u.is_some_and(|u| u.again == Some(k)))
            })
            .collect();
        let again_cached: Vec<Option<Json>> = again_keys
            .iter()
            .zip(&wanted)
            .map(|(key, &w)| if w { load(key) } else { None })
            .collect();
        let work: Vec<Work> = (0..again.len())
            .filter(|&k| wanted[k] && again_cached[k].is_none())
            .map(Work::Again)
            .chain(
                (0..self.points.len())
                    .filter(|&i| cached[i].is_none())
                    .map(Work::Point),
            )
            .collect();
        let (mut outcomes, again_outcomes) =
            identify(&prepared, &again, &work, reused, run.jobs.max(1), &observe);
        // The systems' JSON (a point with a baseline gets its own below, once, unless another
        // point subtracts its own result), then the bearings of the points with baselines.
        let subtracted: Vec<bool> = (0..self.points.len())
            .map(|j| {
                uses.iter()
                    .flatten()
                    .any(|u| u.point == j && u.again.is_none())
            })
            .collect();
        let mut json: Vec<std::result::Result<Json, Failure>> = outcomes
            .iter()
            .zip(&cached)
            .enumerate()
            .map(|(i, (o, c))| match (c, o) {
                (Some(c), _) => Ok(c.clone()),
                (None, Some(Ok(_))) if uses[i].is_some() && !subtracted[i] => Ok(Json::Null),
                (None, Some(Ok(o))) => o.to_json(pf).map_err(Failure::from),
                (None, Some(Err(e))) => Err(e.clone()),
                (None, None) => unreachable!("every point not in the cache is identified"),
            })
            .collect();
        let again_fresh: Vec<bool> = again_cached.iter().map(Option::is_none).collect();
        let again_json: Vec<Option<std::result::Result<Json, Failure>>> = again_cached
            .into_iter()
            .zip(again_outcomes)
            .map(|(c, o)| match (c, o) {
                (Some(c), _) => Some(Ok(c)),
                (None, Some(o)) => Some(o.and_then(|o| o.to_json(pf).map_err(Failure::from))),
                (None, None) => None,
            })
            .collect();
        for (i, point) in self.points.iter().enumerate() {
            let (Some(u), None) = (uses[i], &cached[i]) else {
                continue;
            };
            // The outcome is taken out, given its bearing and put back: never copied.
            let Some(Ok(mut outcome)) = outcomes[i].take() else {
                continue;
            };
            let dry = match u.again {
                None => &json[u.point],
                Some(k) => again_json[k]
                    .as_ref()
                    .unwrap_or_else(|| unreachable!("a point not in the cache wants its baseline")),
            };
            let names = (point.name.as_str(), self.points[u.point].name.as_str());
            let bearing = subtract(&mut outcome, dry, names, u.settings(), pf);
            json[i] = bearing;
            outcomes[i] = Some(Ok(outcome));
        }
        if let Some(cache) = &cache {
            // What was identified now and did not fail, under its key.
            let points = keys
                .iter()
                .zip(cached.iter().map(Option::is_none))
                .zip(json.iter().map(|j| j.as_ref().ok()));
            let baselines = again_keys
                .iter()
                .zip(again_fresh)
                .zip(again_json.iter().map(|j| j.as_ref()?.as_ref().ok()));
            for ((key, fresh), j) in points.chain(baselines) {
                if let (Some(key), true, Some(j)) = (key, fresh, j) {
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
            per_frequency: pf,
        })
    }
}

/// The JSON of `outcome` (point `names.0`'s) less `dry`, the JSON of its baseline point
/// `names.1`'s files at `settings`, with per-line coefficients if `per_frequency`; or the
/// failure of either.
fn subtract(
    outcome: &mut Outcome,
    dry: &std::result::Result<Json, Failure>,
    names: (&str, &str),
    settings: Settings,
    per_frequency: bool,
) -> std::result::Result<Json, Failure> {
    let (point, baseline_point) = names;
    let dry = match dry {
        Ok(dry) => dry,
        Err(e) => {
            let at = match settings {
                Settings::Own => String::new(),
                Settings::Point => format!(" at point `{}`'s settings", excerpt(point)),
            };
            return Err(Failure {
                kind: e.kind.clone(),
                message: format!(
                    "baseline point `{}`{at} failed: {}",
                    excerpt(baseline_point),
                    e.message
                ),
            });
        }
    };
    Baseline::from_json(&dry.to_string())
        .and_then(|b| outcome.subtract_baseline(b, &format!("point {baseline_point}")))
        .and_then(|()| outcome.to_json(per_frequency))
        .map(|mut json| {
            baseline::annotate(&mut json, baseline_point, settings);
            json
        })
        .map_err(Failure::from)
}

/// The identifications of `work` made on `jobs` threads, telling `observe` of each point done
/// (`done` points were before, from the cache): the points' outcomes at their indices, and the
/// baselines' identified again at theirs (`None` for what was not identified now).
fn identify(
    prepared: &[std::result::Result<Prepared, Failure>],
    again: &[Again],
    work: &[Work],
    done: usize,
    jobs: usize,
    observe: &(impl Fn(usize, usize) + Sync),
) -> (Outcomes, Outcomes) {
    let slots: Vec<Mutex<Option<std::result::Result<Outcome, Failure>>>> =
        work.iter().map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(done);
    std::thread::scope(|scope| {
        for _ in 0..jobs.min(work.len()) {
            scope.spawn(|| {
                loop {
                    let at = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&w) = work.get(at) else {
                        break;
                    };
                    let outcome = match w {
                        Work::Point(i) => match &prepared[i] {
                            Ok(p) => p.job.run_files(&p.files).map_err(Failure::from),
                            Err(e) => Err(e.clone()),
                        },
                        Work::Again(k) => {
                            let (job, files) = again[k].work();
                            job.run_files(files).map_err(Failure::from)
                        }
                    };
                    *slots[at].lock().unwrap_or_else(|e| e.into_inner()) = Some(outcome);
                    if let Work::Point(i) = w {
                        observe(i, done.fetch_add(1, Ordering::Relaxed) + 1);
                    }
                }
            });
        }
    });
    let mut points: Outcomes = (0..prepared.len()).map(|_| None).collect();
    let mut baselines: Outcomes = (0..again.len()).map(|_| None).collect();
    for (w, slot) in work.iter().zip(slots) {
        let outcome = slot.into_inner().unwrap_or_else(|e| e.into_inner());
        match *w {
            Work::Point(i) => points[i] = outcome,
            Work::Again(k) => baselines[k] = outcome,
        }
    }
    (points, baselines)
}

/// The cache keys of the points (`None` for a point that cannot run) and of the baselines
/// identified `again`: a point's own chained with that of the baseline it subtracts (its
/// baseline point's own result, or its files at this point's settings).
fn keys(
    work_of: &[Option<(&Job, &[PathBuf])>],
    uses: &[Option<Use>],
    again: &[Again],
    per_frequency: bool,
) -> (Vec<Option<String>>, Vec<Option<String>>) {
    let key = |(job, files): (&Job, &[PathBuf])| cache::key(job, files, per_frequency).ok();
    let own: Vec<Option<String>> = work_of.iter().map(|w| key((*w)?)).collect();
    let again_keys: Vec<Option<String>> = again.iter().map(|a| key(a.work())).collect();
    let keys = own
        .iter()
        .zip(uses)
        .map(|(own_key, u)| {
            let own_key = own_key.as_deref()?;
            let Some(u) = u else {
                return Some(own_key.to_owned());
            };
            let baseline = match u.again {
                None => own[u.point].as_deref()?,
                Some(k) => again_keys[k].as_deref()?,
            };
            Some(cache::chain(own_key, baseline))
        })
        .collect();
    (keys, again_keys)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::{Channels, Options};
    use crate::simulate::{ImpactTest, seed_rig};

    /// A baseline's result is subtracted and named in the bearing; a baseline that failed
    /// fails the point with its kind, naming the baseline point and, for its files identified
    /// again, the point whose settings they were identified at.
    #[test]
    fn a_baseline_is_subtracted_or_its_failure_named() {
        let records = ImpactTest {
            per_direction: 2,
            ..ImpactTest::seed_rig()
        }
        .run(&seed_rig())
        .unwrap();
        let mut outcome = Job::new(Options::new(8.0, 49.0), Channels::default())
            .run_records(records)
            .unwrap();
        let itself = Ok(outcome.to_json(false).unwrap());
        let json = subtract(&mut outcome, &itself, ("oil", "dry"), Settings::Own, false).unwrap();
        assert_eq!(json["bearing"]["K"][0][0], 0.0);
        assert_eq!(json["bearing"]["baseline"], "point dry");
        assert_eq!(json["bearing"]["baseline_point"], "dry");
        assert_eq!(json["bearing"]["baseline_settings"], "own");
        let failed = Err(Failure {
            kind: "dead_channel".into(),
            message: "dry/hit-0.csv: force `fx` is flat".into(),
        });
        let e = subtract(
            &mut outcome,
            &failed,
            ("oil", "dry"),
            Settings::Point,
            false,
        )
        .unwrap_err();
        assert_eq!(e.kind, "dead_channel");
        assert_eq!(
            e.message,
            "baseline point `dry` at point `oil`'s settings failed: dry/hit-0.csv: force `fx` \
             is flat"
        );
        let e = subtract(&mut outcome, &failed, ("oil", "dry"), Settings::Own, false).unwrap_err();
        assert!(
            e.message.starts_with("baseline point `dry` failed: "),
            "{}",
            e.message
        );
    }
}
