#version 460
// Pass `debug_view`: the visibility buffer as colours (RGBA8 storage image), one thread per pixel.
// Modes (push constant, DebugViewPush::mode; src/passes/debug_view.rs ViewMode): 0 lit, 1 depth,
// 2 triangles, 3 clusters, 4 instances, 5 LOD level, 6 HW/SW, 7 groups, 8 overdraw (the counter at
// binding 10, filled by the rasterizers), 9 fallback (Lambert, cluster tint, cluster borders and a
// faint wireframe; the frame forces the cut to the DAG roots), 10 residency (the pages of the group
// the cluster would refine into: resident, not needed, requested this frame, wanted but missing;
// RESIDENCY_COLOR_* in src/shared.rs). Empty pixels get the background.
// The `mark` variant is the pass's first step: it flags every visible entry that is in the HW list
// (flags[] cleared to 0 before), which the HW/SW mode reads.
//! variant image VISBUFFER_IMAGE
//! variant mark DEBUG_VIEW_MARK
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"

#ifdef DEBUG_VIEW_MARK

layout(local_size_x = 64) in;
layout(set = 0, binding = 0, scalar) readonly buffer Counters { CullCounters counters; };
layout(set = 0, binding = 1, scalar) readonly buffer HwList { uint hw_list[]; };
layout(set = 0, binding = 2, scalar) buffer Flags { uint hw_flags[]; };
layout(push_constant, scalar) uniform Push { uint visible_capacity; };

void main() {
    uint n = counters.hw_count;
    for (uint i = gl_GlobalInvocationID.x; i < n; i += gl_NumWorkGroups.x * 64u) {
        uint v = hw_list[i] & ~(HW_ENTRY_CULL | HW_ENTRY_MIRRORED);
        if (v < visible_capacity) {
            hw_flags[v] = 1u;
        }
    }
}

#else

#define VISBUFFER_BINDING 9
#define VISBUFFER_READONLY
#include "visbuffer.glsl"
#include "shading.glsl"

layout(local_size_x = TILE_WORKGROUP_SIZE, local_size_y = TILE_WORKGROUP_SIZE) in;

layout(set = 0, binding = 0, scalar) uniform View { ViewGpu view; };
layout(set = 0, binding = 1, scalar) readonly buffer Visible { uvec2 visible[]; };
layout(set = 0, binding = 2, scalar) readonly buffer Flags { uint hw_flags[]; };
layout(set = 0, binding = 3, scalar) readonly buffer Instances { InstanceVgeo instances[]; };
layout(set = 0, binding = 4, scalar) readonly buffer Meshes { MeshGpu meshes[]; };
layout(set = 0, binding = 5, scalar) readonly buffer Clusters { ClusterLoc cluster_locs[]; };
layout(set = 0, binding = 6, scalar) readonly buffer Pages { PageGpu pages[]; };
layout(set = 0, binding = 7, scalar) readonly buffer Pool { uint pool[]; };
layout(set = 0, binding = 8, rgba8) uniform writeonly image2D out_image;
// binding 9: the visibility buffer (visbuffer.glsl)
layout(set = 0, binding = 10, scalar) readonly buffer Overdraw { uint overdraw_counts[]; };
// The residency view: DAG groups (their pages) and the cull's page requests of this frame (per
// entry of `pages`: the largest wish to refine into the page, 0 for none; src/scene_gpu.rs).
layout(set = 0, binding = 11, scalar) readonly buffer Groups { Group groups[]; };
layout(set = 0, binding = 12) readonly buffer PageRequests { uint page_requests[]; };

layout(push_constant, scalar) uniform Push {
    vec4 background;  // sRGB-encoded
    vec4 light_dir;   // towards the light, world space
    uint mode;
    uint visible_capacity;
    uint _pad0;
    uint _pad1;
};

#include "raster.glsl"
#include "lod.glsl"

uint hash_u32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// A cluster's identity for its colour: its group and its box's five cull words (grid
// coordinates and extents), hashed. By what the cluster is, not where its page lies in the pool (a
// visible entry's word): a streamed cluster keeps its colour when its page moves to another slot.
uint cluster_id(uint at) {
    uint h = hash_u32(cluster_group(at));
    for (uint k = 0u; k < 5u; k++) {
        h = hash_u32(h ^ pool[at + k]);
    }
    return h;
}

vec3 hash_color(uint x) {
    x = hash_u32(x);
    return vec3(uvec3(x, x >> 8, x >> 16) & 0xffu) / 255.0 * 0.8 + 0.2;
}

