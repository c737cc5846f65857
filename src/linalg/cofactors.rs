//! Right division `H = F X⁻¹` of many `3 × 3` complex pairs, [`LANES`] pairs side by side,
//! one per SIMD lane: `X⁻¹` by [`invert3`]'s cofactors, then the product of [`mul_into`].
//!
//! The cofactors are a straight line of multiplications and subtractions, with one division
//! (`1 / det`) and no branch in the usual case, so [`LANES`] matrices go through them as
//! SIMD operations on structures of arrays (entry `e` of every lane's matrix in one
//! `[f64; LANES]`). Each lane runs the operations of [`invert3`] and [`mul_into`] on its own
//! pair in the same order (no fused multiply-add: Rust does not contract `a * b + c`), so
//! every quotient is bit for bit the one-at-a-time one. A lane whose pair leaves the
//! straight line (an exponent out of the normal range, a determinant whose squared modulus
//! is not a normal number, which includes a singular `X`, or a quotient that is not finite)
//! is done again one at a time by [`Inverter::invert_by_cofactors`] and [`mul_into`].
//!
//! [`invert3`]: super::invert3

use faer::c64;
use faer::traits::pulp::{Arch, Simd, WithSimd};

use super::{Inverter, mul_into};

/// Matrices side by side, one per lane: four `f64` fill an AVX2 register (the count of the
/// crate's other lane passes, written here so that `linalg` needs nothing but faer: the
/// benches compile it alone).
pub(crate) const LANES: usize = 4;

/// One number of each of the [`LANES`] pairs.
type Lanes = [f64; LANES];

/// One complex entry of each of the [`LANES`] pairs, its parts apart.
#[derive(Clone, Copy)]
struct Z {
    re: Lanes,
    im: Lanes,
}

/// `f(a, b)` lane by lane.
#[inline(always)]
fn map2(a: Lanes, b: Lanes, f: impl Fn(f64, f64) -> f64) -> Lanes {
    let mut out = a;
    for l in 0..LANES {
        out[l] = f(a[l], b[l]);
    }
    out
}

impl Z {
    const ZERO: Z = Z {
        re: [0.0; LANES],
        im: [0.0; LANES],
    };

    /// `a · b` as `num_complex` forms it: `(a'b' − a''b'') + i(a'b'' + a''b')`.
    #[inline(always)]
    fn mul(self, b: Z) -> Z {
        let mut out = Z::ZERO;
        for l in 0..LANES {
            out.re[l] = self.re[l] * b.re[l] - self.im[l] * b.im[l];
            out.im[l] = self.re[l] * b.im[l] + self.im[l] * b.re[l];
        }
        out
    }

    /// `a + b`.
    #[inline(always)]
    fn add(self, b: Z) -> Z {
        Z {
            re: map2(self.re, b.re, |x, y| x + y),
            im: map2(self.im, b.im, |x, y| x + y),
        }
    }
}

/// The pass of [`right_divide3`] as an operation of faer's SIMD dispatch (a named type, so
/// that the whole pass is compiled for the instruction set chosen).
struct Batch<'a> {
    inverter: &'a mut Inverter,
    f: &'a [c64],
    x: &'a [c64],
    h: &'a mut Vec<c64>,
    regular: &'a mut Vec<bool>,
}

