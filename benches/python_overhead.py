#!/usr/bin/env python3
"""What stepping envc from Python costs, side by side with Gymnasium and EnvPool (one interleaved run).

Every round, for every env (rotated order) and every contender (rotated order), back to back:

single env, µs per step (thread CPU time and wall time, reset calls not counted):
  - ``envc bench X``: envc's Rust rates (physics ceiling and single env; thread CPU time), the
    Rust ``VecEnv`` with 8 envs on 2 threads (wall time), run as a subprocess;
  - the physics ceiling in Python: ``mujoco.mj_step(model, data, nstep=frame_skip)`` (+
    ``mj_rnePostConstraint`` where the spec reads contact forces, as ``envc bench``) on the
    reference's own model, restarting from its reset state every mean episode length; once as
    the bindings run by default (``import mujoco`` installs MuJoCo's timer callback ``mjcb_time``,
    read by every ``mj_step``'s profiling timers) and once with that callback cleared;
  - ``gymnasium.make("envc/X")`` (the standard wrappers) and its ``.unwrapped`` (another instance),
    and the native core under ``.unwrapped`` (``_core.step_f32``: the binding without the Python
    class), so that what envc adds splits into the binding, the class and Gymnasium's wrappers;
  - Gymnasium's ``gymnasium.make("X")`` and its ``.unwrapped``;
  - EnvPool ``make_gymnasium(X, num_envs=1, num_threads=1)`` (wall time only: it steps on its own
    worker thread; autoreset calls not counted);
  - a no-op ``step`` in the same loop: the harness's own cost.

vector, steps/s (wall time, autoreset calls not counted), 8 and 16 envs on 2 threads:
  - ``envc.make_vec(X, n, num_threads=2)`` (Gymnasium's default ``copy=True``) paired with the
    Rust ``VecEnv`` under it: the same envs stepped by ``_core.rust_steps`` (Rust stepping the
    batch over and over, no Python between steps, results left in the Rust buffers), in
    alternating blocks of ``--pair-ms`` of ``make_vec`` calls and as many Rust steps; the ratio
    ``make_vec`` ÷ Rust ``VecEnv`` is the median of those pairs. ``make_vec(..., copy=False)``
    (the env's own arrays every call) the same way;
  - Gymnasium's ``SyncVectorEnv`` and ``AsyncVectorEnv`` (``gymnasium.make_vec``), EnvPool
    (``num_threads=2``) if it is installed (else its columns come from ``ENVPOOL_RECORDED``, an
    earlier run of this script, said so in the table);
  - every figure against twice the single-thread physics ceiling (``envc bench``'s, thread CPU
    time, the same round) and against "2 raw loops at once" (``envc bench``'s parallel ceiling:
    two raw ``mj_step`` loops on two threads, wall time, what two cores gave at that moment).

``--sweep Hopper``: batch sizes 8 … 4096 on 2 threads, each in a fresh interpreter (optionally
under an address-space cap, ``--sweep-as-limit GIB``, as ``ulimit -v``): steps/s of ``make_vec``
and of the Rust ``VecEnv`` under it (paired as above), resident memory per env (RSS growth over
making and stepping the batch ÷ n) beside E1403's estimate. ``--threads-sweep Hopper``: 1 … CPUs
threads with 16 envs per thread, each against t × the single-thread physics ceiling. Both run
inside the same rounds (rotated order). ``--no-single`` skips the single-env measurements.

Tables of medians over rounds go to stdout (Markdown) and, with ``--markdown``, to a file; the
per-round samples to ``--json``. Actions: uniform random float32 in the action space (what
``action_space.sample()`` and Stable-Baselines3 give), the same stream for every contender.

    bash scripts/setup.sh && cargo build --release -p envc-cli
    .venv/bin/python benches/python_overhead.py --rounds 5 --seconds 0.5 --no-single \\
        --sweep Hopper --sweep-as-limit 64 --threads-sweep Hopper InvertedPendulum

Needs a venv with gymnasium and mujoco at the reference pins (tests/reference/requirements.txt;
scripts/setup.sh makes one), the ``envc`` package in it and, optionally, ``envpool``. Rebuild
envc only between runs: a library rewritten under a running process kills it (SIGBUS).
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import datetime
import gc
import json
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ENVS = ["Ant", "Humanoid", "Walker2d", "Hopper", "InvertedPendulum"]
HEAVY = {"Ant", "Humanoid", "Walker2d"}
SINGLE = [
    "ceiling_py", "ceiling_nt", "envc_gym", "envc_raw", "envc_core", "gym_gym", "gym_raw", "envpool",
]
VEC_SIZES = (8, 16)
SWEEP_SIZES = (8, 16, 64, 256, 1024, 4096)
VECTOR = ["envc_vec", "envc_views", "sync", "async", "envpool_vec"]
BLOCK = 64  # steps timed as one block (a block also ends at the end of an episode)
NACT = 4096

wall_ns, cpu_ns = time.perf_counter_ns, time.thread_time_ns


def timer_cost() -> tuple[float, float]:
    """ns that one timed block adds to a measurement (four clock reads), wall and CPU."""
    w, c = [], []
    for _ in range(20000):
        w0, c0 = wall_ns(), cpu_ns()
        w1, c1 = wall_ns(), cpu_ns()
        w.append(w1 - w0)
        c.append(c1 - c0)
    return statistics.median(w), statistics.median(c)


class Tally:
    """Steps and time of one measurement, reset calls excluded, timer cost subtracted."""

    def __init__(self, cost):
        self.steps, self.wall, self.cpu, self.blocks, self.cost = 0, 0, 0, 0, cost

    def add(self, steps, w, c):
        self.steps, self.wall, self.cpu, self.blocks = (
            self.steps + steps, self.wall + w, self.cpu + c, self.blocks + 1)

    def us(self):
        w = (self.wall - self.blocks * self.cost[0]) / self.steps / 1e3
        c = (self.cpu - self.blocks * self.cost[1]) / self.steps / 1e3
        return w, c


def gym_block(env, acts, k):
    """Up to BLOCK steps of a Gymnasium-API env, stopping at the end of an episode."""
    for i in range(BLOCK):
        _, _, term, trunc, _ = env.step(acts[(k + i) % NACT])
        if term or trunc:
            return i + 1, True
    return BLOCK, False


def measure_env(env, acts, seconds, cost):
    """µs/step (wall, CPU) of ``env.step``; resets are outside the timed blocks."""
    def run(budget):
        t, k, done = Tally(cost), 0, True
        while t.wall < budget:
            if done:
                env.reset()
            w0, c0 = wall_ns(), cpu_ns()
            n, done = gym_block(env, acts, k)
            c1, w1 = cpu_ns(), wall_ns()
            t.add(n, w1 - w0, c1 - c0)
            k += n
        return t
    run(seconds * 0.25e9)
    return run(seconds * 1e9).us()


def measure_ceiling(mujoco, model, start, fs, rne, ep_len, acts, seconds, cost):
    """µs/step of the raw loop through the ``mujoco`` bindings (restarts outside the blocks)."""
    data = mujoco.MjData(model)
    qpos, qvel = start

    def restart():
        mujoco.mj_resetData(model, data)
        data.qpos[:] = qpos
        data.qvel[:] = qvel
        mujoco.mj_forward(model, data)

    def block(k, n):
        ctrl, step, post = data.ctrl, mujoco.mj_step, mujoco.mj_rnePostConstraint
        for i in range(n):
            ctrl[:] = acts[(k + i) % NACT]
            step(model, data, nstep=fs)
            if rne:
                post(model, data)

    def run(budget):
        t, k = Tally(cost), 0
        while t.wall < budget:
            restart()
            left = ep_len
            while left > 0:
                n = min(BLOCK, left)
                w0, c0 = wall_ns(), cpu_ns()
                block(k, n)
                c1, w1 = cpu_ns(), wall_ns()
                t.add(n, w1 - w0, c1 - c0)
                k, left = k + n, left - n
        return t
    run(seconds * 0.25e9)
    return run(seconds * 1e9).us()


@contextlib.contextmanager
def mujoco_timer(on: bool):
    """MuJoCo's ``mjcb_time`` as the bindings set it (``on``) or cleared, for a ``with`` block."""
    import mujoco

    cell = ctypes.c_void_p.in_dll(ctypes.CDLL(f"libmujoco.so.{mujoco.__version__}"), "mjcb_time")
    saved = cell.value
    if not on:
        cell.value = None
    try:
        yield
    finally:
        cell.value = saved


