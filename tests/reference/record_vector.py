#!/usr/bin/env python3
"""Record Gymnasium 1.4.0 vector-env trajectories (`gym.make_vec(..., vectorization_mode="sync")`)
in both autoreset modes, for tests/vector.rs.

    .venv/bin/python tests/reference/record_vector.py              # re-record tests/reference/fixtures/vector
    .venv/bin/python tests/reference/record_vector.py --out DIR --seed N   # live cross-check, fresh seeds

Per case `<name>.npz` holds, for T steps of N envs: `actions` [T,N,A] (float64, uniform in 1.2 x the
action bounds), `obs0` [N,O] (after `reset(seed=s)`), `obs`, `final_obs` [T,N,O], `reward`,
`terminated`, `truncated`, `has_final` [T,N] (`final_obs` is zero where `has_final` is false; NextStep
cases never have one). `manifest.json` lists the cases with their seed, mode and overrides.
"""

import argparse
import json
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from record import install_render_shims  # noqa: E402  (imageio/packaging stand-ins)
import numerics_profile  # noqa: E402

# name, env id, num_envs, steps, overrides (exact reference kwargs; max_episode_steps goes to TimeLimit)
CASES = [
    ("hopper_n4", "Hopper-v5", 4, 120, {}),
    ("invertedpendulum_n5", "InvertedPendulum-v5", 5, 80, {}),
    ("ant_n3_trunc", "Ant-v5", 3, 60, {"max_episode_steps": 17}),
    ("halfcheetah_n2_trunc", "HalfCheetah-v5", 2, 40, {"max_episode_steps": 9}),
    ("walker2d_n3", "Walker2d-v5", 3, 80, {"reset_noise_scale": 0.05}),
]
MODES = ("next_step", "same_step")


def record_case(gym, np, AutoresetMode, env_id, n, steps, overrides, mode, seed, action_seed):
    envs = gym.make_vec(env_id, num_envs=n, vectorization_mode="sync",
                        vector_kwargs={"autoreset_mode": AutoresetMode.NEXT_STEP if mode == "next_step"
                                       else AutoresetMode.SAME_STEP},
                        **overrides)
    if "max_episode_steps" in overrides:
        assert all(e.spec.max_episode_steps == overrides["max_episode_steps"] for e in envs.envs)
    low, high = envs.single_action_space.low.astype(np.float64), envs.single_action_space.high.astype(np.float64)
    rng = np.random.default_rng(action_seed)
    obs0, _ = envs.reset(seed=seed)
    out = {k: [] for k in ("actions", "obs", "reward", "terminated", "truncated", "final_obs", "has_final")}
    for _ in range(steps):
        a = rng.uniform(low * 1.2, high * 1.2, size=(n, low.size))
        obs, rew, term, trunc, info = envs.step(a)
        fo = np.zeros_like(obs)
        hf = np.zeros(n, dtype=bool)
        if "final_obs" in info:
            hf = info["_final_obs"].copy()
            for i in np.flatnonzero(hf):
                fo[i] = info["final_obs"][i]
        for k, v in (("actions", a), ("obs", obs), ("reward", rew), ("terminated", term),
                     ("truncated", trunc), ("final_obs", fo), ("has_final", hf)):
            out[k].append(np.array(v, copy=True))
    envs.close()
    arrays = {k: np.stack(v) for k, v in out.items()}
    arrays["obs0"] = np.array(obs0, copy=True)
    assert arrays["obs"].dtype == np.float64 and arrays["reward"].dtype == np.float64
    return arrays


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(HERE, "fixtures", "vector"))
    ap.add_argument("--seed", type=int, default=None)
    args = ap.parse_args()
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    install_render_shims()
    import gymnasium as gym
    import mujoco
    import numpy as np
    from gymnasium.vector import AutoresetMode

    seeds = np.random.default_rng(args.seed) if args.seed is not None else None
    manifest = {"gymnasium": gym.__version__, "mujoco": mujoco.__version__,
                "numerics": numerics_profile.profile_name(), "numerics_settings": numerics_profile.settings(),
                "cases": []}
    os.chdir(tempfile.mkdtemp())  # MuJoCo's MUJOCO_LOG.TXT never lands in the tree
    for k, (name, env_id, n, steps, overrides) in enumerate(CASES):
        for mode in MODES:
            if seeds is None:
                seed, action_seed = 100 + k, 2000 + k
            else:
                seed, action_seed = (int(x) for x in seeds.integers(0, 2**31, size=2))
            arrays = record_case(gym, np, AutoresetMode, env_id, n, steps, overrides, mode, seed, action_seed)
            case = f"{name}_{mode}"
            np.savez_compressed(os.path.join(out, case + ".npz"), **arrays)
            ends = int(arrays["terminated"].sum() + arrays["truncated"].sum())
            print(f"{case}: {n} envs x {steps} steps, {ends} episode ends, seed {seed}")
            manifest["cases"].append({
                "name": case, "env_id": env_id, "num_envs": n, "steps": steps, "mode": mode,
                "seed": seed, "action_seed": action_seed,
                "overrides": {k: json.dumps(v) for k, v in overrides.items()},
            })
    with open(os.path.join(out, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=1)


if __name__ == "__main__":
    main()
