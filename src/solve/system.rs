//! The stacked real system `A Θ = Ī` shared by least squares and IVF, with its column scaling.

use super::Method;
use faer::linalg::matmul::matmul;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par, c64};

use crate::error::{Error, Result};
use crate::frf::Frf;
use crate::linalg;

use super::required_lines;

/// `A` with unit-norm columns (`A_s = A D`), the scaling `D` and the line frequencies (rad/s).
#[derive(Debug)]
pub(super) struct Stacked {
    pub n: usize,
    pub omegas: Vec<f64>,
    /// Scaled `A_s = A D`, `2nN × 3n`.
    pub a: Mat<f64>,
    /// Diagonal of `D`: `1 / ‖a_p‖`.
    pub scale: Vec<f64>,
}

/// Writes the `2n × 3n` block of one line: real rows on top, imaginary rows below.
pub(super) fn fill_line(mut dst: MatMut<'_, f64>, g: &[c64], w: f64, n: usize, scale: &[f64]) {
    // Column by column: `dst` is column-major, so each inner loop writes contiguous rows.
    for m in 0..n {
        let (sm, sc, sk) = (-w * w * scale[m], w * scale[n + m], scale[2 * n + m]);
        let col = &g[m * n..(m + 1) * n];
        for (i, v) in col.iter().enumerate() {
            dst[(i, m)] = sm * v.re;
            dst[(n + i, m)] = sm * v.im;
        }
        for (i, v) in col.iter().enumerate() {
            dst[(i, n + m)] = -sc * v.im;
            dst[(n + i, n + m)] = sc * v.re;
        }
        for (i, v) in col.iter().enumerate() {
            dst[(i, 2 * n + m)] = sk * v.re;
            dst[(n + i, 2 * n + m)] = sk * v.im;
        }
    }
}

/// [`Error::TooFewLines`] unless `frf` holds [`required_lines`] lines.
pub(super) fn check_lines(frf: &Frf) -> Result<()> {
    let (n, lines) = (frf.dofs(), frf.line_count());
    if lines >= required_lines(n) {
        return Ok(());
    }
    Err(Error::TooFewLines {
        lines,
        required: required_lines(n),
        resolution_hz: frf.line_spacing_hz(),
    })
}

impl Stacked {
    pub fn new(frf: &Frf, method: Method) -> Result<Self> {
        check_lines(frf)?;
        let n = frf.dofs();
        let lines = frf.line_count();
        let omegas: Vec<f64> = frf
            .freqs_hz()
            .iter()
            .map(|f| 2.0 * std::f64::consts::PI * f)
            .collect();
        let mut a = Mat::<f64>::zeros(2 * n * lines, 3 * n);
        let ones = vec![1.0; 3 * n];
        let g = frf.flexibility_data();
        for (k, &w) in omegas.iter().enumerate() {
            fill_line(
                a.as_mut().subrows_mut(2 * n * k, 2 * n),
                &g[k * n * n..(k + 1) * n * n],
                w,
                n,
                &ones,
            );
        }
        let mut scale = vec![0.0; 3 * n];
        for (p, s) in scale.iter_mut().enumerate() {
            let norm = a.col(p).norm_l2();
            if !(norm > 0.0 && norm.is_finite()) {
                return Err(Error::SingularFit { method });
            }
            *s = 1.0 / norm;
            a.col_mut(p).iter_mut().for_each(|v| *v *= *s);
        }
        Ok(Self {
            n,
            omegas,
            a,
            scale,
        })
    }

    /// The dense right-hand side `Ī = [I; 0; I; 0; …]` (`2nN × n`).
    pub fn rhs(&self) -> Mat<f64> {
        let n = self.n;
        Mat::from_fn(self.a.nrows(), n, |r, j| {
            f64::from(u8::from(r % (2 * n) == j))
        })
    }

    /// `Wᵀ Ī` without forming `Ī`: the sum over lines of the transposed real rows.
    pub fn instrument_rhs(&self, w: MatRef<'_, f64>, mut out: MatMut<'_, f64>) {
        let n = self.n;
        out.fill(0.0);
        for k in 0..self.omegas.len() {
            for j in 0..n {
                let r = 2 * n * k + j;
                for p in 0..3 * n {
                    out[(p, j)] += w[(r, p)];
                }
            }
        }
    }

    /// `Θ = D Θ_s`.
    pub fn unscale(&self, theta_s: MatRef<'_, f64>) -> Mat<f64> {
        Mat::from_fn(theta_s.nrows(), theta_s.ncols(), |p, j| {
            theta_s[(p, j)] * self.scale[p]
        })
    }

    /// `out = D Θ_s`, in place.
    pub fn unscale_into(&self, theta_s: MatRef<'_, f64>, mut out: MatMut<'_, f64>) {
        for j in 0..theta_s.ncols() {
            for p in 0..theta_s.nrows() {
                out[(p, j)] = theta_s[(p, j)] * self.scale[p];
            }
        }
    }

    /// `‖A Θ − Ī‖_F` using the caller's buffers (`3n × n` and `2nN × n`); no allocation.
    pub fn residual_norm_into(
        &self,
        theta: MatRef<'_, f64>,
        theta_s: MatMut<'_, f64>,
        mut residual: MatMut<'_, f64>,
    ) -> f64 {
        self.residual_into(theta, theta_s, residual.rb_mut());
        residual.rb().norm_l2()
    }

