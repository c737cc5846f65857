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

mod btree;
mod data;
mod messages;

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
    Fixed {
        size: usize,
        signed: bool,
        big: bool,
    },
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

/// Where a dataset's bytes are.
#[derive(Debug)]
enum Layout<'a> {
    Compact(&'a [u8]),
    Contiguous(u64),
    /// Chunks indexed by a version 1 B-tree; chunk dimensions, the last one the element size.
    Chunked {
        btree: u64,
        chunk: Vec<u64>,
    },
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
            self.file.bad(
                self.here(),
                format!("{}: a name without its NUL", self.what),
            )
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
                return Err(file.bad(
                    base + 8,
                    format!("HDF5 superblock version {other}, not 0–3"),
                ));
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
            if at
                .checked_add(size)
                .is_none_or(|end| end > self.bytes.len())
            {
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
            let header = if v2 {
                4 + 2 * usize::from(creation_order)
            } else {
                8
            };
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
                                "an object header continuation without its `OCHK` signature".into(),
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
}

/// Refuses offsets and lengths other than 8 bytes (what every writer of MAT-files uses).
fn check_sizes(file: &File<'_>, base: usize, offsets: u8, lengths: u8) -> Result<()> {
    if offsets != 8 || lengths != 8 {
        return Err(file.bad(
            base + 9,
            format!(
                "HDF5 offsets of {offsets} bytes and lengths of {lengths}: only 8 and 8 are read"
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A superblock of version 2 (48 bytes) whose root object header follows it, at address 48,
    /// then `rest` at address 48 + its length.
    fn file(header: &[u8], rest: &[u8]) -> Vec<u8> {
        let mut bytes = SIGNATURE.to_vec();
        bytes.extend([2, 8, 8, 0]);
        bytes.extend(0u64.to_le_bytes()); // base address
        bytes.extend(UNDEFINED.to_le_bytes()); // superblock extension
        bytes.extend(0u64.to_le_bytes()); // end of file (not read)
        bytes.extend(48u64.to_le_bytes()); // root object header
        bytes.extend([0; 4]); // checksum (not read)
        bytes.extend(header);
        bytes.extend(rest);
        bytes
    }

    /// A version 1 object header of `size` bytes of messages, then the messages.
    fn header(size: u32, messages: &[u8]) -> Vec<u8> {
        let mut h = vec![1, 0, 1, 0];
        h.extend(1u32.to_le_bytes());
        h.extend(size.to_le_bytes());
        h.extend([0; 4]);
        h.extend(messages);
        h
    }

    /// A version 1 message: type, data (a multiple of 8 bytes).
    fn message(kind: u16, data: &[u8]) -> Vec<u8> {
        let mut m = kind.to_le_bytes().to_vec();
        m.extend((data.len() as u16).to_le_bytes());
        m.extend([0; 4]);
        m.extend(data);
        m
    }

    fn error(bytes: &[u8]) -> String {
        let file = File::open(bytes, "t.mat");
        let e = match file {
            Ok(f) => f.object(f.root).err().expect("an error"),
            Err(e) => e,
        };
        assert_eq!(e.kind(), "malformed_mat");
        e.to_string()
    }

    #[test]
    fn a_truncated_superblock_is_malformed() {
        let bytes = file(&[], &[]);
        for cut in [9, 12, 40] {
            let m = error(&bytes[..cut]);
            assert!(m.contains("truncated: the superblock needs"), "{cut}: {m}");
        }
        let m = error(&bytes);
        assert!(
            m.contains("an object header at address 0x30, past the end"),
            "{m}"
        );
    }

    #[test]
    fn an_object_header_that_claims_more_bytes_than_the_file_has_is_malformed() {
        let bytes = file(&header(10_000, &[]), &[]);
        let m = error(&bytes);
        assert!(
            m.contains(
                "t.mat, byte 64: truncated: an object header block of 10000 bytes, 0 remain"
            ),
            "{m}"
        );
    }

    #[test]
    fn a_continuation_back_to_its_own_block_is_a_cycle() {
        // The messages start at address 64; the continuation points there again.
        let continuation = [64u64.to_le_bytes(), 24u64.to_le_bytes()].concat();
        let bytes = file(&header(24, &message(MSG_CONTINUATION, &continuation)), &[]);
        let m = error(&bytes);
        assert!(
            m.contains("byte 64: object header continuations form a cycle"),
            "{m}"
        );
    }

    #[test]
    fn a_group_b_tree_node_that_is_its_own_child_is_a_cycle() {
        // Root header (16 + 24 bytes) at 48; then a local heap at 88 (32 bytes, its 8 data
        // bytes at 120) and a B-tree node at 128 whose only child is itself.
        let table = [128u64.to_le_bytes(), 88u64.to_le_bytes()].concat();
        let mut rest = b"HEAP".to_vec();
        rest.extend([0; 4]);
        rest.extend(8u64.to_le_bytes());
        rest.extend(0u64.to_le_bytes());
        rest.extend(120u64.to_le_bytes());
        rest.extend([0; 8]);
        rest.extend(b"TREE");
        rest.extend([0, 1, 1, 0]); // groups, level 1, one entry
        rest.extend(UNDEFINED.to_le_bytes());
        rest.extend(UNDEFINED.to_le_bytes());
        rest.extend(0u64.to_le_bytes());
        rest.extend(128u64.to_le_bytes());
        rest.extend(0u64.to_le_bytes());
        let bytes = file(&header(24, &message(MSG_SYMBOL_TABLE, &table)), &rest);
        let m = error(&bytes);
        assert!(
            m.contains("byte 128: a B-tree node reached twice: the B-tree has a cycle"),
            "{m}"
        );
    }
}
