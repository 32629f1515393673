"""The `python` fuzz target (docs/fuzzing.md): the envc Python API under mutated arguments.

Input ``i`` is built from SplitMix64 seeded with ``(seed, "python", i)``, exactly as
``cli/tests/fuzz.rs`` seeds its targets, so every input can be rebuilt from its number. An input
is a short script of calls: ``envc.make`` or ``envc.make_vec`` of a bundled id with mutated
keyword arguments (the spec's parameters and Gymnasium's), ``reset`` with mutated seeds and
options, a few ``step``s with mutated action arrays, ``envc.collect`` with mutated counts, or
``envc.register`` of a directory of good and broken specs, bad and duplicate ids, FIFOs and
symbolic-link loops (or of ``/proc/self``).

A finding is an input that ends the worker (a signal, an abort), runs past the time limit, or
raises an exception that is not an ``envc.Error`` with a code (Gymnasium's own
``gymnasium.error`` checks are allowed). The supervisor runs inputs in a worker process under a
4 GB address-space cap, starts a new worker after the input that killed the last one, and keeps
at most three findings per signature under ``--out``.

    python tests/fuzz/python_api.py --seconds 60 --seed 16 --out /tmp/fz-python
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
import traceback

MASK = (1 << 64) - 1
INPUT_SECONDS = 20
IDS = ["Hopper-v5", "InvertedPendulum-v5", "Reacher-v5", "Swimmer-v5", "HalfCheetah-v5"]
GYM_KEYS = ["max_episode_steps", "render_mode", "disable_env_checker", "camera_name", "width"]


class Rng:
    """SplitMix64, seeded as ``cli/tests/fuzz.rs``'s ``Rng::for_input``."""

    def __init__(self, seed: int, target: str, i: int):
        h = 0xCBF29CE484222325
        for b in target.encode():
            h = ((h ^ b) * 0x100000001B3) & MASK
        self.state = (seed ^ h ^ (i * 0x9E3779B97F4A7C15)) & MASK

    def next(self) -> int:
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        return z ^ (z >> 31)

    def below(self, n: int) -> int:
        return self.next() % n

    def pick(self, xs):
        return xs[self.below(len(xs))]

    def chance(self, k: int) -> bool:
        return self.below(k) == 0


def values(rng: Rng, np):
    """A dictionary of awkward Python values, each built fresh (some mutated further)."""
    base = [
        0, 1, -1, 2, 3, 1000, 2**31, 2**63, 2**64, -(2**63), 10**400, 0.0, -0.0, 0.5, 1.5, -1.5,
        1e-300, 1e308, float("nan"), float("inf"), float("-inf"), True, False, None, "", "1",
        "1.5", "nan", "Hopper-v5", "a" * 70_000, "\u202e", "\x00", b"1", bytearray(b"2"),
        {1.0}, frozenset(), 1j, (), [], {}, [0.1, 0.2], (0.7, float("inf")), [[1.0]],
        {"a": 1}, {"distance": 2.0}, {0: True}, object(), Ellipsis, range(3), slice(1),
        np.float32(0.25), np.float64("nan"), np.int64(7), np.uint64(2**64 - 1), np.bool_(True),
        np.array(0.5), np.array([0.1, 0.2]), np.array(["a"]), np.array([[1.0, 2.0]]),
        np.zeros((0,)), np.array(1 + 2j), np.array(None, dtype=object), os.devnull,
        "/dev/zero", "../../etc/passwd", __import__("pathlib").Path("hopper.xml"),
    ]
    v = rng.pick(base)
    if rng.chance(6):
        v = [v, rng.pick(base)]
    if rng.chance(8):
        v = (v,)
    return v


