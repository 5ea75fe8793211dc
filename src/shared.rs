//! The single source of constants and `#[repr(C)]` GPU structs shared by Rust and GLSL.
//!
//! build.rs reads every `pub const NAME: u32|i32|f32 = literal;` line between the two marker comments
//! below and passes it to shaderc as a macro, so GLSL sees the same values by the same names.
//! GPU structs are `Pod` and their sizes are asserted here; the GLSL side declares them in
//! `shaders_glsl/common/shared.glsl` with the same layout (scalar block layout).

use bytemuck::{Pod, Zeroable};

// BEGIN SHADER CONSTANTS
/// Sub-pixel precision of rasterization (fixed point), the same in HW, SW and the CPU reference.
pub const SUBPIXEL_BITS: u32 = 8;
/// Most triangles in one cluster.
pub const MAX_CLUSTER_TRIANGLES: u32 = 128;
/// Most vertices in one cluster (indices are stored as u8).
pub const MAX_CLUSTER_VERTICES: u32 = 255;
/// Visibility buffer low word: visible-cluster index << TRIANGLE_BITS | triangle.
pub const VISBUFFER_TRIANGLE_BITS: u32 = 7;
/// Bits of the visible-cluster index in the visibility buffer's low word.
pub const VISBUFFER_CLUSTER_BITS: u32 = 25;
/// Visibility buffer low word of a pixel the host's depth covers (`depth_import`): the largest
/// value, past every visible-cluster index (the visible list holds at most `2^25 - 1` entries), so
/// readers treat it as "not vgeo's" and a vgeo fragment at exactly the host's depth loses the tie.
pub const VISBUFFER_HOST: u32 = 0xffffffff;
/// `MaterialViewGpu::flags`: `shade` writes only the pixels vgeo's geometry covers (embedding: the
/// host's own pixels and background stay as the host drew them).
pub const SHADE_FLAG_COVERED_ONLY: u32 = 1;
/// `MaterialViewGpu::flags`: `shade` tells covered pixels by `material_classify`'s per-pixel
/// material (written for every pixel) instead of the albedo's alpha, so the compute
/// `emit_gbuffer` needs no clear of the GBuffer (a 1080p clear cost 0.17 ms on the H100).
pub const SHADE_FLAG_PIXEL_MATERIALS: u32 = 2;
/// Workgroup size of simple 2D image passes.
pub const TILE_WORKGROUP_SIZE: u32 = 8;
/// `shade`: pixels per side of one 16x16 workgroup's tile (a multiple of 16).
pub const SHADE_TILE: u32 = 32;
/// `depth_pyramid`: one workgroup is HZB_GROUP x HZB_GROUP threads; its head dispatch reduces a
/// tile of 2 * HZB_GROUP texels of level 0 square through the first HZB_HEAD_LEVELS levels.
pub const HZB_GROUP: u32 = 16;
/// `depth_pyramid`: levels the head dispatch makes (log2 of 2 * HZB_GROUP, plus one).
pub const HZB_HEAD_LEVELS: u32 = 6;
/// Threads of one `instance_cull` workgroup.
pub const INSTANCE_CULL_WORKGROUP_SIZE: u32 = 64;
/// Workgroups along x of a compute dispatch (the specification's minimum
/// `maxComputeWorkGroupCount[0]`); more take rows of this many ([`compute_grid`]).
pub const COMPUTE_GROUPS_X: u32 = 65535;
/// Threads of one persistent `cluster_cull` workgroup (items popped per iteration).
pub const CLUSTER_CULL_WORKGROUP_SIZE: u32 = 64;
/// Threads of one `raster_sw` workgroup: one per triangle of a cluster.
pub const RASTER_SW_WORKGROUP_SIZE: u32 = 128;
/// SW clusters whose bounding sphere projects to at most this many pixels across, and whose
/// triangles to at most [`RASTER_SW_SMALL_TRIANGLE_PX`], go to the small end of the SW list, which
/// `raster_sw` draws two clusters to a workgroup (64 threads, two triangles a thread, no shared
/// pass for large triangles): on tiny clusters its cost is per cluster, not per triangle. 20 and 4
/// against session 23's 7 px alone (H100, bench/results/2026-11-26-session25, calls 7-8): stress
/// N=100 -3 %, N=20 -2 %, foliage -1 %, the other scenes the same; 20 px alone cost outdoor 1.5 %
/// (clusters of a few large triangles, each walked by one invocation).
pub const RASTER_SW_SMALL_PX: f32 = 20.0;
/// The largest edge-length equivalent (pixels, `emit_cluster`'s `size_px`) of a small SW cluster's
/// triangles ([`RASTER_SW_SMALL_PX`]).
pub const RASTER_SW_SMALL_TRIANGLE_PX: f32 = 4.0;
/// The most vertices of a small SW cluster ([`RASTER_SW_SMALL_PX`]): the small path keeps its
/// two clusters' snapped vertices (three words each) where the other path keeps one cluster's
/// vertices and its large triangles (`raster_sw`'s shared array). 170 takes foliage's grass
/// clusters (152 and 132 vertices), which 127 kept out.
pub const RASTER_SW_SMALL_VERTICES: u32 = 170;
/// The most vertices of a small SW cluster that `raster_sw` draws four to a workgroup (32
/// threads a cluster, a quarter of its shared array each): the cull puts those at the end of the
/// HW list (`CullCounters::sw_quarter_count`). Tiny clusters cost a chain of dependent reads
/// each, so more of them to a workgroup hide more of it (stress N=200's clusters of a far blade,
/// 12-96 triangles: 7.56 -> 6.16 ms, N=100 2.08 -> 1.87). The shared array stays the same
/// size: room for 170 vertices a quarter made it twice as large and cost more than it gained
/// (N=200 7.11 ms, foliage +12 %: bench/results/2026-11-27-session30, calls 5-6), so foliage's
/// grass clusters (132-152 vertices) stay two to a workgroup.
pub const RASTER_SW_QUARTER_VERTICES: u32 = 85;
/// Threads of one `raster_hw` mesh-shader workgroup (the mesh path, one workgroup per HW cluster):
/// one per triangle, each also decoding up to two of the cluster's vertices.
pub const RASTER_HW_MESH_WORKGROUP_SIZE: u32 = 128;
/// `raster_hw` mesh path: workgroups along x of its `vkCmdDrawMeshTasksIndirectEXT` (the
/// specification's minimum `maxMeshWorkGroupCount[0]`); more HW clusters take rows of this many.
pub const MESH_GROUPS_X: u32 = 65535;
/// `raster_hw` mesh path: most HW clusters one phase draws, the whole rows of [`MESH_GROUPS_X`]
/// within the specification's minimum `maxMeshWorkGroupTotalCount` (2^22). More are counted in
/// `CullCounters::hw_overflow` (an error, never silent).
pub const MESH_MAX_CLUSTERS: u32 = 4194240;
/// `instance_cull` walks an instance's BVH itself (no global queue) when at most this many of
/// its mesh's clusters can be in the cut (`MeshGpu::walk_error`), so a small instance costs one
/// thread's short walk instead of a trip per node through `cluster_cull`'s persistent queue. In a
/// view of at least [`WALK_WIDE_INSTANCES`] instances, a mesh of at most this many clusters takes
/// its small-instance table at any size instead ([`TINY_CUT_RADIUS_PX`]): its table holds every
/// cut of it (asserted below against [`TINY_CUT_CLUSTERS`] and [`TINY_CUT_ENTRIES`]).
pub const WALK_CLUSTERS: u32 = 16;
/// With at least [`WALK_WIDE_INSTANCES`] instances in the view, the local walk takes meshes with up
/// to this many clusters in the cut (`MeshGpu::walk_error_wide`): with many instances the GPU is
/// busy with one thread each and the queue's atomics are the bottleneck (stress N=100: 24.3 ->
/// 8.2 ms on the H100); with few, a long walk in one thread is the frame's latency (outdoor, 91
/// instances: 0.84 -> 0.97 ms).
pub const WALK_CLUSTERS_WIDE: u32 = 64;
/// Instances of a view from which `instance_cull` walks with [`WALK_CLUSTERS_WIDE`].
pub const WALK_WIDE_INSTANCES: u32 = 4096;
/// In a view of at least [`WALK_WIDE_INSTANCES`] and fewer than this many instances,
/// `instance_cull`'s workgroup shares the cluster tests of its threads' small-instance cuts and
/// local walks (`common/cull.glsl`, shared runs): a pass of a few thousand threads leaves the GPU
/// mostly idle, and one thread's serial run of up to [`TINY_CUT_CLUSTERS`] tests was its latency.
/// With more instances every thread has its own and the sharing's barriers cost more than they
/// save (stress N=100 +11 %, foliage +24 % when every view shared), with fewer there are no table
/// cuts and the walks are short ([`WALK_CLUSTERS`]).
pub const SHARED_RUNS_MAX_INSTANCES: u32 = 65536;
/// Runs (a small-instance cut, or a group a local walk reaches) each `instance_cull` thread can
/// hand to its workgroup per item; a walk's groups past them go to `cluster_cull`'s queue.
pub const SHARED_RUNS_PER_THREAD: u32 = 8;
// A thread's small-instance cut is its item's first run: it always fits.
const _: () = assert!(SHARED_RUNS_PER_THREAD >= 1);
/// Most clusters of a small instance's cut that `instance_cull` draws from its mesh's table of
/// cuts ([`crate::builder::cut::TinyCuts`]) in O(1), without a BVH walk.
pub const TINY_CUT_CLUSTERS: u32 = 64;
/// Most cluster entries of one mesh's table of small-instance cuts (all its rows together).
pub const TINY_CUT_ENTRIES: u32 = 4096;
/// u32 words per row of a small-instance cut table: error, first entry, count, coverage part
/// (`builder::cut::TinyCuts::words`).
pub const TINY_ROW_WORDS: u32 = 4;
/// Largest projected radius (pixels, of the mesh's bounding sphere at its point nearest to the
/// camera) of an instance that takes its cut from the table, unless its mesh has at most
/// [`WALK_CLUSTERS`] clusters: a larger instance of a bigger mesh walks its BVH, whose per-group
/// LOD test at each group's own sphere draws fewer clusters than the table's one distance.
pub const TINY_CUT_RADIUS_PX: f32 = 32.0;
/// Below this projected radius (pixels, of the mesh's bounding sphere at its point nearest to the
/// camera) an instance counts `radius / SMALL_WEIGHT_RADIUS_PX` (at least [`SMALL_WEIGHT_MIN`])
/// of each LOD error and its coverage part whole (`builder::cut::small_instance_weight`,
/// `common/lod.glsl`'s `weighted_error`), in every test of vgeo's cut and in the `lod` baseline's
/// level choice. An error bounds how far the surface (and, through the normal weight, its
/// shading) moves over a region; inside an instance a few pixels across every such region is
/// about a pixel, which the supersampled reference averages, while a thin part that vanishes is
/// missed at any size (docs/architecture.md, "Small instances: a lighter error"). The cost is
/// measured, not assumed: stress N=20 rendered at the sizes of N=100 and N=200 at 1080p stays
/// within 1 dB of brute at one sample per pixel (bench/results/2026-11-27-session29/).
pub const SMALL_WEIGHT_RADIUS_PX: f32 = 16.0;
/// The smallest weight of [`SMALL_WEIGHT_RADIUS_PX`]: instances under a quarter of that radius.
pub const SMALL_WEIGHT_MIN: f32 = 0.25;
/// A frame without a previous HZB (the first, or the first after a camera cut:
/// [`VIEW_FLAG_COLD_FRAME`]) has nothing to test its main phase against. Pass `occluder_select`
/// first sums the projected area of the instances in the frustum by how far they are
/// ([`CullCounters::cold_area`]: bins of [`COLD_BINS_PER_OCTAVE`] per doubling of the distance
/// from the near plane), and the main phase draws only the nearest bins, those whose bounding
/// spheres add up to [`COLD_OCCLUDER_COVER`] times the screen; the rest wait for the post phase,
/// which tests them against the HZB of what the main phase drew (docs/architecture.md, "A frame
/// without history"). Without it such a frame drew every instance in the frustum: stress N=200's
/// first frame drew 351 M triangles against 146 M for the next.
pub const COLD_DEPTH_BINS: u32 = 32;
/// Bins per doubling of the distance in [`CullCounters::cold_area`] (the last bin holds everything
/// beyond `near * 2^(COLD_DEPTH_BINS / COLD_BINS_PER_OCTAVE)`).
pub const COLD_BINS_PER_OCTAVE: f32 = 2.0;
/// How many times the screen's area the bounding spheres drawn in a cold frame's main phase
/// cover (a sphere's disc overstates a thin mesh's coverage several times).
pub const COLD_OCCLUDER_COVER: f32 = 4.0;
/// [`CullCounters::cold_area`]'s unit: 1 / this of a pixel.
pub const COLD_AREA_SCALE: f32 = 16.0;
/// Most workgroups of `occluder_select` (each sums many instances in shared memory first: one
/// atomic per instance on the few bins' words cost stress N=200's cold frame 6 ms on the H100).
pub const OCCLUDER_SELECT_GROUPS: u32 = 1024;
/// `cluster_cull` tests a BVH leaf's clusters in ranges of at most this many, each range a queue
/// item of its own (so lanes share a leaf's clusters instead of one lane testing them all, one
/// after another: a close mesh's leaves hold a hundred). An item's low word is then
/// `CULL_RANGE_FLAG | (count - 1) << CULL_RANGE_INDEX_BITS | first cluster` (global index).
pub const CULL_RANGE_CLUSTERS: u32 = 8;
/// Bits of a range item's first cluster (global cluster index); a scene has fewer clusters.
pub const CULL_RANGE_INDEX_BITS: u32 = 28;
const _: () = assert!(CULL_RANGE_CLUSTERS <= 1 << (31 - CULL_RANGE_INDEX_BITS));
// raster_sw's large-triangle entries: a triangle's index in 7 bits, its corners in 8 bits each.
const _: () = assert!(MAX_CLUSTER_TRIANGLES <= 1 << 7 && MAX_CLUSTER_VERTICES <= 1 << 8);
// raster_sw's shared array: the small path's two clusters (three words a vertex) within the other
// path's one cluster and its large triangles (two words each).
const _: () = assert!(
    2 * 3 * RASTER_SW_SMALL_VERTICES <= 3 * MAX_CLUSTER_VERTICES + 2 * MAX_CLUSTER_TRIANGLES
        && RASTER_SW_SMALL_VERTICES <= MAX_CLUSTER_VERTICES
);
// The same for the quarter path's four clusters; its clusters are small ones.
const _: () = assert!(
    4 * 3 * RASTER_SW_QUARTER_VERTICES <= 3 * MAX_CLUSTER_VERTICES + 2 * MAX_CLUSTER_TRIANGLES
        && RASTER_SW_QUARTER_VERTICES <= RASTER_SW_SMALL_VERTICES
);
/// Marks a queue item's low word as a range of clusters, not a BVH node.
pub const CULL_RANGE_FLAG: u32 = 0x8000_0000;
/// Nodes the local walk keeps pending in registers; more go to the global queue.
pub const WALK_STACK: u32 = 32;
/// `cluster_cull` gives up (and reports) after this many loop iterations per workgroup.
pub const CLUSTER_CULL_WATCHDOG: u32 = 1000000;
/// An empty slot of the `cluster_cull` work queue (items are `instance << 32 | bvh node`).
pub const QUEUE_EMPTY_LO: u32 = 0xffffffff;
/// `ViewGpu::flags`: all clusters to the SW rasterizer.
pub const VIEW_FLAG_FORCE_SW: u32 = 1;
/// `ViewGpu::flags`: all clusters to the HW rasterizer.
pub const VIEW_FLAG_FORCE_HW: u32 = 2;
/// `ViewGpu::flags`: skip frustum culling (tests compare the pure LOD cut).
pub const VIEW_FLAG_NO_FRUSTUM: u32 = 4;
/// `ViewGpu::flags`: visible-list slots are assigned directly (instance's base + cluster index in
/// its mesh) instead of in atomic order, so the visibility buffer is the same bit for bit on every
/// run. Used whenever every (instance, cluster) pair of the scene fits the visible list.
pub const VIEW_FLAG_DIRECT_VISIBLE: u32 = 8;
/// `ViewGpu::flags`: `raster_sw` (each pixel a triangle covers, i.e. each visibility-buffer atomic)
/// and `raster_hw` (each fragment) add 1 to a per-pixel u32 counter (the overdraw view). Off, the
/// rasterizers only pay the branch.
pub const VIEW_FLAG_COUNT_OVERDRAW: u32 = 16;
/// `ViewGpu::flags`: draw each mesh's fallback mesh (`MeshGpu::fallback_level`: the complete DAG
/// level nearest the fallback triangle count) instead of the LOD cut: a cluster is drawn when its
/// level is at most that level and its group was simplified at or after it (the fallback view).
pub const VIEW_FLAG_FALLBACK_CUT: u32 = 32;
/// `ViewGpu::flags`: `raster_hw` runs its mesh-shader path, which takes at most
/// [`MESH_MAX_CLUSTERS`] clusters per phase: the cull counts those beyond in
/// `CullCounters::hw_overflow`.
pub const VIEW_FLAG_HW_MESH: u32 = 64;
/// `ViewGpu::flags`: the cull keeps its statistics (`CullCounters`' instances tested and visible,
/// nodes visited, clusters tested, triangles, local walks, occlusions), which nothing on the GPU
/// reads. The renderer sets it for frames whose counters are read back and leaves it out of timed
/// paths: an atomic per test cost foliage 9 % of its frame and stress N=100 5 % (session 16).
pub const VIEW_FLAG_CULL_STATS: u32 = 128;
/// `ViewGpu::flags`: the main phase has no previous HZB but the post phase tests one: pass
/// `occluder_select` runs first and the main phase draws only the nearest instances
/// ([`COLD_DEPTH_BINS`]).
pub const VIEW_FLAG_COLD_FRAME: u32 = 256;
/// `BvhNode::flags`: the node is a leaf over groups `first .. first + count`.
pub const BVH_FLAG_LEAF: u32 = 1;
/// `MeshGpu::streams`: the mesh's pages hold UVs.
pub const MESH_STREAM_UVS: u32 = 1;
/// `MeshGpu::streams`: the mesh's pages hold per-vertex materials (u16).
pub const MESH_STREAM_MATERIALS: u32 = 2;
/// `MeshGpu::streams`: some of the mesh's pages may be absent (`PageGpu::word` is
/// [`PAGE_NOT_RESIDENT`]): the cull checks residency (see `src/builder/cut.rs`).
pub const MESH_STREAM_PARTIAL: u32 = 4;
/// Specialization constant id of the cull passes' `CULL_STREAMING` (`common/cull.glsl`, default
/// true): false compiles `instance_cull` and `cluster_cull` without the partial-residency code, for
/// frames in which no mesh has [`MESH_STREAM_PARTIAL`] (`passes::cull::CullPipelines`). The code
/// then takes no branch it would not have taken, yet its mere presence read stress N=100
/// 0.0021 ms slower in `instance_cull` on the H200 (bench/results/2026-11-28-session43).
pub const SPEC_CULL_STREAMING: u32 = 0;
/// `MeshGpu::streams`: the mesh is a closed solid (`BuildStats::closed_solid`): the hardware
/// rasterizer may drop its faces turned away from a camera outside its box (`HW_ENTRY_CULL`).
pub const MESH_CLOSED_SOLID: u32 = 8;
/// A HW-list entry (visible index in the low bits): drop the cluster's triangles that face away
/// (seen from outside a closed solid's box, far enough that the near plane cuts none of it).
pub const HW_ENTRY_CULL: u32 = 0x8000_0000;
/// A HW-list entry with `HW_ENTRY_CULL`: the instance mirrors (its linear part's determinant is
/// negative), so the faces that face away wind the other way on screen.
pub const HW_ENTRY_MIRRORED: u32 = 0x4000_0000;
// A visible index (below 2^VISBUFFER_CLUSTER_BITS) leaves a HW-list entry's two flags free.
const _: () = assert!(1 << VISBUFFER_CLUSTER_BITS <= HW_ENTRY_MIRRORED);
/// `PageGpu::word` of a page that is not in the pool.
pub const PAGE_NOT_RESIDENT: u32 = 0xffffffff;
/// `Cluster::creator` of a level-0 cluster (the builder's `NO_GROUP`).
pub const NO_GROUP_ID: u32 = 0xffffffff;
/// Cluster flag: vertex references are full u32 words (otherwise u16 offsets from the first
/// vertex of the cluster's page); only before the builder's pagination.
pub const CLUSTER_FLAG_REFS_U32: u32 = 1;
/// Most bytes of one geometry page (the encoded clusters of whole groups; see
/// `src/builder/page.rs`): the unit a `.vgeo` file stores and checks, and the GPU holds per slot.
pub const PAGE_BYTES: u32 = 131072;
/// Words at the start of a cluster's header in its page that culling reads: its box on the mesh's
/// grid (the smallest coordinates, 3 words, then the extents, 2 words; the bounds are
/// `quant_origin + coordinate * quant_step`), `vertex_count | triangle_count << 8 | level << 16 |
/// size_code << 24`, group, creator group (`src/builder/page.rs`); the vertex code follows them.
pub const CLUSTER_CULL_WORDS: u32 = 8;
/// Bits of a grid coordinate (`builder::quantize::POSITION_BITS`). In an encoded cluster's header
/// the bits above them in its smallest x coordinate carry its triangle code's header, the corner
/// offsets' width (`builder::tricode`, [`TRIANGLE_HEAD_BITS`]), then its normals' y components'
/// bit width (`builder::page`).
pub const CLUSTER_COORD_BITS: u32 = 21;
/// Bits of the triangle code's header (the corner offsets' width, at most 8) above
/// [`CLUSTER_COORD_BITS`] in a cluster's smallest x coordinate.
pub const TRIANGLE_HEAD_BITS: u32 = 4;
/// Triangles per word of the triangle code's steps (`builder::tricode`).
pub const TRIANGLE_CODE_BLOCK: u32 = 12;
/// Most DAG levels of a mesh: a cluster's level has 8 bits in its cull words (the builder stops
/// with `BuildError::Stuck` before; a level takes at least a 15 % reduction, so 255 levels would
/// need more than 2^32 triangles).
pub const MAX_CLUSTER_LEVEL: u32 = 255;
/// The size code of a cluster (bits 24-31 of its counts and of its cull words' info word, see
/// `builder::size`) in steps of `1 / CLUSTER_SIZE_STEPS` octave: the edge-length equivalent of
/// its triangles is at most `diagonal * 2^((code - CLUSTER_SIZE_CODE_MAX) / CLUSTER_SIZE_STEPS)`,
/// `diagonal` the length of its bounds' diagonal.
pub const CLUSTER_SIZE_STEPS: u32 = 16;
/// The largest size code: a size equal to the cluster's bounds diagonal.
pub const CLUSTER_SIZE_CODE_MAX: u32 = 255;
/// Default SW/HW split (`FrameSettings::hw_threshold_px`, `--hw-threshold`): a cluster goes to
/// the hardware rasterizer when the edge-length equivalent of its triangles (see
/// `builder::size`), projected at the cluster's nearest point, exceeds this many pixels.
pub const DEFAULT_HW_THRESHOLD_PX: f32 = 64.0;
/// Colours of the `residency` debug view, RGBA8 packed as `r | g << 8 | b << 16 | a << 24` (GLSL
/// `unpackUnorm4x8`; the image holds these bytes exactly). Per drawn cluster, by the pages of the
/// group it would refine into (the group that produced it, `Cluster::creator`): resident (green)
/// when they are resident or the cluster is a leaf (level 0) or its mesh is wholly resident.
pub const RESIDENCY_COLOR_RESIDENT: u32 = 0xff4cb82e;
/// `residency` view: the finer pages are absent and nothing this frame asked for them, but the
/// cut does not want them here (the cluster is fine at this threshold): dark green.
pub const RESIDENCY_COLOR_NOT_NEEDED: u32 = 0xff3c5a23;
/// `residency` view: the finer pages are absent, the cluster is fine here, but the cull asked for
/// one of them this frame (for another instance of the mesh): amber.
pub const RESIDENCY_COLOR_REQUESTED: u32 = 0xff1ebef0;
/// `residency` view: wanted but missing: the cut would refine the cluster at this threshold but
/// the finer pages are not resident (the cull asked for them this frame): the pixel is coarser
/// than the all-resident image. Red.
pub const RESIDENCY_COLOR_MISSING: u32 = 0xff2828dc;
/// Threads of one `lod_cull` workgroup (one instance, or one mesh in the commands phase, each).
pub const LOD_CULL_WORKGROUP_SIZE: u32 = 64;
/// Levels of a discrete-LOD chain (`baseline::lod::LOD_COUNT`): buckets per mesh in `lod_cull`.
pub const LOD_LEVELS: u32 = 8;
/// `lod_cull` push constant `phase`: test every instance (frustum, LOD, previous frame's HZB).
pub const LOD_PHASE_MAIN: u32 = 0;
/// `lod_cull` phase: re-test the instances the main phase deferred against this frame's HZB.
pub const LOD_PHASE_POST: u32 = 1;
/// `lod_cull` phase: one thread per mesh writes its draw commands and draw count from the buckets.
pub const LOD_PHASE_COMMANDS: u32 = 2;
/// `LodViewGpu::flags`: cull instances outside the view frustum.
pub const LOD_FLAG_FRUSTUM: u32 = 1;
/// `LodViewGpu::flags`: HZB occlusion culling (two phases).
pub const LOD_FLAG_OCCLUSION: u32 = 2;
/// `LodViewGpu::flags`: the HZB holds an earlier frame of the same size (`prev_view_proj`):
/// the main phase tests against it; without it every instance in the frustum is drawn first.
pub const LOD_FLAG_HISTORY: u32 = 4;
/// `lod_cull`'s per-instance level readback: the instance is outside the frustum.
pub const LOD_LEVEL_CULLED: u32 = 0xffffffff;
/// `lod_cull`'s per-instance level readback: bit set when the post phase found it occluded.
pub const LOD_LEVEL_OCCLUDED: u32 = 256;
// END SHADER CONSTANTS

