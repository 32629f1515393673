#!/usr/bin/env python3
"""Train the Go1 to track velocity commands: Stable-Baselines3 PPO over envc's vector env.

    python python/examples/train_go1_joystick.py --steps 3000000          # the joystick task
    python python/examples/train_go1_joystick.py --spec specs/examples/go1.toml --steps 50000
    python python/examples/train_go1_joystick.py --bench-vec               # adapter vs SB3's own

The env is ``envc.EnvcVectorEnv`` (Rust threads step every env; SameStep autoreset), wrapped by
``EnvcSB3VecEnv``, a small adapter to SB3's ``VecEnv`` protocol (``terminal_observation``,
``TimeLimit.truncated``). ``--bench-vec`` measures it against SB3's ``DummyVecEnv`` and
``SubprocVecEnv`` of single ``envc.EnvcEnv``s.

Logged per finished training episode: the return and, for each tracking term (the info keys
matched by ``--track-keys``, default every key containing ``tracking``), the episode's sum and its
mean per step. Before training, a zero policy (all-zero actions: with PD position actions, standing
at the default pose) is evaluated for the same metrics; after training, the deterministic policy
is. Writes ``<out>.csv`` (one row per training episode), ``<out>.json`` (summary) and ``<out>.png``
(tracking reward per episode vs env steps, with the zero policy's as a dashed line).

Hyper-parameters follow the spirit of MuJoCo Playground's Go1 joystick PPO and legged_gym
(discount 0.97, lr 3e-4, small entropy bonus, observation normalisation) scaled to a 2-core
machine: 32 envs × 256 steps per rollout, minibatches of 2048, 5 epochs.

Needs ``stable-baselines3``, ``torch`` and ``matplotlib`` besides ``envc``; not run in CI (torch is
too large for it). docs/training.md records a run.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import re
import time
from typing import Any

import numpy as np

GO1_XML = "/work/shared/models/unitree_go1/scene.xml"
DEFAULT_SPEC = "specs/examples/go1_joystick.toml"

try:  # the adapter subclasses SB3's VecEnv; the module still imports (for --help) without SB3
    from stable_baselines3.common.vec_env import VecEnv as _VecEnvBase
except ImportError:  # pragma: no cover
    _VecEnvBase = object


class EnvcSB3VecEnv(_VecEnvBase):
    """An ``envc.EnvcVectorEnv`` (SameStep autoreset) as a Stable-Baselines3 ``VecEnv``.

    SB3 wants the episode's last observation in ``infos[i]["terminal_observation"]`` and the
    returned observation already reset: that is Gymnasium's SameStep autoreset, which envc's
    vector env does natively (``final_obs``). Episode statistics (return, length and the sums of
    ``track_keys``) are accumulated here, in numpy, and reported in ``infos[i]["episode"]`` as
    SB3's ``Monitor`` does.
    """

    def __init__(self, venv, track_keys: list[str] | None = None, seed: int = 0):
        self.venv = venv
        n = venv.num_envs
        self.render_mode = None
        super().__init__(n, venv.single_observation_space, venv.single_action_space)
        self.track_keys = list(track_keys or [])
        self._base_seed = seed
        self._actions: np.ndarray | None = None
        self._ret = np.zeros(n)
        self._len = np.zeros(n, dtype=np.int64)
        self._sums = {k: np.zeros(n) for k in self.track_keys}
        self.episodes: list[dict[str, float]] = []  # finished episodes, drained by the caller

    def reset(self):
        seeds = [s if s is not None else None for s in self._seeds]
        if all(s is None for s in seeds):
            seeds = self._base_seed
            self._base_seed = None  # seed once; later resets continue each env's stream
        obs, _ = self.venv.reset(seed=seeds)
        self._reset_seeds()
        self._ret[:] = 0.0
        self._len[:] = 0
        for v in self._sums.values():
            v[:] = 0.0
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions, dtype=np.float32)

    def step_wait(self):
        obs, rew, term, trunc, info = self.venv.step(self._actions)
        self._ret += rew
        self._len += 1
        for k, v in self._sums.items():
            if k in info:
                v += np.where(info["_" + k], info[k], 0.0)
        dones = term | trunc
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        for i in np.flatnonzero(dones):
            ep = {"r": float(self._ret[i]), "l": int(self._len[i])}
            for k, v in self._sums.items():
                ep[k] = float(v[i])
                v[i] = 0.0
            infos[i]["terminal_observation"] = info["final_obs"][i]
            infos[i]["TimeLimit.truncated"] = bool(trunc[i] and not term[i])
            infos[i]["episode"] = ep
            self.episodes.append({**ep, "terminated": bool(term[i])})
            self._ret[i] = 0.0
            self._len[i] = 0
        return obs, rew.astype(np.float32), dones, infos

    def close(self) -> None:
        self.venv.close()

    def get_attr(self, attr_name, indices=None):
        return [getattr(self, attr_name, None) for _ in self._get_indices(indices)]

    def set_attr(self, attr_name, value, indices=None) -> None:
        setattr(self, attr_name, value)

    def env_method(self, method_name, *args, indices=None, **kwargs):
        raise NotImplementedError("envc vector envs have no per-env methods")

    def env_is_wrapped(self, wrapper_class, indices=None):
        return [False for _ in self._get_indices(indices)]


def make_venv(args, num_envs: int):
    """envc's vector env of the spec, SameStep autoreset (what SB3 expects)."""
    import envc

    return envc.EnvcVectorEnv(
        args.spec, num_envs=num_envs, num_threads=args.threads, autoreset_mode="SameStep",
        **overrides(args),
    )


