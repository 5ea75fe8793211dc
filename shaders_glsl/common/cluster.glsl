// A cluster read from its page (src/builder/page.rs): the resident locator `cluster_locs[ci]`
// (ClusterLocGpu: page and word) gives where its data starts in the pool, and its first
// CLUSTER_CULL_WORDS words are what the passes need of it. Their layout, read only here:
// words 0-2 bounds min and 3-5 bounds max (f32 bits), 6 `vertex_count | triangle_count << 8 |
// level << 16 | size_code << 24` (8 bits each; the size code of its triangles: src/builder/size.rs),
// 7 its group, 8 its creator group. Its LOD pairs are its groups' (cull.glsl). The cull writes
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
vec3 cluster_bounds_min(uint at) {
    return uintBitsToFloat(uvec3(pool[at], pool[at + 1u], pool[at + 2u]));
}
vec3 cluster_bounds_max(uint at) {
    return uintBitsToFloat(uvec3(pool[at + 3u], pool[at + 4u], pool[at + 5u]));
}
// `vertex_count | triangle_count << 8 | level << 16 | size_code << 24`.
uint cluster_info(uint at) {
    return pool[at + 6u];
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
    return pool[at + 7u];
}
uint cluster_creator(uint at) {
    return pool[at + 8u];
}

// The cluster whose data starts at pool word `at`: what a visible-list entry names.
Cluster cluster_at(uint at) {
    uint info = cluster_info(at);
    Cluster c;
    c.bounds_min = cluster_bounds_min(at);
    c.bounds_max = cluster_bounds_max(at);
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
