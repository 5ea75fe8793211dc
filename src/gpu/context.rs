//! Instance, device, queue, allocator, debug messenger and one-shot submission.

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
}

impl ContextOptions {
    /// Options from the environment: `VGEO_VALIDATION`, `VGEO_SYNC_VALIDATION`, `VGEO_DEVICE`.
    pub fn from_env() -> Self {
        let flag = |k: &str| std::env::var(k).is_ok_and(|v| !v.is_empty() && v != "0");
        Self {
            validation: flag("VGEO_VALIDATION") || flag("VGEO_SYNC_VALIDATION"),
            sync_validation: flag("VGEO_SYNC_VALIDATION"),
            device_filter: std::env::var("VGEO_DEVICE").ok().filter(|s| !s.is_empty()),
        }
    }
}

/// What the chosen device is and can do.
#[derive(Clone, Debug)]
pub struct Caps {
    pub device_name: String,
    pub device_type: String,
    pub driver_name: String,
    pub driver_info: String,
    pub api_version: String,
    pub shader_int64: bool,
    pub buffer_int64_atomics: bool,
    /// `VK_EXT_shader_image_atomic_int64`: the R64 visibility-buffer image path.
    pub image_int64_atomics: bool,
    pub mesh_shader: bool,
    pub multi_draw_indirect: bool,
    pub draw_indirect_count: bool,
    /// Nanoseconds per timestamp tick; `None` when the queue has no timestamps.
    pub timestamp_period_ns: Option<f32>,
    pub subgroup_size: u32,
    pub max_compute_workgroups: [u32; 3],
    /// `maxImageDimension2D`: the largest side of a 2D image (at least 4096).
    pub max_image_dimension_2d: u32,
    pub validation: bool,
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
        writeln!(f, "multiDrawIndirect:     {}", yn(self.multi_draw_indirect))?;
        writeln!(f, "drawIndirectCount:     {}", yn(self.draw_indirect_count))?;
        match self.timestamp_period_ns {
            Some(p) => writeln!(f, "timestamps:            yes ({p} ns/tick)")?,
            None => writeln!(f, "timestamps:            no")?,
        }
        writeln!(f, "subgroup size:         {}", self.subgroup_size)?;
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
    pub debug_instance: Option<ash::ext::debug_utils::Instance>,
    pub debug_device: Option<ash::ext::debug_utils::Device>,
    messenger: vk::DebugUtilsMessengerEXT,
    pub device: ash::Device,
    pub push_descriptor: ash::khr::push_descriptor::Device,
    pub dynamic_rendering: ash::khr::dynamic_rendering::Device,
    pub sync2: ash::khr::synchronization2::Device,
    pub queue: vk::Queue,
    pub allocator: Mutex<Option<Allocator>>,
    pub caps: Caps,
    messages: Box<Messages>,
    pub last_pass: Mutex<String>,
    pool: Mutex<vk::CommandPool>,
}

