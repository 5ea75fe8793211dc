//! Buffers and images with memory from `gpu-allocator`, uploads and readbacks.

use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};

use super::{Context, GpuError, GpuResult, VkResultExt};

/// Where a resource's memory lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemoryKind {
    /// Device-local, not host visible.
    Gpu,
    /// Host-visible, written by the CPU (uploads, small uniforms).
    Upload,
    /// Host-visible, read by the CPU (readbacks).
    Readback,
}

impl MemoryKind {
    fn location(self) -> MemoryLocation {
        match self {
            MemoryKind::Gpu => MemoryLocation::GpuOnly,
            MemoryKind::Upload => MemoryLocation::CpuToGpu,
            MemoryKind::Readback => MemoryLocation::GpuToCpu,
        }
    }
}

/// With `VGEO_LOG_ALLOCATIONS=1`, one line on stderr per buffer: its name, size, the alignment
/// the device asks for and where the allocator placed it (for layout effects on frame times:
/// docs/profiling.md).
fn log_allocation(
    name: &str,
    size: u64,
    requirements: &vk::MemoryRequirements,
    allocation: &Allocation,
) {
    static ON: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    if *ON.get_or_init(|| std::env::var("VGEO_LOG_ALLOCATIONS").is_ok_and(|v| v == "1")) {
        eprintln!(
            "[allocation] {name}: {size} B, alignment {}, block offset {}",
            requirements.alignment,
            allocation.offset()
        );
    }
}

/// With `VGEO_BUFFER_ALIGN=N` (a power of two), every buffer starts on a multiple of N bytes in
/// its memory block at least (the device's own alignment otherwise): for measuring whether a
/// frame time moves with where the buffers lie (docs/profiling.md). 1 when unset or invalid.
fn buffer_alignment() -> u64 {
    static ALIGN: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
    *ALIGN.get_or_init(|| {
        std::env::var("VGEO_BUFFER_ALIGN")
            .ok()
            .and_then(|v| v.parse::<u64>().ok())
            .filter(|n| n.is_power_of_two())
            .unwrap_or(1)
    })
}

/// Memory for a resource from the context's allocator.
fn allocate(
    ctx: &Context,
    name: &str,
    requirements: vk::MemoryRequirements,
    location: MemoryLocation,
    linear: bool,
) -> GpuResult<Allocation> {
    ctx.inner
        .allocator
        .lock()
        .map_err(|_| GpuError::Other("allocator lock poisoned".into()))?
        .as_mut()
        .ok_or_else(|| GpuError::Other("allocator gone".into()))?
        .allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })
        .map_err(|e| GpuError::Alloc {
            name: name.into(),
            msg: e.to_string(),
        })
}

/// Returns memory to the allocator (on drop; errors cannot be reported there).
fn free(ctx: &Context, allocation: Allocation) {
    if let Ok(mut alloc) = ctx.inner.allocator.lock()
        && let Some(alloc) = alloc.as_mut()
    {
        let _ = alloc.free(allocation);
    }
}

/// A buffer and its memory; freed on drop.
pub struct Buffer {
    ctx: Context,
    pub(crate) raw: vk::Buffer,
    allocation: Option<Allocation>,
    size: u64,
    name: String,
}