def overrides(args) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if args.xml_file:
        out["xml_file"] = args.xml_file
    for item in args.set or []:
        key, _, value = item.partition("=")
        try:
            out[key] = json.loads(value)
        except json.JSONDecodeError:
            out[key] = value
    return out


def track_keys_of(venv, pattern: str) -> list[str]:
    """Info keys of the tracking terms: envc reports every reward term's info key at each step."""
    _, info = venv.reset(seed=0)
    keys = [k for k in info if not k.startswith("_")]
    if not any(re.search(pattern, k) for k in keys):
        obs, *_rest, info = venv.step(np.zeros(venv.action_space.shape, dtype=np.float32))
        keys = [k for k in info if not k.startswith("_")]
    return [k for k in keys if re.search(pattern, k)]


def evaluate(venv, per_env: int, act, seed: int, track_keys: list[str]) -> dict[str, float]:
    """Mean return, length and tracking sums of ``act(obs)`` over the first ``per_env`` episodes
    of every env (not the first episodes to end overall, which would over-count falls)."""
    env = EnvcSB3VecEnv(venv, track_keys, seed=seed)
    obs = env.reset()
    done_count = np.zeros(env.num_envs, dtype=np.int64)
    kept: list[dict[str, float]] = []
    while done_count.min() < per_env:
        before = len(env.episodes)
        obs, _r, dones, _infos = env.step(act(obs))
        for i, ep in zip(np.flatnonzero(dones), env.episodes[before:]):
            done_count[i] += 1
            if done_count[i] <= per_env:
                kept.append(ep)
    return summarize(kept, track_keys)


def summarize(eps: list[dict[str, float]], track_keys: list[str]) -> dict[str, float]:
    out = {
        "episodes": len(eps),
        "return": float(np.mean([e["r"] for e in eps])),
        "length": float(np.mean([e["l"] for e in eps])),
        "fell": float(np.mean([e["terminated"] for e in eps])),
    }
    for k in track_keys:
        out[k] = float(np.mean([e[k] for e in eps]))
        out[k + "_per_step"] = float(np.mean([e[k] / e["l"] for e in eps]))
    return out


def bench_vec(args) -> None:
    """Raw steps/s of the adapter vs SB3's DummyVecEnv/SubprocVecEnv of single envc envs."""
    import envc
    import gymnasium as gym
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    n, steps = args.num_envs, args.bench_steps

    def single():
        e = envc.EnvcEnv(os.path.abspath(args.spec), **overrides(args))
        return gym.wrappers.TimeLimit(e, max_episode_steps=1000)

    def run(name, make):
        env = make()
        env.reset()
        rng = np.random.default_rng(0)
        acts = rng.uniform(-0.3, 0.3, size=(16, n, env.action_space.shape[0])).astype(np.float32)
        t = time.perf_counter()
        for s in range(steps):
            env.step(acts[s % 16])
        rate = steps * n / (time.perf_counter() - t)
        env.close()
        print(f"{name:>34}: {rate:8.0f} env steps/s", flush=True)
        return rate

    rates = {}
    for rep in range(2):  # interleaved, twice
        rates.setdefault("envc vector env + adapter", []).append(
            run(f"envc EnvcVectorEnv ({args.threads} threads)",
                lambda: EnvcSB3VecEnv(make_venv(args, n))))
        rates.setdefault("DummyVecEnv", []).append(
            run("SB3 DummyVecEnv of EnvcEnv", lambda: DummyVecEnv([single] * n)))
        rates.setdefault("SubprocVecEnv", []).append(
            run("SB3 SubprocVecEnv of EnvcEnv", lambda: SubprocVecEnv([single] * n, "fork")))
    print(json.dumps({k: round(float(np.median(v))) for k, v in rates.items()}))


