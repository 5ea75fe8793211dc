#version 460
// Pass `cluster_cull`: persistent workgroups over a global queue of (instance, BVH node) items and
// (instance, cluster range) items. Each iteration one lane claims up to CLUSTER_CULL_WORKGROUP_SIZE
// items for the workgroup (shared through shared memory; the loop is workgroup-uniform with
// barriers inside), every lane processes one: frustum and LOD tests of the node, children pushed
// back to the queue; for a leaf the LOD test per group and each group's clusters pushed in ranges
// of CULL_RANGE_CLUSTERS; for a range the cut rule per cluster and an append to the visible list
// and the SW or HW list. The end is detected by
// a counter of outstanding items (pushed but not processed), never by an empty queue alone; a
// watchdog bounds the loop. The last workgroup to finish writes the rasterizers' indirect arguments.
//
// The queue is a bounded array per frame (slots start empty, all ones): a push reserves a slot with
// atomicAdd and publishes the item with an atomic exchange; a consumer waits for the publish. A
// producer never waits, so no lane waits on a lane that cannot run.
#define CULL_RANGE_ITEMS
#include "cull_bindings.glsl"

layout(local_size_x = CLUSTER_CULL_WORKGROUP_SIZE) in;

const uint64_t EMPTY = ~uint64_t(0);

shared uint s_first;
shared uint s_count;
shared uint s_done;

uint load_queue_tail() {
    return min(atomicAdd(counters.queue_tail, 0u), view.queue_capacity);
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
                process_node(item, false);
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
            uint sw_front = atomicAdd(counters.sw_count, 0u);
            uint sw_small = atomicAdd(counters.sw_small_count, 0u);
            uint hw_front = atomicAdd(counters.hw_count, 0u);
            uint sw_quarter = atomicAdd(counters.sw_quarter_count, 0u);
            // What the main phase deferred, read with the others in both phases (only the main
            // phase uses it): this tail is the pass's last work, and reads behind a branch of
            // their own may wait for the first four to return (b8908f4, which read them so,
            // timed the H200's main-phase cluster_cull 0.0059 ms on stress N=100 against 0.0061
            // with the branch: bench/results/2026-11-28-session42, call 1, F and M).
            uint post_items = atomicAdd(counters.post_instance_count, 0u)
                + min(atomicAdd(counters.post_node_count, 0u), view.queue_capacity)
                + min(atomicAdd(counters.post_cluster_count, 0u), view.visible_capacity);
            uint sw = min(sw_front, view.visible_capacity);
            uint small = min(sw_small, view.visible_capacity - sw);
            uint hw = min(hw_front, view.visible_capacity);
            uint quarter = min(sw_quarter, view.visible_capacity - hw);
            // The two ends of a list meet only if a cluster was emitted twice under direct
            // visible slots (never, by the cut's rule): reported, never silent.
            if (sw_front + sw_small > view.visible_capacity) {
                atomicAdd(counters.visible_overflow, sw_front + sw_small - view.visible_capacity);
            }
            if (hw_front + sw_quarter > view.visible_capacity) {
                atomicAdd(counters.visible_overflow, hw_front + sw_quarter - view.visible_capacity);
            }
            // raster_sw: the first workgroups take the small clusters two at a time (their
            // number in w), the next sw_quarter_groups the quarter ones four at a time, the rest
            // the others (grid-stride loops: at most 65535 workgroups in all); sw_count from here
            // on counts all three.
            uint small_groups = min((small + 1u) / 2u, 16384u);
            uint quarter_groups = min((quarter + 3u) / 4u, 32768u);
            counters.sw_small_count = small;
            counters.sw_quarter_count = quarter;
            counters.sw_quarter_groups = quarter_groups;
            counters.sw_count = sw + small + quarter;
            uint front_groups = min(sw, 65535u - small_groups - quarter_groups);
            counters.sw_dispatch = uvec4(small_groups + quarter_groups + front_groups, 1u, 1u, small_groups);
            counters.hw_draw = uvec4(MAX_CLUSTER_TRIANGLES * 3u, hw, 0u, 0u);
            // The mesh path: rows of MESH_GROUPS_X workgroups (src/shared.rs hw_mesh_args).
            uint hw_mesh = min(hw, MESH_MAX_CLUSTERS);
            counters.hw_mesh = uvec4(min(hw_mesh, MESH_GROUPS_X),
                                     (hw_mesh + MESH_GROUPS_X - 1u) / MESH_GROUPS_X, 1u, hw_mesh);
            if ((view.flags & VIEW_FLAG_HW_MESH) != 0u) {
                counters.hw_overflow = hw - hw_mesh;
            }
            // depth_pyramid's workgroups (tiles of 2 * HZB_GROUP texels of level 0, which is
            // half the frame), none when this phase drew nothing.
            uvec2 level0 = (uvec2(view.viewport.xy) + 1u) / 2u;
            uvec2 groups = (level0 + 2u * HZB_GROUP - 1u) / (2u * HZB_GROUP);
            counters.hzb_dispatch = uvec4(sw + small + quarter + hw > 0u ? groups.x : 0u, groups.y, 1u, 0u);
            // The post phase's instance_cull: a thread per item this phase deferred (src/shared.rs
            // post_dispatch_args), not one per instance (a view of few instances gave a workgroup
            // or two hundreds of deferred clusters each, in turn).
            if (pc.phase == 0u) {
                uint post_groups = (post_items + INSTANCE_CULL_WORKGROUP_SIZE - 1u) / INSTANCE_CULL_WORKGROUP_SIZE;
                counters.post_dispatch = uvec3(min(post_groups, COMPUTE_GROUPS_X),
                                               max((post_groups + COMPUTE_GROUPS_X - 1u) / COMPUTE_GROUPS_X, 1u), 1u);
            }
        }
    }
}
