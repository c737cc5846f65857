//! Edge (feature `plot`): SVG figures of an identification and a static HTML report.
//!
//! Every figure is drawn with [plotters](https://docs.rs/plotters) into a self-contained SVG
//! string (no fonts, scripts or system libraries are needed: text is SVG `<text>` in the
//! viewer's sans-serif). Matrices are laid out as matrices: the panel in grid row `i`, column
//! `j` shows element `ij` (output `i` per input `j`), with the axis names of
//! [`FigureOptions::axes`].
//!
//! | function | shows |
//! | --- | --- |
//! | [`flexibility`] | `\|G_ij\|` (log scale, m/N) and `∠G_ij` (°) against frequency: the measured lines as points, the fitted model `G(ω) = (K − ω²M + iωC)⁻¹` as a line |
//! | [`impedance`] | `Re H_ij` with the fitted `K − ω²M` and `Im H_ij` with the fitted `ωC` (N/m), error bars `±σ` with `σ² = E|δH_ij|²/2` when the FRF carries a variance |
//! | [`coherence`] | the multiple coherence of every output and the condition number per line, the thresholds of [`ConditionLimits`](crate::ConditionLimits), the band shaded and the lines dropped marked |
//! | [`per_frequency`] | `K_ij(ω)` and `C_ij(ω)` line by line ([`PerFrequency`](crate::per_frequency::PerFrequency)) with error bars, and the constant fit |
//! | [`records`] | force (N) and displacement per record against time, the impact (peak of the dominant force) marked, double hits and clipping from [`check_record`](crate::quality::check_record) marked, the force gate shaded and an exponential window drawn |
//! | [`convergence`] | the IVF history: the block-wise relative changes of `M`, `C`, `K` per iteration (log scale) |
//! | [`residual`] | the model check: each line's share of the χ² statistic over its expectation ([`ModelCheck::line_ratios`](crate::identify::ModelCheck::line_ratios)), about 1 where the model fits, with the 95 % band of pure error |
//! | [`nonlinear`] | the reverse path's coefficient spectra `Âⱼ(ω)`: real part with the fitted constant, imaginary part with zero, `±σ` |
//! | `synchronous` | a campaign's synchronous `K`, `C` (each point's at its speed) against speed with `±σ` and the plan's predictions (feature `campaign`; [`campaign_report`] writes it as `synchronous.svg`) |
//! | [`field`] | field identification: per bearing `K(Ω)`, `C(Ω)` with `±σ` and the condition number of the response pair against speed ([`field_report`] writes it with a table) |
//!
//! [`report`] writes all of them as `.svg` files into a directory together with an `index.html`
//! that holds the coefficient table (with standard deviations and 95 % intervals), the
//! diagnostics, the warnings and every figure, shown from its file (each figure stored once):
//! the folder is the report, with no scripts and no external assets.
//!
//! A figure's size does not grow with the data: a time trace is drawn by its minimum and
//! maximum per pixel column, and a per-line series with more than one line per four pixel
//! columns by its extremes per pixel column (a line instead of markers), its error bars merged
//! into a band. Only the drawing is thinned; tables and JSON keep every number.
//!
//! [`coefficient_rows`] formats the cells of that table (value, `±1σ`, 95 % interval, truth and
//! error per element), once for the page and the command-line tool's text table.
//!
//! Every drawn series is an SVG group `<g class="series" data-series="…">` whose `<title>`
//! names it (a browser shows it on hover), so a figure can be checked or restyled by its
//! series.
//!
//! # Examples
//! ```
//! use bearing_ident::Identifier;
//! use bearing_ident::plot::{self, FigureOptions};
//! use bearing_ident::simulate::{ImpactTest, seed_rig};
//!
//! let records = ImpactTest { per_direction: 2, ..ImpactTest::seed_rig() }.run(&seed_rig())?;
//! let id = Identifier::new(8.0, 49.0).identify(&records)?;
//! let svg = plot::impedance(&id, &FigureOptions::default())?;
//! assert!(svg.starts_with("<svg"));
//! // Four series per element: Re H and Im H, measured and fitted.
//! assert_eq!(svg.matches("class=\"series\"").count(), 4 * 2 * 2);
//! # Ok::<(), bearing_ident::Error>(())
//! ```
//!
// Without feature `campaign`, the link goes to the crate's feature list.
#![cfg_attr(
    not(feature = "campaign"),
    doc = "[`campaign_report`]: crate#feature-flags"
)]

#[cfg(feature = "campaign")]
mod campaign_report;
mod field_report;
mod figures;
mod html;
mod nonlinear_report;
mod table;

