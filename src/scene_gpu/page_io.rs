//! Streaming I/O of a [`GpuScene`] without waiting: page loads and evictions staged for the next
//! frame's `scene_update` copies, and the cull's page feedback copied at the end of a frame into
//! a ring of host-visible slots that the host reads once that frame is done.
//!
//! - [`GpuScene::update_pages`] records nothing and submits nothing: it updates the CPU's page
//!   table and keeps the changes (page-table entries, page bytes by pool word, mesh-table entries)
//!   until [`GpuScene::prepare_updates`] writes them into the frame's staging-ring buffer (beside
//!   the instance updates) and [`GpuScene::record_updates`] records their copies at the start of
//!   the frame. A frame already in flight keeps the page table and pool contents it was recorded
//!   with: the copies run after it on the queue, behind the same barrier as the instance copies.
//! - [`GpuScene::record_feedback`] copies the feedback buffers (`page_requests`, `page_usage`)
//!   into the next ring slot, clears them, and writes a sequence number after the copy.
//!   [`GpuScene::take_page_feedback`] returns the newest slot whose sequence number has landed
//!   and that was not taken yet: it never waits (the host calls it after the frame's fence, as it
//!   does before reusing the frame's resources).

use std::cell::Cell;
use std::collections::{BTreeMap, BTreeSet};

use super::{
    GpuScene, MESH_GPU_BYTES, MeshHandle, PAGES, POOL, PageChange, SceneError, SceneResult,
};
use crate::gpu::{Buffer, Cmd, GpuResult, MemoryKind, vk};
use crate::shared::{PAGE_NOT_RESIDENT, PageGpu};

/// Region lists of the prepared page copies, by destination.
pub(super) const TO_POOL: usize = 0;
pub(super) const TO_PAGES: usize = 1;
pub(super) const TO_MESHES: usize = 2;

/// Page changes waiting for the next frame's `scene_update` (kept until it was recorded).
#[derive(Default)]
pub(super) struct StagedPages {
    /// (mesh slot, page) whose page-table entry changed: written from the CPU's table.
    entries: BTreeSet<(u32, u32)>,
    /// Page bytes by destination pool word (a later load into the same slot replaces it).
    loads: BTreeMap<u32, Vec<u8>>,
    /// Mesh slots whose [`crate::shared::MeshGpu`] changed (the partial flag).
    meshes: BTreeSet<u32>,
}

impl StagedPages {
    /// Staging-ring bytes the changes take (an upper bound).
    pub(super) fn bytes(&self) -> u64 {
        self.loads.values().map(|b| b.len() as u64).sum::<u64>()
            + (self.entries.len() * size_of::<PageGpu>()) as u64
            + self.meshes.len() as u64 * MESH_GPU_BYTES
    }

    /// Whether a mesh entry's change waits for its copy.
    pub(super) fn has_mesh_changes(&self) -> bool {
        !self.meshes.is_empty()
    }

    /// Forgets what targets mesh slot `index` (removed).
    pub(super) fn forget_mesh(&mut self, index: u32) {
        self.entries.retain(|&(m, _)| m != index);
        self.meshes.remove(&index);
    }
}

/// One host-visible copy of the feedback: requests, usage, then the sequence number.
struct FeedbackSlot {
    buffer: Buffer,
    /// Sequence number of the copy recorded into it (0: none).
    seq: Cell<u64>,
    /// Bytes of each of the two copied buffers.
    len: Cell<u64>,
}

/// A feedback copy: its sequence number, per page entry the wish (f32 bits) and the used flag.
type Feedback = (u64, Vec<u32>, Vec<u32>);

/// The feedback read-back ring.
#[derive(Default)]
pub(super) struct FeedbackRing {
    slots: Vec<FeedbackSlot>,
    next: Cell<usize>,
    /// Sequence number of the last copy recorded.
    seq: Cell<u64>,
    /// Frames recorded (their culls wrote feedback) since the last copy.
    frames: Cell<u32>,
    /// Newest sequence number handed out by `take_page_feedback`.
    taken: u64,
}

