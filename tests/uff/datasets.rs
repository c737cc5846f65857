//! Universal File dataset 58 / 58b: the files of other software (UFFFiles.jl, pyuff; MIT, kept
//! outside the repository with their licences, see `FIXTURES.md`) read to the values they hold,
//! ASCII and binary alike (skipped, with a line saying so, when they are absent); write → read
//! round trips; typed errors naming block and line; no panic on any bytes; records from time
//! histories identified as from CSV.
#![cfg(feature = "uff")]

use std::path::{Path, PathBuf};

use bearing_ident::Error;
use bearing_ident::faer::c64;
use bearing_ident::uff::{
    self, Abscissa, Axis, ByteOrder, DataType, Dof, Function, FunctionType, Ordinate, Precision,
};
use proptest::prelude::*;

/// The third-party files' folder, or `None` (and a line saying why `test` skips).
fn data(test: &str) -> Option<PathBuf> {
    crate::common::fixtures("uff", test)
}

fn one(dir: &Path, name: &str) -> Function {
    let mut f = uff::read(dir.join(name)).unwrap();
    assert_eq!(f.len(), 1, "{name}");
    f.pop().unwrap()
}

/// The ordinate as reals (complex interleaved re, im).
fn reals(o: &Ordinate) -> Vec<f64> {
    match o {
        Ordinate::Real(v) => v.clone(),
        Ordinate::Complex(v) => v.iter().flat_map(|c| [c.re, c.im]).collect(),
    }
}

/// Largest `|a − b|` relative to the largest `|b|` of the function.
fn worst(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 0.0);
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

