//! vgeo inside a host engine (issue 12): this program is the host. It creates its own Vulkan
//! instance, device and queue (enabling what `vgeo::requirements()` lists), loads two meshes,
//! places 1,000 instances, draws triangles of its own with its own pipeline before and after
//! vgeo's frame (occluding and occluded by vgeo's geometry through the shared depth image),
//! renders 100 frames with 2 in flight into its own images, and writes the last frame as PNG:
//!
//! ```text
//! cargo run --release --example embed -- --out last.png
//! ```
//!
//! Options: `--frames N`, `--instances N`, `--size WxH`, `--mesh PATH` (twice; `generated:box` is
//! a unit cube), `--no-host-draws`, `--no-vgeo`, `--validate` (Khronos validation with synchronization
//! validation; errors are counted and make the program fail), `--geometry-budget MIB` (stream the
//! meshes' pages under that budget: a `vgeo::Streamer` steps after each fence wait, reading the
//! page feedback of the frames already done and staging its uploads for the next frame, without
//! waiting for the GPU), `--still-from N` (the camera and instances stop at frame N), `--orbit X`
//! (the camera's orbit X times the default: smaller is closer).
//!
//! tests/embed.rs runs this same code (`run`) on lavapipe and checks its image against vgeo's own
//! `render` and the occlusion between the host's triangles and vgeo's geometry.

use std::ffi::{CStr, CString, c_void};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context as _, Result, anyhow, bail};
use ash::vk;
use glam::{DMat4, DVec3, Vec3};
use vgeo::{
    BuildOptions, BuiltMesh, Camera, Context, DeviceFeatures, FrameSettings, HostDevice, HostImage,
    HostTargets, Light, Placement, Renderer as VgeoRenderer, ShadeMode, View, ViewFrame,
    device_extensions_for_vgeo,
};

/// What the host renders.
#[derive(Clone, Debug)]
pub struct Options {
    pub frames: u32,
    pub frames_in_flight: u32,
    pub instances: u32,
    pub width: u32,
    pub height: u32,
    /// Two meshes: files, or `generated:box`.
    pub meshes: Vec<String>,
    /// Whether the host draws its triangles (before vgeo: occluding it; after: occluded by it).
    pub host_draws: bool,
    /// Whether vgeo's frame is recorded (off: the host's triangles alone, for comparisons).
    pub vgeo_draws: bool,
    /// Khronos validation (and synchronization validation where the layer has it).
    pub validate: bool,
    pub out: Option<PathBuf>,
    /// Stream the meshes' geometry pages under this many GPU bytes (`None`: all resident): a
    /// [`vgeo::Streamer`] steps after each fence wait, its uploads ride in the next frame.
    pub geometry_budget: Option<u64>,
    /// The camera and the instances stop moving from this frame on (`None`: they move to the end).
    pub still_from: Option<u32>,
    /// The camera's orbit, as a multiple of the default one (smaller: closer).
    pub orbit: f64,
}

impl Default for Options {
    fn default() -> Self {
        let asset = |n: &str| format!("{}/assets/{n}", env!("CARGO_MANIFEST_DIR"));
        Self {
            frames: 100,
            frames_in_flight: 2,
            instances: 1000,
            width: 640,
            height: 360,
            meshes: vec![asset("spot.obj"), asset("bunny.ply")],
            host_draws: true,
            vgeo_draws: true,
            validate: false,
            out: None,
            geometry_budget: None,
            still_from: None,
            orbit: 1.0,
        }
    }
}

/// What streaming did over the run (with [`Options::geometry_budget`]).
#[derive(Clone, Debug, Default)]
pub struct StreamSummary {
    /// Pages uploaded, and evicted.
    pub uploads: u64,
    pub evictions: u64,
    /// Requests the last step saw, and whether it was at rest (staged nothing, read nothing).
    pub last_requests: u64,
    pub last_settled: bool,
    /// Most resident page bytes after a step.
    pub peak_resident_bytes: u64,
    /// Submissions vgeo made and waited for inside the streaming steps (a step should make none).
    pub waits: u64,
}

/// What the host got: the last frame's colour (RGBA8, sRGB-encoded) and depth (reverse-Z), its
/// camera, the scene, and what the validation layer and vgeo's stats said.
pub struct Output {
    pub width: u32,
    pub height: u32,
    pub color: Vec<u8>,
    pub depth: Vec<f32>,
    pub camera: Camera,
    pub built: Vec<BuiltMesh>,
    pub placements: Vec<Placement>,
    pub validation_errors: Vec<String>,
    /// Frames whose stats came back (with `try_stats`, `frames_in_flight` frames later).
    pub stats_frames: u32,
    /// Triangles vgeo drew in the last frame whose stats came back.
    pub last_triangles: u64,
    pub sync_validation: bool,
    /// With a geometry budget, what streaming did.
    pub stream: Option<StreamSummary>,
}

/// The host's colour format and the background it clears to (vgeo's, sRGB-encoded, so a frame
/// where the host draws nothing equals `vgeo render`).
const COLOR_FORMAT: vk::Format = vgeo::HOST_COLOR_FORMAT;
const DEPTH_FORMAT: vk::Format = vgeo::HOST_DEPTH_FORMAT;

