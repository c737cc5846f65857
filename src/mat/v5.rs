//! The level 5 MAT-file format: header, data elements, arrays (see the module's table).

use crate::error::{Error, Result};

use super::{Array, Variable};

/// Deepest nesting of arrays (a struct in a cell in a struct …) read; deeper is refused, so a
/// crafted file cannot exhaust the stack.
pub const MAX_DEPTH: usize = 32;

/// Most bytes a compressed element may inflate to, per compressed byte: 1032 is deflate's own
/// limit (a run of one byte), so no valid element is refused and no bomb grows past it.
pub const MAX_INFLATE_RATIO: usize = 1032;

const MI_INT8: u32 = 1;
const MI_UINT8: u32 = 2;
const MI_INT16: u32 = 3;
const MI_UINT16: u32 = 4;
const MI_INT32: u32 = 5;
const MI_UINT32: u32 = 6;
const MI_SINGLE: u32 = 7;
const MI_DOUBLE: u32 = 9;
const MI_INT64: u32 = 12;
const MI_UINT64: u32 = 13;
const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;
const MI_UTF8: u32 = 16;

/// Parses the bytes of a level 5 MAT-file: every named variable, in the file's order (the
/// unnamed subsystem data MATLAB appends for objects is skipped).
pub(super) fn parse(bytes: &[u8], label: &str) -> Result<Vec<Variable>> {
    let bad = |offset: usize, message: String| Error::Mat {
        path: label.to_owned(),
        offset: offset as u64,
        message,
    };
    if bytes.len() < 128 {
        return Err(bad(
            0,
            format!(
                "{} bytes: shorter than the 128-byte header of a level 5 MAT-file",
                bytes.len()
            ),
        ));
    }
    let little = match &bytes[126..128] {
        b"IM" => true,
        b"MI" => false,
        other => {
            return Err(bad(
                126,
                format!(
                    "endian indicator {:?}, not `IM` or `MI`: not a level 5 MAT-file",
                    String::from_utf8_lossy(other)
                ),
            ));
        }
    };
    let mut variables = Vec::new();
    let mut at = 128;
    while at < bytes.len() {
        let r = Reader {
            bytes,
            little,
            label,
            base: 0,
        };
        let (tag, next) = r.element(at, true)?;
        let array = match tag.kind {
            MI_MATRIX => r.matrix(tag.start, tag.len, 0)?,
            MI_COMPRESSED => {
                let data = &bytes[tag.start..tag.start + tag.len];
                let limit = data.len().saturating_mul(MAX_INFLATE_RATIO);
                let inflated = miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(data, limit)
                    .map_err(|e| {
                        bad(
                            at,
                            format!(
                                "compressed element of {} bytes: bad zlib data ({:?})",
                                data.len(),
                                e.status
                            ),
                        )
                    })?;
                let inner = Reader {
                    bytes: &inflated,
                    little,
                    label,
                    base: tag.start,
                };
                let (t, _) = inner.element(0, false)?;
                if t.kind != MI_MATRIX {
                    return Err(bad(
                        at,
                        format!(
                            "compressed element holds element type {}, not miMATRIX",
                            t.kind
                        ),
                    ));
                }
                inner.matrix(t.start, t.len, 0)?
            }
            other => {
                return Err(bad(
                    at,
                    format!("top-level element of type {other}, not a variable"),
                ));
            }
        };
        if let Some(variable) = array {
            if !variable.name.is_empty() {
                variables.push(variable);
            }
        }
        at = next;
    }
    Ok(variables)
}

/// A data element's tag: its type, and where its data are.
struct Tag {
    kind: u32,
    start: usize,
    len: usize,
}

/// A view of bytes holding data elements (the file, or one inflated element: `base` is its
/// data's offset in the file, for messages).
struct Reader<'a> {
    bytes: &'a [u8],
    little: bool,
    label: &'a str,
    base: usize,
}