// `shade` deals each 16x16 block of its tile to its 16x16 threads.
const _: () = assert!(SHADE_TILE.is_multiple_of(16) && SHADE_TILE >= 16);
// A mesh of at most WALK_CLUSTERS clusters has at most WALK_CLUSTERS + 1 rows (a distinct parent
// error each, and 0) of at most WALK_CLUSTERS clusters: its table always reaches its first level.
const _: () = assert!(
    WALK_CLUSTERS <= TINY_CUT_CLUSTERS && (WALK_CLUSTERS + 1) * WALK_CLUSTERS <= TINY_CUT_ENTRIES
);
const _: () = assert!(2 * HZB_GROUP == 1 << (HZB_HEAD_LEVELS - 1));
// Above a cluster's smallest x coordinate: the triangle code's header (the corner offsets' width,
// at most 8) and the normals' y width (at most 16: 5 bits).
const _: () =
    assert!(8 < 1 << TRIANGLE_HEAD_BITS && CLUSTER_COORD_BITS + TRIANGLE_HEAD_BITS + 5 <= 32);

/// Per-frame uniforms of the classic (brute) path. All positions are camera-relative.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    /// Projection * view rotation (the camera sits at the origin of the camera-relative space).
    pub view_proj: [[f32; 4]; 4],
    /// Direction towards the light, world space, w unused.
    pub light_dir: [f32; 4],
    /// Width, height, 1/width, 1/height.
    pub viewport: [f32; 4],
}
const _: () = assert!(size_of::<FrameUniforms>() == 96);

