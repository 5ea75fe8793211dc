//! What vgeo needs of a Vulkan instance and device ([`requirements`]), the feature structs to
//! enable them ([`DeviceFeatures`]), and the check of a device a host created against them.

use std::ffi::CStr;
use std::fmt;

use ash::vk;

use super::{GpuError, GpuResult, VkResultExt};

/// One Vulkan feature: its name in the specification and the struct that enables it.
#[derive(Clone, Copy)]
pub struct Feature {
    /// The member's name, e.g. `shaderBufferInt64Atomics`.
    pub name: &'static str,
    /// The struct that holds it, e.g. `VkPhysicalDeviceVulkan12Features`.
    pub structure: &'static str,
    field: fn(&mut DeviceFeatures) -> &mut vk::Bool32,
}

impl PartialEq for Feature {
    fn eq(&self, other: &Self) -> bool {
        (self.name, self.structure) == (other.name, other.structure)
    }
}

impl Eq for Feature {}

impl fmt::Debug for Feature {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}::{}", self.structure, self.name)
    }
}

impl fmt::Display for Feature {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.name, self.structure)
    }
}

/// What vgeo requires of the instance and device it runs on, and what it uses when present.
///
/// A host that creates its own device (see [`super::HostDevice`]) enables at least the required
/// lists; [`DeviceFeatures::for_vgeo`] and [`device_extensions_for_vgeo`] give a chain and a list
/// that do it. vgeo's own headless context is created from the same lists.
#[derive(Clone, Debug)]
pub struct Requirements {
    /// Lowest Vulkan version of the instance (`VkApplicationInfo::apiVersion`) and the device.
    pub api_version: u32,
    /// The queue vgeo records for: one family with these flags (graphics and compute).
    pub queue_flags: vk::QueueFlags,
    /// Instance extensions vgeo requires (none).
    pub instance_extensions: &'static [&'static CStr],
    /// Instance extensions used when enabled: `VK_EXT_debug_utils` (object names and pass labels
    /// for RenderDoc; the validation messenger that [`super::Context::validation_errors`] reads).
    pub optional_instance_extensions: &'static [&'static CStr],
    /// Device extensions vgeo requires.
    pub device_extensions: &'static [&'static CStr],
    /// Device extensions used when enabled: `VK_EXT_shader_image_atomic_int64` (the R64 image
    /// visibility buffer; without it, a `uint64_t` storage buffer with 64-bit buffer atomics) and
    /// `VK_EXT_mesh_shader` (`raster_hw`'s mesh path; without it, vertex pulling).
    pub optional_device_extensions: &'static [&'static CStr],
    /// Device features vgeo requires.
    pub features: &'static [Feature],
    /// Device features used when enabled.
    pub optional_features: &'static [Feature],
}

macro_rules! feature {
    ($name:literal, $structure:expr, $($path:ident).+) => {
        Feature {
            name: $name,
            structure: $structure,
            field: |f: &mut DeviceFeatures| &mut f.$($path).+,
        }
    };
}

const CORE: &str = "VkPhysicalDeviceFeatures";
const V12: &str = "VkPhysicalDeviceVulkan12Features";

static FEATURES: [Feature; 12] = [
    feature!("shaderInt64", CORE, core.shader_int64),
    feature!("multiDrawIndirect", CORE, core.multi_draw_indirect),
    feature!(
        "fragmentStoresAndAtomics",
        CORE,
        core.fragment_stores_and_atomics
    ),
    feature!(
        "shaderBufferInt64Atomics",
        V12,
        v12.shader_buffer_int64_atomics
    ),
    feature!("drawIndirectCount", V12, v12.draw_indirect_count),
    feature!("scalarBlockLayout", V12, v12.scalar_block_layout),
    feature!("timelineSemaphore", V12, v12.timeline_semaphore),
    feature!("runtimeDescriptorArray", V12, v12.runtime_descriptor_array),
    feature!(
        "shaderSampledImageArrayNonUniformIndexing",
        V12,
        v12.shader_sampled_image_array_non_uniform_indexing
    ),
    feature!(
        "dynamicRendering",
        "VkPhysicalDeviceDynamicRenderingFeatures",
        dynamic_rendering.dynamic_rendering
    ),
    feature!(
        "synchronization2",
        "VkPhysicalDeviceSynchronization2Features",
        synchronization2.synchronization2
    ),
    feature!(
        "maintenance4",
        "VkPhysicalDeviceMaintenance4Features",
        maintenance4.maintenance4
    ),
];

