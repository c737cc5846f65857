//! The IVF's three-degree-of-freedom per-line kernels four lines at once, one line per SIMD
//! lane.
//!
//! A `3 × 3` matrix fills no whole register of the column-wise kernels of [`split`] (four
//! `f64` lanes on AVX2): their cofactor inverse and their products ran in scalar, one line
//! after the other. Here a group of four lines is held entry-major, `[entry][lane]`
//! ([`Lanes`]), so every operation of the impedance, of [`linalg::invert3`]'s cofactor inverse
//! and of the product is one operation on four lines, which the compiler packs into one SIMD
//! instruction inside the pass's [`Arch::dispatch`](super::split::Arch).
//!
//! Each lane does the operations of one line in their order, with a fused multiply-add
//! exactly where the per-line kernel of the same SIMD width has one (the impedance's entries
//! that fill whole registers, [`fused`]), so each line's model flexibility `G_m` and product
//! are the per-line path's bit for bit. The sums over the lines (the eight weighted sums of
//! the normal equations, the squared residual norm) are kept per lane and the lanes combined
//! at the end ([`combine`]): that rounds differently from the line-by-line sum, within the
//! usual `N·ε·Σ|x|`. Measured on the three-degree-of-freedom impact probe (18 records,
//! 461 lines, 4 IVF iterations): `M`, `C`, `K` move by at most 1.3e-12 relative entry by
//! entry (1.4e-14 of each block's largest entry), with the same iterations and warnings;
//! the sums in line order cost 0.6 M more instructions a fit. A group where a lane leaves
//! the cofactor path's normal range (an impedance or determinant scale out of range, where
//! the per-line path takes Gauss–Jordan or the slow reciprocal) is left to the per-line path
//! whole ([`Group::instruments`] returns `None`).

#[cfg(doc)]
use super::split;
use super::split::Simd;
#[cfg(doc)]
use crate::linalg;

/// Lines per group: the lanes.
pub(super) const QUAD: usize = 4;

/// One value of each line of a group.
pub(super) type Lanes = [f64; QUAD];

/// A split `3 × 3` matrix of each line of a group, column-major entries, each four lanes.
#[derive(Clone, Copy)]
struct Mat3 {
    re: [Lanes; 9],
    im: [Lanes; 9],
}

impl Mat3 {
    /// Zero in every entry of every lane.
    const ZERO: Self = Self {
        re: [[0.0; QUAD]; 9],
        im: [[0.0; QUAD]; 9],
    };
}

/// The measured data of the full groups of four lines, entry-major: built once per fit.
#[derive(Debug)]
pub(super) struct Quads {
    /// `ω` of each group's lines.
    omegas: Vec<Lanes>,
    /// `Gᵀ` of each group's lines (real parts), `[group][entry][lane]`.
    gt_re: Vec<[Lanes; 9]>,
    /// Their imaginary parts.
    gt_im: Vec<[Lanes; 9]>,
}

impl Quads {
    /// The full groups of `omegas` (rad/s) and the transposed measured flexibilities
    /// `gt_re`, `gt_im` (`[line][9]`, column-major); the last `lines mod 4` lines are left
    /// to the per-line path.
    pub(super) fn new(omegas: &[f64], gt_re: &[f64], gt_im: &[f64]) -> Self {
        let groups = omegas.len() / QUAD;
        let lanes = |src: &[f64], g: usize| -> [Lanes; 9] {
            std::array::from_fn(|e| std::array::from_fn(|l| src[(g * QUAD + l) * 9 + e]))
        };
        Self {
            omegas: (0..groups)
                .map(|g| std::array::from_fn(|l| omegas[g * QUAD + l]))
                .collect(),
            gt_re: (0..groups).map(|g| lanes(gt_re, g)).collect(),
            gt_im: (0..groups).map(|g| lanes(gt_im, g)).collect(),
        }
    }

    /// How many full groups.
    pub(super) fn groups(&self) -> usize {
        self.omegas.len()
    }
}