/// One instance of the classic path: camera-relative model matrix and its normal matrix.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct InstanceGpu {
    pub model: [[f32; 4]; 4],
    /// Inverse-transpose of the model's 3x3 part, as three columns (w unused).
    pub normal_matrix: [[f32; 4]; 3],
    /// Base colour tint (rgb) and material index (w, as float bits are not needed: small ints).
    pub color: [f32; 4],
}
const _: () = assert!(size_of::<InstanceGpu>() == 128);

/// Vertex of the classic paths (`brute`, `lod`): position, normal, UV and global material id
/// (vertices are split so each has one material).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct VertexGpu {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    pub material: u32,
}
const _: () = assert!(size_of::<VertexGpu>() == 36);

/// Per mesh of the vgeo path: where its data starts in the scene's shared buffers.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct MeshGpu {
    /// First cluster / group / BVH node / page ([`PageGpu`]) of the mesh.
    pub cluster_offset: u32,
    pub group_offset: u32,
    pub bvh_offset: u32,
    pub page_offset: u32,
    /// Pages of the mesh, and how many of them (the first) are always resident.
    pub page_count: u32,
    pub resident_pages: u32,
    pub cluster_count: u32,
    /// BVH root node, relative to `bvh_offset` (0 when the mesh has a BVH).
    pub bvh_root: u32,
    /// Position grid: `position = origin + code * step`.
    pub quant_origin: [f32; 3],
    pub quant_step: f32,
    /// Object-space bounding sphere of the whole mesh.
    pub bounds_center: [f32; 3],
    pub bounds_radius: f32,
    /// The DAG's root cluster, relative to `cluster_offset` (instance-level LOD: when it alone is
    /// fine, `instance_cull` emits it without walking the BVH).
    pub root_cluster: u32,
    /// DAG level of the fallback mesh ([`crate::builder::BuiltMesh::fallback_level`]), drawn
    /// under [`VIEW_FLAG_FALLBACK_CUT`].
    pub fallback_level: u32,
    /// `MESH_STREAM_*`: which optional vertex streams the mesh's pages hold.
    pub streams: u32,
    /// The largest parent error among the mesh's clusters but its [`WALK_CLUSTERS`] largest
    /// (0 when it has no more clusters): when it projects under the threshold on the sphere of
    /// radius `walk_radius` around `bounds_center`, at most that many clusters can be in the cut
    /// and `instance_cull` walks the BVH itself.
    pub walk_error: f32,
    /// As `walk_error` for [`WALK_CLUSTERS_WIDE`] clusters, a group whose members share one
    /// creator counted once (the walk tests them once: `GroupGpu::members_creator`): an
    /// estimate there, not a bound (`scene_gpu::walk_bound`).
    pub walk_error_wide: f32,
    /// Radius around `bounds_center` enclosing every cluster's parent sphere and every BVH
    /// node's LOD sphere.
    pub walk_radius: f32,
    /// Largest magnitude of a normal component code (`builder::quantize::normal_scale`).
    pub normal_scale: f32,
    /// The mesh's small-instance cuts in the scene's tiny-cut words
    /// ([`crate::builder::cut::TinyCuts::words`]): `instance_cull` draws an instance whose cut
    /// is one of them without walking its BVH.
    pub tiny_offset: u32,
}

