// raster_hw's geometry-stage bindings 0-7, one declaration for its vertex path
// (raster_hw.vert.glsl) and its mesh path (raster_hw.mesh.glsl): both run with the one descriptor
// layout src/passes/raster_hw.rs builds (8 and 9 are the fragment stage's: visibility buffer,
// overdraw; the mesh path adds 10, the cull counters). Includes raster.glsl after them.
#ifndef VGEO_RASTER_HW_BINDINGS_GLSL
#define VGEO_RASTER_HW_BINDINGS_GLSL

layout(set = 0, binding = 0, scalar) uniform View { ViewGpu view; };
layout(set = 0, binding = 1, scalar) readonly buffer Visible { uvec2 visible[]; };
layout(set = 0, binding = 2, scalar) readonly buffer HwList { uint hw_list[]; };
layout(set = 0, binding = 3, scalar) readonly buffer Instances { InstanceVgeo instances[]; };
layout(set = 0, binding = 4, scalar) readonly buffer Meshes { MeshGpu meshes[]; };
layout(set = 0, binding = 5, scalar) readonly buffer Clusters { ClusterLoc cluster_locs[]; };
layout(set = 0, binding = 6, scalar) readonly buffer Pages { PageGpu pages[]; };
layout(set = 0, binding = 7, scalar) readonly buffer Pool { uint pool[]; };

#include "raster.glsl"

#endif
