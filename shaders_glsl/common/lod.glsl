// The LOD error projection and the camera-relative transform it is computed in (mirrors
// src/builder/cut.rs::lod_error_px operation for operation): one definition for every shader that
// decides or explains the cut (instance_cull and cluster_cull through cull.glsl; debug_view's
// residency view). Needs `shared.glsl` (InstanceVgeo, ViewGpu, MeshGpu).
#ifndef VGEO_LOD_GLSL
#define VGEO_LOD_GLSL

// Camera-relative position of object-space point p of an instance for a camera at hi + lo:
// translation minus camera first (exact for large coordinates), then the linear part by column.
vec3 relative_to(InstanceVgeo inst, vec3 cam_hi, vec3 cam_lo, vec3 p) {
    precise vec3 t = (inst.translation_hi - cam_hi) + (inst.translation_lo - cam_lo);
    precise vec3 l = inst.linear[0].xyz * p.x + inst.linear[1].xyz * p.y + inst.linear[2].xyz * p.z;
    return t + l;
}

vec3 relative_position(InstanceVgeo inst, ViewGpu v, vec3 p) {
    return relative_to(inst, v.camera_hi.xyz, v.camera_lo.xyz, p);
}

// Whether every point within the near plane's reach of the camera (at the origin) lies outside
// an object-space box of half extents `h` placed by the linear part `linear` at camera-relative
// centre `c` (the world box around it: conservative), so that the near plane cuts nothing
// of what the box holds (a closed solid in it shows no face turned away: docs/architecture.md,
// "Faces turned away"). The view is centred: the near plane's half-extents over its distance are
// `viewport / (2 proj_scale)`. The distance is taken by the largest axis gap (at most the
// Euclidean one), with margin for the rounding of c and e. Each comparison is false with a NaN
// (GLSL's max leaves NaN undefined, so none is used on a value that may be one), so NaN anywhere
// or a near plane not in front of the camera gives false.
bool near_plane_clear_of_box(vec3 c, vec3 h, mat3 linear, vec2 viewport, float proj_scale,
                             float near) {
    vec3 e = abs(linear[0]) * h.x + abs(linear[1]) * h.y + abs(linear[2]) * h.z;
    vec2 t = viewport / (2.0 * proj_scale);
    float reach = near * sqrt(1.0 + dot(t, t));
    vec3 gap = abs(c) - e;
    vec3 mag = abs(c) + e;
    float slack = 1.01 * reach + 1e-5 * (mag.x + mag.y + mag.z);
    return near > 0.0 && (gap.x > slack || gap.y > slack || gap.z > slack);
}

// Projected size in pixels of `error` at the sphere's point nearest to the camera (at the origin).
float lod_error_px(float error, vec3 center, float radius, float proj_scale) {
    if (error <= 0.0) {
        return 0.0;
    }
    precise float d = length(center) - radius;
    if (d <= 0.0) {
        return 1.0 / 0.0;
    }
    precise float e = error * proj_scale;
    return e / d;
}

// The share of its LOD errors that counts for an instance whose bounding sphere projects to a
// radius of `radius_px` pixels (src/builder/cut.rs small_instance_weight; SMALL_WEIGHT_RADIUS_PX
// in src/shared.rs says why): radius / SMALL_WEIGHT_RADIUS_PX, at least SMALL_WEIGHT_MIN, 1 from
// that radius up (lod_error_px's infinity included). No clamp(): a NaN radius gives 1 as on the CPU.
float small_instance_weight(float radius_px) {
    return radius_px < SMALL_WEIGHT_RADIUS_PX
        ? max(radius_px / SMALL_WEIGHT_RADIUS_PX, SMALL_WEIGHT_MIN) : 1.0;
}

// The projected radius (pixels) of instance `inst`'s bounding sphere at its point nearest to the
// camera: the size vgeo's small-instance table and weight go by.
float instance_size_px(InstanceVgeo inst, MeshGpu mesh, ViewGpu v) {
    vec3 c = relative_position(inst, v, mesh.bounds_center);
    float br = mesh.bounds_radius * inst.max_scale;
    return lod_error_px(br, c, br, v.proj_scale);
}

// The share of its LOD errors instance `inst` counts (small_instance_weight of its size).
float instance_weight(InstanceVgeo inst, MeshGpu mesh, ViewGpu v) {
    return small_instance_weight(instance_size_px(inst, mesh, v));
}

// A LOD error as an instance of weight `w` counts it: its coverage part (at most the error: a
// thin part's lost area, which a small instance shows as much as a large one) whole, the rest
// (position and shading) weighted. At w = 1 it is `error`. Mirror: src/reference/cut.rs.
float weighted_error(float error, float coverage, float w) {
    return max(error * w, coverage);
}

#endif
