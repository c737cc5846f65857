//! Records of nonlinear elements by **prescribed displacement**: a band-limited random
//! multisine $x(t)$ per DOF (random phases, flat amplitude over a band, on the record's own
//! frequency grid, so the sampled signal and its derivatives are exact: $\dot x$ and $\ddot x$
//! are the inverse transforms of $i\omega X$ and $-\omega^2 X$), then the force computed
//! exactly at every sample,
//! $$f = M\ddot x + C\dot x + Kx + \sum_j a_j\,y_j(x, \dot x),$$
//! and white noise of a given fraction of the RMS added to the force and displacement
//! channels ([`bearing_ident::simulate::add_noise`]). No integrator is involved: the truth is
//! exact, and the identification is judged against it alone.
#![allow(dead_code)]

use bearing_ident::nonlinear::Term;
use bearing_ident::simulate::add_noise;
use bearing_ident::{Coefficients, Record};
use faer::{c64, mat};
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Uniform};
use realfft::RealFftPlanner;

/// A nonlinear test: the linear system, the terms with their coefficients, and the records'
/// shape.
#[derive(Debug, Clone)]
pub struct NonlinearTest {
    /// The linear part.
    pub system: Coefficients,
    /// The nonlinear terms and their coefficients.
    pub terms: Vec<(Term, f64)>,
    /// Sampling rate (Hz).
    pub sample_rate: f64,
    /// Samples per record.
    pub len: usize,
    /// Records.
    pub records: usize,
    /// Band of the prescribed displacement (Hz).
    pub band_hz: (f64, f64),
    /// RMS of each prescribed displacement (m).
    pub rms_m: f64,
    /// Noise level (fraction of RMS) on force and displacement channels.
    pub noise: f64,
    /// Seed of the phases and the noise.
    pub seed: u64,
}

/// A 2-DOF rig like the seed's (≈ 4.7 kg, 146–169 kN/m, cross-coupled), on 2 records of 32 s
/// at 1024 Hz, displacements of 20 µm RMS over 5–80 Hz, 2 % noise.
pub fn rig(terms: Vec<(Term, f64)>) -> NonlinearTest {
    let system = Coefficients::new(
        mat![[4.7, 0.1], [0.1, 4.8]],
        mat![[220.0, 30.0], [-20.0, 260.0]],
        mat![[146.3e3, 25.0e3], [-18.0e3, 169.1e3]],
    )
    .unwrap();
    NonlinearTest {
        system,
        terms,
        sample_rate: 1024.0,
        len: 32 * 1024,
        records: 2,
        band_hz: (5.0, 80.0),
        rms_m: 2e-5,
        noise: 0.02,
        seed: 15,
    }
}

impl NonlinearTest {
    /// The records, noise included.
    pub fn run(&self) -> Vec<Record> {
        let mut rng = StdRng::seed_from_u64(self.seed);
        (0..self.records)
            .map(|r| {
                let clean = self.clean_record(&format!("nl-{r}"), &mut rng);
                add_noise(&clean, self.noise, &mut rng).unwrap()
            })
            .collect()
    }

    /// One noise-free record.
    pub fn clean_record(&self, label: &str, rng: &mut StdRng) -> Record {
        let n = self.system.dofs();
        let len = self.len;
        let mut x = Vec::with_capacity(n);
        let mut v = Vec::with_capacity(n);
        let mut a = Vec::with_capacity(n);
        for _ in 0..n {
            let [xi, vi, ai] = self.multisine(rng);
            x.push(xi);
            v.push(vi);
            a.push(ai);
        }
        let (m, c, k) = (
            self.system.mass(),
            self.system.damping(),
            self.system.stiffness(),
        );
        let mut forces = vec![vec![0.0; len]; n];
        let (mut xs, mut vs, mut ys) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for s in 0..len {
            for i in 0..n {
                xs[i] = x[i][s];
                vs[i] = v[i][s];
            }
            for i in 0..n {
                forces[i][s] = (0..n)
                    .map(|j| m[(i, j)] * a[j][s] + c[(i, j)] * v[j][s] + k[(i, j)] * x[j][s])
                    .sum();
            }
            for (term, coefficient) in &self.terms {
                term.force_shape(&xs, &vs, None, &mut ys);
                for i in 0..n {
                    forces[i][s] += coefficient * ys[i];
                }
            }
        }
        Record::new(label, self.sample_rate, forces, x).unwrap()
    }

    /// Displacement, velocity and acceleration of one random-phase multisine of RMS
    /// `rms_m` over `band_hz`.
    fn multisine(&self, rng: &mut StdRng) -> [Vec<f64>; 3] {
        let len = self.len;
        let df = self.sample_rate / len as f64;
        let phase = Uniform::new(0.0, std::f64::consts::TAU).unwrap();
        let lines = len / 2 + 1;
        let mut spectrum = vec![c64::new(0.0, 0.0); lines];
        let mut count = 0usize;
        for (k, s) in spectrum.iter_mut().enumerate() {
            let f = k as f64 * df;
            if f >= self.band_hz.0 && f <= self.band_hz.1 {
                let p: f64 = phase.sample(rng);
                *s = c64::new(p.cos(), p.sin());
                count += 1;
            }
        }
        // Each line of unit modulus gives a cosine of amplitude 2/len after the unnormalised
        // inverse transform: RMS √(2·count)/len in all.
        let scale = self.rms_m * len as f64 / (2.0 * count as f64).sqrt();
        let mut planner = RealFftPlanner::<f64>::new();
        let inverse = planner.plan_fft_inverse(len);
        let w = |k: usize| std::f64::consts::TAU * k as f64 * df;
        let out = |factor: &dyn Fn(usize) -> c64| {
            let mut spec: Vec<c64> = spectrum
                .iter()
                .enumerate()
                .map(|(k, s)| s * factor(k) * (scale / len as f64))
                .collect();
            let mut time = vec![0.0; len];
            inverse.process(&mut spec, &mut time).unwrap();
            time
        };
        [
            out(&|_| c64::new(1.0, 0.0)),
            out(&|k| c64::new(0.0, w(k))),
            out(&|k| c64::new(-w(k) * w(k), 0.0)),
        ]
    }
}