/// Where one page of a mesh lies in the scene's geometry pool: the pool word where its encoded
/// bytes start (`src/builder/page.rs`), or [`PAGE_NOT_RESIDENT`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct PageGpu {
    pub word: u32,
}
const _: () = assert!(size_of::<PageGpu>() == 4);

/// Where a cluster lies: its page (in its mesh's page table) and the word of its data in the page
/// ([`crate::builder::Cluster::page`], `data_offset`). The only per-cluster data that stays
/// resident: the rest (bounds, counts, level, groups, vertices, triangles) is read from the page
/// (`src/builder/page.rs`, `shaders_glsl/common/raster.glsl` `cluster_at`), its LOD pairs from its
/// groups.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct ClusterLocGpu {
    pub page: u32,
    pub data_offset: u32,
}
const _: () = assert!(size_of::<ClusterLocGpu>() == 8);

const _: () = assert!(size_of::<MeshGpu>() == 96);

/// A DAG group as the cull reads it (`builder::Group` without the bounds, which only the CPU
/// uses, and with its coverage part: `BuiltMesh::group_coverage_of`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GroupGpu {
    pub lod_sphere: [f32; 4],
    pub error: f32,
    /// The coverage part of `error` (at most it): what a small instance counts whole.
    pub coverage: f32,
    pub first_cluster: u32,
    pub cluster_count: u32,
    pub iteration: u32,
    pub page_first: u32,
    pub page_count: u32,
    /// The creator group of every member when they have one and the same ([`NO_GROUP_ID`]
    /// otherwise): the walk then tests the members' LOD error once for all of them (a group of
    /// a whole-mesh level, whose members are the whole level below, all too coarse but one).
    pub members_creator: u32,
}
const _: () = assert!(size_of::<GroupGpu>() == 48);

