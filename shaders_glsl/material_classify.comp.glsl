#version 460
// Pass `material_classify`: the global material id of every pixel (the material of the first vertex
// of its triangle; NO_MATERIAL where empty) and, per 64x64 tile, the min and max id present
// (uvec2(NO_MATERIAL, 0) for an empty tile). One 16x16 workgroup per tile, 16 pixels per thread:
// the tile in 16 blocks of 16x16 pixels, one pixel of each block per thread, so that neighbouring
// threads read and write neighbouring pixels.
//! variant image VISBUFFER_IMAGE
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared.glsl"
#include "material.glsl"

#define VISBUFFER_BINDING 9
#define VISBUFFER_READONLY
#include "visbuffer.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = 0, scalar) uniform MaterialView { MaterialViewGpu mview; };
layout(set = 0, binding = 1, scalar) readonly buffer Visible { uvec2 visible[]; };
layout(set = 0, binding = 2, scalar) readonly buffer Instances { InstanceVgeo instances[]; };
layout(set = 0, binding = 3, scalar) readonly buffer Meshes { MeshGpu meshes[]; };
layout(set = 0, binding = 4, scalar) readonly buffer Clusters { ClusterLoc cluster_locs[]; };
layout(set = 0, binding = 5, scalar) readonly buffer Pages { PageGpu pages[]; };
layout(set = 0, binding = 6, scalar) readonly buffer Pool { uint pool[]; };
layout(set = 0, binding = 7, scalar) readonly buffer MeshMaterials { MeshMaterialGpu mesh_materials[]; };
layout(set = 0, binding = 8, scalar) writeonly buffer Tiles { uvec2 tiles[]; };
layout(set = 0, binding = 10, scalar) writeonly buffer PixelMaterials { uint pixel_materials[]; };

layout(set = 0, binding = 11, scalar) uniform View { ViewGpu view; };
#include "raster.glsl"

shared uint s_min;
shared uint s_max;

void main() {
    if (gl_LocalInvocationIndex == 0u) {
        s_min = NO_MATERIAL;
        s_max = 0u;
    }
    barrier();
    uint width = uint(mview.viewport.x);
    uint height = uint(mview.viewport.y);
    uvec2 base = gl_WorkGroupID.xy * MATERIAL_TILE + gl_LocalInvocationID.xy;
    uint lo = NO_MATERIAL;
    uint hi = 0u;
    for (uint by = 0u; by < MATERIAL_TILE / 16u; by++) {
        for (uint bx = 0u; bx < MATERIAL_TILE / 16u; bx++) {
            uvec2 p = base + 16u * uvec2(bx, by);
            if (p.x >= width || p.y >= height) {
                continue;
            }
            uint64_t value = vis_read(ivec2(p), width);
            uint id = NO_MATERIAL;
            if (value != 0ul) {
                uint low = uint(value);
                uint tri = low & ((1u << VISBUFFER_TRIANGLE_BITS) - 1u);
                uint vi = low >> VISBUFFER_TRIANGLE_BITS;
                if (vi < mview.visible_capacity) {
                    uvec2 entry = visible[vi];
                    uint mi = instances[entry.x].mesh;
                    MeshGpu mesh = meshes[mi];
                    MeshMaterialGpu mm = mesh_materials[mi];
                    Cluster c = cluster_at(entry.y);
                    id = mm.material_offset;
                    if ((mesh.streams & MESH_STREAM_MATERIALS) != 0u) {
                        ClusterData d = cluster_data(mesh, c);
                        uvec3 t = cluster_triangle(d, c, tri);
                        uint local = cluster_material(d, t.x);
                        id += min(local, max(mm.material_count, 1u) - 1u);
                    }
                    lo = min(lo, id);
                    hi = max(hi, id);
                }
            }
            pixel_materials[p.y * width + p.x] = id;
        }
    }
    if (lo != NO_MATERIAL) {
        atomicMin(s_min, lo);
        atomicMax(s_max, hi);
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        tiles[gl_WorkGroupID.y * mview.tiles_x + gl_WorkGroupID.x] = uvec2(s_min, s_max);
    }
}
