//! A dataset's bytes: contiguous, compact or in chunks (deflate, shuffle undone), and its
//! elements as numbers.

use std::collections::HashSet;

use crate::error::Result;

use super::{Dataset, Datatype, File, Layout, UNDEFINED};
use crate::mat::dims_text;

impl Datatype {
    /// Bytes per element.
    pub fn size(&self) -> usize {
        match self {
            Datatype::Fixed { size, .. }
            | Datatype::Float { size, .. }
            | Datatype::String { size }
            | Datatype::Compound { size, .. }
            | Datatype::Reference { size }
            | Datatype::Other { size, .. } => *size,
        }
    }

    /// The elements of `bytes` (a whole number of elements) as `f64`; a compound's first
    /// member (the real part). `None` if the type is not numeric.
    pub fn numbers(&self, bytes: &[u8]) -> Option<Vec<f64>> {
        let size = self.size();
        let (member, offset) = match self {
            Datatype::Compound { members, .. } => {
                let (_, offset, member) = members.first()?;
                (member, *offset)
            }
            other => (other, 0),
        };
        let width = member.size();
        if size == 0 || offset + width > size {
            return None;
        }
        let decode: fn(&[u8], bool, bool) -> f64 = match member {
            Datatype::Float { size: 4, .. } => |b, big, _| {
                let w = b.try_into().unwrap_or([0; 4]);
                f64::from(if big {
                    f32::from_be_bytes(w)
                } else {
                    f32::from_le_bytes(w)
                })
            },
            Datatype::Float { size: 8, .. } => |b, big, _| {
                let w = b.try_into().unwrap_or([0; 8]);
                if big {
                    f64::from_be_bytes(w)
                } else {
                    f64::from_le_bytes(w)
                }
            },
            Datatype::Fixed {
                size: 1 | 2 | 4 | 8,
                ..
            } => |b, big, signed| {
                let mut w = [0u8; 8];
                let n = b.len();
                if big {
                    w[8 - n..].copy_from_slice(b);
                } else {
                    w[..n].copy_from_slice(b);
                }
                let bits = if big {
                    u64::from_be_bytes(w)
                } else {
                    u64::from_le_bytes(w)
                };
                if signed {
                    // Sign-extend from n bytes.
                    let shift = 64 - 8 * n as u32;
                    ((bits << shift) as i64 >> shift) as f64
                } else {
                    bits as f64
                }
            },
            _ => return None,
        };
        let (big, signed) = match member {
            Datatype::Float { big, .. } => (*big, false),
            Datatype::Fixed { big, signed, .. } => (*big, *signed),
            _ => (false, false),
        };
        Some(
            bytes
                .chunks_exact(size)
                .map(|e| decode(&e[offset..offset + width], big, signed))
                .collect(),
        )
    }

    /// What the type is, for messages.
    pub fn describe(&self) -> String {
        match self {
            Datatype::Fixed { size, signed, .. } => {
                format!("{}int{}", if *signed { "" } else { "u" }, size * 8)
            }
            Datatype::Float { size, .. } => format!("float{}", size * 8),
            Datatype::String { size } => format!("a string of {size} bytes"),
            Datatype::Compound { members, .. } => {
                format!("a compound of {} members", members.len())
            }
            Datatype::Reference { .. } => "object references".into(),
            Datatype::Other { class, .. } => format!("an HDF5 datatype of class {class}"),
        }
    }
}

