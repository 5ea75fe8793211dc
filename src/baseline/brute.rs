//! Pass `brute`: the classic path and the baseline of every benchmark. Every instance at full detail
//! with `vkCmdDrawIndexed` (one instanced draw per mesh), a reverse-Z depth buffer (infinite far
//! plane, compare GREATER), writing the GBuffer through the material model every path shares
//! (shaders_glsl/common/gbuffer.glsl), then `shade`, so its images compare with vgeo's.
//!
//! Also home of what `brute` and `lod` share: [`ClassicMesh`] (vertices split per material),
//! [`GpuMesh`] and the `Classic` renderer core.

use std::borrow::Cow;
use std::collections::HashMap;

use glam::DMat3;

use crate::camera::Camera;
use crate::gpu::{
    Buffer, Context, Desc, GeometryStage, GpuResult, GraphicsPipeline, GraphicsPipelineDesc, Image,
    MemoryKind, RenderTarget, ShaderStage, Timer, vk,
};
use crate::material::{GpuMaterials, SceneMaterials, ShadeMode};
use crate::mesh::Mesh;
use crate::passes::shade::{ALBEDO_FORMAT, GbufferTargets, NORMAL_FORMAT, PARAMS_FORMAT, Shade};
use crate::render::{Frame, Light, Placement};
use crate::shared::{FrameUniforms, InstanceGpu, VertexGpu};

pub(crate) const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// A mesh as the classic paths draw it: vertices split so that each belongs to one material (a
/// vertex shared by triangles of two materials is duplicated), with each vertex's local material.
pub struct ClassicMesh<'a> {
    /// The mesh (borrowed when it has at most one material: nothing to split).
    pub mesh: Cow<'a, Mesh>,
    /// Local material per vertex (empty: all 0).
    pub vertex_materials: Vec<u32>,
}

impl<'a> ClassicMesh<'a> {
    /// Splits `mesh`'s vertices by material (triangles' material ids past the table clamp to its
    /// last entry, as the builder does). Deterministic; triangle order and winding kept.
    pub fn new(mesh: &'a Mesh) -> Self {
        if mesh.materials.len() <= 1 || mesh.material_ids.is_empty() {
            return Self {
                mesh: Cow::Borrowed(mesh),
                vertex_materials: Vec::new(),
            };
        }
        let last = mesh.materials.len() as u32 - 1;
        let n = mesh.positions.len();
        let mut out = Mesh {
            name: mesh.name.clone(),
            positions: Vec::with_capacity(n),
            normals: Vec::with_capacity(n),
            uvs: Vec::with_capacity(n),
            indices: Vec::with_capacity(mesh.indices.len()),
            material_ids: mesh.material_ids.clone(),
            materials: mesh.materials.clone(),
            has_normals: mesh.has_normals,
            has_uvs: mesh.has_uvs,
        };
        let mut vertex_materials = Vec::with_capacity(n);
        // First copy of each source vertex (with its material), further copies by (vertex, material).
        let mut first: Vec<Option<(u32, u32)>> = vec![None; n];
        let mut extra: HashMap<(u32, u32), u32> = HashMap::new();
        for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
            let m = mesh.material_ids.get(t).copied().unwrap_or(0).min(last);
            for &v in tri {
                let slot = match first[v as usize] {
                    Some((fm, idx)) if fm == m => idx,
                    Some(_) => *extra.entry((v, m)).or_insert_with(|| {
                        push_vertex(mesh, v, &mut out, &mut vertex_materials, m)
                    }),
                    None => {
                        let idx = push_vertex(mesh, v, &mut out, &mut vertex_materials, m);
                        first[v as usize] = Some((m, idx));
                        idx
                    }
                };
                out.indices.push(slot);
            }
        }
        Self {
            mesh: Cow::Owned(out),
            vertex_materials,
        }
    }
}

fn push_vertex(src: &Mesh, v: u32, out: &mut Mesh, materials: &mut Vec<u32>, m: u32) -> u32 {
    let v = v as usize;
    out.positions.push(src.positions[v]);
    out.normals.push(src.normals[v]);
    out.uvs.push(src.uvs[v]);
    materials.push(m);
    out.positions.len() as u32 - 1
}

