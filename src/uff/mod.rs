//! Edge: Universal File Format dataset 58 and 58b (feature `uff`).
//!
//! Data-acquisition and modal software (and pyuff, UFFFiles.jl) exchange time histories, FRFs,
//! coherences and spectra as *function at nodal DOF* blocks of the Universal File Format. A file
//! is a sequence of blocks, each between two lines `    -1`; the line after the opening `-1`
//! names the dataset. This module reads and writes dataset 58 (ASCII) and 58b (binary values),
//! skips every other dataset, and builds [`Record`](crate::Record)s from time histories
//! ([`records`]: forces of data type 13; displacement, velocity and acceleration responses of
//! data types 8, 11 and 12), or from channels named by node and direction or ID line
//! ([`records_with`], [`UffLayout`], [`UffChannel`]).
//!
//! # The layout of a dataset 58 block
//! | record | format | content |
//! |---|---|---|
//! | 1–5 | `80A1` | ID lines: description, name, date and time, two more ([`Function::id`]) |
//! | 6 | `2(I5,I10),2(1X,10A1,I10,I4)` | function type, function ID, version, load case; response entity, node, direction; reference entity, node, direction |
//! | 7 | `3I10,3E13.5` | ordinate type (2 real single, 4 real double, 5 complex single, 6 complex double), number of points `n`, spacing (1 even, 0 uneven), abscissa minimum `x0`, increment `dx`, z-axis value |
//! | 8–11 | `I10,3I5,2(1X,20A1)` | abscissa, ordinate numerator, ordinate denominator and z-axis: data type (17 time, 18 frequency, 8 displacement, 11 velocity, 12 acceleration, 13 excitation force, …), length, force and temperature unit exponents, label, units label |
//! | 12 | see below | the values |
//!
//! Record 12 is written in fixed-width Fortran fields, one line after another; neighbouring
//! fields may touch (`-1.23E-01-4.56E-02`), exponents may have three digits or the letter `D`:
//!
//! | ordinate | even spacing | uneven spacing (`x` then the value) |
//! |---|---|---|
//! | real single | `6E13.5` | `6E13.5` (three pairs) |
//! | complex single | `6E13.5` (three values) | `6E13.5` (two triples) |
//! | real double | `4E20.12` | `2(E13.5,E20.12)` |
//! | complex double | `4E20.12` (two values) | `E13.5,2E20.12` |
//!
//! A 58b block has the same eleven header lines; its dataset line
//! `    58b     1     2          11        6408 …` (`I6,A1,I6,I6,I12,I12,…`) gives the byte
//! order (1 little-, 2 big-endian), the float format (2 IEEE 754), the number of ASCII lines
//! (11) and the number of bytes of values that follow the header. The values are those of
//! record 12 in the same order, as `f32` (single) or `f64` (double); an uneven abscissa is always
//! `f32`. The block is skipped by its byte count, never by scanning for `-1`.
//!
//! # Precision
//! The abscissa minimum and increment of record 7 and an uneven abscissa carry six significant
//! digits (`E13.5`, or `f32` in 58b); ASCII double values carry thirteen (`E20.12`). Binary
//! double values round-trip exactly. A time history written for [`records`] should therefore
//! use a sampling interval that six digits hold (e.g. 1/5000 s, not 1/6700 s).
//!
//! # Reading
//! [`read`] and [`parse`] return every dataset 58/58b block of a file as a [`Function`], in file
//! order. A field is read by its Fortran width first; a line whose fields do not parse at their
//! widths is split at whitespace instead (some writers use free format). Lines may end in
//! `\n` or `\r\n`; a last line of values may be short. Every problem is an
//! [`Error::Uff`](crate::Error::Uff) naming the file, the block (one-based) and the line; no
//! input makes the reader panic, and no count in a file sizes an allocation beyond the bytes
//! actually present.
//!
//! # Examples
//! ```
//! use bearing_ident::uff::{self, Abscissa, Function, FunctionType, Ordinate};
//! let f = Function::time_response(1, 3, 13, 0.0, 2e-4, vec![1.0, -2.5, 0.25]);
//! let mut bytes = Vec::new();
//! uff::write(&mut bytes, std::slice::from_ref(&f))?;
//! let back = uff::parse(&bytes, "mem.uff")?;
//! assert_eq!(back[0].function_type, FunctionType::TimeResponse);
//! assert_eq!(back[0].abscissa, Abscissa::Even { x0: 0.0, dx: 2e-4, n: 3 });
//! assert_eq!(back[0].ordinate, Ordinate::Real(vec![1.0, -2.5, 0.25]));
//! # Ok::<(), bearing_ident::Error>(())
//! ```

mod fortran;
mod read;
mod records;
mod types;
mod write;

pub use read::{parse, read};
pub use records::{UffChannel, UffLayout, record, records, records_with};
pub use types::{Abscissa, Axis, DataType, Dof, Function, FunctionType, Ordinate, Precision};
pub use write::{ByteOrder, write, write_binary};