impl GpuScene {
    /// Loads pages into the pool and evicts others at the start of the next frame: each change
    /// names a mesh's page and either its bytes and the pool word to put them at (a slot of
    /// [`GpuScene::reserve_page_slots`]), or `None` to mark it absent. Nothing is submitted or
    /// waited for: the changes are written into the staging ring by [`GpuScene::prepare_updates`]
    /// and copied by [`GpuScene::record_updates`], before anything of that frame reads them; a
    /// frame recorded earlier (in flight) keeps the pages it was recorded with. An evicted page's
    /// slot may be given to another page right away (the copies of one update run in order after
    /// every earlier frame).
    pub fn update_pages(&mut self, changes: &[PageChange]) -> SceneResult<()> {
        let pool_words = self.arenas[POOL].size();
        // Check everything first: a refused change stages nothing.
        for c in changes {
            let live = self.live_mesh(c.mesh)?;
            let p = c.page as usize;
            if p >= live.page_records.len() || p < live.resident_pages as usize {
                return Err(SceneError::Residency(format!(
                    "page {p} of {} cannot be loaded or evicted (always resident: {})",
                    live.page_records.len(),
                    live.resident_pages
                )));
            }
            if let Some((word, bytes)) = &c.load {
                let len = live.page_records[p].bytes as usize;
                if bytes.len() != len || *word as u64 + (len / 4) as u64 > pool_words {
                    return Err(SceneError::Residency(format!(
                        "page {p}: {} bytes at word {word} (its page table says {len}, the pool {pool_words} words)",
                        bytes.len()
                    )));
                }
            }
        }
        for c in changes {
            let ri = c.mesh.index;
            let word = match &c.load {
                Some((word, bytes)) => {
                    self.staged.loads.insert(*word, bytes.clone());
                    *word
                }
                None => PAGE_NOT_RESIDENT,
            };
            let live = self.mesh_slots[ri as usize]
                .live
                .as_mut()
                .expect("checked live");
            live.loaded[c.page as usize] = word;
            live.hidden[c.page as usize] = false;
            let partial = live.partial();
            self.staged.entries.insert((ri, c.page));
            // The mesh's partial flag follows its pages.
            if self.set_mesh_partial(ri as usize, partial) {
                self.staged.meshes.insert(ri);
            }
        }
        Ok(())
    }

    /// Page changes staged and not yet recorded (loads, page-table entries, mesh entries).
    pub fn staged_page_changes(&self) -> (usize, usize, usize) {
        (
            self.staged.loads.len(),
            self.staged.entries.len(),
            self.staged.meshes.len(),
        )
    }

    /// Writes the staged page changes into staging-ring buffer `slot` from byte `off` on and
    /// prepares their copies (`page_regions`); returns the end offset. The ring buffer holds at
    /// least [`StagedPages::bytes`] from `off`.
    pub(super) fn stage_pages_into(&mut self, slot: usize, mut off: u64) -> GpuResult<u64> {
        for r in &mut self.page_regions {
            r.clear();
        }
        let ring = &mut self.ring[slot];
        for (&word, bytes) in &self.staged.loads {
            ring.write(off, bytes)?;
            self.page_regions[TO_POOL].push(vk::BufferCopy {
                src_offset: off,
                dst_offset: 4 * word as u64,
                size: bytes.len() as u64,
            });
            off += bytes.len() as u64;
        }
        // Page-table entries from the CPU's table, runs of one mesh's consecutive pages merged.
        let stride = size_of::<PageGpu>() as u64;
        let mut entries = self.staged.entries.iter().peekable();
        while let Some(&(mi, p0)) = entries.next() {
            let Some(live) = self.mesh_slots[mi as usize].live.as_ref() else {
                continue;
            };
            let mut run = vec![live.entry(p0 as usize)];
            let mut last = p0;
            while let Some(&&(m, p)) = entries.peek() {
                if m != mi || p != last + 1 {
                    break;
                }
                run.push(live.entry(p as usize));
                last = p;
                entries.next();
            }
            let bytes: &[u8] = bytemuck::cast_slice(&run);
            ring.write(off, bytes)?;
            self.page_regions[TO_PAGES].push(vk::BufferCopy {
                src_offset: off,
                dst_offset: (live.ranges[PAGES].0 + p0 as u64) * stride,
                size: bytes.len() as u64,
            });
            off += bytes.len() as u64;
        }
        for &mi in &self.staged.meshes {
            let bytes = bytemuck::bytes_of(&self.mesh_table[mi as usize]);
            ring.write(off, bytes)?;
            self.page_regions[TO_MESHES].push(vk::BufferCopy {
                src_offset: off,
                dst_offset: MESH_GPU_BYTES * mi as u64,
                size: bytes.len() as u64,
            });
            off += bytes.len() as u64;
        }
        Ok(off)
    }