/// A mesh's vertex and index buffers on the GPU.
pub struct GpuMesh {
    pub(crate) vertices: Buffer,
    pub(crate) indices: Buffer,
    index_count: u32,
    /// `MESH_HAS_UVS | MESH_HAS_NORMALS` (the GBuffer shader's push constant).
    pub(crate) flags: u32,
}

impl GpuMesh {
    /// Uploads `m`'s vertices (global material = `material_offset` + local) with `indices` (which
    /// index `m`'s vertices) as the index buffer: the discrete-LOD path puts all LODs of a mesh in
    /// one index buffer this way. `flags` are the mesh's material flags.
    pub fn upload(
        ctx: &Context,
        m: &ClassicMesh<'_>,
        indices: &[u32],
        material_offset: u32,
        flags: u32,
    ) -> GpuResult<Self> {
        let mesh = &m.mesh;
        let verts: Vec<VertexGpu> = (0..mesh.positions.len())
            .map(|i| VertexGpu {
                position: mesh.positions[i],
                normal: mesh.normals[i],
                uv: mesh.uvs[i],
                material: material_offset + m.vertex_materials.get(i).copied().unwrap_or(0),
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
            flags,
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

/// The classic pipeline (vertex position, normal, UV, material; writes the GBuffer through the
/// shared material model; reverse-Z depth) shared by the `brute` and `lod` passes so their images
/// compare; `pass` names the pipeline, `materials`' textures are set 1. With `instance_list`, the
/// vertex shader's `list` variant: binding 3 is the instance list `gl_InstanceIndex` indexes (the
/// GPU-driven `lod`, whose draws come from `lod_cull`). `cull`: the faces it culls (`BACK`: the
/// `lod` draws of closed solids seen from outside; front faces wind counter-clockwise in the
/// framebuffer, the projection flips y).
fn classic_pipeline(
    ctx: &Context,
    pass: &str,
    materials: &GpuMaterials,
    instance_list: bool,
    cull: vk::CullModeFlags,
) -> GpuResult<GraphicsPipeline> {
    use vk::DescriptorType as D;
    let (vertex, bindings): (&[u8], &[D]) = if instance_list {
        (
            crate::shaders::BRUTE_VERT_LIST,
            &[
                D::UNIFORM_BUFFER,
                D::STORAGE_BUFFER,
                D::STORAGE_BUFFER,
                D::STORAGE_BUFFER,
            ],
        )
    } else {
        (
            crate::shaders::BRUTE_VERT,
            &[D::UNIFORM_BUFFER, D::STORAGE_BUFFER, D::STORAGE_BUFFER],
        )
    };
    let attrs = [
        (0, vk::Format::R32G32B32_SFLOAT, 0),
        (1, vk::Format::R32G32B32_SFLOAT, 12),
        (2, vk::Format::R32G32_SFLOAT, 24),
        (3, vk::Format::R32_UINT, 32),
    ];
    GraphicsPipeline::with_textures(
        ctx,
        &GraphicsPipelineDesc {
            name: pass,
            geometry: GeometryStage::Vertex(ShaderStage {
                name: "brute.vert",
                spirv: vertex,
            }),
            fragment: ShaderStage {
                name: "brute.frag",
                spirv: crate::shaders::BRUTE_FRAG,
            },
            bindings,
            push_constant_size: 4,
            vertex_layout: Some((size_of::<VertexGpu>() as u32, &attrs)),
            color_formats: &[ALBEDO_FORMAT, NORMAL_FORMAT, PARAMS_FORMAT],
            depth_format: Some(DEPTH_FORMAT),
            depth_compare: vk::CompareOp::GREATER,
            depth_write: true,
            cull,
        },
        &materials.textures,
    )
}

/// The classic pipeline's uniforms for `view_proj` (camera-relative), `light` and a
/// `width` x `height` target.
pub(crate) fn frame_uniforms(
    view_proj: &glam::Mat4,
    light: &Light,
    (width, height): (u32, u32),
) -> FrameUniforms {
    FrameUniforms {
        view_proj: view_proj.to_cols_array_2d(),
        light_dir: light.direction.normalize_or_zero().extend(0.0).into(),
        viewport: [
            width as f32,
            height as f32,
            1.0 / width as f32,
            1.0 / height as f32,
        ],
    }
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

/// What `brute` and `lod` share: the scene's materials and meshes on the GPU, the GBuffer pipeline
/// and `shade`.
pub(crate) struct Classic {
    pub(crate) ctx: Context,
    pass: &'static str,
    /// The classic pipeline, or its `list` variant when made with `instance_list` (then only
    /// the GPU-driven `lod` records with it; [`Classic::render_frames`] refuses).
    pub(crate) pipeline: GraphicsPipeline,
    /// With `instance_list`: the same pipeline culling faces turned away, for the instances of
    /// closed solids that `lod_cull` finds seen from outside (docs/architecture.md, "Faces turned
    /// away").
    pub(crate) pipeline_cull_back: Option<GraphicsPipeline>,
    instance_list: bool,
    pub(crate) shade: Shade,
    pub(crate) materials: GpuMaterials,
    pub(crate) meshes: Vec<GpuMesh>,
}

impl Classic {
    /// Uploads `meshes` (split per material) with `indices[i]` as mesh i's index buffer (`None`:
    /// its own triangles) and the scene's materials; `pass` names everything. `instance_list`:
    /// the pipeline reads instances through a list (see [`Classic::pipeline`]).
    pub(crate) fn new(
        ctx: &Context,
        pass: &'static str,
        meshes: &[ClassicMesh<'_>],
        indices: &[Option<&[u32]>],
        instance_list: bool,
    ) -> GpuResult<Self> {
        let table = SceneMaterials::from_meshes(meshes.iter().map(|m| m.mesh.as_ref()))
            .map_err(crate::gpu::GpuError::Other)?;
        let materials = GpuMaterials::new(ctx, &table)?;
        let gpu = meshes
            .iter()
            .zip(&table.meshes)
            .zip(indices)
            .map(|((m, mm), ix)| {
                let ix = ix.unwrap_or(&m.mesh.indices);
                GpuMesh::upload(ctx, m, ix, mm.material_offset, mm.flags)
            })
            .collect::<GpuResult<Vec<_>>>()?;
        Ok(Self {
            ctx: ctx.clone(),
            pass,
            pipeline: classic_pipeline(
                ctx,
                pass,
                &materials,
                instance_list,
                vk::CullModeFlags::NONE,
            )?,
            pipeline_cull_back: if instance_list {
                Some(classic_pipeline(
                    ctx,
                    &format!("{pass} cull back"),
                    &materials,
                    true,
                    vk::CullModeFlags::BACK,
                )?)
            } else {
                None
            },
            instance_list,
            shade: Shade::new(ctx)?,
            materials,
            meshes: gpu,
        })
    }

    /// Warnings about the materials (unreadable textures), each naming its file and material.
    pub(crate) fn warnings(&self) -> &[String] {
        &self.materials.warnings
    }

    /// GPU bytes of geometry.
    pub(crate) fn geometry_bytes(&self) -> u64 {
        self.meshes.iter().map(GpuMesh::bytes).sum()
    }

    /// Records and runs one frame: the GBuffer draws of `draws` (instances from `instances`), then
    /// `shade` as `mode`; reads colour and depth back when `readback` (else they stay empty).
    /// `Frame::triangles` counts the triangles of every draw times its instances.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn render_draws(
        &self,
        instances: &[InstanceGpu],
        draws: &[Draw],
        camera: &Camera,
        light: &Light,
        width: u32,
        height: u32,
        mode: ShadeMode,
        readback: bool,
    ) -> GpuResult<Frame> {
        let frame = ClassicFrame {
            instances: instances.to_vec(),
            draws: draws.to_vec(),
            camera: *camera,
            view_proj: None,
        };
        let mut frames = self.render_frames(
            std::slice::from_ref(&frame),
            light,
            (width, height),
            mode,
            readback,
        )?;
        frames
            .pop()
            .ok_or_else(|| crate::gpu::GpuError::Other("no frame rendered".into()))
    }

    /// Records `frames` into one submission, back to back (each frame's uniforms and material
    /// view written into the command buffer), submits and waits: per frame its GPU times and
    /// triangles; colour and depth of the last frame when `readback`.
    pub(crate) fn render_frames(
        &self,
        frames: &[ClassicFrame],
        light: &Light,
        (width, height): (u32, u32),
        mode: ShadeMode,
        readback: bool,
    ) -> GpuResult<Vec<Frame>> {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        if self.instance_list {
            return Err(crate::gpu::GpuError::Other(format!(
                "`{}` draws through lod_cull's instance list, not CPU draws",
                self.pass
            )));
        }
        let (ctx, pass) = (&self.ctx, self.pass);
        let ubo = Buffer::new(
            ctx,
            &format!("{pass} frame uniforms"),
            size_of::<FrameUniforms>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryKind::Gpu,
        )?;
        // An empty frame still binds a valid (one-record) instance buffer.
        let zero = [bytemuck::Zeroable::zeroed()];
        let inst_bufs = frames
            .iter()
            .map(|f| {
                let data: &[InstanceGpu] = if f.instances.is_empty() {
                    &zero
                } else {
                    &f.instances
                };
                Buffer::with_data(
                    ctx,
                    &format!("{pass} instances"),
                    bytemuck::cast_slice(data),
                    vk::BufferUsageFlags::STORAGE_BUFFER,
                )
            })
            .collect::<GpuResult<Vec<_>>>()?;
        let targets = GbufferTargets::new(ctx, &format!("{pass} gbuffer"), width, height)?;
        let depth = Image::new(
            ctx,
            &format!("{pass} depth"),
            width,
            height,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
        )?;
        let mut timer = Timer::new(ctx, 4 * frames.len() as u32)?;
        let mut triangles = vec![0u64; frames.len()];
        let mut starts = Vec::with_capacity(frames.len());
        ctx.submit_and_wait(&format!("{pass} frame"), |cmd| {
            timer.reset(cmd);
            for ((f, inst_buf), tris) in frames.iter().zip(&inst_bufs).zip(&mut triangles) {
                starts.push(timer.count());
                let view_proj = f
                    .view_proj
                    .unwrap_or_else(|| f.camera.view_proj(width, height));
                let uniforms = frame_uniforms(&view_proj, light, (width, height));
                let view = targets.view_for_matrix(&view_proj, light.direction, mode);
                // The previous frame is done with this frame's inputs before they are rewritten.
                cmd.barrier(
                    (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
                    (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                );
                cmd.update_buffer(&ubo, 0, bytemuck::bytes_of(&uniforms));
                cmd.update_buffer(&targets.view, 0, bytemuck::bytes_of(&view));
                cmd.barrier(
                    (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                    (S::ALL_COMMANDS, A::MEMORY_READ),
                );
                timer.begin(cmd, pass);
                cmd.begin_rendering(
                    &targets.attachments(),
                    Some(RenderTarget {
                        image: &depth,
                        clear: Some([0.0; 4]),
                    }),
                );
                cmd.bind_graphics(&self.pipeline);
                cmd.push_graphics_descriptors(
                    &self.pipeline,
                    &[
                        Desc::Uniform(&ubo),
                        Desc::Storage(inst_buf),
                        Desc::Storage(&self.materials.table),
                    ],
                );
                cmd.bind_graphics_textures(&self.pipeline, &self.materials.textures);
                let mut bound: Option<u32> = None;
                for d in &f.draws {
                    if d.instance_count == 0 || d.index_count == 0 {
                        continue;
                    }
                    let Some(mesh) = self.meshes.get(d.mesh as usize) else {
                        continue;
                    };
                    if bound != Some(d.mesh) {
                        cmd.bind_mesh_buffers(&mesh.vertices, &mesh.indices);
                        cmd.graphics_push_constants(
                            &self.pipeline,
                            bytemuck::bytes_of(&mesh.flags),
                        );
                        bound = Some(d.mesh);
                    }
                    cmd.draw_indexed(
                        d.index_count,
                        d.instance_count,
                        d.first_index,
                        d.first_instance,
                    );
                    *tris += (d.index_count / 3) as u64 * d.instance_count as u64;
                }
                cmd.end_rendering();
                timer.end(cmd);
                self.shade.record(cmd, &mut timer, &targets);
            }
        })?;
        let all = timer.results()?;
        let (color, depth) = if readback {
            let d = depth.download()?;
            (
                targets.output.download()?,
                bytemuck::cast_slice(&d).to_vec(),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        let mut ends: Vec<usize> = starts.iter().skip(1).copied().collect();
        ends.push(all.len());
        let n = frames.len();
        let mut out: Vec<Frame> = starts
            .iter()
            .zip(ends)
            .zip(triangles)
            .map(|((&a, b), triangles)| Frame {
                width,
                height,
                color: Vec::new(),
                depth: Vec::new(),
                gpu_ms: all[a.min(all.len())..b.min(all.len())].to_vec(),
                triangles,
            })
            .collect();
        if let Some(last) = out.get_mut(n.saturating_sub(1)) {
            last.color = color;
            last.depth = depth;
        }
        Ok(out)
    }
}

impl Classic {
    /// The GPU times per pass of `frames` rendered lit, back to back in one submission, without
    /// read-back.
    pub(crate) fn path_times(
        &self,
        frames: &[ClassicFrame],
        light: &Light,
        size: (u32, u32),
    ) -> GpuResult<Vec<Vec<(String, f64)>>> {
        let out = self.render_frames(frames, light, size, ShadeMode::Lit, false)?;
        Ok(out.into_iter().map(|f| f.gpu_ms).collect())
    }
}

/// One frame of a classic path: its instance records, draws and camera.
pub(crate) struct ClassicFrame {
    pub(crate) instances: Vec<InstanceGpu>,
    pub(crate) draws: Vec<Draw>,
    pub(crate) camera: Camera,
    /// The projection, when not the camera's for the target (a tile of a larger image).
    pub(crate) view_proj: Option<glam::Mat4>,
}

/// The brute-force renderer: every mesh at full detail, one instanced draw per mesh.
pub struct Brute {
    classic: Classic,
}

impl Brute {
    /// Uploads `meshes` (vertices split per material) and their materials (decoding textures) and
    /// creates the pipelines.
    /// `meshes` may hold the meshes or references to them (anything that borrows as one).
    pub fn new<M: std::borrow::Borrow<Mesh>>(ctx: &Context, meshes: &[M]) -> GpuResult<Self> {
        let split: Vec<ClassicMesh> = meshes
            .iter()
            .map(|m| ClassicMesh::new(m.borrow()))
            .collect();
        let indices = vec![None; split.len()];
        Ok(Self {
            classic: Classic::new(ctx, "brute", &split, &indices, false)?,
        })
    }

    /// GPU bytes of geometry.
    pub fn geometry_bytes(&self) -> u64 {
        self.classic.geometry_bytes()
    }

    /// Warnings about the materials (unreadable textures), each naming its file and material.
    pub fn warnings(&self) -> &[String] {
        self.classic.warnings()
    }

    /// Renders `placements` seen from `camera` into a `width` x `height` lit frame and reads it back.
    pub fn render(
        &self,
        placements: &[Placement],
        camera: &Camera,
        light: &Light,
        width: u32,
        height: u32,
    ) -> GpuResult<Frame> {
        self.render_view(placements, camera, light, width, height, ShadeMode::Lit)
    }

    /// [`Brute::render`] with `shade` drawing `mode` (lit, albedo, normals or materials).
    pub fn render_view(
        &self,
        placements: &[Placement],
        camera: &Camera,
        light: &Light,
        width: u32,
        height: u32,
        mode: ShadeMode,
    ) -> GpuResult<Frame> {
        self.frame(placements, camera, (width, height), light, mode, true)
    }

    fn frame(
        &self,
        placements: &[Placement],
        camera: &Camera,
        (width, height): (u32, u32),
        light: &Light,
        mode: ShadeMode,
        readback: bool,
    ) -> GpuResult<Frame> {
        let f = self.frame_input(placements, camera)?;
        self.classic.render_draws(
            &f.instances,
            &f.draws,
            camera,
            light,
            width,
            height,
            mode,
            readback,
        )
    }

    /// The frames of `cameras` (a camera path) in one submission, back to back, without
    /// read-back: the GPU times per pass of each frame (the benchmark times paths this way).
    pub fn render_path_timed(
        &self,
        placements: &[Placement],
        cameras: &[Camera],
        light: &Light,
        width: u32,
        height: u32,
    ) -> GpuResult<Vec<Vec<(String, f64)>>> {
        let frames = cameras
            .iter()
            .map(|c| self.frame_input(placements, c))
            .collect::<GpuResult<Vec<_>>>()?;
        self.classic.path_times(&frames, light, (width, height))
    }

    /// One instanced draw per mesh of every placement seen from `camera`.
    fn frame_input(&self, placements: &[Placement], camera: &Camera) -> GpuResult<ClassicFrame> {
        let meshes = &self.classic.meshes;
        check_placements(placements, meshes.len())?;
        let (instances, ranges) = instances_by_mesh(camera, placements, meshes.len());
        let draws: Vec<Draw> = meshes
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
        Ok(ClassicFrame {
            instances,
            draws,
            camera: *camera,
            view_proj: None,
        })
    }

    /// The supersampled reference of a `width` x `height` view (DESIGN.md, "Measures"): the lit
    /// image at `samples_per_axis` times the resolution (`n x n` samples per pixel on a regular
    /// grid), box-filtered, with each pixel's sample coverage and depth range
    /// ([`crate::imgerr::Reference`]). Rendered in tiles of at most [`REFERENCE_TILE_SIDE`]
    /// samples a side, or the device's largest image if smaller (off-centre projections of the
    /// same camera, [`Camera::view_proj_window`]): a 4x4 reference of 1920x1080 is one tile of
    /// 7680x4320 samples where the device allows 8192 (every desktop GPU, lavapipe), four on a
    /// device of 4096 (Vulkan's minimum). Each tile draws every instance: fewer tiles, less work.
    pub fn render_reference(
        &self,
        placements: &[Placement],
        camera: &Camera,
        light: &Light,
        (width, height): (u32, u32),
        samples_per_axis: u32,
    ) -> GpuResult<crate::imgerr::Reference> {
        self.render_reference_tiled(
            placements,
            camera,
            light,
            (width, height),
            samples_per_axis,
            REFERENCE_TILE_SIDE.min(self.classic.ctx.caps().max_image_dimension_2d),
        )
    }

    /// [`Brute::render_reference`] with tiles of at most `tile_side` samples a side (at least one
    /// pixel's worth).
    pub fn render_reference_tiled(
        &self,
        placements: &[Placement],
        camera: &Camera,
        light: &Light,
        (width, height): (u32, u32),
        samples_per_axis: u32,
        tile_side: u32,
    ) -> GpuResult<crate::imgerr::Reference> {
        let n = samples_per_axis;
        if !(1..=255).contains(&n) || width == 0 || height == 0 {
            return Err(crate::gpu::GpuError::Other(format!(
                "a reference needs 1 to 255 samples per axis and a non-empty image (got {n}, {width}x{height})"
            )));
        }
        let mut reference = crate::imgerr::Reference::new(width, height, n);
        let mut frame = self.frame_input(placements, camera)?;
        // Output pixels per tile side.
        let side = (tile_side / n).max(1);
        let full = (width * n, height * n);
        for y0 in (0..height).step_by(side as usize) {
            for x0 in (0..width).step_by(side as usize) {
                let (tw, th) = (side.min(width - x0), side.min(height - y0));
                let size = (tw * n, th * n);
                frame.view_proj = Some(camera.view_proj_window(full, (x0 * n, y0 * n), size));
                let tile = self
                    .classic
                    .render_frames(
                        std::slice::from_ref(&frame),
                        light,
                        size,
                        ShadeMode::Lit,
                        true,
                    )?
                    .pop()
                    .ok_or_else(|| crate::gpu::GpuError::Other("no tile rendered".into()))?;
                reference
                    .add_tile(x0, y0, &tile)
                    .map_err(|e| crate::gpu::GpuError::Other(e.to_string()))?;
            }
        }
        Ok(reference)
    }
}

/// Largest side, in samples, of one tile of [`Brute::render_reference`] (8192: a 4x4 reference of
/// 1920x1080 in one tile of 7680x4320 samples, about 1 GB of targets on the GPU and 0.27 GB read
/// back), unless the device's `maxImageDimension2D` is smaller.
pub const REFERENCE_TILE_SIDE: u32 = 8192;
