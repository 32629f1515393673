"""GPU executor throughput (envc.gpu, MJX backend) against envc's CPU vector env, in one run.

    python benches/gpu_throughput.py [--out results.json] [--budget 420] [--sizes 1024,4096,16384]
                                     [--go1-xml path/to/unitree_go1/scene.xml] [--quick]

For each spec and world count: compile time (first call, tracing and XLA), full env steps/s
(physics + terms + termination + same-step autoreset, no resets happening), physics alone
(frame_skip × mjx.step [+ rne_postconstraint]) steps/s, the cost of resetting about 2 % of the
worlds every step, and peak GPU memory. Specs the executor refuses are reported with the refused
parts, and their compiled model is timed for physics alone. The baseline is envc's CPU vector env
on all host cores, same specs, same run. Configurations are run in priority order and skipped
once `--budget` seconds are spent (reported as skipped). docs/gpu.md explains the numbers."""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time

import numpy as np


def log(*a):
    print(*a, flush=True)


def gpu_info():
    try:
        return subprocess.run(
            ["nvidia-smi", "--query-gpu=name,memory.total,driver_version", "--format=csv,noheader"],
            capture_output=True,
            text=True,
            timeout=20,
        ).stdout.strip()
    except Exception as e:  # no nvidia-smi (CPU run)
        return f"none ({type(e).__name__})"


def peak_bytes():
    import jax

    try:
        s = jax.devices()[0].memory_stats() or {}
        return int(s.get("peak_bytes_in_use", 0))
    except Exception:
        return 0


def timed(fn, *args, reps: int):
    import jax

    out = fn(*args)
    jax.block_until_ready(out)
    t = time.perf_counter()
    for _ in range(reps):
        out = fn(*args)
    jax.block_until_ready(out)
    return (time.perf_counter() - t) / reps, out


def patched(p, variant):
    """The plan with its compiled model changed as `variant` says (a labelled benchmark row of a
    model MJX refuses: not the spec's model, so not its physics)."""
    import mujoco

    from envc import gpu
    from envc.gpu import _mjx

    m = _mjx.load_mjmodel(p.mjb)
    if variant == "newton":
        m.opt.solver = mujoco.mjtSolver.mjSOL_NEWTON
    elif variant == "pyramidal":
        m.opt.cone = mujoco.mjtCone.mjCONE_PYRAMIDAL
    elif variant == "fast_solver":
        # MJX's performance advice: few solver and line-search iterations.
        m.opt.iterations, m.opt.ls_iterations = 4, 8
    buf = np.zeros(mujoco.mj_sizeModel(m), np.uint8)
    mujoco.mj_saveModel(m, None, buf)
    return gpu.Plan(p.raw, buf.tobytes())


def bench_gpu(spec, overrides, n, reps, variant=None):
    """One (spec, world count) configuration on the default JAX device."""
    import jax
    import jax.numpy as jnp

    from envc import gpu
    from envc.gpu import _mjx
    from envc.gpu._executor import Executor, State

    p = gpu.plan(spec, **overrides)
    if variant:
        p = patched(p, variant)
    refused = p.refusals(_mjx.MjxBackend.fields_supported)
    row = {"spec": spec, "num_envs": n, "variant": variant, "refused": refused}
    backend = _mjx.MjxBackend(p, None)
    ex = Executor(p, backend, n)
    key = jax.random.PRNGKey(0)
    act = jax.random.uniform(
        key, (n, len(p["act_low"])), minval=jnp.asarray(p["act_low"]),
        maxval=jnp.asarray(p["act_high"]), dtype=jnp.float32,
    )
    t = time.perf_counter()
    if refused:
        # The executor cannot reset this spec: its compiled model at qpos0, for physics alone.
        zero = jnp.zeros_like(backend.d0.qvel)
        init = jax.jit(jax.vmap(lambda _: backend.initial(backend.qpos0(), zero)))
        state = State(init(jnp.arange(n)), None, None, key)
    else:
        state, _ = ex.reset(key)
    jax.block_until_ready(state.data)
    row["compile_reset_s"] = time.perf_counter() - t
    # Physics alone: the same frame_skip × mjx.step (+ rne) the full step runs.
    phys = jax.jit(lambda d, a: jax.vmap(backend.physics)(d, a))
    t = time.perf_counter()
    jax.block_until_ready(phys(state.data, act))
    row["compile_physics_s"] = time.perf_counter() - t
    dt_phys, _ = timed(phys, state.data, act, reps=reps)
    row["physics_sps"] = n / dt_phys
    if refused:
        row["peak_gpu_bytes"] = peak_bytes()
        return row

    def step_reset(s: State, a, mask):
        return ex._reset_where(ex._step(s, a).state, mask)

    full = jax.jit(step_reset)
    none = jnp.zeros((n,), bool)
    t = time.perf_counter()
    jax.block_until_ready(full(state, act, none))
    row["compile_step_s"] = time.perf_counter() - t
    dt_full, _ = timed(full, state, act, none, reps=reps)
    row["full_sps"] = n / dt_full
    row["non_physics_fraction"] = max(0.0, 1.0 - dt_phys / dt_full)
    # ~2 % of worlds reset every step (a fresh random mask each call).
    masks = [jax.random.uniform(jax.random.PRNGKey(i), (n,)) < 0.02 for i in range(8)]
    jax.block_until_ready(masks)
    full(state, act, masks[0])
    t = time.perf_counter()
    s = state
    for i in range(reps):
        s = full(s, act, masks[i % 8])
    jax.block_until_ready(s)
    dt_reset = (time.perf_counter() - t) / reps
    row["full_with_2pct_reset_sps"] = n / dt_reset
    row["reset_2pct_cost_fraction"] = max(0.0, dt_reset / dt_full - 1.0)
    row["peak_gpu_bytes"] = peak_bytes()
    return row


