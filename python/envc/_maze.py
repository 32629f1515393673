"""Maze envs as Gymnasium-Robotics ``GoalEnv``: dict observations and batched goal functions.

The env class subclasses ``gymnasium_robotics.core.GoalEnv`` when Gymnasium-Robotics is installed
(``pip install envc[robotics]``); without it, it subclasses ``gymnasium.Env`` and offers the same
API (``GoalEnv`` adds only the check of the observation space's keys at reset).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, cast

import gymnasium as gym
import numpy as np

from . import _envc, _errors
from ._core_env import CoreEnv, _Closed
from ._gym import (
    RENDER_MODES,
    as_actions,
    check_render_mode,
    goal_batches,
    overrides_to_toml,
    recovered_spec,
    reference_seed,
    render_overrides,
)

if TYPE_CHECKING:
    from ._envc import _F64, _Frame, _RenderMode

try:
    from gymnasium_robotics.core import GoalEnv as _Base
except ImportError:  # Gymnasium-Robotics is an optional dependency.
    _Base = gym.Env


def _cell(options: dict[str, Any], key: str) -> tuple[int, int] | None:
    """``options[key]`` as a ``(row, col)`` pair of non-negative ints (``None`` when absent)."""
    cell = options.get(key)
    if cell is None:
        return None
    c = np.asarray(cell)
    if c.shape != (2,) or not np.issubdtype(c.dtype, np.integer) or (c < 0).any():
        raise ValueError(f"options[{key!r}] = {cell!r}: expected a (row, col) pair of cell indices")
    return int(c[0]), int(c[1])


def _goal_batches(
    achieved_goal: Any, desired_goal: Any
) -> tuple[np.ndarray, np.ndarray, tuple[int, ...]]:
    """Goals broadcast against each other as ``[N, 2]`` float64 rows, and the leading shape."""
    return goal_batches(achieved_goal, desired_goal, 2)


def _unbounded(n: int) -> gym.spaces.Box[np.float64]:
    return gym.spaces.Box(-np.inf, np.inf, shape=(n,), dtype=np.float64)


class EnvcMazeEnv(CoreEnv, _Base):
    """A maze env of any envc maze spec (PointMaze, AntMaze, a robot of your own), stepping in Rust.

    ``EnvcMazeEnv("PointMaze_UMaze-v3", continuing_task=False)``, or through Gymnasium:
    ``gymnasium.make("envc/AntMaze_Medium_Diverse_GRDense-v5")``. It behaves as the reference's
    ``PointMazeEnv`` / ``AntMazeEnv`` (Gymnasium-Robotics 1.4.2): same observation dict, rewards,
    flags and infos for the same seed and actions.

    Keyword arguments: the reference's ``maze_map`` (a list of rows of ``1``, ``0``, ``"r"``,
    ``"g"``, ``"c"``), ``reward_type`` (``"sparse"`` or ``"dense"``), ``continuing_task``,
    ``reset_target``, ``maze_size_scaling``, ``maze_height``, ``position_noise_range``; any other
    keyword is a parameter of the robot's spec (e.g. ``ctrl_cost_weight`` for the ant). The time
    limit is Gymnasium's ``TimeLimit``, as for the reference.

    ``reset(seed=..., options={"goal_cell": (i, j), "reset_cell": (i, j)})`` places the goal and
    the robot in given free cells (a wall or out-of-range cell raises ``ValueError``).

    ``compute_reward``, ``compute_terminated`` and ``compute_truncated`` take goals of shape
    ``[2]`` (returning a scalar, as the reference) or ``[..., 2]`` (returning one value per goal
    pair, for hindsight relabelling as SB3's ``HerReplayBuffer`` does). They are the env's own goal
    terms, computed in Rust exactly as the step computes them. Unlike the reference, a batch
    given to ``compute_terminated`` / ``compute_truncated`` gives one flag per pair (the
    reference's take the norm of the whole batch and return one bool).

    Actions: float64 or float32 arrays as for ``envc.EnvcEnv``; bad actions (wrong shape, NaN)
    raise ``ValueError``, ``step`` before ``reset`` raises ``RuntimeError``.
    """

    # The reference maze classes declare 50 fps whatever their dt.
    metadata = {"render_modes": list(RENDER_MODES), "render_fps": 50}

    def __init__(
        self,
        spec_id: str,
        render_mode: str | None = None,
        maze_map: list[Any] | None = None,
        envc_provenance: dict[str, Any] | None = None,
        accept_changed_spec: bool = False,
        refuse_other_mujoco: bool = False,
        use_recorded_spec: bool = False,
        **overrides: Any,
    ) -> None:
        spec_id = recovered_spec(
            spec_id, envc_provenance, accept_changed_spec, refuse_other_mujoco, use_recorded_spec
        )
        check_render_mode(render_mode)
        overrides = render_overrides(overrides)
        if maze_map is not None:
            if "map" in overrides:
                raise _errors.coded(
                    "error[E1105]: pass either `maze_map` or `map`, not both", "E1105"
                )
            overrides["map"] = maze_map
        pairs = overrides_to_toml(overrides)
        if "max_episode_steps" not in overrides:
            pairs.append(("max_episode_steps", "0"))
        kind, opened = _envc.open(spec_id, pairs)
        if kind != "maze":
            raise _errors.coded(
                f"error[E0602]: `{spec_id}` is a {kind} spec, not a maze; open it with envc.make",
                "E0602",
            )
        core = cast("_envc.MazeCore", opened)  # a "maze" spec opens as a MazeCore
        self._core: _envc.MazeCore | _Closed = core
        self.render_mode = render_mode
        self.dt = core.dt
        # As the reference builds it (spaces.Dict sorts the keys).
        self.observation_space = gym.spaces.Dict(
            dict(
                observation=_unbounded(core.observation_dim),
                achieved_goal=_unbounded(2),
                desired_goal=_unbounded(2),
            )
        )
        self.action_space = gym.spaces.Box(
            low=core.act_low.astype(np.float32),
            high=core.act_high.astype(np.float32),
            dtype=np.float32,
        )
        self.reward_type = core.reward_type
        self.continuing_task = core.continuing_task
        self.reset_target = core.reset_target

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, _F64], dict[str, Any]]:
        """Start an episode: ``(obs dict, info)``. ``options`` may hold ``goal_cell`` and
        ``reset_cell`` (``(row, col)`` of free cells); others are drawn as the reference draws."""
        seed = reference_seed(seed, super().reset)
        opts = _errors.options(options)
        return self._core.reset(
            seed,
            _cell(opts, "goal_cell"),
            _cell(opts, "reset_cell"),
        )

    def step(
        self, action: object
    ) -> tuple[dict[str, _F64], np.float64, bool, bool, dict[str, Any]]:
        """``(obs dict, reward, terminated, truncated, info)``; ``info["success"]`` says whether
        the robot is within the goal threshold."""
        a = as_actions(action)
        if a.ndim != 1:
            raise _errors.coded(
                f"error[E1101]: action has shape {a.shape}; expected {self.action_space.shape}",
                "E1101",
            )
        if a.dtype == np.float32:
            obs, reward, terminated, truncated, info = self._core.step_f32(np.ascontiguousarray(a))
        else:
            obs, reward, terminated, truncated, info = self._core.step(
                np.ascontiguousarray(a, dtype=np.float64)
            )
        return obs, np.float64(reward), terminated, truncated, info

    def compute_reward(self, achieved_goal: Any, desired_goal: Any, info: Any = None) -> Any:
        """The goal reward of ``achieved_goal`` against ``desired_goal`` (``info`` is unused):
        a float64 scalar for ``[2]`` goals, a float64 array of the leading shape for
        ``[..., 2]``."""
        a, d, lead = _goal_batches(achieved_goal, desired_goal)
        r = self._core.compute_reward(a, d)
        return r.reshape(lead) if lead else r[0]

    def compute_terminated(
        self, achieved_goal: Any, desired_goal: Any, info: Any = None
    ) -> Any:
        """Whether the episode ends for these goals (reaching the goal, unless the task is
        continuing): a bool for ``[2]`` goals, a bool array of the leading shape for
        ``[..., 2]``."""
        a, d, lead = _goal_batches(achieved_goal, desired_goal)
        t = self._core.compute_terminated(a, d)
        return t.reshape(lead) if lead else bool(t[0])

    def compute_truncated(self, achieved_goal: Any, desired_goal: Any, info: Any = None) -> Any:
        """Always false (the ``TimeLimit`` truncates): a bool for ``[2]`` goals, a bool array of
        the leading shape for ``[..., 2]``."""
        a, d, lead = _goal_batches(achieved_goal, desired_goal)
        t = self._core.compute_truncated(a, d)
        return t.reshape(lead) if lead else bool(t[0])

    def render(self) -> _Frame | None:
        """A frame of the maze with its goal marker, in ``render_mode`` (docs/rendering.md)."""
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        # `check_render_mode` let only envc's modes through.
        return self._core.render(cast("_RenderMode", self.render_mode))

    @property
    def goal(self) -> np.ndarray:
        """The current goal (x, y): the next step's ``desired_goal``."""
        return self._core.goal
