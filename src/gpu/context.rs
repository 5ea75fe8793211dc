//! Instance, device, queue, allocator, debug messenger and one-shot submission: the context on a
//! host's device ([`Context::from_host`]) or on one vgeo creates ([`Context::new`], the same path).

use std::ffi::{CStr, CString, c_void};
use std::sync::{Arc, Mutex};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::{Cmd, GpuError, GpuResult, VkResultExt};

/// How to create a [`Context`].
#[derive(Clone, Debug, Default)]
pub struct ContextOptions {
    /// Enable `VK_LAYER_KHRONOS_validation` and collect its errors (also: `VGEO_VALIDATION=1`).
    pub validation: bool,
    /// Also enable synchronization validation (slow).
    pub sync_validation: bool,
    /// Pick the first device whose name contains this (also: `VGEO_DEVICE=<substring>`).
    pub device_filter: Option<String>,
    /// Compile the GLSL in this folder at start-up in place of the built-in shaders
    /// (`--shader-dir`, also `VGEO_SHADER_DIR`; see [`Context::use_shader_dir`]).
    pub shader_dir: Option<std::path::PathBuf>,
}

impl ContextOptions {
    /// Options from the environment: `VGEO_VALIDATION`, `VGEO_SYNC_VALIDATION`, `VGEO_DEVICE`,
    /// `VGEO_SHADER_DIR`.
    pub fn from_env() -> Self {
        let flag = |k: &str| std::env::var(k).is_ok_and(|v| !v.is_empty() && v != "0");
        Self {
            validation: flag("VGEO_VALIDATION") || flag("VGEO_SYNC_VALIDATION"),
            sync_validation: flag("VGEO_SYNC_VALIDATION"),
            device_filter: std::env::var("VGEO_DEVICE").ok().filter(|s| !s.is_empty()),
            shader_dir: shader_dir_from_env(),
        }
    }
}

/// What the chosen device is and can do.
#[derive(Clone, Debug)]
pub struct Caps {
    /// The device's name.
    pub device_name: String,
    /// Discrete, integrated, virtual, cpu or other.
    pub device_type: String,
    /// The driver's name (VK_KHR_driver_properties).
    pub driver_name: String,
    /// The driver's version string.
    pub driver_info: String,
    /// The device's Vulkan version (major.minor.patch).
    pub api_version: String,
    /// `shaderInt64` (required).
    pub shader_int64: bool,
    /// `shaderBufferInt64Atomics` (required: the buffer visibility buffer).
    pub buffer_int64_atomics: bool,
    /// `VK_EXT_shader_image_atomic_int64`: the R64 visibility-buffer image path.
    pub image_int64_atomics: bool,
    /// `VK_EXT_mesh_shader` with `meshShader` enabled on the device: `raster_hw` can take its mesh
    /// path (`--hw-path auto|mesh`); without it, vertex pulling.
    pub mesh_shader: bool,
    /// `VK_KHR_pipeline_executable_properties` with `pipelineExecutableInfo` enabled: with
    /// `VGEO_PIPELINE_STATS=1` each pipeline's compiled statistics (registers, shared memory, ...,
    /// as the driver names them) are printed as it is created.
    pub pipeline_statistics: bool,
    /// `multiDrawIndirect` (required).
    pub multi_draw_indirect: bool,
    /// `drawIndirectCount` (required).
    pub draw_indirect_count: bool,
    /// Nanoseconds per timestamp tick; `None` when the queue has no timestamps.
    pub timestamp_period_ns: Option<f32>,
    /// The subgroup size of compute shaders.
    pub subgroup_size: u32,
    /// `maxComputeWorkGroupCount`.
    pub max_compute_workgroups: [u32; 3],
    /// `maxImageDimension2D`: the largest side of a 2D image (at least 4096).
    pub max_image_dimension_2d: u32,
    /// `maxStorageBufferRange`: the largest storage buffer a shader may bind (the geometry pool
    /// is one).
    pub max_storage_buffer_range: u32,
    /// Bytes of the device's largest device-local memory heap (`auto` geometry budgets are a
    /// share of it, at most `max_storage_buffer_range`; on a CPU device such as lavapipe,
    /// system memory).
    pub device_local_bytes: u64,
    /// Whether vgeo's validation messenger collects errors.
    pub validation: bool,
    /// Tools hooked into Vulkan (`VK_EXT_tooling_info`: RenderDoc, the validation layer), by name
    /// and version.
    pub tools: Vec<String>,
    /// What vgeo does without an optional extension or feature it uses (a tool such as RenderDoc
    /// may hide one it cannot capture): one line each.
    pub fallbacks: Vec<String>,
}

