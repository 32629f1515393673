#!/usr/bin/env python3
"""Record Gymnasium-Robotics 1.4.2's goal-conditioned envs (Fetch v4, the Shadow Hand; sparse and
dense) for envc's replay tests (tests/fetch.rs, tests/hand.rs) and the live check: from a seed,
random actions (half of them float32, some outside [-1, 1] so the clip shows), every observation
dict, reward, termination, truncation and `is_success`; then `compute_reward` on a batch of goal
pairs.

    .venv/bin/python tests/reference/record_robotics.py            # re-record the committed fixtures
    .venv/bin/python tests/reference/record_robotics.py --out DIR --seed N [--family hand]

Format (one JSON file per id, in DIR/<family>/): `{"id", "numerics", "numerics_settings", "seed",
"actions" (hex, steps x the action size, float64 values of the actions given), "float32" (per step: the action was passed as
float32), "obs" / "achieved" / "desired" (hex per event, the reset first), "reward" (hex per step),
"is_success" (hex per step), "terminated", "truncated" (per step), "batch_achieved",
"batch_desired" (hex, n x the goal size), "batch_reward" (hex, float64 of the reference's values),
"batch_float32" (whether the reference's batch reward was float32)}`. The patch the reference
needs on MuJoCo 3.17 is robotics_patch.py.
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

import numerics_profile  # noqa: E402
import robotics_patch  # noqa: E402,F401

gym.register_envs(gymnasium_robotics)

TOUCH = [f"HandManipulateBlock{v}_{t}TouchSensors{r}-v1" for v in ("", "RotateZ", "RotateXYZ", "RotateParallel")
         for t in ("Continuous", "Boolean") for r in ("", "Dense")]
TOUCH += [f"HandManipulate{o}{v}_{t}TouchSensors{r}-v1" for o in ("Egg", "Pen") for v in ("", "Rotate")
          for t in ("Continuous", "Boolean") for r in ("", "Dense")]

FAMILIES = {
    "fetch": [f"Fetch{t}{r}-v4" for t in ("Reach", "Push", "Slide", "PickAndPlace") for r in ("", "Dense")],
    "hand": [f"HandReach{r}-v3" for r in ("", "Dense")]
    + [f"HandManipulateBlock{v}{r}-v1" for v in ("", "Full", "RotateZ", "RotateXYZ", "RotateParallel") for r in ("", "Dense")]
    + [f"HandManipulate{o}{v}{r}-v1" for o in ("Egg", "Pen") for v in ("", "Full", "Rotate") for r in ("", "Dense")]
    + TOUCH,
}


def hexa(a):
    return np.ascontiguousarray(np.asarray(a, dtype="<f8")).tobytes().hex()


def record(env_id, seed):
    """One rollout over the time limit (so a truncation and a second reset are in it)."""
    env = gym.make(env_id)
    steps = max(60, env.spec.max_episode_steps + 10)
    rng = np.random.default_rng(seed + 7)
    actions, f32 = [], []
    obs_l, ach, des, rew, succ, term, trunc, resets = [], [], [], [], [], [], [], []

    def event(o):
        obs_l.append(hexa(o["observation"]))
        ach.append(hexa(o["achieved_goal"]))
        des.append(hexa(o["desired_goal"]))

    o, info = env.reset(seed=seed)
    assert info == {}
    event(o)
    for t in range(steps):
        a = rng.uniform(-1.3, 1.3, env.action_space.shape[0])
        as32 = bool(t % 2)
        if as32:
            a = a.astype(np.float32)
        actions.append(np.asarray(a, dtype=np.float64))
        f32.append(as32)
        o, r, te, tr, info = env.step(a)
        event(o)
        rew.append(float(r))
        succ.append(float(info["is_success"]))
        term.append(bool(te))
        trunc.append(bool(tr))
        if te or tr:
            o, _ = env.reset()
            resets.append(t)
            event(o)
    u = env.unwrapped
    n = 256
    k = np.asarray(u.goal).shape[0]
    g = rng.uniform(-0.1, 0.1, (n, k)) + np.asarray(u.goal)
    d = g + rng.normal(0, 0.04 if k == 3 else 0.004, (n, k))
    d[:8] = g[:8]
    if "Pen" in env_id:
        # The pen's batched compute_reward replaces the Z angle of row 2 alone (its
        # `euler_a[2] = euler_b[2]` indexes rows in a batch): each row as a single goal instead,
        # which is what the step reward is.
        br = np.array([u.compute_reward(g[i], d[i], {}) for i in range(n)])
    else:
        br = u.compute_reward(g, d, {})
    return {
        "id": env_id, "numerics": numerics_profile.profile_name(),
        "numerics_settings": numerics_profile.settings(), "seed": seed,
        "actions": hexa(actions), "float32": f32, "obs": obs_l, "achieved": ach, "desired": des,
        "reward": hexa(rew), "is_success": hexa(succ), "terminated": term, "truncated": trunc,
        "resets_after": resets, "batch_achieved": hexa(g), "batch_desired": hexa(d),
        "batch_reward": hexa(br), "batch_float32": br.dtype == np.float32,
    }


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(here, "fixtures"))
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--family", nargs="*", default=list(FAMILIES), choices=list(FAMILIES))
    args = ap.parse_args()
    for family in args.family:
        out = os.path.join(args.out, family)
        os.makedirs(out, exist_ok=True)
        for k, env_id in enumerate(FAMILIES[family]):
            rec = record(env_id, args.seed + k)
            with open(os.path.join(out, f"{env_id}.json"), "w") as f:
                json.dump(rec, f, separators=(",", ":"))
            print(f"record_robotics: {env_id} seed {rec['seed']}, {len(rec['float32'])} steps, "
                  f"{len(rec['resets_after'])} resets", file=sys.stderr)


if __name__ == "__main__":
    main()
