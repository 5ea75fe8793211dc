#version 460
// Pass `occluder_select`: in a frame without a previous HZB (VIEW_FLAG_COLD_FRAME), before the
// main phase's instance_cull, the projected area of the instances in the frustum summed by
// distance (CullCounters::cold_area; src/shared.rs COLD_DEPTH_BINS says why), and from it the
// farthest bin the main phase draws (cold_cutoff): instance_cull's main phase draws only the
// nearest instances and defers the rest to the post phase, which tests them against the HZB of
// what the main phase drew.
// At most OCCLUDER_SELECT_GROUPS workgroups, each summing its share of the instances in shared
// memory and adding its bins once: the sums go to few words.
#include "cull_bindings.glsl"

layout(local_size_x = INSTANCE_CULL_WORKGROUP_SIZE) in;

// This workgroup's sums: (low, high) words per bin.
shared uint s_area[COLD_DEPTH_BINS][2];
shared bool s_last;

// Adds `units` to the 64-bit sum (low, high): the low word's wrap carries into the high one.
#define ADD64(lo, hi, units) { uint before = atomicAdd(lo, units); if (before + (units) < before) { atomicAdd(hi, 1u); } }

// The farthest bin whose areas, with the nearer bins', reach COLD_OCCLUDER_COVER screens (the last
// bin if they never do).
uint cold_cutoff() {
    float goal = COLD_OCCLUDER_COVER * view.viewport.x * view.viewport.y * COLD_AREA_SCALE;
    float sum = 0.0;
    for (uint b = 0u; b < COLD_DEPTH_BINS; b++) {
        uvec2 a = counters.cold_area[b];
        sum += float(a.x) + float(a.y) * 4294967296.0;
        if (sum >= goal) {
            return b;
        }
    }
    return COLD_DEPTH_BINS - 1u;
}

void main() {
    uint t = gl_LocalInvocationID.x;
    for (uint b = t; b < COLD_DEPTH_BINS; b += INSTANCE_CULL_WORKGROUP_SIZE) {
        s_area[b][0] = 0u;
        s_area[b][1] = 0u;
    }
    barrier();
    uint threads = gl_NumWorkGroups.x * INSTANCE_CULL_WORKGROUP_SIZE;
    float screen = view.viewport.x * view.viewport.y;
    for (uint i = gl_GlobalInvocationID.x; i < view.instance_count; i += threads) {
        InstanceVgeo inst = instances[i];
        MeshGpu mesh = meshes[inst.mesh];
        vec3 c;
        float r;
        instance_sphere(inst, mesh, c, r);
        if (frustum_rejects(c, r)) {
            continue;
        }
        // The disc of its bounding sphere at its nearest point, at most the screen (a NaN or
        // infinite size, the camera inside the sphere: the screen), in units that fit 32 bits
        // whatever the screen. A sphere around the camera counts a whole screen, as a wall in
        // front does; four ground tiles or a room's walls around the camera then make bin 0 the
        // cutoff and defer even what stands in front of them: the post phase draws that, a
        // frame's latency later (a cost of speed in that one frame, never of the image).
        // instance_size_px, from the sphere already at hand.
        float px = lod_error_px(r, c, r, view.proj_scale);
        float area = px < 1e6 ? min(3.14159265 * px * px, screen) : screen;
        uint units = uint(min(ceil(area * COLD_AREA_SCALE), 4294967040.0));
        uint bin = cold_bin(c, r);
        ADD64(s_area[bin][0], s_area[bin][1], units)
    }
    barrier();
    for (uint b = t; b < COLD_DEPTH_BINS; b += INSTANCE_CULL_WORKGROUP_SIZE) {
        uint lo = s_area[b][0];
        uint hi = s_area[b][1];
        if (lo != 0u || hi != 0u) {
            ADD64(counters.cold_area[b].x, counters.cold_area[b].y, lo)
            atomicAdd(counters.cold_area[b].y, hi);
        }
    }
    // The last workgroup to add its sums reads them all and writes the cutoff.
    memoryBarrierBuffer();
    barrier();
    if (t == 0u) {
        s_last = atomicAdd(counters.cold_groups_done, 1u) == gl_NumWorkGroups.x - 1u;
    }
    barrier();
    if (s_last && t == 0u) {
        memoryBarrierBuffer();
        counters.cold_cutoff = cold_cutoff();
    }
}
