#version 460
// Pass `depth_import`: seeds the visibility buffer from the host's depth (embedding). The host's
// D32 depth (reverse-Z, 0 = far) was copied into a float buffer; each pixel the host covered
// (depth > 0) becomes `depth bits << 32 | VISBUFFER_HOST`, the others 0 (empty). Then the
// rasterizers' atomicMax keeps a vgeo fragment only where it is nearer than the host's surface,
// and depth_pyramid builds the HZB over both (the host's depth occludes vgeo's instances and
// clusters). Replaces the visibility buffer's clear.
//! variant image VISBUFFER_IMAGE
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"

layout(local_size_x = TILE_WORKGROUP_SIZE, local_size_y = TILE_WORKGROUP_SIZE) in;

#define VISBUFFER_BINDING 0
#include "visbuffer.glsl"
layout(set = 0, binding = 1) readonly buffer HostDepth { float host_depth[]; };

layout(push_constant) uniform Push {
    uint width;
    uint height;
} pc;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.width || p.y >= pc.height) {
        return;
    }
    float d = host_depth[p.y * pc.width + p.x];
    uint64_t v = d > 0.0 ? (uint64_t(floatBitsToUint(d)) << 32) | uint64_t(VISBUFFER_HOST) : 0ul;
    vis_store(ivec2(p), pc.width, v);
}
