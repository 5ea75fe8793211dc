#version 460
// Pass `raster_sw`: the compute rasterizer for small triangles. One workgroup per SW cluster
// (grid-stride over CullCounters.sw_count), the cluster's vertices decoded, transformed and snapped
// into shared memory, then one thread per triangle: fixed-point edge functions (SUBPIXEL_BITS) with
// the top-left rule exactly as src/reference/raster.rs, depth from the snapped positions, atomicMax
// into the visibility buffer. Small triangles walk their bounding box with int32 edge functions,
// larger ones walk scanlines (the covered span of each row solved from the edge functions, int64).
// With VIEW_FLAG_COUNT_OVERDRAW each covered pixel also adds 1 to the overdraw counter (binding 11)
//! variant image VISBUFFER_IMAGE
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#define VISBUFFER_BINDING 9
#include "shared.glsl"
#include "visbuffer.glsl"

layout(local_size_x = RASTER_SW_WORKGROUP_SIZE) in;

layout(set = 0, binding = 0, scalar) uniform View { ViewGpu view; };
layout(set = 0, binding = 1, scalar) readonly buffer Counters { CullCounters counters; };
layout(set = 0, binding = 2, scalar) readonly buffer Visible { uvec2 visible[]; };
layout(set = 0, binding = 3, scalar) readonly buffer SwList { uint sw_list[]; };
layout(set = 0, binding = 4, scalar) readonly buffer Instances { InstanceVgeo instances[]; };
layout(set = 0, binding = 5, scalar) readonly buffer Meshes { MeshGpu meshes[]; };
layout(set = 0, binding = 6, scalar) readonly buffer Clusters { ClusterLoc cluster_locs[]; };
layout(set = 0, binding = 7, scalar) readonly buffer Pages { PageGpu pages[]; };
layout(set = 0, binding = 8, scalar) readonly buffer Pool { uint pool[]; };

#include "raster.glsl"
#define OVERDRAW_BINDING 10
#include "overdraw.glsl"

// Bounding boxes of at most this many pixels, with vertex extents under 64 pixels (int32-safe
// edge functions), are walked pixel by pixel; others by scanline.
#define SMALL_BOX_PIXELS 64
#define SMALL_EXTENT_FIXED (64 * RASTER_ONE)

shared ivec2 s_xy[MAX_CLUSTER_VERTICES];
shared float s_z[MAX_CLUSTER_VERTICES];  // ndc depth; < 0: the vertex cannot be snapped

