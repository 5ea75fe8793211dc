// The overdraw counter of the `overdraw` view: one uint per pixel (row-major, width from the
// view), incremented by raster_sw for each pixel a triangle covers (each visibility-buffer atomic)
// and by raster_hw for each fragment, only when ViewGpu.flags has VIEW_FLAG_COUNT_OVERDRAW (else a
// placeholder buffer is bound and the rasterizers pay only the branch). The including shader
// defines OVERDRAW_BINDING and declares `view` (ViewGpu) before including this file.
#ifndef VGEO_OVERDRAW_GLSL
#define VGEO_OVERDRAW_GLSL

layout(set = 0, binding = OVERDRAW_BINDING, scalar) buffer Overdraw { uint overdraw_counts[]; };

void overdraw_count(ivec2 p, uint width) {
    if ((view.flags & VIEW_FLAG_COUNT_OVERDRAW) != 0u) {
        uint i = uint(p.y) * width + uint(p.x);
        // A placeholder (flag set by mistake) drops the count instead of writing out of bounds.
        if (i < uint(overdraw_counts.length())) {
            atomicAdd(overdraw_counts[i], 1u);
        }
    }
}

#endif
