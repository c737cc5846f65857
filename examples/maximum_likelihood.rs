//! Maximum likelihood on periodic records, against IVF and the Cramér–Rao bound.
//!
//! Run: `cargo run --release -p bearing-ident-examples --example maximum_likelihood`
//!
//! Simulates the seed's rig driven by a multisine in each direction (16 periods of 1 s at
//! 1000 samples/s, lines 8–49 Hz), adds a displacement-probe noise floor (1.0 × the RMS), and
//! identifies it by IVF and by maximum likelihood: the periods give the noise covariances the
//! likelihood needs. Prints both against the truth with their standard deviations and the
//! Cramér–Rao bound the likelihood reaches.

use bearing_ident::records::Record;
use bearing_ident::simulate::{AntiAlias, Simulator, multisine, seed_rig};
use bearing_ident::{Estimator, Identifier, Method, Segmentation};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

fn main() -> Result<(), bearing_ident::Error> {
    let truth = seed_rig();
    let (period, periods, settle) = (1000, 16, 2000);
    let total = settle + periods * period;
    let mut sim = Simulator::new(&truth, 1000.0, total, AntiAlias::default())?;
    let mut rng = rand::rngs::StdRng::seed_from_u64(3);
    let mut records = Vec::new();
    for d in 0..2 {
        let mut forces = vec![vec![0.0; total]; 2];
        forces[d] = multisine(period, 8..=49, 30.0, total, d as u64)?;
        let clean = sim
            .held_record(format!("multisine-{d}"), &forces)?
            .trimmed(settle..total)?;
        // Probe noise: 1.0 × the displacement RMS on both displacement channels.
        let rms =
            (clean.displacement(d).iter().map(|v| v * v).sum::<f64>() / clean.len() as f64).sqrt();
        let noise = Normal::new(0.0, rms).expect("positive");
        let disps = (0..2)
            .map(|c| {
                clean
                    .displacement(c)
                    .iter()
                    .map(|v| v + noise.sample(&mut rng))
                    .collect()
            })
            .collect();
        let forces = (0..2).map(|c| clean.force(c).to_vec()).collect();
        records.push(Record::new(clean.label(), 1000.0, forces, disps)?);
    }
    let identifier = Identifier::new(8.0, 49.0)
        .estimator(Estimator::H1)
        .segmentation(Segmentation::Periods { len: period });
    let ivf = identifier.clone().method(Method::Ivf).identify(&records)?;
    let ml = identifier.method(Method::Ml).identify(&records)?;
    let report = ml.ml().expect("method ml reports");
    println!(
        "ML: {} steps, cost {:.1} from IVF's {:.1}, cost / expected {:.3}\n",
        report.convergence.iterations(),
        report.cost,
        report.start_cost,
        report.cost_ratio
    );
    for (name, id) in [("IVF", &ivf), ("ML", &ml)] {
        let check = id.model_check();
        println!(
            "model check ({name}): {}, χ²/expected {:.3}, p = {:.2e}",
            check.verdict.name(),
            check.ratio().unwrap_or(f64::NAN),
            check.p_value.unwrap_or(f64::NAN)
        );
    }
    println!(
        "{:<8} {:>12} {:>22} {:>22}",
        "", "truth", "IVF ± σ (sandwich)", "ML ± σ (Fisher ≈ CRLB)"
    );
    let rows = [
        ("K_xx", 2, 0),
        ("K_yy", 2, 1),
        ("C_xx", 1, 0),
        ("C_yy", 1, 1),
        ("M_xx", 0, 0),
        ("M_yy", 0, 1),
    ];
    for (name, block, i) in rows {
        let get = |c: &bearing_ident::Coefficients| match block {
            0 => c.mass()[(i, i)],
            1 => c.damping()[(i, i)],
            _ => c.stiffness()[(i, i)],
        };
        let (a, b) = (
            ivf.std_dev().expect("sandwich"),
            ml.std_dev().expect("fisher"),
        );
        println!(
            "{name:<8} {:>12.4} {:>12.4} ± {:>7.3} {:>12.4} ± {:>7.3}",
            get(&truth),
            get(ivf.coefficients()),
            get(a),
            get(ml.coefficients()),
            get(b)
        );
    }
    Ok(())
}
