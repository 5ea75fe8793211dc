#version 460
// Pass `depth_export`: the visibility buffer's depth (the nearer of the host's surface and vgeo's,
// reverse-Z, 0 where empty) into a float buffer that is then copied into the host's D32 depth
// image (embedding): the host's later draws are occluded by vgeo's geometry.
//! variant image VISBUFFER_IMAGE
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"

layout(local_size_x = TILE_WORKGROUP_SIZE, local_size_y = TILE_WORKGROUP_SIZE) in;

#ifdef VISBUFFER_IMAGE
#extension GL_EXT_shader_image_int64 : require
layout(set = 0, binding = 0, r64ui) uniform readonly u64image2D vis_image;
#else
layout(set = 0, binding = 0) readonly buffer Vis { uint64_t vis[]; };
#endif
layout(set = 0, binding = 1) writeonly buffer HostDepth { float host_depth[]; };

layout(push_constant) uniform Push {
    uint width;
    uint height;
} pc;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.width || p.y >= pc.height) {
        return;
    }
#ifdef VISBUFFER_IMAGE
    uint64_t v = imageLoad(vis_image, ivec2(p)).x;
#else
    uint64_t v = vis[p.y * pc.width + p.x];
#endif
    host_depth[p.y * pc.width + p.x] = uintBitsToFloat(uint(v >> 32));
}
