//! Pass `brute`: the classic path and the baseline of every benchmark. Every instance at full detail
//! with `vkCmdDrawIndexed` (one instanced draw per mesh), a reverse-Z depth buffer (infinite far
//! plane, compare GREATER) and Lambert shading from vertex normals.

use glam::DMat3;

use crate::camera::Camera;
use crate::gpu::{
    Buffer, Context, Desc, GpuResult, GraphicsPipeline, GraphicsPipelineDesc, Image, MemoryKind,
    RenderTarget, ShaderStage, Timer, vk,
};
use crate::mesh::Mesh;
use crate::render::{BACKGROUND, Frame, Light, Placement};
use crate::shared::{FrameUniforms, InstanceGpu, VertexGpu};

const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// A mesh's vertex and index buffers on the GPU.
pub struct GpuMesh {
    vertices: Buffer,
    indices: Buffer,
    index_count: u32,
}

impl GpuMesh {
    /// Uploads `mesh` (positions, normals, uvs, u32 indices).
    pub fn upload(ctx: &Context, mesh: &Mesh) -> GpuResult<Self> {
        Self::upload_with_indices(ctx, mesh, &mesh.indices)
    }

    /// Uploads `mesh`'s vertices with `indices` (which index `mesh`'s vertices) as the index
    /// buffer: the discrete-LOD path puts all LODs of a mesh in one index buffer this way.
    pub fn upload_with_indices(ctx: &Context, mesh: &Mesh, indices: &[u32]) -> GpuResult<Self> {
        let verts: Vec<VertexGpu> = (0..mesh.positions.len())
            .map(|i| VertexGpu {
                position: mesh.positions[i],
                normal: mesh.normals[i],
                uv: mesh.uvs[i],
            })
            .collect();
        let name = if mesh.name.is_empty() {
            "mesh"
        } else {
            &mesh.name
        };
        Ok(Self {
            vertices: Buffer::with_data(
                ctx,
                &format!("{name} vertices"),
                bytemuck::cast_slice(&verts),
                vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
            )?,
            indices: Buffer::with_data(
                ctx,
                &format!("{name} indices"),
                bytemuck::cast_slice(indices),
                vk::BufferUsageFlags::INDEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
            )?,
            index_count: indices.len() as u32,
        })
    }

    /// Indices in the index buffer.
    pub fn index_count(&self) -> u32 {
        self.index_count
    }

    /// Bytes of GPU memory held.
    pub fn bytes(&self) -> u64 {
        self.vertices.size() + self.indices.size()
    }
}

/// The brute-force renderer: a pipeline plus the scene's meshes on the GPU.
pub struct Brute {
    ctx: Context,
    pipeline: GraphicsPipeline,
    meshes: Vec<GpuMesh>,
}

/// One instanced indexed draw of a classic pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Draw {
    /// Index into the pass's `GpuMesh` list.
    pub mesh: u32,
    /// First index and index count in that mesh's index buffer.
    pub first_index: u32,
    pub index_count: u32,
    /// Range in the instance buffer (`gl_InstanceIndex` = first_instance + i).
    pub first_instance: u32,
    pub instance_count: u32,
}

/// The classic pipeline (vertex positions and normals, Lambert shading, reverse-Z depth) shared by
/// the `brute` and `lod` passes so their images compare; `pass` names the pipeline.
pub(crate) fn classic_pipeline(ctx: &Context, pass: &str) -> GpuResult<GraphicsPipeline> {
    let attrs = [
        (0, vk::Format::R32G32B32_SFLOAT, 0),
        (1, vk::Format::R32G32B32_SFLOAT, 12),
    ];
    GraphicsPipeline::new(
        ctx,
        &GraphicsPipelineDesc {
            name: pass,
            vertex: ShaderStage {
                name: "brute.vert",
                spirv: crate::shaders::BRUTE_VERT,
            },
            fragment: ShaderStage {
                name: "brute.frag",
                spirv: crate::shaders::BRUTE_FRAG,
            },
            bindings: &[
                vk::DescriptorType::UNIFORM_BUFFER,
                vk::DescriptorType::STORAGE_BUFFER,
            ],
            push_constant_size: 0,
            vertex_layout: Some((size_of::<VertexGpu>() as u32, &attrs)),
            color_formats: &[COLOR_FORMAT],
            depth_format: Some(DEPTH_FORMAT),
            depth_compare: vk::CompareOp::GREATER,
            depth_write: true,
            cull: vk::CullModeFlags::NONE,
        },
    )
}

/// The GPU instance record of `p` seen from `camera` (camera-relative model, normal matrix).
pub(crate) fn instance_gpu(camera: &Camera, p: &Placement) -> InstanceGpu {
    let model = camera.relative_model(&p.transform);
    let nm = DMat3::from_mat4(p.transform)
        .inverse()
        .transpose()
        .as_mat3();
    InstanceGpu {
        model: model.to_cols_array_2d(),
        normal_matrix: [
            nm.x_axis.extend(0.0).into(),
            nm.y_axis.extend(0.0).into(),
            nm.z_axis.extend(0.0).into(),
        ],
        color: [p.color[0], p.color[1], p.color[2], 0.0],
    }
}

/// An error if a placement refers to a mesh that is not loaded.
pub(crate) fn check_placements(placements: &[Placement], mesh_count: usize) -> GpuResult<()> {
    if let Some(p) = placements.iter().find(|p| p.mesh as usize >= mesh_count) {
        return Err(crate::gpu::GpuError::Other(format!(
            "placement refers to mesh {} but only {} meshes are loaded",
            p.mesh, mesh_count
        )));
    }
    Ok(())
}