static OPTIONAL_FEATURES: [Feature; 8] = [
    feature!(
        "vertexPipelineStoresAndAtomics",
        CORE,
        core.vertex_pipeline_stores_and_atomics
    ),
    feature!(
        "pipelineStatisticsQuery",
        CORE,
        core.pipeline_statistics_query
    ),
    feature!("descriptorIndexing", V12, v12.descriptor_indexing),
    feature!(
        "descriptorBindingPartiallyBound",
        V12,
        v12.descriptor_binding_partially_bound
    ),
    feature!("hostQueryReset", V12, v12.host_query_reset),
    feature!(
        "shaderImageInt64Atomics",
        "VkPhysicalDeviceShaderImageAtomicInt64FeaturesEXT",
        image_int64.shader_image_int64_atomics
    ),
    feature!(
        "meshShader",
        "VkPhysicalDeviceMeshShaderFeaturesEXT",
        mesh_shader.mesh_shader
    ),
    feature!(
        "pipelineExecutableInfo",
        "VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR",
        pipeline_executable.pipeline_executable_info
    ),
];

static DEVICE_EXTENSIONS: [&CStr; 4] = [
    ash::khr::dynamic_rendering::NAME,
    ash::khr::synchronization2::NAME,
    ash::khr::push_descriptor::NAME,
    ash::khr::maintenance4::NAME,
];

static OPTIONAL_DEVICE_EXTENSIONS: [&CStr; 3] = [
    ash::ext::shader_image_atomic_int64::NAME,
    ash::ext::mesh_shader::NAME,
    ash::khr::pipeline_executable_properties::NAME,
];

static OPTIONAL_INSTANCE_EXTENSIONS: [&CStr; 1] = [ash::ext::debug_utils::NAME];

/// What vgeo requires of the Vulkan instance and device, and the optional parts it uses when
/// present:
///
/// - Vulkan 1.2 (instance `apiVersion` and device), one queue family with graphics and compute;
/// - device extensions `VK_KHR_dynamic_rendering`, `VK_KHR_synchronization2`,
///   `VK_KHR_push_descriptor`, `VK_KHR_maintenance4` (the extensions, also on a 1.3 device: vgeo
///   calls their entry points);
/// - features `shaderInt64`, `multiDrawIndirect`, `fragmentStoresAndAtomics`;
///   `shaderBufferInt64Atomics`, `drawIndirectCount`, `scalarBlockLayout`, `timelineSemaphore`,
///   `runtimeDescriptorArray`, `shaderSampledImageArrayNonUniformIndexing` (1.2);
///   `dynamicRendering`, `synchronization2`, `maintenance4` (their extensions' structs);
/// - optional: `VK_EXT_debug_utils` on the instance (names, labels, validation messages),
///   `VK_EXT_shader_image_atomic_int64` with `shaderImageInt64Atomics` (the R64 image visibility
///   buffer), `VK_EXT_mesh_shader` with `meshShader` (`raster_hw`'s mesh path: a mesh-shader
///   workgroup per hardware-rasterized cluster; without it, or with `--hw-path vertex`, vertex
///   pulling), `VK_KHR_pipeline_executable_properties` with `pipelineExecutableInfo` (with
///   `VGEO_PIPELINE_STATS=1`, each pipeline's compiled statistics, such as registers, printed as
///   it is created), `vertexPipelineStoresAndAtomics`, `pipelineStatisticsQuery`, `descriptorIndexing`,
///   `descriptorBindingPartiallyBound`, `hostQueryReset`. Timestamps are used when the queue family
///   has `timestampValidBits` and the device `timestampComputeAndGraphics` (pass times; none
///   otherwise).
///
/// No buffer device address, so vgeo runs where RenderDoc on lavapipe exposes only Vulkan 1.2.
pub fn requirements() -> Requirements {
    Requirements {
        api_version: vk::API_VERSION_1_2,
        queue_flags: vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE,
        instance_extensions: &[],
        optional_instance_extensions: &OPTIONAL_INSTANCE_EXTENSIONS,
        device_extensions: &DEVICE_EXTENSIONS,
        optional_device_extensions: &OPTIONAL_DEVICE_EXTENSIONS,
        features: &FEATURES,
        optional_features: &OPTIONAL_FEATURES,
    }
}

