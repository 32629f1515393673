"""E1403: the memory a vector env's envs need, estimated before making them, against what they
really hold (resident memory, measured in a fresh interpreter), and the two ways it went wrong:
MuJoCo's untouched arenas refused large CPU batches, and envs with huge observations passed the
check and then aborted the interpreter. Each case runs in a subprocess with its memory capped."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
GIB = 1 << 30


def run(code: str, timeout: float = 300) -> dict:
    """Run `PRELUDE` and `code` in a fresh interpreter; it prints one JSON line last."""
    p = subprocess.run(
        [sys.executable, "-c", PRELUDE + textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert p.returncode == 0, f"exit {p.returncode}\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}"
    return json.loads(p.stdout.strip().splitlines()[-1])


PRELUDE = """
import json, resource
import numpy as np
import envc

def rss():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmRSS:"))
"""


@pytest.mark.parametrize("env_id", ["Hopper-v5", "Humanoid-v5"])
def test_estimate_matches_resident_memory(env_id):
    """The estimate per env covers what an env holds once stepped (resident), and is not far
    above it: the untouched part of MuJoCo's arena is not counted."""
    out = run(
        f"""
        warm = envc.make_vec({env_id!r}, 2, num_threads=1)  # code, model cache, first pages
        warm.reset(seed=0); warm.step(np.zeros((2,) + warm.single_action_space.shape))
        n = 400
        before = rss()
        env = envc.make_vec({env_id!r}, n, num_threads=2)
        env.reset(seed=0)
        rng = np.random.default_rng(0)
        low, high = env.single_action_space.low, env.single_action_space.high
        for _ in range(100):  # past the first falls and their contacts
            res = env.step(rng.uniform(low, high, size=(n, low.size)).astype(np.float32))
        after = rss()
        resident, mapped = env._core.bytes_per_env
        print(json.dumps(dict(measured=(after - before) / n, resident=resident, mapped=mapped)))
        """
    )
    measured, estimate = out["measured"], out["resident"]
    assert measured <= estimate, out
    assert estimate <= 2 * measured + (64 << 10), out
    assert out["mapped"] > 10 * estimate, out  # the arenas: mapped, not written


def test_4096_hopper_envs_make_and_step():
    out = run(
        """
        before = rss()
        env = envc.make_vec("Hopper-v5", 4096)
        obs, _ = env.reset(seed=0)
        for _ in range(5):
            obs, r, term, trunc, info = env.step(np.full((4096, 3), 0.1, dtype=np.float32))
        print(json.dumps(dict(shape=obs.shape, finite=bool(np.isfinite(obs).all()),
                              per_env=(rss() - before) / 4096, estimate=env._core.bytes_per_env[0])))
        """
    )
    assert out["shape"] == [4096, 11] and out["finite"], out
    assert out["per_env"] <= out["estimate"], out


def huge_spec(tmp_path: Path, bodies: int, segments: int) -> Path:
    """A cart-pole with `bodies` static bodies more and `segments` copies of their `cinert`
    (10 numbers a body) in its observation."""
    xml = (ROOT / "assets/gymnasium/inverted_pendulum.xml").read_text()
    extra = "".join(
        f'<body name="b{i}" pos="{i} 5 0"><geom type="sphere" size="0.1"/></body>'
        for i in range(bodies)
    )
    (tmp_path / "model.xml").write_text(xml.replace("</worldbody>", extra + "</worldbody>"))
    spec = (ROOT / "specs/gymnasium/inverted_pendulum.toml").read_text()
    spec = spec.replace('id = "InvertedPendulum-v5"', 'id = "HugeObs-v0"')
    spec = spec.replace("../../assets/gymnasium/inverted_pendulum.xml", str(tmp_path / "model.xml"))
    spec = spec.replace("entry_point", "# entry_point")
    spec += "".join(f'\n[observation.c{k}]\nsource = "cinert"\n' for k in range(segments))
    path = tmp_path / "huge.toml"
    path.write_text(spec)
    return path


def test_huge_observations_are_refused_with_e1403_never_abort(tmp_path):
    """About a million observation numbers per env (8 MB a row): under a 2 GiB address-space cap
    every count either works or is refused with E1403, whatever it allocates on the way (the
    env's vectors, the batch, numpy's buffers and copies)."""
    spec = huge_spec(tmp_path, 1000, 100)
    out = run(
        f"""
        path = {str(spec)!r}
        try:
            one = envc.make_vec(path, 1, num_threads=1)
        except envc.SpecError as e:  # an observation-size limit refuses the spec itself
            print(json.dumps(dict(spec_refused=str(e)))); raise SystemExit
        obs_dim = one.single_observation_space.shape[0]
        one.close(); del one
        with open("/proc/self/status") as f:
            vm = next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmSize:"))
        resource.setrlimit(resource.RLIMIT_AS, (vm + {2 * GIB}, resource.RLIM_INFINITY))
        outcome = {{}}
        for n in (1, 2, 4, 8, 12, 20, 30, 55, 200):
            try:
                env = envc.make_vec(path, n, num_threads=2)
                env.reset(seed=0)
                kept = [env.step(np.zeros((n, 1)))[0] for _ in range(2)]
                outcome[n] = "ok"
                env.close(); del env, kept
            except ValueError as e:
                outcome[n] = "E1403" if "E1403" in str(e) else repr(e)
            except BaseException as e:  # MemoryError and the like: what must not happen
                outcome[n] = repr(e)
        print(json.dumps(dict(obs_dim=obs_dim, outcome=outcome)))
        """
    )
    if "spec_refused" in out:
        pytest.skip(f"the spec itself is refused: {out['spec_refused']}")
    assert out["obs_dim"] > 1_000_000
    outcome = out["outcome"]
    assert set(outcome.values()) <= {"ok", "E1403"}, outcome
    assert outcome["1"] == "ok" and outcome["200"] == "E1403", outcome
    # Refused from some count on, never admitted again above it.
    counts = sorted(outcome, key=int)
    first = next(c for c in counts if outcome[c] == "E1403")
    assert all(outcome[c] == "E1403" for c in counts[counts.index(first) :]), outcome


def test_huge_observations_beyond_the_machine_are_refused(tmp_path):
    """Without a cap: more envs than the machine's memory holds is E1403 before allocating."""
    spec = huge_spec(tmp_path, 1000, 100)
    out = run(
        f"""
        try:
            envc.make_vec({str(spec)!r}, 50_000, num_threads=2)
            print(json.dumps(dict(result="made")))
        except envc.SpecError as e:
            print(json.dumps(dict(result="spec refused")))
        except ValueError as e:
            print(json.dumps(dict(result=str(e))))
        """
    )
    if out["result"] == "spec refused":
        pytest.skip("the spec itself is refused")
    assert "E1403" in out["result"] and "of memory" in out["result"], out
