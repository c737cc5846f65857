//! MAT-files written by SciPy (`tests/mat/make_fixtures.py`): every layout reads back to the
//! samples of the CSV of the same data, bit for bit; what cannot be records and every kind of
//! bad file is a typed error naming the file; mutated files never panic.

use std::path::{Path, PathBuf};

use bearing_ident::Record;
use bearing_ident::job::{Channels, read_file};
use bearing_ident::mat;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/mat/fixtures")
        .join(name)
}

fn names(list: &str) -> Vec<String> {
    list.split(',')
        .map(str::to_owned)
        .filter(|s| !s.is_empty())
        .collect()
}

/// The records of `file` with channels `force`, `disp` and time `time`.
fn read(file: &str, force: &str, disp: &str, time: &str) -> bearing_ident::Result<Vec<Record>> {
    let path = fixture(file);
    let channels = Channels::named(
        &names(force),
        &names(disp),
        &[],
        time,
        std::slice::from_ref(&path),
    )?;
    read_file(&path, &channels)
}

fn csv(name: &str) -> Record {
    let path = fixture(name);
    read_file(&path, &Channels::default())
        .unwrap()
        .swap_remove(0)
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Same samples bit for bit; the same rate bit for bit when both come from a time vector.
fn assert_same(got: &Record, want: &Record, same_rate_bits: bool) {
    assert_eq!(got.dofs(), want.dofs());
    for i in 0..want.dofs() {
        assert_eq!(
            bits(got.force(i)),
            bits(want.force(i)),
            "{} force {i}",
            got.label()
        );
        assert_eq!(
            bits(got.displacement(i)),
            bits(want.displacement(i)),
            "{} displacement {i}",
            got.label()
        );
    }
    if same_rate_bits {
        assert_eq!(got.sample_rate().to_bits(), want.sample_rate().to_bits());
    } else {
        assert_eq!(got.sample_rate(), 1000.0);
        let relative = (want.sample_rate() / 1000.0 - 1.0).abs();
        assert!(relative < 1e-12, "{relative}");
    }
}

#[test]
fn variables_uncompressed_and_compressed_read_as_the_csv() {
    let a = csv("a.csv");
    for file in ["plain.mat", "compressed.mat"] {
        let r = read(file, "", "", "t").unwrap();
        assert_eq!(r.len(), 1, "{file}");
        assert_same(&r[0], &a, true);
        assert!(r[0].label().ends_with(file), "{}", r[0].label());
    }
}

#[test]
fn matrix_columns_counted_from_one_read_as_the_csv() {
    let r = read("matrix.mat", "data:2,data:3", "data:4,data:5", "data:1").unwrap();
    assert_eq!(r.len(), 1);
    assert_same(&r[0], &csv("a.csv"), true);
    let e = read("matrix.mat", "data,data:3", "data:4,data:5", "data:1").unwrap_err();
    assert_eq!(e.kind(), "inconsistent_records");
    assert!(
        e.to_string().contains("512×5 matrix: name one column"),
        "{e}"
    );
    let e = read("matrix.mat", "data:6,data:3", "data:4,data:5", "data:1").unwrap_err();
    assert!(
        e.to_string()
            .contains("column 6 of a 512×5 double, which has 5 columns"),
        "{e}"
    );
}

#[test]
fn struct_fields_with_a_scalar_rate_read_as_the_csv() {
    let r = read("struct.mat", "rec.fx,rec.fy", "rec.x,rec.y", "rec.t").unwrap();
    assert_eq!(r.len(), 1);
    assert_same(&r[0], &csv("a.csv"), false);
    let e = read("struct.mat", "rec.fx,rec.fz", "rec.x,rec.y", "rec.t").unwrap_err();
    assert_eq!(e.kind(), "inconsistent_records");
    let message = e.to_string();
    assert!(
        message.contains("`rec.fz`: no `fz` here; there are: fx, fy, x, y, fs"),
        "{message}"
    );
    assert!(message.contains("struct.mat"), "{message}");
}

#[test]
fn struct_and_cell_arrays_give_a_record_per_element_in_order() {
    let (a, b) = (csv("a.csv"), csv("b.csv"));
    for (file, prefix) in [("struct_array.mat", "recs"), ("cell.mat", "hits")] {
        let f = format!("{prefix}.fx,{prefix}.fy");
        let x = format!("{prefix}.x,{prefix}.y");
        let r = read(file, &f, &x, "t").unwrap();
        assert_eq!(r.len(), 2, "{file}");
        assert_same(&r[0], &a, false);
        assert_same(&r[1], &b, false);
        assert!(
            r[1].label().ends_with(&format!("{file}(2)")),
            "{}",
            r[1].label()
        );
    }
}

#[test]
fn no_rate_is_an_error_unless_given() {
    // matrix.mat holds no `t`, `fs`, `Fs`, `rate` or `dt`.
    let e = read("matrix.mat", "data:2,data:3", "data:4,data:5", "t").unwrap_err();
    assert_eq!(e.kind(), "inconsistent_records");
    assert!(e.to_string().contains("give --rate"), "{e}");
    let path = fixture("matrix.mat");
    let mut channels = Channels::named(
        &names("data:2,data:3"),
        &names("data:4,data:5"),
        &[],
        "t",
        std::slice::from_ref(&path),
    )
    .unwrap();
    channels.mat.rate = Some(1000.0);
    let r = read_file(&path, &channels).unwrap();
    assert_eq!(r[0].sample_rate(), 1000.0);
    assert_eq!(bits(r[0].force(0)), bits(csv("a.csv").force(0)));
}

#[test]
fn text_and_complex_numbers_are_not_channels() {
    let e = read("wrong_classes.mat", "fx", "x", "t").unwrap_err();
    assert_eq!(e.kind(), "inconsistent_records");
    assert!(
        e.to_string().ends_with("`fx`: a 1×12 char, not numbers"),
        "{e}"
    );
    let e = read("wrong_classes.mat", "fy", "x", "t").unwrap_err();
    assert!(
        e.to_string()
            .ends_with("`fy`: a complex 1×512 double: a channel is real"),
        "{e}"
    );
}

fn bytes(name: &str) -> Vec<u8> {
    std::fs::read(fixture(name)).unwrap()
}

fn parse_error(data: &[u8]) -> String {
    let e = mat::parse(data, "bad.mat").unwrap_err();
    assert_eq!(e.kind(), "malformed_mat", "{e}");
    let message = e.to_string();
    assert!(message.starts_with("bad.mat, byte "), "{message}");
    message
}

#[test]
fn a_truncated_file_is_malformed_at_every_length() {
    for name in ["plain.mat", "compressed.mat", "struct_array.mat"] {
        let data = bytes(name);
        // Every cut inside the header, then every 97th byte, then the last few.
        let cuts = (0..130)
            .chain((130..data.len()).step_by(97))
            .chain(data.len() - 9..data.len());
        for cut in cuts {
            match mat::parse(&data[..cut], "bad.mat") {
                // A cut between two variables leaves whole variables.
                Ok(vars) => assert!(vars.len() < 5, "{name} cut at {cut}"),
                Err(e) => assert_eq!(e.kind(), "malformed_mat", "{name} cut at {cut}: {e}"),
            }
        }
    }
    let m = parse_error(&bytes("plain.mat")[..200]);
    assert!(m.contains("truncated"), "{m}");
    let m = parse_error(&bytes("plain.mat")[..100]);
    assert!(m.contains("shorter than the 128-byte header"), "{m}");
}

#[test]
fn bad_zlib_data_is_malformed() {
    let mut data = bytes("compressed.mat");
    // The first element is miCOMPRESSED: its zlib stream starts at byte 136 (a two-byte
    // header); a first deflate block of type 3 (reserved) does not inflate.
    assert_eq!(u32::from_le_bytes(data[128..132].try_into().unwrap()), 15);
    data[138..146].fill(0xff);
    let m = parse_error(&data);
    assert!(m.contains("bad zlib data"), "{m}");
}

#[test]
fn lying_and_huge_sizes_are_refused_before_allocating() {
    // A byte count past the end of the file.
    let mut data = bytes("plain.mat");
    data[132..136].copy_from_slice(&0x7fff_fff0u32.to_le_bytes());
    let m = parse_error(&data);
    assert!(
        m.contains("truncated: an element of type 14 declares 2147483632 bytes"),
        "{m}"
    );
    // Dimensions of 2³¹−1 × 2³¹−1 in a variable of a few kilobytes.
    let mut data = bytes("plain.mat");
    assert_eq!(u32::from_le_bytes(data[152..156].try_into().unwrap()), 5);
    data[160..168].copy_from_slice(&[0xff, 0xff, 0xff, 0x7f, 0xff, 0xff, 0xff, 0x7f]);
    let m = parse_error(&data);
    assert!(m.contains("more elements than its"), "{m}");
    // Not a MAT-file; a -v7.3 file.
    let m = parse_error(&[b'x'; 200]);
    assert!(m.contains("not a level 5 MAT-file"), "{m}");
    let mut v73 = b"MATLAB 7.3 MAT-file".to_vec();
    v73.resize(600, 0);
    let m = parse_error(&v73);
    assert!(m.contains("no HDF5 signature at byte 0, 512"), "{m}");
}

#[test]
fn nesting_past_the_limit_is_malformed() {
    // A cell holding a cell holding … 40 deep, each a 1×1 cell with an empty name.
    let le = |v: u32| v.to_le_bytes();
    let mut inner: Vec<u8> = Vec::new();
    for depth in 0..40 {
        let mut body = [&le(6)[..], &le(8), &[1, 0, 0, 0, 0, 0, 0, 0]].concat(); // flags: cell
        body.extend([&le(5)[..], &le(8), &le(1), &le(1)].concat()); // dims 1×1
        let name: &[u8] = if depth == 39 { b"c\0\0\0" } else { b"\0\0\0\0" };
        body.extend([&le(0x0001_0001)[..], name].concat()); // name, small format
        if depth > 0 {
            body.extend(&inner);
        } else {
            body.extend([&le(14)[..], &le(0)].concat()); // an empty cell
        }
        inner = [&le(14)[..], &le(body.len() as u32), &body].concat();
    }
    let mut file = vec![b' '; 116];
    file.extend([0; 8]);
    file.extend([0x00, 0x01, b'I', b'M']);
    file.extend(&inner);
    let m = parse_error(&file);
    assert!(m.contains("nested deeper than 32"), "{m}");
}

/// A small deterministic generator (splitmix64) for the mutations below.
fn next(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[test]
fn mutated_files_give_records_or_typed_errors_never_a_panic() {
    let layouts = [
        ("plain.mat", "fx,fy", "x,y", "t"),
        ("compressed.mat", "fx,fy", "x,y", "t"),
        ("struct_array.mat", "recs.fx,recs.fy", "recs.x,recs.y", "t"),
        ("cell.mat", "hits.fx,hits.fy", "hits.x,hits.y", "t"),
        ("plain_v73.mat", "fx,fy", "x,y", "t"),
        ("compressed_v73.mat", "fx,fy", "x,y", "t"),
        ("latest_v73.mat", "fx,fy", "x,y", "t"),
        (
            "struct_array_v73.mat",
            "recs.fx,recs.fy",
            "recs.x,recs.y",
            "t",
        ),
        ("cell_v73.mat", "hits.fx,hits.fy", "hits.x,hits.y", "t"),
    ];
    let mut state = 38;
    for (name, force, disp, time) in layouts {
        let original = bytes(name);
        let path = fixture(name);
        let channels = Channels::named(
            &names(force),
            &names(disp),
            &[],
            time,
            std::slice::from_ref(&path),
        )
        .unwrap();
        for _ in 0..400 {
            let mut data = original.clone();
            for _ in 0..1 + next(&mut state) % 4 {
                let at = (next(&mut state) as usize) % data.len();
                match next(&mut state) % 4 {
                    0 => data[at] = next(&mut state) as u8,
                    1 => data[at] ^= 1 << (next(&mut state) % 8),
                    2 => data.truncate(at.max(1)),
                    _ => {
                        let word = [0xff, 0xff, 0xff, 0x7f];
                        let end = (at + 4).min(data.len());
                        data[at..end].copy_from_slice(&word[..end - at]);
                    }
                }
            }
            match mat::parse(&data, name) {
                Ok(vars) => {
                    if let Err(e) = mat::records(&vars, name, &channels.mat) {
                        assert!(
                            matches!(
                                e.kind().as_str(),
                                "inconsistent_records"
                                    | "invalid_argument"
                                    | "non_finite"
                                    | "record_too_short"
                                    | "invalid_sample_rate"
                            ),
                            "{e}"
                        );
                    }
                }
                Err(e) => {
                    assert_eq!(e.kind(), "malformed_mat", "{e}");
                    assert!(e.to_string().len() < 300, "{e}");
                }
            }
        }
    }
}

// MATLAB -v7.3 (HDF5) files written by h5py in MATLAB's layout.

#[test]
fn v73_variables_contiguous_chunked_and_new_style_read_as_the_csv() {
    let a = csv("a.csv");
    for file in ["plain_v73.mat", "compressed_v73.mat", "latest_v73.mat"] {
        let r = read(file, "", "", "t").unwrap();
        assert_eq!(r.len(), 1, "{file}");
        assert_same(&r[0], &a, true);
    }
    // Columns (N×1) and rows (1×N) as MATLAB saw them.
    let vars = mat::read(fixture("plain_v73.mat")).unwrap();
    let names: Vec<&str> = vars.iter().map(|v| v.name.as_str()).collect();
    assert_eq!(names, ["fx", "fy", "t", "x", "y"]);
    assert_eq!(vars[0].array.dims(), [512, 1]);
    assert_eq!(vars[0].array.class(), "double");
    let vars = mat::read(fixture("compressed_v73.mat")).unwrap();
    assert_eq!(vars[0].array.dims(), [1, 512]);
}

#[test]
fn v73_matrix_columns_are_matlab_columns() {
    let r = read("matrix_v73.mat", "data:2,data:3", "data:4,data:5", "data:1").unwrap();
    assert_eq!(r.len(), 1);
    assert_same(&r[0], &csv("a.csv"), true);
    let vars = mat::read(fixture("matrix_v73.mat")).unwrap();
    assert_eq!(vars[0].array.size_text(), "512×5");
    // The same matrix in 2×100 chunks (cut at both edges) reads to the same values.
    assert_eq!(vars[1].name, "tiles");
    let (data, tiles) = (vars[0].array.samples(), vars[1].array.samples());
    assert_eq!(bits(tiles.unwrap()), bits(data.unwrap()));
}

#[test]
fn v73_struct_fields_with_a_scalar_rate_read_as_the_csv() {
    let r = read("struct_v73.mat", "rec.fx,rec.fy", "rec.x,rec.y", "rec.t").unwrap();
    assert_eq!(r.len(), 1);
    assert_same(&r[0], &csv("a.csv"), false);
    let e = read("struct_v73.mat", "rec.fx,rec.fz", "rec.x,rec.y", "rec.t").unwrap_err();
    assert!(
        e.to_string()
            .contains("`rec.fz`: no `fz` here; there are: fs, fx, fy, x, y"),
        "{e}"
    );
}

#[test]
fn v73_struct_and_cell_arrays_give_a_record_per_element_in_order() {
    let (a, b) = (csv("a.csv"), csv("b.csv"));
    for (file, prefix) in [("struct_array_v73.mat", "recs"), ("cell_v73.mat", "hits")] {
        let f = format!("{prefix}.fx,{prefix}.fy");
        let x = format!("{prefix}.x,{prefix}.y");
        let r = read(file, &f, &x, "t").unwrap();
        assert_eq!(r.len(), 2, "{file}");
        assert_same(&r[0], &a, false);
        assert_same(&r[1], &b, false);
    }
    let vars = mat::read(fixture("struct_array_v73.mat")).unwrap();
    assert_eq!(vars[1].name, "recs");
    assert_eq!(vars[1].array.size_text(), "1×2");
}

#[test]
fn v73_text_and_complex_numbers_are_not_channels() {
    let e = read("wrong_classes_v73.mat", "fx", "x", "t").unwrap_err();
    assert!(
        e.to_string().ends_with("`fx`: a 1×12 char, not numbers"),
        "{e}"
    );
    let e = read("wrong_classes_v73.mat", "fy", "x", "t").unwrap_err();
    assert!(
        e.to_string()
            .ends_with("`fy`: a complex 1×512 double: a channel is real"),
        "{e}"
    );
}

#[test]
fn v73_cycles_are_malformed() {
    let m = parse_error(&bytes("cycle_v73.mat"));
    assert!(
        m.contains("`c{1}` refers back to an array that holds it"),
        "{m}"
    );
    let m = parse_error(&bytes("loop_v73.mat"));
    assert!(
        m.contains("`s.self` refers back to an array that holds it"),
        "{m}"
    );
}

/// Where the 16 bytes `pattern` start in `data` (once).
fn find(data: &[u8], pattern: &[u8]) -> usize {
    let hits: Vec<usize> = data
        .windows(pattern.len())
        .enumerate()
        .filter(|(_, w)| *w == pattern)
        .map(|(i, _)| i)
        .collect();
    assert!(!hits.is_empty(), "{pattern:?} not found");
    hits[0]
}

#[test]
fn v73_truncated_lying_and_foreign_files_are_malformed() {
    for name in [
        "plain_v73.mat",
        "compressed_v73.mat",
        "latest_v73.mat",
        "cell_v73.mat",
    ] {
        let data = bytes(name);
        let cuts = (0..700)
            .step_by(7)
            .chain((700..data.len()).step_by(61))
            .chain(data.len() - 9..data.len());
        for cut in cuts {
            match mat::parse(&data[..cut], "bad.mat") {
                Ok(vars) => assert!(vars.len() < 5, "{name} cut at {cut}"),
                Err(e) => assert_eq!(e.kind(), "malformed_mat", "{name} cut at {cut}: {e}"),
            }
        }
    }
    let m = parse_error(&bytes("plain_v73.mat")[..3000]);
    assert!(m.contains("past the end of the file"), "{m}");
    // Dimensions 1×2⁴⁰ in a dataspace that says 1×512.
    let mut data = bytes("plain_v73.mat");
    let dims = [1u64.to_le_bytes(), 512u64.to_le_bytes()].concat();
    let at = find(&data, &dims);
    data[at + 8..at + 16].copy_from_slice(&(1u64 << 40).to_le_bytes());
    let m = parse_error(&data);
    assert!(m.contains("more than a file of 25088 bytes holds"), "{m}");
    // Offsets of 4 bytes; a superblock version 9.
    let mut data = bytes("plain_v73.mat");
    data[512 + 13] = 4;
    let m = parse_error(&data);
    assert!(m.contains("HDF5 offsets of 4 bytes"), "{m}");
    data[512 + 8] = 9;
    let m = parse_error(&data);
    assert!(m.contains("superblock version 9"), "{m}");
}
