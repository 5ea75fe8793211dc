// The 64-bit visibility buffer: `floatBitsToUint(depth) << 32 | visible index << 7 | triangle`,
// written with atomicMax (reverse-Z: the nearest wins), 0 = empty. Two storage paths from one
// source: `VISBUFFER_IMAGE` defined -> an r64ui storage image (GL_EXT_shader_image_int64), else a
// uint64_t storage buffer (GL_EXT_shader_atomic_int64). The including shader defines
// VISBUFFER_BINDING (and VISBUFFER_READONLY for readers) before including this file.
#ifndef VGEO_VISBUFFER_GLSL
#define VGEO_VISBUFFER_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#ifdef VISBUFFER_IMAGE
#extension GL_EXT_shader_image_int64 : require
#else
#extension GL_EXT_shader_atomic_int64 : require
#endif

#ifdef VISBUFFER_IMAGE
layout(set = 0, binding = VISBUFFER_BINDING, r64ui) uniform
#ifdef VISBUFFER_READONLY
    readonly
#endif
    u64image2D vis_image;
#else
layout(set = 0, binding = VISBUFFER_BINDING, scalar) buffer
#ifdef VISBUFFER_READONLY
    readonly
#endif
    VisBuffer { uint64_t vis_words[]; };
#endif

uint64_t vis_pack(float depth, uint visible_index, uint triangle) {
    uint lo = (visible_index << VISBUFFER_TRIANGLE_BITS) | triangle;
    return (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(lo);
}

#ifndef VISBUFFER_READONLY
// A plain store (seeding the buffer, not rasterizing).
void vis_store(ivec2 p, uint width, uint64_t value) {
#ifdef VISBUFFER_IMAGE
    imageStore(vis_image, p, u64vec4(value, 0ul, 0ul, 0ul));
#else
    vis_words[uint(p.y) * width + uint(p.x)] = value;
#endif
}

void vis_write(ivec2 p, uint width, uint64_t value) {
#ifdef VISBUFFER_IMAGE
    imageAtomicMax(vis_image, p, value);
#else
    atomicMax(vis_words[uint(p.y) * width + uint(p.x)], value);
#endif
}
#endif

// The depth of a visibility-buffer value (0: empty, infinitely far).
float vis_depth(uint64_t value) {
    return uintBitsToFloat(uint(value >> 32));
}

uint64_t vis_read(ivec2 p, uint width) {
#ifdef VISBUFFER_IMAGE
    return imageLoad(vis_image, p).x;
#else
    return vis_words[uint(p.y) * width + uint(p.x)];
#endif
}

#endif
