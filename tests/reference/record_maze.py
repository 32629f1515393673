#!/usr/bin/env python3
"""Record maze trajectories from Gymnasium-Robotics 1.4.2 (PointMaze_*-v3, AntMaze_*-v5) for envc's
maze parity test (tests/maze.rs).

Usage (project venv, any directory):

    .venv/bin/python tests/reference/record_maze.py                     # re-record the committed fixtures
    .venv/bin/python tests/reference/record_maze.py --out DIR --seed N  # fresh-seed live cross-check

Format: one JSON file per case, `{"name", "id", "overrides": {param: TOML text}, "numerics": profile,
"numerics_settings": {var: value|null}, "events": [...]}` (the profile and settings of
numerics_profile.py: the dense rewards are np.exp, SVML or glibc; Ant's distance_from_origin is a ddot).
Every float array is the hex of its little-endian float64 bytes (exact). Events are
`{"reset": seed|null, "options": {...}|null, "obs": {...}, "success": bool, "info": {...}}` and
`{"action": hex, "obs": {...}, "reward": hex, "terminated", "truncated", "success", "info"}`.
After an episode ends the next reset has no seed (the RNG streams continue), as a training loop does.
"""
import argparse
import json
import os
import sys
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
import gymnasium_robotics  # noqa: E402,F401

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numerics_profile  # noqa: E402

gym.register_envs(gymnasium_robotics)

MAPS = ["UMaze", "Open", "Open_Diverse_G", "Open_Diverse_GR", "Medium", "Medium_Diverse_G",
        "Medium_Diverse_GR", "Large", "Large_Diverse_G", "Large_Diverse_GR"]
CUSTOM = [[1, 1, 1, 1, 1, 1], [1, "r", 0, 0, 1, 1], [1, 0, 1, "g", 0, 1], [1, "c", 0, 0, "g", 1],
          [1, 1, 1, 1, 1, 1]]
GO1 = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared",
                                   "models", "unitree_go1", "go1.xml"))
CUSTOM_TEXT = "\n".join(" ".join(str(c) for c in row) for row in CUSTOM)


def cases():
    """(name, id, gym kwargs, envc overrides, steps, max_episode_steps, policy, first-reset options)."""
    out = []
    for i, m in enumerate(MAPS):
        for dense in ("", "Dense"):
            out.append((f"point_{m.lower()}{dense.lower()}", f"PointMaze_{m}{dense}-v3", {}, {}, 150, 60,
                        "seek" if i % 2 else "random", None))
    for m in MAPS:
        for dense in ("", "Dense"):
            out.append((f"ant_{m.lower()}{dense.lower()}", f"AntMaze_{m}{dense}-v5", {}, {}, 40, 20,
                        "random", None))
    out += [
        ("point_open_reset_target", "PointMaze_Open_Diverse_GR-v3", dict(reset_target=True),
         {"reset_target": "true"}, 600, None, "seek", None),
        ("point_open_episodic", "PointMaze_Open-v3", dict(continuing_task=False),
         {"continuing_task": "false"}, 400, None, "seek", None),
        ("point_custom_map_dense", "PointMaze_UMazeDense-v3", dict(maze_map=CUSTOM),
         {"map": CUSTOM_TEXT}, 300, 80, "seek", None),
        ("point_custom_options", "PointMaze_UMaze-v3", dict(maze_map=CUSTOM),
         {"map": CUSTOM_TEXT}, 100, 50, "seek", {"goal_cell": [3, 4], "reset_cell": [2, 1]}),
        ("ant_custom_map_episodic", "AntMaze_UMaze-v5", dict(maze_map=CUSTOM, continuing_task=False,
                                                               ctrl_cost_weight=0.1),
         {"map": CUSTOM_TEXT, "continuing_task": "false", "ctrl_cost_weight": "0.1"}, 40, 25, "random", None),
        # a third-party robot in AntMaze (the reference's xml_file): the Unitree Go1 under Ant-v5's task
        ("ant_go1_xml_file", "AntMaze_UMazeDense-v5", dict(xml_file=GO1),
         {"xml_file": "$SHARED/models/unitree_go1/go1.xml"}, 60, 25, "random", None),
    ]
    return out


