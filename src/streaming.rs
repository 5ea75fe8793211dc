//! Streaming: geometry as virtual memory. A [`Streamer`] keeps the meshes it was given partly
//! resident in the scene's geometry pool under a byte budget: each mesh's always-resident pages
//! (the DAG's top, [`BuiltMesh::resident_pages`]) for good, the other pages in fixed-size slots,
//! loaded when the cull asks for them and evicted least-recently-used.
//!
//! Per frame ([`Streamer::update`], between frames, never waiting for the GPU): the pages the
//! previous step's worker thread read are staged for the next frame's `scene_update` copies
//! ([`GpuScene::update_pages`]); the newest page feedback that has landed in host memory is read
//! (per page, the largest wish to refine into it, and whether a drawn cluster used it;
//! `shaders_glsl/common/cull.glsl`, copied at the end of a frame by
//! [`GpuScene::record_feedback`]); requests are taken by decreasing wish, each with the pages that
//! keep the residency closed ([`crate::builder::page::close_residency`]: a resident group's
//! products' groups stay resident, so the cut is crack-free); slots are freed by evicting
//! least-recently-used pages that no resident group needs and reserved for the new loads, at most
//! [`StreamOptions::upload_bytes_per_frame`] per step; and the new loads are read on a worker
//! thread (pages in parallel) while the next frame draws. A request is thus drawn two frames
//! after the frame that asked. A page that cannot be read (I/O error, checksum) is reported once
//! and never asked for again: its mesh stays coarser there.

use rayon::prelude::*;

use crate::builder::BuiltMesh;
use crate::builder::page::group_needs;
use crate::scene_gpu::{GpuScene, MeshHandle, PageChange, SceneError, SceneResult};

/// Where a streamed mesh's pages come from.
pub trait PageSource: Send + Sync {
    /// Page `page`'s encoded bytes (`builder::page::page_bytes`), checked; an error says why not.
    fn read_page(&self, page: u32) -> Result<Vec<u8>, String>;
}

/// A mesh in memory serves its own pages.
impl PageSource for BuiltMesh {
    fn read_page(&self, page: u32) -> Result<Vec<u8>, String> {
        if page as usize >= self.pages.len() {
            return Err(format!("page {page} out of range"));
        }
        Ok(crate::builder::page::page_bytes(self, page))
    }
}

/// A `.vgeo` file serves its pages one at a time, each checked as it is read.
impl PageSource for crate::format::VgeoFile {
    fn read_page(&self, page: u32) -> Result<Vec<u8>, String> {
        crate::format::VgeoFile::read_page(self, page).map_err(|e| e.to_string())
    }
}

/// Budgets of a [`Streamer`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StreamOptions {
    /// GPU bytes the streamed meshes' pages may take: the always-resident pages plus the slots.
    pub budget_bytes: u64,
    /// Most page bytes read and uploaded per [`Streamer::update`]. A request is served with the
    /// pages that keep the residency closed (its load set); a set larger than this on its own
    /// is loaded alone, in an update of its own, so that no request waits forever.
    pub upload_bytes_per_frame: u64,
}

/// A geometry budget as the command line gives it (`vgeo render` and `vgeo bench`,
/// `--geometry-budget MIB|auto`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum GeometryBudget {
    /// A share of the device's memory: its largest device-local heap over
    /// [`GeometryBudget::AUTO_DIVISOR`] (a quarter), leaving the rest to the frame's buffers,
    /// the hierarchy (cluster records, groups, BVH: resident in full) and the application; at
    /// most what one storage buffer binds (the page pool is one).
    Auto,
    /// This many bytes.
    Bytes(u64),
}

impl GeometryBudget {
    /// `auto` takes the device-local heap over this.
    pub const AUTO_DIVISOR: u64 = 4;

