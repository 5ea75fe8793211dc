#version 460
// Pass `raster_sw`: the compute rasterizer for small triangles. The first
// CullCounters.sw_dispatch.w workgroups take the small clusters (CullCounters.sw_small_count, at
// the SW list's end) two at a time (raster_small, below), the next sw_quarter_groups the smallest
// (sw_quarter_count, at the HW list's end) four at a time; the others one workgroup per SW cluster
// (grid-stride over the list's front: sw_count - sw_small_count - sw_quarter_count entries), the
// cluster's vertices decoded, transformed and snapped into shared memory, then one thread per
// triangle: fixed-point edge functions (SUBPIXEL_BITS) with the top-left rule exactly as
// src/reference/raster.rs, depth from the snapped positions, atomicMax into the visibility
// buffer. Small triangles walk their bounding box with int32 edge functions, larger ones walk
// scanlines (the covered span of each row solved from the int64 edge functions without an int64
// division: a float estimate made exact, first_inside / last_inside), and those whose box exceeds
// RASTER_SW_BIG_BOX_PIXELS are left to the whole workgroup after the per-thread pass (pieces of
// rows, one per invocation), so one large triangle does not hold its cluster's workgroup for as
// many steps as it has pixels.
// With VIEW_FLAG_COUNT_OVERDRAW each covered pixel also adds 1 to the overdraw counter (binding 10).
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
// Binding 9: the visibility buffer; 10: the overdraw counter. The HW list's end holds the
// quarter path's clusters.
layout(set = 0, binding = 11, scalar) readonly buffer HwList { uint hw_list[]; };

#include "raster.glsl"
#define OVERDRAW_BINDING 10
#include "overdraw.glsl"

// Bounding boxes of at most this many pixels, with vertex extents under 64 pixels (int32-safe
// edge functions), are walked pixel by pixel; others by scanline.
#define SMALL_BOX_PIXELS 64
#define SMALL_EXTENT_FIXED (64 * RASTER_ONE)

// Triangles whose pixel box is larger than this are rasterized by the whole workgroup after the
// per-thread pass (rows cut into RASTER_SW_CHUNK-pixel pieces, dealt round-robin), so that a
// cluster with a few large triangles does not wait for one invocation to walk each of them alone.
// 64 measured best of 64 / 256 / 1024 on the H100 (bench/results/2026-11-25-session15, call 8).
#define RASTER_SW_BIG_BOX_PIXELS 64
#define RASTER_SW_CHUNK 32

// Both paths keep their shared data in one array, so that the small path's two clusters fit in
// what the other path needs for one (its size bounds how many workgroups an SM holds: arrays of
// its own for the small path cost stress 20-28 % and foliage 39 %, bench/results/
// 2026-11-26-session23, call 9; twice the arrays, stress 15 % and foliage 11 %, session 26, call 1):
// - a snapped vertex in three words from its entry on (snap_vertices; read by sw_vertex_xy and
//   sw_vertex_z): fixed-point x, y and the ndc depth's bits (< 0: the vertex cannot be
//   snapped); the other path's cluster has vertex k at entry 3k, the small path's half h at
//   SMALL_HALF_WORDS * h + 3k (clusters of at most RASTER_SW_SMALL_VERTICES vertices), its
//   quarter q at SMALL_QUARTER_WORDS * q + 3k (RASTER_SW_QUARTER_VERTICES);
// - the other path's triangles left to its shared pass at SW_BIG + b (big_entry: the triangle's
//   index in the cluster and its corners, so that the shared pass needs no cluster data), and
//   their pieces (rows x RASTER_SW_CHUNK columns) at SW_PIECES + b.
#define SW_BIG (3u * MAX_CLUSTER_VERTICES)
#define SW_PIECES (SW_BIG + MAX_CLUSTER_TRIANGLES)
#define SW_WORDS (SW_PIECES + MAX_CLUSTER_TRIANGLES)
#define SMALL_HALF_WORDS (3u * RASTER_SW_SMALL_VERTICES)
#define SMALL_QUARTER_WORDS (3u * RASTER_SW_QUARTER_VERTICES)
shared uint s_mem[SW_WORDS];
shared uint s_big_count;

