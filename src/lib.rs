//! # bearing-ident
//!
//! Identification of the dynamic force coefficients of fluid-film bearings, seals and squeeze
//! film dampers — the `n × n` stiffness `K`, damping `C` and added-mass `M` matrices — from
//! measured forces and displacements.
//!
//! The test element is modelled as a linear system about an equilibrium,
//!
//! $$ M\ddot x + C\dot x + K x = f(t), \qquad
//!    H(\omega) = K - \omega^2 M + i\omega C, \qquad G(\omega) = H(\omega)^{-1}, $$
//!
//! with `M`, `C`, `K` real and not necessarily symmetric. Independent excitations (impacts in x
//! and y, shakers) give the impedance `H` per frequency line; fits over a band give `M`, `C`,
//! `K`, by a direct per-element fit, least squares on the flexibilities, or the
//! instrumental-variable filter (IVF) of Fritzen, which removes the noise bias of least squares.
//!
//! ## Quick start
//! ```
//! use bearing_ident::{Identifier, Method};
//! use bearing_ident::simulate::{ImpactTest, seed_rig};
//!
//! // The 2-DOF test rig of Diaz & San Andrés (1999): 8 impacts per direction,
//! // 6700 samples/s for 1.2 s, 2 % noise.
//! let truth = seed_rig();
//! let records = ImpactTest { noise: 0.02, ..ImpactTest::seed_rig() }.run(&truth)?;
//! let id = Identifier::new(8.0, 49.0).method(Method::Ivf).identify(&records)?;
//!
//! let k = id.coefficients().stiffness();
//! assert!((k[(0, 0)] / 146.3e3 - 1.0).abs() < 0.01);
//! assert!(id.converged());
//! let modes = id.modes()?;
//! assert!((modes[0].natural_frequency_hz - 27.5).abs() < 0.5);
//! # Ok::<(), bearing_ident::Error>(())
//! ```
//!
//! New to the method? The guide in the repository, `docs/guide/` (start with
//! `01-one-test-point.md`), works one test point through by hand and then with this crate,
//! chapter by chapter: excitations, estimators, error bars, campaigns, field identification,
//! nonlinear elements, element models, lab files, the rotor; its reference chapters list every
//! option and output of the command-line tool.
//!
//! ## The pipeline
//! Modules follow the data, each importing only those before it:
//!
//! 1. [`records`] — validated time records ([`Record`]);
//! 2. [`spectra`] — windows and planned FFTs ([`spectra::SpectralEstimator`]);
//! 3. [`frf`] — impedance and flexibility per line, by paired sets or MIMO H1, H2, Hv;
//!    [`stepped`] — the same at the drive frequencies of a stepped-sine test;
//! 4. [`conditioning`] — condition numbers, warnings, refusal of rank-deficient excitation;
//! 5. [`model`] — [`Coefficients`]: `H(ω)`, `G(ω)`, modes, baseline subtraction;
//! 6. [`solve`] — the direct, least-squares, IVF and maximum-likelihood fits; [`gate`] — the
//!    checks of a finished fit and of its settings (poor `r²`, unphysical or unstable models,
//!    dependent replicates, degenerate windows, gates and resolutions), each a [`Warning`];
//!    [`per_frequency`] — `K(ω)`, `C(ω)` line by line, with error bars and effective
//!    coefficients;
//! 7. [`identify`] — the [`Identifier`] façade, its checked settings ([`Settings`]), the error
//!    bars ([`Uncertainty`]) and its [`Identification`] result;
//! 8. [`excitation`] — the kind of test ([`Excitation`]): detected from the records' force
//!    (crest factor, tone, sweep, period), and the estimator, segmentation and window each
//!    kind calls for.
//!
//! Beside the linear pipeline, [`nonlinear`] identifies M, C, K together with dry friction,
//! cubic stiffness or quadratic damping by the reverse path (the nonlinear forces as extra
//! inputs, each with its coefficient spectrum and a model check), from the same records and
//! stages.
//!
//! [`screening`] screens records of every excitation for dead and flat channels, identical
//! records, clipping, level outliers and paired sets far from the others (with [`quality`]'s
//! double-hit and clipping checks), before and after they reach the spectra. Beneath every
//! stage sit [`error`] (the one [`Error`], the [`Warning`]s, the quoting rule),
//! [`tolerance`] (every numerical tolerance with its reason) and [`text`] (numbers as every
//! table and report prints them). [`simulate`] produces exact time
//! records of a known system, linear or nonlinear, for learning and testing. `ARCHITECTURE.md` in the repository
//! maps every concept to its file and gives the recipes for adding an estimator, a window, a
//! solver or a file reader.
//!
//! ## Conventions
//! - **Units:** SI throughout — N, m, s, kg; `K` in N/m, `C` in N·s/m, `M` in kg.
//! - **Frequency:** Hz at the API surface, `ω = 2πf` in rad/s inside the maths.
//! - **DFT:** $X_k = \Delta t \sum_m x_m e^{-2\pi i k m/N}$, one-sided (`k = 0…N/2`), mean
//!   removed; so `ẋ → iωX` and `ẍ → −ω²X`.
//! - **Direction of transfer functions:** `G` maps force to displacement (`X = G F`), `H` maps
//!   displacement to force (`F = H X`); element `(i, j)` is output `i` per input `j`.
//! - **System vs element:** identified coefficients are those of the whole test system; the
//!   bearing's own are system minus dry structure ([`Coefficients::subtract`]).
//!
//! ## Feature flags
//! The core depends only on faer, num-complex, realfft, thiserror, rand, rand_distr (the
//! simulators' noise) and statrs (the χ² and F tails of the model check). Edges are opt-in:
//! - `csv` — [`io`]: read and write records as CSV files;
//! - `json` — [`Baseline::from_json`]: a dry-structure baseline read back from a saved
//!   identification (implies `serde`);
//! - `serde` — `Serialize` for [`Identification`], [`Coefficients`] and [`Mode`];
//! - `plot` — [`plot`]: SVG figures of an identification (flexibility, impedance, coherence
//!   and conditioning, per-frequency coefficients, time records, IVF convergence, the model
//!   check's residuals), of a nonlinear and of a field identification, and static HTML
//!   reports, drawn by plotters' SVG backend (no system libraries);
//! - `uff` — [`uff`]: read and write Universal File Format dataset 58 / 58b (time histories,
//!   FRFs, coherence, spectra; ASCII and binary) and build records from its time histories;
//! - `tdms` — [`tdms`]: TDMS files of NI LabVIEW and DAQmx (every numeric type, little- and
//!   big-endian, interleaved and contiguous, incremental metadata, linear and polynomial
//!   scaling) and records from their channels; no dependencies;
//! - `mat` — [`mat`]: read MATLAB MAT-files, level 5 (`-v6`, `-v7`; compressed or not) and
//!   `-v7.3` (HDF5, read in pure Rust), and build records from their variables, struct fields, matrix columns, struct and cell arrays;
//! - `ross` — [`export::ross`]: an identified 2-DOF bearing as a ROSS 3.x bearing element
//!   (TOML or JSON), constant or per frequency; with `uff`, [`export::uff`] writes the measured
//!   and model FRFs and the coherences of an identification as dataset 58 functions;
//! - `cli` — the `bearing-ident` command-line tool (implies `uff`, `mat`, `ross`, `csv`, `json`,
//!   `serde` and `plot`);
//! - `rayon` — per-record FFTs in parallel and [`Identifier::identify_batch`] over many test
//!   conditions in parallel, with results bit for bit those of the sequential build;
//! - `job` — [`job`]: one path from record files (CSV, Universal File, TDMS, MAT-file) to a
//!   result, as the command line's `identify` takes it (implies `csv`, `uff`, `tdms`, `mat`).
//!
//! ## References
//! - C.-P. Fritzen (1985), *Identification of mass, damping and stiffness matrices of
//!   mechanical systems*, ASME paper 85-DET-91.
//! - S. Diaz and L. San Andrés (1999), *A method for identification of bearing force
//!   coefficients and its application to a squeeze film damper with a bubbly lubricant*, STLE
//!   Tribology Transactions 42(4), 739–746.
//! - H. Massmann and R. Nordmann (1985), *Some new results concerning the dynamic behavior of
//!   annular turbulent seals*, NASA CP 2409, 179–194.
//! - J. S. Bendat and A. G. Piersol, *Random Data: Analysis and Measurement Procedures*, Wiley.
//!
// Without its feature, an item of the feature list links to the list.
#![cfg_attr(not(feature = "csv"), doc = "[`io`]: crate#feature-flags")]
#![cfg_attr(
    not(feature = "json"),
    doc = "[`Baseline::from_json`]: crate#feature-flags"
)]
#![cfg_attr(not(feature = "plot"), doc = "[`plot`]: crate#feature-flags")]
#![cfg_attr(not(feature = "uff"), doc = "[`uff`]: crate#feature-flags")]
#![cfg_attr(not(feature = "tdms"), doc = "[`tdms`]: crate#feature-flags")]
#![cfg_attr(not(feature = "mat"), doc = "[`mat`]: crate#feature-flags")]
#![cfg_attr(not(feature = "ross"), doc = "[`export::ross`]: crate#feature-flags")]
#![cfg_attr(not(feature = "uff"), doc = "[`export::uff`]: crate#feature-flags")]
#![cfg_attr(not(feature = "job"), doc = "[`job`]: crate#feature-flags")]
#![warn(missing_docs)]
#![forbid(unsafe_code)]
#![deny(clippy::float_cmp)]

