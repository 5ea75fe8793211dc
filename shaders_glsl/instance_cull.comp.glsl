#version 460
// Pass `instance_cull`.
// Main phase: a thread per instance; frustum test of the mesh's bounding sphere, in a frame
// without a previous HZB the distance (occluder_select's cutoff: farther instances wait for the
// post phase), then the previous frame's HZB: visible instances whose cut is in their mesh's
// table of small-instance cuts emit it directly (emit_tiny_cut, cull.glsl), as do those whose
// whole cut is the DAG's root cluster (instance-level LOD), small ones walk their BVH here
// (walk_or_push_item), the others push their BVH root into cluster_cull's queue; occluded ones
// wait in `post_instances` for the post phase.
// Post phase: grid-stride over what the main phase deferred: instances (tested against this frame's
// HZB, walked or pushed if visible), BVH-node items (walked here for small instances, else pushed
// back: cluster_cull tests them again) and clusters
// (tested against this frame's HZB, emitted if visible).
// The `shared` variant (views of WALK_WIDE_INSTANCES to SHARED_RUNS_MAX_INSTANCES instances,
// chosen by src/passes/instance_cull.rs): the workgroup shares its threads' cluster tests
// (cull.glsl's shared runs); the plain one has no shared memory but s_cold_cutoff.
//! variant shared CULL_SHARED_RUNS
#include "cull_bindings.glsl"

layout(local_size_x = INSTANCE_CULL_WORKGROUP_SIZE) in;

// VIEW_FLAG_COLD_FRAME (main phase): the farthest distance bin drawn now (occluder_select's
// CullCounters::cold_cutoff, read once per workgroup).
shared uint s_cold_cutoff;

// Whether instance `i` is visible: the frustum test of its mesh's bounding sphere (main phase
// only: the post phase retests instances the frustum already passed), then the HZB test of its
// mesh's box (occluded in the main phase: deferred to the post phase; in the post phase: rejected
// for good).
bool instance_visible(uint i, InstanceVgeo inst, MeshGpu mesh) {
    CULL_STAT(instances_tested, 1u)
    if (pc.phase == 0u) {
        vec3 c;
        float r;
        instance_sphere(inst, mesh, c, r);
        if (frustum_rejects(c, r)) {
            return false;
        }
        // No previous HZB: only the nearest instances now, the rest tested by the post phase
        // against what they drew.
        if ((view.flags & VIEW_FLAG_COLD_FRAME) != 0u && cold_bin(c, r) > s_cold_cutoff) {
            post_instances[atomicAdd(counters.post_instance_count, 1u)] = i;
            return false;
        }
    }
    // The HZB by the mesh's box (its BVH root's), not the cube around its sphere: a long thin
    // mesh's cube projects to several times its box (stress N=200: 5.2 -> 4.2 M instances pass).
    BvhNode root = bvh[mesh.bvh_offset + mesh.bvh_root];
    if (hzb_occluded(inst, root.bounds_min, root.bounds_max)) {
        if (pc.phase == 0u) {
            post_instances[atomicAdd(counters.post_instance_count, 1u)] = i;
        } else {
            CULL_STAT(occluded_instances, 1u)
        }
        return false;
    }
    CULL_STAT(instances_visible, 1u)
    return true;
}

// One work item of a phase, with one call site per kind of work. The driver inlines every call:
// a site per phase and kind (the local walk and the cut's tests copied into each) made the H100's
// binary 406 KB of 128 registers, where one site each makes it 130 KB of 96 (stress N=20 0.95 ->
// 0.90 ms, N=200 -1 %, the same images: bench/results/2026-11-27-session27, call 1). Main phase:
// item j is instance j. Post phase: the deferred instances, then the deferred BVH-node items,
// then the deferred clusters, as one index range.
void cull_item(uint j, uint n_inst, uint n_nodes) {
    uint64_t item;
    if (j < n_inst) {
        uint i = pc.phase == 0u ? j : post_instances[j];
        InstanceVgeo inst = instances[i];
        MeshGpu mesh = meshes[inst.mesh];
        if (!instance_visible(i, inst, mesh) || emit_tiny_cut(i, inst, mesh)
            || emit_root_if_whole_cut(i, inst, mesh)) {
            return;
        }
        item = (uint64_t(i) << 32) | uint64_t(mesh.bvh_offset + mesh.bvh_root);
    } else if (j < n_inst + n_nodes) {
        item = post_nodes[j - n_inst];
    } else {
        uvec2 e = post_clusters[j - n_inst - n_nodes];
        InstanceVgeo inst = instances[e.x];
        MeshGpu mesh = meshes[inst.mesh];
        uint at = cluster_word(mesh, e.y);
        vec3 bmin = cluster_bounds_min(mesh, at);
        vec3 bmax = cluster_bounds_max(mesh, at);
        if (hzb_occluded(inst, bmin, bmax)) {
            CULL_STAT(occluded_clusters, 1u)
            return;
        }
        vec3 cc;
        float cr;
        box_sphere(inst, bmin, bmax, cc, cr);
        emit_cluster(e.x, e.y, at, cluster_info(at), cc, cr);
        return;
    }
    InstanceVgeo inst = instances[uint(item >> 32)];
    walk_or_push_item(item, inst, meshes[inst.mesh]);
}

// The shared variant takes the items that may leave runs in rounds of a workgroup-uniform loop
// (a grid-stride loop whose trip count is the workgroup's): in each, every thread takes one item
// (cull_item), then the workgroup tests and draws the clusters of the runs they left
// (run_round).
void main() {
    uint lid = gl_LocalInvocationID.x;
    uint threads = gl_NumWorkGroups.x * gl_NumWorkGroups.y * INSTANCE_CULL_WORKGROUP_SIZE;
    uint base = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * INSTANCE_CULL_WORKGROUP_SIZE;
#ifdef CULL_SHARED_RUNS
    s_thread_runs[lid] = 0u;
#endif
    if (pc.phase == 0u && (view.flags & VIEW_FLAG_COLD_FRAME) != 0u) {
        if (lid == 0u) {
            s_cold_cutoff = counters.cold_cutoff;
        }
        barrier();
    }
    uint n_inst;
    uint n_nodes = 0u;
    uint n_clusters = 0u;
    if (pc.phase == 0u) {
        n_inst = view.instance_count;
    } else {
        n_inst = main_counters.post_instance_count;
        n_nodes = min(main_counters.post_node_count, view.queue_capacity);
        n_clusters = min(main_counters.post_cluster_count, view.visible_capacity);
    }
    uint total = n_inst + n_nodes + n_clusters;
#ifdef CULL_SHARED_RUNS
    // Instances and BVH-node items may leave runs: rounds. The post phase's deferred clusters
    // leave none: a plain grid-stride loop after them (rounds over them paid the barriers for
    // nothing).
    uint with_runs = n_inst + n_nodes;
    for (uint b = base; b < with_runs; b += threads) {
        if (b + lid < with_runs) {
            cull_item(b + lid, n_inst, n_nodes);
        }
        run_round();
    }
    for (uint j = with_runs + base + lid; j < total; j += threads) {
        cull_item(j, n_inst, n_nodes);
    }
#else
    // The plain variant: a grid-stride loop, a thread leaving when its items are done.
    for (uint j = base + lid; j < total; j += threads) {
        cull_item(j, n_inst, n_nodes);
    }
#endif
}
