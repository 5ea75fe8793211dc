// Shared by instance_cull and cluster_cull: frustum and HZB tests, the cut (with the LOD error
// projection and camera-relative transforms of lod.glsl), queue pushes and cluster emission. The
// including shader declares, before including this file: `view` (ViewGpu), `counters`
// (CullCounters), `queue` (uint64_t[]), `occ` (OcclusionGpu), `hzb` (float[]), `groups`, `pages`,
// `pool`, `cluster_locs` (and includes common/cluster.glsl), `visible`, `sw_list`, `hw_list`.
#ifndef VGEO_CULL_GLSL
#define VGEO_CULL_GLSL

#include "lod.glsl"
#include "hzb.glsl"

// A statistic of CullCounters (nothing on the GPU reads it), kept only in frames whose counters
// are read back (VIEW_FLAG_CULL_STATS, src/shared.rs).
#define CULL_STAT(counter, n) if ((view.flags & VIEW_FLAG_CULL_STATS) != 0u) { atomicAdd(counters.counter, n); }

// The distance bin (CullCounters::cold_area) of a bounding sphere at camera-relative centre `c`
// with radius `r`: COLD_BINS_PER_OCTAVE per doubling of its nearest point's distance from the
// near plane's, the last bin holding everything beyond.
uint cold_bin(vec3 c, float r) {
    float d = max(length(c) - r, view.near);
    float b = log2(d / view.near) * COLD_BINS_PER_OCTAVE;
    return b < float(COLD_DEPTH_BINS - 1u) ? uint(b) : COLD_DEPTH_BINS - 1u;
}

// Whether a camera-relative sphere touches the frustum (far plane at infinity).
bool sphere_in_frustum(ViewGpu v, vec3 c, float r) {
    for (int i = 0; i < 5; i++) {
        if (dot(v.frustum[i].xyz, c) + v.frustum[i].w < -r) {
            return false;
        }
    }
    return true;
}

// Whether an instance's object-space box lies entirely behind the HZB in `occ` (conservative: a box
// reaching the near plane or leaving the screen entirely is never called occluded here).
bool hzb_occluded(InstanceVgeo inst, vec3 bmin, vec3 bmax) {
    if (occ.enabled == 0u) {
        return false;
    }
    vec2 lo = vec2(1e30);
    vec2 hi = vec2(-1e30);
    float nearest = 0.0;
    for (int i = 0; i < 8; i++) {
        vec3 p = relative_to(inst, occ.camera_hi.xyz, occ.camera_lo.xyz, box_corner(bmin, bmax, i));
        if (!hzb_add_corner(occ.view_proj * vec4(p, 1.0), occ.near, occ.viewport.xy, lo, hi, nearest)) {
            return false;
        }
    }
    return hzb_rect_occluded(lo, hi, nearest, occ.viewport.xy, occ.levels);
}

// Pushes an (instance, BVH node) item; a full queue counts an overflow (reported) instead.
void push_item(uint64_t item) {
    atomicAdd(counters.outstanding, 1u);
    uint slot = atomicAdd(counters.queue_tail, 1u);
    if (slot >= view.queue_capacity) {
        atomicAdd(counters.queue_overflow, 1u);
        atomicAdd(counters.outstanding, 0xffffffffu);
        return;
    }
    atomicExchange(queue[slot], item);
}

// The flags of an instance's HW-list entries (src/shared.rs HW_ENTRY_*). A closed solid
// (MESH_CLOSED_SOLID) seen from outside its box, with the whole near plane outside it too, never
// shows a face turned away: every ray enters it through a face turned towards the camera first.
// Then the hardware path drops those faces (common/raster.glsl hw_faces_away). The box is the
// BVH root's (every cluster of every level), through the instance's linear part (conservative).
uint hw_entry_flags(uint instance) {
    InstanceVgeo inst = instances[instance];
    MeshGpu mesh = meshes[inst.mesh];
    if ((mesh.streams & MESH_CLOSED_SOLID) == 0u) {
        return 0u;
    }
    BvhNode root = bvh[mesh.bvh_offset + mesh.bvh_root];
    vec3 h = (root.bounds_max - root.bounds_min) * 0.5;
    vec3 c = relative_position(inst, view, root.bounds_min + h);
    mat3 linear = mat3(inst.linear[0].xyz, inst.linear[1].xyz, inst.linear[2].xyz);
    if (!near_plane_clear_of_box(c, h, linear, view.viewport.xy, view.proj_scale, view.near)) {
        return 0u;
    }
    return HW_ENTRY_CULL | (determinant(linear) < 0.0 ? HW_ENTRY_MIRRORED : 0u);
}

