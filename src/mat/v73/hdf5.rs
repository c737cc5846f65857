//! The subset of HDF5 that MATLAB (`save -v7.3`) and h5py write: the superblock, object
//! headers and their messages, groups (old and new style) and the bytes of a dataset.
//!
//! Every address is checked against the file's length before it is read; every structure read
//! is charged to a work budget and every decoded byte to a memory budget, both proportional to
//! the file's size, so a crafted file cannot loop, recurse or allocate without bound.

use std::cell::Cell;
use std::collections::HashSet;

use crate::error::{Error, Result};

use super::super::MAX_INFLATE_RATIO;

/// An address that points nowhere (all bits set).
const UNDEFINED: u64 = u64::MAX;
/// HDF5's format signature, at byte 0, 512, 1024, 2048 … of a file.
pub(in crate::mat) const SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";
/// Structure bytes read per byte of the file, at most (plus [`WORK_FLOOR`]).
const WORK_PER_BYTE: usize = 64;
const WORK_FLOOR: usize = 1 << 20;

/// Object header message types read.
const MSG_DATASPACE: u16 = 0x01;
const MSG_LINK_INFO: u16 = 0x02;
const MSG_DATATYPE: u16 = 0x03;
const MSG_LINK: u16 = 0x06;
const MSG_LAYOUT: u16 = 0x08;
const MSG_FILTERS: u16 = 0x0B;
const MSG_ATTRIBUTE: u16 = 0x0C;
const MSG_CONTINUATION: u16 = 0x10;
const MSG_SYMBOL_TABLE: u16 = 0x11;

/// An HDF5 file in memory: its bytes, where its addresses count from, and the budgets.
pub(super) struct File<'a> {
    bytes: &'a [u8],
    base: usize,
    label: &'a str,
    /// The root group's object header address.
    pub root: u64,
    work: Cell<usize>,
    memory: Cell<usize>,
}

/// An HDF5 datatype, as far as MATLAB's arrays need one.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Datatype {
    /// An integer of `size` bytes.
    Fixed { size: usize, signed: bool, big: bool },
    /// An IEEE float of 4 or 8 bytes.
    Float { size: usize, big: bool },
    /// A fixed-length string of `size` bytes.
    String { size: usize },
    /// A compound (MATLAB's complex numbers: `real`, `imag`): members at byte offsets.
    Compound {
        size: usize,
        members: Vec<(String, usize, Datatype)>,
    },
    /// An object reference (an object header address).
    Reference { size: usize },
    /// Any other class (its number), not read.
    Other { class: u8, size: usize },
}

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
            Datatype::Fixed { size: 1 | 2 | 4 | 8, .. } => |b, big, signed| {
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
            Datatype::Compound { members, .. } => format!("a compound of {} members", members.len()),
            Datatype::Reference { .. } => "object references".into(),
            Datatype::Other { class, .. } => format!("an HDF5 datatype of class {class}"),
        }
    }
}

/// Where a dataset's bytes are.
#[derive(Debug)]
enum Layout<'a> {
    Compact(&'a [u8]),
    Contiguous(u64),
    /// Chunks indexed by a version 1 B-tree; chunk dimensions, the last one the element size.
    Chunked { btree: u64, chunk: Vec<u64> },
    /// One chunk holding the whole dataset (layout version 4), its stored size and filter mask
    /// when filtered.
    SingleChunk {
        address: u64,
        chunk: Vec<u64>,
        filtered: Option<(u64, u32)>,
    },
}

/// A dataset: its type, dimensions (HDF5's order, C order), where its bytes are and how they
/// are filtered.
#[derive(Debug)]
pub(super) struct Dataset<'a> {
    pub datatype: Datatype,
    pub dims: Vec<u64>,
    layout: Layout<'a>,
    filters: Vec<u16>,
    /// The file offset of its object header, for messages.
    pub at: usize,
}

