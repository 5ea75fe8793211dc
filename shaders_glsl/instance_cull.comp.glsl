#version 460
// Pass `instance_cull`.
// Main phase: a thread per instance; frustum test of the mesh's bounding sphere, then the previous
// frame's HZB: visible instances whose cut is in their mesh's table of small-instance cuts emit
// it directly (emit_tiny_cut, cull.glsl), as do those whose whole cut is the DAG's root cluster
// (instance-level LOD), small ones walk their BVH here (walk_or_push), the others push their BVH
// root into cluster_cull's queue;
// occluded ones wait in `post_instances` for the post phase.
// Post phase: grid-stride over what the main phase deferred: instances (tested against this frame's
// HZB, walked or pushed if visible), BVH-node items (walked here for small instances, else pushed
// back: cluster_cull tests them again) and clusters
// (tested against this frame's HZB, emitted if visible).
#include "cull_bindings.glsl"

layout(local_size_x = INSTANCE_CULL_WORKGROUP_SIZE) in;

void instance_main(uint i) {
    CULL_STAT(instances_tested, 1u)
    InstanceVgeo inst = instances[i];
    MeshGpu mesh = meshes[inst.mesh];
    vec3 c = relative_position(inst, view, mesh.bounds_center);
    float r = mesh.bounds_radius * inst.max_scale;
    if ((view.flags & VIEW_FLAG_NO_FRUSTUM) == 0u && !sphere_in_frustum(view, c, r)) {
        return;
    }
    vec3 rr = vec3(mesh.bounds_radius);
    if (hzb_occluded(inst, mesh.bounds_center - rr, mesh.bounds_center + rr)) {
        post_instances[atomicAdd(counters.post_instance_count, 1u)] = i;
        return;
    }
    CULL_STAT(instances_visible, 1u)
    if (!emit_tiny_cut(i, inst, mesh) && !emit_root_if_whole_cut(i, inst, mesh)) {
        walk_or_push(i, inst, mesh);
    }
}

void main() {
    uint threads = gl_NumWorkGroups.x * gl_NumWorkGroups.y * INSTANCE_CULL_WORKGROUP_SIZE;
    uint gid = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * INSTANCE_CULL_WORKGROUP_SIZE
        + gl_LocalInvocationID.x;
    if (pc.phase == 0u) {
        if (gid < view.instance_count) {
            instance_main(gid);
        }
        return;
    }
    uint n_inst = main_counters.post_instance_count;
    uint n_nodes = min(main_counters.post_node_count, view.queue_capacity);
    uint n_clusters = min(main_counters.post_cluster_count, view.visible_capacity);
    for (uint j = gid; j < n_inst; j += threads) {
        uint i = post_instances[j];
        InstanceVgeo inst = instances[i];
        MeshGpu mesh = meshes[inst.mesh];
        vec3 rr = vec3(mesh.bounds_radius);
        CULL_STAT(instances_tested, 1u)
        if (hzb_occluded(inst, mesh.bounds_center - rr, mesh.bounds_center + rr)) {
            CULL_STAT(occluded_instances, 1u)
            continue;
        }
        CULL_STAT(instances_visible, 1u)
        if (!emit_tiny_cut(i, inst, mesh) && !emit_root_if_whole_cut(i, inst, mesh)) {
            walk_or_push(i, inst, mesh);
        }
    }
    for (uint j = gid; j < n_nodes; j += threads) {
        uint64_t item = post_nodes[j];
        InstanceVgeo inst = instances[uint(item >> 32)];
        walk_or_push_item(item, inst, meshes[inst.mesh]);
    }
    for (uint j = gid; j < n_clusters; j += threads) {
        uvec2 e = post_clusters[j];
        InstanceVgeo inst = instances[e.x];
        uint at = cluster_word(meshes[inst.mesh], e.y);
        vec3 bmin = cluster_bounds_min(at);
        vec3 bmax = cluster_bounds_max(at);
        if (hzb_occluded(inst, bmin, bmax)) {
            CULL_STAT(occluded_clusters, 1u)
            continue;
        }
        vec3 cc = relative_position(inst, view, (bmin + bmax) * 0.5);
        float cr = length(bmax - bmin) * 0.5 * inst.max_scale;
        emit_cluster(e.x, e.y, at, cluster_info(at), cc, cr);
    }
}