impl std::fmt::Display for Caps {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let yn = |b: bool| if b { "yes" } else { "no" };
        writeln!(
            f,
            "device:                {} ({})",
            self.device_name, self.device_type
        )?;
        writeln!(
            f,
            "driver:                {} {}",
            self.driver_name, self.driver_info
        )?;
        writeln!(f, "Vulkan API:            {}", self.api_version)?;
        writeln!(f, "shaderInt64:           {}", yn(self.shader_int64))?;
        writeln!(
            f,
            "64-bit buffer atomics: {}",
            yn(self.buffer_int64_atomics)
        )?;
        writeln!(
            f,
            "64-bit image atomics:  {} (VK_EXT_shader_image_atomic_int64)",
            yn(self.image_int64_atomics)
        )?;
        writeln!(f, "mesh shaders:          {}", yn(self.mesh_shader))?;
        writeln!(
            f,
            "pipeline statistics:   {} (VK_KHR_pipeline_executable_properties; VGEO_PIPELINE_STATS=1 \
             prints them)",
            yn(self.pipeline_statistics)
        )?;
        writeln!(f, "multiDrawIndirect:     {}", yn(self.multi_draw_indirect))?;
        writeln!(f, "drawIndirectCount:     {}", yn(self.draw_indirect_count))?;
        if !self.tools.is_empty() {
            writeln!(f, "tools:                 {}", self.tools.join(", "))?;
        }
        for fb in &self.fallbacks {
            writeln!(f, "fallback:              {fb}")?;
        }
        match self.timestamp_period_ns {
            Some(p) => writeln!(f, "timestamps:            yes ({p} ns/tick)")?,
            None => writeln!(f, "timestamps:            no")?,
        }
        writeln!(f, "subgroup size:         {}", self.subgroup_size)?;
        writeln!(
            f,
            "device-local memory:   {:.2} GiB (largest heap)",
            self.device_local_bytes as f64 / (1u64 << 30) as f64
        )?;
        write!(
            f,
            "validation:            {}",
            if self.validation { "on" } else { "off" }
        )
    }
}

pub(crate) struct Inner {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub debug_device: Option<ash::ext::debug_utils::Device>,
    pub device: ash::Device,
    pub push_descriptor: ash::khr::push_descriptor::Device,
    pub dynamic_rendering: ash::khr::dynamic_rendering::Device,
    pub sync2: ash::khr::synchronization2::Device,
    /// `VK_EXT_mesh_shader`'s commands, when enabled ([`Caps::mesh_shader`]).
    pub mesh_shader: Option<ash::ext::mesh_shader::Device>,
    /// `VK_KHR_pipeline_executable_properties`' commands, when enabled and asked for
    /// (`VGEO_PIPELINE_STATS=1`; [`Caps::pipeline_statistics`]).
    pub pipeline_executable: Option<ash::khr::pipeline_executable_properties::Device>,
    pub queue: vk::Queue,
    pub allocator: Mutex<Option<Allocator>>,
    pub caps: Caps,
    /// vgeo's validation messenger (vgeo's: destroyed by vgeo, on the host's instance too).
    validation: Option<Validation>,
    /// The instance and device when vgeo created them (headless); `None` for a host's.
    owned: bool,
    pub last_pass: Mutex<String>,
    pool: Mutex<vk::CommandPool>,
    /// Shaders compiled from a folder (`--shader-dir`), set once before pipelines are made.
    shaders: std::sync::OnceLock<super::shader_dir::ShaderOverrides>,
    /// Submissions vgeo made and waited for ([`Context::submit_and_wait`]).
    waits: std::sync::atomic::AtomicU64,
}

/// `VGEO_SHADER_DIR`, when set and not empty.
fn shader_dir_from_env() -> Option<std::path::PathBuf> {
    std::env::var_os("VGEO_SHADER_DIR")
        .filter(|s| !s.is_empty())
        .map(Into::into)
}

#[derive(Default)]
struct Messages {
    errors: Mutex<Vec<String>>,
}

/// A debug messenger vgeo created that stores validation errors.
struct Validation {
    debug_instance: ash::ext::debug_utils::Instance,
    messenger: vk::DebugUtilsMessengerEXT,
    messages: Box<Messages>,
}

impl Validation {
    /// A messenger on `instance` (which must have `VK_EXT_debug_utils` enabled).
    fn new(entry: &ash::Entry, instance: &ash::Instance) -> GpuResult<Self> {
        let debug_instance = ash::ext::debug_utils::Instance::new(entry, instance);
        let messages = Box::<Messages>::default();
        let ci = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                    | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE
                    | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL,
            )
            .pfn_user_callback(Some(debug_callback))
            .user_data(&*messages as *const Messages as *mut c_void);
        // SAFETY: `messages` is boxed and kept with the messenger, which is destroyed first.
        let messenger = unsafe { debug_instance.create_debug_utils_messenger(&ci, None) }
            .call("vkCreateDebugUtilsMessengerEXT")?;
        Ok(Self {
            debug_instance,
            messenger,
            messages,
        })
    }

    /// Destroys the messenger (before its instance).
    fn destroy(&self) {
        // SAFETY: the messenger belongs to this instance and is destroyed once, by its owner.
        unsafe {
            self.debug_instance
                .destroy_debug_utils_messenger(self.messenger, None)
        };
    }
}

