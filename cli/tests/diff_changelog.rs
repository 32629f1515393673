//! `envc diff` of every v4/v5 spec pair against Gymnasium's v5 changelog (appendix A of the seed
//! thesis): each changelog entry that a spec can express must appear in the diff. The full text
//! of each diff is also pinned (`cli/tests/diff_golden/*.txt`, every change line with its rule id;
//! regenerate with ENVC_BLESS=1 and review the change).

use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn diff(v4: &str, v5: &str) -> (i32, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .current_dir(root())
        .args([
            "diff",
            &format!("specs/gymnasium/{v4}.toml"),
            &format!("specs/gymnasium/{v5}.toml"),
        ])
        .output()
        .expect("run envc diff");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
    )
}

/// (v4 spec, v5 spec, changelog entries as text the diff must contain)
const PAIRS: &[(&str, &str, &[&str])] = &[
    (
        "ant_v4",
        "ant",
        &[
            // healthy reward only when healthy
            "reward.healthy: paid_when_unhealthy: was \"terminate_when_unhealthy\"",
            "info.reward_survive: definition: was reward term `healthy`: +1 (paid even when unhealthy)",
            // contact cost always in the reward
            "reward.contact: when: was \"use_contact_forces\"",
            "reward: sum: was (forward + healthy) + ctrl",
            "now (forward + healthy) + (ctrl + contact)",
            // worldbody cfrc_ext excluded
            "observation.cfrc_ext: source: was \"cfrc_ext\"",
            "now \"cfrc_ext[1:]\"",
            // new and removed arguments
            "param main_body: added",
            "param forward_reward_weight: added",
            "param include_cfrc_ext_in_observation: added",
            "param use_contact_forces: removed",
            // info["reward_ctrl"] sometimes held the contact cost
            "info.reward_ctrl_contact: removed",
            // x/y position and distance from qpos, not xpos
            "info.x_position: definition: was xpos[torso][0]",
            "now qpos[0]",
            "info.distance_from_origin: definition: was ‖xpos[torso][0:2]‖₂",
            // forward_reward removed
            "info.forward_reward: removed",
            // reset info non-empty
            "info.x_position: reported at: was step only",
        ],
    ),
    (
        "half_cheetah_v4",
        "half_cheetah",
        &[
            "info.reward_run: renamed: was reward_run",
            "now reward_forward",
            "info.x_position: reported at: was step only",
        ],
    ),
    (
        "hopper_v4",
        "hopper",
        &[
            "reward.healthy: paid_when_unhealthy: was \"terminate_when_unhealthy\"",
            "info.reward_forward: added",
            "info.reward_ctrl: added",
            "info.reward_survive: added",
            "info.z_distance_from_origin: added: qpos[1] − qpos0[1]",
        ],
    ),
    (
        "humanoid_v4",
        "humanoid",
        &[
            "reward.healthy: paid_when_unhealthy: was \"terminate_when_unhealthy\"",
            "reward.contact: added",
            "param contact_cost_weight: added",
            "param contact_cost_range: added",
            "observation.cinert: source: was \"cinert\"",
            "observation.cvel: source: was \"cvel\"",
            "observation.qfrc_actuator: source: was \"qfrc_actuator\"",
            "observation.cfrc_ext: source: was \"cfrc_ext\"",
            "param include_cinert_in_observation: added",
            "param include_cvel_in_observation: added",
            "param include_qfrc_actuator_in_observation: added",
            "param include_cfrc_ext_in_observation: added",
            "info.x_position: definition: was mass_center[0]",
            "info.tendon_length: added",
            "info.tendon_velocity: added",
            "info.reward_alive: renamed: was reward_alive",
            "info.reward_linvel: renamed: was reward_linvel",
            "info.reward_quadctrl: renamed: was reward_quadctrl",
            "info.forward_reward: removed",
        ],
    ),
    (
        "humanoidstandup_v4",
        "humanoidstandup",
        &[
            "observation.cinert: source: was \"cinert\"",
            "observation.cvel: source: was \"cvel\"",
            "observation.qfrc_actuator: source: was \"qfrc_actuator\"",
            "observation.cfrc_ext: source: was \"cfrc_ext\"",
            "param uph_cost_weight: added",
            "param ctrl_cost_weight: added",
            "param impact_cost_weight: added",
            "param impact_cost_range: added",
            "param reset_noise_scale: added",
            "param include_cinert_in_observation: added",
            "info.tendon_length: added",
            "info.tendon_velocity: added",
            "info.x_position: added",
            "info.y_position: added",
            "info.z_distance_from_origin: added",
        ],
    ),
    (
        "inverted_double_pendulum_v4",
        "inverted_double_pendulum",
        &[
            "reward.alive: kind: was \"constant\"",
            "now \"healthy\"",
            "observation.qfrc_constraint: source: was \"qfrc_constraint\"",
            "now \"qfrc_constraint[:1]\"",
            "param reset_noise_scale: added",
            "param healthy_reward: added",
            "info.reward_survive: added",
            "info.distance_penalty: added",
            "info.velocity_penalty: added",
        ],
    ),
    (
        "inverted_pendulum_v4",
        "inverted_pendulum",
        &[
            "reward.survive: added: { kind = \"healthy\"",
            "param reset_noise_scale: added",
            "info.reward_survive: added",
        ],
    ),
    (
        "pusher_v4",
        "pusher",
        &[
            // object density higher than air: the object's mass changes
            "model: body_mass[object]: was",
            "reward.dist: at: was \"before\"",
            "reward.near: at: was \"before\"",
            "param reward_near_weight: added",
            "param reward_dist_weight: added",
            "param reward_control_weight: added",
            "info.reward_ctrl: definition: was reward term `ctrl` without its weight",
            "info.reward_near: added",
        ],
    ),
    (
        "reacher_v4",
        "reacher",
        &[
            "reward.dist: at: was \"before\"",
            "observation: layout: was 11 elements, now 10 elements",
            "removed xpos[fingertip].z - xpos[target].z",
            "param reward_dist_weight: added",
            // v4 had no control weight at all: the new argument is what the diff can show.
            "param reward_control_weight: added",
        ],
    ),
    (
        "swimmer_v4",
        "swimmer",
        &[
            "info.reward_fwd: renamed: was reward_fwd",
            "info.forward_reward: removed",
        ],
    ),
    (
        "walker2d_v4",
        "walker2d",
        &[
            "model: geom_friction[foot_geom]: was [0.9, 0.1, 0.1], now [1.9, 0.1, 0.1]",
            "reward.healthy: paid_when_unhealthy: was \"terminate_when_unhealthy\"",
            "info.reward_forward: added",
            "info.reward_ctrl: added",
            "info.reward_survive: added",
            "info.z_distance_from_origin: added",
        ],
    ),
];

