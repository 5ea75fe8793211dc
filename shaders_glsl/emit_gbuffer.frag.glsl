#version 460
// Pass `emit_gbuffer`: runs only where the material depth equals this draw's material (depth test
// EQUAL). Rebuilds the pixel's triangle from the visibility buffer: barycentrics from the camera
// ray through the pixel centre, UV and position derivatives from the rays through the next pixels,
// and writes the GBuffer through the shared material model (common/gbuffer.glsl): albedo
// (sRGB-encoded RGBA8, alpha 1 = covered), normal (world, facing the camera, RGBA16F), params
// (metallic, roughness, material id low and high byte).
//! variant image VISBUFFER_IMAGE
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_nonuniform_qualifier : require
#include "shared.glsl"
#include "material.glsl"

#define VISBUFFER_BINDING 12
#define VISBUFFER_READONLY
#include "visbuffer.glsl"

layout(set = 0, binding = 0, scalar) uniform MaterialView { MaterialViewGpu mview; };
layout(set = 0, binding = 2, scalar) uniform View { ViewGpu view; };
layout(set = 0, binding = 3, scalar) readonly buffer Visible { uvec2 visible[]; };
layout(set = 0, binding = 4, scalar) readonly buffer Instances { InstanceVgeo instances[]; };
layout(set = 0, binding = 5, scalar) readonly buffer Meshes { MeshGpu meshes[]; };
layout(set = 0, binding = 6, scalar) readonly buffer Clusters { Cluster clusters[]; };
layout(set = 0, binding = 7, scalar) readonly buffer Vertices { PackedVertex vertices[]; };
layout(set = 0, binding = 8, scalar) readonly buffer VertexRefs { uint vertex_refs[]; };
layout(set = 0, binding = 9, scalar) readonly buffer Triangles { uint triangle_words[]; };
layout(set = 0, binding = 10, scalar) readonly buffer Materials { MaterialGpu materials[]; };
layout(set = 0, binding = 11, scalar) readonly buffer MeshMaterials { MeshMaterialGpu mesh_materials[]; };
layout(set = 0, binding = 13, scalar) buffer FragmentCounts { uint fragment_counts[]; };
layout(set = 1, binding = 0) uniform sampler2D textures[];

layout(push_constant, scalar) uniform Push { uint material; };

// The depth test (EQUAL against the material depth) must run before the shader: only this
// material's pixels may execute it (and count).
layout(early_fragment_tests) in;

layout(location = 0) out vec4 out_albedo;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_params;

#include "raster.glsl"
#include "shading.glsl"
#include "gbuffer.glsl"

vec2 decode_uv(MeshMaterialGpu mm, uint code) {
    vec2 t = vec2(code & 0xffffu, code >> 16) / 65535.0;
    return mm.uv_min + t * (mm.uv_max - mm.uv_min);
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint width = uint(mview.viewport.x);
    uint64_t value = vis_read(px, width);
    uint low = uint(value);
    uint tri = low & ((1u << VISBUFFER_TRIANGLE_BITS) - 1u);
    uint vi = low >> VISBUFFER_TRIANGLE_BITS;
    if (value == 0ul || vi >= mview.visible_capacity) {
        discard;
    }
    if (mview.count_fragments != 0u) {
        atomicAdd(fragment_counts[material], 1u);
    }
    uvec2 entry = visible[vi];
    InstanceVgeo inst = instances[entry.x];
    MeshGpu mesh = meshes[inst.mesh];
    MeshMaterialGpu mm = mesh_materials[inst.mesh];
    Cluster c = clusters[entry.y];
    uvec3 t = cluster_triangle(mesh, c, tri);
    vec3 p[3];
    vec3 n[3];
    vec2 uv[3];
    for (uint k = 0u; k < 3u; k++) {
        PackedVertex pv = vertices[cluster_vertex(mesh, c, t[k])];
        p[k] = relative_position(inst, decode_position(mesh, pv));
        n[k] = decode_normal(pv.normal);
        uv[k] = decode_uv(mm, pv.uv);
    }
    vec2 pc = vec2(px) + 0.5;
    vec3 dir = pixel_ray(mview.inv_view_proj, pc, mview.viewport);
    vec3 e1 = p[1] - p[0];
    vec3 e2 = p[2] - p[0];
    mat3 lin = mat3(inst.linear[0].xyz, inst.linear[1].xyz, inst.linear[2].xyz);
    mat3 normal_matrix = transpose(inverse(lin));
    Surface s;
    s.face = normal_matrix * cross(e1, e2);
    s.dir = dir;
    s.tint = inst.color.rgb;
    s.normal = vec3(0.0);
    s.has_uvs = false;
    s.uv = vec2(0.0);
    s.ddx = vec2(0.0);
    s.ddy = vec2(0.0);
    s.dpx = vec3(0.0);
    s.dpy = vec3(0.0);
    vec2 b;
    if (ray_barycentrics(dir, p[0], p[1], p[2], b)) {
        vec2 bc = clamp(b, 0.0, 1.0);
        bc.y = min(bc.y, 1.0 - bc.x);
        s.normal = normal_matrix * (n[0] * (1.0 - bc.x - bc.y) + n[1] * bc.x + n[2] * bc.y);
        if ((mm.flags & MESH_HAS_UVS) != 0u) {
            // Derivatives from the rays through the next pixels (exact for the triangle's plane).
            vec2 bx;
            vec2 by;
            ray_barycentrics(pixel_ray(mview.inv_view_proj, pc + vec2(1.0, 0.0), mview.viewport),
                             p[0], p[1], p[2], bx);
            ray_barycentrics(pixel_ray(mview.inv_view_proj, pc + vec2(0.0, 1.0), mview.viewport),
                             p[0], p[1], p[2], by);
            vec2 duv1 = uv[1] - uv[0];
            vec2 duv2 = uv[2] - uv[0];
            s.has_uvs = true;
            s.uv = uv[0] * (1.0 - b.x - b.y) + uv[1] * b.x + uv[2] * b.y;
            s.ddx = duv1 * (bx.x - b.x) + duv2 * (bx.y - b.y);
            s.ddy = duv1 * (by.x - b.x) + duv2 * (by.y - b.y);
            s.dpx = e1 * (bx.x - b.x) + e2 * (bx.y - b.y);
            s.dpy = e1 * (by.x - b.x) + e2 * (by.y - b.y);
        }
    }
    material_gbuffer(materials[material], material, s, out_albedo, out_normal, out_params);
}