/// The host's triangles: world-space corners and a flat colour each. The first is drawn before
/// vgeo's frame (it occludes vgeo's geometry through the depth it leaves), the second after (vgeo's
/// depth occludes it). Both cut through the instance grid, so each is partly in front and partly
/// behind.
pub fn host_triangles() -> [([[f32; 3]; 3], [f32; 4]); 2] {
    [
        (
            [[-9.0, -0.3, 6.0], [9.0, -0.3, -6.0], [-1.0, 3.5, 1.0]],
            [1.0, 0.15, 0.1, 1.0],
        ),
        (
            [[-3.0, -0.3, -9.0], [9.0, -0.3, 5.0], [4.0, 2.5, -1.0]],
            [0.1, 0.35, 1.0, 1.0],
        ),
    ]
}

/// The camera of frame `i`: an orbit around the grid.
pub fn camera_at(i: u32) -> Camera {
    camera_orbit(i, 1.0)
}

/// The camera of frame `i` on an orbit `scale` times as large (smaller: closer).
pub fn camera_orbit(i: u32, scale: f64) -> Camera {
    let a = 0.6 + i as f64 * 0.01;
    let eye = DVec3::new(a.sin() * 16.0, 7.0, a.cos() * 16.0) * scale;
    Camera::look_at(
        eye,
        DVec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        50f32.to_radians(),
        0.05,
    )
}

/// Instance `j`'s transform in frame `i`: its place on the grid, bobbing up and down (every
/// instance moves every frame).
pub fn transform_at(p: &Placement, j: u32, i: u32) -> DMat4 {
    let bob = 0.25 * (0.15 * i as f64 + 0.37 * j as f64).sin();
    DMat4::from_translation(DVec3::new(0.0, bob, 0.0)) * p.transform
}

/// The instances: a grid on the ground, alternating meshes, each scaled to about one unit (frame
/// 0's places; [`transform_at`] animates them).
pub fn placements(built: &[BuiltMesh], count: u32) -> Vec<Placement> {
    let bounds: Vec<(DVec3, DVec3)> = built
        .iter()
        .map(|b| {
            let p = b.positions();
            let v = |q: &[f32; 3]| DVec3::from(q.map(f64::from));
            let lo = p.iter().fold(DVec3::splat(f64::MAX), |a, q| a.min(v(q)));
            let hi = p.iter().fold(DVec3::splat(f64::MIN), |a, q| a.max(v(q)));
            (lo, hi)
        })
        .collect();
    let side = (count as f64).sqrt().ceil() as u32;
    let spacing = 22.0 / side as f64;
    (0..count)
        .map(|i| {
            let mesh = i % built.len() as u32;
            let (lo, hi) = bounds[mesh as usize];
            let size = (hi - lo).max_element().max(1e-9);
            let s = 0.8 * spacing / size;
            let centre = (lo + hi) * 0.5;
            let (gx, gz) = ((i % side) as f64, (i / side) as f64);
            let pos = DVec3::new(
                (gx - side as f64 / 2.0) * spacing,
                (hi.y - lo.y) * s * 0.5,
                (gz - side as f64 / 2.0) * spacing,
            );
            let turn = DMat4::from_rotation_y(i as f64 * 0.7);
            Placement {
                mesh,
                transform: DMat4::from_translation(pos)
                    * turn
                    * DMat4::from_scale(DVec3::splat(s))
                    * DMat4::from_translation(-centre),
                color: [
                    0.55 + 0.4 * ((i * 37 % 11) as f32 / 10.0),
                    0.55 + 0.4 * ((i * 53 % 7) as f32 / 6.0),
                    0.6,
                ],
            }
        })
        .collect()
}

/// Imports and builds the meshes (files, or `generated:NAME`).
pub fn build_meshes(sources: &[String]) -> Result<Vec<BuiltMesh>> {
    sources
        .iter()
        .map(|s| {
            let mesh = match s.strip_prefix("generated:") {
                Some(name) => vgeo::generated_mesh(name)
                    .ok_or_else(|| anyhow!("unknown generated mesh {name}"))?,
                None => vgeo::merge_meshes(
                    vgeo::load_mesh(Path::new(s), &vgeo::ImportOptions::default())
                        .with_context(|| format!("loading {s}"))?
                        .meshes,
                ),
            };
            vgeo::build(&mesh, &BuildOptions::default()).map_err(|e| anyhow!("building {s}: {e}"))
        })
        .collect()
}

/// The device a host picks for vgeo: the first of the kind vgeo prefers (discrete first) with
/// the API version and a queue family vgeo requires (`VGEO_DEVICE=<substring>` filters by name);
/// the physical device and that queue family.
pub fn pick_device(instance: &ash::Instance) -> Result<Option<(vk::PhysicalDevice, u32)>> {
    let reqs = vgeo::requirements();
    // SAFETY: queries on a valid instance.
    let devices = unsafe { instance.enumerate_physical_devices() }?;
    let filter = std::env::var("VGEO_DEVICE").ok().filter(|s| !s.is_empty());
    let mut best: Option<(u32, vk::PhysicalDevice, u32)> = None;
    for pd in devices {
        // SAFETY: queries on a valid physical device.
        let (props, families) = unsafe {
            (
                instance.get_physical_device_properties(pd),
                instance.get_physical_device_queue_family_properties(pd),
            )
        };
        let name = props
            .device_name_as_c_str()
            .map(|n| n.to_string_lossy().to_lowercase())
            .unwrap_or_default();
        if filter
            .as_ref()
            .is_some_and(|f| !name.contains(&f.to_lowercase()))
            || props.api_version < reqs.api_version
        {
            continue;
        }
        let Some(qf) = families
            .iter()
            .position(|q| q.queue_flags.contains(reqs.queue_flags))
        else {
            continue;
        };
        let rank = match props.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => 0,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
            vk::PhysicalDeviceType::CPU => 3,
            _ => 2,
        };
        if best.is_none_or(|b| rank < b.0) {
            best = Some((rank, pd, qf as u32));
        }
    }
    Ok(best.map(|(_, pd, qf)| (pd, qf)))
}