    /// Parses `auto` or a positive, finite number of MiB (fractions allowed); the error says what
    /// is accepted.
    pub fn parse(s: &str) -> Result<Self, String> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("auto") {
            return Ok(GeometryBudget::Auto);
        }
        match s.parse::<f64>() {
            Ok(mib)
                if mib.is_finite() && mib > 0.0 && mib * ((1u64 << 20) as f64) < 2f64.powi(63) =>
            {
                Ok(GeometryBudget::Bytes((mib * (1u64 << 20) as f64) as u64))
            }
            _ => Err(format!(
                "`{s}` is no geometry budget: a positive number of MiB, or `auto` (a quarter of the device-local memory, at most what one buffer binds)"
            )),
        }
    }

    /// The budget in bytes on a device whose largest device-local heap holds
    /// `device_local_bytes` (see [`crate::gpu::Caps::device_local_bytes`]) and which binds at
    /// most `max_pool_bytes` in the geometry pool's one storage buffer
    /// ([`crate::gpu::Caps::max_storage_buffer_range`]): `auto` takes no more than that, so that
    /// the default streams any scene (a quarter of a large GPU's memory is more than a buffer
    /// binds); a given budget is taken as given.
    pub fn bytes(self, device_local_bytes: u64, max_pool_bytes: u64) -> u64 {
        match self {
            GeometryBudget::Auto => (device_local_bytes / Self::AUTO_DIVISOR).min(max_pool_bytes),
            GeometryBudget::Bytes(b) => b,
        }
    }

    /// [`GeometryBudget::bytes`] on the device `caps` describes.
    pub fn bytes_on(self, caps: &crate::gpu::Caps) -> u64 {
        self.bytes(
            caps.device_local_bytes,
            caps.max_storage_buffer_range as u64,
        )
    }

    /// [`GeometryBudget::describe`] on the device `caps` describes.
    pub fn describe_on(self, caps: &crate::gpu::Caps) -> String {
        self.describe(
            caps.device_local_bytes,
            caps.max_storage_buffer_range as u64,
        )
    }

    /// One line for the start of a run: the budget, and for `auto` where it comes from.
    pub fn describe(self, device_local_bytes: u64, max_pool_bytes: u64) -> String {
        match self {
            GeometryBudget::Auto => {
                let quarter = device_local_bytes / Self::AUTO_DIVISOR;
                let cap = if quarter > max_pool_bytes {
                    format!(
                        ", capped at the {} one storage buffer binds (maxStorageBufferRange)",
                        mib(max_pool_bytes)
                    )
                } else {
                    String::new()
                };
                format!(
                    "geometry budget: {} (auto: a quarter of the {} device-local heap{cap})",
                    mib(self.bytes(device_local_bytes, max_pool_bytes)),
                    mib(device_local_bytes)
                )
            }
            GeometryBudget::Bytes(b) => format!("geometry budget: {}", mib(b)),
        }
    }
}

/// What one [`Streamer::update`] did, and the residency after it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StreamStats {
    /// Pages resident (always-resident ones included; pages being read count: their slots are
    /// theirs) and the bytes they take (slots counted whole).
    pub resident_pages: u64,
    pub resident_bytes: u64,
    /// Pages the frames of the newest feedback used (those holding a drawn cluster) and their
    /// bytes: what the cut needs resident.
    pub used_pages: u64,
    pub used_bytes: u64,
    /// Pages the cull asked for.
    pub requests: u64,
    /// Requests served (each with its load set, see [`StreamOptions::upload_bytes_per_frame`]).
    pub load_sets: u64,
    /// Pages staged for the next frame (read by the previous step) and their bytes; pages
    /// evicted.
    pub uploads: u64,
    pub upload_bytes: u64,
    pub evictions: u64,
    /// Pages that could not be read (reported once each, in [`Streamer::take_errors`]).
    pub failed: u64,
    /// Pages whose reads this step started on worker threads: they are staged by the next step.
    pub reading: u64,
}

impl StreamStats {
    /// Whether streaming has come to rest: this step staged nothing and started no read (what
    /// the frames ask for is resident, or the budget holds no more).
    pub fn settled(&self) -> bool {
        self.uploads == 0 && self.reading == 0 && self.evictions == 0
    }
}

