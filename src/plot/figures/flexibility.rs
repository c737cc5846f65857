//! The flexibility figure: `|G_ij|` and `∠G_ij`, measured and fitted.

use crate::Choice;
use faer::{Mat, c64};
use plotters::prelude::*;

use super::canvas::{Key, MEASURED, MODEL, font, header, render, series};
use super::chart::{
    MARKER_RADIUS, MODEL_POINTS, X_LABELS, Y_LABELS, draw_markers, freq_range, grid_size,
    log_chart, log_span, model_freqs, phase_segments, stacked, tick, titled, y_tick,
};
use crate::error::Result;
use crate::identify::Identification;
use crate::plot::FigureOptions;

/// Flexibility `G_ij`: magnitude (log scale) over phase, measured points and fitted model.
///
/// The figure is an `n × n` grid, element `ij` in row `i`, column `j`; each panel holds
/// `|G_ij|` (m/N, logarithmic) above `∠G_ij` (degrees), the measured lines as points and the
/// fitted model `G(ω) = (K − ω²M + iωC)⁻¹` as a line; lines denser than one per four pixel
/// columns are drawn as a line through their extremes per pixel column, as wide as a point.
/// Series, per element:
/// `|G ij| measured`, `|G ij| model`, `∠G ij measured`, `∠G ij model`.
///
/// # Errors
/// [`Error::Plot`](crate::Error::Plot) if plotters fails to draw (not expected for an SVG held
/// in memory).
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let svg = plot::flexibility(&id, &FigureOptions::default())?;
/// assert!(svg.starts_with("<svg") && svg.contains("|G xy| model"));
/// let path = std::env::temp_dir().join("bearing-ident-doc-flexibility.svg");
/// std::fs::write(&path, &svg).unwrap();
/// assert!(std::fs::read_to_string(&path).unwrap().ends_with("</svg>\n"));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn flexibility(id: &Identification, options: &FigureOptions) -> Result<String> {
    let n = id.coefficients().dofs();
    let names = options.axis_names(n);
    let freqs = id.freqs_hz();
    let x = freq_range(freqs);
    let model: Vec<(f64, Mat<c64>)> = model_freqs(&x, MODEL_POINTS)
        .into_iter()
        .filter_map(|f| id.coefficients().flexibility_at(f).ok().map(|g| (f, g)))
        .collect();
    let title = format!(
        "Flexibility G = H⁻¹: measured and fitted ({}, {} lines)",
        id.method().name(),
        freqs.len()
    );
    render(
        crate::plot::Figure::Flexibility,
        grid_size(options, n),
        |root| {
            let body = header(
                root,
                &title,
                &[
                    (Key::Point(MEASURED), "measured"),
                    (Key::Line(MODEL), "fitted model"),
                ],
            )?;
            for (p, panel) in body.split_evenly((n, n)).iter().enumerate() {
                let (i, j) = (p / n, p % n);
                let el = format!("{}{}", names[i], names[j]);
                let panel = titled(panel, &format!("G {el}"))?;
                let (top, bottom) = stacked(&panel);
                let measured: Vec<(f64, c64)> = freqs
                    .iter()
                    .enumerate()
                    .map(|(k, &f)| (f, id.frf().flexibility(k)[(i, j)]))
                    .collect();
                let fitted: Vec<(f64, c64)> = model.iter().map(|(f, g)| (*f, g[(i, j)])).collect();
                let magnitude = |v: &[(f64, c64)]| -> Vec<(f64, f64)> {
                    v.iter()
                        .map(|(f, g)| (*f, g.norm()))
                        .filter(|p| p.1 > 0.0 && p.1.is_finite())
                        .collect()
                };
                let phase = |v: &[(f64, c64)]| -> Vec<(f64, f64)> {
                    v.iter()
                        .map(|(f, g)| (*f, g.arg().to_degrees()))
                        .filter(|p| p.1.is_finite())
                        .collect()
                };
                let (m_meas, m_fit) = (magnitude(&measured), magnitude(&fitted));
                let y = log_span(m_meas.iter().chain(&m_fit).map(|p| p.1));
                let mut chart = log_chart(&top, x.clone(), y, None, "|G| (m/N)")?;
                series(&top, &format!("|G {el}| measured"), || {
                    draw_markers(&mut chart, &m_meas, MARKER_RADIUS, MEASURED, false)
                })?;
                series(&top, &format!("|G {el}| model"), || {
                    chart.draw_series(LineSeries::new(
                        m_fit.iter().copied(),
                        MODEL.stroke_width(2),
                    ))?;
                    Ok(())
                })?;
                let mut chart = ChartBuilder::on(&bottom)
                    .margin(8)
                    .margin_right(16)
                    .x_label_area_size(X_LABELS)
                    .y_label_area_size(Y_LABELS)
                    .build_cartesian_2d(x.clone(), -200.0..200.0)?;
                chart
                    .configure_mesh()
                    .x_labels(7)
                    .y_labels(0)
                    .disable_y_mesh()
                    .x_label_formatter(&tick)
                    .x_desc("frequency (Hz)")
                    .y_desc("∠G (°)")
                    .label_style(("sans-serif", font::TICK))
                    .axis_desc_style(("sans-serif", font::DESC))
                    .light_line_style(TRANSPARENT)
                    .bold_line_style(RGBColor(225, 225, 225))
                    .draw()?;
                // Phase ticks at multiples of 90°, which plotters' automatic ticks do not hit.
                for deg in [-180.0, -90.0, 0.0, 90.0, 180.0] {
                    y_tick(&mut chart, &x, deg, &format!("{deg:.0}"))?;
                }
                let (p_meas, p_fit) = (phase(&measured), phase(&fitted));
                series(&bottom, &format!("∠G {el} measured"), || {
                    draw_markers(&mut chart, &p_meas, MARKER_RADIUS, MEASURED, true)
                })?;
                series(&bottom, &format!("∠G {el} model"), || {
                    for segment in phase_segments(&p_fit) {
                        chart.draw_series(LineSeries::new(segment, MODEL.stroke_width(2)))?;
                    }
                    Ok(())
                })?;
            }
            Ok(())
        },
    )
}
