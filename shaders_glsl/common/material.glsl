// Materials and the material passes' shared view (src/material.rs, src/passes/material_classify.rs).
#ifndef VGEO_MATERIAL_GLSL
#define VGEO_MATERIAL_GLSL

struct MaterialGpu {
    vec4 base_color;  // linear
    float metallic;
    float roughness;
    uint base_color_texture;  // index into textures[] (0 = white)
    uint normal_texture;      // tangent-space normal map, NO_TEXTURE = none
    uint metallic_roughness_texture;  // glTF: blue metallic, green roughness; NO_TEXTURE = none
    uint _pad0;
    uint _pad1;
    uint _pad2;
};

struct MeshMaterialGpu {
    vec2 uv_min;
    vec2 uv_max;
    uint flags;  // 1: has UVs, 2: has normals
    uint material_offset;
    uint material_count;  // the mesh's materials (local ids are clamped to the last)
    uint _pad1;
};

#define MESH_HAS_UVS 1u
#define MESH_HAS_NORMALS 2u

// Mirrors MaterialViewGpu (src/passes/material_classify.rs).
struct MaterialViewGpu {
    mat4 inv_view_proj;  // of the camera-relative view_proj
    vec4 light_dir;      // towards the light, world space, normalized
    vec4 background;     // sRGB-encoded
    vec4 viewport;       // width, height, 1/width, 1/height
    uint tiles_x;
    uint tiles_y;
    uint material_count;
    uint visible_capacity;
    uint mode;           // shade: 0 shaded, 1 albedo, 2 normals, 3 materials
    uint count_fragments;
    uint flags;          // SHADE_FLAG_*
    uint _pad1;
};

#define MATERIAL_TILE 64u
#define NO_MATERIAL 0xffffffffu
#define NO_TEXTURE 0xffffffffu

// Material depth of a global material id: exactly representable, never 0 (the clear value).
float material_depth(uint id) { return float(id + 1u) * (1.0 / 16777216.0); }

// The view ray through a pixel position (camera-relative, not normalized).
vec3 pixel_ray(mat4 inv_view_proj, vec2 pixel, vec4 viewport) {
    vec2 ndc = pixel * viewport.zw * 2.0 - 1.0;
    vec4 a = inv_view_proj * vec4(ndc, 1.0, 1.0);
    return a.xyz / a.w;
}

// Barycentrics (u, v) of the point where the ray from the camera (origin) along `dir` meets the
// plane of p0 p1 p2: P = p0 + u (p1 - p0) + v (p2 - p0). False for a ray parallel to the plane.
bool ray_barycentrics(vec3 dir, vec3 p0, vec3 p1, vec3 p2, out vec2 uv) {
    vec3 e1 = p1 - p0;
    vec3 e2 = p2 - p0;
    vec3 pv = cross(dir, e2);
    float det = dot(e1, pv);
    uv = vec2(0.0);
    if (!(abs(det) > 1e-30)) {
        return false;
    }
    vec3 tv = -p0;
    uv = vec2(dot(tv, pv), dot(dir, cross(tv, e1))) / det;
    return true;
}

vec3 material_hash_color(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return vec3(uvec3(x, x >> 8, x >> 16) & 0xffu) / 255.0 * 0.8 + 0.2;
}

#endif
