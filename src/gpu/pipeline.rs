//! Shader modules and pipelines. Every pipeline uses one push-descriptor set layout and an optional
//! push-constant range; graphics pipelines use dynamic rendering.

use ash::vk;

use super::{Context, GpuError, GpuResult, TextureSet, VkResultExt};

/// A shader stage's SPIR-V (as embedded by build.rs).
#[derive(Clone, Copy)]
pub struct ShaderStage<'a> {
    pub name: &'a str,
    pub spirv: &'a [u8],
}

fn module(ctx: &Context, stage: ShaderStage<'_>) -> GpuResult<vk::ShaderModule> {
    let spirv = ctx.shader_spirv(stage.spirv);
    let words =
        ash::util::read_spv(&mut std::io::Cursor::new(spirv)).map_err(|e| GpuError::Shader {
            name: stage.name.into(),
            msg: e.to_string(),
        })?;
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    // SAFETY: `words` is SPIR-V produced by shaderc (at build time, or from `--shader-dir`).
    let m =
        unsafe { ctx.device().create_shader_module(&info, None) }.call("vkCreateShaderModule")?;
    ctx.set_name(m, stage.name);
    Ok(m)
}

struct Layout {
    set: vk::DescriptorSetLayout,
    pipeline: vk::PipelineLayout,
}

fn layout(
    ctx: &Context,
    name: &str,
    bindings: &[vk::DescriptorType],
    stages: vk::ShaderStageFlags,
    push_constant_size: u32,
    extra_sets: &[vk::DescriptorSetLayout],
) -> GpuResult<Layout> {
    let b: Vec<_> = bindings
        .iter()
        .enumerate()
        .map(|(i, t)| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(i as u32)
                .descriptor_type(*t)
                .descriptor_count(1)
                .stage_flags(stages)
        })
        .collect();
    let info = vk::DescriptorSetLayoutCreateInfo::default()
        .flags(vk::DescriptorSetLayoutCreateFlags::PUSH_DESCRIPTOR_KHR)
        .bindings(&b);
    // SAFETY: valid create info.
    let set = unsafe { ctx.device().create_descriptor_set_layout(&info, None) }
        .call("vkCreateDescriptorSetLayout")?;
    ctx.set_name(set, &format!("{name} set layout"));
    let mut sets = vec![set];
    sets.extend_from_slice(extra_sets);
    let ranges = [vk::PushConstantRange {
        stage_flags: stages,
        offset: 0,
        size: push_constant_size,
    }];
    let mut pinfo = vk::PipelineLayoutCreateInfo::default().set_layouts(&sets);
    if push_constant_size > 0 {
        pinfo = pinfo.push_constant_ranges(&ranges);
    }
    // SAFETY: valid create info referencing the set layout above.
    let pipeline = unsafe { ctx.device().create_pipeline_layout(&pinfo, None) }
        .call("vkCreatePipelineLayout")?;
    ctx.set_name(pipeline, &format!("{name} layout"));
    Ok(Layout { set, pipeline })
}

/// A compute pipeline.
pub struct ComputePipeline {
    ctx: Context,
    pub(crate) raw: vk::Pipeline,
    pub(crate) layout: vk::PipelineLayout,
    set_layout: vk::DescriptorSetLayout,
    pub(crate) push_constant_size: u32,
    pub(crate) name: String,
}

impl ComputePipeline {
    /// Creates a compute pipeline from `shader` with descriptor bindings `bindings` (binding i = entry i).
    pub fn new(
        ctx: &Context,
        shader: ShaderStage<'_>,
        bindings: &[vk::DescriptorType],
        push_constant_size: u32,
    ) -> GpuResult<Self> {
        Self::with_sets(ctx, shader, bindings, push_constant_size, &[], &[])
    }

    /// Like [`ComputePipeline::new`] with specialization constants: `(constant_id, value)` pairs,
    /// each a 32-bit scalar (a GLSL `bool` takes 0 or 1).
    pub fn specialized(
        ctx: &Context,
        shader: ShaderStage<'_>,
        bindings: &[vk::DescriptorType],
        push_constant_size: u32,
        constants: &[(u32, u32)],
    ) -> GpuResult<Self> {
        Self::with_sets(ctx, shader, bindings, push_constant_size, &[], constants)
    }

