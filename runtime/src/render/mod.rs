//! Headless rendering over MuJoCo's own renderer (`mjv_updateScene`, `mjr_render`,
//! `mjr_readPixels`), doing what Gymnasium's `MujocoRenderer` / `OffScreenViewer` do, step for
//! step, so that frames match the reference's (docs/rendering.md):
//! - the GL context is EGL's, made as `mujoco.egl.GLContext` makes it ([`egl`]);
//! - the offscreen buffer is `max(offwidth, width) × max(offheight, height)`, as `MujocoEnv`
//!   grows it in the model; the viewport is `width × height` at the origin;
//! - the free camera starts at the median of `geom_xpos` and `stat.extent` when the renderer is
//!   created (first render), then takes `default_camera_config`'s attributes in order;
//! - every frame sets the camera type from `camera_id` (free for -1, fixed otherwise);
//! - rows are flipped (OpenGL's first row is the bottom one); depth is the raw depth buffer
//!   in [0, 1], as Gymnasium returns it (not linearised).
//!
//! mujoco-rs 7's `MjRenderer` (feature `renderer`) is not used: it brings glutin and ~45 crates,
//! makes its context its own way (not Python's), and is `!Send`; this module needs only libEGL
//! at run time.

pub mod egl;

use std::sync::Arc;

use crate::mj::log::ffi;
use envspec::camera::{CameraKey, Located, ObjRef, RenderSettings};
use envspec::{Code, Diagnostic, Diagnostics};
use mujoco_rs::mujoco_c as c;
use mujoco_rs::mujoco_c::{
    mjData, mjModel, mjrContext, mjrRect, mjtCamera, mjtCatBit, mjtFontScale, mjtFramebuffer,
    mjtObj, mjvCamera, mjvOption, mjvPerturb, mjvScene,
};

/// Rendering problems (codes E1501–E1506, docs/errors.md).
#[derive(Debug, Clone, thiserror::Error)]
pub enum RenderError {
    /// libEGL or its OpenGL could not be loaded (E1501).
    #[error(
        "error[E1501]: no OpenGL for headless rendering ({what}); install Mesa's EGL, e.g. `sudo apt-get install {}` (scripts/setup.sh does this as root)",
        egl::PACKAGES
    )]
    NoGl {
        /// What failed to load.
        what: String,
    },
    /// EGL loaded but gave no headless context (E1502).
    #[error(
        "error[E1502]: EGL gives no headless OpenGL context: {what}; with Mesa (`apt-get install {}`) the software rasteriser llvmpipe serves when there is no GPU",
        egl::PACKAGES
    )]
    NoDisplay {
        /// What EGL refused.
        what: String,
    },
    /// Settings or names that do not check out (E1503, E1505), with their locations.
    #[error("{0}")]
    Spec(Arc<Diagnostics>),
    /// A render mode that is not one of `RenderMode::NAMES` (E1504).
    #[error(
        "error[E1504]: unknown render mode `{0}`; expected rgb_array, depth_array or rgbd_tuple"
    )]
    Mode(String),
    /// A rendering setting that does not fit (E1505).
    #[error("error[E1505]: {0}")]
    Setting(String),
    /// MuJoCo's renderer failed, e.g. on a frame or scene larger than it can hold (E1507).
    #[error(
        "error[E1507]: MuJoCo's renderer failed: {0}; a smaller frame (width, height) or max_geom may fit"
    )]
    Mujoco(String),
}

impl RenderError {
    /// The stable code (docs/errors.md).
    pub fn code(&self) -> Code {
        match self {
            RenderError::NoGl { .. } => Code::E1501,
            RenderError::NoDisplay { .. } => Code::E1502,
            RenderError::Spec(d) => d.0.first().map(|d| d.code).unwrap_or(Code::E1505),
            RenderError::Mode(_) => Code::E1504,
            RenderError::Setting(_) => Code::E1505,
            RenderError::Mujoco(_) => Code::E1507,
        }
    }
}

impl From<Diagnostics> for RenderError {
    fn from(d: Diagnostics) -> Self {
        RenderError::Spec(Arc::new(d))
    }
}

/// Gymnasium's render modes (`human` needs a window and is not served).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderMode {
    /// `rgb_array`: an RGB image.
    RgbArray,
    /// `depth_array`: the depth buffer.
    DepthArray,
    /// `rgbd_tuple`: both, from one render.
    RgbdTuple,
}

