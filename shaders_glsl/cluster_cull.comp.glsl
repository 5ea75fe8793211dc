#version 460
// Pass `cluster_cull`: persistent workgroups over a global queue of (instance, BVH node) items.
// Each iteration one lane claims up to CLUSTER_CULL_WORKGROUP_SIZE items for the workgroup (shared
// through shared memory; the loop is workgroup-uniform with barriers inside), every lane processes
// one: frustum and LOD tests of the node, children pushed back to the queue, or for a leaf the cut
// rule per cluster and an append to the visible list and the SW or HW list. The end is detected by
// a counter of outstanding items (pushed but not processed), never by an empty queue alone; a
// watchdog bounds the loop. The last workgroup to finish writes the rasterizers' indirect arguments.
//
// The queue is a bounded array per frame (slots start empty, all ones): a push reserves a slot with
// atomicAdd and publishes the item with an atomic exchange; a consumer waits for the publish. A
// producer never waits, so no lane waits on a lane that cannot run.
#include "cull_bindings.glsl"

layout(local_size_x = CLUSTER_CULL_WORKGROUP_SIZE) in;

const uint64_t EMPTY = ~uint64_t(0);

shared uint s_first;
shared uint s_count;
shared uint s_done;

uint load_queue_tail() {
    return min(atomicAdd(counters.queue_tail, 0u), view.queue_capacity);
}

void process(uint64_t item) {
    uint instance = uint(item >> 32);
    uint node_index = uint(item & 0xffffffffu);
    atomicAdd(counters.nodes_visited, 1u);
    InstanceVgeo inst = instances[instance];
    MeshGpu mesh = meshes[inst.mesh];
    BvhNode node = bvh[node_index];
    float scale = inst.max_scale;
    bool frustum = (view.flags & VIEW_FLAG_NO_FRUSTUM) == 0u;

    if (frustum) {
        vec3 bc = relative_position(inst, view, (node.bounds_min + node.bounds_max) * 0.5);
        float br = length(node.bounds_max - node.bounds_min) * 0.5 * scale;
        if (!sphere_in_frustum(view, bc, br)) {
            return;
        }
    }
    // Occlusion: in the main phase against the previous frame's HZB (rejected items wait for the
    // post phase), in the post phase against this frame's (rejected for good).
    if (hzb_occluded(inst, node.bounds_min, node.bounds_max)) {
        if (pc.phase == 0u) {
            uint j = atomicAdd(counters.post_node_count, 1u);
            if (j < view.queue_capacity) {
                post_nodes[j] = item;
            } else {
                atomicAdd(counters.queue_overflow, 1u);
            }
        } else {
            atomicAdd(counters.occluded_nodes, 1u);
        }
        return;
    }
    // No cluster below can be drawn when even the largest parent error is already fine (the
    // fallback cut is by level: every node is walked).
    bool fallback = (view.flags & VIEW_FLAG_FALLBACK_CUT) != 0u;
    vec3 lc = relative_position(inst, view, node.lod_sphere.xyz);
    if (!fallback
        && lod_error_px(node.max_parent_error * scale, lc, node.lod_sphere.w * scale, view.proj_scale) <= view.error_px) {
        return;
    }
    if ((node.flags & BVH_FLAG_LEAF) == 0u) {
        for (uint k = 0u; k < node.count; k++) {
            push_item((uint64_t(instance) << 32) | uint64_t(mesh.bvh_offset + node.first + k));
        }
        return;
    }
    for (uint g = 0u; g < node.count; g++) {
        Group group = groups[mesh.group_offset + node.first + g];
        for (uint k = 0u; k < group.cluster_count; k++) {
            uint ci = mesh.cluster_offset + group.first_cluster + k;
            Cluster cl = clusters[ci];
            atomicAdd(counters.clusters_tested, 1u);
            bool in_cut;
            if (fallback) {
                in_cut = cl.level <= mesh.fallback_level
                    && groups[mesh.group_offset + cl.group].iteration >= mesh.fallback_level;
            } else {
                vec3 sc = relative_position(inst, view, cl.self_sphere.xyz);
                vec3 pcen = relative_position(inst, view, cl.parent_sphere.xyz);
                bool fine = lod_error_px(cl.self_error * scale, sc, cl.self_sphere.w * scale, view.proj_scale) <= view.error_px;
                bool parent_coarse =
                    lod_error_px(cl.parent_error * scale, pcen, cl.parent_sphere.w * scale, view.proj_scale) > view.error_px;
                in_cut = fine && parent_coarse;
            }
            if (!in_cut) {
                continue;
            }
            vec3 cc = relative_position(inst, view, (cl.bounds_min + cl.bounds_max) * 0.5);
            float cr = length(cl.bounds_max - cl.bounds_min) * 0.5 * scale;
            if (frustum && !sphere_in_frustum(view, cc, cr)) {
                continue;
            }
            if (!cluster_occluded(instance, inst, cl, ci)) {
                emit_cluster(instance, ci, cc, cr);
            }
        }
    }
}

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint iterations = 0u;
    for (;;) {
        if (lane == 0u) {
            s_count = 0u;
            s_done = 0u;
            // Claim up to a workgroup's worth of published-or-reserved items.
            uint h = atomicAdd(counters.queue_head, 0u);
            for (uint tries = 0u; tries < 64u; tries++) {
                uint t = load_queue_tail();
                if (h >= t) {
                    break;
                }
                uint k = min(t - h, uint(CLUSTER_CULL_WORKGROUP_SIZE));
                uint prev = atomicCompSwap(counters.queue_head, h, h + k);
                if (prev == h) {
                    s_first = h;
                    s_count = k;
                    break;
                }
                h = prev;
            }
            if (s_count == 0u && atomicAdd(counters.outstanding, 0u) == 0u) {
                s_done = 1u;
            }
            iterations++;
            if (iterations > CLUSTER_CULL_WATCHDOG) {
                atomicOr(counters.watchdog, 1u);
                s_done = 1u;
            }
        }
        barrier();
        memoryBarrierShared();
        if (s_done != 0u) {
            break;
        }
        uint count = s_count;
        uint first = s_first;
        barrier();
        if (lane < count) {
            // Wait for the producer's publish (it reserved the slot and publishes right away).
            uint64_t item = EMPTY;
            for (uint spin = 0u; spin < CLUSTER_CULL_WATCHDOG; spin++) {
                item = atomicExchange(queue[first + lane], EMPTY);
                if (item != EMPTY) {
                    break;
                }
            }
            if (item == EMPTY) {
                atomicOr(counters.watchdog, 2u);
            } else {
                process(item);
            }
            memoryBarrierBuffer();
            atomicAdd(counters.outstanding, 0xffffffffu);
        }
        barrier();
    }
    // The last workgroup to finish writes the rasterizers' indirect arguments.
    if (lane == 0u) {
        memoryBarrierBuffer();
        uint finished = atomicAdd(counters.finished_workgroups, 1u);
        if (finished == gl_NumWorkGroups.x - 1u) {
            uint sw = atomicAdd(counters.sw_count, 0u);
            uint hw = atomicAdd(counters.hw_count, 0u);
            counters.sw_dispatch = uvec4(min(sw, 65535u), 1u, 1u, 0u);
            counters.hw_draw = uvec4(MAX_CLUSTER_TRIANGLES * 3u, hw, 0u, 0u);
        }
    }
}