    /// Like [`ComputePipeline::new`] with a bindless texture array as descriptor set 1.
    pub fn with_textures(
        ctx: &Context,
        shader: ShaderStage<'_>,
        bindings: &[vk::DescriptorType],
        push_constant_size: u32,
        textures: &TextureSet,
    ) -> GpuResult<Self> {
        Self::with_sets(
            ctx,
            shader,
            bindings,
            push_constant_size,
            &[textures.layout],
            &[],
        )
    }

    fn with_sets(
        ctx: &Context,
        shader: ShaderStage<'_>,
        bindings: &[vk::DescriptorType],
        push_constant_size: u32,
        extra_sets: &[vk::DescriptorSetLayout],
        constants: &[(u32, u32)],
    ) -> GpuResult<Self> {
        let l = layout(
            ctx,
            shader.name,
            bindings,
            vk::ShaderStageFlags::COMPUTE,
            push_constant_size,
            extra_sets,
        )?;
        let m = module(ctx, shader)?;
        let entries: Vec<vk::SpecializationMapEntry> = constants
            .iter()
            .enumerate()
            .map(|(i, &(id, _))| vk::SpecializationMapEntry {
                constant_id: id,
                offset: 4 * i as u32,
                size: 4,
            })
            .collect();
        let data: Vec<u32> = constants.iter().map(|&(_, v)| v).collect();
        let spec = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(bytemuck::cast_slice(&data));
        let mut stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(m)
            .name(c"main");
        if !constants.is_empty() {
            stage = stage.specialization_info(&spec);
        }
        let info = vk::ComputePipelineCreateInfo::default()
            .flags(statistics_flags(ctx))
            .stage(stage)
            .layout(l.pipeline);
        // SAFETY: valid create info; the module may be destroyed after pipeline creation.
        let result = unsafe {
            ctx.device()
                .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
        };
        // SAFETY: the module is no longer needed.
        unsafe { ctx.device().destroy_shader_module(m, None) };
        let raw = result
            .map_err(|(_, e)| e)
            .call("vkCreateComputePipelines")?[0];
        ctx.set_name(raw, shader.name);
        print_statistics(ctx, raw, shader.name);
        Ok(Self {
            ctx: ctx.clone(),
            raw,
            layout: l.pipeline,
            set_layout: l.set,
            push_constant_size,
            name: shader.name.into(),
        })
    }
}