void raster_triangle(ivec2 v[3], vec3 z, uint visible_index, uint tri, uint width, uint height) {
    int64_t area = edge_fn(v[0], v[1], v[2]);
    if (area == 0) {
        return;
    }
    if (area < 0) {
        ivec2 t = v[1]; v[1] = v[2]; v[2] = t;
        z = z.xzy;
        area = -area;
    }
    ivec2 lo = min(v[0], min(v[1], v[2]));
    ivec2 hi = max(v[0], max(v[1], v[2]));
    // Pixels whose centre lies in the box, clamped to the screen (floor division by >>).
    int x0 = max((lo.x - RASTER_HALF + RASTER_ONE - 1) >> SUBPIXEL_BITS, 0);
    int x1 = min((hi.x - RASTER_HALF) >> SUBPIXEL_BITS, int(width) - 1);
    int y0 = max((lo.y - RASTER_HALF + RASTER_ONE - 1) >> SUBPIXEL_BITS, 0);
    int y1 = min((hi.y - RASTER_HALF) >> SUBPIXEL_BITS, int(height) - 1);
    if (x0 > x1 || y0 > y1) {
        return;
    }
    precise float inv_area = 1.0 / float(area);
    // Edge k is opposite vertex k: from a = v[k+1] to b = v[k+2].
    ivec3 dx, dy, bias;
    for (int k = 0; k < 3; k++) {
        ivec2 a = v[(k + 1) % 3];
        ivec2 b = v[(k + 2) % 3];
        dx[k] = b.x - a.x;
        dy[k] = b.y - a.y;
        bool top_left = (dy[k] == 0 && dx[k] > 0) || dy[k] < 0;
        bias[k] = top_left ? 0 : -1;
    }
    ivec2 extent = hi - lo;
    int box = (x1 - x0 + 1) * (y1 - y0 + 1);
    if (box <= SMALL_BOX_PIXELS && extent.x < SMALL_EXTENT_FIXED && extent.y < SMALL_EXTENT_FIXED) {
        // Bounding-box walk, int32 edge functions relative to `lo` (translation-invariant, exact).
        ivec2 start = ivec2(x0, y0) * RASTER_ONE + RASTER_HALF - lo;
        ivec3 row;
        for (int k = 0; k < 3; k++) {
            ivec2 a = v[(k + 1) % 3] - lo;
            row[k] = dx[k] * (start.y - a.y) - dy[k] * (start.x - a.x);
        }
        ivec3 step_x = -dy * RASTER_ONE;
        ivec3 step_y = dx * RASTER_ONE;
        for (int y = y0; y <= y1; y++) {
            ivec3 e = row;
            for (int x = x0; x <= x1; x++) {
                ivec3 t = e + bias;
                if ((t.x | t.y | t.z) >= 0) {
                    float d = raster_depth(float(e.x), float(e.y), float(e.z), z, inv_area);
                    vis_write(ivec2(x, y), width, vis_pack(d, visible_index, tri));
                    overdraw_count(ivec2(x, y), width);
                }
                e += step_x;
            }
            row += step_y;
        }
        return;
    }
    // Scanline walk, int64: per row, the span where every e_k + bias_k >= 0, solved per edge.
    ivec2 start = ivec2(x0, y0) * RASTER_ONE + RASTER_HALF;
    i64vec3 row;
    i64vec3 step_x, step_y;
    for (int k = 0; k < 3; k++) {
        row[k] = edge_fn(v[(k + 1) % 3], v[(k + 2) % 3], start);
        step_x[k] = -int64_t(dy[k]) * RASTER_ONE;
        step_y[k] = int64_t(dx[k]) * RASTER_ONE;
    }
    int64_t last = int64_t(x1 - x0);
    for (int y = y0; y <= y1; y++) {
        int64_t t_lo = 0;
        int64_t t_hi = last;
        for (int k = 0; k < 3; k++) {
            int64_t r = row[k] + bias[k];
            int64_t a = step_x[k];
            if (a > 0) {
                // r + t a >= 0  <=>  t >= ceil(-r / a)
                if (r < 0) {
                    t_lo = max(t_lo, (-r + a - 1) / a);
                }
            } else if (a < 0) {
                // r + t a >= 0  <=>  t <= floor(r / -a)
                t_hi = r < 0 ? int64_t(-1) : min(t_hi, r / (-a));
            } else if (r < 0) {
                t_hi = -1;
            }
        }
        if (t_lo <= t_hi) {
            i64vec3 e = row + step_x * t_lo;
            for (int64_t t = t_lo; t <= t_hi; t++) {
                float d = raster_depth(float(e.x), float(e.y), float(e.z), z, inv_area);
                vis_write(ivec2(x0 + int(t), y), width, vis_pack(d, visible_index, tri));
                overdraw_count(ivec2(x0 + int(t), y), width);
                e += step_x;
            }
        }
        row += step_y;
    }
}

void main() {
    uint width = uint(view.viewport.x);
    uint height = uint(view.viewport.y);
    uint sw_count = min(counters.sw_count, view.visible_capacity);
    uint tid = gl_LocalInvocationID.x;
    for (uint i = gl_WorkGroupID.x; i < sw_count; i += gl_NumWorkGroups.x) {
        uint visible_index = sw_list[i];
        uvec2 entry = visible[visible_index];
        InstanceVgeo inst = instances[entry.x];
        MeshGpu mesh = meshes[inst.mesh];
        Cluster c = cluster_at(mesh, entry.y);
        ClusterData d = cluster_data(mesh, c);
        uint vcount = cluster_vertex_count(c);
        uint tcount = cluster_triangle_count(c);
        for (uint k = tid; k < vcount; k += RASTER_SW_WORKGROUP_SIZE) {
            PackedVertex pv = cluster_vertex(d, k);
            vec4 clip = clip_position(relative_position(inst, decode_position(mesh, pv)));
            ivec2 xy;
            float z;
            bool ok = project_fixed(clip, xy, z);
            s_xy[k] = xy;
            s_z[k] = ok ? z : -1.0;
        }
        barrier();
        if (tid < tcount) {
            uvec3 t = cluster_triangle(d, c, tid);
            vec3 z = vec3(s_z[t.x], s_z[t.y], s_z[t.z]);
            // Behind the near plane or beyond the guard band: the cull sends such clusters to HW.
            if (min(z.x, min(z.y, z.z)) >= 0.0) {
                ivec2 v[3] = ivec2[3](s_xy[t.x], s_xy[t.y], s_xy[t.z]);
                raster_triangle(v, z, visible_index, tid, width, height);
            }
        }
        barrier();
    }
}