// A triangle ready to rasterize: counter-clockwise snapped vertices, their depths, the pixel box
// (pixel centres inside the vertices' box, clamped to the screen) and the edge functions' steps.
struct Tri {
    ivec2 v[3];
    vec3 z;
    float inv_area;
    ivec3 dx, dy, bias;
    int x0, x1, y0, y1;
    ivec2 lo;
};

// False: nothing to draw (no area, or no pixel centre in the box on screen).
bool tri_setup(ivec2 v[3], vec3 z, uint width, uint height, out Tri t) {
    t.v = v;
    t.z = z;
    t.inv_area = 0.0;
    t.dx = t.dy = t.bias = ivec3(0);
    ivec2 lo = min(v[0], min(v[1], v[2]));
    ivec2 hi = max(v[0], max(v[1], v[2]));
    t.lo = lo;
    // Pixels whose centre lies in the box, clamped to the screen (floor division by >>). Most
    // triangles of a far instance hold none, so this test comes before the area's (stress N=200
    // -1.4 %, foliage -0.5 %: bench/results/2026-11-27-session27, call 2).
    t.x0 = max((lo.x - RASTER_HALF + RASTER_ONE - 1) >> SUBPIXEL_BITS, 0);
    t.x1 = min((hi.x - RASTER_HALF) >> SUBPIXEL_BITS, int(width) - 1);
    t.y0 = max((lo.y - RASTER_HALF + RASTER_ONE - 1) >> SUBPIXEL_BITS, 0);
    t.y1 = min((hi.y - RASTER_HALF) >> SUBPIXEL_BITS, int(height) - 1);
    if (t.x0 > t.x1 || t.y0 > t.y1) {
        return false;
    }
    int64_t area = edge_fn(v[0], v[1], v[2]);
    if (area == 0) {
        return false;
    }
    if (area < 0) {
        t.v[1] = v[2];
        t.v[2] = v[1];
        t.z = z.xzy;
        area = -area;
    }
    precise float inv_area = 1.0 / float(area);
    t.inv_area = inv_area;
    // Edge k is opposite vertex k: from a = v[k+1] to b = v[k+2].
    for (int k = 0; k < 3; k++) {
        ivec2 a = t.v[(k + 1) % 3];
        ivec2 b = t.v[(k + 2) % 3];
        t.dx[k] = b.x - a.x;
        t.dy[k] = b.y - a.y;
        bool top_left = (t.dy[k] == 0 && t.dx[k] > 0) || t.dy[k] < 0;
        t.bias[k] = top_left ? 0 : -1;
    }
    return true;
}

// The first i in 0..n + 1 with r + i a >= 0, for a > 0 (n + 1: none up to n). ceil(-r / a) is
// estimated in float: two int64-to-float conversions (an ulp each, whichever way they round) and
// a division (Vulkan allows 2.5 ulp) put the quotient within 2^-20 of its value relative to it,
// so while it is at most n + 2 (n < 2^19, rows are at most a viewport wide) the estimate is within
// one of the answer, and the int64 value at the estimate or its neighbour makes it exact. An int64
// division is a long emulated sequence on GPUs: solving rows with it cost foliage 11 % of its
// frame (bench/results/2026-11-26-session24, call 6).
int first_inside(int64_t r, int64_t a, int n) {
    if (r >= 0) {
        return 0;
    }
    int i = int(min(ceil(float(-r) / float(a)), float(n + 1)));
    if (r + int64_t(i) * a < 0) {
        i++;
    } else if (i > 0 && r + int64_t(i - 1) * a >= 0) {
        i--;
    }
    return min(i, n + 1);
}

// The last i in -1..n with r + i a >= 0, for a < 0 (-1: none from 0 on), as first_inside.
int last_inside(int64_t r, int64_t a, int n) {
    if (r < 0) {
        return -1;
    }
    int i = int(min(floor(float(r) / float(-a)), float(n)));
    if (r + int64_t(i) * a < 0) {
        i--;
    } else if (i < n && r + int64_t(i + 1) * a >= 0) {
        i++;
    }
    return i;
}