/// Where the resident bytes go against the cut the newest feedback saw
/// ([`Streamer::cut_residency`]). Page bytes are the pages' own encoded bytes; `resident_bytes`
/// counts slots whole, as the budget does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct CutResidency {
    /// The always-resident pages and the slots in use (whole): [`StreamStats::resident_bytes`].
    pub resident_bytes: u64,
    /// The resident pages' own bytes.
    pub resident_page_bytes: u64,
    /// Pages holding a cluster the newest feedback's frames drew: [`StreamStats::used_bytes`].
    pub used_bytes: u64,
    /// The smallest closed residency holding the used pages and the always-resident ones
    /// ([`crate::builder::page::close_residency`]): what drawing this cut needs resident (the
    /// used pages, the groups above them up to the root, the groups those pages also hold).
    pub needed_bytes: u64,
    /// The always-resident pages, and those of them the cut did not use.
    pub fixed_bytes: u64,
    pub fixed_unused_bytes: u64,
    /// Resident pages outside `needed_bytes`'s set. After a cold cut settles these are groups
    /// the cull asked for to refine a coarse cluster it drew, none of whose own members it then
    /// drew (all culled by the BVH nodes' frustum or HZB tests): without them the coarse cluster
    /// would be drawn again (and ask for them again), so the settled image needs them too. After
    /// camera motion they also hold what earlier views left (evicted only for room,
    /// least-recently-used first).
    pub other_bytes: u64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PageState {
    /// One of the always-resident pages.
    Fixed,
    Absent,
    /// In slot `n`.
    Slot(u32),
    /// Being read into slot `n` (staged by the next step).
    Loading(u32),
    /// Could not be read: never asked for again.
    Failed,
}

struct StreamedMesh {
    handle: MeshHandle,
    head: BuiltMesh,
    source: std::sync::Arc<dyn PageSource>,
    state: Vec<PageState>,
    last_used: Vec<u64>,
    /// Per group, the pages that must be resident while it is ([`group_needs`]).
    needs: Vec<Vec<u32>>,
    /// Per page, the groups with a member on it.
    groups_on: Vec<Vec<u32>>,
    /// Per page, the groups (with no member on it) that need it.
    needed_by: Vec<Vec<u32>>,
    /// Per page, whether the newest feedback's frames drew a cluster of it.
    used: Vec<bool>,
}

impl StreamedMesh {
    fn resident(&self, p: u32) -> bool {
        matches!(
            self.state[p as usize],
            PageState::Fixed | PageState::Slot(_)
        )
    }

    /// Whether page `p` is resident or being read (it will be, once its read lands).
    fn held(&self, p: u32) -> bool {
        self.resident(p) || matches!(self.state[p as usize], PageState::Loading(_))
    }

    /// Whether group `g` is wholly held, or will be once `extra` lands too.
    fn group_held(&self, g: u32, extra: &[u32]) -> bool {
        let g = &self.head.groups[g as usize];
        (g.page_first..g.page_first + g.page_count).all(|p| self.held(p) || extra.contains(&p))
    }

    /// `page`, the absent pages of the groups on it (a group larger than a page is refined only
    /// whole) and the absent pages that must come with them to keep the residency closed; `None`
    /// when one of them failed. Pages being read (an earlier set of this step) count as
    /// resident: a set that took one again gave it a second slot and lost the first.
    fn load_set(&self, page: u32) -> Option<Vec<u32>> {
        let mut set = vec![page];
        let mut k = 0;
        while k < set.len() {
            let p = set[k];
            k += 1;
            for &g in &self.groups_on[p as usize] {
                let grp = &self.head.groups[g as usize];
                for q in grp.page_first..grp.page_first + grp.page_count {
                    if !self.held(q) && !set.contains(&q) {
                        set.push(q);
                    }
                }
            }
            for &g in &self.groups_on[p as usize] {
                if !self.group_held(g, &set) {
                    continue;
                }
                for &q in &self.needs[g as usize] {
                    if !self.held(q) && !set.contains(&q) {
                        set.push(q);
                    }
                }
            }
        }
        if set
            .iter()
            .any(|&p| self.state[p as usize] == PageState::Failed)
        {
            return None;
        }
        Some(set)
    }

    /// Whether page `p` (in a slot) may be evicted: no group (without a member on it) that is
    /// resident, or will be once the pages being read and `coming` (a load set being chosen)
    /// land, needs it. (Counting only resident groups let a page go while a group that needs it
    /// was being read: the group landed with its need absent, and the residency was not closed.)
    fn evictable(&self, p: u32, coming: &[u32]) -> bool {
        matches!(self.state[p as usize], PageState::Slot(_))
            && self.needed_by[p as usize]
                .iter()
                .all(|&g| !self.group_held(g, coming))
    }
}

