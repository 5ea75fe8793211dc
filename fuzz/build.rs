//! Links the fuzz targets against the glslang and SPIRV-Tools libraries missing from Debian's
//! `libshaderc_combined.a`: vgeo compiles replaced shaders at run time (`--shader-dir`) through
//! shaderc, so every binary linking vgeo needs them, and cargo fuzz replaces the rustflags that
//! the repository's `.cargo/config.toml` would add (see README.md, "Running").
fn main() {
    let libs = [
        "glslang",
        "MachineIndependent",
        "GenericCodeGen",
        "OSDependent",
        "OGLCompiler",
        "SPIRV",
        "glslang-default-resource-limits",
        "SPIRV-Tools-opt",
        "SPIRV-Tools",
    ];
    println!("cargo:rustc-link-arg-bins=-Wl,--start-group");
    for l in libs {
        println!("cargo:rustc-link-arg-bins=-l{l}");
    }
    println!("cargo:rustc-link-arg-bins=-Wl,--end-group");
}
