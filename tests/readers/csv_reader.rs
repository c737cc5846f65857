//! The CSV reader against an independent reference: every value bit for bit `str::parse`'s,
//! and on messy inputs (quotes, CRLF, blank lines, whitespace, ragged rows, bad numbers) the
//! same record or the same error kind and line as a plain csv-crate reader (the reader before
//! the fast path: csv with trimmed fields, `str::parse` on each).

use bearing_ident::Error;
use bearing_ident::io::{CsvLayout, CsvReader, read_record_from};
use proptest::prelude::*;

fn layout1() -> CsvLayout {
    CsvLayout {
        time: "t".into(),
        forces: vec!["fx".into()],
        displacements: vec!["x".into()],
    }
}

/// The reference: the channels in layout order (time first), or the error's kind and line.
fn reference(text: &[u8], layout: &CsvLayout) -> Result<Vec<Vec<f64>>, (&'static str, u64)> {
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text);
    let line = |e: &csv::Error| e.position().map_or(0, csv::Position::line);
    let header = rdr.byte_headers().map_err(|e| ("csv", line(&e)))?.clone();
    let names: Vec<&String> = std::iter::once(&layout.time)
        .chain(&layout.forces)
        .chain(&layout.displacements)
        .collect();
    let index: Vec<usize> = names
        .iter()
        .map(|c| header.iter().position(|h| h == c.as_bytes()))
        .collect::<Option<_>>()
        .ok_or(("missing_column", 0))?;
    let mut columns = vec![Vec::new(); index.len()];
    let mut row = csv::ByteRecord::new();
    while rdr
        .read_byte_record(&mut row)
        .map_err(|e| ("csv", line(&e)))?
    {
        let l = row.position().map_or(0, csv::Position::line);
        for (col, &i) in columns.iter_mut().zip(&index) {
            let v = std::str::from_utf8(&row[i])
                .ok()
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or(("csv", l))?;
            if !v.is_finite() {
                return Err(("csv_non_finite", l));
            }
            col.push(v);
        }
    }
    Ok(columns)
}

/// The reader's result in the reference's terms; record-level errors (time grid, length) as
/// `None`.
fn ours(text: &[u8], layout: &CsvLayout) -> Result<Vec<Vec<f64>>, Option<(&'static str, u64)>> {
    match CsvReader::new(layout.clone()).read_from(text, "f.csv") {
        Ok(r) => {
            let t: Vec<f64> = (0..r.len()).map(|m| m as f64).collect();
            let mut c = vec![t];
            c.extend((0..r.dofs()).map(|i| r.force(i).to_vec()));
            c.extend((0..r.dofs()).map(|i| r.displacement(i).to_vec()));
            Ok(c)
        }
        Err(Error::Csv { line, .. }) => Err(Some(("csv", line))),
        Err(Error::CsvNonFinite { line, .. }) => Err(Some(("csv_non_finite", line))),
        Err(Error::MissingColumn { .. }) => Err(Some(("missing_column", 0))),
        Err(_) => Err(None),
    }
}

fn same(text: &[u8], layout: &CsvLayout) {
    let want = reference(text, layout);
    let got = ours(text, layout);
    let shown = String::from_utf8_lossy(text);
    match (&want, &got) {
        (Ok(w), Ok(g)) => {
            for (a, b) in w[1..].iter().zip(&g[1..]) {
                let (a, b): (Vec<u64>, Vec<u64>) = (
                    a.iter().map(|v| v.to_bits()).collect(),
                    b.iter().map(|v| v.to_bits()).collect(),
                );
                assert_eq!(a, b, "{shown:?}");
            }
        }
        // A record-level error (time off its grid, too few rows) on channels read alike.
        (Ok(_), Err(None)) => {}
        (Err(w), Err(Some(g))) => assert_eq!(w, g, "{shown:?}"),
        _ => panic!("{shown:?}: reference {want:?}, ours {got:?}"),
    }
}

