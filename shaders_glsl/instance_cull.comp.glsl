#version 460
// Pass `instance_cull`: a thread per instance; frustum test of the mesh's bounding sphere; visible
// instances push their mesh's BVH root into the cluster_cull work queue.
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"
#include "cull.glsl"

layout(local_size_x = INSTANCE_CULL_WORKGROUP_SIZE) in;

layout(set = 0, binding = 0, scalar) uniform View { ViewGpu view; };
layout(set = 0, binding = 1, scalar) readonly buffer Meshes { MeshGpu meshes[]; };
layout(set = 0, binding = 2, scalar) readonly buffer Instances { InstanceVgeo instances[]; };
layout(set = 0, binding = 3, scalar) coherent buffer Counters { CullCounters counters; };
layout(set = 0, binding = 4) coherent buffer Queue { uint64_t queue[]; };

void main() {
    // 2D grid of workgroups for more than 65535 * 64 instances.
    uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * INSTANCE_CULL_WORKGROUP_SIZE + gl_LocalInvocationID.x;
    if (i >= view.instance_count) {
        return;
    }
    atomicAdd(counters.instances_tested, 1u);
    InstanceVgeo inst = instances[i];
    MeshGpu mesh = meshes[inst.mesh];
    vec3 c = relative_position(inst, view, mesh.bounds_center);
    float r = mesh.bounds_radius * inst.max_scale;
    if ((view.flags & VIEW_FLAG_NO_FRUSTUM) == 0u && !sphere_in_frustum(view, c, r)) {
        return;
    }
    atomicAdd(counters.instances_visible, 1u);
    atomicAdd(counters.outstanding, 1u);
    uint slot = atomicAdd(counters.queue_tail, 1u);
    if (slot >= view.queue_capacity) {
        atomicAdd(counters.queue_overflow, 1u);
        atomicAdd(counters.outstanding, 0xffffffffu);
        return;
    }
    uint64_t item = (uint64_t(i) << 32) | uint64_t(mesh.bvh_offset + mesh.bvh_root);
    atomicExchange(queue[slot], item);
}
