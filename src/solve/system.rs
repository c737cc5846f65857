//! The stacked real system `A Θ = Ī` shared by least squares and IVF, with its column scaling.

use super::Method;
use faer::linalg::matmul::matmul;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par, c64};

use crate::error::{Error, Result};
use crate::frf::Frf;
use crate::linalg;

use super::quad::{self, Quads};
use super::required_lines;
use super::split::{self, Simd, WithSimd};

/// Per line of `frf`, the variance of each entry of `G H − I` that the noise of the measured
/// flexibility leaves at the true coefficients ([`Frf::equation_variance`]); where only the
/// impedance's variance is known, from $\delta G = -G\,\delta H\,G$ and $GH = I$ (the
/// residual is $-G\,\delta H$): $\sum_a |G_{ia}|^2 v_{aj}$ for independent element errors
/// `v` ([`Frf::impedance_variance`]). `None` unless every line has a finite variance.
fn row_variance(frf: &Frf) -> Option<Vec<f64>> {
    let n = frf.dofs();
    let mut out = Vec::with_capacity(frf.line_count() * n * n);
    for k in 0..frf.line_count() {
        if let Some(e) = frf.equation_variance(k) {
            for j in 0..n {
                for i in 0..n {
                    let var = e[(i, j)];
                    if !var.is_finite() {
                        return None;
                    }
                    out.push(var);
                }
            }
            continue;
        }
        let (g, v) = (frf.flexibility(k), frf.impedance_variance(k)?);
        for j in 0..n {
            for i in 0..n {
                let var: f64 = (0..n).map(|a| g[(i, a)].norm_sqr() * v[(a, j)]).sum();
                if !var.is_finite() {
                    return None;
                }
                out.push(var);
            }
        }
    }
    Some(out)
}

/// `A` with unit-norm columns (`A_s = A D`), the scaling `D` and the line frequencies (rad/s).
#[derive(Debug)]
pub(super) struct Stacked {
    pub n: usize,
    pub omegas: Vec<f64>,
    /// Scaled `A_s = A D`, `2nN × 3n`.
    pub a: Mat<f64>,
    /// Diagonal of `D`: `1 / ‖a_p‖`.
    pub scale: Vec<f64>,
    /// The measured flexibilities transposed, `G_kᵀ`, `[line][n × n]` column-major, real
    /// parts (`A`'s unscaled blocks, split for the kernels of [`split`]).
    gt_re: Vec<f64>,
    /// Their imaginary parts.
    gt_im: Vec<f64>,
    /// Per line, the variance of the residual `(G H − I)_ij` a right model leaves, from the
    /// measured impedance's own variance ([`Frf::impedance_variance`]):
    /// $\sum_a |G_{ia}|^2 v_{aj}$, `[k * n² + i + j * n]`; `None` when the FRF has none.
    row_variance: Option<Vec<f64>>,
    /// For three degrees of freedom, the full groups of four lines of `omegas`, `gt_re`,
    /// `gt_im` in lanes ([`quad`]); `None` otherwise.
    quads: Option<Quads>,
}

/// The buffers of [`Stacked::instrument_normal`] and [`Stacked::residual_norm_into`], split
/// (real parts, imaginary parts) as the kernels of [`split`] want them: `M`, `C`, `K` of the
/// iterate (or their transposes), the model impedance and flexibility of one line, one
/// product, and the eight weighted `n × n` sums over the lines.
pub(super) struct InstrumentWork {
    n: usize,
    /// `M`, `C`, `K` column-major, one after the other (`3n²`).
    blocks: Vec<f64>,
    h_re: Vec<f64>,
    h_im: Vec<f64>,
    p_re: Vec<f64>,
    p_im: Vec<f64>,
    /// `Σ Pᴿ, Σ ω² Pᴿ, Σ ω⁴ Pᴿ, Σ ω Pᴵ, Σ ω³ Pᴵ` (of `Pᵀ`), `Σ G_mᴿ, Σ ω² G_mᴿ, Σ ω G_mᴵ`.
    sums: Vec<f64>,
    pivots: Vec<usize>,
    arch: split::Arch,
}

