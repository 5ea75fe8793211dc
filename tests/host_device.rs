//! vgeo on a device the host created (issue 12, "The host's device"): the test is the host. It
//! creates its own instance (validation layer on) and device with ash, enabling what
//! `vgeo::gpu::requirements()` lists, hands the handles to vgeo, renders, compares with vgeo's
//! headless context, and destroys its own handles afterwards (vgeo must not have). A device
//! created without a required feature or extension is refused with an error naming it.

mod common;

use std::ffi::{CStr, CString, c_void};
use std::sync::Mutex;

use ash::vk;
use common::{assert_no_validation_errors, assets, filling_camera, gpu, load_built};
use glam::DMat4;
use vgeo::HwPath;
use vgeo::baseline::brute::Brute;
use vgeo::camera::Camera;
use vgeo::frame::VgeoRenderer;
use vgeo::gpu::{
    Context, DeviceFeatures, GpuError, HostDevice, device_extensions_for_vgeo, requirements,
};
use vgeo::passes::debug_view::ViewMode;
use vgeo::passes::view::FrameSettings;
use vgeo::render::{Frame, Light, Placement};

const W: u32 = 128;
const H: u32 = 96;

// The host's messenger (from examples/embed.rs, a host too): it lives from instance creation to
// destruction, so it also sees what happens after vgeo is gone.
#[allow(dead_code)]
#[path = "../examples/embed.rs"]
mod example;
use example::{Errors, on_message};

/// The host's Vulkan objects.
struct Host {
    entry: ash::Entry,
    instance: ash::Instance,
    debug: ash::ext::debug_utils::Instance,
    messenger: vk::DebugUtilsMessengerEXT,
    errors: Box<Errors>,
    physical: vk::PhysicalDevice,
    queue_family: u32,
}

impl Host {
    /// An instance at Vulkan 1.2 with the validation layer and debug utils, and the device vgeo's
    /// headless context would pick (discrete first; `VGEO_DEVICE` respected).
    fn new() -> Host {
        // SAFETY: loading the system loader.
        let entry = unsafe { ash::Entry::load() }.expect("a Vulkan loader");
        let app = vk::ApplicationInfo::default().api_version(requirements().api_version);
        let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
        let exts = [ash::ext::debug_utils::NAME.as_ptr()];
        let info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&exts);
        // SAFETY: pointers to locals alive for the call.
        let instance = unsafe { entry.create_instance(&info, None) }.expect("instance");
        let debug = ash::ext::debug_utils::Instance::new(&entry, &instance);
        let errors = Box::new(Errors(Mutex::new(Vec::new())));
        let ci = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL,
            )
            .pfn_user_callback(Some(on_message))
            .user_data(&*errors as *const Errors as *mut c_void);
        // SAFETY: `errors` is boxed and outlives the messenger.
        let messenger = unsafe { debug.create_debug_utils_messenger(&ci, None) }.unwrap();
        let (physical, queue_family) = example::pick_device(&instance)
            .unwrap()
            .expect("a Vulkan 1.2 device");
        Host {
            entry,
            instance,
            debug,
            messenger,
            errors,
            physical,
            queue_family,
        }
    }

    /// A device with `extensions` and `features` and its queue, described for vgeo.
    fn device(&self, extensions: &[&CStr], mut features: DeviceFeatures) -> HostDevice {
        let names: Vec<*const std::ffi::c_char> = extensions.iter().map(|n| n.as_ptr()).collect();
        let prio = [1.0f32];
        let qinfo = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(self.queue_family)
            .queue_priorities(&prio)];
        let enabled = features;
        let info = features.chain(
            vk::DeviceCreateInfo::default()
                .queue_create_infos(&qinfo)
                .enabled_extension_names(&names),
        );
        // SAFETY: pointers to locals alive for the call.
        let device = unsafe { self.instance.create_device(self.physical, &info, None) }
            .expect("the host's device");
        // SAFETY: queue 0 of the family the device was created with.
        let queue = unsafe { device.get_device_queue(self.queue_family, 0) };
        HostDevice {
            entry: self.entry.clone(),
            instance: self.instance.clone(),
            api_version: requirements().api_version,
            debug_utils: true,
            physical_device: self.physical,
            device,
            device_extensions: extensions.iter().map(|n| CString::from(*n)).collect(),
            features: enabled,
            queue_family_index: self.queue_family,
            queue,
        }
    }

    /// What vgeo enables on this device (as its headless context does).
    fn vgeo_features(&self) -> DeviceFeatures {
        let supported = DeviceFeatures::supported(&self.instance, self.physical).unwrap();
        DeviceFeatures::for_vgeo(&supported).expect("the device has what vgeo requires")
    }

    fn errors(&self) -> Vec<String> {
        self.errors.0.lock().unwrap().clone()
    }

    /// Destroys the host's device (after vgeo is gone), then the messenger and instance.
    fn destroy(self, device: ash::Device) {
        // SAFETY: vgeo's context is dropped; the device is idle and owns nothing of vgeo's. A
        // double destroy (had vgeo destroyed it) would be reported by the layer or crash.
        unsafe {
            device
                .device_wait_idle()
                .expect("the host's device is still alive");
            device.destroy_device(None);
            self.debug
                .destroy_debug_utils_messenger(self.messenger, None);
            self.instance.destroy_instance(None);
        }
    }
}