/// An attribute: its name, and its type and raw data (decoded only when asked for).
pub(super) struct Attribute<'a> {
    pub name: String,
    message: &'a [u8],
    at: usize,
    version: u8,
}

/// What an object header describes.
pub(super) enum Node<'a> {
    /// A group: its members' names and object header addresses.
    Group(Vec<(String, u64)>),
    /// A dataset.
    Dataset(Dataset<'a>),
}

/// An object header's message: type, flags, data and where the data are in the file.
struct Message<'a> {
    kind: u16,
    flags: u8,
    data: &'a [u8],
    at: usize,
}

/// A reader of little-endian fields in a slice of the file that starts at file byte `at`.
struct Cursor<'f, 'a> {
    file: &'f File<'a>,
    data: &'a [u8],
    pos: usize,
    at: usize,
    what: &'static str,
}

impl<'a> Cursor<'_, 'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8]> {
        let slice = self
            .pos
            .checked_add(n)
            .and_then(|end| self.data.get(self.pos..end))
            .ok_or_else(|| {
                self.file.bad(
                    self.at + self.pos,
                    format!(
                        "truncated: {} needs {n} bytes, {} remain",
                        self.what,
                        self.data.len().saturating_sub(self.pos)
                    ),
                )
            })?;
        self.pos += n;
        Ok(slice)
    }

    fn uint(&mut self, n: usize) -> Result<u64> {
        let b = self.take(n)?;
        let mut w = [0u8; 8];
        w[..n.min(8)].copy_from_slice(&b[..n.min(8)]);
        Ok(u64::from_le_bytes(w))
    }

    fn u8(&mut self) -> Result<u8> {
        Ok(self.take(1)?[0])
    }

    fn u16(&mut self) -> Result<u16> {
        Ok(self.uint(2)? as u16)
    }

    fn u32(&mut self) -> Result<u32> {
        Ok(self.uint(4)? as u32)
    }

    fn u64(&mut self) -> Result<u64> {
        self.uint(8)
    }

    fn skip(&mut self, n: usize) -> Result<()> {
        self.take(n).map(|_| ())
    }

    /// The file offset of the next byte.
    fn here(&self) -> usize {
        self.at + self.pos
    }

    fn rest(&mut self) -> &'a [u8] {
        let rest = self.data.get(self.pos..).unwrap_or_default();
        self.pos = self.data.len();
        rest
    }

    /// A NUL-terminated name, padded with NULs to a multiple of `pad` bytes from its start.
    fn name(&mut self, pad: usize) -> Result<String> {
        let rest = self.data.get(self.pos..).unwrap_or_default();
        let len = rest.iter().position(|&b| b == 0).ok_or_else(|| {
            self.file
                .bad(self.here(), format!("{}: a name without its NUL", self.what))
        })?;
        let name = String::from_utf8_lossy(&rest[..len]).into_owned();
        self.skip((len + 1).div_ceil(pad) * pad)?;
        Ok(name)
    }
}

