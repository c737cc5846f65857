//! The kernels of one element's robust linear fit ([`Design`], [`Element`]): the basis that
//! every element and every reweighting share, with what does not depend on the weights (the
//! basis at each line, the Gram products `Re(φ_b φ̄_c)`) formed once per fit, and per
//! reweighting a few passes over the lines in split real and imaginary storage (the
//! residuals, the robust weights, one weighted sum per entry of the normal equations that is
//! not zero at every line), solved by a pivoted LU of at most [`MAX_PER`] unknowns.

use faer::c64;

use super::Family;
use crate::lanes::simd;

/// Most basis functions of an element ([`Family::parameters_per_element`] of the largest
/// family).
pub(super) const MAX_PER: usize = {
    let poly = 2 * (Family::MAX_DEGREE + 1);
    let states = 3 + Family::MAX_POLES;
    if poly > states { poly } else { states }
};

/// Coefficients of one element (the first `per` used).
pub(super) type Coefficients = [f64; MAX_PER];

/// The basis of a fit at every line, shared by its elements.
#[derive(Debug)]
pub(super) struct Design {
    per: usize,
    lines: usize,
    /// `[b * lines + k]`: `Re φ_b(ω_k)`, `Im φ_b(ω_k)`.
    re: Vec<f64>,
    im: Vec<f64>,
    /// The basis functions with a real (imaginary) part at some line.
    with_re: Vec<usize>,
    with_im: Vec<usize>,
    /// The entries `(b, c)`, `b ≤ c`, of the normal equations' upper triangle whose products
    /// `Re(φ_b φ̄_c)` are not zero at every line, and those products, `[pair * lines + k]`.
    pairs: Vec<(usize, usize)>,
    gram: Vec<f64>,
}

impl Design {
    /// The design of the basis `phi`, `[k * per + b]` over `lines` lines.
    pub(super) fn new(phi: &[c64], per: usize, lines: usize) -> Design {
        assert!(per <= MAX_PER, "{per} basis functions, at most {MAX_PER}");
        let column = |b: usize, part: fn(&c64) -> f64| -> Vec<f64> {
            phi.chunks_exact(per).map(|row| part(&row[b])).collect()
        };
        let mut re = Vec::with_capacity(per * lines);
        let mut im = Vec::with_capacity(per * lines);
        for b in 0..per {
            re.extend(column(b, |z| z.re));
            im.extend(column(b, |z| z.im));
        }
        let used = |x: &[f64]| -> Vec<usize> {
            (0..per)
                .filter(|&b| x[b * lines..(b + 1) * lines].iter().any(|&v| v != 0.0))
                .collect()
        };
        let (with_re, with_im) = (used(&re), used(&im));
        let (mut pairs, mut gram) = (Vec::new(), Vec::new());
        for b in 0..per {
            for c in b..per {
                let products: Vec<f64> = phi
                    .chunks_exact(per)
                    .map(|row| (row[b] * row[c].conj()).re)
                    .collect();
                if products.iter().any(|&v| v != 0.0) {
                    pairs.push((b, c));
                    gram.extend(products);
                }
            }
        }
        Design {
            per,
            lines,
            re,
            im,
            with_re,
            with_im,
            pairs,
            gram,
        }
    }

    fn re(&self, b: usize) -> &[f64] {
        &self.re[b * self.lines..(b + 1) * self.lines]
    }

    fn im(&self, b: usize) -> &[f64] {
        &self.im[b * self.lines..(b + 1) * self.lines]
    }

    /// Scratch for the elements of this design.
    pub(super) fn element(&self) -> Element {
        let zeros = || vec![0.0; self.lines];
        Element {
            y_re: zeros(),
            y_im: zeros(),
            var: zeros(),
            projections: vec![0.0; self.per * self.lines],
            r_re: zeros(),
            r_im: zeros(),
            weights: zeros(),
        }
    }

