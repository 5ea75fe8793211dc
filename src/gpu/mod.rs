//! The GPU layer: the only module with raw `ash` calls.
//!
//! [`Context`] owns the instance, device, queue, allocator and debug messenger; [`Buffer`] and
//! [`Image`] own memory from `gpu-allocator`; [`Cmd`] records commands through a small safe API;
//! [`Timer`] measures passes with timestamp queries. Every object gets a debug name and every pass a
//! labelled region (`VK_EXT_debug_utils`), so a RenderDoc capture reads like the design.

mod capture;
mod cmd;
mod context;
mod memory;
mod pipeline;
mod query;
mod requirements;
mod shader_dir;
mod shaderc_options;
mod texture;

pub use ash::vk;
pub use capture::RenderDoc;
pub use cmd::{Cmd, CmdCounts, Desc, DescList, MAX_DESCRIPTORS, RenderTarget};
pub use context::{Caps, Context, ContextOptions, HostDevice};
pub use memory::{Buffer, HostImage, Image, MemoryKind};
pub use pipeline::{
    ComputePipeline, GeometryStage, GraphicsPipeline, GraphicsPipelineDesc, ShaderStage,
};
pub use query::Timer;
pub use requirements::{
    DeviceFeatures, Feature, Requirements, device_extensions_for_vgeo, requirements,
};
pub use texture::TextureSet;

/// Errors of the GPU layer.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "the Vulkan loader could not be loaded ({0}); install libvulkan1 and a driver (e.g. mesa-vulkan-drivers)"
    )]
    Loader(String),
    #[error("no usable Vulkan device: {0}")]
    NoDevice(String),
    /// The device (or instance) lacks what [`requirements`] lists: each missing item named.
    #[error("the Vulkan device lacks what vgeo requires: {} (see vgeo::gpu::requirements())", missing.join(", "))]
    Unsupported { missing: Vec<String> },
    #[error("Vulkan call {call} failed: {result}")]
    Vk {
        call: &'static str,
        result: vk::Result,
    },
    #[error("the device was lost while running pass `{pass}`")]
    DeviceLost { pass: String },
    #[error("memory allocation for `{name}` failed: {msg}")]
    Alloc { name: String, msg: String },
    #[error("invalid SPIR-V for `{name}`: {msg}")]
    Shader { name: String, msg: String },
    #[error("{0}")]
    Other(String),
}

/// Result of the GPU layer.
pub type GpuResult<T> = Result<T, GpuError>;

pub(crate) trait VkResultExt<T> {
    fn call(self, call: &'static str) -> GpuResult<T>;
}

impl<T> VkResultExt<T> for Result<T, vk::Result> {
    fn call(self, call: &'static str) -> GpuResult<T> {
        self.map_err(|result| GpuError::Vk { call, result })
    }
}
