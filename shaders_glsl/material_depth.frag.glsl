#version 460
// Pass `material_depth`: writes every covered pixel's material as depth (material_depth(id)),
// from material_classify's per-pixel ids; empty pixels keep the clear value 0.
#include "shared.glsl"
#include "material.glsl"

layout(set = 0, binding = 0, scalar) uniform MaterialView { MaterialViewGpu mview; };
layout(set = 0, binding = 1, scalar) readonly buffer PixelMaterials { uint pixel_materials[]; };

void main() {
    uvec2 p = uvec2(gl_FragCoord.xy);
    uint id = pixel_materials[p.y * uint(mview.viewport.x) + p.x];
    if (id == NO_MATERIAL) {
        discard;
    }
    gl_FragDepth = material_depth(id);
}
