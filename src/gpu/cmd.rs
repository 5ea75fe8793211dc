//! A command buffer being recorded, with a small safe API over the commands vgeo uses.

use std::ffi::CStr;
use std::sync::atomic::Ordering;

use ash::vk;

use super::{Buffer, ComputePipeline, Context, GraphicsPipeline, Image, TextureSet};

/// A descriptor pushed with `vkCmdPushDescriptorSetKHR` (binding i = entry i).
#[derive(Clone, Copy)]
pub enum Desc<'a> {
    Storage(&'a Buffer),
    Uniform(&'a Buffer),
    StorageImage(&'a Image),
}

/// Most descriptors of one push (bindings of a pipeline's set 0) and most mip levels of one copy:
/// recording keeps them in arrays on the stack, so it allocates nothing.
pub const MAX_DESCRIPTORS: usize = 32;

/// Descriptors in a fixed-capacity list on the stack (pushing past [`MAX_DESCRIPTORS`] panics:
/// a pipeline layout with more bindings is a programming error).
#[derive(Clone, Copy)]
pub struct DescList<'a> {
    items: [Option<Desc<'a>>; MAX_DESCRIPTORS],
    len: usize,
}

impl Default for DescList<'_> {
    fn default() -> Self {
        Self {
            items: [None; MAX_DESCRIPTORS],
            len: 0,
        }
    }
}

impl<'a> DescList<'a> {
    /// Appends `d`.
    pub fn push(&mut self, d: Desc<'a>) {
        assert!(
            self.len < MAX_DESCRIPTORS,
            "more than {MAX_DESCRIPTORS} descriptors"
        );
        self.items[self.len] = Some(d);
        self.len += 1;
    }

    /// Appends each of `ds`.
    pub fn extend(&mut self, ds: impl IntoIterator<Item = Desc<'a>>) {
        for d in ds {
            self.push(d);
        }
    }

    /// Number of descriptors.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the list is empty.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl<'b, 'a> IntoIterator for &'b DescList<'a> {
    type Item = &'b Desc<'a>;
    type IntoIter = std::iter::Flatten<std::slice::Iter<'b, Option<Desc<'a>>>>;
    fn into_iter(self) -> Self::IntoIter {
        self.items[..self.len].iter().flatten()
    }
}

/// A colour or depth attachment of a rendering pass, with its clear value.
pub struct RenderTarget<'a> {
    pub image: &'a Image,
    /// Clear colour (RGBA) or, for depth, `[depth, 0, 0, 0]`; `None` loads the contents.
    pub clear: Option<[f32; 4]>,
}

/// How many Vulkan commands a [`Cmd`] recorded, by kind: what a frame costs the driver on the
/// CPU (`vgeo bench --record-cpu` reports it beside the time).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct CmdCounts {
    /// `vkCmdPipelineBarrier2` (global barriers and image transitions).
    pub barriers: u32,
    /// Direct and indirect dispatches.
    pub dispatches: u32,
    /// Direct and indirect draws.
    pub draws: u32,
    /// Pipeline binds, descriptor pushes and binds, push constants, vertex and index buffers.
    pub bindings: u32,
    /// Copies, fills, buffer updates and clears.
    pub transfers: u32,
    /// Debug label begins and ends.
    pub labels: u32,
    /// Timestamp writes and query-pool resets.
    pub timestamps: u32,
    /// Rendering begins and ends, viewport and scissor.
    pub other: u32,
}

impl CmdCounts {
    /// The commands recorded after `earlier` (a snapshot of the same recorder).
    pub fn since(&self, earlier: &CmdCounts) -> CmdCounts {
        CmdCounts {
            barriers: self.barriers - earlier.barriers,
            dispatches: self.dispatches - earlier.dispatches,
            draws: self.draws - earlier.draws,
            bindings: self.bindings - earlier.bindings,
            transfers: self.transfers - earlier.transfers,
            labels: self.labels - earlier.labels,
            timestamps: self.timestamps - earlier.timestamps,
            other: self.other - earlier.other,
        }
    }

    /// All commands.
    pub fn total(&self) -> u32 {
        self.barriers
            + self.dispatches
            + self.draws
            + self.bindings
            + self.transfers
            + self.labels
            + self.timestamps
            + self.other
    }
}

/// Records commands into one command buffer. Created by [`Context::submit_and_wait`].
pub struct Cmd {
    ctx: Context,
    cb: vk::CommandBuffer,
    open_labels: u32,
    counts: CmdCounts,
}

