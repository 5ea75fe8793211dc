#version 460
// Pass `brute`: classic indexed draw of every instance at full detail.
#include "shared.glsl"

layout(set = 0, binding = 0, scalar) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1, scalar) readonly buffer Instances { InstanceGpu instances[]; };

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec3 out_normal;
layout(location = 1) flat out vec3 out_color;

void main() {
    InstanceGpu inst = instances[gl_InstanceIndex];
    vec4 rel = inst.model * vec4(in_position, 1.0);
    gl_Position = frame.view_proj * rel;
    mat3 nm = mat3(inst.normal_matrix[0].xyz, inst.normal_matrix[1].xyz, inst.normal_matrix[2].xyz);
    out_normal = nm * in_normal;
    out_color = inst.color.rgb;
}
