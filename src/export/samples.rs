//! Index-aligned samples of a 2-DOF element's coefficients drawn from its joint uncertainty
//! ([`BearingSamples`]), for stochastic rotor models (ROSS's `ST_BearingElement`) and other
//! rotor codes (CSV).

use std::fmt::Write as _;

use faer::Mat;
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};

use super::ross::{Matrix2, two};
use crate::error::{Error, Result};
use crate::identify::Identification;
use crate::model::Coefficients;

/// The columns of [`BearingSamples::to_csv`] after `sample`, in ROSS's names.
pub const COLUMNS: [&str; 12] = [
    "kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy", "mxx", "mxy", "myx", "myy",
];

/// `N` samples of a 2-DOF element's `K`, `C`, `M`, paired by index (sample `i` of every
/// coefficient is one draw of the whole set, so their correlations survive): draws of the
/// multivariate normal `θ + L z`, `z ~ N(0, I)`, `L Lᵀ = Σ` the coefficients' full covariance
/// ([`Identification::covariance`]: the error bars' own correlations and the calibration's
/// common sources), from a generator seeded with `seed`. The sample mean tends to the
/// coefficients and the sample covariance to `Σ` as `N` grows.
#[derive(Debug, Clone, PartialEq)]
pub struct BearingSamples {
    stiffness: Vec<Matrix2>,
    damping: Vec<Matrix2>,
    mass: Vec<Matrix2>,
}

fn invalid(message: String) -> Error {
    Error::InvalidOption {
        option: "ross-samples",
        message,
    }
}

