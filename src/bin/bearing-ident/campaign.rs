//! `bearing-ident campaign PLAN.toml`: every test point of a plan identified (the library's
//! [`Plan::run`]), then the table, JSON, CSV, figures and ROSS speed table written. The exit
//! status is 1 when a point failed, after everything is written.

use std::path::PathBuf;

use bearing_ident::campaign::{Campaign, Plan, RunOptions, Value};
use bearing_ident::error::excerpt;

use crate::failure::{Failure, invalid, print_out};

#[derive(Debug, clap::Args)]
pub struct CampaignArgs {
    /// The plan (TOML): shared `identify` options, conditions, geometry, points.
    plan: PathBuf,
    /// Print the campaign as JSON on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Write `coefficients.csv`, `campaign.json` and each point's JSON into DIR.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Write figures of M, C, K against a condition (`--x`) and an HTML report into DIR.
    #[arg(long, value_name = "DIR")]
    plot: Option<PathBuf>,
    /// The condition on the figures' x axis (default: the first).
    #[arg(long, value_name = "CONDITION")]
    x: Option<String>,
    /// Points identified at once (default: the cores).
    #[arg(long)]
    jobs: Option<usize>,
    /// Keep each point's result in DIR by a digest of its files and settings; a rerun
    /// recomputes only what changed.
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
    /// Keep per-line K(ω), C(ω) in each point's JSON; with `--ross`, a 2-D speed × frequency
    /// table.
    #[arg(long)]
    per_frequency: bool,
    /// Write the bearing as one ROSS 3.x element over the `speed` condition (TOML).
    #[arg(long, value_name = "OUT.toml")]
    ross: Option<PathBuf>,
    /// ROSS node of the bearing.
    #[arg(long, default_value_t = 0)]
    ross_node: usize,
    /// ROSS tag of the bearing.
    #[arg(long, default_value = "bearing")]
    ross_tag: String,
    /// Pick one slice of the points for the ROSS table: `CONDITION=VALUE` (comma list).
    #[arg(long, value_delimiter = ',', value_name = "CONDITION=VALUE")]
    ross_where: Vec<String>,
    /// Write N samples of the bearing at each speed of the ROSS table (the same points and
    /// slice) to FILE.csv: rows `speed_rpm,point,sample,kxx,…,myy`, sample i at every speed
    /// one stochastic bearing (ROSS's `ST_BearingElement` over speed); drawn about what the
    /// table holds (the synchronous K, C when every point has them).
    #[arg(long, num_args = 2, value_names = ["N", "FILE.csv"], allow_hyphen_values = true)]
    ross_samples: Vec<String>,
    /// Seed of `--ross-samples`' generator (a whole number ≥ 0; speed k uses seed + k).
    #[arg(
        long,
        default_value = "0",
        requires = "ross_samples",
        allow_hyphen_values = true
    )]
    ross_seed: String,
}

/// Runs the campaign; `Ok(false)` when a point failed (everything written all the same).
pub fn campaign(args: &CampaignArgs) -> Result<bool, Failure> {
    if args.jobs == Some(0) {
        return Err(invalid("--jobs 0: expected at least 1".into()));
    }
    let plan = Plan::read(&args.plan)?;
    let slice = args
        .ross_where
        .iter()
        .map(|s| {
            let (name, value) = s.split_once('=').ok_or_else(|| {
                invalid(format!(
                    "--ross-where `{}`: expected CONDITION=VALUE",
                    excerpt(s)
                ))
            })?;
            let value = value.trim();
            let value = value
                .parse::<f64>()
                .map_or_else(|_| Value::Text(value.to_owned()), Value::Number);
            Ok((name.trim().to_owned(), value))
        })
        .collect::<Result<Vec<_>, Failure>>()?;
    let samples = match args.ross_samples.as_slice() {
        [count, file] => Some((
            crate::export::samples_count_and_seed(count, &args.ross_seed)?,
            PathBuf::from(file),
        )),
        _ => None,
    };
    let mut run = RunOptions {
        cache: args.cache.clone(),
        per_frequency: args.per_frequency,
        ..RunOptions::default()
    };
    if let Some(jobs) = args.jobs {
        run.jobs = jobs;
    }
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(plan.points.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let campaign = plan.run(&run, |_, done| bar.set_position(done as u64));
    bar.finish_and_clear();
    let campaign = campaign?;
    if let Some(dir) = &args.out {
        campaign.write(dir)?;
    }
    if let Some(dir) = &args.plot {
        plot(&campaign, dir, args.x.as_deref())?;
    }
    if let Some(path) = &args.ross {
        let table = campaign.ross_speed_table(args.ross_node, &args.ross_tag, &slice)?;
        std::fs::write(path, table.to_toml()).map_err(|e| Failure {
            kind: "io_error",
            message: format!("{}: {e}", excerpt(&path.display().to_string())),
        })?;
        if table.speed_rad_s.len() < bearing_ident::export::ross::MIN_POINTS {
            crate::failure::print_err(format_args!(
                "bearing-ident: note: the ROSS table has {} speeds; ROSS recommends at least {}",
                table.speed_rad_s.len(),
                bearing_ident::export::ross::MIN_POINTS
            ));
        }
    }
    if let Some(((n, seed), path)) = &samples {
        let samples = campaign.ross_samples(&slice, *n, *seed)?;
        std::fs::write(path, samples.to_csv()).map_err(|e| Failure {
            kind: "io_error",
            message: format!("{}: {e}", excerpt(&path.display().to_string())),
        })?;
    }
    if args.json {
        print_out(format_args!("{}\n", campaign.to_json()))?;
    } else {
        print_out(format_args!("{}", campaign.to_table()))?;
    }
    Ok(!campaign.any_failed())
}

/// The figures and report of `--plot` (each point identified in this run with its own report).
fn plot(campaign: &Campaign, dir: &std::path::Path, x: Option<&str>) -> Result<(), Failure> {
    let options = bearing_ident::plot::ReportOptions {
        title: "bearing-ident campaign".into(),
        ..Default::default()
    };
    let files = bearing_ident::plot::campaign_report(campaign, dir, x, &options)?;
    crate::failure::print_err(format_args!(
        "wrote {} files (figures, the campaign's index.html and each point's report) into {}",
        files.len(),
        excerpt(&dir.display().to_string())
    ));
    Ok(())
}
