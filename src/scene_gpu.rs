//! The vgeo path's scene on the GPU, a scene that changes: meshes (their cluster DAGs in shared,
//! growable buffers) and instances come and go at run time behind stable generational handles
//! ([`MeshHandle`], [`InstanceHandle`]); instance transforms change every frame in O(changed)
//! through a staging ring copied into the dense instance array at the start of the frame.
//! See docs/architecture.md, "A scene that changes".

mod arena;
mod page_io;

use std::borrow::Borrow;

use glam::{DMat4, DVec3, Mat3};

use crate::builder::BuiltMesh;
use crate::builder::cut::TinyCuts;
use crate::builder::page::Page;
use crate::gpu::{Buffer, Cmd, Context, Desc, GpuError, GpuResult, MemoryKind, vk};
use crate::material::{MeshMaterialSource, SceneMaterials};
use crate::render::Placement;
use crate::shared::{
    ClusterLocGpu, InstanceVgeo, MESH_CLOSED_SOLID, MESH_STREAM_MATERIALS, MESH_STREAM_PARTIAL,
    MESH_STREAM_UVS, MeshGpu, PAGE_NOT_RESIDENT, PageGpu,
};

pub use arena::RangeAllocator;
use arena::{Arena, grow_buffer};

/// Splits an f64 into a high f32 and the f32 of the remainder (`hi + lo` is exact to ~1e-14 relative).
pub fn split_f64(v: f64) -> (f32, f32) {
    let hi = v as f32;
    (hi, (v - hi as f64) as f32)
}

/// The GPU form of one placement.
pub fn instance_gpu(p: &Placement) -> InstanceVgeo {
    instance_of(p.mesh, &p.transform, p.color)
}

/// The GPU form of an instance of mesh slot `mesh` (its `visible_base` is 0).
fn instance_of(mesh: u32, transform: &DMat4, color: [f32; 3]) -> InstanceVgeo {
    let m: DMat4 = *transform;
    let lin = Mat3::from_cols(
        m.x_axis.truncate().as_vec3(),
        m.y_axis.truncate().as_vec3(),
        m.z_axis.truncate().as_vec3(),
    );
    let t: DVec3 = m.w_axis.truncate();
    let (hx, lx) = split_f64(t.x);
    let (hy, ly) = split_f64(t.y);
    let (hz, lz) = split_f64(t.z);
    let max_scale = crate::render::max_axis_scale(&m);
    InstanceVgeo {
        linear: [
            lin.x_axis.extend(0.0).into(),
            lin.y_axis.extend(0.0).into(),
            lin.z_axis.extend(0.0).into(),
        ],
        translation_hi: [hx, hy, hz],
        mesh,
        translation_lo: [lx, ly, lz],
        max_scale,
        color,
        visible_base: 0,
    }
}

/// Bytes of one mesh record on the GPU.
const MESH_GPU_BYTES: u64 = std::mem::size_of::<MeshGpu>() as u64;

/// Bounding sphere (center, radius) of a built mesh's level-0 bounds.
pub(crate) fn mesh_sphere(m: &BuiltMesh) -> ([f32; 3], f32) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for c in &m.clusters {
        for k in 0..3 {
            lo[k] = lo[k].min(c.bounds_min[k]);
            hi[k] = hi[k].max(c.bounds_max[k]);
        }
    }
    if !lo[0].is_finite() {
        return ([0.0; 3], 0.0);
    }
    let c = [
        (lo[0] + hi[0]) * 0.5,
        (lo[1] + hi[1]) * 0.5,
        (lo[2] + hi[2]) * 0.5,
    ];
    let r =
        ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt() * 0.5;
    (c, r * 1.0001)
}

/// Slots of the staging ring: one per frame that may be in flight (at least this many; more
/// when a host's views have more, [`GpuScene::set_frames_in_flight`]).
pub const FRAMES_IN_FLIGHT: usize = 2;

/// A mesh of a [`GpuScene`]: stable until removed (then every use is a [`SceneError::StaleMesh`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MeshHandle {
    index: u32,
    generation: u32,
}

impl MeshHandle {
    /// The mesh's slot: `InstanceVgeo::mesh` and the index into the mesh table.
    pub fn index(self) -> u32 {
        self.index
    }
}

/// An instance of a [`GpuScene`]: stable until removed (then every use is a
/// [`SceneError::StaleInstance`]). Its place in the dense instance array may change
/// ([`GpuScene::instance_slot`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct InstanceHandle {
    index: u32,
    generation: u32,
}

/// One instance to add: a mesh, object -> world in f64, an albedo tint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceDesc {
    /// The mesh it shows (a live handle of the same scene).
    pub mesh: MeshHandle,
    /// Object -> world, in f64 (made camera-relative before it becomes f32).
    pub transform: DMat4,
    /// Albedo tint.
    pub color: [f32; 3],
}

impl InstanceDesc {
    /// The instances of `placements`, whose meshes were added as `handles` (in the placements'
    /// mesh order). The caller has checked each placement's mesh index.
    pub fn placed(placements: &[Placement], handles: &[MeshHandle]) -> Vec<InstanceDesc> {
        placements
            .iter()
            .map(|p| InstanceDesc {
                mesh: handles[p.mesh as usize],
                transform: p.transform,
                color: p.color,
            })
            .collect()
    }
}

/// A page to load into the geometry pool, or to evict ([`GpuScene::update_pages`]).
#[derive(Clone, Debug)]
pub struct PageChange {
    pub mesh: MeshHandle,
    pub page: u32,
    /// The pool word (a reserved slot) and the page's bytes; `None`: evict.
    pub load: Option<(u32, Vec<u8>)>,
}

/// Errors of scene changes (never a panic).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("stale mesh handle {0:?}: the mesh was removed (or is not of this scene)")]
    /// A mesh handle whose mesh was removed (or of another scene).
    StaleMesh(MeshHandle),
    #[error("stale instance handle {0:?}: the instance was removed (or is not of this scene)")]
    /// An instance handle whose instance was removed (or of another scene).
    StaleInstance(InstanceHandle),
    #[error("mesh {mesh:?} is still used by {instances} instance(s): remove them first")]
    /// A mesh that instances still show cannot be removed.
    MeshInUse {
        /// The mesh.
        mesh: MeshHandle,
        /// Instances still showing it.
        instances: u32,
    },
    #[error("scene limit: {0}")]
    /// A size limit of the GPU layout (instances, clusters, buffer bytes).
    Limit(String),
    #[error("invalid page residency: {0}")]
    /// A page residency that does not fit the mesh (length, always-resident pages).
    Residency(String),
    #[error(transparent)]
    /// A GPU error while uploading or growing a buffer.
    Gpu(#[from] GpuError),
}

impl From<SceneError> for GpuError {
    fn from(e: SceneError) -> Self {
        match e {
            SceneError::Gpu(g) => g,
            other => GpuError::Other(other.to_string()),
        }
    }
}

/// Result of scene changes.
pub type SceneResult<T> = Result<T, SceneError>;

/// Bytes of one GPU buffer of the scene: in use, and allocated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BufferMemory {
    /// The buffer's debug name.
    pub name: &'static str,
    /// Bytes holding live data.
    pub used_bytes: u64,
    /// Bytes allocated (it grows by doubling).
    pub capacity_bytes: u64,
}

/// What the scene holds on the GPU, per buffer ([`GpuScene::memory`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SceneMemory {
    /// One entry per GPU buffer of the scene.
    pub buffers: Vec<BufferMemory>,
}

impl SceneMemory {
    /// Bytes holding live data, all buffers.
    pub fn used_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.used_bytes).sum()
    }
    /// Bytes allocated, all buffers.
    pub fn capacity_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.capacity_bytes).sum()
    }
}

impl std::fmt::Display for SceneMemory {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for b in &self.buffers {
            writeln!(
                f,
                "{:<20} {:>12} B used of {:>12} B",
                b.name, b.used_bytes, b.capacity_bytes
            )?;
        }
        write!(
            f,
            "{:<20} {:>12} B used of {:>12} B",
            "total",
            self.used_bytes(),
            self.capacity_bytes()
        )
    }
}