/// Validation errors a host's debug messenger saw (`on_message` is its callback, with a boxed
/// `Errors` as user data, alive until after the messenger is destroyed).
pub struct Errors(pub Mutex<Vec<String>>);

/// The host's debug-messenger callback: prints and collects validation errors into `Errors`.
///
/// # Safety
/// Called by the validation layer with valid callback data and `user` pointing at an `Errors`.
pub unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        // SAFETY: the layer passes valid data for the call; `user` is the host's boxed `Errors`,
        // alive until after the messenger is destroyed.
        let (msg, errors) = unsafe {
            let d = &*data;
            let msg = if d.p_message.is_null() {
                String::new()
            } else {
                CStr::from_ptr(d.p_message).to_string_lossy().into_owned()
            };
            (msg, &*(user as *const Errors))
        };
        eprintln!("[validation] {msg}");
        if let Ok(mut e) = errors.0.lock() {
            e.push(msg);
        }
    }
    vk::FALSE
}

/// An image of the host's with its memory and view.
struct HostImg {
    image: vk::Image,
    memory: vk::DeviceMemory,
    view: vk::ImageView,
}

/// The host's Vulkan objects (destroyed in `Host::destroy`, after vgeo is gone).
struct Host {
    entry: ash::Entry,
    instance: ash::Instance,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    errors: Box<Errors>,
    physical: vk::PhysicalDevice,
    queue_family: u32,
    device: ash::Device,
    queue: vk::Queue,
    sync_validation: bool,
}

