//! A headless EGL context, made the way MuJoCo's Python `mujoco.egl.GLContext` makes it (the
//! reference's `MUJOCO_GL=egl`): a display on the first EGL device that initialises
//! (`EGL_EXT_platform_device`), the same config attributes, desktop OpenGL, no surface.
//!
//! libEGL is opened at run time (libloading), so a machine without it gets E1501 naming the
//! Debian packages, never a link failure: the `envc` binary starts without any GL library.

use std::ffi::{c_char, c_void};
use std::sync::{Mutex, OnceLock};

use super::RenderError;

type EGLDisplay = *mut c_void;
type EGLConfig = *mut c_void;
type EGLContext = *mut c_void;
type EGLDeviceEXT = *mut c_void;
type EGLint = i32;
type EGLBoolean = u32;

const EGL_SUCCESS: EGLint = 0x3000;
const EGL_NONE: EGLint = 0x3038;
const EGL_RED_SIZE: EGLint = 0x3024;
const EGL_GREEN_SIZE: EGLint = 0x3023;
const EGL_BLUE_SIZE: EGLint = 0x3022;
const EGL_ALPHA_SIZE: EGLint = 0x3021;
const EGL_DEPTH_SIZE: EGLint = 0x3025;
const EGL_STENCIL_SIZE: EGLint = 0x3026;
const EGL_COLOR_BUFFER_TYPE: EGLint = 0x303F;
const EGL_RGB_BUFFER: EGLint = 0x308E;
const EGL_SURFACE_TYPE: EGLint = 0x3033;
const EGL_PBUFFER_BIT: EGLint = 0x0001;
const EGL_RENDERABLE_TYPE: EGLint = 0x3040;
const EGL_OPENGL_BIT: EGLint = 0x0008;
const EGL_OPENGL_API: u32 = 0x30A2;
const EGL_PLATFORM_DEVICE_EXT: u32 = 0x313F;
const EGL_DRAW: EGLint = 0x3059;
const EGL_READ: EGLint = 0x305A;

/// What to install when libEGL or Mesa's drivers are missing (Debian / Ubuntu names).
pub const PACKAGES: &str = "libegl1 libegl-mesa0 libgl1-mesa-dri libgl1";

struct Api {
    _lib: libloading::Library,
    get_error: unsafe extern "C" fn() -> EGLint,
    initialize: unsafe extern "C" fn(EGLDisplay, *mut EGLint, *mut EGLint) -> EGLBoolean,
    choose_config: unsafe extern "C" fn(
        EGLDisplay,
        *const EGLint,
        *mut EGLConfig,
        EGLint,
        *mut EGLint,
    ) -> EGLBoolean,
    bind_api: unsafe extern "C" fn(u32) -> EGLBoolean,
    create_context:
        unsafe extern "C" fn(EGLDisplay, EGLConfig, EGLContext, *const EGLint) -> EGLContext,
    make_current:
        unsafe extern "C" fn(EGLDisplay, *mut c_void, *mut c_void, EGLContext) -> EGLBoolean,
    destroy_context: unsafe extern "C" fn(EGLDisplay, EGLContext) -> EGLBoolean,
    get_current_context: unsafe extern "C" fn() -> EGLContext,
    get_current_display: unsafe extern "C" fn() -> EGLDisplay,
    get_current_surface: unsafe extern "C" fn(EGLint) -> *mut c_void,
    /// The initialised device display, shared by every context of the process (as in Python).
    display: EGLDisplay,
}

// SAFETY: the function pointers and the display handle are process-wide EGL objects; EGL's
// entry points are thread-safe.
unsafe impl Send for Api {}
// SAFETY: as for `Send`.
unsafe impl Sync for Api {}

static API: OnceLock<Result<Api, RenderError>> = OnceLock::new();
/// eglMakeCurrent / render / release is one critical section per frame: Mesa is thread-safe,
/// but MuJoCo's GL function table (glad) is process-global, so frames from several threads are
/// serialised rather than interleaved.
pub(super) static GL_LOCK: Mutex<()> = Mutex::new(());

