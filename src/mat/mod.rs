//! Edge: MATLAB MAT-files, level 5 (`save -v6`, `-v7`; compressed or not) and `-v7.3` (HDF5)
//! (feature `mat`).
//!
//! MATLAB, SciPy (`scipy.io.savemat`) and dynamic-signal analysers save arrays as MAT-files.
//! This module reads both formats ([`read`], [`parse`]) into the same [`Variable`]s — numeric
//! arrays of every class, structs, struct arrays and cell arrays, nested — and builds
//! [`Record`](crate::Record)s from them ([`records`], [`MatLayout`]). The `-v7.3` reader is
//! pure Rust (no HDF5 library): it reads the part of HDF5 that MATLAB and h5py write.
//!
//! # The layout of a level 5 MAT-file
//! | bytes | content |
//! |---|---|
//! | 0–115 | descriptive text (`MATLAB 5.0 MAT-file, …`) |
//! | 116–123 | subsystem data offset |
//! | 124–125 | version (`0x0100`) |
//! | 126–127 | `IM` read as two bytes: little-endian file; `MI`: big-endian |
//! | 128– | data elements, one per variable |
//!
//! A data element is a tag (type, byte count: two 32-bit words; or, in the small format, both
//! as 16-bit halves of one word and at most four bytes of data after them) and its data,
//! padded to a multiple of eight bytes. A variable is a `miMATRIX` element (array flags with
//! the class, dimensions, name, then the class's parts: real and imaginary data, the fields of
//! a struct, the cells of a cell array), or a `miCOMPRESSED` element holding one `miMATRIX`
//! deflated with zlib. Arrays are stored column by column (column-major).
//!
//! # The layout of a `-v7.3` MAT-file
//! A 512-byte user block whose first 128 bytes are a level 5 header (text `MATLAB 7.3
//! MAT-file, …`, version `0x0200`), then an HDF5 file (superblock version 0, or 2 and 3 as
//! h5py writes with `libver='latest'`; addresses count from the superblock). Each variable is
//! an object of the root group with an attribute `MATLAB_class`:
//! | MATLAB | HDF5 |
//! |---|---|
//! | numeric, logical array, M×N | dataset of dimensions N×M (C order: MATLAB's column-major bytes) |
//! | complex array | dataset of a compound `{real, imag}` (the imaginary parts are not kept) |
//! | struct | group, one member per field |
//! | struct array | group, each field a dataset of references, one per element |
//! | cell array | dataset of object references (to arrays in the group `#refs#`) |
//! | empty array | dataset holding its dimensions, attribute `MATLAB_empty` |
//! | `char`, sparse, objects | named by class, not read |
//!
//! Groups are read in both styles (symbol table: B-tree and local heap; link messages), object
//! headers in versions 1 and 2 with their continuation blocks, data compact, contiguous or
//! chunked (a version 1 B-tree, or one chunk), filtered by deflate and shuffle.
//!
//! # Safety on bad files
//! A file is read whole (at most [`MAX_FILE_BYTES`]); every byte count, dimension and field
//! count is checked against the bytes that remain before anything is allocated, a compressed
//! element inflates to at most [`MAX_INFLATE_RATIO`] times its size, and arrays nest at most
//! [`MAX_DEPTH`] deep, so memory stays bounded by a small multiple of the file's size. In a
//! `-v7.3` file every address and size is checked against the file's length, the data
//! decoded add up to at most [`MAX_INFLATE_RATIO`] times the file's size, its structures are
//! read at most 64 times over, and a link or reference back to an array that holds it (a cycle) is
//! refused. Whatever is wrong is an [`Error::Mat`] naming the file, the byte offset
//! and what was found.
//!
//! # Examples
//! ```
//! use bearing_ident::mat;
//! // A little-endian MAT-file holding `fs = 1000` (double, 1×1).
//! let mut bytes = vec![b' '; 116];
//! bytes.extend([0; 8]);
//! bytes.extend([0x00, 0x01, b'I', b'M']);
//! let element: Vec<u8> = [
//!     &14u32.to_le_bytes()[..], &56u32.to_le_bytes(),           // miMATRIX, 56 bytes
//!     &6u32.to_le_bytes(), &8u32.to_le_bytes(), &[6, 0, 0, 0, 0, 0, 0, 0], // flags: double
//!     &5u32.to_le_bytes(), &8u32.to_le_bytes(), &1i32.to_le_bytes(), &1i32.to_le_bytes(),
//!     &0x0002_0001u32.to_le_bytes(), b"fs\0\0",                     // name, small format
//!     &9u32.to_le_bytes(), &8u32.to_le_bytes(), &1000f64.to_le_bytes(),
//! ]
//! .concat();
//! bytes.extend(element);
//! let vars = mat::parse(&bytes, "mem.mat")?;
//! assert_eq!(vars[0].name, "fs");
//! assert_eq!(vars[0].array.samples(), Some(&[1000.0][..]));
//! # Ok::<(), bearing_ident::Error>(())
//! ```

