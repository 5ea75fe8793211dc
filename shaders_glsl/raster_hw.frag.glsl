#version 460
// Pass `raster_hw`, fragment stage of both paths: no attachments; the hardware's coverage, the
// depth recomputed from the snapped vertices with raster_sw's exact integer edge functions and
// float operations (so both rasterizers write bit-identical values), atomicMax into the visibility
// buffer. Triangles with a vertex that cannot be snapped (behind the near plane: the hardware
// clips them) carry their depth plane in `in_z` instead (raster.glsl's clipped_plane, once per
// triangle), and take the depth of clipped_depth, not the hardware's (so both paths agree there too). With VIEW_FLAG_COUNT_OVERDRAW each fragment also increments the overdraw counter (binding
// 9). The same inputs come flat from the vertex path (raster_hw.vert.glsl) or per primitive from
// the mesh path (raster_hw.mesh.glsl): variants `mesh` and `mesh_image` (RASTER_HW_MESH).
//! variant image VISBUFFER_IMAGE
//! variant mesh RASTER_HW_MESH
//! variant mesh_image RASTER_HW_MESH_IMAGE
#ifdef RASTER_HW_MESH_IMAGE
#define RASTER_HW_MESH
#define VISBUFFER_IMAGE
#endif
#ifdef RASTER_HW_MESH
#extension GL_EXT_mesh_shader : require
#define RASTER_HW_IN perprimitiveEXT flat in
#else
#define RASTER_HW_IN flat in
#endif
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#define VISBUFFER_BINDING 8
#include "shared.glsl"
#include "visbuffer.glsl"

layout(set = 0, binding = 0, scalar) uniform View { ViewGpu view; };

layout(location = 0) RASTER_HW_IN uint in_id;
layout(location = 1) RASTER_HW_IN uint in_snapped;
layout(location = 2) RASTER_HW_IN ivec4 in_xy01;
layout(location = 3) RASTER_HW_IN ivec2 in_xy2;
layout(location = 4) RASTER_HW_IN vec3 in_z;

#define RASTER_NO_SCENE
#include "raster.glsl"
#define OVERDRAW_BINDING 9
#include "overdraw.glsl"

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    float depth = gl_FragCoord.z;
    if (in_snapped != 0u) {
        ivec2 v[3] = ivec2[3](in_xy01.xy, in_xy01.zw, in_xy2);
        vec3 z = in_z;
        int64_t area = edge_fn(v[0], v[1], v[2]);
        if (area < 0) {
            ivec2 t = v[1]; v[1] = v[2]; v[2] = t;
            z = z.xzy;
            area = -area;
        }
        if (area > 0) {
            ivec2 centre = px * (1 << SUBPIXEL_BITS) + (1 << (SUBPIXEL_BITS - 1));
            precise float inv_area = 1.0 / float(area);
            float e0 = float(edge_fn(v[1], v[2], centre));
            float e1 = float(edge_fn(v[2], v[0], centre));
            float e2 = float(edge_fn(v[0], v[1], centre));
            depth = raster_depth(e0, e1, e2, z, inv_area);
        }
    } else {
        // in_z = the triangle's depth plane (clipped_plane, computed once per triangle).
        depth = clipped_depth(px, in_z, depth);
    }
    vis_write(px, uint(view.viewport.x), vis_pack(depth, in_id >> VISBUFFER_TRIANGLE_BITS,
                                                   in_id & ((1u << VISBUFFER_TRIANGLE_BITS) - 1u)));
    overdraw_count(px, uint(view.viewport.x));
}
