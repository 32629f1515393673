#!/usr/bin/env python3
"""Mean return of every committed suite policy, measured in Gymnasium (the reference env).

    .venv/bin/python scripts/policy_returns.py [--episodes 100] [SPEC_ID ...]

Episode k is reset with the spec's seed + k, as a build does; each policy runs through envc's
runner (`envc.datasets.policy`, no torch) deterministically and in its spec's mode (stochastic
noise from default_rng(seed)). Prints one Markdown row per policy.
"""

from __future__ import annotations

import argparse
import os

import gymnasium as gym
import numpy as np

import envc.datasets


def returns(spec_path: str, episodes: int, deterministic: bool) -> np.ndarray:
    ds = envc.datasets.read_spec(spec_path)["dataset"]
    env = gym.make(ds["env"], **ds.get("params", {}))
    pol = envc.datasets.policy(spec_path, seed=ds["seed"], deterministic=deterministic)
    out = []
    for k in range(episodes):
        obs, _ = env.reset(seed=ds["seed"] + k)
        total, done = 0.0, False
        while not done:
            obs, r, term, trunc, _ = env.step(pol(obs))
            total += float(r)
            done = term or trunc
        out.append(total)
    return np.array(out)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("ids", nargs="*")
    ap.add_argument("--episodes", type=int, default=100)
    a = ap.parse_args()
    root = os.path.join(os.path.dirname(__file__), "..", "specs", "datasets")
    ids = a.ids or envc.datasets.bundled()
    print("| dataset | deterministic | spec's mode |")
    print("|---|---:|---:|")
    for i in ids:
        path = os.path.abspath(os.path.join(root, i + ".toml"))
        pol = envc.datasets.read_spec(path)["policy"]["file"]
        if not os.path.exists(os.path.join(os.path.dirname(path), pol)):
            continue
        det = returns(path, a.episodes, True)
        mode = returns(path, a.episodes, False)
        print(f"| {i} | {det.mean():.1f} ± {det.std():.1f} | {mode.mean():.1f} ± {mode.std():.1f} |", flush=True)


if __name__ == "__main__":
    main()
