"""envc's task envs through Python against the reference, live.

Every bundled single-agent id that Gymnasium also registers (the v5 and v4 MuJoCo suites) runs
through ``gymnasium.make("X")`` and ``gymnasium.make("envc/X")`` with the same seed and actions:
float64 and float32 arrays, lists, out-of-bound values, auto-reset continuation. Observations are
compared bit for bit, rewards, flags and infos exactly. The seed is fresh every run
(``ENVC_LIVE_SEED`` repeats one) and printed.
"""

from __future__ import annotations

import os
import random
import warnings

import gymnasium as gym
import numpy as np
import pytest

import envc

SEED = int(os.environ.get("ENVC_LIVE_SEED", random.randrange(2**31)))
print(f"test_gymnasium: seed {SEED} (ENVC_LIVE_SEED={SEED} repeats this run)")

# Goal-conditioned tasks (dict observations; Gymnasium-Robotics' Fetch) have their own live
# check against the patched reference: tests/python/test_fetch.py.
TASKS = [
    i
    for i in envc.bundled_ids("task")
    if i in gym.registry and not isinstance(envc.make(i).observation_space, gym.spaces.Dict)
]


def _actions(space: gym.spaces.Box, rng: np.random.Generator, n: int) -> list:
    """Random actions in several forms: in and out of bounds, float64, float32 and lists."""
    low, high = space.low.astype(np.float64), space.high.astype(np.float64)
    out = []
    for k in range(n):
        a = rng.uniform(low * 1.3, high * 1.3)
        form = k % 4
        if form == 1:
            a = a.astype(np.float32)
        elif form == 2:
            a = a.tolist()
        out.append(a)
    return out


def _same_info(ref: dict, ours: dict, where: str) -> None:
    assert sorted(ref) == sorted(ours), f"{where}: info keys {sorted(ref)} != {sorted(ours)}"
    for k, v in ref.items():
        assert np.array_equal(np.asarray(v), np.asarray(ours[k])), f"{where}: info[{k!r}] {v} != {ours[k]}"


def _rollout_pair(env_id: str, seed: int, steps: int, **kwargs) -> int:
    """Step the reference and envc side by side; returns the number of resets seen."""
    try:
        ref = gym.make(env_id, **kwargs)
    except ImportError as e:  # Pusher-v4 refuses mujoco>=3 in the reference itself
        pytest.skip(f"the reference cannot build {env_id}: {e}")
    ours = gym.make(f"envc/{env_id}", **kwargs)
    assert ours.observation_space == ref.observation_space
    assert ours.action_space == ref.action_space
    assert ours.spec.max_episode_steps == ref.spec.max_episode_steps
    assert ours.spec.reward_threshold == ref.spec.reward_threshold
    assert ours.metadata["render_fps"] == ref.metadata["render_fps"]
    rng = np.random.default_rng(seed)
    o1, i1 = ref.reset(seed=seed)
    o2, i2 = ours.reset(seed=seed)
    assert np.array_equal(o1, o2), f"{env_id} reset obs"
    _same_info(i1, i2, f"{env_id} reset")
    resets = 0
    for t, a in enumerate(_actions(ref.action_space, rng, steps)):
        r1 = ref.step(a)
        r2 = ours.step(a)
        where = f"{env_id} seed {seed} step {t}"
        assert np.array_equal(r1[0], r2[0]), f"{where}: obs"
        assert r1[1] == r2[1], f"{where}: reward {r1[1]} != {r2[1]}"
        assert (r1[2], r1[3]) == (r2[2], r2[3]), f"{where}: flags"
        _same_info(r1[4], r2[4], where)
        if r1[2] or r1[3]:
            resets += 1
            o1, i1 = ref.reset()
            o2, i2 = ours.reset()
            assert np.array_equal(o1, o2), f"{where}: auto-reset obs"
            _same_info(i1, i2, f"{where} reset")
    ref.close()
    ours.close()
    return resets


@pytest.mark.parametrize("env_id", TASKS)
def test_bit_identical_to_the_reference(env_id):
    assert len(TASKS) >= 22
    _rollout_pair(env_id, SEED, 120)


def test_time_limit_and_auto_reset_continue_identically():
    # Reacher truncates at 50, Hopper terminates early: both cross several episodes.
    assert _rollout_pair("Reacher-v5", SEED + 1, 130) >= 2
    assert _rollout_pair("Hopper-v5", SEED + 2, 300) >= 1


