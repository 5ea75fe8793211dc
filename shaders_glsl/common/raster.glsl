// Shared by the rasterizers (raster_sw, raster_hw) and debug_view: cluster data access, vertex
// decode, camera-relative transform, projection to snapped fixed-point pixels and the depth of a
// pixel from the snapped triangle. Every float expression is `precise` so that the compute and the
// vertex/fragment stages produce bit-identical values (no contraction into fma, no reassociation):
// SW and HW must agree on depth bit for bit.
//
// The including shader declares the scene buffers with these names before including this file:
// `instances[]` (InstanceVgeo), `meshes[]` (MeshGpu), `cluster_locs[]` (ClusterLoc), `pages[]`
// (PageGpu), `pool[]` (uint: the geometry pool, every resident page's bytes) and `view` (ViewGpu). A shader with only `view` defines RASTER_NO_SCENE first (fixed-point helpers only).
#ifndef VGEO_RASTER_GLSL
#define VGEO_RASTER_GLSL

// Fixed point: one pixel = 1 << SUBPIXEL_BITS.
#define RASTER_ONE (1 << SUBPIXEL_BITS)
#define RASTER_HALF (RASTER_ONE / 2)
// Viewport coordinates beyond this many pixels from the origin are not snapped (the triangle goes
// elsewhere: skipped by SW, clipped_depth in HW). Keeps fixed-point coordinates within 2^28 so
// that edge functions fit in int64 (and a coordinate in int32).
#define RASTER_GUARD_PIXELS 1048576.0

#ifndef RASTER_NO_SCENE
#include "cluster.glsl"

// A cluster's encoded data in the pool (src/builder/page.rs): where its vertices and triangles
// start, the per-field bit widths and the minimums its vertices are coded from.
struct ClusterData {
    uint vertex_word;    // first word of the vertex bit stream
    uint triangle_word;  // first word of the triangle code (tricode.rs)
    uint vertex_bits;
    uint wx;             // bit widths: position x, y, z, normal x, normal y, uv (per
    uint wy;             // component), material
    uint wz;
    uint wnx;
    uint wny;
    uint wu;
    uint wm;
    uvec3 position_min;
    uint triangle_head;  // the triangle code's header: the corner offsets' width (tricode.rs)
    uint normal_min;     // two i16
    uint uv_min;         // two u16
    uint material_min;
};

// Mask of the low `bits` (0..32) bits.
uint low_mask(uint bits) {
    return bits >= 32u ? 0xffffffffu : (1u << bits) - 1u;
}

// The `bits` (0..32) bits at bit `bit` of the stream starting at pool word `word0`. Always reads
// two words, without a branch (threads of a wave read fields at different alignments): every
// page ends with a spare word, so the second read stays inside the page.
uint pool_field(uint word0, uint bit, uint bits) {
    uint w = word0 + (bit >> 5);
    uint sh = bit & 31u;
    uint v = (pool[w] >> sh) | ((pool[w + 1u] << 1u) << (31u - sh));
    return v & low_mask(bits);
}

// 64 bits of the stream starting at pool word `word0`, from bit `bit` on (three words read; the
// third may be the page's spare word).
uint64_t pool_bits64(uint word0, uint bit) {
    uint w = word0 + (bit >> 5);
    uint sh = bit & 31u;
    uint64_t lo = uint64_t(pool[w]) | (uint64_t(pool[w + 1u]) << 32);
    uint64_t hi = uint64_t(pool[w + 2u]);
    return (lo >> sh) | ((hi << 31) << (33u - sh));
}

// The cluster's data, from its page's slot (the page must be resident).
ClusterData cluster_data(MeshGpu mesh, Cluster c) {
    ClusterData d;
    // The smallest coordinates (the first cull words); x's high bits hold more (below).
    uint px = pool[c.word];
    d.position_min = uvec3(px & ((1u << CLUSTER_COORD_BITS) - 1u), pool[c.word + 1u],
        pool[c.word + 2u]);
    // Above them the triangle code's header, then the normals' y components' bit width.
    d.triangle_head = (px >> CLUSTER_COORD_BITS) & ((1u << TRIANGLE_HEAD_BITS) - 1u);
    d.wny = px >> (CLUSTER_COORD_BITS + TRIANGLE_HEAD_BITS);
    uint at = c.word + CLUSTER_CULL_WORDS;
    uint w = pool[at];
    d.normal_min = pool[at + 1u];
    uint h = at + 2u;
    d.uv_min = 0u;
    if ((mesh.streams & MESH_STREAM_UVS) != 0u) {
        d.uv_min = pool[h];
        h += 1u;
    }
    d.material_min = 0u;
    if ((mesh.streams & MESH_STREAM_MATERIALS) != 0u) {
        d.material_min = pool[h];
        h += 1u;
    }
    d.wx = w & 31u;
    d.wy = (w >> 5) & 31u;
    d.wz = (w >> 10) & 31u;
    d.wnx = (w >> 15) & 31u;
    d.wu = (w >> 20) & 31u;
    d.wm = (w >> 25) & 31u;
    d.vertex_bits = d.wx + d.wy + d.wz + d.wnx + d.wny + 2u * d.wu + d.wm;
    d.vertex_word = h;
    d.triangle_word = h + (cluster_vertex_count(c) * d.vertex_bits + 31u) / 32u;
    return d;
}

