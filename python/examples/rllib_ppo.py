#!/usr/bin/env python3
"""RLlib PPO on an envc env through Gymnasium's registration, against Gymnasium's own env.

    python python/examples/rllib_ppo.py --iterations 10                 # envc/Hopper-v5 vs Hopper-v5
    python python/examples/rllib_ppo.py --env Walker2d-v5 --only envc

RLlib's new API stack builds each env runner's env with ``gymnasium.make_vec(config.env,
num_envs_per_env_runner, vectorization_mode=gym_env_vectorize_mode)``. For envc the env is
``"envc:envc/Hopper-v5"`` (Gymnasium's ``module:id`` form, so every Ray worker imports ``envc``,
which registers the ``envc/`` namespace) with ``gym_env_vectorize_mode="vector_entry_point"``:
each env runner steps one ``envc.EnvcVectorEnv`` (Rust threads, NextStep autoreset, which is what
RLlib expects). The comparison is the same config on ``"Hopper-v5"`` with RLlib's default
``"sync"`` mode (Gymnasium's ``SyncVectorEnv`` of MuJoCo envs).

The two algorithms are built side by side and their ``train()`` calls interleaved (envc, then
Gymnasium, for each iteration), so load from other processes hits both alike. Reported per
iteration: ``episode_return_mean``, env steps sampled, and steps/s of the whole iteration
(sampling + learning) and of sampling alone (RLlib's env-runner sample timer).

Ray runs in-process (``ray.init(num_cpus=2, include_dashboard=False)``, a private temp dir); never
``ray stop``. Needs ``ray[rllib]`` and ``torch`` besides ``envc``. Ray 2.60's ``rllib`` extra pins
``gymnasium==1.2.2``; envc needs gymnasium 1.4, so install ``ray`` and the extra's other requirements
without it (docs/training.md). Not run in CI (too heavy: Ray, torch).
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time

import numpy as np


def build(env: str, vector_mode: str, args):
    from ray.rllib.algorithms.ppo import PPOConfig

    config = (
        PPOConfig()
        .environment(env)
        .env_runners(
            num_env_runners=1,
            num_envs_per_env_runner=args.num_envs,
            num_cpus_per_env_runner=1,
            gym_env_vectorize_mode=vector_mode,
        )
        .learners(num_learners=0)
        .training(
            train_batch_size_per_learner=args.batch,
            minibatch_size=256,
            num_epochs=6,
            lr=3e-4,
            gamma=0.99,
            lambda_=0.95,
            vf_loss_coeff=0.5,
        )
        .debugging(seed=args.seed)
    )
    return config.build_algo()


def sample_time(result: dict) -> float | None:
    """Seconds the env runners spent sampling in this iteration (RLlib's timer), if reported."""
    runners = result.get("env_runners", {})
    for key in ("sample", "env_runner_sampling_timer"):
        if key in runners:
            return float(runners[key])
    timers = result.get("timers", {})
    return float(timers["env_runner_sampling_timer"]) if "env_runner_sampling_timer" in timers else None


def sampling_rate(algo, steps: int) -> float:
    """Env steps/s of the env runner's own ``sample()`` (policy inference + env + connectors),
    timed inside the runner process, without learning."""

    def run(runner):
        t = time.perf_counter()
        episodes = runner.sample(num_timesteps=steps, random_actions=False)
        n = sum(len(e) for e in episodes)
        return n / (time.perf_counter() - t)

    return float(algo.env_runner_group.foreach_env_runner(run, local_env_runner=False)[0])


def main() -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--env", default="Hopper-v5")
    ap.add_argument("--iterations", type=int, default=10)
    ap.add_argument("--num-envs", type=int, default=8, help="envs per env runner")
    ap.add_argument("--batch", type=int, default=4000, help="env steps per iteration")
    ap.add_argument("--only", choices=["envc", "gymnasium"], help="run one side only")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--sample-rounds", type=int, default=5, help="interleaved sampling rounds")
    args = ap.parse_args()

    import ray

    ray.init(
        num_cpus=2,
        include_dashboard=False,
        _temp_dir=tempfile.mkdtemp(prefix="rllib-envc-"),
        log_to_driver=False,
    )
    sides = {
        "envc": (f"envc:envc/{args.env}", "vector_entry_point"),
        "gymnasium": (args.env, "sync"),
    }
    if args.only:
        sides = {args.only: sides[args.only]}
    algos = {name: build(env, mode, args) for name, (env, mode) in sides.items()}
    log: dict[str, list[dict]] = {name: [] for name in algos}
    for it in range(1, args.iterations + 1):
        for name, algo in algos.items():
            t0 = time.perf_counter()
            result = algo.train()
            wall = time.perf_counter() - t0
            runners = result.get("env_runners", {})
            steps = int(runners.get("num_env_steps_sampled", 0))
            st = sample_time(result)
            row = {
                "iteration": it,
                "episode_return_mean": float(runners.get("episode_return_mean", float("nan"))),
                "env_steps": steps,
                "env_steps_lifetime": int(runners.get("num_env_steps_sampled_lifetime", 0)),
                "iter_seconds": round(wall, 2),
                "steps_per_s": round(steps / wall, 1),
                "sample_steps_per_s": None if not st else round(steps / st, 1),  # smoothed timer
            }
            log[name].append(row)
            print(f"{name:>9} it {it:2d}: return {row['episode_return_mean']:8.1f}  "
                  f"{steps} steps in {wall:5.1f} s = {row['steps_per_s']:7.0f} steps/s"
                  f"  (sampling {row['sample_steps_per_s']} steps/s)", flush=True)
    summary: dict = {"env": args.env, "num_envs_per_env_runner": args.num_envs,
                     "iterations": args.iterations}
    for name, rows in log.items():
        steps = sum(r["env_steps"] for r in rows)
        secs = sum(r["iter_seconds"] for r in rows)
        samp = [r for r in rows if r["sample_steps_per_s"]]
        summary[name] = {
            "final_episode_return_mean": rows[-1]["episode_return_mean"],
            "env_steps": steps,
            "train_seconds": round(secs, 1),
            "steps_per_s": round(steps / secs, 1),
            "sample_steps_per_s": round(
                sum(r["env_steps"] for r in samp)
                / sum(r["env_steps"] / r["sample_steps_per_s"] for r in samp), 1)
            if samp else None,
        }
    # Sampling alone, interleaved rounds (RLlib's own sample timer is a smoothed mean).
    rates: dict[str, list[float]] = {name: [] for name in algos}
    for _ in range(args.sample_rounds):
        for name, algo in algos.items():
            rates[name].append(sampling_rate(algo, args.batch))
    for name in algos:
        summary[name]["runner_sample_steps_per_s_median"] = round(float(np.median(rates[name])), 1)
        summary[name]["runner_sample_steps_per_s_rounds"] = [round(r, 1) for r in rates[name]]
    if len(log) == 2:
        summary["ratio_runner_sample_steps_per_s"] = round(
            summary["envc"]["runner_sample_steps_per_s_median"]
            / summary["gymnasium"]["runner_sample_steps_per_s_median"], 2)
        summary["ratio_steps_per_s"] = round(
            summary["envc"]["steps_per_s"] / summary["gymnasium"]["steps_per_s"], 2)
        if summary["envc"]["sample_steps_per_s"] and summary["gymnasium"]["sample_steps_per_s"]:
            summary["ratio_sample_steps_per_s"] = round(
                summary["envc"]["sample_steps_per_s"] / summary["gymnasium"]["sample_steps_per_s"], 2)
    print(json.dumps(summary, indent=1))
    for algo in algos.values():
        algo.stop()
    ray.shutdown()
    return summary


if __name__ == "__main__":
    os.environ.setdefault("RAY_DEDUP_LOGS", "0")
    main()