/// Largest element-wise relative error `|a − b| / |b|` over the nonzero `b`.
fn worst_elementwise(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .filter(|(_, y)| **y != 0.0)
        .map(|(x, y)| ((x - y) / y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn the_eight_layouts_read_alike_in_ascii_and_binary() {
    let Some(dir) = data("the_eight_layouts_read_alike_in_ascii_and_binary") else {
        return;
    };
    // (case, ordinate type, points, even)
    let cases = [
        (1, 2, 1602, true),
        (2, 2, 1602, false),
        (3, 5, 801, true),
        (4, 5, 801, false),
        (5, 4, 1602, true),
        (6, 4, 1602, false),
        (7, 6, 801, true),
        (8, 6, 801, false),
    ];
    let reference = reals(&one(&dir, "dataset58_case7_binary.unv").ordinate);
    assert_eq!(reference.len(), 1602);
    for (case, otype, n, even) in cases {
        let a = one(&dir, &format!("dataset58_case{case}_ascii.unv"));
        let b = one(&dir, &format!("dataset58_case{case}_binary.unv"));
        for f in [&a, &b] {
            assert_eq!(f.function_type, FunctionType::Frf, "case {case}");
            assert_eq!(f.ordinate_type(), otype, "case {case}");
            assert_eq!(f.ordinate.len(), n, "case {case}");
            assert_eq!((f.response.node, f.response.direction), (1, 1));
            assert_eq!((f.reference.node, f.reference.direction), (22, 1));
            assert_eq!(f.abscissa_axis.data_type, DataType::Frequency);
            assert_eq!(f.numerator.data_type, DataType::Acceleration);
            assert_eq!(f.denominator.data_type, DataType::ExcitationForce);
            assert_eq!(f.id[2], "28-Jan-21 14:01:42");
            match &f.abscissa {
                Abscissa::Even { x0, dx, n: m } => {
                    assert!(even);
                    assert_eq!((*x0, *dx, *m), (0.0, 0.25, n));
                }
                Abscissa::Uneven(x) => {
                    assert!(!even);
                    assert_eq!(x.len(), n);
                    assert_eq!(x[0], 10.0);
                    // Logarithmic spacing: 10.0288 (1602 points) or 10.0577 (801 points).
                    let second = if n == 1602 { 10.0288 } else { 10.0577 };
                    assert!((x[1] - second).abs() < 1e-4, "case {case}: {}", x[1]);
                }
            }
        }
        // The first values, as printed in the ASCII file.
        let ra = reals(&a.ordinate);
        let rb = reals(&b.ordinate);
        let first = if a.precision == Precision::Single {
            1.73331e-4
        } else {
            1.733310054988e-4
        };
        assert_eq!(ra[0], first, "case {case}");
        assert_eq!(ra[1], 0.0);
        assert!((rb[2] / -5.45225e-7 - 1.0).abs() < 1e-6, "case {case}");
        // ASCII vs binary: single values carry six digits in ASCII and f32 in binary; double
        // values thirteen digits in ASCII and f64 in binary.
        let (tol, tol_x) = if a.precision == Precision::Single {
            (5e-6, 5e-6)
        } else {
            (5e-13, 5e-6)
        };
        let e = worst_elementwise(&ra, &rb);
        assert!(e <= tol, "case {case}: ASCII vs binary {e:e}");
        if let (Abscissa::Uneven(xa), Abscissa::Uneven(xb)) = (&a.abscissa, &b.abscissa) {
            let e = worst_elementwise(xa, xb);
            assert!(e <= tol_x, "case {case}: abscissa {e:e}");
        }
        // Single vs double (of the same even/uneven, real/complex layout) within single
        // precision; all are one FRF.
        let e = worst(&rb, &reference);
        assert!(e <= 1e-6, "case {case}: vs double {e:e}");
        assert_eq!(a.precision == Precision::Single, otype == 2 || otype == 5);
    }
}

#[test]
fn pyuff_sample_reads_alike_in_ascii_and_binary() {
    let Some(dir) = data("pyuff_sample_reads_alike_in_ascii_and_binary") else {
        return;
    };
    let a = one(&dir, "Sample_UFF58_ascii.uff");
    let b = one(&dir, "Sample_UFF58b_bin.uff");
    for f in [&a, &b] {
        assert_eq!(f.function_type, FunctionType::TimeResponse);
        assert_eq!(f.ordinate.len(), 79_292);
        assert_eq!(
            f.abscissa,
            Abscissa::Even {
                x0: 0.0,
                dx: 1.52588e-5,
                n: 79_292
            }
        );
        assert_eq!(f.response.entity, "Mic 01");
        assert_eq!((f.response.node, f.response.direction), (0, 1));
        assert_eq!(f.numerator.data_type, DataType::SoundPressure);
        assert_eq!(f.numerator.units, "Pa");
        assert_eq!(f.id[0], "Mic 01.0Scalar");
    }
    let (ra, rb) = (reals(&a.ordinate), reals(&b.ordinate));
    assert_eq!(ra[0], -1.47553e-2);
    let e = worst_elementwise(&ra, &rb);
    assert!(e <= 5e-6, "ASCII vs binary {e:e}");
}

#[test]
fn binary_double_reads_a_sine() {
    let Some(dir) = data("binary_double_reads_a_sine") else {
        return;
    };
    let f = one(&dir, "binary8byte.uff");
    assert_eq!(f.ordinate_type(), 4);
    assert_eq!(f.response.entity, "sine 5 Hz");
    assert_eq!(f.response.node, 1);
    assert_eq!(f.numerator.data_type, DataType::Acceleration);
    let Ordinate::Real(y) = &f.ordinate else {
        panic!("real expected")
    };
    assert_eq!(y.len(), 250);
    // 5 Hz sampled every 0.01 s, computed in single precision (errors grow to 7.4e-6 by the end).
    assert_eq!(y[1], 0.30901697278022766);
    for (k, v) in y.iter().enumerate() {
        let t = k as f64 * 0.01;
        assert!(
            (v - (2.0 * std::f64::consts::PI * 5.0 * t).sin()).abs() < 1e-5,
            "{k}"
        );
    }
}

#[test]
fn time_frf_and_coherence_files_read_with_their_types() {
    let Some(dir) = data("time_frf_and_coherence_files_read_with_their_types") else {
        return;
    };
    let t = one(&dir, "dataset58_time.unv");
    assert_eq!(t.function_type, FunctionType::TimeResponse);
    assert_eq!(t.abscissa_axis.data_type, DataType::Time);
    assert_eq!(t.numerator.label, "Force");
    assert_eq!(t.numerator.units, "N");
    assert_eq!(t.response.entity, ".1.Z-");
    assert_eq!((t.response.node, t.response.direction), (0, 0));
    assert_eq!(t.z_value, 4.0);
    assert_eq!(
        t.abscissa,
        Abscissa::Even {
            x0: 0.0,
            dx: 4.88281e-4,
            n: 4096
        }
    );
    assert_eq!(
        reals(&t.ordinate)[..3],
        [1.06578e-2, 8.08909e-3, 7.99399e-3]
    );

    let h = one(&dir, "dataset58_FRF.unv");
    assert_eq!(h.function_type, FunctionType::Frf);
    assert_eq!(h.ordinate_type(), 5);
    assert_eq!(h.reference.entity, ".56.Z");
    assert_eq!(h.numerator.label, "Receptance");
    let Ordinate::Complex(v) = &h.ordinate else {
        panic!("complex expected")
    };
    assert_eq!(v.len(), 1600);
    assert_eq!(v[0], c64::new(-7.69795e-1, 0.0));
    assert_eq!(v[1], c64::new(-1.29302, -9.27769e-1));

    let c = one(&dir, "dataset58_coh.unv");
    assert_eq!(c.function_type, FunctionType::Coherence);
    assert_eq!(c.ordinate_type(), 2);
    let r = reals(&c.ordinate);
    assert_eq!(r.len(), 1600);
    assert_eq!(r[0], 3.69221e-1);
    assert!(r.iter().all(|v| (0.0..=1.0).contains(v)));
}

/// Deterministic values spanning many decades and both signs.
fn values(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            let e = ((s >> 3) % 40) as i32 - 20;
            (u - 0.5) * 10f64.powi(e)
        })
        .collect()
}

/// A function of every layout, with header fields that are not the defaults.
fn layouts() -> Vec<Function> {
    let mut out = Vec::new();
    for (k, (complex, precision, even)) in [
        (false, Precision::Single, true),
        (false, Precision::Single, false),
        (true, Precision::Single, true),
        (true, Precision::Single, false),
        (false, Precision::Double, true),
        (false, Precision::Double, false),
        (true, Precision::Double, true),
        (true, Precision::Double, false),
    ]
    .into_iter()
    .enumerate()
    {
        let n = 7 + k;
        let y = values(2 * n, k as u64 + 1);
        let mut f = Function::time_response(3, -2, 12, 0.5, 0.25, y[..n].to_vec());
        f.function_type = if complex {
            FunctionType::Frf
        } else {
            FunctionType::Spectrum
        };
        f.precision = precision;
        f.load_case = 40 + k as i64;
        f.function_id = 9;
        f.id[1] = format!("layout {k}");
        f.reference = Dof {
            entity: "shaker".into(),
            node: 22,
            direction: 3,
        };
        f.denominator = Axis::new(DataType::ExcitationForce, "Force", "N");
        if complex {
            f.ordinate = Ordinate::Complex((0..n).map(|i| c64::new(y[i], y[n + i])).collect());
        }
        if !even {
            // Values a 13.5 field and an f32 both hold exactly.
            f.abscissa = Abscissa::Uneven((0..n).map(|i| 10.0 + 0.125 * (i * i) as f64).collect());
        }
        out.push(f);
    }
    out
}

/// `v` rounded to the digits the writer keeps: six for single, thirteen for double.
fn written(v: f64, p: Precision) -> f64 {
    let d = if p == Precision::Single { 5 } else { 12 };
    format!("{v:.d$e}").parse().unwrap()
}

#[test]
fn ascii_round_trip_keeps_every_written_digit() {
    let fs = layouts();
    let mut bytes = Vec::new();
    uff::write(&mut bytes, &fs).unwrap();
    let back = uff::parse(&bytes, "mem.uff").unwrap();
    assert_eq!(back.len(), 8);
    for (f, g) in fs.iter().zip(&back) {
        assert_eq!(g.abscissa, f.abscissa);
        assert_eq!(g.function_type, f.function_type);
        assert_eq!(g.precision, f.precision);
        assert_eq!(g.load_case, f.load_case);
        assert_eq!(g.function_id, 9);
        assert_eq!(g.id, f.id);
        assert_eq!(g.response, f.response);
        assert_eq!(g.reference, f.reference);
        assert_eq!(
            (g.numerator.clone(), g.denominator.clone()),
            (f.numerator.clone(), f.denominator.clone())
        );
        let want: Vec<f64> = reals(&f.ordinate)
            .iter()
            .map(|&v| written(v, f.precision))
            .collect();
        assert_eq!(reals(&g.ordinate), want);
    }
    // Written again, the file is the same bytes.
    let mut again = Vec::new();
    uff::write(&mut again, &back).unwrap();
    assert_eq!(again, bytes);
}

#[test]
fn binary_round_trip_is_exact_in_double_precision_both_byte_orders() {
    let fs = layouts();
    for order in [ByteOrder::Little, ByteOrder::Big] {
        let mut bytes = Vec::new();
        uff::write_binary(&mut bytes, &fs, order).unwrap();
        let back = uff::parse(&bytes, "mem.uff").unwrap();
        assert_eq!(back.len(), 8);
        for (f, g) in fs.iter().zip(&back) {
            assert_eq!(g.abscissa, f.abscissa);
            assert_eq!(g.load_case, f.load_case);
            let want: Vec<f64> = reals(&f.ordinate)
                .iter()
                .map(|&v| match f.precision {
                    Precision::Double => v,
                    Precision::Single => f64::from(v as f32),
                })
                .collect();
            assert_eq!(reals(&g.ordinate), want, "{order:?}");
        }
    }
}

/// A small ASCII block around `data` lines.
fn block(record7: &str, data: &str) -> String {
    format!(
        "    -1\n    58\nid1\nid2\nid3\nid4\nid5\n\
         \x20   1         0    0         0 NONE               1   1 NONE               0   0\n\
         {record7}\n\
         \x20       17    0    0    0 Time                 s\n\
         \x20       13    0    0    0 Force                N\n\
         \x20        0    0    0    0 NONE                 NONE\n\
         \x20        0    0    0    0 NONE                 NONE\n\
         {data}    -1\n"
    )
}

const R7_REAL4: &str = "         2         4         1  0.00000E+00  1.00000E-03  0.00000E+00";

#[test]
fn fortran_fields_touch_take_three_digit_and_d_exponents_short_lines_and_crlf() {
    let text = block(
        R7_REAL4,
        "-1.23450E-100-4.56000D+002 7.00000E-100\n  1.00000E+00\n",
    );
    let f = &uff::parse(text.as_bytes(), "t.uff").unwrap()[0];
    assert_eq!(
        f.ordinate,
        Ordinate::Real(vec![-1.2345e-100, -456.0, 7e-100, 1.0])
    );
    // Fortran's three-digit exponent without its letter, and CRLF line ends.
    let text = block(
        R7_REAL4,
        "  1.00000-100  2.50000+101 -3.00000E+00  4.00000E+00\n",
    )
    .replace('\n', "\r\n");
    let f = &uff::parse(text.as_bytes(), "t.uff").unwrap()[0];
    assert_eq!(f.ordinate, Ordinate::Real(vec![1e-100, 2.5e101, -3.0, 4.0]));
    // Free format (space-separated) is read too.
    let text = block(R7_REAL4, "1 2.5\n-3 4e0\n");
    let f = &uff::parse(text.as_bytes(), "t.uff").unwrap()[0];
    assert_eq!(f.ordinate, Ordinate::Real(vec![1.0, 2.5, -3.0, 4.0]));
}

#[test]
fn other_datasets_are_skipped_and_58b_by_its_byte_count() {
    // A 58b block whose values contain the bytes of "\n    -1\n" (skipped by count, not by
    // scanning), between two other datasets.
    let mut f = Function::time_response(1, 1, 13, 0.0, 1e-3, vec![0.0; 4]);
    let trap = f64::from_le_bytes(*b"\n    -1\n");
    f.ordinate = Ordinate::Real(vec![trap, 1.0, trap, 2.0]);
    let mut bytes = b"    -1\n   151\nmodel\n    -1\n".to_vec();
    uff::write_binary(&mut bytes, &[f], ByteOrder::Little).unwrap();
    bytes.extend_from_slice(b"    -1\n  2411\n         1         1\n    -1\n");
    let back = uff::parse(&bytes, "mixed.uff").unwrap();
    assert_eq!(back.len(), 1);
    let Ordinate::Real(y) = &back[0].ordinate else {
        panic!()
    };
    assert_eq!(y[1], 1.0);
    assert_eq!(y[0].to_bits(), trap.to_bits());
}

fn uff_error(bytes: &[u8]) -> (usize, u64, String) {
    match uff::parse(bytes, "bad.uff") {
        Err(e @ Error::Uff { .. }) => {
            assert_eq!(e.kind(), "malformed_uff");
            assert!(e.to_string().starts_with("bad.uff, block "), "{e}");
            let Error::Uff {
                block,
                line,
                message,
                ..
            } = e
            else {
                unreachable!()
            };
            (block, line, message)
        }
        other => panic!("expected a UFF error, got {other:?}"),
    }
}

#[test]
fn errors_name_block_and_line() {
    // Second block (after a skipped one), a value that is not a number on line 18.
    let text = format!(
        "    -1\n   164\nunits\n    -1\n{}",
        block(R7_REAL4, "  1.00000E+00  2.00000E+00\n  3.0000xE+00\n")
    );
    let (b, l, m) = uff_error(text.as_bytes());
    assert_eq!((b, l), (2, 19), "{m}");
    assert!(m.contains("3.0000xE+00"), "{m}");

    // Too few values: the closing -1 (line 15) names the count.
    let (b, l, m) = uff_error(block(R7_REAL4, "  1.00000E+00\n").as_bytes());
    assert_eq!((b, l), (1, 15));
    assert!(m.contains("1 of the 4 values"), "{m}");

    // Too many: on a line of their own, or not zeros filling the last line.
    let (_, l, m) = uff_error(block(R7_REAL4, " 1 2 3 4\n 5\n").as_bytes());
    assert_eq!(l, 15);
    assert!(m.contains("more than"), "{m}");
    let (_, l, m) = uff_error(block(R7_REAL4, " 1 2 3 4 5\n").as_bytes());
    assert_eq!(l, 14);
    assert!(m.contains("more than"), "{m}");
    let text = block(R7_REAL4, " 1 2 3 4 0 0\n");
    assert_eq!(
        uff::parse(text.as_bytes(), "t").unwrap()[0].ordinate.len(),
        4
    );

    // Unknown ordinate type, on record 7 (line 9).
    let r7 = R7_REAL4.replacen("         2", "         3", 1);
    let (_, l, m) = uff_error(block(&r7, " 1 2 3 4\n").as_bytes());
    assert_eq!(l, 9);
    assert!(m.contains("ordinate type 3"), "{m}");

    // A header integer that is not one (record 6, line 8).
    let text = block(R7_REAL4, " 1 2 3 4\n").replacen("    1         0", "    x         0", 1);
    let (_, l, m) = uff_error(text.as_bytes());
    assert_eq!(l, 8);
    assert!(m.contains("function type"), "{m}");

    // A block never closed; text outside a block.
    let (_, _, m) = uff_error(b"    -1\n  2411\n 1 2\n");
    assert!(m.contains("not closed"), "{m}");
    let (b, l, m) = uff_error(b"hello\n");
    assert_eq!((b, l), (1, 1));
    assert!(m.contains("outside a block"), "{m}");

    // 58b: a byte count larger than the bytes present, or than the points take.
    let f = Function::time_response(1, 1, 13, 0.0, 1e-3, vec![1.0; 4]);
    let mut bytes = Vec::new();
    uff::write_binary(&mut bytes, &[f], ByteOrder::Big).unwrap();
    let (_, l, m) = uff_error(&bytes[..bytes.len() - 12]);
    assert_eq!(l, 13);
    assert!(m.contains("holds"), "{m}");
    let text = String::from_utf8_lossy(&bytes).replacen("          32", "   999999999", 1);
    let (_, _, m) = uff_error(text.as_bytes());
    assert!(m.contains("999999999 bytes"), "{m}");
    // A huge count of points in record 7 allocates nothing: a count past the readers' size
    // rule is refused from the header, before any value is read.
    let r7 = R7_REAL4.replacen("         4", "2000000000", 1);
    let e = uff::parse(block(&r7, " 1 2 3 4\n").as_bytes(), "bad.uff").unwrap_err();
    assert_eq!(e.kind(), "too_large", "{e}");
    assert!(e.to_string().contains("bad.uff"), "{e}");
    // A count within the rule but past the values there names what is missing.
    let r7 = R7_REAL4.replacen("         4", "  20000000", 1);
    let (_, _, m) = uff_error(block(&r7, " 1 2 3 4\n").as_bytes());
    assert!(m.contains("4 of the 20000000"), "{m}");
}

fn valid_file() -> Vec<u8> {
    let fs = layouts();
    let mut bytes = Vec::new();
    uff::write(&mut bytes, &fs[..4]).unwrap();
    uff::write_binary(&mut bytes, &fs[4..], ByteOrder::Big).unwrap();
    bytes
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// Arbitrary bytes, and valid files with bytes changed, cut or inserted: never a panic;
    /// every error is a UFF error.
    #[test]
    fn parse_never_panics(
        noise in proptest::collection::vec(any::<u8>(), 0..400),
        edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0u8..3), 0..6),
        cut in any::<prop::sample::Index>(),
    ) {
        if let Err(e) = uff::parse(&noise, "noise") {
            prop_assert_eq!(e.kind(), "malformed_uff");
        }
        let mut bytes = valid_file();
        for (at, b, op) in edits {
            let i = at.index(bytes.len());
            match op {
                0 => bytes[i] = b,
                1 => bytes.insert(i, b),
                _ => { bytes.remove(i); }
            }
        }
        let i = cut.index(bytes.len() + 1);
        for data in [&bytes[..], &bytes[..i]] {
            if let Err(e) = uff::parse(data, "edited") {
                prop_assert_eq!(e.kind(), "malformed_uff");
                prop_assert!(e.to_string().len() < 400);
            }
        }
    }
}

