//! The static HTML report of a field identification ([`field_report`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::html::{
    Kind, create_dir, esc, figure_html, page_head, page_tail, warnings_list, write_file,
};
use super::{ReportOptions, significant as sig};
use crate::error::Result;
use crate::field::{FieldIdentification, SpeedCoefficients};

/// The eight cells of a bearing at one speed, `K_xx K_xy K_yx K_yy C_xx C_xy C_yx C_yy`, each
/// with its standard deviation after `plus_minus` when there is one (the report's and the
/// CLI table's rows).
///
/// # Examples
/// ```
/// use bearing_ident::field::SpeedCoefficients;
/// use bearing_ident::plot::field_cells;
/// let c = SpeedCoefficients {
///     stiffness: [[2.0e7, 1.0e6], [-1.0e6, 3.0e7]],
///     damping: [[2.0e4, 0.0], [0.0, 3.0e4]],
///     stiffness_std: Some([[1.0e5; 2]; 2]),
///     damping_std: None,
///     noise_gain: 5.0,
/// };
/// let cells = field_cells(&c, "±");
/// assert_eq!(cells[0], "2.0000e7±100000");
/// assert_eq!(cells[4], "20000.0");
/// ```
pub fn field_cells(c: &SpeedCoefficients, plus_minus: &str) -> [String; 8] {
    let cell = |v: f64, sd: Option<f64>| match sd {
        Some(sd) => format!("{}{plus_minus}{}", sig(v, 5), sig(sd, 2)),
        None => sig(v, 6),
    };
    std::array::from_fn(|k| {
        let (i, j) = ((k % 4) / 2, k % 2);
        if k < 4 {
            cell(c.stiffness[i][j], c.stiffness_std.map(|m| m[i][j]))
        } else {
            cell(c.damping[i][j], c.damping_std.map(|m| m[i][j]))
        }
    })
}

/// Writes `field.svg` (the figure [`field`](super::field)) and an `index.html` into `dir`
/// (created if needed): per bearing a table of `K(Ω)`, `C(Ω)` with `±σ`, the condition number
/// and the noise gain per speed, the model residual, the pinned critical speeds, the warnings,
/// the figure (shown from its file) and `options.text` folded at the end. Returns the files written, `index.html` last.
///
/// # Errors
/// [`Error::Io`](crate::Error::Io) if the directory or a file cannot be written, or the
/// directory holds an `index.html` that is not a field identification's report;
/// [`Error::Plot`](crate::Error::Plot) if the figure fails.
///
/// # Examples
/// ```
/// # use bearing_ident::field::{self, *};
/// # let rotor = BeamRotor { element_lengths: vec![0.15; 6], diameter: 0.05, density: 7850.0,
/// #     young: 2.1e11, poisson: 0.3,
/// #     disks: vec![Disk { node: 2, mass: 15.0, polar: 0.12, diametral: 0.06 }],
/// #     bearings: vec![BearingSite::new("brg0", 0), BearingSite::new("brg1", 6)] }.model()?;
/// # let probes = [0, 6].into_iter()
/// #     .flat_map(|node| [Direction::X, Direction::Y].map(|dir| Probe { node, dir })).collect();
/// # let at = |node, phase_rad| vec![Imbalance { node, magnitude_kg_m: 1e-4, phase_rad }];
/// # let brg = |_b: usize, _w: f64| BearingCoefficients {
/// #     stiffness: [[2e7, 3e6], [-4e6, 3e7]], damping: [[2e4, 1e3], [-1e3, 3e4]] };
/// # let tests = ImbalanceRuns { speeds_rad_s: vec![100.0, 200.0], probes,
/// #     residual: at(3, 1.0), added: [at(2, 0.0), at(5, 2.0)], noise: 0.0, repeats: 1, seed: 1 }
/// #     .simulate(&rotor, brg)?;
/// let id = field::identify(&rotor, &tests)?;
/// let tmp = tempfile::tempdir().unwrap();
/// let dir = tmp.path().join("report");
/// let written = bearing_ident::plot::field_report(&id, &dir, &Default::default())?;
/// assert_eq!(written.len(), 2);
/// let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
/// assert!(html.contains("brg1") && html.contains("<img src=\"field.svg\""));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn field_report(
    id: &FieldIdentification,
    dir: &Path,
    options: &ReportOptions,
) -> Result<Vec<PathBuf>> {
    create_dir(dir, Kind::Field)?;
    let svg = super::field(id, &options.figure)?;
    let mut written = vec![write_file(&dir.join("field.svg"), &svg)?];
    written.push(write_file(&dir.join("index.html"), &page(id, options))?);
    Ok(written)
}