// Appends a drawn cluster to the visible list and to the SW or HW list. `at`: the pool word of
// its data (what the visible list holds), `info`: its cull words' info word
// (common/cluster.glsl); `center`/`radius`: its camera-relative bounding sphere (the
// radius is half its bounds' diagonal times the instance's largest axis scale).
void emit_cluster(uint instance, uint cluster_index, uint at, uint info, vec3 center, float radius) {
    uint triangles = info_triangles(info);
    uint v = atomicAdd(counters.visible_count, 1u);
    if ((view.flags & VIEW_FLAG_DIRECT_VISIBLE) != 0u) {
        // The same slot on every run: the instance's base + the cluster's index in its mesh.
        InstanceVgeo di = instances[instance];
        v = di.visible_base + (cluster_index - meshes[di.mesh].cluster_offset);
    }
    if (v >= view.visible_capacity) {
        atomicAdd(counters.visible_overflow, 1u);
        return;
    }
    visible[v] = uvec2(instance, at);
    // Clusters reaching the near plane always go to HW (the SW rasterizer cannot clip); otherwise
    // by the projected size of their triangles, unless forced.
    float dist = length(center) - radius;
    // The cluster's size across and the edge-length equivalent of its triangles (src/builder/
    // size.rs: the side of a square grid cell of their area-weighted mean area; stored relative
    // to the bounds' diagonal, 2 * radius / scale), scaled by the instance and projected at the
    // sphere's nearest point (conservative: no triangle of the cluster is nearer). Meaningful
    // only beyond the near plane.
    float across_px = 2.0 * radius * view.proj_scale / dist;
    float size_px = info_size_ratio(info) * across_px;
    bool hw;
    if (dist <= view.near) {
        hw = true;
    } else if ((view.flags & VIEW_FLAG_FORCE_HW) != 0u) {
        hw = true;
    } else if ((view.flags & VIEW_FLAG_FORCE_SW) != 0u) {
        hw = false;
    } else {
        // What the compute rasterizer's cost follows is the pixels per triangle; long thin
        // blades (a large sphere, a small area) stay in software, large triangles go to hardware.
        hw = size_px > view.hw_threshold_px;
    }
    // SW clusters that project to at most RASTER_SW_SMALL_PX across with triangles of at most
    // RASTER_SW_SMALL_TRIANGLE_PX (of at most RASTER_SW_SMALL_VERTICES) fill the SW list from its
    // end (raster_sw draws them two to a workgroup), those of them with at most
    // RASTER_SW_QUARTER_VERTICES the HW list from its end (four to a workgroup); the others the
    // lists from their starts. Each emitted cluster holds its own visible slot below
    // visible_capacity, so the two ends of a list never meet.
    uint vertices = info & 0xffu;
    bool small = !hw && across_px <= RASTER_SW_SMALL_PX && size_px <= RASTER_SW_SMALL_TRIANGLE_PX
        && vertices <= RASTER_SW_SMALL_VERTICES;
    bool quarter = small && vertices <= RASTER_SW_QUARTER_VERTICES;
    // The lists hold visible_capacity entries each; a cluster emitted twice (never, by the cut's
    // rule, but a direct slot is not a count) must not write past them.
    uint slot = hw    ? atomicAdd(counters.hw_count, 1u)
        : quarter ? atomicAdd(counters.sw_quarter_count, 1u)
        : small   ? atomicAdd(counters.sw_small_count, 1u)
                  : atomicAdd(counters.sw_count, 1u);
    if (slot >= view.visible_capacity) {
        atomicAdd(counters.visible_overflow, 1u);
        return;
    }
    if (hw) {
        hw_list[slot] = v | hw_entry_flags(instance);
    } else if (quarter) {
        hw_list[view.visible_capacity - 1u - slot] = v;
    } else if (small) {
        sw_list[view.visible_capacity - 1u - slot] = v;
    } else {
        sw_list[slot] = v;
    }
    CULL_STAT(triangles, triangles)
}

// The HZB test of a cluster in the cut: occluded in the main phase, it waits in `post_clusters`
// for the post phase; occluded in the post phase, it is rejected for good. False: visible.
bool cluster_occluded(uint instance, InstanceVgeo inst, vec3 bmin, vec3 bmax, uint ci) {
    if (!hzb_occluded(inst, bmin, bmax)) {
        return false;
    }
    if (pc.phase == 0u) {
        uint j = atomicAdd(counters.post_cluster_count, 1u);
        if (j < view.visible_capacity) {
            post_clusters[j] = uvec2(instance, ci);
        } else {
            atomicAdd(counters.visible_overflow, 1u);
        }
    } else {
        CULL_STAT(occluded_clusters, 1u)
    }
    return true;
}

// Whether the view's frustum test rejects the camera-relative sphere (c, r) (never with
// VIEW_FLAG_NO_FRUSTUM).
bool frustum_rejects(vec3 c, float r) {
    return (view.flags & VIEW_FLAG_NO_FRUSTUM) == 0u && !sphere_in_frustum(view, c, r);
}

// The camera-relative bounding sphere of instance `inst` of `mesh`: what instance_cull tests and
// occluder_select bins by (the same sphere, so that the cutoff sorts what instance_cull sees).
void instance_sphere(InstanceVgeo inst, MeshGpu mesh, out vec3 c, out float r) {
    c = relative_position(inst, view, mesh.bounds_center);
    r = mesh.bounds_radius * inst.max_scale;
}