    /// Records the prepared page copies (inside `record_updates`' barriers).
    pub(super) fn record_page_copies(&self, cmd: &mut Cmd, slot: usize) {
        let ring = &self.ring[slot];
        cmd.copy_buffer_regions(ring, &self.pool, &self.page_regions[TO_POOL]);
        cmd.copy_buffer_regions(ring, &self.pages, &self.page_regions[TO_PAGES]);
        cmd.copy_buffer_regions(ring, &self.meshes, &self.page_regions[TO_MESHES]);
    }

    /// The staged page changes were recorded: forget them.
    pub(super) fn pages_submitted(&mut self) {
        self.staged = StagedPages::default();
        for r in &mut self.page_regions {
            r.clear();
        }
    }

    /// Makes the feedback ring's slots as large as the feedback buffers (allocates; called
    /// before recording, by [`GpuScene::prepare_updates`]).
    pub(super) fn prepare_feedback(&mut self) -> GpuResult<()> {
        let len = self.page_requests.size();
        let need = 2 * len + 8;
        // One per frame in flight, and one more: one of them holds a copy that has landed.
        let slots = self.ring_slots + 1;
        let ring = &mut self.feedback;
        for k in 0..slots {
            if k < ring.slots.len() && ring.slots[k].buffer.size() >= need {
                continue;
            }
            let slot = FeedbackSlot {
                buffer: Buffer::new(
                    &self.ctx,
                    &format!("scene page feedback {k}"),
                    need,
                    vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryKind::Readback,
                )?,
                seq: Cell::new(0),
                len: Cell::new(0),
            };
            if k < ring.slots.len() {
                // A frame in flight may still write the old one: keep it until the GPU is done.
                let old = std::mem::replace(&mut ring.slots[k], slot);
                self.retired.push(old.buffer);
            } else {
                ring.slots.push(slot);
            }
        }
        Ok(())
    }

    /// A frame (or a cull) that writes page feedback was recorded: the next
    /// [`GpuScene::record_feedback`] copies it.
    pub(crate) fn note_feedback_frame(&self) {
        self.feedback.frames.set(self.feedback.frames.get() + 1);
    }

