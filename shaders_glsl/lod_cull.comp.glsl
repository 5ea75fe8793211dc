#version 460
// Pass `lod_cull` (src/baseline/lod_cull.rs): the GPU-driven discrete-LOD baseline's culling and
// level selection, in three phases (push constant `phase`):
// - LOD_PHASE_MAIN, a thread per instance: frustum test of the mesh's bounding sphere, the level
//   (the coarsest whose error projected at the sphere stays within `tau` pixels, lod.glsl's
//   lod_error_px, as src/baseline/lod.rs select_lod), then, with a history, the previous frame's
//   HZB: occluded instances wait in `post_list`, the others go to their (mesh, level) bucket.
// - LOD_PHASE_POST, a thread per deferred instance: this frame's HZB (built from what the main
//   phase drew); visible ones go to their bucket, the others are rejected for good.
// - LOD_PHASE_COMMANDS, a thread per mesh: one VkDrawIndexedIndirectCommand per non-empty bucket
//   of the mesh, in level order, and the mesh's draw count (vkCmdDrawIndexedIndirectCount); then
//   the same for the instances drawn with the faces turned away culled (commands and draw counts
//   after every mesh's plain ones).
// Bucket (m, k) of mesh m with n instances starting at `first` (mesh_slots[m]) owns instance-list
// slots 8 first + k n .. + n: the draw's firstInstance, so gl_InstanceIndex indexes the list
// (brute.vert's LOD_INSTANCE_LIST variant). Its plain instances fill it from the start, those of a
// closed solid seen from outside (culls_back_faces) from the end.
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"
#include "lod.glsl"

layout(local_size_x = LOD_CULL_WORKGROUP_SIZE) in;

// src/shared.rs LodStatsGpu (here, not in shared.glsl: it needs the int64 extensions).
struct LodStatsGpu {
    uint frustum_culled;
    uint drawn_main;
    uint post_count;
    uint drawn_post;
    uint occluded;
    uint cull_back;
    uint64_t triangles;
};

layout(set = 0, binding = 0, scalar) uniform View { LodViewGpu view; };
layout(set = 0, binding = 1, scalar) readonly buffer Instances { InstanceGpu instances[]; };
layout(set = 0, binding = 2, scalar) readonly buffer InstanceMeshes { uint instance_mesh[]; };
layout(set = 0, binding = 3, scalar) readonly buffer Meshes { LodMeshGpu meshes[]; };
layout(set = 0, binding = 4, scalar) readonly buffer MeshSlots { uvec2 mesh_slots[]; };
layout(set = 0, binding = 5, scalar) buffer BucketCounts { uint bucket_counts[]; };
layout(set = 0, binding = 6, scalar) writeonly buffer InstanceList { uint instance_list[]; };
layout(set = 0, binding = 7, scalar) buffer PostList { uint post_list[]; };
layout(set = 0, binding = 8, scalar) writeonly buffer Commands { LodDrawGpu commands[]; };
layout(set = 0, binding = 9, scalar) writeonly buffer DrawCounts { uint draw_counts[]; };
layout(set = 0, binding = 10, scalar) buffer Stats { LodStatsGpu stats[]; };
layout(set = 0, binding = 11, scalar) buffer Levels { uint levels[]; };
layout(set = 0, binding = 12, scalar) readonly buffer Hzb { float hzb[]; };

layout(push_constant) uniform Push {
    uint phase;
    uint frame;  // this frame's entry of `stats`
} pc;

#include "hzb.glsl"

// Camera-relative centre, radius and largest axis scale of instance `inst`'s bounding sphere.
void instance_sphere(InstanceGpu inst, LodMeshGpu mesh, out vec3 c, out float r, out float scale) {
    c = (inst.model * vec4(mesh.sphere.xyz, 1.0)).xyz;
    scale = max(length(inst.model[0].xyz), max(length(inst.model[1].xyz), length(inst.model[2].xyz)));
    r = mesh.sphere.w * scale;
}

bool outside_frustum(vec3 c, float r) {
    for (int i = 0; i < 5; i++) {
        if (dot(view.frustum[i].xyz, c) + view.frustum[i].w < -r) {
            return true;
        }
    }
    return false;
}

// The coarsest level whose error projects to at most `tau` pixels (0 when tau <= 0 or NaN); an
// instance under SMALL_WEIGHT_RADIUS_PX counts a share of its errors (their coverage part whole),
// as vgeo's small instances do (lod.glsl's small_instance_weight of the sphere's projected radius
// and weighted_error).
uint select_level(LodMeshGpu mesh, vec3 c, float r, float scale) {
    if (!(view.tau > 0.0)) {
        return 0u;
    }
    float w = small_instance_weight(lod_error_px(r, c, r, view.proj_scale));
    for (int k = int(LOD_LEVELS) - 1; k >= 1; k--) {
        float e = weighted_error(mesh.errors[k], mesh.coverages[k], w);
        if (lod_error_px(e * scale, c, r, view.proj_scale) <= view.tau) {
            return uint(k);
        }
    }
    return 0u;
}

// Whether the instance's object-space bounding box (around its sphere) lies behind the HZB, seen
// through `vp` from a camera `delta` away from this frame's (conservative near the eye).
bool occluded(InstanceGpu inst, LodMeshGpu mesh, mat4 vp, vec3 delta) {
    vec3 bmin = mesh.sphere.xyz - vec3(mesh.sphere.w);
    vec3 bmax = mesh.sphere.xyz + vec3(mesh.sphere.w);
    vec2 lo = vec2(1e30);
    vec2 hi = vec2(-1e30);
    float nearest = 0.0;
    for (int i = 0; i < 8; i++) {
        vec3 p = (inst.model * vec4(box_corner(bmin, bmax, i), 1.0)).xyz + delta;
        if (!hzb_add_corner(vp * vec4(p, 1.0), view.near, view.viewport.xy, lo, hi, nearest)) {
            return false;
        }
    }
    return hzb_rect_occluded(lo, hi, nearest, view.viewport.xy, view.hzb_levels);
}