/// Every value as `str::parse` reads it, in each of Rust's float formats.
fn values_round_trip(values: &[f64], format: usize) {
    let fmt = |v: f64| match format {
        0 => format!("{v}"),
        1 => format!("{v:e}"),
        _ => format!("{v:.17e}"),
    };
    let mut text = String::from("t,fx,x\n");
    for (m, &v) in values.iter().enumerate() {
        text += &format!("{},{},{}\n", m, fmt(v), fmt(-v));
    }
    let rec = read_record_from(text.as_bytes(), "f.csv", &layout1()).expect("reads");
    for (m, &v) in values.iter().enumerate() {
        let want: f64 = fmt(v).parse().expect("std parses");
        assert_eq!(rec.force(0)[m].to_bits(), want.to_bits(), "{}", fmt(v));
        let want: f64 = fmt(-v).parse().expect("std parses");
        assert_eq!(rec.displacement(0)[m].to_bits(), want.to_bits());
    }
}

#[test]
fn tricky_numbers_parse_as_std_does() {
    let tricky = [
        "0",
        "-0",
        "+1",
        "1.",
        ".5",
        "-.5",
        "+.5e-3",
        "1.e5",
        "1E+5",
        "1e-5",
        "5e-324",
        "4.9406564584124654e-324",
        "2.4703282292062327e-324",
        "2.4703282292062328e-324",
        "2.2250738585072011e-308",
        "2.2250738585072014e-308",
        "1.7976931348623157e308",
        "1.7976931348623158e308",
        "9007199254740993",
        "9007199254740992.9999999999999999999999",
        "0.1000000000000000055511151231257827021181583404541015625",
        "0.1000000000000000055511151231257827021181583404541015626",
        "123456789012345678901234567890e-30",
        "0.000000000000000000000000000000000000000000001e300",
        "00000000000000000000000000001.5",
        "1e-400",
        "-1e-400",
        "7.038531e-26",
        "3.0000000000000004",
        "  2.5  ",
        "\t-3e2",
    ];
    let mut text = String::from("t,fx,x\n");
    for (m, s) in tricky.iter().enumerate() {
        text += &format!("{m},{s},{s}\n");
    }
    let rec = read_record_from(text.as_bytes(), "f.csv", &layout1()).expect("reads");
    for (m, s) in tricky.iter().enumerate() {
        let want: f64 = s.trim().parse().expect("std parses");
        assert_eq!(rec.force(0)[m].to_bits(), want.to_bits(), "{s}");
        assert_eq!(rec.displacement(0)[m].to_bits(), want.to_bits(), "{s}");
    }
}

#[test]
fn what_std_rejects_is_an_error_on_its_line() {
    let bad = [
        "1e", "1e+", "e5", ".", "-", "+", "1.5e", "0x10", "1_000", "1,5x", "١", "1..2", "--1",
        "1e5e5", "in", "nan1", "1 2",
    ];
    for s in bad {
        let text = format!("t,fx,x\n0,0,0\n1,{s},0\n2,0,0\n");
        same(text.as_bytes(), &layout1());
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::Csv { line: 3, .. }), "{s}: {e:?}");
    }
    for s in ["inf", "-infinity", "NaN", "+nan", "1e400", "-1e309"] {
        let text = format!("t,fx,x\n0,0,0\n1,{s},0\n2,0,0\n");
        same(text.as_bytes(), &layout1());
    }
}

