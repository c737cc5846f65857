//! The IVF convergence figure: block-wise relative changes of `M`, `C`, `K` per iteration.

use crate::Choice;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::canvas::{Key, colour, font, header, message, render, series};
use super::chart::{X_LABELS, Y_LABELS, log_span, log_tick, log_ticks, y_tick};
use crate::error::Result;
use crate::identify::Identification;
use crate::plot::FigureOptions;

/// IVF convergence: the block-wise relative changes `‖ΔM‖/‖M‖`, `‖ΔC‖/‖C‖`, `‖ΔK‖/‖K‖`
/// (Frobenius norms) per iteration on a log scale (series `mass change`, `damping change`,
/// `stiffness change`). For a method that does not iterate, the figure says so and holds no
/// series.
///
/// # Errors
/// [`Error::Plot`](crate::Error::Plot) if plotters fails to draw.
///
/// # Examples
/// ```
/// use bearing_ident::Identifier;
/// use bearing_ident::plot::{self, FigureOptions};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records =
///     ImpactTest { per_direction: 2, noise: 0.05, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
/// let id = Identifier::new(8.0, 49.0).identify(&records)?;
/// let svg = plot::convergence(&id, &FigureOptions::default())?;
/// assert_eq!(svg.matches("class=\"series\"").count(), 3);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn convergence(id: &Identification, options: &FigureOptions) -> Result<String> {
    let history = id.history();
    let (w, h) = options.panel();
    let size = (2 * w + 10, h + 120);
    let floor = crate::tolerance::PLOT_CHANGE_FLOOR;
    let blocks: [(&str, Vec<f64>); 3] = [
        ("mass", history.iter().map(|i| i.mass_change).collect()),
        (
            "damping",
            history.iter().map(|i| i.damping_change).collect(),
        ),
        (
            "stiffness",
            history.iter().map(|i| i.stiffness_change).collect(),
        ),
    ];
    let legend = [
        (Key::Line(colour(0)), "‖ΔM‖/‖M‖"),
        (Key::Line(colour(1)), "‖ΔC‖/‖C‖"),
        (Key::Line(colour(2)), "‖ΔK‖/‖K‖"),
    ];
    let title = format!(
        "IVF convergence: {} ({} iterations)",
        id.convergence().name().replace('_', " "),
        history.len()
    );
    render(crate::plot::Figure::Convergence, size, |root| {
        let body = header(root, &title, if history.is_empty() { &[] } else { &legend })?;
        if history.is_empty() {
            return message(
                &body,
                &format!("method {} does not iterate", id.method().name()),
            );
        }
        let m = history.len();
        let x = 0.5..(m as f64 + 0.5);
        let y = log_span(blocks.iter().flat_map(|b| b.1.iter().map(|v| v.max(floor))));
        let mut chart = ChartBuilder::on(&body)
            .margin(8)
            .margin_right(24)
            .x_label_area_size(X_LABELS)
            .y_label_area_size(Y_LABELS)
            .build_cartesian_2d(x.clone(), y.clone().log_scale())?;
        // Whole iterations only.
        let every = m.div_ceil(12).max(1);
        chart
            .configure_mesh()
            .x_labels(0)
            .y_labels(0)
            .disable_mesh()
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .x_desc("iteration")
            .y_desc("relative change ‖ΔB‖/‖B‖ (Frobenius)")
            .axis_desc_style(("sans-serif", font::DESC))
            .draw()?;
        for v in log_ticks(&y) {
            y_tick(&mut chart, &x, v, &log_tick(&v))?;
        }
        for it in (1..=m).filter(|it| (it - 1) % every == 0) {
            chart.draw_series([EmptyElement::at((it as f64, y.start))
                + Text::new(
                    it.to_string(),
                    (0, 8),
                    TextStyle::from(("sans-serif", font::TICK).into_font())
                        .pos(Pos::new(HPos::Center, VPos::Top)),
                )])?;
        }
        for (c, (name, values)) in blocks.iter().enumerate() {
            let points: Vec<(f64, f64)> = values
                .iter()
                .enumerate()
                .map(|(m, v)| ((m + 1) as f64, v.max(floor)))
                .collect();
            series(&body, &format!("{name} change"), || {
                chart.draw_series(LineSeries::new(
                    points.iter().copied(),
                    // Wider first, so coinciding curves all show.
                    colour(c).stroke_width(2 + 2 * (2 - c) as u32),
                ))?;
                chart.draw_series(
                    points
                        .iter()
                        .map(|&p| Circle::new(p, 3 + (2 - c) as u32, colour(c).filled())),
                )?;
                Ok(())
            })?;
        }
        Ok(())
    })
}
