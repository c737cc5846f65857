//! [`Parameter`]: which numeric parameter an [`Error::InvalidParameter`](super::Error::InvalidParameter)
//! names, as an enum a program can match on, with the words messages and JSON have always used.

use std::fmt;

/// Declares [`Parameter`] from a table of variant → name, so each parameter is stated once.
macro_rules! parameters {
    ($($(#[$group:meta])* $variant:ident => $name:literal,)*) => {
        /// A numeric parameter that can be out of range ([`Error::InvalidParameter`](super::Error::InvalidParameter)).
        ///
        /// [`Parameter::as_str`] (and `Display`) give the words the message prints, e.g.
        /// `sample rate`; the variants are grouped by the stage that checks them.
        ///
        /// # Examples
        /// ```
        /// use bearing_ident::{Error, Parameter};
        /// use bearing_ident::spectra::Window;
        /// let e = Window::exponential(-1.0).unwrap_err();
        /// assert!(matches!(e, Error::InvalidParameter { name: Parameter::ExponentialWindowDecay, .. }));
        /// assert_eq!(Parameter::ExponentialWindowDecay.as_str(), "exponential window decay");
        /// ```
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[non_exhaustive]
        pub enum Parameter {
            $(#[doc = concat!("`", $name, "`,")] $(#[$group])* $variant,)*
        }

        impl Parameter {
            /// Every parameter, in the order of the table.
            pub const ALL: &'static [Parameter] = &[$(Parameter::$variant,)*];

            /// The parameter's name as messages and JSON print it.
            ///
            /// # Examples
            /// ```
            /// use bearing_ident::Parameter;
            /// assert_eq!(Parameter::SampleRate.as_str(), "sample rate");
            /// ```
            pub const fn as_str(self) -> &'static str {
                match self {
                    $(Parameter::$variant => $name,)*
                }
            }
        }
    };
}

parameters! {
    // ---- Records (`crate::records`) ----
    /// checked in `records`.
    TrimRangeEnd => "trim range end",
    /// checked in `records`.
    PlanePosition => "plane position",
    /// checked in `records`.
    DistanceBetweenThePlanes => "distance between the planes",
    /// checked in `records`.
    TransformedSample => "transformed sample",
    // ---- Geometry (`crate::job::Geometry`) ----
    /// checked in `job::Geometry`.
    GeometryPivot => "geometry pivot",
    /// checked in `job::Geometry`.
    GeometryBearing => "geometry bearing",
    /// checked in `job::Geometry`.
    GeometryProbes => "geometry probes",
    /// checked in `job::Geometry`.
    GeometryForces => "geometry forces",
    // ---- Spectra (`crate::spectra`) ----
    /// checked in `spectra`.
    ForceGate => "force gate",
    /// checked in `spectra`.
    ForceGateTaper => "force gate taper",
    /// checked in `spectra`.
    SegmentLength => "segment length",
    /// checked in `spectra`.
    SpectralSegmentLength => "spectral segment length",
    // ---- Stepped sine (`crate::stepped`) ----
    /// checked in `stepped`.
    SignalLength => "signal length",
    /// checked in `stepped`.
    SignalSample => "signal sample",
    /// checked in `stepped`.
    PhasorFrequency => "phasor frequency",
    /// checked in `stepped`.
    Signal => "signal",
    /// checked in `stepped`.
    StepTolerance => "step tolerance",
    // ---- FRFs (`crate::frf`) ----
    /// checked in `frf::transfer`.
    ChannelDelay => "channel delay",
    /// checked in `frf::transfer`.
    HighPassCorner => "high-pass corner",
    /// checked in `frf::transfer`.
    HighPassOrder => "high-pass order",
    /// checked in `frf::transfer`.
    CorrectedChannel => "corrected channel",
    /// checked in `frf`.
    FlexibilityLines => "flexibility lines",
    /// checked in `frf`.
    FlexibilityMatrixSize => "flexibility matrix size",
    /// checked in `frf`, `solve::ml::data`.
    Frequency => "frequency",
    // ---- Impact checks (`crate::quality`) ----
    /// checked in `quality`.
    DoubleHitRatio => "double_hit_ratio",
    /// checked in `quality`, `screening`.
    ClipRun => "clip_run",
    /// checked in `quality`.
    MinCrestFactor => "min_crest_factor",
    // ---- Record screening (`crate::screening`) ----
    /// checked in `screening`.
    DeadRatio => "dead_ratio",
    /// checked in `screening`.
    LevelSigmas => "level_sigmas",
    /// checked in `screening`.
    LevelFactor => "level_factor",
    /// checked in `screening`.
    SetSigmas => "set_sigmas",
    /// checked in `screening`.
    SetFloor => "set_floor",
    /// checked in `screening`.
    SetFraction => "set_fraction",
    // ---- The fits (`crate::solve`) ----
    /// checked in `solve::ivf`.
    IvfTolerance => "ivf tolerance",
    /// checked in `solve::ivf`.
    IvfMaxIterations => "ivf max iterations",
    /// checked in `solve::ml::crlb`.
    SystemSize => "system size",
    /// checked in `solve::ml::data`.
    MlDataLines => "ml data lines",
    /// checked in `solve::ml::data`.
    MlDataColumns => "ml data columns",
    /// checked in `solve::ml::data`.
    MlDataShape => "ml data shape",
    /// checked in `solve::ml::data`.
    MlData => "ml data",
    /// checked in `solve::ml::noise`, `solve::ml`.
    StartSize => "start size",
    /// checked in `solve::ml`.
    MlTolerance => "ml tolerance",
    // ---- Checks of a fit and per-frequency coefficients (`crate::gate`, `crate::per_frequency`) ----
    /// checked in `gate`.
    MinimumR2 => "minimum r²",
    /// checked in `per_frequency`, `spectra`.
    ExponentialWindowDecay => "exponential window decay",
    /// checked in `per_frequency`, `simulate::rig`.
    MassMatrix => "mass matrix",
    // ---- Settings of an identification (`crate::identify`) ----
    /// checked in `identify::calibration`.
    Calibration => "calibration",
    /// checked in `identify::calibration`.
    CalibrationChannel => "calibration channel",
    /// checked in `identify::calibration`.
    CalibrationUncertainty => "calibration uncertainty",
    /// checked in `identify::pipeline`.
    MinCoherence => "min_coherence",
    /// checked in `identify::settings`.
    UncertaintyWithMethodMl => "uncertainty with method ml",
    /// checked in `identify::settings`.
    BootstrapReplicates => "bootstrap replicates",
    /// checked in `identify::settings`.
    MinimumCoherence => "minimum coherence",
    /// checked in `identify::settings`.
    ConditionLimits => "condition limits",
    // ---- Kinds of test (`crate::excitation`, `crate::job`) ----
    /// checked in `excitation`, `job`.
    Period => "period",
    // ---- Distributions (`crate::statistics`) ----
    /// checked in `statistics`.
    ChiSquaredDegreesOfFreedom => "χ² degrees of freedom",
    /// checked in `statistics`.
    FNumeratorDegreesOfFreedom => "F numerator degrees of freedom",
    /// checked in `statistics`.
    FDenominatorDegreesOfFreedom => "F denominator degrees of freedom",
    /// checked in `statistics`.
    FDegreesOfFreedom => "F degrees of freedom",
    /// checked in `statistics`.
    TailProbability => "tail probability",
    /// checked in `statistics`.
    TestStatistic => "test statistic",
    // ---- Nonlinear elements (`crate::nonlinear`) ----
    /// checked in `nonlinear::regressor`.
    DegreesOfFreedomForCoulombPlanar => "degrees of freedom for coulomb-planar",
    /// checked in `nonlinear::velocity`.
    VelocityCutoff => "velocity cutoff",
    /// checked in `nonlinear::velocity`.
    SamplesToDifferentiate => "samples to differentiate",
    /// checked in `nonlinear::velocity`, `simulate::nonlinear`, `simulate::simulator`, `simulate::waveforms`, `simulate`, `spectra`, `stepped`.
    SampleRate => "sample rate",
    // ---- Simulation (`crate::simulate`) ----
    /// checked in `simulate::anti_alias`.
    AntiAliasOrder => "anti-alias order",
    /// checked in `simulate::anti_alias`.
    AntiAliasCutoffRatio => "anti-alias cutoff ratio",
    /// checked in `simulate::impact`, `simulate`.
    RecordDuration => "record duration",
    /// checked in `simulate::noise`.
    NoiseLevel => "noise level",
    /// checked in `simulate::nonlinear`, `simulate::simulator`.
    Samples => "samples",
    /// checked in `simulate::nonlinear`.
    NonlinearCoefficient => "nonlinear coefficient",
    /// checked in `simulate::nonlinear`.
    NonlinearTermDegreeOfFreedom => "nonlinear term degree of freedom",
    /// checked in `simulate::nonlinear`.
    FrictionSmoothing => "friction smoothing",
    /// checked in `simulate::nonlinear`.
    Oversampling => "oversampling",
    /// checked in `simulate::rig`.
    DampingMatrix => "damping matrix",
    /// checked in `simulate::rig`.
    StiffnessMatrix => "stiffness matrix",
    /// checked in `simulate::simulator`.
    ForceRms => "force rms",
    /// checked in `simulate::simulator`.
    PulseDuration => "pulse duration",
    /// checked in `simulate::simulator`.
    PulsePeak => "pulse peak",
    /// checked in `simulate::simulator`.
    PulseDirectionLength => "pulse direction length",
    /// checked in `simulate::simulator`.
    PulseStart => "pulse start",
    /// checked in `simulate::simulator`.
    HeldForceChannels => "held force channels",
    /// checked in `simulate::simulator`.
    HeldForceLength => "held force length",
    /// checked in `simulate::waveforms`.
    SineFrequency => "sine frequency",
    /// checked in `simulate::waveforms`.
    SineAmplitude => "sine amplitude",
    /// checked in `simulate::waveforms`.
    MultisinePeriod => "multisine period",
    /// checked in `simulate::waveforms`.
    MultisineLines => "multisine lines",
    /// checked in `simulate::waveforms`.
    MultisineRms => "multisine rms",
    /// checked in `simulate::waveforms`.
    SweepStartFrequency => "sweep start frequency",
    /// checked in `simulate::waveforms`.
    SweepEndFrequency => "sweep end frequency",
    /// checked in `simulate::waveforms`.
    SweepDuration => "sweep duration",
    /// checked in `simulate::waveforms`.
    SweepAmplitude => "sweep amplitude",
    /// checked in `simulate::waveforms`.
    BandNoiseLowFrequency => "band noise low frequency",
    /// checked in `simulate::waveforms`.
    BandNoiseHighFrequency => "band noise high frequency",
    /// checked in `simulate::waveforms`.
    BandNoiseRms => "band noise rms",
    /// checked in `simulate::waveforms`.
    BandNoiseSamples => "band noise samples",
    /// checked in `simulate::nonlinear`.
    InitialDisplacement => "initial displacement",
    /// checked in `simulate::nonlinear`.
    InitialVelocity => "initial velocity",
    // ---- Export (`crate::export`) ----
    /// checked in `export::ross`, `per_frequency`.
    MassMatrixSize => "mass matrix size",
    /// checked in `export::ross`.
    PerFrequencyLines => "per-frequency lines",
    // ---- Universal File writing (`crate::uff`) ----
    /// checked in `uff::write`.
    AbscissaLength => "abscissa length",
    /// checked in `uff::write`.
    UffValue => "UFF value",
    /// checked in `uff::write`.
    FunctionType => "function type",
    /// checked in `uff::write`.
    FunctionId => "function ID",
    /// checked in `uff::write`.
    VersionNumber => "version number",
    /// checked in `uff::write`.
    LoadCase => "load case",
    /// checked in `uff::write`.
    ResponseNode => "response node",
    /// checked in `uff::write`.
    ResponseDirection => "response direction",
    /// checked in `uff::write`.
    ReferenceNode => "reference node",
    /// checked in `uff::write`.
    ReferenceDirection => "reference direction",
    /// checked in `uff::write`.
    OrdinateType => "ordinate type",
    /// checked in `uff::write`.
    NumberOfPoints => "number of points",
    /// checked in `uff::write`.
    DataType => "data type",
    /// checked in `uff::write`.
    LengthExponent => "length exponent",
    /// checked in `uff::write`.
    ForceExponent => "force exponent",
    /// checked in `uff::write`.
    TemperatureExponent => "temperature exponent",
}

impl fmt::Display for Parameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::Parameter;

    #[test]
    fn names_are_distinct_and_display_as_named() {
        let mut names: Vec<&str> = Parameter::ALL.iter().map(|p| p.as_str()).collect();
        let n = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), n, "two parameters share a name");
        for p in Parameter::ALL {
            assert_eq!(p.to_string(), p.as_str());
        }
    }
}
