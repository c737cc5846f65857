//! The SVG canvas every figure draws on: rendering into a string, series grouped as `<g>`
//! elements, the palette, the title and legend of a figure, a message in an empty panel.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::Choice;
use crate::error::{Error, Result};

/// The drawing area of an SVG held in a string.
pub(crate) type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

/// A plotters error, boxed.
pub(crate) type Boxed = Box<dyn std::error::Error>;

/// What a drawing closure returns.
pub(crate) type Drawn = std::result::Result<(), Boxed>;

/// Font sizes in plotters' units (the SVG backend writes `size / 1.24` px).
pub(crate) mod font {
    pub const TICK: f64 = 17.0;
    pub const DESC: f64 = 18.0;
    pub const PANEL: f64 = 20.0;
    pub const TITLE: f64 = 25.0;
    pub const NOTE: f64 = 17.0;
}

/// Text markers around a series; [`group_series`] turns them into `<g>` elements.
const BEGIN: &str = "@@series-begin@@";
const END: &str = "@@series-end@@";

/// Draws `figure` of `size` pixels into an SVG string, white background, series grouped.
pub(crate) fn render(
    figure: crate::plot::Figure,
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Drawn,
) -> Result<String> {
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, size).into_drawing_area();
        let plot_error = |e: &dyn std::fmt::Display| Error::Plot {
            figure: figure.name(),
            message: e.to_string(),
        };
        root.fill(&WHITE).map_err(|e| plot_error(&e))?;
        draw(&root).map_err(|e| plot_error(&e))?;
        root.present().map_err(|e| plot_error(&e))?;
    }
    Ok(group_series(&buf))
}

/// Draws the series `name` with `draw`, marked so that it becomes one SVG group.
pub(crate) fn series(area: &Area<'_>, name: &str, draw: impl FnOnce() -> Drawn) -> Drawn {
    let marker = ("sans-serif", 1.0).into_font().color(&BLACK);
    area.draw(&Text::new(format!("{BEGIN}{name}"), (0, 0), marker.clone()))?;
    draw()?;
    area.draw(&Text::new(END.to_string(), (0, 0), marker))?;
    Ok(())
}

/// Replaces the marker texts of [`series`] by `<g class="series" data-series="NAME">` with a
/// `<title>`, and `</g>`. The name is already XML-escaped by the SVG backend.
fn group_series(svg: &str) -> String {
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg;
    while let Some(at) = rest.find("<text") {
        let (before, from) = rest.split_at(at);
        out.push_str(before);
        let Some(end) = from.find("</text>") else {
            out.push_str(from);
            return out;
        };
        let element = &from[..end + "</text>".len()];
        let content = element
            .split_once('>')
            .map_or("", |(_, c)| c.trim_end_matches("</text>").trim());
        if let Some(name) = content.strip_prefix(BEGIN) {
            out.push_str(&format!(
                "<g class=\"series\" data-series=\"{name}\">\n<title>{name}</title>"
            ));
        } else if content == END {
            out.push_str("</g>");
        } else {
            out.push_str(element);
        }
        rest = &from[end + "</text>".len()..];
    }
    out.push_str(rest);
    out
}

/// Colours of channels and outputs, distinguishable in colour-blind palettes (Okabe–Ito).
const PALETTE: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
];

pub(crate) fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Measured points and the fitted model.
pub(crate) const MEASURED: RGBColor = RGBColor(0, 90, 160);
pub(crate) const MODEL: RGBColor = RGBColor(213, 60, 0);
pub(crate) const GREY: RGBColor = RGBColor(120, 120, 120);
pub(crate) const DARK: RGBColor = RGBColor(40, 40, 40);
pub(crate) const ALERT: RGBColor = RGBColor(200, 0, 0);