vec3 hsv_to_rgb(float h, float s, float v) {
    vec3 k = clamp(abs(fract(h + vec3(0.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0) - 1.0, 0.0, 1.0);
    return v * mix(vec3(1.0), k, s);
}

// Groups: the hue walks the golden-ratio sequence over the group index (groups with nearby indices,
// which the builder tends to give to neighbours, land far apart on the hue circle), offset per
// instance; saturation and brightness take one of three levels each from a hash, so two groups
// whose hues happen to be close still differ.
vec3 group_color(uint instance, uint group) {
    uint h = hash_u32(group * 0x9e3779b9u ^ hash_u32(instance + 0x632be5abu));
    float offset = float(hash_u32(instance) & 0xffffu) / 65536.0;
    float hue = fract(float(group % 1048576u) * 0.61803399 + offset);
    float sat = 0.45 + 0.25 * float(h % 3u);
    float val = 0.55 + 0.2 * float((h / 3u) % 3u);
    return hsv_to_rgb(hue, sat, val);
}

// Overdraw heat ramp on log2(count): 1 dark blue, 2 light blue, 4 green, 8 red, >= 16 white.
vec3 heat_color(uint n) {
    const vec3 stops[5] = vec3[5](vec3(0.05, 0.08, 0.45), vec3(0.10, 0.55, 0.95),
                                  vec3(0.20, 0.85, 0.25), vec3(0.95, 0.25, 0.08), vec3(1.0));
    float t = clamp(log2(float(max(n, 1u))), 0.0, 4.0);
    uint i = min(uint(t), 3u);
    return mix(stops[i], stops[i + 1u], t - float(i));
}

vec3 level_color(uint level) {
    const vec3 palette[8] = vec3[8](vec3(0.10, 0.35, 0.95), vec3(0.10, 0.75, 0.85),
                                    vec3(0.15, 0.80, 0.25), vec3(0.70, 0.85, 0.10),
                                    vec3(0.95, 0.75, 0.10), vec3(0.95, 0.45, 0.10),
                                    vec3(0.90, 0.15, 0.15), vec3(0.85, 0.20, 0.80));
    return palette[min(level, 7u)];
}

// Residency: the state of the pages of the group the drawn cluster would refine into (the group
// that produced it). Only meshes with absent pages (MESH_STREAM_PARTIAL) can read other than
// resident; the cut's test is the cull's (common/cull.glsl: `!fine` with absent children is what
// makes it ask for their pages).
vec3 residency_color(uvec2 entry) {
    InstanceVgeo inst = instances[entry.x];
    MeshGpu mesh = meshes[inst.mesh];
    Cluster cl = cluster_at(entry.y);
    if ((mesh.streams & MESH_STREAM_PARTIAL) == 0u || cl.creator == NO_GROUP_ID) {
        return unpackUnorm4x8(RESIDENCY_COLOR_RESIDENT).rgb;
    }
    Group g = groups[mesh.group_offset + cl.creator];
    bool resident = true;
    bool requested = false;
    for (uint p = g.page_first; p < g.page_first + g.page_count; p++) {
        uint i = mesh.page_offset + p;
        if (pages[i].word == PAGE_NOT_RESIDENT) {
            resident = false;
            requested = requested || page_requests[i] != 0u;
        }
    }
    if (resident) {
        return unpackUnorm4x8(RESIDENCY_COLOR_RESIDENT).rgb;
    }
    float scale = inst.max_scale;
    // The cluster's self pair is its creator group's (common/cull.glsl), its error weighted as the
    // cull weighs it.
    vec3 sc = relative_position(inst, view, g.lod_sphere.xyz);
    float e = weighted_error(g.error, g.coverage, instance_weight(inst, mesh, view));
    float self_px = lod_error_px(e * scale, sc, g.lod_sphere.w * scale, view.proj_scale);
    if (self_px > view.error_px) {
        return unpackUnorm4x8(RESIDENCY_COLOR_MISSING).rgb;
    }
    return unpackUnorm4x8(requested ? RESIDENCY_COLOR_REQUESTED : RESIDENCY_COLOR_NOT_NEEDED).rgb;
}

// Lambert shading with the interpolated vertex normal at the pixel centre (barycentrics from the
// view ray through the pixel, camera-relative space).
vec3 lit_color(uvec2 entry, uint tri, ivec2 px) {
    InstanceVgeo inst = instances[entry.x];
    MeshGpu mesh = meshes[inst.mesh];
    Cluster c = cluster_at(entry.y);
    ClusterData d = cluster_data(mesh, c);
    uvec3 t = cluster_triangle(d, c, tri);
    vec3 p[3];
    vec3 n[3];
    for (uint k = 0u; k < 3u; k++) {
        PackedVertex pv = cluster_vertex(d, t[k]);
        p[k] = relative_position(inst, decode_position(mesh, pv));
        n[k] = decode_normal(pv.normal, mesh.normal_scale);
    }
    vec2 ndc = (vec2(px) + 0.5) * view.viewport.zw * 2.0 - 1.0;
    vec4 a = inverse(view.view_proj) * vec4(ndc, 1.0, 1.0);
    vec3 dir = a.xyz / a.w;
    vec3 e1 = p[1] - p[0];
    vec3 e2 = p[2] - p[0];
    vec3 pv = cross(dir, e2);
    float det = dot(e1, pv);
    mat3 lin = mat3(inst.linear[0].xyz, inst.linear[1].xyz, inst.linear[2].xyz);
    mat3 normal_matrix = transpose(inverse(lin));
    vec3 normal;
    if (abs(det) > 1e-30) {
        vec3 tv = -p[0];
        float u = clamp(dot(tv, pv) / det, 0.0, 1.0);
        float v = clamp(dot(dir, cross(tv, e1)) / det, 0.0, 1.0 - u);
        normal = normal_matrix * (n[0] * (1.0 - u - v) + n[1] * u + n[2] * v);
    } else {
        normal = cross(e1, e2);
    }
    if (!(dot(normal, normal) > 0.0)) {
        normal = cross(e1, e2);
    }
    return encode_srgb(shade_lambert(inst.color.rgb, normal, light_dir.xyz));
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    uint width = uint(view.viewport.x);
    uint height = uint(view.viewport.y);
    if (px.x >= int(width) || px.y >= int(height)) {
        return;
    }
    uint64_t value = vis_read(px, width);
    vec3 color = background.rgb;
    if (mode == 8u) {
        // Overdraw: the count alone (it is 0 exactly where nothing was rasterized).
        uint n = overdraw_counts[uint(px.y) * width + uint(px.x)];
        imageStore(out_image, px, vec4(n == 0u ? background.rgb : heat_color(n), 1.0));
        return;
    }
    if (value != 0ul) {
        float depth = uintBitsToFloat(uint(value >> 32));
        uint lo = uint(value);
        uint tri = lo & ((1u << VISBUFFER_TRIANGLE_BITS) - 1u);
        uint visible_index = lo >> VISBUFFER_TRIANGLE_BITS;
        uvec2 entry = visible_index < visible_capacity ? visible[visible_index] : uvec2(0u);
        switch (mode) {
        case 0u:
            color = lit_color(entry, tri, px);
            break;
        case 1u:
        {
            // Reverse-Z depth is near / distance: t = log2(distance / near) in stops from the near
            // plane. Brightness falls over 16 stops, the hue cycles 4 times per stop.
            float t = clamp(-log2(max(depth, 1e-30)), 0.0, 16.0);
            vec3 hue = 0.75 + 0.25 * cos(6.2831853 * (fract(t * 4.0) + vec3(0.0, 0.333, 0.667)));
            color = (1.0 - t / 16.0) * hue;
            break;
        }
        case 2u:
            color = hash_color(lo);
            break;
        case 3u:
            color = hash_color(cluster_id(entry.y) * 0x9e3779b9u + entry.x);
            break;
        case 4u:
            color = hash_color(entry.x);
            break;
        case 5u:
            color = level_color(cluster_at(entry.y).level);
            break;
        case 7u:
            color = group_color(entry.x, cluster_at(entry.y).group);
            break;
        case 9u:
        {
            // The fallback (root) clusters: Lambert, a light tint per cluster, dark lines where the
            // right or lower neighbour shows another cluster, faint ones where it shows another
            // triangle of the same cluster (the proxy's wireframe).
            vec3 tint = hash_color(cluster_id(entry.y) * 0x9e3779b9u + entry.x);
            color = lit_color(entry, tri, px) * mix(vec3(1.0), tint, 0.35);
            float edge = 1.0;
            for (int k = 0; k < 2; k++) {
                ivec2 q = px + (k == 0 ? ivec2(1, 0) : ivec2(0, 1));
                if (q.x < int(width) && q.y < int(height)) {
                    uint64_t nv = vis_read(q, width);
                    if (nv != 0ul && uint(nv) != lo) {
                        bool same_cluster = (uint(nv) >> VISBUFFER_TRIANGLE_BITS) == visible_index;
                        edge = min(edge, same_cluster ? 0.75 : 0.25);
                    }
                }
            }
            color *= edge;
            break;
        }
        case 10u:
            color = residency_color(entry);
            break;
        default: {
            bool hw = visible_index < visible_capacity && hw_flags[visible_index] != 0u;
            color = hw ? vec3(0.95, 0.45, 0.10) : vec3(0.15, 0.45, 0.95);
            break;
        }
        }
    }
    imageStore(out_image, px, vec4(color, 1.0));
}

#endif
