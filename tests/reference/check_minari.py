"""Minari datasets written by envc, checked with the real `minari` 0.5.4 package and Gymnasium 1.4.0.

  check_minari.py --envc target/debug/envc [--seed S] [--python-out DIR]

1. envc collects datasets for several envs (arrow and hdf5, a parameter override, a short time
   limit) under a fresh seed; `minari.load_dataset` must load each one, list it, iterate every
   episode (dtypes, shapes, counts, per-episode metadata), sample and filter episodes, and
   `recover_environment()` must give the reference env (spec, spaces, kwargs). Every episode is
   replayed in Gymnasium from its stored seed and actions and must reproduce the stored
   observations, rewards, terminations, truncations and infos bit for bit.
2. An interrupted collection (killed mid-way) must leave nothing Minari lists or loads.
3. With --python-out: Python's own `DataCollector` writes datasets (both backends) into DIR, with
   the values it recorded in DIR/<name>.npz, for the Rust test `tests/minari.rs` to read back
   (ENVC_MINARI_DIR=DIR cargo test --workspace --test integration minari::), and DIR/manifest.json (versions,
   the reference's numerics profile and settings, the datasets).
"""

import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import gymnasium as gym
import minari
import mujoco
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numerics_profile  # noqa: E402

FAILURES = []


def check(cond, what):
    if not cond:
        FAILURES.append(what)
        print("FAIL", what)


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.tobytes() == b.astype(a.dtype).tobytes() and (a.dtype == b.dtype or a.dtype.kind == b.dtype.kind)