// Pixels xa..xb of row y (inside the box) that the triangle covers: the span where every
// e_k + bias_k >= 0, solved per edge from the int64 edge functions at (xa, y).
void raster_row(Tri t, int y, int xa, int xb, uint visible_index, uint tri, uint width) {
    ivec2 start = ivec2(xa, y) * RASTER_ONE + RASTER_HALF;
    i64vec3 e0, step_x;
    for (int k = 0; k < 3; k++) {
        e0[k] = edge_fn(t.v[(k + 1) % 3], t.v[(k + 2) % 3], start);
        step_x[k] = -int64_t(t.dy[k]) * RASTER_ONE;
    }
    int n = xb - xa;
    int lo = 0;
    int hi = n;
    for (int k = 0; k < 3; k++) {
        int64_t r = e0[k] + t.bias[k];
        int64_t a = step_x[k];
        if (a > 0) {
            lo = max(lo, first_inside(r, a, n));
        } else if (a < 0) {
            hi = min(hi, last_inside(r, a, n));
        } else if (r < 0) {
            hi = -1;
        }
    }
    int64_t t_lo = lo;
    int64_t t_hi = hi;
    if (t_lo <= t_hi) {
        i64vec3 e = e0 + step_x * t_lo;
        for (int64_t i = t_lo; i <= t_hi; i++) {
            float d = raster_depth(float(e.x), float(e.y), float(e.z), t.z, t.inv_area);
            ivec2 p = ivec2(xa + int(i), y);
            vis_write(p, width, vis_pack(d, visible_index, tri));
            overdraw_count(p, width);
            e += step_x;
        }
    }
}

// A triangle left to the shared pass: its index in the cluster (7 bits) and its three corners
// (8 bits each).
uint big_entry(uint tri, uvec3 t) {
    return tri | (t.x << 7) | (t.y << 15) | (t.z << 23);
}

// One invocation's triangle: small boxes walked pixel by pixel here, larger ones by rows here,
// the largest left to the workgroup (SW_BIG, `entry`) when `shared_big`.
void raster_triangle(ivec2 v[3], vec3 z, uint visible_index, uint tri, uint entry, uint width,
                     uint height, bool shared_big) {
    Tri t;
    if (!tri_setup(v, z, width, height, t)) {
        return;
    }
    ivec2 extent = max(t.v[0], max(t.v[1], t.v[2])) - t.lo;
    int box = (t.x1 - t.x0 + 1) * (t.y1 - t.y0 + 1);
    if (shared_big && box > RASTER_SW_BIG_BOX_PIXELS) {
        uint b = atomicAdd(s_big_count, 1u);
        s_mem[SW_BIG + b] = entry;
        s_mem[SW_PIECES + b] = (uint(t.x1 - t.x0) / RASTER_SW_CHUNK + 1u) * uint(t.y1 - t.y0 + 1);
        return;
    }
    if (box <= SMALL_BOX_PIXELS && extent.x < SMALL_EXTENT_FIXED && extent.y < SMALL_EXTENT_FIXED) {
        // Bounding-box walk, int32 edge functions relative to `lo` (translation-invariant, exact:
        // the same values as raster_row's).
        ivec2 start = ivec2(t.x0, t.y0) * RASTER_ONE + RASTER_HALF - t.lo;
        ivec3 row;
        for (int k = 0; k < 3; k++) {
            ivec2 a = t.v[(k + 1) % 3] - t.lo;
            row[k] = t.dx[k] * (start.y - a.y) - t.dy[k] * (start.x - a.x);
        }
        ivec3 step_x = -t.dy * RASTER_ONE;
        ivec3 step_y = t.dx * RASTER_ONE;
        for (int y = t.y0; y <= t.y1; y++) {
            ivec3 e = row;
            for (int x = t.x0; x <= t.x1; x++) {
                ivec3 b = e + t.bias;
                if ((b.x | b.y | b.z) >= 0) {
                    float d = raster_depth(float(e.x), float(e.y), float(e.z), t.z, t.inv_area);
                    vis_write(ivec2(x, y), width, vis_pack(d, visible_index, tri));
                    overdraw_count(ivec2(x, y), width);
                }
                e += step_x;
            }
            row += step_y;
        }
        return;
    }
    for (int y = t.y0; y <= t.y1; y++) {
        raster_row(t, y, t.x0, t.x1, visible_index, tri, width);
    }
}

// The snapped vertex stored from s_mem's word `at` on.
ivec2 sw_vertex_xy(uint at) {
    return ivec2(int(s_mem[at]), int(s_mem[at + 1u]));
}
float sw_vertex_z(uint at) {
    return uintBitsToFloat(s_mem[at + 2u]);
}