    /// Records (label `page_feedback`) the copy of the page feedback that the frames recorded
    /// since the last copy accumulated into the next read-back slot, clears the feedback, and
    /// writes the copy's sequence number behind it. Records nothing when no frame was recorded
    /// since, or before [`GpuScene::prepare_updates`] made the slots.
    pub fn record_feedback(&self, cmd: &mut Cmd) {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        let ring = &self.feedback;
        let len = self.page_requests.size();
        if ring.frames.get() == 0 || ring.slots.is_empty() {
            return;
        }
        let k = ring.next.get();
        let slot = &ring.slots[k];
        if slot.buffer.size() < 2 * len + 8 {
            return;
        }
        ring.next.set((k + 1) % ring.slots.len());
        ring.frames.set(0);
        let seq = ring.seq.get() + 1;
        ring.seq.set(seq);
        slot.seq.set(seq);
        slot.len.set(len);
        cmd.begin_label("page_feedback");
        cmd.barrier(
            (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
            (S::ALL_TRANSFER, A::TRANSFER_READ | A::TRANSFER_WRITE),
        );
        cmd.copy_buffer_region(&self.page_requests, 0, &slot.buffer, 0, len);
        cmd.copy_buffer_region(&self.page_usage, 0, &slot.buffer, len, len);
        cmd.barrier(
            (S::ALL_TRANSFER, A::TRANSFER_READ | A::TRANSFER_WRITE),
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
        );
        cmd.fill_buffer(&self.page_requests, 0);
        cmd.fill_buffer(&self.page_usage, 0);
        cmd.update_buffer(&slot.buffer, 2 * len, &seq.to_le_bytes());
        cmd.barrier(
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            (
                S::ALL_COMMANDS | S::HOST,
                A::MEMORY_READ | A::MEMORY_WRITE | A::HOST_READ,
            ),
        );
        cmd.end_label();
    }

    /// The newest feedback copy that has landed (its sequence number is in memory): (sequence
    /// number, per page entry its wish as f32 bits, per page entry its used flag). Reads
    /// host-visible memory; never waits.
    fn newest_feedback(&self) -> GpuResult<Option<Feedback>> {
        // Newest first; a slot whose copy has not landed yet falls back to an older one.
        let mut order: Vec<(u64, usize)> = self
            .feedback
            .slots
            .iter()
            .enumerate()
            .filter(|(_, s)| s.seq.get() != 0)
            .map(|(k, s)| (s.seq.get(), k))
            .collect();
        order.sort_unstable_by(|a, b| b.cmp(a));
        for (seq, k) in order {
            let s = &self.feedback.slots[k];
            let len = s.len.get() as usize;
            let bytes = s.buffer.read()?;
            let marker = u64::from_le_bytes(bytes[2 * len..2 * len + 8].try_into().expect("8"));
            if marker != seq {
                continue;
            }
            let words = |r: std::ops::Range<usize>| bytemuck::pod_collect_to_vec(&bytes[r]);
            return Ok(Some((seq, words(0..len), words(len..2 * len))));
        }
        Ok(None)
    }

    /// The page feedback of the frames before the newest copy that has landed and that this was
    /// not given before (per page entry, indexed as [`GpuScene::page_range`]: the largest wish
    /// as f32 bits, and the used flag); `None` when there is no new one. Never waits.
    pub fn take_page_feedback(&mut self) -> SceneResult<Option<(Vec<u32>, Vec<u32>)>> {
        match self.newest_feedback()? {
            Some((seq, wish, used)) if seq > self.feedback.taken => {
                self.feedback.taken = seq;
                Ok(Some((wish, used)))
            }
            _ => Ok(None),
        }
    }

    /// The streaming feedback of every page entry of the scene (requests as f32 bits, usage
    /// flags), indexed by [`GpuScene::page_range`]'s first entry plus the page, as the newest
    /// copy that landed holds it (the frames recorded before it). Never waits; empty before the
    /// first copy.
    pub fn page_feedback_words(&self) -> SceneResult<(Vec<u32>, Vec<u32>)> {
        Ok(self
            .newest_feedback()?
            .map(|(_, w, u)| (w, u))
            .unwrap_or_default())
    }

    /// The streaming feedback of mesh `h`'s pages as the newest copy holds it (see
    /// [`GpuScene::page_feedback_words`]): per page, the largest wish to refine into it
    /// (projected error over the threshold; 0: not asked for) and whether a drawn cluster used it.
    pub fn page_feedback(&self, h: MeshHandle) -> SceneResult<(Vec<f32>, Vec<bool>)> {
        let (first, n) = self.live_mesh(h)?.ranges[PAGES];
        let (wish, used) = self.page_feedback_words()?;
        let range = first as usize..(first + n) as usize;
        let pick = |w: &[u32]| -> Vec<u32> {
            range
                .clone()
                .map(|i| w.get(i).copied().unwrap_or(0))
                .collect()
        };
        Ok((
            pick(&wish).into_iter().map(f32::from_bits).collect(),
            pick(&used).into_iter().map(|u| u != 0).collect(),
        ))
    }

    /// Zeroes the streaming feedback of every page (one-shot submission, waited for).
    pub fn clear_page_feedback(&self) -> SceneResult<()> {
        let (req, used) = (&self.page_requests, &self.page_usage);
        self.ctx
            .submit_and_wait("scene clear page feedback", |cmd| {
                use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
                cmd.barrier(
                    (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
                    (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                );
                cmd.fill_buffer(req, 0);
                cmd.fill_buffer(used, 0);
                cmd.barrier(
                    (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                    (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
                );
            })?;
        Ok(())
    }
}