// The cluster's local vertex `i` (grid coordinates and normal code): the position's three fields
// (at most 63 bits) from one 64-bit window, the normal's two from one 32-bit field. A shader that
// defines RASTER_DECODE_32 first reads the position as three 32-bit fields instead (fewer
// registers: emit_gbuffer, whose occupancy they limit).
PackedVertex cluster_vertex(ClusterData d, uint i) {
    uint bit = i * d.vertex_bits;
    PackedVertex pv;
#ifdef RASTER_DECODE_32
    pv.position.x = d.position_min.x + pool_field(d.vertex_word, bit, d.wx);
    pv.position.y = d.position_min.y + pool_field(d.vertex_word, bit + d.wx, d.wy);
    pv.position.z = d.position_min.z + pool_field(d.vertex_word, bit + d.wx + d.wy, d.wz);
#else
    uint64_t p = pool_bits64(d.vertex_word, bit);
    pv.position.x = d.position_min.x + (uint(p) & low_mask(d.wx));
    pv.position.y = d.position_min.y + (uint(p >> d.wx) & low_mask(d.wy));
    pv.position.z = d.position_min.z + (uint(p >> (d.wx + d.wy)) & low_mask(d.wz));
#endif
    uint n = pool_field(d.vertex_word, bit + d.wx + d.wy + d.wz, d.wnx + d.wny);
    uint nx = (d.normal_min + (n & low_mask(d.wnx))) & 0xffffu;
    uint ny = ((d.normal_min >> 16) + (n >> d.wnx)) & 0xffffu;
    pv.normal = nx | (ny << 16);
    return pv;
}

// Bit offset of the UV fields of the cluster's local vertex `i`.
uint cluster_uv_bit(ClusterData d, uint i) {
    return i * d.vertex_bits + d.wx + d.wy + d.wz + d.wnx + d.wny;
}

// The packed UV (2 x 16 bits) of the cluster's local vertex `i` (meshes with MESH_STREAM_UVS).
uint cluster_uv(ClusterData d, uint i) {
    uint uv = pool_field(d.vertex_word, cluster_uv_bit(d, i), 2u * d.wu);
    uint u = (d.uv_min & 0xffffu) + (uv & low_mask(d.wu));
    uint v = (d.uv_min >> 16) + (uv >> d.wu);
    return (u & 0xffffu) | (v << 16);
}

// The mesh-local material of the cluster's local vertex `i` (meshes with MESH_STREAM_MATERIALS).
uint cluster_material(ClusterData d, uint i) {
    uint bit = cluster_uv_bit(d, i) + 2u * d.wu;
    return d.material_min + pool_field(d.vertex_word, bit, d.wm);
}

// The three local vertex indices of the cluster's triangle `t`, from its max-delta code
// (src/builder/tricode.rs): header `w` (from the cluster's code, `triangle_head`), then a word per
// TRIANGLE_CODE_BLOCK triangles (2-bit steps of the largest index, the block's base in bits
// 24-31), then two `w`-bit corner offsets per triangle. The largest index is the block's base
// plus the steps up to `t` (a population count); header 0: plain packed indices
// (`index_bits(vertex_count)` bits each).
uvec3 cluster_triangle(ClusterData d, Cluster c, uint t) {
    uint w = d.triangle_head;
    if (w == 0u) {
        uint vc = max(cluster_vertex_count(c), 1u);
        uint bits = uint(max(findMSB(vc - 1u) + 1, 1));
        uint mask = (1u << bits) - 1u;
        uint v = pool_field(d.triangle_word, 3u * t * bits, 3u * bits);
        return uvec3(v & mask, (v >> bits) & mask, (v >> (2u * bits)) & mask);
    }
    uint b = t / TRIANGLE_CODE_BLOCK;
    uint x = pool[d.triangle_word + b];
    uint steps = x & ((1u << (2u * (t - b * TRIANGLE_CODE_BLOCK) + 2u)) - 1u);
    uint m = (x >> 24u) + bitCount(steps) + bitCount(steps & 0x00aaaaaau) - 1u;
    uint blocks = (cluster_triangle_count(c) + TRIANGLE_CODE_BLOCK - 1u) / TRIANGLE_CODE_BLOCK;
    uint o = pool_field(d.triangle_word + blocks, 2u * w * t, 2u * w);
    return uvec3(m, m - 1u - (o & low_mask(w)), m - 1u - (o >> w));
}