class NoOp:
    """A step that does nothing: what the timing loop itself costs per step."""

    _out = (None, 0.0, False, False, {})

    def reset(self):
        return None, {}

    def step(self, action):
        return self._out


class CoreEnv:
    """An envc env's native core as the timing loop calls it: ``step`` is ``_core.step_f32``."""

    def __init__(self, env):
        self.env, self.step = env, env._core.step_f32

    def reset(self, seed=None):
        return self.env.reset(seed=seed)


def measure_envpool(env, seconds):
    """µs/step (wall) of an EnvPool env of one env; autoreset calls are not counted."""
    n_act = env.action_space.shape[0]
    acts = np.random.default_rng(1).uniform(env.action_space.low, env.action_space.high,
                                            size=(NACT, 1, n_act)).astype(np.float32)

    def run(budget):
        steps, k, start = 0, 0, wall_ns()
        while wall_ns() - start < budget:
            for _ in range(16):
                info = env.step(acts[k % NACT])[4]
                k += 1
                steps += int(info["elapsed_step"][0] != 0)
        return (wall_ns() - start) / max(steps, 1) / 1e3
    env.reset()
    run(seconds * 0.25e9)
    return run(seconds * 1e9)


def measure_vec(env, n, seconds, envpool=False):
    """Steps/s (wall) of a vector env; autoreset calls (envs done at the previous call) not counted."""
    space = getattr(env, "single_action_space", None) or env.action_space  # EnvPool: one env's
    acts = np.random.default_rng(2).uniform(space.low, space.high,
                                            size=(256, n) + space.shape).astype(np.float32)
    env.reset() if envpool else env.reset(seed=0)
    prev_done = np.zeros(n, dtype=bool)

    def run(budget):
        nonlocal prev_done
        steps, k, start = 0, 0, wall_ns()
        while wall_ns() - start < budget:
            for _ in range(8):
                _, _, term, trunc, info = env.step(acts[k % 256])
                k += 1
                if envpool:
                    steps += int(np.count_nonzero(info["elapsed_step"] != 0))
                else:
                    steps += n - int(np.count_nonzero(prev_done))
                    prev_done = np.logical_or(term, trunc)
        return steps / ((wall_ns() - start) / 1e9)
    run(seconds * 0.25e9)
    return run(seconds * 1e9)


