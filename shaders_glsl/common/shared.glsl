// GPU structs shared with Rust (src/shared.rs); layouts must match byte for byte (scalar layout).
// The constants (SUBPIXEL_BITS, ...) are defined by build.rs from src/shared.rs.
#ifndef VGEO_SHARED_GLSL
#define VGEO_SHARED_GLSL

#extension GL_EXT_scalar_block_layout : require

struct FrameUniforms {
    mat4 view_proj;
    vec4 light_dir;
    vec4 viewport;
};

struct InstanceGpu {
    mat4 model;
    vec4 normal_matrix[3];
    vec4 color;
};

#endif