impl Host {
    fn new(validate: bool) -> Result<(Host, HostDevice)> {
        // SAFETY: loading the system Vulkan loader.
        let entry = unsafe { ash::Entry::load() }?;
        let reqs = vgeo::requirements();
        // SAFETY: plain enumeration queries.
        let (layers, inst_exts) = unsafe {
            (
                entry.enumerate_instance_layer_properties()?,
                entry.enumerate_instance_extension_properties(None)?,
            )
        };
        let validation_layer = c"VK_LAYER_KHRONOS_validation";
        let has_layer = layers
            .iter()
            .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == validation_layer));
        if validate && !has_layer {
            bail!("--validate needs VK_LAYER_KHRONOS_validation (vulkan-validationlayers)");
        }
        let has_debug = inst_exts
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(ash::ext::debug_utils::NAME));
        // Synchronization validation: VK_EXT_validation_features, offered by the layer.
        let sync_validation = validate && {
            // SAFETY: enumeration query of the layer's extensions.
            let exts =
                unsafe { entry.enumerate_instance_extension_properties(Some(validation_layer)) }?;
            exts.iter()
                .any(|e| e.extension_name_as_c_str() == Ok(ash::ext::validation_features::NAME))
        };
        let mut ext_names = Vec::new();
        if has_debug {
            ext_names.push(ash::ext::debug_utils::NAME.as_ptr());
        }
        if sync_validation {
            ext_names.push(ash::ext::validation_features::NAME.as_ptr());
        }
        let layer_names = if validate {
            vec![validation_layer.as_ptr()]
        } else {
            Vec::new()
        };
        let app = vk::ApplicationInfo::default()
            .application_name(c"vgeo embed example")
            .api_version(reqs.api_version);
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layer_names)
            .enabled_extension_names(&ext_names);
        if sync_validation {
            info = info.push_next(&mut features);
        }
        // SAFETY: pointers to locals alive for the call.
        let instance = unsafe { entry.create_instance(&info, None) }?;
        let errors = Box::new(Errors(Mutex::new(Vec::new())));
        let debug = if has_debug && validate {
            let d = ash::ext::debug_utils::Instance::new(&entry, &instance);
            let ci = vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                        | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL,
                )
                .pfn_user_callback(Some(on_message))
                .user_data(&*errors as *const Errors as *mut c_void);
            // SAFETY: `errors` is boxed and outlives the messenger.
            let m = unsafe { d.create_debug_utils_messenger(&ci, None) }?;
            Some((d, m))
        } else {
            None
        };
        let (physical, queue_family) =
            pick_device(&instance)?.ok_or_else(|| anyhow!("no Vulkan 1.2 device"))?;
        // What vgeo needs (and the optional parts the device has), plus what the host itself uses
        // (dynamic rendering and synchronization2 are among vgeo's requirements already).
        let extensions = device_extensions_for_vgeo(&instance, physical)?;
        let supported = DeviceFeatures::supported(&instance, physical)?;
        let mut features = DeviceFeatures::for_vgeo(&supported)
            .map_err(|missing| anyhow!("the device lacks {missing:?}"))?;
        let names: Vec<*const std::ffi::c_char> = extensions.iter().map(|n| n.as_ptr()).collect();
        let prio = [1.0f32];
        let qinfo = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&prio)];
        let enabled = features;
        let info = features.chain(
            vk::DeviceCreateInfo::default()
                .queue_create_infos(&qinfo)
                .enabled_extension_names(&names),
        );
        // SAFETY: pointers to locals alive for the call.
        let device = unsafe { instance.create_device(physical, &info, None) }?;
        // SAFETY: queue 0 of the family the device was created with.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let hd = HostDevice {
            entry: entry.clone(),
            instance: instance.clone(),
            api_version: reqs.api_version,
            debug_utils: has_debug,
            physical_device: physical,
            device: device.clone(),
            device_extensions: extensions.iter().map(|n| CString::from(*n)).collect(),
            features: enabled,
            queue_family_index: queue_family,
            queue,
        };
        Ok((
            Host {
                entry,
                instance,
                debug,
                errors,
                physical,
                queue_family,
                device,
                queue,
                sync_validation,
            },
            hd,
        ))
    }

    fn memory_type(&self, bits: u32, flags: vk::MemoryPropertyFlags) -> Result<u32> {
        // SAFETY: query on a valid physical device.
        let props = unsafe {
            self.instance
                .get_physical_device_memory_properties(self.physical)
        };
        (0..props.memory_type_count)
            .find(|&i| {
                bits & (1 << i) != 0
                    && props.memory_types[i as usize]
                        .property_flags
                        .contains(flags)
            })
            .ok_or_else(|| anyhow!("no memory type {flags:?}"))
    }

    fn image(
        &self,
        width: u32,
        height: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<HostImg> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let d = &self.device;
        // SAFETY: valid create info; memory bound once, view over the whole image.
        unsafe {
            let image = d.create_image(&info, None)?;
            let req = d.get_image_memory_requirements(image);
            let mt =
                self.memory_type(req.memory_type_bits, vk::MemoryPropertyFlags::DEVICE_LOCAL)?;
            let memory = d.allocate_memory(
                &vk::MemoryAllocateInfo::default()
                    .allocation_size(req.size)
                    .memory_type_index(mt),
                None,
            )?;
            d.bind_image_memory(image, memory, 0)?;
            let view = d.create_image_view(
                &vk::ImageViewCreateInfo::default()
                    .image(image)
                    .view_type(vk::ImageViewType::TYPE_2D)
                    .format(format)
                    .subresource_range(range(aspect)),
                None,
            )?;
            Ok(HostImg {
                image,
                memory,
                view,
            })
        }
    }

    fn destroy_image(&self, i: &HostImg) {
        // SAFETY: the device is idle; the image is the host's.
        unsafe {
            self.device.destroy_image_view(i.view, None);
            self.device.destroy_image(i.image, None);
            self.device.free_memory(i.memory, None);
        }
    }

    fn errors(&self) -> Vec<String> {
        self.errors.0.lock().map(|e| e.clone()).unwrap_or_default()
    }

    fn destroy(self) {
        // SAFETY: vgeo's context is gone; the host destroys what it created, device first.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_device(None);
            if let Some((d, m)) = &self.debug {
                d.destroy_debug_utils_messenger(*m, None);
            }
            self.instance.destroy_instance(None);
        }
        let _ = &self.entry;
    }
}

fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

/// The host's GLSL: corners and colour in push constants, reverse-Z depth from vgeo's projection.
const VERT: &str = r#"#version 450
layout(push_constant) uniform Push { mat4 view_proj; vec4 corners[3]; vec4 color; } pc;
void main() { gl_Position = pc.view_proj * vec4(pc.corners[gl_VertexIndex].xyz, 1.0); }
"#;
const FRAG: &str = r#"#version 450
layout(push_constant) uniform Push { mat4 view_proj; vec4 corners[3]; vec4 color; } pc;
layout(location = 0) out vec4 out_color;
void main() { out_color = pc.color; }
"#;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Push {
    view_proj: [[f32; 4]; 4],
    corners: [[f32; 4]; 3],
    color: [f32; 4],
}
const _: () = assert!(size_of::<Push>() == 128);

/// The host's triangle pipeline (dynamic rendering, depth test GREATER: reverse-Z).
struct HostPipeline {
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
}

