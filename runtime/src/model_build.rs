//! Building the model a spec runs on: the model file as is, or, when the spec has `[actuators]` or
//! `[physics]`, the file loaded into an mjSpec, edited and compiled. Works the same for MJCF and
//! URDF files (MuJoCo reads both).

use envspec::ir::{
    ActuatorKind, AddedActuator, AddedElement, AddedGeomType, Integrator, ModelEdits, SolverOption,
};
use envspec::mjcf::JointKind;
use mujoco_rs::mujoco_c::mjtIntegrator;
use mujoco_rs::prelude::*;
use mujoco_rs::wrappers::mj_editing::{MjsBody, MjtLimited, PositionConfig};

/// E1001 as people read it. MuJoCo's message ends by naming the element and its line in the
/// model file (`Element 'joint', line 4` for XML errors, `Element name 'torso', id 1, line 7`
/// for compile errors); the error is then a diagnostic at `model.xml:line:col` showing that line,
/// as spec errors are. Line 0 (an element from an `<include>`d file) or no line keeps the plain
/// form.
pub(crate) fn compile_error_text(path: &std::path::Path, message: &str) -> String {
    let message = message.trim_start_matches("model load failed: ").trim();
    let plain = || {
        format!(
            "error[E1001]: MuJoCo could not compile {}: {}",
            path.display(),
            envspec::diagnostic::escape(message)
        )
    };
    let (what, element) = match message.rfind("\nElement ") {
        Some(i) => (message[..i].trim(), &message[i + 1..]),
        None => return plain(),
    };
    let Some(line) = element
        .rsplit_once(", line ")
        .and_then(|(_, n)| n.trim().parse::<usize>().ok())
        .filter(|&n| n > 0)
    else {
        return plain();
    };
    // (MuJoCo has read the file, so it is within the limit; any failure keeps the plain form)
    let limit = envspec::limits::MAX_MODEL_BYTES;
    let unreadable = |e: envspec::limits::ReadError| {
        envspec::Diagnostic::new(envspec::Code::E1001, e.to_string())
    };
    let read = envspec::source::read_source(path, limit, envspec::Code::E1001, "", unreadable);
    let Ok(file) = read else {
        return plain();
    };
    let Some(start) = file.offset(line, 1) else {
        return plain();
    };
    let quoted = |after: &str| -> Option<String> {
        let rest = &what[what.find(after)? + after.len()..];
        Some(rest[..rest.find('\'')?].to_string())
    };
    let text = &file.text[start..];
    let text = &text[..text.find('\n').unwrap_or(text.len())];
    // The span: the attribute an XML error names, else the element's tag (`Element 'joint'`),
    // else the line's first non-blank text.
    // (a compile error names the kind last: "size 0 must be positive in geom")
    let tag = element
        .strip_prefix("Element '")
        .and_then(|t| t.split('\'').next())
        .or_else(|| what.rsplit_once(" in ").map(|(_, k)| k.trim()))
        .filter(|t| !t.is_empty() && text.contains(&format!("<{t}")));
    let attr = quoted("attribute: '").or_else(|| quoted("attribute '"));
    let find = |needle: &str| text.find(needle).map(|i| (i, needle.len()));
    let (at, len) = attr
        .and_then(|a| find(&format!("{a}=")).map(|(i, _)| (i, a.len())))
        .or_else(|| tag.and_then(|t| find(&format!("<{t}"))))
        .unwrap_or_else(|| {
            let i = text.len() - text.trim_start().len();
            (i, text.trim().len().max(1))
        });
    let label = match tag {
        Some(t) => format!("MuJoCo's error is about this <{t}>"),
        None => format!("MuJoCo's error is about this element ({})", element.trim()),
    };
    envspec::Diagnostic::new(
        envspec::Code::E1001,
        format!("MuJoCo could not compile {}: {what}", path.display()),
    )
    .at(envspec::Location::new(&file, start + at..start + at + len))
    .label(label)
    .to_string()
    .trim_end()
    .to_string()
}

/// Load the model file into an mjSpec, apply the edits and compile it.
pub(crate) fn compile_edited(
    path: &std::path::Path,
    edits: &ModelEdits,
) -> Result<MjModel, String> {
    let mut model = crate::mj::catch::compile(&mut load_edited(path, edits)?)?;
    fill_keyframes(edits, &mut model);
    Ok(model)
}

/// Write the spec's keyframes into the compiled model: MuJoCo compiled them as `qpos0` (the
/// spec gave no qpos), so copy the model keyframe each starts `from`, then the spec's values.
pub(crate) fn fill_keyframes(edits: &ModelEdits, model: &mut MjModel) {
    if edits.keyframes.is_empty() {
        return;
    }
    // The spec's keyframes are the last ones and every address is below nq (envspec resolved
    // them against the model's joints).
    let (nq, nkey) = (model.ffi().nq as usize, model.ffi().nkey as usize);
    let first = nkey - edits.keyframes.len();
    let keys = model.key_qpos_mut();
    for (i, k) in edits.keyframes.iter().enumerate() {
        let row = (first + i) * nq;
        if let Some(from) = k.from {
            keys.copy_within(from * nq..from * nq + nq, row);
        }
        for &(adr, x) in &k.values {
            keys[row + adr] = x;
        }
    }
}