impl BearingSamples {
    /// `n` samples of the coefficients of `id` (2 DOF, with error bars), seeded with `seed`.
    ///
    /// # Errors
    /// [`Error::ExportDofs`] unless 2 DOF; [`Error::InvalidOption`] (`ross-samples`) for
    /// `n = 0` or an identification without error bars.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Identifier;
    /// use bearing_ident::export::samples::BearingSamples;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest { per_direction: 2, noise: 0.05, ..ImpactTest::seed_rig() }
    ///     .run(&seed_rig())?;
    /// let id = Identifier::new(8.0, 49.0).identify(&records)?;
    /// let s = BearingSamples::draw(&id, 100, 7)?;
    /// assert_eq!(s.len(), 100);
    /// // Each sample is near the fitted K_xx, within a few σ.
    /// let (k, sd) = (id.coefficients().stiffness()[(0, 0)], id.std_dev().unwrap().stiffness()[(0, 0)]);
    /// assert!((s.stiffness(0)[0][0] - k).abs() < 6.0 * sd);
    /// assert_eq!(BearingSamples::draw(&id, 100, 7)?, s); // seeded
    /// assert!(BearingSamples::draw(&id, 0, 7).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn draw(id: &Identification, n: usize, seed: u64) -> Result<Self> {
        let cov = id
            .covariance()
            .ok_or_else(|| invalid("--ross-samples: the identification has no error bars to draw from (uncertainty none)".into()))?;
        Self::from_covariance(id.coefficients(), &cov, n, seed)
    }

    /// `n` samples of `coefficients` (2 DOF) with covariance `covariance` over the stacked
    /// `[M; C; K]` read column by column (the order of [`Identification::covariance`]),
    /// seeded with `seed`. `Σ` may be singular (coefficients without uncertainty): its
    /// factor is the Cholesky factor with the columns of zero pivots left out.
    ///
    /// # Errors
    /// [`Error::ExportDofs`] unless 2 DOF; [`Error::InvalidOption`] (`ross-samples`) for
    /// `n = 0`, a covariance of another size or one with a negative or non-finite variance.
    pub fn from_covariance(
        coefficients: &Coefficients,
        covariance: &Mat<f64>,
        n: usize,
        seed: u64,
    ) -> Result<Self> {
        if coefficients.dofs() != 2 {
            return Err(Error::ExportDofs {
                format: "ROSS bearing samples",
                dofs: coefficients.dofs(),
                expected: 2,
            });
        }
        if n == 0 {
            return Err(invalid(
                "--ross-samples 0: expected at least 1 sample".into(),
            ));
        }
        let theta = coefficients.stacked();
        let rows = theta.nrows();
        let p = rows * theta.ncols();
        if covariance.nrows() != p || covariance.ncols() != p {
            return Err(invalid(format!(
                "a covariance of {} × {} for {p} coefficients",
                covariance.nrows(),
                covariance.ncols()
            )));
        }
        let factor = semidefinite_factor(covariance)
            .ok_or_else(|| invalid("a covariance with a negative or non-finite variance".into()))?;
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let mut out = Self {
            stiffness: Vec::with_capacity(n),
            damping: Vec::with_capacity(n),
            mass: Vec::with_capacity(n),
        };
        for _ in 0..n {
            let z: Vec<f64> = (0..p).map(|_| StandardNormal.sample(&mut rng)).collect();
            let drawn = Mat::from_fn(rows, theta.ncols(), |q, j| {
                let i = j * rows + q;
                theta[(q, j)] + (0..=i).map(|r| factor[(i, r)] * z[r]).sum::<f64>()
            });
            let c = Coefficients::from_stacked(drawn.as_ref())?;
            out.stiffness.push(two(c.stiffness()));
            out.damping.push(two(c.damping()));
            out.mass.push(two(c.mass()));
        }
        Ok(out)
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.stiffness.len()
    }

    /// Whether there is none (never, for samples drawn).
    pub fn is_empty(&self) -> bool {
        self.stiffness.is_empty()
    }

    /// `K` of sample `i`.
    ///
    /// # Panics
    /// If `i ≥ len()`.
    pub fn stiffness(&self, i: usize) -> Matrix2 {
        self.stiffness[i]
    }

    /// `C` of sample `i`.
    ///
    /// # Panics
    /// If `i ≥ len()`.
    pub fn damping(&self, i: usize) -> Matrix2 {
        self.damping[i]
    }

    /// `M` of sample `i`.
    ///
    /// # Panics
    /// If `i ≥ len()`.
    pub fn mass(&self, i: usize) -> Matrix2 {
        self.mass[i]
    }

    /// The twelve values of sample `i` in the order of [`COLUMNS`].
    ///
    /// # Panics
    /// If `i ≥ len()`.
    pub fn row(&self, i: usize) -> [f64; 12] {
        let mut out = [0.0; 12];
        for (b, m) in [self.stiffness[i], self.damping[i], self.mass[i]]
            .iter()
            .enumerate()
        {
            for r in 0..2 {
                for c in 0..2 {
                    out[4 * b + 2 * r + c] = m[r][c];
                }
            }
        }
        out
    }

    /// CSV, one row per sample: `sample,kxx,kxy,kyx,kyy,cxx,…,myy` (SI), numbers in the
    /// shortest form that reads back every bit.
    pub fn to_csv(&self) -> String {
        let mut s = format!("sample,{}\n", COLUMNS.join(","));
        for i in 0..self.len() {
            let _ = write!(s, "{i}");
            for v in self.row(i) {
                let _ = write!(s, ",{v:?}");
            }
            s.push('\n');
        }
        s
    }
}