impl fmt::Display for Requirements {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = |l: &[&CStr]| {
            l.iter()
                .map(|n| n.to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let feats = |l: &[Feature]| l.iter().map(|x| x.name).collect::<Vec<_>>().join(", ");
        writeln!(
            f,
            "Vulkan {}.{}, a queue with {:?}",
            vk::api_version_major(self.api_version),
            vk::api_version_minor(self.api_version),
            self.queue_flags
        )?;
        writeln!(f, "device extensions: {}", names(self.device_extensions))?;
        writeln!(f, "features: {}", feats(self.features))?;
        writeln!(
            f,
            "optional: {}, {}; {}",
            names(self.optional_instance_extensions),
            names(self.optional_device_extensions),
            feats(self.optional_features)
        )
    }
}

/// The device feature structs vgeo reads and enables: what a device supports
/// ([`DeviceFeatures::supported`]), what vgeo asks to enable ([`DeviceFeatures::for_vgeo`]), or
/// what a host enabled (filled by the host, see [`super::HostDevice::features`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct DeviceFeatures {
    /// Vulkan 1.0 features.
    pub core: vk::PhysicalDeviceFeatures,
    /// Vulkan 1.2 features.
    pub v12: vk::PhysicalDeviceVulkan12Features<'static>,
    /// `VK_KHR_dynamic_rendering`.
    pub dynamic_rendering: vk::PhysicalDeviceDynamicRenderingFeatures<'static>,
    /// `VK_KHR_synchronization2`.
    pub synchronization2: vk::PhysicalDeviceSynchronization2Features<'static>,
    /// `VK_KHR_maintenance4`.
    pub maintenance4: vk::PhysicalDeviceMaintenance4Features<'static>,
    /// `VK_EXT_shader_image_atomic_int64` (chained only when its feature is on).
    pub image_int64: vk::PhysicalDeviceShaderImageAtomicInt64FeaturesEXT<'static>,
    /// `VK_EXT_mesh_shader` (chained only when `meshShader` is on; vgeo enables no other of its
    /// features: no task shaders).
    pub mesh_shader: vk::PhysicalDeviceMeshShaderFeaturesEXT<'static>,
    /// `VK_KHR_pipeline_executable_properties` (chained only when `pipelineExecutableInfo` is on).
    pub pipeline_executable: vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR<'static>,
}

// SAFETY: the structs' `p_next` pointers are null outside the calls of [`DeviceFeatures::chain`]
// and [`DeviceFeatures::supported`], which use them while `self` is borrowed; the rest is plain data.
unsafe impl Send for DeviceFeatures {}
// SAFETY: as above; shared references never follow the pointers.
unsafe impl Sync for DeviceFeatures {}

impl DeviceFeatures {
    /// Whether `feature` is on.
    pub fn has(&self, feature: &Feature) -> bool {
        let mut copy = *self;
        *(feature.field)(&mut copy) == vk::TRUE
    }

    /// Turns `feature` on or off.
    pub fn set(&mut self, feature: &Feature, on: bool) {
        *(feature.field)(self) = if on { vk::TRUE } else { vk::FALSE };
    }

    /// The features `physical` supports (the image-atomic struct only when the device has its
    /// extension).
    pub fn supported(instance: &ash::Instance, physical: vk::PhysicalDevice) -> GpuResult<Self> {
        // SAFETY: a query on a valid physical device.
        let exts = unsafe { instance.enumerate_device_extension_properties(physical) }
            .call("vkEnumerateDeviceExtensionProperties")?;
        let has = |n: &CStr| {
            exts.iter()
                .any(|e| e.extension_name_as_c_str().is_ok_and(|x| x == n))
        };
        let has_img64 = has(ash::ext::shader_image_atomic_int64::NAME);
        let has_mesh = has(ash::ext::mesh_shader::NAME);
        let has_pipeline_executable = has(ash::khr::pipeline_executable_properties::NAME);
        let mut f = DeviceFeatures::default();
        let mut s2 = vk::PhysicalDeviceFeatures2::default()
            .push_next(&mut f.v12)
            .push_next(&mut f.dynamic_rendering)
            .push_next(&mut f.synchronization2)
            .push_next(&mut f.maintenance4);
        if has_img64 {
            s2 = s2.push_next(&mut f.image_int64);
        }
        if has_mesh {
            s2 = s2.push_next(&mut f.mesh_shader);
        }
        if has_pipeline_executable {
            s2 = s2.push_next(&mut f.pipeline_executable);
        }
        // SAFETY: the chain holds valid, writable structs alive for the call.
        unsafe { instance.get_physical_device_features2(physical, &mut s2) };
        f.core = s2.features;
        Ok(f.unchained())
    }