/// Keeps meshes partly resident under a budget (see the module's documentation).
pub struct Streamer {
    opts: StreamOptions,
    meshes: Vec<StreamedMesh>,
    /// Pool word of slot 0; slot bytes; free slots.
    slot_word: u32,
    slot_bytes: u64,
    slot_count: u32,
    free: Vec<u32>,
    fixed_bytes: u64,
    frame: u64,
    errors: Vec<String>,
    /// The reads started by the last step: (mesh, page, slot) and the worker thread reading them.
    reads: Option<Reads>,
}

/// Page reads running on worker threads while the GPU draws a frame.
struct Reads {
    loads: Vec<(usize, u32, u32)>,
    thread: ReadsThread,
}

/// What reads the pages: a worker thread, or (when none could be started) nothing, done already.
enum ReadsThread {
    Running(std::thread::JoinHandle<Vec<Result<Vec<u8>, String>>>),
    Done(Vec<Result<Vec<u8>, String>>),
}

impl Streamer {
    /// Adds `meshes` (heads without vertex data are enough, e.g. a `.vgeo` file's, with the
    /// sources of their pages) to `scene` with only their always-resident pages, and reserves
    /// page slots for the rest of the budget. A budget smaller than the always-resident pages
    /// (plus one slot) is an error.
    pub fn new(
        scene: &mut GpuScene,
        meshes: Vec<(BuiltMesh, Box<dyn PageSource>)>,
        opts: StreamOptions,
    ) -> SceneResult<(Self, Vec<MeshHandle>)> {
        let mut fixed_bytes = 0u64;
        let mut slot_bytes = 4u64;
        let mut prefixes = Vec::with_capacity(meshes.len());
        for (head, source) in &meshes {
            let mut prefix = Vec::with_capacity(head.resident_pages as usize);
            for p in 0..head.resident_pages {
                let bytes = source.read_page(p).map_err(|e| {
                    SceneError::Residency(format!(
                        "{}: always-resident page {p} cannot be read: {e}",
                        head.name
                    ))
                })?;
                fixed_bytes += bytes.len() as u64;
                prefix.push(bytes);
            }
            for p in &head.pages {
                slot_bytes = slot_bytes.max(p.bytes as u64);
            }
            prefixes.push(prefix);
        }
        slot_bytes = slot_bytes.next_multiple_of(4);
        if opts.budget_bytes < fixed_bytes + slot_bytes {
            return Err(SceneError::Residency(format!(
                "a geometry budget of {} is smaller than the always-resident pages ({}) plus one page slot ({})",
                mib(opts.budget_bytes),
                mib(fixed_bytes),
                mib(slot_bytes)
            )));
        }
        // No more slots than there are pages to hold (a generous budget, e.g. `auto` on a large
        // device, reserves only what the meshes can use).
        let streamable: u64 = meshes
            .iter()
            .map(|(h, _)| (h.pages.len() as u64).saturating_sub(h.resident_pages as u64))
            .sum();
        let slot_count =
            u32::try_from(((opts.budget_bytes - fixed_bytes) / slot_bytes).min(streamable.max(1)))
                .unwrap_or(u32::MAX)
                .min(1 << 20);
        // The pool takes the always-resident pages and the slots in one growth, so that it is
        // no larger than the budget (several growths double it).
        let slot_words = slot_count as u64 * (slot_bytes / 4);
        scene.reserve_pool_words(fixed_bytes / 4 + slot_words)?;
        let mut handles = Vec::with_capacity(meshes.len());
        let mut streamed = Vec::with_capacity(meshes.len());
        for ((head, source), prefix) in meshes.into_iter().zip(prefixes) {
            let handle = scene.add_partial_mesh(&head, &prefix)?;
            let needs = group_needs(&head);
            let n = head.pages.len();
            let mut groups_on = vec![Vec::new(); n];
            for (g, grp) in head.groups.iter().enumerate() {
                for p in grp.page_first..grp.page_first + grp.page_count {
                    groups_on[p as usize].push(g as u32);
                }
            }
            let mut needed_by = vec![Vec::new(); n];
            for (g, need) in needs.iter().enumerate() {
                let grp = &head.groups[g];
                for &p in need {
                    if !(grp.page_first..grp.page_first + grp.page_count).contains(&p) {
                        needed_by[p as usize].push(g as u32);
                    }
                }
            }
            let state = (0..n)
                .map(|p| {
                    if p < head.resident_pages as usize {
                        PageState::Fixed
                    } else {
                        PageState::Absent
                    }
                })
                .collect();
            handles.push(handle);
            streamed.push(StreamedMesh {
                handle,
                head,
                source: source.into(),
                state,
                last_used: vec![0; n],
                used: vec![false; n],
                needs,
                groups_on,
                needed_by,
            });
        }
        let slot_word = scene.reserve_page_slots(slot_words)?;
        Ok((
            Self {
                opts,
                meshes: streamed,
                slot_word,
                slot_bytes,
                slot_count,
                free: (0..slot_count).rev().collect(),
                fixed_bytes,
                frame: 0,
                errors: Vec::new(),
                reads: None,
            },
            handles,
        ))
    }

