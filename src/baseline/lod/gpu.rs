//! The GPU selection of the `lod` baseline (mode `lod`): per frame `lod_cull`, the indirect draw
//! `lod`, and with occlusion culling `depth_pyramid`, `lod_cull (post)` and `lod (post)`, then
//! `shade` (see the parent module and docs/architecture.md, "The lod path").

use std::sync::Mutex;

use glam::{DVec3, Mat4, Vec3, Vec4};

use super::{LOD_COUNT, Lod, LodInfo, LodStats, frustum_planes};
use crate::baseline::brute::{DEPTH_FORMAT, check_placements, frame_uniforms, instance_gpu};
use crate::baseline::lod_cull::{LodCull, LodCullBuffers};
use crate::camera::Camera;
use crate::gpu::{
    Buffer, Cmd, Context, Desc, GpuError, GpuResult, Image, MemoryKind, RenderTarget, Timer, vk,
};
use crate::material::ShadeMode;
use crate::passes::depth_pyramid::DepthPyramid;
use crate::passes::shade::GbufferTargets;
use crate::render::{Frame, Light, Placement};
use crate::shared::{
    FrameUniforms, InstanceGpu, LOD_FLAG_FRUSTUM, LOD_FLAG_HISTORY, LOD_FLAG_OCCLUSION,
    LOD_LEVEL_CULLED, LOD_LEVEL_OCCLUDED, LodDrawGpu, LodMeshGpu, LodStatsGpu, LodViewGpu,
};

/// The HZB the GPU selection tests against and the view it was built from.
struct Occlusion {
    pyramid: DepthPyramid,
    /// The frame's depth as f32 (the pyramid's source).
    depth: Buffer,
    size: (u32, u32),
    /// View-projection and camera position of the frame the HZB holds (`None`: none yet).
    built: Option<(Mat4, DVec3)>,
}

/// The GPU selection's state: the `lod_cull` pipeline, the meshes' levels and the HZB history.
pub(super) struct GpuLod {
    cull: LodCull,
    /// `LodMeshGpu` per mesh.
    meshes: Buffer,
    occlusion: Mutex<Option<Occlusion>>,
}

impl GpuLod {
    /// The `lod_cull` pipeline and the meshes' levels on the GPU (no HZB yet).
    pub(super) fn new(ctx: &Context, infos: &[LodInfo]) -> GpuResult<Self> {
        let mut records: Vec<LodMeshGpu> = infos
            .iter()
            .map(|i| LodMeshGpu {
                sphere: i.sphere,
                errors: i.errors,
                coverages: i.coverages,
                ranges: i.ranges.map(|(first, count)| [first, count]),
                bounds_min: i.bounds[0],
                closed_solid: i.closed_solid as u32,
                bounds_max: i.bounds[1],
                _pad: 0,
            })
            .collect();
        if records.is_empty() {
            records.push(bytemuck::Zeroable::zeroed());
        }
        Ok(Self {
            cull: LodCull::new(ctx)?,
            meshes: Buffer::with_data(
                ctx,
                "lod meshes",
                bytemuck::cast_slice(&records),
                vk::BufferUsageFlags::STORAGE_BUFFER,
            )?,
            occlusion: Mutex::new(None),
        })
    }

    /// Forgets the HZB history.
    pub(super) fn reset_history(&self) {
        if let Ok(mut o) = self.occlusion.lock() {
            *o = None;
        }
    }
}

/// Pass name (label, timer scope) of the main draw of the GPU selection; the pipeline's too.
const DRAW: &str = "lod";
/// Label and timer scope of the post phase's draw.
const DRAW_POST: &str = "lod (post)";

/// Per-frame (or per-call) buffers of the GPU selection.
struct GpuFrameBuffers {
    view: Buffer,
    uniforms: Buffer,
    instance_mesh: Buffer,
    mesh_slots: Buffer,
    bucket_counts: Buffer,
    instance_list: Buffer,
    post_list: Buffer,
    commands: Buffer,
    draw_counts: Buffer,
    stats: Buffer,
    levels: Buffer,
    /// Bound as the HZB when occlusion culling is off.
    no_hzb: Buffer,
}