impl<'a> File<'a> {
    /// Finds the superblock (at byte 0, 512, 1024, …) and reads it.
    ///
    /// Addresses count from the superblock's own position, as the HDF5 library reads them
    /// (a MATLAB file's 512-byte user block comes first).
    pub fn open(bytes: &'a [u8], label: &'a str) -> Result<Self> {
        let mut base = 0;
        while bytes.get(base..base + 8) != Some(SIGNATURE) {
            base = if base == 0 { 512 } else { base * 2 };
            if base + 8 > bytes.len() {
                return Err(Error::Mat {
                    path: label.to_owned(),
                    offset: 512,
                    message: "no HDF5 signature at byte 0, 512, 1024 …: not a -v7.3 MAT-file \
                              (truncated in its header?)"
                        .into(),
                });
            }
        }
        let budget = |per: usize| bytes.len().saturating_mul(per);
        let mut file = File {
            bytes,
            base,
            label,
            root: 0,
            work: Cell::new(budget(WORK_PER_BYTE).saturating_add(WORK_FLOOR)),
            memory: Cell::new(budget(MAX_INFLATE_RATIO)),
        };
        let mut c = file.cursor(base, bytes.len() - base, "the superblock")?;
        c.skip(8)?;
        let version = c.u8()?;
        let (offsets, lengths, root) = match version {
            0 | 1 => {
                c.skip(4)?; // free-space, root symbol table, reserved, shared header versions
                let (offsets, lengths) = (c.u8()?, c.u8()?);
                c.skip(1 + 2 + 2 + 4)?; // reserved, group K's, consistency flags
                if version == 1 {
                    c.skip(4)?;
                }
                check_sizes(&file, base, offsets, lengths)?;
                c.skip(4 * 8)?; // base, free space, end of file, driver info addresses
                c.skip(8)?; // root symbol table entry: link name offset
                (offsets, lengths, c.u64()?)
            }
            2 | 3 => {
                let (offsets, lengths) = (c.u8()?, c.u8()?);
                check_sizes(&file, base, offsets, lengths)?;
                c.skip(1 + 3 * 8)?; // flags, base, extension, end of file addresses
                (offsets, lengths, c.u64()?)
            }
            other => {
                return Err(file.bad(base + 8, format!("HDF5 superblock version {other}, not 0–3")));
            }
        };
        let _ = (offsets, lengths);
        file.root = root;
        Ok(file)
    }

    /// An [`Error::Mat`] at file byte `at`.
    pub fn bad(&self, at: usize, message: String) -> Error {
        Error::Mat {
            path: self.label.to_owned(),
            offset: at as u64,
            message,
        }
    }

    /// The file offset of address `address`, for messages (clamped to the file's end).
    pub fn position(&self, address: u64) -> usize {
        usize::try_from(address)
            .ok()
            .and_then(|a| a.checked_add(self.base))
            .map_or(self.bytes.len(), |a| a.min(self.bytes.len()))
    }

    /// Charges `n` bytes of structure read to the work budget.
    fn charge(&self, at: usize, n: usize) -> Result<()> {
        let left = self.work.get().checked_sub(n).ok_or_else(|| {
            self.bad(
                at,
                "structures read over and over (shared or cyclic references): more work than \
                 the file's size allows"
                    .into(),
            )
        })?;
        self.work.set(left);
        Ok(())
    }

    /// Charges `n` decoded bytes to the memory budget, before they are allocated.
    pub fn allocate(&self, at: usize, n: usize, name: &str) -> Result<()> {
        let left = self.memory.get().checked_sub(n).ok_or_else(|| {
            self.bad(
                at,
                format!(
                    "`{name}` declares {n} bytes of data, more than a file of {} bytes holds",
                    self.bytes.len()
                ),
            )
        })?;
        self.memory.set(left);
        Ok(())
    }

    /// The file offset of address `address` (relative to the superblock).
    fn offset(&self, address: u64, from: usize, what: &str) -> Result<usize> {
        usize::try_from(address)
            .ok()
            .and_then(|a| a.checked_add(self.base))
            .filter(|&a| a < self.bytes.len())
            .ok_or_else(|| {
                self.bad(
                    from,
                    format!(
                        "{what} at address {address:#x}, past the end of the file ({} bytes)",
                        self.bytes.len()
                    ),
                )
            })
    }

    /// A cursor over `len` bytes from file byte `at` (fewer if the file ends first: reading
    /// past them is a truncation error).
    fn cursor(&self, at: usize, len: usize, what: &'static str) -> Result<Cursor<'_, 'a>> {
        let end = at.saturating_add(len).min(self.bytes.len());
        let data = self.bytes.get(at..end).ok_or_else(|| {
            self.bad(at, format!("{what} at byte {at}, past the end of the file"))
        })?;
        Ok(Cursor {
            file: self,
            data,
            pos: 0,
            at,
            what,
        })
    }