/// A Vulkan device that a host (an engine) created for vgeo to run on, with what it enabled.
///
/// The host creates the instance and device with at least what [`super::requirements`] lists
/// (for example with [`super::device_extensions_for_vgeo`] and [`super::DeviceFeatures::for_vgeo`]
/// chained by [`super::DeviceFeatures::chain`]), fills this in, and calls [`Context::from_host`].
/// **Ownership:** the handles stay the host's. vgeo never destroys the instance, the device or the
/// queue; it destroys only what it creates on them (allocator memory, command pool, pipelines,
/// buffers, its debug messenger), all before the last [`Context`] clone drops (it waits for the
/// device to be idle then). The host destroys the device and instance after that.
/// **Queue:** vgeo submits to `queue` (one-shot submissions of its own paths); the host must not
/// use the queue from another thread while a vgeo call runs (Vulkan's external synchronization).
pub struct HostDevice {
    /// The loader the instance came from.
    pub entry: ash::Entry,
    /// The host's instance.
    pub instance: ash::Instance,
    /// The instance's `VkApplicationInfo::apiVersion` (at least 1.2).
    pub api_version: u32,
    /// Whether the instance has `VK_EXT_debug_utils` enabled (names, labels, validation messages).
    pub debug_utils: bool,
    /// The physical device the device was created on.
    pub physical_device: vk::PhysicalDevice,
    /// The host's device.
    pub device: ash::Device,
    /// The device extensions the device was created with.
    pub device_extensions: Vec<CString>,
    /// The features the device was created with (at least those of [`super::requirements`]).
    pub features: super::DeviceFeatures,
    /// A queue family with graphics and compute.
    pub queue_family_index: u32,
    /// A queue of that family.
    pub queue: vk::Queue,
}

/// The Vulkan context. Cheap to clone (shared); resources keep it alive.
#[derive(Clone)]
pub struct Context {
    pub(crate) inner: Arc<Inner>,
}

unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data for the duration of the call; `user` is the
    // `Messages` box owned by the context, which outlives the messenger.
    let (msg, messages) = unsafe {
        let d = &*data;
        let msg = if d.p_message.is_null() {
            String::from("(no message)")
        } else {
            CStr::from_ptr(d.p_message).to_string_lossy().into_owned()
        };
        (msg, &*(user as *const Messages))
    };
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        eprintln!("[vulkan validation error] {msg}");
        if let Ok(mut e) = messages.errors.lock() {
            e.push(msg);
        }
    } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
        eprintln!("[vulkan validation warning] {msg}");
    }
    vk::FALSE
}

fn cstr_array(chars: &[std::ffi::c_char]) -> String {
    // SAFETY: Vulkan fixed-size name arrays are NUL-terminated within their length.
    unsafe { CStr::from_ptr(chars.as_ptr()) }
        .to_string_lossy()
        .into_owned()
}

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Handles the headless path created, destroyed in reverse order if construction fails.
struct Headless {
    entry: ash::Entry,
    instance: ash::Instance,
    debug_utils: bool,
    validation: Option<Validation>,
}

impl Headless {
    fn destroy(self) {
        if let Some(v) = &self.validation {
            v.destroy();
        }
        // SAFETY: nothing else created from the instance is alive.
        unsafe { self.instance.destroy_instance(None) };
    }
}

