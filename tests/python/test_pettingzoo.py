"""envc.parallel_env against the live reference, gymnasium_robotics.mamujoco_v1.parallel_env.

    PYTHONPATH=python .venv/bin/python -m pytest -q tests/python/test_pettingzoo.py

* PettingZoo's ``parallel_api_test`` on every bundled multi-agent spec.
* Bit-identity: the same seed and the same random per-agent actions through envc and the
  reference (a fixed set of scenario/conf/k cases plus a subset chosen by the run's seed), with a
  reset after every episode end; observations per agent and ``state()`` bitwise, rewards, flags
  and infos exactly; the spaces; the four mapping functions.
* Bad input raises.

The run's seed is ``ENVC_LIVE_SEED`` or a fresh one (printed; ``pytest -s`` shows it);
``ENVC_PZ_ALL=1`` runs every case of tests/reference/record_mamujoco.py instead of a sample.
"""

from __future__ import annotations

import os
import random
import sys

import numpy as np
import pytest
from pettingzoo.test import parallel_api_test

import envc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "reference"))
# The reference recorder's cases and reference constructors; importing it also patches the
# installed reference's CoupledHalfCheetah to read MuJoCo 3.17's sparse ten_J as the dense matrix
# it was written for (it crashes otherwise).
import numerics_profile  # noqa: E402
import record_mamujoco as rm  # noqa: E402
from gymnasium_robotics import mamujoco_v1  # noqa: E402

SEED = int(os.environ.get("ENVC_LIVE_SEED", random.SystemRandom().randrange(2**31)))
print(f"test_pettingzoo: seed {SEED} (set ENVC_LIVE_SEED={SEED} to repeat)")
PROFILE = numerics_profile.profile_name()
HAS_GO1 = os.path.isfile(rm.GO1_XML)


# -- envc and reference envs of one case ----------------------------------------------------------


def envc_env(scenario: str, conf: str, k: int, **kw):
    """The envc env of a recorder case, through the reference's scenario names where it has them."""
    if scenario == "Go1":
        kw.setdefault("xml_file", rm.GO1_XML)
        env = envc.parallel_env("go1_agents", conf, agent_obsk=k, **kw)
    elif conf == rm.SINGLE:
        env = envc.parallel_env(scenario, None, **kw)
    else:
        env = envc.parallel_env(scenario, conf, agent_obsk=k, **kw)
    env.numerics = PROFILE
    return env


def reference_env(scenario: str, conf: str, k: int, **kw):
    if not kw:
        return rm.make_env(scenario, conf, k)
    return mamujoco_v1.parallel_env(scenario, None if conf == rm.SINGLE else conf, agent_obsk=k, **kw)


def all_cases():
    out = []
    for _spec, scenario, confs in rm.SCENARIOS:
        if scenario == "Go1" and not HAS_GO1:
            continue
        out += [(scenario, c, k) for c in confs for k in rm.KS]
        if "{n}" not in _spec:
            out.append((scenario, rm.SINGLE, 0))
    return out


FIXED = [
    ("Ant", "2x4", 1, {}),
    ("Ant", "4x2", 2, {"max_episode_steps": 12}),  # two episode ends by the time limit
    ("HalfCheetah", "6x1", 0, {}),
    ("Hopper", "3x1", 1, {"max_episode_steps": 20}),
    ("Humanoid", "9|8", 1, {}),
    ("Reacher", "2x1", 2, {}),
    ("Pusher", "3p", 1, {}),
    ("InvertedPendulum", rm.SINGLE, 0, {}),
    ("CoupledHalfCheetah", "1p1", 1, {}),
    ("ManySegmentAnt", "2x3", 1, {}),
    ("ManySegmentSwimmer", "4x2", 1, {}),
    ("Walker2d", "2x3", 0, {"ctrl_cost_weight": 0.3}),
]
# ENVC_PZ_ALL=1: every recorder case (about 100, a few seconds more) instead of a sample.
SAMPLED = all_cases() if os.environ.get("ENVC_PZ_ALL") else random.Random(SEED).sample(all_cases(), 10)
CASES = FIXED + [(s, c, k, {}) for s, c, k in SAMPLED]


