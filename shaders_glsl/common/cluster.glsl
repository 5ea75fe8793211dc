// A cluster read from its page (src/builder/page.rs): the resident locator `cluster_locs[ci]`
// (ClusterLocGpu: page and word) gives where its data starts in the pool, and its first
// CLUSTER_CULL_WORDS words are what the passes need of it. Their layout, read only here and in
// raster.glsl's cluster_data: words 0-2 its smallest grid coordinates (CLUSTER_COORD_BITS each;
// x's high bits the triangle code's header and the normals' y width), 3-4 the extents (x in bits
// 0-20 of word 3, y in its bits 21-31 and bits 0-9 of word 4, z in bits 10-30 of word 4), 5
// `vertex_count | triangle_count << 8 | level << 16 | size_code << 24` (8 bits each; the size
// code of its triangles: src/builder/size.rs), 6 its group, 7 its creator group. Its LOD pairs are its groups' (cull.glsl). The cull writes
// that pool word into the visible list (`uvec2(instance, word)`), so the passes that read a
// visible cluster (rasterizers, material passes, debug views) go straight to its data with
// `cluster_at`, without the locator and the page table: a chain of dependent reads shorter by two
// (stress -1.5 to -2 % on the H100, bench/results/2026-11-26-session24, calls 1 and 6). The CPU's
// read-back turns words back into cluster indices (GpuScene::clusters_at_words).
//
// The including shader declares `cluster_locs[]` (ClusterLoc), `pages[]` (PageGpu) and `pool[]`
// (uint) before including this file. The cluster's page must be resident.
#ifndef VGEO_CLUSTER_GLSL
#define VGEO_CLUSTER_GLSL

// The first pool word of cluster `ci`'s data (its cull words, then its vertex code).
uint cluster_word(MeshGpu mesh, uint ci) {
    ClusterLoc loc = cluster_locs[ci];
    return pages[mesh.page_offset + loc.page].word + loc.data_offset;
}

// The cull words of the cluster whose data starts at pool word `at`.
// Its smallest grid coordinates.
uvec3 cluster_grid_min(uint at) {
    return uvec3(pool[at] & ((1u << CLUSTER_COORD_BITS) - 1u), pool[at + 1u], pool[at + 2u]);
}
// Its largest grid coordinates.
uvec3 cluster_grid_max(uint at) {
    uint a = pool[at + 3u];
    uint b = pool[at + 4u];
    uint m = (1u << CLUSTER_COORD_BITS) - 1u;
    uvec3 e = uvec3(a & m, (a >> CLUSTER_COORD_BITS) | ((b << (32u - CLUSTER_COORD_BITS)) & m),
        b >> (2u * CLUSTER_COORD_BITS - 32u));
    return cluster_grid_min(at) + e;
}
// A grid corner in the mesh's space, decoded as raster.glsl's decode_position decodes a vertex
// (one fma, `precise`): the box of a cluster's grid coordinates holds every vertex the
// rasterizers draw of it, and where the fma rounds once (NVIDIA, lavapipe; Vulkan does not
// promise it) equals the record's bounds bit for bit (src/builder/quantize.rs, grid_corner).
vec3 grid_corner(MeshGpu mesh, uvec3 c) {
    precise vec3 p = fma(vec3(c), vec3(mesh.quant_step), mesh.quant_origin);
    return p;
}
vec3 cluster_bounds_min(MeshGpu mesh, uint at) {
    return grid_corner(mesh, cluster_grid_min(at));
}
vec3 cluster_bounds_max(MeshGpu mesh, uint at) {
    return grid_corner(mesh, cluster_grid_max(at));
}
// `vertex_count | triangle_count << 8 | level << 16 | size_code << 24`.
uint cluster_info(uint at) {
    return pool[at + 5u];
}
uint info_triangles(uint info) { return (info >> 8) & 0xffu; }
uint info_level(uint info) { return (info >> 16) & 0xffu; }
// The edge-length equivalent of the cluster's triangles (src/builder/size.rs:
// sqrt(2 sum(A^2) / sum(A)) over their areas A) as a share of its bounds' diagonal, rounded up to
// a step of 1/CLUSTER_SIZE_STEPS octave.
float info_size_ratio(uint info) {
    return exp2((float(info >> 24) - float(CLUSTER_SIZE_CODE_MAX)) / float(CLUSTER_SIZE_STEPS));
}
uint cluster_group(uint at) {
    return pool[at + 6u];
}
uint cluster_creator(uint at) {
    return pool[at + 7u];
}

// The cluster whose data starts at pool word `at`: what a visible-list entry names.
Cluster cluster_at(uint at) {
    uint info = cluster_info(at);
    Cluster c;
    c.counts = info & 0xffffu;
    c.level = info_level(info);
    c.group = cluster_group(at);
    c.creator = cluster_creator(at);
    c.word = at;
    return c;
}

uint cluster_vertex_count(Cluster c) { return c.counts & 0xffu; }
uint cluster_triangle_count(Cluster c) { return (c.counts >> 8) & 0xffu; }

#endif