#[test]
fn quotes_crlf_and_blank_lines_read_as_the_csv_crate_does() {
    let body: String = (0..20)
        .map(|m| format!("{m},{}.5,-{m}e-3\n", m * 3))
        .collect();
    let header = "t,fx,x\n";
    let cases = [
        format!("{header}{body}"),
        format!("{header}{body}").replace('\n', "\r\n"),
        format!("\"t\",fx,x\n{body}"),
        format!("{header}{body}").replacen("3,9.5", "\"3\",\"9.5\"", 1),
        format!("{header}{body}").replacen("5,15.5", "5,\"15\n.5\"", 1),
        format!("{header}{body}").replacen("\n7,", "\n\n7,", 1),
        format!("{header}{body}").replacen("\n7,", "\r7,", 1),
        format!("{header}{body}").replacen("\n7,", "\n\"7\",", 1) + "20,1,x\n",
        format!("{header}{body}").replacen("\n7,", "\n\n7,", 1) + "20,1\n",
        format!("{header}{body}").replacen("\n7,", "\n 7 ,", 1),
        format!("\u{feff}{header}{body}"),
        format!(
            "x,t,y,fx,z\n{}",
            (0..20)
                .map(|m| format!("a,{m},b,{m},c\n"))
                .collect::<String>()
        ),
    ];
    for text in cases {
        same(text.as_bytes(), &layout1());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Random finite doubles printed with `{}`, `{:e}` and `{:.17e}` read back bit for bit as
    /// `str::parse` reads them.
    #[test]
    fn random_doubles_read_as_std_parses(
        bits in proptest::collection::vec(any::<u64>(), 1..64),
        format in 0usize..3,
    ) {
        let values: Vec<f64> = bits
            .iter()
            .map(|&b| f64::from_bits(b))
            .filter(|v| v.is_finite())
            .chain((0..8).map(f64::from))
            .collect();
        values_round_trip(&values, format);
    }

    /// Lines built of good, spaced, quoted, bad and missing fields, with blank lines: the same
    /// record or the same error and line as the csv crate.
    #[test]
    fn messy_files_read_as_the_csv_crate_does(
        rows in proptest::collection::vec(
            (proptest::collection::vec(0usize..10, 2..5), 0usize..8), 2..30),
    ) {
        let fields = ["1.5", " -2e-3 ", "\"7\"", "x", "", "nan", "1e400", "+.5", "3.", "\"1\r\n2\""];
        let mut text = String::from("t,fx,x\n");
        for (m, (cells, end)) in rows.iter().enumerate() {
            text += &m.to_string();
            for &c in cells {
                text.push(',');
                text += fields[c];
            }
            text += match end {
                0 => " \n",
                1 => "\n\n",
                _ => "\n",
            };
        }
        same(text.as_bytes(), &layout1());
    }
}

/// A CRLF file's errors name the line they are on. (The csv crate names the line before it:
/// it counts the `\n` of a `\r\n` only when the next record starts; the reader before the fast
/// path did too, so this is one difference, and only in messages.)
#[test]
fn crlf_lines_are_counted_as_lines() {
    let text = "t,fx,x\r\n0,0,0\r\n1,x,0\r\n2,0,0\r\n";
    let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
    assert!(matches!(e, Error::Csv { line: 3, .. }), "{e:?}");
    assert_eq!(reference(text.as_bytes(), &layout1()), Err(("csv", 2)));
}

/// One reader, many inputs: each record is read as a fresh reader reads it.
#[test]
fn a_reader_reused_reads_each_input_afresh() {
    let mut reader = CsvReader::new(layout1());
    let a: String =
        "t,fx,x\n".to_owned() + &(0..100).map(|m| format!("{m},{m},1\n")).collect::<String>();
    let b: String =
        "x,fx,t\n".to_owned() + &(0..9).map(|m| format!("2,{m},{m}\n")).collect::<String>();
    for text in [&a, &b, &a, &b] {
        let reused = reader.read_from(text.as_bytes(), "f.csv").expect("reads");
        let fresh = read_record_from(text.as_bytes(), "f.csv", &layout1()).expect("reads");
        assert_eq!(reused, fresh);
    }
    let e = reader
        .read_from("t,fx,x\n0,1\n".as_bytes(), "g.csv")
        .unwrap_err();
    assert!(matches!(e, Error::Csv { line: 2, .. }), "{e:?}");
    assert_eq!(
        reader
            .read_from(a.as_bytes(), "f.csv")
            .expect("reads")
            .len(),
        100
    );
}