/// Whether the per-line kernels of [`split`] form entry `e` of a `3 × 3` element-wise pass
/// with a fused multiply-add: the entries that fill whole registers of `S` (`0..8` for four
/// lanes, all nine for one), the rest in scalar with a separate multiply and add.
#[inline(always)]
fn fused<S: Simd>(e: usize) -> bool {
    e < 9 / S::F64_LANES * S::F64_LANES
}

/// `H = K − ω² M + iω C` of each lane, as [`split::impedance`] forms it for one line.
#[inline(always)]
fn impedance<S: Simd>(h: &mut Mat3, (m, c, k): (&[f64], &[f64], &[f64]), w: &Lanes) {
    let neg_w2: Lanes = std::array::from_fn(|l| -w[l] * w[l]);
    let w2: Lanes = std::array::from_fn(|l| w[l] * w[l]);
    for e in 0..9 {
        let (re, im) = (&mut h.re[e], &mut h.im[e]);
        if fused::<S>(e) {
            for l in 0..QUAD {
                re[l] = m[e].mul_add(neg_w2[l], k[e]);
            }
        } else {
            for l in 0..QUAD {
                re[l] = k[e] - w2[l] * m[e];
            }
        }
        for l in 0..QUAD {
            im[l] = c[e] * w[l];
        }
    }
}

/// The complex product `a b` of each lane, as `num_complex` forms it.
#[inline(always)]
fn cmul((ar, ai): (&Lanes, &Lanes), (br, bi): (&Lanes, &Lanes)) -> (Lanes, Lanes) {
    (
        std::array::from_fn(|l| ar[l] * br[l] - ai[l] * bi[l]),
        std::array::from_fn(|l| ar[l] * bi[l] + ai[l] * br[l]),
    )
}

/// `a b − c d` of each lane (complex), as [`linalg::invert3`]'s adjugate forms it.
#[inline(always)]
fn cross(
    a: (&Lanes, &Lanes),
    b: (&Lanes, &Lanes),
    c: (&Lanes, &Lanes),
    d: (&Lanes, &Lanes),
) -> (Lanes, Lanes) {
    let (x, y) = (cmul(a, b), cmul(c, d));
    (
        std::array::from_fn(|l| x.0[l] - y.0[l]),
        std::array::from_fn(|l| x.1[l] - y.1[l]),
    )
}

