"""envc vector envs' results as views of buffers the env owns: with ``copy=False`` every step and
reset writes into the same memory (same ``ctypes.data``, same base), nothing proportional to the
batch is allocated in Python per step (tracemalloc, which sees numpy's arrays), float32 and
float64 action batches reach the envs without a copy, and the results equal the copying path
(``copy=True``) bit for bit. ``_core.rust_steps`` (the Rust ``VecEnv`` alone, which the
benchmark times under ``make_vec``) steps the same envs as ``step``."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import envc

def addresses(result):
    """``(ctypes.data, base)`` of every array in a step's or reset's result, infos included."""
    out = {}

    def walk(x, path):
        if isinstance(x, dict):
            for k, v in x.items():
                walk(v, path + (k,))
        elif isinstance(x, tuple):
            for i, v in enumerate(x):
                walk(v, path + (i,))
        elif isinstance(x, np.ndarray) and x.dtype != object:
            out[path] = (x.ctypes.data, id(x.base) if x.base is not None else None, x.nbytes)

    walk(result, ())
    return out


def same_bits(a, b, what):
    if isinstance(b, dict):
        assert sorted(a) == sorted(b), what
        for k in b:
            same_bits(a[k], b[k], f"{what}[{k!r}]")
    elif isinstance(b, tuple):
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            same_bits(x, y, f"{what}[{i}]")
    elif isinstance(b, np.ndarray) and b.dtype == object:
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            assert (x is None) == (y is None), f"{what}[{i}]"
            if y is not None:
                same_bits(x, y, f"{what}[{i}]")
    else:
        a, b = np.asarray(a), np.asarray(b)
        assert (a.dtype, a.shape) == (b.dtype, b.shape), what
        assert a.tobytes() == b.tobytes(), what


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize(
    "mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP], ids=lambda m: m.value
)
def test_views_keep_their_memory_and_equal_the_copies(mode, dtype):
    n = 6
    kw = dict(num_threads=2, autoreset_mode=mode, max_episode_steps=25)
    views = envc.make_vec("Hopper-v5", n, copy=False, **kw)
    copies = envc.make_vec("Hopper-v5", n, **kw)
    rng = np.random.default_rng(3)
    low, high = copies.single_action_space.low, copies.single_action_space.high
    r_v, r_c = views.reset(seed=4), copies.reset(seed=4)
    same_bits(r_v, r_c, "reset")
    where = addresses(r_v)
    held = []  # copy=True's results, kept alive: each must be memory of its own
    for t in range(80):
        a = rng.uniform(low, high, size=(n, low.size)).astype(dtype)
        r_v, r_c = views.step(a), copies.step(a)
        same_bits(r_v, r_c, f"step {t}")
        now = addresses(r_v)
        for path, (data, base, nbytes) in now.items():
            if path in where:
                assert (data, base, nbytes) == where[path], f"step {t}: {path} moved"
            where[path] = (data, base, nbytes)
        assert now[(0,)] == where[(0,)]  # observations: the reset's buffer, still
        held.append(r_c)
        taken = {addr[0] for r in held for addr in addresses(r).values()}
        assert len(taken) == sum(len(addresses(r)) for r in held), "copy=True reused memory"
        if len(held) > 4:
            held.pop(0)
    views.close()
    copies.close()


def step_peak(env, acts, steps=20):
    """The most memory Python traced (numpy's arrays included) during one step beyond what was
    allocated before it, over ``steps`` steps."""
    tracemalloc.start()
    try:
        peaks = []
        for k in range(steps):
            now = tracemalloc.get_traced_memory()[0]
            tracemalloc.reset_peak()
            env.step(acts[k % len(acts)])
            peaks.append(tracemalloc.get_traced_memory()[1] - now)
    finally:
        tracemalloc.stop()
    return max(peaks)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_no_allocation_proportional_to_the_batch(dtype):
    """``copy=False``: a step allocates nothing proportional to the batch in Python, not even for
    a moment (the action batch is read in place, the results are written into the env's own
    arrays; what is left is the result tuple and the info dict). A batch that needs converting
    (integers) shows what a copy of it would cost; ``copy=True`` allocates its fresh results."""
    n = 512
    one_column = n * 4  # bytes: less than any batch-sized copy (a float32 column of the batch)
    env = envc.make_vec("Hopper-v5", n, num_threads=2, copy=False)
    env.reset(seed=0)
    acts = [np.random.default_rng(k).uniform(-1, 1, size=(n, 3)).astype(dtype) for k in range(4)]
    for a in acts:
        env.step(a)
    assert step_peak(env, acts) < one_column
    ints = [np.zeros((n, 3), dtype=np.int64)]
    assert step_peak(env, ints) >= n * 3 * 8  # the conversion to float64 is seen
    env.copy = True
    assert step_peak(env, acts) >= n * 11 * 8  # a fresh observation batch
    env.close()


def test_rust_steps_drive_the_same_envs():
    """``rust_steps`` then ``step`` lands where ``step`` alone does, bit for bit, and both count
    the env steps as the results say (an env that ended is autoreset by the next call, NextStep,
    which is no env step)."""
    n = 5
    rng = np.random.default_rng(8)
    acts = rng.uniform(-1, 1, size=(7, n, 3)).astype(np.float32)
    python = envc.make_vec("Hopper-v5", n, num_threads=2, max_episode_steps=9)
    rust = envc.make_vec("Hopper-v5", n, num_threads=2, max_episode_steps=9)
    python.reset(seed=1)
    rust.reset(seed=1)
    counted, ended = 0, np.zeros(n, dtype=bool)
    for t in range(40):
        last = python.step(acts[t % 7])
        counted += n - int(np.count_nonzero(ended))
        ended = last[2] | last[3]
    assert python._core.env_steps == counted
    rust._core.rust_steps(acts, 0, 39)
    same_bits(rust.step(acts[39 % 7]), last, "step 40, after 39 steps in Rust")
    assert rust._core.env_steps == counted
    with pytest.raises(ValueError):
        rust._core.rust_steps(acts[:, :2], 0, 1)  # not num_envs rows
    python.close()
    rust.close()
