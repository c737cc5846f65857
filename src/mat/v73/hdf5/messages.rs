//! The object header messages read: dataspace, datatype, data layout, filter pipeline,
//! attribute, link.

use crate::error::{Result, excerpt};
use crate::mat::dims_text;

use super::{Attribute, Cursor, Datatype, File, Layout, UNDEFINED};

impl<'a> File<'a> {
    /// Dimensions of a dataspace message (a scalar has none; a null dataspace one of 0).
    pub(super) fn dataspace(&self, data: &'a [u8], at: usize) -> Result<Vec<u64>> {
        let mut c = self.cursor(at, data.len(), "a dataspace message")?;
        let version = c.u8()?;
        let rank = c.u8()?;
        let _flags = c.u8()?;
        match version {
            1 => c.skip(5)?,
            2 => {
                if c.u8()? == 2 {
                    return Ok(vec![0]);
                }
            }
            other => return Err(self.bad(at, format!("dataspace message version {other}"))),
        }
        (0..rank).map(|_| c.u64()).collect()
    }

    /// A datatype message, and the bytes it takes (compound members nest `depth` deep).
    pub(super) fn datatype(
        &self,
        data: &'a [u8],
        at: usize,
        depth: usize,
    ) -> Result<(Datatype, usize)> {
        if depth > 4 {
            return Err(self.bad(at, "compound datatypes nested deeper than 4".into()));
        }
        let mut c = self.cursor(at, data.len(), "a datatype message")?;
        let head = c.u8()?;
        let (class, version) = (head & 0x0F, head >> 4);
        let bits = c.take(3)?;
        let size = c.u32()? as usize;
        let big = bits[0] & 1 != 0;
        let datatype = match class {
            0 => {
                c.skip(4)?;
                if !matches!(size, 1 | 2 | 4 | 8) {
                    return Err(self.bad(at, format!("an integer of {size} bytes (1, 2, 4 or 8)")));
                }
                Datatype::Fixed {
                    size,
                    signed: bits[0] & 0x08 != 0,
                    big,
                }
            }
            1 => {
                c.skip(12)?;
                if bits[0] & 0x40 != 0 || !matches!(size, 4 | 8) {
                    return Err(self.bad(
                        at,
                        format!("a float of {size} bytes that is not IEEE single or double"),
                    ));
                }
                Datatype::Float { size, big }
            }
            3 => Datatype::String { size },
            6 => {
                let count = usize::from(u16::from_le_bytes([bits[0], bits[1]]));
                let mut members = Vec::new();
                for _ in 0..count {
                    let name = c.name(if version < 3 { 8 } else { 1 })?;
                    let offset = if version < 3 {
                        c.u32()? as usize
                    } else {
                        let n = match size {
                            0..=0xFF => 1,
                            0x100..=0xFFFF => 2,
                            0x1_0000..=0xFF_FFFF => 3,
                            _ => 4,
                        };
                        c.uint(n)? as usize
                    };
                    if version == 1 {
                        c.skip(28)?;
                    }
                    let from = c.here();
                    let (member, used) = self.datatype(c.rest(), from, depth + 1)?;
                    c.pos = from - c.at + used;
                    if offset
                        .checked_add(member.size())
                        .is_none_or(|end| end > size)
                    {
                        return Err(self.bad(
                            from,
                            format!("compound member `{}` at byte {offset} past its {size}-byte element", excerpt(&name)),
                        ));
                    }
                    members.push((name, offset, member));
                }
                Datatype::Compound { size, members }
            }
            7 => {
                if bits[0] & 0x0F != 0 || size != 8 {
                    return Err(self.bad(
                        at,
                        "a region reference (or a reference that is not 8 bytes): only object \
                         references are read"
                            .into(),
                    ));
                }
                Datatype::Reference { size }
            }
            _ if depth > 0 => {
                return Err(self.bad(
                    at,
                    format!("a compound member of HDF5 datatype class {class}, which this reader does not read"),
                ));
            }
            _ => Datatype::Other { class, size },
        };
        if size == 0 {
            return Err(self.bad(at, "a datatype of 0 bytes".into()));
        }
        Ok((datatype, c.pos))
    }

