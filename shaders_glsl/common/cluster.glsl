// A cluster read from its page (src/builder/page.rs): the resident locator `cluster_locs[ci]`
// (ClusterLocGpu: page and word) gives where its data starts in the pool, and its first
// CLUSTER_CULL_WORDS words are what the passes need of it: bounds (min, max as f32 bits),
// `vertex_count | triangle_count << 8 | level << 16`, group and creator group.
//
// The including shader declares `cluster_locs[]` (ClusterLoc), `pages[]` (PageGpu) and `pool[]`
// (uint) before including this file. The cluster's page must be resident. The LOD pairs
// (self_*, parent_*) are left zero: they are its groups' (cull.glsl `cluster_with_pairs`).
#ifndef VGEO_CLUSTER_GLSL
#define VGEO_CLUSTER_GLSL

// The first pool word of cluster `ci`'s data (its cull words, then its vertex code).
uint cluster_word(MeshGpu mesh, uint ci) {
    ClusterLoc loc = cluster_locs[ci];
    return pages[mesh.page_offset + loc.page].word + loc.data_offset;
}

Cluster cluster_at(MeshGpu mesh, uint ci) {
    ClusterLoc loc = cluster_locs[ci];
    uint at = pages[mesh.page_offset + loc.page].word + loc.data_offset;
    Cluster c;
    c.bounds_min = uintBitsToFloat(uvec3(pool[at], pool[at + 1u], pool[at + 2u]));
    c.bounds_max = uintBitsToFloat(uvec3(pool[at + 3u], pool[at + 4u], pool[at + 5u]));
    uint info = pool[at + 6u];
    c.counts = info & 0xffffu;
    c.level = info >> 16;
    c.group = pool[at + 7u];
    c.creator = pool[at + 8u];
    c.page = loc.page;
    c.data_offset = loc.data_offset;
    c.self_sphere = vec4(0.0);
    c.self_error = 0.0;
    c.parent_sphere = vec4(0.0);
    c.parent_error = 0.0;
    return c;
}

uint cluster_vertex_count(Cluster c) { return c.counts & 0xffu; }
uint cluster_triangle_count(Cluster c) { return (c.counts >> 8) & 0xffu; }

#endif