/// Load the model file into an mjSpec and apply the edits (a maze then adds its world).
pub(crate) fn load_edited(path: &std::path::Path, edits: &ModelEdits) -> Result<MjSpec, String> {
    let mut spec = crate::mj::catch::parse(path)?;
    if let Some(ts) = edits.timestep {
        spec.option_mut().timestep = ts;
    }
    if let Some(i) = edits.integrator {
        spec.option_mut().integrator = match i {
            Integrator::Euler => mjtIntegrator::mjINT_EULER,
            Integrator::Rk4 => mjtIntegrator::mjINT_RK4,
            Integrator::Implicit => mjtIntegrator::mjINT_IMPLICIT,
            Integrator::ImplicitFast => mjtIntegrator::mjINT_IMPLICITFAST,
        } as i32;
    }
    for &(option, x) in &edits.solver {
        let o = spec.option_mut();
        // The resolver checked each value's range; integers are whole numbers.
        match option {
            SolverOption::Cone => o.cone = x as i32,
            SolverOption::Iterations => o.iterations = x as i32,
            SolverOption::LsIterations => o.ls_iterations = x as i32,
            SolverOption::NoslipIterations => o.noslip_iterations = x as i32,
            SolverOption::CcdIterations => o.ccd_iterations = x as i32,
            SolverOption::Tolerance => o.tolerance = x,
            SolverOption::LsTolerance => o.ls_tolerance = x,
            SolverOption::Impratio => o.impratio = x,
        }
    }
    for e in &edits.added {
        add_element(&mut spec, e)?;
    }
    if let Some(t) = &edits.terrain {
        add_terrain(&mut spec, t)?;
    }
    for a in &edits.actuators {
        add_actuator(&mut spec, a)?;
    }
    for k in &edits.keyframes {
        c_name("keyframe", &k.name)?;
        spec.add_key()
            .set_name(&k.name)
            .map_err(|e| format!("cannot add keyframe `{}`: {e}", k.name))?;
    }
    for g in &edits.geoms {
        let geom = spec
            .geom_mut(&g.geom)
            .ok_or_else(|| format!("no geom `{}` to set properties of", g.geom))?;
        let [contype, conaffinity, condim, priority] = g.ints;
        if let Some(x) = contype {
            geom.set_contype(x);
        }
        if let Some(x) = conaffinity {
            geom.set_conaffinity(x);
        }
        if let Some(x) = condim {
            geom.set_condim(x);
        }
        if let Some(x) = priority {
            geom.set_priority(x);
        }
        let [solmix, margin, gap] = g.reals;
        if let Some(x) = solmix {
            geom.set_solmix(x);
        }
        if let Some(x) = margin {
            geom.set_margin(x);
        }
        if let Some(x) = gap {
            geom.set_gap(x);
        }
        // The resolver keeps at most 3, 2 and 5 entries: the leading ones are set.
        for (dst, src) in geom.friction_mut().iter_mut().zip(&g.friction) {
            *dst = *src;
        }
        for (dst, src) in geom.solref_mut().iter_mut().zip(&g.solref) {
            *dst = *src;
        }
        for (dst, src) in geom.solimp_mut().iter_mut().zip(&g.solimp) {
            *dst = *src;
        }
    }
    for j in &edits.joints {
        let joint = spec
            .joint_mut(&j.joint)
            .ok_or_else(|| format!("no joint `{}` to set properties of", j.joint))?;
        if let Some(x) = j.armature {
            joint.set_armature(x);
        }
        if let Some(x) = j.damping {
            joint.damping_mut()[0] = x;
        }
        if let Some(x) = j.frictionloss {
            joint.set_frictionloss(x);
        }
    }
    Ok(spec)
}

fn geom_type(t: AddedGeomType) -> MjtGeomBase {
    match t {
        AddedGeomType::Sphere => MjtGeomBase::mjGEOM_SPHERE,
        AddedGeomType::Box => MjtGeomBase::mjGEOM_BOX,
        AddedGeomType::Capsule => MjtGeomBase::mjGEOM_CAPSULE,
        AddedGeomType::Cylinder => MjtGeomBase::mjGEOM_CYLINDER,
        AddedGeomType::Plane => MjtGeomBase::mjGEOM_PLANE,
    }
}