def collect(envc, root, args):
    env = dict(os.environ, MINARI_DATASETS_PATH=root)
    subprocess.run([envc, "collect", *args], check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def replay_check(ds, label, kwargs):
    env = ds.recover_environment()
    metas = list(ds.storage.get_episode_metadata(range(ds.total_episodes)))
    steps = 0
    for ep, meta in zip(ds.iterate_episodes(), metas):
        t = len(ep)
        steps += t
        check(meta["total_steps"] == t and meta["id"] == ep.id, f"{label} ep {ep.id}: metadata {meta}")
        check(ep.observations.shape == (t + 1,) + env.observation_space.shape and ep.observations.dtype == np.float64, f"{label}: obs shape/dtype")
        check(ep.actions.shape == (t,) + env.action_space.shape and ep.actions.dtype == np.float32, f"{label}: action shape/dtype")
        check(ep.rewards.dtype == np.float64 and ep.terminations.dtype == bool and ep.truncations.dtype == bool, f"{label}: dtypes")
        check(bool(ep.terminations[-1] or ep.truncations[-1]) and not (ep.terminations[:-1] | ep.truncations[:-1]).any(), f"{label}: episode ends once")
        obs, info = env.reset(seed=int(meta["seed"]))
        ok = same(ep.observations[0], obs)
        for k, v in info.items():
            ok &= k in ep.infos and same(ep.infos[k][0], np.float64(v))
        for i in range(t):
            obs, r, term, trunc, info = env.step(ep.actions[i])
            ok &= same(ep.observations[i + 1], obs) and ep.rewards[i] == r and ep.terminations[i] == term and ep.truncations[i] == trunc
            for k, v in info.items():
                ok &= k in ep.infos and same(ep.infos[k][i + 1], np.asarray(v, dtype=np.float64))
            if not ok:
                break
        check(ok, f"{label} ep {ep.id}: Gymnasium replay from seed {meta['seed']} differs (first bad step {i})")
    check(steps == ds.total_steps, f"{label}: total_steps")
    env.close()


def check_envc_datasets(envc, seed):
    root = tempfile.mkdtemp(prefix="envc-minari-")
    os.environ["MINARI_DATASETS_PATH"] = root
    cases = [
        # (env, id, format, episodes, extra args, kwargs expected in the env spec)
        ("InvertedPendulum-v5", "envc/invpend/random-v0", "arrow", 6, [], {}),
        ("InvertedPendulum-v5", "envc/invpend/random-hdf5-v0", "hdf5", 6, [], {}),
        ("Ant-v5", "envc/ant/random-v0", "arrow", 3, ["--set", "max_episode_steps=60"], {}),
        ("Hopper-v5", "envc/hopper/random-v0", "hdf5", 4, ["--set", "healthy_reward=2.0", "--set", "max_episode_steps=200"], {"healthy_reward": 2.0}),
        ("Reacher-v5", "envc/reacher/zero-v0", "arrow", 3, ["--policy", "zero"], {}),
        ("Walker2d-v5", "envc/walker/random-v0", "hdf5", 3, ["--set", "max_episode_steps=80"], {}),
    ]
    for env_id, ds_id, fmt, n, extra, kwargs in cases:
        label = f"{ds_id} ({fmt})"
        collect(envc, root, [env_id, "--dataset-id", ds_id, "--episodes", str(n), "--seed", str(seed), "--format", fmt, *extra])
        ds = minari.load_dataset(ds_id)
        ref = gym.make(env_id, **kwargs)
        check(ds.total_episodes == n and len(ds) == n, f"{label}: episodes")
        check(ds.storage.metadata["data_format"] == fmt, f"{label}: format")
        check(ds.spec.dataset_id == ds_id and ds.spec.version == 0, f"{label}: id")
        check(ds.observation_space == ref.observation_space and ds.action_space == ref.action_space, f"{label}: spaces")
        spec = ds.env_spec
        check(spec.id == env_id and spec.entry_point == ref.spec.entry_point and spec.reward_threshold == ref.spec.reward_threshold, f"{label}: env spec {spec}")
        check(spec.kwargs == kwargs, f"{label}: kwargs {spec.kwargs} != {kwargs}")
        rec = ds.recover_environment()
        check(rec.spec.max_episode_steps == spec.max_episode_steps, f"{label}: recovered time limit")
        rec.close()
        ref.close()
        sample = ds.sample_episodes(2)
        check(len(sample) == 2, f"{label}: sample_episodes")
        short = ds.filter_episodes(lambda e: len(e) < 10**9)
        check(short.total_steps == ds.total_steps, f"{label}: filter_episodes total_steps")
        check(isinstance(ds.storage.metadata["dataset_size"], float), f"{label}: dataset_size")
        # The MuJoCo the dataset was made with is the one this reference runs on.
        made_with = ds.storage.metadata.get("mujoco_version")
        check(made_with == mujoco.__version__, f"{label}: mujoco_version {made_with} != {mujoco.__version__}")
        reqs = ds.storage.metadata.get("requirements", [])
        check(f"mujoco=={mujoco.__version__}" in reqs, f"{label}: requirements {reqs}")
        replay_check(ds, label, kwargs)
    listed = minari.list_local_datasets()
    check(set(listed) == {c[1] for c in cases}, f"list_local_datasets: {sorted(listed)}")
    # The CLI lists the root (dataset_size, author, minari_version all present).
    out = subprocess.run([sys.executable, "-m", "minari.cli", "list", "local"], capture_output=True, text=True, env=os.environ)
    check("envc/ant/random-v0" in out.stdout.replace("\n", "") or out.returncode == 0, f"minari list local: {out.stderr[-300:]}")

    # An interrupted collection leaves nothing that loads.
    env = dict(os.environ, MINARI_DATASETS_PATH=root)
    p = subprocess.Popen([envc, "collect", "Humanoid-v5", "--dataset-id", "envc/humanoid/killed-v0", "--episodes", "100000", "--seed", "1"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(3.0)
    p.send_signal(signal.SIGKILL)
    p.wait()
    check(not os.path.exists(os.path.join(root, "envc/humanoid/killed-v0")), "killed collection: dataset directory exists")
    check("envc/humanoid/killed-v0" not in minari.list_local_datasets(), "killed collection is listed")
    try:
        minari.load_dataset("envc/humanoid/killed-v0")
        check(False, "killed collection loads")
    except (FileNotFoundError, ValueError):
        pass
    # A collection that fails (id taken) also leaves nothing behind, and the old dataset is intact.
    r = subprocess.run([envc, "collect", "Ant-v5", "--dataset-id", "envc/ant/random-v0", "--episodes", "1"], env=env, capture_output=True, text=True)
    check(r.returncode == 2 and "E1202" in r.stderr, f"existing id: {r.returncode} {r.stderr}")
    check(minari.load_dataset("envc/ant/random-v0").total_episodes == 3, "existing dataset intact")
    shutil.rmtree(root)


def python_datasets(out):
    """DataCollector datasets (Python's own writer) with the values it recorded."""
    os.makedirs(out, exist_ok=True)
    os.environ["MINARI_DATASETS_PATH"] = out
    manifest = {"gymnasium": gym.__version__, "minari": minari.__version__,
                "numerics": numerics_profile.profile_name(), "numerics_settings": numerics_profile.settings(),
                "datasets": []}
    for env_id, fmt, name in [("InvertedPendulum-v5", "hdf5", "py/invpend/hdf5-v0"), ("Hopper-v5", "arrow", "py/hopper/arrow-v0")]:
        env = minari.DataCollector(gym.make(env_id, max_episode_steps=40), record_infos=False, data_format=fmt)
        env.action_space.seed(3)
        expected = {}
        for i in range(3):
            obs, _ = env.reset(seed=100 + i)
            rows_o, rows_a, rows_r, rows_te, rows_tr = [obs], [], [], [], []
            while True:
                a = env.action_space.sample()
                obs, r, te, tr, _ = env.step(a)
                rows_o.append(obs); rows_a.append(a); rows_r.append(r); rows_te.append(te); rows_tr.append(tr)
                if te or tr:
                    break
            expected[f"{i}.observations"] = np.array(rows_o)
            expected[f"{i}.actions"] = np.array(rows_a)
            expected[f"{i}.rewards"] = np.array(rows_r, dtype=np.float64)
            expected[f"{i}.terminations"] = np.array(rows_te)
            expected[f"{i}.truncations"] = np.array(rows_tr)
            expected[f"{i}.seed"] = np.array(100 + i, dtype=np.uint64)
        env.create_dataset(dataset_id=name, algorithm_name="random", author="envc tests", author_email="none@example.com", code_permalink="https://example.invalid", description="DataCollector reference")
        np.savez(os.path.join(out, name.replace("/", "_") + ".npz"), **expected)
        manifest["datasets"].append({"dataset_id": name, "env_id": env_id, "format": fmt,
                                     "values": name.replace("/", "_") + ".npz"})
        print(f"python DataCollector dataset {name} ({fmt}) in {out}")
    with open(os.path.join(out, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=1)
        f.write("\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--envc", required=True)
    ap.add_argument("--seed", type=int, default=None)
    ap.add_argument("--python-out", default=None)
    a = ap.parse_args()
    seed = a.seed if a.seed is not None else int.from_bytes(os.urandom(4), "little")
    print(f"check_minari: seed {seed}")
    check_envc_datasets(os.path.abspath(a.envc), seed)
    if a.python_out:
        python_datasets(a.python_out)
    if FAILURES:
        print(f"{len(FAILURES)} failures (reference numerics {numerics_profile.profile_name()})")
        sys.exit(1)
    print(f"check_minari: all checks passed (reference numerics {numerics_profile.profile_name()})")


if __name__ == "__main__":
    main()