fn layout_access(layout: vk::ImageLayout) -> (vk::PipelineStageFlags2, vk::AccessFlags2) {
    use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
    match layout {
        L::UNDEFINED => (S::TOP_OF_PIPE, A::NONE),
        L::COLOR_ATTACHMENT_OPTIMAL => (
            S::COLOR_ATTACHMENT_OUTPUT,
            A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE,
        ),
        L::DEPTH_ATTACHMENT_OPTIMAL => (
            S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
            A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
        ),
        L::TRANSFER_SRC_OPTIMAL => (S::ALL_TRANSFER, A::TRANSFER_READ),
        L::TRANSFER_DST_OPTIMAL => (S::ALL_TRANSFER, A::TRANSFER_WRITE),
        L::SHADER_READ_ONLY_OPTIMAL => (
            S::FRAGMENT_SHADER | S::COMPUTE_SHADER,
            A::SHADER_SAMPLED_READ,
        ),
        _ => (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
    }
}

impl Cmd {
    pub(crate) fn new(ctx: Context, cb: vk::CommandBuffer) -> Self {
        Self {
            ctx,
            cb,
            open_labels: 0,
            counts: CmdCounts::default(),
        }
    }

    pub(crate) fn finish(&mut self) {
        while self.open_labels > 0 {
            self.end_label();
        }
    }

    /// The commands recorded so far, by kind (see [`CmdCounts`]).
    pub fn counts(&mut self) -> &mut CmdCounts {
        &mut self.counts
    }

    pub(crate) fn raw(&self) -> vk::CommandBuffer {
        self.cb
    }

    pub(crate) fn context(&self) -> &Context {
        &self.ctx
    }

    fn dev(&self) -> &ash::Device {
        self.ctx.device()
    }

    /// Opens a labelled region (one per pass); also remembered as the last pass for device-loss reports.
    pub fn begin_label(&mut self, name: &str) {
        if let Ok(mut p) = self.ctx.inner.last_pass.lock() {
            // Within the string's reserved capacity (cut like the label), so no allocation.
            p.clear();
            let mut end = name.len().min(127);
            while !name.is_char_boundary(end) {
                end -= 1;
            }
            p.push_str(&name[..end]);
        }
        if let Some(d) = &self.ctx.inner.debug_device {
            // The name, NUL-terminated, on the stack (cut at 127 bytes or an inner NUL).
            let mut buf = [0u8; 128];
            let n = name
                .bytes()
                .take(buf.len() - 1)
                .take_while(|b| *b != 0)
                .count();
            buf[..n].copy_from_slice(&name.as_bytes()[..n]);
            let Ok(c) = CStr::from_bytes_until_nul(&buf) else {
                return;
            };
            let label = vk::DebugUtilsLabelEXT::default()
                .label_name(c)
                .color([0.3, 0.6, 0.9, 1.0]);
            self.counts.labels += 1;
            // SAFETY: the command buffer is recording.
            unsafe { d.cmd_begin_debug_utils_label(self.cb, &label) };
            self.open_labels += 1;
        }
    }

    /// Closes the innermost labelled region.
    pub fn end_label(&mut self) {
        if let Some(d) = &self.ctx.inner.debug_device
            && self.open_labels > 0
        {
            self.counts.labels += 1;
            // SAFETY: a label is open on this recording command buffer.
            unsafe { d.cmd_end_debug_utils_label(self.cb) };
            self.open_labels -= 1;
        }
    }

    /// Copies `size` bytes from the start of `src` to the start of `dst`.
    pub fn copy_buffer(&mut self, src: &Buffer, dst: &Buffer, size: u64) {
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size,
        };
        self.counts.transfers += 1;
        // SAFETY: both buffers are valid; sizes are checked by the caller's buffer creation.
        unsafe {
            self.dev()
                .cmd_copy_buffer(self.cb, src.raw, dst.raw, &[region])
        };
    }

    /// Copies `size` bytes from `src` at `src_offset` to `dst` at `dst_offset`.
    pub fn copy_buffer_region(
        &mut self,
        src: &Buffer,
        src_offset: u64,
        dst: &Buffer,
        dst_offset: u64,
        size: u64,
    ) {
        let region = vk::BufferCopy {
            src_offset,
            dst_offset,
            size,
        };
        self.counts.transfers += 1;
        // SAFETY: both buffers are valid; the ranges lie inside them (callers).
        unsafe {
            self.dev()
                .cmd_copy_buffer(self.cb, src.raw, dst.raw, &[region])
        };
    }

    /// Copies `regions` of `src` into `dst` (one command; destination regions must not overlap).
    pub fn copy_buffer_regions(&mut self, src: &Buffer, dst: &Buffer, regions: &[vk::BufferCopy]) {
        if regions.is_empty() {
            return;
        }
        self.counts.transfers += 1;
        // SAFETY: both buffers are valid; the regions lie inside them and do not overlap (callers).
        unsafe {
            self.dev()
                .cmd_copy_buffer(self.cb, src.raw, dst.raw, regions)
        };
    }

    /// Fills a whole buffer with a repeated u32.
    pub fn fill_buffer(&mut self, buf: &Buffer, value: u32) {
        self.counts.transfers += 1;
        // SAFETY: valid buffer; WHOLE_SIZE rounds down to a multiple of 4.
        unsafe {
            self.dev()
                .cmd_fill_buffer(self.cb, buf.raw, 0, vk::WHOLE_SIZE, value)
        };
    }

    /// A global memory barrier between two stage/access scopes.
    pub fn barrier(
        &mut self,
        src: (vk::PipelineStageFlags2, vk::AccessFlags2),
        dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
    ) {
        let mb = [vk::MemoryBarrier2::default()
            .src_stage_mask(src.0)
            .src_access_mask(src.1)
            .dst_stage_mask(dst.0)
            .dst_access_mask(dst.1)];
        let dep = vk::DependencyInfo::default().memory_barriers(&mb);
        self.counts.barriers += 1;
        // SAFETY: the command buffer is recording.
        unsafe { self.ctx.inner.sync2.cmd_pipeline_barrier2(self.cb, &dep) };
    }

    /// Moves `image` to `layout`, with the stages/accesses the two layouts imply.
    pub fn transition(&mut self, image: &Image, layout: vk::ImageLayout) {
        let old = vk::ImageLayout::from_raw(image.layout.swap(layout.as_raw(), Ordering::Relaxed));
        let (ss, sa) = layout_access(old);
        let (ds, da) = layout_access(layout);
        let ib = [vk::ImageMemoryBarrier2::default()
            .src_stage_mask(ss)
            .src_access_mask(sa)
            .dst_stage_mask(ds)
            .dst_access_mask(da)
            .old_layout(old)
            .new_layout(layout)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(image.raw)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: image.aspect,
                base_mip_level: 0,
                level_count: image.mip_levels,
                base_array_layer: 0,
                layer_count: 1,
            })];
        let dep = vk::DependencyInfo::default().image_memory_barriers(&ib);
        self.counts.barriers += 1;
        // SAFETY: the command buffer is recording; the image is valid.
        unsafe { self.ctx.inner.sync2.cmd_pipeline_barrier2(self.cb, &dep) };
    }

    /// Begins dynamic rendering into `colors` and `depth` (images are transitioned as needed) and
    /// sets the viewport and scissor to the full target.
    pub fn begin_rendering(
        &mut self,
        colors: &[RenderTarget<'_>],
        depth: Option<RenderTarget<'_>>,
    ) {
        let (w, h) = colors
            .first()
            .or(depth.as_ref())
            .map(|t| (t.image.width, t.image.height))
            .unwrap_or((1, 1));
        for c in colors {
            self.transition(c.image, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
        }
        if let Some(d) = &depth {
            self.transition(d.image, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL);
        }
        let attach = |t: &RenderTarget<'_>, layout: vk::ImageLayout, is_depth: bool| {
            let clear = t.clear.unwrap_or_default();
            vk::RenderingAttachmentInfo::default()
                .image_view(t.image.view)
                .image_layout(layout)
                .load_op(if t.clear.is_some() {
                    vk::AttachmentLoadOp::CLEAR
                } else {
                    vk::AttachmentLoadOp::LOAD
                })
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(if is_depth {
                    vk::ClearValue {
                        depth_stencil: vk::ClearDepthStencilValue {
                            depth: clear[0],
                            stencil: 0,
                        },
                    }
                } else {
                    vk::ClearValue {
                        color: vk::ClearColorValue { float32: clear },
                    }
                })
        };
        assert!(colors.len() <= 8, "at most 8 colour attachments");
        let mut color_infos = [vk::RenderingAttachmentInfo::default(); 8];
        for (info, c) in color_infos.iter_mut().zip(colors) {
            *info = attach(c, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, false);
        }
        let color_infos = &color_infos[..colors.len()];
        let depth_info = depth
            .as_ref()
            .map(|d| attach(d, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, true));
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: vk::Extent2D {
                width: w,
                height: h,
            },
        };
        let mut info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(color_infos);
        if let Some(d) = depth_info.as_ref() {
            info = info.depth_attachment(d);
        }
        // SAFETY: the attachments are valid images in the layouts set above.
        unsafe { self.start_rendering(&info, area) };
    }

    /// Begins dynamic rendering with no attachments over `width` x `height` (for passes whose
    /// fragment shaders only write storage resources), with viewport and scissor set.
    pub fn begin_rendering_no_attachments(&mut self, width: u32, height: u32) {
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: vk::Extent2D { width, height },
        };
        let info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1);
        // SAFETY: rendering without attachments is valid with dynamic rendering.
        unsafe { self.start_rendering(&info, area) };
    }

    /// `vkCmdBeginRendering` plus a viewport and scissor covering `area`.
    ///
    /// # Safety
    /// `info` must describe valid attachments in the layouts it names, and `area` its render area.
    unsafe fn start_rendering(&mut self, info: &vk::RenderingInfo<'_>, area: vk::Rect2D) {
        let vp = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: area.extent.width as f32,
            height: area.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        self.counts.other += 3;
        // SAFETY: the caller guarantees `info`; viewport and scissor are plain dynamic state.
        unsafe {
            self.ctx
                .inner
                .dynamic_rendering
                .cmd_begin_rendering(self.cb, info);
            self.dev().cmd_set_viewport(self.cb, 0, &[vp]);
            self.dev().cmd_set_scissor(self.cb, 0, &[area]);
        }
    }

    /// Ends dynamic rendering.
    pub fn end_rendering(&mut self) {
        self.counts.other += 1;
        // SAFETY: rendering was begun on this command buffer.
        unsafe { self.ctx.inner.dynamic_rendering.cmd_end_rendering(self.cb) };
    }

    /// Binds a graphics pipeline.
    pub fn bind_graphics(&mut self, p: &GraphicsPipeline) {
        self.counts.bindings += 1;
        // SAFETY: valid pipeline.
        unsafe {
            self.dev()
                .cmd_bind_pipeline(self.cb, vk::PipelineBindPoint::GRAPHICS, p.raw)
        };
    }

    /// Binds a compute pipeline.
    pub fn bind_compute(&mut self, p: &ComputePipeline) {
        self.counts.bindings += 1;
        // SAFETY: valid pipeline.
        unsafe {
            self.dev()
                .cmd_bind_pipeline(self.cb, vk::PipelineBindPoint::COMPUTE, p.raw)
        };
    }

    fn push_descriptors<'b, 'a: 'b>(
        &mut self,
        bind: vk::PipelineBindPoint,
        layout: vk::PipelineLayout,
        descs: impl IntoIterator<Item = &'b Desc<'a>>,
    ) {
        // Fixed arrays on the stack: recording allocates nothing.
        let mut buffer_infos = [[vk::DescriptorBufferInfo::default()]; MAX_DESCRIPTORS];
        let mut image_infos = [[vk::DescriptorImageInfo::default()]; MAX_DESCRIPTORS];
        let mut kinds = [vk::DescriptorType::STORAGE_BUFFER; MAX_DESCRIPTORS];
        let mut n = 0;
        for d in descs {
            assert!(
                n < MAX_DESCRIPTORS,
                "more than {MAX_DESCRIPTORS} descriptors"
            );
            match d {
                Desc::Storage(b) | Desc::Uniform(b) => {
                    buffer_infos[n] = [vk::DescriptorBufferInfo {
                        buffer: b.raw,
                        offset: 0,
                        range: vk::WHOLE_SIZE,
                    }];
                    kinds[n] = match d {
                        Desc::Uniform(_) => vk::DescriptorType::UNIFORM_BUFFER,
                        _ => vk::DescriptorType::STORAGE_BUFFER,
                    };
                }
                Desc::StorageImage(i) => {
                    image_infos[n] = [vk::DescriptorImageInfo {
                        sampler: vk::Sampler::null(),
                        image_view: i.view,
                        image_layout: vk::ImageLayout::GENERAL,
                    }];
                    kinds[n] = vk::DescriptorType::STORAGE_IMAGE;
                }
            }
            n += 1;
        }
        let mut writes = [vk::WriteDescriptorSet::default(); MAX_DESCRIPTORS];
        for (i, w) in writes.iter_mut().enumerate().take(n) {
            let base = vk::WriteDescriptorSet::default()
                .dst_binding(i as u32)
                .descriptor_type(kinds[i]);
            *w = if kinds[i] == vk::DescriptorType::STORAGE_IMAGE {
                base.image_info(&image_infos[i])
            } else {
                base.buffer_info(&buffer_infos[i])
            };
        }
        self.counts.bindings += 1;
        // SAFETY: the writes refer to live resources and match the pipeline's push-descriptor layout.
        unsafe {
            self.ctx.inner.push_descriptor.cmd_push_descriptor_set(
                self.cb,
                bind,
                layout,
                0,
                &writes[..n],
            )
        };
    }

    /// Pushes descriptors (binding i = `descs[i]`) for a graphics pipeline.
    pub fn push_graphics_descriptors<'b, 'a: 'b>(
        &mut self,
        p: &GraphicsPipeline,
        descs: impl IntoIterator<Item = &'b Desc<'a>>,
    ) {
        self.push_descriptors(vk::PipelineBindPoint::GRAPHICS, p.layout, descs);
    }

    /// Pushes descriptors (binding i = `descs[i]`) for a compute pipeline.
    pub fn push_compute_descriptors<'b, 'a: 'b>(
        &mut self,
        p: &ComputePipeline,
        descs: impl IntoIterator<Item = &'b Desc<'a>>,
    ) {
        self.push_descriptors(vk::PipelineBindPoint::COMPUTE, p.layout, descs);
    }

    /// Sets push constants of a graphics pipeline (all its stages).
    pub fn graphics_push_constants(&mut self, p: &GraphicsPipeline, data: &[u8]) {
        assert_eq!(
            data.len() as u32,
            p.push_constant_size,
            "push constants of `{}`",
            p.name
        );
        self.counts.bindings += 1;
        // SAFETY: size matches the layout's range (checked above), whose stages are the pipeline's.
        unsafe {
            self.dev()
                .cmd_push_constants(self.cb, p.layout, p.stages, 0, data)
        };
    }

    /// Sets push constants of a compute pipeline.
    pub fn compute_push_constants(&mut self, p: &ComputePipeline, data: &[u8]) {
        assert_eq!(
            data.len() as u32,
            p.push_constant_size,
            "push constants of `{}`",
            p.name
        );
        self.counts.bindings += 1;
        // SAFETY: size matches the layout's range (checked above).
        unsafe {
            self.dev()
                .cmd_push_constants(self.cb, p.layout, vk::ShaderStageFlags::COMPUTE, 0, data)
        };
    }

    /// Binds vertex buffer 0 and a u32 index buffer.
    pub fn bind_mesh_buffers(&mut self, vertices: &Buffer, indices: &Buffer) {
        self.counts.bindings += 2;
        // SAFETY: valid buffers created with vertex/index usage.
        unsafe {
            self.dev()
                .cmd_bind_vertex_buffers(self.cb, 0, &[vertices.raw], &[0]);
            self.dev()
                .cmd_bind_index_buffer(self.cb, indices.raw, 0, vk::IndexType::UINT32);
        }
    }

    /// `vkCmdDrawIndexed`.
    pub fn draw_indexed(
        &mut self,
        index_count: u32,
        instance_count: u32,
        first_index: u32,
        first_instance: u32,
    ) {
        self.counts.draws += 1;
        // SAFETY: a pipeline and index buffer are bound by the caller.
        unsafe {
            self.dev().cmd_draw_indexed(
                self.cb,
                index_count,
                instance_count,
                first_index,
                0,
                first_instance,
            )
        };
    }

    /// Fills `size` bytes at `offset` of a buffer with a repeated u32.
    pub fn fill_buffer_range(&mut self, buf: &Buffer, offset: u64, size: u64, value: u32) {
        self.counts.transfers += 1;
        // SAFETY: valid buffer; offset and size are multiples of 4 within the buffer (callers).
        unsafe {
            self.dev()
                .cmd_fill_buffer(self.cb, buf.raw, offset, size, value)
        };
    }

    /// Writes small data (at most 65536 bytes, a multiple of 4) into a buffer, in command order.
    pub fn update_buffer(&mut self, buf: &Buffer, offset: u64, data: &[u8]) {
        assert!(
            data.len() <= 65536 && data.len().is_multiple_of(4),
            "vkCmdUpdateBuffer limits"
        );
        self.counts.transfers += 1;
        // SAFETY: valid buffer with TRANSFER_DST usage; size limits asserted above.
        unsafe { self.dev().cmd_update_buffer(self.cb, buf.raw, offset, data) };
    }

    /// Clears a colour/integer image to zero (it ends in `GENERAL` layout, ready for storage use).
    pub fn clear_image_zero(&mut self, image: &Image) {
        self.transition(image, vk::ImageLayout::GENERAL);
        let range = vk::ImageSubresourceRange {
            aspect_mask: image.aspect,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        };
        let clear = vk::ClearColorValue { uint32: [0; 4] };
        self.counts.transfers += 1;
        // SAFETY: the image is in GENERAL layout and was created with TRANSFER_DST usage.
        unsafe {
            self.dev().cmd_clear_color_image(
                self.cb,
                image.raw,
                vk::ImageLayout::GENERAL,
                &clear,
                &[range],
            )
        };
    }

    /// `vkCmdDispatchIndirect` with arguments at `offset` of `args`.
    pub fn dispatch_indirect(&mut self, args: &Buffer, offset: u64) {
        self.counts.dispatches += 1;
        // SAFETY: a compute pipeline is bound; `args` has INDIRECT usage (callers).
        unsafe { self.dev().cmd_dispatch_indirect(self.cb, args.raw, offset) };
    }

    /// `vkCmdDrawIndirect` of one draw with arguments at `offset` of `args`.
    pub fn draw_indirect(&mut self, args: &Buffer, offset: u64) {
        self.counts.draws += 1;
        // SAFETY: a graphics pipeline is bound inside a rendering pass; `args` has INDIRECT usage.
        unsafe {
            self.dev()
                .cmd_draw_indirect(self.cb, args.raw, offset, 1, 16)
        };
    }

    /// `vkCmdDrawMeshTasksIndirectEXT` of one `VkDrawMeshTasksIndirectCommandEXT` (workgroups x,
    /// y, z: three u32) at `offset` in `args`, with a mesh-shader pipeline bound
    /// ([`super::GeometryStage::Mesh`], which exists only on a device with
    /// [`super::Caps::mesh_shader`]).
    pub fn draw_mesh_tasks_indirect(&mut self, args: &Buffer, offset: u64) {
        self.counts.draws += 1;
        let Some(mesh) = self.ctx.inner.mesh_shader.as_ref() else {
            debug_assert!(false, "draw_mesh_tasks_indirect without VK_EXT_mesh_shader");
            return;
        };
        // SAFETY: a mesh-shader pipeline is bound inside a rendering pass (its creation needed the
        // extension and feature, whose commands `mesh` holds); `args` has INDIRECT usage and holds
        // the 12 bytes at `offset` (callers).
        unsafe {
            mesh.cmd_draw_mesh_tasks_indirect(
                self.cb,
                args.raw,
                offset,
                1,
                size_of::<vk::DrawMeshTasksIndirectCommandEXT>() as u32,
            )
        };
    }

    /// `vkCmdDrawIndexedIndirectCount`: up to `max_draws` `VkDrawIndexedIndirectCommand`s of
    /// `stride` bytes from `offset` in `args`, as many as the u32 at `count_offset` in `count` says.
    pub fn draw_indexed_indirect_count(
        &mut self,
        args: &Buffer,
        offset: u64,
        count: &Buffer,
        count_offset: u64,
        max_draws: u32,
        stride: u32,
    ) {
        self.counts.draws += 1;
        // SAFETY: a graphics pipeline, vertex and index buffers are bound inside a rendering pass;
        // `args` and `count` have INDIRECT usage and hold the ranges named (callers).
        unsafe {
            self.dev().cmd_draw_indexed_indirect_count(
                self.cb,
                args.raw,
                offset,
                count.raw,
                count_offset,
                max_draws,
                stride,
            )
        };
    }

    /// `vkCmdDraw`.
    pub fn draw(&mut self, vertex_count: u32, instance_count: u32) {
        self.counts.draws += 1;
        // SAFETY: a graphics pipeline is bound inside a rendering pass.
        unsafe {
            self.dev()
                .cmd_draw(self.cb, vertex_count, instance_count, 0, 0)
        };
    }

    /// Moves `image` to `GENERAL` layout for storage access (no-op if it is already there).
    pub fn to_general(&mut self, image: &Image) {
        if image.layout.load(Ordering::Relaxed) != vk::ImageLayout::GENERAL.as_raw() {
            self.transition(image, vk::ImageLayout::GENERAL);
        }
    }

    /// `vkCmdDispatch`.
    pub fn dispatch(&mut self, x: u32, y: u32, z: u32) {
        self.counts.dispatches += 1;
        // SAFETY: a compute pipeline is bound by the caller.
        unsafe { self.dev().cmd_dispatch(self.cb, x, y, z) };
    }

    /// Binds a bindless texture array as descriptor set 1 of a graphics pipeline (created with
    /// [`GraphicsPipeline::with_textures`]).
    pub fn bind_graphics_textures(&mut self, p: &GraphicsPipeline, textures: &TextureSet) {
        self.counts.bindings += 1;
        // SAFETY: the pipeline's layout has the set's layout at set 1.
        unsafe {
            self.dev().cmd_bind_descriptor_sets(
                self.cb,
                vk::PipelineBindPoint::GRAPHICS,
                p.layout,
                1,
                &[textures.set],
                &[],
            )
        };
    }

    /// Binds a bindless texture array as descriptor set 1 of a compute pipeline (created with
    /// [`ComputePipeline::with_textures`]).
    pub fn bind_compute_textures(&mut self, p: &ComputePipeline, textures: &TextureSet) {
        self.counts.bindings += 1;
        // SAFETY: the pipeline's layout has the set's layout at set 1.
        unsafe {
            self.dev().cmd_bind_descriptor_sets(
                self.cb,
                vk::PipelineBindPoint::COMPUTE,
                p.layout,
                1,
                &[textures.set],
                &[],
            )
        };
    }

    /// `vkCmdDraw` with a first instance.
    pub fn draw_instanced(&mut self, vertex_count: u32, instance_count: u32, first_instance: u32) {
        self.counts.draws += 1;
        // SAFETY: a graphics pipeline is bound inside a rendering pass.
        unsafe {
            self.dev()
                .cmd_draw(self.cb, vertex_count, instance_count, 0, first_instance)
        };
    }

    /// Copies tightly packed mip levels from a buffer into an image (moved to
    /// `TRANSFER_DST_OPTIMAL`): `levels[i]` = (byte offset in `buf`, width, height) of level i.
    pub fn copy_buffer_to_image(
        &mut self,
        buf: &Buffer,
        image: &Image,
        levels: &[(u64, u32, u32)],
    ) {
        self.transition(image, vk::ImageLayout::TRANSFER_DST_OPTIMAL);
        assert!(levels.len() <= MAX_DESCRIPTORS, "too many mip levels");
        let mut regions = [vk::BufferImageCopy::default(); MAX_DESCRIPTORS];
        for (r, (i, &(offset, width, height))) in regions.iter_mut().zip(levels.iter().enumerate())
        {
            *r = vk::BufferImageCopy::default()
                .buffer_offset(offset)
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: image.aspect,
                    mip_level: i as u32,
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .image_extent(vk::Extent3D {
                    width,
                    height,
                    depth: 1,
                });
        }
        self.counts.transfers += 1;
        // SAFETY: the image is in TRANSFER_DST layout; the buffer holds a whole image (caller).
        unsafe {
            self.dev().cmd_copy_buffer_to_image(
                self.cb,
                buf.raw,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &regions[..levels.len()],
            )
        };
    }

    /// Copies a whole colour image (in any layout) into a buffer, tightly packed.
    pub fn copy_image_to_buffer(&mut self, image: &Image, buf: &Buffer) {
        self.transition(image, vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
        let region = vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: image.aspect,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            })
            .image_extent(vk::Extent3D {
                width: image.width,
                height: image.height,
                depth: 1,
            });
        self.counts.transfers += 1;
        // SAFETY: the image is in TRANSFER_SRC layout; the buffer is large enough (caller sizes it).
        unsafe {
            self.dev().cmd_copy_image_to_buffer(
                self.cb,
                image.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buf.raw,
                &[region],
            )
        };
        self.barrier(
            (
                vk::PipelineStageFlags2::ALL_TRANSFER,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
        );
    }
}
