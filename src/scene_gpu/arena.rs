//! Growable GPU arenas for a scene that changes: a best-fit range allocator (CPU only) and a device
//! buffer that grows by doubling, keeping its contents (copied on the GPU) and its debug name.

use std::collections::{BTreeMap, BTreeSet};

use crate::gpu::{Buffer, Context, GpuResult, MemoryKind, vk};

/// Free ranges of a linear space `[0, size)` in elements: best fit, coalescing on free, O(log n)
/// per call. Nothing is ever moved (no compaction): a freed range is reused by the next allocation
/// it fits, and the space only grows ([`RangeAllocator::grow`]).
#[derive(Clone, Debug, Default)]
pub struct RangeAllocator {
    size: u64,
    used: u64,
    /// Free ranges: start -> length.
    by_start: BTreeMap<u64, u64>,
    /// The same ranges as (length, start), for best fit.
    by_len: BTreeSet<(u64, u64)>,
}

impl RangeAllocator {
    /// An empty space of `size` elements, all free.
    pub fn new(size: u64) -> Self {
        let mut a = Self::default();
        a.grow(size);
        a
    }

    /// Size of the space.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Elements in allocated ranges.
    pub fn used(&self) -> u64 {
        self.used
    }

    /// Length of the free range that ends the space (0 when the last element is allocated).
    pub fn tail_free(&self) -> u64 {
        match self.by_start.last_key_value() {
            Some((&s, &l)) if s + l == self.size => l,
            _ => 0,
        }
    }

    /// One past the last allocated element (the high-water mark).
    pub fn end(&self) -> u64 {
        self.size - self.tail_free()
    }

    fn insert_free(&mut self, start: u64, len: u64) {
        self.by_start.insert(start, len);
        self.by_len.insert((len, start));
    }

    fn remove_free(&mut self, start: u64, len: u64) {
        self.by_start.remove(&start);
        self.by_len.remove(&(len, start));
    }

    /// The start of a free range of `len` elements (the smallest that fits; the lowest start among
    /// equals), now allocated; `None` when none fits. `len` 0 allocates nothing and returns 0.
    pub fn alloc(&mut self, len: u64) -> Option<u64> {
        if len == 0 {
            return Some(0);
        }
        let &(flen, fstart) = self.by_len.range((len, 0)..).next()?;
        self.remove_free(fstart, flen);
        if flen > len {
            self.insert_free(fstart + len, flen - len);
        }
        self.used += len;
        Some(fstart)
    }

    /// Frees `[start, start + len)` (which must have been allocated), merging with free neighbours.
    pub fn free(&mut self, start: u64, len: u64) {
        if len == 0 {
            return;
        }
        debug_assert!(start + len <= self.size);
        self.used -= len;
        let (mut s, mut l) = (start, len);
        if let Some((&ps, &pl)) = self.by_start.range(..start).next_back()
            && ps + pl == start
        {
            self.remove_free(ps, pl);
            s = ps;
            l += pl;
        }
        if let Some(&nl) = self.by_start.get(&(start + len)) {
            self.remove_free(start + len, nl);
            l += nl;
        }
        self.insert_free(s, l);
    }

    /// Extends the space to `new_size` elements (no-op when not larger); the new part is free.
    pub fn grow(&mut self, new_size: u64) {
        if new_size <= self.size {
            return;
        }
        let old = self.size;
        self.size = new_size;
        // Freeing the new part merges it with a free tail.
        self.used += new_size - old;
        self.free(old, new_size - old);
    }
}

/// The usage of every growable scene buffer: read by shaders, written by copies, copied when it
/// grows.
pub fn usage() -> vk::BufferUsageFlags {
    vk::BufferUsageFlags::STORAGE_BUFFER
        | vk::BufferUsageFlags::TRANSFER_DST
        | vk::BufferUsageFlags::TRANSFER_SRC
}

/// Replaces `buf` by a device-local buffer of `bytes` bytes with the same name and [`usage`],
/// holding a GPU copy of the first `keep` bytes of the old one; returns the old buffer, to be
/// dropped once the GPU no longer uses it.
pub fn grow_buffer(ctx: &Context, buf: &mut Buffer, bytes: u64, keep: u64) -> GpuResult<Buffer> {
    use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
    let name = buf.name().to_string();
    let new = Buffer::new(ctx, &name, bytes, usage(), MemoryKind::Gpu)?;
    let keep = keep.min(buf.size()).min(new.size());
    if keep > 0 {
        ctx.submit_and_wait(&format!("grow {name}"), |cmd| {
            // Earlier submissions' writes (scene updates) land before the copy reads them.
            cmd.barrier(
                (S::ALL_COMMANDS, A::MEMORY_WRITE),
                (S::ALL_TRANSFER, A::TRANSFER_READ),
            );
            cmd.copy_buffer(buf, &new, keep);
        })?;
    }
    Ok(std::mem::replace(buf, new))
}