    /// Loads the measured impedance `y` and variance `var` of one element (line by line)
    /// into `el`, with its projections `Re(y_k φ̄_b)`, the same at every reweighting.
    pub(super) fn load(
        &self,
        el: &mut Element,
        y: impl Iterator<Item = c64>,
        var: impl Iterator<Item = f64>,
    ) {
        for ((re, im), v) in el.y_re.iter_mut().zip(&mut el.y_im).zip(y) {
            (*re, *im) = (v.re, v.im);
        }
        el.var.iter_mut().zip(var).for_each(|(a, v)| *a = v);
        let lines = self.lines;
        for b in 0..self.per {
            let (pr, pi) = (self.re(b), self.im(b));
            let out = &mut el.projections[b * lines..(b + 1) * lines];
            simd(|| {
                for ((o, (yr, yi)), (br, bi)) in out
                    .iter_mut()
                    .zip(el.y_re.iter().zip(&el.y_im))
                    .zip(pr.iter().zip(pi))
                {
                    *o = yr * br + yi * bi;
                }
            });
        }
    }

    /// The residuals `y_k − Σ_b φ_b(ω_k) θ_b` of `theta` into `el` (the model summed in the
    /// order of the basis, as [`FamilyFit::residuals`](super::FamilyFit) sums it).
    pub(super) fn residuals(&self, el: &mut Element, theta: &[f64]) {
        simd(|| self.residuals_in(el, theta));
    }

    /// [`Design::residuals`], then the robust weights of the element's terms for `ν` degrees
    /// of freedom of the pure error: the derivative of the statistic's term `ν ln(1 + 2t/ν)`
    /// with respect to `t`, over 2, times `1/v`: `1/(v (1 + 2t/ν))`, `t = |r|²/v` (0 for a
    /// term left out).
    pub(super) fn reweigh(&self, el: &mut Element, theta: &[f64], nu: f64) {
        simd(|| {
            self.residuals_in(el, theta);
            let r = el.r_re.iter().zip(&el.r_im);
            for (w, (v, (re, im))) in el.weights.iter_mut().zip(el.var.iter().zip(r)) {
                let t = (re * re + im * im) / v;
                *w = 1.0 / (v * (1.0 + 2.0 * t / nu));
            }
        });
    }

    #[inline(always)]
    fn residuals_in(&self, el: &mut Element, theta: &[f64]) {
        let lines = self.lines;
        for (with, basis, y, r) in [
            (&self.with_re, &self.re, &el.y_re, &mut el.r_re),
            (&self.with_im, &self.im, &el.y_im, &mut el.r_im),
        ] {
            let column = |b: usize| (&basis[b * lines..(b + 1) * lines], theta[b]);
            match with.as_slice() {
                [] => r.copy_from_slice(y),
                [only] => {
                    let (x, t) = column(*only);
                    for ((r, y), x) in r.iter_mut().zip(y).zip(x) {
                        *r = y - x * t;
                    }
                }
                [first, middle @ .., last] => {
                    let (x, t) = column(*first);
                    for (m, x) in r.iter_mut().zip(x) {
                        *m = x * t;
                    }
                    for &b in middle {
                        let (x, t) = column(b);
                        for (m, x) in r.iter_mut().zip(x) {
                            *m += x * t;
                        }
                    }
                    let (x, t) = column(*last);
                    for ((m, y), x) in r.iter_mut().zip(y).zip(x) {
                        *m = y - (*m + x * t);
                    }
                }
            }
        }
    }

    /// The weighted least-squares coefficients of the element in `el` with its weights: the
    /// normal equations `Σ_k w_k Re(φ_b φ̄_c) θ_c = Σ_k w_k Re(y_k φ̄_b)`, columns scaled to
    /// unit diagonal, with the scales `s_b = √(Σ_k w_k |φ_b|²)`; `None` when a scale is zero
    /// or the solution is not finite (singular equations).
    pub(super) fn solve(&self, el: &Element) -> Option<(Coefficients, Coefficients)> {
        let (per, lines) = (self.per, self.lines);
        let mut a = [0.0; MAX_PER * MAX_PER];
        for (p, &(b, c)) in self.pairs.iter().enumerate() {
            let v = dot(&el.weights, &self.gram[p * lines..(p + 1) * lines]);
            a[b * per + c] = v;
            a[c * per + b] = v;
        }
        let mut x = [0.0; MAX_PER];
        for (b, x) in x.iter_mut().enumerate().take(per) {
            *x = dot(&el.weights, &el.projections[b * lines..(b + 1) * lines]);
        }
        let mut scale = [0.0; MAX_PER];
        for b in 0..per {
            scale[b] = a[b * per + b].max(0.0).sqrt();
            if !(scale[b] > 0.0 && scale[b].is_finite()) {
                return None;
            }
        }
        for b in 0..per {
            for c in 0..per {
                a[b * per + c] /= scale[b] * scale[c];
            }
            x[b] /= scale[b];
        }
        lu_solve(&mut a[..per * per], &mut x[..per]);
        for b in 0..per {
            x[b] /= scale[b];
        }
        x[..per].iter().all(|v| v.is_finite()).then_some((x, scale))
    }
}

