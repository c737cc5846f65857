//! The rotor and bearings of the field-identification tests: a two-disk Euler–Bernoulli beam
//! rotor (six degrees of freedom per node, as ROSS builds them) on speed-dependent,
//! cross-coupled bearings, and the imbalance runs on it.
#![allow(dead_code)]

use bearing_ident::field::{
    BeamRotor, BearingCoefficients, BearingSite, Direction, Disk, Imbalance, ImbalanceRuns, Probe,
    RotorModel,
};

pub fn rotor() -> RotorModel {
    BeamRotor {
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
    .model()
    .unwrap()
}

/// Speed-dependent, cross-coupled bearings (a fluid-film bearing's trends: stiffening,
/// cross-coupling growing with speed, skew-symmetric parts).
pub fn bearings(b: usize, w: f64) -> BearingCoefficients {
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

pub fn isotropic(_b: usize, _w: f64) -> BearingCoefficients {
    BearingCoefficients {
        stiffness: [[2e7, 0.0], [0.0, 2e7]],
        damping: [[2e4, 0.0], [0.0, 2e4]],
    }
}

pub fn probes(nodes: [usize; 2]) -> Vec<Probe> {
    nodes
        .into_iter()
        .flat_map(|node| [Direction::X, Direction::Y].map(|dir| Probe { node, dir }))
        .collect()
}

pub fn at(node: usize, magnitude_kg_m: f64, phase_rad: f64) -> Vec<Imbalance> {
    vec![Imbalance {
        node,
        magnitude_kg_m,
        phase_rad,
    }]
}

pub fn runs(probe_nodes: [usize; 2], noise: f64, seed: u64) -> ImbalanceRuns {
    ImbalanceRuns {
        // Between the rigid-body modes on the bearings, where the tests separate best.
        speeds_rad_s: (0..14).map(|k| 350.0 + 25.0 * k as f64).collect(),
        probes: probes(probe_nodes),
        residual: at(3, 5e-5, 0.7),
        added: [at(2, 1e-4, 0.0), at(5, 1e-4, 1.5)],
        noise,
        repeats: 1,
        seed,
    }
}