def actions(rng: Rng, np, shape):
    """A mutated action (or batch) for an action space of ``shape``."""
    kind = rng.below(12)
    good = np.asarray(
        [((rng.next() % 2001) / 1000.0 - 1.0) for _ in range(int(np.prod(shape)))]
    ).reshape(shape)
    if kind == 0:
        return good
    if kind == 1:
        return good.astype(np.float32)
    if kind == 2:
        bad = good.copy().ravel()
        if bad.size:
            bad[rng.below(bad.size)] = rng.pick([np.nan, np.inf, -np.inf, 1e308])
        return bad.reshape(shape)
    if kind == 3:
        return good.ravel()[: max(0, good.size - 1)]
    if kind == 4:
        return np.concatenate([good.ravel(), [0.0]])
    if kind == 5:
        return good.astype(object)
    if kind == 6:
        return good.tolist()
    if kind == 7:
        return good.astype(rng.pick([np.int8, np.int64, np.uint8, np.float16, np.complex128]))
    if kind == 8:
        return np.asfortranarray(np.stack([good, good], axis=-1))[..., 0]
    if kind == 9:
        return good[::-1] if good.ndim else good
    if kind == 10:
        return values(rng, np)
    return np.broadcast_to(good, (2,) + tuple(shape))


def build(seed: int, i: int) -> list:
    """Input i: a list of calls, as plain data (also written to a finding's ``input.json``)."""
    import numpy as np

    rng = Rng(seed, "python", i)
    env_id = rng.pick(IDS)
    calls = []
    kind = rng.pick(["make", "make", "make", "vec", "vec", "collect", "register"])
    if kind == "register":
        return [("register", rng.next())]
    kwargs = {}
    for _ in range(rng.below(3)):
        name = rng.pick(PARAMS.get(env_id, []) + GYM_KEYS + ["no_such_parameter"])
        kwargs[name] = values(rng, np)
    if kind == "collect":
        episodes = rng.pick([1, 2, 0, -1, 1.5, "2", None, 10**7 + 1, 2**64, np.int64(1), True])
        calls.append(("collect", env_id, episodes, kwargs, rng.pick([None, 0, 1.5, "1", -1, 2**64])))
        return calls
    if kind == "vec":
        n = rng.pick([1, 2, 3, 0, -1, 1.5, "2", None, np.int64(2), 10**6, 2**64])
        calls.append(("make_vec", env_id, n, rng.pick([None, 1, 2, 0, 1.5, "1"]), kwargs))
    else:
        calls.append(("make", env_id, kwargs))
    for _ in range(1 + rng.below(3)):
        seed_v = rng.pick([None, 0, 1, 2**64 - 1, 2**64, -1, 1.5, "1", [1, 2], np.uint64(3)])
        if rng.chance(4):
            seed_v = values(rng, np)
        opts = rng.pick([None, {}, "x", {"reset_mask": np.array([True, False])}, [1], 3])
        calls.append(("reset", seed_v, opts))
        for _ in range(rng.below(4)):
            calls.append(("step", rng.next()))
        if rng.chance(6):
            calls.append(("damage", rng.below(3)))
    if rng.chance(5):
        calls.append(("close",))
        calls.append(("step", rng.next()))
    return calls


PARAMS: dict[str, list[str]] = {}


def _spec_dir(seed: int, root: str, i: int) -> str:
    """A directory of specs as a careless user leaves one: valid and broken files, ids Gymnasium
    refuses or another file holds, a FIFO, links back up the tree."""
    rng = Rng(seed, "register", i)
    d = tempfile.mkdtemp(prefix=f"reg{i}-", dir=root)
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "..", "..", "specs", "gymnasium", "hopper.toml")) as f:
        hopper = f.read().replace('"../../assets/', '"' + os.path.join(here, "..", "..", "assets") + "/")
    sub = d
    for k in range(1 + rng.below(5)):
        what = rng.pick(["spec", "spec", "broken", "fifo", "up", "loop", "subdir"])
        name = os.path.join(sub, f"f{k}.toml")
        if what == "spec":
            env_id = rng.pick([f"FzReg{i}x{k}-v0", "a b-v0", "", "envc/X-v0", "Hopper-v5",
                               f"FzDup{i}-v0", "é-v0", "x" * 300])
            with open(name, "w") as f:
                f.write(hopper.replace('id = "Hopper-v5"', f"id = {json.dumps(env_id)}"))
        elif what == "broken":
            with open(name, "w") as f:
                f.write(rng.pick(["[env\n", "\x00", "id = ", "[env]\nid = 3\n", ""]))
        elif what == "fifo":
            os.mkfifo(name)
        elif what == "up":
            os.symlink("..", os.path.join(sub, f"up{k}"))
        elif what == "loop":
            os.symlink(d, os.path.join(sub, f"loop{k}"))
        else:
            sub = os.path.join(sub, f"d{k}")
            os.mkdir(sub)
    return rng.pick([d, d, os.path.join(d, "f0.toml"), "/proc/self"])


