//! MATLAB `-v7.3` MAT-files: HDF5 files ([`hdf5`]) whose objects MATLAB's attributes name.
//!
//! MATLAB writes each variable as an HDF5 object of the root group with an attribute
//! `MATLAB_class`: numeric and logical arrays, `char` (UTF-16 code units) as datasets whose
//! dimensions are MATLAB's reversed (an M×N matrix is stored N×M in C order: the same bytes as
//! column-major M×N); a struct as a group whose members are its fields; a cell array as a
//! dataset of object references to arrays kept in the group `#refs#`; a struct array as a
//! group whose fields are datasets of references, one per element; an empty array as a
//! dataset holding its dimensions, with `MATLAB_empty`; complex numbers as a compound
//! `{real, imag}`.

mod hdf5;

use std::collections::HashSet;

use crate::error::{Result, excerpt};

use super::{Array, MAX_DEPTH, Variable};
use hdf5::{Attribute, Datatype, File, Node};

pub(super) use hdf5::SIGNATURE;

/// What [`Array::Other`] names a class this reader does not know by.
pub(super) const OPAQUE: &str = "object (opaque: timetable, string, table …)";

/// MATLAB classes named as they are; any other is [`OPAQUE`].
const CLASSES: [&str; 22] = [
    "double",
    "single",
    "int8",
    "uint8",
    "int16",
    "uint16",
    "int32",
    "uint32",
    "int64",
    "uint64",
    "logical",
    "char",
    "cell",
    "struct",
    "sparse",
    "function_handle",
    "string",
    "datetime",
    "duration",
    "categorical",
    "table",
    "timetable",
];

/// Parses the bytes of a `-v7.3` MAT-file: every variable of the root group, in the file's
/// order (MATLAB's own `#refs#` and `#subsystem#` groups are skipped).
pub(super) fn parse(bytes: &[u8], label: &str) -> Result<Vec<Variable>> {
    let file = File::open(bytes, label)?;
    let (_, root) = file.object(file.root)?;
    let Node::Group(links) = root else {
        return Err(file.bad(
            file.position(file.root),
            "the root object is a dataset, not a group".into(),
        ));
    };
    let mut reader = Matlab {
        file,
        path: HashSet::new(),
    };
    let mut variables = Vec::new();
    for (name, address) in links {
        if name.starts_with('#') {
            continue;
        }
        let array = reader.array(address, &excerpt(&name), 0)?;
        variables.push(Variable { name, array });
    }
    Ok(variables)
}

/// The file and the objects on the path from the root to the one being read (a reference
/// back to one of them is a cycle).
struct Matlab<'a> {
    file: File<'a>,
    path: HashSet<u64>,
}

/// The attributes MATLAB writes that this reader reads.
struct Marks {
    class: Option<String>,
    empty: bool,
    sparse: Option<f64>,
}