/// The geometry arenas, in the order of [`GpuScene::arena_buffer`].
const ARENAS: usize = 6;
const ARENA_NAMES: [&str; ARENAS] = [
    "scene cluster locators",
    "scene groups",
    "scene bvh",
    "scene pages",
    "scene geometry pool",
    "scene tiny cuts",
];
/// The arena of the cluster locators ([`ClusterLocGpu`]): a mesh's range starts at its
/// `MeshGpu::cluster_offset`.
const CLUSTERS: usize = 0;
/// The arena of [`PageGpu`] entries and the geometry pool's (u32 words).
const PAGES: usize = 3;
const POOL: usize = 4;
/// The arena of the meshes' small-instance cut tables (u32 words, `MeshGpu::tiny_offset`).
const TINY: usize = 5;

/// A live mesh: its ranges in the arenas and what instances need of it.
struct LiveMesh {
    /// (start, length) in elements, per arena.
    ranges: [(u64, u64); ARENAS],
    /// The mesh's pages.
    page_records: Vec<Page>,
    /// Per page, the pool word where its bytes are (whether or not the cull may use them), or
    /// [`PAGE_NOT_RESIDENT`].
    loaded: Vec<u32>,
    /// Per page, whether [`GpuScene::set_page_residency`] marked it absent though its bytes are
    /// loaded (until it is resident again, or a page change names it).
    hidden: Vec<bool>,
    resident_pages: u32,
    /// Its clusters as (page, word in the page, index in the mesh), sorted: where a visible-list
    /// entry's pool word points ([`GpuScene::clusters_at_words`]).
    by_page: Vec<(u32, u32, u32)>,
    instances: u32,
    /// Items one instance of the mesh can push to `cluster_cull`'s queue at most: its BVH nodes
    /// and its groups' cluster ranges (`CULL_RANGE_CLUSTERS` each).
    queue_items: u64,
    material: MeshMaterialSource,
}

impl LiveMesh {
    /// Page `p`'s entry where its bytes are loaded (absent when they are not, or when hidden).
    fn entry(&self, p: usize) -> PageGpu {
        if self.loaded[p] == PAGE_NOT_RESIDENT || self.hidden[p] {
            return PageGpu::absent();
        }
        PageGpu {
            word: self.loaded[p],
        }
    }

    /// Whether some page's entry is absent ([`MESH_STREAM_PARTIAL`]).
    fn partial(&self) -> bool {
        self.loaded.contains(&PAGE_NOT_RESIDENT) || self.hidden.contains(&true)
    }
}

struct MeshSlot {
    generation: u32,
    live: Option<LiveMesh>,
}

/// `InstanceSlot::dense` of a free handle slot.
const NO_SLOT: u32 = u32::MAX;

struct InstanceSlot {
    generation: u32,
    /// Index in the dense instance array ([`NO_SLOT`]: removed).
    dense: u32,
}

/// All meshes' DAG data and the instances, in GPU buffers that grow as the scene does.
///
/// Meshes live in growable arenas (one per kind of data, best-fit ranges, freed on removal, never
/// compacted); instances in a dense array (`instance_count` entries, swap-remove) with a CPU
/// mirror, a handle table and a dirty list: a change writes the mirror and marks the slot, and
/// [`GpuScene::prepare_updates`] + [`GpuScene::record_updates`] copy the dirty slots from a staging
/// ring into the instance buffer at the start of the next frame (O(changed), no allocation once
/// the ring and lists have grown to the steady state). Adding or removing meshes and growing a
/// buffer are one-shot GPU submissions (waited for).
pub struct GpuScene {
    ctx: Context,
    /// [`MeshGpu`] per mesh slot.
    pub meshes: Buffer,
    /// [`InstanceVgeo`], dense: `instance_count` entries in use.
    pub instances: Buffer,
    /// Every live mesh's cluster locators ([`ClusterLocGpu`]: page and word; the clusters
    /// themselves are in their pages, see docs/architecture.md).
    pub clusters: Buffer,
    /// Every live mesh's DAG groups.
    pub groups: Buffer,
    /// Every live mesh's cluster BVH nodes.
    pub bvh: Buffer,
    /// [`PageGpu`] per page of every live mesh (`MeshGpu::page_offset`): where the page lies in
    /// the pool.
    pub pages: Buffer,
    /// Every live mesh's table of small-instance cuts (u32 words, `MeshGpu::tiny_offset`;
    /// [`crate::builder::cut::TinyCuts::words`]), read by `instance_cull`.
    pub tiny_cuts: Buffer,
    /// The geometry pool (u32 words): every page's bytes (`src/builder/page.rs`: vertices,
    /// references and packed triangles of its clusters).
    pub pool: Buffer,
    /// Per entry of `pages`, written by the cull for meshes with absent pages
    /// ([`crate::shared::MESH_STREAM_PARTIAL`]): the largest wish to refine into the page (f32
    /// bits: projected error over the threshold), and 1 when a drawn cluster used it.
    pub page_requests: Buffer,
    pub page_usage: Buffer,
    /// [`MeshGpu`] per mesh slot (all zeros for a free slot); its partial flags change only
    /// through [`GpuScene::set_mesh_partial`], which keeps `partial_count`.
    pub(crate) mesh_table: Vec<MeshGpu>,
    /// Entries of `mesh_table` with [`MESH_STREAM_PARTIAL`].
    partial_count: u32,
    /// Instances in the scene (the dense instance array's length).
    pub instance_count: u32,
    /// Clusters of the live meshes.
    pub total_clusters: u32,
    /// One past the last visible-list slot owned by an instance (each owns a range as long as its
    /// mesh's cluster count): the visible-list length that direct slots need (see
    /// [`crate::shared::VIEW_FLAG_DIRECT_VISIBLE`]).
    pub instance_clusters: u64,
    arenas: [Arena; ARENAS],
    mesh_slots: Vec<MeshSlot>,
    free_meshes: Vec<u32>,
    /// Incremented by every mesh added or removed (the renderer rebuilds materials on a change).
    mesh_epoch: u64,
    /// Instances: CPU mirror of the dense array, its handles, the handle table.
    mirror: Vec<InstanceVgeo>,
    dense_handle: Vec<u32>,
    instance_slots: Vec<InstanceSlot>,
    free_instances: Vec<u32>,
    /// Entries of the instance buffer.
    instance_capacity: u32,
    /// Sum over instances of their mesh's queue items (BVH nodes and cluster ranges: what the
    /// cull queue can need).
    instance_nodes: u64,
    /// Visible-list ranges of the instances; instances beyond 32-bit slots own none.
    visible: RangeAllocator,
    unranged_clusters: u64,
    /// Dense slots changed since the last flush (each once: `dirty_flag`).
    dirty: Vec<u32>,
    dirty_flag: Vec<bool>,
    /// The staging ring (host-visible), one buffer per frame in flight, grown on demand.
    ring: Vec<Buffer>,
    ring_next: usize,
    /// Frames that may be in flight: staging-ring slots (page-feedback slots: one more).
    ring_slots: usize,
    /// The copies of the prepared update (ring slot, regions), until it is submitted.
    pending: Option<usize>,
    regions: Vec<vk::BufferCopy>,
    /// Page loads and evictions for the next frame ([`GpuScene::update_pages`]), and their
    /// prepared copies into the pool, the page table and the mesh table (`page_io`).
    staged: page_io::StagedPages,
    page_regions: [Vec<vk::BufferCopy>; 3],
    /// Host-visible copies of the page feedback, one per frame in flight and one more.
    feedback: page_io::FeedbackRing,
    /// Buffers replaced by growth, kept until the GPU is done with them.
    retired: Vec<Buffer>,
}

impl GpuScene {
    /// The geometry pool is one storage buffer: it must fit the device's `maxStorageBufferRange`.
    fn check_pool(&self) -> SceneResult<()> {
        let bytes = 4 * self.arenas[POOL].size();
        let limit = self.ctx.caps().max_storage_buffer_range as u64;
        if bytes > limit {
            return Err(SceneError::Limit(format!(
                "the geometry pool needs {:.1} MiB, more than this device binds in one buffer \
                 ({:.1} MiB, maxStorageBufferRange): stream the meshes under a geometry budget \
                 of at most {:.0} MiB (`--geometry-budget`, the always-resident pages included; \
                 `--geometry-budget auto` takes no more)",
                bytes as f64 / (1u64 << 20) as f64,
                limit as f64 / (1u64 << 20) as f64,
                (limit >> 20) as f64
            )));
        }
        Ok(())
    }
}

