//! Stage 5: fitting `M`, `C`, `K` to the measured impedances and flexibilities.
//!
//! Four methods, from simplest to best:
//!
//! - [`Method::Direct`] (seed eq. 10): per element, `Re H_ij = K_ij − ω² M_ij` and
//!   `Im H_ij = ω C_ij` by least squares, with `r²`. Simple; biased under noise.
//! - [`Method::LeastSquares`] (seed eq. 19): the flexibility identity `G H = I + E`, split into
//!   real and imaginary rows and stacked over the lines into `A Θ = Ī + Ē` with
//!   `Θ = [M; C; K]`. Per line, with `G = Gᴿ + iGᴵ`,
//!   $$ \begin{bmatrix} -\omega^2 G^R & -\omega G^I & G^R \\ -\omega^2 G^I & \omega G^R & G^I \end{bmatrix} \Theta = \begin{bmatrix} I \\ 0 \end{bmatrix}. $$
//!   The columns of `A` are scaled to unit norm (the M, C, K blocks differ by `ω²` and `ω`) and
//!   the scaled problem is solved by QR, all `n` right-hand sides with one factorisation. Biased
//!   toward zero under noise (errors in variables): `M` and `K` shrink together.
//! - [`Method::Ivf`] (seed eqs. 20–21, Fritzen 1985): the instrumental-variable filter. The
//!   instruments `W` have `A`'s form but are built from the model flexibility
//!   `G(ω; Θ_m) = H(ω; Θ_m)⁻¹`, which carries no measurement noise; then
//!   `Θ_{m+1} = (Wᵀ A)⁻¹ Wᵀ Ī`, with the same column scaling, iterated from the
//!   least-squares start. Unbiased.
//! - [`Method::Ml`] (Pintelon & Schoukens; [`ml`]): maximum likelihood with errors in
//!   variables, from periodic records whose repeated periods give the noise covariances,
//!   started from IVF; its Cramér–Rao bound gives the error bars.

mod convergence;
mod direct;
mod fitter;
mod ivf;
mod ls;
pub mod ml;
mod quad;
mod split;
mod system;

use faer::Mat;

use crate::error::Result;
use crate::frf::Frf;
use crate::model::Coefficients;

pub use convergence::{Convergence, NonConvergence};
pub use direct::DirectFit;
pub use fitter::{Fitted, Fitter};
pub use ivf::{Iteration, IvfOptions, IvfSolver};

/// The fitting method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[non_exhaustive]
pub enum Method {
    /// Per-element fit of the impedance (seed eq. 10).
    Direct,
    /// Least squares on the stacked flexibility identity (seed eq. 19).
    LeastSquares,
    /// Instrumental-variable filter (seed eqs. 20–21), started from least squares.
    #[default]
    Ivf,
    /// Maximum likelihood (errors in variables), started from IVF ([`ml`]): needs the noise
    /// covariances that repeated periods give ([`crate::Segmentation::Periods`]).
    Ml,
}

impl crate::Choice for Method {
    const OPTION: &'static str = "method";
    const ALL: &'static [Method] = &[
        Method::Direct,
        Method::LeastSquares,
        Method::Ivf,
        Method::Ml,
    ];

    /// `"direct"`, `"ls"`, `"ivf"` or `"ml"` (the command line's `--method` values).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Choice, Method};
    /// assert_eq!("ls".parse::<Method>()?, Method::LeastSquares);
    /// assert_eq!(Method::Ml.name(), "ml");
    /// assert!("newton".parse::<Method>().is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    fn name(self) -> &'static str {
        match self {
            Method::Direct => "direct",
            Method::LeastSquares => "ls",
            Method::Ivf => "ivf",
            Method::Ml => "ml",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Method::Direct => "per-element fit of the impedance",
            Method::LeastSquares => "least squares on the flexibility identity",
            Method::Ivf => "instrumental-variable filter, started from least squares",
            Method::Ml => "maximum likelihood (errors in variables), started from IVF",
        }
    }
}

crate::choice::choice_text!(Method);

