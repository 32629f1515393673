"""envc's goal-conditioned robotics specs from Python against the live Gymnasium-Robotics 1.4.2
reference.

Every Fetch v4 id (Reach, Push, Slide, PickAndPlace; sparse and dense) and every Shadow Hand id
envc registers (``HandReach-v3``, the ``HandManipulate`` block and egg ids; sparse and dense) runs
the same seed and actions
through ``gymnasium.make(X)`` and ``gymnasium.make("envc/X")``: spaces, dict observations bitwise,
rewards and ``is_success`` with their numpy types, flags, the auto-reset continuation after the
time limit, and ``compute_reward`` on batches and single goals (as hindsight relabelling calls it).
The reference needs one fix on MuJoCo 3.17 (tests/reference/robotics_patch.py).

Seeds: a fixed one and a fresh one per run (``ENVC_LIVE_SEED`` if set), printed.
"""

from __future__ import annotations

import os
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import envc

gymnasium_robotics = pytest.importorskip("gymnasium_robotics")
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "reference"))
import robotics_patch  # noqa: E402,F401

gym.register_envs(gymnasium_robotics)

LIVE_SEED = int(os.environ.get("ENVC_LIVE_SEED", np.random.SeedSequence().entropy % 2**32))
print(f"test_robotics: live seed {LIVE_SEED} (set ENVC_LIVE_SEED to replay)")
IDS = [f"Fetch{t}{r}-v4" for t in ("Reach", "Push", "Slide", "PickAndPlace") for r in ("", "Dense")]
IDS += [f"HandReach{r}-v3" for r in ("", "Dense")]
IDS += [f"HandManipulateBlock{v}{r}-v1" for v in ("", "Full", "RotateZ", "RotateXYZ", "RotateParallel") for r in ("", "Dense")]
IDS += [f"HandManipulate{o}{v}{r}-v1" for o in ("Egg", "Pen") for v in ("", "Full", "Rotate") for r in ("", "Dense")]
IDS += [f"HandManipulate{o}_{t}TouchSensors{r}-v1" for o in ("Block", "BlockRotateParallel", "EggRotate", "Pen")
        for t in ("Continuous", "Boolean") for r in ("", "Dense")]


def same(x, y) -> bool:
    """Equal bit for bit, numpy type included."""
    x, y = np.asarray(x), np.asarray(y)
    return x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()


@pytest.mark.parametrize("seed", [0, LIVE_SEED])
@pytest.mark.parametrize("env_id", IDS)
def test_robotics_matches_the_reference(env_id, seed):
    ref, ours = gym.make(env_id), gym.make("envc/" + env_id)
    assert ours.observation_space == ref.observation_space
    assert ours.action_space == ref.action_space
    o1, i1 = ref.reset(seed=seed)
    o2, i2 = ours.reset(seed=seed)
    assert i1 == i2 == {}
    assert list(o1) == list(o2)
    rng = np.random.default_rng(seed)
    resets = 0
    for t in range(2 * ref.spec.max_episode_steps + 10):
        # Sampled float32 actions, and float64 ones beyond the bounds (the reference clips).
        a = ours.action_space.sample() if t % 2 else rng.uniform(-1.5, 1.5, ours.action_space.shape)
        r1, r2 = ref.step(a), ours.step(a)
        for k in o1:
            assert same(r1[0][k], r2[0][k]), (env_id, seed, t, k)
        assert same(r1[1], r2[1]), (env_id, t, r1[1], r2[1])
        assert r1[2:4] == r2[2:4]
        assert list(r1[4]) == list(r2[4]) == ["is_success"]
        assert same(r1[4]["is_success"], r2[4]["is_success"])
        if r1[2] or r1[3]:
            o1, _ = ref.reset()
            o2, _ = ours.reset()
            resets += 1
            for k in o1:
                assert same(o1[k], o2[k]), (env_id, seed, "reset", k)
    assert resets == 2
    k = r1[0]["desired_goal"].shape[0]
    g = rng.uniform(-0.2, 0.2, (256, k)) + r1[0]["desired_goal"]
    d = g + rng.normal(0, 0.04 if k == 3 else 0.004, (256, k))
    d[:4] = g[:4]
    u1, u2 = ref.unwrapped, ours.unwrapped
    if "Pen" in env_id:
        # The pen reference's batched compute_reward replaces only row 2's Z angle
        # (`euler_a[2] = euler_b[2]` on a batch); envc's equals the step reward row by row.
        rows = np.array([u1.compute_reward(g[i], d[i], {}) for i in range(len(g))])
        assert same(rows, u2.compute_reward(g, d, {}))
    else:
        assert same(u1.compute_reward(g, d, {}), u2.compute_reward(g, d, {}))
    assert same(u1.compute_reward(g[5], d[5], {}), u2.compute_reward(g[5], d[5], {}))
    g3, d3 = g.reshape(16, 16, k), d.reshape(16, 16, k)
    try:
        r3 = u1.compute_reward(g3, d3, {})
    except AssertionError:
        # The hand manipulation reference's quat_mul takes 1-D and 2-D goals only.
        r3 = None
    if r3 is not None:
        assert same(r3, u2.compute_reward(g3, d3, {}))


@pytest.mark.parametrize("env_id", ["FetchPickAndPlace-v4", "HandReach-v3", "HandManipulateEgg-v1"])
def test_robotics_passes_gymnasiums_env_checker(env_id):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        check_env(gym.make("envc/" + env_id).unwrapped, skip_render_check=True)


def test_compute_reward_refuses_a_task_without_goal():
    env = envc.make("Reacher-v5")
    with pytest.raises(envc.SpecError) as e:
        env.unwrapped.compute_reward(np.zeros(3), np.zeros(3), {})
    assert e.value.code == "E0170"


def test_compute_reward_shapes_are_checked():
    env = envc.make("FetchReach-v4")
    with pytest.raises(ValueError):
        env.unwrapped.compute_reward(np.zeros((4, 2)), np.zeros((4, 2)), {})


def test_a_fetch_dataset_is_minaris_dict_and_replays_in_the_reference(tmp_path, monkeypatch):
    """``envc.collect`` of a goal task writes the dict observation (keys sorted, as Minari's
    DataCollector does); minari loads it, and the reference env ``recover_environment`` makes
    replays every episode's actions to the same observations, rewards and ``is_success``."""
    minari = pytest.importorskip("minari")
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path))
    envc.collect("FetchPickAndPlace-v4", "tests/fetch-v0", 2, seed=LIVE_SEED % 1000, root=tmp_path,
                 policy="random")
    ds = minari.load_dataset("tests/fetch-v0")
    assert list(ds.observation_space.spaces) == ["achieved_goal", "desired_goal", "observation"]
    env = ds.recover_environment()
    for k, ep in enumerate(ds.iterate_episodes()):
        obs, _ = env.reset(seed=(LIVE_SEED % 1000) + k)
        for key in obs:
            assert same(obs[key], ep.observations[key][0]), (k, key)
        for t, a in enumerate(ep.actions):
            obs, r, *_, info = env.step(a)
            for key in obs:
                assert same(obs[key], ep.observations[key][t + 1]), (k, t, key)
            assert r == ep.rewards[t]
            assert info["is_success"] == ep.infos["is_success"][t + 1]
