"""envc's Adroit v1 specs from Python against the live Gymnasium-Robotics 1.4.2 reference.

Every Adroit id that envc registers runs the same seed and actions through ``gymnasium.make(X)``
and ``gymnasium.make("envc/X")``: spaces, observations bitwise, rewards, ``success`` with its
numpy type, flags, and the reset after the 200-step time limit (whose model placements are drawn
again).

Seeds: a fixed one and a fresh one per run (``ENVC_LIVE_SEED`` if set), printed.
"""

from __future__ import annotations

import os
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import envc

gymnasium_robotics = pytest.importorskip("gymnasium_robotics")
gym.register_envs(gymnasium_robotics)

LIVE_SEED = int(os.environ.get("ENVC_LIVE_SEED", np.random.SeedSequence().entropy % 2**32))
print(f"test_adroit: live seed {LIVE_SEED} (set ENVC_LIVE_SEED to replay)")
IDS = [f"AdroitHand{t}{r}-v1" for t in ("Door", "Hammer", "Pen", "Relocate") for r in ("", "Sparse")]


def same(x, y) -> bool:
    """Equal bit for bit, numpy type included."""
    x, y = np.asarray(x), np.asarray(y)
    return x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()


@pytest.mark.parametrize("seed", [0, LIVE_SEED])
@pytest.mark.parametrize("env_id", IDS)
def test_adroit_matches_the_reference(env_id, seed):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = gym.make(env_id)
    ours = gym.make("envc/" + env_id)
    assert ours.observation_space == ref.observation_space
    assert ours.action_space == ref.action_space
    o1, i1 = ref.reset(seed=seed)
    o2, i2 = ours.reset(seed=seed)
    assert i1 == i2 == {}
    assert same(o1, o2)
    rng = np.random.default_rng(seed)
    resets = 0
    nu = ours.action_space.shape[0]
    for t in range(205):
        # Sampled float32 actions, and float64 ones beyond the bounds (the reference clips).
        a = ours.action_space.sample() if t % 2 else rng.uniform(-1.5, 1.5, nu)
        r1, r2 = ref.step(a), ours.step(a)
        assert same(r1[0], r2[0]), (env_id, seed, t)
        assert float(r1[1]).hex() == float(r2[1]).hex(), (env_id, seed, t, r1[1], r2[1])
        assert r1[2:4] == r2[2:4]
        assert list(r1[4]) == list(r2[4]) == ["success"]
        assert bool(r1[4]["success"]) == bool(r2[4]["success"])
        assert isinstance(r2[4]["success"], np.bool_)  # the reference: np.bool_ or bool
        if r1[2] or r1[3]:
            o1, _ = ref.reset()
            o2, _ = ours.reset()
            resets += 1
            assert same(o1, o2), (env_id, seed, "reset")
    assert resets == 1


def test_adroit_passes_gymnasiums_env_checker():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        check_env(gym.make("envc/AdroitHandDoor-v1").unwrapped, skip_render_check=True)


def test_adroit_sparse_is_registered_by_its_suffix():
    assert envc.make("AdroitHandDoorSparse-v1").unwrapped is not None
