// Simple lighting shared by every path (brute, lod, vgeo) so their images compare.
#ifndef VGEO_SHADING_GLSL
#define VGEO_SHADING_GLSL

vec3 shade_lambert(vec3 albedo, vec3 n, vec3 light_dir) {
    float ndl = abs(dot(normalize(n), normalize(light_dir)));
    return albedo * (0.2 + 0.8 * ndl);
}

// Linear -> sRGB-ish output (the target is UNORM; we encode gamma ourselves).
vec3 encode_srgb(vec3 c) {
    return pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2));
}

#endif
