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
use crate::linalg::{SPLIT3_LANES, Split3, invert3_lanes};

/// Lines per group: the lanes.
pub(super) const QUAD: usize = SPLIT3_LANES;

/// One value of each line of a group.
pub(super) type Lanes = [f64; QUAD];

/// A split `3 × 3` matrix of each line of a group, column-major entries, each four lanes.
type Mat3 = Split3;

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

/// Each lane's `3 × 3` inverted in place by [`linalg::invert3`]'s operations
/// ([`invert3_lanes`]): `None` (and `a` unspecified) if a lane's scale or determinant leaves
/// the range where the per-line path takes those operations (it takes Gauss–Jordan or the
/// slow reciprocal there), `Some(false)` if a lane is singular or its inverse is not finite.
#[inline(always)]
fn invert3(a: &mut Mat3) -> Option<bool> {
    let straight = invert3_lanes(a);
    let all = |flags: [bool; QUAD]| flags.iter().all(|&f| f);
    if !all(straight.scale) {
        return None;
    }
    if !all(straight.regular) {
        return Some(false);
    }
    if !all(straight.reciprocal) {
        return None;
    }
    Some(all(straight.finite))
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
