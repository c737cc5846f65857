//! Quick start: simulate the seed's test rig, identify it, compare with the truth.
//!
//! Run with `cargo run --release -p bearing-ident-examples --example quickstart` (optionally
//! `-- NOISE`, e.g. `-- 0.05` for a 5 % noise floor). It simulates 8 impacts per direction on
//! the 2-DOF rig of Diaz & San Andrés (1999), 6700 samples/s for 1.2 s, identifies M, C and K
//! over 8–49 Hz by least squares and by the instrumental-variable filter, and prints both
//! against the true values, with the natural frequencies and the fit diagnostics.

use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::{Coefficients, Identification, Identifier, Method};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let noise: f64 = match std::env::args().nth(1) {
        Some(arg) => arg.parse()?,
        None => 0.02,
    };
    let truth = seed_rig();
    let test = ImpactTest {
        noise,
        ..ImpactTest::seed_rig()
    };
    println!(
        "Simulating {} impacts per direction, {} samples/s for {} s, noise floor {:.1} %",
        test.per_direction,
        test.sample_rate,
        test.duration_s,
        100.0 * noise
    );
    let records = test.run(&truth)?;

    let ls = Identifier::new(8.0, 49.0)
        .method(Method::LeastSquares)
        .identify(&records)?;
    let ivf = Identifier::new(8.0, 49.0).identify(&records)?;

    println!(
        "\nBand {:.2}–{:.2} Hz: {} lines, {} sets of paired impacts",
        ivf.freqs_hz()[0],
        ivf.freqs_hz()[ivf.freqs_hz().len() - 1],
        ivf.freqs_hz().len(),
        ivf.frf().averages()
    );
    print_table(&truth, &ls, &ivf);

    println!("\nNatural frequencies and damping ratios");
    for ((t, l), v) in truth.modes()?.iter().zip(ls.modes()?).zip(ivf.modes()?) {
        println!(
            "  true {:7.3} Hz ζ={:6.4}   ls {:7.3} Hz ζ={:6.4}   ivf {:7.3} Hz ζ={:6.4}",
            t.natural_frequency_hz,
            t.damping_ratio,
            l.natural_frequency_hz,
            l.damping_ratio,
            v.natural_frequency_hz,
            v.damping_ratio
        );
    }

    let c = ivf.conditioning();
    println!("\nDiagnostics (ivf)");
    println!(
        "  condition numbers of [X1 X2]: min {:.3}, median {:.3}, max {:.3}",
        c.best(),
        c.median(),
        c.worst()
    );
    println!(
        "  iterations {}, converged {}, residual ‖AΘ−Ī‖ = {:.4e}",
        ivf.iterations(),
        ivf.converged(),
        ivf.residual_norm()
    );
    let check = ivf.model_check();
    println!(
        "  model check: {} (χ²/expected {:.3}, p = {:.2e})",
        check.verdict.name(),
        check.ratio().unwrap_or(f64::NAN),
        check.p_value.unwrap_or(f64::NAN)
    );
    let r2 = ivf.fit_r2();
    println!(
        "  flexibility fit r²: xx {:.4}  xy {:.4}  yx {:.4}  yy {:.4}",
        r2[(0, 0)],
        r2[(0, 1)],
        r2[(1, 0)],
        r2[(1, 1)]
    );
    for w in ivf.warnings() {
        println!("  warning: {w}");
    }
    Ok(())
}

fn print_table(truth: &Coefficients, ls: &Identification, ivf: &Identification) {
    println!(
        "\n{:<6} {:>14} {:>14} {:>9} {:>14} {:>9} {:>12}",
        "coef", "true", "ls", "ls err", "ivf", "ivf err", "ivf ±1σ"
    );
    let names = ["xx", "xy", "yx", "yy"];
    let blocks = [("M", "kg"), ("C", "N·s/m"), ("K", "N/m")];
    for (b, (name, unit)) in blocks.iter().enumerate() {
        let pick = |c: &Coefficients| match b {
            0 => c.mass().to_owned(),
            1 => c.damping().to_owned(),
            _ => c.stiffness().to_owned(),
        };
        let (t, l, v) = (
            pick(truth),
            pick(ls.coefficients()),
            pick(ivf.coefficients()),
        );
        let s = ivf.std_dev().map(pick);
        for (e, suffix) in names.iter().enumerate() {
            let (i, j) = (e / 2, e % 2);
            let rel = |x: f64| {
                if t[(i, j)] == 0.0 {
                    "      —".to_string()
                } else {
                    format!("{:+8.3}%", 100.0 * (x / t[(i, j)] - 1.0))
                }
            };
            println!(
                "{:<6} {:>14.4} {:>14.4} {:>9} {:>14.4} {:>9} {:>12}",
                format!("{name}{suffix}"),
                t[(i, j)],
                l[(i, j)],
                rel(l[(i, j)]),
                v[(i, j)],
                rel(v[(i, j)]),
                s.as_ref()
                    .map_or("—".to_string(), |s| format!("{:.4}", s[(i, j)]))
            );
        }
        println!("{:<6} ({unit})", "");
    }
}