impl Buffer {
    /// Creates a buffer of `size` bytes (at least 4).
    pub fn new(
        ctx: &Context,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        kind: MemoryKind,
    ) -> GpuResult<Self> {
        let size = size.max(4);
        let dev = ctx.device();
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info.
        let raw = unsafe { dev.create_buffer(&info, None) }.call("vkCreateBuffer")?;
        // SAFETY: `raw` was just created on this device.
        let mut requirements = unsafe { dev.get_buffer_memory_requirements(raw) };
        requirements.alignment = requirements.alignment.max(buffer_alignment());
        let allocation = match allocate(ctx, name, requirements, kind.location(), true) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: the buffer has no memory bound and is not in use.
                unsafe { dev.destroy_buffer(raw, None) };
                return Err(e);
            }
        };
        log_allocation(name, size, &requirements, &allocation);
        // SAFETY: the allocation satisfies the buffer's requirements and is not bound elsewhere.
        unsafe { dev.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
            .call("vkBindBufferMemory")?;
        ctx.set_name(raw, name);
        Ok(Self {
            ctx: ctx.clone(),
            raw,
            allocation: Some(allocation),
            size,
            name: name.into(),
        })
    }

    /// A host-visible transfer source holding `data` (the source of an upload copy).
    pub fn staging(ctx: &Context, name: &str, data: &[u8]) -> GpuResult<Self> {
        let mut b = Self::new(
            ctx,
            name,
            data.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryKind::Upload,
        )?;
        b.write(0, data)?;
        Ok(b)
    }

    /// A device-local buffer filled with `data` through a staging copy.
    pub fn with_data(
        ctx: &Context,
        name: &str,
        data: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> GpuResult<Self> {
        let buf = Self::new(
            ctx,
            name,
            data.len() as u64,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryKind::Gpu,
        )?;
        if !data.is_empty() {
            let staging = Self::staging(ctx, &format!("{name} (staging)"), data)?;
            ctx.submit_and_wait(&format!("upload {name}"), |cmd| {
                cmd.copy_buffer(&staging, &buf, data.len() as u64)
            })?;
        }
        Ok(buf)
    }

    /// Size in bytes.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Debug name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Writes `data` at `offset` into a host-visible buffer.
    pub fn write(&mut self, offset: u64, data: &[u8]) -> GpuResult<()> {
        let end = offset
            .checked_add(data.len() as u64)
            .filter(|e| *e <= self.size);
        if end.is_none() {
            return Err(GpuError::Other(format!(
                "write past the end of buffer `{}`",
                self.name
            )));
        }
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| {
                GpuError::Other(format!("buffer `{}` is not host visible", self.name))
            })?;
        slice[offset as usize..offset as usize + data.len()].copy_from_slice(data);
        Ok(())
    }

    /// Reads the contents of a host-visible buffer.
    pub fn read(&self) -> GpuResult<Vec<u8>> {
        let slice = self
            .allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .ok_or_else(|| {
                GpuError::Other(format!("buffer `{}` is not host visible", self.name))
            })?;
        Ok(slice[..self.size as usize].to_vec())
    }

    /// Copies a device buffer back to the CPU (through a readback buffer).
    pub fn download(&self) -> GpuResult<Vec<u8>> {
        self.download_prefix(self.size)
    }

    /// The first `bytes` bytes of the buffer (at most its size; at least 1 is copied), for
    /// reading back the used part of a large list.
    pub fn download_prefix(&self, bytes: u64) -> GpuResult<Vec<u8>> {
        self.download_range(0, bytes)
    }

    /// `bytes` bytes from byte `offset` on (clamped to the buffer; at least 1 is copied), for
    /// reading back the used part of a list filled from its end.
    pub fn download_range(&self, offset: u64, bytes: u64) -> GpuResult<Vec<u8>> {
        let offset = offset.min(self.size.saturating_sub(1));
        let len = bytes.min(self.size - offset);
        let size = len.max(1);
        let rb = Self::new(
            &self.ctx,
            &format!("{} (readback)", self.name),
            size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryKind::Readback,
        )?;
        self.ctx
            .submit_and_wait(&format!("download {}", self.name), |cmd| {
                cmd.copy_buffer_region(self, offset, &rb, 0, size)
            })?;
        let mut out = rb.read()?;
        out.truncate(len as usize);
        Ok(out)
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        let dev = self.ctx.device();
        // SAFETY: callers wait for GPU work that uses the buffer before dropping it (every submission
        // here is waited on); the allocation is returned to the allocator it came from.
        unsafe { dev.destroy_buffer(self.raw, None) };
        if let Some(a) = self.allocation.take() {
            free(&self.ctx, a);
        }
    }
}

/// A 2D image with a view over all its mip levels (one unless made by [`Image::with_rgba8_mips`]);
/// freed on drop.
pub struct Image {
    ctx: Context,
    pub(crate) raw: vk::Image,
    pub(crate) view: vk::ImageView,
    allocation: Option<Allocation>,
    pub format: vk::Format,
    pub width: u32,
    pub height: u32,
    pub(crate) aspect: vk::ImageAspectFlags,
    /// Mip levels (transitions cover them all).
    pub mip_levels: u32,
    /// Current layout, tracked in recording order (commands are recorded in execution order).
    pub(crate) layout: std::sync::atomic::AtomicI32,
    name: std::borrow::Cow<'static, str>,
    /// False for a host's image ([`Image::from_host`]): vgeo neither names nor destroys it.
    owned: bool,
}

/// An image the host owns, handed to vgeo for the recording of one frame: its handles, format,
/// size and the layout it is in when vgeo's commands start (vgeo leaves it in that layout).
#[derive(Clone, Copy, Debug)]
pub struct HostImage {
    /// The host's image (vgeo neither names nor destroys it).
    pub image: vk::Image,
    /// A 2D view of mip 0 (storage writes go through it); may be null for a depth image, which vgeo
    /// reads and writes with transfers only.
    pub view: vk::ImageView,
    /// Its format (checked against what the target needs, e.g. `HOST_DEPTH_FORMAT`).
    pub format: vk::Format,
    /// Width in pixels (the view's).
    pub width: u32,
    /// Height in pixels (the view's).
    pub height: u32,
    /// The layout at entry, and at exit.
    pub layout: vk::ImageLayout,
}

impl Image {
    /// Creates a device-local 2D image.
    pub fn new(
        ctx: &Context,
        name: &str,
        width: u32,
        height: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
    ) -> GpuResult<Self> {
        Self::with_levels(ctx, name, width, height, format, usage, 1)
    }