impl Reader<'_> {
    fn bad(&self, offset: usize, message: String) -> Error {
        Error::Mat {
            path: self.label.to_owned(),
            offset: (self.base + offset) as u64,
            message,
        }
    }

    fn u32_at(&self, at: usize) -> Result<u32> {
        let b: [u8; 4] = self
            .bytes
            .get(at..at + 4)
            .and_then(|b| b.try_into().ok())
            .ok_or_else(|| {
                self.bad(
                    at,
                    "truncated: the file ends inside an element's tag".into(),
                )
            })?;
        Ok(if self.little {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    }

    /// The element whose tag starts at `at`, and where the next element starts (its data
    /// padded to eight bytes; a top-level compressed element is not padded).
    fn element(&self, at: usize, top: bool) -> Result<(Tag, usize)> {
        let first = self.u32_at(at)?;
        let (kind, len, start) = if first >> 16 != 0 {
            // Small data element: type and byte count share one word, data in the next four.
            let (kind, len) = (first & 0xFFFF, (first >> 16) as usize);
            if len > 4 {
                return Err(self.bad(at, format!("small data element of {len} bytes (at most 4)")));
            }
            (kind, len, at + 4)
        } else {
            (first, self.u32_at(at + 4)? as usize, at + 8)
        };
        let end = start
            .checked_add(len)
            .filter(|&e| e <= self.bytes.len())
            .ok_or_else(|| {
                self.bad(
                    at,
                    format!(
                        "truncated: an element of type {kind} declares {len} bytes, {} remain",
                        self.bytes.len().saturating_sub(start)
                    ),
                )
            })?;
        let next = if start == at + 4 {
            at + 8
        } else if top && kind == MI_COMPRESSED {
            end
        } else {
            end.div_ceil(8) * 8
        };
        Ok((
            Tag { kind, start, len },
            next.min(self.bytes.len()).max(end),
        ))
    }

    /// The numbers of a numeric data element, as `f64`.
    fn numbers(&self, tag: &Tag) -> Result<Vec<f64>> {
        let data = &self.bytes[tag.start..tag.start + tag.len];
        let width = match tag.kind {
            MI_INT8 | MI_UINT8 | MI_UTF8 => 1,
            MI_INT16 | MI_UINT16 => 2,
            MI_INT32 | MI_UINT32 | MI_SINGLE => 4,
            MI_DOUBLE | MI_INT64 | MI_UINT64 => 8,
            other => {
                return Err(self.bad(tag.start, format!("numeric data of element type {other}")));
            }
        };
        if data.len() % width != 0 {
            return Err(self.bad(
                tag.start,
                format!("{} bytes of {width}-byte numbers", data.len()),
            ));
        }
        let little = self.little;
        let word = |c: &[u8]| -> [u8; 8] {
            let mut w = [0u8; 8];
            if little {
                w[..c.len()].copy_from_slice(c);
            } else {
                w[8 - c.len()..].copy_from_slice(c);
            }
            w
        };
        let from = |w: [u8; 8]| {
            if little {
                u64::from_le_bytes(w)
            } else {
                u64::from_be_bytes(w)
            }
        };
        Ok(data
            .chunks_exact(width)
            .map(|c| {
                let bits = from(word(c));
                match tag.kind {
                    MI_INT8 => f64::from(bits as u8 as i8),
                    MI_INT16 => f64::from(bits as u16 as i16),
                    MI_INT32 => f64::from(bits as u32 as i32),
                    MI_INT64 => bits as i64 as f64,
                    MI_SINGLE => f64::from(f32::from_bits(bits as u32)),
                    MI_DOUBLE => f64::from_bits(bits),
                    _ => bits as f64,
                }
            })
            .collect())
    }

    /// The array of a `miMATRIX` element whose data are `len` bytes from `start`, with its
    /// name; `None` for an empty element.
    fn matrix(&self, start: usize, len: usize, depth: usize) -> Result<Option<Variable>> {
        if len == 0 {
            return Ok(None);
        }
        if depth > MAX_DEPTH {
            return Err(self.bad(start, format!("arrays nested deeper than {MAX_DEPTH}")));
        }
        let end = start + len;
        let sub = Reader {
            bytes: &self.bytes[..end],
            little: self.little,
            label: self.label,
            base: self.base,
        };
        let (flags, at) = sub.element(start, false)?;
        if flags.len < 8 {
            return Err(self.bad(
                start,
                format!("array flags of {} bytes (8 expected)", flags.len),
            ));
        }
        let word = sub.u32_at(flags.start)?;
        let (class, complex, logical) = (word & 0xFF, word & 0x800 != 0, word & 0x200 != 0);
        let (dims_tag, at) = sub.element(at, false)?;
        let dims: Vec<usize> = sub
            .numbers(&dims_tag)?
            .into_iter()
            .map(|d| if d >= 0.0 { d as usize } else { usize::MAX })
            .collect();
        if dims.len() < 2 || dims.contains(&usize::MAX) {
            return Err(self.bad(
                dims_tag.start,
                format!(
                    "dimensions {}: at least two, none negative",
                    super::dims_text(&dims)
                ),
            ));
        }
        let count = dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
        let (name_tag, mut at) = sub.element(at, false)?;
        let name =
            String::from_utf8_lossy(&sub.bytes[name_tag.start..name_tag.start + name_tag.len])
                .into_owned();
        let shown = crate::error::excerpt(&name);
        let count = count.filter(|&n| n <= len).ok_or_else(|| {
            self.bad(
                dims_tag.start,
                format!("array `{shown}` declares dimensions {}, more elements than its {len} bytes hold", super::dims_text(&dims)),
            )
        })?;
        let array = match class {
            6..=15 => {
                let (real, next) = sub.element(at, false)?;
                let real = sub.numbers(&real)?;
                if complex {
                    sub.element(next, false)?;
                }
                if real.len() != count {
                    return Err(self.bad(
                        at,
                        format!(
                            "array `{shown}` of dimensions {} holds {} values",
                            super::dims_text(&dims),
                            real.len()
                        ),
                    ));
                }
                const NAMES: [&str; 10] = [
                    "double", "single", "int8", "uint8", "int16", "uint16", "int32", "uint32",
                    "int64", "uint64",
                ];
                Array::Numeric {
                    class: if logical {
                        "logical"
                    } else {
                        NAMES[class as usize - 6]
                    },
                    dims,
                    real,
                    complex,
                }
            }
            1 => {
                // Every cell is an element of at least a tag.
                if count.saturating_mul(8) > len {
                    return Err(self.bad(
                        start,
                        format!("cell `{shown}`: {count} cells in {len} bytes"),
                    ));
                }
                let mut cells = Vec::with_capacity(count);
                for _ in 0..count {
                    let (cell, next) = sub.element(at, false)?;
                    cells.push(sub.cell(&cell, &shown, depth)?);
                    at = next;
                }
                Array::Cell { dims, cells }
            }
            2 | 3 => {
                if class == 3 {
                    // An object: its class name, then fields as a struct's.
                    at = sub.element(at, false)?.1;
                }
                let (width_tag, next) = sub.element(at, false)?;
                let width = sub.numbers(&width_tag)?.first().copied().unwrap_or(0.0) as usize;
                let (names, mut at) = sub.element(next, false)?;
                let raw = &sub.bytes[names.start..names.start + names.len];
                if width == 0 || raw.len() % width != 0 {
                    return Err(self.bad(
                        names.start,
                        format!(
                            "struct `{shown}`: {} bytes of field names of width {width}",
                            raw.len()
                        ),
                    ));
                }
                let fields: Vec<String> = raw
                    .chunks_exact(width)
                    .map(|c| {
                        let c = c.split(|&b| b == 0).next().unwrap_or_default();
                        String::from_utf8_lossy(c).into_owned()
                    })
                    .collect();
                if count
                    .checked_mul(fields.len())
                    .is_none_or(|n| n.saturating_mul(8) > len)
                {
                    return Err(self.bad(
                        start,
                        format!(
                            "struct `{shown}`: {count} elements of {} fields in {len} bytes",
                            fields.len()
                        ),
                    ));
                }
                let mut elements = Vec::with_capacity(count);
                for _ in 0..count {
                    let mut values = Vec::with_capacity(fields.len());
                    for _ in &fields {
                        let (cell, next) = sub.element(at, false)?;
                        values.push(sub.cell(&cell, &shown, depth)?);
                        at = next;
                    }
                    elements.push(values);
                }
                Array::Struct {
                    dims,
                    fields,
                    elements,
                }
            }
            4 => Array::Other {
                class: "char",
                dims,
            },
            5 => Array::Other {
                class: "sparse",
                dims,
            },
            16 => Array::Other {
                class: "function_handle",
                dims,
            },
            17 => Array::Other {
                class: "object (opaque: timetable, string, table …)",
                dims,
            },
            other => {
                return Err(self.bad(
                    flags.start,
                    format!("array `{shown}` of unknown class {other}"),
                ));
            }
        };
        Ok(Some(Variable { name, array }))
    }

    /// A cell or field value: a `miMATRIX` element (empty: an empty double).
    fn cell(&self, tag: &Tag, parent: &str, depth: usize) -> Result<Array> {
        if tag.kind != MI_MATRIX {
            return Err(self.bad(
                tag.start,
                format!(
                    "an element of `{parent}` of type {}, not miMATRIX",
                    tag.kind
                ),
            ));
        }
        Ok(self.matrix(tag.start, tag.len, depth + 1)?.map_or(
            Array::Numeric {
                class: "double",
                dims: vec![0, 0],
                real: Vec::new(),
                complex: false,
            },
            |v| v.array,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file holding `fs = 1000` (double, 1×1) and `n = [1 2 3]` (int16 data in a double
    /// array, as MATLAB narrows stored values), in either byte order.
    fn file(little: bool) -> Vec<u8> {
        let w = |v: u32| {
            if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            }
        };
        let mut bytes = vec![b' '; 116];
        bytes.extend([0; 8]);
        bytes.extend(if little {
            [0x00, 0x01, b'I', b'M']
        } else {
            [0x01, 0x00, b'M', b'I']
        });
        let double = if little {
            1000f64.to_le_bytes()
        } else {
            1000f64.to_be_bytes()
        };
        let fs: Vec<u8> = [
            &w(14)[..],
            &w(56),
            &w(6),
            &w(8),
            &w(6),
            &w(0),
            &w(5),
            &w(8),
            &w(1),
            &w(1),
            &w(0x0002_0001),
            b"fs\0\0",
            &w(9),
            &w(8),
            &double,
        ]
        .concat();
        let mut shorts = Vec::new();
        for v in [1i16, 2, 3] {
            shorts.extend(if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            });
        }
        shorts.extend([0, 0]);
        let n: Vec<u8> = [
            &w(14)[..],
            &w(56),
            &w(6),
            &w(8),
            &w(6),
            &w(0),
            &w(5),
            &w(8),
            &w(1),
            &w(3),
            &w(0x0001_0001),
            b"n\0\0\0",
            &w(3),
            &w(6),
            &shorts,
        ]
        .concat();
        bytes.extend(fs);
        bytes.extend(n);
        bytes
    }

    #[test]
    fn both_byte_orders_and_narrowed_storage_read_the_same() {
        for little in [true, false] {
            let vars = parse(&file(little), "o.mat").unwrap();
            assert_eq!(vars.len(), 2, "little {little}");
            assert_eq!(vars[0].array.samples(), Some(&[1000.0][..]));
            assert_eq!(vars[1].name, "n");
            assert_eq!(vars[1].array.samples(), Some(&[1.0, 2.0, 3.0][..]));
            assert_eq!(vars[1].array.dims(), [1, 3]);
            assert_eq!(vars[1].array.class(), "double");
        }
    }

    #[test]
    fn a_small_element_longer_than_four_bytes_is_malformed() {
        let mut bytes = file(true);
        // The name tag of `fs`: small format, 2 bytes → 9 bytes.
        let at = 128 + 8 + 16 + 16;
        bytes[at..at + 4].copy_from_slice(&0x0009_0001u32.to_le_bytes());
        let e = parse(&bytes, "o.mat").unwrap_err();
        assert_eq!(e.kind(), "malformed_mat");
        assert!(
            e.to_string().contains("small data element of 9 bytes"),
            "{e}"
        );
    }
}
