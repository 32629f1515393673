#!/usr/bin/env python3
"""Train a Stable-Baselines3 PPO agent on an envc env, from the documented one-liner.

    import envc, gymnasium as gym
    env = gym.make("envc/InvertedPendulum-v5")      # instead of gym.make("InvertedPendulum-v5")

Trains PPO (SB3's defaults, ``MlpPolicy``) in chunks of ``--eval-every`` steps; after each chunk
``evaluate_policy`` runs ``--eval-episodes`` deterministic episodes on a separate env, and training
stops once the mean return reaches ``--target`` (or at ``--max-steps``). Prints the mean return,
the steps trained and the wall time (training alone, and with the evaluations).

    python python/examples/train_sb3.py                 # envc's InvertedPendulum-v5
    python python/examples/train_sb3.py --gymnasium     # the same script on Gymnasium's env

``--gymnasium`` runs Gymnasium's own ``InvertedPendulum-v5``: the same seeds give the same
observations (envc is bit-identical to it), so the two runs train the same agent and differ in
wall time only, unless torch itself is not deterministic on the machine.

Needs ``stable-baselines3`` and ``torch`` besides ``envc``. Not run in CI (torch is too large for
it); docs/PERFORMANCE.md records a run.
"""

from __future__ import annotations

import argparse
import json
import time

import gymnasium as gym


def make_env(env_id: str, use_gymnasium: bool) -> gym.Env:
    """The one-liner: ``gym.make("envc/<id>")`` after ``import envc``, or Gymnasium's own env."""
    if use_gymnasium:
        return gym.make(env_id)
    import envc  # noqa: F401  (registers the envc/ namespace)

    return gym.make(f"envc/{env_id}")


def main() -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--env", default="InvertedPendulum-v5")
    ap.add_argument("--gymnasium", action="store_true", help="Gymnasium's own env instead of envc's")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--target", type=float, default=900.0, help="stop at this mean return")
    ap.add_argument("--max-steps", type=int, default=300_000)
    ap.add_argument("--eval-every", type=int, default=10_240, help="steps between evaluations")
    ap.add_argument("--eval-episodes", type=int, default=10)
    ap.add_argument("--torch-threads", type=int, default=1, help="small MLPs train fastest on one")
    args = ap.parse_args()

    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.evaluation import evaluate_policy
    from stable_baselines3.common.monitor import Monitor

    torch.set_num_threads(args.torch_threads)
    env = make_env(args.env, args.gymnasium)
    eval_env = Monitor(make_env(args.env, args.gymnasium))
    eval_env.reset(seed=args.seed + 1000)
    model = PPO("MlpPolicy", env, seed=args.seed, verbose=0, device="cpu")

    source = "Gymnasium" if args.gymnasium else "envc"
    train_s, start, mean, std = 0.0, time.perf_counter(), float("-inf"), 0.0
    while model.num_timesteps < args.max_steps and mean < args.target:
        t0 = time.perf_counter()
        model.learn(total_timesteps=args.eval_every, reset_num_timesteps=False)
        train_s += time.perf_counter() - t0
        mean, std = evaluate_policy(model, eval_env, n_eval_episodes=args.eval_episodes,
                                    deterministic=True)
        print(f"{source} {args.env}: {model.num_timesteps} steps, mean return {mean:.1f} ± {std:.1f} "
              f"({train_s:.0f} s training)", flush=True)
    result = {
        "env": f"{'' if args.gymnasium else 'envc/'}{args.env}",
        "mean_return": float(mean),
        "std_return": float(std),
        "timesteps": model.num_timesteps,
        "train_seconds": round(train_s, 1),
        "wall_seconds": round(time.perf_counter() - start, 1),
        "reached_target": bool(mean >= args.target),
    }
    print(json.dumps(result))
    return result


if __name__ == "__main__":
    main()
