//! `bearing-ident field`: the bearings' `K(Ω)`, `C(Ω)` of a running machine from imbalance
//! responses and a rotor model (library: `bearing_ident::field`), as a table, as JSON, and as
//! an HTML report with the figure.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use bearing_ident::Error;
use bearing_ident::field::{self, FieldIdentification, FieldTests, RotorModel};
use bearing_ident::plot::{field_cells, significant as sig};
use bearing_ident::text::{self, Align};

use crate::failure::{Failure, print_out};

#[derive(Debug, clap::Args)]
pub struct FieldArgs {
    /// The free rotor's model: `{"dof_per_node", "dof_names", "M", "K", "G", "C" (optional),
    /// "bearings": [{"tag", "node"}]}` (`docs/guide/06-field.md` builds one with ROSS).
    #[arg(long, value_name = "ROTOR.json")]
    rotor: PathBuf,
    /// The imbalance tests: `{"imbalances": {"1": […], "2": […]}, "responses": […]}`.
    #[arg(long, value_name = "TESTS.json")]
    tests: PathBuf,
    /// Print one JSON object on stdout (`speeds_rad_s`, `bearings` with `K`, `C`, their `_std`
    /// and `condition_number` per speed, `measured`, `model_residual`, `residual_ratio`, `warnings`, …).
    #[arg(long)]
    pub json: bool,
    /// Also write `field.svg` (K(Ω), C(Ω) per bearing with condition numbers) and an
    /// `index.html` report into DIR.
    #[arg(long, value_name = "DIR")]
    plot: Option<PathBuf>,
}

/// The text of a JSON input, under the readers' size rule (`/dev/zero` is refused, not read
/// to the end).
fn read(path: &PathBuf) -> Result<String, Failure> {
    Ok(bearing_ident::limits::read_json_text(path)?)
}

/// Reads the rotor and the tests, identifies, prints.
pub fn field(args: &FieldArgs) -> Result<(), Failure> {
    let start = Instant::now();
    let in_file = |path: &PathBuf, e: Error| -> Failure {
        let mut f = Failure::from(e);
        f.message = format!("{}: {}", path.display(), f.message);
        f
    };
    let rotor = RotorModel::from_json(&read(&args.rotor)?).map_err(|e| in_file(&args.rotor, e))?;
    let tests = FieldTests::from_json(&read(&args.tests)?).map_err(|e| in_file(&args.tests, e))?;
    let id = field::identify(&rotor, &tests)?;
    let compute_ms = start.elapsed().as_secs_f64() * 1e3;
    if let Some(dir) = &args.plot {
        let options = bearing_ident::plot::ReportOptions {
            title: "Field identification of bearing coefficients".to_owned(),
            context: vec![format!(
                "Rotor model {} ({} degrees of freedom), tests {}.",
                args.rotor.display(),
                rotor.dofs(),
                args.tests.display()
            )],
            text: Some(table(&id)),
            ..Default::default()
        };
        let written = bearing_ident::plot::field_report(&id, dir, &options)?;
        crate::failure::print_err(format_args!(
            "bearing-ident: wrote {} figure(s) and {}",
            written.len().saturating_sub(1),
            dir.join("index.html").display()
        ));
    }
    if args.json {
        print_out(format_args!("{}\n", id.to_json(compute_ms)))
    } else {
        print_out(format_args!("{}", table(&id)))
    }
}

/// The result as a text table: per bearing and speed, `K` and `C` (with `±σ` when known), the
/// condition number and the noise gain (split into a `K` and a `C` block when wider than
/// [`TABLE_WIDTH`](bearing_ident::text::TABLE_WIDTH)); the model residual; the bearings'
/// added masses summed against the rotor model's mass; the warnings.
pub fn table(id: &FieldIdentification) -> String {
    let mut out = String::new();
    let probes: Vec<String> = id
        .probes()
        .iter()
        .map(|p| format!("{}{}", p.node, p.dir.name()))
        .collect();
    let _ = writeln!(
        out,
        "Field identification: {} speeds, probes {}",
        id.speeds_rad_s().len(),
        probes.join(" ")
    );
    let names = ["xx", "xy", "yx", "yy"];
    for b in id.bearings() {
        let _ = writeln!(out, "\nbearing {} (node {})", b.tag, b.node);
        let mut header: Vec<String> = vec!["Ω rad/s".into(), "cond".into(), "gain".into()];
        header.extend(names.map(|n| format!("K_{n} N/m")));
        header.extend(names.map(|n| format!("C_{n} N·s/m")));
        let mut rows = vec![header];
        let mut singular = false;
        for (s, &w) in id.speeds_rad_s().iter().enumerate() {
            let mut row = vec![sig(w, 6), sig(b.condition_number[s], 3)];
            match &b.coefficients[s] {
                None => {
                    singular = true;
                    row.extend(std::iter::repeat_n("—".to_owned(), 9));
                }
                Some(c) => {
                    row.push(sig(c.noise_gain, 3));
                    row.extend(field_cells(c, "±"));
                }
            }
            rows.push(row);
        }
        out.push_str(&text::table(&rows, 3, &[4, 4], Align::Right, 0));
        if singular {
            let _ = writeln!(out, "— singular pair: K, C not given at that speed");
        }
    }
    let residual: Vec<String> = id
        .model_residual()
        .iter()
        .map(|r| r.map_or("—".to_owned(), |r| sig(r, 2)))
        .collect();
    out.push('\n');
    out.push_str(&text::wrap(
        "model residual per speed:",
        &residual.join(" "),
        2,
    ));
    if let Some(m) = id.mass_sum() {
        let _ = writeln!(
            out,
            "bearings' added mass ΣM_xx = {} ± {} kg, ΣM_yy = {} ± {} kg; rotor model {} kg",
            sig(m.sum[0], 3),
            sig(m.sum_std[0], 2),
            sig(m.sum[1], 3),
            sig(m.sum_std[1], 2),
            sig(m.rotor_mass[0], 4)
        );
    }
    for w in id.warnings() {
        let _ = writeln!(out, "warning: {w}");
    }
    out
}
