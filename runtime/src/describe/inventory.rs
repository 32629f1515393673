//! What a compiled model holds, with the selector text to paste into a spec (`envc show --model`).
//! The selectable kinds come from the spec language's own resolver, so every line pastes back
//! (`envspec/tests/selector_roundtrip.rs`); geoms, cameras and lights are listed by name (the
//! spec language reads no geom fields; renderers take cameras by name).

use envspec::ResolvedSpec;
use envspec::diagnostic::{Location, SourceFile};
use mujoco_rs::mujoco_c::{mjModel, mjtObj};
use mujoco_rs::prelude::MjModel;

/// One kind of model element: a title and one line per element.
#[derive(Clone, Debug)]
pub struct Group {
    /// The heading, e.g. `joints, qpos entries`.
    pub title: &'static str,
    /// One line per element.
    pub lines: Vec<String>,
    /// The element's index is its position in the list (selector rows, keyframes), which
    /// `envc show --model` prints beside it.
    pub numbered: bool,
}

/// The fields listed, with what they read, and whether their rows have columns (`[x]` / `.x`).
const FIELDS: &[(&str, &str)] = &[
    ("qpos", "joints, qpos entries"),
    (
        "qvel",
        "joints, dofs (qvel, qfrc_actuator, qfrc_constraint)",
    ),
    ("action", "actuators (action, ctrl)"),
    (
        "xpos",
        "bodies (xpos, xipos, cvel, cfrc_ext, cinert, ...; columns by name)",
    ),
    ("site_xpos", "sites (site_xpos; columns .x .y .z)"),
    ("ten_length", "tendons (ten_length, ten_velocity)"),
];

pub(crate) fn name(m: &mjModel, obj: mjtObj, id: usize) -> String {
    crate::mj::names::name(m, obj, id).unwrap_or_else(|| format!("#{id} (unnamed)"))
}

/// The inventory of a spec's model: selectable elements as pasteable selectors (rows of matrix
/// fields once, e.g. `xpos[torso]`), then geoms, cameras and lights by name.
pub fn inventory(spec: &ResolvedSpec, model: &MjModel) -> Vec<Group> {
    let mut out = vec![];
    for (field, title) in FIELDS {
        let file = SourceFile::new("inventory", field.to_string());
        let loc = Location::new(&file, 0..field.len());
        let Ok(sel) = envspec::selector::resolve(field, &loc, &spec.model, &|_| {
            Err(envspec::Diagnostic::new(
                envspec::Code::E0201,
                "no parameters",
            ))
        }) else {
            continue;
        };
        let mut lines: Vec<String> = vec![];
        for n in &sel.names {
            // A matrix row once: `xpos[torso].x` → `xpos[torso]`.
            let row = match n.rfind("].") {
                Some(i) => n[..=i].to_string(),
                None => n.clone(),
            };
            if lines.last() != Some(&row) {
                lines.push(row);
            }
        }
        if !lines.is_empty() {
            out.push(Group {
                title,
                lines,
                numbered: true,
            });
        }
    }
    if !spec.model.keyframes.is_empty() {
        out.push(Group {
            title: "keyframes (reset kind = \"keyframe\", [actions] default_pose)",
            lines: spec
                .model
                .keyframes
                .iter()
                .enumerate()
                .map(|(i, k)| {
                    if k.is_empty() {
                        format!("#{i} (unnamed)")
                    } else {
                        k.clone()
                    }
                })
                .collect(),
            numbered: true,
        });
    }
    let m = model.ffi();
    for (title, obj, n) in [
        ("geoms", mjtObj::mjOBJ_GEOM, m.ngeom),
        ("cameras", mjtObj::mjOBJ_CAMERA, m.ncam),
        ("lights", mjtObj::mjOBJ_LIGHT, m.nlight),
    ] {
        let lines: Vec<String> = (0..n.max(0) as usize).map(|i| name(m, obj, i)).collect();
        if !lines.is_empty() {
            out.push(Group {
                title,
                lines,
                numbered: false,
            });
        }
    }
    out
}