// The camera-relative sphere around a cluster's box [bmin, bmax] in instance `inst` (what the
// frustum test and emit_cluster take).
void box_sphere(InstanceVgeo inst, vec3 bmin, vec3 bmax, out vec3 cc, out float cr) {
    cc = relative_position(inst, view, (bmin + bmax) * 0.5);
    cr = length(bmax - bmin) * 0.5 * inst.max_scale;
}

// The tests a cluster of the cut gets before it is drawn (frustum by its bounds' sphere, the HZB:
// deferred in the main phase, rejected in the post phase), then its emission. `at`: its pool word,
// `info`: its info word.
void draw_if_visible(uint instance, InstanceVgeo inst, MeshGpu mesh, uint ci, uint at, uint info) {
    vec3 bmin = cluster_bounds_min(mesh, at);
    vec3 bmax = cluster_bounds_max(mesh, at);
    vec3 cc;
    float cr;
    box_sphere(inst, bmin, bmax, cc, cr);
    if (frustum_rejects(cc, cr)) {
        return;
    }
    if (!cluster_occluded(instance, inst, bmin, bmax, ci)) {
        emit_cluster(instance, ci, at, info, cc, cr);
    }
}

// Partial residency (meshes with MESH_STREAM_PARTIAL; src/builder/cut.rs): a group is refinable
// only when all its pages are resident; its error otherwise counts as 0, so its members are never
// drawn and the clusters it produced are never refined (they ask for its pages instead).
bool page_resident(MeshGpu mesh, uint page) {
    return pages[mesh.page_offset + page].word != PAGE_NOT_RESIDENT;
}

bool group_pages_resident(MeshGpu mesh, Group g) {
    for (uint p = g.page_first; p < g.page_first + g.page_count; p++) {
        if (!page_resident(mesh, p)) {
            return false;
        }
    }
    return true;
}

// False in the pipelines for frames without a partial mesh (src/passes/cull.rs): the compiler then
// drops the partial-residency code.
layout(constant_id = SPEC_CULL_STREAMING) const bool CULL_STREAMING = true;

bool mesh_partial(MeshGpu mesh) {
    return CULL_STREAMING && (mesh.streams & MESH_STREAM_PARTIAL) != 0u;
}

// Whether the children of a cluster made by group `creator` (that group's members) are all
// resident.
bool children_resident(MeshGpu mesh, uint creator) {
    return !mesh_partial(mesh) || creator == NO_GROUP_ID
        || group_pages_resident(mesh, groups[mesh.group_offset + creator]);
}

// A cluster's LOD pairs are its groups' (the builder stores exactly those, verify checks it): its
// parent pair is its group's (lod_sphere, error), its self pair its creator group's; a level-0
// cluster (no creator) has self error 0. The self error in pixels, for a cluster made by
// `creator`, weighted by `w` (lod.glsl's instance_weight and weighted_error).
float self_error_px(InstanceVgeo inst, MeshGpu mesh, uint creator, float scale, float w) {
    if (creator == NO_GROUP_ID) {
        return 0.0;
    }
    Group g = groups[mesh.group_offset + creator];
    vec3 sc = relative_position(inst, view, g.lod_sphere.xyz);
    return lod_error_px(weighted_error(g.error, g.coverage, w) * scale, sc, g.lod_sphere.w * scale,
                        view.proj_scale);
}

// A drawn cluster that is coarser than wanted (`wish`: its projected error over the threshold)
// because its children are absent asks for their pages; a drawn cluster marks its page used.
// No request when the children's group's LOD sphere is outside the frustum: it encloses every
// member and descendant of the group, so none of them could reach the screen (a coarse cluster
// at the frustum's edge asked for detail that lies outside it).
void request_children(InstanceVgeo inst, MeshGpu mesh, uint creator, float wish) {
    Group g = groups[mesh.group_offset + creator];
    if ((view.flags & VIEW_FLAG_NO_FRUSTUM) == 0u
        && !sphere_in_frustum(view, relative_position(inst, view, g.lod_sphere.xyz), g.lod_sphere.w * inst.max_scale)) {
        return;
    }
    for (uint p = g.page_first; p < g.page_first + g.page_count; p++) {
        if (!page_resident(mesh, p)) {
            atomicMax(page_requests[mesh.page_offset + p], floatBitsToUint(min(wish, 1e30)));
        }
    }
}

// Whether the box of the cluster whose word is `at` may meet the view frustum: false when all its
// corners are outside one plane. Tighter than the box's sphere, which near the eye reaches past
// the near plane from clusters wholly behind it (and would stream in the detail of meshes behind
// the camera).
bool cluster_in_frustum(InstanceVgeo inst, MeshGpu mesh, uint at) {
    vec3 bmin = cluster_bounds_min(mesh, at);
    vec3 bmax = cluster_bounds_max(mesh, at);
    vec3 corners[8];
    for (int i = 0; i < 8; i++) {
        corners[i] = relative_position(inst, view, box_corner(bmin, bmax, i));
    }
    for (int k = 0; k < 5; k++) {
        bool outside = true;
        for (int i = 0; i < 8; i++) {
            outside = outside && dot(view.frustum[k].xyz, corners[i]) + view.frustum[k].w < 0.0;
        }
        if (outside) {
            return false;
        }
    }
    return true;
}