/// One instance of the vgeo path. The translation is split into high and low f32 parts so that
/// camera-relative positions are exact for scenes far from the origin.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct InstanceVgeo {
    /// Columns of the 3x3 linear part (w unused).
    pub linear: [[f32; 4]; 3],
    pub translation_hi: [f32; 3],
    pub mesh: u32,
    pub translation_lo: [f32; 3],
    /// Largest axis scale of `linear` (scales errors and radii).
    pub max_scale: f32,
    /// Albedo tint (rgb).
    pub color: [f32; 3],
    /// First visible-list slot of this instance when slots are assigned directly
    /// ([`VIEW_FLAG_DIRECT_VISIBLE`]): slot = `visible_base` + the cluster's index in its mesh.
    pub visible_base: u32,
}
const _: () = assert!(size_of::<InstanceVgeo>() == 96);

/// Per-frame view of the vgeo path.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ViewGpu {
    /// Projection * view rotation, applied to camera-relative positions.
    pub view_proj: [[f32; 4]; 4],
    /// Frustum planes (camera-relative; inside: `dot(n, p) + d >= 0`): left, right, top, bottom, near.
    pub frustum: [[f32; 4]; 5],
    /// Camera position split into high and low f32 parts (w unused).
    pub camera_hi: [f32; 4],
    pub camera_lo: [f32; 4],
    /// Width, height, 1/width, 1/height.
    pub viewport: [f32; 4],
    /// `height / (2 tan(fov_y / 2))`: pixels per unit of error at distance 1.
    pub proj_scale: f32,
    /// LOD threshold in pixels.
    pub error_px: f32,
    /// The SW/HW split: clusters whose triangles' projected edge-length equivalent exceeds this
    /// many pixels go to the HW rasterizer (`common/cull.glsl::emit_cluster`).
    pub hw_threshold_px: f32,
    pub near: f32,
    pub instance_count: u32,
    /// `VIEW_FLAG_*`.
    pub flags: u32,
    /// Capacity of the cull work queue (items) and of the visible-cluster list.
    pub queue_capacity: u32,
    pub visible_capacity: u32,
}
const _: () = assert!(size_of::<ViewGpu>() == 224);

