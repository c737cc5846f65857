//! Old-style groups (a version 1 B-tree of symbol table nodes, names in a local heap) and
//! the version 1 B-trees that also index a dataset's chunks.

use std::collections::HashSet;

use crate::error::Result;

use super::File;

impl<'a> File<'a> {
    /// The members of an old-style group, appended to `links`: a version 1 B-tree of symbol
    /// table nodes, names in a local heap.
    pub(super) fn symbol_table(
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
        self.btree(
            btree,
            0,
            None,
            from,
            &mut HashSet::new(),
            &mut |_, child| {
                nodes.push(child);
                Ok(())
            },
        )?;
        for node in nodes {
            let at = self.offset(node, from, "a symbol table node")?;
            let mut c = self.cursor(at, 8, "a symbol table node")?;
            if c.take(4)? != b"SNOD" {
                return Err(self.bad(
                    at,
                    "a symbol table node without its `SNOD` signature".into(),
                ));
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
                        self.bad(
                            at,
                            format!("a link name at heap offset {name_at}, outside the heap"),
                        )
                    })?;
                links.push((String::from_utf8_lossy(name).into_owned(), address));
            }
        }
        Ok(())
    }

    /// Walks the version 1 B-tree at `address` of node type `kind` (0 groups, 1 chunks), calling
    /// `leaf` with each key (its file offset) and child address of its leaves. Keys of chunk nodes
    /// have `key_len` bytes; group keys 8.
    pub(super) fn btree(
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
    pub(super) fn btree_with(
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
            return Err(self.bad(
                at,
                "a B-tree node reached twice: the B-tree has a cycle".into(),
            ));
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
}