def hexa(x):
    return np.ascontiguousarray(np.asarray(x, dtype=np.float64)).astype("<f8").tobytes().hex()


def enc_obs(o):
    return {k: hexa(o[k]) for k in ("observation", "achieved_goal", "desired_goal")}


def enc_info(info):
    return {k: hexa(v) for k, v in info.items() if k != "success"}


def policy(kind, rng, env, obs):
    space = env.action_space
    if kind == "seek" and space.shape == (2,):
        # a P-controller towards the goal, with noise (reaches goals, so success/termination/resampling happen)
        d = obs["desired_goal"] - obs["achieved_goal"]
        a = np.clip(3.0 * d - 0.3 * obs["observation"][2:4] + rng.normal(0, 0.3, 2), -1.0, 1.0)
        return a.astype(np.float64)
    return rng.uniform(space.low, space.high).astype(np.float64)


def record(case, seed, action_seed):
    name, env_id, kwargs, overrides, steps, max_steps, kind, options = case
    mk = dict(kwargs)
    if max_steps is not None:
        mk["max_episode_steps"] = max_steps
    env = gym.make(env_id, **mk)
    ov = dict(overrides)
    if max_steps is not None:
        ov["max_episode_steps"] = str(max_steps)
    rng = np.random.default_rng(action_seed)
    events = []
    obs, info = env.reset(seed=seed, options=options)
    events.append({"reset": seed, "options": options, "obs": enc_obs(obs), "success": bool(info["success"]),
                   "info": enc_info(info)})
    for _ in range(steps):
        a = policy(kind, rng, env, obs)
        obs, r, term, trunc, info = env.step(a)
        events.append({"action": hexa(a), "obs": enc_obs(obs), "reward": hexa(r), "terminated": bool(term),
                       "truncated": bool(trunc), "success": bool(info["success"]), "info": enc_info(info)})
        if term or trunc:
            obs, info = env.reset()
            events.append({"reset": None, "options": None, "obs": enc_obs(obs),
                           "success": bool(info["success"]), "info": enc_info(info)})
    env.close()
    return {"name": name, "id": env_id, "overrides": ov, "numerics": numerics_profile.profile_name(),
            "numerics_settings": numerics_profile.settings(), "events": events}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "fixtures", "maze"))
    ap.add_argument("--seed", type=int, default=None, help="fresh seeds derived from this (live check)")
    ap.add_argument("--only", default=None, help="substring filter on case names")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    seeder = np.random.default_rng(args.seed) if args.seed is not None else None
    n = 0
    for k, case in enumerate(cases()):
        if args.only and args.only not in case[0]:
            continue
        if seeder is None:
            seed, aseed = k, 5000 + k
        else:
            seed, aseed = (int(x) for x in seeder.integers(0, 2**31, 2))
        rec = record(case, seed, aseed)
        with open(os.path.join(args.out, case[0] + ".json"), "w") as f:
            json.dump(rec, f, separators=(",", ":"))
        n += 1
    # np.exp as the dense reward computes it (SVML on AVX512 CPUs), over the distances a maze sees.
    xr = seeder if seeder is not None else np.random.default_rng(7)
    xs = np.concatenate([-xr.uniform(0, 40, 4000), -xr.exponential(1.0, 1000), xr.uniform(-700, 700, 1000)])
    with open(os.path.join(args.out, "npexp.json"), "w") as f:
        json.dump({"numerics": numerics_profile.profile_name(), "numerics_settings": numerics_profile.settings(),
                   "x": hexa(xs), "exp": hexa(np.exp(xs))}, f)
    print(f"record_maze: {n} cases in {args.out} (numerics {numerics_profile.profile_name()})", file=sys.stderr)


if __name__ == "__main__":
    main()