/// Noise-free simulated impact records of the seed's rig, sampled at 5000 Hz (an interval that
/// `E13.5` holds exactly), 2 hits per direction, with 1 % noise.
fn simulated() -> Vec<bearing_ident::Record> {
    use bearing_ident::simulate::{ImpactTest, seed_rig};
    let test = ImpactTest {
        per_direction: 2,
        sample_rate: 5000.0,
        noise: 0.01,
        ..ImpactTest::seed_rig()
    };
    test.run(&seed_rig()).unwrap()
}

/// The time histories of a record: forces (data type 13) and displacements (8) in X and Y,
/// written in a shuffled order with load case `lc`.
fn histories(r: &bearing_ident::Record, lc: i64) -> Vec<Function> {
    let dt = 1.0 / r.sample_rate();
    let mut out = Vec::new();
    for i in (0..r.dofs()).rev() {
        let dir = i as i64 + 1;
        out.push(Function::time_response(
            7,
            dir,
            8,
            0.0,
            dt,
            r.displacement(i).to_vec(),
        ));
        out.push(Function::time_response(
            7,
            dir,
            13,
            0.0,
            dt,
            r.force(i).to_vec(),
        ));
    }
    for f in &mut out {
        f.load_case = lc;
    }
    out
}

#[test]
fn records_from_uff_identify_as_the_originals() {
    use bearing_ident::{Identifier, Method};
    let records = simulated();
    // One file, every record a load case, binary double: samples back exactly.
    let functions: Vec<Function> = records
        .iter()
        .enumerate()
        .flat_map(|(k, r)| histories(r, k as i64 + 1))
        .collect();
    let mut bytes = Vec::new();
    uff::write_binary(&mut bytes, &functions, ByteOrder::Little).unwrap();
    let back = uff::records(&uff::parse(&bytes, "rig.uff").unwrap(), "rig.uff").unwrap();
    assert_eq!(back.len(), records.len());
    for (k, (a, b)) in back.iter().zip(&records).enumerate() {
        assert_eq!(a.label(), format!("rig.uff#{}", k + 1));
        assert_eq!(a.dofs(), 2);
        assert!((a.sample_rate() / b.sample_rate() - 1.0).abs() < 1e-15);
        for i in 0..2 {
            assert_eq!(a.force(i), b.force(i));
            assert_eq!(a.displacement(i), b.displacement(i));
        }
    }
    let id = |rs: &[bearing_ident::Record]| {
        Identifier::new(8.0, 49.0)
            .method(Method::Ivf)
            .identify(rs)
            .unwrap()
    };
    let truth = id(&records);
    for got in [id(&back), {
        // ASCII (thirteen digits), one record per load case too.
        let mut text = Vec::new();
        uff::write(&mut text, &functions).unwrap();
        id(&uff::records(&uff::parse(&text, "rig.unv").unwrap(), "rig.unv").unwrap())
    }] {
        let (g, t) = (got.coefficients(), truth.coefficients());
        for (a, b) in [
            (g.mass(), t.mass()),
            (g.damping(), t.damping()),
            (g.stiffness(), t.stiffness()),
        ] {
            let e = crate::common::matrix_relative_error(a, b);
            assert!(e < 1e-12, "{e:e}");
        }
    }
}