def case_id(case) -> str:
    s, c, k, kw = case
    return f"{s}-{c}-k{k}" + "".join(f"-{a}={b}" for a, b in kw.items())


# -- comparisons ------------------------------------------------------------------------------------


def same_array(got, want) -> bool:
    got, want = np.asarray(got), np.asarray(want)
    return got.dtype == want.dtype and got.shape == want.shape and got.tobytes() == want.tobytes()


def same_obs(scenario: str, agent: str, got, want) -> bool:
    if same_array(got, want):
        return True
    # Pusher agent_0: the reference orders its two nodes labelled "r_wrist_roll_joint" by object
    # address (a set), so either order is the reference's.
    if scenario == "Pusher" and agent == "agent_0":
        sw = np.array(got)
        sw[[2, 3, 4, 5]] = got[[4, 5, 2, 3]]
        return same_array(sw, want)
    return False


# Single-agent mode with float32 actions: CoupledHalfCheetah's reward adds its two float32 control
# costs in float32 before halving; envc's spec (weights 0.05) adds the halves in float64.
F32_GAPS = {("CoupledHalfCheetah", rm.SINGLE)}
# Info keys envc does not reproduce (specs/mamujoco/coupled_half_cheetah.toml says why).
INFO_GAPS = {"CoupledHalfCheetah": {"reward_run", "reward_ctrl1", "reward_ctrl2"}}


def assert_same_info(got: dict, want: dict, where: str, gaps=frozenset()):
    want = {key: w for key, w in want.items() if key not in gaps}
    assert set(got) == set(want), f"{where}: info keys {sorted(got)} != {sorted(want)}"
    for key, w in want.items():
        g = got[key]
        if np.ndim(w) == 0:
            assert np.float64(g).tobytes() == np.float64(w).tobytes(), f"{where}: info[{key}] {g!r} != {w!r}"
        else:
            assert same_array(np.asarray(g, dtype=np.float64), np.asarray(w, dtype=np.float64)), f"{where}: info[{key}]"


def assert_same_spaces(ours, ref, scenario):
    assert ours.possible_agents == ref.possible_agents
    for a in ref.possible_agents:
        for mine, theirs in ((ours.action_space(a), ref.action_space(a)), (ours.observation_space(a), ref.observation_space(a))):
            assert mine.shape == theirs.shape and mine.dtype == theirs.dtype, (a, mine, theirs)
            if scenario == "Go1" and mine is ours.action_space(a):
                continue  # go1_agents.toml keeps each actuator's range (no "first_element" bounds)
            assert same_array(mine.low, theirs.low) and same_array(mine.high, theirs.high), (a, mine, theirs)


# -- the tests ------------------------------------------------------------------------------------


AGENT_IDS = envc.bundled_ids("agents")


def test_bundled_ids_cover_every_scenario():
    assert len(AGENT_IDS) >= 50
    from envc import _pettingzoo

    for scenario, spec_id in _pettingzoo._SCENARIOS.items():
        assert spec_id in AGENT_IDS, scenario


@pytest.mark.parametrize("spec_id", AGENT_IDS)
def test_parallel_api(spec_id):
    kw = {"xml_file": rm.GO1_XML} if spec_id == "go1_agents" else {}
    if kw and not HAS_GO1:
        pytest.skip("no Go1 model")
    env = envc.parallel_env(spec_id, **kw)
    parallel_api_test(env, num_cycles=8)
    assert env.state().shape == env.state_space.shape
    env.close()