fn page(id: &FieldIdentification, options: &ReportOptions) -> String {
    let mut h = String::new();
    page_head(&mut h, options, Kind::Field);
    let probes: Vec<String> = id
        .probes()
        .iter()
        .map(|p| format!("{}{}", p.node, p.dir.name()))
        .collect();
    let _ = writeln!(
        h,
        "<p>Imbalance tests at {} speeds; probes (node, direction) {}. Bearing forces and \
         unmeasured degrees of freedom by column-scaled least squares on the rotor model; \
         Z(Ω) = −[f¹ f²][q¹ q²]⁻¹ per bearing, K = Re Z, C = Im Z/Ω; ±σ propagated to first \
         order from the responses' standard deviations.</p>",
        id.speeds_rad_s().len(),
        esc(&probes.join(", "))
    );
    let elements = ["xx", "xy", "yx", "yy"];
    for b in id.bearings() {
        let _ = writeln!(
            h,
            "<h2>Bearing {} (node {})</h2>\n<table>\n<tr><th>Ω (rad/s)</th><th>cond</th>\
             <th>noise gain</th>",
            esc(&b.tag),
            b.node
        );
        for e in elements {
            let _ = write!(h, "<th>K_{e} (N/m)</th>");
        }
        for e in elements {
            let _ = write!(h, "<th>C_{e} (N·s/m)</th>");
        }
        let _ = writeln!(h, "</tr>");
        for (s, &w) in id.speeds_rad_s().iter().enumerate() {
            let gain = b.coefficients[s].map_or("—".to_owned(), |c| sig(c.noise_gain, 3));
            let _ = write!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{gain}</td>",
                sig(w, 6),
                sig(b.condition_number[s], 3)
            );
            match &b.coefficients[s] {
                None => {
                    let _ = write!(
                        h,
                        "<td colspan=\"8\" class=\"warn\">singular pair: not given</td>"
                    );
                }
                Some(c) => {
                    for cell in field_cells(c, " ± ") {
                        let _ = write!(h, "<td>{cell}</td>");
                    }
                }
            }
            let _ = writeln!(h, "</tr>");
        }
        let _ = writeln!(h, "</table>");
    }
    let _ = writeln!(h, "<h2 id=\"diagnostics\">Diagnostics</h2>");
    let residual: Vec<String> = id
        .model_residual()
        .iter()
        .map(|r| r.map_or("—".to_owned(), |r| sig(r, 2)))
        .collect();
    let _ = writeln!(
        h,
        "<p>Model residual ‖Ax − b‖/‖b‖ per speed: {}.</p>",
        residual.join(", ")
    );
    let critical: Vec<String> = id
        .pinned_critical_speeds()
        .iter()
        .filter(|&&c| c > 0.0)
        .take(6)
        .map(|&c| sig(c, 5))
        .collect();
    let _ = writeln!(
        h,
        "<p>Lowest critical speeds of the rotor pinned at the probes (rad/s): {}.</p>",
        critical.join(", ")
    );
    warnings_list(&mut h, id.warnings());
    figure_html(
        &mut h,
        "field",
        None,
        "field.svg",
        "Per bearing: K(Ω) and C(Ω) per element (±σ where known) and the condition number of \
         the response pair, with the warning threshold.",
    );
    page_tail(&mut h, options);
    h
}