// Whether instance `inst` of `mesh` is drawn with the faces turned away culled: a closed solid
// (LodMeshGpu::closed_solid) seen from outside its box, the near plane clear of it, not mirrored
// (the culling pipeline's front faces wind one way). The box through the camera-relative model
// (conservative), as vgeo's hardware path decides (common/cull.glsl hw_entry_flags).
bool culls_back_faces(InstanceGpu inst, LodMeshGpu mesh) {
    if (mesh.closed_solid == 0u) {
        return false;
    }
    vec3 h = (mesh.bounds_max - mesh.bounds_min) * 0.5;
    vec3 c = (inst.model * vec4(mesh.bounds_min + h, 1.0)).xyz;
    mat3 linear = mat3(inst.model);
    return determinant(linear) > 0.0
        && near_plane_clear_of_box(c, h, linear, view.viewport.xy, view.proj_scale, view.near);
}

// Appends instance i to bucket (m, level): the bucket's start for the plain draw, its end for the
// draw with the faces turned away culled (each instance is in one bucket once, so they never meet).
void draw_instance(uint i, InstanceGpu inst, uint m, LodMeshGpu mesh, uint level) {
    uvec2 s = mesh_slots[m];
    uint base = LOD_LEVELS * s.x + level * s.y;
    if (culls_back_faces(inst, mesh)) {
        atomicAdd(stats[pc.frame].cull_back, 1u);
        uint slot = atomicAdd(bucket_counts[(view.mesh_count + m) * LOD_LEVELS + level], 1u);
        instance_list[base + s.y - 1u - slot] = i;
    } else {
        uint slot = atomicAdd(bucket_counts[m * LOD_LEVELS + level], 1u);
        instance_list[base + slot] = i;
    }
}

void main_phase(uint i) {
    InstanceGpu inst = instances[i];
    uint m = instance_mesh[i];
    LodMeshGpu mesh = meshes[m];
    vec3 c;
    float r;
    float scale;
    instance_sphere(inst, mesh, c, r, scale);
    if ((view.flags & LOD_FLAG_FRUSTUM) != 0u && outside_frustum(c, r)) {
        levels[i] = LOD_LEVEL_CULLED;
        atomicAdd(stats[pc.frame].frustum_culled, 1u);
        return;
    }
    uint level = select_level(mesh, c, r, scale);
    levels[i] = level;
    uint need = LOD_FLAG_OCCLUSION | LOD_FLAG_HISTORY;
    if ((view.flags & need) == need && occluded(inst, mesh, view.prev_view_proj, view.prev_delta.xyz)) {
        post_list[atomicAdd(stats[pc.frame].post_count, 1u)] = i;
        return;
    }
    atomicAdd(stats[pc.frame].drawn_main, 1u);
    draw_instance(i, inst, m, mesh, level);
}

void post_phase(uint j) {
    uint i = post_list[j];
    InstanceGpu inst = instances[i];
    uint m = instance_mesh[i];
    LodMeshGpu mesh = meshes[m];
    uint level = levels[i];
    if (occluded(inst, mesh, view.view_proj, vec3(0.0))) {
        levels[i] = level | LOD_LEVEL_OCCLUDED;
        atomicAdd(stats[pc.frame].occluded, 1u);
        return;
    }
    atomicAdd(stats[pc.frame].drawn_post, 1u);
    draw_instance(i, inst, m, mesh, level);
}

// The draws of mesh m: per non-empty bucket, one for its plain start (commands and draw count
// `m`) and one for its end drawn with the faces turned away culled (`mesh_count + m`).
void commands_phase(uint m) {
    uvec2 s = mesh_slots[m];
    LodMeshGpu mesh = meshes[m];
    uint64_t tris = 0ul;
    for (uint culled = 0u; culled < 2u; culled++) {
        uint list = culled * view.mesh_count + m;
        uint n = 0u;
        for (uint k = 0u; k < LOD_LEVELS; k++) {
            uint count = bucket_counts[list * LOD_LEVELS + k];
            if (count == 0u) {
                continue;
            }
            uint base = LOD_LEVELS * s.x + k * s.y;
            LodDrawGpu d;
            d.index_count = mesh.ranges[k].y;
            d.instance_count = count;
            d.first_index = mesh.ranges[k].x;
            d.vertex_offset = 0;
            d.first_instance = culled == 0u ? base : base + s.y - count;
            commands[list * LOD_LEVELS + n] = d;
            tris += uint64_t(mesh.ranges[k].y / 3u) * uint64_t(count);
            n++;
        }
        draw_counts[list] = n;
    }
    if (tris > 0ul) {
        atomicAdd(stats[pc.frame].triangles, tris);
    }
}

void main() {
    uint gid = gl_GlobalInvocationID.x;
    if (pc.phase == LOD_PHASE_MAIN) {
        if (gid < view.instance_count) {
            main_phase(gid);
        }
    } else if (pc.phase == LOD_PHASE_POST) {
        if (gid < stats[pc.frame].post_count) {
            post_phase(gid);
        }
    } else if (gid < view.mesh_count) {
        commands_phase(gid);
    }
}