impl Drop for ComputePipeline {
    fn drop(&mut self) {
        // SAFETY: the pipeline is idle (all submissions are waited on).
        unsafe {
            let d = self.ctx.device();
            d.destroy_pipeline(self.raw, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}

/// A vertex attribute: (shader location, format, byte offset in the vertex).
pub type VertexAttribute = (u32, vk::Format, u32);

/// The stage before rasterization of a graphics pipeline.
#[derive(Clone, Copy)]
pub enum GeometryStage<'a> {
    /// A vertex shader (with the pipeline's vertex input and triangle-list assembly).
    Vertex(ShaderStage<'a>),
    /// A mesh shader (`VK_EXT_mesh_shader`, no task shader): needs [`super::Caps::mesh_shader`].
    Mesh(ShaderStage<'a>),
}

impl GeometryStage<'_> {
    fn flag(&self) -> vk::ShaderStageFlags {
        match self {
            GeometryStage::Vertex(_) => vk::ShaderStageFlags::VERTEX,
            GeometryStage::Mesh(_) => vk::ShaderStageFlags::MESH_EXT,
        }
    }
}

/// How to build a graphics pipeline.
pub struct GraphicsPipelineDesc<'a> {
    pub name: &'a str,
    /// The vertex or mesh shader.
    pub geometry: GeometryStage<'a>,
    pub fragment: ShaderStage<'a>,
    pub bindings: &'a [vk::DescriptorType],
    pub push_constant_size: u32,
    /// Vertex buffer 0: stride and (location, format, offset) attributes; `None` for vertex pulling.
    pub vertex_layout: Option<(u32, &'a [VertexAttribute])>,
    pub color_formats: &'a [vk::Format],
    pub depth_format: Option<vk::Format>,
    pub depth_compare: vk::CompareOp,
    pub depth_write: bool,
    pub cull: vk::CullModeFlags,
}

/// A graphics pipeline (dynamic rendering, dynamic viewport and scissor).
pub struct GraphicsPipeline {
    ctx: Context,
    pub(crate) raw: vk::Pipeline,
    pub(crate) layout: vk::PipelineLayout,
    set_layout: vk::DescriptorSetLayout,
    pub(crate) push_constant_size: u32,
    /// The shader stages (vertex or mesh, and fragment): those of its push-constant range.
    pub(crate) stages: vk::ShaderStageFlags,
    pub(crate) name: String,
}

impl GraphicsPipeline {
    /// Creates the pipeline.
    pub fn new(ctx: &Context, d: &GraphicsPipelineDesc<'_>) -> GpuResult<Self> {
        Self::with_sets(ctx, d, &[])
    }

    /// Like [`GraphicsPipeline::new`] with a bindless texture array as descriptor set 1.
    pub fn with_textures(
        ctx: &Context,
        d: &GraphicsPipelineDesc<'_>,
        textures: &TextureSet,
    ) -> GpuResult<Self> {
        Self::with_sets(ctx, d, &[textures.layout])
    }

    fn with_sets(
        ctx: &Context,
        d: &GraphicsPipelineDesc<'_>,
        extra_sets: &[vk::DescriptorSetLayout],
    ) -> GpuResult<Self> {
        let (geometry, mesh) = match d.geometry {
            GeometryStage::Vertex(s) => (s, false),
            GeometryStage::Mesh(s) => (s, true),
        };
        if mesh && !ctx.caps().mesh_shader {
            return Err(GpuError::Other(format!(
                "pipeline `{}` has a mesh shader but the device has no VK_EXT_mesh_shader with \
                 meshShader enabled",
                d.name
            )));
        }
        let stages = d.geometry.flag() | vk::ShaderStageFlags::FRAGMENT;
        let l = layout(
            ctx,
            d.name,
            d.bindings,
            stages,
            d.push_constant_size,
            extra_sets,
        )?;
        let vm = module(ctx, geometry)?;
        let fm = match module(ctx, d.fragment) {
            Ok(m) => m,
            Err(e) => {
                // SAFETY: unused module.
                unsafe { ctx.device().destroy_shader_module(vm, None) };
                return Err(e);
            }
        };
        let sinfo = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(d.geometry.flag())
                .module(vm)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(fm)
                .name(c"main"),
        ];
        let mut vb = Vec::new();
        let mut va = Vec::new();
        if let Some((stride, attrs)) = d.vertex_layout {
            vb.push(vk::VertexInputBindingDescription {
                binding: 0,
                stride,
                input_rate: vk::VertexInputRate::VERTEX,
            });
            for &(location, format, offset) in attrs {
                va.push(vk::VertexInputAttributeDescription {
                    location,
                    binding: 0,
                    format,
                    offset,
                });
            }
        }
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&vb)
            .vertex_attribute_descriptions(&va);
        let ia = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let vp = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let rs = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(d.cull)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let ms = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let ds = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(d.depth_format.is_some())
            .depth_write_enable(d.depth_write)
            .depth_compare_op(d.depth_compare);
        let blend: Vec<_> = d
            .color_formats
            .iter()
            .map(|_| {
                vk::PipelineColorBlendAttachmentState::default()
                    .color_write_mask(vk::ColorComponentFlags::RGBA)
            })
            .collect();
        let cb = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
        let dyn_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dyn_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(d.color_formats)
            .depth_attachment_format(d.depth_format.unwrap_or(vk::Format::UNDEFINED));
        let mut info = vk::GraphicsPipelineCreateInfo::default()
            .flags(statistics_flags(ctx))
            .stages(&sinfo)
            .viewport_state(&vp)
            .rasterization_state(&rs)
            .multisample_state(&ms)
            .depth_stencil_state(&ds)
            .color_blend_state(&cb)
            .dynamic_state(&dynamic)
            .layout(l.pipeline)
            .push_next(&mut rendering);
        // A mesh pipeline has no vertex input or input assembly.
        if !mesh {
            info = info
                .vertex_input_state(&vertex_input)
                .input_assembly_state(&ia);
        }
        // SAFETY: every pointer in `info` refers to locals alive for the call.
        let result = unsafe {
            ctx.device()
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        };
        // SAFETY: the modules are no longer needed after pipeline creation.
        unsafe {
            ctx.device().destroy_shader_module(vm, None);
            ctx.device().destroy_shader_module(fm, None);
        }
        let raw = result
            .map_err(|(_, e)| e)
            .call("vkCreateGraphicsPipelines")?[0];
        ctx.set_name(raw, d.name);
        print_statistics(ctx, raw, d.name);
        Ok(Self {
            ctx: ctx.clone(),
            raw,
            layout: l.pipeline,
            set_layout: l.set,
            push_constant_size: d.push_constant_size,
            stages,
            name: d.name.into(),
        })
    }
}

impl Drop for GraphicsPipeline {
    fn drop(&mut self) {
        // SAFETY: the pipeline is idle (all submissions are waited on).
        unsafe {
            let d = self.ctx.device();
            d.destroy_pipeline(self.raw, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}

/// `CAPTURE_STATISTICS_KHR` when pipeline statistics were asked for (`VGEO_PIPELINE_STATS=1`) and
/// the device has them ([`super::Caps::pipeline_statistics`]).
fn statistics_flags(ctx: &Context) -> vk::PipelineCreateFlags {
    if ctx.inner.pipeline_executable.is_some() {
        vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR
    } else {
        vk::PipelineCreateFlags::empty()
    }
}

/// Prints each executable (shader stage) of `pipeline` with the statistics its driver reports
/// (`VK_KHR_pipeline_executable_properties`: registers, shared memory, instructions, ... as the
/// driver names them), one line each on stderr, when they were asked for. A query that fails says
/// so on that line: it never fails the pipeline.
fn print_statistics(ctx: &Context, pipeline: vk::Pipeline, name: &str) {
    let Some(pe) = ctx.inner.pipeline_executable.as_ref() else {
        return;
    };
    let info = vk::PipelineInfoKHR::default().pipeline(pipeline);
    // SAFETY: a query on a valid pipeline created with CAPTURE_STATISTICS_KHR.
    let executables = match unsafe { pe.get_pipeline_executable_properties(&info) } {
        Ok(e) => e,
        Err(e) => {
            eprintln!("[pipeline statistics] {name}: vkGetPipelineExecutablePropertiesKHR: {e}");
            return;
        }
    };
    for (i, exe) in executables.iter().enumerate() {
        let exe_name = exe
            .name_as_c_str()
            .map(|c| c.to_string_lossy().into_owned());
        let exe_name = exe_name.unwrap_or_else(|_| format!("executable {i}"));
        let einfo = vk::PipelineExecutableInfoKHR::default()
            .pipeline(pipeline)
            .executable_index(i as u32);
        // SAFETY: a query on a valid pipeline's executable `i`.
        let stats = match unsafe { pe.get_pipeline_executable_statistics(&einfo) } {
            Ok(s) => s,
            Err(e) => {
                eprintln!("[pipeline statistics] {name} / {exe_name}: {e}");
                continue;
            }
        };
        let values: Vec<String> = stats.iter().map(statistic_text).collect();
        eprintln!(
            "[pipeline statistics] {name} / {exe_name} (subgroup {}): {}",
            exe.subgroup_size,
            values.join(", ")
        );
    }
}

/// `name = value` of one statistic.
fn statistic_text(s: &vk::PipelineExecutableStatisticKHR<'_>) -> String {
    let name = s
        .name_as_c_str()
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_default();
    // SAFETY: the union member read is the one `format` names.
    let value = unsafe {
        match s.format {
            vk::PipelineExecutableStatisticFormatKHR::BOOL32 => (s.value.b32 != 0).to_string(),
            vk::PipelineExecutableStatisticFormatKHR::INT64 => s.value.i64.to_string(),
            vk::PipelineExecutableStatisticFormatKHR::UINT64 => s.value.u64.to_string(),
            vk::PipelineExecutableStatisticFormatKHR::FLOAT64 => format!("{:.3}", s.value.f64),
            _ => "?".into(),
        }
    };
    format!("{name} = {value}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_read_as_name_and_value() {
        let mut s = vk::PipelineExecutableStatisticKHR::default();
        s.name[..9].copy_from_slice(&b"Registers".map(|b| b as std::ffi::c_char));
        s.format = vk::PipelineExecutableStatisticFormatKHR::UINT64;
        s.value.u64 = 72;
        assert_eq!(statistic_text(&s), "Registers = 72");
        s.format = vk::PipelineExecutableStatisticFormatKHR::BOOL32;
        s.value.b32 = vk::TRUE;
        assert_eq!(statistic_text(&s), "Registers = true");
        s.format = vk::PipelineExecutableStatisticFormatKHR::FLOAT64;
        s.value.f64 = 0.5;
        assert_eq!(statistic_text(&s), "Registers = 0.500");
        s.format = vk::PipelineExecutableStatisticFormatKHR::INT64;
        s.value.i64 = -3;
        assert_eq!(statistic_text(&s), "Registers = -3");
    }
}
