#version 460
// Pass `emit_gbuffer`: one draw per material of a grid of 64x64 tile quads (6 vertices per tile)
// at the material's depth; tiles whose [min, max] material range (material_classify) excludes the
// material collapse to a point outside the view volume.
#include "shared.glsl"
#include "material.glsl"

layout(set = 0, binding = 0, scalar) uniform MaterialView { MaterialViewGpu mview; };
layout(set = 0, binding = 1, scalar) readonly buffer Tiles { uvec2 tiles[]; };

layout(push_constant, scalar) uniform Push { uint material; };

void main() {
    uint tile = uint(gl_VertexIndex) / 6u;
    uint corner = uint(gl_VertexIndex) % 6u;
    uvec2 range = tiles[tile];
    if (material < range.x || material > range.y) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    const uvec2 corners[6] = uvec2[6](uvec2(0, 0), uvec2(1, 0), uvec2(0, 1), uvec2(1, 0),
                                       uvec2(1, 1), uvec2(0, 1));
    uvec2 t = uvec2(tile % mview.tiles_x, tile / mview.tiles_x) + corners[corner];
    vec2 px = min(vec2(t * MATERIAL_TILE), mview.viewport.xy);
    gl_Position = vec4(px * mview.viewport.zw * 2.0 - 1.0, material_depth(material), 1.0);
}