/// Counters and indirect arguments written by the culling passes (read back for `--stats`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct CullCounters {
    /// Work queue: next item to pop, next slot to push, items pushed but not yet processed.
    pub queue_head: u32,
    pub queue_tail: u32,
    pub outstanding: u32,
    /// `cluster_cull` workgroups that have finished (the last one writes the indirect arguments).
    pub finished_workgroups: u32,
    pub instances_tested: u32,
    pub instances_visible: u32,
    pub nodes_visited: u32,
    pub clusters_tested: u32,
    /// Entries of the visible-cluster list, and how many of them go to each rasterizer.
    /// `sw_count` counts every SW cluster once the phase's cull is done; while it runs, only
    /// those at the front of the SW list (the last `cluster_cull` workgroup adds the small ones).
    pub visible_count: u32,
    pub sw_count: u32,
    pub hw_count: u32,
    pub triangles: u32,
    /// Items or clusters dropped because a capacity was exceeded (reported, never silent).
    pub queue_overflow: u32,
    pub visible_overflow: u32,
    /// Non-zero when a `cluster_cull` workgroup hit its watchdog (a bug: reported as an error).
    pub watchdog: u32,
    /// Walks `instance_cull` made itself (`MeshGpu::walk_error`): visible small instances, and in
    /// the post phase the deferred BVH nodes of small instances.
    pub local_walks: u32,
    /// `vkCmdDispatchIndirect` arguments of `raster_sw` (x, y, z) + pad.
    pub sw_dispatch: [u32; 4],
    /// `vkCmdDrawIndirect` arguments of `raster_hw` (vertices, instances, first vertex, first instance).
    pub hw_draw: [u32; 4],
    /// Main phase: instances, BVH-node items and clusters the previous frame's HZB rejected; they
    /// wait for the post phase (two-pass occlusion culling).
    pub post_instance_count: u32,
    pub post_node_count: u32,
    pub post_cluster_count: u32,
    /// Post phase: what the current HZB rejected for good.
    pub occluded_instances: u32,
    pub occluded_nodes: u32,
    pub occluded_clusters: u32,
    /// `vkCmdDrawMeshTasksIndirectEXT` arguments of `raster_hw`'s mesh path (workgroups x, y, z:
    /// rows of [`MESH_GROUPS_X`]), then the number of HW-list clusters they draw (the workgroups
    /// of the last row beyond it draw nothing).
    pub hw_mesh: [u32; 4],
    /// With [`VIEW_FLAG_HW_MESH`]: HW clusters beyond [`MESH_MAX_CLUSTERS`], not drawn (reported).
    pub hw_overflow: u32,
    /// Statistic: instances drawn with a cut from their mesh's small-instance table
    /// (`emit_tiny_cut`, no BVH walk).
    pub tiny_cuts: u32,
    /// SW clusters whose bounds project to at most [`RASTER_SW_SMALL_PX`] across, with triangles
    /// of at most [`RASTER_SW_SMALL_TRIANGLE_PX`] and at most [`RASTER_SW_SMALL_VERTICES`] (but
    /// more than [`RASTER_SW_QUARTER_VERTICES`]: `sw_quarter_count`): the last
    /// `sw_small_count` entries of the SW list, from its end backwards (`raster_sw` draws two at
    /// a time in a workgroup; `sw_dispatch[3]` holds how many workgroups take them).
    pub sw_small_count: u32,
    /// `vkCmdDispatchIndirect` arguments of the post phase's `depth_pyramid` (x, y, z) + pad: its
    /// workgroups when the phase drew anything, else none (the visibility buffer, and so the
    /// HZB, are what the main phase left).
    pub hzb_dispatch: [u32; 4],
    /// Small SW clusters of at most [`RASTER_SW_QUARTER_VERTICES`]: the last `sw_quarter_count`
    /// entries of the HW list, from its end backwards (`raster_sw` draws four at a time in a
    /// workgroup, in the `sw_quarter_groups` workgroups after the small ones). Not in
    /// `sw_small_count`; in `sw_count` once the phase's cull is done.
    pub sw_quarter_count: u32,
    /// `raster_sw` workgroups that take the `sw_quarter_count` clusters (four at a time, after
    /// the `sw_dispatch[3]` that take the small ones).
    pub sw_quarter_groups: u32,
    /// [`VIEW_FLAG_COLD_FRAME`] (main phase): the farthest distance bin the main phase draws
    /// (`occluder_select`'s last workgroup writes it from `cold_area`).
    pub cold_cutoff: u32,
    /// [`VIEW_FLAG_COLD_FRAME`] (main phase): how many `occluder_select` workgroups have added
    /// their sums to `cold_area` (the last one picks `cold_cutoff`); 0 in other frames.
    pub cold_groups_done: u32,
    /// Main phase: `vkCmdDispatchIndirect` arguments (x, y, z) of the post phase's
    /// `instance_cull`, a thread per item the main phase deferred ([`post_dispatch_args`]; the
    /// main phase's last `cluster_cull` workgroup writes them). A dispatch by the instance count
    /// gave a view of few instances one or two workgroups for hundreds of deferred clusters.
    /// Three words, no pad (448 bytes). A 16-byte pad (452) was suspected of slowing stress
    /// N=100 by moving the buffers after the counters; the H200 timed both alike, and aligns
    /// storage buffers to 16 bytes (bench/results/2026-11-28-session42, call 1).
    pub post_dispatch: [u32; 3],
    /// [`VIEW_FLAG_COLD_FRAME`] (main phase): the projected area of the instances in the frustum
    /// (their bounding spheres' discs at their nearest point, at most the screen each), in
    /// 1 / [`COLD_AREA_SCALE`] pixel, by distance bin ([`COLD_DEPTH_BINS`]); 64-bit sums as (low,
    /// high) words, written by `occluder_select` and read by `instance_cull`.
    pub cold_area: [[u32; 2]; COLD_DEPTH_BINS as usize],
}
const _: () = assert!(size_of::<CullCounters>() == 448);
const _: () = assert!(std::mem::offset_of!(CullCounters, hw_mesh) % 4 == 0);

