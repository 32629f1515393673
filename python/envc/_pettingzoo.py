"""Multi-agent specs as PettingZoo ``ParallelEnv``: ``envc.parallel_env`` and its env class.

``envc.parallel_env("Ant", "2x4", agent_obsk=1)`` is a drop-in for
``gymnasium_robotics.mamujoco_v1.parallel_env("Ant", "2x4", agent_obsk=1)``: the same agents,
spaces, observations, rewards, flags and infos, bit for bit under the same seeds and actions
(tests/python/test_pettingzoo.py). Known gaps: CoupledHalfCheetah's info lacks reward_run,
reward_ctrl1 and reward_ctrl2, and its single-agent mode with float32 actions rounds the control
cost differently (specs/mamujoco/coupled_half_cheetah.toml). Where the reference's
``map_global_state_to_local_observations`` returns values the agents do not observe (Walker2d's
clipped qvel, ManySegmentAnt v1's wrong ids), envc raises ``ValueError`` instead.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, cast

import gymnasium
import numpy as np
import pettingzoo

from . import _envc, _errors
from ._core_env import CoreEnv, _Closed
from ._gym import (
    RENDER_MODES,
    _fps,
    check_render_mode,
    overrides_to_toml,
    render_overrides,
)

if TYPE_CHECKING:
    from ._envc import _F64, _Frame, _RenderMode

# MaMuJoCo v1 scenario names → bundled envc ids. The ManySegment scenarios have one spec per
# segment count n = N·M of their agent_conf "NxM".
_SCENARIOS = {
    "Ant": "MaMuJoCo-Ant-v1",
    "HalfCheetah": "MaMuJoCo-HalfCheetah-v1",
    "Hopper": "MaMuJoCo-Hopper-v1",
    "HumanoidStandup": "MaMuJoCo-HumanoidStandup-v1",
    "Humanoid": "MaMuJoCo-Humanoid-v1",
    "Reacher": "MaMuJoCo-Reacher-v1",
    "Swimmer": "MaMuJoCo-Swimmer-v1",
    "Pusher": "MaMuJoCo-Pusher-v1",
    "Walker2d": "MaMuJoCo-Walker2d-v1",
    "InvertedPendulum": "MaMuJoCo-InvertedPendulum-v1",
    "InvertedDoublePendulum": "MaMuJoCo-InvertedDoublePendulum-v1",
    "CoupledHalfCheetah": "MaMuJoCo-CoupledHalfCheetah-v1",
}
_MANY_SEGMENT = {
    "ManySegmentAnt": "MaMuJoCo-ManySegmentAnt{n}-v1",
    "ManySegmentSwimmer": "MaMuJoCo-ManySegmentSwimmer{n}-v1",
}
# Arguments of the reference's constructor that envc takes from the spec instead.
_SPEC_CONTENT = ("agent_factorization", "local_categories", "global_categories", "gym_env")
_SINGLE_AGENT = "none"


def _segments(scenario: str, agent_conf: str | None) -> int:
    try:
        n, m = agent_conf.split("x")  # type: ignore[union-attr]  # None fails too, as it should
        return int(n) * int(m)
    except Exception:  # noqa: BLE001 - whatever it is, the conf is not "NxM"
        raise ValueError(
            f"{scenario}: agent_conf must be 'NxM' (N agents of M segments), got {agent_conf!r}"
        ) from None


def resolve_scenario(
    scenario: str, agent_conf: str | None, agent_obsk: int | None
) -> tuple[str, list[tuple[str, str]]]:
    """The envc spec (id or path) and agent overrides of ``parallel_env``'s first three arguments.

    A MaMuJoCo scenario name follows the reference: ``agent_conf=None`` or ``agent_obsk=None``
    is single-agent mode (envc's conf ``"none"``). A bundled id or spec path keeps the spec's
    default conf when ``agent_conf`` is None.
    """
    if agent_obsk is not None and (
        isinstance(agent_obsk, bool) or not isinstance(agent_obsk, (int, np.integer))
        or agent_obsk < 0
    ):
        raise ValueError(f"agent_obsk must be an int >= 0 or None, got {agent_obsk!r}")
    if agent_conf is not None and not isinstance(agent_conf, str):
        raise ValueError(f"agent_conf must be a string or None, got {agent_conf!r}")
    if scenario in _SCENARIOS or scenario in _MANY_SEGMENT:
        if scenario in _MANY_SEGMENT:
            spec = _MANY_SEGMENT[scenario].format(n=_segments(scenario, agent_conf))
        else:
            spec = _SCENARIOS[scenario]
        if agent_conf is None or agent_obsk is None:
            return spec, [("agent_conf", '"none"')]
        return spec, overrides_to_toml({"agent_conf": agent_conf, "agent_obsk": agent_obsk})
    if not isinstance(scenario, (str, os.PathLike)):
        raise _errors.coded(
            f"error[E1105]: scenario must be a str or path, got {type(scenario).__name__}",
            "E1105",
        )
    spec = os.fspath(scenario)
    pairs: dict[str, str | int] = {} if agent_conf is None else {"agent_conf": agent_conf}
    if agent_obsk is None:
        pairs = {"agent_conf": _SINGLE_AGENT}
    else:
        pairs["agent_obsk"] = agent_obsk
    return spec, overrides_to_toml(pairs)


class EnvcParallelEnv(CoreEnv, pettingzoo.ParallelEnv):
    """A multi-agent envc spec (``[agents]``) as a PettingZoo ``ParallelEnv``, stepping in Rust.

    Every agent shares the reward, terminated, truncated and info of the single-agent task it
    factorizes, as in MaMuJoCo. Besides the ``ParallelEnv`` API: ``state()`` (the single-agent
    observation), ``state_space``, and the reference's mappings
    ``map_local_actions_to_global_action``, ``map_global_action_to_local_actions``,
    ``map_global_state_to_local_observations``, ``map_local_observations_to_global_state``.

    Like the reference, stepping after the episode has ended keeps stepping the simulation
    (``agents`` stays empty until ``reset``); the time limit is the task's
    (``max_episode_steps``, overridable), applied as Gymnasium's ``TimeLimit`` applies it.

    Bad input raises: a missing or unknown agent, a wrong action shape or a NaN action
    (``ValueError``), ``step`` before ``reset`` (``RuntimeError``), any use after ``close``
    (``RuntimeError``).
    """

    def __init__(
        self,
        spec: str,
        overrides: Sequence[tuple[str, str]] = (),
        render_mode: str | None = None,
    ) -> None:
        """Open a multi-agent spec (id or path) with overrides as ``(name, TOML literal)`` pairs
        (``envc.overrides_to_toml`` writes them); ``envc.parallel_env`` is the friendlier door."""
        check_render_mode(render_mode)
        try:
            kind = _envc.describe(spec)[0]
        except _envc.SpecError:
            kind = "agents"  # a spec that needs its overrides to check out: open reports the rest
        if kind != "agents":
            raise _errors.coded(
                f"error[E0602]: `{spec}` is a {kind} spec, not a multi-agent one; open it with "
                "envc.make",
                "E0602",
            )
        _, opened = _envc.open(spec, list(overrides))
        core = cast("_envc.MultiAgentCore", opened)  # a multi-agent spec opens as a MultiAgentCore
        self._core: _envc.MultiAgentCore | _Closed = core
        self.render_mode = render_mode
        self.metadata = {
            "render_modes": list(RENDER_MODES),
            "name": core.id,
            "is_parallelizable": True,
            "render_fps": _fps(core.dt),
            "has_manual_policy": False,
        }
        self.possible_agents = list(core.possible_agents)
        self.agents = list(self.possible_agents)
        self._index = {a: i for i, a in enumerate(self.possible_agents)}
        self.observation_spaces = {
            a: gymnasium.spaces.Box(
                low=core.agent_obs_low(i), high=core.agent_obs_high(i), dtype=np.float64
            )
            for a, i in self._index.items()
        }
        self.action_spaces = {
            a: gymnasium.spaces.Box(
                low=core.agent_act_low(i).astype(np.float32),
                high=core.agent_act_high(i).astype(np.float32),
                dtype=np.float32,
            )
            for a, i in self._index.items()
        }
        self.state_space = gymnasium.spaces.Box(
            low=core.state_low, high=core.state_high, dtype=np.float64
        )
        self.agent_conf = core.conf
        self.agent_obsk = core.k
        self._single = core.conf == _SINGLE_AGENT
        self.dt = core.dt
        self.max_episode_steps = core.max_episode_steps

    # -- the ParallelEnv API ------------------------------------------------------------------

    def observation_space(self, agent: str) -> gymnasium.spaces.Box:
        """The agent's observation space (float64, unbounded), the same object on every call."""
        return self.observation_spaces[agent]

    def action_space(self, agent: str) -> gymnasium.spaces.Box:
        """The agent's action space (float32), the same object on every call."""
        return self.action_spaces[agent]

    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, _F64], dict[str, dict[str, Any]]]:
        """``(observations, infos)``: a dict per agent; every agent gets the same info dict.

        A seed restarts the env's RNG stream (as ``np_random`` is reseeded in the reference);
        ``None`` continues it. ``options`` is accepted and ignored, as MuJoCo envs ignore it.
        """
        seed = _errors.seed(seed)
        _errors.options(options)
        obs, info = self._core.reset(seed)
        self.agents = list(self.possible_agents)
        return self._per_agent(obs), {a: info for a in self.possible_agents}

    def step(
        self, actions: dict[str, Any]
    ) -> tuple[
        dict[str, _F64],
        dict[str, float],
        dict[str, bool],
        dict[str, bool],
        dict[str, dict[str, Any]],
    ]:
        """Step with ``{agent: action}`` for every possible agent.

        Returns ``(observations, rewards, terminations, truncations, infos)``, each a dict over
        every possible agent; reward, flags and info are shared by all agents. When the episode
        ends, ``agents`` becomes empty.
        """
        local = self._local_actions(actions)
        if self._single and np.asarray(actions[self.possible_agents[0]]).dtype == np.float32:
            # Single-agent mode hands the action to the task as given (float32 costs).
            step = self._core.step_f32(local[0].astype(np.float32))
        else:
            step = self._core.step_agents(local)
        obs, reward, term, trunc, info = step
        if term or trunc:
            self.agents = []
        agents = self.possible_agents
        return (
            self._per_agent(obs),
            {a: reward for a in agents},
            {a: term for a in agents},
            {a: trunc for a in agents},
            {a: info for a in agents},
        )

    def state(self) -> np.ndarray:
        """The global state: the single-agent task's observation (float64)."""
        return self._core.state()

    def color_agents(self, on: bool = True) -> None:
        """Draw each agent's limbs in its own colour in later frames (``False``: the model's
        colours, which is what MaMuJoCo draws). A picture of the factorization; the model and
        every observation are unchanged."""
        self._core.color_agents(on)

    def render(self) -> _Frame | None:
        """A frame of the whole robot in ``render_mode`` (None without one), as MaMuJoCo renders."""
        if self.render_mode is None:
            return None
        # `check_render_mode` let only envc's modes through.
        return self._core.render(cast("_RenderMode", self.render_mode))


    # -- the reference's mappings -------------------------------------------------------------

    def map_local_actions_to_global_action(self, actions: dict[str, Any]) -> np.ndarray:
        """The single-agent (global) action of ``{agent: action}`` (float64)."""
        local = self._local_actions(actions)
        if self._single and np.asarray(actions[self.possible_agents[0]]).dtype == np.float32:
            return local[0].astype(np.float32)  # the agent's action as given, as the reference
        return self._core.local_actions_to_global(local)

    def map_global_action_to_local_actions(self, action: Any) -> dict[str, np.ndarray]:
        """``{agent: its share of the global action}``, in the global action's float dtype."""
        a = np.asarray(action)
        dtype = a.dtype if np.issubdtype(a.dtype, np.floating) else np.float64
        local = self._core.global_action_to_local(self._vector(a, "action"))
        return {
            ag: x.astype(dtype, copy=False)
            for ag, x in zip(self.possible_agents, local, strict=False)
        }

    def map_global_state_to_local_observations(self, global_state: Any) -> dict[str, np.ndarray]:
        """``{agent: the observation it would get in this global state}`` (float64)."""
        local = self._core.global_state_to_local(self._vector(global_state, "global_state"))
        return self._per_agent(local)

    def map_local_observations_to_global_state(
        self, local_observation: dict[str, Any]
    ) -> np.ndarray:
        """The global state rebuilt from ``{agent: observation}``; raises ``ValueError`` when a
        state entry is observed by no agent or two observations disagree about it."""
        return self._core.local_observations_to_global(
            self._per_agent_list(local_observation, "observation")
        )

    # -- envc extras --------------------------------------------------------------------------

    @property
    def spec_id(self) -> str:
        """The envc id of the multi-agent spec, e.g. ``MaMuJoCo-Ant-v1``."""
        return self._core.id

    def __repr__(self) -> str:
        return f"EnvcParallelEnv<{self.metadata['name']} {self.agent_conf} k={self.agent_obsk}>"

    # -- helpers ------------------------------------------------------------------------------

    def _per_agent(self, arrays: list[np.ndarray]) -> dict[str, np.ndarray]:
        return dict(zip(self.possible_agents, arrays, strict=False))

    @staticmethod
    def _vector(x: Any, what: str) -> np.ndarray:
        a = np.asarray(x)
        if a.ndim != 1:
            raise ValueError(f"{what} has shape {a.shape}; expected a vector")
        # Strings, dates and objects are not numbers, whatever numpy would make of them.
        if a.dtype.kind not in "biuf":
            raise ValueError(f"{what} is not numeric: dtype {a.dtype}")
        try:
            return np.ascontiguousarray(a, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise ValueError(f"{what} is not numeric: {e}") from None

    def _per_agent_list(self, d: dict[str, Any], what: str) -> list[np.ndarray]:
        if not isinstance(d, dict):
            raise ValueError(f"expected a dict {{agent: {what}}}, got {type(d).__name__}")
        unknown = set(d) - set(self._index)
        if unknown:
            raise ValueError(
                f"unknown agents {sorted(map(str, unknown))}; agents are {self.possible_agents}"
            )
        missing = [a for a in self.possible_agents if a not in d]
        if missing:
            raise ValueError(f"no {what} for {missing}")
        return [self._vector(d[a], f"{what} of {a}") for a in self.possible_agents]

    def _local_actions(self, actions: dict[str, Any]) -> list[np.ndarray]:
        return self._per_agent_list(actions, "action")


def parallel_env(
    scenario: str,
    agent_conf: str | None = None,
    agent_obsk: int | None = 1,
    render_mode: str | None = None,
    **overrides: Any,
) -> EnvcParallelEnv:
    """A multi-agent env as a PettingZoo ``ParallelEnv``, like ``mamujoco_v1.parallel_env``.

    ``scenario`` is a MaMuJoCo v1 scenario name ("Ant", "HalfCheetah", "Hopper", "Humanoid",
    "HumanoidStandup", "Reacher", "Swimmer", "Pusher", "Walker2d", "InvertedPendulum",
    "InvertedDoublePendulum", "CoupledHalfCheetah", "ManySegmentAnt", "ManySegmentSwimmer"),
    with the reference's meaning of ``agent_conf`` ("2x4", "9|8", ...; None: single-agent mode)
    and ``agent_obsk`` (observation depth; None: single-agent mode); or any bundled multi-agent
    id (``envc.bundled_ids("agents")``) or ``[agents]`` spec file, where ``agent_conf=None``
    keeps the spec's default conf.

    Keyword arguments are parameters of the task every agent shares (``ctrl_cost_weight=0.1``,
    ``max_episode_steps=200``, ...). The reference's ``agent_factorization``,
    ``local_categories``, ``global_categories`` and ``gym_env`` are spec content in envc: write
    an ``[agents]`` spec instead (specs/mamujoco/ shows how).
    """
    for name in _SPEC_CONTENT:
        if name in overrides:
            raise _errors.coded(
                f"error[E1105]: parallel_env: `{name}` is spec content in envc; write an "
                "[agents] spec (see specs/mamujoco/) and pass its path as the scenario",
                "E1105",
            )
    spec, pairs = resolve_scenario(scenario, agent_conf, agent_obsk)
    overrides = render_overrides(overrides)
    return EnvcParallelEnv(spec, pairs + overrides_to_toml(overrides), render_mode=render_mode)