def measure_envc_pair(env, n, seconds, block_ms=20.0):
    """``make_vec``'s ``step`` against the Rust ``VecEnv`` under it, on the same envs: blocks of
    ``make_vec`` calls (``block_ms`` of wall time) alternate with as many Rust steps
    (``_core.rust_steps``), which of the two goes first alternating too. Steps/s of each (wall;
    the env's own count, ``_core.env_steps``, leaves out autoreset steps) and the median over
    pairs of their ratio."""
    space = env.single_action_space
    acts = np.random.default_rng(2).uniform(space.low, space.high,
                                            size=(256, n) + space.shape).astype(np.float32)
    rows = list(acts)  # the batches as arrays, made before the clock starts
    core = env.unwrapped._core
    env.reset(seed=0)
    state = {"k": 0}  # the next action row

    def py_block(budget):
        k, before, start = state["k"], core.env_steps, wall_ns()
        while True:
            env.step(rows[k % 256])
            k += 1
            t = wall_ns() - start
            if t >= budget:
                calls, state["k"] = k - state["k"], k
                return core.env_steps - before, calls, t

    def rust_block(calls):
        before, start = core.env_steps, wall_ns()
        core.rust_steps(acts, state["k"] % 256, calls)
        t = wall_ns() - start
        state["k"] += calls
        return core.env_steps - before, t

    def run(budget, pairs):
        py, rust, calls = [0, 0], [0, 0], 0
        start = wall_ns()
        while wall_ns() - start < budget:
            if calls == 0 or len(pairs) % 2 == 0:
                s_p, calls, t_p = py_block(block_ms * 1e6)
                s_r, t_r = rust_block(calls)
            else:  # as many steps as the last block of make_vec calls, Rust first
                s_r, t_r = rust_block(calls)
                s_p, calls, t_p = py_block(block_ms * 1e6)
            py = [py[0] + s_p, py[1] + t_p]
            rust = [rust[0] + s_r, rust[1] + t_r]
            pairs.append((s_p / t_p) / (s_r / t_r))
        return py, rust

    run(seconds * 0.25e9, [])
    pairs = []
    py, rust = run(seconds * 1e9, pairs)
    return {"py": py[0] / py[1] * 1e9, "rust": rust[0] / rust[1] * 1e9, "ratio": med(pairs),
            "pairs": pairs}