/// The one check of an iterative fit's tolerance ([`IvfOptions::check`],
/// [`MlOptions::check`](ml::MlOptions::check)): relative, in `(0, 1)`; `name` is the
/// parameter as the error names it.
pub(crate) fn check_tolerance(tolerance: f64, name: crate::Parameter) -> Result<()> {
    if tolerance > 0.0 && tolerance < 1.0 {
        Ok(())
    } else {
        Err(crate::Error::InvalidParameter {
            name,
            value: tolerance,
            expected: "0 < tolerance < 1",
        })
    }
}

/// The outcome of a fit: coefficients plus what the fit knows about their quality.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    method: Method,
    coefficients: Coefficients,
    residual_norm: f64,
    convergence: Convergence,
    history: Vec<Iteration>,
    std_dev: Option<Coefficients>,
    covariance: Option<Vec<Mat<f64>>>,
    direct: Option<DirectFit>,
}

/// Relative change `‖new − old‖ / ‖new‖` (Frobenius) of one block of `Θ` given as its
/// `(new, old)` pairs, summed in the order given; the absolute change `‖new − old‖` when the
/// new block is zero. The one convergence measure of the iterative fits (IVF, ML).
fn block_change(pairs: impl IntoIterator<Item = (f64, f64)>) -> f64 {
    let (mut diff, mut norm) = (0.0, 0.0);
    for (new, old) in pairs {
        diff += (new - old).powi(2);
        norm += new.powi(2);
    }
    if norm > 0.0 {
        (diff / norm).sqrt()
    } else {
        diff.sqrt()
    }
}

/// Standard deviations (square roots of the diagonals) of per-column covariances of `Θ`.
fn std_from(covariance: &[Mat<f64>]) -> Result<Coefficients> {
    let p = covariance.first().map_or(0, |c| c.nrows());
    let theta = Mat::from_fn(p, covariance.len(), |q, j| {
        covariance[j][(q, q)].max(0.0).sqrt()
    });
    Coefficients::from_stacked(theta.as_ref())
}

impl Fit {
    /// The fit of exponentially windowed data (decay `a`, 1/s) mapped back to the system
    /// itself. Windowed data belong to `Z(s + a)`, so
    /// $M = M_w,\; C = C_w - 2aM_w,\; K = K_w - aC_w + a^2M_w$, every element, cross terms
    /// included; covariances follow the same linear map, `Cov = T Cov_w Tᵀ`. The residual,
    /// history and `r²` stay those of the windowed fit.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::frf::Frf;
    /// use bearing_ident::model::Coefficients;
    /// use bearing_ident::solve::{fit, IvfOptions, Method};
    /// use faer::{Mat, c64, mat};
    /// // The seed's figures: a = 3.8376 1/s on 4.7 kg gives C_w − C = 2aM = 36.07 N·s/m.
    /// let a = 3.8376;
    /// let windowed = Coefficients::new(mat![[4.7]], mat![[20.0 + 2.0 * a * 4.7]],
    ///     mat![[146.3e3 + a * 20.0 + a * a * 4.7]])?;
    /// let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
    /// let g: Vec<Mat<c64>> = freqs.iter().map(|&f| windowed.flexibility_at(f)).collect::<Result<_, _>>()?;
    /// let w = fit(&Frf::from_flexibility(freqs, &g)?, Method::LeastSquares, &IvfOptions::default())?;
    /// let c = w.corrected_for_window(a)?;
    /// assert!((c.coefficients().damping()[(0, 0)] - 20.0).abs() < 1e-6);
    /// assert!((c.coefficients().stiffness()[(0, 0)] - 146.3e3).abs() < 1e-4);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::NonFiniteCoefficient`](crate::Error::NonFiniteCoefficient) if `a` is not finite.
    pub fn corrected_for_window(&self, a: f64) -> Result<Fit> {
        let n = self.coefficients.dofs();
        let p = 3 * n;
        // Θ = T Θ_w with T = [[I, 0, 0], [−2aI, I, 0], [a²I, −aI, I]].
        let t = Mat::from_fn(p, p, |r, c| {
            if r % n != c % n {
                return 0.0;
            }
            match (r / n, c / n) {
                (x, y) if x == y => 1.0,
                (1, 0) => -2.0 * a,
                (2, 0) => a * a,
                (2, 1) => -a,
                _ => 0.0,
            }
        });
        let theta = &t * self.coefficients.stacked();
        let covariance = self.covariance.as_ref().map(|cs| {
            cs.iter()
                .map(|c| &t * c * t.transpose())
                .collect::<Vec<_>>()
        });
        Ok(Fit {
            coefficients: Coefficients::from_stacked(theta.as_ref())?,
            std_dev: covariance.as_deref().map(std_from).transpose()?,
            covariance,
            ..self.clone()
        })
    }

