//! `bearing-ident inspect`: the dataset 58 / 58b functions of Universal Files, as a table or as
//! JSON with every value; the groups and channels of TDMS files with their properties
//! (`inspect/tdms.rs`); the variables of MAT-files (struct fields and cells below them), with
//! their class and size.

mod tdms;

use std::fmt::Write as _;
use std::path::PathBuf;

use bearing_ident::mat;
use bearing_ident::uff::{self, Abscissa, Function, Ordinate};
use serde_json::{Value, json};

use crate::failure::{Failure, print_out};

#[derive(Debug, clap::Args)]
pub struct InspectArgs {
    /// Print `{"records": [...]}` on stdout: one object per dataset 58 block with its header
    /// fields and every value (`x`, `re`, `im`; `im` null for real data); with TDMS files
    /// also `"tdms": [...]`, one object per file with its properties and groups, each with its
    /// properties and channels (`name`, `data_type`, `n`, `unit`, `properties`).
    #[arg(long)]
    pub json: bool,
    /// Universal Files (`.uff`, `.unv`; other datasets in them are skipped), TDMS files
    /// (`.tdms`) or MAT-files
    /// (`.mat`: their variables and the fields of their structs, as `--force` names them,
    /// with class and size, in `variables` with `--json`).
    #[arg(required = true)]
    files: Vec<PathBuf>,
}

/// Reads every file and prints its functions.
pub fn inspect(args: &InspectArgs) -> Result<(), Failure> {
    let mut all = Vec::new();
    let mut tdms_files = Vec::new();
    let mut variables = Vec::new();
    let mut mat_text = String::new();
    for path in &args.files {
        if bearing_ident::job::is_tdms(path) {
            tdms_files.push((path.display().to_string(), bearing_ident::tdms::read(path)?));
            continue;
        }
        let file = path.display().to_string();
        if mat::is_mat(path) {
            let vars = mat::read(path)?;
            let mut lines = Vec::new();
            for v in &vars {
                mat_entries(&v.name, &v.array, &mut lines);
            }
            let _ = writeln!(mat_text, "{file}: {} MAT-file variables", vars.len());
            for (name, class, dims) in lines {
                let size: Vec<String> = dims.iter().map(usize::to_string).collect();
                let _ = writeln!(mat_text, "  {name:<24} {class:<10} {}", size.join("×"));
                variables.push(json!({ "file": file, "name": name, "class": class, "size": dims }));
            }
            continue;
        }
        let functions = uff::read(path)?;
        all.push((file, functions));
    }
    if args.json {
        let records: Vec<Value> = all
            .iter()
            .flat_map(|(file, fs)| fs.iter().map(move |f| record_json(file, f)))
            .collect();
        let mut out = json!({ "records": records, "variables": variables });
        if !tdms_files.is_empty() {
            out["tdms"] = tdms_files.iter().map(|(p, f)| tdms::json(p, f)).collect();
        }
        print_out(format_args!("{out}\n"))
    } else {
        let mut text = table(&all);
        for (path, file) in &tdms_files {
            text.push_str(&tdms::table(path, file));
        }
        text.push_str(&mat_text);
        print_out(format_args!("{text}"))
    }
}