/// The body an added element hangs from (`world`, a model body, or one added before).
fn body_named<'s>(spec: &'s mut MjSpec, name: &str) -> Result<&'s mut MjsBody, String> {
    if name == "world" {
        return Ok(spec.world_body_mut());
    }
    spec.body_mut(name)
        .ok_or_else(|| format!("no body `{name}` to attach to"))
}

/// A name mujoco-rs can pass to MuJoCo (it panics on a NUL byte; envspec refuses such names
/// first, this keeps a spec built another way from panicking).
fn c_name(what: &str, name: &str) -> Result<(), String> {
    if name.contains('\0') {
        return Err(format!(
            "cannot add {what} `{}`: its name contains a NUL byte",
            name.escape_debug()
        ));
    }
    Ok(())
}

/// `r` with the element it was adding named in its error.
fn named(what: &str, name: &str, r: Result<(), MjEditError>) -> Result<(), String> {
    r.map_err(|err| format!("cannot add {what} `{name}`: {err}"))
}

/// A `weld` of an added body to body `to`.
fn add_weld(spec: &mut MjSpec, name: &str, to: &str) -> Result<(), String> {
    c_name("a weld to body", to)?;
    // As the MJCF parser leaves `<weld body1 body2>`: anchor and relative pose all
    // zero, so the compiler takes the pose at qpos0 (mjSpec's own default differs);
    // `[init] reset_welds` makes it the identity later.
    let eq = spec.add_equality();
    eq.set_type(MjtEq::mjEQ_WELD);
    eq.set_objtype(MjtObjBase::mjOBJ_BODY);
    eq.set_name1(name);
    eq.set_name2(to);
    eq.data_mut()[..10].fill(0.0);
    Ok(())
}

/// An added body's joints: name, kind and axis each.
fn add_joints(b: &mut MjsBody, joints: &[(String, JointKind, [f64; 3])]) -> Result<(), String> {
    for (j, kind, axis) in joints {
        let jt = b.add_joint();
        named("joint", j, jt.set_name(j))?;
        jt.set_type(match kind {
            JointKind::Slide => MjtJoint::mjJNT_SLIDE,
            JointKind::Hinge => MjtJoint::mjJNT_HINGE,
            JointKind::Free => MjtJoint::mjJNT_FREE,
            JointKind::Ball => MjtJoint::mjJNT_BALL,
        });
        *jt.axis_mut() = *axis;
    }
    Ok(())
}

/// An added body's marker geom: no contacts, and a small mass so the joints have inertia.
fn add_marker(
    b: &mut MjsBody,
    t: AddedGeomType,
    size: [f64; 3],
    rgba: [f32; 4],
    mass: Option<f64>,
) {
    let g = b.add_geom();
    g.set_type(geom_type(t));
    *g.size_mut() = size;
    *g.rgba_mut() = rgba;
    g.set_contype(0);
    g.set_conaffinity(0);
    if let Some(m) = mass {
        g.set_mass(m);
    }
}

/// The names an added element gives MuJoCo (its own, its joints', its body's) pass `c_name`.
fn check_names(e: &AddedElement) -> Result<(), String> {
    let (name, body) = match e {
        AddedElement::Body { name, joints, .. } => {
            for (j, _, _) in joints {
                c_name("joint", j)?;
            }
            (name, None)
        }
        AddedElement::Site { name, body, .. }
        | AddedElement::Geom { name, body, .. }
        | AddedElement::Camera { name, body, .. }
        | AddedElement::Light { name, body, .. } => (name, Some(body)),
    };
    c_name("element", name)?;
    if let Some(b) = body {
        c_name("an element to body", b)?;
    }
    Ok(())
}

/// Add a spec's `[bodies]`, `[sites]`, `[geoms]`, `[cameras]` or `[lights]` element.
fn add_element(spec: &mut MjSpec, e: &AddedElement) -> Result<(), String> {
    check_names(e)?;
    match e {
        AddedElement::Body {
            name,
            pos,
            joints,
            geom,
            mocap,
            gravcomp,
            mass,
            weld,
        } => {
            if let Some(w) = weld {
                add_weld(spec, name, w)?;
            }
            let b = spec.world_body_mut().add_body();
            named("body", name, b.set_name(name))?;
            *b.pos_mut() = *pos;
            b.set_mocap(*mocap);
            b.set_gravcomp(*gravcomp);
            add_joints(b, joints)?;
            if let Some((t, size, rgba)) = geom {
                add_marker(b, *t, *size, *rgba, *mass);
            }
        }
        AddedElement::Site {
            name,
            body,
            pos,
            size,
            rgba,
        } => {
            let s = body_named(spec, body)?.add_site();
            named("site", name, s.set_name(name))?;
            *s.pos_mut() = *pos;
            s.size_mut()[0] = *size;
            *s.rgba_mut() = *rgba;
        }
        AddedElement::Geom {
            name,
            body,
            kind,
            pos,
            size,
            rgba,
            contact,
            mass,
            density,
        } => {
            let g = body_named(spec, body)?.add_geom();
            named("geom", name, g.set_name(name))?;
            g.set_type(geom_type(*kind));
            *g.pos_mut() = *pos;
            *g.size_mut() = *size;
            *g.rgba_mut() = *rgba;
            if !contact {
                g.set_contype(0);
                g.set_conaffinity(0);
            }
            if let Some(m) = mass {
                g.set_mass(*m);
            }
            if let Some(d) = density {
                g.set_density(*d);
            }
        }
        AddedElement::Camera {
            name,
            body,
            pos,
            xyaxes,
            fovy,
        } => {
            let c = body_named(spec, body)?.add_camera();
            named("camera", name, c.set_name(name))?;
            *c.pos_mut() = *pos;
            if let Some(x) = xyaxes {
                c.alt_mut().set_xy_axis(x);
            }
            if let Some(f) = fovy {
                c.set_fovy(*f);
            }
        }
        AddedElement::Light {
            name,
            body,
            pos,
            dir,
        } => {
            let l = body_named(spec, body)?.add_light();
            named("light", name, l.set_name(name))?;
            *l.pos_mut() = *pos;
            *l.dir_mut() = *dir;
        }
    }
    Ok(())
}