def physics_parity(spec, overrides, steps=30):
    """One env step of physics (frame_skip × mjx.step [+ rne]) on the device against C MuJoCo
    (float64) from the same states: the largest |difference| in qpos, qvel."""
    import jax
    import jax.numpy as jnp
    import mujoco
    from mujoco import mjx

    from envc import gpu
    from envc.gpu import _mjx

    p = gpu.plan(spec, **overrides)
    b = _mjx.MjxBackend(p, None)
    m = b.mjm
    d = mujoco.MjData(m)
    rng = np.random.default_rng(0)
    mujoco.mj_resetData(m, d)
    d.qpos[:] = m.qpos0 + rng.uniform(-0.1, 0.1, m.nq)
    mujoco.mj_forward(m, d)
    starts, ctrls, want = [], [], []
    for _ in range(steps):
        a = rng.uniform(-1, 1, m.nu)
        c = mujoco.MjData(m)
        mujoco.mj_copyData(c, m, d)
        starts.append(mjx.put_data(m, c, impl="jax"))
        ctrls.append(a)
        d.ctrl[:] = a
        for _ in range(p["frame_skip"]):
            mujoco.mj_step(m, d)
        if p["needs_rne_post_constraint"]:
            mujoco.mj_rnePostConstraint(m, d)
        want.append((d.qpos.copy(), d.qvel.copy()))
    dx = jax.tree_util.tree_map(lambda *xs: jnp.stack(xs), *starts)
    got = jax.jit(jax.vmap(b.physics))(dx, jnp.asarray(np.stack(ctrls), jnp.float32))
    eq = max(float(np.abs(np.asarray(got.qpos[k]) - w[0]).max()) for k, w in enumerate(want))
    ev = max(float(np.abs(np.asarray(got.qvel[k]) - w[1]).max()) for k, w in enumerate(want))
    return {"spec": spec, "states": steps, "max_abs_qpos": eq, "max_abs_qvel": ev}