impl InstrumentWork {
    pub(super) fn new(n: usize) -> Self {
        let nn = n * n;
        Self {
            n,
            blocks: vec![0.0; 3 * nn],
            h_re: vec![0.0; nn],
            h_im: vec![0.0; nn],
            p_re: vec![0.0; nn],
            p_im: vec![0.0; nn],
            sums: vec![0.0; 8 * nn],
            pivots: vec![0; n],
            arch: split::Arch::new(),
        }
    }

    /// Copies `M`, `C`, `K` of the stacked `Θ` (transposed when `transpose`) into `blocks`.
    fn load(&mut self, theta: MatRef<'_, f64>, transpose: bool) {
        let n = self.n;
        for (b, block) in self.blocks.chunks_exact_mut(n * n).enumerate() {
            for j in 0..n {
                for i in 0..n {
                    block[i + j * n] = if transpose {
                        theta[(b * n + j, i)]
                    } else {
                        theta[(b * n + i, j)]
                    };
                }
            }
        }
    }
}

/// `$body` with `$n` bound to the size `$size`, a constant for 2, 3 and 4: the kernels of
/// [`split`] are inlined, so a constant size unrolls their loops for the small systems (bit for
/// bit the same operations). A macro, not a function taking a closure: the closure was not
/// inlined into the SIMD context, and the pass ran twice as slow as without the split.
macro_rules! small_n {
    ($size:expr, $n:ident => $body:expr) => {
        match $size {
            2 => {
                let $n = 2;
                $body
            }
            3 => {
                let $n = 3;
                $body
            }
            4 => {
                let $n = 4;
                $body
            }
            $n => $body,
        }
    };
}

/// One pass of [`Stacked::instrument_normal`] over the lines, vectorised: `false` if the
/// model impedance is singular at a line.
struct InstrumentSums<'a> {
    sys: &'a Stacked,
    work: &'a mut InstrumentWork,
}

impl WithSimd for InstrumentSums<'_> {
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) -> bool {
        small_n!(self.sys.n, n => self.pass(simd, n))
    }
}

impl InstrumentSums<'_> {
    #[inline(always)]
    fn pass<S: Simd>(self, simd: S, n: usize) -> bool {
        let Self { sys, work } = self;
        let nn = n * n;
        let InstrumentWork {
            blocks,
            h_re,
            h_im,
            p_re,
            p_im,
            sums,
            pivots,
            ..
        } = work;
        sums.fill(0.0);
        let (m, c, k) = (&blocks[..nn], &blocks[nn..2 * nn], &blocks[2 * nn..]);
        let line = |q: usize| {
            let at = q * nn..(q + 1) * nn;
            (sys.omegas[q], (&sys.gt_re[at.clone()], &sys.gt_im[at]))
        };
        // Three degrees of freedom: the full groups of four lines in lanes ([`quad`]), each
        // line then summed in line order as below; the last lines, and a group out of the
        // cofactors' range, line by line.
        let mut first = 0;
        if let (3, Some(quads)) = (n, &sys.quads) {
            let mut group = quad::Group::new();
            for g in 0..quads.groups() {
                let lines = g * quad::QUAD..(g + 1) * quad::QUAD;
                match group.instruments::<S>(quads, g, (m, c, k)) {
                    Some(false) => return false,
                    Some(true) => {}
                    None => {
                        for q in lines {
                            let (w, gt) = line(q);
                            let buffers = (&mut **h_re, &mut **h_im, &mut **p_re, &mut **p_im);
                            if !line_sums(simd, n, w, gt, (m, c, k), buffers, sums, pivots) {
                                return false;
                            }
                        }
                    }
                }
            }
            first = quads.groups() * quad::QUAD;
            group.add_sums_to(sums);
        }
        for q in first..sys.omegas.len() {
            let (w, gt) = line(q);
            let buffers = (&mut **h_re, &mut **h_im, &mut **p_re, &mut **p_im);
            if !line_sums(simd, n, w, gt, (m, c, k), buffers, sums, pivots) {
                return false;
            }
        }
        true
    }
}

