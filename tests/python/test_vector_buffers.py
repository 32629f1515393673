"""envc vector envs' own buffers: ``copy=False`` hands out the same arrays every call (the env
writes each batch into them), and its results equal ``copy=True``'s bit for bit, in both autoreset
modes, for float32 and float64 batches, contiguous or not."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import envc

STEPS = 120
N = 4


def snapshot(x):
    """A deep copy of a step's result (``copy=False`` arrays are overwritten by the next call)."""
    if isinstance(x, dict):
        return {k: snapshot(v) for k, v in x.items()}
    if isinstance(x, tuple):
        return tuple(snapshot(v) for v in x)
    if isinstance(x, np.ndarray) and x.dtype == object:
        out = np.empty(x.shape, dtype=object)
        for i, v in enumerate(x):
            out[i] = None if v is None else v.copy()
        return out
    return x.copy() if isinstance(x, np.ndarray) else x


def same(a, b, what):
    if isinstance(b, dict):
        assert list(a) == list(b), f"{what}: keys {list(a)} vs {list(b)}"
        for k in b:
            same(a[k], b[k], f"{what}[{k!r}]")
    elif isinstance(b, tuple):
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            same(x, y, f"{what}[{i}]")
    elif isinstance(b, np.ndarray) and b.dtype == object:
        assert a.dtype == object and a.shape == b.shape, what
        for i, (x, y) in enumerate(zip(a, b)):
            assert (x is None) == (y is None), f"{what}[{i}]"
            if y is not None:
                same(x, y, f"{what}[{i}]")
    else:
        a, b = np.asarray(a), np.asarray(b)
        assert (a.dtype, a.shape) == (b.dtype, b.shape), f"{what}: {a.dtype}{a.shape} vs {b.dtype}{b.shape}"
        assert a.tobytes() == b.tobytes(), f"{what}: {a} vs {b}"


def arrays(info):
    """Every array of an info dict (nested ``final_info`` included), by key path."""
    out = {}
    for k, v in info.items():
        if isinstance(v, dict):
            out.update({(k, kk): vv for kk, vv in arrays(v).items()})
        elif k != "final_obs":  # a fresh object array of fresh rows, as Gymnasium's
            out[(k,)] = v
    return out


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP], ids=lambda m: m.value)
@pytest.mark.parametrize("env_id", ["Hopper-v5", "Reacher-v5"])
def test_copy_false_reuses_its_buffers_and_equals_copy_true(env_id, mode, dtype):
    views = envc.make_vec(env_id, N, num_threads=2, autoreset_mode=mode, max_episode_steps=30)
    views.copy = False
    fresh = envc.make_vec(env_id, N, num_threads=2, autoreset_mode=mode, max_episode_steps=30)
    assert fresh.copy is True
    rng = np.random.default_rng(5)
    low, high = fresh.single_action_space.low, fresh.single_action_space.high
    o_v, i_v = views.reset(seed=11)
    o_f, i_f = fresh.reset(seed=11)
    same(snapshot((o_v, i_v)), (o_f, i_f), "reset")
    first = None
    kept = {}  # info key path -> the array copy=False handed out for it
    finals = 0
    for t in range(STEPS):
        a = rng.uniform(low, high, size=(N, low.size)).astype(dtype)
        if t == STEPS // 2:
            mask = np.array([True, False] * (N // 2))
            o_v, i_v = views.reset(seed=3, options={"reset_mask": mask})
            o_f, i_f = fresh.reset(seed=3, options={"reset_mask": mask})
            same(snapshot((o_v, i_v)), (o_f, i_f), f"masked reset at {t}")
            assert o_v is first[0]
        r_v = views.step(a)
        r_f = fresh.step(a)
        same(snapshot(r_v), r_f, f"{env_id} {mode.value} {np.dtype(dtype)} step {t}")
        if first is None:
            first = r_v
            assert r_v[0] is o_v  # reset and step share the observation buffer
        for k in range(4):  # obs, rewards, terminated, truncated: the same arrays every step
            assert r_v[k] is first[k], f"step {t}: result {k} is a new array"
            assert r_f[k] is not first[k]
        for path, arr in arrays(r_v[4]).items():
            if path in kept:
                assert arr is kept[path], f"step {t}: info {path} is a new array"
            kept[path] = arr
        finals += "final_obs" in r_v[4]
    assert mode == AutoresetMode.NEXT_STEP or finals > 0
    prev = fresh.step(a)
    assert fresh.step(a)[4] is not prev[4]
    views.close()
    fresh.close()


def test_action_batches_of_any_layout_give_the_same_steps():
    """A C-contiguous float32/float64 batch is read in place; any other layout or dtype is
    converted first, with the same results."""
    envs = [envc.make_vec("Hopper-v5", N, num_threads=2) for _ in range(4)]
    for e in envs:
        e.reset(seed=2)
    rng = np.random.default_rng(9)
    for t in range(60):
        a = rng.uniform(-1, 1, size=(N, 3)).astype(np.float32)
        b = a.astype(np.float64)
        r = [
            envs[0].step(a),
            envs[1].step(np.asfortranarray(a)),  # not C-contiguous
            envs[2].step(b),
            envs[3].step(np.repeat(b, 2, axis=1)[:, ::2]),  # a strided view
        ]
        same(r[1], r[0], f"step {t}, float32 in Fortran order")
        same(r[3], r[2], f"step {t}, float64 strided")
    for e in envs:
        e.close()


def test_a_buffer_the_user_breaks_is_replaced():
    env = envc.EnvcVectorEnv("Hopper-v5", 2, copy=False)
    obs, _ = env.reset(seed=0)
    ref = envc.EnvcVectorEnv("Hopper-v5", 2)
    ref.reset(seed=0)
    obs.flags.writeable = False
    r = env.step(np.zeros((2, 3)))
    same(snapshot(r), ref.step(np.zeros((2, 3))), "after the user made obs read-only")
    assert r[0] is not obs and r[0].flags.writeable
    assert env.step(np.zeros((2, 3)))[0] is r[0]
    env.close()
    ref.close()
