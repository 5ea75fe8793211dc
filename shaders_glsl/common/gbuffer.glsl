// The material model, shared by every path so their images compare: `emit_gbuffer` (vgeo, the
// surface rebuilt from the visibility buffer) and `brute` / `lod` (the classic forward draws) call
// material_gbuffer() with the same inputs and write the same GBuffer, which `shade` lights.
// The including shader declares `layout(set = 1, binding = 0) uniform sampler2D textures[];` and
// includes material.glsl and shading.glsl first.
#ifndef VGEO_GBUFFER_GLSL
#define VGEO_GBUFFER_GLSL

// What the material model needs of the surface at a pixel (world orientation, camera-relative).
struct Surface {
    vec3 normal;  // interpolated vertex normal (any length; zero = none, the face normal is used)
    vec3 face;    // geometric normal (any length, either side)
    vec3 dir;     // from the camera through the pixel to the surface (any length)
    bool has_uvs; // false: no texture is sampled
    vec2 uv;      // texture coordinates at the pixel
    vec2 ddx;     // uv difference to the next pixel right
    vec2 ddy;     // ... and below
    vec3 dpx;     // position difference to the next pixel right (tangent frame for normal maps)
    vec3 dpy;     // ... and below
    vec3 tint;    // the instance's albedo tint
};

// GBuffer of one pixel: albedo (sRGB-encoded, alpha 1 = covered), normal (world, unit, facing the
// camera: two-sided), params (metallic, roughness, material id low and high byte).
void material_gbuffer(MaterialGpu mat, uint material, Surface s, out vec4 out_albedo,
                      out vec4 out_normal, out vec4 out_params) {
    vec3 normal = s.normal;
    if (!(dot(normal, normal) > 0.0)) {
        normal = s.face;
    }
    normal = normalize(normal);
    // Two-sided: a surface seen from behind gets the negated normal (decided before the normal
    // map, whose perturbed normal may legitimately lean away from the viewer).
    bool facing_away = dot(normal, s.dir) > 0.0;
    vec4 albedo = mat.base_color * vec4(s.tint, 1.0);
    float metallic = mat.metallic;
    float roughness = mat.roughness;
    if (s.has_uvs) {
        albedo *= textureGrad(textures[mat.base_color_texture], s.uv, s.ddx, s.ddy);
        if (mat.metallic_roughness_texture != NO_TEXTURE) {
            vec4 mr = textureGrad(textures[mat.metallic_roughness_texture], s.uv, s.ddx, s.ddy);
            metallic *= mr.b;
            roughness *= mr.g;
        }
        if (mat.normal_texture != NO_TEXTURE && dot(normal, normal) > 0.0) {
            // Tangent from the position and UV derivatives (no stored tangents), as the Khronos
            // glTF sample viewer does: t along increasing u, b = n x t.
            float det = s.ddx.x * s.ddy.y - s.ddy.x * s.ddx.y;
            vec3 t_raw = (s.ddy.y * s.dpx - s.ddx.y * s.dpy) / det;
            vec3 t_ortho = t_raw - normal * dot(normal, t_raw);
            if (abs(det) > 0.0 && dot(t_ortho, t_ortho) > 0.0 && !any(isinf(t_ortho))) {
                vec3 tangent = normalize(t_ortho);
                vec3 bitangent = cross(normal, tangent);
                vec3 tn = textureGrad(textures[mat.normal_texture], s.uv, s.ddx, s.ddy).xyz * 2.0
                        - 1.0;
                vec3 perturbed = tangent * tn.x + bitangent * tn.y + normal * tn.z;
                if (dot(perturbed, perturbed) > 0.0) {
                    normal = normalize(perturbed);
                }
            }
        }
    }
    if (!(dot(normal, normal) > 0.0)) {
        normal = -normalize(s.dir);
        facing_away = false;
    }
    if (facing_away) {
        normal = -normal;
    }
    out_albedo = vec4(encode_srgb(albedo.rgb), 1.0);
    out_normal = vec4(normal, 1.0);
    out_params = vec4(clamp(metallic, 0.0, 1.0), clamp(roughness, 0.0, 1.0),
                      float(material & 0xffu) / 255.0, float((material >> 8) & 0xffu) / 255.0);
}

#endif
