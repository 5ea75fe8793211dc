// The HZB test of a projected box (shared by cull.glsl's hzb_occluded and lod_cull): the box's
// corners give a screen rectangle (`hzb_add_corner`), and `hzb_rect_occluded` tells whether
// pixels `lo`..`hi` (corners of a projected box, unclamped) at nearest depth `nearest` (reverse-Z:
// the largest) lie behind the farthest depth the HZB holds there. The HZB is built from a
// `viewport`-sized frame with `levels` levels (depth_pyramid); the including shader declares
// `hzb` (float[]). Conservative: a rectangle wholly off screen is never called occluded.
#ifndef VGEO_HZB_GLSL
#define VGEO_HZB_GLSL

// Texels per side of the window a box is tested in (see hzb_rect_occluded).
#define HZB_WINDOW 5u

// Corner `i` (0..7) of the box [bmin, bmax].
vec3 box_corner(vec3 bmin, vec3 bmax, int i) {
    return vec3((i & 1) != 0 ? bmax.x : bmin.x, (i & 2) != 0 ? bmax.y : bmin.y, (i & 4) != 0 ? bmax.z : bmin.z);
}

// Adds a box corner in clip space `c` to the screen rectangle `lo`..`hi` (pixels of a
// `viewport`-sized frame) and the nearest depth; false when it reaches the `near` plane (the box
// is then never called occluded).
bool hzb_add_corner(vec4 c, float near, vec2 viewport, inout vec2 lo, inout vec2 hi, inout float nearest) {
    if (c.w <= near) {
        return false;
    }
    vec3 n = c.xyz / c.w;
    vec2 px = (n.xy * 0.5 + 0.5) * viewport;
    lo = min(lo, px);
    hi = max(hi, px);
    nearest = max(nearest, n.z);
    return true;
}

bool hzb_rect_occluded(vec2 lo, vec2 hi, float nearest, vec2 viewport, uint levels) {
    lo = max(lo, vec2(0.0));
    hi = min(hi, viewport - 1.0);
    if (hi.x < lo.x || hi.y < lo.y) {
        return false;
    }
    float size = max(hi.x - lo.x, hi.y - lo.y);
    // Level k texels cover 2^(k+1) pixels: pick the level where the box spans at most
    // HZB_WINDOW x HZB_WINDOW texels (size <= 2^(k+3) pixels, so the texel rows and columns it
    // touches number at most 5: the clamp below never cuts the box). A 2x2 window, two levels
    // coarser, reached up to a texel of 2^(k+3) pixels past the box and let through what a
    // porous field hides (foliage 2.98 -> 2.44 ms, stress N=200 8.16 -> 7.51, the same images:
    // bench/results/2026-11-27-session30).
    uint k = uint(max(0, int(ceil(log2(max(size, 1.0)))) - 3));
    k = min(k, levels - 1u);
    uint w = (uint(viewport.x) + 1u) / 2u;
    uint h = (uint(viewport.y) + 1u) / 2u;
    uint offset = 0u;
    for (uint l = 0u; l < k; l++) {
        offset += w * h;
        w = (w + 1u) / 2u;
        h = (h + 1u) / 2u;
    }
    float texel = float(1u << (k + 1u));
    uvec2 t0 = min(uvec2(floor(lo / texel)), uvec2(w - 1u, h - 1u));
    uvec2 t1 = min(uvec2(floor(hi / texel)), uvec2(w - 1u, h - 1u));
    t1 = min(t1, t0 + (HZB_WINDOW - 1u));
    // A row's texels are read at once (independent loads; a column past the box reads its last
    // texel again), and a row holding a texel at least as near as the box ends the test: visible
    // (as is a NaN depth: only a box surely behind is occluded).
    for (uint y = t0.y; y <= t1.y; y++) {
        float farthest = 1.0;
        for (uint i = 0u; i < HZB_WINDOW; i++) {
            farthest = min(farthest, hzb[offset + y * w + min(t0.x + i, t1.x)]);
        }
        if (!(nearest < farthest)) {
            return false;
        }
    }
    return true;
}

#endif