#[derive(Default)]
struct Messages {
    errors: Mutex<Vec<String>>,
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

impl Context {
    /// Creates a headless context (no window, no surface).
    pub fn new(opts: &ContextOptions) -> GpuResult<Self> {
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
        let has_inst_ext = |n: &CStr| {
            inst_exts
                .iter()
                .any(|e| e.extension_name_as_c_str().is_ok_and(|x| x == n))
        };
        let debug_utils = has_inst_ext(ash::ext::debug_utils::NAME);

        let app_name = c"vgeo";
        let app = vk::ApplicationInfo::default()
            .application_name(app_name)
            .engine_name(app_name)
            .api_version(vk::API_VERSION_1_2);
        let mut ext_names = Vec::new();
        if debug_utils {
            ext_names.push(ash::ext::debug_utils::NAME.as_ptr());
        }
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

        let messages = Box::<Messages>::default();
        let (debug_instance, messenger) = if debug_utils {
            let di = ash::ext::debug_utils::Instance::new(&entry, &instance);
            let mut messenger = vk::DebugUtilsMessengerEXT::null();
            if opts.validation {
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
                // SAFETY: `messages` is boxed and stored in the context, outliving the messenger.
                messenger = unsafe { di.create_debug_utils_messenger(&ci, None) }
                    .call("vkCreateDebugUtilsMessengerEXT")?;
            }
            (Some(di), messenger)
        } else {
            (None, vk::DebugUtilsMessengerEXT::null())
        };

        let picked = Self::pick_device(&instance, opts.device_filter.as_deref());
        let (physical, queue_family) = match picked {
            Ok(p) => p,
            Err(e) => {
                // SAFETY: nothing else was created from the instance yet but the messenger.
                unsafe {
                    if let Some(di) = &debug_instance {
                        di.destroy_debug_utils_messenger(messenger, None);
                    }
                    instance.destroy_instance(None);
                }
                return Err(e);
            }
        };
        Self::create_device(
            entry,
            instance,
            debug_instance,
            messenger,
            messages,
            physical,
            queue_family,
            opts,
        )
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

    #[allow(clippy::too_many_arguments)]
    fn create_device(
        entry: ash::Entry,
        instance: ash::Instance,
        debug_instance: Option<ash::ext::debug_utils::Instance>,
        messenger: vk::DebugUtilsMessengerEXT,
        messages: Box<Messages>,
        physical: vk::PhysicalDevice,
        queue_family: u32,
        opts: &ContextOptions,
    ) -> GpuResult<Self> {
        // SAFETY: queries on a valid physical device.
        let (props, dev_exts, families) = unsafe {
            (
                instance.get_physical_device_properties(physical),
                instance
                    .enumerate_device_extension_properties(physical)
                    .call("vkEnumerateDeviceExtensionProperties")?,
                instance.get_physical_device_queue_family_properties(physical),
            )
        };
        let has = |n: &CStr| {
            dev_exts
                .iter()
                .any(|e| e.extension_name_as_c_str().is_ok_and(|x| x == n))
        };
        let required = [
            ash::khr::dynamic_rendering::NAME,
            ash::khr::synchronization2::NAME,
            ash::khr::push_descriptor::NAME,
            ash::khr::maintenance4::NAME,
        ];
        let missing: Vec<String> = required
            .iter()
            .filter(|n| !has(n))
            .map(|n| n.to_string_lossy().into_owned())
            .collect();
        let device_name = cstr_array(&props.device_name);
        if !missing.is_empty() {
            return Err(GpuError::NoDevice(format!(
                "{device_name} lacks required extensions {missing:?}"
            )));
        }

        // What the device supports.
        let mut s12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut s_img64 = vk::PhysicalDeviceShaderImageAtomicInt64FeaturesEXT::default();
        let mut s_dr = vk::PhysicalDeviceDynamicRenderingFeatures::default();
        let mut s_sync2 = vk::PhysicalDeviceSynchronization2Features::default();
        let mut s_m4 = vk::PhysicalDeviceMaintenance4Features::default();
        let has_img64 = has(ash::ext::shader_image_atomic_int64::NAME);
        let mut s2 = vk::PhysicalDeviceFeatures2::default()
            .push_next(&mut s12)
            .push_next(&mut s_dr)
            .push_next(&mut s_sync2)
            .push_next(&mut s_m4);
        if has_img64 {
            s2 = s2.push_next(&mut s_img64);
        }
        // SAFETY: the chain holds valid, writable structs.
        unsafe { instance.get_physical_device_features2(physical, &mut s2) };
        let s10 = s2.features;
        let image_int64 = has_img64 && s_img64.shader_image_int64_atomics == vk::TRUE;
        let need = [
            ("shaderInt64", s10.shader_int64),
            ("multiDrawIndirect", s10.multi_draw_indirect),
            ("fragmentStoresAndAtomics", s10.fragment_stores_and_atomics),
            ("shaderBufferInt64Atomics", s12.shader_buffer_int64_atomics),
            ("drawIndirectCount", s12.draw_indirect_count),
            ("scalarBlockLayout", s12.scalar_block_layout),
            ("timelineSemaphore", s12.timeline_semaphore),
            ("dynamicRendering", s_dr.dynamic_rendering),
            ("synchronization2", s_sync2.synchronization2),
            ("maintenance4", s_m4.maintenance4),
        ];
        let lacking: Vec<&str> = need
            .iter()
            .filter(|(_, v)| *v != vk::TRUE)
            .map(|(n, _)| *n)
            .collect();
        if !lacking.is_empty() {
            return Err(GpuError::NoDevice(format!(
                "{device_name} lacks required features {lacking:?}"
            )));
        }

        // What we enable.
        let f10 = vk::PhysicalDeviceFeatures::default()
            .shader_int64(true)
            .multi_draw_indirect(true)
            .fragment_stores_and_atomics(true)
            .vertex_pipeline_stores_and_atomics(s10.vertex_pipeline_stores_and_atomics == vk::TRUE)
            .pipeline_statistics_query(s10.pipeline_statistics_query == vk::TRUE);
        let mut e12 = vk::PhysicalDeviceVulkan12Features::default()
            .shader_buffer_int64_atomics(true)
            .draw_indirect_count(true)
            .scalar_block_layout(true)
            .timeline_semaphore(true)
            .descriptor_indexing(s12.descriptor_indexing == vk::TRUE)
            .runtime_descriptor_array(s12.runtime_descriptor_array == vk::TRUE)
            .shader_sampled_image_array_non_uniform_indexing(
                s12.shader_sampled_image_array_non_uniform_indexing == vk::TRUE,
            )
            .descriptor_binding_partially_bound(s12.descriptor_binding_partially_bound == vk::TRUE)
            .host_query_reset(s12.host_query_reset == vk::TRUE);
        let mut e_dr =
            vk::PhysicalDeviceDynamicRenderingFeatures::default().dynamic_rendering(true);
        let mut e_sync2 =
            vk::PhysicalDeviceSynchronization2Features::default().synchronization2(true);
        let mut e_m4 = vk::PhysicalDeviceMaintenance4Features::default().maintenance4(true);
        let mut e_img64 = vk::PhysicalDeviceShaderImageAtomicInt64FeaturesEXT::default()
            .shader_image_int64_atomics(true);
        let mut ext_names: Vec<*const std::ffi::c_char> =
            required.iter().map(|n| n.as_ptr()).collect();
        let prio = [1.0f32];
        let qinfo = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&prio)];
        let mut dinfo = vk::DeviceCreateInfo::default()
            .queue_create_infos(&qinfo)
            .enabled_features(&f10)
            .push_next(&mut e12)
            .push_next(&mut e_dr)
            .push_next(&mut e_sync2)
            .push_next(&mut e_m4);
        if image_int64 {
            ext_names.push(ash::ext::shader_image_atomic_int64::NAME.as_ptr());
            dinfo = dinfo.push_next(&mut e_img64);
        }
        dinfo = dinfo.enabled_extension_names(&ext_names);
        // SAFETY: every pointer in `dinfo` refers to locals alive for the call.
        let device =
            unsafe { instance.create_device(physical, &dinfo, None) }.call("vkCreateDevice")?;
        // SAFETY: queue 0 of a family we created.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };

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
        let caps = Caps {
            device_name: device_name.clone(),
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
            mesh_shader: has(ash::ext::mesh_shader::NAME),
            multi_draw_indirect: true,
            draw_indirect_count: true,
            timestamp_period_ns: (ts_bits > 0
                && props.limits.timestamp_compute_and_graphics == vk::TRUE)
                .then_some(props.limits.timestamp_period),
            subgroup_size: subgroup.subgroup_size,
            max_compute_workgroups: props.limits.max_compute_work_group_count,
            max_image_dimension_2d: props.limits.max_image_dimension2_d,
            validation: opts.validation,
        };

        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .map_err(|e| GpuError::Alloc {
            name: "allocator".into(),
            msg: e.to_string(),
        })?;

        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create info.
        let pool =
            unsafe { device.create_command_pool(&pool_info, None) }.call("vkCreateCommandPool")?;

