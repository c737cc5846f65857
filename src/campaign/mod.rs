//! A test campaign: many test points (operating conditions) identified from one plan, with
//! their coefficients tabulated against the conditions, checked against independent
//! references, and handed to ROSS as tables over rotor speed (feature `campaign`).
//!
//! A plan is TOML:
//!
//! ```toml
//! [identify]                 # shared options: any `identify` option by its long name
//! band = [8.0, 49.0]
//! method = "ivf"
//! [conditions]               # the test variables and their units
//! speed = "rpm"              # speed: rpm, rad/s, Hz; load: N, kN, lbf; else free text
//! air_fraction = "1"
//! [geometry]                 # optional: probe planes moved to the bearing plane
//! mode = "conical"
//! pivot = 0.0                # m, axial positions from one datum
//! bearing = 0.151
//! probes = [0.213, 0.254]    # one per response channel
//! [[point]]
//! name = "dry"
//! files = ["dry/*.csv"]      # globs, relative to the plan's folder
//! speed = 0
//! air_fraction = 1.0
//! [point.expect]             # independent references: value, standard uncertainty
//! M_xx = [4.02, 0.1]
//! [[point]]
//! name = "oil"
//! files = ["oil/*.csv"]
//! speed = 3000
//! air_fraction = 0.0
//! baseline = "dry"           # subtract that point's coefficients (variances add)
//! identify = { band = [9.0, 48.0] }   # this point's own options (the baseline's too)
//! ```
//!
//! Each point is identified by [`Job`](crate::job::Job), the path `identify` takes, with the
//! command's defaults, then the shared options, then its own: a point's JSON is that of
//! `identify --json` on its files with those options (and `--baseline` the saved JSON of its
//! baseline point's files identified with those options too). A baseline is subtracted at the
//! point's settings: the baseline point's own result when their settings are the same, else
//! the baseline point's files identified again with the point's (cached as points are; its
//! own row keeps its own settings); the point's `bearing` says which, `baseline_point` and
//! `baseline_settings` (`own` or `point`). Points run in parallel ([`RunOptions::jobs`]); one
//! that fails carries its [`Failure`] and the others complete. A reference `expect`ed is compared with the
//! identified value, `z = (value − reference)/√(σ² + σ_ref²)`; |z| > 3 adds the warning
//! `reference_mismatch`.
//!
//! | file | what lives there |
//! |---|---|
//! | `point.rs` | what a plan names: [`Unit`], [`Condition`], [`Value`], [`Coefficient`], [`Point`] |
//! | `settings.rs` | a point's options, channels and files from the plan's settings and its own |
//! | `plan.rs` | [`Plan`] read from TOML, every fault named by line |
//! | `baseline.rs` | which result of its baseline point a point subtracts: that point's own, or its files identified again at the point's settings |
//! | `cache.rs` | results kept by a digest of the files' bytes and the settings |
//! | `run.rs` | [`Plan::run`]: files, jobs, parallel identifications, baselines, references |
//! | `output.rs` | [`Campaign::to_json`], [`Campaign::to_csv`], [`Campaign::to_table`] |
//! | `ross.rs` | [`SpeedTable`]: the bearing over rotor speed for ROSS 3.x |
//!
//! # Examples
//! ```
//! use bearing_ident::campaign::{Plan, RunOptions};
//! use bearing_ident::io::{CsvLayout, write_record};
//! use bearing_ident::simulate::{ImpactTest, seed_rig};
//! let dir = tempfile::tempdir()?;
//! std::fs::create_dir(dir.path().join("dry"))?;
//! let hits = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
//! for (i, r) in hits.iter().enumerate() {
//!     write_record(dir.path().join(format!("dry/hit-{i}.csv")), r, &CsvLayout::default())?;
//! }
//! let plan = dir.path().join("plan.toml");
//! std::fs::write(&plan, "[identify]\nband = [8.0, 49.0]\n[conditions]\nspeed = \"rpm\"\n\
//!     [[point]]\nname = \"dry\"\nfiles = \"dry/*.csv\"\nspeed = 0\n\
//!     [point.expect]\nK_xx = [146.3e3, 1e3]\n")?;
//! let campaign = Plan::read(&plan)?.run(&RunOptions::default(), |_, _| {})?;
//! let fit = campaign.points[0].result.as_ref().unwrap();
//! assert!((fit.coefficients.stiffness()[(0, 0)] / 146.3e3 - 1.0).abs() < 1e-6);
//! assert!(fit.checks[0].z.unwrap().abs() < 1e-3);
//! assert_eq!(campaign.points[0].files.len(), 4);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod baseline;
mod cache;
mod output;
mod plan;
mod point;
mod ross;
mod run;
mod samples;
mod settings;

pub use output::json_file_name;
pub use plan::Plan;
pub(crate) use point::axis_names;
pub use point::{Coefficient, Condition, Expectation, Point, Setting, Unit, Value};
pub use ross::SpeedTable;
pub use run::{Campaign, Check, Failure, Fit, PointResult, RunOptions};
pub use samples::SpeedSamples;
