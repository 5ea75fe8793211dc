#version 460
// Pass `depth_pyramid`: one level of the hierarchical depth buffer (HZB) per dispatch. Level 0
// reduces the visibility buffer's depth 2x2, each further level the previous one. Each texel keeps
// the FARTHEST depth below it (reverse-Z: the minimum); empty pixels have depth 0, i.e. infinitely
// far, so they never occlude. Texels outside the source are ignored.
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
layout(set = 0, binding = 1) buffer Hzb { float hzb[]; };

layout(push_constant) uniform Push {
    uint src_offset;
    uint src_w;
    uint src_h;
    uint dst_offset;
    uint dst_w;
    uint dst_h;
    uint from_visbuffer;
    uint _pad;
} pc;

float src_depth(uint x, uint y) {
    if (x >= pc.src_w || y >= pc.src_h) {
        return 1.0;  // neutral for min
    }
    if (pc.from_visbuffer != 0u) {
#ifdef VISBUFFER_IMAGE
        uint64_t v = imageLoad(vis_image, ivec2(x, y)).x;
#else
        uint64_t v = vis[y * pc.src_w + x];
#endif
        return uintBitsToFloat(uint(v >> 32));
    }
    return hzb[pc.src_offset + y * pc.src_w + x];
}

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.dst_w || p.y >= pc.dst_h) {
        return;
    }
    uint sx = 2u * p.x;
    uint sy = 2u * p.y;
    float d = min(min(src_depth(sx, sy), src_depth(sx + 1u, sy)), min(src_depth(sx, sy + 1u), src_depth(sx + 1u, sy + 1u)));
    hzb[pc.dst_offset + p.y * pc.dst_w + p.x] = d;
}