/// Each lane's `3 × 3` inverted in place by [`linalg::invert3`]'s operations: `None` (and
/// `a` unspecified) if a lane's scale or determinant leaves the range where the per-line
/// path takes those operations (it takes Gauss–Jordan or the slow reciprocal there),
/// `Some(false)` if a lane is singular or its inverse is not finite.
// A lane index runs over several arrays at once: clearer as an index than as zips.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn invert3(a: &mut Mat3) -> Option<bool> {
    let mut largest = [0.0_f64; QUAD];
    for e in 0..9 {
        for l in 0..QUAD {
            largest[l] = largest[l].max(a.re[e][l].abs()).max(a.im[e][l].abs());
        }
    }
    let mut down = [0.0; QUAD];
    let mut normal = true;
    for l in 0..QUAD {
        // The power of two at or below `largest`: its exponent bits alone.
        let scale = f64::from_bits(largest[l].to_bits() & 0x7ff0_0000_0000_0000);
        down[l] = 1.0 / scale;
        normal &= scale.is_normal() && down[l].is_normal();
    }
    if !normal {
        return None;
    }
    let mut s = Mat3::ZERO;
    for e in 0..9 {
        for l in 0..QUAD {
            s.re[e][l] = a.re[e][l] * down[l];
            s.im[e][l] = a.im[e][l] * down[l];
        }
    }
    let at = |i: usize, j: usize| (&s.re[i + 3 * j], &s.im[i + 3 * j]);
    let (a00, a10, a20) = (at(0, 0), at(1, 0), at(2, 0));
    let (a01, a11, a21) = (at(0, 1), at(1, 1), at(2, 1));
    let (a02, a12, a22) = (at(0, 2), at(1, 2), at(2, 2));
    // The adjugate, column-major.
    let adj = [
        cross(a11, a22, a12, a21),
        cross(a12, a20, a10, a22),
        cross(a10, a21, a11, a20),
        cross(a02, a21, a01, a22),
        cross(a00, a22, a02, a20),
        cross(a01, a20, a00, a21),
        cross(a01, a12, a02, a11),
        cross(a02, a10, a00, a12),
        cross(a00, a11, a01, a10),
    ];
    let (t0, t1, t2) = (
        cmul(a00, (&adj[0].0, &adj[0].1)),
        cmul(a01, (&adj[1].0, &adj[1].1)),
        cmul(a02, (&adj[2].0, &adj[2].1)),
    );
    let det_re: Lanes = std::array::from_fn(|l| t0.0[l] + t1.0[l] + t2.0[l]);
    let det_im: Lanes = std::array::from_fn(|l| t0.1[l] + t1.1[l] + t2.1[l]);
    let mut factor = ([0.0; QUAD], [0.0; QUAD]);
    let (mut regular, mut fast) = (true, true);
    for l in 0..QUAD {
        regular &= !(det_re[l] == 0.0 && det_im[l] == 0.0);
        // `linalg::reciprocal` through the squared modulus, where it is a normal number.
        let r2 = det_re[l] * det_re[l] + det_im[l] * det_im[l];
        fast &= r2.is_finite() && r2 >= f64::MIN_POSITIVE;
        // (A/s)⁻¹ = s A⁻¹: the inverse is (A/s)⁻¹ / s.
        factor.0[l] = det_re[l] / r2 * down[l];
        factor.1[l] = -det_im[l] / r2 * down[l];
    }
    if !regular {
        return Some(false);
    }
    if !fast {
        return None;
    }
    let mut finite = true;
    for (e, adj) in adj.iter().enumerate() {
        let (re, im) = cmul((&adj.0, &adj.1), (&factor.0, &factor.1));
        for l in 0..QUAD {
            finite &= re[l].is_finite() && im[l].is_finite();
        }
        (a.re[e], a.im[e]) = (re, im);
    }
    Some(finite)
}

/// `out = X Y` (`conj = false`) or `X Ȳ` (`conj = true`) of each lane, as [`split::mul`]
/// forms a `3 × 3` product for `S`: the rows that fill whole registers with fused
/// multiply-adds (none for four lanes), the rest in scalar.
#[inline(always)]
fn mul<S: Simd>(out: &mut Mat3, x: &Mat3, y: &Mat3, conj: bool) {
    let sign = if conj { -1.0 } else { 1.0 };
    for a in 0..3 {
        for i in 0..3 {
            let (mut sr, mut si) = ([0.0; QUAD], [0.0; QUAD]);
            let in_registers = i < 3 / S::F64_LANES * S::F64_LANES;
            for c in 0..3 {
                let (xr, xi) = (&x.re[i + c * 3], &x.im[i + c * 3]);
                let (yr, yi) = (&y.re[c + a * 3], &y.im[c + a * 3]);
                for l in 0..QUAD {
                    let yi = sign * yi[l];
                    if in_registers {
                        sr[l] = xr[l].mul_add(yr[l], xi[l].mul_add(-yi, sr[l]));
                        si[l] = xr[l].mul_add(yi, xi[l].mul_add(yr[l], si[l]));
                    } else {
                        sr[l] += xr[l] * yr[l] - xi[l] * yi;
                        si[l] += xr[l] * yi + xi[l] * yr[l];
                    }
                }
            }
            out.re[i + a * 3] = sr;
            out.im[i + a * 3] = si;
        }
    }
}

/// The sum of the lanes, `(a₀ + a₁) + (a₂ + a₃)`.
#[inline(always)]
pub(super) fn combine(a: &Lanes) -> f64 {
    (a[0] + a[1]) + (a[2] + a[3])
}

