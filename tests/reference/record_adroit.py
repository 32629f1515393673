#!/usr/bin/env python3
"""Record Gymnasium-Robotics 1.4.2's Adroit v1 envs (dense and sparse) for envc's replay test
(tests/adroit.rs) and the live check: from a seed, random actions (half of them float32, some
outside [-1, 1] so the clip shows), every observation, reward, termination, truncation and
`success`, through the 200-step truncation and the reset after it.

    .venv/bin/python tests/reference/record_adroit.py              # re-record the committed fixtures
    .venv/bin/python tests/reference/record_adroit.py --out DIR --seed N

Format (one JSON file per id): `{"id", "numerics", "numerics_settings", "seed", "actions" (hex,
steps x nu, float64 values of the actions given), "float32" (per step: the action was passed as
float32), "obs" (hex per event, the reset first), "reward" (hex per step), "success" (per step,
bool), "terminated", "truncated" (per step), "resets_after" (the steps a reset followed)}`.
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

gym.register_envs(gymnasium_robotics)

IDS = [f"AdroitHand{t}{r}-v1" for t in ("Door", "Hammer", "Pen", "Relocate") for r in ("", "Sparse")]


def hexa(a):
    return np.ascontiguousarray(np.asarray(a, dtype="<f8")).tobytes().hex()


def record(env_id, seed, steps=205):
    """One rollout over the 200-step limit (so a truncation and a second reset are in it)."""
    env = gym.make(env_id)
    nu = env.action_space.shape[0]
    rng = np.random.default_rng(seed + 7)
    actions, f32, obs_l, rew, succ, term, trunc, resets = [], [], [], [], [], [], [], []
    o, info = env.reset(seed=seed)
    assert info == {}
    obs_l.append(hexa(o))
    for t in range(steps):
        a = rng.uniform(-1.3, 1.3, nu)
        as32 = bool(t % 2)
        if as32:
            a = a.astype(np.float32)
        actions.append(np.asarray(a, dtype=np.float64))
        f32.append(as32)
        o, r, te, tr, info = env.step(a)
        obs_l.append(hexa(o))
        rew.append(float(r))
        succ.append(bool(info["success"]))
        term.append(bool(te))
        trunc.append(bool(tr))
        if te or tr:
            o, _ = env.reset()
            resets.append(t)
            obs_l.append(hexa(o))
    return {
        "id": env_id, "numerics": numerics_profile.profile_name(),
        "numerics_settings": numerics_profile.settings(), "seed": seed,
        "actions": hexa(actions), "float32": f32, "obs": obs_l, "reward": hexa(rew),
        "success": succ, "terminated": term, "truncated": trunc, "resets_after": resets,
    }


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(here, "fixtures", "adroit"))
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--ids", nargs="*", default=IDS)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for env_id in args.ids:
        # The same seed for an id whichever ids are recorded with it.
        rec = record(env_id, args.seed + (IDS.index(env_id) if env_id in IDS else 0))
        with open(os.path.join(args.out, f"{env_id}.json"), "w") as f:
            json.dump(rec, f, separators=(",", ":"))
        print(f"record_adroit: {env_id} seed {rec['seed']}, {len(rec['float32'])} steps, "
              f"{len(rec['resets_after'])} resets, {sum(rec['success'])} successes",
              file=sys.stderr)


if __name__ == "__main__":
    main()
