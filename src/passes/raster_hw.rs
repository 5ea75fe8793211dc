//! Pass `raster_hw`: the hardware rasterizer, in one of two paths ([`HwPath`]):
//!
//! - **mesh** (shaders_glsl/raster_hw.mesh.glsl, where the device has `VK_EXT_mesh_shader`): one
//!   `vkCmdDrawMeshTasksIndirectEXT` (`CullCounters::hw_mesh`: a mesh-shader workgroup per HW-list
//!   entry, in rows of [`MESH_GROUPS_X`](crate::shared::MESH_GROUPS_X)); each workgroup decodes,
//!   transforms and snaps its cluster's vertices once into shared memory and emits the cluster as
//!   a meshlet (up to 255 vertices, 128 triangles), with the triangle's id, snapped vertices and
//!   depths as per-primitive outputs;
//! - **vertex** (shaders_glsl/raster_hw.vert.glsl, the default: measured faster, see
//!   [`HwPath::Auto`]): one `vkCmdDrawIndirect`
//!   (`CullCounters::hw_draw`: `MAX_CLUSTER_TRIANGLES * 3` vertices, one instance per HW-list
//!   entry) with no vertex buffers: each vertex invocation pulls and snaps all three vertices of
//!   its triangle (triangles beyond the cluster's count collapse to a point outside the view
//!   volume).
//!
//! No attachments: the fragment shader (shaders_glsl/raster_hw.frag.glsl, one source for both
//! paths) does the same `atomicMax` into the visibility buffer as `raster_sw`. Coverage is the
//! hardware's, of `raster_sw`'s own snapped vertices (`hw_position` in
//! shaders_glsl/common/raster.glsl: the same fill rule and 8 sub-pixel bits, so both cover the
//! same pixels; given the unsnapped clip position, the H100 covered 4-47 pixels of a 1080p frame
//! differently); depth is recomputed from the snapped vertices with `raster_sw`'s exact integer
//! edge functions and float operations, so SW and both HW paths write bit-identical values.
//! Triangles with a vertex behind the near plane (which only HW can draw: the hardware clips
//! them) pass their depth plane instead (2D homogeneous interpolation, `clipped_plane` in
//! shaders_glsl/common/raster.glsl, once per triangle), and the fragment stage takes one dot
//! product (`clipped_depth`), independent of how the pipeline clipped them, so the two paths
//! agree there too. With
//! [`VIEW_FLAG_COUNT_OVERDRAW`](crate::shared::VIEW_FLAG_COUNT_OVERDRAW) every fragment also
//! increments a per-pixel counter ([`RasterHw::record_counting`]).

use crate::gpu::{
    Buffer, Caps, Cmd, Context, Desc, GeometryStage, GpuError, GpuResult, GraphicsPipeline,
    GraphicsPipelineDesc, ShaderStage, Timer, vk,
};
use crate::passes::cull::Phase;
use crate::passes::{FrameBuffers, VisPath, with_geometry};
use crate::scene_gpu::GpuScene;
use crate::shared::CullCounters;

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "raster_hw";

/// How `raster_hw` feeds the hardware rasterizer (`--hw-path`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum HwPath {
    /// Vertex pulling, the faster of the two wherever measured (H100, session 14: all clusters to
    /// hardware 232 vs 314 ms on foliage, 556 vs 706 ms on stress N=100; the default split within
    /// 3 %; lavapipe: a mesh draw costs milliseconds even when empty); `VGEO_HW_PATH=mesh|vertex`
    /// overrides it.
    #[default]
    Auto,
    /// A mesh-shader workgroup per cluster, each vertex decoded once (`VK_EXT_mesh_shader`).
    Mesh,
    /// Vertex pulling: one draw of `MAX_CLUSTER_TRIANGLES * 3` vertices per cluster.
    Vertex,
}

impl HwPath {
    /// `auto`, `mesh` or `vertex`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "auto" => Some(HwPath::Auto),
            "mesh" => Some(HwPath::Mesh),
            "vertex" => Some(HwPath::Vertex),
            _ => None,
        }
    }

    /// `auto`, `mesh` or `vertex`.
    pub fn name(self) -> &'static str {
        match self {
            HwPath::Auto => "auto",
            HwPath::Mesh => "mesh",
            HwPath::Vertex => "vertex",
        }
    }

    /// The path this request takes on a device with `caps`: [`HwPath::Mesh`] or
    /// [`HwPath::Vertex`]. `Auto` is vertex pulling (or `VGEO_HW_PATH`; see [`HwPath::Auto`]);
    /// `Mesh` on a device without mesh shaders is an error that says so.
    pub fn resolve(self, caps: &Caps) -> Result<Self, String> {
        let requested = match self {
            HwPath::Auto => match std::env::var("VGEO_HW_PATH").ok().as_deref() {
                None | Some("") | Some("auto") => return Ok(HwPath::Vertex),
                Some(v) => HwPath::parse(v).ok_or_else(|| {
                    format!("VGEO_HW_PATH={v:?}: expected `auto`, `mesh` or `vertex`")
                })?,
            },
            p => p,
        };
        if requested == HwPath::Mesh && !caps.mesh_shader {
            return Err(format!(
                "the mesh-shader path of raster_hw needs VK_EXT_mesh_shader with meshShader, which \
                 {} does not have enabled (a capture tool may hide it); use --hw-path vertex or auto",
                caps.device_name
            ));
        }
        Ok(requested)
    }
}

/// The hardware rasterizer's pipeline for one visibility-buffer path and one [`HwPath`].
pub struct RasterHw {
    pipeline: GraphicsPipeline,
    path: VisPath,
    hw_path: HwPath,
    /// Bound as the overdraw counter when the frame does not count.
    no_overdraw: Buffer,
}

