// Shared by instance_cull and cluster_cull: camera-relative transforms, frustum test, the LOD
// error projection (mirrors src/builder/cut.rs::lod_error_px operation for operation) and the
// work-queue push.
#ifndef VGEO_CULL_GLSL
#define VGEO_CULL_GLSL

// Camera-relative position of object-space point p of an instance: hi/lo translation minus the
// camera first (exact for large coordinates), then the linear part, column by column.
vec3 relative_position(InstanceVgeo inst, ViewGpu view, vec3 p) {
    precise vec3 t = (inst.translation_hi - view.camera_hi.xyz) + (inst.translation_lo - view.camera_lo.xyz);
    precise vec3 l = inst.linear[0].xyz * p.x + inst.linear[1].xyz * p.y + inst.linear[2].xyz * p.z;
    return t + l;
}

// Whether a camera-relative sphere touches the frustum (far plane at infinity).
bool sphere_in_frustum(ViewGpu view, vec3 c, float r) {
    for (int i = 0; i < 5; i++) {
        if (dot(view.frustum[i].xyz, c) + view.frustum[i].w < -r) {
            return false;
        }
    }
    return true;
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

#endif