        let debug_device = debug_instance
            .as_ref()
            .map(|_| ash::ext::debug_utils::Device::new(&instance, &device));
        let inner = Inner {
            push_descriptor: ash::khr::push_descriptor::Device::new(&instance, &device),
            dynamic_rendering: ash::khr::dynamic_rendering::Device::new(&instance, &device),
            sync2: ash::khr::synchronization2::Device::new(&instance, &device),
            entry,
            instance,
            debug_instance,
            debug_device,
            messenger,
            device,
            queue,
            allocator: Mutex::new(Some(allocator)),
            caps,
            messages,
            last_pass: Mutex::new(String::from("(none)")),
            pool: Mutex::new(pool),
        };
        let ctx = Context {
            inner: Arc::new(inner),
        };
        ctx.set_name(queue, "main queue");
        ctx.set_name(pool, "main command pool");
        Ok(ctx)
    }

    /// The device's capabilities.
    pub fn caps(&self) -> &Caps {
        &self.inner.caps
    }

    /// Validation errors collected so far (empty when validation is off).
    pub fn validation_errors(&self) -> Vec<String> {
        self.inner
            .messages
            .errors
            .lock()
            .map(|e| e.clone())
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

    /// Records commands with `record`, submits them and waits for completion.
    pub fn submit_and_wait<R>(
        &self,
        name: &str,
        record: impl FnOnce(&mut Cmd) -> R,
    ) -> GpuResult<R> {
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
        // device to go idle and destroy in reverse order of creation.
        unsafe {
            let _ = self.device.device_wait_idle();
            if let Ok(p) = self.pool.lock() {
                self.device.destroy_command_pool(*p, None);
            }
            if let Ok(mut a) = self.allocator.lock() {
                a.take();
            }
            self.device.destroy_device(None);
            if let Some(di) = &self.debug_instance
                && self.messenger != vk::DebugUtilsMessengerEXT::null()
            {
                di.destroy_debug_utils_messenger(self.messenger, None);
            }
            self.instance.destroy_instance(None);
        }
        let _ = &self.entry;
    }
}