    /// What vgeo enables on a device that supports `supported`: every required feature (an error
    /// naming each one `supported` lacks) and the optional ones it has.
    pub fn for_vgeo(supported: &DeviceFeatures) -> Result<Self, Vec<Feature>> {
        let mut f = DeviceFeatures::default();
        let mut missing = Vec::new();
        for r in FEATURES.iter() {
            if supported.has(r) {
                f.set(r, true);
            } else {
                missing.push(*r);
            }
        }
        for o in OPTIONAL_FEATURES.iter() {
            f.set(o, supported.has(o));
        }
        if missing.is_empty() {
            Ok(f)
        } else {
            Err(missing)
        }
    }

    /// `info` with these features: `enabled_features` set to [`DeviceFeatures::core`] and the
    /// extension structs chained (the image-atomic and mesh-shader ones only when on). `self` must
    /// stay borrowed until the device is created.
    pub fn chain<'a>(&'a mut self, info: vk::DeviceCreateInfo<'a>) -> vk::DeviceCreateInfo<'a> {
        *self = self.unchained();
        let img64 = self.image_int64.shader_image_int64_atomics == vk::TRUE;
        let mesh = self.mesh_shader.mesh_shader == vk::TRUE;
        let pipeline_executable = self.pipeline_executable.pipeline_executable_info == vk::TRUE;
        let mut info = info
            .enabled_features(&self.core)
            .push_next(&mut self.v12)
            .push_next(&mut self.dynamic_rendering)
            .push_next(&mut self.synchronization2)
            .push_next(&mut self.maintenance4);
        if img64 {
            info = info.push_next(&mut self.image_int64);
        }
        if mesh {
            info = info.push_next(&mut self.mesh_shader);
        }
        if pipeline_executable {
            info = info.push_next(&mut self.pipeline_executable);
        }
        info
    }

    /// A copy with every `p_next` null.
    fn unchained(mut self) -> Self {
        self.v12.p_next = std::ptr::null_mut();
        self.dynamic_rendering.p_next = std::ptr::null_mut();
        self.synchronization2.p_next = std::ptr::null_mut();
        self.maintenance4.p_next = std::ptr::null_mut();
        self.image_int64.p_next = std::ptr::null_mut();
        self.mesh_shader.p_next = std::ptr::null_mut();
        self.pipeline_executable.p_next = std::ptr::null_mut();
        self
    }
}

/// The device extensions vgeo enables on `physical`: the required ones (an error naming those it
/// lacks) and the optional ones it has.
pub fn device_extensions_for_vgeo(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
) -> GpuResult<Vec<&'static CStr>> {
    // SAFETY: a query on a valid physical device.
    let exts = unsafe { instance.enumerate_device_extension_properties(physical) }
        .call("vkEnumerateDeviceExtensionProperties")?;
    let has = |n: &CStr| {
        exts.iter()
            .any(|e| e.extension_name_as_c_str().is_ok_and(|x| x == n))
    };
    let missing: Vec<String> = DEVICE_EXTENSIONS
        .iter()
        .filter(|n| !has(n))
        .map(|n| format!("device extension {}", n.to_string_lossy()))
        .collect();
    if !missing.is_empty() {
        return Err(GpuError::Unsupported { missing });
    }
    let mut out: Vec<&'static CStr> = DEVICE_EXTENSIONS.to_vec();
    out.extend(OPTIONAL_DEVICE_EXTENSIONS.iter().filter(|n| has(n)));
    Ok(out)
}
