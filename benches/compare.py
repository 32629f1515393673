#!/usr/bin/env python3
"""envc vs Gymnasium v5 vs EnvPool, one interleaved run on this machine (run through compare.sh).

Every round, for every env, back to back: `envc bench ID --rounds 1` (ceiling, envc single,
envc vectorized: paired in one process), Gymnasium `gym.make(ID)` single env, EnvPool single
env (1 env, 1 thread) and EnvPool vectorized (8 envs, 2 threads, sync). Medians over rounds go to
docs/PERFORMANCE.md. Single-env rates are per thread CPU time (as `envc bench`), vectorized rates
per wall time; autoreset calls are not counted as steps (envc NextStep slots, EnvPool
elapsed_step == 0).
"""

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ENVS = ["Ant", "HalfCheetah", "Hopper", "Humanoid", "HumanoidStandup", "InvertedPendulum",
        "InvertedDoublePendulum", "Pusher", "Reacher", "Swimmer", "Walker2d"]
VEC_TARGETS = {"Ant", "HalfCheetah", "Hopper", "Humanoid"}


def timed(seconds, clock, chunk):
    """Run chunk() (returns steps done) until `seconds` of `clock` passed; steps per second."""
    start, steps = clock(), 0
    while True:
        steps += chunk()
        t = clock() - start
        if t >= seconds:
            return steps / t


def gym_single(gym, env_id, seconds):
    env = gym.make(env_id)
    env.reset(seed=0)
    space = env.action_space
    acts = np.random.default_rng(0).uniform(space.low, space.high, size=(4096, space.shape[0]))
    k = [0]

    def chunk():
        for _ in range(16):
            _, _, term, trunc, _ = env.step(acts[k[0] % 4096])
            k[0] += 1
            if term or trunc:
                env.reset()
        return 16

    timed(seconds / 4, time.thread_time, chunk)  # warm-up
    r = timed(seconds, time.thread_time, chunk)
    env.close()
    return r


def envpool_rate(envpool, task, num_envs, threads, seconds, clock):
    env = envpool.make_gymnasium(task, num_envs=num_envs, batch_size=num_envs, num_threads=threads, seed=0)
    env.reset()
    space = env.action_space
    acts = np.random.default_rng(0).uniform(space.low, space.high, size=(4096, num_envs, space.shape[0]))
    k = [0]

    def chunk():
        real = 0
        for _ in range(4):
            _, _, _, _, info = env.step(acts[k[0] % 4096])
            k[0] += 1
            real += int(np.count_nonzero(info["elapsed_step"] != 0))
        return real

    timed(seconds / 4, clock, chunk)
    r = timed(seconds, clock, chunk)
    env.close()
    return r