    /// Residual `A Θ − Ī = A_s Θ_s − Ī` into `residual` (`2nN × n`), `theta_s` as scratch.
    pub fn residual_into(
        &self,
        theta: MatRef<'_, f64>,
        mut theta_s: MatMut<'_, f64>,
        mut residual: MatMut<'_, f64>,
    ) {
        self.rescale(theta, theta_s.rb_mut());
        matmul(
            residual.rb_mut(),
            Accum::Replace,
            self.a.as_ref(),
            theta_s.rb(),
            1.0,
            Par::Seq,
        );
        let n = self.n;
        for row in 0..residual.nrows() {
            let j = row % (2 * n);
            if j < n {
                residual[(row, j)] -= 1.0;
            }
        }
    }

    /// `Θ_s = D⁻¹ Θ`.
    pub fn rescale(&self, theta: MatRef<'_, f64>, mut out: MatMut<'_, f64>) {
        for j in 0..theta.ncols() {
            for p in 0..theta.nrows() {
                out[(p, j)] = theta[(p, j)] / self.scale[p];
            }
        }
    }

    /// Residual `A_s Θ_s − Ī` (`2nN × n`), allocated.
    pub fn residual(&self, theta: MatRef<'_, f64>) -> Mat<f64> {
        let mut theta_s = Mat::zeros(theta.nrows(), theta.ncols());
        let mut r = Mat::zeros(self.a.nrows(), self.n);
        self.residual_into(theta, theta_s.as_mut(), r.as_mut());
        r
    }

    /// `‖A Θ − Ī‖_F`.
    pub fn residual_norm(&self, theta: MatRef<'_, f64>) -> f64 {
        let mut theta_s = Mat::zeros(theta.nrows(), theta.ncols());
        let mut residual = Mat::zeros(self.a.nrows(), self.n);
        self.residual_norm_into(theta, theta_s.as_mut(), residual.as_mut())
    }

    /// Fills the scaled instruments `W_s` from the model flexibility of `theta` (unscaled).
    /// Returns `false` if the model impedance is singular at some line.
    pub fn fill_instruments(
        &self,
        theta: MatRef<'_, f64>,
        mut w_s: MatMut<'_, f64>,
        g: &mut [c64],
        inverter: &mut linalg::Inverter,
    ) -> bool {
        let n = self.n;
        for (k, &w) in self.omegas.iter().enumerate() {
            for j in 0..n {
                for i in 0..n {
                    g[i + j * n] = c64::new(
                        theta[(2 * n + i, j)] - w * w * theta[(i, j)],
                        w * theta[(n + i, j)],
                    );
                }
            }
            if !inverter.invert(g) {
                return false;
            }
            fill_line(
                w_s.rb_mut().subrows_mut(2 * n * k, 2 * n),
                g,
                w,
                n,
                &self.scale,
            );
        }
        true
    }

    /// Sandwich covariance of every column of `Θ` (unscaled, `3n × 3n` each), instruments
    /// `w_s` (scaled; `A_s` for least squares):
    /// `(WᵀA)⁻¹ Wᵀ diag(r_j²) W (AᵀW)⁻¹ · m/(m − p)`. `None` without redundancy or when not
    /// finite.
    pub fn sandwich_covariance(
        &self,
        theta: MatRef<'_, f64>,
        w_s: MatRef<'_, f64>,
    ) -> Option<Vec<Mat<f64>>> {
        use faer::linalg::solvers::DenseSolveCore;
        let (m, p) = (self.a.nrows(), self.a.ncols());
        if m <= p {
            return None;
        }
        let mut bread = Mat::zeros(p, p);
        matmul(
            bread.as_mut(),
            Accum::Replace,
            w_s.transpose(),
            self.a.as_ref(),
            1.0,
            Par::Seq,
        );
        let inv = bread.partial_piv_lu().inverse();
        let r = self.residual(theta);
        let mut weighted = Mat::<f64>::zeros(m, p);
        let mut meat = Mat::zeros(p, p);
        let mut tmp = Mat::zeros(p, p);
        let dof = m as f64 / (m - p) as f64;
        let mut out = Vec::with_capacity(self.n);
        for j in 0..self.n {
            for c in 0..p {
                for row in 0..m {
                    weighted[(row, c)] = w_s[(row, c)] * r[(row, j)];
                }
            }
            matmul(
                meat.as_mut(),
                Accum::Replace,
                weighted.transpose(),
                weighted.as_ref(),
                1.0,
                Par::Seq,
            );
            matmul(
                tmp.as_mut(),
                Accum::Replace,
                inv.as_ref(),
                meat.as_ref(),
                1.0,
                Par::Seq,
            );
            let mut cov = Mat::zeros(p, p);
            matmul(
                cov.as_mut(),
                Accum::Replace,
                tmp.as_ref(),
                inv.transpose(),
                dof,
                Par::Seq,
            );
            // Undo the column scaling: Cov(Θ) = D Cov(Θ_s) D.
            let cov = Mat::from_fn(p, p, |a, b| cov[(a, b)] * self.scale[a] * self.scale[b]);
            if !cov.col_iter().all(|c| c.iter().all(|v| v.is_finite())) {
                return None;
            }
            out.push(cov);
        }
        Some(out)
    }
}