impl HostPipeline {
    fn new(device: &ash::Device) -> Result<Self> {
        let compiler = shaderc::Compiler::new().ok_or_else(|| anyhow!("shaderc"))?;
        let spv = |src: &str, kind, name: &str| -> Result<Vec<u32>> {
            Ok(compiler
                .compile_into_spirv(src, kind, name, "main", None)?
                .as_binary()
                .to_vec())
        };
        let vs = spv(VERT, shaderc::ShaderKind::Vertex, "host.vert")?;
        let fs = spv(FRAG, shaderc::ShaderKind::Fragment, "host.frag")?;
        // SAFETY: valid SPIR-V and create infos; modules destroyed after pipeline creation.
        unsafe {
            let vm = device
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&vs), None)?;
            let fm = device
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&fs), None)?;
            let ranges = [vk::PushConstantRange {
                stage_flags: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                offset: 0,
                size: size_of::<Push>() as u32,
            }];
            let layout = device.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&ranges),
                None,
            )?;
            let stages = [
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(vk::ShaderStageFlags::VERTEX)
                    .module(vm)
                    .name(c"main"),
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(vk::ShaderStageFlags::FRAGMENT)
                    .module(fm)
                    .name(c"main"),
            ];
            let vi = vk::PipelineVertexInputStateCreateInfo::default();
            let ia = vk::PipelineInputAssemblyStateCreateInfo::default()
                .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
            let vp = vk::PipelineViewportStateCreateInfo::default()
                .viewport_count(1)
                .scissor_count(1);
            let rs = vk::PipelineRasterizationStateCreateInfo::default()
                .polygon_mode(vk::PolygonMode::FILL)
                .cull_mode(vk::CullModeFlags::NONE)
                .line_width(1.0);
            let ms = vk::PipelineMultisampleStateCreateInfo::default()
                .rasterization_samples(vk::SampleCountFlags::TYPE_1);
            let ds = vk::PipelineDepthStencilStateCreateInfo::default()
                .depth_test_enable(true)
                .depth_write_enable(true)
                .depth_compare_op(vk::CompareOp::GREATER);
            let blend = [vk::PipelineColorBlendAttachmentState::default()
                .color_write_mask(vk::ColorComponentFlags::RGBA)];
            let cb = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
            let dynamic = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
            let dy = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
            let formats = [COLOR_FORMAT];
            let mut rendering = vk::PipelineRenderingCreateInfo::default()
                .color_attachment_formats(&formats)
                .depth_attachment_format(DEPTH_FORMAT);
            let info = vk::GraphicsPipelineCreateInfo::default()
                .stages(&stages)
                .vertex_input_state(&vi)
                .input_assembly_state(&ia)
                .viewport_state(&vp)
                .rasterization_state(&rs)
                .multisample_state(&ms)
                .depth_stencil_state(&ds)
                .color_blend_state(&cb)
                .dynamic_state(&dy)
                .layout(layout)
                .push_next(&mut rendering);
            let pipeline = device
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
                .map_err(|(_, e)| e)?[0];
            device.destroy_shader_module(vm, None);
            device.destroy_shader_module(fm, None);
            Ok(Self { layout, pipeline })
        }
    }

    fn destroy(&self, device: &ash::Device) {
        // SAFETY: the device is idle.
        unsafe {
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
        }
    }
}

