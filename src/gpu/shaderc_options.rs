//! How vgeo compiles GLSL with shaderc, shared by build.rs (the embedded shaders) and
//! `--shader-dir` (src/gpu/shader_dir.rs), so both make the same SPIR-V from the same source.

/// The shader kind of a `<pass>.<stage>.glsl` stage name.
pub(crate) fn shader_kind(stage: &str) -> Option<shaderc::ShaderKind> {
    Some(match stage {
        "vert" => shaderc::ShaderKind::Vertex,
        "frag" => shaderc::ShaderKind::Fragment,
        "comp" => shaderc::ShaderKind::Compute,
        "mesh" => shaderc::ShaderKind::Mesh,
        "task" => shaderc::ShaderKind::Task,
        _ => return None,
    })
}

/// Options: Vulkan 1.2 / SPIR-V 1.5, GLSL, the macros given; with `debug`, debug info and no
/// optimization (for RenderDoc's shader debugger), else optimized for performance.
pub(crate) fn compile_options<'a>(
    debug: bool,
    macros: &[(&str, &str)],
) -> Option<shaderc::CompileOptions<'a>> {
    let mut opts = shaderc::CompileOptions::new()?;
    opts.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    opts.set_target_spirv(shaderc::SpirvVersion::V1_5);
    opts.set_source_language(shaderc::SourceLanguage::GLSL);
    if debug {
        opts.set_generate_debug_info();
        opts.set_optimization_level(shaderc::OptimizationLevel::Zero);
    } else {
        opts.set_optimization_level(shaderc::OptimizationLevel::Performance);
    }
    for (k, v) in macros {
        opts.add_macro_definition(k, Some(v));
    }
    Some(opts)
}