/// "Restored / added the xml_file argument" (every env but Ant) and "added frame_skip" (all).
const ARGUMENTS: &[(&str, &[&str])] = &[
    ("ant_v4", &["frame_skip"]),
    ("half_cheetah_v4", &["xml_file", "frame_skip"]),
    ("hopper_v4", &["xml_file", "frame_skip"]),
    ("humanoid_v4", &["xml_file", "frame_skip"]),
    ("humanoidstandup_v4", &["xml_file", "frame_skip"]),
    ("inverted_double_pendulum_v4", &["xml_file", "frame_skip"]),
    ("inverted_pendulum_v4", &["xml_file", "frame_skip"]),
    ("pusher_v4", &["xml_file", "frame_skip"]),
    ("reacher_v4", &["xml_file", "frame_skip"]),
    ("swimmer_v4", &["xml_file", "frame_skip"]),
    ("walker2d_v4", &["xml_file", "frame_skip"]),
];

#[test]
fn v4_to_v5_diffs_report_the_changelog() {
    let bless = std::env::var_os("ENVC_BLESS").is_some();
    let mut missing = vec![];
    for (v4, v5, entries) in PAIRS {
        let (status, text) = diff(v4, v5);
        assert_eq!(status, 3, "{v4} → {v5} must be breaking:\n{text}");
        let args = ARGUMENTS
            .iter()
            .find(|(s, _)| s == v4)
            .map(|(_, a)| *a)
            .unwrap_or(&[]);
        let args: Vec<String> = args
            .iter()
            .map(|a| format!("param {a}: constructor argument: was no (fixed)"))
            .collect();
        for e in entries
            .iter()
            .copied()
            .chain(args.iter().map(String::as_str))
        {
            if !text.contains(e) {
                missing.push(format!("{v4} → {v5}: missing `{e}`"));
            }
        }
        let golden = root()
            .join("cli/tests/diff_golden")
            .join(format!("{v5}.txt"));
        if bless {
            std::fs::write(&golden, &text).unwrap();
        } else {
            let want = std::fs::read_to_string(&golden).unwrap_or_default();
            assert_eq!(
                text,
                want,
                "{v4} → {v5} differs from {} (ENVC_BLESS=1 to update)",
                golden.display()
            );
        }
    }
    assert!(
        missing.is_empty(),
        "changelog entries not reported:\n{}",
        missing.join("\n")
    );
}

