// GPU structs shared with Rust (src/shared.rs); layouts must match byte for byte (scalar layout).
// The constants (SUBPIXEL_BITS, ...) are defined by build.rs from src/shared.rs.
#ifndef VGEO_SHARED_GLSL
#define VGEO_SHARED_GLSL

#extension GL_EXT_scalar_block_layout : require

struct FrameUniforms {
    mat4 view_proj;
    vec4 light_dir;
    vec4 viewport;
};

struct InstanceGpu {
    mat4 model;
    vec4 normal_matrix[3];
    vec4 color;
};

struct MeshGpu {
    uint cluster_offset;
    uint group_offset;
    uint bvh_offset;
    uint page_offset;  // first PageGpu of the mesh
    uint page_count;
    uint resident_pages;
    uint cluster_count;
    uint bvh_root;
    vec3 quant_origin;
    float quant_step;
    vec3 bounds_center;
    float bounds_radius;
    uint root_cluster;
    uint fallback_level;
    uint streams;  // MESH_STREAM_*
    float walk_error;  // instance_cull walks the BVH itself below this (see src/shared.rs)
    float walk_error_wide;  // the same for WALK_CLUSTERS_WIDE, with WALK_WIDE_INSTANCES instances
    float walk_radius;
    float normal_scale;  // largest normal component code (src/builder/quantize.rs normal_scale)
    uint tiny_offset;    // the mesh's small-instance cuts in tiny_cuts[] (builder/cut.rs TinyCuts)
};

// Where a page lies in the geometry pool (src/shared.rs PageGpu): the pool word of its encoded
// bytes (src/builder/page.rs), or PAGE_NOT_RESIDENT.
struct PageGpu {
    uint word;
};

struct InstanceVgeo {
    vec4 linear[3];
    vec3 translation_hi;
    uint mesh;
    vec3 translation_lo;
    float max_scale;
    vec3 color;
    uint visible_base;
};

struct ViewGpu {
    mat4 view_proj;
    vec4 frustum[5];
    vec4 camera_hi;
    vec4 camera_lo;
    vec4 viewport;
    float proj_scale;
    float error_px;
    float hw_threshold_px;
    float near;
    uint instance_count;
    uint flags;
    uint queue_capacity;
    uint visible_capacity;
};

struct CullCounters {
    uint queue_head;
    uint queue_tail;
    uint outstanding;
    uint finished_workgroups;
    uint instances_tested;
    uint instances_visible;
    uint nodes_visited;
    uint clusters_tested;
    uint visible_count;
    uint sw_count;
    uint hw_count;
    uint triangles;
    uint queue_overflow;
    uint visible_overflow;
    uint watchdog;
    uint local_walks;
    uvec4 sw_dispatch;
    uvec4 hw_draw;
    uint post_instance_count;
    uint post_node_count;
    uint post_cluster_count;
    uint occluded_instances;
    uint occluded_nodes;
    uint occluded_clusters;
    uvec4 hw_mesh;
    uint hw_overflow;
    uint tiny_cuts;
    uint sw_small_count;
    uvec4 hzb_dispatch;
    uint sw_quarter_count;
    uint sw_quarter_groups;
    uint cold_cutoff;
    uint cold_groups_done;
    uvec3 post_dispatch;
    uvec2 cold_area[COLD_DEPTH_BINS];
};

struct OcclusionGpu {
    mat4 view_proj;
    vec4 camera_hi;
    vec4 camera_lo;
    vec4 viewport;
    float near;
    uint levels;
    uint enabled;
    uint _pad;
};

// A cluster as the passes use it: read from the pool word a visible-list entry holds (`cluster_at`,
// common/cluster.glsl). Its LOD pairs are not here: they are its groups' (common/cull.glsl).
struct Cluster {
    uint word;  // pool word of the cluster's encoded data
    uint counts;  // vertex_count | triangle_count << 8
    uint group;
    uint creator;
    uint level;
};

// Where a cluster lies (ClusterLocGpu in src/shared.rs): the only per-cluster data kept resident.
struct ClusterLoc {
    uint page;
    uint data_offset;
};

// A DAG group as the cull reads it (GroupGpu in src/shared.rs: builder::Group without its bounds,
// with its coverage part).
struct Group {
    vec4 lod_sphere;
    float error;
    float coverage;
    uint first_cluster;
    uint cluster_count;
    uint iteration;
    uint page_first;
    uint page_count;
    uint members_creator;  // every member's creator group when they share one, else NO_GROUP_ID
};

// Builder structs (src/builder/mod.rs), as stored in the .vgeo file (a BVH node's
// max_parent_coverage recomputed at load: src/format.rs).
struct BvhNode {
    vec3 bounds_min;
    float max_parent_error;
    vec3 bounds_max;
    uint flags;
    vec4 lod_sphere;
    uint first;
    uint count;
    float max_parent_coverage;
    uint _pad;
};

// A decoded vertex of a page (positions and normals are separate streams in the pool).
// A cluster vertex as decoded from its page (src/builder/page.rs).
struct PackedVertex {
    uvec3 position;  // grid coordinates on the mesh grid (21 bits each)
    uint normal;     // octahedral, 2 x 16 bits
};

// The GPU-driven `lod` baseline (src/shared.rs LodMeshGpu, LodViewGpu, LodDrawGpu; LodStatsGpu,
// which holds a uint64_t, is declared in lod_cull.comp.glsl, the one shader with int64 types).
struct LodMeshGpu {
    vec4 sphere;
    float errors[LOD_LEVELS];
    float coverages[LOD_LEVELS];
    uvec2 ranges[LOD_LEVELS];
    vec3 bounds_min;
    uint closed_solid;
    vec3 bounds_max;
    uint _pad;
};

struct LodViewGpu {
    mat4 view_proj;
    vec4 frustum[5];
    mat4 prev_view_proj;
    vec4 prev_delta;
    vec4 viewport;
    float proj_scale;
    float tau;
    float near;
    uint instance_count;
    uint mesh_count;
    uint flags;
    uint hzb_levels;
    uint _pad;
};

struct LodDrawGpu {
    uint index_count;
    uint instance_count;
    uint first_index;
    int vertex_offset;
    uint first_instance;
};

#endif