impl<'a> File<'a> {
    /// The bytes of a dataset, in C order of its dimensions (`name` for messages).
    pub fn read(&self, d: &Dataset<'a>, name: &str) -> Result<Vec<u8>> {
        let element = d.datatype.size();
        let count = d
            .dims
            .iter()
            .try_fold(1u64, |n, &x| n.checked_mul(x))
            .and_then(|n| usize::try_from(n).ok());
        let len = count.and_then(|n| n.checked_mul(element)).ok_or_else(|| {
            self.bad(
                d.at,
                format!(
                    "`{name}` of dimensions {}: too many elements",
                    dims_text(&d.dims)
                ),
            )
        })?;
        self.allocate(d.at, len, name)?;
        if len == 0 {
            return Ok(Vec::new());
        }
        match &d.layout {
            Layout::Compact(data) => data.get(..len).map(<[u8]>::to_vec).ok_or_else(|| {
                self.bad(
                    d.at,
                    format!(
                        "`{name}`: {} compact bytes for {len} bytes of data",
                        data.len()
                    ),
                )
            }),
            Layout::Contiguous(UNDEFINED) => Ok(vec![0; len]),
            Layout::Contiguous(address) => Ok(self
                .slice(*address, len as u64, d.at, &format!("the data of `{name}`"))?
                .to_vec()),
            Layout::Chunked { btree, chunk } => {
                let chunk = self.chunk_shape(d, chunk, name)?;
                let mut out = vec![0; len];
                if *btree == UNDEFINED {
                    return Ok(out);
                }
                let rank = chunk.len();
                let key_len = 8 + 8 * (rank + 1);
                let mut chunks = Vec::new();
                self.btree_with(
                    *btree,
                    1,
                    key_len,
                    None,
                    d.at,
                    &mut HashSet::new(),
                    &mut |key, child| {
                        chunks.push((key, child));
                        Ok(())
                    },
                )?;
                let most = d
                    .dims
                    .iter()
                    .zip(&chunk)
                    .fold(1u64, |n, (&x, &c)| n.saturating_mul(x.div_ceil(c)));
                if chunks.len() as u64 > most {
                    return Err(self.bad(
                        d.at,
                        format!(
                            "`{name}`: {} chunks where {most} fill its dimensions",
                            chunks.len()
                        ),
                    ));
                }
                for (key, address) in chunks {
                    let mut c = self.cursor(key, key_len, "a chunk key")?;
                    let size = u64::from(c.u32()?);
                    let mask = c.u32()?;
                    let offsets: Vec<u64> = (0..rank).map(|_| c.u64()).collect::<Result<_>>()?;
                    let raw = self.slice(address, size, d.at, &format!("a chunk of `{name}`"))?;
                    let data = self.unfilter(d, raw, mask, &chunk, name)?;
                    place(&mut out, &data, &d.dims, &chunk, &offsets, element);
                }
                Ok(out)
            }
            Layout::SingleChunk {
                address,
                chunk,
                filtered,
            } => {
                let chunk = self.chunk_shape(d, chunk, name)?;
                let (size, mask) = filtered.unwrap_or((
                    chunk
                        .iter()
                        .fold(element as u64, |n, &x| n.saturating_mul(x)),
                    0,
                ));
                let raw = self.slice(*address, size, d.at, &format!("the chunk of `{name}`"))?;
                let data = self.unfilter(d, raw, mask, &chunk, name)?;
                let mut out = vec![0; len];
                place(
                    &mut out,
                    &data,
                    &d.dims,
                    &chunk,
                    &vec![0; chunk.len()],
                    element,
                );
                Ok(out)
            }
        }
    }

    /// A chunk's dimensions (without the element size), checked against the dataset's.
    fn chunk_shape(&self, d: &Dataset<'a>, chunk: &[u64], name: &str) -> Result<Vec<u64>> {
        let rank = d.dims.len().max(1);
        if chunk.len() != rank + 1 || chunk[..rank].contains(&0) {
            return Err(self.bad(
                d.at,
                format!(
                    "`{name}`: chunk dimensions {} for data of dimensions {}",
                    dims_text(chunk),
                    dims_text(&d.dims)
                ),
            ));
        }
        Ok(chunk[..rank].to_vec())
    }

