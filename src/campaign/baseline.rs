//! The baseline a point subtracts. When the point's settings are its baseline point's, that
//! point's own result; else the baseline point's files identified again with the point's
//! settings (read by the baseline point's channels), so that band, lines, estimator and window
//! are the point's and the subtraction is never refused as a mismatch. Such an identification
//! is made once for every point that shares its settings, and cached as a point is: under the
//! digest of the baseline's files and the settings used.

use std::path::PathBuf;

use serde_json::Value as Json;

use crate::job::{Job, Options};

/// Which identification of its baseline point a point subtracts: JSON
/// `bearing.baseline_settings`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Settings {
    /// `own`: the baseline point's own result (the two points' settings are the same).
    Own,
    /// `point`: the baseline point's files identified again with this point's settings.
    Point,
}

impl Settings {
    /// The name in JSON.
    pub(super) fn name(self) -> &'static str {
        match self {
            Settings::Own => "own",
            Settings::Point => "point",
        }
    }

    /// The settings a point's JSON names (`bearing.baseline_settings`), if it has a baseline.
    pub(super) fn of(json: &Json) -> Option<Self> {
        match json.get("bearing")?.get("baseline_settings")?.as_str()? {
            "own" => Some(Settings::Own),
            "point" => Some(Settings::Point),
            _ => None,
        }
    }
}

/// How a point gets its baseline: the baseline point (an index into the plan's points) and the
/// identification of its files again (an index into the list [`uses`] returns), or `None` for
/// the baseline point's own result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Use {
    pub(super) point: usize,
    pub(super) again: Option<usize>,
}

impl Use {
    /// Which of the baseline point's results is subtracted.
    pub(super) fn settings(self) -> Settings {
        match self.again {
            None => Settings::Own,
            Some(_) => Settings::Point,
        }
    }
}

/// A baseline point's files to identify again with another point's settings.
pub(super) struct Again {
    /// The baseline point (an index into the plan's points).
    pub(super) point: usize,
    /// The other point's options with the baseline point's channels.
    pub(super) job: Job,
    /// The baseline point's files.
    pub(super) files: Vec<PathBuf>,
}

impl Again {
    /// The job and its files.
    pub(super) fn work(&self) -> (&Job, &[PathBuf]) {
        (&self.job, &self.files)
    }
}

/// What a point's baseline is identified with: its options, less a `baseline` of its own
/// (what is subtracted is always the baseline point's system).
fn settings(job: &Job) -> Options {
    Options {
        baseline: None,
        ..job.options().clone()
    }
}

/// Each point's baseline (`None` for a point without one), from the points' `baselines` and
/// their `jobs` and files (`None` for a point that cannot run); and the identifications to make
/// again, one for each baseline point and distinct settings that differ from its own. A point
/// or a baseline point that cannot run uses the baseline point's own result: the point fails
/// with its own error or its baseline point's.
pub(super) fn uses(
    baselines: &[Option<usize>],
    jobs: &[Option<(&Job, &[PathBuf])>],
) -> (Vec<Option<Use>>, Vec<Again>) {
    let mut again: Vec<Again> = Vec::new();
    let uses = baselines
        .iter()
        .zip(jobs)
        .map(|(&baseline, point)| {
            let j = baseline?;
            let own = Use {
                point: j,
                again: None,
            };
            let (Some((job, _)), Some((dry, files))) = (point, jobs[j]) else {
                return Some(own);
            };
            let wanted = settings(job);
            if wanted == settings(dry) {
                return Some(own);
            }
            let k = match again
                .iter()
                .position(|a| a.point == j && *a.job.options() == wanted)
            {
                Some(k) => k,
                None => {
                    again.push(Again {
                        point: j,
                        job: Job::new(wanted, dry.channels().clone()),
                        files: files.to_vec(),
                    });
                    again.len() - 1
                }
            };
            Some(Use {
                point: j,
                again: Some(k),
            })
        })
        .collect();
    (uses, again)
}

/// Names in the `bearing` of a point's `json` the baseline point subtracted
/// (`baseline_point`) and which of its results (`baseline_settings`: `own` or `point`).
pub(super) fn annotate(json: &mut Json, baseline_point: &str, settings: Settings) {
    if let Some(bearing) = json.get_mut("bearing").and_then(Json::as_object_mut) {
        bearing.insert("baseline_point".into(), baseline_point.into());
        bearing.insert("baseline_settings".into(), settings.name().into());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::Channels;

    fn job(band: &str, baseline: Option<&str>) -> Job {
        let mut o = Options::new(f64::NAN, f64::NAN);
        o.set("band", band).unwrap();
        if let Some(b) = baseline {
            o.set("baseline", b).unwrap();
        }
        Job::new(o, Channels::default())
    }

    /// Same settings: the baseline point's own result; other settings: one identification
    /// again per baseline point and settings, shared by the points that have them; a point
    /// whose baseline point cannot run uses that point's (failed) result.
    #[test]
    fn baselines_are_identified_again_only_at_other_settings() {
        let files = vec![PathBuf::from("dry/a.csv")];
        let (dry, same, narrow, narrow_too, other) = (
            job("8,49", None),
            job("8,49", Some("elsewhere/")),
            job("9,48", None),
            job("9,48", None),
            job("10,40", None),
        );
        let jobs: Vec<Option<(&Job, &[PathBuf])>> = [&dry, &same, &narrow, &narrow_too, &other]
            .into_iter()
            .map(|j| Some((j, files.as_slice())))
            .chain([None])
            .collect();
        let baselines = [None, Some(0), Some(0), Some(0), Some(0), Some(0)];
        let (each, again) = uses(&baselines, &jobs);
        let own = Use {
            point: 0,
            again: None,
        };
        let at = |k| Use {
            point: 0,
            again: Some(k),
        };
        assert_eq!(
            each,
            [
                None,
                Some(own),
                Some(at(0)),
                Some(at(0)),
                Some(at(1)),
                Some(own)
            ]
        );
        assert_eq!(again.len(), 2);
        assert_eq!(again[0].job.options().band, (9.0, 48.0));
        assert_eq!(again[1].job.options().band, (10.0, 40.0));
        assert_eq!(again[0].files, files);
        assert_eq!(each[2].map(Use::settings), Some(Settings::Point));
        assert_eq!(each[1].map(Use::settings), Some(Settings::Own));
        // A baseline point that cannot run: its own (failed) result.
        let (each, again) = uses(&[None, Some(0)], &[None, jobs[2]]);
        assert_eq!(each, [None, Some(own)]);
        assert!(again.is_empty());
    }

    /// The settings are named in the bearing and read back; a result without a bearing is
    /// left as it is.
    #[test]
    fn the_bearing_names_its_baseline() {
        let mut json = serde_json::json!({ "K": [[1.0]], "bearing": { "baseline": "point dry" } });
        annotate(&mut json, "dry", Settings::Point);
        assert_eq!(json["bearing"]["baseline_point"], "dry");
        assert_eq!(json["bearing"]["baseline_settings"], "point");
        assert_eq!(Settings::of(&json), Some(Settings::Point));
        let mut plain = serde_json::json!({ "K": [[1.0]] });
        annotate(&mut plain, "dry", Settings::Own);
        assert_eq!(plain, serde_json::json!({ "K": [[1.0]] }));
        assert_eq!(Settings::of(&plain), None);
    }
}