    /// Bytes of one page slot (the largest page of the streamed meshes).
    pub fn slot_bytes(&self) -> u64 {
        self.slot_bytes
    }

    /// Page slots under the budget.
    pub fn slot_count(&self) -> u32 {
        self.slot_count
    }

    /// Per streamed mesh (in the order given), which pages are resident.
    pub fn residency(&self) -> Vec<Vec<bool>> {
        self.meshes
            .iter()
            .map(|m| (0..m.state.len() as u32).map(|p| m.resident(p)).collect())
            .collect()
    }

    /// The problems found since the last call (each failed page once).
    pub fn take_errors(&mut self) -> Vec<String> {
        std::mem::take(&mut self.errors)
    }

    /// The resident pages against the cut of the newest feedback (the pages its frames drew a
    /// cluster of, as [`StreamStats::used_bytes`] counts them), after the last
    /// [`Streamer::update`].
    pub fn cut_residency(&self) -> CutResidency {
        let mut out = CutResidency {
            resident_bytes: self.residency_stats().1,
            ..Default::default()
        };
        for m in self.cut_residency_by_mesh() {
            out.resident_page_bytes += m.resident_page_bytes;
            out.used_bytes += m.used_bytes;
            out.needed_bytes += m.needed_bytes;
            out.fixed_bytes += m.fixed_bytes;
            out.fixed_unused_bytes += m.fixed_unused_bytes;
            out.other_bytes += m.other_bytes;
        }
        out
    }

    /// [`Streamer::cut_residency`] per streamed mesh (in the order given); each mesh's
    /// `resident_bytes` is its resident pages' own bytes (slots are shared, not per mesh).
    pub fn cut_residency_by_mesh(&self) -> Vec<CutResidency> {
        self.meshes
            .iter()
            .map(|m| {
                let mut out = CutResidency::default();
                let mut needed = m.used.clone();
                crate::builder::page::close_residency(&m.head, &m.needs, &mut needed);
                for (p, page) in m.head.pages.iter().enumerate() {
                    let bytes = page.bytes as u64;
                    let resident = m.resident(p as u32);
                    let fixed = m.state[p] == PageState::Fixed;
                    if resident {
                        out.resident_page_bytes += bytes;
                    }
                    if m.used[p] {
                        out.used_bytes += bytes;
                    }
                    if needed[p] {
                        out.needed_bytes += bytes;
                    }
                    if fixed {
                        out.fixed_bytes += bytes;
                        if !m.used[p] {
                            out.fixed_unused_bytes += bytes;
                        }
                    }
                    if resident && !needed[p] {
                        out.other_bytes += bytes;
                    }
                }
                out.resident_bytes = out.resident_page_bytes;
                out
            })
            .collect()
    }

    /// Resident pages and bytes now.
    fn residency_stats(&self) -> (u64, u64) {
        let fixed: u64 = self
            .meshes
            .iter()
            .map(|m| m.head.resident_pages as u64)
            .sum();
        let slots = (self.slot_count as usize - self.free.len()) as u64;
        (fixed + slots, self.fixed_bytes + slots * self.slot_bytes)
    }