def envc_bench(envc, env_id, seconds, envs, threads):
    out = subprocess.run([envc, "bench", env_id, "--rounds", "1", "--seconds", str(seconds),
                          "--envs", str(envs), "--threads", str(threads), "--format", "json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)[0]


def machine():
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} logical CPUs, {platform.system()} {platform.release()}, Python {platform.python_version()}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--envc", default=os.path.join(ROOT, "target", "release", "envc"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=1.0, help="per measurement per round")
    ap.add_argument("--envs", nargs="*", default=ENVS)
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "PERFORMANCE.md"))
    args = ap.parse_args()

    import gymnasium as gym
    import mujoco
    try:
        import envpool
        envpool_version, envpool_error = envpool.__version__, None
    except Exception as e:  # recorded in the report, the rest still runs
        envpool, envpool_version, envpool_error = None, None, f"{type(e).__name__}: {e}"

    rows = {name: {k: [] for k in ("ceiling", "single", "vector", "single_ratio", "vector_ratio",
                                   "gym", "gym_ratio", "ep1", "ep8", "ep8_vs_envc", "par", "par_ratio")} for name in args.envs}
    tasks = {}
    for r in range(args.rounds):
        order = args.envs[r % len(args.envs):] + args.envs[:r % len(args.envs)]
        for name in order:
            env_id = f"{name}-v5"
            row = rows[name]
            # envc's four measurements take 4 x seconds (+ a warm-up quarter).
            e = envc_bench(args.envc, env_id, 4 * args.seconds, 8, 2)
            row["ceiling"].append(e["ceiling_steps_per_s"])
            row["single"].append(e["single_steps_per_s"])
            row["vector"].append(e["vector_steps_per_s"])
            row["single_ratio"].append(e["single_over_ceiling"])
            row["vector_ratio"].append(e["vector_over_threads_x_ceiling"])
            row["par"].append(e["parallel_ceiling_steps_per_s"])
            row["par_ratio"].append(e["vector_over_parallel_ceiling"])
            g = gym_single(gym, env_id, args.seconds)
            row["gym"].append(g)
            row["gym_ratio"].append(g / e["ceiling_steps_per_s"])
            if envpool is not None:
                if name not in tasks:
                    tasks[name] = env_id if env_id in envpool.list_all_envs() else f"{name}-v4"
                row["ep1"].append(envpool_rate(envpool, tasks[name], 1, 1, args.seconds, time.perf_counter))
                ep8 = envpool_rate(envpool, tasks[name], 8, 2, args.seconds, time.perf_counter)
                row["ep8"].append(ep8)
                row["ep8_vs_envc"].append(e["vector_steps_per_s"] / ep8)
            print(f"round {r + 1}/{args.rounds} {env_id}: ceiling {e['ceiling_steps_per_s']:.0f}, "
                  f"envc {e['single_steps_per_s']:.0f} / vec {e['vector_steps_per_s']:.0f}, gym {g:.0f}"
                  + (f", envpool {row['ep1'][-1]:.0f} / vec {row['ep8'][-1]:.0f}" if envpool else ""),
                  flush=True)

    med = lambda v: statistics.median(v) if v else float("nan")  # noqa: E731
    f0 = lambda x: "–" if x != x else f"{x:,.0f}"  # noqa: E731
    f2 = lambda x: "–" if x != x else f"{x:.2f}"  # noqa: E731
    lines = [
        "# Performance",
        "",
        "Generated by `benches/compare.sh` (do not edit by hand; re-run it). One interleaved run on one machine:",
        "every round measures, per env and back to back, the physics ceiling, envc (single and vectorized),",
        "Gymnasium v5 and EnvPool; the tables show medians over rounds (ratios: medians of the per-round ratios).",
        "",
        f"- Machine: {machine()}; absolute rates drift between runs (±15 % or more), so compare ratios from one interleaved run.",
        f"- Software: envc (this tree, release build), MuJoCo {mujoco.__version__} (same library for the ceiling and envc),",
        f"  Gymnasium {gym.__version__}, EnvPool {envpool_version or 'not installed'}"
        + (f" ({envpool_error})" if envpool_error else "")
        + f"; {args.rounds} rounds, {args.seconds:g} s per measurement per round.",
        "- Ceiling: `frame_skip × mj_step` (+ `mj_rnePostConstraint` where the spec reads contact forces) on a raw",
        "  `MjData` of the same model, same random actions, one thread, thread CPU time.",
        "- Single env: envc `Env` / Gymnasium `gym.make(id)` (default wrappers, Python bindings' default timer on) /",
        "  EnvPool `make_gymnasium(task, num_envs=1, num_threads=1)`; random uniform actions, autoreset; thread CPU time for",
        "  envc and Gymnasium, wall time for EnvPool (its stepping runs on its own worker thread).",
        "- Vectorized: 8 envs, 2 threads, wall time. envc `VecEnv` (caller + 1 worker, NextStep autoreset);",
        "  EnvPool sync (`batch_size = num_envs = 8`, `num_threads = 2`). Autoreset calls are not counted.",
        "  Vectorized ratio: envc ÷ (2 × single-thread ceiling). \"2 raw loops at once\": two raw ceiling loops on two",
        "  threads, wall time, in the same round: the 2-core ceiling that the machine's load actually allowed.",
        "  Gymnasium has no threaded vector env",
        "  (`AsyncVectorEnv` uses processes; the performance anchors measured it slower than one env here), so it is",
        "  not in the vectorized table.",
        "- EnvPool runs its own statically linked MuJoCo build and its own copies of the models"
        + (", v5 tasks where it has them: " + ", ".join(sorted(set(tasks.values()))) if tasks else "") + ".",
        "",
        "## Single env (steps/s)",
        "",
        "| env | ceiling | envc | envc ÷ ceiling | Gymnasium v5 | Gym ÷ ceiling | EnvPool (1 env, 1 thread) |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name in args.envs:
        r = rows[name]
        lines.append(f"| {name} | {f0(med(r['ceiling']))} | {f0(med(r['single']))} | {f2(med(r['single_ratio']))} | "
                     f"{f0(med(r['gym']))} | {f2(med(r['gym_ratio']))} | {f0(med(r['ep1']))} |")
    lines += [
        "",
        "## Vectorized, 8 envs on 2 threads (steps/s)",
        "",
        "| env | 2 × ceiling | envc | envc ÷ (2 × ceiling) | envc ÷ ceiling | 2 raw loops at once | envc ÷ that | EnvPool | envc ÷ EnvPool |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in args.envs:
        r = rows[name]
        lines.append(f"| {name}{' (target)' if name in VEC_TARGETS else ''} | {f0(2 * med(r['ceiling']))} | "
                     f"{f0(med(r['vector']))} | {f2(med(r['vector_ratio']))} | {f2(2 * med(r['vector_ratio']))} | "
                     f"{f0(med(r['par']))} | {f2(med(r['par_ratio']))} | "
                     f"{f0(med(r['ep8']))} | {f2(med(r['ep8_vs_envc']))} |")
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    body = "\n".join(lines) + "\n"
    marker = "<!-- measured tables end; notes below are kept by compare.py -->"
    notes = ""
    if os.path.exists(args.out):
        old = open(args.out).read()
        if marker in old:
            notes = old[old.index(marker):]
    with open(args.out, "w") as f:
        f.write(body + "\n" + (notes or marker + "\n"))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    sys.exit(main())