#[test]
fn identical_specs_have_no_change_and_formats_agree() {
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .current_dir(root())
        .args(["diff", "specs/gymnasium/ant.toml", "Ant-v5"])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    for format in ["markdown", "json", "github"] {
        let o = Command::new(env!("CARGO_BIN_EXE_envc"))
            .current_dir(root())
            .args([
                "diff",
                "specs/gymnasium/walker2d_v4.toml",
                "specs/gymnasium/walker2d.toml",
                "--format",
                format,
            ])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(3));
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(out.contains("geom_friction[foot_geom]"), "{format}: {out}");
        if format == "json" {
            let v: serde_json::Value = serde_json::from_str(&out).unwrap();
            assert_eq!(v["verdict"], "breaking");
            let friction = v["changes"]
                .as_array()
                .unwrap()
                .iter()
                .find(|c| c["aspect"] == "geom_friction[foot_geom]")
                .unwrap();
            assert_eq!(friction["rule"], "model-array-changed");
            assert_eq!(friction["category"], "dynamics");
        }
        if format == "markdown" {
            assert!(
                out.contains("| ⚠️ | `model-array-changed` | model geom_friction[foot_geom] |"),
                "{out}"
            );
        }
        if format == "github" {
            assert!(out.lines().all(|l| l.starts_with("::")), "{out}");
            assert!(
                out.contains("::[model-array-changed] model: geom_friction[foot_geom]: was"),
                "{out}"
            );
        }
    }
}

#[test]
fn a_layout_change_without_a_version_bump_is_flagged() {
    let dir = std::env::temp_dir().join(format!("envc-diff-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let ant = std::fs::read_to_string(root().join("specs/gymnasium/ant.toml")).unwrap();
    let assets = root().join("assets").canonicalize().unwrap();
    let fix = |t: &str| t.replace("../../assets", assets.to_str().unwrap());
    std::fs::write(dir.join("old.toml"), fix(&ant)).unwrap();
    let changed = fix(&ant).replace("source = \"cfrc_ext[1:]\"", "source = \"cfrc_ext[2:]\"");
    std::fs::write(dir.join("new.toml"), changed).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args([
            "diff",
            dir.join("old.toml").to_str().unwrap(),
            dir.join("new.toml").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(3), "{out}");
    assert!(
        out.contains("flag: this change breaks trained policies but the env id stays `Ant-v5`"),
        "{out}"
    );
    assert!(out.contains("obs dim 105 → 99"), "{out}");
    assert!(
        out.contains("removed cfrc_ext[torso].rx … cfrc_ext[torso].tz (6 elements)"),
        "{out}"
    );
}
