#version 460
// Pass `emit_gbuffer`: runs only where the material depth equals this draw's material (depth test
// EQUAL). Rebuilds the pixel's triangle from the visibility buffer: barycentrics from the camera
// ray through the pixel centre, UV derivatives from the rays through the next pixels (textureGrad),
// the normal map (if any) applied in a tangent frame built from the same derivatives,
// and writes the GBuffer: albedo (sRGB-encoded RGBA8, alpha 1 = covered), normal (world, facing
// the camera, RGBA16F), params (metallic, roughness, material id low and high byte).
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
    MaterialGpu mat = materials[material];
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
    vec2 b;
    vec3 e1 = p[1] - p[0];
    vec3 e2 = p[2] - p[0];
    vec3 face = cross(e1, e2);
    mat3 lin = mat3(inst.linear[0].xyz, inst.linear[1].xyz, inst.linear[2].xyz);
    mat3 normal_matrix = transpose(inverse(lin));
    vec3 normal;
    bool facing_away = false;
    vec4 albedo = mat.base_color * vec4(inst.color.rgb, 1.0);
    if (ray_barycentrics(dir, p[0], p[1], p[2], b)) {
        vec2 bc = clamp(b, 0.0, 1.0);
        bc.y = min(bc.y, 1.0 - bc.x);
        normal = normal_matrix * (n[0] * (1.0 - bc.x - bc.y) + n[1] * bc.x + n[2] * bc.y);
        if (!(dot(normal, normal) > 0.0)) {
            normal = normal_matrix * face;
        }
        normal = normalize(normal);
        // Two-sided: a surface seen from behind gets the negated normal (decided before the
        // normal map, whose perturbed normal may legitimately lean away from the viewer).
        facing_away = dot(normal, dir) > 0.0;
        if ((mm.flags & MESH_HAS_UVS) != 0u) {
            vec2 tex_uv = uv[0] * (1.0 - b.x - b.y) + uv[1] * b.x + uv[2] * b.y;
            vec2 bx;
            vec2 by;
            ray_barycentrics(pixel_ray(mview.inv_view_proj, pc + vec2(1.0, 0.0), mview.viewport),
                             p[0], p[1], p[2], bx);
            ray_barycentrics(pixel_ray(mview.inv_view_proj, pc + vec2(0.0, 1.0), mview.viewport),
                             p[0], p[1], p[2], by);
            vec2 duv1 = uv[1] - uv[0];
            vec2 duv2 = uv[2] - uv[0];
            vec2 ddx = duv1 * (bx.x - b.x) + duv2 * (bx.y - b.y);
            vec2 ddy = duv1 * (by.x - b.x) + duv2 * (by.y - b.y);
            albedo *= textureGrad(textures[mat.base_color_texture], tex_uv, ddx, ddy);
            if (mat.normal_texture != NO_TEXTURE) {
                // Tangent from the position and UV derivatives (no stored tangents), as the
                // Khronos glTF sample viewer does: t along increasing u, b = n x t.
                vec3 dpx = e1 * (bx.x - b.x) + e2 * (bx.y - b.y);
                vec3 dpy = e1 * (by.x - b.x) + e2 * (by.y - b.y);
                float det = ddx.x * ddy.y - ddy.x * ddx.y;
                vec3 t_raw = (ddy.y * dpx - ddx.y * dpy) / det;
                vec3 t_ortho = t_raw - normal * dot(normal, t_raw);
                if (abs(det) > 0.0 && dot(t_ortho, t_ortho) > 0.0 && !any(isinf(t_ortho))) {
                    vec3 tangent = normalize(t_ortho);
                    vec3 bitangent = cross(normal, tangent);
                    vec3 tn = textureGrad(textures[mat.normal_texture], tex_uv, ddx, ddy).xyz * 2.0
                            - 1.0;
                    vec3 perturbed = tangent * tn.x + bitangent * tn.y + normal * tn.z;
                    if (dot(perturbed, perturbed) > 0.0) {
                        normal = normalize(perturbed);
                    }
                }
            }
        }
    } else {
        normal = normalize(normal_matrix * face);
        facing_away = dot(normal, dir) > 0.0;
    }
    if (!(dot(normal, normal) > 0.0)) {
        normal = -dir;
        facing_away = false;
    }
    if (facing_away) {
        normal = -normal;
    }
    out_albedo = vec4(encode_srgb(albedo.rgb), 1.0);
    out_normal = vec4(normal, 1.0);
    out_params = vec4(mat.metallic, mat.roughness, float(material & 0xffu) / 255.0,
                      float((material >> 8) & 0xffu) / 255.0);
}
