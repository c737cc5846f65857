//! The reader on hand-made segments: layouts nptdms does not write (big-endian,
//! interleaved, DAQmx raw data) and malformed files, each with its error kind.

use super::*;

/// A test writer of TDMS segments.
pub(super) struct Segment {
    pub toc: u32,
    pub meta: Vec<u8>,
    pub raw: Vec<u8>,
    pub big_endian: bool,
}

pub(super) fn put_u32(out: &mut Vec<u8>, v: u32, be: bool) {
    out.extend(if be { v.to_be_bytes() } else { v.to_le_bytes() });
}

pub(super) fn put_u64(out: &mut Vec<u8>, v: u64, be: bool) {
    out.extend(if be { v.to_be_bytes() } else { v.to_le_bytes() });
}

pub(super) fn put_str(out: &mut Vec<u8>, s: &str, be: bool) {
    put_u32(out, s.len() as u32, be);
    out.extend(s.as_bytes());
}

impl Segment {
    pub fn bytes(&self) -> Vec<u8> {
        let be = self.big_endian;
        let mut out = b"TDSm".to_vec();
        out.extend((self.toc | if be { 1 << 6 } else { 0 }).to_le_bytes());
        put_u32(&mut out, 4713, be);
        put_u64(&mut out, (self.meta.len() + self.raw.len()) as u64, be);
        put_u64(&mut out, self.meta.len() as u64, be);
        out.extend(&self.meta);
        out.extend(&self.raw);
        out
    }
}

/// Metadata of channels `/'g'/'NAME'` of doubles, `count` values each, with `wf_increment`.
fn meta(names: &[&str], data_type: u32, count: u64, be: bool) -> Vec<u8> {
    let mut m = Vec::new();
    put_u32(&mut m, names.len() as u32, be);
    for name in names {
        put_str(&mut m, &format!("/'g'/'{name}'"), be);
        put_u32(&mut m, 20, be);
        put_u32(&mut m, data_type, be);
        put_u32(&mut m, 1, be);
        put_u64(&mut m, count, be);
        put_u32(&mut m, 1, be);
        put_str(&mut m, "wf_increment", be);
        put_u32(&mut m, 10, be);
        m.extend(if be {
            0.5f64.to_be_bytes()
        } else {
            0.5f64.to_le_bytes()
        });
    }
    m
}

const META_RAW_NEW: u32 = (1 << 1) | (1 << 2) | (1 << 3);

fn values(file: &TdmsFile, name: &str) -> Vec<f64> {
    file.groups[0]
        .channels
        .iter()
        .find(|c| c.name == name)
        .unwrap()
        .values
        .clone()
}

#[test]
fn big_endian_contiguous_and_interleaved_segments_read_the_same_samples() {
    let a = [1.5f64, -2.0, 3.25];
    let b = [10i16, -20, 30];
    for be in [false, true] {
        for interleaved in [false, true] {
            let mut raw = Vec::new();
            let f = |v: f64| if be { v.to_be_bytes() } else { v.to_le_bytes() };
            let g = |v: i16| if be { v.to_be_bytes() } else { v.to_le_bytes() };
            if interleaved {
                for k in 0..3 {
                    raw.extend(f(a[k]));
                    raw.extend(g(b[k]));
                }
            } else {
                a.iter().for_each(|&v| raw.extend(f(v)));
                b.iter().for_each(|&v| raw.extend(g(v)));
            }
            let mut m = Vec::new();
            put_u32(&mut m, 2, be);
            for (name, ty) in [("a", 10u32), ("b", 2)] {
                put_str(&mut m, &format!("/'g'/'{name}'"), be);
                put_u32(&mut m, 20, be);
                put_u32(&mut m, ty, be);
                put_u32(&mut m, 1, be);
                put_u64(&mut m, 3, be);
                put_u32(&mut m, 0, be);
            }
            let toc = META_RAW_NEW | if interleaved { 1 << 5 } else { 0 };
            let file = parse(
                &Segment {
                    toc,
                    meta: m,
                    raw,
                    big_endian: be,
                }
                .bytes(),
                "t.tdms",
            )
            .unwrap();
            assert_eq!(values(&file, "a"), a, "be {be} interleaved {interleaved}");
            assert_eq!(values(&file, "b"), [10.0, -20.0, 30.0]);
        }
    }
}

