#version 460
// Pass `depth_export`: the visibility buffer's depth (the nearer of the host's surface and vgeo's,
// reverse-Z, 0 where empty) into a float buffer that is then copied into the host's D32 depth
// image (embedding): the host's later draws are occluded by vgeo's geometry.
//! variant image VISBUFFER_IMAGE
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"

layout(local_size_x = TILE_WORKGROUP_SIZE, local_size_y = TILE_WORKGROUP_SIZE) in;

#define VISBUFFER_BINDING 0
#define VISBUFFER_READONLY
#include "visbuffer.glsl"
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
    host_depth[p.y * pc.width + p.x] = vis_depth(vis_read(ivec2(p), pc.width));
}
