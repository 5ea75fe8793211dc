#version 460
// Pass `emit_gbuffer`, compute form (the default; the raster form is emit_gbuffer.frag): one
// dispatch per material over the 64x64 classification tiles. A workgroup whose tile range
// (material_classify) excludes the material leaves at once; in the others each thread takes 16
// pixels and shades those whose material (material_classify's per-pixel id) is this dispatch's,
// writing the GBuffer images directly. No material depth and no fragment shading: on the H100
// this is several times faster than the tile-quad draws (docs/architecture.md).
//! variant image VISBUFFER_IMAGE
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_nonuniform_qualifier : require
#include "shared.glsl"
#include "material.glsl"

#define VISBUFFER_BINDING 11
#define VISBUFFER_READONLY
#include "visbuffer.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

#include "emit_bindings.glsl"
layout(set = 0, binding = 1, scalar) readonly buffer Tiles { uvec2 tiles[]; };
layout(set = 0, binding = 13, scalar) readonly buffer PixelMaterials { uint pixel_materials[]; };
layout(set = 0, binding = 14, rgba8) uniform writeonly image2D albedo_image;
layout(set = 0, binding = 15, rgba16f) uniform writeonly image2D normal_image;
layout(set = 0, binding = 16, rgba8) uniform writeonly image2D params_image;

layout(push_constant, scalar) uniform Push { uint material; };

#define RASTER_DECODE_32
#include "raster.glsl"
#include "shading.glsl"
#include "gbuffer.glsl"
#include "emit.glsl"

void main() {
    uvec2 range = tiles[gl_WorkGroupID.y * mview.tiles_x + gl_WorkGroupID.x];
    if (material < range.x || material > range.y) {
        return;
    }
    uint width = uint(mview.viewport.x);
    uint height = uint(mview.viewport.y);
    // Thread (x, y) takes pixels (x + 16 i, y + 16 j): a subgroup reads and writes runs of
    // neighbouring pixels.
    uvec2 base = gl_WorkGroupID.xy * MATERIAL_TILE + gl_LocalInvocationID.xy;
    for (uint dy = 0u; dy < 4u; dy++) {
        for (uint dx = 0u; dx < 4u; dx++) {
            uvec2 p = base + uvec2(dx, dy) * 16u;
            if (p.x >= width || p.y >= height || pixel_materials[p.y * width + p.x] != material) {
                continue;
            }
            vec4 a;
            vec4 n;
            vec4 q;
            if (emit_pixel(ivec2(p), material, a, n, q)) {
                imageStore(albedo_image, ivec2(p), a);
                imageStore(normal_image, ivec2(p), n);
                imageStore(params_image, ivec2(p), q);
            }
        }
    }
}