impl GpuFrameBuffers {
    fn new(
        ctx: &Context,
        instance_mesh: &[u32],
        mesh_slots: &[[u32; 2]],
        frames: usize,
    ) -> GpuResult<Self> {
        use vk::BufferUsageFlags as U;
        let n = instance_mesh.len().max(1) as u64;
        // Per mesh and level a plain bucket and one with the faces turned away culled; a draw
        // count per mesh for each.
        let buckets = (2 * mesh_slots.len().max(1) * LOD_COUNT) as u64;
        let storage = |name: &str, bytes: u64, usage: U| {
            Buffer::new(ctx, name, bytes, U::STORAGE_BUFFER | usage, MemoryKind::Gpu)
        };
        let data = |name: &str, bytes: &[u8]| {
            Buffer::with_data(
                ctx,
                name,
                if bytes.is_empty() { &[0; 8] } else { bytes },
                U::STORAGE_BUFFER,
            )
        };
        Ok(Self {
            view: Buffer::new(
                ctx,
                "lod view",
                size_of::<LodViewGpu>() as u64,
                U::UNIFORM_BUFFER | U::TRANSFER_DST,
                MemoryKind::Gpu,
            )?,
            uniforms: Buffer::new(
                ctx,
                "lod frame uniforms",
                size_of::<FrameUniforms>() as u64,
                U::UNIFORM_BUFFER | U::TRANSFER_DST,
                MemoryKind::Gpu,
            )?,
            instance_mesh: data("lod instance meshes", bytemuck::cast_slice(instance_mesh))?,
            mesh_slots: data("lod mesh slots", bytemuck::cast_slice(mesh_slots))?,
            bucket_counts: storage("lod bucket counts", 4 * buckets, U::TRANSFER_DST)?,
            instance_list: storage("lod instance list", 4 * LOD_COUNT as u64 * n, U::empty())?,
            post_list: storage("lod post list", 4 * n, U::empty())?,
            commands: storage(
                "lod draw commands",
                size_of::<LodDrawGpu>() as u64 * buckets,
                U::INDIRECT_BUFFER,
            )?,
            draw_counts: storage(
                "lod draw counts",
                4 * 2 * mesh_slots.len().max(1) as u64,
                U::INDIRECT_BUFFER,
            )?,
            stats: storage(
                "lod stats",
                (size_of::<LodStatsGpu>() * frames.max(1)) as u64,
                U::TRANSFER_DST | U::TRANSFER_SRC,
            )?,
            levels: storage("lod levels", 4 * n, U::TRANSFER_SRC)?,
            no_hzb: storage("lod no hzb", 4, U::empty())?,
        })
    }
}

