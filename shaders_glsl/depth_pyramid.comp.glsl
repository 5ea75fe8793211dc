#version 460
// Pass `depth_pyramid`: the hierarchical depth buffer (HZB) in one dispatch, whatever the frame
// size. Each texel keeps the FARTHEST depth below it (reverse-Z: the minimum); empty pixels have
// depth 0, i.e. infinitely far, so they never occlude; texels outside a level's source are neutral
// (1.0). Level 0 is half the frame (see depth_pyramid.rs, hzb_levels).
//
// One dispatch: each workgroup of 16x16 (HZB_GROUP) reduces 32x32 texels of level 0 (64x64 pixels)
// through levels 0..5 (HZB_HEAD_LEVELS) in registers and shared memory (`head`); the last
// workgroup to finish (a counter it resets for the next dispatch) then makes the rest from level
// HZB_HEAD_LEVELS-1, level by level through the buffer (`tail`). One dispatch instead of two saves
// a drain of the GPU between them, and lets the post phase skip the pass with an indirect dispatch
// of no workgroups when it drew nothing (CullCounters::hzb_dispatch).
// Variant `depth` (the GPU-driven `lod` baseline): the source is a depth attachment copied into a
// float buffer (reverse-Z, cleared to 0) instead of the visibility buffer.
//! variant image VISBUFFER_IMAGE
//! variant depth DEPTH_PYRAMID_FROM_DEPTH
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"

layout(local_size_x = HZB_GROUP, local_size_y = HZB_GROUP) in;

#ifdef DEPTH_PYRAMID_FROM_DEPTH
layout(set = 0, binding = 0) readonly buffer Depth { float depth_texels[]; };
#else
#define VISBUFFER_BINDING 0
#define VISBUFFER_READONLY
#include "visbuffer.glsl"
#endif
layout(set = 0, binding = 1) coherent buffer Hzb { float hzb[]; };
// Workgroups of this dispatch that have finished their head (0 between dispatches).
layout(set = 0, binding = 2) coherent buffer Sync { uint finished_groups; };

layout(push_constant) uniform Push {
    uint width;   // the frame
    uint height;
    uint levels;  // levels in the HZB
    uint _pad;
} pc;

shared float s16[16][16];
shared bool s_last;

// Size of level k and the offset of its first texel (levels one after another).
uvec3 level_of(uint k) {
    uint w = (pc.width + 1u) / 2u;
    uint h = (pc.height + 1u) / 2u;
    uint offset = 0u;
    for (uint i = 0u; i < k; i++) {
        offset += w * h;
        w = (w + 1u) / 2u;
        h = (h + 1u) / 2u;
    }
    return uvec3(max(w, 1u), max(h, 1u), offset);
}

float pixel_depth(uint x, uint y) {
    if (x >= pc.width || y >= pc.height) {
        return 1.0;  // neutral for min
    }
#ifdef DEPTH_PYRAMID_FROM_DEPTH
    return depth_texels[y * pc.width + x];
#else
    return vis_depth(vis_read(ivec2(x, y), pc.width));
#endif
}

void store(uint k, uvec3 level, uvec2 p, float d) {
    if (k < pc.levels && p.x < level.x && p.y < level.y) {
        hzb[level.z + p.y * level.x + p.x] = d;
    }
}

// The tile's 64x64 pixels, read so that neighbouring threads read neighbouring pixels.
shared float s_px[4u * HZB_GROUP][4u * HZB_GROUP];

// Level 0 texel (x, y) of the tile (local coordinates): the farthest of its 2x2 pixels.
float tile_level0(uvec2 q) {
    return min(min(s_px[2u * q.y][2u * q.x], s_px[2u * q.y][2u * q.x + 1u]),
               min(s_px[2u * q.y + 1u][2u * q.x], s_px[2u * q.y + 1u][2u * q.x + 1u]));
}

void head() {
    uvec2 t = gl_LocalInvocationID.xy;
    uvec2 g = gl_WorkGroupID.xy;
    // The pixels: 16 blocks of HZB_GROUP x HZB_GROUP, one pixel of each per thread.
    for (uint by = 0u; by < 4u; by++) {
        for (uint bx = 0u; bx < 4u; bx++) {
            uvec2 q = HZB_GROUP * uvec2(bx, by) + t;
            uvec2 p = 4u * HZB_GROUP * g + q;
            s_px[q.y][q.x] = pixel_depth(p.x, p.y);
        }
    }
    barrier();
    // Level 0: this thread's 2x2 texels; level 1: their minimum. A texel outside a level has
    // only sources outside the level below, so it comes out neutral by itself.
    uvec3 l0 = level_of(0u);
    uvec2 base = 32u * g + 2u * t;
    float a = tile_level0(2u * t);
    float b = tile_level0(2u * t + uvec2(1u, 0u));
    float c = tile_level0(2u * t + uvec2(0u, 1u));
    float d = tile_level0(2u * t + uvec2(1u, 1u));
    store(0u, l0, base, a);
    store(0u, l0, base + uvec2(1u, 0u), b);
    store(0u, l0, base + uvec2(0u, 1u), c);
    store(0u, l0, base + uvec2(1u, 1u), d);
    float m = min(min(a, b), min(c, d));
    store(1u, level_of(1u), 16u * g + t, m);
    s16[t.y][t.x] = m;
    barrier();
    // Levels 2..5: the tile's n x n texels (8, 4, 2, 1) from the 2n x 2n below, in place (read,
    // barrier, write, barrier).
    for (uint k = 2u; k < HZB_HEAD_LEVELS; k++) {
        uint n = 32u >> k;
        bool on = t.x < n && t.y < n;
        if (on) {
            m = min(min(s16[2u * t.y][2u * t.x], s16[2u * t.y][2u * t.x + 1u]),
                    min(s16[2u * t.y + 1u][2u * t.x], s16[2u * t.y + 1u][2u * t.x + 1u]));
        }
        barrier();
        if (on) {
            store(k, level_of(k), n * g + t, m);
            s16[t.y][t.x] = m;
        }
        barrier();
    }
}

void tail() {
    uint lid = gl_LocalInvocationIndex;
    uvec3 src = level_of(HZB_HEAD_LEVELS - 1u);
    for (uint k = HZB_HEAD_LEVELS; k < pc.levels; k++) {
        uvec3 dst = level_of(k);
        for (uint i = lid; i < dst.x * dst.y; i += HZB_GROUP * HZB_GROUP) {
            uvec2 p = uvec2(i % dst.x, i / dst.x);
            float d = 1.0;
            for (uint j = 0u; j < 4u; j++) {
                uvec2 q = 2u * p + uvec2(j & 1u, j >> 1u);
                if (q.x < src.x && q.y < src.y) {
                    d = min(d, hzb[src.z + q.y * src.x + q.x]);
                }
            }
            hzb[dst.z + i] = d;
        }
        // This level's texels, written by other invocations, are read for the next.
        memoryBarrierBuffer();
        barrier();
        src = dst;
    }
}

void main() {
    head();
    if (pc.levels <= HZB_HEAD_LEVELS) {
        return;
    }
    // This group's texels are visible device-wide before it counts itself finished; the last
    // group to finish sees every group's.
    memoryBarrierBuffer();
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y;
        s_last = atomicAdd(finished_groups, 1u) == groups - 1u;
    }
    barrier();
    if (!s_last) {
        return;
    }
    memoryBarrierBuffer();
    tail();
    if (gl_LocalInvocationIndex == 0u) {
        finished_groups = 0u;
    }
}