/// [`CullCounters::post_dispatch`] for what the main phase deferred (`counters`: its counters
/// once its cull is done) in a view of the given capacities, as `cluster_cull` writes it: a
/// thread per deferred instance, BVH-node item (at most `queue_capacity`) and cluster (at most
/// `visible_capacity`), in rows of at most 65,535 workgroups.
pub fn post_dispatch_args(
    counters: &CullCounters,
    queue_capacity: u32,
    visible_capacity: u32,
) -> [u32; 3] {
    let items = counters.post_instance_count
        + counters.post_node_count.min(queue_capacity)
        + counters.post_cluster_count.min(visible_capacity);
    compute_grid(items.div_ceil(INSTANCE_CULL_WORKGROUP_SIZE))
}

/// A dispatch of `groups` workgroups as (x, y, z): rows of at most [`COMPUTE_GROUPS_X`], at least
/// one row (`[0, 1, 1]` for none).
pub fn compute_grid(groups: u32) -> [u32; 3] {
    [
        groups.min(COMPUTE_GROUPS_X),
        groups.div_ceil(COMPUTE_GROUPS_X).max(1),
        1,
    ]
}

/// [`CullCounters::hw_mesh`] for `clusters` HW clusters, as `cluster_cull` writes it: rows of
/// [`MESH_GROUPS_X`] workgroups, at most [`MESH_MAX_CLUSTERS`] clusters.
pub fn hw_mesh_args(clusters: u32) -> [u32; 4] {
    let n = clusters.min(MESH_MAX_CLUSTERS);
    let x = n.min(MESH_GROUPS_X);
    let y = n.div_ceil(MESH_GROUPS_X);
    [x, y, 1, n]
}

/// The HZB an occlusion test reads, and the view it was built from. The main phase tests against
/// the previous frame's HZB (with that frame's view), the post phase against this frame's.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct OcclusionGpu {
    /// Camera-relative view-projection of the frame that built the HZB.
    pub view_proj: [[f32; 4]; 4],
    pub camera_hi: [f32; 4],
    pub camera_lo: [f32; 4],
    /// Width and height of that frame (the HZB's level 0 is half of it), unused, unused.
    pub viewport: [f32; 4],
    pub near: f32,
    /// Levels in the HZB buffer.
    pub levels: u32,
    /// 0: no HZB (first frame or occlusion off): nothing is occluded.
    pub enabled: u32,
    pub _pad: u32,
}
const _: () = assert!(size_of::<OcclusionGpu>() == 128);

