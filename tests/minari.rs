//! Minari datasets: envc's writer and reader (both backends), with the typed and the dynamic env,
//! and datasets written by Python's `DataCollector` (tests/reference/check_minari.py
//! --python-out; committed under tests/reference/fixtures/minari, or fresh ones in ENVC_MINARI_DIR).
//! The real `minari` package loading envc's datasets is checked by check_minari.py.

use std::path::{Path, PathBuf};

use envc::{Env, Environment, JointEnv};
use envc_datasets::{CollectOptions, Collector, Data, Dataset, DatasetError, DatasetInfo, Format};
use ndarray::ArrayD;
use ndarray_npy::NpzReader;

fn tmp_root(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("envc-minari-test-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn opts(root: &Path, id: &str, format: Format) -> CollectOptions {
    CollectOptions {
        root: Some(root.to_path_buf()),
        dataset_id: id.into(),
        format,
        info: DatasetInfo {
            author: vec!["t".into()],
            ..Default::default()
        },
    }
}

/// A deterministic policy that depends on the observation.
fn policy(obs: &[f64], a: &mut [f32]) {
    for (i, x) in a.iter_mut().enumerate() {
        *x = ((obs[i % obs.len()] * 7.0 + i as f64).sin() * 0.8) as f32;
    }
}

/// Record the same episodes by hand with a second env: what the dataset must hold.
struct Expected {
    obs: Vec<Vec<f64>>,
    act: Vec<Vec<f32>>,
    rew: Vec<f64>,
    term: Vec<bool>,
    trunc: Vec<bool>,
    info0: Vec<(String, Vec<f64>)>,
}

fn expected<E: Environment>(env: &mut E, seed: u64) -> Expected {
    let (o, info) = env.reset(Some(seed));
    let mut e = Expected {
        obs: vec![o.to_vec()],
        act: vec![],
        rew: vec![],
        term: vec![],
        trunc: vec![],
        info0: info
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_vec()))
            .collect(),
    };
    loop {
        let mut a = vec![0f32; env.act_dim()];
        policy(e.obs.last().unwrap(), &mut a);
        let s = env.step_f32(&a).unwrap();
        e.obs.push(s.obs.to_vec());
        e.act.push(a);
        e.rew.push(s.reward);
        e.term.push(s.terminated);
        e.trunc.push(s.truncated);
        if s.terminated || s.truncated {
            return e;
        }
    }
}

fn rows_f64(d: &Data) -> ArrayD<f64> {
    d.tensor().expect("a plain array").to_f64()
}