#[test]
fn segments_without_metadata_reuse_the_previous_list_and_incremental_metadata_adds_to_it() {
    let raw = |v: &[f64]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let first = Segment {
        toc: META_RAW_NEW,
        meta: meta(&["a"], 10, 2, false),
        raw: raw(&[1.0, 2.0]),
        big_endian: false,
    };
    // Raw data only: the list and index of the segment before.
    let second = Segment {
        toc: 1 << 3,
        meta: Vec::new(),
        raw: raw(&[3.0, 4.0, 5.0, 6.0]),
        big_endian: false,
    };
    // Incremental: `b` added with its index, `a` keeps its own (index 0, "as before").
    let mut m = Vec::new();
    put_u32(&mut m, 2, false);
    put_str(&mut m, "/'g'/'a'", false);
    put_u32(&mut m, 0, false);
    put_u32(&mut m, 0, false);
    put_str(&mut m, "/'g'/'b'", false);
    put_u32(&mut m, 20, false);
    put_u32(&mut m, 3, false);
    put_u32(&mut m, 1, false);
    put_u64(&mut m, 2, false);
    put_u32(&mut m, 0, false);
    let mut r = raw(&[7.0, 8.0]);
    r.extend([9i32, 10].iter().flat_map(|x| x.to_le_bytes()));
    let third = Segment {
        toc: (1 << 1) | (1 << 3),
        meta: m,
        raw: r,
        big_endian: false,
    };
    let bytes = [first.bytes(), second.bytes(), third.bytes()].concat();
    let file = parse(&bytes, "t.tdms").unwrap();
    assert_eq!(values(&file, "a"), [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
    assert_eq!(values(&file, "b"), [9.0, 10.0]);
}

#[test]
fn daqmx_raw_data_with_a_linear_scale_is_decoded() {
    // Two channels sharing one raw buffer of 4 bytes per sample: i16 at offsets 0 and 2.
    let mut m = Vec::new();
    put_u32(&mut m, 2, false);
    for (name, offset) in [("a", 0u32), ("b", 2)] {
        put_str(&mut m, &format!("/'g'/'{name}'"), false);
        put_u32(&mut m, 0x6912_0000, false);
        put_u32(&mut m, 0xFFFF_FFFF, false);
        put_u32(&mut m, 1, false);
        put_u64(&mut m, 3, false);
        put_u32(&mut m, 1, false); // one scaler
        for v in [3, 0, offset, 0, 0] {
            put_u32(&mut m, v, false);
        }
        put_u32(&mut m, 1, false); // one raw buffer
        put_u32(&mut m, 4, false);
        put_u32(&mut m, 3, false);
        for (p, v) in [
            ("NI_Scale[0]_Scale_Type", None),
            ("NI_Scale[0]_Linear_Slope", Some(0.5)),
            ("NI_Scale[0]_Linear_Y_Intercept", Some(1.0)),
        ] {
            put_str(&mut m, p, false);
            match v {
                None => {
                    put_u32(&mut m, 0x20, false);
                    put_str(&mut m, "Linear", false);
                }
                Some(v) => {
                    put_u32(&mut m, 10, false);
                    m.extend(f64::to_le_bytes(v));
                }
            }
        }
    }
    let raw: Vec<u8> = [(2i16, -2i16), (4, -4), (6, -6)]
        .iter()
        .flat_map(|&(a, b)| [a.to_le_bytes(), b.to_le_bytes()].concat())
        .collect();
    let seg = Segment {
        toc: META_RAW_NEW | (1 << 7),
        meta: m,
        raw,
        big_endian: false,
    };
    let file = parse(&seg.bytes(), "daq.tdms").unwrap();
    assert_eq!(values(&file, "a"), [2.0, 3.0, 4.0]);
    assert_eq!(values(&file, "b"), [0.0, -1.0, -2.0]);
}

#[test]
fn polynomial_scaling_applies_its_coefficients_in_order() {
    let p = |name: &str, value: Value| Property {
        name: name.into(),
        value,
    };
    let props = vec![
        p("NI_Number_Of_Scales", Value::Uint(2)),
        p("NI_Scale[0]_Scale_Type", Value::Text("Linear".into())),
        p("NI_Scale[0]_Linear_Slope", Value::Float(2.0)),
        p("NI_Scale[0]_Linear_Y_Intercept", Value::Float(0.0)),
        p("NI_Scale[1]_Scale_Type", Value::Text("Polynomial".into())),
        p("NI_Scale[1]_Polynomial_Coefficients_Size", Value::Int(3)),
        p("NI_Scale[1]_Polynomial_Coefficients[0]", Value::Float(1.0)),
        p("NI_Scale[1]_Polynomial_Coefficients[1]", Value::Float(0.0)),
        p("NI_Scale[1]_Polynomial_Coefficients[2]", Value::Float(3.0)),
        p("NI_Scale[1]_Polynomial_Input_Source", Value::Uint(0)),
    ];
    let mut v = [1.0, 2.0];
    scaling::scale(&props, &mut v).unwrap();
    // x → 2x → 1 + 3(2x)².
    assert_eq!(v.map(f64::to_bits), [13.0f64, 49.0].map(f64::to_bits));
    let mut thermo = props.clone();
    thermo[4].value = Value::Text("Thermocouple".into());
    let e = scaling::scale(&thermo, &mut v).unwrap_err();
    assert!(e.contains("Thermocouple"), "{e}");
}

/// Every malformed file is a typed error naming the file, never a panic, and no allocation
/// follows a declared size before the bytes are there.
#[test]
fn malformed_files_are_typed_errors_naming_the_file() {
    let good = Segment {
        toc: META_RAW_NEW,
        meta: meta(&["a"], 10, 4, false),
        raw: [1.0f64, 2.0, 3.0, 4.0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect(),
        big_endian: false,
    };
    let bytes = good.bytes();
    assert_eq!(values(&parse(&bytes, "ok.tdms").unwrap(), "a").len(), 4);
    // Truncated anywhere: inside the lead-in, the metadata or the raw data.
    for cut in [3, 20, 40, bytes.len() - 1] {
        let e = parse(&bytes[..cut], "cut.tdms").unwrap_err();
        assert_eq!(e.kind(), "malformed_tdms", "{cut}: {e}");
        assert!(e.to_string().starts_with("cut.tdms, byte "), "{e}");
    }
    // Not a TDMS file.
    let e = parse(b"PK\x03\x04 and some more bytes of a zip file", "zip.tdms").unwrap_err();
    assert!(e.to_string().contains("TDSm"), "{e}");
    // A segment length that lies (past the file).
    let mut lying = bytes.clone();
    lying[12..20].copy_from_slice(&(1u64 << 40).to_le_bytes());
    let e = parse(&lying, "lying.tdms").unwrap_err();
    assert_eq!(e.kind(), "malformed_tdms");
    assert!(e.to_string().contains("1099511627776 bytes"), "{e}");
    // A huge declared number of values: not whole chunks of what is there, refused unallocated.
    let huge = Segment {
        toc: META_RAW_NEW,
        meta: meta(&["a"], 10, 1 << 60, false),
        raw: vec![0; 32],
        big_endian: false,
    };
    let e = parse(&huge.bytes(), "huge.tdms").unwrap_err();
    assert_eq!(e.kind(), "malformed_tdms");
    assert!(e.to_string().contains("not whole chunks"), "{e}");
    // A count whose byte size overflows.
    let e = parse(
        &Segment {
            meta: meta(&["a"], 10, u64::MAX / 2, false),
            ..huge
        }
        .bytes(),
        "o.tdms",
    )
    .unwrap_err();
    assert_eq!(e.kind(), "malformed_tdms", "{e}");
    // A huge declared string length in the metadata.
    let mut m = Vec::new();
    put_u32(&mut m, 1, false);
    put_u32(&mut m, u32::MAX, false);
    let e = parse(
        &Segment {
            toc: META_RAW_NEW,
            meta: m,
            raw: Vec::new(),
            big_endian: false,
        }
        .bytes(),
        "s.tdms",
    )
    .unwrap_err();
    assert_eq!(e.kind(), "malformed_tdms", "{e}");
    // Index "as before" for a channel that never had one.
    let mut m = Vec::new();
    put_u32(&mut m, 1, false);
    put_str(&mut m, "/'g'/'a'", false);
    put_u32(&mut m, 0, false);
    put_u32(&mut m, 0, false);
    let e = parse(
        &Segment {
            toc: META_RAW_NEW,
            meta: m,
            raw: Vec::new(),
            big_endian: false,
        }
        .bytes(),
        "r.tdms",
    )
    .unwrap_err();
    assert!(e.to_string().contains("never had"), "{e}");
}

#[test]
fn an_incomplete_last_segment_reads_its_whole_chunks() {
    let seg = Segment {
        toc: META_RAW_NEW,
        meta: meta(&["a"], 10, 2, false),
        raw: [1.0f64, 2.0, 3.0, 4.0, 5.0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect(),
        big_endian: false,
    };
    let mut bytes = seg.bytes();
    bytes[12..20].copy_from_slice(&u64::MAX.to_le_bytes());
    let file = parse(&bytes, "crash.tdms").unwrap();
    assert_eq!(values(&file, "a"), [1.0, 2.0, 3.0, 4.0]);
}

#[test]
fn names_with_quotes_and_slashes_split_by_their_quoting() {
    assert_eq!(
        parse::split_path_for_test("/'a/b'/'it''s'"),
        Some(vec!["a/b".into(), "it's".into()])
    );
    assert_eq!(parse::split_path_for_test("/"), Some(vec![]));
    assert_eq!(parse::split_path_for_test("/'open"), None);
}

/// Every byte of a valid two-segment file set to each of a few values, and every truncation:
/// a file or a typed error, never a panic, and never more values than bytes.
#[test]
fn every_single_byte_edit_is_a_file_or_a_typed_error() {
    let raw = |v: &[f64]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let mut bytes = Segment {
        toc: META_RAW_NEW | (1 << 5),
        meta: meta(&["fx", "x"], 10, 2, false),
        raw: raw(&[1.0, 2.0, 3.0, 4.0]),
        big_endian: false,
    }
    .bytes();
    bytes.extend(
        Segment {
            toc: 1 << 3,
            meta: Vec::new(),
            raw: raw(&[5.0, 6.0, 7.0, 8.0]),
            big_endian: false,
        }
        .bytes(),
    );
    let check = |b: &[u8]| match parse(b, "edit.tdms") {
        Ok(file) => {
            let n: usize = file
                .groups
                .iter()
                .flat_map(|g| &g.channels)
                .map(|c| c.values.len())
                .sum();
            assert!(n <= b.len());
            let layout = TdmsLayout {
                time: "t".into(),
                forces: vec!["fx".into()],
                responses: vec!["x".into()],
                record_by: RecordBy::Group,
                ..TdmsLayout::default()
            };
            let _ = records(&file, "edit.tdms", &layout);
        }
        Err(e) => assert!(
            matches!(e.kind().as_str(), "malformed_tdms" | "too_large"),
            "{e}"
        ),
    };
    for i in 0..bytes.len() {
        for v in [0u8, 1, 0x7F, 0x80, 0xFF, bytes[i] ^ 0x40] {
            let mut b = bytes.clone();
            b[i] = v;
            check(&b);
        }
        check(&bytes[..i]);
    }
}

/// A channel's `unit_string` converts it to SI; a given unit outranks it; a unit the file
/// states and the crate does not know is used as read with a warning naming file, channel and
/// unit; a unit of the wrong kind, or a given unit not known, is refused naming the channel.
#[test]
fn stated_units_convert_to_si_and_unknown_ones_warn() {
    let channel = |name: &str, unit: &str| Channel {
        name: name.into(),
        values: vec![1.0; 16],
        properties: vec![
            Property {
                name: "wf_increment".into(),
                value: Value::Float(0.001),
            },
            Property {
                name: "unit_string".into(),
                value: Value::Text(unit.into()),
            },
        ],
        ..Channel::default()
    };
    let file = |f: &str, x: &str| TdmsFile {
        groups: vec![Group {
            name: "g".into(),
            channels: vec![channel("fx", f), channel("x", x)],
            ..Group::default()
        }],
        ..TdmsFile::default()
    };
    let layout = TdmsLayout {
        forces: vec!["fx".into()],
        responses: vec!["x".into()],
        ..TdmsLayout::default()
    };
    let r = records(&file("lbf", "mil"), "us.tdms", &layout).unwrap();
    assert_eq!(r[0].force(0)[0].to_bits(), crate::units::LBF.to_bits());
    assert_eq!(
        r[0].displacement(0)[0].to_bits(),
        (1e-3 * crate::units::INCH).to_bits()
    );
    let given = TdmsLayout {
        force_units: vec!["N".into()],
        ..layout.clone()
    };
    assert_eq!(
        records(&file("lbf", "m"), "g.tdms", &given).unwrap()[0].force(0)[0].to_bits(),
        1f64.to_bits()
    );
    // Unknown in the file: the samples as read (SI), and a warning naming it.
    let r = records(&file("V", "mil"), "volts.tdms", &layout).unwrap();
    assert_eq!(r[0].force(0)[0].to_bits(), 1f64.to_bits());
    assert_eq!(
        r[0].displacement(0)[0].to_bits(),
        (1e-3 * crate::units::INCH).to_bits()
    );
    assert_eq!(
        r[0].warnings(),
        [crate::Warning::UnknownUnit {
            record: "volts.tdms".into(),
            channel: "fx".into(),
            unit: "V".into(),
            force: true,
        }]
    );
    assert_eq!(
        r[0].warnings()[0].to_string(),
        "record `volts.tdms`: channel `fx` has unit `V`, not one this crate converts: its \
         samples were used as read, in N; give --force-unit to convert them"
    );
    assert!(
        records(&file("N", "m"), "si.tdms", &layout).unwrap()[0]
            .warnings()
            .is_empty()
    );
    let unknown_given = TdmsLayout {
        response_units: vec!["furlong".into()],
        ..layout.clone()
    };
    for (f, x, layout, named) in [
        ("N", "lbf", &layout, "`lbf` is not a response unit"),
        (
            "N",
            "m",
            &unknown_given,
            "`furlong` is not one this reader converts",
        ),
    ] {
        let e = records(&file(f, x), "bad.tdms", layout).unwrap_err();
        assert_eq!(e.kind(), "unsupported", "{e}");
        assert!(e.to_string().contains(named), "{e}");
    }
    // Units given for more channels than there are: refused, never matched up by guess.
    let two = TdmsLayout {
        force_units: vec!["N".into(), "lbf".into()],
        ..layout.clone()
    };
    let e = records(&file("N", "m"), "bad.tdms", &two).unwrap_err();
    assert!(
        e.to_string()
            .contains("--force-unit names 2 units for 1 channels"),
        "{e}"
    );
}