// Object-space position of a vertex: origin + code * step (an fma, `precise`: rounded alike in every
// stage).
vec3 decode_position(MeshGpu mesh, PackedVertex v) {
    precise vec3 p = fma(vec3(v.position), vec3(mesh.quant_step), mesh.quant_origin);
    return p;
}

// Unit normal of an octahedral code (two i16 of magnitude at most `scale`, the mesh's
// normal_scale), as src/builder/quantize.rs decodes it.
vec3 decode_normal(uint code, float scale) {
    float x = float(int(code << 16) >> 16) / scale;
    float y = float(int(code) >> 16) / scale;
    float z = 1.0 - abs(x) - abs(y);
    float t = max(-z, 0.0);
    x += x >= 0.0 ? -t : t;
    y += y >= 0.0 ? -t : t;
    vec3 n = vec3(x, y, z);
    float l = length(n);
    return l > 0.0 ? n / l : vec3(0.0, 0.0, 1.0);
}

// Camera-relative position: (translation_hi - camera_hi) + (translation_lo - camera_lo) + linear * p,
// the linear part's columns accumulated onto the translation by fma (`precise`: Vulkan does not
// promise one rounding for fma, but every fma feeding a precise value rounds the same way in
// every stage, so raster_sw and raster_hw snap alike).
vec3 relative_position(InstanceVgeo inst, vec3 p) {
    precise vec3 t = (inst.translation_hi - view.camera_hi.xyz) + (inst.translation_lo - view.camera_lo.xyz);
    precise vec3 r = fma(inst.linear[0].xyz, vec3(p.x),
                         fma(inst.linear[1].xyz, vec3(p.y), fma(inst.linear[2].xyz, vec3(p.z), t)));
    return r;
}

// Clip-space position: view_proj * (rel, 1), its columns accumulated by fused multiply-adds.
vec4 clip_position(vec3 rel) {
    precise vec4 c = fma(view.view_proj[0], vec4(rel.x),
                         fma(view.view_proj[1], vec4(rel.y), fma(view.view_proj[2], vec4(rel.z), view.view_proj[3])));
    return c;
}

// Vertex `i` of a cluster (its data `d`) of instance `inst`, in clip space: what every rasterizer
// projects and snaps.
vec4 cluster_vertex_clip(InstanceVgeo inst, MeshGpu mesh, ClusterData d, uint i) {
    return clip_position(relative_position(inst, decode_position(mesh, cluster_vertex(d, i))));
}
#endif

// Projects a clip-space vertex to snapped fixed-point viewport coordinates (round half to even, as
// src/reference/raster.rs) and ndc depth. False when the vertex is behind the near plane (z > w), not
// finite, or beyond the guard band: such a triangle cannot be rasterized from snapped vertices.
bool project_fixed(vec4 c, out ivec2 fixed_xy, out float z) {
    fixed_xy = ivec2(0);
    z = 0.0;
    const float INF = uintBitsToFloat(0x7f800000u);
    // NaN anywhere fails one of these comparisons or the guard band's below; an infinite x or y
    // fails the guard band; an infinite z or w fails these.
    if (!(c.z <= c.w) || !(c.w > 0.0) || !(c.w < INF) || !(c.z > -INF)) {
        return false;
    }
    precise vec3 ndc = c.xyz / c.w;
    precise vec2 half_size = view.viewport.xy * 0.5;
    precise vec2 xy = ndc.xy * half_size + half_size;
    if (!(abs(xy.x) < RASTER_GUARD_PIXELS && abs(xy.y) < RASTER_GUARD_PIXELS)) {
        return false;
    }
    precise vec2 scaled = xy * float(RASTER_ONE);
    fixed_xy = ivec2(roundEven(scaled));
    z = ndc.z;
    return true;
}

