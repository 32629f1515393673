"""envc in a process that imported ``mujoco``: its timer callback is left as found, steps unchanged.

``import mujoco`` installs MuJoCo's process-wide timer callback ``mjcb_time``; envc's cores step
with it cleared (it costs ~2.5 µs per ``mj_step``, docs/PERFORMANCE.md) and put it back after.
Checked against the live reference in the same process: observations bitwise, rewards and flags
exactly, the callback unchanged after every call, the reference's own timers still counting.
"""

import ctypes
import os
import random

import gymnasium as gym
import mujoco
import numpy as np
import pytest

import envc  # noqa: F401  (registers envc/)

SEED = int(os.environ.get("ENVC_LIVE_SEED", random.randrange(2**32)))
print(f"ENVC_LIVE_SEED={SEED}")


def timer_cell() -> ctypes.c_void_p:
    return ctypes.c_void_p.in_dll(ctypes.CDLL(f"libmujoco.so.{mujoco.__version__}"), "mjcb_time")


@pytest.mark.parametrize("env_id", ["InvertedPendulum-v5", "Hopper-v5", "Ant-v5"])
@pytest.mark.parametrize("seed", [0, SEED])
def test_steps_match_reference_and_leave_the_timer(env_id, seed):
    cell = timer_cell()
    before = cell.value
    assert before, "import mujoco installs a timer callback"
    e, g = gym.make(f"envc/{env_id}"), gym.make(env_id)
    oe, _ = e.reset(seed=seed)
    og, _ = g.reset(seed=seed)
    assert np.array_equal(oe, og) and cell.value == before
    rng = np.random.default_rng(seed)
    for t in range(200):
        a = rng.uniform(g.action_space.low, g.action_space.high).astype(np.float32)
        re, rg = e.step(a), g.step(a)
        assert np.array_equal(re[0], rg[0]), (env_id, seed, t)
        assert (re[1], re[2], re[3]) == (rg[1], rg[2], rg[3]), (env_id, seed, t)
        assert cell.value == before
        if re[2] or re[3]:
            oe, _ = e.reset()
            og, _ = g.reset()
            assert np.array_equal(oe, og)


def test_reference_timers_still_count():
    g = gym.make("Hopper-v5").unwrapped
    g.reset(seed=0)
    e = gym.make("envc/Hopper-v5")
    e.reset(seed=0)
    n0 = g.data.timer[mujoco.mjtTimer.mjTIMER_STEP].number
    e.step(e.action_space.sample())
    g.step(g.action_space.sample())
    assert g.data.timer[mujoco.mjtTimer.mjTIMER_STEP].number - n0 == g.frame_skip