def run_input(seed: int, i: int, root: str) -> str | None:
    """Run input i; None when fine, else what went wrong."""
    import gymnasium
    import numpy as np

    import envc

    calls = build(seed, i)
    env = None
    vec = False
    # Gymnasium's PassiveEnvChecker checks only the first reset and keeps its result: when that
    # reset raised, its state stays None and every later step fails in it, whatever the env.
    reset_ok, reset_failed, resets = False, False, 0
    for c in calls:
        if c[0] == "step" and (reset_failed or not reset_ok):
            continue
        try:
            if c[0] == "make":
                env = envc.make(c[1], **c[2])
            elif c[0] == "make_vec":
                env = envc.make_vec(c[1], c[2], num_threads=c[3], **c[4])
                vec = True
            elif c[0] == "register":
                envc.register(_spec_dir(c[1], root, i))
            elif c[0] == "collect":
                envc.collect(c[1], f"fz/in{i}-v0", c[2], seed=c[4], root=root,
                             max_episode_steps=5, **{k: v for k, v in c[3].items()
                                                      if k != "max_episode_steps"})
            elif env is None:
                return None
            elif c[0] == "reset":
                resets += 1
                reset_ok, reset_failed = False, reset_failed or (resets == 1 and not vec)
                env.reset(seed=c[1], options=c[2])
                reset_ok = True
                if resets == 1:
                    reset_failed = False
            elif c[0] == "step":
                rng = Rng(c[1], "action", 0)
                shape = env.action_space.shape
                env.step(actions(rng, np, shape))
            elif c[0] == "damage" and vec:
                # copy=False hands out the env's own arrays: a user may freeze or resize them,
                # and the next step must still work.
                env.copy = False
                space = env.action_space
                buf = env.step(np.zeros(space.shape, dtype=space.dtype))[0]
                if c[1] == 0:
                    buf.flags.writeable = False
                elif c[1] == 1:
                    buf.resize((1,), refcheck=False)
            elif c[0] == "close":
                env.close()
        except envc.Error as e:
            if not (isinstance(e.code, str) and e.code.startswith("E")):
                return f"envc.Error without a code: {type(e).__name__}: {e}"
            if c[0] in ("make", "make_vec"):
                return None
        except gymnasium.error.Error as e:
            # Gymnasium's own checks of make/reset arguments are allowed; an id that reached
            # Gymnasium's registry unchecked is not.
            if c[0] == "register":
                return f"gymnasium error from register: {str(e)[:300]}"
        except Exception as e:  # noqa: BLE001 - what the fuzzer looks for
            where = traceback.extract_tb(e.__traceback__)[-1]
            return (
                f"uncoded {type(e).__name__} in {c[0]} at "
                f"{os.path.basename(where.filename)}:{where.lineno}: {str(e)[:300]}"
            )
    if env is not None:
        try:
            env.close()
        except Exception:  # noqa: BLE001
            pass
    return None


def worker(seed: int, start: int, deadline: float, root: str) -> None:
    """Run inputs from ``start`` until ``deadline``, one protocol line per input."""
    import envc

    for env_id in IDS:
        PARAMS[env_id] = [p[0] for p in envc._envc.parameters(env_id)]
    i = start
    while time.time() < deadline:
        print(f"input {i}", flush=True)
        with tempfile.TemporaryDirectory(dir=root) as d:
            bad = run_input(seed, i, d)
        print(f"finding {i} {json.dumps(bad)}" if bad else f"ok {i}", flush=True)
        i += 1
    print(f"done {i}", flush=True)