fn load() -> Result<Api, RenderError> {
    // ENVC_EGL_LIBRARY names another libEGL (a vendor's, or a missing one to test E1501).
    let names: Vec<String> = match std::env::var("ENVC_EGL_LIBRARY") {
        Ok(n) if !n.is_empty() => vec![n],
        _ => vec!["libEGL.so.1".into(), "libEGL.so".into()],
    };
    let lib = names
        .iter()
        .find_map(|name| {
            // RTLD_GLOBAL: MuJoCo resolves GL entry points through the process's libraries.
            // SAFETY: loading libEGL runs its initialisers, which have no preconditions.
            unsafe {
                libloading::os::unix::Library::open(
                    Some(name.as_str()),
                    libloading::os::unix::RTLD_NOW | libloading::os::unix::RTLD_GLOBAL,
                )
            }
            .ok()
        })
        .ok_or_else(|| RenderError::NoGl {
            what: format!("{} could not be loaded", names.join(" / ")),
        })?;
    let lib: libloading::Library = lib.into();
    macro_rules! sym {
        ($name:literal) => {
            // SAFETY: the symbol has the EGL 1.5 signature of the field it is stored in.
            *unsafe { lib.get($name) }.map_err(|e| RenderError::NoGl {
                what: format!("libEGL lacks {}: {e}", String::from_utf8_lossy($name)),
            })?
        };
    }
    let get_proc: unsafe extern "C" fn(*const c_char) -> *mut c_void = sym!(b"eglGetProcAddress");
    let mut api = Api {
        get_error: sym!(b"eglGetError"),
        initialize: sym!(b"eglInitialize"),
        choose_config: sym!(b"eglChooseConfig"),
        bind_api: sym!(b"eglBindAPI"),
        create_context: sym!(b"eglCreateContext"),
        make_current: sym!(b"eglMakeCurrent"),
        destroy_context: sym!(b"eglDestroyContext"),
        get_current_context: sym!(b"eglGetCurrentContext"),
        get_current_display: sym!(b"eglGetCurrentDisplay"),
        get_current_surface: sym!(b"eglGetCurrentSurface"),
        display: std::ptr::null_mut(),
        _lib: lib,
    };
    // SAFETY: eglGetProcAddress takes a NUL-terminated name and returns null or the function.
    let query = unsafe { get_proc(c"eglQueryDevicesEXT".as_ptr()) };
    // SAFETY: as above.
    let platform = unsafe { get_proc(c"eglGetPlatformDisplayEXT".as_ptr()) };
    if query.is_null() || platform.is_null() {
        return Err(RenderError::NoDisplay {
            what: "EGL has no EGL_EXT_device_enumeration / EGL_EXT_platform_device (Mesa's EGL has both)".into(),
        });
    }
    // SAFETY: the two pointers are the extension functions of these signatures.
    let query: unsafe extern "C" fn(EGLint, *mut EGLDeviceEXT, *mut EGLint) -> EGLBoolean =
        unsafe { std::mem::transmute(query) };
    let platform: unsafe extern "C" fn(u32, *mut c_void, *const EGLint) -> EGLDisplay =
        // SAFETY: as above.
        unsafe { std::mem::transmute(platform) };
    let mut devices = [std::ptr::null_mut(); 10];
    let mut n = 0;
    // SAFETY: `devices` has room for 10 handles; `n` receives the count.
    if unsafe { query(10, devices.as_mut_ptr(), &mut n) } == 0 || n < 1 {
        return Err(RenderError::NoDisplay {
            what: "EGL lists no device (is libgl1-mesa-dri installed?)".into(),
        });
    }
    // MUJOCO_EGL_DEVICE_ID picks one device, as in Python.
    let chosen: Vec<EGLDeviceEXT> = match std::env::var("MUJOCO_EGL_DEVICE_ID") {
        Ok(s) => match s.trim().parse::<usize>() {
            Ok(i) if i < n as usize => vec![devices[i]],
            _ => {
                return Err(RenderError::NoDisplay {
                    what: format!(
                        "MUJOCO_EGL_DEVICE_ID must be an integer from 0 to {}, got {s:?}",
                        n - 1
                    ),
                });
            }
        },
        Err(_) => devices[..n as usize].to_vec(),
    };
    for dev in chosen {
        // SAFETY: `dev` came from eglQueryDevicesEXT; a null attribute list is allowed.
        let display = unsafe { platform(EGL_PLATFORM_DEVICE_EXT, dev, std::ptr::null()) };
        // SAFETY: a plain EGL query of this thread's last error.
        if display.is_null() || unsafe { (api.get_error)() } != EGL_SUCCESS {
            continue;
        }
        let (mut major, mut minor) = (0, 0);
        // SAFETY: a display from eglGetPlatformDisplayEXT; out-pointers are valid.
        if unsafe { (api.initialize)(display, &mut major, &mut minor) } == 1
            // SAFETY: as above.
            && unsafe { (api.get_error)() } == EGL_SUCCESS
        {
            api.display = display;
            return Ok(api);
        }
    }
    Err(RenderError::NoDisplay {
        what: "no EGL device display could be initialised".into(),
    })
}