// Decodes, transforms and snaps the cluster's vertices `first, first + stride, ...` into s_mem
// from word `base` on, three words a vertex (z < 0: the vertex cannot be snapped).
void snap_vertices(InstanceVgeo inst, MeshGpu mesh, ClusterData d, uint vcount, uint first,
                   uint stride, uint base) {
    for (uint k = first; k < vcount; k += stride) {
        vec4 clip = cluster_vertex_clip(inst, mesh, d, k);
        ivec2 xy;
        float z;
        bool ok = project_fixed(clip, xy, z);
        uint at = base + 3u * k;
        s_mem[at] = uint(xy.x);
        s_mem[at + 1u] = uint(xy.y);
        s_mem[at + 2u] = floatBitsToUint(ok ? z : -1.0);
    }
}

// Triangle `tri` (local corners `t`, snapped from s_mem's word `base` on) of the cluster of
// `visible_index`.
void raster_snapped(uvec3 t, uint base, uint visible_index, uint tri, uint width, uint height,
                    bool shared_big) {
    uvec3 at = base + 3u * t;
    vec3 z = vec3(sw_vertex_z(at.x), sw_vertex_z(at.y), sw_vertex_z(at.z));
    // Behind the near plane or beyond the guard band: the cull sends such clusters to HW.
    if (min(z.x, min(z.y, z.z)) >= 0.0) {
        ivec2 v[3] = ivec2[3](sw_vertex_xy(at.x), sw_vertex_xy(at.y), sw_vertex_xy(at.z));
        raster_triangle(v, z, visible_index, tri, big_entry(tri, t), width, height, shared_big);
    }
}

// The small clusters (CullCounters::sw_small_count, at the end of the SW list): two to a
// workgroup, each half of it (RASTER_SW_WORKGROUP_SIZE / 2 invocations) one cluster, two
// triangles an invocation, every triangle walked by its invocation (no shared pass: a cluster
// projecting to at most RASTER_SW_SMALL_PX across, with triangles of at most
// RASTER_SW_SMALL_TRIANGLE_PX, has few triangles of a large box, and none beyond the cluster's
// extent). Their cost is per cluster (a chain of dependent reads, the barrier), so a workgroup
// takes two; the smallest (CullCounters::sw_quarter_count, at the end of the HW list, at most
// RASTER_SW_QUARTER_VERTICES vertices) four, a quarter of it each (up to four triangles an
// invocation).
// Each part keeps its cluster's vertices in its part of s_mem (3 words a vertex: the cull sends
// only clusters of at most RASTER_SW_SMALL_VERTICES / RASTER_SW_QUARTER_VERTICES vertices here).
// `parts` clusters to a workgroup (2: the SW list's end; 4: the HW list's end), each taken by
// RASTER_SW_WORKGROUP_SIZE / parts invocations with `words` words of s_mem.
void raster_small(uint parts, uint words, uint first_group, uint groups, uint small_count,
                  uint width, uint height) {
    uint lanes = RASTER_SW_WORKGROUP_SIZE / parts;
    uint part = gl_LocalInvocationID.x / lanes;
    uint lane = gl_LocalInvocationID.x % lanes;
    uint at = part * words;
    uint last = view.visible_capacity - 1u;
    for (uint p = first_group; parts * p < small_count; p += groups) {
        uint j = parts * p + part;
        bool in_list = j < small_count;
        uint visible_index = 0u;
        if (in_list) {
            visible_index = parts == 2u ? sw_list[last - j] : hw_list[last - j];
            // Only if a cluster was emitted twice (reported as a visible overflow) can the HW
            // list's ends meet, and an HW entry carries flags in its high bits: never read past
            // the visible list.
            in_list = visible_index < view.visible_capacity;
        }
        uint tcount = 0u;
        uvec3 t0 = uvec3(0u);
        Cluster c;
        ClusterData d;
        if (in_list) {
            uvec2 entry = visible[visible_index];
            InstanceVgeo inst = instances[entry.x];
            MeshGpu mesh = meshes[inst.mesh];
            c = cluster_at(entry.y);
            d = cluster_data(mesh, c);
            tcount = cluster_triangle_count(c);
            snap_vertices(inst, mesh, d, cluster_vertex_count(c), lane, lanes, at);
            if (lane < tcount) {
                t0 = cluster_triangle(d, c, lane);
            }
        }
        barrier();
        for (uint tri = lane; tri < tcount; tri += lanes) {
            uvec3 t = tri == lane ? t0 : cluster_triangle(d, c, tri);
            raster_snapped(t, at, visible_index, tri, width, height, false);
        }
        barrier();
    }
}

