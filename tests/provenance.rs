//! Datasets carry what made them (`envc_provenance`, docs/datasets.md "What made a dataset"): a
//! dataset recovers its env after its spec moved away, refuses a spec edited since (E1212, or
//! W1212 when accepted), and warns (W1214) or refuses (E1214) under another MuJoCo version.

use std::path::{Path, PathBuf};

use envc::{AnyEnv, Env, JointAction, JointEnv};
use envc_datasets::{CollectOptions, Collector, Dataset, DatasetInfo, Format, RecoverOptions};

fn policy(obs: &[f64], a: &mut [f32]) {
    for (i, x) in a.iter_mut().enumerate() {
        *x = ((obs[i % obs.len()] * 5.0 + i as f64).cos() * 0.7) as f32;
    }
}

/// A user's spec and model beside it: Hopper-v5 under another id, without an entry point (so
/// its env spec is envc's registration), its model in a sibling directory.
fn write_spec(dir: &Path) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("specs/gymnasium/hopper.toml")).unwrap();
    let text = text
        .replace("id = \"Hopper-v5\"", "id = \"ProvHopper-v0\"")
        .replace("../../assets/gymnasium/hopper.xml", "../models/hopper.xml")
        .lines()
        .filter(|l| !l.starts_with("entry_point"))
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::create_dir_all(dir.join("specs")).unwrap();
    std::fs::create_dir_all(dir.join("models")).unwrap();
    std::fs::copy(
        root.join("assets/gymnasium/hopper.xml"),
        dir.join("models/hopper.xml"),
    )
    .unwrap();
    let spec = dir.join("specs/prov_hopper.toml");
    std::fs::write(&spec, text).unwrap();
    spec
}

/// Every stored observation, replayed from the stored seeds and actions in `env`.
fn replays_bit_for_bit(ds: &Dataset, env: &mut AnyEnv) {
    let AnyEnv::Task(env) = env else {
        panic!("a task env was expected")
    };
    for ep in ds.episodes() {
        let ep = ep.unwrap();
        env.reset(ep.seed);
        let stored = ep.observations.tensor().unwrap().to_f64();
        let mut obs = vec![env.obs().to_vec()];
        let act = ep.actions.tensor().unwrap().as_f32().unwrap().clone();
        for a in act.outer_iter() {
            env.step_joint(JointAction::F32(a.as_slice().unwrap()))
                .unwrap();
            obs.push(env.obs().to_vec());
        }
        let flat: Vec<u64> = obs.concat().iter().map(|x| x.to_bits()).collect();
        let want: Vec<u64> = stored.iter().map(|x| x.to_bits()).collect();
        assert_eq!(flat, want, "episode with seed {:?}", ep.seed);
    }
}

fn set_recorded_mujoco(dir: &Path, version: &str) {
    let meta = dir.join("data/metadata.json");
    let mut m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&meta).unwrap()).unwrap();
    m["mujoco_version"] = version.into();
    m["envc_provenance"]["mujoco_version"] = version.into();
    std::fs::write(&meta, m.to_string()).unwrap();
}