impl WithSimd for Batch<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) {
        let Self {
            inverter,
            f,
            x,
            h,
            regular,
        } = self;
        let count = f.len() / 9;
        for start in (0..count).step_by(LANES) {
            // The last group is padded by repeating its last pair.
            let last = (count - start).min(LANES) - 1;
            let pair = |l: usize| start + l.min(last);
            let mut fz = [Z::ZERO; 9];
            let mut xs = Split3::ZERO;
            for l in 0..LANES {
                let m = pair(l);
                // Slices of the known length: no bounds check per entry.
                let (fm, xm) = (&f[9 * m..][..9], &x[9 * m..][..9]);
                for e in 0..9 {
                    (fz[e].re[l], fz[e].im[l]) = (fm[e].re, fm[e].im);
                    (xs.re[e][l], xs.im[e][l]) = (xm[e].re, xm[e].im);
                }
            }
            let straight = invert3_lanes(&mut xs);
            let inv: [Z; 9] = std::array::from_fn(|e| Z {
                re: xs.re[e],
                im: xs.im[e],
            });
            // `H = F X⁻¹` as `mul_into` sums it: from zero, over `k` in order.
            let mut hz = [Z::ZERO; 9];
            for j in 0..3 {
                for i in 0..3 {
                    let mut s = Z::ZERO;
                    for k in 0..3 {
                        s = s.add(fz[i + 3 * k].mul(inv[k + 3 * j]));
                    }
                    hz[i + 3 * j] = s;
                }
            }
            for l in 0..=last {
                let m = start + l;
                if straight.lane(l) {
                    let out: [c64; 9] = std::array::from_fn(|e| c64::new(hz[e].re[l], hz[e].im[l]));
                    h.extend_from_slice(&out);
                    regular.push(true);
                } else {
                    let mut out = [c64::new(0.0, 0.0); 9];
                    regular.push(one_at_a_time(
                        inverter,
                        &f[9 * m..9 * (m + 1)],
                        &x[9 * m..9 * (m + 1)],
                        &mut out,
                    ));
                    h.extend_from_slice(&out);
                }
            }
        }
    }
}

/// A `3 × 3` complex matrix in each of [`LANES`] lanes: column-major entries, each entry's
/// real parts (one per lane) apart from its imaginary parts.
#[derive(Clone, Copy)]
pub(crate) struct Split3 {
    pub(crate) re: [Lanes; 9],
    pub(crate) im: [Lanes; 9],
}

impl Split3 {
    /// Zero in every entry of every lane.
    pub(crate) const ZERO: Self = Self {
        re: [[0.0; LANES]; 9],
        im: [[0.0; LANES]; 9],
    };
}

/// Per lane, which conditions of [`invert3`]'s straight line [`invert3_lanes`] met: where
/// all of them hold, the lane's inverse is [`invert3`]'s bit for bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Straight {
    /// The power of two scaling the matrix, and its reciprocal, are normal numbers.
    pub(crate) scale: [bool; LANES],
    /// The determinant is not zero.
    pub(crate) regular: [bool; LANES],
    /// The determinant's squared modulus is a finite normal number (its reciprocal is taken
    /// through it).
    pub(crate) reciprocal: [bool; LANES],
    /// Every entry of the inverse is finite.
    pub(crate) finite: [bool; LANES],
}

impl Straight {
    /// Whether lane `l` took the straight line all the way (a regular matrix then).
    pub(crate) fn lane(&self, l: usize) -> bool {
        self.scale[l] && self.reciprocal[l] && self.finite[l]
    }
}

/// The complex product `a b` of each lane, as `num_complex` forms it:
/// `(a'b' − a''b'') + i(a'b'' + a''b')`.
#[inline(always)]
fn cmul((ar, ai): (&Lanes, &Lanes), (br, bi): (&Lanes, &Lanes)) -> (Lanes, Lanes) {
    (
        std::array::from_fn(|l| ar[l] * br[l] - ai[l] * bi[l]),
        std::array::from_fn(|l| ar[l] * bi[l] + ai[l] * br[l]),
    )
}

/// `a b − c d` of each lane (complex), as [`invert3`]'s adjugate forms it.
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

