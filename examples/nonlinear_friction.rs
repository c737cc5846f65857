//! A squeeze film damper with a dry-friction end seal: identified linearly, then with the
//! friction as a nonlinear term (the reverse path, `docs/method.md` section 4).
//!
//! Run: `cargo run --release -p bearing-ident-examples --example nonlinear_friction`
//!
//! The rig is the seed's (4.7 kg, K ≈ 150 kN/m); its damping stands for the film's. The end
//! seal rubs with a friction force of 20 N along x and 15 N along y, opposing the velocity on
//! each axis. Two shakers drive it at once with band-limited random forces (50 N RMS, 8–49 Hz),
//! two records of 32 s at 1024 samples/s, and every channel carries 2 % noise.
//!
//! A linear identification cannot tell friction from damping: it returns the damping that
//! dissipates as much energy at these amplitudes — an equivalent damping, tens of percent too
//! high, that would change with the test amplitude. Adding `coulomb` to the model (the
//! regressor `sign(ẋᵢ)` as an extra input) returns the film's damping and the seal's
//! friction force together, each with its standard deviation, and a model check that says
//! whether the friction law fits.

use bearing_ident::nonlinear::{Regressor, ReversePath, Term};
use bearing_ident::simulate::{AntiAlias, NonlinearSimulator, add_noise, band_noise, seed_rig};
use bearing_ident::{Error, Estimator, Identifier, Segmentation};
use rand::SeedableRng;

fn main() -> Result<(), Error> {
    let truth = seed_rig();
    let (rate, samples, friction) = (1024.0, 32 * 1024, [20.0, 15.0]);
    let mut sim = NonlinearSimulator::new(&truth, rate, samples, AntiAlias::default())?;
    for (dof, &f) in friction.iter().enumerate() {
        let term = Term {
            regressor: Regressor::Coulomb,
            dof: Some(dof),
        };
        sim = sim.with_term(term, f)?;
    }
    let mut rng = rand::rngs::StdRng::seed_from_u64(11);
    let mut records = Vec::new();
    for r in 0..2u64 {
        let forces = (0..2u64)
            .map(|d| band_noise(8.0, 49.0, 50.0, rate, samples, 10 * r + d))
            .collect::<Result<Vec<_>, _>>()?;
        let clean = sim.held_record(format!("random-{r}"), &forces)?;
        records.push(add_noise(&clean, 0.02, &mut rng)?);
    }

    // Linear only: MIMO H1 over Welch averages of 4 s segments (both forces in every record), IVF.
    let linear = Identifier::new(8.0, 49.0)
        .estimator(Estimator::H1)
        .segmentation(Segmentation::Welch { len: 4096 })
        .identify(&records)?;
    // With the friction as two more inputs.
    let nonlinear = ReversePath::new(8.0, 49.0, &[Regressor::Coulomb])
        .segment_len(4096)
        .identify(&records)?;

    let c_true = truth.damping();
    let (c_lin, c_nl) = (
        linear.coefficients().damping(),
        nonlinear.coefficients().damping(),
    );
    println!("Damping of the film (N·s/m), truth vs identified:");
    println!(
        "{:<6} {:>9} {:>18} {:>18}",
        "", "truth", "linear only", "with coulomb"
    );
    for (i, name) in ["C_xx", "C_yy"].iter().enumerate() {
        let (t, l, n) = (c_true[(i, i)], c_lin[(i, i)], c_nl[(i, i)]);
        println!(
            "{name:<6} {t:>9.1} {l:>9.1} ({:+5.1} %) {n:>9.1} ({:+5.1} %)",
            100.0 * (l / t - 1.0),
            100.0 * (n / t - 1.0)
        );
    }
    println!("\nFriction of the seal (N):");
    for (estimate, check) in nonlinear.terms().iter().zip(nonlinear.checks()) {
        let dof = estimate.term.dof.expect("per-axis friction");
        let std = estimate.std.unwrap_or(f64::NAN);
        println!(
            "{:<12} truth {:>5.1}  identified {:>6.2} ± {:.2} ({:+.1} %), Im/Re {:+.3}, slope {:+.3}{}",
            estimate.term.label(),
            friction[dof],
            estimate.value,
            std,
            100.0 * (estimate.value / friction[dof] - 1.0),
            check.imaginary_ratio,
            check.slope,
            if check.misfit { "  (misfit)" } else { "" }
        );
    }
    for w in nonlinear.warnings() {
        println!("warning: {w}");
    }
    // The equivalent damping is far off; the reverse path recovers both within a few percent.
    for i in 0..2 {
        assert!(c_lin[(i, i)] / c_true[(i, i)] > 1.10);
        assert!((c_nl[(i, i)] / c_true[(i, i)] - 1.0).abs() < 0.05);
    }
    for estimate in nonlinear.terms() {
        let dof = estimate.term.dof.expect("per-axis friction");
        assert!((estimate.value / friction[dof] - 1.0).abs() < 0.05);
    }
    Ok(())
}