#[test]
fn records_errors_name_the_load_case() {
    let mut f = Function::time_response(1, 1, 13, 0.0, 1e-3, vec![1.0; 16]);
    f.load_case = 5;
    let e = uff::records(std::slice::from_ref(&f), "a.uff").unwrap_err();
    assert_eq!(e.kind(), "inconsistent_records");
    assert!(
        e.to_string().starts_with("a.uff: load case 5: 1 force"),
        "{e}"
    );
    let mut x = Function::time_response(1, 1, 8, 0.0, 2e-3, vec![1.0; 16]);
    x.load_case = 5;
    let e = uff::records(&[f.clone(), x.clone()], "a.uff").unwrap_err();
    assert!(e.to_string().contains("increments differ"), "{e}");
    x.abscissa = Abscissa::Uneven(vec![0.0; 16]);
    let e = uff::records(&[f, x], "a.uff").unwrap_err();
    assert!(e.to_string().contains("uneven"), "{e}");
    let e = uff::records(&[], "a.uff").unwrap_err();
    assert!(e.to_string().contains("no time history"), "{e}");
}

#[cfg(feature = "cli")]
mod cli {
    use super::*;
    use serde_json::Value;

    use crate::common::run;
    fn json(args: &[&str]) -> Value {
        let out = run(args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).expect("valid JSON")
    }

