// The descriptor set both forms of pass `emit_gbuffer` share (src/passes/emit_gbuffer.rs builds
// the matching layout); the compute form adds bindings 13-16 after it.
#ifndef VGEO_EMIT_BINDINGS_GLSL
#define VGEO_EMIT_BINDINGS_GLSL

layout(set = 0, binding = 0, scalar) uniform MaterialView { MaterialViewGpu mview; };
layout(set = 0, binding = 2, scalar) uniform View { ViewGpu view; };
layout(set = 0, binding = 3, scalar) readonly buffer Visible { uvec2 visible[]; };
layout(set = 0, binding = 4, scalar) readonly buffer Instances { InstanceVgeo instances[]; };
layout(set = 0, binding = 5, scalar) readonly buffer Meshes { MeshGpu meshes[]; };
layout(set = 0, binding = 6, scalar) readonly buffer Clusters { ClusterLoc cluster_locs[]; };
layout(set = 0, binding = 7, scalar) readonly buffer Pages { PageGpu pages[]; };
layout(set = 0, binding = 8, scalar) readonly buffer Pool { uint pool[]; };
layout(set = 0, binding = 9, scalar) readonly buffer Materials { MaterialGpu materials[]; };
layout(set = 0, binding = 10, scalar) readonly buffer MeshMaterials { MeshMaterialGpu mesh_materials[]; };
layout(set = 0, binding = 12, scalar) buffer FragmentCounts { uint fragment_counts[]; };
layout(set = 1, binding = 0) uniform sampler2D textures[];

#endif