/// The name of the model's numeric that holds each terrain tile's spawn origin (x, y, z, row-major
/// over rows × cols): the compiled model carries them, so every env of a vector env reads them
/// without generating the terrain again.
pub(crate) const TERRAIN_ORIGINS: &str = "envc_terrain_origins";

/// `[terrain]`'s geoms on the world body (boxes, and heightfields with their fields), and the
/// tiles' spawn origins.
fn add_terrain(spec: &mut MjSpec, t: &envspec::ir::Terrain) -> Result<(), String> {
    use crate::terrain::TerrainGeom;
    let g = crate::terrain::generate(t);
    // Terrain grey; the robot keeps its own colours.
    const RGBA: [f32; 4] = [0.5, 0.5, 0.5, 1.0];
    for (i, geom) in g.geoms.iter().enumerate() {
        match geom {
            TerrainGeom::Box(b) => {
                let gm = spec.world_body_mut().add_geom();
                gm.set_type(MjtGeomBase::mjGEOM_BOX);
                *gm.pos_mut() = b.pos;
                *gm.size_mut() = b.size;
                *gm.rgba_mut() = RGBA;
            }
            TerrainGeom::Field(f) => {
                let name = format!("envc_terrain_{i}");
                let h = spec.add_hfield().with_size(f.size);
                h.set_name(&name)
                    .map_err(|e| format!("cannot add heightfield `{name}`: {e}"))?;
                h.set_nrow(f.nrow as i32);
                h.set_ncol(f.ncol as i32);
                h.set_userdata(&f.data);
                let gm = spec.world_body_mut().add_geom();
                gm.set_type(MjtGeomBase::mjGEOM_HFIELD);
                gm.set_hfieldname(&name);
                *gm.pos_mut() = f.pos;
                *gm.rgba_mut() = RGBA;
            }
        }
    }
    let n = spec.add_numeric();
    n.set_name(TERRAIN_ORIGINS)
        .map_err(|e| format!("cannot add the terrain origins: {e}"))?;
    let flat: Vec<f64> = g.origins.iter().flatten().copied().collect();
    n.set_data(&flat);
    n.set_size(flat.len() as i32)
        .map_err(|e| format!("cannot size the terrain origins: {e}"))?;
    Ok(())
}

fn add_actuator(spec: &mut MjSpec, a: &AddedActuator) -> Result<(), String> {
    c_name("actuator", &a.name)?;
    c_name("an actuator of joint", &a.joint)?;
    let act = spec.add_actuator();
    act.set_name(&a.name)
        .map_err(|e| format!("cannot add actuator `{}`: {e}", a.name))?;
    act.set_trntype(MjtTrn::mjTRN_JOINT);
    act.set_target(&a.joint);
    match a.kind {
        ActuatorKind::Motor => act.set_to_motor(),
        ActuatorKind::Position { kp, kv } => act
            .set_to_position(PositionConfig {
                kp,
                kv,
                ..Default::default()
            })
            .map_err(|e| format!("actuator `{}`: {e}", a.name))?,
        ActuatorKind::Velocity { kv } => act.set_to_velocity(kv),
    }
    act.gear_mut()[0] = a.gear;
    act.set_ctrllimited(MjtLimited::mjLIMITED_TRUE);
    *act.ctrlrange_mut() = [a.ctrlrange.0, a.ctrlrange.1];
    if let Some((lo, hi)) = a.forcerange {
        act.set_forcelimited(MjtLimited::mjLIMITED_TRUE);
        *act.forcerange_mut() = [lo, hi];
    }
    Ok(())
}