    fn path(dir: &Path, name: &str) -> String {
        dir.join(name).display().to_string()
    }

    #[test]
    fn inspect_json_lists_every_field_and_value() {
        let Some(dir) = data("inspect_json_lists_every_field_and_value") else {
            return;
        };
        let v = json(&[
            "inspect",
            "--json",
            &path(&dir, "dataset58_case7_ascii.unv"),
            &path(&dir, "dataset58_coh.unv"),
        ]);
        let records = v["records"].as_array().unwrap();
        assert_eq!(records.len(), 2);
        let r = &records[0];
        assert_eq!(r["function_type"], 4);
        assert_eq!(r["ordinate_type"], 6);
        assert_eq!(r["n"], 801);
        assert_eq!(r["even"], true);
        assert_eq!(r["x0"], 0.0);
        assert_eq!(r["dx"], 0.25);
        assert_eq!(r["response_node"], 1);
        assert_eq!(r["response_dir"], 1);
        assert_eq!(r["reference_node"], 22);
        assert_eq!(r["reference_dir"], 1);
        assert_eq!(r["abscissa_type"], 18);
        assert_eq!(r["ordinate_type_num"], 12);
        assert_eq!(r["id"].as_array().unwrap().len(), 5);
        assert_eq!(r["id"][2], "28-Jan-21 14:01:42");
        assert_eq!(r["x"].as_array().unwrap().len(), 801);
        assert_eq!(r["x"][800], 200.0);
        assert_eq!(r["re"][0], 1.733310054988e-4);
        assert_eq!(r["im"][1], -1.329629958491e-5);
        let c = &records[1];
        assert_eq!(c["function_type"], 6);
        assert_eq!(c["ordinate_type"], 2);
        assert_eq!(c["re"][0], 0.369221);
        assert!(c["im"].is_null());
    }

