#!/usr/bin/env python3
"""Collection throughput on Ray against ``envc.collect`` alone, one interleaved run (docs/SCALING.md).

Starts its own single-node Ray (127.0.0.1, its own ports and --temp-dir, 4 logical CPUs on however
many cores the machine has; killed by pid at the end, never `ray stop`), then every round, in
rotated order: ``envc.collect`` in this process, and ``envc.ray.collect`` with 1, 2 and 4 workers,
each writing a fresh dataset of the same episodes. Reported per contender (medians over rounds):
wall steps/s (actor start-up and merge included), the merge (driver ``finish``) time, the summed
in-chunk worker time, and the per-episode overhead Ray adds: (wall x workers - in-chunk time) /
episodes, i.e. the worker-seconds not spent recording.

    .venv/bin/python benches/ray_scaling.py [--env Hopper-v5] [--episodes 400] [--rounds 3]
"""

from __future__ import annotations

import argparse
import os
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import envc
import envc.ray
import ray


def _temp_base() -> str:
    """Where the cluster's session files go: $ENVC_RAY_TMP, else /tmp (Ray's unix sockets need a
    short path)."""
    base = os.environ.get("ENVC_RAY_TMP")
    if base:
        return base
    return "/tmp"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def processes_under(tag: str) -> list[int]:
    pids = []
    for p in Path("/proc").iterdir():
        if not p.name.isdigit() or int(p.name) == os.getpid():
            continue
        try:
            cmd = (p / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            mine = tag in cmd or any(tag in os.readlink(f) for f in (p / "fd").iterdir())
        except OSError:
            continue
        if mine:
            pids.append(int(p.name))
    return pids


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--env", default="Hopper-v5")
    ap.add_argument("--episodes", type=int, default=400)
    ap.add_argument("--max-steps", type=int, default=1000)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--chunk-size", type=int)
    a = ap.parse_args()
    temp = tempfile.mkdtemp(prefix=f"ray-envc-bench-{os.getpid()}-", dir=_temp_base())
    out = Path(tempfile.mkdtemp(prefix="envc-scaling-"))
    port = free_port()
    home = os.path.join(temp, "home")  # not ~/.ray: another Ray's auth token is not ours
    os.makedirs(home)
    env = {k: v for k, v in os.environ.items() if not k.startswith("RAY_")}
    env.update(HOME=home, RAY_AUTH_MODE="disabled")
    os.environ["RAY_AUTH_MODE"] = "disabled"
    cmd = [str(Path(sys.executable).parent / "ray"), "start", "--head", "--node-ip-address=127.0.0.1",
           f"--port={port}", f"--temp-dir={temp}", "--include-dashboard=false", "--num-cpus=4",
           "--object-store-memory=200000000", "--disable-usage-stats",
           f"--node-manager-port={free_port()}", f"--object-manager-port={free_port()}",
           f"--ray-client-server-port={free_port()}"]
    results: dict[str, list[dict]] = {}
    try:
        subprocess.run(cmd, check=True, capture_output=True, timeout=180, env=env)
        ray.init(address=f"127.0.0.1:{port}", log_to_driver=False)
        contenders = ["envc.collect", "shards, no Ray", "ray x1", "ray x2", "ray x4"]
        n = 0
        for r in range(a.rounds):
            order = contenders[r % len(contenders):] + contenders[: r % len(contenders)]
            for c in order:
                n += 1
                root = out / f"{n}"
                t0 = time.perf_counter()
                if c == "envc.collect":
                    envc.collect(a.env, "bench/s-v0", a.episodes, seed=r, root=root, policy="random",
                                 max_episode_steps=a.max_steps)
                    wall = time.perf_counter() - t0
                    import minari

                    steps = minari.load_dataset(str(root / "bench" / "s-v0")).total_steps
                    row = dict(wall=wall, steps=steps, finish=0.0, worker=wall, workers=1)
                elif c == "shards, no Ray":
                    # The sharded path (driver + worker writes + merge) in this process: what
                    # sharding costs without Ray.
                    from envc import _envc
                    from envc._gym import overrides_to_toml

                    ov = overrides_to_toml({"max_episode_steps": a.max_steps})
                    d = _envc.ShardedCollection(a.env, "bench/s-v0", a.episodes, "random", r, "arrow",
                                                str(root), ov)
                    lengths = []
                    for lo in range(0, a.episodes, 64):
                        lengths += _envc.collect_shard(a.env, d.staging, lo, min(lo + 64, a.episodes), d.seed,
                                                       "random", "arrow", ov)
                    t1 = time.perf_counter()
                    d.finish(lengths)
                    wall = time.perf_counter() - t0
                    row = dict(wall=wall, steps=sum(e[0] for e in lengths), finish=time.perf_counter() - t1, worker=t1 - t0, workers=1)
                else:
                    w = int(c.split("x")[1])
                    st: dict = {}
                    envc.ray.collect(a.env, "bench/s-v0", a.episodes, "random", seed=r, num_workers=w,
                                     root=root, chunk_size=a.chunk_size, stats=st, max_episode_steps=a.max_steps)
                    wall = time.perf_counter() - t0
                    row = dict(wall=wall, steps=st["steps"], finish=st["finish_s"], worker=st["worker_s"], workers=w)
                shutil.rmtree(root, ignore_errors=True)
                results.setdefault(c, []).append(row)
                print(f"round {r} {c}: {row['steps'] / row['wall']:.0f} steps/s", file=sys.stderr)
        # Actor start-up alone: one episode on fresh actors.
        starts = []
        for _ in range(a.rounds):
            t0 = time.perf_counter()
            envc.ray.collect(a.env, "bench/one-v0", 1, "random", seed=0, num_workers=1, root=out / "one",
                             max_episode_steps=a.max_steps)
            starts.append(time.perf_counter() - t0)
            shutil.rmtree(out / "one", ignore_errors=True)
    finally:
        if ray.is_initialized():
            ray.shutdown()
        for _ in range(3):
            pids = processes_under(temp)
            for pid in pids:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            if not pids:
                break
            time.sleep(0.5)
        shutil.rmtree(temp, ignore_errors=True)
        shutil.rmtree(out, ignore_errors=True)
    med = lambda xs: statistics.median(xs)  # noqa: E731
    print(f"{a.env}, {a.episodes} episodes (max {a.max_steps} steps), random policy, {a.rounds} rounds, "
          f"{os.cpu_count()} cores; medians\n")
    print("| contender | steps | wall s | steps/s (wall) | merge s | in-chunk worker s | Ray overhead ms/episode |")
    print("|---|---|---|---|---|---|---|")
    for c, rows in results.items():
        wall = med([r["wall"] for r in rows])
        over = med([(r["wall"] * r["workers"] - r["worker"]) / a.episodes * 1e3 for r in rows])
        print(f"| {c} | {med([r['steps'] for r in rows]):.0f} | {wall:.2f} | {med([r['steps'] / r['wall'] for r in rows]):.0f} "
              f"| {med([r['finish'] for r in rows]):.3f} | {med([r['worker'] for r in rows]):.2f} | "
              f"{'—' if not c.startswith('ray') else f'{over:.2f}'} |")
    print(f"\nactor start-up + 1 episode + merge (1 worker): {med(starts):.2f} s")


if __name__ == "__main__":
    main()