/// A MAT-file array and what is below it, as `--force` names them: `rec` then `rec.fx`
/// (fields of every element of a struct array, once; of the structs in a cell array `c`, as
/// `c.fx`).
fn mat_entries(name: &str, array: &mat::Array, out: &mut Vec<(String, &'static str, Vec<usize>)>) {
    out.push((name.to_owned(), array.class(), array.dims().to_vec()));
    match array {
        mat::Array::Struct {
            fields, elements, ..
        } => {
            if let Some(first) = elements.first() {
                for (field, value) in fields.iter().zip(first) {
                    mat_entries(&format!("{name}.{field}"), value, out);
                }
            }
        }
        mat::Array::Cell { cells, .. } => {
            if let Some(mat::Array::Struct {
                fields, elements, ..
            }) = cells.first()
            {
                if let Some(first) = elements.first() {
                    for (field, value) in fields.iter().zip(first) {
                        mat_entries(&format!("{name}.{field}"), value, out);
                    }
                }
            }
        }
        _ => {}
    }
}

/// One function as JSON: the fields of issue 13 item 5 (codes as in the file), and `file`.
fn record_json(file: &str, f: &Function) -> Value {
    let x = f.abscissa.values();
    let (even, x0, dx) = match &f.abscissa {
        Abscissa::Even { x0, dx, .. } => (true, Some(*x0), Some(*dx)),
        Abscissa::Uneven(x) => (false, x.first().copied(), None),
    };
    let (re, im): (Vec<f64>, Option<Vec<f64>>) = match &f.ordinate {
        Ordinate::Real(v) => (v.clone(), None),
        Ordinate::Complex(v) => (
            v.iter().map(|c| c.re).collect(),
            Some(v.iter().map(|c| c.im).collect()),
        ),
    };
    json!({
        "file": file,
        "function_type": f.function_type.code(),
        "ordinate_type": f.ordinate_type(),
        "n": f.ordinate.len(),
        "even": even,
        "x0": x0,
        "dx": dx,
        "response_node": f.response.node,
        "response_dir": f.response.direction,
        "reference_node": f.reference.node,
        "reference_dir": f.reference.direction,
        "abscissa_type": f.abscissa_axis.data_type.code(),
        "ordinate_type_num": f.numerator.data_type.code(),
        "load_case": f.load_case,
        "id": f.id,
        "x": x,
        "re": re,
        "im": im,
    })
}

/// `22+X`, `3-Y`, `0` (scalar): a node and its direction.
fn dof(node: i64, dir: i64) -> String {
    let axis = match dir.saturating_abs() {
        0 => return node.to_string(),
        1 => "X",
        2 => "Y",
        3 => "Z",
        4 => "RX",
        5 => "RY",
        6 => "RZ",
        _ => return format!("{node}:{dir}"),
    };
    format!("{node}{}{axis}", if dir < 0 { '-' } else { '+' })
}

/// The summary table: one line per function.
fn table(all: &[(String, Vec<Function>)]) -> String {
    let mut s = String::new();
    for (file, fs) in all {
        let plural = if fs.len() == 1 { "" } else { "s" };
        let _ = writeln!(s, "{file}: {} dataset 58 function{plural}", fs.len());
        if fs.is_empty() {
            continue;
        }
        let _ = writeln!(
            s,
            "  {:>3}  {:<16} {:<14} {:>8} {:<7} {:>12} {:>12} {:>9} {:>9} {:>6} {:>6}  id",
            "#",
            "type",
            "ordinate",
            "n",
            "spacing",
            "x0",
            "dx",
            "response",
            "ref",
            "xtype",
            "ytype"
        );
        for (k, f) in fs.iter().enumerate() {
            let (spacing, x0, dx) = match &f.abscissa {
                Abscissa::Even { x0, dx, .. } => ("even", format!("{x0:e}"), format!("{dx:e}")),
                Abscissa::Uneven(x) => (
                    "uneven",
                    x.first().map_or_else(String::new, |v| format!("{v:e}")),
                    "-".into(),
                ),
            };
            let ordinate = format!(
                "{} {}",
                if f.ordinate.is_complex() {
                    "complex"
                } else {
                    "real"
                },
                match f.precision {
                    uff::Precision::Single => "single",
                    uff::Precision::Double => "double",
                }
            );
            let _ = writeln!(
                s,
                "  {:>3}  {:<16} {:<14} {:>8} {:<7} {:>12} {:>12} {:>9} {:>9} {:>6} {:>6}  {}",
                k + 1,
                format!("{:?}", f.function_type),
                ordinate,
                f.ordinate.len(),
                spacing,
                x0,
                dx,
                dof(f.response.node, f.response.direction),
                dof(f.reference.node, f.reference.direction),
                f.abscissa_axis.data_type.code(),
                f.numerator.data_type.code(),
                bearing_ident::error::excerpt(&f.id[0]),
            );
        }
    }
    s
}