    #[test]
    fn inspect_table_and_errors() {
        let Some(dir) = data("inspect_table_and_errors") else {
            return;
        };
        let out = run(&["inspect", &path(&dir, "dataset58_case4_binary.unv")]);
        assert!(out.status.success());
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(text.contains("1 dataset 58 function\n"), "{text}");
        assert!(text.contains("Frf"), "{text}");
        assert!(text.contains("complex single"), "{text}");
        assert!(text.contains("uneven"), "{text}");
        assert!(text.contains("1+X") && text.contains("22+X"), "{text}");
    }

    #[test]
    fn inspect_errors_name_block_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let bad = dir.path().join("bad.uff");
        std::fs::write(&bad, "    -1\n    58\n").unwrap();
        let out = run(&["inspect", "--json", bad.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2));
        let v: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["error"], "malformed_uff");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("bad.uff, block 1, line 2"), "{stderr}");
    }

    /// The table's first line counts the functions in words: "1 dataset 58 function",
    /// "2 dataset 58 functions".
    #[test]
    fn inspect_counts_functions_singular_and_plural() {
        let dir = tempfile::tempdir().unwrap();
        let functions = histories(&simulated()[0], 1);
        for n in [1, 2] {
            let file = dir.path().join(format!("{n}.uff"));
            let mut out = std::fs::File::create(&file).unwrap();
            uff::write(&mut out, &functions[..n]).unwrap();
            drop(out);
            let out = run(&["inspect", file.to_str().unwrap()]);
            assert!(out.status.success());
            let text = String::from_utf8(out.stdout).unwrap();
            let word = if n == 1 { "function" } else { "functions" };
            let first = text.lines().next().unwrap_or_default();
            assert!(
                first.ends_with(&format!("{n} dataset 58 {word}")),
                "{first}"
            );
        }
    }

    #[test]
    fn identify_reads_uff_as_csv() {
        let records = simulated();
        let dir = tempfile::tempdir().unwrap();
        let mut csv = Vec::new();
        let layout = bearing_ident::io::CsvLayout::for_dofs(2);
        let mut functions = Vec::new();
        for (k, r) in records.iter().enumerate() {
            let p = dir.path().join(format!("r{k}.csv"));
            bearing_ident::io::write_record(&p, r, &layout).unwrap();
            csv.push(p.display().to_string());
            functions.extend(histories(r, k as i64));
        }
        // Every record in one binary file, as load cases.
        let uff_path = dir.path().join("all.uff");
        let mut file = std::fs::File::create(&uff_path).unwrap();
        uff::write_binary(&mut file, &functions, ByteOrder::Little).unwrap();
        let args = ["identify", "--json", "--band", "8,49"];
        let from_csv = json(
            &[
                &args[..],
                &csv.iter().map(String::as_str).collect::<Vec<_>>(),
            ]
            .concat(),
        );
        let from_uff = json(&[&args[..], &[uff_path.to_str().unwrap()]].concat());
        assert_eq!(from_uff["n_records"], from_csv["n_records"]);
        assert_eq!(from_csv["n_records"], records.len());
        for key in ["M", "C", "K"] {
            let (a, b) = (&from_uff[key], &from_csv[key]);
            let norm: f64 = b
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
                .map(|x| x * x)
                .sum::<f64>()
                .sqrt();
            for i in 0..2 {
                for j in 0..2 {
                    let (x, y) = (a[i][j].as_f64().unwrap(), b[i][j].as_f64().unwrap());
                    assert!((x - y).abs() <= 1e-12 * norm, "{key}[{i}][{j}]: {x} vs {y}");
                }
            }
        }
    }
}