pub use crate::text::significant;
#[cfg(feature = "campaign")]
pub use campaign_report::campaign_report;
pub use field_report::{field_cells, field_report};
#[cfg(feature = "campaign")]
pub use figures::{campaign, synchronous};
pub use figures::{
    coherence, convergence, field, flexibility, impedance, nonlinear, per_frequency, records,
    residual,
};
pub use html::{ReportOptions, report};
pub use nonlinear_report::nonlinear_report;
pub use table::{CoefficientRow, coefficient_rows};

/// The figures of an identification, one per drawing function of this module.
///
/// # Examples
/// ```
/// use bearing_ident::plot::Figure;
/// use bearing_ident::Choice;
/// assert_eq!(Figure::PerFrequency.name(), "per_frequency");
/// assert_eq!(Figure::REPORT.len(), 7);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Figure {
    /// [`flexibility`]: `|G_ij|` and phase, measured and fitted.
    Flexibility,
    /// [`impedance`]: `Re H_ij`, `Im H_ij` against the fit.
    Impedance,
    /// [`coherence`]: coherence and condition numbers per line.
    Coherence,
    /// [`per_frequency`]: `K(ω)`, `C(ω)` line by line.
    PerFrequency,
    /// [`records`]: the time records.
    Records,
    /// [`convergence`]: the IVF iterations.
    Convergence,
    /// [`residual`]: the model check, residual against the pure error per line.
    Residual,
    /// [`nonlinear`]: the coefficient spectra of the nonlinear terms of a
    /// [`NonlinearIdentification`](crate::nonlinear::NonlinearIdentification) (not in
    /// [`Figure::REPORT`], which lists the figures of an [`Identification`](crate::Identification)).
    Nonlinear,
    /// [`field`]: `K(Ω)`, `C(Ω)` and condition numbers per bearing of a
    /// [`FieldIdentification`](crate::field::FieldIdentification) (not in [`Figure::REPORT`]).
    Field,
    /// `campaign` (feature `campaign`): one block of coefficients against a test condition
    /// over the points of a campaign (not in [`Figure::REPORT`]).
    Campaign,
    /// `synchronous` (feature `campaign`): the synchronous `K`, `C` of a campaign's points
    /// against their speed, with the predictions (not in [`Figure::REPORT`]).
    Synchronous,
}

impl Figure {
    /// The figures of an [`Identification`](crate::Identification)'s report, in its order.
    pub const REPORT: &'static [Figure] = &[
        Figure::Flexibility,
        Figure::Impedance,
        Figure::Coherence,
        Figure::PerFrequency,
        Figure::Records,
        Figure::Convergence,
        Figure::Residual,
    ];

    /// The heading of this figure in a report.
    pub(crate) fn heading(self) -> &'static str {
        match self {
            Figure::Flexibility => "Flexibility",
            Figure::Impedance => "Impedance",
            Figure::Coherence => "Coherence and conditioning",
            Figure::PerFrequency => "Per-frequency coefficients",
            Figure::Records => "Time records",
            Figure::Convergence => "IVF convergence",
            Figure::Residual => "Model check",
            Figure::Nonlinear => "Nonlinear terms",
            Figure::Field => "Field identification",
            Figure::Campaign => "Campaign",
            Figure::Synchronous => "Synchronous coefficients",
        }
    }

    /// The caption of this figure in an identification's report.
    pub(crate) fn caption(self) -> &'static str {
        match self {
            Figure::Flexibility => {
                "Measured flexibility G = H⁻¹ per element (points) and the fitted model (line): \
                 magnitude on a log scale above phase."
            }
            Figure::Impedance => {
                "Real part against the fitted K − ω²M, imaginary part against the fitted ωC; \
                 error bars ±σ where the FRF carries a variance."
            }
            Figure::Coherence => {
                "Multiple coherence per output and the condition number per line, with the \
                 warning and refusal thresholds; the band used is shaded."
            }
            Figure::PerFrequency => {
                "K(ω) = Re H + ω²M and C(ω) = Im H/ω line by line with ±σ, against the constant \
                 fit: a trend says the coefficients depend on frequency."
            }
            Figure::Records => {
                "Force and displacement of some records (the first two per excitation direction \
                 and any with an issue); the impact is marked at the dominant force's peak."
            }
            Figure::Convergence => "Block-wise relative change of M, C and K per iteration.",
            Figure::Residual => {
                "Per line, the fit's squared residual over the replicates' own scatter (the pure \
                 error), about 1 where the model fits; the shaded band holds 95 % of the lines \
                 of a right model. Lines far above it are what the model misses."
            }
            Figure::Nonlinear | Figure::Field | Figure::Campaign | Figure::Synchronous => {
                crate::Choice::describe(self)
            }
        }
    }

    /// This figure of `id`'s report drawn: the records figure from `records` (`None` when
    /// there are none to draw), `None` for a figure that is not of an identification.
    pub(crate) fn of_report(
        self,
        id: &crate::Identification,
        records: &[crate::Record],
        checks: Option<&crate::ImpactChecks>,
        fig: &FigureOptions,
    ) -> crate::Result<Option<String>> {
        Ok(Some(match self {
            Figure::Flexibility => flexibility(id, fig)?,
            Figure::Impedance => impedance(id, fig)?,
            Figure::Coherence => coherence(id, fig)?,
            Figure::PerFrequency => per_frequency(id, fig)?,
            Figure::Records if !records.is_empty() => {
                self::records(records, Some(id), checks, fig)?
            }
            Figure::Convergence => convergence(id, fig)?,
            Figure::Residual => residual(id, fig)?,
            Figure::Records
            | Figure::Nonlinear
            | Figure::Field
            | Figure::Campaign
            | Figure::Synchronous => {
                return Ok(None);
            }
        }))
    }
}

