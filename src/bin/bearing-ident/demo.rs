//! `bearing-ident demo`: the seed's rig simulated with impacts and identified, as the
//! quickstart example does.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use bearing_ident::Choice;
use bearing_ident::Identifier;
use bearing_ident::excitation::{Excitation, crest_factor};
use bearing_ident::quality::ImpactChecks;
use bearing_ident::simulate::{ImpactTest, seed_rig};

use crate::failure::{Failure, print_out};
use crate::output::{emit, write_report};
use crate::report;
use bearing_ident::job::Timings;

#[derive(Debug, clap::Args)]
pub struct DemoArgs {
    /// Noise level (fraction of each signal kind's RMS).
    #[arg(long, default_value_t = 0.02)]
    noise: f64,
    /// Print the result as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write figures (SVG) and a static `index.html` report into DIR.
    #[arg(long, value_name = "DIR")]
    plot: Option<PathBuf>,
}

/// Simulates the seed's rig (8 impacts per direction, `--noise`), identifies it over 8–49 Hz
/// by IVF and prints the result beside the truth.
pub fn demo(args: &DemoArgs) -> Result<(), Failure> {
    let truth = seed_rig();
    let test = ImpactTest {
        noise: args.noise,
        ..ImpactTest::seed_rig()
    };
    let records = test.run(&truth)?;
    let start = Instant::now();
    let id = Identifier::new(8.0, 49.0).identify(&records)?;
    let context = report::Context {
        excitation: Excitation::Impact.name(),
        excitation_auto: false,
        crest_factor: crest_factor(&records[0]),
        segment_len: None,
        welch_choice: None,
        sample_rate: test.sample_rate,
        files: records.iter().map(|r| r.label().to_owned()).collect(),
        timings: Timings::new(id.timings(), Duration::ZERO, start.elapsed()),
        show_timings: false,
        axes: vec!["x".into(), "y".into()],
        bearing: None,
        per_frequency: None,
        us_units: false,
        units: serde_json::Value::Null,
        dimensionless: None,
        stability: None,
        synchronous: None,
    };
    if let Some(dir) = &args.plot {
        write_report(
            dir,
            &id,
            &records,
            &context,
            Some(&truth),
            Some(ImpactChecks::default()),
        )?;
    }
    if !args.json {
        let intro = format!(
            "the 2-DOF test rig of Diaz & San Andrés (1999), {} impacts per direction, {} samples/s \
             for {} s, noise {:.1} %, identified over 8–49 Hz by IVF.",
            test.per_direction,
            test.sample_rate,
            test.duration_s,
            100.0 * args.noise
        );
        print_out(format_args!(
            "{}\n",
            bearing_ident::text::wrap("Demo:", &intro, 2)
        ))?;
    }
    emit(&id, &context, Some(&truth), args.json)
}