impl<'a> Matlab<'a> {
    /// The attributes `MATLAB_class`, `MATLAB_empty`, `MATLAB_sparse`.
    fn marks(&self, attributes: &[Attribute<'a>]) -> Result<Marks> {
        let mut marks = Marks {
            class: None,
            empty: false,
            sparse: None,
        };
        for a in attributes {
            match a.name.as_str() {
                "MATLAB_class" => {
                    let (datatype, _, data) = self.file.attribute_value(a)?;
                    if let Datatype::String { .. } = datatype {
                        let text = data.split(|&b| b == 0).next().unwrap_or_default();
                        marks.class = Some(String::from_utf8_lossy(text).trim().to_owned());
                    }
                }
                "MATLAB_empty" | "MATLAB_sparse" => {
                    let (datatype, _, data) = self.file.attribute_value(a)?;
                    let value = datatype
                        .numbers(data)
                        .and_then(|v| v.first().copied())
                        .unwrap_or(0.0);
                    if a.name == "MATLAB_empty" {
                        marks.empty = value != 0.0;
                    } else {
                        marks.sparse = Some(value);
                    }
                }
                _ => {}
            }
        }
        Ok(marks)
    }

    /// The array of the object at `address` (`name` as a path for messages), nested `depth`
    /// deep.
    fn array(&mut self, address: u64, name: &str, depth: usize) -> Result<Array> {
        let at = self.file.position(address);
        if depth > MAX_DEPTH {
            return Err(self.file.bad(
                at,
                format!("`{name}`: arrays nested deeper than {MAX_DEPTH}"),
            ));
        }
        if !self.path.insert(address) {
            return Err(self.file.bad(
                at,
                format!("`{name}` refers back to an array that holds it: a cycle"),
            ));
        }
        let (attributes, node) = self.file.object(address)?;
        let marks = self.marks(&attributes)?;
        let array = match node {
            Node::Dataset(d) => self.dataset(&d, &marks, name, depth),
            Node::Group(links) => self.group(links, &marks, name, depth, at),
        };
        self.path.remove(&address);
        array
    }

    /// A dataset: a numeric array, a cell array (references), or another class, named.
    fn dataset(
        &mut self,
        d: &hdf5::Dataset<'a>,
        marks: &Marks,
        name: &str,
        depth: usize,
    ) -> Result<Array> {
        let class = match (&marks.class, &d.datatype) {
            (Some(class), _) => class_name(class),
            (None, Datatype::Reference { .. }) => "cell",
            (None, Datatype::Float { size: 4, .. }) => "single",
            (None, Datatype::Float { .. } | Datatype::Compound { .. }) => "double",
            (None, Datatype::String { .. }) => "char",
            (None, Datatype::Fixed { size, signed, .. }) => class_name(&format!(
                "{}int{}",
                if *signed { "" } else { "u" },
                size * 8
            )),
            (None, Datatype::Other { .. }) => OPAQUE,
        };
        if marks.empty {
            // The data are the dimensions.
            let bytes = self.file.read(d, name)?;
            let dims: Vec<usize> = d
                .datatype
                .numbers(&bytes)
                .unwrap_or_default()
                .into_iter()
                .map(|x| x as usize)
                .collect();
            if dims.len() < 2 || !dims.contains(&0) {
                return Err(self.file.bad(
                    d.at,
                    format!(
                        "`{name}`: an empty {class} of dimensions {}",
                        super::dims_text(&dims)
                    ),
                ));
            }
            return Ok(empty(class, dims));
        }
        let dims = matlab_dims(&d.dims);
        if marks.sparse.is_some() {
            return Ok(Array::Other {
                class: "sparse",
                dims,
            });
        }
        match class {
            "double" | "single" | "int8" | "uint8" | "int16" | "uint16" | "int32" | "uint32"
            | "int64" | "uint64" | "logical" => {
                let bytes = self.file.read(d, name)?;
                let real = d.datatype.numbers(&bytes).ok_or_else(|| {
                    self.file.bad(
                        d.at,
                        format!(
                            "`{name}`: a {class} stored as {}, not as numbers",
                            d.datatype.describe()
                        ),
                    )
                })?;
                Ok(Array::Numeric {
                    class,
                    dims,
                    real,
                    complex: matches!(d.datatype, Datatype::Compound { .. }),
                })
            }
            "cell" => {
                let references = self.references(d, name)?;
                let mut cells = Vec::with_capacity(references.len());
                for (i, r) in references.into_iter().enumerate() {
                    cells.push(self.array(
                        r,
                        &excerpt(&format!("{name}{{{}}}", i + 1)),
                        depth + 1,
                    )?);
                }
                Ok(Array::Cell { dims, cells })
            }
            class => Ok(Array::Other { class, dims }),
        }
    }

    /// The object addresses of a dataset of references.
    fn references(&self, d: &hdf5::Dataset<'a>, name: &str) -> Result<Vec<u64>> {
        if !matches!(d.datatype, Datatype::Reference { .. }) {
            return Err(self.file.bad(
                d.at,
                format!(
                    "`{name}`: a cell array stored as {}, not as object references",
                    d.datatype.describe()
                ),
            ));
        }
        let bytes = self.file.read(d, name)?;
        Ok(bytes
            .chunks_exact(8)
            .map(|b| u64::from_le_bytes(b.try_into().unwrap_or_default()))
            .collect())
    }

    /// A group: a struct (its members are the fields), a struct array (its fields are
    /// datasets of references, one per element), or another class (sparse, objects), named;
    /// `at` is its object header's file offset.
    fn group(
        &mut self,
        links: Vec<(String, u64)>,
        marks: &Marks,
        name: &str,
        depth: usize,
        at: usize,
    ) -> Result<Array> {
        if let Some(rows) = marks.sparse {
            let columns = links
                .iter()
                .find(|(n, _)| n == "jc")
                .map(|&(_, a)| self.file.object(a))
                .transpose()?
                .and_then(|(_, node)| match node {
                    Node::Dataset(d) => d.dims.first().map(|&n| n.saturating_sub(1) as usize),
                    Node::Group(_) => None,
                })
                .unwrap_or(0);
            return Ok(Array::Other {
                class: "sparse",
                dims: vec![rows as usize, columns],
            });
        }
        let class = marks.class.as_deref().map_or("struct", class_name);
        if class != "struct" {
            return Ok(Array::Other {
                class,
                dims: vec![1, 1],
            });
        }
        let fields: Vec<String> = links.iter().map(|(n, _)| n.clone()).collect();
        if marks.empty {
            return Ok(Array::Struct {
                dims: vec![0, 0],
                fields,
                elements: Vec::new(),
            });
        }
        // A struct array when every field is a dataset of references not marked as a class.
        let mut columns = Vec::new();
        for (_, address) in &links {
            let (attributes, node) = self.file.object(*address)?;
            match node {
                Node::Dataset(d)
                    if matches!(d.datatype, Datatype::Reference { .. })
                        && self.marks(&attributes)?.class.is_none() =>
                {
                    columns.push((matlab_dims(&d.dims), self.references(&d, name)?));
                }
                _ => break,
            }
        }
        if columns.is_empty() || columns.len() < links.len() {
            let mut values = Vec::with_capacity(links.len());
            for (field, address) in &links {
                values.push(self.array(
                    *address,
                    &excerpt(&format!("{name}.{field}")),
                    depth + 1,
                )?);
            }
            return Ok(Array::Struct {
                dims: vec![1, 1],
                fields,
                elements: vec![values],
            });
        }
        let (dims, first) = &columns[0];
        let count = first.len();
        if let Some((_, other)) = columns.iter().find(|(_, r)| r.len() != count) {
            return Err(self.file.bad(
                at,
                format!(
                    "struct array `{name}`: its fields hold {count} and {} elements",
                    other.len()
                ),
            ));
        }
        let dims = dims.clone();
        let mut elements = Vec::with_capacity(count);
        for e in 0..count {
            let mut values = Vec::with_capacity(fields.len());
            for (f, (_, references)) in columns.iter().enumerate() {
                let shown = excerpt(&format!("{name}({}).{}", e + 1, fields[f]));
                values.push(self.array(references[e], &shown, depth + 1)?);
            }
            elements.push(values);
        }
        Ok(Array::Struct {
            dims,
            fields,
            elements,
        })
    }
}

/// MATLAB's dimensions of a dataset of HDF5 dimensions `dims`: reversed, at least two.
fn matlab_dims(dims: &[u64]) -> Vec<usize> {
    let mut out: Vec<usize> = dims.iter().rev().map(|&d| d as usize).collect();
    while out.len() < 2 {
        out.push(1);
    }
    out
}

/// An empty array of `class` and dimensions `dims`.
fn empty(class: &'static str, dims: Vec<usize>) -> Array {
    match class {
        "cell" => Array::Cell {
            dims,
            cells: Vec::new(),
        },
        "struct" => Array::Struct {
            dims,
            fields: Vec::new(),
            elements: Vec::new(),
        },
        "double" | "single" | "int8" | "uint8" | "int16" | "uint16" | "int32" | "uint32"
        | "int64" | "uint64" | "logical" => Array::Numeric {
            class,
            dims,
            real: Vec::new(),
            complex: false,
        },
        class => Array::Other { class, dims },
    }
}

/// The class named `name`, as a `'static` name ([`OPAQUE`] for one not in [`CLASSES`]).
fn class_name(name: &str) -> &'static str {
    CLASSES
        .iter()
        .find(|&&c| c == name)
        .copied()
        .unwrap_or(OPAQUE)
}