fn oversize(what: &str) -> SceneError {
    SceneError::Limit(format!("{what} exceed 32-bit offsets"))
}

impl GpuScene {
    /// Uploads `built` meshes and `placements` (whose `mesh` indexes `built`): mesh `i` gets
    /// slot `i`, placement `j` dense slot `j`, buffers exactly as large as needed.
    pub fn new<B: Borrow<BuiltMesh>>(
        ctx: &Context,
        built: &[B],
        placements: &[Placement],
    ) -> GpuResult<Self> {
        if let Some(p) = placements.iter().find(|p| p.mesh as usize >= built.len()) {
            return Err(GpuError::Other(format!(
                "placement refers to mesh {} of {}",
                p.mesh,
                built.len()
            )));
        }
        let mut s = Self::empty(ctx)?;
        let handles = s.add_meshes(built)?;
        s.add_instances(&InstanceDesc::placed(placements, &handles))?;
        s.release_retired();
        Ok(s)
    }

    /// A scene with no meshes and no instances (every buffer at its 4-byte minimum).
    pub fn empty(ctx: &Context) -> GpuResult<Self> {
        let buf = |name: &str| Buffer::new(ctx, name, 0, arena::usage(), MemoryKind::Gpu);
        let elem = [
            size_of::<ClusterLocGpu>(),
            size_of::<crate::shared::GroupGpu>(),
            size_of::<crate::builder::BvhNode>(),
            size_of::<PageGpu>(),
            4,
            4,
        ];
        Ok(Self {
            ctx: ctx.clone(),
            meshes: buf("scene meshes")?,
            instances: buf("scene instances")?,
            clusters: buf(ARENA_NAMES[0])?,
            groups: buf(ARENA_NAMES[1])?,
            bvh: buf(ARENA_NAMES[2])?,
            pages: buf(ARENA_NAMES[PAGES])?,
            pool: buf(ARENA_NAMES[POOL])?,
            tiny_cuts: buf(ARENA_NAMES[TINY])?,
            page_requests: buf("scene page requests")?,
            page_usage: buf("scene page usage")?,
            mesh_table: Vec::new(),
            partial_count: 0,
            instance_count: 0,
            total_clusters: 0,
            instance_clusters: 0,
            arenas: std::array::from_fn(|k| Arena::new(elem[k] as u64, 1)),
            mesh_slots: Vec::new(),
            free_meshes: Vec::new(),
            mesh_epoch: 0,
            mirror: Vec::new(),
            dense_handle: Vec::new(),
            instance_slots: Vec::new(),
            free_instances: Vec::new(),
            instance_capacity: 0,
            instance_nodes: 0,
            visible: RangeAllocator::new(0),
            unranged_clusters: 0,
            dirty: Vec::new(),
            dirty_flag: Vec::new(),
            ring: Vec::new(),
            ring_next: 0,
            ring_slots: FRAMES_IN_FLIGHT,
            pending: None,
            regions: Vec::new(),
            staged: Default::default(),
            page_regions: Default::default(),
            feedback: Default::default(),
            retired: Vec::new(),
        })
    }

    /// The geometry arenas' buffers, in arena order (see `ARENA_NAMES`).
    fn arena_buffers(&self) -> [&Buffer; ARENAS] {
        [
            &self.clusters,
            &self.groups,
            &self.bvh,
            &self.pages,
            &self.pool,
            &self.tiny_cuts,
        ]
    }

    fn arena_buffer(&mut self, k: usize) -> (&mut Arena, &mut Buffer) {
        let buf = match k {
            0 => &mut self.clusters,
            1 => &mut self.groups,
            2 => &mut self.bvh,
            PAGES => &mut self.pages,
            POOL => &mut self.pool,
            _ => &mut self.tiny_cuts,
        };
        (&mut self.arenas[k], buf)
    }

    fn retire(&mut self, old: Option<Buffer>) {
        self.retired.extend(old);
    }

    /// Whether buffers replaced by a growth wait to be freed.
    pub fn has_retired(&self) -> bool {
        !self.retired.is_empty()
    }

    /// Drops the buffers that growth replaced (call when the GPU has finished every frame
    /// recorded before the growth).
    pub fn release_retired(&mut self) {
        self.retired.clear();
    }

    /// Element counts of `m` per arena (`tiny`: its small-instance cut table's words).
    fn lengths(m: &BuiltMesh, present: Option<&[Vec<u8>]>, tiny: &[u32]) -> [u64; ARENAS] {
        [
            m.clusters.len() as u64,
            m.groups.len() as u64,
            m.bvh.len() as u64,
            m.pages.len() as u64,
            match present {
                None => m.pages.iter().map(|p| (p.bytes / 4) as u64).sum(),
                Some(b) => b.iter().map(|b| (b.len() / 4) as u64).sum(),
            },
            tiny.len() as u64,
        ]
    }

    /// Adds one mesh (built in memory or loaded from a `.vgeo` file); its handle.
    pub fn add_mesh(&mut self, built: &BuiltMesh) -> SceneResult<MeshHandle> {
        let h = self.add_meshes(std::slice::from_ref(&built))?;
        Ok(h[0])
    }

    /// Adds meshes in one upload (each arena grows at most once); their handles, in order.
    pub fn add_meshes<B: Borrow<BuiltMesh>>(
        &mut self,
        built: &[B],
    ) -> SceneResult<Vec<MeshHandle>> {
        let items: Vec<(&BuiltMesh, Option<&[Vec<u8>]>)> =
            built.iter().map(|m| (m.borrow(), None)).collect();
        self.add_meshes_paged(&items)
    }

    /// Adds a mesh of which only the first pages are in memory: `present[p]` is page `p`'s bytes
    /// (`builder::page::page_bytes`, or a `.vgeo` file's page) for the first `present.len()`
    /// pages, at least the always-resident ones; the other pages are absent (the mesh is drawn
    /// coarser where it would need them, and the cull asks for them: a streamed mesh, see
    /// [`crate::streaming`]). `head` needs no vertex data (a `.vgeo` file's head).
    pub fn add_partial_mesh(
        &mut self,
        head: &BuiltMesh,
        present: &[Vec<u8>],
    ) -> SceneResult<MeshHandle> {
        if present.len() < head.resident_pages as usize || present.len() > head.pages.len() {
            return Err(SceneError::Residency(format!(
                "{} pages given, {} always resident of {}",
                present.len(),
                head.resident_pages,
                head.pages.len()
            )));
        }
        for (i, (b, p)) in present.iter().zip(&head.pages).enumerate() {
            if b.len() != p.bytes as usize {
                return Err(SceneError::Residency(format!(
                    "page {i}: {} bytes, its page table says {}",
                    b.len(),
                    p.bytes
                )));
            }
        }
        Ok(self.add_meshes_paged(&[(head, Some(present))])?[0])
    }