impl RasterHw {
    /// Creates the pipeline for `path` (the image variant needs 64-bit image atomics) and
    /// `hw_path` ([`HwPath::resolve`]d: `Mesh` without mesh shaders is an error).
    pub fn new(ctx: &Context, path: VisPath, hw_path: HwPath) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let hw_path = hw_path.resolve(ctx.caps()).map_err(GpuError::Other)?;
        let mesh = hw_path == HwPath::Mesh;
        let frag = match (path, mesh) {
            (VisPath::Buffer, false) => crate::shaders::RASTER_HW_FRAG,
            (VisPath::Image, false) => crate::shaders::RASTER_HW_FRAG_IMAGE,
            (VisPath::Buffer, true) => crate::shaders::RASTER_HW_FRAG_MESH,
            (VisPath::Image, true) => crate::shaders::RASTER_HW_FRAG_MESH_IMAGE,
        };
        let geometry = if mesh {
            GeometryStage::Mesh(ShaderStage {
                name: "raster_hw.mesh",
                spirv: crate::shaders::RASTER_HW_MESH,
            })
        } else {
            GeometryStage::Vertex(ShaderStage {
                name: "raster_hw.vert",
                spirv: crate::shaders::RASTER_HW_VERT,
            })
        };
        // view, visible, HW list, the 5 geometry buffers, visibility buffer, overdraw; the mesh
        // path also reads the counters (how many entries its workgroup grid covers).
        let vis = path.descriptor_type();
        let mut bindings = vec![D::UNIFORM_BUFFER];
        bindings.extend([D::STORAGE_BUFFER; 7]);
        bindings.push(vis);
        bindings.push(D::STORAGE_BUFFER);
        if mesh {
            bindings.push(D::STORAGE_BUFFER);
        }
        let pipeline = GraphicsPipeline::new(
            ctx,
            &GraphicsPipelineDesc {
                name: NAME,
                geometry,
                fragment: ShaderStage {
                    name: "raster_hw.frag",
                    spirv: frag,
                },
                bindings: &bindings,
                push_constant_size: 0,
                vertex_layout: None,
                color_formats: &[],
                depth_format: None,
                depth_compare: vk::CompareOp::ALWAYS,
                depth_write: false,
                cull: vk::CullModeFlags::NONE,
            },
        )?;
        let no_overdraw = crate::passes::raster_sw::overdraw_placeholder(ctx, NAME)?;
        Ok(Self {
            pipeline,
            path,
            hw_path,
            no_overdraw,
        })
    }

    /// The visibility-buffer path the pipeline was made for.
    pub fn path(&self) -> VisPath {
        self.path
    }

    /// The path it draws with: [`HwPath::Mesh`] or [`HwPath::Vertex`].
    pub fn hw_path(&self) -> HwPath {
        self.hw_path
    }

    /// The shader stages that read the cull's output (lists, counters): the barrier after the
    /// cull must make its writes visible to these (and to `DRAW_INDIRECT`).
    pub fn input_stages(&self) -> vk::PipelineStageFlags2 {
        let first = match self.hw_path {
            HwPath::Mesh => vk::PipelineStageFlags2::MESH_SHADER_EXT,
            _ => vk::PipelineStageFlags2::VERTEX_SHADER,
        };
        first | vk::PipelineStageFlags2::FRAGMENT_SHADER
    }

    /// Records the pass: draws every cluster of `fb.hw_list` (count and draw arguments in
    /// `fb.counters`) into `fb.visbuffer`. Inputs must be visible to [`RasterHw::input_stages`]
    /// and to the indirect-command stage (the frame records those barriers). Counts no
    /// overdraw: the view's flags must not have
    /// [`VIEW_FLAG_COUNT_OVERDRAW`](crate::shared::VIEW_FLAG_COUNT_OVERDRAW).
    pub fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        phase: Phase,
    ) {
        self.record_counting(cmd, timer, scene, fb, phase, None);
    }

    /// [`RasterHw::record`] with the overdraw counter: `overdraw` (`fb.width * fb.height` u32,
    /// row-major) gets 1 added per fragment when the view's flags have
    /// [`VIEW_FLAG_COUNT_OVERDRAW`](crate::shared::VIEW_FLAG_COUNT_OVERDRAW). `None` binds a
    /// placeholder (counts, if the flag is set anyway, are dropped).
    pub fn record_counting(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        phase: Phase,
        overdraw: Option<&Buffer>,
    ) {
        let (counters, _, hw_list) = fb.phase_lists(phase);
        timer.begin(cmd, phase.name("raster_hw", "raster_hw (post)"));
        let vis = fb.visbuffer_desc(cmd);
        debug_assert_eq!(
            fb.vis_path(),
            self.path,
            "raster_hw: pipeline for another path"
        );
        let mesh = self.hw_path == HwPath::Mesh;
        let overdraw = Desc::Storage(overdraw.unwrap_or(&self.no_overdraw));
        let after = [vis, overdraw, Desc::Storage(counters)];
        cmd.begin_rendering_no_attachments(fb.width, fb.height);
        cmd.bind_graphics(&self.pipeline);
        cmd.push_graphics_descriptors(
            &self.pipeline,
            &with_geometry(
                &[
                    Desc::Uniform(&fb.view),
                    Desc::Storage(&fb.visible),
                    Desc::Storage(hw_list),
                ],
                scene,
                &after[..if mesh { 3 } else { 2 }],
            ),
        );
        if mesh {
            cmd.draw_mesh_tasks_indirect(
                counters,
                std::mem::offset_of!(CullCounters, hw_mesh) as u64,
            );
        } else {
            cmd.draw_indirect(counters, std::mem::offset_of!(CullCounters, hw_draw) as u64);
        }
        cmd.end_rendering();
        timer.end(cmd);
    }
}
