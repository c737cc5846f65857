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
use crate::lanes::LANES;

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

    /// `a − b`.
    #[inline(always)]
    fn sub(self, b: Z) -> Z {
        Z {
            re: map2(self.re, b.re, |x, y| x - y),
            im: map2(self.im, b.im, |x, y| x - y),
        }
    }

    /// `a + b`.
    #[inline(always)]
    fn add(self, b: Z) -> Z {
        Z {
            re: map2(self.re, b.re, |x, y| x + y),
            im: map2(self.im, b.im, |x, y| x + y),
        }
    }

    /// `a · s`, real `s` per lane.
    #[inline(always)]
    fn scale(self, s: Lanes) -> Z {
        Z {
            re: map2(self.re, s, |x, y| x * y),
            im: map2(self.im, s, |x, y| x * y),
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
            let mut xz = [Z::ZERO; 9];
            for l in 0..LANES {
                let m = pair(l);
                // Slices of the known length: no bounds check per entry.
                let (fm, xm) = (&f[9 * m..][..9], &x[9 * m..][..9]);
                for e in 0..9 {
                    (fz[e].re[l], fz[e].im[l]) = (fm[e].re, fm[e].im);
                    (xz[e].re[l], xz[e].im[l]) = (xm[e].re, xm[e].im);
                }
            }
            let (inv, straight) = inverse(&xz);
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
            for (l, &straight) in straight.iter().enumerate().take(last + 1) {
                let m = start + l;
                if straight {
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

/// [`invert3`] on every lane: the inverse, and per lane whether it took the straight line
/// (a normal scale and determinant, a finite inverse), where it is [`invert3`]'s bit for
/// bit. Other lanes hold numbers to be discarded.
#[inline(always)]
fn inverse(a: &[Z; 9]) -> ([Z; 9], [bool; LANES]) {
    let mut largest = [0.0_f64; LANES];
    for z in a {
        for (l, m) in largest.iter_mut().enumerate() {
            *m = m.max(z.re[l].abs()).max(z.im[l].abs());
        }
    }
    let mut straight = [true; LANES];
    let mut down = [1.0; LANES];
    for l in 0..LANES {
        let scale = f64::from_bits(largest[l].to_bits() & 0x7ff0_0000_0000_0000);
        straight[l] = scale.is_normal() && (1.0 / scale).is_normal();
        down[l] = 1.0 / scale;
    }
    let at = |e: usize| a[e].scale(down);
    let (a00, a10, a20) = (at(0), at(1), at(2));
    let (a01, a11, a21) = (at(3), at(4), at(5));
    let (a02, a12, a22) = (at(6), at(7), at(8));
    let adj = [
        a11.mul(a22).sub(a12.mul(a21)),
        a12.mul(a20).sub(a10.mul(a22)),
        a10.mul(a21).sub(a11.mul(a20)),
        a02.mul(a21).sub(a01.mul(a22)),
        a00.mul(a22).sub(a02.mul(a20)),
        a01.mul(a20).sub(a00.mul(a21)),
        a01.mul(a12).sub(a02.mul(a11)),
        a02.mul(a10).sub(a00.mul(a12)),
        a00.mul(a11).sub(a01.mul(a10)),
    ];
    let det = a00.mul(adj[0]).add(a01.mul(adj[1])).add(a02.mul(adj[2]));
    // `reciprocal(det) · down` through the squared modulus (its straight line).
    let mut factor = Z::ZERO;
    for (l, straight) in straight.iter_mut().enumerate() {
        let r2 = det.re[l] * det.re[l] + det.im[l] * det.im[l];
        *straight &= r2.is_finite() && r2 >= f64::MIN_POSITIVE;
        factor.re[l] = det.re[l] / r2;
        factor.im[l] = -det.im[l] / r2;
    }
    let factor = factor.scale(down);
    // A loop rather than `adj.map`, which was not inlined (so not compiled for the SIMD
    // instructions chosen).
    let mut inv = adj;
    for z in &mut inv {
        *z = z.mul(factor);
        for (l, straight) in straight.iter_mut().enumerate() {
            *straight &= z.re[l].is_finite() && z.im[l].is_finite();
        }
    }
    (inv, straight)
}

/// `h = f x⁻¹` of one pair by [`Inverter::invert_by_cofactors`] and [`mul_into`]; whether `x` could be inverted (`h` zero if not).
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