def bench_cpu(spec, overrides, seconds=4.0):
    """envc's CPU vector env on every host core (Rust threads), random actions."""
    import envc

    threads = os.cpu_count() or 1
    n = threads * 16
    env = envc.make_vec(spec, n, num_threads=threads, **overrides)
    env.reset(seed=0)
    env.action_space.seed(0)
    acts = [env.action_space.sample() for _ in range(4)]
    k = 0
    t = time.perf_counter()
    while time.perf_counter() - t < seconds:
        env.step(acts[k % 4])
        k += 1
    dt = time.perf_counter() - t
    env.close()
    return {"spec": spec, "num_envs": n, "threads": threads, "sps": n * k / dt}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="gpu_throughput.json")
    ap.add_argument("--budget", type=float, default=420.0)
    ap.add_argument("--sizes", default="1024,4096,16384")
    ap.add_argument("--reps", type=int, default=20)
    ap.add_argument("--go1-xml", default=None)
    ap.add_argument("--quick", action="store_true", help="tiny sizes, for a CPU dry run")
    ap.add_argument(
        "--only",
        default=None,
        help="configurations SPEC_INDEX:N[:VARIANT],... instead of the default order "
        "(specs: 0 Ant, 1 Humanoid, 2 Go1 joystick; variants: newton, pyramidal, fast_solver)",
    )
    args = ap.parse_args()
    t0 = time.perf_counter()
    import jax

    import envc
    import envc.gpu

    sizes = [int(s) for s in args.sizes.split(",")]
    if args.quick:
        sizes, args.reps = [4], 2
    here = os.path.dirname(os.path.abspath(__file__))
    go1_spec = os.path.join(here, "..", "specs", "examples", "go1_joystick.toml")
    go1_xml = args.go1_xml or os.path.join(
        here, "..", "..", "shared", "models", "unitree_go1", "scene.xml"
    )
    # The benchmark's own settings: no natural resets (no termination, no time limit), so the
    # 2 % reset figure is the only reset cost measured.
    steady = {"terminate_when_unhealthy": False, "max_episode_steps": 0}
    specs = [
        ("Ant-v5", dict(steady)),
        ("Humanoid-v5", dict(steady)),
        (go1_spec, {"xml_file": os.path.abspath(go1_xml), "max_episode_steps": 0}),
    ]
    res = {
        "host": platform.node(),
        "python": sys.version.split()[0],
        "jax": jax.__version__,
        "device": str(jax.devices()[0]),
        "gpu": gpu_info(),
        "cpu_count": os.cpu_count(),
        "envc": envc.__version__,
        "gpu_rows": [],
        "cpu_rows": [],
        "refusals": {},
        "skipped": [],
    }

    def save():
        with open(args.out, "w") as fh:
            json.dump(res, fh, indent=1)

    # The CPU baseline first (cheap, and always wanted).
    for spec, ov in specs:
        try:
            res["cpu_rows"].append(bench_cpu(spec, ov, 1.0 if args.quick else 4.0))
            log("cpu", res["cpu_rows"][-1])
        except Exception as e:
            res["cpu_rows"].append({"spec": spec, "error": f"{type(e).__name__}: {e}"})
            log("cpu error", spec, e)
    save()
    for spec, ov in specs:
        try:
            envc.gpu.make_vec(spec, 2, **ov)
        except envc.gpu.Unsupported as e:
            res["refusals"][spec] = e.parts
    save()

    def parity():
        try:
            res["physics_parity"] = physics_parity("Ant-v5", {})
            log("parity", res["physics_parity"])
        except Exception as e:
            res["physics_parity"] = {"error": f"{type(e).__name__}: {e}"}
        save()
    # Priority order: the spec's own models first (Ant; Humanoid and Go1 are refused by MJX:
    # one quick row each says why), then labelled variants of the refused models (Humanoid with
    # the Newton solver, the Go1 with pyramidal cones: physics MJX can run, not the spec's).
    mid = sizes[1:2] or sizes[:1]
    rest = [n for n in sizes if n not in mid]
    order = [(0, n, None) for n in mid] + [(1, mid[0], None), (2, mid[0], None)]
    order += [(1, mid[0], "newton"), (0, rest[-1], None) if rest else None]
    order += [(2, mid[0], "pyramidal")] + [(0, n, None) for n in rest[:-1]]
    order += [(1, n, "newton") for n in rest] + [(2, n, "pyramidal") for n in rest]
    if args.only:
        order = []
        for c in args.only.split(","):
            f = c.split(":")
            order.append((int(f[0]), int(f[1]), f[2] if len(f) > 2 else None))
        res["physics_parity"] = "not run (--only)"
    for si, n, variant in [o for o in order if o]:
        spec, ov = specs[si]
        spent = time.perf_counter() - t0
        if spent > args.budget:
            res["skipped"].append(
                {"spec": spec, "num_envs": n, "variant": variant, "why": f"budget ({spent:.0f} s)"}
            )
            continue
        try:
            row = bench_gpu(spec, ov, n, args.reps, variant)
        except Exception as e:
            why = f"{type(e).__name__}: {e}"[:2000]
            row = {"spec": spec, "num_envs": n, "variant": variant, "error": why}
        row["at_s"] = time.perf_counter() - t0
        res["gpu_rows"].append(row)
        log("gpu", {k: v for k, v in row.items() if k != "refused"})
        save()
        if "physics_parity" not in res:
            parity()
    save()
    log(f"done in {time.perf_counter() - t0:.0f} s -> {args.out}")


if __name__ == "__main__":
    main()