def plot(rows, zero, trained, track_keys, path: str, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    steps = np.array([r["env_steps"] for r in rows], dtype=float)
    xs = np.unique(steps)  # one point per rollout: the mean of the episodes that ended in it
    window = max(1, len(xs) // 30)

    def smooth(key):
        y = np.array([r[key] for r in rows], dtype=float)
        means = np.array([y[steps == x].mean() for x in xs])
        kernel = np.ones(window) / window
        return np.convolve(means, kernel, mode="valid"), xs[window - 1 :]

    ax = axes[0]
    for j, k in enumerate(track_keys):
        color = f"C{j}"
        ax.plot(steps, [r[k] for r in rows], ".", ms=2, alpha=0.25, color=color)
        y, x = smooth(k)
        ax.plot(x, y, color=color, label=f"{k} (PPO)")
        ax.axhline(zero[k], color=color, ls="--", label=f"{k} (zero policy)")
    ax.set_xlabel("env steps")
    ax.set_ylabel("tracking reward per episode (sum over steps)")
    ax.legend(fontsize=7)
    ax.set_title(title, fontsize=9)
    ax = axes[1]
    ax.plot(steps, [r["return"] for r in rows], ".", ms=2, alpha=0.25, color="C3")
    y, x = smooth("return")
    ax.plot(x, y, color="C3", label="return (PPO)")
    ax.axhline(zero["return"], color="C3", ls="--", label="return (zero policy)")
    y, x = smooth("length")
    ax2 = ax.twinx()
    ax2.plot(x, y, color="C4", label="episode length (PPO, right axis)")
    ax2.set_ylabel("episode length")
    ax2.legend(fontsize=7, loc="lower right")
    ax.set_xlabel("env steps")
    ax.legend(fontsize=7)
    ax.set_title(
        f"final deterministic policy: return {trained['return']:.1f} vs zero {zero['return']:.1f}",
        fontsize=9,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spec", default=DEFAULT_SPEC)
    ap.add_argument("--xml-file", default=GO1_XML if os.path.exists(GO1_XML) else None)
    ap.add_argument("--set", action="append", help="spec parameter KEY=VALUE (JSON value)")
    ap.add_argument("--steps", type=int, default=3_000_000, help="env steps to train")
    ap.add_argument("--minutes", type=float, default=None, help="stop after this wall time")
    ap.add_argument("--num-envs", type=int, default=32)
    ap.add_argument("--threads", type=int, default=2, help="Rust threads stepping the envs")
    ap.add_argument("--torch-threads", type=int, default=1)
    ap.add_argument("--n-steps", type=int, default=256)
    ap.add_argument("--batch-size", type=int, default=2048)
    ap.add_argument("--n-epochs", type=int, default=5)
    ap.add_argument("--lr", type=float, default=3e-4)
    ap.add_argument("--gamma", type=float, default=0.97)
    ap.add_argument("--ent-coef", type=float, default=0.005)
    ap.add_argument("--net", default="256,128,128", help="hidden layer sizes (policy and value)")
    ap.add_argument("--track-keys", default="tracking", help="regex over info keys")
    ap.add_argument("--eval-per-env", type=int, default=2, help="evaluation episodes per env")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="docs/go1_joystick_learning", help="output path stem")
    ap.add_argument("--bench-vec", action="store_true")
    ap.add_argument("--bench-steps", type=int, default=200)
    args = ap.parse_args()
    if args.bench_vec:
        return bench_vec(args)

    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecNormalize

    torch.set_num_threads(args.torch_threads)
    probe = make_venv(args, 1)
    track_keys = track_keys_of(probe, args.track_keys)
    probe.close()
    if not track_keys:
        raise SystemExit(f"no info key matches --track-keys {args.track_keys!r}")
    print(f"spec {args.spec}; tracking keys {track_keys}", flush=True)

    act_dim = make_venv(args, 1).single_action_space.shape[0]
    zero = evaluate(make_venv(args, args.num_envs), args.eval_per_env,
                    lambda o: np.zeros((len(o), act_dim), np.float32), 10_000 + args.seed,
                    track_keys)
    print("zero policy:", json.dumps(zero), flush=True)

    env = EnvcSB3VecEnv(make_venv(args, args.num_envs), track_keys, seed=args.seed)
    venv = VecNormalize(env, norm_obs=True, norm_reward=True, gamma=args.gamma)
    net = [int(x) for x in args.net.split(",")]
    model = PPO(
        "MlpPolicy", venv, n_steps=args.n_steps, batch_size=args.batch_size,
        n_epochs=args.n_epochs, learning_rate=args.lr, gamma=args.gamma, gae_lambda=0.95,
        ent_coef=args.ent_coef, clip_range=0.2, max_grad_norm=1.0, seed=args.seed,
        policy_kwargs={"net_arch": {"pi": net, "vf": net}, "activation_fn": torch.nn.ELU},
        device="cpu", verbose=0,
    )
    rows: list[dict[str, float]] = []
    start = time.perf_counter()
    deadline = None if args.minutes is None else start + 60 * args.minutes

    class Log(BaseCallback):
        def _on_rollout_end(self) -> None:
            now = time.perf_counter() - start
            for ep in env.episodes:
                row = {"env_steps": self.num_timesteps, "wall_s": round(now, 1), "return": ep["r"],
                       "length": ep["l"], "terminated": int(ep["terminated"])}
                row["return"] = round(row["return"], 4)
                row.update({k: round(ep[k], 4) for k in track_keys})
                rows.append(row)
            recent = env.episodes[-64:]
            env.episodes.clear()
            if recent:
                s = summarize(recent, track_keys)
                tr = " ".join(f"{k} {s[k]:.2f}" for k in track_keys)
                print(f"{self.num_timesteps:>9} steps {now:7.0f} s "
                      f"{self.num_timesteps / max(now, 1e-9):6.0f} steps/s  return {s['return']:8.2f} "
                      f"len {s['length']:6.1f}  {tr}", flush=True)

        def _on_step(self) -> bool:
            return deadline is None or time.perf_counter() < deadline

    model.learn(total_timesteps=args.steps, callback=Log())
    train_s = time.perf_counter() - start
    steps_done = model.num_timesteps

    venv.training = False
    eval_env = make_venv(args, args.num_envs)
    trained = evaluate(
        eval_env, args.eval_per_env,
        lambda o: model.predict(venv.normalize_obs(o), deterministic=True)[0].astype(np.float32),
        10_000 + args.seed, track_keys,
    )
    print("trained policy:", json.dumps(trained), flush=True)
    stochastic = evaluate(
        make_venv(args, args.num_envs), args.eval_per_env,
        lambda o: model.predict(venv.normalize_obs(o), deterministic=False)[0].astype(np.float32),
        10_000 + args.seed, track_keys,
    )
    print("trained policy (stochastic):", json.dumps(stochastic), flush=True)
    model.save(args.out + "_model.zip")  # not committed: for re-evaluation
    venv.save(args.out + "_vecnormalize.pkl")

    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    with open(args.out + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]) if rows else ["env_steps"])
        w.writeheader()
        w.writerows(rows)
    summary = {
        "spec": args.spec, "track_keys": track_keys, "env_steps": steps_done,
        "train_seconds": round(train_s, 1), "steps_per_second": round(steps_done / train_s),
        "num_envs": args.num_envs, "threads": args.threads, "zero_policy": zero,
        "trained_policy": trained, "trained_policy_stochastic": stochastic,
        "hyper_parameters": {k: getattr(args, k) for k in (
            "n_steps", "batch_size", "n_epochs", "lr", "gamma", "ent_coef", "net", "seed")},
    }
    with open(args.out + ".json", "w") as f:
        json.dump(summary, f, indent=1)
    if rows:
        plot(rows, zero, trained, track_keys, args.out + ".png",
             f"{os.path.basename(args.spec)}: SB3 PPO, {args.num_envs} envc envs, "
             f"{steps_done / 1e6:.2f} M steps in {train_s / 60:.0f} min")
    print(json.dumps({k: summary[k] for k in ("env_steps", "train_seconds", "steps_per_second")}))
    return summary


if __name__ == "__main__":
    main()
