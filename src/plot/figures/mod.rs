//! The figures, one per file (each a [`Figure`](super::Figure) arm), and the helpers they share: `canvas` (the SVG string, series
//! groups, palette, title and legend) and `chart` (charts, ticks, ranges, error bars).

#[cfg(feature = "campaign")]
mod campaign;
mod canvas;
mod chart;
mod coherence;
mod convergence;
mod field;
mod flexibility;
mod impedance;
mod nonlinear;
mod per_frequency;
mod records;
mod residual;
#[cfg(feature = "campaign")]
mod synchronous;
mod trace;

#[cfg(feature = "campaign")]
pub use campaign::campaign;
pub(crate) use chart::tick;
pub use coherence::coherence;
pub use convergence::convergence;
pub use field::field;
pub use flexibility::flexibility;
pub use impedance::impedance;
pub use nonlinear::nonlinear;
pub use per_frequency::per_frequency;
pub use records::records;
pub use residual::residual;
#[cfg(feature = "campaign")]
pub use synchronous::synchronous;
