//! The bundled Gymnasium v5 specs resolve to Gymnasium 1.4.0's observation and action sizes
//! (`env.observation_space.shape`, `env.action_space.shape` of each `gym.make(id)`).
use std::path::PathBuf;

use envspec::{Override, load};

fn spec(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../specs/gymnasium")
        .join(file)
}

#[test]
fn sizes_match_the_reference() {
    // (file, id, nq, nv, nu, nbody, obs dim, frame_skip, max steps)
    let table = [
        ("ant.toml", "Ant-v5", 15, 14, 8, 14, 105, 5, 1000),
        (
            "half_cheetah.toml",
            "HalfCheetah-v5",
            9,
            9,
            6,
            8,
            17,
            5,
            1000,
        ),
        ("hopper.toml", "Hopper-v5", 6, 6, 3, 5, 11, 4, 1000),
        ("humanoid.toml", "Humanoid-v5", 24, 23, 17, 14, 348, 5, 1000),
        (
            "humanoidstandup.toml",
            "HumanoidStandup-v5",
            24,
            23,
            17,
            14,
            348,
            5,
            1000,
        ),
        (
            "inverted_pendulum.toml",
            "InvertedPendulum-v5",
            2,
            2,
            1,
            3,
            4,
            2,
            1000,
        ),
        (
            "inverted_double_pendulum.toml",
            "InvertedDoublePendulum-v5",
            3,
            3,
            1,
            4,
            9,
            5,
            1000,
        ),
        ("pusher.toml", "Pusher-v5", 11, 11, 7, 13, 23, 5, 100),
        ("reacher.toml", "Reacher-v5", 4, 4, 2, 5, 10, 2, 50),
        ("swimmer.toml", "Swimmer-v5", 5, 5, 2, 4, 8, 4, 1000),
        ("walker2d.toml", "Walker2d-v5", 9, 9, 6, 8, 17, 4, 1000),
    ];
    for (file, id, nq, nv, nu, nbody, obs, fs, max) in table {
        let r = load(&spec(file), &[]).unwrap_or_else(|e| panic!("{file}:\n{e}"));
        assert_eq!(r.id, id);
        assert_eq!(
            (r.model.nq, r.model.nv, r.model.nu(), r.model.nbody()),
            (nq, nv, nu, nbody),
            "{id} sizes"
        );
        assert_eq!(r.obs_dim, obs, "{id} obs dim");
        assert_eq!(r.frame_skip, fs, "{id} frame_skip");
        assert_eq!(r.max_episode_steps, Some(max), "{id} max_episode_steps");
    }
}

#[test]
fn flags_change_the_layout_as_in_the_reference() {
    // Gymnasium 1.4.0's sizes with the observation flags (Ant's `use_contact_forces`,
    // `include_cfrc_ext_in_observation`; Humanoid's `include_*_in_observation`).
    let ant = |o: &[(&str, &str)]| {
        let o: Vec<Override> = o.iter().map(|(k, v)| Override::text(k, v)).collect();
        load(&spec("ant.toml"), &o).unwrap().obs_dim
    };
    assert_eq!(
        ant(&[("exclude_current_positions_from_observation", "false")]),
        107
    );
    assert_eq!(ant(&[("include_cfrc_ext_in_observation", "false")]), 27);
    let hum = |k: &str| {
        load(&spec("humanoid.toml"), &[Override::text(k, "false")])
            .unwrap()
            .obs_dim
    };
    assert_eq!(hum("exclude_current_positions_from_observation"), 350);
    assert_eq!(hum("include_cinert_in_observation"), 218);
    assert_eq!(hum("include_cvel_in_observation"), 270);
    assert_eq!(hum("include_qfrc_actuator_in_observation"), 331);
    assert_eq!(hum("include_cfrc_ext_in_observation"), 270);
}

#[test]
fn observation_element_names_follow_the_model() {
    let r = load(&spec("ant.toml"), &[]).unwrap();
    let names = r.obs_names();
    assert_eq!(names[0], "qpos[root:z]");
    assert_eq!(names[5], "qpos[hip_1]");
    assert_eq!(names[13], "qvel[root:vx]");
    assert_eq!(names[27], "cfrc_ext[torso].rx");
    assert_eq!(names.len(), 105);
}