void mark_used(MeshGpu mesh, uint ci) {
    if (mesh_partial(mesh)) {
        page_usage[mesh.page_offset + cluster_locs[ci].page] = 1u;
    }
}

// Instance-level LOD. When the mesh's root cluster alone is fine for this view, the cut is exactly
// {root}: every other cluster's parent error projects to at most the root's own (errors and LOD
// spheres grow towards the root), so none of them is drawn and the BVH walk is skipped. The root
// then gets the tests cluster_cull gives a drawn cluster (frustum, HZB: deferred in the main phase,
// rejected in the post phase) and is emitted. False when the root is too coarse (walk the BVH).
bool emit_root_if_whole_cut(uint instance, InstanceVgeo inst, MeshGpu mesh) {
    uint ci = mesh.cluster_offset + mesh.root_cluster;
    uint at = cluster_word(mesh, ci);
    uint info = cluster_info(at);
    uint creator = cluster_creator(at);
    float scale = inst.max_scale;
    if ((view.flags & VIEW_FLAG_FALLBACK_CUT) != 0u) {
        // The fallback cut is the root alone only when the fallback level is the root's.
        if (info_level(info) > mesh.fallback_level) {
            return false;
        }
    } else {
        float self_px = self_error_px(inst, mesh, creator, scale, instance_weight(inst, mesh, view));
        if (self_px > view.error_px) {
            if (children_resident(mesh, creator)) {
                return false;
            }
            if ((view.flags & VIEW_FLAG_NO_FRUSTUM) != 0u || cluster_in_frustum(inst, mesh, at)) {
                request_children(inst, mesh, creator, self_px / view.error_px);
            }
        }
    }
    mark_used(mesh, ci);
    CULL_STAT(clusters_tested, 1u)
    draw_if_visible(instance, inst, mesh, ci, at, info);
    return true;
}

// A run's count flag: a local walk's group, its members' cut rule still to apply.
#define RUN_TEST 0x80000000u
#ifdef CULL_SHARED_RUNS
// instance_cull's shared runs. A run is `count` clusters of one instance: a small-instance cut
// (`first`: its word in `tiny_cuts`) or a group a local walk reached (RUN_TEST set in the count:
// the cut rule still to apply; `first`: the group's first cluster, global). Each thread writes
// its item's runs to its own SHARED_RUNS_PER_THREAD entries; after each round of items the
// workgroup tests and draws the clusters of all of them (run_round). Only in instance_cull's
// `shared` variant, which src/passes/instance_cull.rs takes for views of the size where that
// pays (SHARED_RUNS_MAX_INSTANCES); in the plain one a thread tests its small-instance cut and
// its walk's groups itself.
#define SHARED_RUN_ENTRIES (INSTANCE_CULL_WORKGROUP_SIZE * SHARED_RUNS_PER_THREAD)
shared uint s_run_instance[SHARED_RUN_ENTRIES];
shared uint s_run_first[SHARED_RUN_ENTRIES];
shared uint s_run_count[SHARED_RUN_ENTRIES];
// Per thread: its runs this round, and (shared) the first of its clusters among all threads'.
shared uint s_thread_runs[INSTANCE_CULL_WORKGROUP_SIZE];
shared uint s_thread_start[INSTANCE_CULL_WORKGROUP_SIZE];
shared uint s_round_items;

// Whether the workgroup shares its threads' runs (instance_cull's `shared` variant).
bool shared_runs() {
    return true;
}

// Adds a run to this thread's; false when it has SHARED_RUNS_PER_THREAD already.
bool push_run(uint instance, uint first, uint count) {
    uint lid = gl_LocalInvocationID.x;
    uint j = s_thread_runs[lid];
    if (j >= SHARED_RUNS_PER_THREAD) {
        return false;
    }
    uint e = lid * SHARED_RUNS_PER_THREAD + j;
    s_run_instance[e] = instance;
    s_run_first[e] = first;
    s_run_count[e] = count;
    s_thread_runs[lid] = j + 1u;
    return true;
}
#else
bool shared_runs() {
    return false;
}

bool push_run(uint instance, uint first, uint count) {
    return false;
}
#endif

// The error of the small-instance table's row at word `row` (its error, first entry, count and
// coverage part: src/builder/cut.rs TinyCuts::words) as an instance of weight `w` counts it.
float tiny_row_error(uint row, float w) {
    return weighted_error(uintBitsToFloat(tiny_cuts[row]), uintBitsToFloat(tiny_cuts[row + 3u]), w);
}

// Whether every cluster of the small-instance table's row at word `row` lies in a resident page
// (`base`: the mesh's table).
bool tiny_row_resident(MeshGpu mesh, uint base, uint row) {
    uint first = base + tiny_cuts[row + 1u];
    uint count = tiny_cuts[row + 2u];
    for (uint k = 0u; k < count; k++) {
        if (!page_resident(mesh, cluster_locs[mesh.cluster_offset + tiny_cuts[first + k]].page)) {
            return false;
        }
    }
    return true;
}

