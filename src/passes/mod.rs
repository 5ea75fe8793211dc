//! The passes of the vgeo frame, one file each (file, shader, debug label, timer scope and pipeline
//! share the pass's name), and the per-frame buffers they share ([`FrameBuffers`]).
//!
//! Data flow of one frame (see `crate::frame`):
//! `instance_cull` -> `cluster_cull` -> (`raster_sw`, `raster_hw`) -> `debug_view`, or for the
//! material views `material_classify` -> `material_depth` -> `emit_gbuffer` -> `shade`.
//! - the work queue: u64 items `instance << 32 | bvh node` (global node index), empty = all ones;
//! - the visible-cluster list: `uvec2(instance, global cluster index)`;
//! - the SW and HW lists: u32 indices into the visible list;
//! - [`CullCounters`]: counts, overflow flags and the indirect arguments of the rasterizers;
//! - the visibility buffer: 64 bits per pixel, `depth bits << 32 | visible index << 7 | triangle`.

pub mod cluster_cull;
pub mod debug_view;
pub mod depth_export;
pub mod depth_import;
pub mod depth_pyramid;
pub mod emit_gbuffer;
pub mod instance_cull;
pub mod material_classify;
pub mod material_depth;
pub mod materials;
pub mod occluder_select;
pub mod raster_hw;
pub mod raster_sw;
pub mod shade;
pub mod view;
pub mod visbuffer;

/// The descriptors of `instance_cull` and `cluster_cull` (one layout for both, see
/// `shaders_glsl/common/cull_bindings.glsl`).
pub mod cull;

use crate::gpu::{Buffer, Cmd, Context, Desc, DescList, GpuResult, Image, MemoryKind, vk};
use crate::scene_gpu::GpuScene;
use crate::shared::{CullCounters, OcclusionGpu, ViewGpu};

/// `before`, then the scene's cluster-geometry descriptors ([`GpuScene::geometry_descs`]), then
/// `after`: the binding order of every pass that decodes clusters.
pub fn with_geometry<'a>(
    before: &[Desc<'a>],
    scene: &'a GpuScene,
    after: &[Desc<'a>],
) -> DescList<'a> {
    let mut list = DescList::default();
    list.extend(before.iter().copied());
    list.extend(scene.geometry_descs());
    list.extend(after.iter().copied());
    list
}

/// Where the 64-bit visibility buffer lives.
pub enum VisBuffer {
    /// `uint64_t` storage buffer with `atomicMax` (VK_KHR_shader_atomic_int64; lavapipe).
    Buffer(Buffer),
    /// `R64_UINT` storage image with `imageAtomicMax` (VK_EXT_shader_image_atomic_int64).
    Image(Image),
}

/// Which visibility-buffer path to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VisPath {
    Buffer,
    Image,
}

impl VisPath {
    /// The descriptor type a pass binds the visibility buffer with on this path.
    pub fn descriptor_type(self) -> vk::DescriptorType {
        match self {
            VisPath::Buffer => vk::DescriptorType::STORAGE_BUFFER,
            VisPath::Image => vk::DescriptorType::STORAGE_IMAGE,
        }
    }

    /// The path for this device: the image path where 64-bit image atomics exist, else the buffer
    /// path; `VGEO_VISBUFFER=buffer|image` forces one (image without support is an error).
    pub fn choose(ctx: &Context) -> Result<Self, String> {
        let has_image = ctx.caps().image_int64_atomics;
        match std::env::var("VGEO_VISBUFFER").ok().as_deref() {
            None | Some("") => Ok(if has_image {
                VisPath::Image
            } else {
                VisPath::Buffer
            }),
            Some("buffer") => Ok(VisPath::Buffer),
            Some("image") if has_image => Ok(VisPath::Image),
            Some("image") => Err(
                "VGEO_VISBUFFER=image but the device lacks VK_EXT_shader_image_atomic_int64".into(),
            ),
            Some(other) => Err(format!(
                "VGEO_VISBUFFER={other:?}: expected `buffer` or `image`"
            )),
        }
    }
}

/// The per-frame buffers shared by the passes. Sized once for a resolution and capacities.
pub struct FrameBuffers {
    pub width: u32,
    pub height: u32,
    /// [`ViewGpu`] (host-visible, written each frame).
    pub view: Buffer,
    /// [`CullCounters`] (device-local; cleared each frame).
    pub counters: Buffer,
    /// Work queue of `cluster_cull` (`queue_capacity` u64 items).
    pub queue: Buffer,
    /// Visible clusters, `uvec2(instance, cluster)`, `visible_capacity` entries.
    pub visible: Buffer,
    /// Indices into `visible` of the clusters each rasterizer draws.
    pub sw_list: Buffer,
    pub hw_list: Buffer,
    pub visbuffer: VisBuffer,
    /// Post phase (two-pass occlusion culling): its counters and rasterizer lists.
    pub counters_post: Buffer,
    pub sw_list_post: Buffer,
    pub hw_list_post: Buffer,
    /// What the main phase deferred: instance indices, queue items, `uvec2(instance, cluster)`.
    pub post_instances: Buffer,
    pub post_nodes: Buffer,
    pub post_clusters: Buffer,
    /// [`crate::shared::OcclusionGpu`] of each phase (host-visible, written each frame).
    pub occ_main: Buffer,
    pub occ_post: Buffer,
    pub queue_capacity: u32,
    pub visible_capacity: u32,
}

