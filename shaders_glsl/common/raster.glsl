// Shared by the rasterizers (raster_sw, raster_hw) and debug_view: cluster data access, vertex
// decode, camera-relative transform, projection to snapped fixed-point pixels and the depth of a
// pixel from the snapped triangle. Every float expression is `precise` so that the compute and the
// vertex/fragment stages produce bit-identical values (no contraction into fma, no reassociation):
// SW and HW must agree on depth bit for bit.
//
// The including shader declares the scene buffers with these names before including this file:
// `instances[]` (InstanceVgeo), `meshes[]` (MeshGpu), `clusters[]` (Cluster), `pages[]`
// (PageGpu), `pool[]` (uint: the geometry pool, every resident page's bytes) and `view` (ViewGpu). A shader with only `view` defines RASTER_NO_SCENE first (fixed-point helpers only).
#ifndef VGEO_RASTER_GLSL
#define VGEO_RASTER_GLSL

// Fixed point: one pixel = 1 << SUBPIXEL_BITS.
#define RASTER_ONE (1 << SUBPIXEL_BITS)
#define RASTER_HALF (RASTER_ONE / 2)
// Viewport coordinates beyond this many pixels from the origin are not snapped (the triangle goes
// elsewhere: skipped by SW, hardware depth in HW). Keeps fixed-point coordinates within 2^28 so
// that edge functions fit in int64 (and a coordinate in int32).
#define RASTER_GUARD_PIXELS 1048576.0

#ifndef RASTER_NO_SCENE
uint cluster_vertex_count(Cluster c) { return c.counts & 0xffu; }
uint cluster_triangle_count(Cluster c) { return (c.counts >> 8) & 0xffu; }
uint cluster_flags(Cluster c) { return c.counts >> 16; }

// The page holding the cluster's data.
PageGpu cluster_page(MeshGpu mesh, Cluster c) {
    return pages[mesh.page_offset + c.page];
}

// The mesh's vertex index (the builder's, see PageGpu) of the cluster's local vertex `i`.
uint cluster_vertex(PageGpu page, Cluster c, uint i) {
    uint base = page.ref_base + c.vertex_ref_offset;
    if ((cluster_flags(c) & CLUSTER_FLAG_REFS_U32) != 0u) {
        return pool[base + i];
    }
    uint w = pool[base + (i >> 1)];
    return c.vertex_base + ((w >> (16u * (i & 1u))) & 0xffffu);
}

// The mesh's vertex `v` as stored in its page.
PackedVertex page_vertex(PageGpu page, uint v) {
    PackedVertex pv;
    uint at = page.position_base + 2u * v;
    pv.position = uvec2(pool[at], pool[at + 1u]);
    pv.normal = pool[page.normal_base + v];
    return pv;
}

// The packed UV (2 x 16 bits) of the mesh's vertex `v` (meshes with MESH_STREAM_UVS).
uint page_uv(PageGpu page, uint v) {
    return pool[page.uv_base + v];
}

// The mesh-local material of the mesh's vertex `v` (meshes with MESH_STREAM_MATERIALS).
uint page_material(PageGpu page, uint v) {
    uint h = page.material_base + v;
    return (pool[h >> 1] >> (16u * (h & 1u))) & 0xffffu;
}

// The three local vertex indices of the cluster's triangle `t`. Indices are bit-packed per cluster
// (src/builder/mod.rs `pack_indices`): `index_bits(vertex_count)` bits each, little-endian, from the
// cluster's 4-byte-aligned `triangle_offset`.
uvec3 cluster_triangle(PageGpu page, Cluster c, uint t) {
    uint vc = max(cluster_vertex_count(c), 1u);
    uint bits = uint(max(findMSB(vc - 1u) + 1, 1));
    uint mask = (1u << bits) - 1u;
    uint word0 = page.triangle_base + (c.triangle_offset >> 2);
    uint base = 3u * t * bits;
    uvec3 r;
    for (uint k = 0u; k < 3u; k++) {
        uint bit = base + k * bits;
        uint w = word0 + (bit >> 5);
        uint sh = bit & 31u;
        uint v = pool[w] >> sh;
        if (sh + bits > 32u) {
            v |= pool[w + 1u] << (32u - sh);
        }
        r[k] = v & mask;
    }
    return r;
}

// Object-space position of a packed vertex: origin + code * step (21 bits per axis).
vec3 decode_position(MeshGpu mesh, PackedVertex v) {
    uint lo = v.position.x;
    uint hi = v.position.y;
    uvec3 code = uvec3(lo & 0x1fffffu, (lo >> 21) | ((hi & 0x3ffu) << 11), (hi >> 10) & 0x1fffffu);
    precise vec3 p = mesh.quant_origin + vec3(code) * mesh.quant_step;
    return p;
}

// Unit normal of an octahedral code (2 x 16-bit snorm), as src/builder/quantize.rs decodes it.
vec3 decode_normal(uint code) {
    float x = float(int(code << 16) >> 16) / 32767.0;
    float y = float(int(code) >> 16) / 32767.0;
    float z = 1.0 - abs(x) - abs(y);
    float t = max(-z, 0.0);
    x += x >= 0.0 ? -t : t;
    y += y >= 0.0 ? -t : t;
    vec3 n = vec3(x, y, z);
    float l = length(n);
    return l > 0.0 ? n / l : vec3(0.0, 0.0, 1.0);
}

// Camera-relative position: (translation_hi - camera_hi) + (translation_lo - camera_lo) + linear * p.
vec3 relative_position(InstanceVgeo inst, vec3 p) {
    precise vec3 t = (inst.translation_hi - view.camera_hi.xyz) + (inst.translation_lo - view.camera_lo.xyz);
    precise vec3 l = inst.linear[0].xyz * p.x + inst.linear[1].xyz * p.y + inst.linear[2].xyz * p.z;
    precise vec3 r = t + l;
    return r;
}

vec4 clip_position(vec3 rel) {
    precise vec4 c = view.view_proj * vec4(rel, 1.0);
    return c;
}
#endif

// Projects a clip-space vertex to snapped fixed-point viewport coordinates (round half to even, as
// src/reference/raster.rs) and ndc depth. False when the vertex is behind the near plane (z > w), not
// finite, or beyond the guard band: such a triangle cannot be rasterized from snapped vertices.
bool project_fixed(vec4 c, out ivec2 fixed_xy, out float z) {
    fixed_xy = ivec2(0);
    z = 0.0;
    if (!(c.z <= c.w) || !(c.w > 0.0) || any(isnan(c)) || any(isinf(c))) {
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

// Edge function E_ab(p) = (b - a) x (p - a), exact in int64.
int64_t edge_fn(ivec2 a, ivec2 b, ivec2 p) {
    return int64_t(b.x - a.x) * int64_t(p.y - a.y) - int64_t(b.y - a.y) * int64_t(p.x - a.x);
}

// Depth from the (positively oriented) edge values of a pixel: sum(e_k z_k) / area, the same float
// operations in every rasterizer so that SW and HW agree bit for bit.
float raster_depth(float e0, float e1, float e2, vec3 z, float inv_area) {
    precise float d = (e0 * z.x + e1 * z.y + e2 * z.z) * inv_area;
    return clamp(d, 0.0, 1.0);
}

#endif