/// One line of [`InstrumentSums`]: the model impedance `H` of the blocks `M`, `C`, `K` at
/// `w`, its inverse `G_m` (in `h`), `Pᵀ = Gᵀ Ḡ_m` (in `p`) from the line's `Gᵀ`, and the
/// eight weighted sums ([`add_sums`]). `false` if the impedance is singular.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn line_sums<S: Simd>(
    simd: S,
    n: usize,
    w: f64,
    (gt_re, gt_im): (&[f64], &[f64]),
    (m, c, k): (&[f64], &[f64], &[f64]),
    (h_re, h_im, p_re, p_im): (&mut [f64], &mut [f64], &mut [f64], &mut [f64]),
    sums: &mut [f64],
    pivots: &mut [usize],
) -> bool {
    split::impedance(simd, (h_re, h_im), (m, c, k), w);
    // Three degrees of freedom by cofactors; Gauss–Jordan otherwise, or where the
    // impedance's scale leaves the normal range.
    let cofactors = if n == 3 {
        split::invert3((h_re, h_im))
    } else {
        None
    };
    let regular = match cofactors {
        Some(regular) => regular,
        None => split::invert(simd, (h_re, h_im), n, pivots),
    };
    if !regular {
        return false;
    }
    // Pᵀ = Gᵀ Ḡ_m, the transpose of P = G_mᴴ G.
    split::mul(simd, (p_re, p_im), (gt_re, gt_im), (h_re, h_im), n, true);
    add_sums(simd, sums, (p_re, p_im), (h_re, h_im), w);
    true
}

/// Adds one line's `Pᵀ` and `G_m` at `w` to the eight weighted sums of [`InstrumentWork`].
#[inline(always)]
fn add_sums<S: Simd>(
    simd: S,
    sums: &mut [f64],
    (p_re, p_im): (&[f64], &[f64]),
    (h_re, h_im): (&[f64], &[f64]),
    w: f64,
) {
    let (w2, w3, w4) = (w * w, w * w * w, w * w * w * w);
    let sources: [(&[f64], f64); 8] = [
        (p_re, 1.0),
        (p_re, w2),
        (p_re, w4),
        (p_im, w),
        (p_im, w3),
        (h_re, 1.0),
        (h_re, w2),
        (h_im, w),
    ];
    for (dst, (src, weight)) in sums.chunks_exact_mut(p_re.len()).zip(sources) {
        split::add_scaled(simd, dst, src, weight);
    }
}

/// [`Stacked::residual_norm_into`]'s pass over the lines, vectorised.
struct ResidualNorm<'a> {
    sys: &'a Stacked,
    work: &'a mut InstrumentWork,
}

impl WithSimd for ResidualNorm<'_> {
    type Output = f64;

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) -> f64 {
        small_n!(self.sys.n, n => self.pass(simd, n))
    }
}

impl ResidualNorm<'_> {
    #[inline(always)]
    fn pass<S: Simd>(self, simd: S, n: usize) -> f64 {
        let Self { sys, work } = self;
        let nn = n * n;
        let InstrumentWork {
            blocks,
            h_re,
            h_im,
            p_re,
            p_im,
            ..
        } = work;
        let (m, c, k) = (&blocks[..nn], &blocks[nn..2 * nn], &blocks[2 * nn..]);
        let mut sum = 0.0;
        // Three degrees of freedom: the full groups of four lines in lanes ([`quad`]), each
        // line's norm then formed and summed in line order as below.
        let mut first = 0;
        if let (3, Some(quads)) = (n, &sys.quads) {
            let (mut group, mut acc) = (quad::Group::new(), [0.0; quad::QUAD]);
            for g in 0..quads.groups() {
                group.residual::<S>(quads, g, (m, c, k), &mut acc);
            }
            sum = quad::combine(&acc);
            first = quads.groups() * quad::QUAD;
        }
        let (gt_re, gt_im) = (sys.gt_re.chunks_exact(nn), sys.gt_im.chunks_exact(nn));
        for ((&w, gt_re), gt_im) in sys.omegas.iter().zip(gt_re).zip(gt_im).skip(first) {
            // Hᵀ from the transposed blocks; (G H)ᵀ = Hᵀ Gᵀ.
            split::impedance(simd, (h_re, h_im), (m, c, k), w);
            split::mul(simd, (p_re, p_im), (h_re, h_im), (gt_re, gt_im), n, false);
            for d in 0..n {
                p_re[d * (n + 1)] -= 1.0;
            }
            sum += split::norm_sqr(simd, p_re, p_im);
        }
        sum
    }
}

