#version 460
// Pass `raster_hw`, vertex stage: vertex pulling for one vkCmdDrawIndirect over the HW list
// (gl_InstanceIndex = HW list index, gl_VertexIndex / 3 = triangle, % 3 = corner). Each corner also
// snaps all three vertices of its triangle (flat outputs) so that the fragment stage computes depth
// exactly as raster_sw does (or, for a triangle that cannot be snapped, passes its depth plane,
// in the same outputs). An entry with HW_ENTRY_CULL (a closed solid seen from outside) drops its
// faces turned away (common/raster.glsl hw_faces_away).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"

#include "raster_hw_bindings.glsl"

layout(location = 0) flat out uint out_id;      // visible index << 7 | triangle
layout(location = 1) flat out uint out_snapped; // 1: the three snapped vertices below are valid
layout(location = 2) flat out ivec4 out_xy01;
layout(location = 3) flat out ivec2 out_xy2;
layout(location = 4) flat out vec3 out_z;

void main() {
    uint hw_entry = hw_list[gl_InstanceIndex];
    uint visible_index = hw_entry & ~(HW_ENTRY_CULL | HW_ENTRY_MIRRORED);
    uvec2 entry = visible[visible_index];
    InstanceVgeo inst = instances[entry.x];
    MeshGpu mesh = meshes[inst.mesh];
    Cluster c = cluster_at(entry.y);
    uint tri = uint(gl_VertexIndex) / 3u;
    uint corner = uint(gl_VertexIndex) % 3u;
    out_id = 0u;
    out_snapped = 0u;
    out_xy01 = ivec4(0);
    out_xy2 = ivec2(0);
    out_z = vec3(0.0);
    if (tri >= cluster_triangle_count(c)) {
        // No such triangle: all corners at one point outside the view volume (culled, no NaN).
        gl_Position = vec4(2.0, 2.0, 0.5, 1.0);
        return;
    }
    ClusterData d = cluster_data(mesh, c);
    uvec3 t = cluster_triangle(d, c, tri);
    vec4 clip[3];
    ivec2 xy[3];
    vec3 z;
    bool ok = true;
    for (uint k = 0u; k < 3u; k++) {
        clip[k] = cluster_vertex_clip(inst, mesh, d, t[k]);
        float zk;
        ok = project_fixed(clip[k], xy[k], zk) && ok;
        z[k] = zk;
    }
    if (hw_faces_away(hw_entry, ok, xy[0], xy[1], xy[2], clip[0].xyw, clip[1].xyw, clip[2].xyw)) {
        // A face turned away from outside a closed solid: its three corners (each invocation
        // decides alike) at one point outside the view volume.
        gl_Position = vec4(2.0, 2.0, 0.5, 1.0);
        return;
    }
    // Snapped: the hardware gets raster_sw's fixed-point vertex (hw_position), so both cover the
    // same pixels; otherwise the clip position (the hardware clips at the near plane).
    gl_Position = ok ? hw_position(clip[corner], xy[corner], z[corner]) : clip[corner];
    out_id = (visible_index << VISBUFFER_TRIANGLE_BITS) | tri;
    out_snapped = ok ? 1u : 0u;
    if (ok) {
        out_xy01 = ivec4(xy[0], xy[1]);
        out_xy2 = xy[2];
        out_z = z;
    } else {
        // Not snapped: the depth plane for the fragment stage's clipped_depth.
        out_xy01 = ivec4(0);
        out_xy2 = ivec2(0);
        out_z = clipped_plane(vec3(clip[0].x, clip[1].x, clip[2].x),
                              vec3(clip[0].y, clip[1].y, clip[2].y),
                              vec3(clip[0].w, clip[1].w, clip[2].w));
    }
}
