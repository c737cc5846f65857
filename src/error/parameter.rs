//! [`Parameter`]: which numeric parameter an [`Error::InvalidParameter`](super::Error::InvalidParameter)
//! names, as an enum a program can match on, with the words messages and JSON have always used.

use super::table::named_table;

named_table! {
    /// A numeric parameter that can be out of range
    /// ([`Error::InvalidParameter`](super::Error::InvalidParameter)), or a setting that is
    /// not a number ([`Error::InvalidSetting`](super::Error::InvalidSetting)).
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
    pub enum Parameter {
        // ---- Records (`crate::records`) ----
        /// `trim range end`, checked in `records`.
        TrimRangeEnd => "trim range end",
        /// `plane position`, checked in `records`.
        PlanePosition => "plane position",
        /// `distance between the planes`, checked in `records`.
        DistanceBetweenThePlanes => "distance between the planes",
        /// `transformed sample`, checked in `records`.
        TransformedSample => "transformed sample",
        // ---- Geometry (`crate::job::Geometry`) ----
        /// `geometry pivot`, checked in `job::Geometry`.
        GeometryPivot => "geometry pivot",
        /// `geometry bearing`, checked in `job::Geometry`.
        GeometryBearing => "geometry bearing",
        /// `geometry probes`, checked in `job::Geometry`.
        GeometryProbes => "geometry probes",
        /// `geometry forces`, checked in `job::Geometry`.
        GeometryForces => "geometry forces",
        // ---- Predicted bias (`crate::gate`) ----
        /// `lightest half-power bandwidth`, checked in `gate::leaked_flexibility`.
        LightestBandwidth => "lightest half-power bandwidth",
        // ---- Spectra (`crate::spectra`) ----
        /// `force gate`, checked in `spectra`.
        ForceGate => "force gate",
        /// `force gate taper`, checked in `spectra`.
        ForceGateTaper => "force gate taper",
        /// `segment length`, checked in `spectra`.
        SegmentLength => "segment length",
        /// `spectral segment length`, checked in `spectra`.
        SpectralSegmentLength => "spectral segment length",
        // ---- Stepped sine (`crate::stepped`) ----
        /// `signal length`, checked in `stepped`.
        SignalLength => "signal length",
        /// `signal sample`, checked in `stepped`.
        SignalSample => "signal sample",
        /// `phasor frequency`, checked in `stepped`.
        PhasorFrequency => "phasor frequency",
        /// `signal`, checked in `stepped`.
        Signal => "signal",
        /// `step tolerance`, checked in `stepped`.
        StepTolerance => "step tolerance",
        // ---- FRFs (`crate::frf`) ----
        /// `channel delay`, checked in `frf::transfer`.
        ChannelDelay => "channel delay",
        /// `high-pass corner`, checked in `frf::transfer`.
        HighPassCorner => "high-pass corner",
        /// `high-pass order`, checked in `frf::transfer`.
        HighPassOrder => "high-pass order",
        /// `corrected channel`, checked in `frf::transfer`.
        CorrectedChannel => "corrected channel",
        /// `channel transfer uncertainty`, checked in `frf::transfer`.
        TransferUncertainty => "channel transfer uncertainty",
        /// `flexibility lines`, checked in `frf`.
        FlexibilityLines => "flexibility lines",
        /// `flexibility matrix size`, checked in `frf`.
        FlexibilityMatrixSize => "flexibility matrix size",
        /// `frequency`, checked in `frf`, `solve::ml::data`.
        Frequency => "frequency",
        // ---- Impact checks (`crate::quality`) ----
        /// `double_hit_ratio`, checked in `quality`.
        DoubleHitRatio => "double_hit_ratio",
        /// `clip_run`, checked in `quality`, `screening`.
        ClipRun => "clip_run",
        /// `min_crest_factor`, checked in `quality`.
        MinCrestFactor => "min_crest_factor",
        // ---- Record screening (`crate::screening`) ----
        /// `dead_ratio`, checked in `screening`.
        DeadRatio => "dead_ratio",
        /// `level_sigmas`, checked in `screening`.
        LevelSigmas => "level_sigmas",
        /// `level_factor`, checked in `screening`.
        LevelFactor => "level_factor",
        /// `set_sigmas`, checked in `screening`.
        SetSigmas => "set_sigmas",
        /// `set_floor`, checked in `screening`.
        SetFloor => "set_floor",
        /// `set_fraction`, checked in `screening`.
        SetFraction => "set_fraction",
        // ---- The fits (`crate::solve`) ----
        /// `ivf tolerance`, checked in `solve::ivf`.
        IvfTolerance => "ivf tolerance",
        /// `ivf max iterations`, checked in `solve::ivf`.
        IvfMaxIterations => "ivf max iterations",
        /// `system size`, checked in `solve::ml::crlb`.
        SystemSize => "system size",
        /// `ml data lines`, checked in `solve::ml::data`.
        MlDataLines => "ml data lines",
        /// `ml data columns`, checked in `solve::ml::data`.
        MlDataColumns => "ml data columns",
        /// `ml data shape`, checked in `solve::ml::data`.
        MlDataShape => "ml data shape",
        /// `ml data`, checked in `solve::ml::data`.
        MlData => "ml data",
        /// `start size`, checked in `solve::ml::noise`, `solve::ml`.
        StartSize => "start size",
        /// `ml tolerance`, checked in `solve::ml`.
        MlTolerance => "ml tolerance",
        // ---- Checks of a fit and per-frequency coefficients (`crate::gate`, `crate::per_frequency`) ----
        /// `minimum r²`, checked in `gate`.
        MinimumR2 => "minimum r²",
        /// `exponential window decay`, checked in `per_frequency`, `spectra`.
        ExponentialWindowDecay => "exponential window decay",
        /// `mass matrix`, checked in `per_frequency`, `simulate::rig`.
        MassMatrix => "mass matrix",
        // ---- Settings of an identification (`crate::identify`) ----
        /// `calibration`, checked in `identify::calibration`.
        Calibration => "calibration",
        /// `calibration channel`, checked in `identify::calibration`.
        CalibrationChannel => "calibration channel",
        /// `calibration uncertainty`, checked in `identify::calibration`.
        CalibrationUncertainty => "calibration uncertainty",
        /// `min_coherence`, checked in `identify::pipeline`.
        MinCoherence => "min_coherence",
        /// `uncertainty with method ml`, checked in `identify::settings`.
        UncertaintyWithMethodMl => "uncertainty with method ml",
        /// `bootstrap replicates`, checked in `identify::settings`.
        BootstrapReplicates => "bootstrap replicates",
        /// `minimum coherence`, checked in `identify::settings`.
        MinimumCoherence => "minimum coherence",
        /// `condition limits`, checked in `identify::settings`.
        ConditionLimits => "condition limits",
        // ---- Kinds of test (`crate::excitation`, `crate::job`) ----
        /// `period`, checked in `excitation`, `job`.
        Period => "period",
        // ---- Distributions (`crate::statistics`) ----
        /// `χ² degrees of freedom`, checked in `statistics`.
        ChiSquaredDegreesOfFreedom => "χ² degrees of freedom",
        /// `F numerator degrees of freedom`, checked in `statistics`.
        FNumeratorDegreesOfFreedom => "F numerator degrees of freedom",
        /// `F denominator degrees of freedom`, checked in `statistics`.
        FDenominatorDegreesOfFreedom => "F denominator degrees of freedom",
        /// `F degrees of freedom`, checked in `statistics`.
        FDegreesOfFreedom => "F degrees of freedom",
        /// `tail probability`, checked in `statistics`.
        TailProbability => "tail probability",
        /// `test statistic`, checked in `statistics`.
        TestStatistic => "test statistic",
        // ---- Nonlinear elements (`crate::nonlinear`) ----
        /// `degrees of freedom for coulomb-planar`, checked in `nonlinear::regressor`.
        DegreesOfFreedomForCoulombPlanar => "degrees of freedom for coulomb-planar",
        /// `velocity cutoff`, checked in `nonlinear::velocity`.
        VelocityCutoff => "velocity cutoff",
        /// `samples to differentiate`, checked in `nonlinear::velocity`.
        SamplesToDifferentiate => "samples to differentiate",
        /// `sample rate`, checked in `nonlinear::velocity`, `simulate::nonlinear`, `simulate::simulator`, `simulate::waveforms`, `simulate`, `spectra`, `stepped`.
        SampleRate => "sample rate",
        // ---- Simulation (`crate::simulate`) ----
        /// `anti-alias order`, checked in `simulate::anti_alias`.
        AntiAliasOrder => "anti-alias order",
        /// `anti-alias cutoff ratio`, checked in `simulate::anti_alias`.
        AntiAliasCutoffRatio => "anti-alias cutoff ratio",
        /// `record duration`, checked in `simulate::impact`, `simulate`.
        RecordDuration => "record duration",
        /// `noise level`, checked in `simulate::noise`.
        NoiseLevel => "noise level",
        /// `samples`, checked in `simulate::nonlinear`, `simulate::simulator`.
        Samples => "samples",
        /// `nonlinear coefficient`, checked in `simulate::nonlinear`.
        NonlinearCoefficient => "nonlinear coefficient",
        /// `nonlinear term degree of freedom`, checked in `simulate::nonlinear`.
        NonlinearTermDegreeOfFreedom => "nonlinear term degree of freedom",
        /// `friction smoothing`, checked in `simulate::nonlinear`.
        FrictionSmoothing => "friction smoothing",
        /// `oversampling`, checked in `simulate::nonlinear`.
        Oversampling => "oversampling",
        /// `damping matrix`, checked in `simulate::rig`.
        DampingMatrix => "damping matrix",
        /// `stiffness matrix`, checked in `simulate::rig`.
        StiffnessMatrix => "stiffness matrix",
        /// `force rms`, checked in `simulate::simulator`.
        ForceRms => "force rms",
        /// `pulse duration`, checked in `simulate::simulator`.
        PulseDuration => "pulse duration",
        /// `pulse peak`, checked in `simulate::simulator`.
        PulsePeak => "pulse peak",
        /// `pulse direction length`, checked in `simulate::simulator`.
        PulseDirectionLength => "pulse direction length",
        /// `pulse start`, checked in `simulate::simulator`.
        PulseStart => "pulse start",
        /// `held force channels`, checked in `simulate::simulator`.
        HeldForceChannels => "held force channels",
        /// `held force length`, checked in `simulate::simulator`.
        HeldForceLength => "held force length",
        /// `sine frequency`, checked in `simulate::waveforms`.
        SineFrequency => "sine frequency",
        /// `sine amplitude`, checked in `simulate::waveforms`.
        SineAmplitude => "sine amplitude",
        /// `multisine period`, checked in `simulate::waveforms`.
        MultisinePeriod => "multisine period",
        /// `multisine lines`, checked in `simulate::waveforms`.
        MultisineLines => "multisine lines",
        /// `multisine rms`, checked in `simulate::waveforms`.
        MultisineRms => "multisine rms",
        /// `sweep start frequency`, checked in `simulate::waveforms`.
        SweepStartFrequency => "sweep start frequency",
        /// `sweep end frequency`, checked in `simulate::waveforms`.
        SweepEndFrequency => "sweep end frequency",
        /// `sweep duration`, checked in `simulate::waveforms`.
        SweepDuration => "sweep duration",
        /// `sweep amplitude`, checked in `simulate::waveforms`.
        SweepAmplitude => "sweep amplitude",
        /// `band noise low frequency`, checked in `simulate::waveforms`.
        BandNoiseLowFrequency => "band noise low frequency",
        /// `band noise high frequency`, checked in `simulate::waveforms`.
        BandNoiseHighFrequency => "band noise high frequency",
        /// `band noise rms`, checked in `simulate::waveforms`.
        BandNoiseRms => "band noise rms",
        /// `band noise samples`, checked in `simulate::waveforms`.
        BandNoiseSamples => "band noise samples",
        /// `initial displacement`, checked in `simulate::nonlinear`.
        InitialDisplacement => "initial displacement",
        /// `initial velocity`, checked in `simulate::nonlinear`.
        InitialVelocity => "initial velocity",
        /// `state pole`, checked in `simulate::states`.
        StatePole => "state pole",
        /// `state residue count`, checked in `simulate::states`.
        StateResidueCount => "state residue count",
        /// `state residue size`, checked in `simulate::states`.
        StateResidueSize => "state residue size",
        /// `state residue`, checked in `simulate::states`.
        StateResidue => "state residue",
        /// `decay with internal states`, checked in `simulate::states`.
        StateDecay => "decay with internal states",
        // ---- Export (`crate::export`) ----
        /// `mass matrix size`, checked in `export::ross`, `per_frequency`.
        MassMatrixSize => "mass matrix size",
        /// `per-frequency lines`, checked in `export::ross`.
        PerFrequencyLines => "per-frequency lines",
        // ---- Universal File writing (`crate::uff`) ----
        /// `abscissa length`, checked in `uff::write`.
        AbscissaLength => "abscissa length",
        /// `UFF value`, checked in `uff::write`.
        UffValue => "UFF value",
        /// `function type`, checked in `uff::write`.
        FunctionType => "function type",
        /// `function ID`, checked in `uff::write`.
        FunctionId => "function ID",
        /// `version number`, checked in `uff::write`.
        VersionNumber => "version number",
        /// `load case`, checked in `uff::write`.
        LoadCase => "load case",
        /// `response node`, checked in `uff::write`.
        ResponseNode => "response node",
        /// `response direction`, checked in `uff::write`.
        ResponseDirection => "response direction",
        /// `reference node`, checked in `uff::write`.
        ReferenceNode => "reference node",
        /// `reference direction`, checked in `uff::write`.
        ReferenceDirection => "reference direction",
        /// `ordinate type`, checked in `uff::write`.
        OrdinateType => "ordinate type",
        /// `number of points`, checked in `uff::write`.
        NumberOfPoints => "number of points",
        /// `data type`, checked in `uff::write`.
        DataType => "data type",
        /// `length exponent`, checked in `uff::write`.
        LengthExponent => "length exponent",
        /// `force exponent`, checked in `uff::write`.
        ForceExponent => "force exponent",
        /// `temperature exponent`, checked in `uff::write`.
        TemperatureExponent => "temperature exponent",
    }
}