impl RenderMode {
    /// The modes' Gymnasium names, as `parse` takes them.
    pub const NAMES: &'static [&'static str] = &["rgb_array", "depth_array", "rgbd_tuple"];
    /// The mode of a Gymnasium name (E1504 for any other).
    pub fn parse(s: &str) -> Result<RenderMode, RenderError> {
        match s {
            "rgb_array" => Ok(RenderMode::RgbArray),
            "depth_array" => Ok(RenderMode::DepthArray),
            "rgbd_tuple" => Ok(RenderMode::RgbdTuple),
            _ => Err(RenderError::Mode(s.to_string())),
        }
    }
    fn rgb(self) -> bool {
        self != RenderMode::DepthArray
    }
    fn depth(self) -> bool {
        self != RenderMode::RgbArray
    }
}

/// One rendered frame, top row first: `rgb` is `height × width × 3` bytes, `depth` is
/// `height × width` raw depth-buffer values; each is present when the mode asks for it.
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// RGB bytes, when the mode asks for colour.
    pub rgb: Option<&'a [u8]>,
    /// Depth values, when the mode asks for depth.
    pub depth: Option<&'a [f32]>,
}

/// The camera of a spec's settings, names resolved against a compiled model.
#[derive(Clone, Debug)]
struct Camera {
    /// `camera_id` after `camera_name`: -1 for the free viewer camera.
    id: i32,
    /// `default_camera_config` with ids for names.
    config: Vec<Key>,
    /// The config sets `type` itself (an envc extension: a tracking camera in one line).
    own_type: bool,
}

#[derive(Clone, Copy, Debug)]
enum Key {
    Type(i32),
    FixedCam(i32),
    TrackBody(i32),
    Lookat([f64; 3]),
    Distance(f64),
    Azimuth(f64),
    Elevation(f64),
    Orthographic(i32),
}

fn lookup(
    m: &mjModel,
    r: &Located<ObjRef>,
    obj: mjtObj,
    count: i64,
    what: &str,
) -> Result<i32, Diagnostic> {
    let id = match &r.value {
        ObjRef::Id(i) => {
            if *i >= -1 && *i < count {
                return Ok(*i as i32);
            }
            -2
        }
        ObjRef::Name(n) => crate::mj::names::id(m, obj, n).map_or(-1, |i| i as i32),
    };
    if id >= 0 {
        return Ok(id);
    }
    let names = model_names(m, obj, count);
    let (message, label) = match &r.value {
        ObjRef::Id(i) => (
            format!("{what} {i} is not in the model ({} = {i})", r.param),
            format!("expected -1 or an id below {count}"),
        ),
        ObjRef::Name(n) => (
            format!("the model has no {what} `{n}` ({})", r.param),
            if names.is_empty() {
                format!("the model has no {what}s")
            } else {
                format!("expected one of: {}", names.join(", "))
            },
        ),
    };
    let help = match &r.value {
        ObjRef::Name(n) => envspec::diagnostic::suggest(n, names.iter().map(String::as_str)),
        ObjRef::Id(_) => None,
    };
    Err(Diagnostic::new(Code::E1503, message)
        .at_opt(r.loc.clone())
        .label(label)
        .help_opt(help))
}

fn model_names(m: &mjModel, obj: mjtObj, count: i64) -> Vec<String> {
    (0..usize::try_from(count).unwrap_or(0))
        .filter_map(|i| crate::mj::names::name(m, obj, i))
        .filter(|n| !n.is_empty())
        .collect()
}

/// Check a spec's rendering settings against its compiled model (no GL needed): every named
/// camera and tracked body exists. Called when an env is built, so the mistake is a spec error.
pub fn check(m: &mjModel, s: &RenderSettings) -> Result<(), RenderError> {
    resolve_camera(m, s).map(|_| ())
}