/// The spot cow, built, in front of the camera: lit by vgeo's path and by brute.
fn render(ctx: &Context) -> (Frame, Frame) {
    let (mesh, built) = load_built(&assets().join("spot.obj"));
    let camera: Camera = filling_camera(&mesh, 2.0);
    let placements = vec![Placement {
        mesh: 0,
        transform: DMat4::IDENTITY,
        color: [0.9, 0.8, 0.7],
    }];
    let mut r = VgeoRenderer::new(ctx, std::slice::from_ref(&built), &placements).unwrap();
    let settings = FrameSettings::default();
    let light = Light::default();
    let mut last = None;
    for _ in 0..2 {
        let f = r
            .render(&camera, W, H, &settings, ViewMode::Lit, &light)
            .expect("vgeo renders on the context");
        f.check().expect("a complete frame");
        last = Some(f.frame);
    }
    let brute = Brute::new(ctx, std::slice::from_ref(&mesh)).unwrap();
    let b = brute
        .render(&placements, &camera, &light, W, H)
        .expect("brute renders on the context");
    (last.unwrap(), b)
}

#[test]
fn renders_on_the_hosts_device_as_on_its_own() {
    let host = Host::new();
    let extensions = device_extensions_for_vgeo(&host.instance, host.physical).unwrap();
    let hd = host.device(&extensions, host.vgeo_features());
    let device = hd.device.clone();
    let ctx = Context::from_host(hd, true).expect("vgeo accepts the host's device");
    assert!(!ctx.owns_device());
    assert!(
        ctx.caps().validation,
        "vgeo's messenger on the host's instance"
    );
    let device_name = ctx.caps().device_name.clone();
    let (vgeo_frame, brute_frame) = render(&ctx);
    assert_no_validation_errors(&ctx);
    assert!(vgeo_frame.covered() > 1000, "the cow is drawn");
    drop(ctx);

    // The host's device outlives vgeo: still usable, then destroyed by the host.
    let info = vk::BufferCreateInfo::default()
        .size(256)
        .usage(vk::BufferUsageFlags::STORAGE_BUFFER);
    // SAFETY: a valid device and create info; the buffer is destroyed at once.
    unsafe {
        let b = device
            .create_buffer(&info, None)
            .expect("the device is alive");
        device.destroy_buffer(b, None);
    }
    let errors = host.errors();
    host.destroy(device);
    assert!(errors.is_empty(), "host's messenger: {errors:#?}");

    // vgeo's own headless context renders the same images.
    let own = gpu();
    assert!(own.owns_device());
    let (vgeo_own, brute_own) = render(&own);
    assert_no_validation_errors(&own);
    assert_eq!(own.caps().device_name, device_name, "the same device");
    for (name, a, b) in [
        ("vgeo", &vgeo_frame, &vgeo_own),
        ("brute", &brute_frame, &brute_own),
    ] {
        let diff = (a.color.iter().zip(&b.color))
            .filter(|(x, y)| x != y)
            .count();
        assert_eq!(diff, 0, "{name}: {diff} colour bytes differ");
        assert!(a.depth == b.depth, "{name}: depth differs");
    }
}

#[test]
fn a_device_without_a_required_feature_or_extension_is_refused_by_name() {
    let host = Host::new();
    let all = device_extensions_for_vgeo(&host.instance, host.physical).unwrap();
    let reqs = requirements();
    let int64_atomics = (reqs.features.iter())
        .find(|f| f.name == "shaderBufferInt64Atomics")
        .expect("a required feature");

    // Without the feature: the device is valid Vulkan, but not enough for vgeo.
    let mut features = host.vgeo_features();
    features.set(int64_atomics, false);
    let hd = host.device(&all, features);
    let device = hd.device.clone();
    match Context::from_host(hd, true) {
        Ok(_) => panic!("a device without shaderBufferInt64Atomics was accepted"),
        Err(e) => {
            let msg = e.to_string();
            assert!(matches!(e, GpuError::Unsupported { .. }), "{e:?}");
            assert!(
                msg.contains("shaderBufferInt64Atomics")
                    && msg.contains("VkPhysicalDeviceVulkan12Features"),
                "{msg}"
            );
        }
    }
    // SAFETY: vgeo refused the device and created nothing on it.
    unsafe { device.destroy_device(None) };

    // Without an extension (and without its feature struct's flag).
    let push = ash::khr::push_descriptor::NAME;
    let fewer: Vec<&CStr> = all.iter().copied().filter(|n| *n != push).collect();
    let hd = host.device(&fewer, host.vgeo_features());
    let device = hd.device.clone();
    let err = Context::from_host(hd, true)
        .err()
        .expect("a device without VK_KHR_push_descriptor is refused");
    assert!(
        err.to_string()
            .contains("device extension VK_KHR_push_descriptor"),
        "{err}"
    );
    let errors = host.errors();
    host.destroy(device);
    assert!(errors.is_empty(), "host's messenger: {errors:#?}");
}