    /// One streaming step between frames (see the module's documentation). It never waits for
    /// the GPU: the pages read by the last step's worker thread are staged for the next frame
    /// (waiting for that thread only if the reads took longer than a frame), the newest page
    /// feedback that has landed is read, requests are served by evicting and reserving slots,
    /// and the reads of the new loads start on a worker thread while the next frame draws.
    pub fn update(&mut self, scene: &mut GpuScene) -> SceneResult<StreamStats> {
        self.frame += 1;
        let frame = self.frame;
        let mut stats = StreamStats::default();
        let mut changes: Vec<PageChange> = Vec::new();
        self.finish_reads(frame, &mut stats, &mut changes);
        // The newest feedback copy that landed (none new: nothing asked, nothing marked used).
        let (wish, used) = scene.take_page_feedback()?.unwrap_or_default();
        // (wish, mesh, page) of absent pages asked for, largest wish first.
        let mut asks: Vec<(f32, usize, u32)> = Vec::new();
        for (mi, m) in self.meshes.iter_mut().enumerate() {
            let first = scene.page_range(m.handle)?.0 as usize;
            for p in 0..m.state.len() {
                m.used[p] = used.get(first + p).is_some_and(|&u| u != 0);
                if m.used[p] {
                    m.last_used[p] = frame;
                    stats.used_pages += 1;
                    stats.used_bytes += m.head.pages[p].bytes as u64;
                }
                let w = wish.get(first + p).map_or(0.0, |&w| f32::from_bits(w));
                if w > 0.0 && m.state[p] == PageState::Absent {
                    asks.push((w, mi, p as u32));
                }
            }
        }
        stats.requests = asks.len() as u64;
        asks.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut budget = self.opts.upload_bytes_per_frame;
        let mut loads: Vec<(usize, u32, u32)> = Vec::new(); // (mesh, page, slot)
        for (_, mi, page) in asks {
            if self.meshes[mi].state[page as usize] != PageState::Absent {
                continue; // came with an earlier set
            }
            let Some(set) = self.meshes[mi].load_set(page) else {
                continue;
            };
            let bytes: u64 = set
                .iter()
                .map(|&p| self.meshes[mi].head.pages[p as usize].bytes as u64)
                .sum();
            // A set that does not fit what is left waits for a later update (a smaller one
            // may still fit); one larger than a whole update's uploads goes alone, first.
            let alone = loads.is_empty() && bytes > self.opts.upload_bytes_per_frame;
            if bytes > budget && !alone {
                continue;
            }
            // Free slots: evict least-recently-used pages nobody needs (not used this frame).
            while self.free.len() < set.len() {
                let victim = self
                    .meshes
                    .iter()
                    .enumerate()
                    .flat_map(|(vi, v)| {
                        let coming: &[u32] = if vi == mi { &set } else { &[] };
                        (0..v.state.len() as u32)
                            .filter(move |&p| {
                                v.last_used[p as usize] < frame && v.evictable(p, coming)
                            })
                            .map(move |p| (v.last_used[p as usize], vi, p))
                    })
                    .filter(|&(_, vi, p)| !(vi == mi && set.contains(&p)))
                    .min();
                let Some((_, vi, p)) = victim else { break };
                let v = &mut self.meshes[vi];
                if let PageState::Slot(s) = v.state[p as usize] {
                    self.free.push(s);
                }
                v.state[p as usize] = PageState::Absent;
                changes.push(PageChange {
                    mesh: v.handle,
                    page: p,
                    load: None,
                });
                stats.evictions += 1;
            }
            if self.free.len() < set.len() {
                break;
            }
            budget = budget.saturating_sub(bytes);
            stats.load_sets += 1;
            let m = &mut self.meshes[mi];
            for &p in &set {
                let s = self.free.pop().expect("counted");
                m.state[p as usize] = PageState::Loading(s);
                m.last_used[p as usize] = frame;
                loads.push((mi, p, s));
            }
        }
        self.start_reads(loads, &mut stats);
        scene.update_pages(&changes)?;
        let (pages, bytes) = self.residency_stats();
        stats.resident_pages = pages;
        stats.resident_bytes = bytes;
        Ok(stats)
    }