/// The model impedance `H(ω; Θ) = K − ω² M + iω C` of the stacked `Θ = [M; C; K]` into
/// `h` (`n × n` column-major).
fn impedance_into(theta: MatRef<'_, f64>, w: f64, h: &mut [c64], n: usize) {
    for j in 0..n {
        for i in 0..n {
            h[i + j * n] = c64::new(
                theta[(2 * n + i, j)] - w * w * theta[(i, j)],
                w * theta[(n + i, j)],
            );
        }
    }
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

/// The transposes of the column-major `n × n` blocks of `g`, one part (`part`) of each entry.
fn transposed(g: &[c64], n: usize, part: fn(&c64) -> f64) -> Vec<f64> {
    let mut out = vec![0.0; g.len()];
    for (dst, src) in out.chunks_exact_mut(n * n).zip(g.chunks_exact(n * n)) {
        for j in 0..n {
            for i in 0..n {
                dst[j + i * n] = part(&src[i + j * n]);
            }
        }
    }
    out
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
        let (gt_re, gt_im) = (transposed(g, n, |z| z.re), transposed(g, n, |z| z.im));
        Ok(Self {
            n,
            quads: (n == 3).then(|| Quads::new(&omegas, &gt_re, &gt_im)),
            omegas,
            a,
            scale,
            gt_re,
            gt_im,
            row_variance: row_variance(frf),
        })
    }

    /// The dense right-hand side `Ī = [I; 0; I; 0; …]` (`2nN × n`).
    pub fn rhs(&self) -> Mat<f64> {
        let n = self.n;
        let mut rhs = Mat::zeros(self.a.nrows(), n);
        for line in 0..self.omegas.len() {
            for j in 0..n {
                rhs[(2 * n * line + j, j)] = 1.0;
            }
        }
        rhs
    }

    /// `Wᵀ Ī` without forming `Ī`: the sum over lines of the transposed real rows (the
    /// dense reference of [`Stacked::instrument_normal`]).
    #[cfg(test)]
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

    /// `‖A Θ − Ī‖_F` line by line, without `A` or an `m × n` residual: line `k`'s rows of
    /// `A Θ − Ī` are $R(G_k)\,T_k\Theta - (I; 0)$ with $T_k\Theta = (H_k^R; H_k^I)$,
    /// $H_k = K - \omega_k^2 M + i\omega_k C$, i.e. the real form of $G_k H_k - I$, so
    /// $\lVert A\Theta - \bar I \rVert_F^2 = \sum_k \lVert G_k H_k - I \rVert_F^2$:
    /// one complex `n × n` product per line (`8n³` flops instead of the dense `12n³`), formed
    /// as $(G_k H_k)^\top = H_k^\top G_k^\top$ in split storage ([`split`]); for three
    /// degrees of freedom four lines at once ([`quad`]), each lane summed apart. No allocation.
    pub fn residual_norm_into(&self, theta: MatRef<'_, f64>, work: &mut InstrumentWork) -> f64 {
        work.load(theta, true);
        let arch = work.arch;
        arch.dispatch(ResidualNorm { sys: self, work }).sqrt()
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

    /// `‖A Θ − Ī‖_F` (the dense residual's norm; [`Stacked::residual_norm_into`] is the
    /// allocation-free per-line form).
    pub fn residual_norm(&self, theta: MatRef<'_, f64>) -> f64 {
        self.residual(theta).norm_l2()
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
            impedance_into(theta, w, g, n);
            if !inverter.invert_by_cofactors(g) {
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

    /// `W_sᵀ A_s` (`3n × 3n`) and `W_sᵀ Ī` (`3n × n`) with instruments from the model
    /// flexibility `G_m = H(ω; Θ)⁻¹` of `theta` (unscaled), without forming `W`: per line
    /// `W_k = R(G_m) T_k D`, `A_k = R(G) T_k D` with the real form
    /// $R(Z) = \begin{pmatrix} Z^R & -Z^I \\ Z^I & Z^R \end{pmatrix}$ and
    /// $T_k = (-\omega^2 E_1 \;\; \omega E_2 \;\; E_1)$, so with $P_k = G_m^H G$,
    /// $W_k^\top A_k = D\,T_k^\top R(P_k) T_k\,D$, whose `n × n` blocks are
    /// $\begin{pmatrix} \omega^4 P^R & \omega^3 P^I & -\omega^2 P^R \\ -\omega^3 P^I & \omega^2 P^R & \omega P^I \\ -\omega^2 P^R & -\omega P^I & P^R \end{pmatrix}$:
    /// one complex `n × n` product per line (`8n³` flops instead of `36n³` for the dense
    /// `Wᵀ A`) and five weighted sums. `W_kᵀ Ī` is the real rows of `W_k`: `−ω² G_mᴿ`,
    /// `−ω G_mᴵ`, `G_mᴿ`, transposed. Per line, in split storage and vectorised ([`split`]):
    /// `H`, its Gauss–Jordan inverse `G_m` (`8n³` flops), $P^\top = G^\top \bar G_m$ from
    /// the stored `Gᵀ` (`8n³`) and the eight weighted sums; for three degrees of freedom,
    /// `H`, `G_m`, `Pᵀ` and the sums of four lines at once, one per SIMD lane ([`quad`]).
    /// Returns `false` if the model impedance is singular at some line. No allocation.
    pub fn instrument_normal(
        &self,
        theta: MatRef<'_, f64>,
        mut normal: MatMut<'_, f64>,
        mut rhs: MatMut<'_, f64>,
        work: &mut InstrumentWork,
    ) -> bool {
        work.load(theta, false);
        let arch = work.arch;
        if !arch.dispatch(InstrumentSums { sys: self, work }) {
            return false;
        }
        let (n, nn) = (self.n, self.n * self.n);
        let sums = &work.sums;
        let s = &self.scale;
        // Block (X, Y) of T_kᵀ R(P) T_k: the sum, its sign.
        const BLOCKS: [[(usize, f64); 3]; 3] = [
            [(2, 1.0), (4, 1.0), (1, -1.0)],
            [(4, -1.0), (1, 1.0), (3, 1.0)],
            [(1, -1.0), (3, -1.0), (0, 1.0)],
        ];
        for y in 0..3 {
            for b in 0..n {
                for (x, blocks) in BLOCKS.iter().enumerate() {
                    let (sum, sign) = blocks[y];
                    for a in 0..n {
                        // The sums are of Pᵀ: entry (a, b) of P is at b + a n.
                        normal[(x * n + a, y * n + b)] =
                            sign * s[x * n + a] * s[y * n + b] * sums[sum * nn + b + a * n];
                    }
                }
            }
        }
        // W_sᵀ Ī: row m of block X, column j, from entry (j, m) of the block's G_m sum.
        const RHS: [(usize, f64); 3] = [(6, -1.0), (7, -1.0), (5, 1.0)];
        for j in 0..n {
            for (x, &(sum, sign)) in RHS.iter().enumerate() {
                for m in 0..n {
                    rhs[(x * n + m, j)] = sign * s[x * n + m] * sums[sum * nn + j + m * n];
                }
            }
        }
        true
    }

    /// Sandwich covariance of every column of `Θ` (unscaled, `3n × 3n` each), instruments
    /// `w_s` (scaled; `A_s` for least squares): `(WᵀA)⁻¹ Wᵀ Σ_j W (AᵀW)⁻¹`. Where the FRF
    /// carries its own variance (replicates: paired sets, periods, segments), `Σ_j` is the
    /// variance of the rows of column `j` a right model leaves ([`row_variance`], half to the
    /// real and half to the imaginary row of each entry): known from the replicates with many
    /// degrees of freedom per line, where a residual squared has one, so the error bars do not
    /// swing from seed to seed with the residuals at the few lines that decide a coefficient
    /// (on multisine records of two excitations, 16 periods, the residual form's standard
    /// deviation of `M_xx` ranged over a factor of 6 between seeds). Otherwise the squared
    /// residuals, `diag(r_j²)·m/(m − p)`. `None` without redundancy or when not finite.
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
        // The residuals only where the FRF carries no variance of its own (empty otherwise).
        let r = match self.row_variance {
            Some(_) => Mat::new(),
            None => self.residual(theta),
        };
        let n = self.n;
        let mut weighted = Mat::<f64>::zeros(m, p);
        let mut meat = Mat::zeros(p, p);
        let mut tmp = Mat::zeros(p, p);
        let mut sigma = vec![0.0; m];
        let dof = m as f64 / (m - p) as f64;
        let mut out = Vec::with_capacity(self.n);
        for j in 0..self.n {
            // Row `2nk + i` (real) and `2nk + n + i` (imaginary) of line `k`: entry `(i, j)`.
            match &self.row_variance {
                Some(v) => {
                    for (k, line) in sigma.chunks_exact_mut(2 * n).enumerate() {
                        let var = &v[k * n * n + j * n..k * n * n + (j + 1) * n];
                        for (i, &var) in var.iter().enumerate() {
                            let s = (0.5 * var).sqrt();
                            line[i] = s;
                            line[n + i] = s;
                        }
                    }
                }
                None => {
                    for (row, sigma) in sigma.iter_mut().enumerate() {
                        *sigma = r[(row, j)] * dof.sqrt();
                    }
                }
            }
            // Column by column, down contiguous columns.
            for c in 0..p {
                let dst = weighted.col_mut(c).iter_mut();
                for (dst, (w, sigma)) in dst.zip(w_s.col(c).iter().zip(&sigma)) {
                    *dst = w * sigma;
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
                1.0,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Coefficients;

    /// For three degrees of freedom, the lines in groups of four ([`quad`]) give the normal
    /// equations and the residual norm of the per-line path to the rounding of their sums
    /// over the lines (the lanes summed apart), at every scale the coefficients may have (the
    /// impedance scaled exactly by a power of two either way), and a singular model impedance
    /// is refused by both.
    #[test]
    fn grouped_lines_are_the_per_line_path() {
        // Powers of two (about 1e-140 and 1e140), so that the singular model below is exact.
        for scale in [2f64.powi(-465), 1.0, 2f64.powi(465)] {
            for lines in [13, 16, 19] {
                let truth = Coefficients::new(
                    faer::mat![[2.0, 0.1, 0.0], [0.1, 2.5, 0.2], [0.0, 0.2, 3.0]] * scale,
                    faer::mat![[60.0, 8.0, -3.0], [-5.0, 70.0, 4.0], [2.0, -6.0, 80.0]] * scale,
                    faer::mat![[4e5, 6e4, -1e4], [2e4, 6e5, 5e4], [-2e4, 1e4, 9e5]] * scale,
                )
                .unwrap();
                let freqs: Vec<f64> = (0..lines).map(|l| 20.0 + 13.0 * l as f64).collect();
                let g: Vec<Mat<c64>> = freqs
                    .iter()
                    .map(|&f| {
                        let g = truth.flexibility_at(f).unwrap();
                        Mat::from_fn(3, 3, |i, j| {
                            g[(i, j)] * (1.0 + 0.01 * ((i + 2 * j) % 3) as f64)
                        })
                    })
                    .collect();
                let frf = Frf::from_flexibility(freqs, &g).unwrap();
                let grouped = Stacked::new(&frf, Method::Ivf).unwrap();
                assert_eq!(grouped.quads.as_ref().unwrap().groups(), lines / 4);
                let mut per_line = Stacked::new(&frf, Method::Ivf).unwrap();
                per_line.quads = None;
                let model = Coefficients::new(
                    truth.mass() * 1.01,
                    truth.damping() * 0.97,
                    truth.stiffness() * 1.02,
                )
                .unwrap();
                let mut out = Vec::new();
                for sys in [&grouped, &per_line] {
                    let (mut normal, mut rhs) = (Mat::zeros(9, 9), Mat::zeros(9, 3));
                    let mut work = InstrumentWork::new(3);
                    let theta = model.stacked();
                    assert!(sys.instrument_normal(
                        theta.as_ref(),
                        normal.as_mut(),
                        rhs.as_mut(),
                        &mut work
                    ));
                    let residual = sys.residual_norm_into(theta.as_ref(), &mut work);
                    out.push((normal, rhs, residual));
                }
                let ((normal, rhs, residual), reference) = (&out[0], &out[1]);
                let errors = [
                    (normal - &reference.0).norm_l2() / reference.0.norm_l2(),
                    (rhs - &reference.1).norm_l2() / reference.1.norm_l2(),
                    (residual - reference.2).abs() / reference.2,
                ];
                for err in errors {
                    assert!(err < 1e-14, "scale {scale:e}, {lines} lines: {errors:?}");
                }
                // A model singular at the line at 20 Hz (the first group's first lane).
                let w = 2.0 * std::f64::consts::PI * 20.0;
                let singular = Coefficients::new(
                    Mat::<f64>::identity(3, 3) * scale,
                    Mat::<f64>::zeros(3, 3),
                    Mat::<f64>::identity(3, 3) * (w * w * scale),
                )
                .unwrap();
                for sys in [&grouped, &per_line] {
                    let (mut normal, mut rhs) = (Mat::zeros(9, 9), Mat::zeros(9, 3));
                    let theta = singular.stacked();
                    assert!(!sys.instrument_normal(
                        theta.as_ref(),
                        normal.as_mut(),
                        rhs.as_mut(),
                        &mut InstrumentWork::new(3)
                    ));
                }
            }
        }
    }

    /// `instrument_normal` is the dense `W_sᵀ A_s`, `W_sᵀ Ī` of `fill_instruments`, and
    /// `residual_norm_into` the dense `‖A Θ − Ī‖_F`, to rounding, for every size, both
    /// product paths included.
    #[test]
    fn instrument_normal_is_the_dense_product() {
        for n in [1, 2, 3, 8, 17] {
            let lines = 3 * n + 4;
            let m = Mat::from_fn(n, n, |i, j| if i == j { 2.0 + i as f64 } else { 0.1 });
            let c = Mat::from_fn(n, n, |i, j| 30.0 + 5.0 * i as f64 - 2.0 * j as f64);
            let k = Mat::from_fn(n, n, |i, j| {
                if i == j {
                    4e5 * (1.0 + i as f64)
                } else {
                    1e4 * (i as f64 - j as f64)
                }
            });
            let truth = Coefficients::new(m, c, k).unwrap();
            let freqs: Vec<f64> = (0..lines).map(|l| 20.0 + 7.0 * l as f64).collect();
            let g: Vec<Mat<c64>> = freqs
                .iter()
                .map(|&f| {
                    let g = truth.flexibility_at(f).unwrap();
                    // Measurement error, so that the model and measured G differ.
                    Mat::from_fn(n, n, |i, j| {
                        g[(i, j)] * (1.0 + 0.01 * ((i + 2 * j) % 3) as f64)
                    })
                })
                .collect();
            let sys =
                Stacked::new(&Frf::from_flexibility(freqs, &g).unwrap(), Method::Ivf).unwrap();
            let model = Coefficients::new(
                truth.mass() * 1.01,
                truth.damping() * 0.97,
                truth.stiffness() * 1.02,
            )
            .unwrap();
            let theta = model.stacked();
            let p = 3 * n;
            let mut w_s = Mat::zeros(sys.a.nrows(), p);
            let mut scratch = vec![c64::new(0.0, 0.0); n * n];
            assert!(sys.fill_instruments(
                theta.as_ref(),
                w_s.as_mut(),
                &mut scratch,
                &mut linalg::Inverter::new(n)
            ));
            let dense = w_s.transpose() * &sys.a;
            let mut dense_rhs = Mat::zeros(p, n);
            sys.instrument_rhs(w_s.as_ref(), dense_rhs.as_mut());
            let (mut normal, mut rhs) = (Mat::zeros(p, p), Mat::zeros(p, n));
            assert!(sys.instrument_normal(
                theta.as_ref(),
                normal.as_mut(),
                rhs.as_mut(),
                &mut InstrumentWork::new(n)
            ));
            let err = (&normal - &dense).norm_l2() / dense.norm_l2();
            assert!(err < 1e-13, "n = {n}: {err:e}");
            let err = (&rhs - &dense_rhs).norm_l2() / dense_rhs.norm_l2();
            assert!(err < 1e-13, "n = {n}: rhs {err:e}");
            // The per-line residual norm is the dense one's, at the model and at the truth
            // (where only the measurement error is left), relative to `‖Ī‖_F` (Θ = 0's).
            let reference = ((n * lines) as f64).sqrt();
            assert!(sys.residual_norm(theta.as_ref()) > 1e-3 * reference);
            for theta in [theta.as_ref(), truth.stacked().as_ref()] {
                let dense = sys.residual_norm(theta);
                let per_line = sys.residual_norm_into(theta, &mut InstrumentWork::new(n));
                let err = (per_line - dense).abs() / reference;
                assert!(err < 1e-13, "n = {n}: residual {err:e}");
            }
        }
    }
}