    /// The fit with other coefficients and standard deviations (an element model's constant
    /// part); no covariance.
    pub(crate) fn replaced(
        &self,
        coefficients: Coefficients,
        std_dev: Option<Coefficients>,
    ) -> Fit {
        Fit {
            coefficients,
            std_dev,
            covariance: None,
            ..self.clone()
        }
    }

    /// Covariance of column `j` of `Θ = [M; C; K]` (`3n × 3n`, rows and columns ordered
    /// `M_0j … M_(n-1)j, C_0j …, K_0j …`), for every `j`; least squares and IVF only. Columns
    /// are independent in this first-order (sandwich) model. `None` for an identification
    /// under [`Uncertainty::None`](crate::Uncertainty::None), which forms no error bars.
    pub fn covariance(&self) -> Option<&[Mat<f64>]> {
        self.covariance.as_deref()
    }

    /// The method used.
    pub fn method(&self) -> Method {
        self.method
    }

    /// The fitted `M`, `C`, `K`.
    pub fn coefficients(&self) -> &Coefficients {
        &self.coefficients
    }

    /// Frobenius norm of the residual of the stacked flexibility identity, `‖A Θ − Ī‖_F`
    /// (dimensionless), for every method alike.
    pub fn residual_norm(&self) -> f64 {
        self.residual_norm
    }

    /// How the iteration ended.
    pub fn convergence(&self) -> Convergence {
        self.convergence
    }

    /// IVF iteration history (empty for direct and least squares).
    pub fn history(&self) -> &[Iteration] {
        &self.history
    }

    /// First-order (sandwich) standard deviations of every coefficient, laid out as
    /// [`Coefficients`] (for least squares and IVF):
    /// $\mathrm{Cov}(\Theta_j) = (W^\top A)^{-1} W^\top \mathrm{diag}(r_j^2) W (A^\top W)^{-1}
    /// \cdot \frac{m}{m-p}$ with the residuals `r_j = A Θ_j − Ī_j`, `W = A` for least squares.
    /// `None` for an identification under [`Uncertainty::None`](crate::Uncertainty::None),
    /// which forms no error bars (the sandwich costs about as much as three IVF iterations).
    pub fn std_dev(&self) -> Option<&Coefficients> {
        self.std_dev.as_ref()
    }

    /// The maximum-likelihood refinement of an IVF `start`: its coefficients and covariances,
    /// IVF's history and residual, and `convergence` of the likelihood loop.
    pub(crate) fn refined_by_ml(
        start: &Fit,
        coefficients: Coefficients,
        covariance: Vec<Mat<f64>>,
        convergence: Convergence,
    ) -> Result<Fit> {
        Ok(Fit {
            method: Method::Ml,
            coefficients,
            residual_norm: start.residual_norm,
            convergence,
            history: start.history.clone(),
            std_dev: Some(std_from(&covariance)?),
            covariance: Some(covariance),
            direct: None,
        })
    }

    /// The per-element `r²` of a direct fit.
    pub fn direct(&self) -> Option<&DirectFit> {
        self.direct.as_ref()
    }
}

/// Fits `frf` by `method`.
///
/// # Errors
/// [`Error::TooFewLines`](crate::Error::TooFewLines) when the band holds fewer than
/// [`required_lines`] lines; [`Error::SingularFit`](crate::Error::SingularFit) when the stacked
/// system is singular; [`Error::CoefficientShape`](crate::Error::CoefficientShape) never.
pub fn fit(frf: &Frf, method: Method, options: &IvfOptions) -> Result<Fit> {
    match method {
        Method::Direct => direct::fit(frf),
        Method::LeastSquares => ls::fit(frf),
        Method::Ivf => ivf::fit(frf, options),
        Method::Ml => Err(crate::Error::MlNeedsRepeats),
    }
}