mod records;
mod v5;
mod v73;
mod write;

use std::path::Path;

#[cfg(doc)]
use crate::error::Error;
use crate::error::{Result, excerpt};

pub use records::{MatChannel, MatLayout, records};
pub use v5::{MAX_DEPTH, MAX_INFLATE_RATIO};
pub use write::write;

/// Largest MAT-file read (2 GiB, the size past which MATLAB itself saves as `-v7.3`).
pub const MAX_FILE_BYTES: u64 = 1 << 31;

/// One variable of a MAT-file: its name and its array.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// The variable's name.
    pub name: String,
    /// Its value.
    pub array: Array,
}

/// A MATLAB array as read: dimensions are MATLAB's (at least two), elements column-major.
#[derive(Debug, Clone, PartialEq)]
pub enum Array {
    /// A numeric or logical array, its values as `f64` (64-bit integers rounded).
    Numeric {
        /// MATLAB's class name: `double`, `single`, `int8` … `uint64`, `logical`.
        class: &'static str,
        /// Dimensions.
        dims: Vec<usize>,
        /// Real parts, column-major.
        real: Vec<f64>,
        /// Whether the array is complex (its imaginary parts are not kept).
        complex: bool,
    },
    /// A struct or struct array (also an old-style object): its fields, and per element (in
    /// column-major order) one value per field.
    Struct {
        /// Dimensions of the struct array.
        dims: Vec<usize>,
        /// Field names, in the file's order.
        fields: Vec<String>,
        /// Per element, one array per field.
        elements: Vec<Vec<Array>>,
    },
    /// A cell array: its cells in column-major order.
    Cell {
        /// Dimensions.
        dims: Vec<usize>,
        /// The cells.
        cells: Vec<Array>,
    },
    /// Any other class (`char`, `sparse`, `function_handle`, MATLAB objects such as
    /// `timetable` or `string`): named, not read.
    Other {
        /// MATLAB's class name.
        class: &'static str,
        /// Dimensions.
        dims: Vec<usize>,
    },
}

impl Array {
    /// MATLAB's class name (`double`, `struct`, `cell`, `char`, …).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::mat::Array;
    /// let a = Array::Cell { dims: vec![1, 0], cells: vec![] };
    /// assert_eq!(a.class(), "cell");
    /// ```
    pub fn class(&self) -> &'static str {
        match self {
            Array::Numeric { class, .. } | Array::Other { class, .. } => class,
            Array::Struct { .. } => "struct",
            Array::Cell { .. } => "cell",
        }
    }

    /// The dimensions, as MATLAB's `size` gives them.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::mat::Array;
    /// let a = Array::Other { class: "char", dims: vec![1, 5] };
    /// assert_eq!(a.dims(), [1, 5]);
    /// ```
    pub fn dims(&self) -> &[usize] {
        match self {
            Array::Numeric { dims, .. }
            | Array::Struct { dims, .. }
            | Array::Cell { dims, .. }
            | Array::Other { dims, .. } => dims,
        }
    }

    /// `rows×columns` (or more dimensions), as MATLAB's workspace shows a size.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::mat::Array;
    /// let a = Array::Other { class: "char", dims: vec![1, 5] };
    /// assert_eq!(a.size_text(), "1×5");
    /// ```
    pub fn size_text(&self) -> String {
        let dims: Vec<String> = self.dims().iter().map(usize::to_string).collect();
        dims.join("×")
    }

    /// The values of a real numeric array, column-major; `None` for any other array.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::mat::Array;
    /// let a = Array::Numeric { class: "double", dims: vec![1, 2], real: vec![1.0, 2.0], complex: false };
    /// assert_eq!(a.samples(), Some(&[1.0, 2.0][..]));
    /// ```
    pub fn samples(&self) -> Option<&[f64]> {
        match self {
            Array::Numeric {
                real,
                complex: false,
                ..
            } => Some(real),
            _ => None,
        }
    }
}

