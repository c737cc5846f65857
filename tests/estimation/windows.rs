//! A lightly damped system whose records are cut off long before the response decays: the
//! rectangular window leaks and ruins the damping; the exponential window with the exact
//! correction `C = C_w − 2aM_w`, `K = K_w − aC_w + a²M_w` recovers it.
//!
//! Measured (noise-free, 0.6 s records, exponential window to 10⁻⁴ at the end, a = 15.35/s):
//! rectangular C_xx +37.3 %, C_yy +16.7 %, K_xx +9.96 %, K_yy +9.05 %; exponential with the
//! correction C_xx +0.019 %, C_yy +0.013 %, K_xx +0.0016 %, K_yy +0.0015 %. Correcting C alone
//! would leave K_xx off by aC + a²M = 246 + 1108 N/m = 0.93 %.

use crate::common;

use bearing_ident::simulate::{AntiAlias, Simulator};
use bearing_ident::{Coefficients, Identifier, Record, Window};
use faer::mat;

/// ζ ≈ 1 %: C = 16–17 N·s/m on the seed's 4.7/4.8 kg, 146–169 kN/m rig, cross-coupled.
fn light() -> Coefficients {
    Coefficients::new(
        mat![[4.7, 0.0], [0.0, 4.8]],
        mat![[16.0, 2.0], [-1.0, 17.0]],
        mat![[146.3e3, 22.3e3], [11.5e3, 169.1e3]],
    )
    .unwrap()
}

/// Record length (s): the response is still at about a third of its initial amplitude when
/// the record ends.
const DURATION: f64 = common::TRUNCATED_S;

/// Two hits per direction, 6700 samples/s for [`DURATION`].
fn truncated_records(sys: &Coefficients) -> Vec<Record> {
    let samples = (6700.0 * DURATION) as usize;
    let mut sim = Simulator::new(sys, 6700.0, samples, AntiAlias::default()).unwrap();
    common::truncated_hits(&mut sim)
}

fn relative(got: f64, want: f64) -> f64 {
    (got / want - 1.0).abs()
}

#[test]
fn exponential_window_with_exact_correction_recovers_a_lightly_damped_system() {
    let truth = light();
    let records = truncated_records(&truth);
    let rect = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    let window = Window::exponential_to(1e-4, DURATION);
    let exp = Identifier::new(8.0, 49.0)
        .window(window)
        .identify(&records)
        .unwrap();
    let a = window.decay_per_s().unwrap();
    for i in 0..2 {
        let (c, k) = (truth.damping()[(i, i)], truth.stiffness()[(i, i)]);
        let c_rect = relative(rect.coefficients().damping()[(i, i)], c);
        let k_rect = relative(rect.coefficients().stiffness()[(i, i)], k);
        let c_exp = relative(exp.coefficients().damping()[(i, i)], c);
        let k_exp = relative(exp.coefficients().stiffness()[(i, i)], k);
        println!(
            "dof {i}: rectangular C {:+.2} %, K {:+.3} %; exponential (a = {a:.3}/s) C {:+.4} %, K {:+.5} %",
            100.0 * c_rect,
            100.0 * k_rect,
            100.0 * c_exp,
            100.0 * k_exp
        );
        assert!(
            c_rect > 0.1,
            "the rectangular window should fail here: C off by {c_rect}"
        );
        assert!(c_exp < 0.01, "C within 1 %: {c_exp}");
        assert!(k_exp < 0.001, "K within 0.1 %: {k_exp}");
    }
    assert_eq!(exp.window(), window);
}

#[test]
fn exponential_window_std_devs_follow_the_correction() {
    let truth = light();
    let mut records = truncated_records(&truth);
    let mut rng = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(3);
    records = records
        .iter()
        .map(|r| bearing_ident::simulate::add_noise(r, 0.05, &mut rng).unwrap())
        .collect();
    let exp = Identifier::new(8.0, 49.0)
        .window(Window::exponential_to(1e-4, DURATION))
        .identify(&records)
        .unwrap();
    let sd = exp.std_dev().unwrap();
    for (b, (got, t)) in common::blocks(exp.coefficients())
        .iter()
        .zip(common::blocks(&truth))
        .enumerate()
    {
        for i in 0..2 {
            let s = common::blocks(sd)[b][(i, i)];
            assert!(
                (got[(i, i)] - t[(i, i)]).abs() < 6.0 * s,
                "block {b} ({i},{i}) beyond 6σ̂"
            );
        }
    }
}
