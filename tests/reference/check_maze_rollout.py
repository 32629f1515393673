#!/usr/bin/env python3
"""`envc rollout` on maze envs against Gymnasium-Robotics 1.4.2, from outside (fresh seeds).

    .venv/bin/python tests/reference/check_maze_rollout.py --envc target/debug/envc [--seed N]

For each case: random actions are saved to .npy, `envc rollout ID --seed S --auto-reset` writes the
trajectory, and the reference replays the same actions (an unseeded reset after each episode end).
The dict observation (obs.observation / obs.achieved_goal / obs.desired_goal), reward, terminated,
truncated, info.success and the robot's info must be bit-identical.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import warnings

import numpy as np

warnings.filterwarnings("ignore")
# Gymnasium-Robotics 1.4.2 writes every maze's MJCF to <tmpdir>/ant_maze<time>.xml and never deletes it
# (reference trap M14): point its temp dir at a private one, removed at exit.
import atexit  # noqa: E402
import shutil  # noqa: E402
import tempfile  # noqa: E402

tempfile.tempdir = tempfile.mkdtemp(prefix="envc-maze-ref-")
atexit.register(shutil.rmtree, tempfile.tempdir, True)
import gymnasium as gym  # noqa: E402
import gymnasium_robotics  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numerics_profile  # noqa: E402

gym.register_envs(gymnasium_robotics)

CASES = [  # id, steps, max_episode_steps, envc --set, gym kwargs
    ("PointMaze_Medium_Diverse_GRDense-v3", 120, 40, [], {}),
    ("PointMaze_Large-v3", 80, None, [], {}),
    ("AntMaze_UMazeDense-v5", 40, 15, [], {}),
    ("AntMaze_Large_Diverse_G-v5", 30, None, ["continuing_task=false"], dict(continuing_task=False)),
]
KEYS = ("observation", "achieved_goal", "desired_goal")


def reference(env_id, seed, actions, max_steps, kwargs):
    mk = dict(kwargs)
    if max_steps:
        mk["max_episode_steps"] = max_steps
    env = gym.make(env_id, **mk)
    o, info = env.reset(seed=seed)
    obs = {k: [o[k]] for k in KEYS}
    out = dict(reward=[], terminated=[], truncated=[], success=[], info={})
    for t, a in enumerate(actions):
        o, r, term, trunc, info = env.step(a)
        for k in KEYS:
            obs[k].append(o[k])
        out["reward"].append(r)
        out["terminated"].append(term)
        out["truncated"].append(trunc)
        out["success"].append(info["success"])
        for k, v in info.items():
            if k != "success":
                out["info"].setdefault(k, []).append(v)
        if (term or trunc) and t + 1 < len(actions):
            env.reset()
    return obs, out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--envc", required=True)
    ap.add_argument("--seed", type=int, default=None)
    args = ap.parse_args()
    seeder = np.random.default_rng(args.seed)
    bad = 0
    with tempfile.TemporaryDirectory() as tmp:
        for env_id, steps, max_steps, sets, kwargs in CASES:
            seed = int(seeder.integers(0, 2**31))
            space = gym.make(env_id).action_space
            actions = np.random.default_rng(seed + 1).uniform(space.low, space.high, (steps, space.shape[0]))
            a_path, out = os.path.join(tmp, "a.npy"), os.path.join(tmp, "t.npz")
            np.save(a_path, actions)
            cmd = [args.envc, "rollout", env_id, "--seed", str(seed), "--actions", a_path, "--out", out,
                   "--auto-reset"]
            for s in sets + ([f"max_episode_steps={max_steps}"] if max_steps else []):
                cmd += ["--set", s]
            subprocess.run(cmd, check=True, capture_output=True)
            z = np.load(out)
            obs, ref = reference(env_id, seed, actions, max_steps, kwargs)
            problems = []
            for k in KEYS:
                if not np.array_equal(z[f"obs.{k}"], np.array(obs[k])):
                    problems.append(f"obs.{k}")
            for k in ("reward", "terminated", "truncated"):
                if not np.array_equal(z[k], np.array(ref[k])):
                    problems.append(k)
            if not np.array_equal(z["info.success"], np.array(ref["success"])):
                problems.append("info.success")
            for k, v in ref["info"].items():
                if f"info.{k}" not in z.files or not np.array_equal(z[f"info.{k}"], np.array(v)):
                    problems.append(f"info.{k}")
            status = "ok" if not problems else "MISMATCH " + ", ".join(problems)
            bad += bool(problems)
            print(f"check_maze_rollout: {env_id} seed {seed}, {steps} steps: {status}", file=sys.stderr)
    print(f"check_maze_rollout: {len(CASES) - bad} of {len(CASES)} cases bit-identical "
          f"(reference numerics {numerics_profile.profile_name()})", file=sys.stderr)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