/// One test, as it sets `XDG_CACHE_HOME` (where a moved spec's copy is written) for the process.
#[test]
fn a_dataset_recovers_its_spec_moved_refuses_it_edited_and_warns_on_another_mujoco() {
    let tmp = std::env::temp_dir().join(format!("envc-provenance-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    // SAFETY: no other test of this binary reads XDG_CACHE_HOME (the bundle's own cache is
    // found before any test runs, or under HOME).
    unsafe { std::env::set_var("XDG_CACHE_HOME", tmp.join("cache")) };
    let home = tmp.join("home");
    let spec = write_spec(&home);
    let env = Env::make(spec.to_str().unwrap(), &[]).unwrap();
    let opts = CollectOptions {
        root: Some(tmp.join("datasets")),
        dataset_id: "test/prov-hopper-v0".into(),
        format: Format::Arrow,
        info: DatasetInfo::default(),
    };
    let mut c = Collector::new(env, opts).unwrap();
    for seed in 0..2 {
        c.episode(seed, &mut policy).unwrap();
    }
    let dir = c.finish().unwrap();
    let ds = Dataset::open(dir.to_str().unwrap()).unwrap();

    // What it records: the versions, the spec and its model by hash and text.
    assert_eq!(ds.mujoco_version(), Some(envc::mujoco_version().as_str()));
    assert_eq!(envc::mujoco_version(), envc::MUJOCO_VERSION);
    let p = ds.provenance().unwrap().clone();
    let files = p["files"].as_array().unwrap();
    let paths: Vec<&str> = files.iter().map(|f| f["path"].as_str().unwrap()).collect();
    assert_eq!(paths, ["prov_hopper.toml", "../models/hopper.xml"]);
    assert_eq!(
        files[0]["text"].as_str().unwrap(),
        std::fs::read_to_string(&spec).unwrap()
    );
    // The env spec Minari's recover_environment uses carries the record to envc's creator.
    let env_spec = &ds.metadata["env_spec"].as_str().unwrap();
    let env_spec: serde_json::Value = serde_json::from_str(env_spec).unwrap();
    assert_eq!(env_spec["kwargs"]["envc_provenance"], p);

    // In place and unchanged: the recorded spec itself.
    let (mut env, warnings) = ds.recover(RecoverOptions::default()).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(env.as_joint().id(), "ProvHopper-v0");
    replays_bit_for_bit(&ds, &mut env);

    // Moved away (spec and model): rebuilt from the dataset's copy, the same episodes.
    let moved = tmp.join("moved");
    std::fs::rename(&home, &moved).unwrap();
    let r = envc_datasets::recover("x", &p, RecoverOptions::default()).unwrap();
    assert!(
        r.target.starts_with(tmp.join("cache").to_str().unwrap()),
        "{}",
        r.target
    );
    let (mut env, warnings) = ds.recover(RecoverOptions::default()).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    replays_bit_for_bit(&ds, &mut env);

    // Back in place, its model edited: refused, naming the model; accepted with W1212.
    std::fs::rename(&moved, &home).unwrap();
    let model = home.join("models/hopper.xml");
    let xml = std::fs::read_to_string(&model).unwrap();
    std::fs::write(&model, xml.replacen("<default>", "<default>\n", 1)).unwrap();
    let err = ds.recover(RecoverOptions::default()).err().unwrap();
    assert_eq!(err.code(), "E1212");
    assert!(
        err.to_string().contains("models/hopper.xml changed"),
        "{err}"
    );
    let accept = RecoverOptions {
        accept_changed_spec: true,
        ..Default::default()
    };
    let (_, warnings) = ds.recover(accept).unwrap();
    assert_eq!(warnings.len(), 1);
    assert!(warnings[0].starts_with("warning[W1212]"), "{warnings:?}");
    // Or the dataset's own copy, wherever a spec is found: the recorded episodes again.
    let recorded = RecoverOptions {
        use_recorded_spec: true,
        ..Default::default()
    };
    let (mut env, warnings) = ds.recover(recorded).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    replays_bit_for_bit(&ds, &mut env);
    std::fs::write(&model, xml).unwrap();

    // Made under another MuJoCo (the recorded version edited): W1214, or E1214 when refused.
    set_recorded_mujoco(&dir, "3.16.0");
    let ds = Dataset::open(dir.to_str().unwrap()).unwrap();
    let (_, warnings) = ds.recover(RecoverOptions::default()).unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].starts_with("warning[W1214]"), "{warnings:?}");
    assert!(warnings[0].contains("MuJoCo 3.16.0"), "{warnings:?}");
    let refuse = RecoverOptions {
        refuse_other_mujoco: true,
        ..Default::default()
    };
    assert_eq!(ds.recover(refuse).err().unwrap().code(), "E1214");

    // A bundled id records the id: it recovers from the bundle wherever that is.
    let env = Env::make("Hopper-v5", &[]).unwrap();
    let opts = CollectOptions {
        root: Some(tmp.join("datasets")),
        dataset_id: "test/prov-bundled-v0".into(),
        format: Format::Arrow,
        info: DatasetInfo::default(),
    };
    let mut c = Collector::new(env, opts).unwrap();
    c.episode(3, &mut policy).unwrap();
    let ds = Dataset::open(c.finish().unwrap().to_str().unwrap()).unwrap();
    assert_eq!(ds.provenance().unwrap()["spec"], "Hopper-v5");
    let (mut env, warnings) = ds.recover(RecoverOptions::default()).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    replays_bit_for_bit(&ds, &mut env);
    let _ = std::fs::remove_dir_all(&tmp);
}
