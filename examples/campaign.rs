//! A simulated test campaign, as the seed's study ran it: the rig of the seed (a rotor on a
//! squeeze film damper, 8 impacts per direction) at six lubricant conditions, from pure oil to
//! dry, the damper's damping rising with a little air and falling to nothing without oil.
//! The displacements are "measured" near the disk (213 and 254 mm from the bushing) and moved
//! back to the damper (151 mm) by the plan's conical geometry.
//!
//! Writes the records under `examples/campaign/records/`, runs `examples/campaign/plan.toml`
//! through the library, and prints the table and each condition's damper damping against the
//! truth. Then try the command line on the same plan:
//!
//! ```text
//! cargo run --release -p bearing-ident-examples --example campaign
//! cargo run --release --features cli -- campaign examples/campaign/plan.toml --plot examples/campaign/report
//! ```

use std::path::Path;

use bearing_ident::Coefficients;
use bearing_ident::campaign::{Plan, RunOptions};
use bearing_ident::faer::mat;
use bearing_ident::io::{CsvLayout, write_record};
use bearing_ident::simulate::ImpactTest;
use bearing_ident::{Record, Result};

/// The conditions: name, air fraction and the damper's own direct damping (N·s/m). With oil,
/// the damping rises with a little air to a maximum near half air, then falls to the dry
/// structure's (the trend the seed reports; the numbers are illustrative).
const POINTS: [(&str, f64, f64); 6] = [
    ("dry", 1.0, 0.0),
    ("oil", 0.0, 110.0),
    ("air-20", 0.2, 126.0),
    ("air-40", 0.4, 138.0),
    ("air-60", 0.6, 118.0),
    ("air-80", 0.8, 62.0),
];

/// The probes and the damper, m from the bushing (the pivot of the conical mode).
const PROBES: [f64; 2] = [0.213, 0.254];
const DAMPER: f64 = 0.151;

/// The rig at the damper with the damper's damping `c_sfd`: the structure of the seed's
/// identification (M, K), the dry structure's 22.3 N·s/m.
fn rig(c_sfd: f64) -> Result<Coefficients> {
    let c = 22.3 + c_sfd;
    Coefficients::new(
        mat![[4.7, 0.0], [0.0, 4.8]],
        mat![[c, 0.0], [0.0, c]],
        mat![[146.3e3, 22.3e3], [11.5e3, 169.1e3]],
    )
}

/// `record` (at the damper) as the probes see it: each displacement scaled by its lever arm.
fn at_probes(record: &Record) -> Result<Record> {
    let forces = (0..2).map(|i| record.force(i).to_vec()).collect();
    let responses = (0..2)
        .map(|i| {
            let arm = PROBES[i] / DAMPER;
            record.displacement(i).iter().map(|x| x * arm).collect()
        })
        .collect();
    Record::new(record.label(), record.sample_rate(), forces, responses)
}

fn main() -> std::result::Result<(), Box<dyn std::error::Error>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaign");
    for (seed, (name, _, c_sfd)) in POINTS.iter().enumerate() {
        // The dry structure rings for seconds (ζ ≈ 1.3 %): 8 s records at 1 kHz, the same
        // for every condition so that the baseline's lines are the points' lines.
        let test = ImpactTest {
            sample_rate: 1000.0,
            duration_s: 8.0,
            pulse_s: 0.005,
            noise: 0.02,
            seed: 100 + seed as u64,
            ..ImpactTest::seed_rig()
        };
        let folder = dir.join("records").join(name);
        std::fs::create_dir_all(&folder)?;
        for (k, r) in test.run(&rig(*c_sfd)?)?.iter().enumerate() {
            write_record(
                folder.join(format!("hit-{k:02}.csv")),
                &at_probes(r)?,
                &CsvLayout::default(),
            )?;
        }
    }
    let plan = Plan::read(&dir.join("plan.toml"))?;
    let campaign = plan.run(&RunOptions::default(), |_, _| {})?;
    print!("{}", campaign.to_table());
    println!("\ndamper damping C_xx (the bearing's own: system less dry), against the truth:");
    for (point, (name, _, c_sfd)) in campaign.points.iter().zip(POINTS).skip(1) {
        let fit = point.result.as_ref().map_err(|e| e.message.clone())?;
        let (c, s) = fit.reported();
        let (value, sd) = (
            c.damping()[(0, 0)],
            s.map_or(f64::NAN, |s| s.damping()[(0, 0)]),
        );
        println!(
            "  {name:<7} {value:7.2} ± {sd:4.2} N·s/m (truth {c_sfd:6.1}, error {:+.2} %)",
            100.0 * (value / c_sfd - 1.0)
        );
    }
    Ok(())
}
