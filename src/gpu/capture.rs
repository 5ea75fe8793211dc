//! RenderDoc's in-application API: capture exactly one vgeo frame to a file.
//!
//! [`RenderDoc::load`] finds RenderDoc's library: the one already in the process when RenderDoc
//! launched (or injected into) vgeo, else `librenderdoc.so` from the system (Debian's
//! `renderdoc`). It must run before the Vulkan instance is created: RenderDoc hooks Vulkan through
//! its implicit layer, which the loader enables only for instances created after the library is
//! there (with `ENABLE_VULKAN_RENDERDOC_CAPTURE=1`, which the caller sets: see
//! [`RenderDoc::LAYER_ENV`]). [`RenderDoc::start`] and [`RenderDoc::end`] bracket the frame's
//! submissions on one instance; `end` returns the capture's path.

use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::path::{Path, PathBuf};

/// `eRENDERDOC_API_Version_1_4_1`: the oldest table with every entry used here (RenderDoc 1.24
/// serves up to 1.6.0, with the same layout at the front).
const API_1_4_1: c_int = 10401;

type GetApi = unsafe extern "C" fn(version: c_int, out: *mut *mut c_void) -> c_int;
type DevWnd = unsafe extern "C" fn(device: *mut c_void, window: *mut c_void);
type DevWndRet = unsafe extern "C" fn(device: *mut c_void, window: *mut c_void) -> u32;

/// The front of `RENDERDOC_API_1_4_1` (renderdoc_app.h): entries vgeo does not call are kept as
/// opaque pointers so that the offsets of the others are right.
#[repr(C)]
struct Api {
    get_api_version: unsafe extern "C" fn(*mut c_int, *mut c_int, *mut c_int),
    _set_capture_option_u32: *const c_void,
    _set_capture_option_f32: *const c_void,
    _get_capture_option_u32: *const c_void,
    _get_capture_option_f32: *const c_void,
    _set_focus_toggle_keys: *const c_void,
    _set_capture_keys: *const c_void,
    _get_overlay_bits: *const c_void,
    _mask_overlay_bits: *const c_void,
    _remove_hooks: *const c_void,
    _unload_crash_handler: *const c_void,
    set_capture_file_path_template: unsafe extern "C" fn(*const c_char),
    _get_capture_file_path_template: *const c_void,
    get_num_captures: unsafe extern "C" fn() -> u32,
    get_capture: unsafe extern "C" fn(u32, *mut c_char, *mut u32, *mut u64) -> u32,
    _trigger_capture: *const c_void,
    _is_target_control_connected: *const c_void,
    _launch_replay_ui: *const c_void,
    _set_active_window: *const c_void,
    start_frame_capture: DevWnd,
    _is_frame_capturing: *const c_void,
    end_frame_capture: DevWndRet,
    _trigger_multi_frame_capture: *const c_void,
    set_capture_file_comments: unsafe extern "C" fn(*const c_char, *const c_char),
}

/// RenderDoc's in-application API, loaded.
pub struct RenderDoc {
    api: *const Api,
    /// Keeps the library loaded (never unloaded before the process ends: RenderDoc's hooks stay).
    _lib: libloading::Library,
    /// Whether RenderDoc was in the process already (launched by RenderDoc).
    launched_by_renderdoc: bool,
    version: (i32, i32, i32),
}

// SAFETY: the API table is immutable and RenderDoc's entry points are callable from any thread.
unsafe impl Send for RenderDoc {}
// SAFETY: as above.
unsafe impl Sync for RenderDoc {}

impl RenderDoc {
    /// The variable that enables RenderDoc's Vulkan layer for instances created afterwards
    /// (set to `1` before creating the instance when RenderDoc did not launch the process).
    pub const LAYER_ENV: &'static str = "ENABLE_VULKAN_RENDERDOC_CAPTURE";

    /// Loads RenderDoc's API: the library already in the process (RenderDoc launched vgeo), else
    /// `librenderdoc.so` from the system. Call before creating the Vulkan instance. The error
    /// says what is missing (RenderDoc not installed: `apt install renderdoc`).
    pub fn load() -> Result<Self, String> {
        let names = ["librenderdoc.so", "/usr/lib/librenderdoc.so"];
        let mut launched = false;
        let mut lib = None;
        #[cfg(unix)]
        for n in names {
            // RTLD_NOLOAD: only if it is in the process already.
            // SAFETY: loading RenderDoc's library runs its initialisers, which install its hooks;
            // that is what capturing needs.
            if let Ok(l) = unsafe {
                libloading::os::unix::Library::open(
                    Some(n),
                    libloading::os::unix::RTLD_NOW | 0x4, /* RTLD_NOLOAD */
                )
            } {
                lib = Some(libloading::Library::from(l));
                launched = true;
                break;
            }
        }
        if lib.is_none() {
            let mut errors = Vec::new();
            for n in names {
                // SAFETY: as above.
                match unsafe { libloading::Library::new(n) } {
                    Ok(l) => {
                        lib = Some(l);
                        break;
                    }
                    Err(e) => errors.push(e.to_string()),
                }
            }
            if lib.is_none() {
                return Err(format!(
                    "RenderDoc is not installed or its library cannot be loaded (Debian: `apt install renderdoc`): {}",
                    errors.join("; ")
                ));
            }
        }
        let lib = lib.ok_or("RenderDoc's library")?;
        // SAFETY: RENDERDOC_GetAPI has this signature in every RenderDoc release.
        let get_api: libloading::Symbol<'_, GetApi> = unsafe { lib.get(b"RENDERDOC_GetAPI\0") }
            .map_err(|e| format!("RenderDoc's library has no RENDERDOC_GetAPI: {e}"))?;
        let mut api: *mut c_void = std::ptr::null_mut();
        // SAFETY: `api` receives a pointer to RenderDoc's static API table.
        let ok = unsafe { get_api(API_1_4_1, &mut api) };
        if ok != 1 || api.is_null() {
            return Err("this RenderDoc does not offer in-application API 1.4.1".into());
        }
        let api = api as *const Api;
        let mut v = (0, 0, 0);
        // SAFETY: `api` is RenderDoc's table of at least version 1.4.1.
        unsafe { ((*api).get_api_version)(&mut v.0, &mut v.1, &mut v.2) };
        Ok(Self {
            api,
            _lib: lib,
            launched_by_renderdoc: launched,
            version: v,
        })
    }

