#version 460
// Pass `raster_hw`, mesh stage (the mesh path, VK_EXT_mesh_shader; no task stage): one workgroup
// per HW-list entry (workgroup (x, y) of the grid is entry y * gl_NumWorkGroups.x + x; the cull
// writes rows of MESH_GROUPS_X, and CullCounters.hw_mesh.w says how many entries there are).
// The cluster's vertices are decoded, transformed and snapped once each into shared memory (and
// written as the mesh's vertices), then one invocation per triangle writes its indices and, as
// per-primitive outputs, what the fragment stage needs to recompute raster_sw's exact depth: the id
// and the three snapped vertices with their ndc depths (or, for a triangle that cannot be snapped,
// its depth plane: raster.glsl's clipped_plane). The fragment stage is raster_hw.frag.glsl
// (its `mesh` variants), the same source as the vertex path's.
#extension GL_EXT_mesh_shader : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"

layout(local_size_x = RASTER_HW_MESH_WORKGROUP_SIZE) in;
layout(triangles, max_vertices = MAX_CLUSTER_VERTICES, max_primitives = MAX_CLUSTER_TRIANGLES) out;

layout(set = 0, binding = 10, scalar) readonly buffer Counters { CullCounters counters; };
#include "raster_hw_bindings.glsl"

// Only the built-in per-primitive output used (the whole block would declare the shading-rate
// output too, which needs an extension's capability).
perprimitiveEXT out gl_MeshPerPrimitiveEXT {
    bool gl_CullPrimitiveEXT;
} gl_MeshPrimitivesEXT[];

// The fragment stage's inputs (raster_hw.frag.glsl), one per triangle.
layout(location = 0) perprimitiveEXT flat out uint out_id[];      // visible index << 7 | triangle
layout(location = 1) perprimitiveEXT flat out uint out_snapped[]; // 1: the snapped vertices are valid
layout(location = 2) perprimitiveEXT flat out ivec4 out_xy01[];
layout(location = 3) perprimitiveEXT flat out ivec2 out_xy2[];
layout(location = 4) perprimitiveEXT flat out vec3 out_z[];

shared ivec2 s_xy[MAX_CLUSTER_VERTICES];
shared float s_z[MAX_CLUSTER_VERTICES];
shared uint s_ok[MAX_CLUSTER_VERTICES];  // 1: snapped (in front of the near plane, in the guard band)
shared vec3 s_clip[MAX_CLUSTER_VERTICES]; // clip-space x, y, w (triangles that cannot be snapped)

void main() {
    uint entry_index = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    // Workgroup-uniform: the last row's workgroups past the list draw nothing.
    if (entry_index >= counters.hw_mesh.w) {
        SetMeshOutputsEXT(0u, 0u);
        return;
    }
    uint tid = gl_LocalInvocationIndex;
    uint hw_entry = hw_list[entry_index];
    uint visible_index = hw_entry & ~(HW_ENTRY_CULL | HW_ENTRY_MIRRORED);
    uvec2 entry = visible[visible_index];
    InstanceVgeo inst = instances[entry.x];
    MeshGpu mesh = meshes[inst.mesh];
    Cluster c = cluster_at(entry.y);
    ClusterData d = cluster_data(mesh, c);
    uint vcount = cluster_vertex_count(c);
    uint tcount = cluster_triangle_count(c);
    SetMeshOutputsEXT(vcount, tcount);
    for (uint k = tid; k < vcount; k += RASTER_HW_MESH_WORKGROUP_SIZE) {
        vec4 clip = cluster_vertex_clip(inst, mesh, d, k);
        ivec2 xy;
        float z;
        bool ok = project_fixed(clip, xy, z);
        // A snapped vertex as raster_sw's fixed-point point (hw_position), in every triangle that
        // uses it: where a triangle's other vertex is not snapped, the point is the same
        // projectively (w > 0), so the hardware's clipping gives the same polygon.
        gl_MeshVerticesEXT[k].gl_Position = ok ? hw_position(clip, xy, z) : clip;
        s_xy[k] = xy;
        s_z[k] = z;
        s_ok[k] = ok ? 1u : 0u;
        s_clip[k] = clip.xyw;
    }
    barrier();
    for (uint t = tid; t < tcount; t += RASTER_HW_MESH_WORKGROUP_SIZE) {
        uvec3 v = cluster_triangle(d, c, t);
        gl_PrimitiveTriangleIndicesEXT[t] = v;
        out_id[t] = (visible_index << VISBUFFER_TRIANGLE_BITS) | t;
        uint ok = s_ok[v.x] & s_ok[v.y] & s_ok[v.z];
        // A face turned away from outside a closed solid is not rasterized.
        gl_MeshPrimitivesEXT[t].gl_CullPrimitiveEXT = hw_faces_away(
            hw_entry, ok != 0u, s_xy[v.x], s_xy[v.y], s_xy[v.z], s_clip[v.x], s_clip[v.y], s_clip[v.z]);
        out_snapped[t] = ok;
        if (ok != 0u) {
            out_xy01[t] = ivec4(s_xy[v.x], s_xy[v.y]);
            out_xy2[t] = s_xy[v.z];
            out_z[t] = vec3(s_z[v.x], s_z[v.y], s_z[v.z]);
        } else {
            // Not snapped: the depth plane for the fragment stage's clipped_depth.
            vec3 c0 = s_clip[v.x];
            vec3 c1 = s_clip[v.y];
            vec3 c2 = s_clip[v.z];
            out_xy01[t] = ivec4(0);
            out_xy2[t] = ivec2(0);
            out_z[t] = clipped_plane(vec3(c0.x, c1.x, c2.x), vec3(c0.y, c1.y, c2.y),
                                     vec3(c0.z, c1.z, c2.z));
        }
    }
}
