//! Field identification for students: a two-disk rotor on anisotropic, cross-coupled bearings,
//! three runs per speed (baseline, mass at disk 1, mass at disk 2), the bearings' K(Ω), C(Ω)
//! recovered from the probes at the bearings and compared with the truth.
//!
//! Run with `cargo run --release -p bearing-ident-examples --example field_two_disk`. It prints,
//! per bearing and speed, the identified k_xx, k_xy, c_xx with their error bars against the
//! truth, and the largest error of the noise-free and the noisy (1 %) identifications.

use bearing_ident::field::{
    self, BeamRotor, BearingCoefficients, BearingSite, Direction, Disk, Imbalance, ImbalanceRuns,
    Probe,
};

/// The bearings' coefficients at speed `w` (rad/s): stiffening with speed, cross-coupled,
/// bearing 1 softer than bearing 0 — the trends of a fluid-film bearing.
fn truth(b: usize, w: f64) -> BearingCoefficients {
    let s = w / 300.0;
    let f = if b == 0 { 1.0 } else { 0.7 };
    BearingCoefficients {
        stiffness: [
            [f * 5e6 * (1.0 + 0.2 * s), f * 3e6 * s],
            [-f * 3.6e6 * s, f * 2e7 * (1.0 + 0.1 * s)],
        ],
        damping: [[f * 5e3 * (1.0 - 0.1 * s), 500.0], [-350.0 * f, f * 7.5e3]],
    }
}

fn main() -> Result<(), bearing_ident::Error> {
    // A 1.05 m steel shaft of 60 mm, eight nodes, disks of 20 and 15 kg at nodes 2 and 5,
    // bearings at the ends. Six degrees of freedom per node, as ROSS builds them.
    let rotor = BeamRotor {
        element_lengths: vec![0.15; 7],
        diameter: 0.06,
        density: 7850.0,
        young: 2.1e11,
        poisson: 0.3,
        disks: vec![
            Disk {
                node: 2,
                mass: 20.0,
                polar: 0.25,
                diametral: 0.13,
            },
            Disk {
                node: 5,
                mass: 15.0,
                polar: 0.2,
                diametral: 0.1,
            },
        ],
        bearings: vec![BearingSite::new("brg0", 0), BearingSite::new("brg1", 7)],
    }
    .model()?;
    println!(
        "rotor model: {} degrees of freedom, {} nodes",
        rotor.dofs(),
        rotor.nodes()
    );

    // Probes x and y at both bearings; 1e-4 kg·m at disk 1, then at disk 2 (other plane and
    // angle: the two tests must be independent); an unknown residual imbalance at node 3.
    let probes: Vec<Probe> = [0, 7]
        .into_iter()
        .flat_map(|node| [Direction::X, Direction::Y].map(|dir| Probe { node, dir }))
        .collect();
    let mass = |node, magnitude_kg_m, phase_rad| {
        vec![Imbalance {
            node,
            magnitude_kg_m,
            phase_rad,
        }]
    };
    let mut plan = ImbalanceRuns {
        speeds_rad_s: (0..8).map(|k| 350.0 + 50.0 * k as f64).collect(),
        probes,
        residual: mass(3, 5e-5, 0.7),
        added: [mass(2, 1e-4, 0.0), mass(5, 1e-4, 1.5)],
        noise: 0.0,
        repeats: 1,
        seed: 1,
    };

    for noise in [0.0, 0.01] {
        plan.noise = noise;
        let tests = plan.simulate(&rotor, truth)?;
        let id = field::identify(&rotor, &tests)?;
        println!("\n== response noise {:.0} %", 100.0 * noise);
        let mut worst: f64 = 0.0;
        for (b, brg) in id.bearings().iter().enumerate() {
            println!(
                "bearing {}: Ω rad/s, cond, k_xx [MN/m] (truth), k_xy [MN/m] (truth), c_xx [kN·s/m] (truth)",
                brg.tag
            );
            for (s, &w) in id.speeds_rad_s().iter().enumerate() {
                let Some(c) = brg.coefficients[s] else {
                    println!("{w:7.0}  singular pair");
                    continue;
                };
                let t = truth(b, w);
                let sd = |m: Option<[[f64; 2]; 2]>, i: usize, j: usize| {
                    m.map_or(String::new(), |m| format!(" ± {:.3}", m[i][j]))
                };
                println!(
                    "{w:7.0} {:6.1}  {:.3}{} ({:.3})  {:.3}{} ({:.3})  {:.3}{} ({:.3})",
                    brg.condition_number[s],
                    c.stiffness[0][0] / 1e6,
                    sd(c.stiffness_std.map(|m| m.map(|r| r.map(|v| v / 1e6))), 0, 0),
                    t.stiffness[0][0] / 1e6,
                    c.stiffness[0][1] / 1e6,
                    sd(c.stiffness_std.map(|m| m.map(|r| r.map(|v| v / 1e6))), 0, 1),
                    t.stiffness[0][1] / 1e6,
                    c.damping[0][0] / 1e3,
                    sd(c.damping_std.map(|m| m.map(|r| r.map(|v| v / 1e3))), 0, 0),
                    t.damping[0][0] / 1e3,
                );
                for i in 0..2 {
                    for j in 0..2 {
                        worst = worst
                            .max((c.stiffness[i][j] / t.stiffness[i][j] - 1.0).abs())
                            .max((c.damping[i][j] / t.damping[i][j] - 1.0).abs());
                    }
                }
            }
        }
        println!("largest relative error of any K or C element: {worst:.2e}");
        for w in id.warnings() {
            println!("warning: {w}");
        }
    }
    Ok(())
}