/// One element's lines and the scratch of its reweightings.
#[derive(Debug)]
pub(super) struct Element {
    y_re: Vec<f64>,
    y_im: Vec<f64>,
    /// The floored variance; `f64::INFINITY` for a term left out.
    var: Vec<f64>,
    /// `[b * lines + k]`: `Re(y_k φ̄_b)`.
    projections: Vec<f64>,
    pub(super) r_re: Vec<f64>,
    pub(super) r_im: Vec<f64>,
    weights: Vec<f64>,
}

impl Element {
    /// The variance of line `k` ([`Design::load`]).
    pub(super) fn var(&self) -> &[f64] {
        &self.var
    }

    /// Weights `1/v` (0 for a term left out).
    pub(super) fn weigh_by_variance(&mut self) {
        let (w, var) = (&mut self.weights, &self.var);
        simd(|| w.iter_mut().zip(var).for_each(|(w, v)| *w = 1.0 / v));
    }
}

/// `Σ a_k b_k` in four lanes.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    simd(|| {
        let mut acc = [0.0; 4];
        let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
        let (ra, rb) = (ca.remainder(), cb.remainder());
        for (x, y) in ca.zip(cb) {
            for l in 0..4 {
                acc[l] += x[l] * y[l];
            }
        }
        for (l, (x, y)) in ra.iter().zip(rb).enumerate() {
            acc[l] += x * y;
        }
        (acc[0] + acc[1]) + (acc[2] + acc[3])
    })
}

/// `x ← A⁻¹ x` for the `n × n` row-major `a` (overwritten), by LU with partial pivoting; a
/// singular `a` leaves non-finite values in `x`.
fn lu_solve(a: &mut [f64], x: &mut [f64]) {
    let n = x.len();
    for col in 0..n {
        let pivot = (col..n).fold(col, |p, i| {
            if a[i * n + col].abs() > a[p * n + col].abs() {
                i
            } else {
                p
            }
        });
        if pivot != col {
            for j in 0..n {
                a.swap(pivot * n + j, col * n + j);
            }
            x.swap(pivot, col);
        }
        let d = a[col * n + col];
        for i in col + 1..n {
            let f = a[i * n + col] / d;
            for j in col + 1..n {
                a[i * n + j] -= f * a[col * n + j];
            }
            x[i] -= f * x[col];
        }
    }
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|j| a[i * n + j] * x[j]).sum();
        x[i] = (x[i] - s) / a[i * n + i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pivoted LU solves a system whose first pivot is zero.
    #[test]
    fn lu_pivots_past_a_zero() {
        let mut a = [0.0, 2.0, 1.0, 3.0, 1.0, 0.0, 1.0, 1.0, 1.0];
        let truth = [1.0, -2.0, 3.0];
        let mut x: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| a[i * 3 + j] * truth[j]).sum())
            .collect();
        lu_solve(&mut a, &mut x);
        for (got, want) in x.iter().zip(truth) {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
        let mut singular = [1.0, 2.0, 2.0, 4.0];
        let mut y = [1.0, 1.0];
        lu_solve(&mut singular, &mut y);
        assert!(!y.iter().all(|v| v.is_finite()));
    }

    /// The design keeps only the Gram products that are not zero everywhere: for `kcm`,
    /// `(K,K)`, `(K,M)`, `(C,C)`, `(M,M)`.
    #[test]
    fn kcm_design_has_four_products() {
        let omegas = [10.0, 20.0, 30.0];
        let mut phi = vec![c64::new(0.0, 0.0); 9];
        for (k, &w) in omegas.iter().enumerate() {
            Family::Kcm.basis(w, &[], 30.0, &mut phi[k * 3..(k + 1) * 3]);
        }
        let d = Design::new(&phi, 3, 3);
        assert_eq!(d.pairs, vec![(0, 0), (0, 2), (1, 1), (2, 2)]);
        assert_eq!(
            (d.with_re.clone(), d.with_im.clone()),
            (vec![0, 2], vec![1])
        );
        assert!((d.gram[3 * 3 + 2] - 8.1e5).abs() < 1e-9);
    }
}
