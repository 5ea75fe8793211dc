// The descriptor set both forms of pass `emit_gbuffer` share (src/passes/emit_gbuffer.rs builds
// the matching layout); the compute form adds bindings 15-18 after it.
#ifndef VGEO_EMIT_BINDINGS_GLSL
#define VGEO_EMIT_BINDINGS_GLSL

layout(set = 0, binding = 0, scalar) uniform MaterialView { MaterialViewGpu mview; };
layout(set = 0, binding = 2, scalar) uniform View { ViewGpu view; };
layout(set = 0, binding = 3, scalar) readonly buffer Visible { uvec2 visible[]; };
layout(set = 0, binding = 4, scalar) readonly buffer Instances { InstanceVgeo instances[]; };
layout(set = 0, binding = 5, scalar) readonly buffer Meshes { MeshGpu meshes[]; };
layout(set = 0, binding = 6, scalar) readonly buffer Clusters { Cluster clusters[]; };
layout(set = 0, binding = 7, scalar) readonly buffer Vertices { PackedVertex vertices[]; };
layout(set = 0, binding = 8, scalar) readonly buffer VertexRefs { uint vertex_refs[]; };
layout(set = 0, binding = 9, scalar) readonly buffer Triangles { uint triangle_words[]; };
layout(set = 0, binding = 10, scalar) readonly buffer Materials { MaterialGpu materials[]; };
layout(set = 0, binding = 11, scalar) readonly buffer MeshMaterials { MeshMaterialGpu mesh_materials[]; };
layout(set = 0, binding = 13, scalar) buffer FragmentCounts { uint fragment_counts[]; };
layout(set = 0, binding = 14, scalar) readonly buffer Uvs { uint uvs[]; };
layout(set = 1, binding = 0) uniform sampler2D textures[];

#endif