/// One mesh of the GPU-driven `lod` baseline: what `lod_cull` needs to pick and draw a level.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LodMeshGpu {
    /// Object-space bounding sphere: centre xyz, radius w.
    pub sphere: [f32; 4],
    /// Object-space error per level (non-decreasing, 0 for level 0).
    pub errors: [f32; LOD_LEVELS as usize],
    /// The coverage part of each level's error (`LodChain::coverages`).
    pub coverages: [f32; LOD_LEVELS as usize],
    /// Per level, (first index, index count) in the mesh's index buffer.
    pub ranges: [[u32; 2]; LOD_LEVELS as usize],
    /// Object-space bounding box.
    pub bounds_min: [f32; 3],
    /// 1: the mesh is a closed solid (`LodChain::closed_solid`): an instance seen from outside
    /// its box is drawn with the faces turned away culled.
    pub closed_solid: u32,
    pub bounds_max: [f32; 3],
    pub _pad: u32,
}
const _: () = assert!(size_of::<LodMeshGpu>() == 176);

/// Per-frame view of `lod_cull`. Positions are camera-relative (the instances' model matrices are).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LodViewGpu {
    /// This frame's projection * view rotation (the post phase's HZB test).
    pub view_proj: [[f32; 4]; 4],
    /// Frustum planes (left, right, bottom, top, near; inside: `dot(n, p) + d >= 0`).
    pub frustum: [[f32; 4]; 5],
    /// The view the HZB was built with (main phase, with [`LOD_FLAG_HISTORY`]).
    pub prev_view_proj: [[f32; 4]; 4],
    /// This camera's position minus that view's (xyz; w unused): a camera-relative point of this
    /// frame plus it is relative to the earlier camera.
    pub prev_delta: [f32; 4],
    /// Width, height, 1/width, 1/height (of the frame and of the HZB's source).
    pub viewport: [f32; 4],
    /// `height / (2 tan(fov_y / 2))`.
    pub proj_scale: f32,
    /// LOD threshold in pixels (`error_px * lod_bias`; 0: level 0 everywhere).
    pub tau: f32,
    pub near: f32,
    pub instance_count: u32,
    pub mesh_count: u32,
    /// `LOD_FLAG_*`.
    pub flags: u32,
    /// Levels in the HZB buffer.
    pub hzb_levels: u32,
    pub _pad: u32,
}
const _: () = assert!(size_of::<LodViewGpu>() == 272);

/// `VkDrawIndexedIndirectCommand`, as `lod_cull` writes it per (mesh, level) bucket.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct LodDrawGpu {
    pub index_count: u32,
    pub instance_count: u32,
    pub first_index: u32,
    pub vertex_offset: i32,
    pub first_instance: u32,
}
const _: () = assert!(size_of::<LodDrawGpu>() == 20);

/// Counters of one `lod` frame (read back: `LodStats`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct LodStatsGpu {
    /// Instances outside the frustum.
    pub frustum_culled: u32,
    /// Instances drawn by the main phase.
    pub drawn_main: u32,
    /// Instances the previous frame's HZB rejected in the main phase (the post phase's list).
    pub post_count: u32,
    /// Of those, drawn by the post phase, and occluded for good.
    pub drawn_post: u32,
    pub occluded: u32,
    /// Instances drawn with the faces turned away culled (both phases).
    pub cull_back: u32,
    /// Triangles drawn (both phases).
    pub triangles: u64,
}
const _: () = assert!(size_of::<LodStatsGpu>() == 32);

#[cfg(test)]
mod tests {
    use super::*;

    /// The post phase's `instance_cull` gets a thread per deferred item (at most the
    /// capacities' worth), none when nothing was deferred, in rows within the limit.
    #[test]
    fn post_dispatch_args_take_a_thread_per_deferred_item() {
        let deferred = |instances: u32, nodes: u32, clusters: u32| CullCounters {
            post_instance_count: instances,
            post_node_count: nodes,
            post_cluster_count: clusters,
            ..Zeroable::zeroed()
        };
        let (queue, visible) = (1 << 20, 1 << 20);
        assert_eq!(
            post_dispatch_args(&deferred(0, 0, 0), queue, visible),
            [0, 1, 1]
        );
        // Outdoor's 887 deferred clusters and 5 nodes: 14 workgroups (its 91 instances gave 2).
        assert_eq!(
            post_dispatch_args(&deferred(0, 5, 887), queue, visible),
            [14, 1, 1]
        );
        // Items past the capacities count at the capacities.
        assert_eq!(
            post_dispatch_args(&deferred(3, 1 << 21, 1 << 21), queue, visible),
            [32769, 1, 1]
        );
        // 8 M deferred instances: rows of 65,535 workgroups covering every one.
        let big = post_dispatch_args(&deferred(8_000_000, 0, 0), queue, visible);
        assert_eq!(big, [65535, 2, 1]);
        assert!(big[0] * big[1] * INSTANCE_CULL_WORKGROUP_SIZE >= 8_000_000);
    }

    /// The mesh path's workgroup grid covers every HW cluster up to the limit, in rows of
    /// `MESH_GROUPS_X`, within the specification's minimum limits.
    #[test]
    fn hw_mesh_args_cover_the_list_within_the_limits() {
        assert_eq!(hw_mesh_args(0), [0, 0, 1, 0]);
        assert_eq!(hw_mesh_args(1), [1, 1, 1, 1]);
        assert_eq!(
            hw_mesh_args(MESH_GROUPS_X),
            [MESH_GROUPS_X, 1, 1, MESH_GROUPS_X]
        );
        assert_eq!(
            hw_mesh_args(MESH_GROUPS_X + 1),
            [MESH_GROUPS_X, 2, 1, MESH_GROUPS_X + 1]
        );
        let top = hw_mesh_args(u32::MAX);
        assert_eq!(top[3], MESH_MAX_CLUSTERS);
        for n in [
            1,
            1000,
            MESH_GROUPS_X + 7,
            3 * MESH_GROUPS_X,
            MESH_MAX_CLUSTERS,
            u32::MAX,
        ] {
            let [x, y, z, count] = hw_mesh_args(n);
            assert!(x <= 65535 && y <= 65535 && z == 1);
            assert!(x as u64 * y as u64 <= 1 << 22, "{n}: {x} x {y}");
            assert!(x as u64 * y as u64 >= count as u64 && (y - 1) * x < count);
        }
    }
}