impl FrameBuffers {
    /// Creates the buffers for a `width` x `height` frame.
    pub fn new(
        ctx: &Context,
        width: u32,
        height: u32,
        path: VisPath,
        queue_capacity: u32,
        visible_capacity: u32,
        instance_count: u32,
    ) -> GpuResult<Self> {
        Self::named(
            ctx,
            "",
            width,
            height,
            path,
            queue_capacity,
            visible_capacity,
            instance_count,
        )
    }

    /// [`FrameBuffers::new`] for the view `view`: its buffers' debug names start with `view: `
    /// (none for vgeo's own view, `""`), so a capture of several views tells them apart.
    #[allow(clippy::too_many_arguments)]
    pub fn named(
        ctx: &Context,
        view: &str,
        width: u32,
        height: u32,
        path: VisPath,
        queue_capacity: u32,
        visible_capacity: u32,
        instance_count: u32,
    ) -> GpuResult<Self> {
        let n = |base: &str| {
            if view.is_empty() {
                base.to_string()
            } else {
                format!("{view}: {base}")
            }
        };
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let dst = vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC;
        let gpu = |name: &str, size: u64, extra: vk::BufferUsageFlags| {
            Buffer::new(ctx, name, size, storage | dst | extra, MemoryKind::Gpu)
        };
        let visbuffer = match path {
            VisPath::Buffer => VisBuffer::Buffer(gpu(
                &n("visbuffer"),
                8 * width as u64 * height as u64,
                vk::BufferUsageFlags::empty(),
            )?),
            VisPath::Image => VisBuffer::Image(Image::new(
                ctx,
                &n("visbuffer"),
                width,
                height,
                vk::Format::R64_UINT,
                vk::ImageUsageFlags::STORAGE
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::TRANSFER_DST,
            )?),
        };
        let fb = Self {
            width,
            height,
            view: Buffer::new(
                ctx,
                &n("view"),
                size_of::<ViewGpu>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER | storage | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryKind::Upload,
            )?,
            counters: gpu(
                &n("cull counters"),
                size_of::<CullCounters>() as u64,
                vk::BufferUsageFlags::INDIRECT_BUFFER,
            )?,
            queue: gpu(
                &n("cull queue"),
                8 * queue_capacity as u64,
                vk::BufferUsageFlags::empty(),
            )?,
            visible: gpu(
                &n("visible clusters"),
                8 * visible_capacity as u64,
                vk::BufferUsageFlags::empty(),
            )?,
            sw_list: gpu(
                &n("sw clusters"),
                4 * visible_capacity as u64,
                vk::BufferUsageFlags::empty(),
            )?,
            hw_list: gpu(
                &n("hw clusters"),
                4 * visible_capacity as u64,
                vk::BufferUsageFlags::empty(),
            )?,
            visbuffer,
            counters_post: gpu(
                &n("cull counters (post)"),
                size_of::<CullCounters>() as u64,
                vk::BufferUsageFlags::INDIRECT_BUFFER,
            )?,
            sw_list_post: gpu(
                &n("sw clusters (post)"),
                4 * visible_capacity as u64,
                vk::BufferUsageFlags::empty(),
            )?,
            hw_list_post: gpu(
                &n("hw clusters (post)"),
                4 * visible_capacity as u64,
                vk::BufferUsageFlags::empty(),
            )?,
            post_instances: gpu(
                &n("post instances"),
                4 * instance_count.max(1) as u64,
                vk::BufferUsageFlags::empty(),
            )?,
            post_nodes: gpu(
                &n("post nodes"),
                8 * queue_capacity as u64,
                vk::BufferUsageFlags::empty(),
            )?,
            post_clusters: gpu(
                &n("post clusters"),
                8 * visible_capacity as u64,
                vk::BufferUsageFlags::empty(),
            )?,
            occ_main: Buffer::new(
                ctx,
                &n("occlusion (main)"),
                size_of::<OcclusionGpu>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryKind::Upload,
            )?,
            occ_post: Buffer::new(
                ctx,
                &n("occlusion (post)"),
                size_of::<OcclusionGpu>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryKind::Upload,
            )?,
            queue_capacity,
            visible_capacity,
        };
        // Counters start at zero: a pass reading a phase that did not run sees empty lists.
        ctx.submit_and_wait("clear frame counters", |cmd| {
            cmd.fill_buffer(&fb.counters, 0);
            cmd.fill_buffer(&fb.counters_post, 0);
        })?;
        Ok(fb)
    }

    /// The counters, SW list and HW list of one culling phase.
    pub fn phase_lists(&self, phase: cull::Phase) -> (&Buffer, &Buffer, &Buffer) {
        match phase {
            cull::Phase::Main => (&self.counters, &self.sw_list, &self.hw_list),
            cull::Phase::Post => (&self.counters_post, &self.sw_list_post, &self.hw_list_post),
        }
    }

    /// The visibility buffer as a descriptor (the image path moves the image to `GENERAL`).
    pub fn visbuffer_desc(&self, cmd: &mut Cmd) -> Desc<'_> {
        match &self.visbuffer {
            VisBuffer::Buffer(b) => Desc::Storage(b),
            VisBuffer::Image(i) => {
                cmd.to_general(i);
                Desc::StorageImage(i)
            }
        }
    }

    /// The path in use.
    pub fn vis_path(&self) -> VisPath {
        match self.visbuffer {
            VisBuffer::Buffer(_) => VisPath::Buffer,
            VisBuffer::Image(_) => VisPath::Image,
        }
    }
}