/// [`fit`] without the first-order covariance (no [`Fit::std_dev`], no
/// [`Fit::covariance`]): the refits of the jackknife and the bootstrap need only the
/// coefficients, and the sandwich costs about as much as three IVF iterations.
///
/// # Errors
/// As [`fit`].
pub(crate) fn fit_point(frf: &Frf, method: Method, options: &IvfOptions) -> Result<Fit> {
    match method {
        Method::LeastSquares => ls::fit_point(frf),
        Method::Ivf => IvfSolver::new(frf, *options)?.run(false),
        _ => fit(frf, method, options),
    }
}

/// [`Error::ImpedanceScale`](crate::Error::ImpedanceScale) when the impedance of `frf` is so
/// far from 1 N/m that the squares a fit forms leave f64: with `h` the median over the lines of
/// the largest `|H_ij|`, one of `h²`, `1/h²` (the flexibility's), `(ω_hi²/h)²` (its products
/// with the mass column) or `(h/ω_lo²)²` is not a normal number. Nominal bearings (`h` of 1e3
/// to 1e10 N/m) are about 140 decades inside; asked only once a fit has failed, to name the
/// cause.
pub(crate) fn impedance_out_of_range(frf: &Frf) -> Option<crate::Error> {
    let mut largest: Vec<f64> = (0..frf.line_count())
        .map(|k| {
            let h = frf.impedance(k);
            h.col_iter()
                .flat_map(|c| c.iter().map(|z| z.norm()).collect::<Vec<_>>())
                .fold(0.0, f64::max)
        })
        .collect();
    if largest.is_empty() {
        return None;
    }
    largest.sort_by(f64::total_cmp);
    let h = largest[largest.len() / 2];
    if h == 0.0 {
        return None;
    }
    let omega = |f: f64| (2.0 * std::f64::consts::PI * f).max(1.0);
    let freqs = frf.freqs_hz().iter();
    let lo = freqs.clone().fold(f64::INFINITY, |m, &f| m.min(omega(f)));
    let hi = freqs.fold(0.0_f64, |m, &f| m.max(omega(f)));
    let normal = |x: f64| (x * x).is_normal();
    let fits = normal(h) && normal(1.0 / h) && normal(hi * hi / h) && normal(h / (lo * lo));
    (!fits).then_some(crate::Error::ImpedanceScale { magnitude: h })
}

/// Lines a band must hold to fit `n` degrees of freedom: `⌈3n/2⌉ + 3`, a few more than the
/// `3n` unknowns per column need (`2N` equations per column).
pub fn required_lines(n: usize) -> usize {
    (3 * n).div_ceil(2) + 3
}