def envc_bench(binary, env_id, seconds, envs=8, threads=2):
    out = subprocess.run([binary, "bench", env_id, "--rounds", "1", "--seconds", str(4 * seconds),
                          "--envs", str(envs), "--threads", str(threads), "--format", "json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)[0]


SWEEP_CHILD = """
import json, sys
import numpy as np
sys.path.insert(0, sys.argv[5])
import envc
from python_overhead import measure_envc_pair
env_id, n, threads, seconds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
def rss():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmRSS:"))
warm = envc.make_vec(env_id, 1, num_threads=1)  # the model, code pages, first allocations
warm.reset(seed=0)
warm.step(np.zeros((1,) + warm.single_action_space.shape, dtype=np.float32))
warm.close()
before = rss()
env = envc.make_vec(env_id, n, num_threads=threads)
got = measure_envc_pair(env, n, seconds, float(sys.argv[6]))
got.update(rss_per_env=(rss() - before) / n, estimate_per_env=env._core.bytes_per_env[0],
           mapped_estimate_per_env=env._core.bytes_per_env[1])
print(json.dumps(got))
"""


def sweep_child(env_id, n, threads, seconds, block_ms, as_limit_gib=None):
    """``make_vec(env_id, n, num_threads=threads)`` in a fresh interpreter (its address space
    capped at ``as_limit_gib`` GiB, as ``ulimit -v``): steps/s of it and of the Rust ``VecEnv``
    under it (``measure_envc_pair``) and resident memory per env (RSS growth over making and
    stepping it, divided by n)."""
    def cap():
        if as_limit_gib:
            import resource
            b = int(as_limit_gib * (1 << 30))
            resource.setrlimit(resource.RLIMIT_AS, (b, b))
    out = subprocess.run([sys.executable, "-c", SWEEP_CHILD, env_id, str(n), str(threads),
                          str(max(seconds, 0.2)), os.path.dirname(os.path.abspath(__file__)),
                          str(block_ms)],
                         check=True, capture_output=True, text=True, env=dict(os.environ),
                         preexec_fn=cap).stdout
    return json.loads(out.strip().splitlines()[-1])


def machine():
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(ln.split(":", 1)[1].strip() for ln in f if ln.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return (f"{cpu}, {os.cpu_count()} logical CPUs, {platform.system()} {platform.release()}, "
            f"Python {platform.python_version()}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--envc", default=os.path.join(ROOT, "target", "release", "envc"),
                    help="the envc CLI binary (release build) for the Rust rates")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=0.5, help="per measurement per round")
    ap.add_argument("--envs", nargs="*", default=ENVS)
    ap.add_argument("--no-vector", action="store_true", help="skip the vector measurements")
    ap.add_argument("--no-single", action="store_true", help="skip the single-env measurements")
    ap.add_argument("--sweep", nargs="*", default=[], metavar="ENV",
                    help="batch-size sweep (8 … 4096 envs, 2 threads) of these envs, e.g. Hopper")
    ap.add_argument("--sweep-sizes", nargs="*", type=int, default=list(SWEEP_SIZES))
    ap.add_argument("--threads-sweep", nargs="*", default=[], metavar="ENV",
                    help="threads sweep (1 … CPUs) of these envs")
    ap.add_argument("--sweep-as-limit", type=float, metavar="GIB",
                    help="cap each sweep interpreter's address space (as ulimit -v), in GiB")
    ap.add_argument("--pair-ms", type=float, default=20.0,
                    help="ms of make_vec calls per block paired with the Rust VecEnv")
    ap.add_argument("--markdown", help="also write the tables to this file")
    ap.add_argument("--json", help="write the per-round samples to this file")
    args = ap.parse_args()

    import gymnasium as gym
    import mujoco

    import envc
    try:
        import envpool
        ep_note = f"EnvPool {envpool.__version__}"
    except Exception as e:  # noqa: BLE001 - reported in the tables' notes
        envpool, ep_note = None, f"EnvPool not measured ({type(e).__name__}: {e})"
    has_vec = hasattr(envc, "make_vec") and not args.no_vector
    if not hasattr(envc, "make_vec"):
        print("envc.make_vec is absent in this envc: the envc vector column is skipped", flush=True)

    cost = timer_cost()
    print(f"envc {envc.__file__}; timer cost per block {cost[0]:.0f} ns wall, {cost[1]:.0f} ns CPU",
          flush=True)
    started = datetime.datetime.now(datetime.timezone.utc)
    head = machine()

    s = {name: {} for name in args.envs}  # per env: key -> list of samples over rounds
    sweep = {}  # (kind, env, n or threads) -> key -> samples
    objs = {}
    for name in args.envs:
        env_id = f"{name}-v5"
        e_w, e_r = gym.make(f"envc/{env_id}"), gym.make(f"envc/{env_id}").unwrapped
        e_c = CoreEnv(gym.make(f"envc/{env_id}").unwrapped)
        g_w, g_r = gym.make(env_id), gym.make(env_id).unwrapped
        for env in (e_w, e_r, e_c, g_w, g_r):
            env.reset(seed=0)
        space = g_r.action_space
        acts = list(np.random.default_rng(0).uniform(space.low, space.high, size=(NACT,) + space.shape)
                    .astype(np.float32))
        g_r.reset(seed=0)
        start = (g_r.data.qpos.copy(), g_r.data.qvel.copy())
        ep = envpool.make_gymnasium(env_id, num_envs=1, batch_size=1, num_threads=1, seed=0) \
            if envpool is not None else None
        objs[name] = dict(envc_gym=e_w, envc_raw=e_r, envc_core=e_c, gym_gym=g_w, gym_raw=g_r, acts=acts,
                          start=start, envpool=ep, fs=g_r.frame_skip)
    noop = NoOp()
    harness = []

    for r in range(args.rounds):
        names = args.envs[r % len(args.envs):] + args.envs[:r % len(args.envs)]
        harness.append(measure_env(noop, objs[names[0]]["acts"], args.seconds, cost))
        for name in names:
            env_id, o, row = f"{name}-v5", objs[name], s[name]
            b = envc_bench(args.envc, env_id, args.seconds)
            row.setdefault("rust_ceiling", []).append(1e6 / b["ceiling_steps_per_s"])
            row.setdefault("rust_single", []).append(1e6 / b["single_steps_per_s"])
            row.setdefault("rust_vec8", []).append(b["vector_steps_per_s"])
            row.setdefault("ceiling_sps", []).append(b["ceiling_steps_per_s"])
            row.setdefault("parallel_sps", []).append(b["parallel_ceiling_steps_per_s"])
            o.setdefault("rne", b["rne_post_constraint"])
            o.setdefault("ep_len", max(1, round(b["mean_episode_len"])))
            order = SINGLE[r % len(SINGLE):] + SINGLE[:r % len(SINGLE)]
            for c in ([] if args.no_single else order):
                gc.collect()
                if c in ("ceiling_py", "ceiling_nt"):
                    with mujoco_timer(c == "ceiling_py"):
                        v = measure_ceiling(mujoco, o["gym_raw"].model, o["start"], o["fs"],
                                            o["rne"], o["ep_len"], o["acts"], args.seconds, cost)
                elif c == "envpool":
                    if o["envpool"] is None:
                        continue
                    v = (measure_envpool(o["envpool"], args.seconds), float("nan"))
                else:
                    v = measure_env(o[c], o["acts"], args.seconds, cost)
                row.setdefault(c + "_wall", []).append(v[0])
                row.setdefault(c + "_cpu", []).append(v[1])
            if not args.no_vector:
                vorder = [(c, n) for n in VEC_SIZES for c in VECTOR]
                vorder = vorder[r % len(vorder):] + vorder[:r % len(vorder)]
                for c, n in vorder:
                    if c in ("envc_vec", "envc_views") and not has_vec:
                        continue
                    if c == "envpool_vec" and envpool is None:
                        continue
                    gc.collect()
                    if c in ("envc_vec", "envc_views"):
                        env = envc.make_vec(env_id, n, num_threads=2, copy=c == "envc_vec")
                    elif c == "envpool_vec":
                        env = envpool.make_gymnasium(env_id, num_envs=n, batch_size=n,
                                                     num_threads=2, seed=0)
                    else:
                        env = gym.make_vec(env_id, num_envs=n, vectorization_mode=c)
                    try:
                        if c in ("envc_vec", "envc_views"):
                            got = measure_envc_pair(env, n, args.seconds, args.pair_ms)
                            row.setdefault(f"{c}{n}", []).append(got["py"])
                            row.setdefault(f"{c}_rust{n}", []).append(got["rust"])
                            row.setdefault(f"{c}_ratio{n}", []).append(got["ratio"])
                            row.setdefault(f"{c}_pairs{n}", []).extend(got["pairs"])
                        else:
                            row.setdefault(f"{c}{n}", []).append(
                                measure_vec(env, n, args.seconds, envpool=c == "envpool_vec"))
                    finally:
                        env.close()
            print(f"round {r + 1}/{args.rounds} {env_id}: "
                  + ", ".join(f"{k} {v[-1]:.2f}" for k, v in row.items()), flush=True)
        sweep_round(args, r, sweep)

    md = tables(args, s, harness, head, started, ep_note, has_vec, gym, mujoco)
    md += sweep_tables(args, sweep)
    print(md)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(md)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"started": started.isoformat(), "machine": head, "harness": harness,
                       "samples": s, "sweep": {" ".join(map(str, k)): v for k, v in sweep.items()}},
                      f, indent=1)