// The position the hardware rasterizer is given for a vertex that project_fixed snapped: the
// snapped point itself (w = 1), so that the hardware's viewport transform and its own sub-pixel
// snap (8 bits, as raster_sw's) land on raster_sw's fixed-point vertex and both rasterizers cover
// the same pixels. The float error of x / half_size * half_size + half_size is about 1e-7 of the
// coordinate, far below half a sub-pixel step within RASTER_EXACT_PIXELS of the origin (where
// the fixed-point value is exact in a float too); farther vertices (off screen) keep `clip`, the
// same point projectively (w > 0), which the hardware snaps on its own. (Passing `clip` for
// every vertex let the H100 round a few vertices to the neighbouring sub-pixel: 4-47 pixels of a
// 1080p frame differed between SW and HW; bench/results/2026-11-25-session15, call 5.)
#define RASTER_EXACT_PIXELS 16384
vec4 hw_position(vec4 clip, ivec2 fixed_xy, float z) {
    if (any(greaterThanEqual(abs(fixed_xy), ivec2(RASTER_EXACT_PIXELS * RASTER_ONE)))) {
        return clip;
    }
    precise vec2 half_size = view.viewport.xy * 0.5;
    precise vec2 xy = vec2(fixed_xy) / float(RASTER_ONE);
    precise vec2 ndc = (xy - half_size) / half_size;
    return vec4(ndc, z, 1.0);
}

// Edge function E_ab(p) = (b - a) x (p - a), exact in int64.
int64_t edge_fn(ivec2 a, ivec2 b, ivec2 p) {
    return int64_t(b.x - a.x) * int64_t(p.y - a.y) - int64_t(b.y - a.y) * int64_t(p.x - a.x);
}

// Whether the hardware path drops a triangle of a HW-list entry with flags `entry` (HW_ENTRY_*):
// with HW_ENTRY_CULL, a face turned away from the camera (common/cull.glsl hw_entry_flags).
// Snapped (all three corners): by the sign of its snapped area, what every rasterizer covers by.
// Otherwise by the sign of the determinant of its clip-space (x, y, w) rows (`p0`..`p2`), the
// side of its plane the eye is on, right also across the near plane, where that sign is clear of
// rounding. With all w > 0 the two signs agree: the area is the determinant over w0 w1 w2 times
// a positive scale.
bool hw_faces_away(uint entry, bool snapped, ivec2 a, ivec2 b, ivec2 c, vec3 p0, vec3 p1, vec3 p2) {
    if ((entry & HW_ENTRY_CULL) == 0u) {
        return false;
    }
    bool mirrored = (entry & HW_ENTRY_MIRRORED) != 0u;
    if (snapped) {
        int64_t area = edge_fn(a, b, c);
        return mirrored ? area < 0 : area > 0;
    }
    float det = dot(p0, cross(p1, p2));
    if (!(abs(det) > 1e-5 * length(p0) * length(p1) * length(p2))) {
        return false;
    }
    return mirrored ? det < 0.0 : det > 0.0;
}

// The depth plane of a triangle that cannot be snapped (a vertex behind the near plane, which
// the hardware clips, or beyond the guard band), from its vertices' clip-space x, y and w (one
// vertex per component): 2D homogeneous interpolation (Olano and Greer), so the value depends on
// the triangle and the pixel only, not on how a pipeline clipped it (raster_hw's mesh and vertex
// paths agree bit for bit). In (x, y, w) space the triangle's plane is n . (q - v0) = 0 with
// n = (v1 - v0) x (v2 - v0); the pixel's ray is q = t (ndc, 1), so 1/w = n . (ndc, 1) / n . v0.
// Reverse-Z infinite projection: every vertex's clip z is the matrix's constant term
// (view_proj[3][2], the near distance), so depth = z / w = a . (ndc, 1) with the coefficients
// a = n view_proj[3][2] / (n . v0) returned here, once per triangle (the geometry stage), so a
// fragment pays one dot product (clipped_depth). Not finite for a triangle degenerate in clip
// space.
vec3 clipped_plane(vec3 x, vec3 y, vec3 w) {
    precise vec3 v0 = vec3(x.x, y.x, w.x);
    precise vec3 n = cross(vec3(x.y, y.y, w.y) - v0, vec3(x.z, y.z, w.z) - v0);
    precise float den = dot(n, v0);
    precise float k = view.view_proj[3][2] / den;
    precise vec3 a = n * k;
    return a;
}

// Depth at pixel `px` of the plane `a` (clipped_plane); `fallback` where it is not finite.
float clipped_depth(ivec2 px, vec3 a, float fallback) {
    precise vec2 ndc = (vec2(px) + 0.5) * view.viewport.zw * 2.0 - 1.0;
    precise float d = dot(a, vec3(ndc, 1.0));
    return (isnan(d) || isinf(d)) ? fallback : clamp(d, 0.0, 1.0);
}

// Depth from the (positively oriented) edge values of a pixel: sum(e_k z_k) / area, the same float
// operations in every rasterizer so that SW and HW agree bit for bit.
float raster_depth(float e0, float e1, float e2, vec3 z, float inv_area) {
    precise float d = (e0 * z.x + e1 * z.y + e2 * z.z) * inv_area;
    return clamp(d, 0.0, 1.0);
}

#endif
