"""``FrankaKitchen-v1`` (``specs/robotics/kitchen/kitchen.toml``) against the live
Gymnasium-Robotics 1.4.2 env, step by step under the same seed and actions: every leaf of the
observation dict (the goals are dicts of named parts), the reward, termination, truncation and
the three task lists of the info, bit for bit (the lists as sets: the reference keeps them in a
Python ``set``, whose order depends on string hashing).

The default threshold (0.3) is not reached by random actions, so the checklist is exercised by
running both envs with a larger one (``BONUS_THRESH`` is a module constant of the reference; the
spec's ``threshold`` is set to the same value), under which some tasks are done from the start.
"""

from __future__ import annotations

import os
import sys

import gymnasium as gym
import numpy as np
import pytest

import envc

gymnasium_robotics = pytest.importorskip("gymnasium_robotics")
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "reference"))
import robotics_patch  # noqa: E402,F401
from gymnasium_robotics.envs.franka_kitchen import kitchen_env  # noqa: E402

gym.register_envs(gymnasium_robotics)

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
SPEC = os.path.join(ROOT, "specs", "robotics", "kitchen", "kitchen.toml")
LIVE_SEED = int(os.environ.get("ENVC_LIVE_SEED", np.random.SeedSequence().entropy % 2**32))
ALL = list(kitchen_env.OBS_ELEMENT_GOALS)


def spec_with_threshold(tmp_path, threshold):
    text = open(SPEC).read()
    assert "\nthreshold = 0.3\n" in text
    p = tmp_path / "kitchen.toml"
    p.write_text(text.replace("\nthreshold = 0.3\n", f"\nthreshold = {threshold!r}\n"))
    return str(p)


def bits(x):
    return np.asarray(x, dtype=np.float64).view(np.uint64)


def same_obs(o, r):
    assert list(o) == ["observation", "achieved_goal", "desired_goal"]
    assert np.array_equal(bits(o["observation"]), bits(r["observation"]))
    for key in ("achieved_goal", "desired_goal"):
        assert list(o[key]) == list(r[key]), key
        for task in r[key]:
            assert np.array_equal(bits(o[key][task]), bits(r[key][task])), (key, task)


def same_info(i, r):
    assert set(i) == set(r)
    for key in ("tasks_to_complete", "step_task_completions", "episode_task_completions"):
        assert sorted(i[key]) == sorted(r[key]), (key, i[key], r[key])
        assert len(i[key]) == len(r[key])


def run(env, ref, seed, steps, rng):
    o, i = env.reset(seed=seed)
    r, ri = ref.reset(seed=seed)
    same_obs(o, r)
    same_info(i, ri)
    assert env.observation_space == ref.observation_space
    rewards, lists = [], set()
    for t in range(steps):
        a = rng.uniform(-1.2, 1.2, size=9)
        o, rew, term, trunc, i = env.step(a)
        r, rrew, rterm, rtrunc, ri = ref.step(a)
        same_obs(o, r)
        assert (rew, term, trunc) == (rrew, rterm, rtrunc), t
        assert type(rew) is type(rrew)
        same_info(i, ri)
        # compute_reward on this step's goals, against the list as it is now.
        got = env.unwrapped.compute_reward(o["achieved_goal"], o["desired_goal"], i)
        want = ref.unwrapped.compute_reward(r["achieved_goal"], r["desired_goal"], ri)
        assert got == want, t
        rewards.append(rew)
        lists.add(tuple(sorted(i["episode_task_completions"])))
        if term or trunc:
            break
    return rewards, lists, t + 1


@pytest.mark.parametrize("seed", [0, LIVE_SEED])
def test_default_tasks_bit_for_bit(seed):
    env = envc.make("FrankaKitchen-v1")
    ref = gym.make("FrankaKitchen-v1")
    rewards, _, n = run(env, ref, seed, 280, np.random.default_rng(seed))
    # The time limit ends it, unless random actions completed every task (never seen).
    assert n == 280 and len(rewards) == 280


@pytest.mark.parametrize(
    "kwargs",
    [
        {},
        {"tasks_to_complete": ["microwave", "kettle", "light switch"]},
        {"remove_task_when_completed": False, "terminate_on_tasks_completed": False},
        {"tasks_to_complete": ["hinge cabinet", "microwave"], "robot_noise_ratio": 0.1},
    ],
)
def test_checklist_bit_for_bit(tmp_path, monkeypatch, kwargs):
    monkeypatch.setattr(kitchen_env, "BONUS_THRESH", 0.9)
    env = envc.make(spec_with_threshold(tmp_path, 0.9), max_episode_steps=280, **kwargs)
    ref = gym.make("FrankaKitchen-v1", **kwargs)
    seed = LIVE_SEED
    rewards, lists, n = run(env, ref, seed, 60, np.random.default_rng(seed))
    # The checklist did something: tasks were completed and rewarded.
    assert max(rewards) >= 1.0
    assert any(lists)
    if kwargs.get("tasks_to_complete") == ["microwave", "kettle", "light switch"]:
        assert n == 1  # all three are within 0.9 of their goals at the start: terminated
    if "remove_task_when_completed" in kwargs:
        assert sum(r > 0 for r in rewards) > 1  # a task done stays rewarded


def test_bad_task_names_are_located_errors():
    with pytest.raises(envc.SpecError) as e:
        envc.make("FrankaKitchen-v1", tasks_to_complete=["microwav"])
    assert "E0105" in str(e.value) and "microwave" in str(e.value)
    with pytest.raises(envc.SpecError) as e:
        envc.make("FrankaKitchen-v1", tasks_to_complete=["kettle", "kettle"])
    assert "twice" in str(e.value)


def test_compute_reward_takes_batches_of_part_dicts():
    env = envc.make("FrankaKitchen-v1")
    o, _ = env.reset(seed=1)
    n = 256
    achieved = {k: np.repeat(v[None], n, axis=0) for k, v in o["achieved_goal"].items()}
    desired = {k: np.repeat(v[None], n, axis=0) for k, v in o["desired_goal"].items()}
    # Half the rows put the microwave at its goal: one task reached there.
    achieved["microwave"][::2] = desired["microwave"][::2]
    r = env.unwrapped.compute_reward(achieved, desired, None)
    assert r.shape == (n,) and list(r[:4]) == [1.0, 0.0, 1.0, 0.0]
    with pytest.raises(envc.ArgumentError):
        env.unwrapped.compute_reward({"kettle": achieved["kettle"]}, desired, None)