def test_parallel_api_through_episode_ends():
    """A time limit of 5 steps: the API test sees every agent truncated and the env reset."""
    env = envc.parallel_env("Hopper", "3x1", max_episode_steps=5)
    parallel_api_test(env, num_cycles=10)
    obs, _ = env.reset(seed=1)
    for t in range(5):
        _, _, term, trunc, _ = env.step({a: env.action_space(a).sample() * 0 for a in env.possible_agents})
        if t < 4:
            assert env.agents == env.possible_agents
    assert trunc == {a: True for a in env.possible_agents} and env.agents == []


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_bit_identical_to_mamujoco(case):
    scenario, conf, k, kw = case
    steps = 40
    ours, ref = envc_env(scenario, conf, k, **kw), reference_env(scenario, conf, k, **kw)
    assert_same_spaces(ours, ref, scenario)
    rng = np.random.default_rng(SEED + 17)
    seed = int(rng.integers(2**31))
    got, want = ours.reset(seed=seed), ref.reset(seed=seed)
    resets = 0
    for t in range(steps + 1):
        where = f"{case_id(case)} seed {seed} step {t}"
        for a in ref.possible_agents:
            assert same_obs(scenario, a, got[0][a], want[0][a]), f"{where}: obs[{a}]"
            assert_same_info(got[-1][a], want[-1][a], where, INFO_GAPS.get(scenario, set()))
        assert same_array(ours.state(), ref.state()), f"{where}: state"
        assert ours.agents == ref.agents, where
        if len(got) == 5:  # a step's (obs, rewards, terminations, truncations, infos)
            for d in range(1, 4):
                assert {a: float(v) for a, v in got[d].items()} == {a: float(v) for a, v in want[d].items()}, (where, d)
            if not ref.agents:
                got, want = ours.reset(), ref.reset()
                resets += 1
                continue
        if t == steps:
            break
        # float32 (as action_space.sample() gives) and float64 actions in turn: single-agent mode
        # hands them to the task as given, with float32 or float64 control costs.
        dtype = np.float32 if t % 2 == 0 and (scenario, conf) not in F32_GAPS else np.float64
        actions = {
            a: rng.uniform(ref.action_space(a).low, ref.action_space(a).high).astype(dtype)
            for a in ref.possible_agents
        }
        got, want = ours.step(actions), ref.step(actions)
    if "max_episode_steps" in kw or scenario == "InvertedPendulum":
        assert resets >= 1  # episode ends by the time limit, or by termination
    ours.close()
    ref.close()


def test_stepping_past_the_time_limit_matches_mamujoco():
    """Both keep stepping after the episode ends, truncated on every later step (TimeLimit)."""
    ours, ref = envc_env("Hopper", "3x1", 1, max_episode_steps=3), reference_env("Hopper", "3x1", 1, max_episode_steps=3)
    ours.reset(seed=SEED)
    ref.reset(seed=SEED)
    rng = np.random.default_rng(SEED)
    for t in range(6):
        actions = {a: rng.uniform(-1, 1, size=1) for a in ref.possible_agents}
        got, want = ours.step(actions), ref.step(actions)
        for a in ref.possible_agents:
            assert same_array(got[0][a], want[0][a]), (t, a)
        assert got[1:4] == want[1:4] and ours.agents == ref.agents, t
        assert got[3]["agent_0"] == (t >= 2)


# Where the reference's index map does not give the agents' observations, envc has no map and
# raises ValueError (an agent observes a value the state does not hold).
REFERENCE_MAP_WRONG = {
    "Walker2d": "the state clips qvel to [-10, 10], the agents observe it raw",
    "ManySegmentAnt": "v1's wrong qpos ids read the skipped x, y, which the reference maps to state[0]",
}


def attempt(f):
    """``(value, None)`` or ``(None, exception)``."""
    try:
        return f(), None
    except (AssertionError, ValueError) as e:
        return None, e