/// The ranges of one growable scene buffer (the buffer itself is the scene's, so passes keep
/// binding it by name): elements of `elem` bytes, ranges rounded up to `align` elements.
#[derive(Clone, Debug)]
pub struct Arena {
    alloc: RangeAllocator,
    elem: u64,
    align: u64,
}

impl Arena {
    /// An empty arena.
    pub fn new(elem: u64, align: u64) -> Self {
        Self {
            alloc: RangeAllocator::new(0),
            elem,
            align: align.max(1),
        }
    }

    /// Bytes per element.
    pub fn elem(&self) -> u64 {
        self.elem
    }

    /// Allocated bytes.
    pub fn used_bytes(&self) -> u64 {
        self.alloc.used() * self.elem
    }

    /// Size of the space in elements.
    pub fn size(&self) -> u64 {
        self.alloc.size()
    }

    /// `len` rounded up to the alignment.
    pub fn rounded(&self, len: u64) -> u64 {
        len.div_ceil(self.align) * self.align
    }

    /// Makes sure `total` elements fit after the last allocated one, growing `buf` if not (to
    /// twice the size, but no more than one storage buffer binds, `maxStorageBufferRange`, and at
    /// least to what is needed; from empty, to exactly `total`). Returns the replaced buffer, if
    /// any.
    pub fn reserve(
        &mut self,
        ctx: &Context,
        buf: &mut Buffer,
        total: u64,
    ) -> GpuResult<Option<Buffer>> {
        let total = self.rounded(total);
        if self.alloc.tail_free() >= total {
            return Ok(None);
        }
        // Doubling stops at the binding limit: a scene whose elements fit is never refused for
        // the growth's slack (the pool holds pages up to the budget, which may be that limit).
        let bindable =
            ctx.caps().max_storage_buffer_range as u64 / self.elem / self.align * self.align;
        let need = self.rounded(self.alloc.end() + total);
        let size = need.max(self.rounded(2 * self.alloc.size()).min(bindable));
        let old = grow_buffer(ctx, buf, size * self.elem, self.alloc.size() * self.elem)?;
        self.alloc.grow(size);
        Ok(Some(old))
    }

    /// Allocates `len` elements, growing `buf` if needed: the start and the replaced buffer.
    pub fn alloc(
        &mut self,
        ctx: &Context,
        buf: &mut Buffer,
        len: u64,
    ) -> GpuResult<(u64, Option<Buffer>)> {
        let len = self.rounded(len);
        if let Some(s) = self.alloc.alloc(len) {
            return Ok((s, None));
        }
        let old = self.reserve(ctx, buf, len)?;
        let s = self.alloc.alloc(len).ok_or_else(|| {
            crate::gpu::GpuError::Other(format!("`{}`: no room after growing", buf.name()))
        })?;
        Ok((s, old))
    }

    /// Frees a range that [`Arena::alloc`] returned for `len` elements.
    pub fn free(&mut self, start: u64, len: u64) {
        self.alloc.free(start, self.rounded(len));
    }
}

#[cfg(test)]
mod tests {
    use super::RangeAllocator;

    #[test]
    fn best_fit_coalesces_and_grows() {
        let mut a = RangeAllocator::new(10);
        assert_eq!(a.alloc(4), Some(0));
        assert_eq!(a.alloc(3), Some(4));
        assert_eq!(a.alloc(3), Some(7));
        assert_eq!(a.alloc(1), None);
        assert_eq!(a.end(), 10);
        a.free(4, 3);
        a.free(0, 4);
        // Coalesced into [0, 7): a 6 fits, the rest stays.
        assert_eq!(a.alloc(6), Some(0));
        assert_eq!(a.used(), 9);
        a.free(7, 3);
        assert_eq!(a.end(), 6);
        assert_eq!(a.tail_free(), 4);
        a.grow(20);
        assert_eq!(a.tail_free(), 14);
        // Best fit: holes of 3 (at 0) and 1 (at 4); a 1 goes to the smaller hole.
        a.free(0, 3);
        a.free(4, 1);
        assert_eq!(a.alloc(1), Some(4));
        assert_eq!(a.alloc(2), Some(0));
        assert_eq!(a.alloc(0), Some(0));
        assert_eq!(a.used(), 5);
    }
}
