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

#define VISBUFFER_BINDING 11
#define VISBUFFER_READONLY
#include "visbuffer.glsl"

#include "emit_bindings.glsl"

layout(push_constant, scalar) uniform Push { uint material; };

// The depth test (EQUAL against the material depth) must run before the shader: only this
// material's pixels may execute it (and count).
layout(early_fragment_tests) in;

layout(location = 0) out vec4 out_albedo;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_params;

#define RASTER_DECODE_32
#include "raster.glsl"
#include "shading.glsl"
#include "gbuffer.glsl"

#include "emit.glsl"

void main() {
    if (!emit_pixel(ivec2(gl_FragCoord.xy), material, out_albedo, out_normal, out_params)) {
        discard;
    }
}
