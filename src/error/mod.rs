//! The one error type of the crate and its [`Result`] alias.
//!
//! Every failure that a user's data can cause is a variant here, with named fields that carry the
//! numbers needed to find the problem: the record's label, the channel, the sample index, the
//! frequency line. Panics are reserved for broken API contracts and are documented under
//! `# Panics` where they can happen.
//!
//! What lives where: the [`Error`] enum is here, its variants grouped by the stage that raises
//! them, in the order data flows; `message.rs` holds their messages (the `Display` arms, with
//! the parts that need code) and the tests of the messages, `kind.rs` [`ErrorKind`] and
//! [`Error::kind`], `parameter.rs` the [`Parameter`]s an [`Error::InvalidParameter`] names, `convert.rs` the conversions from faer's
//! errors, `warning.rs` and `warning_text.rs` the [`Warning`]s and their sentences, `subject.rs`
//! what errors and warnings name ([`Channel`], [`Block`], …), `quote.rs` the bound on quoted
//! input ([`excerpt`]).
//!
//! The error is the floor every stage stands on, so it imports no stage: a figure or a
//! response kind appears by its name (`figure: "impedance"`, `response: "velocity"`), as
//! [`Choice::name`](crate::Choice::name) spells it. The exceptions are the two choices of a fit
//! a caller matches on, [`Method`](crate::Method) and [`Estimator`](crate::Estimator), plain
//! enums that hold no logic.

mod convert;
mod field;
mod kind;
mod message;
mod parameter;
mod quote;
mod subject;
mod table;
mod warning;
mod warning_text;

pub use field::FieldError;
pub use kind::ErrorKind;
pub use parameter::Parameter;
pub use quote::{QUOTE_CHARS, bounded, excerpt, excerpt_bytes};
#[cfg(feature = "csv")]
pub use subject::CsvLimitKind;
pub use subject::{BaselineField, Block, Channel, Factorization, Quantity, SpectrumKind};
pub use warning::{NoiseBiasBasis, Warning};

