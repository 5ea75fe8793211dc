// The descriptor set shared by instance_cull and cluster_cull (one layout for both passes).
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"

layout(set = 0, binding = 0, scalar) uniform View { ViewGpu view; };
layout(set = 0, binding = 1, scalar) readonly buffer Meshes { MeshGpu meshes[]; };
layout(set = 0, binding = 2, scalar) readonly buffer Instances { InstanceVgeo instances[]; };
// This phase's counters; in the post phase `main_counters` holds the main phase's.
layout(set = 0, binding = 3, scalar) coherent buffer Counters { CullCounters counters; };
layout(set = 0, binding = 4) coherent buffer Queue { uint64_t queue[]; };
layout(set = 0, binding = 5, scalar) readonly buffer Bvh { BvhNode bvh[]; };
layout(set = 0, binding = 6, scalar) readonly buffer Groups { Group groups[]; };
layout(set = 0, binding = 7, scalar) readonly buffer Clusters { ClusterLoc cluster_locs[]; };
// (instance, pool word of the cluster's data): common/cluster.glsl.
layout(set = 0, binding = 8) writeonly buffer Visible { uvec2 visible[]; };
layout(set = 0, binding = 9) writeonly buffer SwList { uint sw_list[]; };
layout(set = 0, binding = 10) writeonly buffer HwList { uint hw_list[]; };
layout(set = 0, binding = 11, scalar) uniform Occlusion { OcclusionGpu occ; };
layout(set = 0, binding = 12) readonly buffer Hzb { float hzb[]; };
layout(set = 0, binding = 13, scalar) coherent buffer MainCounters { CullCounters main_counters; };
// Main phase: what the previous frame's HZB rejected, for the post phase to test again.
layout(set = 0, binding = 14) buffer PostInstances { uint post_instances[]; };
layout(set = 0, binding = 15) buffer PostNodes { uint64_t post_nodes[]; };
layout(set = 0, binding = 16) buffer PostClusters { uvec2 post_clusters[]; };
// Geometry pages (residency: `word` != PAGE_NOT_RESIDENT), and per page of the scene the
// streaming feedback: the largest wish to refine into it this frame (projected error over the
// threshold, as float bits), and whether a drawn cluster used it.
layout(set = 0, binding = 17, scalar) readonly buffer Pages { PageGpu pages[]; };
layout(set = 0, binding = 18) buffer PageRequests { uint page_requests[]; };
layout(set = 0, binding = 19) buffer PageUsage { uint page_usage[]; };
// The geometry pool: the resident pages' bytes (a cluster's cull words are read from its page).
layout(set = 0, binding = 20) readonly buffer Pool { uint pool[]; };
// The meshes' small-instance cut tables (MeshGpu::tiny_offset; src/builder/cut.rs TinyCuts::words).
layout(set = 0, binding = 21) readonly buffer TinyCutTables { uint tiny_cuts[]; };

// 0: main phase (test against the previous frame's HZB, defer what it rejects);
// 1: post phase (retest what was deferred against this frame's HZB).
layout(push_constant) uniform Phase { uint phase; } pc;

#include "cluster.glsl"
#include "cull.glsl"