    /// Starts reading `loads` on a worker thread (read right here if no thread can be made).
    fn start_reads(&mut self, loads: Vec<(usize, u32, u32)>, stats: &mut StreamStats) {
        if loads.is_empty() {
            return;
        }
        stats.reading = loads.len() as u64;
        let jobs: Vec<(std::sync::Arc<dyn PageSource>, u32)> = loads
            .iter()
            .map(|&(mi, p, _)| (self.meshes[mi].source.clone(), p))
            .collect();
        let read = move || -> Vec<Result<Vec<u8>, String>> {
            jobs.par_iter().map(|(src, p)| src.read_page(*p)).collect()
        };
        let thread = std::thread::Builder::new()
            .name("vgeo page reads".into())
            .spawn(read.clone());
        let thread = match thread {
            Ok(t) => ReadsThread::Running(t),
            Err(_) => ReadsThread::Done(read()),
        };
        self.reads = Some(Reads { loads, thread });
    }

    /// Stages the pages the last step's reads brought (waiting for its worker thread if it is
    /// still reading). A page that failed is reported once and never asked for again; the other
    /// pages of its mesh from those reads are dropped too (their residency would not be closed
    /// without it).
    fn finish_reads(&mut self, frame: u64, stats: &mut StreamStats, changes: &mut Vec<PageChange>) {
        let Some(reads) = self.reads.take() else {
            return;
        };
        let read = match reads.thread {
            ReadsThread::Done(r) => r,
            ReadsThread::Running(t) => t.join().unwrap_or_else(|_| {
                (0..reads.loads.len())
                    .map(|_| Err("the page-reading thread panicked".to_string()))
                    .collect()
            }),
        };
        let mut failed_meshes: Vec<usize> = Vec::new();
        for (&(mi, p, s), r) in reads.loads.iter().zip(&read) {
            if let Err(e) = r {
                let m = &mut self.meshes[mi];
                self.errors.push(format!(
                    "{}: page {p} cannot be read ({e}); the mesh stays coarser there",
                    m.head.name
                ));
                m.state[p as usize] = PageState::Failed;
                self.free.push(s);
                stats.failed += 1;
                failed_meshes.push(mi);
            }
        }
        for ((mi, p, s), r) in reads.loads.into_iter().zip(read) {
            let Ok(bytes) = r else { continue };
            let m = &mut self.meshes[mi];
            if failed_meshes.contains(&mi) {
                // Keep the residency closed: a mesh with a failed page loads nothing of these.
                m.state[p as usize] = PageState::Absent;
                self.free.push(s);
                continue;
            }
            m.state[p as usize] = PageState::Slot(s);
            m.last_used[p as usize] = frame;
            stats.uploads += 1;
            stats.upload_bytes += bytes.len() as u64;
            let word = self.slot_word + s * (self.slot_bytes / 4) as u32;
            changes.push(PageChange {
                mesh: m.handle,
                page: p,
                load: Some((word, bytes)),
            });
        }
    }
}

fn mib(bytes: u64) -> String {
    format!("{:.2} MiB", bytes as f64 / (1u64 << 20) as f64)
}

/// A scene whose meshes stream (`vgeo render --geometry-budget`): `.vgeo` files are opened
/// head-only ([`crate::format::VgeoFile`]: metadata, clusters, groups, BVH and page table; no
/// page is read until the cull asks for it) and serve their pages from the file; every other mesh
/// goes through the scene's one loader ([`crate::scene::load::MeshCache`]), is built, and serves
/// its pages from memory. Scene entries naming the same mesh share one streamed mesh.
pub struct StreamedScene {
    /// The scene as its file describes it (a single mesh or `.vgeo` file: one instance).
    pub scene: crate::scene::Scene,
    /// Every instance; `mesh` indexes [`StreamedScene::meshes`].
    pub placements: Vec<crate::render::Placement>,
    /// The scene's light.
    pub light: crate::render::Light,
    /// Import warnings (each names its file).
    pub warnings: Vec<String>,
    /// The distinct meshes: the head (or built mesh) and where its pages come from.
    pub meshes: Vec<(BuiltMesh, Box<dyn PageSource>)>,
    /// Per distinct mesh, the bounds of its full detail (as [`crate::scene::load::LoadedScene`]
    /// frames it: a source mesh's own bounds, a `.vgeo` file's level 0, known from its head).
    bounds: Vec<([f32; 3], [f32; 3])>,
    /// Per scene mesh entry, its distinct mesh.
    entry_mesh: Vec<usize>,
}

