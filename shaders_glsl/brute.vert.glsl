#version 460
// Pass `brute` (and `lod`, which shares the pipeline): classic indexed draws of every instance;
// passes the camera-relative position, normal, UV, global material and tint to the GBuffer shader.
// Variant `list` (the GPU-driven `lod`): gl_InstanceIndex indexes `lod_cull`'s instance list, which
// holds the instance's index in `instances`.
//! variant list LOD_INSTANCE_LIST
#include "shared.glsl"

layout(set = 0, binding = 0, scalar) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1, scalar) readonly buffer Instances { InstanceGpu instances[]; };
#ifdef LOD_INSTANCE_LIST
layout(set = 0, binding = 3, scalar) readonly buffer InstanceList { uint instance_list[]; };
#endif

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in uint in_material;

layout(location = 0) out vec3 out_rel;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec2 out_uv;
layout(location = 3) flat out uint out_material;
layout(location = 4) flat out vec3 out_tint;

void main() {
#ifdef LOD_INSTANCE_LIST
    InstanceGpu inst = instances[instance_list[gl_InstanceIndex]];
#else
    InstanceGpu inst = instances[gl_InstanceIndex];
#endif
    vec4 rel = inst.model * vec4(in_position, 1.0);
    gl_Position = frame.view_proj * rel;
    mat3 nm = mat3(inst.normal_matrix[0].xyz, inst.normal_matrix[1].xyz, inst.normal_matrix[2].xyz);
    out_rel = rel.xyz;
    out_normal = nm * in_normal;
    out_uv = in_uv;
    out_material = in_material;
    out_tint = inst.color.rgb;
}