@pytest.mark.parametrize("case", CASES[:8] + CASES[len(FIXED) - 3:], ids=case_id)
def test_mappings_match_mamujoco(case):
    scenario, conf, k, kw = case
    ours, ref = envc_env(scenario, conf, k, **kw), reference_env(scenario, conf, k, **kw)
    rng = np.random.default_rng(SEED + 29)
    ours.reset(seed=3)
    ref.reset(seed=3)
    g = rng.uniform(-0.4, 0.4, size=ref.single_agent_env.action_space.shape)
    for x in (g, g.astype(np.float32)):
        mine, theirs = ours.map_global_action_to_local_actions(x), ref.map_global_action_to_local_actions(x)
        assert mine.keys() == theirs.keys()
        for a in theirs:
            assert same_array(mine[a], theirs[a]), a
        mine, theirs = ours.map_local_actions_to_global_action(theirs), ref.map_local_actions_to_global_action(theirs)
        assert same_array(mine, np.asarray(theirs)), "local → global action"
    local = ref.map_global_action_to_local_actions(g)
    obs = ours.step(local)[0]
    ref_obs = ref.step(local)[0]
    state = ref.state()
    assert same_array(ours.state(), state)

    theirs, ref_err = attempt(lambda: ref.map_global_state_to_local_observations(state))
    mine, err = attempt(lambda: ours.map_global_state_to_local_observations(state))
    if mine is None:
        assert isinstance(err, ValueError)
        assert theirs is None or scenario in REFERENCE_MAP_WRONG, err
    else:
        if theirs is not None:
            for a in theirs:
                assert same_obs(scenario, a, mine[a], theirs[a]), a
        else:  # the reference has no map (its task has no observation_structure); envc has one
            assert isinstance(ref_err, AssertionError)
        for a in obs:
            assert same_array(mine[a], obs[a]), f"envc's map disagrees with its observation of {a}"

    theirs, ref_err = attempt(lambda: ref.map_local_observations_to_global_state(ref_obs))
    mine, err = attempt(lambda: ours.map_local_observations_to_global_state(obs))
    if theirs is not None and scenario not in REFERENCE_MAP_WRONG:
        assert same_array(mine, theirs)
    if mine is None:
        assert isinstance(err, ValueError)
        assert theirs is None or scenario in REFERENCE_MAP_WRONG, err
    else:
        assert same_array(mine, state)
    ours.close()
    ref.close()


def test_reference_maps_wrong_where_envc_refuses():
    """The reference's index map gives values the agents do not observe (envc raises instead)."""
    ref = reference_env("Walker2d", "2x3", 1)
    ref.reset(seed=1)
    u = ref.single_agent_env.unwrapped
    u.set_state(u.data.qpos, u.data.qvel + 20.0)
    mapped, actual = ref.map_global_state_to_local_observations(ref.state()), ref._get_obs()
    assert not np.array_equal(mapped["agent_0"], actual["agent_0"])
    ref = reference_env("ManySegmentAnt", "2x3", 1)
    ref.reset(seed=1)
    mapped, actual = ref.map_global_state_to_local_observations(ref.state()), ref._get_obs()
    assert not all(np.array_equal(mapped[a], actual[a]) for a in actual)
    for scenario, conf in (("Walker2d", "2x3"), ("ManySegmentAnt", "2x3")):
        env = envc.parallel_env(scenario, conf)
        env.reset(seed=1)
        with pytest.raises(ValueError, match="not in the state"):
            env.map_global_state_to_local_observations(env.state())


def test_scenario_names_map_to_specs():
    env = envc.parallel_env("ManySegmentAnt", "2x3")
    assert (env.spec_id, env.agent_conf, env.agent_obsk) == ("MaMuJoCo-ManySegmentAnt6-v1", "2x3", 1)
    env = envc.parallel_env("Ant", None)
    assert env.possible_agents == ["agent_0"] and env.agent_conf == "none"
    assert envc.parallel_env("Ant", "2x4", agent_obsk=None).possible_agents == ["agent_0"]
    env = envc.parallel_env(os.path.join(ROOT, "specs", "mamujoco", "ant.toml"), agent_obsk=2)
    assert (env.spec_id, env.agent_conf, env.agent_obsk) == ("MaMuJoCo-Ant-v1", "2x4", 2)
    assert envc.parallel_env("MaMuJoCo-Humanoid-v2").agent_conf == "9|8"
    assert "MaMuJoCo" in repr(env) and env.metadata["is_parallelizable"]