impl Context {
    /// Creates a headless context (no window, no surface): vgeo creates an instance and a device
    /// with what [`super::requirements`] lists (and the optional parts the device has), then
    /// continues as [`Context::from_host`] does, owning (and at the end destroying) both.
    pub fn new(opts: &ContextOptions) -> GpuResult<Self> {
        let headless = Self::headless_instance(opts)?;
        let picked = Self::pick_device(&headless.instance, opts.device_filter.as_deref())
            .and_then(|(pd, qf)| Self::headless_device(&headless.instance, pd, qf));
        let (physical, queue_family, device, device_extensions, features) = match picked {
            Ok(p) => p,
            Err(e) => {
                headless.destroy();
                return Err(e);
            }
        };
        // SAFETY: queue 0 of the family the device was created with.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let host = HostDevice {
            entry: headless.entry.clone(),
            instance: headless.instance.clone(),
            api_version: vk::API_VERSION_1_2,
            debug_utils: headless.debug_utils,
            physical_device: physical,
            device: device.clone(),
            device_extensions: device_extensions.iter().map(|n| (*n).to_owned()).collect(),
            features,
            queue_family_index: queue_family,
            queue,
        };
        let mut headless = headless;
        match Self::from_host_with(host, &mut headless) {
            Ok(ctx) => {
                if let Some(dir) = &opts.shader_dir {
                    ctx.use_shader_dir(dir)?;
                }
                Ok(ctx)
            }
            Err(e) => {
                // SAFETY: the device is idle and nothing created on it is alive (the failed
                // constructor destroyed what it made).
                unsafe { device.destroy_device(None) };
                headless.destroy();
                Err(e)
            }
        }
    }

    /// The headless instance (Vulkan 1.2; debug utils when present; the validation layer and its
    /// messenger when asked).
    fn headless_instance(opts: &ContextOptions) -> GpuResult<Headless> {
        // SAFETY: loading the system Vulkan loader; its symbols are used through ash's tables only.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| GpuError::Loader(e.to_string()))?;

        // SAFETY: plain enumeration query.
        let layers = unsafe { entry.enumerate_instance_layer_properties() }
            .call("vkEnumerateInstanceLayerProperties")?;
        let have_validation = layers
            .iter()
            .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER));
        if opts.validation && !have_validation {
            return Err(GpuError::Other(
                "validation was requested but VK_LAYER_KHRONOS_validation is not installed (apt-get install vulkan-validationlayers)".into(),
            ));
        }
        // SAFETY: plain enumeration query.
        let inst_exts = unsafe { entry.enumerate_instance_extension_properties(None) }
            .call("vkEnumerateInstanceExtensionProperties")?;
        let reqs = super::requirements();
        let has_inst_ext = |n: &CStr| {
            inst_exts
                .iter()
                .any(|e| e.extension_name_as_c_str().is_ok_and(|x| x == n))
        };
        let missing: Vec<String> = (reqs.instance_extensions.iter())
            .filter(|n| !has_inst_ext(n))
            .map(|n| format!("instance extension {}", n.to_string_lossy()))
            .collect();
        if !missing.is_empty() {
            return Err(GpuError::Unsupported { missing });
        }
        let mut ext_names: Vec<*const std::ffi::c_char> = reqs
            .instance_extensions
            .iter()
            .map(|n| n.as_ptr())
            .collect();
        ext_names.extend(
            (reqs.optional_instance_extensions.iter())
                .filter(|n| has_inst_ext(n))
                .map(|n| n.as_ptr()),
        );
        let debug_utils = has_inst_ext(ash::ext::debug_utils::NAME);

        let app_name = c"vgeo";
        let app = vk::ApplicationInfo::default()
            .application_name(app_name)
            .engine_name(app_name)
            .api_version(reqs.api_version);
        let layer_names = if opts.validation {
            vec![VALIDATION_LAYER.as_ptr()]
        } else {
            vec![]
        };
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_extension_names(&ext_names)
            .enabled_layer_names(&layer_names);
        if opts.validation && opts.sync_validation {
            info = info.push_next(&mut features);
        }
        // SAFETY: all pointers in `info` point to locals alive for the call.
        let instance = unsafe { entry.create_instance(&info, None) }.call("vkCreateInstance")?;
        let mut headless = Headless {
            entry,
            instance,
            debug_utils,
            validation: None,
        };
        // The messenger exists before the device, so device creation is validated too.
        if opts.validation && debug_utils {
            match Validation::new(&headless.entry, &headless.instance) {
                Ok(v) => headless.validation = Some(v),
                Err(e) => {
                    headless.destroy();
                    return Err(e);
                }
            }
        }
        Ok(headless)
    }

    /// The headless device on `physical`: [`super::requirements`]' extensions and features (an
    /// error naming what the device lacks) and the optional ones it has.
    #[allow(clippy::type_complexity)]
    fn headless_device(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        queue_family: u32,
    ) -> GpuResult<(
        vk::PhysicalDevice,
        u32,
        ash::Device,
        Vec<&'static CStr>,
        super::DeviceFeatures,
    )> {
        // SAFETY: a query on a valid physical device.
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let device_name = cstr_array(&props.device_name);
        let extensions =
            super::device_extensions_for_vgeo(instance, physical).map_err(|e| match e {
                GpuError::Unsupported { missing } => GpuError::NoDevice(format!(
                    "{device_name} lacks required extensions {:?}",
                    missing
                        .iter()
                        .map(|m| m.trim_start_matches("device extension "))
                        .collect::<Vec<_>>()
                )),
                e => e,
            })?;
        let supported = super::DeviceFeatures::supported(instance, physical)?;
        let features = super::DeviceFeatures::for_vgeo(&supported).map_err(|missing| {
            GpuError::NoDevice(format!(
                "{device_name} lacks required features {:?}",
                missing.iter().map(|f| f.name).collect::<Vec<_>>()
            ))
        })?;
        let mut enable = features;
        let ext_names: Vec<*const std::ffi::c_char> =
            extensions.iter().map(|n| n.as_ptr()).collect();
        let prio = [1.0f32];
        let qinfo = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&prio)];
        let dinfo = enable.chain(
            vk::DeviceCreateInfo::default()
                .queue_create_infos(&qinfo)
                .enabled_extension_names(&ext_names),
        );
        // SAFETY: every pointer in `dinfo` refers to locals alive for the call.
        let device =
            unsafe { instance.create_device(physical, &dinfo, None) }.call("vkCreateDevice")?;
        Ok((physical, queue_family, device, extensions, features))
    }

    fn pick_device(
        instance: &ash::Instance,
        filter: Option<&str>,
    ) -> GpuResult<(vk::PhysicalDevice, u32)> {
        // SAFETY: enumeration on a valid instance.
        let devices =
            unsafe { instance.enumerate_physical_devices() }.call("vkEnumeratePhysicalDevices")?;
        let mut candidates = Vec::new();
        let mut names = Vec::new();
        for pd in devices {
            // SAFETY: queries on a valid physical device.
            let (props, families) = unsafe {
                (
                    instance.get_physical_device_properties(pd),
                    instance.get_physical_device_queue_family_properties(pd),
                )
            };
            let name = cstr_array(&props.device_name);
            names.push(name.clone());
            if let Some(f) = filter
                && !name.to_lowercase().contains(&f.to_lowercase())
            {
                continue;
            }
            if props.api_version < vk::API_VERSION_1_2 {
                continue;
            }
            let Some(qf) = families.iter().position(|q| {
                q.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
            }) else {
                continue;
            };
            let rank = match props.device_type {
                vk::PhysicalDeviceType::DISCRETE_GPU => 0,
                vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
                vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
                vk::PhysicalDeviceType::CPU => 3,
                _ => 4,
            };
            candidates.push((rank, pd, qf as u32));
        }
        candidates.sort_by_key(|c| c.0);
        candidates.first().map(|c| (c.1, c.2)).ok_or_else(|| {
            GpuError::NoDevice(match filter {
                Some(f) => {
                    format!("no Vulkan 1.2 device matches VGEO_DEVICE={f:?} (devices: {names:?})")
                }
                None if names.is_empty() => {
                    "the loader found no Vulkan driver (install mesa-vulkan-drivers for lavapipe)"
                        .into()
                }
                None => format!(
                    "no Vulkan 1.2 device with a graphics+compute queue (devices: {names:?})"
                ),
            })
        })
    }

    /// vgeo on a device the host created. Checks the device against [`super::requirements`]:
    /// the Vulkan version, the queue family's flags, every required device extension and feature
    /// as the host says it enabled them ([`HostDevice::device_extensions`],
    /// [`HostDevice::features`]); anything missing is a [`GpuError::Unsupported`] naming each one
    /// (never a panic). Optional parts are used when enabled (64-bit image atomics: the extension
    /// and `shaderImageInt64Atomics`). With `collect_validation` and `VK_EXT_debug_utils` on the
    /// instance, vgeo adds its own debug messenger and [`Context::validation_errors`] returns the
    /// errors it saw (the host enables the validation layer itself).
    ///
    /// The handles stay the host's: see [`HostDevice`] for who destroys what. vgeo's own headless
    /// context ([`Context::new`]) is made through this same constructor.
    pub fn from_host(host: HostDevice, collect_validation: bool) -> GpuResult<Self> {
        let validation = if collect_validation && host.debug_utils {
            Some(Validation::new(&host.entry, &host.instance)?)
        } else {
            None
        };
        match Self::from_host_checked(host, validation, false) {
            Ok(ctx) => {
                // A host gets `--shader-dir` through the environment (or calls
                // `use_shader_dir` itself).
                if let Some(dir) = shader_dir_from_env() {
                    ctx.use_shader_dir(&dir)?;
                }
                Ok(ctx)
            }
            Err((e, v)) => {
                if let Some(v) = v {
                    v.destroy();
                }
                Err(e)
            }
        }
    }

    /// [`Context::from_host`] for the headless path: `headless`'s messenger is used and the
    /// context owns the instance and device. On failure the messenger is back in `headless`.
    fn from_host_with(host: HostDevice, headless: &mut Headless) -> GpuResult<Self> {
        let validation = headless.validation.take();
        Self::from_host_checked(host, validation, true).map_err(|(e, v)| {
            headless.validation = v;
            e
        })
    }

    /// What a host's device lacks of [`super::requirements`], one line each.
    fn missing_requirements(host: &HostDevice) -> Vec<String> {
        let reqs = super::requirements();
        let mut missing = Vec::new();
        let version = |v: u32| format!("{}.{}", vk::api_version_major(v), vk::api_version_minor(v));
        if host.api_version < reqs.api_version {
            missing.push(format!(
                "instance apiVersion {} (have {})",
                version(reqs.api_version),
                version(host.api_version)
            ));
        }
        // SAFETY: queries on the host's valid physical device.
        let (props, families) = unsafe {
            (
                host.instance
                    .get_physical_device_properties(host.physical_device),
                host.instance
                    .get_physical_device_queue_family_properties(host.physical_device),
            )
        };
        if props.api_version < reqs.api_version {
            missing.push(format!(
                "device Vulkan {} (have {})",
                version(reqs.api_version),
                version(props.api_version)
            ));
        }
        match families.get(host.queue_family_index as usize) {
            Some(f) if f.queue_flags.contains(reqs.queue_flags) => {}
            _ => missing.push(format!(
                "queue family {} with {:?}",
                host.queue_family_index, reqs.queue_flags
            )),
        }
        let enabled = |n: &CStr| host.device_extensions.iter().any(|e| e.as_c_str() == n);
        for n in reqs.device_extensions {
            if !enabled(n) {
                missing.push(format!("device extension {}", n.to_string_lossy()));
            }
        }
        for f in reqs.features {
            if !host.features.has(f) {
                missing.push(format!("feature {f}"));
            }
        }
        missing
    }

    /// The one constructor behind [`Context::from_host`] and [`Context::new`].
    fn from_host_checked(
        host: HostDevice,
        validation: Option<Validation>,
        owned: bool,
    ) -> Result<Self, (GpuError, Option<Validation>)> {
        let missing = Self::missing_requirements(&host);
        if !missing.is_empty() {
            return Err((GpuError::Unsupported { missing }, validation));
        }
        let HostDevice {
            entry,
            instance,
            debug_utils,
            physical_device: physical,
            device,
            device_extensions,
            features,
            queue_family_index: queue_family,
            queue,
            ..
        } = host;
        let image_int64 = device_extensions
            .iter()
            .any(|e| e.as_c_str() == ash::ext::shader_image_atomic_int64::NAME)
            && features.image_int64.shader_image_int64_atomics == vk::TRUE;
        let mesh_shader = device_extensions
            .iter()
            .any(|e| e.as_c_str() == ash::ext::mesh_shader::NAME)
            && features.mesh_shader.mesh_shader == vk::TRUE;
        let pipeline_statistics = device_extensions
            .iter()
            .any(|e| e.as_c_str() == ash::khr::pipeline_executable_properties::NAME)
            && features.pipeline_executable.pipeline_executable_info == vk::TRUE;
        // SAFETY: queries on a valid physical device.
        let (props, dev_exts, families) = unsafe {
            (
                instance.get_physical_device_properties(physical),
                instance
                    .enumerate_device_extension_properties(physical)
                    .unwrap_or_default(),
                instance.get_physical_device_queue_family_properties(physical),
            )
        };
        let supports = |n: &CStr| {
            dev_exts
                .iter()
                .any(|e| e.extension_name_as_c_str().is_ok_and(|x| x == n))
        };

        // Driver name and subgroup size.
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
        let mut p2 = vk::PhysicalDeviceProperties2::default()
            .push_next(&mut driver)
            .push_next(&mut subgroup);
        // SAFETY: valid chain of writable structs.
        unsafe { instance.get_physical_device_properties2(physical, &mut p2) };

        let ts_bits = families[queue_family as usize].timestamp_valid_bits;
        let v = props.api_version;
        // Tools hooked in (RenderDoc's layer reports itself here and hides what it cannot
        // capture), and what vgeo does without the optional parts.
        let tools: Vec<String> = if supports(ash::ext::tooling_info::NAME) {
            let ti = ash::ext::tooling_info::Instance::new(&entry, &instance);
            // SAFETY: VK_EXT_tooling_info is supported by the physical device (a
            // physical-device-level query).
            unsafe { ti.get_physical_device_tool_properties(physical) }
                .unwrap_or_default()
                .iter()
                .map(|t| format!("{} {}", cstr_array(&t.name), cstr_array(&t.version)))
                .collect()
        } else {
            Vec::new()
        };
        let hidden = if tools.is_empty() {
            String::new()
        } else {
            format!(" (a tool may hide it: {})", tools.join(", "))
        };
        let mut fallbacks = Vec::new();
        if !image_int64 {
            fallbacks.push(format!(
                "no 64-bit image atomics (VK_EXT_shader_image_atomic_int64){hidden}: the \
                 visibility buffer uses 64-bit buffer atomics"
            ));
        }
        if !mesh_shader {
            fallbacks.push(format!(
                "no mesh shaders (VK_EXT_mesh_shader){hidden}: raster_hw pulls vertices (--hw-path \
                 vertex)"
            ));
        }
        if !debug_utils {
            fallbacks.push(format!(
                "no VK_EXT_debug_utils{hidden}: objects are not named and passes not labelled"
            ));
        }
        // SAFETY: `physical` is a physical device of `instance`.
        let memory = unsafe { instance.get_physical_device_memory_properties(physical) };
        let device_local_bytes = memory
            .memory_heaps_as_slice()
            .iter()
            .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|h| h.size)
            .max()
            .unwrap_or(0);
        let caps = Caps {
            device_name: cstr_array(&props.device_name),
            device_type: format!("{:?}", props.device_type)
                .to_lowercase()
                .replace('_', " "),
            driver_name: cstr_array(&driver.driver_name),
            driver_info: cstr_array(&driver.driver_info),
            api_version: format!(
                "{}.{}.{}",
                vk::api_version_major(v),
                vk::api_version_minor(v),
                vk::api_version_patch(v)
            ),
            shader_int64: true,
            buffer_int64_atomics: true,
            image_int64_atomics: image_int64,
            mesh_shader,
            pipeline_statistics,
            multi_draw_indirect: true,
            draw_indirect_count: true,
            timestamp_period_ns: (ts_bits > 0
                && props.limits.timestamp_compute_and_graphics == vk::TRUE)
                .then_some(props.limits.timestamp_period),
            subgroup_size: subgroup.subgroup_size,
            max_compute_workgroups: props.limits.max_compute_work_group_count,
            max_image_dimension_2d: props.limits.max_image_dimension2_d,
            max_storage_buffer_range: props.limits.max_storage_buffer_range,
            device_local_bytes,
            validation: validation.is_some(),
            tools,
            fallbacks,
        };

        let allocator = match Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        }) {
            Ok(a) => a,
            Err(e) => {
                let e = GpuError::Alloc {
                    name: "allocator".into(),
                    msg: e.to_string(),
                };
                return Err((e, validation));
            }
        };

        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create info.
        let pool = match unsafe { device.create_command_pool(&pool_info, None) }
            .call("vkCreateCommandPool")
        {
            Ok(p) => p,
            Err(e) => {
                drop(allocator);
                return Err((e, validation));
            }
        };

        let debug_device =
            debug_utils.then(|| ash::ext::debug_utils::Device::new(&instance, &device));
        let inner = Inner {
            push_descriptor: ash::khr::push_descriptor::Device::new(&instance, &device),
            dynamic_rendering: ash::khr::dynamic_rendering::Device::new(&instance, &device),
            sync2: ash::khr::synchronization2::Device::new(&instance, &device),
            mesh_shader: mesh_shader
                .then(|| ash::ext::mesh_shader::Device::new(&instance, &device)),
            pipeline_executable: (pipeline_statistics
                && std::env::var_os("VGEO_PIPELINE_STATS").is_some_and(|v| v == "1"))
            .then(|| ash::khr::pipeline_executable_properties::Device::new(&instance, &device)),
            entry,
            instance,
            debug_device,
            device,
            queue,
            allocator: Mutex::new(Some(allocator)),
            caps,
            validation,
            owned,
            // Room for any label (`Cmd::begin_label` cuts at 127 bytes): recording never grows it.
            last_pass: Mutex::new({
                let mut s = String::with_capacity(128);
                s.push_str("(none)");
                s
            }),
            pool: Mutex::new(pool),
            shaders: std::sync::OnceLock::new(),
            waits: Default::default(),
        };
        let ctx = Context {
            inner: Arc::new(inner),
        };
        ctx.set_name(queue, "main queue");
        ctx.set_name(pool, "main command pool");
        Ok(ctx)
    }

    /// Whether vgeo created (and will destroy) the instance and device: true for the headless
    /// context, false for a host's ([`Context::from_host`]).
    pub fn owns_device(&self) -> bool {
        self.inner.owned
    }

    /// Compiles the GLSL in `dir` (a folder mirroring `shaders_glsl/`: a pass's file or an
    /// include placed there replaces the built-in one) for every pipeline made from now on; the
    /// shaders it changed, by file (and variant macro). Errors name the file and line, or an
    /// interface block whose size no longer matches vgeo's struct. Once per context, before the
    /// renderers are made.
    pub fn use_shader_dir(&self, dir: &std::path::Path) -> GpuResult<Vec<String>> {
        let debug = std::env::var("SHADER_DEBUG").is_ok_and(|v| v == "1");
        let compiled =
            super::shader_dir::ShaderOverrides::compile(dir, debug).map_err(GpuError::Other)?;
        let names = compiled.names();
        self.inner.shaders.set(compiled).map_err(|_| {
            GpuError::Other("a shader folder is set once per context, before any pipeline".into())
        })?;
        Ok(names)
    }

    /// The shaders a shader folder replaced ([`Context::use_shader_dir`]), by file.
    pub fn replaced_shaders(&self) -> Vec<String> {
        self.inner
            .shaders
            .get()
            .map(|s| s.names())
            .unwrap_or_default()
    }

    /// The SPIR-V to use for the embedded `spirv`: the shader folder's when it changed it.
    pub(crate) fn shader_spirv<'a>(&'a self, spirv: &'a [u8]) -> &'a [u8] {
        self.inner
            .shaders
            .get()
            .and_then(|s| s.replacement(spirv))
            .unwrap_or(spirv)
    }

    /// The instance's handle (for RenderDoc's [`super::RenderDoc::start`], or a host's own calls).
    pub fn vk_instance(&self) -> vk::Instance {
        self.inner.instance.handle()
    }

    /// The device's capabilities.
    pub fn caps(&self) -> &Caps {
        &self.inner.caps
    }

    /// Validation errors collected so far (empty when validation is off).
    pub fn validation_errors(&self) -> Vec<String> {
        (self.inner.validation.as_ref())
            .and_then(|v| v.messages.errors.lock().ok().map(|e| e.clone()))
            .unwrap_or_default()
    }

    /// Names a Vulkan object for debuggers (RenderDoc); a no-op without `VK_EXT_debug_utils`.
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        if let Some(d) = &self.inner.debug_device {
            let Ok(cname) = CString::new(name.replace('\0', " ")) else {
                return;
            };
            let info = vk::DebugUtilsObjectNameInfoEXT::default()
                .object_handle(handle)
                .object_name(&cname);
            // SAFETY: the handle belongs to this device; naming is advisory and has no other effect.
            let _ = unsafe { d.set_debug_utils_object_name(&info) };
        }
    }

    /// Makes one deliberately invalid Vulkan call (a zero-sized buffer), so tests can check that the
    /// validation messenger catches errors. Not for normal use.
    #[doc(hidden)]
    pub fn provoke_validation_error(&self) {
        let info = vk::BufferCreateInfo::default()
            .size(0)
            .usage(vk::BufferUsageFlags::STORAGE_BUFFER);
        // SAFETY: deliberately invalid (size 0) for the validation layer to report; with validation
        // on, the layer reports and the driver still returns a handle or an error, which we clean up.
        if let Ok(b) = unsafe { self.inner.device.create_buffer(&info, None) } {
            // SAFETY: the buffer (if any) is unused.
            unsafe { self.inner.device.destroy_buffer(b, None) };
        }
    }

    pub(crate) fn device(&self) -> &ash::Device {
        &self.inner.device
    }

    /// How many submissions vgeo has made and waited for ([`Context::submit_and_wait`]) on this
    /// context: a way to check that a step (a frame, a streaming update) waited for nothing.
    pub fn waited_submissions(&self) -> u64 {
        self.inner.waits.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Records commands with `record`, submits them and waits for completion.
    pub fn submit_and_wait<R>(
        &self,
        name: &str,
        record: impl FnOnce(&mut Cmd) -> R,
    ) -> GpuResult<R> {
        self.inner
            .waits
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dev = &self.inner.device;
        let pool = self
            .inner
            .pool
            .lock()
            .map_err(|_| GpuError::Other("command pool lock poisoned".into()))?;
        let ai = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is valid and externally synchronized by the mutex we hold.
        let cb = unsafe { dev.allocate_command_buffers(&ai) }.call("vkAllocateCommandBuffers")?[0];
        self.set_name(cb, name);
        let fence_info = vk::FenceCreateInfo::default();
        // SAFETY: valid device.
        let fence = unsafe { dev.create_fence(&fence_info, None) }.call("vkCreateFence")?;
        self.set_name(fence, name);
        let result = (|| {
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            // SAFETY: freshly allocated command buffer.
            unsafe { dev.begin_command_buffer(cb, &begin) }.call("vkBeginCommandBuffer")?;
            let mut cmd = Cmd::new(self.clone(), cb);
            let r = record(&mut cmd);
            cmd.finish();
            // SAFETY: recording began above.
            unsafe { dev.end_command_buffer(cb) }.call("vkEndCommandBuffer")?;
            let cbs = [cb];
            let submit = vk::SubmitInfo::default().command_buffers(&cbs);
            // SAFETY: queue access is serialized by the pool mutex we hold; the fence is unsignaled.
            let submitted = unsafe { dev.queue_submit(self.inner.queue, &[submit], fence) };
            self.check_lost(submitted, "vkQueueSubmit")?;
            // SAFETY: waiting on our own fence.
            let waited = unsafe { dev.wait_for_fences(&[fence], true, u64::MAX) };
            self.check_lost(waited, "vkWaitForFences")?;
            Ok(r)
        })();
        // SAFETY: the submission finished (or never started), so both objects are idle.
        unsafe {
            dev.destroy_fence(fence, None);
            dev.free_command_buffers(*pool, &[cb]);
        }
        result
    }

    /// Records commands with `record` into `cb`, a command buffer the host owns and submits:
    /// nothing is submitted or waited for. Labels `record` leaves open are closed.
    ///
    /// # Safety
    /// `cb` must be a primary command buffer of this context's device, in the recording state, from
    /// a pool of a queue family with graphics and compute; the host submits it (to a queue of that
    /// family) only after this returns, and keeps every resource the commands use alive until the
    /// submission completes.
    pub unsafe fn record_into<R>(
        &self,
        cb: vk::CommandBuffer,
        record: impl FnOnce(&mut Cmd) -> R,
    ) -> R {
        let mut cmd = Cmd::new(self.clone(), cb);
        let r = record(&mut cmd);
        cmd.finish();
        r
    }

    fn check_lost(&self, r: Result<(), vk::Result>, call: &'static str) -> GpuResult<()> {
        match r {
            Err(vk::Result::ERROR_DEVICE_LOST) => Err(GpuError::DeviceLost {
                pass: self
                    .inner
                    .last_pass
                    .lock()
                    .map(|s| s.clone())
                    .unwrap_or_default(),
            }),
            other => other.call(call),
        }
    }
}

impl Drop for Inner {
    fn drop(&mut self) {
        // SAFETY: every resource holds an Arc to this Inner, so none is alive any more; wait for the
        // device to go idle and destroy vgeo's objects in reverse order of creation. The instance
        // and device are destroyed only when vgeo created them (headless); a host's stay alive.
        unsafe {
            let _ = self.device.device_wait_idle();
            if let Ok(p) = self.pool.lock() {
                self.device.destroy_command_pool(*p, None);
            }
            if let Ok(mut a) = self.allocator.lock() {
                a.take();
            }
            if self.owned {
                self.device.destroy_device(None);
            }
            if let Some(v) = &self.validation {
                v.destroy();
            }
            if self.owned {
                self.instance.destroy_instance(None);
            }
        }
        let _ = &self.entry;
    }
}