/// [`invert3`]'s operations on every lane of `a`, in place: the matrix scaled by the power
/// of two at or below its largest part, its adjugate, the determinant along the first row,
/// the inverse as the adjugate times `1/det` (through the squared modulus) and the scale.
/// Returns, per lane, which conditions of that straight line held ([`Straight`]): where all
/// hold, the lane's inverse is [`invert3`]'s bit for bit; elsewhere it is a number to discard
/// (the per-line path takes Gauss–Jordan, the slow reciprocal, or refuses a
/// singular matrix there). A straight line of products and sums, no branch: the lanes go
/// through it as SIMD operations. The IVF's groups of four lines and [`right_divide3`]'s
/// pairs both invert here.
// A lane index runs over several arrays at once: clearer as an index than as zips.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
pub(crate) fn invert3_lanes(a: &mut Split3) -> Straight {
    let mut largest = [0.0_f64; LANES];
    for e in 0..9 {
        for l in 0..LANES {
            largest[l] = largest[l].max(a.re[e][l].abs()).max(a.im[e][l].abs());
        }
    }
    let mut down = [0.0; LANES];
    let mut scale_normal = [true; LANES];
    for l in 0..LANES {
        // The power of two at or below `largest`: its exponent bits alone.
        let scale = f64::from_bits(largest[l].to_bits() & 0x7ff0_0000_0000_0000);
        down[l] = 1.0 / scale;
        scale_normal[l] = scale.is_normal() && down[l].is_normal();
    }
    let mut s = Split3::ZERO;
    for e in 0..9 {
        for l in 0..LANES {
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
    let mut factor = ([0.0; LANES], [0.0; LANES]);
    let mut straight = Straight {
        scale: scale_normal,
        regular: [true; LANES],
        reciprocal: [true; LANES],
        finite: [true; LANES],
    };
    for l in 0..LANES {
        straight.regular[l] = !(det_re[l] == 0.0 && det_im[l] == 0.0);
        // `reciprocal(det)` through the squared modulus, where that is a normal number.
        let r2 = det_re[l] * det_re[l] + det_im[l] * det_im[l];
        straight.reciprocal[l] = r2.is_finite() && r2 >= f64::MIN_POSITIVE;
        // (A/s)⁻¹ = s A⁻¹: the inverse is (A/s)⁻¹ / s.
        factor.0[l] = det_re[l] / r2 * down[l];
        factor.1[l] = -det_im[l] / r2 * down[l];
    }
    // A number times zero is zero, an infinity or NaN times zero NaN: the sum of the
    // entries times zero is zero exactly where every entry is finite (kept as numbers, so the
    // lanes stay in SIMD registers).
    let mut nonfinite = [0.0_f64; LANES];
    for (e, adj) in adj.iter().enumerate() {
        let (re, im) = cmul((&adj.0, &adj.1), (&factor.0, &factor.1));
        for l in 0..LANES {
            nonfinite[l] += re[l] * 0.0 + im[l] * 0.0;
        }
        (a.re[e], a.im[e]) = (re, im);
    }
    for l in 0..LANES {
        straight.finite[l] = nonfinite[l] == 0.0;
    }
    straight
}

/// `h = f x⁻¹` of one pair by [`Inverter::invert_by_cofactors`] and [`mul_into`]; whether `x`
/// could be inverted (`h` zero if not).
fn one_at_a_time(inverter: &mut Inverter, f: &[c64], x: &[c64], h: &mut [c64]) -> bool {
    let mut inv: [c64; 9] = std::array::from_fn(|e| x[e]);
    if inverter.invert_by_cofactors(&mut inv) {
        mul_into(f, &inv, h, 3);
        true
    } else {
        h.fill(c64::new(0.0, 0.0));
        false
    }
}

/// `H_m = F_m X_m⁻¹` of the column-major `3 × 3` complex pairs stored back to back in `f`
/// and `x`, appended to `h`, [`LANES`] pairs at a time: each `H_m` bit for bit what
/// [`Inverter::invert_by_cofactors`] then [`mul_into`] give for it (see the module docs).
/// Whether `X_m` could be inverted is appended to `regular`; `H_m` is zero where it could
/// not. `inverter` (for `n = 3`) does the pairs the lanes hand back. Appending rather than
/// writing into a slice spares the caller a zeroing pass; no allocation where `h` and
/// `regular` have the room.
///
/// # Panics
/// If `inverter` is not for `3 × 3`, or `f` and `x` do not hold the same multiple of 9
/// values.
pub(crate) fn right_divide3(
    inverter: &mut Inverter,
    f: &[c64],
    x: &[c64],
    h: &mut Vec<c64>,
    regular: &mut Vec<bool>,
) {
    assert_eq!(inverter.n, 3, "an inverter for 3 × 3 matrices");
    assert!(
        f.len() == x.len() && f.len() % 9 == 0,
        "pairs of 3 × 3 matrices, not {} and {} entries",
        f.len(),
        x.len()
    );
    Arch::new().dispatch(Batch {
        inverter,
        f,
        x,
        h,
        regular,
    });
}

#[cfg(test)]
mod tests {
    use super::super::invert3;
    use super::*;
    use rand::rngs::StdRng;
    use rand::{RngExt, SeedableRng};

    /// The one-at-a-time reference: a copy inverted by cofactors, then the product.
    fn reference(f: &[c64], x: &[c64]) -> (Vec<c64>, bool) {
        let mut inverter = Inverter::new(3);
        let mut h = vec![c64::new(0.0, 0.0); 9];
        let regular = one_at_a_time(&mut inverter, f, x, &mut h);
        (h, regular)
    }

    fn check(f: &[c64], x: &[c64]) {
        let count = f.len() / 9;
        // Appended after what the buffers hold.
        let mut h = vec![c64::new(7.0, 7.0); 9];
        let mut regular = vec![false];
        right_divide3(&mut Inverter::new(3), f, x, &mut h, &mut regular);
        assert_eq!((h.len(), regular.len()), (9 * (count + 1), count + 1));
        let (h, regular) = (&h[9..], &regular[1..]);
        for m in 0..count {
            let (expect, r) = reference(&f[9 * m..9 * (m + 1)], &x[9 * m..9 * (m + 1)]);
            assert_eq!(regular[m], r, "pair {m}");
            for (a, b) in h[9 * m..9 * (m + 1)].iter().zip(&expect) {
                assert_eq!(
                    (a.re.to_bits(), a.im.to_bits()),
                    (b.re.to_bits(), b.im.to_bits()),
                    "pair {m}"
                );
            }
        }
    }

    fn random(count: usize, rng: &mut StdRng) -> Vec<c64> {
        (0..9 * count)
            .map(|_| c64::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)))
            .collect()
    }

    /// Random pairs of every count (the padded last group too), at scales over the whole
    /// range, match one at a time bit for bit.
    #[test]
    fn lanes_are_the_one_at_a_time_quotients_bit_for_bit() {
        let mut rng = StdRng::seed_from_u64(3);
        for count in 0..11 {
            for scale in [1e-150, 1e-20, 1.0, 3e7, 1e150] {
                let f = random(count, &mut rng);
                let x: Vec<c64> = random(count, &mut rng).iter().map(|z| z * scale).collect();
                check(&f, &x);
            }
        }
    }

    /// Singular, zero, non-finite and out-of-range pairs in any lane, among regular ones:
    /// the same quotients and flags as one at a time.
    #[test]
    fn special_pairs_in_any_lane_match() {
        let mut rng = StdRng::seed_from_u64(4);
        let count = 2 * LANES + 1;
        let specials: [fn(&mut [c64]); 6] = [
            |x| x.fill(c64::new(0.0, 0.0)),
            // A zero column: a zero determinant.
            |x| x[..3].fill(c64::new(0.0, 0.0)),
            |x| x[4] = c64::new(f64::NAN, 0.0),
            |x| x[2] = c64::new(0.0, f64::INFINITY),
            |x| x.iter_mut().for_each(|z| *z *= 1e300),
            |x| x.iter_mut().for_each(|z| *z *= 1e-310),
        ];
        for (s, special) in specials.iter().enumerate() {
            for at in [0, 3, LANES, count - 1] {
                let f = random(count, &mut rng);
                let mut x = random(count, &mut rng);
                special(&mut x[9 * at..9 * (at + 1)]);
                check(&f, &x);
                let (mut h, mut regular) = (Vec::new(), Vec::new());
                right_divide3(&mut Inverter::new(3), &f, &x, &mut h, &mut regular);
                if s < 4 {
                    assert!(!regular[at], "special {s} at {at}");
                }
            }
        }
        // `invert3` itself refuses the pair with a zero column.
        let x = random(1, &mut rng);
        let mut x: [c64; 9] =
            std::array::from_fn(|e| if e < 3 { c64::new(0.0, 0.0) } else { x[e] });
        assert_eq!(invert3(&mut x), Some(false));
    }
}