fn round_trip<E: Environment>(mut make: impl FnMut() -> E, format: Format, tag: &str) {
    let root = tmp_root(tag);
    let id = format!("test/{tag}/run-v0");
    let mut c = Collector::new(make(), opts(&root, &id, format)).unwrap();
    let seeds = [5u64, 6, u64::MAX - 3];
    for s in seeds {
        c.episode(s, &mut policy).unwrap();
    }
    let dir = c.finish().unwrap();
    assert_eq!(dir, root.join(&id));
    assert!(
        !root.join(envc_datasets::STAGING_DIR).exists(),
        "staging left behind"
    );
    let ds = Dataset::open(dir.to_str().unwrap()).unwrap();
    assert_eq!(
        (ds.format, ds.total_episodes, ds.dataset_id.as_str()),
        (format, 3, id.as_str())
    );
    let mut env = make();
    let mut total = 0;
    for (i, ep) in ds.episodes().enumerate() {
        let ep = ep.unwrap();
        let e = expected(&mut env, seeds[i]);
        let t = e.rew.len();
        total += t;
        assert_eq!((ep.id, ep.seed, ep.len()), (i as u64, Some(seeds[i]), t));
        let obs = ep.observations.tensor().unwrap().as_f64().unwrap();
        assert_eq!(obs.shape(), &[t + 1, env.obs_dim()]);
        assert_eq!(obs.iter().copied().collect::<Vec<_>>(), e.obs.concat());
        let act = ep.actions.tensor().unwrap().as_f32().unwrap();
        assert_eq!(act.shape(), &[t, env.act_dim()]);
        assert_eq!(act.iter().copied().collect::<Vec<_>>(), e.act.concat());
        assert_eq!(
            ep.rewards
                .as_f64()
                .unwrap()
                .iter()
                .copied()
                .collect::<Vec<_>>(),
            e.rew
        );
        assert_eq!(ep.terminations.to_vec(), e.term);
        assert_eq!(ep.truncations.to_vec(), e.trunc);
        // Row 0 of the infos is the reset info (keys the reset doesn't report are 0).
        for (k, v) in &e.info0 {
            let col = rows_f64(ep.info(k).unwrap());
            assert_eq!(col.shape()[0], t + 1);
            assert_eq!(
                col.iter().take(v.len()).copied().collect::<Vec<_>>(),
                *v,
                "info {k}"
            );
        }
    }
    assert_eq!(total as u64, ds.total_steps);
    // Never overwritten.
    let again = Collector::new(make(), opts(&root, &id, format));
    assert!(matches!(again, Err(DatasetError::Exists { .. })));
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn dynamic_env_arrow() {
    round_trip(
        || {
            Env::make(
                "Hopper-v5",
                &[envc::Override::text("max_episode_steps", "60")],
            )
            .unwrap()
        },
        Format::Arrow,
        "dyn-arrow",
    );
}

#[test]
fn dynamic_env_hdf5() {
    round_trip(
        || Env::make("Ant-v5", &[envc::Override::text("max_episode_steps", "40")]).unwrap(),
        Format::Hdf5,
        "dyn-hdf5",
    );
}

#[test]
fn typed_env_both_backends() {
    use envc::gymnasium::{InvertedPendulumV5, InvertedPendulumV5Config};
    round_trip(
        || InvertedPendulumV5::new(&InvertedPendulumV5Config::default()).unwrap(),
        Format::Arrow,
        "typed-arrow",
    );
    round_trip(
        || InvertedPendulumV5::new(&InvertedPendulumV5Config::default()).unwrap(),
        Format::Hdf5,
        "typed-hdf5",
    );
}

#[test]
fn failed_collection_leaves_nothing() {
    let root = tmp_root("fail");
    let mut c = Collector::new(
        Env::make("Hopper-v5", &[]).unwrap(),
        opts(&root, "test/fail/x-v0", Format::Arrow),
    )
    .unwrap();
    c.episode(1, &mut policy).unwrap();
    let err = c
        .episode(2, &mut |_: &[f64], a: &mut [f32]| a.fill(f32::NAN))
        .unwrap_err();
    assert!(err.to_string().contains("E1102"), "{err}");
    drop(c);
    assert!(!root.join("test/fail/x-v0").exists());
    assert!(!root.join(envc_datasets::STAGING_DIR).exists());
    assert!(Dataset::open(root.join("test/fail/x-v0").to_str().unwrap()).is_err());
    // Bad ids are refused before anything is written.
    for bad in ["a/x-v0", "noversion", "ns/a.b-v0"] {
        let e = Collector::new(
            Env::make("Hopper-v5", &[]).unwrap(),
            opts(&root, bad, Format::Arrow),
        )
        .err()
        .unwrap();
        assert_eq!(e.code(), "E1201", "{bad}: {e}");
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn reads_python_datacollector_datasets() {
    let dir = std::env::var_os("ENVC_MINARI_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("reference/fixtures/minari")
        });
    for (id, format) in [
        ("py/invpend/hdf5-v0", Format::Hdf5),
        ("py/hopper/arrow-v0", Format::Arrow),
    ] {
        let ds = Dataset::open(dir.join(id).to_str().unwrap()).unwrap();
        assert_eq!((ds.format, ds.total_episodes), (format, 3));
        let mut npz = NpzReader::new(
            std::fs::File::open(dir.join(format!("{}.npz", id.replace('/', "_")))).unwrap(),
        )
        .unwrap();
        let mut steps = 0;
        for ep in ds.episodes() {
            let ep = ep.unwrap();
            let i = ep.id;
            let get = |npz: &mut NpzReader<std::fs::File>, k: &str| -> ArrayD<f64> {
                npz.by_name(&format!("{i}.{k}")).unwrap()
            };
            assert_eq!(
                ep.observations.tensor().unwrap().as_f64().unwrap(),
                &get(&mut npz, "observations"),
                "{id} ep {i} obs"
            );
            let act: ArrayD<f32> = npz.by_name(&format!("{i}.actions")).unwrap();
            assert_eq!(
                ep.actions.tensor().unwrap().as_f32().unwrap(),
                &act,
                "{id} ep {i} actions"
            );
            assert_eq!(
                ep.rewards.to_f64(),
                get(&mut npz, "rewards"),
                "{id} ep {i} rewards"
            );
            let te: ArrayD<bool> = npz.by_name(&format!("{i}.terminations")).unwrap();
            let tr: ArrayD<bool> = npz.by_name(&format!("{i}.truncations")).unwrap();
            assert_eq!(ep.terminations.clone().into_dyn(), te);
            assert_eq!(ep.truncations.clone().into_dyn(), tr);
            let seed: ArrayD<u64> = npz.by_name(&format!("{i}.seed")).unwrap();
            assert_eq!(ep.seed, seed.iter().next().copied());
            steps += ep.len();
            // And envc replays Python's episode exactly from its seed and actions.
            let mut env = Env::make(ds.env_id().unwrap(), &[]).unwrap();
            let (o, _) = env.reset(ep.seed);
            let obs = ep.observations.tensor().unwrap().as_f64().unwrap();
            assert_eq!(o, obs.outer_iter().next().unwrap().as_slice().unwrap());
            for (t, a) in act.outer_iter().enumerate() {
                let s = env.step_f32(a.as_slice().unwrap()).unwrap();
                assert_eq!(
                    s.obs,
                    obs.outer_iter().nth(t + 1).unwrap().as_slice().unwrap(),
                    "{id} ep {i} step {t}"
                );
            }
        }
        assert_eq!(steps as u64, ds.total_steps);
    }
}

/// A dataset names the numerics profile it was computed under, and replaying under that profile
/// reproduces it on any CPU; under another profile Reacher's distance rewards (OpenBLAS `ddot`)
/// change, so the recorded name is what makes a replay exact.
#[test]
fn datasets_record_and_replay_their_numerics_profile() {
    use envc::numerics::Profile;
    let intel = Profile::parse("openblas-skylakex+svml").unwrap();
    let amd = Profile::parse("openblas-haswell").unwrap();
    let root = tmp_root("numerics");
    let id = "test/numerics/reacher-v0";
    let mut env = Env::make("Reacher-v5", &[]).unwrap();
    env.set_numerics(intel);
    let mut c = Collector::new(env, opts(&root, id, Format::Arrow)).unwrap();
    for s in 0..3 {
        c.episode(s, &mut policy).unwrap();
    }
    let dir = c.finish().unwrap();
    let ds = Dataset::open(dir.to_str().unwrap()).unwrap();
    assert_eq!(ds.numerics(), Some(intel));
    let replay = |profile: Profile| -> Vec<f64> {
        let mut rewards = vec![];
        for ep in ds.episodes() {
            let ep = ep.unwrap();
            let mut env = Env::make("Reacher-v5", &[]).unwrap();
            env.set_numerics(profile);
            env.reset(ep.seed);
            let act = ep.actions.tensor().unwrap().as_f32().unwrap().clone();
            for a in act.outer_iter() {
                rewards.push(env.step_f32(a.as_slice().unwrap()).unwrap().reward);
            }
        }
        rewards
    };
    let stored: Vec<f64> = ds
        .episodes()
        .flat_map(|ep| ep.unwrap().rewards.to_f64().into_iter().collect::<Vec<_>>())
        .collect();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&replay(ds.numerics().unwrap())), bits(&stored));
    assert_ne!(
        bits(&replay(amd)),
        bits(&stored),
        "the profile should matter for Reacher"
    );
    let _ = std::fs::remove_dir_all(&root);
}