/// Everything that can go wrong in `bearing-ident`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    // ---- Arguments and limits, at any stage ----
    /// A numeric parameter is outside its valid range.
    InvalidParameter {
        /// Which parameter.
        name: Parameter,
        /// The value given.
        value: f64,
        /// The valid range, in words.
        expected: &'static str,
    },
    /// A setting that is not a number is invalid: settings that do not go together, or a
    /// text that does not parse as the setting's items.
    InvalidSetting {
        /// Which setting.
        name: Parameter,
        /// What is accepted, in words.
        expected: &'static str,
    },
    /// A name given for a choice (a method, an estimator, an excitation…) is not one of its
    /// names.
    UnknownName {
        /// What was being named: `"method"`, `"estimator"`, …
        what: &'static str,
        /// The name given.
        given: String,
        /// The accepted names, in words.
        expected: std::borrow::Cow<'static, str>,
    },
    /// An option of an identification from files ([`crate::job::Options`]) does not fit:
    /// a value that does not parse, or one the records cannot take (a period without periodic
    /// records, a period longer than the records). The message names the option as the
    /// command line spells it.
    ///
    // Without feature `job`, the link goes to the crate's feature list.
    #[cfg_attr(
        not(feature = "job"),
        doc = "[`crate::job::Options`]: crate#feature-flags"
    )]
    InvalidOption {
        /// The option's long name (`period`, `window`, …).
        option: &'static str,
        /// What is wrong, quoting at most 80 characters of the value.
        message: String,
    },
    /// A band given as text is not `LO,HI` in Hz.
    BandText {
        /// The text given (at most 80 characters of it).
        given: String,
    },
    /// A dry-structure baseline could not be had: its folder of records or its JSON file
    /// failed (the kind is that of the failure inside).
    Baseline {
        /// The folder or file given.
        path: String,
        /// What failed.
        source: Box<Error>,
    },
    /// A run that failed while the records look read the wrong way round: the forces not
    /// impulsive but the responses as impulsive as a hammer's (the kind is the failure's).
    LooksSwapped {
        /// What failed.
        failure: Box<Error>,
        /// Crest factor of the force channels (the strongest).
        force_crest: f64,
        /// Largest crest factor of the response channels.
        response_crest: f64,
    },
    /// Two inputs of a library function that must have one length do not.
    LengthMismatch {
        /// Which inputs.
        what: &'static str,
        /// The length of the first input.
        expected: usize,
        /// The length of the one that differs.
        actual: usize,
    },
    /// A requested size (samples, records, degrees of freedom, work) is past a documented limit
    /// of the crate.
    TooLarge {
        /// What was asked for, in words.
        what: &'static str,
        /// The size asked for (as `f64`: it may not fit any integer type).
        value: f64,
        /// The limit.
        limit: f64,
    },
    /// A file is past a reader's documented size rule (`crate::limits`): a line longer than
    /// a mebibyte, more values than a record may hold, a JSON text longer than 16 MiB. Reading
    /// stops there, before the input can exhaust memory.
    FileLimit {
        /// The file.
        path: String,
        /// What was counted, and where (`line 12: bytes of a line`).
        what: String,
        /// The limit.
        limit: u64,
    },
    // ---- Records and their excitations (`crate::records`, `crate::frf::assignment`, `crate::stepped`) ----
    /// A record's sampling rate is not a finite positive number.
    InvalidSampleRate {
        /// Label of the record.
        record: String,
        /// The rejected sampling rate in Hz.
        sample_rate: f64,
    },
    /// A record has no force channels or no displacement channels, or a different number of each.
    ChannelCount {
        /// Label of the record.
        record: String,
        /// Number of force channels given.
        forces: usize,
        /// Number of displacement channels given.
        displacements: usize,
    },
    /// A record was given a different number of response kinds than it has response channels.
    ResponseCount {
        /// Label of the record.
        record: String,
        /// Number of response channels.
        expected: usize,
        /// Number of kinds given.
        actual: usize,
    },
    /// A channel of a record is longer or shorter than the record's first force channel.
    ChannelLength {
        /// Label of the record.
        record: String,
        /// The channel whose length differs.
        channel: Channel,
        /// Length of the record's first force channel.
        expected: usize,
        /// Length of this channel.
        actual: usize,
    },
    /// A record is too short to carry a spectrum.
    RecordTooShort {
        /// Label of the record.
        record: String,
        /// Number of samples in the record.
        samples: usize,
        /// Smallest accepted number of samples.
        minimum: usize,
    },
    /// A sample is NaN or infinite.
    NonFinite {
        /// Label of the record.
        record: String,
        /// The channel holding the value.
        channel: Channel,
        /// Zero-based sample index.
        sample: usize,
        /// The offending value.
        value: f64,
    },
    /// Every force channel (or every displacement channel) of a record is flat: nothing was
    /// recorded, and the identification cannot use the record.
    DeadChannel {
        /// Label of the record.
        record: String,
        /// The first flat channel of the record.
        channel: Channel,
        /// The constant value it holds (N or m).
        value: f64,
    },
    /// The fit failed, and the screening had found a record far out of scale with its siblings
    /// (a channel dead or its level an outlier: a record scaled by 1e-12 or 1e20, a glitch
    /// sample): that record, not the excitations, is the cause. Leaving records with findings
    /// out ([`Screening::Reject`](crate::Screening::Reject)) rescues the run.
    BadRecord {
        /// Label of the record.
        record: String,
        /// What the screening found, in words.
        finding: String,
        /// The error the fit gave.
        failure: String,
    },
    /// No records were given.
    NoRecords,
    /// A record has a different number of degrees of freedom than asked for or than the others.
    DofMismatch {
        /// Label of the record.
        record: String,
        /// Expected number of degrees of freedom.
        expected: usize,
        /// The record's number of degrees of freedom.
        actual: usize,
    },
    /// Records in one identification have different sampling rates.
    SampleRateMismatch {
        /// Label of the record.
        record: String,
        /// Sampling rate of the first record (Hz).
        expected: f64,
        /// Sampling rate of this record (Hz).
        actual: f64,
    },
    /// Records in one identification have different lengths.
    RecordLengthMismatch {
        /// Label of the record.
        record: String,
        /// Length of the first record.
        expected: usize,
        /// Length of this record.
        actual: usize,
    },
    /// An explicit excitation assignment does not fit the records.
    InvalidAssignment {
        /// Label of the record.
        record: String,
        /// The excitation index given.
        excitation: usize,
        /// Number of degrees of freedom.
        dofs: usize,
    },
    /// An explicit excitation assignment has a different length than the record list.
    AssignmentLength {
        /// Number of records.
        expected: usize,
        /// Length of the assignment.
        actual: usize,
    },
    /// A step of a stepped-sine test has no record driving one of the directions.
    IncompleteStep {
        /// Drive frequency of the step (Hz).
        freq_hz: f64,
        /// The first direction without a record.
        direction: usize,
        /// Number of degrees of freedom.
        dofs: usize,
    },
    /// The force of the record that decides the excitation reads as more than one kind of test
    /// ([`Evidence::readings`](crate::excitation::Evidence::readings)): a feature near its
    /// threshold gives a different kind read either way. The user says which.
    UnclearExcitation {
        /// Label of the record.
        record: String,
        /// The kinds it reads as, in the order of [`Excitation`](crate::Excitation)'s
        /// variants.
        kinds: Vec<crate::Excitation>,
        /// What its force said.
        evidence: Box<crate::excitation::Evidence>,
    },
    // ---- Band, spectra and FRF (`crate::frf`, `crate::spectra`) ----
    // Overflow is named where it starts, not where a later stage would only see its effect.
    /// The frequency band is empty, inverted, negative or not finite.
    InvalidBand {
        /// Lower edge (Hz).
        low_hz: f64,
        /// Upper edge (Hz).
        high_hz: f64,
    },
    /// The band reaches above the Nyquist frequency of the records.
    BandAboveNyquist {
        /// Upper edge of the band (Hz).
        high_hz: f64,
        /// Half the sampling rate (Hz).
        nyquist_hz: f64,
    },
    /// The band holds too few frequency lines for the number of unknowns (an empty band
    /// included).
    TooFewLines {
        /// Usable lines in the band.
        lines: usize,
        /// Lines needed.
        required: usize,
        /// Spacing of the lines (Hz): the spectral resolution `fs / N` of the records or
        /// segments; `None` for a ready-made [`Frf`](crate::frf::Frf) of fewer than two lines.
        resolution_hz: Option<f64>,
    },
    /// A velocity or acceleration channel cannot be turned into displacement at a line where
    /// $s = \sigma + i\omega$ is zero (DC with no exponential window): $X = V/s$ is not defined.
    ResponseAtZeroFrequency {
        /// Label of the record.
        record: String,
        /// The response channel.
        channel: Channel,
        /// What it measures: the response kind's name
        /// ([`Response::name`](crate::records::Response), `"velocity"` or `"acceleration"`).
        response: &'static str,
        /// The line's frequency (Hz).
        freq_hz: f64,
    },
    /// A spectrum, or a product of spectra, of finite samples overflowed to infinity or NaN.
    SpectrumOverflow {
        /// Label of the record.
        record: String,
        /// Which spectrum.
        stage: SpectrumKind,
        /// The channel (for a cross-spectrum `S_ab`, channel `a`).
        channel: Channel,
        /// Frequency of the first line that overflowed (Hz).
        freq_hz: f64,
        /// Largest absolute sample of the channel.
        peak: f64,
    },
    /// Every force (or every displacement) channel of a record peaks so low that its squares
    /// underflow f64 (subnormal samples included), or a channel so high that they overflow:
    /// noted per record and named when the fit then fails.
    LevelOutOfRange {
        /// Label of the record.
        record: String,
        /// The channel (for an underflow, the kind's highest).
        channel: Channel,
        /// Its largest absolute sample.
        peak: f64,
    },
    /// The fit failed, and the impedance's level (force over response) is so far from 1 that
    /// the squares the fit forms of it or of its inverse leave f64: units far apart.
    ImpedanceScale {
        /// Median over the lines of the largest `|H_ij|` (N/m).
        magnitude: f64,
    },
    /// A quantity computed from finite spectra (impedance, flexibility, coefficients) is not
    /// finite.
    NonFiniteResult {
        /// Which quantity.
        stage: Quantity,
        /// Frequency of the first line where it appears (Hz).
        freq_hz: f64,
    },
    // ---- Conditioning and the fits (`crate::conditioning`, `crate::solve`) ----
    /// The excitations do not span all degrees of freedom.
    RankDeficient {
        /// Estimated rank of the excitation.
        rank: usize,
        /// Number of degrees of freedom.
        dofs: usize,
    },
    /// The stacked least-squares or instrumental-variable system is singular.
    SingularFit {
        /// The method that failed.
        method: crate::Method,
    },
    /// A matrix that must be inverted is singular.
    Singular {
        /// What was being inverted.
        what: &'static str,
    },
    /// A matrix decomposition from faer did not converge.
    Decomposition {
        /// Which decomposition.
        what: Factorization,
    },
    /// An iterative fit did not converge and the caller asked for convergence.
    NotConverged {
        /// The method.
        method: crate::Method,
        /// Iterations run.
        iterations: usize,
        /// Block-wise relative change at the last iteration (`None` where the fit does not
        /// report one).
        change: Option<f64>,
    },
    /// An iteration of the IVF (the fit, ML's start, the reverse path's linear part) met NaN or
    /// infinity: at a line (the model's impedance or its inverse), or in its normal equations.
    IterationNonFinite {
        /// The iterative method.
        method: crate::Method,
        /// The iteration (1 = the first after the least-squares start).
        iteration: usize,
        /// The line (Hz); `None` for the normal equations of all lines together.
        freq_hz: Option<f64>,
    },
    /// Maximum likelihood needs the records' spectra for its noise model: a ready-made FRF
    /// has none, and periodic records need at least 3 periods.
    MlNeedsRepeats,
    // ---- Coefficients and baselines (`crate::model`, `crate::identify`) ----
    /// Mass, damping and stiffness matrices do not have one common square shape.
    CoefficientShape {
        /// Shape of M.
        mass: (usize, usize),
        /// Shape of C.
        damping: (usize, usize),
        /// Shape of K.
        stiffness: (usize, usize),
    },
    /// A coefficient matrix holds NaN or infinity.
    NonFiniteCoefficient {
        /// The matrix: `M`, `C` or `K`.
        matrix: Block,
        /// Row index.
        row: usize,
        /// Column index.
        col: usize,
    },
    /// Two sets of coefficients that must be combined have different sizes.
    DofCountMismatch {
        /// Degrees of freedom of the left operand.
        left: usize,
        /// Degrees of freedom of the right operand.
        right: usize,
    },
    /// A dry-structure baseline was identified differently from the system it is subtracted
    /// from.
    BaselineMismatch {
        /// What differs.
        what: BaselineField,
    },
    /// A saved baseline (the JSON of an earlier identification) cannot be read (feature
    /// `json`, [`Baseline::from_json`](crate::Baseline::from_json)).
    #[cfg(feature = "json")]
    BadBaseline {
        /// What is wrong, naming the key; at most about 80 characters of the input are quoted.
        message: String,
    },
    // ---- Nonlinear elements (`crate::simulate`, `crate::nonlinear`) ----
    /// A nonlinear simulation stopped being finite: a term drove the state to infinity (a
    /// softening cubic past its turning point, a negative friction or damping), or the RK4 step
    /// is too long for a rate that grows with the amplitude (cubic stiffness, quadratic damping).
    SimulationDiverged {
        /// Label of the record.
        record: String,
        /// The first sample whose state is not finite.
        sample: usize,
        /// The RK4 step (s).
        step_s: f64,
    },
    /// A nonlinear regressor is not finite at a sample of a record (a cube beyond `f64`).
    NonFiniteRegressor {
        /// Label of the record.
        record: String,
        /// The term, as [`Term::label`](crate::nonlinear::Term::label) writes it.
        term: String,
        /// Zero-based sample index.
        sample: usize,
    },
    /// The records give too few Welch averages for the inputs of the reverse path.
    TooFewAverages {
        /// Welch segments over all records.
        averages: usize,
        /// Inputs: degrees of freedom plus nonlinear regressor channels.
        inputs: usize,
        /// Segments needed.
        required: usize,
    },
    /// A campaign plan or geometry file that is not well formed, at `file:line`.
    Plan {
        /// The file.
        file: String,
        /// The line (from 1).
        line: usize,
        /// What is wrong there (input quoted by at most 80 characters).
        message: String,
    },
    // ---- Field identification (`crate::field`) ----
    /// Field identification ([`field`](crate::field)) failed: its rotor model, test set or
    /// probes ([`FieldError`]).
    Field(FieldError),
    // ---- Files and figures at the edge (`crate::io`, `crate::uff`, `crate::export`, `crate::plot`) ----
    /// A file could not be opened, read or written.
    Io {
        /// The file.
        path: String,
        /// What the operating system said.
        message: String,
    },
    /// A CSV line is ragged or holds text that is not a number.
    #[cfg(feature = "csv")]
    Csv {
        /// The file.
        path: String,
        /// One-based line number.
        line: u64,
        /// What is wrong with the line.
        message: String,
    },
    /// A named column is not in a CSV file's header.
    #[cfg(feature = "csv")]
    MissingColumn {
        /// The file.
        path: String,
        /// The column asked for.
        column: String,
        /// The header's column names, comma-separated (at most 80 characters, then `…`).
        header: String,
    },
    /// A CSV value is NaN or infinite.
    #[cfg(feature = "csv")]
    CsvNonFinite {
        /// The file.
        path: String,
        /// One-based line number.
        line: u64,
        /// The column.
        column: String,
    },
    /// The time column of a CSV file is not uniformly sampled.
    #[cfg(feature = "csv")]
    NonUniformTime {
        /// The file.
        path: String,
        /// One-based line number.
        line: u64,
        /// Time on the uniform grid (s).
        expected_s: f64,
        /// Time in the file (s).
        actual_s: f64,
        /// Grid step (s).
        step_s: f64,
    },
    /// A line of a CSV file, its number of columns, or its number of values is past the
    /// reader's documented limit (see the limits of the `io` module, feature `csv`): reading
    /// stops there, before the input can exhaust memory.
    #[cfg(feature = "csv")]
    CsvLimit {
        /// The file.
        path: String,
        /// One-based line number where the limit was reached.
        line: u64,
        /// What was counted.
        what: CsvLimitKind,
        /// The limit.
        limit: u64,
    },
    /// A Universal File (dataset 58 / 58b) is malformed: a header field that is not a number, an
    /// unknown ordinate type, too few values, a binary block shorter than its byte count, a
    /// block that is never closed.
    #[cfg(feature = "uff")]
    Uff {
        /// The file (or the label given to [`uff::parse`](crate::uff::parse)).
        path: String,
        /// One-based number of the `-1`-delimited block in the file.
        block: usize,
        /// One-based line number in the file (of the line at fault, or where the block starts).
        line: u64,
        /// What is wrong.
        message: String,
    },
    /// Time histories read from a Universal File do not make a record: a load case without a
    /// force or displacement channel, channels of different lengths or sample rates, or an
    /// uneven abscissa.
    #[cfg(feature = "uff")]
    UffRecord {
        /// The file (or the label given).
        path: String,
        /// The load case (record 6) of the time histories.
        load_case: i64,
        /// What is wrong.
        message: String,
    },
    /// A TDMS file is malformed: a lead-in without its `TDSm` tag or cut short, a segment
    /// longer than the file, metadata cut short, an unknown data type, raw data that are not
    /// whole chunks of the declared sizes (feature `tdms`).
    #[cfg(feature = "tdms")]
    Tdms {
        /// The file (or the label given to [`tdms::parse`](crate::tdms::parse)).
        path: String,
        /// Byte offset in the file of the segment, metadata or data at fault.
        offset: u64,
        /// What is wrong.
        message: String,
    },
    /// A MATLAB MAT-file is malformed: not a MAT-file, truncated, a byte count, address or
    /// dimensions larger than the bytes that hold them, zlib data that do not inflate, a cycle
    /// of HDF5 links or references, an HDF5 feature a `-v7.3` file does not use (feature
    /// `mat`).
    #[cfg(feature = "mat")]
    Mat {
        /// The file.
        path: String,
        /// Byte offset in the file (of the element at fault, or of the compressed element it
        /// is inside).
        offset: u64,
        /// What is wrong.
        message: String,
    },
    /// A channel of a TDMS file named for a record is not in it, is named ambiguously, or its
    /// samples cannot be read (strings, a scaling other than linear or polynomial).
    #[cfg(feature = "tdms")]
    TdmsChannel {
        /// The file.
        path: String,
        /// The channel as named.
        channel: String,
        /// What is wrong.
        message: String,
        /// Whether the channel is there but its data are of a kind not read (kind
        /// `unsupported`) rather than missing (kind `missing_column`).
        unsupported: bool,
    },
    /// The channels of a TDMS file do not make a record: different lengths or rates, no rate,
    /// a time channel off its grid, no group holding them.
    #[cfg(feature = "tdms")]
    TdmsRecord {
        /// The file (or `FILE:GROUP`).
        path: String,
        /// What is wrong.
        message: String,
    },
    /// Variables of a MAT-file do not make a record: a channel that is not there, not real
    /// numbers (`char`, complex, sparse, an object such as `timetable`), a matrix without a
    /// column, no sample rate (feature `mat`).
    #[cfg(feature = "mat")]
    MatRecord {
        /// The file.
        path: String,
        /// The channel or variable, as named (`rec.fx`, `data:2`).
        variable: String,
        /// What was found.
        message: String,
    },
    /// An identification exported to a format of a fixed number of degrees of freedom has
    /// another: a ROSS bearing element (feature `ross`) is 2-DOF (`x`, `y`).
    ExportDofs {
        /// What was asked for.
        format: &'static str,
        /// Degrees of freedom of the identification.
        dofs: usize,
        /// Degrees of freedom the format takes.
        expected: usize,
    },
    /// A figure could not be drawn (feature `plot`).
    #[cfg(feature = "plot")]
    Plot {
        /// The figure's name (as [`Figure`](crate::plot::Figure) spells it, e.g.
        /// `"impedance"`).
        figure: &'static str,
        /// What the drawing library said.
        message: String,
    },
}

/// `Result` with the crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