def cpus():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def sweep_round(args, r, sweep):
    """One round of the batch-size and threads sweeps, each point a fresh interpreter for
    ``make_vec`` then ``envc bench`` (Rust ``VecEnv``, same size and threads) right after."""
    points = [("size", name, n, 2) for name in args.sweep for n in args.sweep_sizes]
    points += [("threads", name, 16 * t, t) for name in args.threads_sweep
               for t in range(1, cpus() + 1)]
    points = points[r % max(len(points), 1):] + points[:r % max(len(points), 1)]
    for kind, name, n, t in points:
        env_id = f"{name}-v5"
        got = sweep_child(env_id, n, t, args.seconds, args.pair_ms, args.sweep_as_limit)
        b = envc_bench(args.envc, env_id, args.seconds, envs=min(n, 64), threads=t)
        row = sweep.setdefault((kind, name, n if kind == "size" else t), {})
        row.setdefault("pairs", []).extend(got["pairs"])
        for k, v in (("py", got["py"]), ("rust", got["rust"]), ("ratio", got["ratio"]),
                     ("rss", got["rss_per_env"]), ("estimate", got["estimate_per_env"]),
                     ("mapped", got["mapped_estimate_per_env"]),
                     ("ceiling", b["ceiling_steps_per_s"]),
                     ("parallel", b["parallel_ceiling_steps_per_s"])):
            row.setdefault(k, []).append(v)
        print(f"round {r + 1} {kind} {env_id} n={n} threads={t}: make_vec {got['py']:,.0f}/s, "
              f"Rust VecEnv {got['rust']:,.0f}/s (pairs {got['ratio']:.3f}), "
              f"{got['rss_per_env'] / 1024:.0f} KiB/env", flush=True)


