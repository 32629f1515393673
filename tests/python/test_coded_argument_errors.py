"""Calls of the wrong kind or with arguments that cannot work raise envc's coded errors (still the
`TypeError` they were before), never a bare builtin exception without a code."""

import os

import gymnasium as gym
import pytest

import envc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_making_a_single_agent_env_of_a_multi_agent_spec_is_a_kind_error():
    with pytest.raises(envc.KindError) as e:
        envc.make(os.path.join(ROOT, "specs", "mamujoco", "ant.toml"))
    assert e.value.code == "E0602"
    assert isinstance(e.value, TypeError)
    assert "envc.parallel_env" in str(e.value)


def test_a_maze_map_given_twice_is_an_argument_error():
    with pytest.raises(envc.ArgumentError) as e:
        gym.make("envc/PointMaze_UMaze-v3", maze_map=[[1, 1, 1]], map="[[1, 1, 1]]")
    assert e.value.code == "E1105"
    assert isinstance(e.value, TypeError)


def test_parallel_env_refuses_a_scenario_of_the_wrong_type_and_spec_content_with_e1105():
    with pytest.raises(envc.ArgumentError) as e:
        envc.parallel_env(3, "2x4")
    assert e.value.code == "E1105" and isinstance(e.value, TypeError)
    with pytest.raises(envc.ArgumentError, match="spec content") as e:
        envc.parallel_env("Ant", "2x4", agent_factorization={})
    assert e.value.code == "E1105" and isinstance(e.value, TypeError)
