#!/usr/bin/env python3
"""Record Gymnasium-Robotics 1.4.2's FrankaKitchen-v1 for envc's replay test (tests/kitchen.rs)
and the live check: from a seed, random actions (half of them float32, some outside [-1, 1] so
the clip shows), every observation, achieved and desired goal (the dicts' parts end to end, in
play order), reward, termination, truncation and the three task lists, through the end of an
episode and the reset after it; then `compute_reward` on rows of goals against the list as it
is at the end.

Random actions never bring a task within the reference's 0.3, so besides the default the
checklist is recorded at a larger threshold (`BONUS_THRESH`, a module constant of the reference,
patched; the replay writes the same `threshold` into the spec), with the constructor arguments
that change it.

    .venv/bin/python tests/reference/record_kitchen.py          # re-record the committed fixtures
    .venv/bin/python tests/reference/record_kitchen.py --out DIR --seed N

Format (one JSON file per case, DIR/kitchen/<name>.json): `{"name", "threshold", "kwargs"
(constructor arguments), "parts" (names in play order), "numerics", "numerics_settings", "seed",
"actions" (hex, steps x 9), "float32" (per step), "obs" / "achieved" / "desired" (hex per event,
the reset first), "remaining" / "reached" / "completed" (per event, sorted names), "reward" (hex
per step), "terminated", "truncated" (per step), "resets_after", "batch_achieved",
"batch_desired" (hex, rows x the goal size), "batch_reward" (hex)}`.
"""
import argparse
import json
import os
import sys
import warnings

import numpy as np

warnings.filterwarnings("ignore")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gymnasium as gym  # noqa: E402
import gymnasium_robotics  # noqa: E402
from gymnasium_robotics.envs.franka_kitchen import kitchen_env  # noqa: E402

import numerics_profile  # noqa: E402
import robotics_patch  # noqa: E402,F401

gym.register_envs(gymnasium_robotics)

# name: (threshold, constructor arguments, steps)
CASES = {
    "default": (0.3, {}, 290),
    "checklist": (0.9, {}, 60),
    "three_tasks": (0.9, {"tasks_to_complete": ["microwave", "kettle", "light switch"]}, 40),
    "keep_done": (0.9, {"remove_task_when_completed": False, "terminate_on_tasks_completed": False}, 40),
    "noisy_two": (0.9, {"tasks_to_complete": ["hinge cabinet", "microwave"], "robot_noise_ratio": 0.1}, 40),
}


def hexa(a):
    return np.ascontiguousarray(np.asarray(a, dtype="<f8")).tobytes().hex()


def record(name, seed):
    threshold, kwargs, steps = CASES[name]
    kitchen_env.BONUS_THRESH = threshold
    env = gym.make("FrankaKitchen-v1", **kwargs)
    rng = np.random.default_rng(seed + 11)
    out = {k: [] for k in ("obs", "achieved", "desired", "remaining", "reached", "completed")}
    actions, f32, rew, term, trunc, resets = [], [], [], [], [], []

    def event(o, info):
        parts = list(o["achieved_goal"])
        out["obs"].append(hexa(o["observation"]))
        out["achieved"].append(hexa(np.concatenate([o["achieved_goal"][p] for p in parts])))
        out["desired"].append(hexa(np.concatenate([o["desired_goal"][p] for p in parts])))
        out["remaining"].append(sorted(info["tasks_to_complete"]))
        out["reached"].append(sorted(info["step_task_completions"]))
        out["completed"].append(sorted(info["episode_task_completions"]))
        return parts

    o, info = env.reset(seed=seed)
    parts = event(o, info)
    for t in range(steps):
        a = rng.uniform(-1.3, 1.3, 9)
        as32 = bool(t % 2)
        if as32:
            a = a.astype(np.float32)
        actions.append(np.asarray(a, dtype=np.float64))
        f32.append(as32)
        o, r, te, tr, info = env.step(a)
        event(o, info)
        rew.append(float(r))
        term.append(bool(te))
        trunc.append(bool(tr))
        if te or tr:
            o, info = env.reset()
            resets.append(t)
            event(o, info)
    u = env.unwrapped
    # Rows of goals near the desired ones (some exactly at them), each against the list now.
    desired = np.concatenate([u.goal[p] for p in parts])
    sizes = [len(u.goal[p]) for p in parts]
    n = 16
    ach = desired + rng.uniform(-0.5, 0.5, (n, desired.size))
    ach[:4] = desired
    des = np.repeat(desired[None], n, axis=0)
    split = np.cumsum(sizes)[:-1]
    br = [
        u.compute_reward(dict(zip(parts, np.split(ach[i], split))), dict(zip(parts, np.split(des[i], split))), {})
        for i in range(n)
    ]
    kitchen_env.BONUS_THRESH = 0.3
    return {
        "name": name, "threshold": threshold, "kwargs": kwargs, "parts": parts,
        "numerics": numerics_profile.profile_name(), "numerics_settings": numerics_profile.settings(),
        "seed": seed, "actions": hexa(actions), "float32": f32, **out, "reward": hexa(rew),
        "terminated": term, "truncated": trunc, "resets_after": resets,
        "batch_achieved": hexa(ach), "batch_desired": hexa(des), "batch_reward": hexa(br),
    }


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(here, "fixtures"))
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args()
    out = os.path.join(args.out, "kitchen")
    os.makedirs(out, exist_ok=True)
    for k, name in enumerate(CASES):
        rec = record(name, args.seed + k)
        with open(os.path.join(out, f"{name}.json"), "w") as f:
            json.dump(rec, f, separators=(",", ":"))
        print(f"record_kitchen: {name} seed {rec['seed']}, {len(rec['float32'])} steps, "
              f"{len(rec['resets_after'])} resets, {sum(map(len, rec['completed']))} task completions seen",
              file=sys.stderr)


if __name__ == "__main__":
    main()