    /// A data layout message.
    pub(super) fn layout(&self, data: &'a [u8], at: usize) -> Result<Layout<'a>> {
        let mut c = self.cursor(at, data.len(), "a data layout message")?;
        let version = c.u8()?;
        let chunk_dims = |c: &mut Cursor<'_, 'a>, rank: u8, width: usize| -> Result<Vec<u64>> {
            (0..rank).map(|_| c.uint(width)).collect()
        };
        match version {
            1 | 2 => {
                let rank = c.u8()?;
                let class = c.u8()?;
                c.skip(5)?;
                let address = if class == 0 { UNDEFINED } else { c.u64()? };
                let dims = chunk_dims(&mut c, rank, 4)?;
                match class {
                    0 => {
                        let size = c.u32()? as usize;
                        Ok(Layout::Compact(c.take(size)?))
                    }
                    1 => Ok(Layout::Contiguous(address)),
                    2 => {
                        let element = u64::from(c.u32()?);
                        let mut chunk = dims;
                        chunk.push(element);
                        Ok(Layout::Chunked {
                            btree: address,
                            chunk,
                        })
                    }
                    other => Err(self.bad(at, format!("data layout class {other}"))),
                }
            }
            3 | 4 => match c.u8()? {
                0 => {
                    let size = usize::from(c.u16()?);
                    Ok(Layout::Compact(c.take(size)?))
                }
                1 => Ok(Layout::Contiguous(c.u64()?)),
                2 if version == 3 => {
                    let rank = c.u8()?;
                    let btree = c.u64()?;
                    let chunk = chunk_dims(&mut c, rank, 4)?;
                    Ok(Layout::Chunked { btree, chunk })
                }
                2 => {
                    let flags = c.u8()?;
                    let rank = c.u8()?;
                    let width = usize::from(c.u8()?);
                    if !(1..=8).contains(&width) {
                        return Err(self.bad(at, format!("chunk dimensions of {width} bytes")));
                    }
                    let chunk = chunk_dims(&mut c, rank, width)?;
                    match c.u8()? {
                        1 => {
                            let filtered = if flags & 2 != 0 {
                                Some((c.u64()?, c.u32()?))
                            } else {
                                None
                            };
                            Ok(Layout::SingleChunk {
                                address: c.u64()?,
                                chunk,
                                filtered,
                            })
                        }
                        index => Err(self.bad(
                            at,
                            format!(
                                "chunks indexed by {} (HDF5 1.10's layout), which this reader does \
                                 not read: save with MATLAB's -v7.3 or h5py's default libver",
                                match index {
                                    2 => "the implicit index",
                                    3 => "a fixed array",
                                    4 => "an extensible array",
                                    5 => "a version 2 B-tree",
                                    _ => "an unknown index",
                                }
                            ),
                        )),
                    }
                }
                3 => Err(self.bad(
                    at,
                    "a virtual dataset, which this reader does not read".into(),
                )),
                other => Err(self.bad(at, format!("data layout class {other}"))),
            },
            other => Err(self.bad(at, format!("data layout message version {other}"))),
        }
    }

    /// The filter identifiers of a filter pipeline message, in the order they were applied.
    pub(super) fn filters(&self, data: &'a [u8], at: usize) -> Result<Vec<u16>> {
        let mut c = self.cursor(at, data.len(), "a filter pipeline message")?;
        let version = c.u8()?;
        let count = c.u8()?;
        if version == 1 {
            c.skip(6)?;
        } else if version != 2 {
            return Err(self.bad(at, format!("filter pipeline message version {version}")));
        }
        let mut ids = Vec::new();
        for _ in 0..count {
            let id = c.u16()?;
            let name_len = if version == 1 || id >= 256 {
                usize::from(c.u16()?)
            } else {
                0
            };
            let _flags = c.u16()?;
            let values = usize::from(c.u16()?);
            let name_len = if version == 1 {
                name_len.div_ceil(8) * 8
            } else {
                name_len
            };
            c.skip(name_len)?;
            c.skip(4 * values)?;
            if version == 1 && values % 2 == 1 {
                c.skip(4)?;
            }
            ids.push(id);
        }
        Ok(ids)
    }

    /// An attribute message: its name; its type, space and data are read when asked for.
    pub(super) fn attribute(&self, data: &'a [u8], at: usize) -> Result<Attribute<'a>> {
        let mut c = self.cursor(at, data.len(), "an attribute message")?;
        let version = c.u8()?;
        c.skip(1)?;
        let name_len = usize::from(c.u16()?);
        c.skip(4)?;
        if version == 3 {
            c.skip(1)?;
        } else if version != 1 && version != 2 {
            return Err(self.bad(at, format!("attribute message version {version}")));
        }
        let name = c.take(name_len)?;
        let name = name.split(|&b| b == 0).next().unwrap_or_default();
        Ok(Attribute {
            name: String::from_utf8_lossy(name).into_owned(),
            message: data,
            at,
            version,
        })
    }

    /// An attribute's datatype, dimensions and data.
    pub fn attribute_value(&self, a: &Attribute<'a>) -> Result<(Datatype, Vec<u64>, &'a [u8])> {
        let mut c = self.cursor(a.at, a.message.len(), "an attribute message")?;
        c.skip(2)?;
        let sizes = [c.u16()?, c.u16()?, c.u16()?].map(usize::from);
        if a.version == 3 {
            c.skip(1)?;
        }
        let pad = |n: usize| if a.version == 1 { n.div_ceil(8) * 8 } else { n };
        c.skip(pad(sizes[0]))?;
        let from = c.here();
        let datatype = self.datatype(c.take(sizes[1])?, from, 0)?.0;
        c.skip(pad(sizes[1]) - sizes[1])?;
        let from = c.here();
        let dims = self.dataspace(c.take(sizes[2])?, from)?;
        c.skip(pad(sizes[2]) - sizes[2])?;
        let count = dims
            .iter()
            .try_fold(1u64, |n, &d| n.checked_mul(d))
            .and_then(|n| usize::try_from(n).ok())
            .and_then(|n| n.checked_mul(datatype.size()));
        let data = match count {
            Some(n) => c.take(n)?,
            None => {
                return Err(self.bad(
                    a.at,
                    format!(
                        "attribute `{}` of dimensions {}",
                        excerpt(&a.name),
                        dims_text(&dims)
                    ),
                ));
            }
        };
        Ok((datatype, dims, data))
    }

    /// A hard link message's name and address (`None` for soft and external links).
    pub(super) fn link(&self, data: &'a [u8], at: usize) -> Result<Option<(String, u64)>> {
        let mut c = self.cursor(at, data.len(), "a link message")?;
        let version = c.u8()?;
        if version != 1 {
            return Err(self.bad(at, format!("link message version {version}")));
        }
        let flags = c.u8()?;
        let kind = if flags & 0x08 != 0 { c.u8()? } else { 0 };
        if flags & 0x04 != 0 {
            c.skip(8)?;
        }
        if flags & 0x10 != 0 {
            c.skip(1)?;
        }
        let len = c.uint(1 << (flags & 3))?;
        let name = c.take(usize::try_from(len).unwrap_or(usize::MAX))?;
        let name = String::from_utf8_lossy(name).into_owned();
        Ok(if kind == 0 {
            Some((name, c.u64()?))
        } else {
            None
        })
    }
}