/// Parses the bytes of a MAT-file, level 5 or `-v7.3` (HDF5): every named variable, in the
/// file's order.
///
/// A file whose first bytes read `MATLAB 7.3`, or that holds HDF5's signature at byte 0 or
/// 512, is read as `-v7.3`; any other as level 5. The unnamed subsystem data MATLAB appends
/// for objects (level 5) and its `#refs#` and `#subsystem#` groups (`-v7.3`) are skipped.
///
/// # Errors
/// [`Error::Mat`] naming `label`, the byte offset and what is wrong. Level 5: a header that
/// is not a MAT-file's (a `-v4` file has none), a truncated element, a byte count or
/// dimensions larger than the bytes that hold them, zlib data that does not inflate, an
/// unknown element type. `-v7.3`: no HDF5 superblock, an address or size past the end of the
/// file, a structure without its signature, a cycle of links, references or B-tree nodes, an
/// HDF5 feature MATLAB does not write (offsets other than 8 bytes, filters other than
/// deflate and shuffle, HDF5 1.10's chunk indexes, dense link storage), data larger than
/// [`MAX_INFLATE_RATIO`] times the file. Both: arrays nested deeper than [`MAX_DEPTH`].
///
/// # Examples
/// ```
/// let e = bearing_ident::mat::parse(b"not a MAT-file", "x.mat").unwrap_err();
/// assert_eq!(e.kind(), "malformed_mat");
/// assert!(e.to_string().starts_with("x.mat, byte 0:"), "{e}");
/// let e = bearing_ident::mat::parse(&[b"MATLAB 7.3 MAT-file".as_slice(), &[0; 600]].concat(), "y.mat")
///     .unwrap_err();
/// assert!(e.to_string().contains("no HDF5 signature"), "{e}");
/// ```
pub fn parse(bytes: &[u8], label: &str) -> Result<Vec<Variable>> {
    let hdf5 = |at: usize| bytes.get(at..at + 8) == Some(v73::SIGNATURE.as_slice());
    if bytes.starts_with(b"MATLAB 7.3") || hdf5(0) || hdf5(512) {
        v73::parse(bytes, label)
    } else {
        v5::parse(bytes, label)
    }
}

/// Dimensions as `[a, b, c]` for messages: at most four, then how many more.
fn dims_text<T: std::fmt::Display>(dims: &[T]) -> String {
    let shown: Vec<String> = dims.iter().take(4).map(T::to_string).collect();
    match dims.len() {
        0..=4 => format!("[{}]", shown.join(", ")),
        n => format!("[{}, … {} more]", shown.join(", "), n - 4),
    }
}

/// Whether `path` is a MAT-file (`.mat`, any case).
///
/// # Examples
/// ```
/// assert!(bearing_ident::mat::is_mat("rig/hit-3.MAT".as_ref()));
/// assert!(!bearing_ident::mat::is_mat("rig/hit-3.csv".as_ref()));
/// ```
pub fn is_mat(path: &Path) -> bool {
    path.extension()
        .and_then(|x| x.to_str())
        .is_some_and(|x| x.eq_ignore_ascii_case("mat"))
}

/// Reads every variable of a MAT-file, level 5 or `-v7.3` ([`parse`]).
///
/// # Errors
/// [`Error::Io`] if the file cannot be opened or read; [`Error::FileLimit`] past
/// [`MAX_FILE_BYTES`]; [`Error::Mat`] as [`parse`].
///
/// # Examples
/// ```
/// let e = bearing_ident::mat::read("/nonexistent/hit.mat").unwrap_err();
/// assert_eq!(e.kind(), "io_error");
/// ```
pub fn read(path: impl AsRef<Path>) -> Result<Vec<Variable>> {
    let path = path.as_ref();
    let label = excerpt(&path.display().to_string());
    let bytes =
        crate::limits::read_bytes(path, Some("*.mat"), MAX_FILE_BYTES, "bytes of a MAT-file")?;
    parse(&bytes, &label)
}