/// A lower-triangular `L` with `L Lᵀ = Σ` for a symmetric positive semi-definite `Σ`: the
/// Cholesky recursion with a pivot at or below `10⁻¹²` of its diagonal's scale taken as zero
/// (its column left out); `None` for a negative or non-finite diagonal.
fn semidefinite_factor(cov: &Mat<f64>) -> Option<Mat<f64>> {
    let p = cov.nrows();
    let mut l = Mat::<f64>::zeros(p, p);
    for j in 0..p {
        let d = cov[(j, j)];
        if !(d.is_finite() && d >= 0.0) {
            return None;
        }
        let pivot = d - (0..j).map(|k| l[(j, k)].powi(2)).sum::<f64>();
        if pivot <= 1e-12 * d || pivot <= 0.0 {
            continue;
        }
        let root = pivot.sqrt();
        l[(j, j)] = root;
        for i in j + 1..p {
            let s = cov[(i, j)] - (0..j).map(|k| l[(i, k)] * l[(j, k)]).sum::<f64>();
            l[(i, j)] = s / root;
        }
    }
    Some(l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Identifier;
    use crate::simulate::{ImpactTest, seed_rig};

    /// The sample mean and covariance of 20 000 draws reproduce the identification's
    /// coefficients and full covariance (the calibration's common gain among it, so every
    /// coefficient is correlated with every other): each mean within 5 standard errors
    /// `σ/√N`, each covariance `Σ_ab` within 5 of its standard errors
    /// `√((Σ_aa Σ_bb + Σ_ab²)/N)`.
    #[test]
    fn sample_mean_and_covariance_reproduce_the_result() {
        use crate::identify::Calibration;
        let records = ImpactTest {
            per_direction: 2,
            noise: 0.05,
            ..ImpactTest::seed_rig()
        }
        .run(&seed_rig())
        .unwrap();
        let id = Identifier::new(8.0, 49.0)
            .calibration(Calibration::default().force(0.02))
            .identify(&records)
            .unwrap();
        let cov = id.covariance().unwrap();
        let theta = id.coefficients().stacked();
        let rows = theta.nrows();
        let n = 20_000;
        let s = BearingSamples::draw(&id, n, 11).unwrap();
        // Index of (block b, row r, column c) in the covariance's order.
        let index = |b: usize, r: usize, c: usize| c * rows + [4, 2, 0][b] + r;
        let value = |i: usize, b: usize, r: usize, c: usize| match b {
            0 => s.stiffness(i)[r][c],
            1 => s.damping(i)[r][c],
            _ => s.mass(i)[r][c],
        };
        let terms: Vec<(usize, usize, usize)> = (0..3)
            .flat_map(|b| (0..2).flat_map(move |r| (0..2).map(move |c| (b, r, c))))
            .collect();
        let means: Vec<f64> = terms
            .iter()
            .map(|&(b, r, c)| (0..n).map(|i| value(i, b, r, c)).sum::<f64>() / n as f64)
            .collect();
        let nf = n as f64;
        let mut correlated = 0;
        for (x, &(b, r, c)) in terms.iter().enumerate() {
            let a = index(b, r, c);
            let truth = theta[(a % rows, a / rows)];
            let se = (cov[(a, a)] / nf).sqrt();
            assert!((means[x] - truth).abs() < 5.0 * se, "mean of {b}{r}{c}");
            for (y, &(b2, r2, c2)) in terms.iter().enumerate() {
                let bb = index(b2, r2, c2);
                let sample = (0..n)
                    .map(|i| (value(i, b, r, c) - means[x]) * (value(i, b2, r2, c2) - means[y]))
                    .sum::<f64>()
                    / (nf - 1.0);
                let se = ((cov[(a, a)] * cov[(bb, bb)] + cov[(a, bb)].powi(2)) / nf).sqrt();
                assert!(
                    (sample - cov[(a, bb)]).abs() < 5.0 * se,
                    "cov {b}{r}{c}/{b2}{r2}{c2}: {sample:e} vs {:e}",
                    cov[(a, bb)]
                );
                if a != bb && cov[(a, bb)].abs() > 0.3 * (cov[(a, a)] * cov[(bb, bb)]).sqrt() {
                    correlated += 1;
                }
            }
        }
        // The test has teeth: many pairs are strongly correlated.
        assert!(correlated > 20, "{correlated}");
    }

    /// A singular covariance (a coefficient without uncertainty) is factored: that
    /// coefficient is the same in every sample; a negative variance and `n = 0` are refused.
    #[test]
    fn singular_covariances_and_bad_input() {
        let m = |v: [f64; 4]| Mat::from_fn(2, 2, |i, j| v[2 * i + j]);
        let c = Coefficients::new(m([1.0; 4]), m([2.0; 4]), m([3.0; 4])).unwrap();
        let cov = Mat::from_fn(12, 12, |a, b| if a == b && a != 4 { 0.01 } else { 0.0 });
        let s = BearingSamples::from_covariance(&c, &cov, 50, 1).unwrap();
        let (fixed, free) = (3.0f64.to_bits(), |i: usize| s.stiffness(i)[1][1].to_bits());
        assert!((0..50).all(|i| s.stiffness(i)[0][0].to_bits() == fixed));
        assert!((0..50).any(|i| free(i) != fixed));
        let csv = s.to_csv();
        assert!(csv.starts_with("sample,kxx,kxy,kyx,kyy,cxx,"));
        assert_eq!(csv.lines().count(), 51);
        let e = BearingSamples::from_covariance(&c, &cov, 0, 1).unwrap_err();
        assert!(e.to_string().contains("--ross-samples"), "{e}");
        let negative = Mat::from_fn(12, 12, |a, b| if a == b { -1.0 } else { 0.0 });
        assert!(BearingSamples::from_covariance(&c, &negative, 5, 1).is_err());
    }
}