void main() {
    uint width = uint(view.viewport.x);
    uint height = uint(view.viewport.y);
    // The first sw_dispatch.w workgroups take the small clusters; the others the rest.
    uint small_groups = counters.sw_dispatch.w;
    uint small_count = counters.sw_small_count;
    uint quarter_groups = counters.sw_quarter_groups;
    uint quarter_count = counters.sw_quarter_count;
    if (gl_WorkGroupID.x < small_groups) {
        raster_small(2u, SMALL_HALF_WORDS, gl_WorkGroupID.x, small_groups, small_count, width, height);
        return;
    }
    if (gl_WorkGroupID.x < small_groups + quarter_groups) {
        raster_small(4u, SMALL_QUARTER_WORDS, gl_WorkGroupID.x - small_groups, quarter_groups,
                     quarter_count, width, height);
        return;
    }
    // The SW list's front (cluster_cull has clamped the counts to the capacity).
    uint sw_count = counters.sw_count - small_count - quarter_count;
    uint tid = gl_LocalInvocationID.x;
    uint head = small_groups + quarter_groups;
    uint groups = gl_NumWorkGroups.x - head;
    for (uint i = gl_WorkGroupID.x - head; i < sw_count; i += groups) {
        uint visible_index = sw_list[i];
        uvec2 entry = visible[visible_index];
        InstanceVgeo inst = instances[entry.x];
        MeshGpu mesh = meshes[inst.mesh];
        Cluster c = cluster_at(entry.y);
        ClusterData d = cluster_data(mesh, c);
        uint vcount = cluster_vertex_count(c);
        uint tcount = cluster_triangle_count(c);
        if (tid == 0u) {
            s_big_count = 0u;
        }
        snap_vertices(inst, mesh, d, vcount, tid, RASTER_SW_WORKGROUP_SIZE, 0u);
        uvec3 corners = tid < tcount ? cluster_triangle(d, c, tid) : uvec3(0u);
        barrier();
        if (tid < tcount) {
            raster_snapped(corners, 0u, visible_index, tid, width, height, true);
        }
        barrier();
        // The large triangles, by the whole workgroup: their rows cut into pieces of
        // RASTER_SW_CHUNK pixels, dealt round-robin over the invocations across all of them (the
        // same pixels and values as one invocation walking each: every pixel's edge functions
        // are computed exactly). An invocation sets a triangle up only if a piece of it is its.
        uint big = s_big_count;
        uint dealt = 0u;
        for (uint b = 0u; b < big; b++) {
            uint pieces = s_mem[SW_PIECES + b];
            uint p = (tid + RASTER_SW_WORKGROUP_SIZE - dealt % RASTER_SW_WORKGROUP_SIZE) %
                     RASTER_SW_WORKGROUP_SIZE;
            dealt += pieces;
            if (p >= pieces) {
                continue;
            }
            uint e = s_mem[SW_BIG + b];
            uint tri = e & 127u;
            uvec3 tv = 3u * uvec3((e >> 7) & 255u, (e >> 15) & 255u, e >> 23);
            ivec2 v[3] = ivec2[3](sw_vertex_xy(tv.x), sw_vertex_xy(tv.y), sw_vertex_xy(tv.z));
            Tri t;
            vec3 z = vec3(sw_vertex_z(tv.x), sw_vertex_z(tv.y), sw_vertex_z(tv.z));
            if (!tri_setup(v, z, width, height, t)) {
                continue;
            }
            uint pieces_x = uint(t.x1 - t.x0) / RASTER_SW_CHUNK + 1u;
            for (; p < pieces; p += RASTER_SW_WORKGROUP_SIZE) {
                int y = t.y0 + int(p / pieces_x);
                int xa = t.x0 + int(p % pieces_x) * RASTER_SW_CHUNK;
                raster_row(t, y, xa, min(xa + RASTER_SW_CHUNK - 1, t.x1), visible_index, tri, width);
            }
        }
        barrier();
    }
}