#[cfg(feature = "campaign")]
pub mod campaign;
pub mod choice;
pub mod conditioning;
pub mod element;
pub mod error;
pub mod excitation;
#[cfg(any(feature = "uff", feature = "ross"))]
pub mod export;
pub mod field;
pub mod frf;
pub mod gate;
pub mod identify;
#[cfg(feature = "csv")]
pub mod io;
#[cfg(feature = "job")]
pub mod job;
#[cfg(feature = "json")]
pub mod json;
mod kept;
mod lanes;
pub mod limits;
mod linalg;
#[cfg(feature = "mat")]
pub mod mat;
pub mod model;
pub mod nonlinear;
pub mod per_frequency;
#[cfg(feature = "plot")]
pub mod plot;
pub mod quality;
pub mod records;
pub mod rotor;
pub mod screening;
pub mod simulate;
pub mod solve;
pub mod spectra;
pub mod statistics;
pub mod stepped;
#[cfg(feature = "tdms")]
pub mod tdms;
pub mod text;
pub mod tolerance;
#[cfg(feature = "uff")]
pub mod uff;
pub mod units;

// The types the façade's signatures name, at the crate root.
pub use choice::Choice;
pub use conditioning::{ConditionLimits, Conditioning};
pub use error::{Block, Channel, Error, ErrorKind, Parameter, Result, Warning};
pub use excitation::Excitation;
pub use frf::{Assignment, Band, Estimator, Frf};
pub use gate::FitGate;
pub use identify::{
    Baseline, Identification, Identifier, NonConvergence, Screening, Settings, Uncertainty,
};
pub use model::{Coefficients, Mode};
pub use per_frequency::PerFrequency;
pub use quality::ImpactChecks;
pub use records::{Record, Response};
pub use solve::ml::{MlOptions, MlReport};
pub use solve::{Convergence, Fit, Iteration, IvfOptions, Method};
pub use spectra::{ForceGate, Segmentation, Window};

pub use faer;
pub use num_complex;

#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

/// The Rust blocks of the guide run as doctests too.
#[cfg(doctest)]
#[doc = include_str!("../docs/guide/01-one-test-point.md")]
struct GuideOneTestPointDoctests;