def sweep_tables(args, sweep):
    f0 = lambda x: "–" if x != x else f"{x:,.0f}"  # noqa: E731
    f2 = lambda x: "–" if x != x else f"{x:.2f}"  # noqa: E731
    out = []
    cap = (f", each interpreter's address space capped at {args.sweep_as_limit:g} GiB (as `ulimit -v`)"
           if args.sweep_as_limit else "")
    if args.sweep:
        out += [
            "",
            "Batch sizes, 2 threads: steps/s (wall, autoreset calls not counted) of `make_vec` and "
            "of the Rust `VecEnv` under it (paired blocks, as above), each batch in a fresh "
            f"interpreter{cap}; resident memory per env (the interpreter's RSS growth over making "
            "and stepping the batch, ÷ n) beside E1403's estimates per env (resident, mapped):",
            "",
            "| env | n | `make_vec` | Rust `VecEnv` | `make_vec` ÷ Rust | pairs p25–p75 | "
            "`make_vec` ÷ 2 × ceiling | resident KiB/env | E1403 estimate KiB/env | "
            "mapped estimate MiB/env |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for name in args.sweep:
            for n in args.sweep_sizes:
                r = sweep.get(("size", name, n), {})
                out.append(
                    f"| {name} | {n} | {f0(med(r.get('py', [])))} | {f0(med(r.get('rust', [])))} | "
                    f"{f2(med(r.get('pairs', [])))} | {quartiles(r.get('pairs', []))} | "
                    f"{f2(paired(r, lambda a, c: a / (2 * c), 'py', 'ceiling'))} | "
                    f"{f0(med(r.get('rss', [])) / 1024)} | {f0(med(r.get('estimate', [])) / 1024)} | "
                    f"{f2(med(r.get('mapped', [])) / (1 << 20))} |")
    if args.threads_sweep:
        out += [
            "",
            "Threads, 16 envs per thread: steps/s (wall), `make_vec` and the Rust `VecEnv` under it "
            "(paired blocks), against t × the single-thread physics ceiling (`envc bench`'s, thread "
            "CPU time, the same round) and against t raw physics loops on t threads at once (wall, "
            "the same round):",
            "",
            "| env | threads | envs | `make_vec` | Rust `VecEnv` | `make_vec` ÷ Rust | pairs p25–p75 | "
            "`make_vec` ÷ (t × ceiling) | Rust ÷ (t × ceiling) | t raw loops ÷ (t × ceiling) |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for name in args.threads_sweep:
            for t in range(1, cpus() + 1):
                r = sweep.get(("threads", name, t), {})
                tc = lambda a, c, t=t: a / (t * c)  # noqa: E731
                out.append(
                    f"| {name} | {t} | {16 * t} | {f0(med(r.get('py', [])))} | "
                    f"{f0(med(r.get('rust', [])))} | {f2(med(r.get('pairs', [])))} | "
                    f"{quartiles(r.get('pairs', []))} | {f2(paired(r, tc, 'py', 'ceiling'))} | {f2(paired(r, tc, 'rust', 'ceiling'))} | "
                    f"{f2(paired(r, tc, 'parallel', 'ceiling'))} |")
    return "\n".join(out) + ("\n" if out else "")


def quartiles(v):
    """The 25th and 75th percentiles of ``v``, as a table cell."""
    v = [x for x in v if x == x]
    if len(v) < 4:
        return "–"
    q = statistics.quantiles(v, n=4)
    return f"{q[0]:.2f}–{q[2]:.2f}"


def med(v):
    v = [x for x in v if x == x]
    return statistics.median(v) if v else float("nan")


def paired(row, f, *keys):
    """Median over rounds of f(sample of each key in that round)."""
    if not all(k in row for k in keys):
        return float("nan")
    return med([f(*xs) for xs in zip(*(row[k] for k in keys))])


# EnvPool 1.2.5's vector rates (steps/s, wall, 2 threads) and that run's single-thread Rust
# physics ceiling (µs per step, thread CPU time), from this script's run of 2026-11-25 08:18 UTC
# (docs/PERFORMANCE.md): the EnvPool columns where EnvPool is not installed.
ENVPOOL_RECORDED = {
    "when": "2026-11-25 08:18 UTC",
    "Ant": (118.98, {8: 6702, 16: 7447}),
    "Humanoid": (124.13, {8: 6223, 16: 7356}),
    "Walker2d": (57.67, {8: 16088, 16: 14717}),
    "Hopper": (40.41, {8: 19606, 16: 20699}),
    "InvertedPendulum": (7.47, {8: 71016, 16: 85608}),
}


def vector_tables(args, s, has_vec):
    """The vector tables: ``make_vec`` against the Rust ``VecEnv`` under it, and every vector
    env side by side against the physics ceiling."""
    f2 = lambda x: "–" if x != x else f"{x:.2f}"  # noqa: E731
    f0 = lambda x: "–" if x != x else f"{x:,.0f}"  # noqa: E731
    two = lambda a, c: a / (2 * c)  # noqa: E731
    live_ep = any(f"envpool_vec{n}" in s[name] for name in args.envs for n in VEC_SIZES)
    out = [
        "",
        "`make_vec` against the Rust `VecEnv` under it, steps/s, wall time, 2 threads (autoreset "
        "calls not counted). Alternating blocks of "
        f"{args.pair_ms:g} ms of `make_vec` calls and as many Rust steps of the same envs; the ratio "
        "is the median of those pairs, over every pair of every round"
        + ("" if has_vec else "; `envc.make_vec` absent in this build: its columns are –") + ":",
        "",
        "| env | n | `make_vec` | Rust `VecEnv` | `make_vec` ÷ Rust `VecEnv` | pairs p25–p75 | "
        "`make_vec(copy=False)` | Rust `VecEnv` | `copy=False` ÷ Rust `VecEnv` | pairs p25–p75 |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in args.envs:
        r = s[name]
        for n in VEC_SIZES:
            cells = []
            for c in ("envc_vec", "envc_views"):
                cells += [f0(med(r.get(f"{c}{n}", []))), f0(med(r.get(f"{c}_rust{n}", []))),
                          f2(med(r.get(f"{c}_pairs{n}", []))), quartiles(r.get(f"{c}_pairs{n}", []))]
            out.append(f"| {name} | {n} | " + " | ".join(cells) + " |")
    ep_head = "EnvPool" if live_ep else f"EnvPool (recorded {ENVPOOL_RECORDED['when']})"
    out += [
        "",
        "Side by side, steps/s, wall time, 2 threads where the API takes a thread count (Gymnasium's "
        "`SyncVectorEnv` is one thread, `AsyncVectorEnv` one process per env), each ÷ twice the "
        "single-thread physics ceiling (thread CPU time, the same round"
        + ("" if live_ep else "; EnvPool's ÷ its own run's ceiling") + "); \"2 raw loops at "
        "once\": two raw physics loops on two threads, wall time, in the same round:",
        "",
        f"| env | n | 2 × ceiling | 2 raw loops at once | envc `make_vec` | ÷ 2 × ceiling | {ep_head} "
        "| ÷ 2 × ceiling | Gym Sync | ÷ 2 × ceiling | Gym Async | ÷ 2 × ceiling |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in args.envs:
        r = s[name]
        for n in VEC_SIZES:
            if live_ep or name not in ENVPOOL_RECORDED:
                ep = med(r.get(f"envpool_vec{n}", []))
                ep_ratio = paired(r, two, f"envpool_vec{n}", "ceiling_sps")
            else:
                us, rates = ENVPOOL_RECORDED[name]
                ep = rates.get(n, float("nan"))
                ep_ratio = ep / (2 * 1e6 / us)
            cells = [f0(2 * med(r.get("ceiling_sps", []))), f0(med(r.get("parallel_sps", []))),
                     f0(med(r.get(f"envc_vec{n}", []))),
                     f2(paired(r, two, f"envc_vec{n}", "ceiling_sps")), f0(ep), f2(ep_ratio)]
            for c in ("sync", "async"):
                cells += [f0(med(r.get(f"{c}{n}", []))), f2(paired(r, two, f"{c}{n}", "ceiling_sps"))]
            out.append(f"| {name} | {n} | " + " | ".join(cells) + " |")
    return out


def tables(args, s, harness, head, started, ep_note, has_vec, gym, mujoco):
    f2 = lambda x: "–" if x != x else f"{x:.2f}"  # noqa: E731
    f0 = lambda x: "–" if x != x else f"{x:,.0f}"  # noqa: E731
    hw, hc = med([h[0] for h in harness]), med([h[1] for h in harness])
    head_lines = [
        f"Measured {started:%Y-%m-%d %H:%M} UTC by `benches/python_overhead.py` ({args.rounds} rounds, "
        f"{args.seconds:g} s per measurement per round; medians over rounds, ratios and differences "
        "medians of the per-round values).",
        f"Machine: {head}. Gymnasium {gym.__version__}, MuJoCo {mujoco.__version__} (Python bindings "
        f"and envc's library), {ep_note}.",
        f"Harness (a no-op `step` in the same timing loop): {hw:.2f} µs wall, {hc:.2f} µs CPU per step; "
        "included in every Python column below.",
    ]
    out = [
        "",
        "Single env, µs per step, thread CPU time (reset calls not counted):",
        "",
        "| env | ceiling (Rust) | envc (Rust) | ceiling (`mujoco` Python) | same, timer callback "
        "cleared | envc core | envc `.unwrapped` | envc `gym.make` | Gym `.unwrapped` | Gym `gym.make` |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in args.envs:
        r = s[name]
        out.append(f"| {name} | " + " | ".join(f2(med(r.get(k, []))) for k in (
            "rust_ceiling", "rust_single", "ceiling_py_cpu", "ceiling_nt_cpu", "envc_core_cpu",
            "envc_raw_cpu",
            "envc_gym_cpu", "gym_raw_cpu", "gym_gym_cpu")) + " |")
    out += [
        "",
        "Single env, µs per step, wall time:",
        "",
        "| env | ceiling (`mujoco` Python) | same, timer callback cleared | envc core | "
        "envc `.unwrapped` | envc `gym.make` | Gym `.unwrapped` | Gym `gym.make` | "
        "EnvPool (1 env, 1 thread) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in args.envs:
        r = s[name]
        out.append(f"| {name} | " + " | ".join(f2(med(r.get(k, []))) for k in (
            "ceiling_py_wall", "ceiling_nt_wall", "envc_core_wall", "envc_raw_wall", "envc_gym_wall", "gym_raw_wall",
            "gym_gym_wall", "envpool_wall")) + " |")
    d = lambda a, b: a - b  # noqa: E731
    q = lambda a, b: b / a  # noqa: E731
    out += [
        "",
        "What envc adds in Python, µs per step (thread CPU time; medians of per-round differences): "
        "the binding (core − envc's Rust step), the Python class (`.unwrapped` − core), "
        "Gymnasium's wrappers (`gym.make` − `.unwrapped`), in all (`gym.make` − Rust); the same "
        "difference for the `mujoco` bindings' raw loop (timer callback cleared: the bindings' own "
        "call cost plus the noise between processes) and the timer callback's cost (`mujoco` Python "
        "loop with − without it). Rates "
        "against the Rust physics ceiling (CPU time) and envc against Gymnasium (wall time):",
        "",
        "| env | binding | class | wrappers | in all | `mujoco` Python − Rust ceiling | timer callback | "
        "envc `gym.make` ÷ ceiling | Gym `gym.make` ÷ ceiling | envc ÷ Gym (`gym.make`, wall) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in args.envs:
        r = s[name]
        out.append(f"| {name}{' (heavy)' if name in HEAVY else ''} | "
                   f"{f2(paired(r, d, 'envc_core_cpu', 'rust_single'))} | "
                   f"{f2(paired(r, d, 'envc_raw_cpu', 'envc_core_cpu'))} | "
                   f"{f2(paired(r, d, 'envc_gym_cpu', 'envc_raw_cpu'))} | "
                   f"{f2(paired(r, d, 'envc_gym_cpu', 'rust_single'))} | "
                   f"{f2(paired(r, d, 'ceiling_nt_cpu', 'rust_ceiling'))} | "
                   f"{f2(paired(r, d, 'ceiling_py_cpu', 'ceiling_nt_cpu'))} | "
                   f"{f2(paired(r, q, 'envc_gym_cpu', 'rust_ceiling'))} | "
                   f"{f2(paired(r, q, 'gym_gym_cpu', 'rust_ceiling'))} | "
                   f"{f2(paired(r, q, 'envc_gym_wall', 'gym_gym_wall'))} |")
    out = head_lines + ([] if args.no_single else out)
    if not args.no_vector:
        out += vector_tables(args, s, has_vec)
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    sys.exit(main())