def test_bad_input_raises():
    with pytest.raises(envc.SpecError):
        envc.parallel_env("Ant", "3x7")
    with pytest.raises(ValueError, match="NxM"):
        envc.parallel_env("ManySegmentAnt", None)
    with pytest.raises(envc.SpecError):
        envc.parallel_env("NoSuchScenario", "2x4")
    with pytest.raises(TypeError):
        envc.parallel_env("Ant", "2x4", no_such_parameter=1)
    with pytest.raises(TypeError, match="spec content"):
        envc.parallel_env("Ant", "2x4", agent_factorization={})
    with pytest.raises(TypeError, match="envc.make"):
        envc.parallel_env("Ant-v5")
    with pytest.raises(ValueError, match="render"):
        envc.parallel_env("Ant", "2x4", render_mode="human")
    with pytest.raises(ValueError, match="agent_obsk"):
        envc.parallel_env("Ant", "2x4", agent_obsk=-1)

    env = envc.parallel_env("Ant", "2x4")
    zero = {a: np.zeros(4) for a in env.possible_agents}
    with pytest.raises(RuntimeError):
        env.step(zero)
    with pytest.raises(ValueError):
        env.reset(seed=-1)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="agent_1"):
        env.step({"agent_0": np.zeros(4)})
    with pytest.raises(ValueError, match="unknown"):
        env.step({**zero, "agent_9": np.zeros(4)})
    with pytest.raises(ValueError):
        env.step({**zero, "agent_0": np.zeros(3)})
    with pytest.raises(ValueError):
        env.step({**zero, "agent_0": np.zeros((2, 2))})
    with pytest.raises(ValueError):
        env.step({**zero, "agent_0": np.array([0.0, np.nan, 0.0, 0.0])})
    with pytest.raises(ValueError):
        env.step({**zero, "agent_0": ["a", "b", "c", "d"]})
    with pytest.raises(ValueError):
        env.step([np.zeros(4), np.zeros(4)])
    with pytest.raises(ValueError):
        env.map_global_action_to_local_actions(np.zeros(7))
    with pytest.raises(ValueError):
        env.map_global_state_to_local_observations(np.zeros(3))
    obs = env.step(zero)[0]
    with pytest.raises(ValueError, match="disagree"):
        env.map_local_observations_to_global_state({**obs, "agent_0": obs["agent_0"] + 1.0})
    env.close()
    with pytest.raises(RuntimeError, match="closed"):
        env.reset()
    with pytest.raises(RuntimeError, match="closed"):
        env.state()


def test_color_agents_changes_the_picture_only():
    """`color_agents` tints each agent's limbs; observations stay MaMuJoCo's, and switching it
    off gives MaMuJoCo's frame back."""
    env = envc.parallel_env("Ant", "2x4", render_mode="rgb_array", width=96, height=72)
    obs, _ = env.reset(seed=0)
    plain = env.render()
    env.color_agents(True)
    tinted = env.render()
    env.color_agents(False)
    assert np.array_equal(env.render(), plain)
    assert tinted.shape == plain.shape and not np.array_equal(tinted, plain)
    obs_again, _ = env.reset(seed=0)
    for a in env.possible_agents:
        assert np.array_equal(obs[a], obs_again[a])
    env.close()


def test_non_numeric_agent_actions_are_refused_not_coerced():
    env = envc.parallel_env("Ant", "2x4")
    env.reset(seed=0)
    for bad in (np.array(["0"] * 4), np.zeros(4, "datetime64[s]"), np.zeros(4, dtype=object)):
        with pytest.raises(ValueError, match="not numeric"):
            env.step({a: bad for a in env.possible_agents})
    env.step({a: np.zeros(4) for a in env.possible_agents})