impl StreamedScene {
    /// Loads a scene file (`.toml`), a mesh file or a `.vgeo` file; `progress` gets a line per
    /// mesh built.
    pub fn load(path: &std::path::Path, progress: &(dyn Fn(&str) + Sync)) -> anyhow::Result<Self> {
        use crate::scene::load::{MeshCache, MeshKey};
        let is_scene = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        let scene = if is_scene {
            crate::scene::Scene::load(path)?
        } else {
            crate::scene::Scene::single_mesh(path)
        };
        let is_vgeo = |p: &std::path::Path| {
            p.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("vgeo"))
        };
        // Distinct meshes in order of first use; scene entry -> distinct mesh.
        let mut keys: Vec<MeshKey> = Vec::new();
        let entry_mesh: Vec<usize> = scene
            .meshes
            .iter()
            .map(|m| {
                let k = MeshKey::of(m);
                keys.iter().position(|x| *x == k).unwrap_or_else(|| {
                    keys.push(k);
                    keys.len() - 1
                })
            })
            .collect();
        for k in keys.iter().filter(|k| is_vgeo(&k.path)) {
            if let Some(n) = k.materials {
                anyhow::bail!(
                    "{}: materials = {n} needs the source mesh (a .vgeo file keeps its built materials)",
                    k.path.display()
                );
            }
        }
        // The other meshes through the one loader, built.
        let mut built_scene = scene.clone();
        built_scene.meshes.retain(|m| !is_vgeo(&m.path));
        built_scene.instances.clear();
        let loaded =
            crate::scene::load::LoadedScene::from_scene(&mut MeshCache::default(), built_scene)?;
        let built = loaded.built_meshes(progress)?;
        let mut meshes: Vec<(BuiltMesh, Box<dyn PageSource>)> = Vec::with_capacity(keys.len());
        let mut bounds = Vec::with_capacity(keys.len());
        for k in &keys {
            if is_vgeo(&k.path) {
                let file = crate::format::VgeoFile::open(&k.path)
                    .map_err(|e| anyhow::anyhow!("{}: {e}", k.path.display()))?;
                bounds.push(level0_bounds(file.head()));
                meshes.push((file.head().clone(), Box::new(file)));
            } else {
                let i = loaded
                    .prepared
                    .iter()
                    .position(|p| p.key == *k)
                    .ok_or_else(|| anyhow::anyhow!("{}: not prepared", k.path.display()))?;
                bounds.push(
                    loaded.prepared[i]
                        .mesh
                        .bounds()
                        .unwrap_or(([0.0; 3], [0.0; 3])),
                );
                meshes.push((built[i].clone(), Box::new(built[i].clone())));
            }
        }
        let placements = scene
            .instances
            .iter()
            .map(|i| crate::render::Placement {
                mesh: entry_mesh[i.mesh as usize] as u32,
                transform: i.transform,
                color: i.color,
            })
            .collect();
        Ok(Self {
            light: crate::render::Light {
                direction: scene.light_dir,
            },
            warnings: loaded.warnings.clone(),
            scene,
            placements,
            meshes,
            bounds,
            entry_mesh,
        })
    }

    /// Per scene mesh entry (`scene.meshes[i]`), the bounds of its mesh's full detail.
    pub fn mesh_bounds(&self) -> Vec<([f32; 3], [f32; 3])> {
        self.entry_mesh.iter().map(|&i| self.bounds[i]).collect()
    }

    /// The scene's camera for an image of `width` x `height`.
    pub fn camera(&self, width: u32, height: u32) -> crate::camera::Camera {
        self.scene
            .camera(&self.mesh_bounds(), width as f32 / height.max(1) as f32)
    }

    /// Full-detail triangles of the scene (instanced): from each mesh's build statistics.
    pub fn scene_triangles(&self) -> u64 {
        self.placements
            .iter()
            .map(|p| {
                self.meshes
                    .get(p.mesh as usize)
                    .map_or(0, |(m, _)| m.stats.level0_triangles as u64)
            })
            .sum()
    }
}

/// The union of a built mesh's level-0 clusters' bounds (zeros for none).
fn level0_bounds(m: &BuiltMesh) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for c in m.clusters.iter().filter(|c| c.level == 0) {
        for k in 0..3 {
            lo[k] = lo[k].min(c.bounds_min[k]);
            hi[k] = hi[k].max(c.bounds_max[k]);
        }
    }
    if lo[0] > hi[0] {
        return ([0.0; 3], [0.0; 3]);
    }
    (lo, hi)
}