/// Instance data for the GPU, grouped by mesh: (instances, per-mesh (first, count)).
fn instances_by_mesh(
    camera: &Camera,
    placements: &[Placement],
    mesh_count: usize,
) -> (Vec<InstanceGpu>, Vec<(u32, u32)>) {
    let mut order: Vec<usize> = (0..placements.len()).collect();
    order.sort_by_key(|&i| placements[i].mesh);
    let mut ranges = vec![(0u32, 0u32); mesh_count];
    let mut out = Vec::with_capacity(placements.len());
    for i in order {
        let p = &placements[i];
        let r = &mut ranges[p.mesh as usize];
        if r.1 == 0 {
            r.0 = out.len() as u32;
        }
        r.1 += 1;
        out.push(instance_gpu(camera, p));
    }
    (out, ranges)
}

/// Records and runs one classic frame: clears, draws `draws` (instances from `instances`) with
/// `pipeline`, reads colour and depth back. `pass` names the resources and the timer scope.
/// `Frame::triangles` counts the triangles of every draw times its instances.
#[allow(clippy::too_many_arguments)]
pub(crate) fn render_draws(
    ctx: &Context,
    pass: &str,
    pipeline: &GraphicsPipeline,
    meshes: &[GpuMesh],
    instances: &[InstanceGpu],
    draws: &[Draw],
    camera: &Camera,
    light: &Light,
    width: u32,
    height: u32,
) -> GpuResult<Frame> {
    let uniforms = FrameUniforms {
        view_proj: camera.view_proj(width, height).to_cols_array_2d(),
        light_dir: light.direction.normalize_or_zero().extend(0.0).into(),
        viewport: [
            width as f32,
            height as f32,
            1.0 / width as f32,
            1.0 / height as f32,
        ],
    };
    let mut ubo = Buffer::new(
        ctx,
        &format!("{pass} frame uniforms"),
        size_of::<FrameUniforms>() as u64,
        vk::BufferUsageFlags::UNIFORM_BUFFER,
        MemoryKind::Upload,
    )?;
    ubo.write(0, bytemuck::bytes_of(&uniforms))?;
    let inst_buf = Buffer::with_data(
        ctx,
        &format!("{pass} instances"),
        bytemuck::cast_slice(instances),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let color = Image::new(
        ctx,
        &format!("{pass} color"),
        width,
        height,
        COLOR_FORMAT,
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
    )?;
    let depth = Image::new(
        ctx,
        &format!("{pass} depth"),
        width,
        height,
        DEPTH_FORMAT,
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
    )?;
    let mut timer = Timer::new(ctx, 4)?;
    let bg = BACKGROUND.map(|c| c.powf(1.0 / 2.2));
    let mut triangles = 0u64;
    ctx.submit_and_wait(&format!("{pass} frame"), |cmd| {
        timer.reset(cmd);
        timer.begin(cmd, pass);
        cmd.begin_rendering(
            &[RenderTarget {
                image: &color,
                clear: Some([bg[0], bg[1], bg[2], 1.0]),
            }],
            Some(RenderTarget {
                image: &depth,
                clear: Some([0.0; 4]),
            }),
        );
        cmd.bind_graphics(pipeline);
        cmd.push_graphics_descriptors(pipeline, &[Desc::Uniform(&ubo), Desc::Storage(&inst_buf)]);
        let mut bound: Option<u32> = None;
        for d in draws {
            if d.instance_count == 0 || d.index_count == 0 {
                continue;
            }
            let Some(mesh) = meshes.get(d.mesh as usize) else {
                continue;
            };
            if bound != Some(d.mesh) {
                cmd.bind_mesh_buffers(&mesh.vertices, &mesh.indices);
                bound = Some(d.mesh);
            }
            cmd.draw_indexed(
                d.index_count,
                d.instance_count,
                d.first_index,
                d.first_instance,
            );
            triangles += (d.index_count / 3) as u64 * d.instance_count as u64;
        }
        cmd.end_rendering();
        timer.end(cmd);
    })?;
    let gpu_ms = timer.results()?;
    let color_bytes = color.download()?;
    let depth_bytes = depth.download()?;
    Ok(Frame {
        width,
        height,
        color: color_bytes,
        depth: bytemuck::cast_slice(&depth_bytes).to_vec(),
        gpu_ms,
        triangles,
    })
}

impl Brute {
    /// Creates the pipeline and uploads `meshes`.
    pub fn new(ctx: &Context, meshes: &[Mesh]) -> GpuResult<Self> {
        let pipeline = classic_pipeline(ctx, "brute")?;
        let meshes = meshes
            .iter()
            .map(|m| GpuMesh::upload(ctx, m))
            .collect::<GpuResult<Vec<_>>>()?;
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
            meshes,
        })
    }

    /// GPU bytes of geometry.
    pub fn geometry_bytes(&self) -> u64 {
        self.meshes.iter().map(GpuMesh::bytes).sum()
    }

    /// Renders `placements` seen from `camera` into a `width` x `height` frame and reads it back.
    pub fn render(
        &self,
        placements: &[Placement],
        camera: &Camera,
        light: &Light,
        width: u32,
        height: u32,
    ) -> GpuResult<Frame> {
        check_placements(placements, self.meshes.len())?;
        let (instances, ranges) = instances_by_mesh(camera, placements, self.meshes.len());
        let draws: Vec<Draw> = self
            .meshes
            .iter()
            .zip(&ranges)
            .enumerate()
            .map(|(i, (mesh, &(first, count)))| Draw {
                mesh: i as u32,
                first_index: 0,
                index_count: mesh.index_count,
                first_instance: first,
                instance_count: count,
            })
            .collect();
        render_draws(
            &self.ctx,
            "brute",
            &self.pipeline,
            &self.meshes,
            &instances,
            &draws,
            camera,
            light,
            width,
            height,
        )
    }
}