    /// Whether RenderDoc launched (or was injected into) this process.
    pub fn launched_by_renderdoc(&self) -> bool {
        self.launched_by_renderdoc
    }

    /// The in-application API version RenderDoc serves.
    pub fn api_version(&self) -> (i32, i32, i32) {
        self.version
    }

    /// The device pointer RenderDoc expects for a Vulkan instance: the dispatch table pointer at
    /// the start of the dispatchable handle.
    fn device_pointer(instance: ash::vk::Instance) -> *mut c_void {
        use ash::vk::Handle;
        let raw = instance.as_raw() as *const *mut c_void;
        if raw.is_null() {
            return std::ptr::null_mut();
        }
        // SAFETY: a valid VkInstance is a pointer to an object whose first word is the loader's
        // dispatch table pointer (RENDERDOC_DEVICEPOINTER_FROM_VKINSTANCE).
        unsafe { *raw }
    }

    /// Starts capturing everything submitted on `instance`'s devices until [`RenderDoc::end`].
    /// The capture is written beside `path`'s template (RenderDoc appends `_frameN.rdc`);
    /// `end` moves it to `path`.
    pub fn start(&self, instance: ash::vk::Instance, path: &Path) -> Result<(), String> {
        let template = path.with_extension("");
        let t = CString::new(template.to_string_lossy().as_bytes())
            .map_err(|_| format!("capture path {} has a NUL byte", path.display()))?;
        // SAFETY: valid API table; RenderDoc copies the string.
        unsafe {
            ((*self.api).set_capture_file_path_template)(t.as_ptr());
            ((*self.api).start_frame_capture)(Self::device_pointer(instance), std::ptr::null_mut());
        }
        Ok(())
    }

    /// Ends the capture, writes `comments` into it and moves it to `path`; the capture's path.
    pub fn end(
        &self,
        instance: ash::vk::Instance,
        path: &Path,
        comments: &str,
    ) -> Result<PathBuf, String> {
        // SAFETY: valid API table.
        let ok = unsafe {
            ((*self.api).end_frame_capture)(Self::device_pointer(instance), std::ptr::null_mut())
        };
        if ok != 1 {
            return Err(
                "RenderDoc captured nothing: its Vulkan layer is not active for vgeo's instance \
                 (load RenderDoc before creating the instance, with ENABLE_VULKAN_RENDERDOC_CAPTURE=1)"
                    .into(),
            );
        }
        // SAFETY: valid API table.
        let n = unsafe { ((*self.api).get_num_captures)() };
        if n == 0 {
            return Err("RenderDoc reports no capture written".into());
        }
        let mut len = 0u32;
        let mut ts = 0u64;
        // SAFETY: a null filename asks for the length (with the NUL).
        unsafe { ((*self.api).get_capture)(n - 1, std::ptr::null_mut(), &mut len, &mut ts) };
        let mut buf = vec![0u8; len.max(1) as usize];
        // SAFETY: `buf` holds `len` bytes.
        unsafe {
            ((*self.api).get_capture)(n - 1, buf.as_mut_ptr().cast(), &mut len, &mut ts);
        }
        let written = CStr::from_bytes_until_nul(&buf)
            .map_err(|_| "RenderDoc gave a capture path without NUL".to_string())?
            .to_string_lossy()
            .into_owned();
        if let Ok(c) = CString::new(comments) {
            let w = CString::new(written.as_bytes()).unwrap_or_default();
            // SAFETY: valid API table and strings.
            unsafe { ((*self.api).set_capture_file_comments)(w.as_ptr(), c.as_ptr()) };
        }
        let written = PathBuf::from(written);
        if written != path {
            std::fs::rename(&written, path).map_err(|e| {
                format!(
                    "moving the capture {} to {}: {e}",
                    written.display(),
                    path.display()
                )
            })?;
        }
        Ok(path.to_path_buf())
    }
}