    /// A chunk's bytes with its filters undone (those not masked out), exactly a whole
    /// chunk's length.
    fn unfilter(
        &self,
        d: &Dataset<'a>,
        raw: &[u8],
        mask: u32,
        chunk: &[u64],
        name: &str,
    ) -> Result<Vec<u8>> {
        let element = d.datatype.size();
        let want = chunk
            .iter()
            .try_fold(element as u64, |n, &x| n.checked_mul(x))
            .and_then(|n| usize::try_from(n).ok())
            .filter(|&n| n <= self.memory.get())
            .ok_or_else(|| {
                self.bad(
                    d.at,
                    format!(
                        "`{name}`: chunks of {} elements, more than the file holds",
                        dims_text(chunk)
                    ),
                )
            })?;
        let mut data = raw.to_vec();
        for (i, &id) in d.filters.iter().enumerate().rev() {
            if i < 32 && mask & (1 << i) != 0 {
                continue;
            }
            data = match id {
                1 => miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(&data, want).map_err(
                    |e| {
                        self.bad(
                            d.at,
                            format!(
                                "`{name}`: a chunk of {} bytes: bad zlib data ({:?})",
                                raw.len(),
                                e.status
                            ),
                        )
                    },
                )?,
                2 => unshuffle(&data, element),
                3 => {
                    data.truncate(data.len().saturating_sub(4));
                    data
                }
                other => {
                    return Err(self.bad(
                        d.at,
                        format!(
                            "`{name}` is compressed with HDF5 filter {other}{}, which this reader does not read (deflate and shuffle are)",
                            match other {
                                4 => " (szip)",
                                5 => " (nbit)",
                                6 => " (scaleoffset)",
                                32001 => " (blosc)",
                                32004 => " (lz4)",
                                32015 => " (zstd)",
                                _ => "",
                            }
                        ),
                    ));
                }
            };
        }
        if data.len() < want {
            return Err(self.bad(
                d.at,
                format!("`{name}`: a chunk of {} bytes, {want} expected", data.len()),
            ));
        }
        data.truncate(want);
        Ok(data)
    }
}

/// Undoes HDF5's shuffle filter: byte `b` of every element was stored together.
fn unshuffle(data: &[u8], element: usize) -> Vec<u8> {
    let n = data.len() / element.max(1);
    let mut out = data.to_vec();
    for (b, plane) in data.chunks_exact(n.max(1)).take(element).enumerate() {
        if n == 0 {
            break;
        }
        for (i, &byte) in plane.iter().enumerate() {
            out[i * element + b] = byte;
        }
    }
    out
}

/// Copies a decoded chunk (dimensions `chunk`, at element `offsets`) into the dataset's bytes
/// `out` (dimensions `dims`, C order); what lies past the dataset's edge is dropped.
fn place(
    out: &mut [u8],
    data: &[u8],
    dims: &[u64],
    chunk: &[u64],
    offsets: &[u64],
    element: usize,
) {
    let dims: Vec<u64> = if dims.is_empty() {
        vec![1]
    } else {
        dims.to_vec()
    };
    let rank = dims.len();
    let last = rank - 1;
    if offsets.iter().zip(&dims).any(|(o, d)| o >= d) {
        return;
    }
    let run = chunk[last].min(dims[last] - offsets[last]) as usize * element;
    let rows: u64 = chunk[..last].iter().product();
    let mut index = vec![0u64; last];
    for row in 0..rows {
        let mut r = row;
        for k in (0..last).rev() {
            index[k] = r % chunk[k];
            r /= chunk[k];
        }
        if (0..last).any(|k| offsets[k] + index[k] >= dims[k]) {
            continue;
        }
        let mut src = 0u64;
        let mut dst = 0u64;
        for k in 0..last {
            src = src * chunk[k] + index[k];
            dst = dst * dims[k] + offsets[k] + index[k];
        }
        let src = (src * chunk[last]) as usize * element;
        let dst = (dst * dims[last] + offsets[last]) as usize * element;
        if let (Some(from), Some(to)) = (data.get(src..src + run), out.get_mut(dst..dst + run)) {
            to.copy_from_slice(from);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unshuffle_interleaves_the_byte_planes() {
        // Two 4-byte elements 0x04030201 and 0x08070605, shuffled.
        let shuffled = [1, 5, 2, 6, 3, 7, 4, 8];
        assert_eq!(unshuffle(&shuffled, 4), [1, 2, 3, 4, 5, 6, 7, 8]);
    }

    #[test]
    fn place_drops_what_lies_past_the_edge() {
        // A 3×3 dataset of bytes, a 2×2 chunk at (2, 2): only its top-left byte is inside.
        let mut out = vec![0u8; 9];
        place(&mut out, &[9, 8, 7, 6], &[3, 3], &[2, 2], &[2, 2], 1);
        assert_eq!(out, [0, 0, 0, 0, 0, 0, 0, 0, 9]);
        place(&mut out, &[1, 2, 3, 4], &[3, 3], &[2, 2], &[0, 0], 1);
        assert_eq!(out, [1, 2, 0, 3, 4, 0, 0, 0, 9]);
    }
}