fn resolve_camera(m: &mjModel, s: &RenderSettings) -> Result<Camera, RenderError> {
    let mut d = Diagnostics::default();
    let id = match &s.camera {
        None => -1,
        Some(r) => lookup(m, r, mjtObj::mjOBJ_CAMERA, m.ncam, "camera").unwrap_or_else(|e| {
            d.push(e);
            -1
        }),
    };
    let mut config = vec![];
    let mut own_type = false;
    for k in &s.camera_config {
        config.push(match k {
            CameraKey::Type(t) => {
                own_type = true;
                Key::Type(*t)
            }
            CameraKey::FixedCam(r) => Key::FixedCam(
                lookup(m, r, mjtObj::mjOBJ_CAMERA, m.ncam, "camera").unwrap_or_else(|e| {
                    d.push(e);
                    -1
                }),
            ),
            CameraKey::TrackBody(r) => Key::TrackBody(
                lookup(m, r, mjtObj::mjOBJ_BODY, m.nbody, "body").unwrap_or_else(|e| {
                    d.push(e);
                    -1
                }),
            ),
            CameraKey::Lookat(x) => Key::Lookat(*x),
            CameraKey::Distance(x) => Key::Distance(*x),
            CameraKey::Azimuth(x) => Key::Azimuth(*x),
            CameraKey::Elevation(x) => Key::Elevation(*x),
            CameraKey::Orthographic(x) => Key::Orthographic(*x),
        });
    }
    d.into_result(Camera {
        id,
        config,
        own_type,
    })
    .map_err(RenderError::from)
}

/// numpy's `np.median` of a column: the middle value, or the mean of the two middle ones.
fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// One env's renderer: its GL context, MuJoCo scene and context, camera and output buffers.
pub struct Renderer {
    // Field order is drop order: MuJoCo's GL objects go before the context (see Drop).
    con: Box<mjrContext>,
    scn: Box<mjvScene>,
    cam: mjvCamera,
    opt: mjvOption,
    pert: mjvPerturb,
    camera: Camera,
    viewport: mjrRect,
    raw_rgb: Vec<u8>,
    raw_depth: Vec<f32>,
    rgb: Vec<u8>,
    depth: Vec<f32>,
    ctx: egl::Context,
}

// SAFETY: the scene and MuJoCo's GL context are only touched while `ctx` is current, which
// `egl::Context::current` makes so on the calling thread under a process-wide lock.
unsafe impl Send for Renderer {}
// SAFETY: every method that touches GL or MuJoCo's render state takes `&mut self`.
unsafe impl Sync for Renderer {}