def signature(why: str) -> str:
    return why.split(":")[0] if why.startswith("uncoded") else why.split(" ")[0]


def supervise(seed: int, seconds: float, out: str) -> dict:
    """Workers until the budget is spent; returns the counts and findings."""
    deadline = time.time() + seconds
    os.makedirs(out, exist_ok=True)
    scratch = tempfile.mkdtemp(prefix="envc-fuzz-python-")
    start, inputs, ok, findings, kept = 0, 0, 0, [], {}
    while time.time() < deadline:
        cmd = [sys.executable, __file__, "--worker", "--seed", str(seed), "--start", str(start),
               "--deadline", str(deadline), "--scratch", scratch]
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             preexec_fn=_limit, cwd=scratch,
                             env={**os.environ, "MINARI_DATASETS_PATH": scratch})
        current = None
        last = time.time()
        timed_out = False
        while True:
            line = p.stdout.readline()
            if not line:
                break
            word, _, rest = line.strip().partition(" ")
            if word == "input":
                current, last = int(rest), time.time()
            elif word in ("ok", "finding"):
                inputs += 1
                n, _, why = rest.partition(" ")
                if word == "ok":
                    ok += 1
                else:
                    findings.append(_keep(out, seed, int(n), json.loads(why), kept))
                current = None
            elif word == "done":
                break
            if time.time() - last > INPUT_SECONDS:
                timed_out = True
                break
        try:
            p.wait(timeout=max(1.0, INPUT_SECONDS - (time.time() - last)))
        except subprocess.TimeoutExpired:
            timed_out = True
            p.kill()
            p.wait()
        if current is not None:
            inputs += 1
            status = "timeout" if timed_out else f"worker died: status {p.returncode}"
            err = (p.stderr.read() or "")[-2000:]
            findings.append(_keep(out, seed, current, f"{status}\n{err}", kept))
            start = current + 1
        else:
            break
    subprocess.run(["rm", "-rf", scratch])
    return {"inputs": inputs, "ok": ok, "findings": [f for f in findings if f]}


def _keep(out: str, seed: int, i: int, why: str, kept: dict) -> str:
    """Save a finding's input and symptom (at most three per signature)."""
    sig = signature(why)
    kept[sig] = kept.get(sig, 0) + 1
    if kept[sig] <= 3:
        d = os.path.join(out, f"python-{i}")
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, "finding.txt"), "w") as f:
            f.write(f"seed {seed} input {i}\n{why}\n")
        with open(os.path.join(d, "input.txt"), "w") as f:
            import envc  # noqa: F401 - the ids' parameter names

            for env_id in IDS:
                PARAMS[env_id] = [p[0] for p in envc._envc.parameters(env_id)]
            f.write(repr(build(seed, i)))
    return f"input {i}: {why.splitlines()[0]}"


def _limit() -> None:
    cap = 4_000_000 * 1024
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))


def main() -> None:
    a = argparse.ArgumentParser()
    a.add_argument("--seed", type=int, default=16)
    a.add_argument("--seconds", type=float, default=60)
    a.add_argument("--out", default=None)
    a.add_argument("--worker", action="store_true")
    a.add_argument("--start", type=int, default=0)
    a.add_argument("--deadline", type=float, default=0)
    a.add_argument("--scratch", default=None)
    args = a.parse_args()
    if args.worker:
        worker(args.seed, args.start, args.deadline, args.scratch)
        return
    out = args.out or tempfile.mkdtemp(prefix="envc-fuzz-out-")
    r = supervise(args.seed, args.seconds, out)
    print(f"python {r['inputs']} inputs {r['ok']} fine {len(r['findings'])} findings ({out})")
    for f in r["findings"]:
        print(f"NEW: python {f}")
    sys.exit(1 if r["findings"] else 0)


if __name__ == "__main__":
    main()