    fn add_meshes_paged(
        &mut self,
        built: &[(&BuiltMesh, Option<&[Vec<u8>]>)],
    ) -> SceneResult<Vec<MeshHandle>> {
        if built.is_empty() {
            return Ok(Vec::new());
        }
        // The small-instance cut tables (a few KiB per mesh).
        let tiny: Vec<Vec<u32>> = built
            .iter()
            .map(|&(m, _)| TinyCuts::of(m).words())
            .collect();
        // Room for all of them after the last allocated element of each arena.
        let mut totals = [0u64; ARENAS];
        for (&(m, present), tiny) in built.iter().zip(&tiny) {
            for (k, l) in Self::lengths(m, present, tiny).into_iter().enumerate() {
                totals[k] += self.arenas[k].rounded(l);
            }
        }
        for (k, &total) in totals.iter().enumerate() {
            let ctx = self.ctx.clone();
            let (arena, buf) = self.arena_buffer(k);
            let old = arena.reserve(&ctx, buf, total)?;
            self.retire(old);
        }
        // The streaming feedback follows the page table's size (its content is per frame).
        let feedback = 4 * (self.pages.size() / size_of::<PageGpu>() as u64).max(1);
        let grew_feedback = self.page_requests.size() < feedback;
        for k in 0..2 {
            let buf = if k == 0 {
                &mut self.page_requests
            } else {
                &mut self.page_usage
            };
            if buf.size() < feedback {
                let old = grow_buffer(&self.ctx, buf, feedback, 0)?;
                self.retired.push(old);
            }
        }
        // Every range now lies in the arenas (the batch fits after the last allocated element):
        // every offset below u32::MAX, clusters below 2^31.
        self.check_pool()?;
        // The pool below 2^31 words (materials are addressed in u16 units); the clusters below
        // 2^CULL_RANGE_INDEX_BITS (cluster_cull's range items carry a global cluster index).
        if self.arenas[0].size() >= 1 << crate::shared::CULL_RANGE_INDEX_BITS
            || self.arenas[POOL].size() >= 1 << 31
            || self.arenas.iter().any(|a| a.size() >= u32::MAX as u64)
        {
            return Err(oversize("scene geometry"));
        }
        let mut handles = Vec::with_capacity(built.len());
        let mut staged: Vec<u8> = Vec::new();
        // (arena, staging offset, destination byte offset, bytes)
        let mut copies: Vec<(usize, u64, u64, u64)> = Vec::new();
        let mut new_slots = Vec::with_capacity(built.len());
        let old_slots = self.mesh_table.len() as u64;
        for (&(m, present), tiny) in built.iter().zip(&tiny) {
            let lens = Self::lengths(m, present, tiny);
            let mut ranges = [(0u64, 0u64); ARENAS];
            for k in 0..ARENAS {
                let ctx = self.ctx.clone();
                let (arena, buf) = self.arena_buffer(k);
                let (start, old) = arena.alloc(&ctx, buf, lens[k])?;
                self.retire(old);
                ranges[k] = (start, lens[k]);
            }
            let (center, radius) = mesh_sphere(m);
            let q = &m.quantization;
            let (walk_error, walk_error_wide, walk_radius) = walk_bound(m, center);
            let gpu = MeshGpu {
                cluster_offset: ranges[0].0 as u32,
                group_offset: ranges[1].0 as u32,
                bvh_offset: ranges[2].0 as u32,
                page_offset: ranges[PAGES].0 as u32,
                page_count: m.pages.len() as u32,
                resident_pages: m.resident_pages,
                cluster_count: m.clusters.len() as u32,
                bvh_root: 0,
                quant_origin: [q.origin[0] as f32, q.origin[1] as f32, q.origin[2] as f32],
                quant_step: q.step as f32,
                bounds_center: center,
                bounds_radius: radius,
                root_cluster: m.root,
                fallback_level: m
                    .fallback_level(crate::builder::BuildOptions::default().fallback_triangles),
                streams: if m.has_uvs { MESH_STREAM_UVS } else { 0 }
                    | if m.has_material_stream() {
                        MESH_STREAM_MATERIALS
                    } else {
                        0
                    }
                    | if m.stats.closed_solid == Some(true) {
                        MESH_CLOSED_SOLID
                    } else {
                        0
                    },
                walk_error,
                walk_error_wide,
                walk_radius,
                normal_scale: crate::builder::quantize::normal_scale(q.normal_bits),
                tiny_offset: ranges[TINY].0 as u32,
            };
            let (pages, pool) = page_upload(m, ranges[POOL].0 as u32, present);
            // Its partial flag is set with the table entry below (`set_mesh_partial`).
            let partial = pages.iter().any(|e| e.word == PAGE_NOT_RESIDENT);
            let locs: Vec<ClusterLocGpu> = m
                .clusters
                .iter()
                .map(|c| ClusterLocGpu {
                    page: c.page,
                    data_offset: c.data_offset,
                })
                .collect();
            let groups: Vec<crate::shared::GroupGpu> = m
                .groups
                .iter()
                .enumerate()
                .map(|(i, g)| crate::shared::GroupGpu {
                    lod_sphere: g.lod_sphere,
                    error: g.error,
                    coverage: m.group_coverage_of(i as u32),
                    first_cluster: g.first_cluster,
                    cluster_count: g.cluster_count,
                    iteration: g.iteration,
                    page_first: g.page_first,
                    page_count: g.page_count,
                    members_creator: members_creator(m, g),
                })
                .collect();
            let data: [&[u8]; ARENAS] = [
                bytemuck::cast_slice(&locs),
                bytemuck::cast_slice(&groups),
                bytemuck::cast_slice(&m.bvh),
                bytemuck::cast_slice(&pages),
                &pool,
                bytemuck::cast_slice(tiny),
            ];
            for (k, d) in data.iter().enumerate() {
                if !d.is_empty() {
                    let elem = self.arenas[k].elem();
                    copies.push((k, staged.len() as u64, ranges[k].0 * elem, d.len() as u64));
                    staged.extend_from_slice(d);
                    // Copies start on 4 bytes in the staging buffer.
                    staged.resize(staged.len().next_multiple_of(4), 0);
                }
            }
            let slot = match self.free_meshes.pop() {
                Some(i) => i,
                None => {
                    self.mesh_slots.push(MeshSlot {
                        generation: 0,
                        live: None,
                    });
                    self.mesh_table.push(MeshGpu::default());
                    self.mesh_slots.len() as u32 - 1
                }
            };
            let ms = &mut self.mesh_slots[slot as usize];
            ms.live = Some(LiveMesh {
                ranges,
                page_records: m.pages.clone(),
                loaded: pages.iter().map(|e| e.word).collect(),
                hidden: vec![false; pages.len()],
                resident_pages: m.resident_pages,
                by_page: {
                    let mut v: Vec<(u32, u32, u32)> = locs
                        .iter()
                        .enumerate()
                        .map(|(i, l)| (l.page, l.data_offset, i as u32))
                        .collect();
                    v.sort_unstable();
                    v
                },
                instances: 0,
                queue_items: m.bvh.len() as u64
                    + m.groups
                        .iter()
                        .map(|g| {
                            g.cluster_count.div_ceil(crate::shared::CULL_RANGE_CLUSTERS) as u64
                        })
                        .sum::<u64>(),
                material: MeshMaterialSource::of(m),
            });
            let generation = ms.generation;
            self.mesh_table[slot as usize] = gpu;
            self.set_mesh_partial(slot as usize, partial);
            self.total_clusters += gpu.cluster_count;
            handles.push(MeshHandle {
                index: slot,
                generation,
            });
            new_slots.push(slot);
        }
        // The mesh table: grown to hold every slot (by doubling, or exactly from empty).
        let need = MESH_GPU_BYTES * self.mesh_table.len() as u64;
        if self.meshes.size() < need {
            let keep = MESH_GPU_BYTES * old_slots;
            let bytes = if keep == 0 {
                need
            } else {
                need.max(2 * self.meshes.size())
            };
            let old = grow_buffer(&self.ctx, &mut self.meshes, bytes, keep)?;
            self.retired.push(old);
        }
        let staging = if staged.is_empty() {
            None
        } else {
            Some(Buffer::staging(
                &self.ctx,
                "scene mesh upload (staging)",
                &staged,
            )?)
        };
        let table = &self.mesh_table;
        let bufs = self.arena_buffers();
        let meshes = &self.meshes;
        self.ctx.submit_and_wait("scene add meshes", |cmd| {
            use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
            // Earlier frames' reads of reused ranges finish before they are overwritten.
            cmd.barrier(
                (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
                (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            );
            if let Some(st) = &staging {
                for &(k, src, dst, bytes) in &copies {
                    cmd.copy_buffer_region(st, src, bufs[k], dst, bytes);
                }
            }
            for &slot in &new_slots {
                let e = &table[slot as usize];
                cmd.update_buffer(meshes, MESH_GPU_BYTES * slot as u64, bytemuck::bytes_of(e));
            }
            cmd.barrier(
                (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                (S::ALL_COMMANDS, A::MEMORY_READ),
            );
        })?;
        self.mesh_epoch += 1;
        if grew_feedback {
            // New feedback buffers start empty (no wish, nothing used).
            self.clear_page_feedback()?;
        }
        Ok(handles)
    }

    fn live_mesh(&self, h: MeshHandle) -> SceneResult<&LiveMesh> {
        self.mesh_slots
            .get(h.index as usize)
            .filter(|s| s.generation == h.generation)
            .and_then(|s| s.live.as_ref())
            .ok_or(SceneError::StaleMesh(h))
    }

    /// Removes a mesh no instance uses ([`SceneError::MeshInUse`] otherwise): its ranges are freed
    /// for later meshes (the buffers do not shrink), its handle becomes stale.
    pub fn remove_mesh(&mut self, h: MeshHandle) -> SceneResult<()> {
        let live = self.live_mesh(h)?;
        if live.instances > 0 {
            return Err(SceneError::MeshInUse {
                mesh: h,
                instances: live.instances,
            });
        }
        let slot = &mut self.mesh_slots[h.index as usize];
        let Some(live) = slot.live.take() else {
            return Err(SceneError::StaleMesh(h));
        };
        slot.generation = slot.generation.wrapping_add(1);
        for (k, r) in live.ranges.iter().enumerate() {
            self.arenas[k].free(r.0, r.1);
        }
        self.total_clusters -= self.mesh_table[h.index as usize].cluster_count;
        // No instance reads a free slot's entry; the GPU copy is left as it was.
        self.set_mesh_partial(h.index as usize, false);
        self.mesh_table[h.index as usize] = MeshGpu::default();
        self.staged.forget_mesh(h.index);
        self.free_meshes.push(h.index);
        self.mesh_epoch += 1;
        Ok(())
    }

    /// Sets which of mesh `h`'s pages the cull may use (`resident[p]`; the page data stays in the
    /// pool): absent pages are marked [`crate::shared::PAGE_NOT_RESIDENT`] and the mesh's cut
    /// follows the partial-residency rule (`src/builder/cut.rs`), asking for absent pages through
    /// [`GpuScene::page_requests`]. The always-resident pages must be resident; the set should be
    /// closed ([`crate::builder::page::close_residency`]) or the cut may crack. A one-shot
    /// submission (waited for).
    pub fn set_page_residency(&mut self, h: MeshHandle, resident: &[bool]) -> SceneResult<()> {
        let live = self.live_mesh(h)?;
        if resident.len() != live.page_records.len() {
            return Err(SceneError::Residency(format!(
                "{} flags for {} pages",
                resident.len(),
                live.page_records.len()
            )));
        }
        if let Some(p) = resident[..live.resident_pages as usize]
            .iter()
            .position(|&r| !r)
        {
            return Err(SceneError::Residency(format!(
                "page {p} is always resident (the first {} are)",
                live.resident_pages
            )));
        }
        if let Some(p) =
            (0..resident.len()).find(|&p| resident[p] && live.loaded[p] == PAGE_NOT_RESIDENT)
        {
            return Err(SceneError::Residency(format!(
                "page {p} is not in the pool"
            )));
        }
        let live = self.mesh_slots[h.index as usize]
            .live
            .as_mut()
            .expect("checked live");
        for (p, &r) in resident.iter().enumerate() {
            live.hidden[p] = !r && live.loaded[p] != PAGE_NOT_RESIDENT;
        }
        let entries: Vec<PageGpu> = (0..resident.len()).map(|p| live.entry(p)).collect();
        let first = live.ranges[PAGES].0;
        let partial = live.partial();
        let slot = h.index as usize;
        self.set_mesh_partial(slot, partial);
        let e = &self.mesh_table[slot];
        let staging = Buffer::staging(
            &self.ctx,
            "scene page residency (staging)",
            bytemuck::cast_slice(&entries),
        )?;
        let (pages, meshes, entry) = (&self.pages, &self.meshes, *e);
        self.ctx.submit_and_wait("scene page residency", |cmd| {
            use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
            cmd.barrier(
                (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
                (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            );
            cmd.copy_buffer_region(
                &staging,
                0,
                pages,
                first * size_of::<PageGpu>() as u64,
                std::mem::size_of_val(entries.as_slice()) as u64,
            );
            cmd.update_buffer(
                meshes,
                MESH_GPU_BYTES * slot as u64,
                bytemuck::bytes_of(&entry),
            );
            cmd.barrier(
                (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                (S::ALL_COMMANDS, A::MEMORY_READ),
            );
        })?;
        Ok(())
    }

    /// Turns visible-list entries as the cull writes them, (instance, pool word of the cluster's
    /// data), into (instance, cluster index in the scene's cluster array), in place, over an index
    /// of the pool's pages made for this call (a frame's read-backs share one). Entries of all
    /// ones (unused slots) stay; a word that starts no cluster of a page in the pool is an error.
    #[doc(hidden)]
    pub fn clusters_at_words(&self, entries: &mut [[u32; 2]]) -> Result<(), String> {
        self.pool_words().clusters_at_words(entries)
    }

    /// Every page in the pool by its first word: what turns a visible-list entry's pool word back
    /// into a cluster. The CPU's page table must be the one the frame ran with: `render` and
    /// `cull` record every staged page change in their own submission and read back right after
    /// it; a host that stages page changes ([`GpuScene::update_pages`]) and records them into a
    /// command buffer of its own must have it executed before it reads back a frame this way.
    /// One index serves every read-back of a frame.
    pub(crate) fn pool_words(&self) -> PoolWords<'_> {
        let mut pages: Vec<(u32, u32, usize, u32)> = Vec::new();
        for (slot, ms) in self.mesh_slots.iter().enumerate() {
            let Some(live) = ms.live.as_ref() else {
                continue;
            };
            for (p, &w) in live.loaded.iter().enumerate() {
                if w != PAGE_NOT_RESIDENT {
                    pages.push((w, live.page_records[p].bytes / 4, slot, p as u32));
                }
            }
        }
        pages.sort_unstable();
        PoolWords { scene: self, pages }
    }

    /// The pool word where cluster `cluster` (an index in the scene's cluster array) starts, as
    /// the cull writes it into the visible list; `None` for no live mesh's cluster or one whose
    /// page is not in the pool. For tests that write visible lists themselves.
    #[doc(hidden)]
    pub fn cluster_word(&self, cluster: u32) -> Option<u32> {
        let live = self
            .mesh_slots
            .iter()
            .filter_map(|m| m.live.as_ref())
            .find(|l| {
                let (first, len) = l.ranges[CLUSTERS];
                (first..first + len).contains(&(cluster as u64))
            })?;
        let local = cluster - live.ranges[CLUSTERS].0 as u32;
        let &(page, offset, _) = live.by_page.iter().find(|&&(_, _, i)| i == local)?;
        let w = *live.loaded.get(page as usize)?;
        (w != PAGE_NOT_RESIDENT).then_some(w + offset)
    }

    /// Makes room for `words` more u32 words after the geometry pool's last allocation, in one
    /// growth (a one-shot copy): a streamer that reserves its always-resident pages and its slots
    /// at once gets a pool of that size, not the doubling of several growths.
    pub fn reserve_pool_words(&mut self, words: u64) -> SceneResult<()> {
        let ctx = self.ctx.clone();
        let (arena, buf) = self.arena_buffer(POOL);
        let old = arena.reserve(&ctx, buf, words)?;
        self.retire(old);
        self.check_pool()
    }

    /// Allocates `words` u32 words of page slots in the geometry pool (for
    /// [`GpuScene::update_pages`]); the first slot's pool word. The pool grows as needed (a
    /// one-shot copy).
    pub fn reserve_page_slots(&mut self, words: u64) -> SceneResult<u32> {
        let ctx = self.ctx.clone();
        let (arena, buf) = self.arena_buffer(POOL);
        let (start, old) = arena.alloc(&ctx, buf, words)?;
        self.retire(old);
        if let Err(e) = self.check_pool() {
            self.arenas[POOL].free(start, words);
            return Err(e);
        }
        if self.arenas[POOL].size() >= 1 << 31 {
            self.arenas[POOL].free(start, words);
            return Err(oversize("geometry pool"));
        }
        Ok(start as u32)
    }

    /// Mesh `h`'s first entry in the scene's page table, and its page count.
    pub fn page_range(&self, h: MeshHandle) -> SceneResult<(u64, u64)> {
        Ok(self.live_mesh(h)?.ranges[PAGES])
    }

    /// Whether `h` names a mesh of this scene.
    pub fn contains_mesh(&self, h: MeshHandle) -> bool {
        self.live_mesh(h).is_ok()
    }

    /// Handle of the mesh in slot `index`, if one lives there ([`GpuScene::new`]: mesh `i`).
    pub fn mesh_handle(&self, index: u32) -> Option<MeshHandle> {
        let s = self.mesh_slots.get(index as usize)?;
        s.live.as_ref().map(|_| MeshHandle {
            index,
            generation: s.generation,
        })
    }

    /// Live meshes.
    pub fn mesh_count(&self) -> usize {
        self.mesh_slots.iter().filter(|s| s.live.is_some()).count()
    }

    /// Sets or clears mesh slot `slot`'s [`MESH_STREAM_PARTIAL`] in the CPU's table (keeping
    /// the count of partial meshes); true when it changed.
    pub(crate) fn set_mesh_partial(&mut self, slot: usize, partial: bool) -> bool {
        let e = &mut self.mesh_table[slot];
        let was = e.streams & MESH_STREAM_PARTIAL != 0;
        if was == partial {
            return false;
        }
        if partial {
            e.streams |= MESH_STREAM_PARTIAL;
            self.partial_count += 1;
        } else {
            e.streams &= !MESH_STREAM_PARTIAL;
            self.partial_count -= 1;
        }
        true
    }

    /// Meshes with some page absent ([`MESH_STREAM_PARTIAL`]) in the CPU's table.
    pub fn partial_meshes(&self) -> u32 {
        self.partial_count
    }

    /// Whether a frame recorded now may find a mesh partial on the GPU: one is partial in the
    /// CPU's table, or a mesh's flag changed and its copy is not yet recorded (the GPU may still
    /// hold it partial until the frame that records the staged changes). The culls then take
    /// their pipelines with the partial-residency code (`passes::cull::CullPipelines`).
    pub fn may_be_partial(&self) -> bool {
        self.partial_count > 0 || self.staged.has_mesh_changes()
    }

    /// Changes with every mesh added or removed.
    pub fn mesh_epoch(&self) -> u64 {
        self.mesh_epoch
    }

    /// The material table of the live meshes, one entry per mesh slot
    /// ([`SceneMaterials::with_layout`]).
    pub fn materials(&self) -> Result<SceneMaterials, String> {
        SceneMaterials::with_layout(
            self.mesh_slots
                .iter()
                .map(|s| s.live.as_ref().map(|l| &l.material)),
        )
    }

    /// Entries of the instance buffer (at least `instance_count`).
    pub fn instance_capacity(&self) -> u32 {
        self.instance_capacity
    }

    /// Sum over instances of their mesh's queue items (BVH nodes and cluster ranges): the cull
    /// queue's worst case.
    pub fn instance_nodes(&self) -> u64 {
        self.instance_nodes
    }

    fn ensure_instance_capacity(&mut self, count: u32) -> SceneResult<()> {
        if count <= self.instance_capacity {
            return Ok(());
        }
        let cap = if self.instance_capacity == 0 {
            count
        } else {
            count.max(self.instance_capacity.saturating_mul(2))
        };
        let stride = size_of::<InstanceVgeo>() as u64;
        let keep = stride * self.instance_count as u64;
        let old = grow_buffer(&self.ctx, &mut self.instances, stride * cap as u64, keep)?;
        self.retired.push(old);
        self.instance_capacity = cap;
        Ok(())
    }

    fn mark(&mut self, dense: u32) {
        let d = dense as usize;
        if d >= self.dirty_flag.len() {
            self.dirty_flag.resize(d + 1, false);
        }
        if !self.dirty_flag[d] {
            self.dirty_flag[d] = true;
            self.dirty.push(dense);
        }
    }

    /// Appends one instance to the mirror and handle table (not yet on the GPU); its dense slot.
    fn push_instance(&mut self, d: &InstanceDesc) -> SceneResult<(InstanceHandle, u32)> {
        let live = self.live_mesh(d.mesh)?;
        let nodes = live.queue_items;
        let clusters = self.mesh_table[d.mesh.index as usize].cluster_count as u64;
        if self.instance_count == u32::MAX - 1 {
            return Err(oversize("instances"));
        }
        let mut inst = instance_of(d.mesh.index, &d.transform, d.color);
        inst.visible_base = match self.visible.alloc(clusters) {
            Some(b) => b as u32,
            None => {
                let size = (2 * self.visible.size()).max(self.visible.end() + clusters);
                if size <= u32::MAX as u64 {
                    self.visible.grow(size);
                    self.visible.alloc(clusters).unwrap_or(0) as u32
                } else {
                    // Past 32-bit slots: no range (direct slots are off for such scenes anyway).
                    self.unranged_clusters += clusters;
                    u32::MAX
                }
            }
        };
        if let Some(l) = self.mesh_slots[d.mesh.index as usize].live.as_mut() {
            l.instances += 1;
        }
        self.instance_nodes += nodes;
        let dense = self.instance_count;
        let index = match self.free_instances.pop() {
            Some(i) => i,
            None => {
                self.instance_slots.push(InstanceSlot {
                    generation: 0,
                    dense: NO_SLOT,
                });
                self.instance_slots.len() as u32 - 1
            }
        };
        let slot = &mut self.instance_slots[index as usize];
        slot.dense = dense;
        let h = InstanceHandle {
            index,
            generation: slot.generation,
        };
        self.mirror.push(inst);
        self.dense_handle.push(index);
        self.instance_count += 1;
        self.instance_clusters = self.visible.end() + self.unranged_clusters;
        Ok((h, dense))
    }

    /// Adds an instance; it is drawn from the next frame on (its data goes through the staging
    /// ring). The instance buffer grows (doubling) when full.
    pub fn add_instance(&mut self, d: &InstanceDesc) -> SceneResult<InstanceHandle> {
        self.live_mesh(d.mesh)?;
        self.ensure_instance_capacity(self.instance_count + 1)?;
        let (h, dense) = self.push_instance(d)?;
        self.mark(dense);
        Ok(h)
    }

    /// Adds many instances with one upload (not through the staging ring: bulk loads do not
    /// grow the ring). All or nothing: a stale mesh handle adds none.
    pub fn add_instances(&mut self, descs: &[InstanceDesc]) -> SceneResult<Vec<InstanceHandle>> {
        for d in descs {
            self.live_mesh(d.mesh)?;
        }
        let first = self.instance_count;
        let count = first
            .checked_add(descs.len() as u32)
            .ok_or_else(|| oversize("instances"))?;
        self.ensure_instance_capacity(count)?;
        let mut handles = Vec::with_capacity(descs.len());
        for d in descs {
            handles.push(self.push_instance(d)?.0);
        }
        let bytes: &[u8] = bytemuck::cast_slice(&self.mirror[first as usize..]);
        if !bytes.is_empty() {
            let staging = Buffer::staging(&self.ctx, "scene instances (staging)", bytes)?;
            let dst = first as u64 * size_of::<InstanceVgeo>() as u64;
            let instances = &self.instances;
            self.ctx.submit_and_wait("scene add instances", |cmd| {
                use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
                cmd.barrier(
                    (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
                    (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                );
                cmd.copy_buffer_region(&staging, 0, instances, dst, bytes.len() as u64);
                cmd.barrier(
                    (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                    (S::ALL_COMMANDS, A::MEMORY_READ),
                );
            })?;
        }
        Ok(handles)
    }

    fn dense_of(&self, h: InstanceHandle) -> SceneResult<u32> {
        self.instance_slots
            .get(h.index as usize)
            .filter(|s| s.generation == h.generation && s.dense != NO_SLOT)
            .map(|s| s.dense)
            .ok_or(SceneError::StaleInstance(h))
    }

    /// The instance's current index in the dense array (what `InstanceVgeo` arrays, the visible
    /// list and [`crate::frame::VgeoFrame::resolve`] call an instance). Removals move the last
    /// instance into the hole, so this may change.
    pub fn instance_slot(&self, h: InstanceHandle) -> SceneResult<u32> {
        self.dense_of(h)
    }

    /// The handle of the instance at dense index `slot` ([`GpuScene::new`]: placement `slot`).
    pub fn instance_handle(&self, slot: u32) -> Option<InstanceHandle> {
        let index = *self.dense_handle.get(slot as usize)?;
        Some(InstanceHandle {
            index,
            generation: self.instance_slots[index as usize].generation,
        })
    }

    /// The GPU data of an instance as the next frame will see it.
    pub fn instance(&self, h: InstanceHandle) -> SceneResult<InstanceVgeo> {
        Ok(self.mirror[self.dense_of(h)? as usize])
    }

    /// Removes an instance (the last one takes its place in the dense array); gone from the next
    /// frame on.
    pub fn remove_instance(&mut self, h: InstanceHandle) -> SceneResult<()> {
        let d = self.dense_of(h)?;
        let inst = self.mirror[d as usize];
        let mesh = inst.mesh as usize;
        let clusters = self.mesh_table[mesh].cluster_count as u64;
        if inst.visible_base == u32::MAX && clusters > 0 {
            self.unranged_clusters -= clusters;
        } else {
            self.visible.free(inst.visible_base as u64, clusters);
        }
        if let Some(l) = self.mesh_slots[mesh].live.as_mut() {
            l.instances -= 1;
            self.instance_nodes -= l.queue_items;
        }
        let last = self.instance_count - 1;
        self.mirror.swap_remove(d as usize);
        self.dense_handle.swap_remove(d as usize);
        if d != last {
            let moved = self.dense_handle[d as usize];
            self.instance_slots[moved as usize].dense = d;
            self.mark(d);
        }
        self.instance_count -= 1;
        let slot = &mut self.instance_slots[h.index as usize];
        slot.dense = NO_SLOT;
        slot.generation = slot.generation.wrapping_add(1);
        self.free_instances.push(h.index);
        self.instance_clusters = self.visible.end() + self.unranged_clusters;
        Ok(())
    }

    /// Moves an instance (object -> world, f64); applied at the start of the next frame.
    /// O(1), no allocation once the dirty list has grown.
    pub fn set_transform(&mut self, h: InstanceHandle, transform: &DMat4) -> SceneResult<()> {
        let d = self.dense_of(h)?;
        let old = self.mirror[d as usize];
        let mut inst = instance_of(old.mesh, transform, old.color);
        inst.visible_base = old.visible_base;
        self.mirror[d as usize] = inst;
        self.mark(d);
        Ok(())
    }

    /// Changes an instance's albedo tint; applied at the start of the next frame.
    pub fn set_color(&mut self, h: InstanceHandle, color: [f32; 3]) -> SceneResult<()> {
        let d = self.dense_of(h)?;
        self.mirror[d as usize].color = color;
        self.mark(d);
        Ok(())
    }

    /// Instances changed since the last [`GpuScene::prepare_updates`].
    pub fn pending_changes(&self) -> usize {
        self.dirty.len()
    }

    /// Frames the host keeps in flight (at least [`FRAMES_IN_FLIGHT`]): the staging ring and the
    /// page-feedback read-back get a slot per frame, so that neither is rewritten while a frame
    /// that uses it may still run.
    pub fn set_frames_in_flight(&mut self, frames: usize) {
        self.ring_slots = frames.max(FRAMES_IN_FLIGHT);
        self.ring_next %= self.ring_slots;
    }

    /// Writes the changed instances and the staged page changes ([`GpuScene::update_pages`])
    /// into the next staging-ring buffer (grown if needed) and prepares the copies
    /// [`GpuScene::record_updates`] records: O(changed), contiguous slots merged into one copy.
    /// Also makes the page-feedback read-back slots as large as the feedback. A prepared update
    /// that was never submitted is prepared again.
    pub fn prepare_updates(&mut self) -> GpuResult<()> {
        if self.pending.take().is_some() {
            // Not submitted: those slots are still to be written.
            let stride = size_of::<InstanceVgeo>() as u64;
            for i in 0..self.regions.len() {
                let r = self.regions[i];
                for s in r.dst_offset / stride..(r.dst_offset + r.size) / stride {
                    self.mark(s as u32);
                }
            }
        }
        self.regions.clear();
        self.prepare_feedback()?;
        let count = self.instance_count;
        for &s in &self.dirty {
            self.dirty_flag[s as usize] = false;
        }
        self.dirty.retain(|&s| s < count);
        let page_bytes = self.staged.bytes();
        if self.dirty.is_empty() && page_bytes == 0 {
            return Ok(());
        }
        self.dirty.sort_unstable();
        let stride = size_of::<InstanceVgeo>() as u64;
        let need = stride * self.dirty.len() as u64 + page_bytes;
        let slot = self.ring_next;
        self.ring_next = (self.ring_next + 1) % self.ring_slots;
        if slot >= self.ring.len() || self.ring[slot].size() < need {
            let old = self.ring.get(slot).map(|b| b.size()).unwrap_or(0);
            let b = Buffer::new(
                &self.ctx,
                &format!("scene update ring {slot}"),
                need.max(2 * old),
                vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryKind::Upload,
            )?;
            if slot < self.ring.len() {
                self.ring[slot] = b;
            } else {
                self.ring.push(b);
            }
        }
        let mut i = 0;
        let mut off = 0u64;
        while i < self.dirty.len() {
            let a = self.dirty[i] as usize;
            let mut b = a + 1;
            i += 1;
            while i < self.dirty.len() && self.dirty[i] as usize == b {
                b += 1;
                i += 1;
            }
            let bytes: &[u8] = bytemuck::cast_slice(&self.mirror[a..b]);
            self.ring[slot].write(off, bytes)?;
            self.regions.push(vk::BufferCopy {
                src_offset: off,
                dst_offset: a as u64 * stride,
                size: bytes.len() as u64,
            });
            off += bytes.len() as u64;
        }
        self.stage_pages_into(slot, off)?;
        self.dirty.clear();
        self.pending = Some(slot);
        Ok(())
    }

    /// Records the prepared updates (label `scene_update`): the copies from the staging ring into
    /// the instance buffer, the geometry pool, the page table and the mesh table, between
    /// barriers, before anything of the frame reads them. Records nothing when nothing changed.
    pub fn record_updates(&self, cmd: &mut Cmd) {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        let Some(slot) = self.pending else {
            return;
        };
        cmd.begin_label("scene_update");
        cmd.barrier(
            (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
        );
        cmd.copy_buffer_regions(&self.ring[slot], &self.instances, &self.regions);
        self.record_page_copies(cmd, slot);
        cmd.barrier(
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            (S::ALL_COMMANDS, A::MEMORY_READ),
        );
        cmd.end_label();
    }

    /// The prepared updates were submitted (the mirror and the GPU agree from that frame on).
    pub fn updates_submitted(&mut self) {
        if self.pending.is_some() {
            self.pages_submitted();
        }
        self.pending = None;
        self.regions.clear();
    }

    /// The descriptors every pass that decodes clusters binds, in this order: instances, meshes,
    /// clusters, pages, the geometry pool (see `shaders_glsl/common/raster.glsl`).
    pub fn geometry_descs(&self) -> [Desc<'_>; 5] {
        [
            Desc::Storage(&self.instances),
            Desc::Storage(&self.meshes),
            Desc::Storage(&self.clusters),
            Desc::Storage(&self.pages),
            Desc::Storage(&self.pool),
        ]
    }

    /// GPU bytes of geometry (clusters, groups, BVH, pages, the pool, the small-instance cut
    /// tables), as allocated.
    pub fn geometry_bytes(&self) -> u64 {
        self.arena_buffers().iter().map(|b| b.size()).sum()
    }

    /// Bytes per GPU buffer of the scene: in use and allocated (the buffers grow by doubling and
    /// never shrink; freed mesh ranges are reused by later meshes).
    pub fn memory(&self) -> SceneMemory {
        let inst = size_of::<InstanceVgeo>() as u64;
        let mut buffers = vec![
            BufferMemory {
                name: "scene meshes",
                used_bytes: MESH_GPU_BYTES * (self.mesh_count() as u64),
                capacity_bytes: self.meshes.size(),
            },
            BufferMemory {
                name: "scene instances",
                used_bytes: inst * self.instance_count as u64,
                capacity_bytes: self.instances.size(),
            },
        ];
        let bufs = self.arena_buffers();
        for (k, b) in bufs.iter().enumerate() {
            buffers.push(BufferMemory {
                name: ARENA_NAMES[k],
                used_bytes: self.arenas[k].used_bytes(),
                capacity_bytes: b.size(),
            });
        }
        buffers.push(BufferMemory {
            name: "scene update ring",
            used_bytes: self.regions.iter().map(|r| r.size).sum(),
            capacity_bytes: self.ring.iter().map(|b| b.size()).sum(),
        });
        SceneMemory { buffers }
    }
}

/// The [`PageGpu`] entries of `m`'s pages and the pages' bytes, for the pool range starting at
/// word `pool_word` (pages back to back, each a whole number of words). With `present`, only its
/// pages (the first ones) are there; the others are [`PAGE_NOT_RESIDENT`].
fn page_upload(
    m: &BuiltMesh,
    pool_word: u32,
    present: Option<&[Vec<u8>]>,
) -> (Vec<PageGpu>, Vec<u8>) {
    let mut bytes = Vec::new();
    let by_page = match present {
        None => crate::builder::page::clusters_by_page(m),
        Some(_) => Vec::new(),
    };
    let pages = m
        .pages
        .iter()
        .enumerate()
        .map(|(i, _)| {
            let data = match present {
                None => crate::builder::page::encode_page(m, &by_page[i]),
                Some(b) => match b.get(i) {
                    Some(d) => d.clone(),
                    None => return PageGpu::absent(),
                },
            };
            let word = pool_word.wrapping_add((bytes.len() / 4) as u32);
            bytes.extend_from_slice(&data);
            PageGpu { word }
        })
        .collect();
    (pages, bytes)
}

impl PageGpu {
    /// The entry of an absent page.
    pub fn absent() -> Self {
        PageGpu {
            word: PAGE_NOT_RESIDENT,
        }
    }
}

/// The pages in a scene's pool by first word ([`GpuScene::pool_words`]).
pub(crate) struct PoolWords<'a> {
    scene: &'a GpuScene,
    /// (first word, words, mesh slot, page), by first word.
    pages: Vec<(u32, u32, usize, u32)>,
}

impl PoolWords<'_> {
    /// Turns visible-list entries as the cull writes them, (instance, pool word of the cluster's
    /// data), into (instance, cluster index in the scene's cluster array), in place. Entries of
    /// all ones (unused slots) stay. A word that starts no cluster of a page in the pool is an
    /// error.
    pub(crate) fn clusters_at_words(&self, entries: &mut [[u32; 2]]) -> Result<(), String> {
        for e in entries.iter_mut() {
            if *e == [u32::MAX; 2] {
                continue;
            }
            let word = e[1];
            let i = self.pages.partition_point(|&(w, ..)| w <= word);
            let found = i.checked_sub(1).and_then(|i| {
                let (first, words, slot, page) = self.pages[i];
                if word - first >= words {
                    return None;
                }
                let live = self.scene.mesh_slots[slot].live.as_ref()?;
                let k = live
                    .by_page
                    .binary_search_by(|&(p, o, _)| (p, o).cmp(&(page, word - first)))
                    .ok()?;
                Some(live.ranges[CLUSTERS].0 as u32 + live.by_page[k].2)
            });
            e[1] = found.ok_or_else(|| {
                format!("a visible cluster at pool word {word} is no cluster of a page in the pool")
            })?;
        }
        Ok(())
    }
}

/// `GroupGpu::members_creator` of group `g` of `m`: its members' one creator group, or
/// [`crate::shared::NO_GROUP_ID`] when they have several (or none: level 0).
pub(crate) fn members_creator(m: &BuiltMesh, g: &crate::builder::Group) -> u32 {
    // A range past the clusters (refused where a mesh is loaded or built) reads as no members.
    let members = m
        .clusters
        .get(g.first_cluster as usize..)
        .and_then(|c| c.get(..g.cluster_count as usize))
        .unwrap_or(&[]);
    match members.split_first() {
        Some((first, rest)) if rest.iter().all(|c| c.creator == first.creator) => first.creator,
        _ => crate::shared::NO_GROUP_ID,
    }
}

/// `MeshGpu::walk_error`, `walk_error_wide` and `walk_radius` of a mesh whose bounding sphere is
/// centred at `center`: `walk_error` the largest parent error but the
/// [`crate::shared::WALK_CLUSTERS`] largest (0 when the mesh has no more clusters), and a radius
/// around `center` enclosing every parent sphere and BVH LOD sphere. Any cluster (and node)
/// outside those largest has a parent error at most `walk_error` on a sphere inside that radius,
/// so when `walk_error` projects under the threshold there, none of them is in the cut (nor
/// walked): the walk is short. `walk_error_wide` is the same count for `WALK_CLUSTERS_WIDE`
/// with a group of one creator counted once where the walk tests it once (`members_creator`):
/// an estimate there (the creator's error is projected on its own sphere), which a whole-mesh
/// level's group of many members needs, else its members crowd the count. Only the walk's
/// length depends on either, never the cut.
pub(crate) fn walk_bound(m: &BuiltMesh, center: [f32; 3]) -> (f32, f32, f32) {
    // The walk tests a cluster when its parent error is over the threshold. In a wide view the
    // members of a group of one creator whose error is over it too are tested once for all
    // (`members_creator`): one test, not one per member. So at threshold t it tests (+1 per
    // cluster with parent error > t) - (members - 1 per such group with min(its error, its
    // creator's) > t), counted from the largest key down; the narrow bound (few instances, a
    // long walk is the frame's latency) counts every cluster, as the walk's nodes cost too.
    let mut events: Vec<(f32, i64)> = m
        .clusters
        .iter()
        .map(|c| (c.parent_error.max(0.0), 1))
        .collect();
    let walk_error = bound_of(&mut events, crate::shared::WALK_CLUSTERS);
    for g in &m.groups {
        let mc = members_creator(m, g);
        if let Some(creator) = m.groups.get(mc as usize) {
            events.push((
                g.error.min(creator.error).max(0.0),
                1 - g.cluster_count as i64,
            ));
        }
    }
    let walk_error_wide = bound_of(&mut events, crate::shared::WALK_CLUSTERS_WIDE);
    let reach = |s: &[f32; 4]| {
        let d =
            ((s[0] - center[0]).powi(2) + (s[1] - center[1]).powi(2) + (s[2] - center[2]).powi(2))
                .sqrt();
        d + s[3]
    };
    let radius = m
        .clusters
        .iter()
        .map(|c| reach(&c.parent_sphere))
        .chain(m.bvh.iter().map(|n| reach(&n.lod_sphere)))
        .fold(0.0f32, f32::max);
    // A margin against rounding of the sums above (only the walk's length depends on it).
    (walk_error, walk_error_wide, radius * (1.0 + 1.0 / 1024.0))
}

/// The largest key of `events` (a key and how many tests it adds at thresholds under it) at which
/// the tests at a threshold just under it first exceed `k`: every threshold from there up tests
/// at most `k`. 0 when none does.
fn bound_of(events: &mut [(f32, i64)], k: u32) -> f32 {
    events.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
    let mut tested = 0i64;
    let mut i = 0;
    while i < events.len() {
        let key = events[i].0;
        while i < events.len() && events[i].0 == key {
            tested += events[i].1;
            i += 1;
        }
        if tested > k as i64 {
            return key;
        }
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::bound_of;

    #[test]
    fn the_walk_bound_is_the_key_where_the_tests_first_exceed_k() {
        // One test per key: the (k + 1)-th largest, as a sorted list of parent errors gives it.
        let mut e: Vec<(f32, i64)> = [5.0, 1.0, 4.0, 2.0, 3.0].iter().map(|&x| (x, 1)).collect();
        assert_eq!(bound_of(&mut e, 2), 3.0);
        assert_eq!(bound_of(&mut e, 0), 5.0);
        assert_eq!(bound_of(&mut e, 5), 0.0, "never more than 5 tests");
        // Ties count together.
        let mut t = vec![(2.0, 1), (2.0, 1), (1.0, 1)];
        assert_eq!(bound_of(&mut t, 1), 2.0);
        // A group of 3 members of one creator under key 4: 2 tests fewer from there down, so
        // 2 tests under 5, 2 + 3 - 2 = 3 under 4 and 4 under 3: k = 3 is first exceeded at 3.
        let mut g = vec![(5.0, 2), (4.0, 3), (4.0, -2), (3.0, 1)];
        assert_eq!(bound_of(&mut g, 3), 3.0);
        assert_eq!(bound_of(&mut g, 2), 4.0);
    }
}
