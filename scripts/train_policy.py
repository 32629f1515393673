#!/usr/bin/env python3
"""Train the policy a dataset spec names, with Stable-Baselines3, and export it as `.npz`.

Not part of the test suite: it needs torch, stable-baselines3 and sb3-contrib, which live in their
own environment (`scripts/requirements-train.txt`), never in the package's or CI's:

    python3 -m venv .train-venv
    .train-venv/bin/pip install -r scripts/requirements-train.txt
    .train-venv/bin/python scripts/train_policy.py specs/datasets/mujoco/hopper/simple-v0.toml

The algorithm, its hyperparameters and the training budget are the spec's `[train]` table (the
original generation scripts' values). Training runs on 5 envs (`make_vec_env`, seed 0); every
`eval_freq` calls (5 envs x 1,000 = 5,000 steps) the policy is evaluated on deterministic episodes
and the best one is kept; that best checkpoint is exported to the spec's `[policy] file`:

- SAC / TQC actors: `hidden_w{i}`, `hidden_b{i}` (ReLU layers), `mu_w`, `mu_b`, `log_std_w`,
  `log_std_b`, `squash = 1` (action = tanh(mu), scaled to the action bounds);
- PPO: the policy MLP (tanh layers), `mu_w`, `mu_b` (the mean), a state-independent `log_std`,
  `squash = 0` (action = mean, clipped to the bounds).

Both carry `action_low`, `action_high` and `activation` (0 relu, 1 tanh). envc runs the file in
Rust (`envc::policy::MlpPolicy`) without torch. The spec is read by envc (`envc.datasets.read_spec`):
the training venv's own envc if it has one, else the repository's `python/` as scripts/setup.sh
built it.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np


def load_spec(path: str) -> dict:
    """The spec as envc reads it (a mistake is E1801 at its line and column)."""
    try:
        import envc.datasets
    except ImportError:
        # The training venv does not install envc: the repository's package serves, once
        # scripts/setup.sh has built its native core into python/envc/ (abi3, any Python >= 3.10).
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
        import envc.datasets
    return envc.datasets.read_spec(path)


def make_env_fn(env_id: str, params: dict):
    import gymnasium as gym

    def make():
        return gym.make(env_id, **params)

    return make


def export(model, algo: str, path: str, low, high) -> None:
    import torch

    out: dict[str, np.ndarray] = {}

    def linears(seq):
        return [m for m in seq if isinstance(m, torch.nn.Linear)]

    with torch.no_grad():
        if algo in ("SAC", "TQC"):
            actor = model.actor
            hidden = linears(actor.latent_pi)
            out["activation"] = np.array(0, dtype=np.int64)
            out["squash"] = np.array(1, dtype=np.int64)
            out["log_std_w"] = actor.log_std.weight.numpy().astype(np.float32)
            out["log_std_b"] = actor.log_std.bias.numpy().astype(np.float32)
            mu = actor.mu
        elif algo == "PPO":
            pol = model.policy
            hidden = linears(pol.mlp_extractor.policy_net)
            out["activation"] = np.array(1, dtype=np.int64)
            out["squash"] = np.array(0, dtype=np.int64)
            out["log_std"] = pol.log_std.numpy().astype(np.float32)
            mu = pol.action_net
        else:
            raise SystemExit(f"{algo}: export knows SAC, TQC and PPO")
        for i, layer in enumerate(hidden):
            out[f"hidden_w{i}"] = layer.weight.numpy().astype(np.float32)
            out[f"hidden_b{i}"] = layer.bias.numpy().astype(np.float32)
        out["mu_w"] = mu.weight.numpy().astype(np.float32)
        out["mu_b"] = mu.bias.numpy().astype(np.float32)
    out["action_low"] = np.asarray(low, dtype=np.float32)
    out["action_high"] = np.asarray(high, dtype=np.float32)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    np.savez(path, **out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("spec", help="a dataset spec (specs/datasets/...toml)")
    ap.add_argument("--timesteps", type=int, help="override the spec's training budget")
    ap.add_argument("--eval-episodes", type=int, help="override the spec's eval episodes")
    ap.add_argument("--minutes", type=float, help="stop after this wall time (best kept)")
    ap.add_argument("--workdir", default="train-runs", help="checkpoints and logs")
    ap.add_argument("--out", help="the .npz to write (default: the spec's [policy] file)")
    ap.add_argument("--export-only", action="store_true", help="export the best checkpoint so far")
    args = ap.parse_args()

    import torch

    torch.set_num_threads(1)
    from stable_baselines3 import PPO, SAC
    from stable_baselines3.common.callbacks import BaseCallback, EvalCallback
    from stable_baselines3.common.env_util import make_vec_env

    spec = load_spec(args.spec)
    ds, train = spec["dataset"], spec["train"]
    env_id = ds["env"]
    params = ds.get("params", {})
    algo = train["algorithm"].upper()
    hyper = dict(train.get("hyperparameters", {}))
    timesteps = args.timesteps or int(train["timesteps"])
    n_envs = int(train.get("n_envs", 5))
    eval_freq = int(train.get("eval_freq", 1000))
    eval_episodes = args.eval_episodes or int(train.get("eval_episodes", 50))
    seed = int(train.get("seed", 0))
    work = os.path.join(args.workdir, ds["id"].replace("/", "_"))

    env = make_vec_env(make_env_fn(env_id, params), n_envs=n_envs, seed=seed)
    eval_env = make_vec_env(make_env_fn(env_id, params), n_envs=n_envs, seed=seed + 1000)
    if algo == "SAC":
        model = SAC("MlpPolicy", env, seed=seed, device="cpu", **hyper)
    elif algo == "TQC":
        from sb3_contrib import TQC

        model = TQC("MlpPolicy", env, seed=seed, device="cpu", **hyper)
    elif algo == "PPO":
        model = PPO("MlpPolicy", env, seed=seed, device="cpu", **hyper)
    else:
        raise SystemExit(f"{algo}: expected SAC, TQC or PPO")

    class Deadline(BaseCallback):
        def __init__(self, minutes):
            super().__init__()
            self.end = None if minutes is None else time.time() + 60 * minutes

        def _on_step(self) -> bool:
            return self.end is None or time.time() < self.end

    evalcb = EvalCallback(
        eval_env,
        best_model_save_path=work,
        log_path=work,
        n_eval_episodes=eval_episodes,
        eval_freq=eval_freq,
        deterministic=True,
        verbose=1,
    )
    if not args.export_only:
        model.learn(total_timesteps=timesteps, callback=[evalcb, Deadline(args.minutes)])
    best_path = os.path.join(work, "best_model.zip")
    best = type(model).load(best_path, device="cpu") if os.path.exists(best_path) else model
    space = env.action_space
    out = args.out or os.path.join(os.path.dirname(os.path.abspath(args.spec)), spec["policy"]["file"])
    export(best, algo, out, space.low, space.high)
    print(f"best mean return {evalcb.best_mean_reward:.2f}; wrote {out}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