impl Renderer {
    /// Make the renderer for a model in its current state (`d` gives the free camera's
    /// starting point, as Gymnasium's viewer takes it at its first render).
    pub fn new(m: &mjModel, d: &mjData, s: &RenderSettings) -> Result<Renderer, RenderError> {
        let camera = resolve_camera(m, s)?;
        let ctx = egl::Context::new()?;
        // SAFETY: zeroed then initialised by MuJoCo's default functions (plain C structs).
        let mut cam: mjvCamera = unsafe { std::mem::zeroed() };
        // SAFETY: as above.
        let mut opt: mjvOption = unsafe { std::mem::zeroed() };
        // SAFETY: as above.
        let mut pert: mjvPerturb = unsafe { std::mem::zeroed() };
        // SAFETY: as above.
        let mut scn: Box<mjvScene> = Box::new(unsafe { std::mem::zeroed() });
        // SAFETY: as above.
        let mut con: Box<mjrContext> = Box::new(unsafe { std::mem::zeroed() });
        // SAFETY: the structs made above; plain C calls that fill them with MuJoCo's defaults.
        unsafe {
            c::mjv_defaultCamera(&mut cam);
            c::mjv_defaultOption(&mut opt);
            c::mjv_defaultPerturb(&mut pert);
            c::mjv_defaultScene(&mut *scn);
            c::mjr_defaultContext(&mut *con);
        }
        for &(flag, on) in &s.visual_options {
            opt.flags[flag] = on as u8;
        }
        for &(g, on) in &s.geom_groups {
            opt.geomgroup[g] = on as u8;
        }
        let (w, h) = (s.width as i32, s.height as i32);
        let made = ctx.current(|| {
            // The model as MujocoEnv leaves it: offscreen buffer grown to the frame, never
            // shrunk. A copy, so the env's (maybe shared) model is untouched.
            // SAFETY: mj_copyModel allocates a copy of a valid model; freed below, also when
            // MuJoCo raises an error in between (the inner guard).
            let copy = unsafe { ffi::mj_copyModel(std::ptr::null_mut(), m) };
            if copy.is_null() {
                return Ok(false);
            }
            // SAFETY: `copy` is a live model copy (checked non-null), `m` the env's model; `scn`
            // and `con` were set to defaults, and this thread's GL context is current.
            let made = crate::mj::log::guard(|| unsafe {
                let g = &mut (*copy).vis.global;
                g.offwidth = g.offwidth.max(w);
                g.offheight = g.offheight.max(h);
                ffi::mjv_makeScene(m, &mut *scn, s.max_geom as i32);
                ffi::mjr_makeContext(copy, &mut *con, mjtFontScale::mjFONTSCALE_150 as i32);
                ffi::mjr_setBuffer(mjtFramebuffer::mjFB_OFFSCREEN as i32, &mut *con);
            });
            // SAFETY: our own copy, no longer used: the scene and context keep no pointer to it.
            unsafe { c::mj_deleteModel(copy) };
            made.map(|()| con.offFBO != 0)
        })?;
        let made = match made {
            Ok(made) => made,
            Err(e) => {
                // What MuJoCo made before the error: freed with the context current.
                // SAFETY: the scene and context MuJoCo made part of, freed with their GL context
                // current.
                let _ = ctx.current(|| unsafe {
                    ffi::mjr_freeContext(&mut *con);
                    ffi::mjv_freeScene(&mut *scn);
                });
                return Err(RenderError::Mujoco(e));
            }
        };
        if !made {
            return Err(RenderError::NoDisplay {
                what: "MuJoCo could not make its offscreen framebuffer (mjr_makeContext)".into(),
            });
        }
        // OffScreenViewer._init_camera, then MujocoRenderer._set_cam_config.
        cam.type_ = mjtCamera::mjCAMERA_FREE as i32;
        cam.fixedcamid = -1;
        let ngeom = m.ngeom as usize;
        for i in 0..3 {
            // SAFETY: geom_xpos holds ngeom × 3 numbers.
            let col = (0..ngeom)
                .map(|g| unsafe { *d.geom_xpos.add(3 * g + i) })
                .collect();
            cam.lookat[i] = median(col);
        }
        cam.distance = m.stat.extent;
        for k in &camera.config {
            match *k {
                Key::Type(t) => cam.type_ = t,
                Key::FixedCam(i) => cam.fixedcamid = i,
                Key::TrackBody(i) => cam.trackbodyid = i,
                Key::Lookat(x) => cam.lookat = x,
                Key::Distance(x) => cam.distance = x,
                Key::Azimuth(x) => cam.azimuth = x,
                Key::Elevation(x) => cam.elevation = x,
                Key::Orthographic(x) => cam.orthographic = x,
            }
        }
        let n = (s.width * s.height) as usize;
        Ok(Renderer {
            con,
            scn,
            cam,
            opt,
            pert,
            camera,
            viewport: mjrRect {
                left: 0,
                bottom: 0,
                width: w,
                height: h,
            },
            raw_rgb: vec![0; 3 * n],
            raw_depth: vec![0.0; n],
            rgb: vec![0; 3 * n],
            depth: vec![0.0; n],
            ctx,
        })
    }