/// A title across the top of `area` and a legend under it; returns the area below.
pub(crate) fn header<'a>(
    area: &Area<'a>,
    title: &str,
    legend: &[(Key, &str)],
) -> std::result::Result<Area<'a>, Boxed> {
    let height = if legend.is_empty() { 44 } else { 78 };
    let (top, below) = area.split_vertically(height);
    let width = top.dim_in_pixel().0 as i32;
    top.draw(&Text::new(
        title.to_string(),
        (width / 2, 10),
        TextStyle::from(
            ("sans-serif", font::TITLE)
                .into_font()
                .style(FontStyle::Bold),
        )
        .pos(Pos::new(HPos::Center, VPos::Top)),
    ))?;
    draw_legend(&top, legend, 56)?;
    Ok(below)
}

/// How a legend entry is drawn.
#[derive(Clone, Copy)]
pub(crate) enum Key {
    Point(RGBColor),
    Line(RGBColor),
    Dashed(RGBColor),
    Band(RGBColor),
    Cross(RGBColor),
}

/// A legend centred on row `y` of `area`.
fn draw_legend(area: &Area<'_>, legend: &[(Key, &str)], y: i32) -> Drawn {
    if legend.is_empty() {
        return Ok(());
    }
    let style = TextStyle::from(("sans-serif", font::DESC).into_font());
    let gap = 28;
    let widths: Vec<i32> = legend
        .iter()
        .map(|(_, text)| {
            let w = area
                .estimate_text_size(text, &style)
                .map_or(8 * text.chars().count() as i32, |s| s.0 as i32);
            // The naive estimate counts bytes; non-ASCII letters are narrower than that.
            w.min(9 * text.chars().count() as i32) + 30
        })
        .collect();
    let total: i32 = widths.iter().sum::<i32>() + gap * (legend.len() as i32 - 1);
    let mut x = (area.dim_in_pixel().0 as i32 - total).max(0) / 2;
    for ((key, text), w) in legend.iter().zip(widths) {
        match *key {
            Key::Point(c) => area.draw(&Circle::new((x + 10, y), 4, c.filled()))?,
            Key::Line(c) => area.draw(&PathElement::new(
                vec![(x, y), (x + 22, y)],
                c.stroke_width(2),
            ))?,
            Key::Dashed(c) => {
                for k in 0..3 {
                    area.draw(&PathElement::new(
                        vec![(x + 8 * k, y), (x + 8 * k + 5, y)],
                        c.stroke_width(2),
                    ))?;
                }
            }
            Key::Band(c) => area.draw(&Rectangle::new(
                [(x, y - 7), (x + 22, y + 7)],
                c.mix(0.25).filled(),
            ))?,
            Key::Cross(c) => area.draw(&Cross::new((x + 10, y), 5, c.stroke_width(2)))?,
        }
        area.draw(&Text::new(
            text.to_string(),
            (x + 28, y),
            style.clone().pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        x += w + gap;
    }
    Ok(())
}

/// A message in the middle of an empty panel.
pub(crate) fn message(area: &Area<'_>, text: &str) -> Drawn {
    let (w, h) = area.dim_in_pixel();
    area.draw(&Text::new(
        text.to_string(),
        (w as i32 / 2, h as i32 / 2),
        ("sans-serif", font::NOTE)
            .into_font()
            .color(&GREY)
            .pos(Pos::new(HPos::Center, VPos::Center)),
    ))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_replace_markers() {
        let svg = "<svg>\n<text x=\"0\">\n@@series-begin@@G xy &amp; z\n</text>\n<circle/>\n\
                   <text x=\"0\">\n@@series-end@@\n</text>\n<text x=\"1\">\nlabel\n</text>\n</svg>";
        let out = group_series(svg);
        assert!(out.contains("<g class=\"series\" data-series=\"G xy &amp; z\">"));
        assert!(out.contains("<title>G xy &amp; z</title>"));
        assert!(out.contains("</g>"));
        assert!(out.contains("label"));
        assert!(!out.contains("@@"));
    }
}