impl Lod {
    /// Renders `cameras` back to back in one submission with the GPU selection (`lod_cull`, then
    /// multi-draw-indirect-count per mesh; two phases with occlusion culling): per frame its GPU
    /// times and triangles; colour and depth of the last frame when `readback`, and its stats.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn gpu_frames(
        &self,
        g: &GpuLod,
        placements: &[Placement],
        cameras: &[Camera],
        light: &Light,
        (width, height): (u32, u32),
        error_px: f32,
        mode: ShadeMode,
        readback: bool,
    ) -> GpuResult<(Vec<Frame>, Option<LodStats>)> {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        check_placements(placements, self.infos.len())?;
        let ctx = &self.classic.ctx;
        let n = placements.len() as u32;
        let mesh_count = self.infos.len() as u32;
        // Per mesh, the first of its placements (in mesh order) and how many: its buckets' regions.
        let mut mesh_slots = vec![[0u32; 2]; self.infos.len()];
        for p in placements {
            mesh_slots[p.mesh as usize][1] += 1;
        }
        let mut first = 0;
        for s in &mut mesh_slots {
            s[0] = first;
            first += s[1];
        }
        let instance_mesh: Vec<u32> = placements.iter().map(|p| p.mesh).collect();
        let bufs = GpuFrameBuffers::new(ctx, &instance_mesh, &mesh_slots, cameras.len())?;
        let zero = [bytemuck::Zeroable::zeroed()];
        let inst_bufs = cameras
            .iter()
            .map(|c| {
                let records: Vec<InstanceGpu> =
                    placements.iter().map(|p| instance_gpu(c, p)).collect();
                let data: &[InstanceGpu] = if records.is_empty() { &zero } else { &records };
                Buffer::with_data(
                    ctx,
                    "lod instances",
                    bytemuck::cast_slice(data),
                    vk::BufferUsageFlags::STORAGE_BUFFER,
                )
            })
            .collect::<GpuResult<Vec<_>>>()?;
        let targets = GbufferTargets::new(ctx, "lod gbuffer", width, height)?;
        let depth = Image::new(
            ctx,
            "lod depth",
            width,
            height,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
        )?;
        let mut occ_guard = g
            .occlusion
            .lock()
            .map_err(|_| GpuError::Other("lod: the HZB history lock is poisoned".into()))?;
        if !self.opts.occlusion_cull {
            *occ_guard = None;
        } else if occ_guard.as_ref().is_none_or(|o| o.size != (width, height)) {
            *occ_guard = Some(Occlusion {
                pyramid: DepthPyramid::for_depth(ctx, width, height)?,
                depth: Buffer::new(
                    ctx,
                    "lod depth copy",
                    4 * width as u64 * height as u64,
                    vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryKind::Gpu,
                )?,
                size: (width, height),
                built: None,
            });
        }
        let (ps_tau, planes): (Vec<(f32, f32)>, Vec<[Vec4; 5]>) = cameras
            .iter()
            .map(|c| {
                (
                    self.threshold(c, height, error_px),
                    frustum_planes(&c.view_proj(width, height)),
                )
            })
            .unzip();
        let mut timer = Timer::new(ctx, 8 * cameras.len() as u32)?;
        let mut starts = Vec::with_capacity(cameras.len());
        let occ = occ_guard.as_ref();
        // The view of the HZB the next frame tests against (written back after the submission).
        let mut built = occ.and_then(|o| o.built);
        let result = ctx.submit_and_wait("lod frame", |cmd| {
            timer.reset(cmd);
            cmd.barrier(
                (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
                (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            );
            cmd.fill_buffer(&bufs.stats, 0);
            for (f, ((cam, inst_buf), ((ps, tau), planes))) in cameras
                .iter()
                .zip(&inst_bufs)
                .zip(ps_tau.iter().zip(&planes))
                .enumerate()
            {
                starts.push(timer.count());
                let view_proj = cam.view_proj(width, height);
                let mut flags = 0;
                if self.opts.frustum_cull {
                    flags |= LOD_FLAG_FRUSTUM;
                }
                let (mut prev_view_proj, mut prev_delta, mut hzb_levels) =
                    (Mat4::IDENTITY, Vec3::ZERO, 0);
                if let Some(o) = occ {
                    flags |= LOD_FLAG_OCCLUSION;
                    hzb_levels = o.pyramid.levels.len() as u32;
                    if let Some((vp, pos)) = built {
                        flags |= LOD_FLAG_HISTORY;
                        prev_view_proj = vp;
                        prev_delta = (cam.position - pos).as_vec3();
                    }
                }
                let lod_view = LodViewGpu {
                    view_proj: view_proj.to_cols_array_2d(),
                    frustum: planes.map(|p| p.to_array()),
                    prev_view_proj: prev_view_proj.to_cols_array_2d(),
                    prev_delta: prev_delta.extend(0.0).to_array(),
                    viewport: [
                        width as f32,
                        height as f32,
                        1.0 / width as f32,
                        1.0 / height as f32,
                    ],
                    proj_scale: *ps,
                    tau: *tau,
                    near: cam.near,
                    instance_count: n,
                    mesh_count,
                    flags,
                    hzb_levels,
                    _pad: 0,
                };
                let uniforms = frame_uniforms(&view_proj, light, (width, height));
                let material_view = targets.view_for_matrix(&view_proj, light.direction, mode);
                // The previous frame is done with this frame's inputs before they are rewritten.
                cmd.barrier(
                    (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
                    (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                );
                cmd.update_buffer(&bufs.view, 0, bytemuck::bytes_of(&lod_view));
                cmd.update_buffer(&bufs.uniforms, 0, bytemuck::bytes_of(&uniforms));
                cmd.update_buffer(&targets.view, 0, bytemuck::bytes_of(&material_view));
                cmd.barrier(
                    (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                    (S::ALL_COMMANDS, A::MEMORY_READ),
                );
                let hzb = occ.map_or(&bufs.no_hzb, |o| &o.pyramid.hzb);
                let cull = LodCullBuffers {
                    view: &bufs.view,
                    instances: inst_buf,
                    instance_mesh: &bufs.instance_mesh,
                    meshes: &g.meshes,
                    mesh_slots: &bufs.mesh_slots,
                    bucket_counts: &bufs.bucket_counts,
                    instance_list: &bufs.instance_list,
                    post_list: &bufs.post_list,
                    commands: &bufs.commands,
                    draw_counts: &bufs.draw_counts,
                    stats: &bufs.stats,
                    levels: &bufs.levels,
                    hzb,
                };
                g.cull
                    .record(cmd, &mut timer, &cull, false, f as u32, n, mesh_count);
                let draw = |cmd: &mut Cmd, timer: &mut Timer, post: bool| {
                    self.record_indirect_draws(
                        cmd,
                        timer,
                        post,
                        (&targets, &depth),
                        &bufs,
                        inst_buf,
                        &mesh_slots,
                    )
                };
                draw(cmd, &mut timer, false);
                if let Some(o) = occ {
                    // This frame's HZB from what the main phase drew, then the deferred instances
                    // against it.
                    o.pyramid.record_depth(cmd, &mut timer, &depth, &o.depth);
                    g.cull
                        .record(cmd, &mut timer, &cull, true, f as u32, n, mesh_count);
                    draw(cmd, &mut timer, true);
                    built = Some((view_proj, cam.position));
                }
                self.classic.shade.record(cmd, &mut timer, &targets);
            }
        });
        if let Err(e) = result {
            // The history may name a frame the GPU did not finish.
            *occ_guard = None;
            return Err(e);
        }
        if let Some(o) = occ_guard.as_mut() {
            o.built = built;
        }
        drop(occ_guard);
        let all = timer.results()?;
        let stats: Vec<LodStatsGpu> = bytemuck::pod_collect_to_vec(&bufs.stats.download()?);
        let mut ends: Vec<usize> = starts.iter().skip(1).copied().collect();
        ends.push(all.len());
        let mut frames: Vec<Frame> = starts
            .iter()
            .zip(ends)
            .zip(&stats)
            .map(|((&a, b), s)| Frame {
                width,
                height,
                color: Vec::new(),
                depth: Vec::new(),
                gpu_ms: all[a.min(all.len())..b.min(all.len())].to_vec(),
                triangles: s.triangles,
            })
            .collect();
        if !readback {
            return Ok((frames, None));
        }
        let last_stats = stats.last().copied().unwrap_or_default();
        let raw: Vec<u32> = bytemuck::pod_collect_to_vec(&bufs.levels.download()?);
        let raw = &raw[..n as usize];
        let out = LodStats {
            frustum_culled: last_stats.frustum_culled,
            drawn_main: last_stats.drawn_main,
            post_tested: last_stats.post_count,
            drawn_post: last_stats.drawn_post,
            occluded: last_stats.occluded,
            cull_back: last_stats.cull_back,
            levels: raw
                .iter()
                .map(|&l| (l != LOD_LEVEL_CULLED).then_some((l & !LOD_LEVEL_OCCLUDED) as u8))
                .collect(),
            occluded_instances: raw
                .iter()
                .map(|&l| l != LOD_LEVEL_CULLED && l & LOD_LEVEL_OCCLUDED != 0)
                .collect(),
        };
        if let Some(last) = frames.last_mut() {
            let d = depth.download()?;
            last.color = targets.output.download()?;
            last.depth = bytemuck::pod_collect_to_vec(&d);
        }
        Ok((frames, Some(out)))
    }

    /// Records one draw pass of the GPU selection: per mesh with instances, one
    /// `vkCmdDrawIndexedIndirectCount` over its `LOD_COUNT` command slots, and for a closed solid
    /// a second one with the pipeline that culls faces turned away, over the slots of its
    /// instances seen from outside (`lod_cull.comp.glsl`). The main draw clears the targets, the
    /// post draw (`post`) adds to them.
    #[allow(clippy::too_many_arguments)]
    fn record_indirect_draws(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        post: bool,
        (targets, depth): (&GbufferTargets, &Image),
        bufs: &GpuFrameBuffers,
        instances: &Buffer,
        mesh_slots: &[[u32; 2]],
    ) {
        let c = &self.classic;
        timer.begin(cmd, if post { DRAW_POST } else { DRAW });
        let clear = (!post).then_some([0.0; 4]);
        let colors = targets.attachments().map(|t| RenderTarget {
            image: t.image,
            clear,
        });
        cmd.begin_rendering(
            &colors,
            Some(RenderTarget {
                image: depth,
                clear,
            }),
        );
        let stride = size_of::<LodDrawGpu>() as u64;
        let meshes = self.infos.len();
        let cull_back = c.pipeline_cull_back.as_ref();
        for (culled, pipeline) in [Some(&c.pipeline), cull_back].into_iter().enumerate() {
            let Some(pipeline) = pipeline else { continue };
            cmd.bind_graphics(pipeline);
            cmd.push_graphics_descriptors(
                pipeline,
                &[
                    Desc::Uniform(&bufs.uniforms),
                    Desc::Storage(instances),
                    Desc::Storage(&c.materials.table),
                    Desc::Storage(&bufs.instance_list),
                ],
            );
            cmd.bind_graphics_textures(pipeline, &c.materials.textures);
            for (m, (mesh, slots)) in c.meshes.iter().zip(mesh_slots).enumerate() {
                let closed = self.infos.get(m).is_some_and(|i| i.closed_solid);
                if slots[1] == 0 || mesh.index_count() == 0 || (culled == 1 && !closed) {
                    continue;
                }
                // The plain lists first, then every mesh's culled ones (`lod_cull`'s layout).
                let list = culled * meshes + m;
                cmd.bind_mesh_buffers(&mesh.vertices, &mesh.indices);
                cmd.graphics_push_constants(pipeline, bytemuck::bytes_of(&mesh.flags));
                cmd.draw_indexed_indirect_count(
                    &bufs.commands,
                    (list * LOD_COUNT) as u64 * stride,
                    &bufs.draw_counts,
                    4 * list as u64,
                    LOD_COUNT as u32,
                    stride as u32,
                );
            }
        }
        cmd.end_rendering();
        timer.end(cmd);
    }
}