    /// Render the current state. Allocates nothing: the frame lives in this renderer's buffers.
    /// `tint[g]`, where given, replaces geom `g`'s colour in this frame only (the model is shared
    /// and stays untouched).
    pub fn render(
        &mut self,
        m: &mjModel,
        d: &mut mjData,
        mode: RenderMode,
        tint: &[Option<[f32; 4]>],
    ) -> Result<Frame<'_>, RenderError> {
        // OffScreenViewer.render: camera_id is never None by then (-1 for the free camera).
        if self.camera.id == -1 {
            if !self.camera.own_type {
                self.cam.type_ = mjtCamera::mjCAMERA_FREE as i32;
            }
        } else {
            self.cam.type_ = mjtCamera::mjCAMERA_FIXED as i32;
        }
        if self.camera.id != -1 || !self.camera.own_type {
            self.cam.fixedcamid = self.camera.id;
        }
        let (rgb, depth) = (mode.rgb(), mode.depth());
        let Renderer {
            con,
            scn,
            cam,
            opt,
            pert,
            viewport,
            raw_rgb,
            raw_depth,
            ctx,
            ..
        } = self;
        ctx.current(|| unsafe {
            // SAFETY: the context is current; model, data, scene and buffers are valid and
            // the buffers hold width × height pixels.
            ffi::mjr_setBuffer(mjtFramebuffer::mjFB_OFFSCREEN as i32, &mut **con);
            ffi::mjv_updateScene(
                m,
                d,
                &*opt,
                &*pert,
                cam,
                mjtCatBit::mjCAT_ALL as i32,
                &mut **scn,
            );
            if !tint.is_empty() {
                // SAFETY: mjv_updateScene filled `ngeom` entries of `geoms`.
                let geoms = std::slice::from_raw_parts_mut(scn.geoms, scn.ngeom.max(0) as usize);
                for g in geoms {
                    if g.objtype == mjtObj::mjOBJ_GEOM as i32
                        && let Some(Some(rgba)) =
                            usize::try_from(g.objid).ok().and_then(|i| tint.get(i))
                    {
                        g.rgba = *rgba;
                    }
                }
            }
            ffi::mjr_render(*viewport, &mut **scn, &**con);
            ffi::mjr_readPixels(
                if rgb {
                    raw_rgb.as_mut_ptr()
                } else {
                    std::ptr::null_mut()
                },
                if depth {
                    raw_depth.as_mut_ptr()
                } else {
                    std::ptr::null_mut()
                },
                *viewport,
                &**con,
            );
        })?;
        let (w, h) = (self.viewport.width as usize, self.viewport.height as usize);
        if rgb {
            for (dst, src) in self
                .rgb
                .chunks_exact_mut(3 * w)
                .zip(self.raw_rgb.chunks_exact(3 * w).rev())
            {
                dst.copy_from_slice(src);
            }
        }
        if depth {
            for (dst, src) in self
                .depth
                .chunks_exact_mut(w)
                .zip(self.raw_depth.chunks_exact(w).rev())
            {
                dst.copy_from_slice(src);
            }
        }
        Ok(Frame {
            width: w,
            height: h,
            rgb: rgb.then_some(&self.rgb[..]),
            depth: depth.then_some(&self.depth[..]),
        })
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        let Renderer { con, scn, ctx, .. } = self;
        // mjr_freeContext deletes GL objects: the context must be current.
        let _ = ctx.current(|| unsafe {
            // SAFETY: both were made in `new` and are freed once.
            ffi::mjr_freeContext(&mut **con);
            ffi::mjv_freeScene(&mut **scn);
        });
    }
}

/// An env's rendering state: its settings (checked when the env is built) and the renderer,
/// made on the first frame.
pub struct EnvRender {
    settings: RenderSettings,
    renderer: Option<Box<Renderer>>,
    /// Per-geom colour overrides (empty: the model's colours).
    tint: Vec<Option<[f32; 4]>>,
}

impl EnvRender {
    /// Read and check the spec's rendering settings against the compiled model.
    pub fn new(params: &[envspec::Param], m: &mjModel) -> Result<EnvRender, RenderError> {
        let settings = RenderSettings::from_params(params)?;
        check(m, &settings)?;
        Ok(EnvRender {
            settings,
            renderer: None,
            tint: vec![],
        })
    }
    /// Draw geom `g` in `tint[g]` where given (empty: the model's colours).
    pub fn set_tint(&mut self, tint: Vec<Option<[f32; 4]>>) {
        self.tint = tint;
    }
    /// Render a frame, making the renderer first if there is none yet.
    pub fn frame(
        &mut self,
        m: &mjModel,
        d: &mut mjData,
        mode: RenderMode,
    ) -> Result<Frame<'_>, RenderError> {
        let r = match &mut self.renderer {
            Some(r) => r,
            slot => slot.insert(Box::new(Renderer::new(m, d, &self.settings)?)),
        };
        r.render(m, d, mode, &self.tint)
    }
    /// [`EnvRender::frame`] of an env's model and data.
    pub(crate) fn frame_of<M: mujoco_rs::wrappers::mj_model::traits::ModelType>(
        &mut self,
        model: &mujoco_rs::prelude::MjModel,
        data: &mut mujoco_rs::prelude::MjData<M>,
        mode: RenderMode,
    ) -> Result<Frame<'_>, RenderError> {
        // SAFETY: mjv_updateScene reads the state and writes only visualisation fields, which no
        // invariant of mujoco-rs's wrapper covers.
        let d = unsafe { data.ffi_mut() };
        self.frame(model.ffi(), d, mode)
    }
    /// Drop the renderer (Gymnasium's `close`); the next frame makes a new one.
    pub fn close(&mut self) {
        self.renderer = None;
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn median_is_numpys() {
        assert_eq!(super::median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(super::median(vec![4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(super::median(vec![]).is_nan());
    }
}
