#!/usr/bin/env python3
"""Cross-check `envc rollout` against the Python reference, as any outside tool would.

For each env: draw a fresh seed and random actions (a third of the values outside the action
bounds), write them to A.npy, run `envc rollout`, run Gymnasium with the same seed and actions,
and require every array of the trajectory file to be bit-identical. Covers plain rollouts (stop at
the first episode end), --auto-reset (reset() without seed after each end), parameter overrides
and float32 actions.

    .venv/bin/python tests/reference/check_rollout.py --envc target/debug/envc [--seed N]
"""

import argparse
import os
import subprocess
import sys
import tempfile

import mujoco
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numerics_profile  # noqa: E402

# (env id, overrides as --set literals and as Python kwargs, steps, auto_reset, float32 actions)
CASES = [
    ("Ant-v5", {}, 120, False, False),
    ("Ant-v5", {"healthy_z_range": ("[0.3, 0.9]", (0.3, 0.9)), "max_episode_steps": ("40", 40)}, 150, True, False),
    ("HalfCheetah-v5", {"max_episode_steps": ("30", 30)}, 100, True, True),
    ("Hopper-v5", {}, 200, True, False),
    ("Humanoid-v5", {"include_cinert_in_observation": ("false", False)}, 120, True, False),
    ("HumanoidStandup-v5", {}, 60, False, True),
    ("InvertedPendulum-v5", {}, 150, True, False),
    ("InvertedDoublePendulum-v5", {"healthy_reward": ("3.0", 3.0)}, 150, True, False),
    ("Pusher-v5", {}, 110, True, True),
    ("Reacher-v5", {}, 120, True, False),
    ("Swimmer-v5", {"exclude_current_positions_from_observation": ("false", False)}, 80, False, False),
    ("Walker2d-v5", {}, 200, True, True),
]


def reference(gym, env_id, kwargs, seed, actions, auto_reset):
    kw = dict(kwargs)
    mes = kw.pop("max_episode_steps", None)
    env = gym.make(env_id, **kw) if mes is None else gym.make(env_id, max_episode_steps=mes, **kw)
    obs, info0 = env.reset(seed=seed)
    out = {"obs": [obs], "reward": [], "terminated": [], "truncated": [], "reset_obs": [obs], "reset_at": [0]}
    infos = []
    for t, a in enumerate(actions):
        obs, r, term, trunc, info = env.step(a)
        out["obs"].append(obs)
        out["reward"].append(float(r))
        out["terminated"].append(bool(term))
        out["truncated"].append(bool(trunc))
        infos.append(info)
        if term or trunc:
            if not auto_reset:
                break
            if t + 1 < len(actions):
                o, _ = env.reset()
                out["reset_obs"].append(o)
                out["reset_at"].append(t + 1)
    arrays = {
        "obs": np.array(out["obs"], dtype=np.float64),
        "reward": np.array(out["reward"], dtype=np.float64),
        "terminated": np.array(out["terminated"], dtype=bool),
        "truncated": np.array(out["truncated"], dtype=bool),
    }
    for k in infos[0]:
        arrays[f"info.{k}"] = np.array([np.asarray(i[k], dtype=np.float64) for i in infos])
    for k, v in info0.items():
        arrays[f"reset_info.{k}"] = np.asarray(v, dtype=np.float64)
    if auto_reset:
        arrays["reset_obs"] = np.array(out["reset_obs"], dtype=np.float64)
        arrays["reset_at"] = np.array(out["reset_at"], dtype=np.int64)
    env.close()
    return arrays


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--envc", required=True, help="path to the envc binary")
    ap.add_argument("--seed", type=int, default=None, help="master seed (default: fresh)")
    args = ap.parse_args()
    envc = os.path.abspath(args.envc)
    master = args.seed if args.seed is not None else int.from_bytes(os.urandom(4), "little")
    print(f"check_rollout: master seed {master}")
    rng = np.random.default_rng(master)

    tmp = tempfile.TemporaryDirectory(prefix="envc-rollout-")
    os.chdir(tmp.name)  # keeps MuJoCo's MUJOCO_LOG.TXT (HalfCheetah's warning) out of the tree
    import gymnasium as gym

    failures = 0
    for i, (env_id, overrides, steps, auto_reset, f32) in enumerate(CASES):
        seed = int(rng.integers(0, 2**31))
        probe = gym.make(env_id)
        low, high = probe.action_space.low.astype(np.float64), probe.action_space.high.astype(np.float64)
        probe.close()
        actions = rng.uniform(1.5 * low, 1.5 * high, size=(steps, low.size))
        if f32:
            actions = actions.astype(np.float32)
        a_path, t_path = f"a{i}.npy", f"t{i}.npz"
        np.save(a_path, actions)
        cmd = [envc, "rollout", env_id, "--seed", str(seed), "--actions", a_path, "--out", t_path]
        for k, (lit, _) in overrides.items():
            cmd += ["--set", f"{k}={lit}"]
        if auto_reset:
            cmd.append("--auto-reset")
        run = subprocess.run(cmd, capture_output=True, text=True)
        if run.returncode != 0:
            print(f"FAIL {env_id}: envc exited {run.returncode}: {run.stderr.strip()}")
            failures += 1
            continue
        ours = dict(np.load(t_path))
        # What made the file, not part of the trajectory: the MuJoCo it ran on is the reference's.
        made_with = bytes(ours.pop("mujoco_version")).decode()
        ours.pop("envc_version")
        if made_with != mujoco.__version__:
            print(f"FAIL {env_id}: the file records MuJoCo {made_with}, the reference runs {mujoco.__version__}")
            failures += 1
        ref = reference(gym, env_id, {k: v for k, (_, v) in overrides.items()}, seed, actions, auto_reset)
        problems = []
        if sorted(ours) != sorted(ref):
            problems.append(f"keys differ: envc {sorted(set(ours) - set(ref))} vs reference {sorted(set(ref) - set(ours))}")
        for k in sorted(set(ours) & set(ref)):
            a, b = ours[k], ref[k]
            if a.shape != b.shape or a.dtype != b.dtype:
                problems.append(f"{k}: envc {a.dtype}{a.shape} vs reference {b.dtype}{b.shape}")
            elif a.dtype == np.float64 and not np.array_equal(a.view(np.uint64), b.view(np.uint64)):
                idx = np.argwhere(a.view(np.uint64) != b.view(np.uint64))[0]
                problems.append(f"{k}{list(idx)}: envc {a[tuple(idx)]!r} vs reference {b[tuple(idx)]!r}")
            elif a.dtype != np.float64 and not np.array_equal(a, b):
                problems.append(f"{k}: values differ")
        n = len(ours.get("reward", []))
        tag = f"{env_id} seed {seed} {n} steps{' auto-reset' if auto_reset else ''}{' float32' if f32 else ''}"
        if problems:
            failures += 1
            print(f"FAIL {tag}:\n  " + "\n  ".join(problems[:10]))
        else:
            print(f"ok {tag}: {len(ours)} arrays bit-identical")
    print(f"{len(CASES) - failures} passed, {failures} failed (reference numerics {numerics_profile.profile_name()})")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