def test_overrides_are_python_values():
    kw = dict(
        ctrl_cost_weight=0.2,
        healthy_z_range=(0.3, 1.1),
        terminate_when_unhealthy=False,
        reset_noise_scale=0.05,
        max_episode_steps=40,
    )
    assert _rollout_pair("Ant-v5", SEED + 3, 90, **kw) >= 2


def _check_env_warnings(env_id: str) -> list[str]:
    from gymnasium.utils.env_checker import check_env

    env = gym.make(env_id)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        check_env(env.unwrapped, skip_render_check=True)
        env.reset(seed=0)
        env.step(env.action_space.sample())
    env.close()
    return sorted({str(x.message) for x in w if "out of date" not in str(x.message)})


@pytest.mark.parametrize("env_id", TASKS)
def test_check_env_passes_with_no_warning_beyond_the_references(env_id):
    # The reference's own spaces draw check_env's "-infinity" warnings; envc must add none.
    ours = _check_env_warnings(f"envc/{env_id}")
    try:
        ref = _check_env_warnings(env_id)
    except ImportError as e:  # Pusher-v4 refuses mujoco>=3 in the reference itself
        pytest.skip(f"the reference cannot build {env_id}: {e}")
    assert ours == ref


def test_parameter_errors_say_which_and_why():
    with pytest.raises(TypeError, match="ctrl_cost_weight"):
        gym.make("envc/Ant-v5", ctrl_cost_wieght=0.1)
    with pytest.raises(envc.SpecError) as e:
        gym.make("envc/Hopper-v5", frame_skip=0)
    assert isinstance(e.value, ValueError) and "frame_skip" in str(e.value)
    assert e.value.code.startswith("E")
    with pytest.raises(ValueError):
        gym.make("envc/Hopper-v5", healthy_z_range=object())
    with pytest.raises(envc.SpecError) as e:
        envc.make("Ant-v55")
    assert e.value.code == "E0601" and "Ant-v5" in str(e.value)


def test_bad_actions_raise_not_crash():
    env = gym.make("envc/Hopper-v5").unwrapped
    with pytest.raises(RuntimeError):
        env.step(np.zeros(3))  # before reset
    env.reset(seed=0)
    with pytest.raises(ValueError):
        env.step(np.zeros(4))
    with pytest.raises(ValueError):
        env.step(np.zeros((1, 3)))
    with pytest.raises(ValueError):
        env.step(np.array([0.0, np.nan, 0.0]))
    with pytest.raises((ValueError, TypeError)):
        env.step(np.array(["a", "b", "c"]))
    env.close()
    with pytest.raises(RuntimeError):
        env.step(np.zeros(3))


def test_a_spec_file_of_ones_own(tmp_path):
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    text = open(os.path.join(root, "specs", "gymnasium", "hopper.toml")).read()
    assets = os.path.abspath(os.path.join(root, "assets"))
    text = text.replace("../../assets/", assets + "/").replace('"Hopper-v5"', '"MyHopper-v0"')
    p = tmp_path / "my_hopper.toml"
    p.write_text(text)
    ours = envc.make(str(p), frame_skip=4)
    ref = gym.make("Hopper-v5")
    assert ours.spec.id == "envc/MyHopper-v0"
    o1, _ = ref.reset(seed=5)
    o2, _ = ours.reset(seed=5)
    assert np.array_equal(o1, o2)
    a = np.full(3, 0.3)
    assert ref.step(a)[1] == ours.step(a)[1]


def test_a_spec_file_whose_default_model_is_elsewhere_opens_with_xml_file():
    # specs/examples/go1_joystick.toml defaults to a Menagerie checkout that is not here; the
    # model given as `xml_file=` must be enough for envc.make and envc.make_vec alike.
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    spec = os.path.join(root, "specs", "examples", "go1_joystick.toml")
    xml = os.path.abspath(os.path.join(root, "..", "shared", "models", "unitree_go1", "scene.xml"))
    if not os.path.isfile(xml):
        pytest.skip(f"the shared Go1 model is not at {xml}")
    env = envc.make(spec, xml_file=xml)
    assert env.spec.id == "envc/Go1Joystick-v0"
    obs, _ = env.reset(seed=3)
    assert obs.shape == (48,)
    assert np.isfinite(env.step(np.zeros(12))[1])
    venv = envc.make_vec(spec, num_envs=2, xml_file=xml)
    vobs, _ = venv.reset(seed=3)
    assert np.array_equal(vobs[0], obs)
    venv.close()
    with pytest.raises(envc.SpecError):
        envc.make(spec)  # without it: the missing default model, as a spec error
