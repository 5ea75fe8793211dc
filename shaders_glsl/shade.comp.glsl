#version 460
// Pass `shade`: one directional light plus ambient from the GBuffer into the output image (RGBA8,
// sRGB-encoded), background where nothing was drawn: where material_classify's per-pixel material
// is NO_MATERIAL (SHADE_FLAG_PIXEL_MATERIALS, vgeo's compute emit_gbuffer, which leaves the GBuffer
// uncleared), else where the albedo's alpha is 0 (GBuffers drawn by rasterization). Modes: 0 shaded,
// 1 albedo, 2 normals, 3 materials (a hashed colour per material id). With SHADE_FLAG_COVERED_ONLY
// (embedding) only pixels vgeo's geometry covers are written.
// Shading (mirrored by the CPU reference in tests/material.rs): n faces the camera, l towards the
// light, v towards the camera; f0 = mix(0.04, albedo, metallic);
// colour = albedo (1 - metallic) (0.2 + 0.8 |n.l|) + f0 (0.2 + 0.8 max(n.l, 0) blinn(n.h)),
// blinn = pow(max(n.h, 0), s) (s + 8) / (8 pi) / 4 with s = 2 / max(roughness^4, 1e-4) - 2.
#include "shared.glsl"
#include "material.glsl"
#include "shading.glsl"

// One 16x16 workgroup per SHADE_TILE x SHADE_TILE pixels, (SHADE_TILE / 16)^2 pixels per thread:
// the tile in blocks of 16x16 pixels, one pixel of each block per thread, so that neighbouring
// threads read and write neighbouring pixels and each thread has several pixels' loads in flight
// (one pixel per thread took 0.026 ms for a 1080p frame on the H100, nothing covered).
layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = 0, scalar) uniform MaterialView { MaterialViewGpu mview; };
layout(set = 0, binding = 1, rgba8) uniform readonly image2D albedo_image;
layout(set = 0, binding = 2, rgba16f) uniform readonly image2D normal_image;
layout(set = 0, binding = 3, rgba8) uniform readonly image2D params_image;
layout(set = 0, binding = 4, rgba8) uniform writeonly image2D out_image;
layout(set = 0, binding = 5, scalar) readonly buffer PixelMaterials { uint pixel_materials[]; };

void shade_pixel(ivec2 px) {
    bool covered;
    vec4 a = vec4(0.0);
    if ((mview.flags & SHADE_FLAG_PIXEL_MATERIALS) != 0u) {
        covered = pixel_materials[px.y * int(mview.viewport.x) + px.x] != NO_MATERIAL;
        if (covered) {
            a = imageLoad(albedo_image, px);
        }
    } else {
        a = imageLoad(albedo_image, px);
        covered = a.a > 0.5;
    }
    if ((mview.flags & SHADE_FLAG_COVERED_ONLY) != 0u && !covered) {
        return;  // the host's pixel (its geometry or its background)
    }
    vec3 color = mview.background.rgb;
    if (covered) {
        vec3 n = imageLoad(normal_image, px).xyz;
        vec4 params = imageLoad(params_image, px);
        vec3 albedo = pow(a.rgb, vec3(2.2));
        switch (mview.mode) {
        case 1u:
            color = a.rgb;
            break;
        case 2u:
            color = n * 0.5 + 0.5;
            break;
        case 3u:
        {
            uint id = uint(round(params.z * 255.0)) | (uint(round(params.w * 255.0)) << 8);
            color = material_hash_color(id);
            break;
        }
        default:
        {
            float metallic = params.x;
            float roughness = params.y;
            vec3 l = mview.light_dir.xyz;
            vec3 v = -normalize(pixel_ray(mview.inv_view_proj, vec2(px) + 0.5, mview.viewport));
            vec3 h = normalize(l + v);
            float r4 = roughness * roughness * roughness * roughness;
            float s = 2.0 / max(r4, 1e-4) - 2.0;
            float blinn = pow(max(dot(n, h), 0.0), s) * (s + 8.0) / (8.0 * 3.14159265) * 0.25;
            vec3 f0 = mix(vec3(0.04), albedo, metallic);
            float ndl = dot(n, l);
            vec3 lit = albedo * (1.0 - metallic) * (0.2 + 0.8 * abs(ndl))
                     + f0 * (0.2 + 0.8 * max(ndl, 0.0) * blinn);
            color = encode_srgb(lit);
            break;
        }
        }
    }
    imageStore(out_image, px, vec4(color, 1.0));
}

void main() {
    ivec2 base = ivec2(gl_WorkGroupID.xy * SHADE_TILE + gl_LocalInvocationID.xy);
    ivec2 size = ivec2(mview.viewport.xy);
    for (int by = 0; by < int(SHADE_TILE / 16u); by++) {
        for (int bx = 0; bx < int(SHADE_TILE / 16u); bx++) {
            ivec2 px = base + 16 * ivec2(bx, by);
            if (px.x < size.x && px.y < size.y) {
                shade_pixel(px);
            }
        }
    }
}