/// A device without `VK_EXT_mesh_shader` (RenderDoc hides it, for one): vgeo runs, `raster_hw`
/// takes its vertex path, asking for the mesh path is an error naming the extension (not a
/// panic), and the frame equals the one of vgeo's own context (the mesh path where the device
/// has mesh shaders).
#[test]
fn without_mesh_shaders_raster_hw_pulls_vertices() {
    let host = Host::new();
    let all = device_extensions_for_vgeo(&host.instance, host.physical).unwrap();
    let fewer: Vec<&CStr> = (all.iter().copied())
        .filter(|n| *n != ash::ext::mesh_shader::NAME)
        .collect();
    let mesh_shader = (requirements().optional_features.iter())
        .find(|f| f.name == "meshShader")
        .expect("meshShader is an optional feature");
    let mut features = host.vgeo_features();
    features.set(mesh_shader, false);
    let hd = host.device(&fewer, features);
    let device = hd.device.clone();
    let ctx = Context::from_host(hd, true).expect("vgeo runs without mesh shaders");
    assert!(!ctx.caps().mesh_shader);
    assert!(
        (ctx.caps().fallbacks.iter()).any(|f| f.contains("VK_EXT_mesh_shader")),
        "{:?}",
        ctx.caps().fallbacks
    );
    let (_, built) = load_built(&assets().join("spot.obj"));
    let one = [Placement {
        mesh: 0,
        transform: DMat4::IDENTITY,
        color: [0.9, 0.8, 0.7],
    }];
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &one).unwrap();
    if std::env::var("VGEO_HW_PATH").is_err() {
        assert_eq!(
            r.hw_path(),
            HwPath::Vertex,
            "auto falls back to vertex pulling"
        );
    }
    let err = r
        .set_hw_path(HwPath::Mesh)
        .expect_err("no mesh path without the extension");
    assert!(err.to_string().contains("VK_EXT_mesh_shader"), "{err}");
    r.set_hw_path(HwPath::Vertex).expect("the vertex path");
    drop(r);
    let (frame, _) = render(&ctx);
    assert_no_validation_errors(&ctx);
    assert!(frame.covered() > 1000, "the cow is drawn");
    drop(ctx);
    let errors = host.errors();
    host.destroy(device);
    assert!(errors.is_empty(), "host's messenger: {errors:#?}");

    let own = gpu();
    let (own_frame, _) = render(&own);
    assert_no_validation_errors(&own);
    assert!(
        frame.color == own_frame.color,
        "the vertex path's image differs"
    );
    assert!(
        frame.depth == own_frame.depth,
        "the vertex path's depth differs"
    );
}

#[test]
fn requirements_list_what_the_context_enables() {
    let r = requirements();
    assert_eq!(r.api_version, vk::API_VERSION_1_2);
    for ext in [
        "VK_KHR_dynamic_rendering",
        "VK_KHR_synchronization2",
        "VK_KHR_push_descriptor",
        "VK_KHR_maintenance4",
    ] {
        assert!(
            r.device_extensions.iter().any(|n| n.to_str() == Ok(ext)),
            "{ext}"
        );
    }
    for ext in ["VK_EXT_shader_image_atomic_int64", "VK_EXT_mesh_shader"] {
        assert!(
            (r.optional_device_extensions.iter()).any(|n| n.to_str() == Ok(ext)),
            "{ext}"
        );
    }
    assert!(
        (r.optional_features.iter()).any(|f| f.name == "meshShader"),
        "{r}"
    );
    assert!(r.features.iter().any(|f| f.name == "shaderInt64"));
    assert!(
        (r.optional_features.iter()).any(|f| f.name == "shaderImageInt64Atomics"),
        "{r}"
    );
    // No feature is both required and optional; every one can be set and read back.
    let mut f = DeviceFeatures::default();
    for x in r.features.iter().chain(r.optional_features) {
        assert!(!r.features.contains(x) || !r.optional_features.contains(x));
        assert!(!f.has(x));
        f.set(x, true);
        assert!(f.has(x), "{x}");
    }
}