/// One synchronization2 image barrier.
fn image_barrier(
    sync2: &ash::khr::synchronization2::Device,
    cb: vk::CommandBuffer,
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    (old, src_stage, src_access): (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
    (new, dst_stage, dst_access): (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
) {
    let b = [vk::ImageMemoryBarrier2::default()
        .src_stage_mask(src_stage)
        .src_access_mask(src_access)
        .dst_stage_mask(dst_stage)
        .dst_access_mask(dst_access)
        .old_layout(old)
        .new_layout(new)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(range(aspect))];
    // SAFETY: recording command buffer; synchronization2 is enabled (vgeo requires it).
    unsafe {
        sync2.cmd_pipeline_barrier2(cb, &vk::DependencyInfo::default().image_memory_barriers(&b))
    };
}

/// Renders `opts.frames` frames as a host would and returns the last one.
pub fn run(opts: &Options) -> Result<Output> {
    use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
    if opts.meshes.len() != 2 {
        bail!("two meshes, please (got {})", opts.meshes.len());
    }
    let built = build_meshes(&opts.meshes)?;
    let placements = placements(&built, opts.instances);
    let (host, hd) = Host::new(opts.validate)?;
    let dev = host.device.clone();
    // Vulkan 1.2 with the extensions (vgeo requires both; RenderDoc on lavapipe is 1.2).
    let sync2 = ash::khr::synchronization2::Device::new(&host.instance, &dev);
    let rendering = ash::khr::dynamic_rendering::Device::new(&host.instance, &dev);
    let (w, h) = (opts.width, opts.height);
    let color_aspect = vk::ImageAspectFlags::COLOR;
    let depth_aspect = vk::ImageAspectFlags::DEPTH;
    let color = host.image(
        w,
        h,
        COLOR_FORMAT,
        vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC,
        color_aspect,
    )?;
    let depth = host.image(
        w,
        h,
        DEPTH_FORMAT,
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST,
        depth_aspect,
    )?;
    let pipeline = HostPipeline::new(&dev)?;
    // The read-back of the last frame: colour (4 bytes) and depth (4 bytes) per pixel.
    let rb_size = 8 * w as u64 * h as u64;
    // SAFETY: a host-visible buffer for the final read-back, bound once.
    let (rb, rb_mem) = unsafe {
        let b = dev.create_buffer(
            &vk::BufferCreateInfo::default()
                .size(rb_size)
                .usage(vk::BufferUsageFlags::TRANSFER_DST),
            None,
        )?;
        let req = dev.get_buffer_memory_requirements(b);
        let mt = host.memory_type(
            req.memory_type_bits,
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
        )?;
        let m = dev.allocate_memory(
            &vk::MemoryAllocateInfo::default()
                .allocation_size(req.size)
                .memory_type_index(mt),
            None,
        )?;
        dev.bind_buffer_memory(b, m, 0)?;
        (b, m)
    };
    // Per frame in flight: a command buffer and a fence.
    let nf = opts.frames_in_flight.max(1);
    // SAFETY: pool, command buffers and signalled fences on the host's device.
    let (pool, cbs, fences) = unsafe {
        let pool = dev.create_command_pool(
            &vk::CommandPoolCreateInfo::default()
                .queue_family_index(host.queue_family)
                .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER),
            None,
        )?;
        let cbs = dev.allocate_command_buffers(
            &vk::CommandBufferAllocateInfo::default()
                .command_pool(pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(nf),
        )?;
        let fences = (0..nf)
            .map(|_| {
                dev.create_fence(
                    &vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED),
                    None,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        (pool, cbs, fences)
    };

    let ctx = Context::from_host(hd, false)?;
    let (mut renderer, mut streamer) = match opts.geometry_budget {
        None => (VgeoRenderer::new(&ctx, &built, &placements)?, None),
        Some(budget_bytes) => {
            // Only the always-resident pages at first; the rest comes at the GPU's request.
            let sources: Vec<(BuiltMesh, Box<dyn vgeo::PageSource>)> = built
                .iter()
                .map(|m| (m.clone(), Box::new(m.clone()) as Box<dyn vgeo::PageSource>))
                .collect();
            let stream_opts = vgeo::StreamOptions {
                budget_bytes,
                upload_bytes_per_frame: 4 << 20,
            };
            let (r, s) = VgeoRenderer::streamed(&ctx, sources, &placements, stream_opts)?;
            (r, Some(s))
        }
    };
    let mut stream = streamer.as_ref().map(|_| StreamSummary::default());
    let mut view: View = renderer.create_view("main", w, h, nf)?;
    // Handles of the instances, by their placement (slot j is placement j in a new renderer).
    let handles = (0..placements.len() as u32)
        .map(|j| renderer.scene.instance_handle(j))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| anyhow!("an instance without a handle"))?;
    let bg = vgeo::BACKGROUND.map(|c| c.clamp(0.0, 1.0).powf(1.0 / 2.2));
    let tris = host_triangles();
    let mut stats_frames = 0;
    let mut last_triangles = 0;
    let mut camera = camera_at(0);
    let result = (|| -> Result<()> {
        for i in 0..opts.frames {
            let slot = (i % nf) as usize;
            let (cb, fence) = (cbs[slot], fences[slot]);
            // SAFETY: the slot's previous submission is waited for before its buffer is reused.
            unsafe {
                dev.wait_for_fences(&[fence], true, u64::MAX)?;
                dev.reset_fences(&[fence])?;
            }
            // That frame (nf frames ago) is done: its stats are there without waiting.
            if i >= nf
                && let Some(s) = view.try_stats((i - nf) as u64)?
            {
                s.check().map_err(|e| anyhow!(e))?;
                stats_frames += 1;
                last_triangles = s.triangles();
            }
            // Streaming: the page feedback of the frames done so far, loads and evictions
            // staged for this frame's `update_scene`.
            if let (Some(st), Some(sum)) = (streamer.as_mut(), stream.as_mut()) {
                let waits = ctx.waited_submissions();
                let step = st.update(&mut renderer.scene)?;
                sum.waits += ctx.waited_submissions() - waits;
                sum.uploads += step.uploads;
                sum.evictions += step.evictions;
                sum.last_requests = step.requests;
                sum.last_settled = step.settled();
                sum.peak_resident_bytes = sum.peak_resident_bytes.max(step.resident_bytes);
                if let Some(e) = st.take_errors().first() {
                    bail!("streaming: {e}");
                }
            }
            // The pose of the scene this frame (it stops changing at `still_from`).
            let t = opts.still_from.map_or(i, |k| i.min(k));
            camera = camera_orbit(t, opts.orbit);
            let vp = camera.view_proj(w, h);
            let last = i + 1 == opts.frames;
            // SAFETY: recording the slot's command buffer, idle since the fence wait.
            unsafe {
                dev.reset_command_buffer(cb, vk::CommandBufferResetFlags::empty())?;
                dev.begin_command_buffer(
                    cb,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )?;
            }
            // The host's pass before vgeo: clear, and draw the first triangle.
            let any = (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE);
            image_barrier(
                &sync2,
                cb,
                color.image,
                color_aspect,
                (L::UNDEFINED, any.0, any.1),
                (
                    L::COLOR_ATTACHMENT_OPTIMAL,
                    S::COLOR_ATTACHMENT_OUTPUT,
                    A::COLOR_ATTACHMENT_WRITE | A::COLOR_ATTACHMENT_READ,
                ),
            );
            let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
            let ds_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
            image_barrier(
                &sync2,
                cb,
                depth.image,
                depth_aspect,
                (L::UNDEFINED, any.0, any.1),
                (L::DEPTH_ATTACHMENT_OPTIMAL, tests, ds_rw),
            );
            let draw = |load: bool, which: &[usize]| {
                let op = if load {
                    vk::AttachmentLoadOp::LOAD
                } else {
                    vk::AttachmentLoadOp::CLEAR
                };
                let ca = [vk::RenderingAttachmentInfo::default()
                    .image_view(color.view)
                    .image_layout(L::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(op)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue {
                        color: vk::ClearColorValue { float32: bg },
                    })];
                let da = vk::RenderingAttachmentInfo::default()
                    .image_view(depth.view)
                    .image_layout(L::DEPTH_ATTACHMENT_OPTIMAL)
                    .load_op(op)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue {
                        depth_stencil: vk::ClearDepthStencilValue {
                            depth: 0.0,
                            stencil: 0,
                        },
                    });
                let area = vk::Rect2D {
                    offset: vk::Offset2D { x: 0, y: 0 },
                    extent: vk::Extent2D {
                        width: w,
                        height: h,
                    },
                };
                let info = vk::RenderingInfo::default()
                    .render_area(area)
                    .layer_count(1)
                    .color_attachments(&ca)
                    .depth_attachment(&da);
                // SAFETY: recording; attachments in the layouts named; the pipeline matches.
                unsafe {
                    rendering.cmd_begin_rendering(cb, &info);
                    dev.cmd_set_viewport(
                        cb,
                        0,
                        &[vk::Viewport {
                            x: 0.0,
                            y: 0.0,
                            width: w as f32,
                            height: h as f32,
                            min_depth: 0.0,
                            max_depth: 1.0,
                        }],
                    );
                    dev.cmd_set_scissor(cb, 0, &[area]);
                    dev.cmd_bind_pipeline(cb, vk::PipelineBindPoint::GRAPHICS, pipeline.pipeline);
                    for &t in which {
                        let (corners, col) = tris[t];
                        // Camera-relative corners, as vgeo's projection expects.
                        let rel = corners.map(|c| {
                            let p = DVec3::from(c.map(f64::from)) - camera.position;
                            [p.x as f32, p.y as f32, p.z as f32, 1.0]
                        });
                        let push = Push {
                            view_proj: vp.to_cols_array_2d(),
                            corners: rel,
                            color: col,
                        };
                        dev.cmd_push_constants(
                            cb,
                            pipeline.layout,
                            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                            0,
                            bytemuck::bytes_of(&push),
                        );
                        dev.cmd_draw(cb, 3, 1, 0, 0);
                    }
                    rendering.cmd_end_rendering(cb);
                }
            };
            draw(false, if opts.host_draws { &[0] } else { &[] });
            // vgeo's frame: reads the host's depth, draws, writes depth back and lights its pixels.
            let frame = ViewFrame {
                frame: i as u64,
                camera: &camera,
                settings: FrameSettings::default(),
                light: Light::default(),
                shade: ShadeMode::Lit,
                targets: HostTargets {
                    depth: Some(HostImage {
                        image: depth.image,
                        view: depth.view,
                        format: DEPTH_FORMAT,
                        width: w,
                        height: h,
                        layout: L::DEPTH_ATTACHMENT_OPTIMAL,
                    }),
                    color: Some(HostImage {
                        image: color.image,
                        view: color.view,
                        format: COLOR_FORMAT,
                        width: w,
                        height: h,
                        layout: L::COLOR_ATTACHMENT_OPTIMAL,
                    }),
                    gbuffer: None,
                },
            };
            if opts.vgeo_draws {
                // Every instance moves: O(changed) staging, one copy recorded before the frame.
                for (j, (&h, p)) in handles.iter().zip(&placements).enumerate() {
                    renderer
                        .scene
                        .set_transform(h, &transform_at(p, j as u32, t))?;
                }
                // SAFETY: `cb` is recording, outside a render pass; the images and vgeo's objects
                // live until the device is idle at the end.
                unsafe {
                    renderer.update_scene(cb, &mut [&mut view])?;
                    renderer.record(cb, &mut view, &frame)?;
                }
            }
            // The host's pass after vgeo: the second triangle, depth-tested against vgeo's.
            if opts.host_draws {
                draw(true, &[1]);
            }
            if last {
                // Read back colour and depth.
                image_barrier(
                    &sync2,
                    cb,
                    color.image,
                    color_aspect,
                    (
                        L::COLOR_ATTACHMENT_OPTIMAL,
                        S::COLOR_ATTACHMENT_OUTPUT,
                        A::COLOR_ATTACHMENT_WRITE,
                    ),
                    (L::TRANSFER_SRC_OPTIMAL, S::ALL_TRANSFER, A::TRANSFER_READ),
                );
                image_barrier(
                    &sync2,
                    cb,
                    depth.image,
                    depth_aspect,
                    (L::DEPTH_ATTACHMENT_OPTIMAL, tests, ds_rw),
                    (L::TRANSFER_SRC_OPTIMAL, S::ALL_TRANSFER, A::TRANSFER_READ),
                );
                let region = |offset: u64, aspect| {
                    vk::BufferImageCopy::default()
                        .buffer_offset(offset)
                        .image_subresource(vk::ImageSubresourceLayers {
                            aspect_mask: aspect,
                            mip_level: 0,
                            base_array_layer: 0,
                            layer_count: 1,
                        })
                        .image_extent(vk::Extent3D {
                            width: w,
                            height: h,
                            depth: 1,
                        })
                };
                let mb = [vk::MemoryBarrier2::default()
                    .src_stage_mask(S::ALL_TRANSFER)
                    .src_access_mask(A::TRANSFER_WRITE)
                    .dst_stage_mask(S::HOST)
                    .dst_access_mask(A::HOST_READ)];
                // SAFETY: images in TRANSFER_SRC layout; the buffer holds both.
                unsafe {
                    dev.cmd_copy_image_to_buffer(
                        cb,
                        color.image,
                        L::TRANSFER_SRC_OPTIMAL,
                        rb,
                        &[region(0, color_aspect)],
                    );
                    dev.cmd_copy_image_to_buffer(
                        cb,
                        depth.image,
                        L::TRANSFER_SRC_OPTIMAL,
                        rb,
                        &[region(4 * w as u64 * h as u64, depth_aspect)],
                    );
                    sync2.cmd_pipeline_barrier2(
                        cb,
                        &vk::DependencyInfo::default().memory_barriers(&mb),
                    );
                }
            }
            // SAFETY: recording ends; submitted with the slot's fence.
            unsafe {
                dev.end_command_buffer(cb)?;
                let cbs_ = [cb];
                let submit = vk::SubmitInfo::default().command_buffers(&cbs_);
                dev.queue_submit(host.queue, &[submit], fence)?;
            }
        }
        // SAFETY: the last submissions finish; then the read-back is visible to the host.
        unsafe { dev.wait_for_fences(&fences, true, u64::MAX)? };
        for i in opts.frames.saturating_sub(nf)..opts.frames {
            if let Some(s) = view.try_stats(i as u64)? {
                s.check().map_err(|e| anyhow!(e))?;
                stats_frames += 1;
                last_triangles = s.triangles();
            }
        }
        Ok(())
    })();
    let mut out_color = Vec::new();
    let mut out_depth = Vec::new();
    if result.is_ok() {
        // SAFETY: the memory is host-visible and coherent; the GPU is done with it.
        unsafe {
            let p = dev.map_memory(rb_mem, 0, rb_size, vk::MemoryMapFlags::empty())?;
            let bytes = std::slice::from_raw_parts(p as *const u8, rb_size as usize);
            let n = 4 * (w * h) as usize;
            out_color = bytes[..n].to_vec();
            out_depth = bytes[n..2 * n]
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect();
            dev.unmap_memory(rb_mem);
        }
    }
    // vgeo goes first (it waits for the device), then the host's objects.
    drop(view);
    drop(renderer);
    drop(ctx);
    // SAFETY: the device is idle (vgeo waited when its context dropped).
    unsafe {
        let _ = dev.device_wait_idle();
        for f in &fences {
            dev.destroy_fence(*f, None);
        }
        dev.destroy_command_pool(pool, None);
        dev.destroy_buffer(rb, None);
        dev.free_memory(rb_mem, None);
    }
    pipeline.destroy(&dev);
    host.destroy_image(&color);
    host.destroy_image(&depth);
    let validation_errors = host.errors();
    let sync_validation = host.sync_validation;
    host.destroy();
    result?;
    // The last frame's places (what a fresh render of the same scene must show).
    let last_frame = opts.frames.saturating_sub(1);
    let last_frame = opts.still_from.map_or(last_frame, |k| last_frame.min(k));
    let placements = placements
        .iter()
        .enumerate()
        .map(|(j, p)| Placement {
            transform: transform_at(p, j as u32, last_frame),
            ..*p
        })
        .collect();
    let out = Output {
        width: w,
        height: h,
        color: out_color,
        depth: out_depth,
        camera,
        built,
        placements,
        validation_errors,
        stats_frames,
        last_triangles,
        sync_validation,
        stream,
    };
    if let Some(path) = &opts.out {
        image::save_buffer(path, &out.color, w, h, image::ColorType::Rgba8)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(out)
}

fn parse_args() -> Result<Options> {
    let mut o = Options::default();
    let mut meshes = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or_else(|| anyhow!("{a} needs a value"));
        match a.as_str() {
            "--out" => o.out = Some(PathBuf::from(value()?)),
            "--frames" => o.frames = value()?.parse()?,
            "--instances" => o.instances = value()?.parse()?,
            "--frames-in-flight" => o.frames_in_flight = value()?.parse()?,
            "--size" => {
                let v = value()?;
                let (x, y) = v.split_once('x').ok_or_else(|| anyhow!("--size WxH"))?;
                (o.width, o.height) = (x.parse()?, y.parse()?);
            }
            "--mesh" => meshes.push(value()?),
            "--no-host-draws" => o.host_draws = false,
            "--no-vgeo" => o.vgeo_draws = false,
            "--validate" => o.validate = true,
            "--geometry-budget" => o.geometry_budget = Some(value()?.parse::<u64>()? << 20),
            "--still-from" => o.still_from = Some(value()?.parse()?),
            "--orbit" => o.orbit = value()?.parse()?,
            other => bail!("unknown argument {other}"),
        }
    }
    if !meshes.is_empty() {
        o.meshes = meshes;
    }
    Ok(o)
}

#[allow(dead_code)]
fn main() -> Result<()> {
    let opts = parse_args()?;
    let out = run(&opts)?;
    println!(
        "{} frames of {}x{} ({} in flight), {} instances; stats of {} frames came back, last: {} triangles",
        opts.frames,
        out.width,
        out.height,
        opts.frames_in_flight,
        opts.instances,
        out.stats_frames,
        out.last_triangles
    );
    if let Some(st) = &out.stream {
        println!(
            "streaming: {} uploads, {} evictions, peak {:.1} MiB resident, {} requests in the last step, {} waits",
            st.uploads,
            st.evictions,
            st.peak_resident_bytes as f64 / (1 << 20) as f64,
            st.last_requests,
            st.waits
        );
    }
    if let Some(p) = &opts.out {
        println!("wrote {}", p.display());
    }
    if !out.validation_errors.is_empty() {
        bail!("{} validation errors", out.validation_errors.len());
    }
    Ok(())
}