fn finish(
    method: Method,
    theta: Mat<f64>,
    sys: &system::Stacked,
    convergence: Convergence,
    history: Vec<Iteration>,
    covariance: Option<Vec<Mat<f64>>>,
) -> Result<Fit> {
    let residual_norm = sys.residual_norm(theta.as_ref());
    Ok(Fit {
        method,
        coefficients: Coefficients::from_stacked(theta.as_ref())?,
        residual_norm,
        convergence,
        history,
        std_dev: covariance.as_deref().map(std_from).transpose()?,
        covariance,
        direct: None,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::Choice;
    use crate::error::Error;
    use faer::{c64, mat};

    fn exact_frf(c: &Coefficients, freqs: &[f64]) -> Frf {
        let g: Vec<Mat<c64>> = freqs
            .iter()
            .map(|&f| c.flexibility_at(f).unwrap())
            .collect();
        Frf::from_flexibility(freqs.to_vec(), &g).unwrap()
    }

    fn truth() -> Coefficients {
        Coefficients::new(
            mat![[4.7, 0.2], [0.1, 4.8]],
            mat![[132.0, 6.0], [-4.0, 120.0]],
            mat![[146.3e3, 22.3e3], [11.5e3, 169.1e3]],
        )
        .unwrap()
    }

    fn rel_err(a: &Coefficients, b: &Coefficients) -> f64 {
        (a.stacked() - b.stacked()).norm_l2() / b.stacked().norm_l2()
    }

    #[test]
    fn every_method_is_exact_on_exact_flexibilities() {
        let freqs: Vec<f64> = (10..=50).map(f64::from).collect();
        let frf = exact_frf(&truth(), &freqs);
        for method in [Method::Direct, Method::LeastSquares, Method::Ivf] {
            let fit = fit(&frf, method, &IvfOptions::default()).unwrap();
            assert!(rel_err(fit.coefficients(), &truth()) < 1e-10, "{method}");
            assert!(fit.residual_norm() < 1e-8, "{method}");
            assert!(fit.convergence().is_converged());
        }
    }

    #[test]
    fn direct_fit_reports_r2() {
        let freqs: Vec<f64> = (10..=50).map(f64::from).collect();
        let fit = fit(
            &exact_frf(&truth(), &freqs),
            Method::Direct,
            &IvfOptions::default(),
        )
        .unwrap();
        let d = fit.direct().unwrap();
        assert!((d.r2_real[(0, 0)] - 1.0).abs() < 1e-12);
        assert!((d.r2_imag[(1, 1)] - 1.0).abs() < 1e-12);
        assert!(fit.std_dev().is_none());
    }

    #[test]
    fn ivf_keeps_its_history() {
        let freqs: Vec<f64> = (10..=50).map(f64::from).collect();
        let fit = fit(
            &exact_frf(&truth(), &freqs),
            Method::Ivf,
            &IvfOptions::default(),
        )
        .unwrap();
        assert_eq!(fit.history().len(), fit.convergence().iterations());
        assert!(fit.history()[0].change() < 1e-8);
        assert!(fit.std_dev().is_some());
    }

    #[test]
    fn too_few_lines() {
        let frf = exact_frf(&truth(), &[10.0, 20.0, 30.0]);
        assert_eq!(required_lines(2), 6);
        let e = fit(&frf, Method::Ivf, &IvfOptions::default()).unwrap_err();
        assert!(matches!(
            e,
            Error::TooFewLines {
                lines: 3,
                required: 6,
                ..
            }
        ));
        let e = fit(&frf, Method::Direct, &IvfOptions::default()).unwrap_err();
        assert!(matches!(e, Error::TooFewLines { .. }));
    }

    #[test]
    fn singular_stacked_system() {
        // Ten copies of one line: the M and K columns differ only by the factor −ω².
        let g: Vec<Mat<c64>> = (0..10).map(|_| mat![[c64::new(1e-5, 2e-6)]]).collect();
        let frf = Frf::from_flexibility(vec![5.0; 10], &g).unwrap();
        let e = fit(&frf, Method::LeastSquares, &IvfOptions::default()).unwrap_err();
        assert_eq!(
            e,
            Error::SingularFit {
                method: Method::LeastSquares
            }
        );
    }

    #[test]
    fn ivf_options_are_validated() {
        let bad = IvfOptions {
            tolerance: 0.0,
            ..IvfOptions::default()
        };
        assert!(matches!(bad.check(), Err(Error::InvalidParameter { .. })));
        let bad = IvfOptions {
            max_iterations: 0,
            ..IvfOptions::default()
        };
        assert!(matches!(bad.check(), Err(Error::InvalidParameter { .. })));
    }

    #[test]
    fn divergence_falls_back_to_the_best_iterate() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        // A lightly damped SDOF (ζ ≈ 0.04 %) whose flexibility carries 200 % complex noise:
        // for this seed the IVF change rises three times in a row.
        let mut rng = rand::rngs::StdRng::seed_from_u64(34);
        let normal = Normal::new(0.0, 2.0).unwrap();
        let freqs: Vec<f64> = (5..=40).map(|k| f64::from(k) * 0.5).collect();
        let g: Vec<Mat<c64>> = freqs
            .iter()
            .map(|&f| {
                let w = 2.0 * std::f64::consts::PI * f;
                let e = c64::new(normal.sample(&mut rng), normal.sample(&mut rng));
                mat![[c64::new(1.0e4 - w * w, 0.05 * w).inv() * (1.0 + e)]]
            })
            .collect();
        let frf = Frf::from_flexibility(freqs, &g).unwrap();
        let fit = fit(&frf, Method::Ivf, &IvfOptions::default()).unwrap();
        let Convergence::Diverged {
            iterations,
            fallback_iteration,
        } = fit.convergence()
        else {
            panic!("expected divergence, got {:?}", fit.convergence());
        };
        let h = fit.history();
        assert_eq!(h.len(), iterations);
        assert!(
            h[h.len() - 3..]
                .windows(2)
                .all(|w| w[1].change() > w[0].change())
        );
        // The fallback is the iterate with the smallest change, and it is finite.
        let best = (0..h.len())
            .min_by(|&a, &b| h[a].change().total_cmp(&h[b].change()))
            .unwrap();
        assert_eq!(fallback_iteration, best + 1);
        assert!(fit.coefficients().stacked().norm_l2().is_finite());
        assert!(!fit.convergence().is_converged());
    }

    /// The seed-like `truth`'s exact flexibilities × 1e-200 over 8–49 Hz: an impedance of
    /// about 1e205 N/m, whose least-squares start is fine but whose IVF normal equations
    /// underflow.
    pub(crate) fn out_of_range_frf() -> Frf {
        let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
        let g: Vec<Mat<c64>> = freqs
            .iter()
            .map(|&f| {
                let g = truth().flexibility_at(f).unwrap();
                Mat::from_fn(2, 2, |i, j| g[(i, j)] * 1e-200)
            })
            .collect();
        Frf::from_flexibility(freqs, &g).unwrap()
    }

    /// NaN inside the IVF ends it as `NonFinite` (not `Diverged` "after 0 iterations"), with
    /// the least-squares start returned; the impedance's level is named as out of range, a
    /// nominal one is not.
    #[test]
    fn an_iteration_that_meets_nan_says_so() {
        let frf = out_of_range_frf();
        let fit = fit(&frf, Method::Ivf, &IvfOptions::default()).unwrap();
        assert!(
            matches!(
                fit.convergence(),
                Convergence::NonFinite {
                    iterations: 0,
                    fallback_iteration: 0,
                    ..
                }
            ),
            "{:?}",
            fit.convergence()
        );
        assert_eq!(fit.convergence().name(), "non_finite");
        assert!(fit.coefficients().stacked().norm_l2().is_finite());
        match impedance_out_of_range(&frf) {
            Some(Error::ImpedanceScale { magnitude }) => {
                assert!((magnitude.log10() - 205.0).abs() < 1.0, "{magnitude:e}")
            }
            e => panic!("{e:?}"),
        }
        let freqs: Vec<f64> = (8..=49).map(f64::from).collect();
        assert!(impedance_out_of_range(&exact_frf(&truth(), &freqs)).is_none());
    }

    #[test]
    fn convergence_helpers() {
        assert!(Convergence::NotIterative.is_converged());
        assert_eq!(Convergence::NotIterative.iterations(), 0);
        let d = Convergence::Diverged {
            iterations: 5,
            fallback_iteration: 2,
        };
        assert!(!d.is_converged());
        assert_eq!(d.iterations(), 5);
        assert_eq!(Method::LeastSquares.to_string(), "ls");
    }

    #[test]
    fn method_names_round_trip() {
        for m in [
            Method::Direct,
            Method::LeastSquares,
            Method::Ivf,
            Method::Ml,
        ] {
            assert_eq!(m.name().parse::<Method>(), Ok(m));
        }
        assert_eq!("LS".parse::<Method>(), Ok(Method::LeastSquares));
        assert!(matches!(
            "lsq".parse::<Method>(),
            Err(crate::Error::UnknownName { what: "method", .. })
        ));
    }

    #[test]
    fn block_change_is_relative_and_absolute_at_zero() {
        assert!((block_change([(3.0, 0.0), (4.0, 0.0)]) - 1.0).abs() < 1e-15);
        assert!((block_change([(2.0, 1.0)]) - 0.5).abs() < 1e-15);
        assert!((block_change([(0.0, 3.0), (0.0, 4.0)]) - 5.0).abs() < 1e-15);
    }
}
