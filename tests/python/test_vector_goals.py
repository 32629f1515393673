"""envc vector envs of a goal-conditioned task against Gymnasium's SyncVectorEnv over the live
Gymnasium-Robotics reference, bit for bit.

``envc.make_vec("FetchPush-v4", 4)`` (1 and 2 threads) and ``SyncVectorEnv`` over four
``gym.make("FetchPush-v4")`` take the same seeds and action batches for 120 steps (episodes of
50 steps: two autoresets per env, and a masked reset between them), and every leaf is compared
exactly: the observation dicts (keys, their order, dtypes, shapes, bits), rewards, flags and
infos (``is_success`` as float32, its mask; SAME_STEP's ``final_obs`` dicts and
``final_info``). A fresh seed each run (``ENVC_LIVE_SEED`` if set) picks seeds and actions; it
is printed. AdroitHandDoor-v1 (no goal; a ``dtype = "bool"`` info key, ``success``) runs the
same way: its infos are numpy bools in the reference, so bool arrays in the vector env.
"""

from __future__ import annotations

import os
import random
import sys

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import envc

gymnasium_robotics = pytest.importorskip("gymnasium_robotics")
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "reference"))
import robotics_patch  # noqa: E402,F401

gym.register_envs(gymnasium_robotics)

LIVE_SEED = int(os.environ.get("ENVC_LIVE_SEED", random.SystemRandom().randrange(2**32)))
print(f"test_vector_goals: ENVC_LIVE_SEED={LIVE_SEED}")

ENV_ID = "FetchPush-v4"
ENV_IDS = [ENV_ID, "AdroitHandDoor-v1"]
NUM_ENVS = 4
STEPS = 120
MODES = [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP]


def same_tree(a, b, what: str, ordered: bool = True) -> None:
    """``a`` equals the reference ``b`` leaf by leaf: dict keys the same (in the same order where
    ``ordered``: observation dicts), arrays of the same dtype, shape and bytes, object arrays
    element by element (each ended env's observation dict, ordered)."""
    if isinstance(b, dict):
        assert isinstance(a, dict), f"{what}: {type(a)} vs reference dict"
        keys, ref_keys = (list(a), list(b)) if ordered else (sorted(a), sorted(b))
        assert keys == ref_keys, f"{what}: keys {list(a)} vs reference {list(b)}"
        for k in b:
            same_tree(a[k], b[k], f"{what}[{k!r}]", ordered)
        return
    if b is None:
        assert a is None, f"{what}: {a!r} vs reference None"
        return
    a, b = np.asarray(a), np.asarray(b)
    assert a.dtype == b.dtype, f"{what}: dtype {a.dtype} vs reference {b.dtype}"
    assert a.shape == b.shape, f"{what}: shape {a.shape} vs reference {b.shape}"
    if b.dtype == object:
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            same_tree(x, y, f"{what}[{i}]")
        return
    assert a.tobytes() == b.tobytes(), f"{what}: {a} vs reference {b}"


def reference(env_id: str, mode: AutoresetMode) -> gym.vector.SyncVectorEnv:
    return gym.vector.SyncVectorEnv(
        [lambda: gym.make(env_id, max_episode_steps=50) for _ in range(NUM_ENVS)],
        autoreset_mode=mode,
    )


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("mode", MODES, ids=lambda m: m.value)
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_matches_sync_vector_env_over_the_live_reference(env_id, mode, dtype):
    ref = reference(env_id, mode)
    envs = [
        envc.make_vec(env_id, NUM_ENVS, num_threads=t, autoreset_mode=mode, max_episode_steps=50)
        for t in (1, 2)
    ]
    for ours in envs:
        assert ours.single_observation_space == ref.single_observation_space
        assert ours.observation_space == ref.observation_space
        assert ours.single_action_space == ref.single_action_space
        assert ours.action_space == ref.action_space
    rng = np.random.default_rng(LIVE_SEED)
    seed = int(rng.integers(2**31))
    mask = np.array([True, False, True, False])
    resets = {
        0: lambda: {"seed": seed},
        70: lambda: {"seed": seed + 10, "options": {"reset_mask": mask.copy()}},
    }
    ended = finals = 0
    for t in range(STEPS):
        if t in resets:
            r = ref.reset(**resets[t]())
            for k, ours in enumerate(envs):
                o = ours.reset(**resets[t]())
                same_tree(o[0], r[0], f"reset {t} threads={k + 1} obs")
                same_tree(o[1], r[1], f"reset {t} threads={k + 1} info", ordered=False)
        low, high = ref.single_action_space.low, ref.single_action_space.high
        a = rng.uniform(1.2 * low, 1.2 * high, size=(NUM_ENVS, low.size)).astype(dtype)
        r = ref.step(a)
        for k, ours in enumerate(envs):
            what = f"{mode.value} {np.dtype(dtype)} threads={k + 1} step {t}"
            names = ("obs", "reward", "terminated", "truncated", "info")
            # An info's key order follows which env reported first in the reference.
            for name, x, y in zip(names, ours.step(a), r, strict=True):
                same_tree(x, y, f"{what} {name}", ordered=name != "info")
        ended += int(np.sum(r[2] | r[3]))
        finals += int("final_obs" in r[4])
    assert ended >= 2 * NUM_ENVS, f"only {ended} episodes ended"
    assert mode != AutoresetMode.SAME_STEP or finals >= 2
    for e in (*envs, ref):
        e.close()


def test_copy_false_reuses_the_goal_batches():
    env = envc.EnvcVectorEnv(ENV_ID, 2, copy=False)
    obs, _ = env.reset(seed=LIVE_SEED % 1000)
    again = env.step(np.zeros((2, 4)))[0]
    assert all(again[k] is obs[k] for k in obs)  # overwritten in place
    assert env.step(np.zeros((2, 4)))[0]["desired_goal"] is obs["desired_goal"]
    env.close()


def test_a_goal_of_named_parts_is_refused():
    with pytest.raises(envc.Error, match=r"E0602.*goal of named parts") as e:
        envc.make_vec("FrankaKitchen-v1", 2)
    assert e.value.code == "E0602"