fn api() -> Result<&'static Api, RenderError> {
    API.get_or_init(load).as_ref().map_err(Clone::clone)
}

/// One OpenGL context (desktop GL, no surface). Current only inside `Context::current`.
pub struct Context {
    ctx: EGLContext,
}

// SAFETY: the context is made current only while GL_LOCK is held and released before the lock
// is, so it is never current on two threads.
unsafe impl Send for Context {}

impl Context {
    /// A headless (surfaceless) OpenGL context from libEGL, loaded at run time.
    pub fn new() -> Result<Context, RenderError> {
        let api = api()?;
        let attributes = [
            EGL_RED_SIZE,
            8,
            EGL_GREEN_SIZE,
            8,
            EGL_BLUE_SIZE,
            8,
            EGL_ALPHA_SIZE,
            8,
            EGL_DEPTH_SIZE,
            24,
            EGL_STENCIL_SIZE,
            8,
            EGL_COLOR_BUFFER_TYPE,
            EGL_RGB_BUFFER,
            EGL_SURFACE_TYPE,
            EGL_PBUFFER_BIT,
            EGL_RENDERABLE_TYPE,
            EGL_OPENGL_BIT,
            EGL_NONE,
        ];
        let mut config = std::ptr::null_mut();
        let mut n = 0;
        // SAFETY: a NONE-terminated attribute list and room for one config.
        let ok = unsafe {
            (api.choose_config)(api.display, attributes.as_ptr(), &mut config, 1, &mut n)
        };
        if ok == 0 || n < 1 {
            return Err(RenderError::NoDisplay {
                what:
                    "no EGL config with 8-bit RGBA, 24-bit depth, 8-bit stencil and desktop OpenGL"
                        .into(),
            });
        }
        // SAFETY: plain EGL calls on the initialised display.
        unsafe { (api.bind_api)(EGL_OPENGL_API) };
        // SAFETY: as above.
        let ctx = unsafe {
            (api.create_context)(api.display, config, std::ptr::null_mut(), std::ptr::null())
        };
        if ctx.is_null() {
            return Err(RenderError::NoDisplay {
                // SAFETY: a plain EGL query of this thread's last error.
                what: format!("eglCreateContext failed (EGL error {:#x})", unsafe {
                    (api.get_error)()
                }),
            });
        }
        Ok(Context { ctx })
    }

    /// Run `f` with this context current on the calling thread, then give the thread back the
    /// context it had (another renderer's in the same process, e.g. Gymnasium's, which assumes
    /// its context stays current), or none.
    pub fn current<T>(&self, f: impl FnOnce() -> T) -> Result<T, RenderError> {
        let api = api()?;
        let _guard = GL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let none = std::ptr::null_mut();
        // SAFETY: plain queries of the calling thread's EGL state.
        let previous = unsafe {
            (
                (api.get_current_display)(),
                (api.get_current_surface)(EGL_DRAW),
                (api.get_current_surface)(EGL_READ),
                (api.get_current_context)(),
            )
        };
        // SAFETY: our context on the initialised display, no surfaces (surfaceless GL).
        if unsafe { (api.make_current)(api.display, none, none, self.ctx) } == 0 {
            return Err(RenderError::NoDisplay {
                // SAFETY: a plain EGL query of this thread's last error.
                what: format!("eglMakeCurrent failed (EGL error {:#x})", unsafe {
                    (api.get_error)()
                }),
            });
        }
        // MuJoCo's renderer raises mju_error (an offscreen buffer it cannot allocate, say):
        // guarded, it is an error after the context is given back, not a silent exit.
        let out = crate::mj::log::guard(f);
        // SAFETY: restore the thread's previous context (valid: it was current until now), or
        // release ours so that another thread may make it current.
        unsafe {
            match previous {
                (d, draw, read, ctx) if !ctx.is_null() && !d.is_null() && ctx != self.ctx => {
                    (api.make_current)(d, draw, read, ctx)
                }
                _ => (api.make_current)(api.display, none, none, std::ptr::null_mut()),
            }
        };
        out.map_err(RenderError::Mujoco)
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        if let Ok(api) = api() {
            // SAFETY: our context; it is not current on any thread (see `current`).
            unsafe { (api.destroy_context)(api.display, self.ctx) };
        }
    }
}
