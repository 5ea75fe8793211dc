#version 460
// Pass `brute` (and `lod`): writes the GBuffer through the material model every path shares
// (common/gbuffer.glsl); `shade` lights it. Derivatives are the hardware's (fine), which for a
// triangle's plane equal the ray differences `emit_gbuffer` computes.
#extension GL_EXT_nonuniform_qualifier : require
#include "shared.glsl"
#include "material.glsl"
#include "shading.glsl"

layout(set = 0, binding = 2, scalar) readonly buffer Materials { MaterialGpu materials[]; };
layout(set = 1, binding = 0) uniform sampler2D textures[];

// MESH_HAS_UVS | MESH_HAS_NORMALS of the drawn mesh.
layout(push_constant, scalar) uniform Push { uint mesh_flags; };

#include "gbuffer.glsl"

layout(location = 0) in vec3 in_rel;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) flat in uint in_material;
layout(location = 4) flat in vec3 in_tint;

layout(location = 0) out vec4 out_albedo;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_params;

void main() {
    Surface s;
    s.dpx = dFdxFine(in_rel);
    s.dpy = dFdyFine(in_rel);
    s.face = cross(s.dpx, s.dpy);
    s.normal = in_normal;
    s.dir = in_rel;
    s.tint = in_tint;
    s.has_uvs = (mesh_flags & MESH_HAS_UVS) != 0u;
    s.uv = in_uv;
    s.ddx = dFdxFine(in_uv);
    s.ddy = dFdyFine(in_uv);
    material_gbuffer(materials[in_material], in_material, s, out_albedo, out_normal, out_params);
}
