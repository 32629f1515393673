//! One invariant matrix over every bundled spec (in the spirit of dm_control's suite tests): the
//! properties every env must have, whatever its robot and terms.

use envc::Env;
use envc::registry::bundled;

/// Models of the example specs, passed as `xml_file` overrides.
const EXAMPLE_MODELS: &[(&str, &str)] = &[
    (
        "MjlabVelocityFlatG1-v0",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../assets/mjlab/unitree_g1/g1.xml"
        ),
    ),
    (
        "MjlabVelocityRoughGo1-v0",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../assets/mjlab/unitree_go1/go1.xml"
        ),
    ),
    (
        "MjlabVelocityFlatGo1-v0",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../assets/mjlab/unitree_go1/go1.xml"
        ),
    ),
    (
        "Go1-v0",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/models/unitree_go1/scene.xml"
        ),
    ),
    (
        "Go1Joystick-v0",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/models/unitree_go1/scene.xml"
        ),
    ),
    (
        "Go1Randomized-v0",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/models/unitree_go1/scene.xml"
        ),
    ),
    (
        "ReacherGoal-v0",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../assets/gymnasium/reacher.xml"
        ),
    ),
    (
        "ArmPickAndPlace-v0",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../assets/examples/arm/arm.xml"
        ),
    ),
];

fn each_env(f: impl Fn(&str, Env)) {
    let all = bundled();
    assert!(all.len() >= 11);
    for (id, path) in all {
        let env = Env::from_spec_file(&path, &[]).unwrap_or_else(|e| panic!("{id}: {e}"));
        f(&id, env);
    }
    let examples = envc::registry::examples();
    assert_eq!(
        examples.len(),
        EXAMPLE_MODELS.len(),
        "a model for every example spec"
    );
    for (id, path) in examples {
        let model = EXAMPLE_MODELS
            .iter()
            .find(|(i, _)| *i == id)
            .map(|(_, m)| *m);
        let xml = envc::Override::text(
            "xml_file",
            model.unwrap_or_else(|| panic!("no model for {id}")),
        );
        let env = Env::from_spec_file(&path, &[xml]).unwrap_or_else(|e| panic!("{id}: {e}"));
        f(&id, env);
    }
}

fn actions(env: &Env, n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = envc::rng::NumpyRng::from_seed(seed);
    let sp = env.action_space().clone();
    (0..n)
        .map(|_| {
            (0..sp.dim())
                .map(|i| rng.uniform(1.5 * sp.low[i], 1.5 * sp.high[i]))
                .collect()
        })
        .collect()
}

#[test]
fn observations_have_the_declared_size_and_are_finite() {
    each_env(|id, mut env| {
        let dim = env.obs_dim();
        assert_eq!(env.observation_space().dim(), dim, "{id}");
        let (obs, _) = env.reset(Some(1));
        assert_eq!(obs.len(), dim, "{id}");
        assert!(obs.iter().all(|x| x.is_finite()), "{id} reset obs");
        for a in actions(&env, 30, 2) {
            let s = env.step(&a).unwrap();
            assert_eq!(s.obs.len(), dim, "{id}");
            assert!(s.obs.iter().all(|x| x.is_finite()), "{id} step obs");
            assert!(s.reward.is_finite(), "{id} reward");
            if s.terminated || s.truncated {
                env.reset(None);
            }
        }
    });
}

#[test]
fn same_seed_same_trajectory() {
    each_env(|id, mut env| {
        let acts = actions(&env, 40, 3);
        let run = |env: &mut Env| {
            let mut out = env.reset(Some(7)).0.to_vec();
            for a in &acts {
                let s = env.step(a).unwrap();
                out.extend_from_slice(s.obs);
                out.push(s.reward);
                if s.terminated {
                    out.extend_from_slice(env.reset(None).0);
                }
            }
            out
        };
        let first = run(&mut env);
        let second = run(&mut env);
        assert!(
            first
                .iter()
                .zip(&second)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{id}: reset(seed) must restart everything"
        );
    });
}

#[test]
fn reset_without_seed_continues_the_stream() {
    each_env(|id, mut env| {
        // The observation and the goal vector (a goal task may draw nothing else).
        let mut state = |seed| {
            let mut s = env.reset(seed).0.to_vec();
            s.extend_from_slice(env.goal());
            s
        };
        let a = state(Some(11));
        let b = state(None);
        let a2 = state(Some(11));
        assert_eq!(a, a2, "{id}");
        if env
            .spec()
            .reset
            .iter()
            .any(|r| !matches!(r.dist, envc::envspec::ir::Distribution::Constant { .. }))
        {
            assert_ne!(a, b, "{id}: a reset without seed draws new noise");
        }
    });
}

#[test]
fn info_keys_are_stable_and_reset_keys_are_step_keys() {
    each_env(|id, mut env| {
        let reset_keys: Vec<String> = env.reset(Some(0)).1.keys().map(String::from).collect();
        let a = vec![0.0; env.act_dim()];
        let step_keys: Vec<String> = env
            .step(&a)
            .unwrap()
            .info
            .keys()
            .map(String::from)
            .collect();
        for k in &reset_keys {
            assert!(
                step_keys.contains(k),
                "{id}: reset key {k} missing after step"
            );
        }
        let again: Vec<String> = env
            .step(&a)
            .unwrap()
            .info
            .keys()
            .map(String::from)
            .collect();
        assert_eq!(step_keys, again, "{id}");
    });
}

#[test]
fn truncation_at_max_episode_steps() {
    each_env(|id, env| {
        let path = env.spec().spec_path.clone();
        // Same model as `env` (example specs get theirs by override).
        let xml = env.spec().model_path.display().to_string();
        let mut overrides = vec![envc::Override::text("max_episode_steps", "3")];
        // A `fixed` xml_file (e.g. Gymnasium v4) is not overridable, and is at its default anyway.
        let fixed = env
            .spec()
            .params
            .iter()
            .any(|p| p.name == "xml_file" && p.fixed);
        if !fixed {
            overrides.push(envc::Override::text("xml_file", &xml));
        }
        let mut env3 = Env::from_spec_file(&path, &overrides).unwrap();
        env3.reset(Some(0));
        let a = vec![0.0; env3.act_dim()];
        let flags: Vec<bool> = (0..3).map(|_| env3.step(&a).unwrap().truncated).collect();
        assert_eq!(flags, [false, false, true], "{id}");
    });
}

#[test]
fn action_space_is_the_float32_ctrlrange() {
    let env = Env::make("Humanoid-v5", &[]).unwrap();
    assert_eq!(env.action_space().high[0], 0.4f32 as f64);
    assert_eq!(env.action_space().low[0], -0.4f32 as f64);
    let env = Env::make("InvertedPendulum-v5", &[]).unwrap();
    assert_eq!(
        (
            env.action_space().low.clone(),
            env.action_space().high.clone()
        ),
        (vec![-3.0], vec![3.0])
    );
}