    /// Exactly `len` bytes at address `address`.
    fn slice(&self, address: u64, len: u64, from: usize, what: &str) -> Result<&'a [u8]> {
        let at = self.offset(address, from, what)?;
        usize::try_from(len)
            .ok()
            .and_then(|n| at.checked_add(n))
            .and_then(|end| self.bytes.get(at..end))
            .ok_or_else(|| {
                self.bad(
                    from,
                    format!(
                        "truncated: {what} of {len} bytes at byte {at}, {} remain",
                        self.bytes.len() - at
                    ),
                )
            })
    }

    /// The messages of the object header at `address`, continuation blocks followed.
    fn messages(&self, address: u64) -> Result<Vec<Message<'a>>> {
        let start = self.offset(address, self.base, "an object header")?;
        let mut c = self.cursor(start, 16, "an object header")?;
        let mut blocks = Vec::new();
        let v2 = self.bytes.get(start..start + 4) == Some(b"OHDR");
        let mut creation_order = false;
        if v2 {
            c.skip(4)?;
            let version = c.u8()?;
            if version != 2 {
                return Err(self.bad(start + 4, format!("object header version {version}, not 2")));
            }
            let flags = c.u8()?;
            creation_order = flags & 0x04 != 0;
            let mut c = self.cursor(start + 6, 32, "an object header")?;
            if flags & 0x20 != 0 {
                c.skip(16)?;
            }
            if flags & 0x10 != 0 {
                c.skip(4)?;
            }
            let size = c.uint(1 << (flags & 3))?;
            blocks.push((c.here(), size));
        } else {
            let version = c.u8()?;
            if version != 1 {
                return Err(self.bad(
                    start,
                    format!("object header version {version}, not 1 (nor `OHDR`): not an object"),
                ));
            }
            c.skip(1 + 2 + 4)?;
            let size = c.u32()?;
            blocks.push((start + 16, u64::from(size)));
        }
        let mut seen = HashSet::new();
        let mut messages = Vec::new();
        let mut i = 0;
        while let Some(&(at, size)) = blocks.get(i) {
            i += 1;
            if !seen.insert(at) {
                return Err(self.bad(at, "object header continuations form a cycle".into()));
            }
            let size = usize::try_from(size).unwrap_or(usize::MAX);
            if at.checked_add(size).is_none_or(|end| end > self.bytes.len()) {
                return Err(self.bad(
                    at,
                    format!(
                        "truncated: an object header block of {size} bytes, {} remain",
                        self.bytes.len().saturating_sub(at)
                    ),
                ));
            }
            self.charge(at, size.max(16))?;
            let mut c = self.cursor(at, size, "an object header message")?;
            let header = if v2 { 4 + 2 * usize::from(creation_order) } else { 8 };
            while c.data.len() - c.pos >= header {
                let (kind, len, flags) = if v2 {
                    let kind = u16::from(c.u8()?);
                    let len = c.u16()?;
                    let flags = c.u8()?;
                    if creation_order {
                        c.skip(2)?;
                    }
                    (kind, len, flags)
                } else {
                    let kind = c.u16()?;
                    let len = c.u16()?;
                    let flags = c.u8()?;
                    c.skip(3)?;
                    (kind, len, flags)
                };
                let data_at = c.here();
                let data = c.take(usize::from(len))?;
                if kind == MSG_CONTINUATION {
                    let mut m = self.cursor(data_at, data.len(), "a continuation message")?;
                    let (address, length) = (m.u64()?, m.u64()?);
                    let block = self.offset(address, data_at, "an object header continuation")?;
                    if v2 {
                        if self.bytes.get(block..block + 4) != Some(b"OCHK") {
                            return Err(self.bad(
                                block,
                                "an object header continuation without its `OCHK` signature"
                                    .into(),
                            ));
                        }
                        blocks.push((block + 4, length.saturating_sub(8)));
                    } else {
                        blocks.push((block, length));
                    }
                } else {
                    messages.push(Message {
                        kind,
                        flags,
                        data,
                        at: data_at,
                    });
                }
            }
        }
        Ok(messages)
    }

    /// The object header at `address`: its attributes and what it is (group or dataset).
    pub fn object(&self, address: u64) -> Result<(Vec<Attribute<'a>>, Node<'a>)> {
        let messages = self.messages(address)?;
        let at = self.offset(address, self.base, "an object header")?;
        let mut attributes = Vec::new();
        let (mut space, mut datatype, mut layout, mut filters) = (None, None, None, Vec::new());
        let mut links = Vec::new();
        let mut group = false;
        for m in &messages {
            let shared = m.flags & 0x02 != 0;
            if shared && matches!(m.kind, MSG_DATASPACE | MSG_DATATYPE | MSG_FILTERS) {
                return Err(self.bad(
                    m.at,
                    format!(
                        "a shared (committed) object header message of type {}, which this reader does not read",
                        m.kind
                    ),
                ));
            }
            match m.kind {
                MSG_DATASPACE => space = Some(self.dataspace(m.data, m.at)?),
                MSG_DATATYPE => datatype = Some(self.datatype(m.data, m.at, 0)?.0),
                MSG_LAYOUT => layout = Some(self.layout(m.data, m.at)?),
                MSG_FILTERS => filters = self.filters(m.data, m.at)?,
                MSG_ATTRIBUTE if !shared => attributes.push(self.attribute(m.data, m.at)?),
                MSG_SYMBOL_TABLE => {
                    group = true;
                    let mut c = self.cursor(m.at, m.data.len(), "a symbol table message")?;
                    let (btree, heap) = (c.u64()?, c.u64()?);
                    self.symbol_table(btree, heap, m.at, &mut links)?;
                }
                MSG_LINK => {
                    group = true;
                    if let Some(link) = self.link(m.data, m.at)? {
                        links.push(link);
                    }
                }
                MSG_LINK_INFO => {
                    group = true;
                    let mut c = self.cursor(m.at, m.data.len(), "a link info message")?;
                    c.skip(1)?;
                    let flags = c.u8()?;
                    if flags & 1 != 0 {
                        c.skip(8)?;
                    }
                    if c.u64()? != UNDEFINED {
                        return Err(self.bad(
                            m.at,
                            "a group whose links are in a fractal heap (dense storage: more than \
                             8 members written with libver='latest'), which this reader does not \
                             read: save with MATLAB's -v7.3 or h5py's default libver"
                                .into(),
                        ));
                    }
                }
                _ => {}
            }
        }
        let node = match (space, datatype, layout) {
            (Some(dims), Some(datatype), Some(layout)) => Node::Dataset(Dataset {
                datatype,
                dims,
                layout,
                filters,
                at,
            }),
            _ if group => Node::Group(links),
            _ => {
                return Err(self.bad(
                    at,
                    "an object header that is neither a group nor a dataset (no dataspace, \
                     datatype and layout; no links)"
                        .into(),
                ));
            }
        };
        Ok((attributes, node))
    }

    /// Dimensions of a dataspace message (a scalar has none; a null dataspace one of 0).
    fn dataspace(&self, data: &'a [u8], at: usize) -> Result<Vec<u64>> {
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
    fn datatype(&self, data: &'a [u8], at: usize, depth: usize) -> Result<(Datatype, usize)> {
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
                    if offset.checked_add(member.size()).is_none_or(|end| end > size) {
                        return Err(self.bad(
                            from,
                            format!("compound member `{name}` at byte {offset} past its {size}-byte element"),
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
    fn layout(&self, data: &'a [u8], at: usize) -> Result<Layout<'a>> {
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
                3 => Err(self.bad(at, "a virtual dataset, which this reader does not read".into())),
                other => Err(self.bad(at, format!("data layout class {other}"))),
            },
            other => Err(self.bad(at, format!("data layout message version {other}"))),
        }
    }

    /// The filter identifiers of a filter pipeline message, in the order they were applied.
    fn filters(&self, data: &'a [u8], at: usize) -> Result<Vec<u16>> {
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
    fn attribute(&self, data: &'a [u8], at: usize) -> Result<Attribute<'a>> {
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
            None => return Err(self.bad(a.at, format!("attribute `{}` of dimensions {dims:?}", a.name))),
        };
        Ok((datatype, dims, data))
    }

    /// A hard link message's name and address (`None` for soft and external links).
    fn link(&self, data: &'a [u8], at: usize) -> Result<Option<(String, u64)>> {
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

    /// The members of an old-style group: a version 1 B-tree of symbol table nodes, names in a
    /// local heap.
    fn symbol_table(
        &self,
        btree: u64,
        heap: u64,
        from: usize,
        links: &mut Vec<(String, u64)>,
    ) -> Result<()> {
        let h = self.offset(heap, from, "a local heap")?;
        let mut c = self.cursor(h, 32, "a local heap")?;
        if c.take(4)? != b"HEAP" {
            return Err(self.bad(h, "a local heap without its `HEAP` signature".into()));
        }
        c.skip(4)?;
        let size = c.u64()?;
        c.skip(8)?;
        let names = self.slice(c.u64()?, size, h, "a local heap's data")?;
        let mut nodes = Vec::new();
        self.btree(btree, 0, None, from, &mut HashSet::new(), &mut |_, child| {
            nodes.push(child);
            Ok(())
        })?;
        for node in nodes {
            let at = self.offset(node, from, "a symbol table node")?;
            let mut c = self.cursor(at, 8, "a symbol table node")?;
            if c.take(4)? != b"SNOD" {
                return Err(self.bad(at, "a symbol table node without its `SNOD` signature".into()));
            }
            c.skip(2)?;
            let count = usize::from(c.u16()?);
            self.charge(at, 8 + 40 * count)?;
            let mut c = self.cursor(at + 8, 40 * count, "a symbol table entry")?;
            for _ in 0..count {
                let name_at = c.u64()?;
                let address = c.u64()?;
                c.skip(24)?;
                let name = usize::try_from(name_at)
                    .ok()
                    .and_then(|n| names.get(n..))
                    .and_then(|s| s.split(|&b| b == 0).next().filter(|_| s.contains(&0)))
                    .ok_or_else(|| {
                        self.bad(at, format!("a link name at heap offset {name_at}, outside the heap"))
                    })?;
                links.push((String::from_utf8_lossy(name).into_owned(), address));
            }
        }
        Ok(())
    }

    /// Walks the version 1 B-tree at `address` of node type `kind` (0 groups, 1 chunks), calling
    /// `leaf` with each key (its file offset) and child address of its leaves. Keys of chunk nodes
    /// have `key_len` bytes; group keys 8.
    fn btree(
        &self,
        address: u64,
        kind: u8,
        expect_level: Option<u8>,
        from: usize,
        seen: &mut HashSet<u64>,
        leaf: &mut dyn FnMut(usize, u64) -> Result<()>,
    ) -> Result<()> {
        self.btree_with(address, kind, 8, expect_level, from, seen, leaf)
    }

    #[allow(clippy::too_many_arguments)]
    fn btree_with(
        &self,
        address: u64,
        kind: u8,
        key_len: usize,
        expect_level: Option<u8>,
        from: usize,
        seen: &mut HashSet<u64>,
        leaf: &mut dyn FnMut(usize, u64) -> Result<()>,
    ) -> Result<()> {
        let at = self.offset(address, from, "a B-tree node")?;
        if !seen.insert(address) {
            return Err(self.bad(at, "a B-tree node reached twice: the B-tree has a cycle".into()));
        }
        let mut c = self.cursor(at, 24, "a B-tree node")?;
        if c.take(4)? != b"TREE" {
            return Err(self.bad(at, "a B-tree node without its `TREE` signature".into()));
        }
        let (node_kind, level, entries) = (c.u8()?, c.u8()?, usize::from(c.u16()?));
        if node_kind != kind || expect_level.is_some_and(|l| l != level) {
            return Err(self.bad(
                at,
                format!("a B-tree node of type {node_kind} at level {level}, not of type {kind} at level {expect_level:?}"),
            ));
        }
        let bytes = entries * (key_len + 8) + key_len;
        self.charge(at, 24 + bytes)?;
        let mut c = self.cursor(at + 24, bytes, "a B-tree node's entries")?;
        for _ in 0..entries {
            let key = c.here();
            c.skip(key_len)?;
            let child = c.u64()?;
            if level == 0 {
                leaf(key, child)?;
            } else {
                self.btree_with(child, kind, key_len, Some(level - 1), at, seen, leaf)?;
            }
        }
        Ok(())
    }

    /// The bytes of a dataset, in C order of its dimensions (`name` for messages).
    pub fn read(&self, d: &Dataset<'a>, name: &str) -> Result<Vec<u8>> {
        let element = d.datatype.size();
        let count = d
            .dims
            .iter()
            .try_fold(1u64, |n, &x| n.checked_mul(x))
            .and_then(|n| usize::try_from(n).ok());
        let len = count.and_then(|n| n.checked_mul(element)).ok_or_else(|| {
            self.bad(d.at, format!("`{name}` of dimensions {:?}: too many elements", d.dims))
        })?;
        self.allocate(d.at, len, name)?;
        if len == 0 {
            return Ok(Vec::new());
        }
        match &d.layout {
            Layout::Compact(data) => data.get(..len).map(<[u8]>::to_vec).ok_or_else(|| {
                self.bad(
                    d.at,
                    format!("`{name}`: {} compact bytes for {len} bytes of data", data.len()),
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
                let most = d.dims.iter().zip(&chunk).fold(1u64, |n, (&x, &c)| {
                    n.saturating_mul(x.div_ceil(c))
                });
                if chunks.len() as u64 > most {
                    return Err(self.bad(
                        d.at,
                        format!("`{name}`: {} chunks where {most} fill its dimensions", chunks.len()),
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
                    chunk.iter().product::<u64>().saturating_mul(element as u64),
                    0,
                ));
                let raw = self.slice(*address, size, d.at, &format!("the chunk of `{name}`"))?;
                let data = self.unfilter(d, raw, mask, &chunk, name)?;
                let mut out = vec![0; len];
                place(&mut out, &data, &d.dims, &chunk, &vec![0; chunk.len()], element);
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
                format!("`{name}`: chunk dimensions {chunk:?} for data of dimensions {:?}", d.dims),
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
                self.bad(d.at, format!("`{name}`: chunks of {chunk:?} elements, more than the file holds"))
            })?;
        let mut data = raw.to_vec();
        for (i, &id) in d.filters.iter().enumerate().rev() {
            if i < 32 && mask & (1 << i) != 0 {
                continue;
            }
            data = match id {
                1 => miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(&data, want)
                    .map_err(|e| {
                        self.bad(
                            d.at,
                            format!("`{name}`: a chunk of {} bytes: bad zlib data ({:?})", raw.len(), e.status),
                        )
                    })?,
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

/// Refuses offsets and lengths other than 8 bytes (what every writer of MAT-files uses).
fn check_sizes(file: &File<'_>, base: usize, offsets: u8, lengths: u8) -> Result<()> {
    if offsets != 8 || lengths != 8 {
        return Err(file.bad(
            base + 9,
            format!("HDF5 offsets of {offsets} bytes and lengths of {lengths}: only 8 and 8 are read"),
        ));
    }
    Ok(())
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
fn place(out: &mut [u8], data: &[u8], dims: &[u64], chunk: &[u64], offsets: &[u64], element: usize) {
    let dims: Vec<u64> = if dims.is_empty() { vec![1] } else { dims.to_vec() };
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
