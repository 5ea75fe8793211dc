// The body of pass `emit_gbuffer`, shared by its raster (emit_gbuffer.frag) and compute
// (emit_gbuffer.comp) forms: the pixel's triangle rebuilt from the visibility buffer (barycentrics
// from the camera ray through the pixel centre, UV and position derivatives from the rays through
// the next pixels, exact for the triangle's plane), then the material model (gbuffer.glsl).
// The including shader declares the bindings (mview, visible, instances, meshes, clusters,
// vertices, uvs, vertex_refs, triangle_words, materials, mesh_materials, fragment_counts, textures,
// vis_read) and includes raster.glsl, shading.glsl and gbuffer.glsl first.
#ifndef VGEO_EMIT_GLSL
#define VGEO_EMIT_GLSL

vec2 decode_uv(MeshMaterialGpu mm, uint code) {
    vec2 t = vec2(code & 0xffffu, code >> 16) / 65535.0;
    return mm.uv_min + t * (mm.uv_max - mm.uv_min);
}

// The GBuffer of pixel `px` for `material` (its triangle's material); false where the visibility
// buffer is empty (nothing written then).
bool emit_pixel(ivec2 px, uint material, out vec4 out_albedo, out vec4 out_normal,
                out vec4 out_params) {
    out_albedo = vec4(0.0);
    out_normal = vec4(0.0);
    out_params = vec4(0.0);
    uint width = uint(mview.viewport.x);
    uint64_t value = vis_read(px, width);
    uint low = uint(value);
    uint tri = low & ((1u << VISBUFFER_TRIANGLE_BITS) - 1u);
    uint vi = low >> VISBUFFER_TRIANGLE_BITS;
    if (value == 0ul || vi >= mview.visible_capacity) {
        return false;
    }
    if (mview.count_fragments != 0u) {
        atomicAdd(fragment_counts[material], 1u);
    }
    uvec2 entry = visible[vi];
    InstanceVgeo inst = instances[entry.x];
    MeshGpu mesh = meshes[inst.mesh];
    MeshMaterialGpu mm = mesh_materials[inst.mesh];
    Cluster c = cluster_at(entry.y);
    ClusterData d = cluster_data(mesh, c);
    uvec3 t = cluster_triangle(d, c, tri);
    vec3 p[3];
    vec3 n[3];
    vec2 uv[3];
    bool has_uvs = (mm.flags & MESH_HAS_UVS) != 0u && (mesh.streams & MESH_STREAM_UVS) != 0u;
    for (uint k = 0u; k < 3u; k++) {
        PackedVertex pv = cluster_vertex(d, t[k]);
        p[k] = relative_position(inst, decode_position(mesh, pv));
        n[k] = decode_normal(pv.normal, mesh.normal_scale);
        uv[k] = has_uvs ? decode_uv(mm, cluster_uv(d, t[k])) : vec2(0.0);
    }
    vec2 pc = vec2(px) + 0.5;
    vec3 dir = pixel_ray(mview.inv_view_proj, pc, mview.viewport);
    vec3 e1 = p[1] - p[0];
    vec3 e2 = p[2] - p[0];
    mat3 lin = mat3(inst.linear[0].xyz, inst.linear[1].xyz, inst.linear[2].xyz);
    mat3 normal_matrix = transpose(inverse(lin));
    Surface s;
    s.face = normal_matrix * cross(e1, e2);
    s.dir = dir;
    s.tint = inst.color.rgb;
    s.normal = vec3(0.0);
    s.has_uvs = false;
    s.uv = vec2(0.0);
    s.ddx = vec2(0.0);
    s.ddy = vec2(0.0);
    s.dpx = vec3(0.0);
    s.dpy = vec3(0.0);
    vec2 b;
    if (ray_barycentrics(dir, p[0], p[1], p[2], b)) {
        vec2 bc = clamp(b, 0.0, 1.0);
        bc.y = min(bc.y, 1.0 - bc.x);
        s.normal = normal_matrix * (n[0] * (1.0 - bc.x - bc.y) + n[1] * bc.x + n[2] * bc.y);
        if (has_uvs) {
            // Derivatives from the rays through the next pixels (exact for the triangle's plane).
            vec2 bx;
            vec2 by;
            ray_barycentrics(pixel_ray(mview.inv_view_proj, pc + vec2(1.0, 0.0), mview.viewport),
                             p[0], p[1], p[2], bx);
            ray_barycentrics(pixel_ray(mview.inv_view_proj, pc + vec2(0.0, 1.0), mview.viewport),
                             p[0], p[1], p[2], by);
            vec2 duv1 = uv[1] - uv[0];
            vec2 duv2 = uv[2] - uv[0];
            s.has_uvs = true;
            s.uv = uv[0] * (1.0 - b.x - b.y) + uv[1] * b.x + uv[2] * b.y;
            s.ddx = duv1 * (bx.x - b.x) + duv2 * (bx.y - b.y);
            s.ddy = duv1 * (by.x - b.x) + duv2 * (by.y - b.y);
            s.dpx = e1 * (bx.x - b.x) + e2 * (bx.y - b.y);
            s.dpy = e1 * (by.x - b.x) + e2 * (by.y - b.y);
        }
    }
    material_gbuffer(materials[material], material, s, out_albedo, out_normal, out_params);
    return true;
}

#endif
