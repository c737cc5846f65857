//! What errors and warnings name: a channel, a coefficient block, a spectrum, a quantity, a
//! factorization, a baseline setting, a reader limit — enums, so a program can match on them.

use std::fmt;

#[cfg(doc)]
use super::Error;

/// A measured channel of a [`Record`](crate::records::Record).
///
/// Force channels and displacement channels are numbered from zero, in the order of the
/// degrees of freedom.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// Force channel `i` (N).
    Force(usize),
    /// Displacement channel `i` (m).
    Displacement(usize),
}

impl fmt::Display for Channel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Channel::Force(i) => write!(f, "force channel {i}"),
            Channel::Displacement(i) => write!(f, "displacement channel {i}"),
        }
    }
}

/// A block of the coefficient matrices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Block {
    /// The mass matrix `M` (kg).
    Mass,
    /// The damping matrix `C` (N·s/m).
    Damping,
    /// The stiffness matrix `K` (N/m).
    Stiffness,
}

impl fmt::Display for Block {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Block::Mass => "M",
            Block::Damping => "C",
            Block::Stiffness => "K",
        })
    }
}

/// Which spectrum overflowed ([`Error::SpectrumOverflow`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpectrumKind {
    /// The DFT of one channel.
    Spectrum,
    /// A product of two channels' DFTs.
    CrossSpectrum,
    /// A running sum of cross-spectra over records and segments.
    AccumulatedCrossSpectrum,
}

impl fmt::Display for SpectrumKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SpectrumKind::Spectrum => "spectrum",
            SpectrumKind::CrossSpectrum => "cross-spectrum",
            SpectrumKind::AccumulatedCrossSpectrum => "accumulated cross-spectrum",
        })
    }
}

/// A per-line quantity computed from the spectra ([`Error::NonFiniteResult`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// The impedance `H`.
    Impedance,
    /// The flexibility `G = H⁻¹`.
    Flexibility,
    /// The multiple coherence.
    Coherence,
    /// A flexibility handed in by the caller ([`Frf::from_flexibility`](crate::Frf::from_flexibility)).
    GivenFlexibility,
    /// The spectra and noise covariances maximum likelihood fits
    /// ([`MlData`](crate::solve::ml::MlData)).
    MlData,
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quantity::Impedance => "impedance",
            Quantity::Flexibility => "flexibility",
            Quantity::Coherence => "coherence",
            Quantity::GivenFlexibility => "given flexibility",
            Quantity::MlData => "maximum-likelihood data (spectra and noise covariances)",
        })
    }
}

/// A matrix factorization of faer ([`Error::Decomposition`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Factorization {
    /// The singular value decomposition.
    SingularValue,
    /// The eigenvalue decomposition.
    Eigenvalue,
}

impl fmt::Display for Factorization {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Factorization::SingularValue => "singular value",
            Factorization::Eigenvalue => "eigenvalue",
        })
    }
}

/// What a dry-structure baseline must share with the system it is subtracted from
/// ([`Error::BaselineMismatch`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BaselineField {
    /// The number of degrees of freedom (of the coefficients or of their standard deviations).
    DegreesOfFreedom,
    /// The frequency band.
    Band,
    /// The frequency lines used.
    FrequencyLines,
    /// The FRF estimator.
    Estimator,
    /// The window.
    Window,
}

impl fmt::Display for BaselineField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BaselineField::DegreesOfFreedom => "degrees of freedom",
            BaselineField::Band => "band",
            BaselineField::FrequencyLines => "frequency lines",
            BaselineField::Estimator => "estimator",
            BaselineField::Window => "window",
        })
    }
}

/// What a CSV reader limit counts ([`Error::CsvLimit`], feature `csv`).
#[cfg(feature = "csv")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CsvLimitKind {
    /// The bytes of one line.
    LineBytes,
    /// The columns of a line.
    Columns,
    /// The values of a record (samples × columns).
    Values,
}

#[cfg(feature = "csv")]
impl fmt::Display for CsvLimitKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CsvLimitKind::LineBytes => "line length (bytes)",
            CsvLimitKind::Columns => "columns",
            CsvLimitKind::Values => "values (samples × columns)",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_display_names_kind_and_index() {
        assert_eq!(Channel::Force(1).to_string(), "force channel 1");
        assert_eq!(
            Channel::Displacement(0).to_string(),
            "displacement channel 0"
        );
    }
}