// Asks, with priority `wish`, for the absent pages of the table row at word `row`.
void request_tiny_row(MeshGpu mesh, uint base, uint row, float wish) {
    uint first = base + tiny_cuts[row + 1u];
    uint count = tiny_cuts[row + 2u];
    for (uint k = 0u; k < count; k++) {
        uint p = cluster_locs[mesh.cluster_offset + tiny_cuts[first + k]].page;
        if (!page_resident(mesh, p)) {
            atomicMax(page_requests[mesh.page_offset + p], floatBitsToUint(min(wish, 1e30)));
        }
    }
}

// Small instances (src/builder/cut.rs, TinyCuts): the cut of an instance far from the camera
// compared to its size comes from its mesh's table. Every group error is projected at the point
// of the mesh's LOD bound (`walk_radius` around `bounds_center`, enclosing every group's LOD
// sphere) nearest to the camera, never farther than the group's own sphere, so the cut is as fine
// or finer than the per-group rule everywhere; with one distance for all, it is the first row
// whose error projects to at most the threshold, the errors of an instance under
// SMALL_WEIGHT_RADIUS_PX weighted by small_instance_weight. Its clusters are tested for the frustum and
// the HZB and emitted, with no BVH walk and no LOD test. False when the
// instance's bounding sphere projects to a radius over TINY_CUT_RADIUS_PX (unless its mesh has
// at most WALK_CLUSTERS clusters) or the table holds no cut fine enough (a larger instance: walk
// it), in a view of fewer than WALK_WIDE_INSTANCES instances and for the fallback cut. Under
// partial residency the instance takes the finest row at most as fine as wanted whose clusters
// are all resident (rows are crack-free cuts: any of them may be drawn), and asks for the absent
// pages of the next finer row and of the wanted one (the streamer brings each with what keeps
// the residency closed).
bool emit_tiny_cut(uint instance, InstanceVgeo inst, MeshGpu mesh) {
    // One thread tests and emits the whole cut: in a view of few instances that is the frame's
    // latency (outdoor, 91 instances: +11 % with cuts of up to 64 clusters, +3 % with 16), so
    // only views of many instances, where every thread has its instance, take the table.
    if ((view.flags & VIEW_FLAG_FALLBACK_CUT) != 0u || view.instance_count < WALK_WIDE_INSTANCES) {
        return false;
    }
    uint base = mesh.tiny_offset;
    uint rows = tiny_cuts[base];
    if (rows == 0u) {
        return false;
    }
    float scale = inst.max_scale;
    vec3 c = relative_position(inst, view, mesh.bounds_center);
    // A mesh of at most WALK_CLUSTERS clusters (grass clumps; its table reaches the first level)
    // takes the table at any size: a close instance's local walk (which such a mesh always takes)
    // kept its whole subgroup waiting, where the table's cut is at most as many clusters, each
    // still tested (foliage's instance_cull 0.58 -> 0.17 ms on the H100, the same cut and image).
    float size = instance_size_px(inst, mesh, view);
    if (mesh.cluster_count > WALK_CLUSTERS && size > TINY_CUT_RADIUS_PX) {
        return false;
    }
    float r = mesh.walk_radius * scale;
    // An instance under SMALL_WEIGHT_RADIUS_PX counts a share of its rows' errors
    // (instance_weight, weighted_error: their coverage part whole).
    float w = small_instance_weight(size);
    uint row0 = base + 1u;
    float last = tiny_row_error(row0 + TINY_ROW_WORDS * (rows - 1u), w);
    if (lod_error_px(last * scale, c, r, view.proj_scale) > view.error_px) {
        return false;
    }
    // The first row whose error projects to at most the threshold (the projection grows with
    // the error, and the rows' errors decrease).
    uint lo = 0u;
    uint hi = rows - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        float e = tiny_row_error(row0 + TINY_ROW_WORDS * mid, w);
        if (lod_error_px(e * scale, c, r, view.proj_scale) <= view.error_px) {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    uint row = row0 + TINY_ROW_WORDS * lo;
    if (mesh_partial(mesh) && !tiny_row_resident(mesh, base, row)) {
        uint wanted = row;
        // Row 0 (the mesh's top) is always resident; a row that is not is never taken.
        do {
            if (lo == 0u) {
                return false;
            }
            lo--;
            row = row0 + TINY_ROW_WORDS * lo;
        } while (!tiny_row_resident(mesh, base, row));
        // The next finer row first, with how far the drawn row is over the threshold
        // (request_children's priority): its pages are the fewest that refine the drawn row, so
        // a budget that cannot take the wanted row's closure at once still moves. Then the
        // wanted row, with the priority of the row before it.
        uint next = row + TINY_ROW_WORDS;
        float wish = lod_error_px(tiny_row_error(row, w) * scale, c, r, view.proj_scale) / view.error_px;
        request_tiny_row(mesh, base, next, wish);
        if (next != wanted) {
            float px = lod_error_px(tiny_row_error(wanted - TINY_ROW_WORDS, w) * scale, c, r, view.proj_scale);
            request_tiny_row(mesh, base, wanted, px / view.error_px);
        }
    }
    uint first = base + tiny_cuts[row + 1u];
    uint count = tiny_cuts[row + 2u];
    CULL_STAT(tiny_cuts, 1u)
    // A cut of one cluster of a mesh of more than WALK_CLUSTERS clusters is the mesh whole at a
    // coarse level (the instance is under TINY_CUT_RADIUS_PX): the instance's own frustum and HZB
    // tests, by the mesh's sphere and box, stand for the cluster's (stress N=200: instance_cull
    // -0.15 ms for 0.2 % more triangles; foliage's clumps, which take the table at any size,
    // keep the test: there it rejected 2 % of the triangles).
    if (count == 1u && mesh.cluster_count > WALK_CLUSTERS) {
        uint ci = mesh.cluster_offset + tiny_cuts[first];
        uint at = cluster_word(mesh, ci);
        vec3 cc;
        float cr;
        box_sphere(inst, cluster_bounds_min(mesh, at), cluster_bounds_max(mesh, at), cc, cr);
        mark_used(mesh, ci);
        emit_cluster(instance, ci, at, cluster_info(at), cc, cr);
        return true;
    }
    CULL_STAT(clusters_tested, count)
    // Otherwise each cluster is still tested (frustum, HZB) as test_cluster tests a drawn one:
    // emitting the whole cut untested drew 14 % more triangles on stress N=100 (clusters these
    // tests reject), and rasterizing them cost more than the tests. In a view of shared runs
    // the workgroup runs them after the round (run_round; a thread's first run always fits).
    if (shared_runs()) {
        push_run(instance, first, count);
        return true;
    }
    for (uint k = 0u; k < count; k++) {
        uint ci = mesh.cluster_offset + tiny_cuts[first + k];
        uint at = cluster_word(mesh, ci);
        mark_used(mesh, ci);
        draw_if_visible(instance, inst, mesh, ci, at, cluster_info(at));
    }
    return true;
}

// Nodes a local walk (instance_cull) keeps pending; per invocation.
uint walk_stack[WALK_STACK];
uint walk_sp;

// The cut rule of a cluster (pool word `at`, info word `info`) of a visible instance whose
// parent pair is already over the threshold (its group's test): whether it is drawn. `w` is the
// instance's weight (lod.glsl's instance_weight). Under partial residency a cluster drawn for
// want of its children asks for them. Written as one if/else with the view's flags read first
// (test_cluster's body before it was split out): a form with an early return for the fallback
// cut made cluster_cull's H100 binary larger and stress N=100 / N=200 0.4-0.8 % slower
// (bench/results/2026-11-28-session39, calls 1-3).
bool in_cut(InstanceVgeo inst, MeshGpu mesh, uint at, uint info, bool partial, float w) {
    float scale = inst.max_scale;
    bool frustum = (view.flags & VIEW_FLAG_NO_FRUSTUM) == 0u;
    bool fallback = (view.flags & VIEW_FLAG_FALLBACK_CUT) != 0u;
    CULL_STAT(clusters_tested, 1u)
    bool drawn;
    if (fallback) {
        drawn = info_level(info) <= mesh.fallback_level;
    } else {
        uint creator = cluster_creator(at);
        float self_px = self_error_px(inst, mesh, creator, scale, w);
        bool fine = self_px <= view.error_px;
        if (partial && !fine && !children_resident(mesh, creator)) {
            // Drawn for want of its children; only a cluster in the frustum asks for them (one
            // outside it shows nothing their detail could change).
            if (!frustum || cluster_in_frustum(inst, mesh, at)) {
                request_children(inst, mesh, creator, self_px / view.error_px);
            }
            fine = true;
        }
        drawn = fine;
    }
    return drawn;
}

// The cut rule, frustum and occlusion for cluster `ci` (global index) of a visible instance, and
// its emission when drawn; `w` is the instance's weight, which the caller computes once for all
// the clusters it tests.
void test_cluster(uint instance, InstanceVgeo inst, MeshGpu mesh, uint ci, bool partial, float w) {
    uint at = cluster_word(mesh, ci);
    uint info = cluster_info(at);
    if (!in_cut(inst, mesh, at, info, partial, w)) {
        return;
    }
    mark_used(mesh, ci);
    draw_if_visible(instance, inst, mesh, ci, at, info);
}

#ifdef CULL_RANGE_ITEMS
// A queue item of CULL_RANGE_CLUSTERS or fewer clusters of one group (see process_node).
void process_range(uint instance, uint low) {
    InstanceVgeo inst = instances[instance];
    MeshGpu mesh = meshes[inst.mesh];
    uint first = low & ((1u << CULL_RANGE_INDEX_BITS) - 1u);
    uint count = ((low & ~CULL_RANGE_FLAG) >> CULL_RANGE_INDEX_BITS) + 1u;
    bool partial = mesh_partial(mesh);
    float w = instance_weight(inst, mesh, view);
    for (uint k = 0u; k < count; k++) {
        test_cluster(instance, inst, mesh, first + k, partial, w);
    }
}
#endif

// One (instance, BVH node) item: frustum and LOD tests of the node, then its children (to the
// global queue, or with `local` to `walk_stack` while it has room) or, for a leaf, the cut rule per
// cluster and the drawn clusters' emission. cluster_cull runs it on the items of its queue,
// instance_cull on a small instance's whole BVH (`walk_locally`): the same tests, so the same cut.
void process_node(uint64_t item, bool local) {
    uint instance = uint(item >> 32);
    uint node_index = uint(item & 0xffffffffu);
#ifdef CULL_RANGE_ITEMS
    // Only cluster_cull pops range items (instance_cull walks nodes: leaving the branch out
    // keeps its shader as small as it was).
    if ((node_index & CULL_RANGE_FLAG) != 0u) {
        process_range(instance, node_index);
        return;
    }
#endif
    CULL_STAT(nodes_visited, 1u)
    InstanceVgeo inst = instances[instance];
    MeshGpu mesh = meshes[inst.mesh];
    BvhNode node = bvh[node_index];
    float scale = inst.max_scale;
    bool frustum = (view.flags & VIEW_FLAG_NO_FRUSTUM) == 0u;

    if (frustum) {
        vec3 bc = relative_position(inst, view, (node.bounds_min + node.bounds_max) * 0.5);
        float br = length(node.bounds_max - node.bounds_min) * 0.5 * scale;
        if (!sphere_in_frustum(view, bc, br)) {
            return;
        }
    }
    // Occlusion: in the main phase against the previous frame's HZB (rejected items wait for the
    // post phase), in the post phase against this frame's (rejected for good).
    if (hzb_occluded(inst, node.bounds_min, node.bounds_max)) {
        if (pc.phase == 0u) {
            uint j = atomicAdd(counters.post_node_count, 1u);
            if (j < view.queue_capacity) {
                post_nodes[j] = item;
            } else {
                atomicAdd(counters.queue_overflow, 1u);
            }
        } else {
            CULL_STAT(occluded_nodes, 1u)
        }
        return;
    }
    // No cluster below can be drawn when even the largest parent error is already fine (the
    // fallback cut is by level: every node is walked).
    bool fallback = (view.flags & VIEW_FLAG_FALLBACK_CUT) != 0u;
    vec3 lc = relative_position(inst, view, node.lod_sphere.xyz);
    float w = fallback ? 1.0 : instance_weight(inst, mesh, view);
    // Every group's weighted parent error below is at most this (weighted_error grows with both).
    float bound = weighted_error(node.max_parent_error, node.max_parent_coverage, w);
    if (!fallback
        && lod_error_px(bound * scale, lc, node.lod_sphere.w * scale, view.proj_scale) <= view.error_px) {
        return;
    }
    if ((node.flags & BVH_FLAG_LEAF) == 0u) {
        for (uint k = 0u; k < node.count; k++) {
            uint child = mesh.bvh_offset + node.first + k;
            if (local && walk_sp < WALK_STACK) {
                walk_stack[walk_sp] = child;
                walk_sp++;
            } else {
                push_item((uint64_t(instance) << 32) | uint64_t(child));
            }
        }
        return;
    }
    bool partial = mesh_partial(mesh);
    for (uint g = 0u; g < node.count; g++) {
        Group group = groups[mesh.group_offset + node.first + g];
        // A group not wholly resident: its members' parent error counts as 0, none is drawn.
        // (Its members are read from its pages: only a resident group's are, in either cut.)
        if (partial && !group_pages_resident(mesh, group)) {
            continue;
        }
        // The fallback cut draws only groups simplified at or after the fallback level (always
        // resident when the mesh was built with the default fallback size).
        if (fallback && group.iteration < mesh.fallback_level) {
            continue;
        }
        // The members' parent pair is the group's: when it is already fine, none is drawn.
        if (!fallback) {
            vec3 pcen = relative_position(inst, view, group.lod_sphere.xyz);
            float e = weighted_error(group.error, group.coverage, w);
            if (lod_error_px(e * scale, pcen, group.lod_sphere.w * scale, view.proj_scale) <= view.error_px) {
                CULL_STAT(clusters_tested, group.cluster_count)
                continue;
            }
        }
        // Members of one creator share their own error: when it is over the threshold, none is
        // drawn (test_cluster's test, once). Under partial residency a member may be drawn for
        // want of its children, so then only when their creator group, the members' children,
        // is resident (in_cut's exception never applies to them).
        if (!fallback && group.members_creator != NO_GROUP_ID
            && children_resident(mesh, group.members_creator)
            && self_error_px(inst, mesh, group.members_creator, scale, w) > view.error_px) {
            CULL_STAT(clusters_tested, group.cluster_count)
            continue;
        }
        uint first = mesh.cluster_offset + group.first_cluster;
        // A small instance's walk (instance_cull) tests its members itself, or in a view of
        // shared runs hands them to the workgroup; in cluster_cull, and when this thread's runs
        // are full, they go in ranges on the queue, for other lanes.
        if (local && !shared_runs()) {
            for (uint k = 0u; k < group.cluster_count; k++) {
                test_cluster(instance, inst, mesh, first + k, partial, w);
            }
        } else if (!local || !push_run(instance, first, group.cluster_count | RUN_TEST)) {
            for (uint k = 0u; k < group.cluster_count; k += CULL_RANGE_CLUSTERS) {
                uint n = min(group.cluster_count - k, CULL_RANGE_CLUSTERS);
                uint low = CULL_RANGE_FLAG | ((n - 1u) << CULL_RANGE_INDEX_BITS) | (first + k);
                push_item((uint64_t(instance) << 32) | uint64_t(low));
            }
        }
    }
}

// Whether instance_cull walks this instance's BVH itself: at most WALK_CLUSTERS of its mesh's
// clusters can be in the cut (MeshGpu::walk_error projected on the sphere of radius walk_radius),
// or WALK_CLUSTERS_WIDE in a view of at least WALK_WIDE_INSTANCES instances (walk_error_wide).
// The fallback cut walks every node: never locally.
bool walk_locally(InstanceVgeo inst, MeshGpu mesh) {
    if ((view.flags & VIEW_FLAG_FALLBACK_CUT) != 0u) {
        return false;
    }
    vec3 c = relative_position(inst, view, mesh.bounds_center);
    float scale = inst.max_scale;
    float e = view.instance_count >= WALK_WIDE_INSTANCES ? mesh.walk_error_wide : mesh.walk_error;
    // Whole errors: a weighted cut holds no cluster this bound leaves out (weighted_error is at
    // most the error).
    return lod_error_px(e * scale, c, mesh.walk_radius * scale, view.proj_scale) <= view.error_px;
}

// An (instance, BVH node) item of a visible instance: walked here, node and subtree, when the
// instance is small (see walk_locally), else pushed to cluster_cull's queue.
void walk_or_push_item(uint64_t item, InstanceVgeo inst, MeshGpu mesh) {
    if (!walk_locally(inst, mesh)) {
        push_item(item);
        return;
    }
    CULL_STAT(local_walks, 1u)
    uint64_t instance = item & 0xffffffff00000000ul;
    // The item's node starts the stack (one call site of process_node: the driver inlines it).
    walk_stack[0] = uint(item & 0xffffffffu);
    walk_sp = 1u;
    while (walk_sp > 0u) {
        walk_sp--;
        process_node(instance | uint64_t(walk_stack[walk_sp]), true);
    }
}

#ifdef CULL_SHARED_RUNS
// The end of a round of instance_cull's items in a view of shared runs (every thread of the
// workgroup calls it: it has barriers): the clusters of all the threads' runs are tested and
// drawn, each thread taking every INSTANCE_CULL_WORKGROUP_SIZE-th of them. A cluster's run is
// found by a binary search over the threads' first clusters, then along its thread's runs. The
// runs are then cleared.
void run_round() {
    uint lid = gl_LocalInvocationID.x;
    uint own = 0u;
    for (uint j = 0u; j < s_thread_runs[lid]; j++) {
        own += s_run_count[lid * SHARED_RUNS_PER_THREAD + j] & ~RUN_TEST;
    }
    s_thread_start[lid] = own;
    barrier();
    if (lid == 0u) {
        uint sum = 0u;
        for (uint i = 0u; i < INSTANCE_CULL_WORKGROUP_SIZE; i++) {
            uint n = s_thread_start[i];
            s_thread_start[i] = sum;
            sum += n;
        }
        s_round_items = sum;
    }
    barrier();
    uint items = s_round_items;
    // The run's instance, mesh, residency and weight, loaded when the run changes.
    uint run = 0xffffffffu;
    uint instance = 0u;
    InstanceVgeo inst;
    MeshGpu mesh;
    bool partial = false;
    float w = 1.0;
    for (uint t = lid; t < items; t += INSTANCE_CULL_WORKGROUP_SIZE) {
        // The last thread whose clusters start at or before t (one with none shares its start
        // with the next, so this one has t among its clusters), then its run holding t.
        uint lo = 0u;
        uint hi = INSTANCE_CULL_WORKGROUP_SIZE - 1u;
        while (lo < hi) {
            uint mid = (lo + hi + 1u) / 2u;
            if (s_thread_start[mid] <= t) {
                lo = mid;
            } else {
                hi = mid - 1u;
            }
        }
        uint k = t - s_thread_start[lo];
        uint e = lo * SHARED_RUNS_PER_THREAD;
        while (k >= (s_run_count[e] & ~RUN_TEST)) {
            k -= s_run_count[e] & ~RUN_TEST;
            e++;
        }
        if (e != run) {
            run = e;
            instance = s_run_instance[e];
            inst = instances[instance];
            mesh = meshes[inst.mesh];
            partial = mesh_partial(mesh);
            w = instance_weight(inst, mesh, view);
        }
        bool walked = (s_run_count[e] & RUN_TEST) != 0u;
        uint ci = walked ? s_run_first[e] + k : mesh.cluster_offset + tiny_cuts[s_run_first[e] + k];
        uint at = cluster_word(mesh, ci);
        uint info = cluster_info(at);
        if (walked && !in_cut(inst, mesh, at, info, partial, w)) {
            continue;
        }
        mark_used(mesh, ci);
        draw_if_visible(instance, inst, mesh, ci, at, info);
    }
    // Every thread's runs read before any is cleared and rewritten.
    barrier();
    s_thread_runs[lid] = 0u;
}
#endif

#endif