/// The buffers of one group's pass: the model impedance (then flexibility) and a product.
pub(super) struct Group {
    h: Mat3,
    p: Mat3,
    /// The eight weighted sums of the lines, per lane.
    sums: [[Lanes; 9]; 8],
}

impl Group {
    /// Zeroed buffers (on the stack: a pass allocates nothing).
    pub(super) fn new() -> Self {
        Self {
            h: Mat3::ZERO,
            p: Mat3::ZERO,
            sums: [[[0.0; QUAD]; 9]; 8],
        }
    }

    /// Group `g` of [`Stacked::instrument_normal`](super::system::Stacked): the model
    /// flexibility `G_m` of each line (in `h`) and `Pᵀ = Gᵀ Ḡ_m` (in `p`) from the contiguous
    /// `M`, `C`, `K`. `Some(false)` if a line's model impedance is singular, `None` where
    /// the group is the per-line path's ([`invert3`]).
    #[inline(always)]
    pub(super) fn instruments<S: Simd>(
        &mut self,
        quads: &Quads,
        g: usize,
        blocks: (&[f64], &[f64], &[f64]),
    ) -> Option<bool> {
        impedance::<S>(&mut self.h, blocks, &quads.omegas[g]);
        if !invert3(&mut self.h)? {
            return Some(false);
        }
        let gt = Mat3 {
            re: quads.gt_re[g],
            im: quads.gt_im[g],
        };
        mul::<S>(&mut self.p, &gt, &self.h, true);
        let w = &quads.omegas[g];
        let one = [1.0; QUAD];
        let w2: Lanes = std::array::from_fn(|l| w[l] * w[l]);
        let w3: Lanes = std::array::from_fn(|l| w[l] * w[l] * w[l]);
        let w4: Lanes = std::array::from_fn(|l| w[l] * w[l] * w[l] * w[l]);
        let sources: [(&[Lanes; 9], &Lanes); 8] = [
            (&self.p.re, &one),
            (&self.p.re, &w2),
            (&self.p.re, &w4),
            (&self.p.im, w),
            (&self.p.im, &w3),
            (&self.h.re, &one),
            (&self.h.re, &w2),
            (&self.h.im, w),
        ];
        for (dst, (src, weight)) in self.sums.iter_mut().zip(sources) {
            for e in 0..9 {
                for l in 0..QUAD {
                    dst[e][l] = src[e][l].mul_add(weight[l], dst[e][l]);
                }
            }
        }
        Some(true)
    }

    /// Adds the lanes' weighted sums of [`Group::instruments`] to `sums` (`8 × 9`, as
    /// `InstrumentWork` holds them), the lanes combined as [`combine`] does.
    pub(super) fn add_sums_to(&self, sums: &mut [f64]) {
        for (dst, lanes) in sums.chunks_exact_mut(9).zip(&self.sums) {
            for (d, a) in dst.iter_mut().zip(lanes) {
                *d += combine(a);
            }
        }
    }

    /// Group `g` of [`Stacked::residual_norm_into`](super::system::Stacked): adds
    /// $\lVert G H - I \rVert_F^2$ of each line, formed as `Hᵀ Gᵀ − I` from the transposed
    /// `M`, `C`, `K`, to its lane of `acc`.
    #[inline(always)]
    pub(super) fn residual<S: Simd>(
        &mut self,
        quads: &Quads,
        g: usize,
        blocks: (&[f64], &[f64], &[f64]),
        acc: &mut Lanes,
    ) {
        impedance::<S>(&mut self.h, blocks, &quads.omegas[g]);
        let gt = Mat3 {
            re: quads.gt_re[g],
            im: quads.gt_im[g],
        };
        mul::<S>(&mut self.p, &self.h, &gt, false);
        for d in 0..3 {
            for l in 0..QUAD {
                self.p.re[d * 4][l] -= 1.0;
            }
        }
        for (re, im) in self.p.re.iter().zip(&self.p.im) {
            for l in 0..QUAD {
                acc[l] = re[l].mul_add(re[l], im[l].mul_add(im[l], acc[l]));
            }
        }
    }
}