    /// Creates a device-local 2D image with `mip_levels` levels (at least 1).
    pub(crate) fn with_levels(
        ctx: &Context,
        name: &str,
        width: u32,
        height: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        mip_levels: u32,
    ) -> GpuResult<Self> {
        let mip_levels = mip_levels.max(1);
        let dev = ctx.device();
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })
            .mip_levels(mip_levels)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let raw = unsafe { dev.create_image(&info, None) }.call("vkCreateImage")?;
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { dev.get_image_memory_requirements(raw) };
        let allocation = match allocate(ctx, name, requirements, MemoryLocation::GpuOnly, false) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: the image has no memory bound and is not in use.
                unsafe { dev.destroy_image(raw, None) };
                return Err(e);
            }
        };
        // SAFETY: the allocation satisfies the image's requirements.
        unsafe { dev.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
            .call("vkBindImageMemory")?;
        let aspect = match format {
            vk::Format::D32_SFLOAT | vk::Format::D16_UNORM => vk::ImageAspectFlags::DEPTH,
            _ => vk::ImageAspectFlags::COLOR,
        };
        let vinfo = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: aspect,
                base_mip_level: 0,
                level_count: mip_levels,
                base_array_layer: 0,
                layer_count: 1,
            });
        // SAFETY: the image is valid and bound to memory.
        let view = unsafe { dev.create_image_view(&vinfo, None) }.call("vkCreateImageView")?;
        ctx.set_name(raw, name);
        ctx.set_name(view, &format!("{name} view"));
        Ok(Self {
            ctx: ctx.clone(),
            raw,
            view,
            allocation: Some(allocation),
            format,
            width,
            height,
            aspect,
            mip_levels,
            layout: std::sync::atomic::AtomicI32::new(vk::ImageLayout::UNDEFINED.as_raw()),
            name: name.to_string().into(),
            owned: true,
        })
    }

    /// Wraps a host's image for recording (barriers, copies, storage writes). vgeo does not name,
    /// destroy or free it; the wrapper's layout starts at `host.layout`. The caller keeps the image
    /// alive while commands recorded with the wrapper may run.
    pub fn from_host(ctx: &Context, name: &'static str, host: &HostImage) -> Self {
        let aspect = match host.format {
            vk::Format::D32_SFLOAT | vk::Format::D16_UNORM => vk::ImageAspectFlags::DEPTH,
            _ => vk::ImageAspectFlags::COLOR,
        };
        Self {
            ctx: ctx.clone(),
            raw: host.image,
            view: host.view,
            allocation: None,
            format: host.format,
            width: host.width,
            height: host.height,
            aspect,
            mip_levels: 1,
            layout: std::sync::atomic::AtomicI32::new(host.layout.as_raw()),
            name: name.into(),
            owned: false,
        }
    }

    /// The image described as a host's image ([`HostImage`]) in its current layout: a vgeo-made
    /// image handed to an API that takes the host's images (tests, or a host that lets vgeo
    /// allocate its targets). Commands recorded with the description must leave the image in that
    /// layout (vgeo's embedded frame does).
    pub fn as_host(&self) -> HostImage {
        HostImage {
            image: self.raw,
            view: self.view,
            format: self.format,
            width: self.width,
            height: self.height,
            layout: self.current_layout(),
        }
    }

    /// The layout the image is in, in recording order.
    pub fn current_layout(&self) -> vk::ImageLayout {
        vk::ImageLayout::from_raw(self.layout.load(std::sync::atomic::Ordering::Relaxed))
    }

    /// Debug name.
    pub fn name(&self) -> &str {
        &self.name
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        if !self.owned {
            return;
        }
        let dev = self.ctx.device();
        // SAFETY: GPU work using the image has been waited for (all submissions are waited on).
        unsafe {
            dev.destroy_image_view(self.view, None);
            dev.destroy_image(self.raw, None);
        }
        if let Some(a) = self.allocation.take() {
            free(&self.ctx, a);
        }
    }
}

impl Image {
    /// Bytes per texel of the formats vgeo reads back.
    fn texel_size(&self) -> Option<u64> {
        match self.format {
            vk::Format::R8G8B8A8_UNORM | vk::Format::R8G8B8A8_SRGB | vk::Format::D32_SFLOAT => {
                Some(4)
            }
            vk::Format::R32_UINT | vk::Format::R32_SFLOAT => Some(4),
            vk::Format::R32G32_UINT | vk::Format::R64_UINT | vk::Format::R16G16B16A16_SFLOAT => {
                Some(8)
            }
            _ => None,
        }
    }

    /// Copies the image back to the CPU, tightly packed rows.
    pub fn download(&self) -> GpuResult<Vec<u8>> {
        let texel = self.texel_size().ok_or_else(|| {
            GpuError::Other(format!(
                "readback of {:?} (`{}`) is not supported",
                self.format, self.name
            ))
        })?;
        let size = texel * self.width as u64 * self.height as u64;
        let rb = Buffer::new(
            &self.ctx,
            &format!("{} (readback)", self.name),
            size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryKind::Readback,
        )?;
        self.ctx
            .submit_and_wait(&format!("download {}", self.name), |cmd| {
                cmd.copy_image_to_buffer(self, &rb)
            })?;
        let mut v = rb.read()?;
        v.truncate(size as usize);
        Ok(v)
    }
}