impl crate::Choice for Figure {
    const OPTION: &'static str = "figure";
    const ALL: &'static [Figure] = &[
        Figure::Flexibility,
        Figure::Impedance,
        Figure::Coherence,
        Figure::PerFrequency,
        Figure::Records,
        Figure::Convergence,
        Figure::Residual,
        Figure::Nonlinear,
        Figure::Field,
        Figure::Campaign,
        Figure::Synchronous,
    ];

    /// The figure's file stem: `"flexibility"`, `"impedance"`, `"coherence"`,
    /// `"per_frequency"`, `"records"`, `"convergence"`, `"residual"`, `"nonlinear"`,
    /// `"field"`, `"campaign"` or `"synchronous"`.
    fn name(self) -> &'static str {
        match self {
            Figure::Flexibility => "flexibility",
            Figure::Impedance => "impedance",
            Figure::Coherence => "coherence",
            Figure::PerFrequency => "per_frequency",
            Figure::Records => "records",
            Figure::Convergence => "convergence",
            Figure::Residual => "residual",
            Figure::Nonlinear => "nonlinear",
            Figure::Field => "field",
            Figure::Campaign => "campaign",
            Figure::Synchronous => "synchronous",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Figure::Flexibility => "|G| and phase, measured and fitted",
            Figure::Impedance => "Re H and Im H against the fit",
            Figure::Coherence => "coherence and condition numbers per line",
            Figure::PerFrequency => "K(ω) and C(ω) line by line",
            Figure::Records => "the time records, issues marked",
            Figure::Convergence => "the IVF iterations",
            Figure::Residual => "the model check: residual against the pure error",
            Figure::Nonlinear => "the coefficient spectra of nonlinear terms",
            Figure::Field => "K(Ω), C(Ω) per bearing of a field identification",
            Figure::Campaign => "coefficients against a test condition over a campaign",
            Figure::Synchronous => {
                "synchronous K, C against speed over a campaign, with predictions"
            }
        }
    }
}

crate::choice::choice_text!(Figure);

/// Size and labels of the figures.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureOptions {
    /// Width of one panel of a matrix grid, or of a single-panel figure's column, in pixels.
    /// Default 440; at least 200 is readable.
    pub panel_width: u32,
    /// Height of one panel (for the flexibility, impedance and per-frequency figures a panel
    /// holds two stacked plots), in pixels. Default 380.
    pub panel_height: u32,
    /// Names of the degrees of freedom, e.g. `["x", "y"]`; element `ij` is labelled
    /// `G xy`. Empty (the default), or of the wrong length, gives `x, y` for two degrees of
    /// freedom, `x, y, z` for three and `1, 2, …` otherwise.
    pub axes: Vec<String>,
}

impl Default for FigureOptions {
    fn default() -> Self {
        Self {
            panel_width: 440,
            panel_height: 380,
            axes: Vec::new(),
        }
    }
}

impl FigureOptions {
    /// The names of `n` degrees of freedom (see [`FigureOptions::axes`]).
    fn axis_names(&self, n: usize) -> Vec<String> {
        if self.axes.len() == n {
            return self.axes.clone();
        }
        match n {
            2 => vec!["x".into(), "y".into()],
            3 => vec!["x".into(), "y".into(), "z".into()],
            _ => (1..=n).map(|i| i.to_string()).collect(),
        }
    }

    fn panel(&self) -> (u32, u32) {
        (self.panel_width.max(200), self.panel_height.max(160))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_names_default_by_size() {
        let o = FigureOptions::default();
        assert_eq!(o.axis_names(2), ["x", "y"]);
        assert_eq!(o.axis_names(4), ["1", "2", "3", "4"]);
        let o = FigureOptions {
            axes: vec!["u".into()],
            ..FigureOptions::default()
        };
        assert_eq!(o.axis_names(1), ["u"]);
    }
}
