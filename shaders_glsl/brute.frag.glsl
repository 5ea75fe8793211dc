#version 460
// Pass `brute`: Lambert shading from interpolated normals.
#include "shared.glsl"
#include "shading.glsl"

layout(set = 0, binding = 0, scalar) uniform Frame { FrameUniforms frame; };

layout(location = 0) in vec3 in_normal;
layout(location = 1) flat in vec3 in_color;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 c = shade_lambert(in_color, in_normal, frame.light_dir.xyz);
    out_color = vec4(encode_srgb(c), 1.0);
}
