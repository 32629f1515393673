"""Single-agent envs as ``gymnasium.Env``: the task env class and ``envc.make``."""

from __future__ import annotations

import json
import math
import os
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, cast

import gymnasium as gym
import numpy as np

from . import _envc, _errors
from ._core_env import CoreEnv, _Closed

if TYPE_CHECKING:
    from ._envc import _F64, _Frame, _RenderMode


def _toml(value: Any, name: str) -> str:
    """A Python value as the TOML literal an envc override takes."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value.item()
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        x = float(value)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return repr(x)
    if isinstance(value, (str, os.PathLike)):
        return json.dumps(os.fspath(value))
    if isinstance(value, (tuple, list, np.ndarray)):
        return "[" + ", ".join(_toml(v, name) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml(v, name)}" for k, v in value.items()) + "}"
    raise _errors.coded(
        f"error[E0203]: parameter `{name}`: cannot pass a {type(value).__name__} "
        "(expected a bool, number, string, path, tuple/list or dict)",
        "E0203",
    )


def overrides_to_toml(overrides: dict[str, Any]) -> list[tuple[str, str]]:
    """Keyword arguments as envc overrides: ``[(name, TOML literal), ...]``."""
    return [(k, _toml(v, k)) for k, v in overrides.items()]


RENDER_MODES: tuple[_RenderMode, ...] = ("rgb_array", "depth_array", "rgbd_tuple")


def check_render_mode(render_mode: str | None) -> None:
    if render_mode is not None and not (
        isinstance(render_mode, str) and render_mode in RENDER_MODES
    ):
        raise _errors.coded(
            f"error[E1504]: render_mode={render_mode!r}: envc renders headless only; expected "
            f"one of {', '.join(RENDER_MODES)} (wrap with gymnasium.wrappers.HumanRendering to "
            "watch)",
            "E1504",
        )


def render_overrides(overrides: dict[str, Any]) -> dict[str, Any]:
    """Gymnasium's rendering keywords as envc parameters: ``None`` is the default (dropped),
    ``visual_options`` keys may be ``mujoco.mjtVisFlag`` members."""
    out = dict(overrides)
    for k in ("camera_id", "camera_name", "visual_options", "default_camera_config"):
        if k in out and out[k] is None:
            del out[k]
    if isinstance(out.get("visual_options"), dict):
        try:
            out["visual_options"] = {int(k): bool(v) for k, v in out["visual_options"].items()}
        except (TypeError, ValueError, OverflowError) as e:
            raise _errors.coded(
                f"error[E1505]: visual_options: expected mjtVisFlag keys and bools ({e})", "E1505"
            ) from None
    return out


class SeedError(_errors.ArgumentError, gym.error.Error):
    """A negative seed: E1105, and the ``gymnasium.error.Error`` the reference raises."""



def reference_seed(seed: object, gym_reset: Callable[..., object]) -> int | None:
    """A reset seed checked as the reference checks it: an integer goes to Gymnasium's own
    ``Env.reset`` first (a negative seed is its error, as for the reference's envs); then
    anything but an integer in [0, 2**64) is ``ArgumentError`` (E1105), never converted."""
    import numbers

    if isinstance(seed, numbers.Integral) and not isinstance(seed, (bool, np.bool_)):
        try:
            gym_reset(seed=int(seed))
        except gym.error.Error as e:
            # Still Gymnasium's error (as for the reference's envs), and coded as envc's.
            message = f"error[E1105]: seed must be in [0, 2**64), got {int(seed)} ({e})"
            raise SeedError(message, "E1105") from None
        return _errors.seed(seed)
    seed = _errors.seed(seed)
    gym_reset(seed=seed)
    return seed


def as_actions(actions: object) -> np.ndarray:
    """An action (or batch) as a float array; what numpy cannot read as numbers is E1101."""
    try:
        a = np.asarray(actions)
    except (TypeError, ValueError, OverflowError) as e:
        raise _errors.coded(f"error[E1101]: actions must be numbers ({e})", "E1101") from None
    if a.dtype == np.float32:
        return a
    # Only booleans, integers and floats are numbers: numpy would parse strings ("0") and
    # turn dates, durations and objects into numbers without a word.
    if a.dtype.kind not in "biuf":
        raise _errors.coded(
            f"error[E1101]: actions must be real numbers, got {a.dtype}", "E1101"
        )
    try:
        return np.asarray(a, dtype=np.float64)
    except (TypeError, ValueError, OverflowError) as e:
        raise _errors.coded(
            f"error[E1101]: actions must be numbers, got {a.dtype} ({e})", "E1101"
        ) from None


def goal_batches(
    achieved_goal: Any, desired_goal: Any, n: int
) -> tuple[np.ndarray, np.ndarray, tuple[int, ...]]:
    """Goals broadcast against each other as ``[N, n]`` float64 rows, and the leading shape
    (anything else is E1105)."""
    try:
        a = np.asarray(achieved_goal, dtype=np.float64)
        d = np.asarray(desired_goal, dtype=np.float64)
    except (TypeError, ValueError, OverflowError) as e:
        raise _errors.coded(f"error[E1105]: goals must be numbers ({e})", "E1105") from None
    if (
        a.shape == d.shape
        and a.ndim >= 1
        and a.shape[-1] == n
        and a.flags.c_contiguous
        and d.flags.c_contiguous
    ):
        # The usual batch: views, no copy.
        return a.reshape(-1, n), d.reshape(-1, n), a.shape[:-1]
    try:
        a, d = np.broadcast_arrays(a, d)
    except ValueError:
        raise _errors.coded(
            f"error[E1105]: achieved_goal {a.shape} and desired_goal {d.shape} do not "
            "broadcast together",
            "E1105",
        ) from None
    if a.ndim == 0 or a.shape[-1] != n:
        raise _errors.coded(
            f"error[E1105]: goals have shape {a.shape}; expected [..., {n}]", "E1105"
        )
    ra, rd = (np.ascontiguousarray(x.reshape(-1, n)) for x in (a, d))
    return ra, rd, a.shape[:-1]


class DatasetWarning(UserWarning):
    """A coded warning about a dataset's provenance (W1212, W1214; docs/errors.md): ``.code``."""

    def __init__(self, message: str, code: str | None = None) -> None:
        super().__init__(message)
        self.code = code


#: The Gymnasium version envc's bit-for-bit parity with the reference is proven against
#: (tests/reference/requirements.txt pins it; pyproject.toml allows any 1.4.x).
PARITY_GYMNASIUM = "1.4.0"


class ParityWarning(UserWarning):
    """The installed Gymnasium is not the version envc's bit-for-bit parity with the reference is
    proven against (``PARITY_GYMNASIUM``): envc runs, but matching that Gymnasium's own envs bit
    for bit is not proven. Warned once, at ``import envc``."""


def _parity_warning(installed: str) -> None:
    """Warn (:class:`ParityWarning`) when ``installed``, the installed Gymnasium's version, is not
    the one parity is proven against; nothing when it is."""
    if installed == PARITY_GYMNASIUM:
        return
    import warnings

    warnings.warn(
        ParityWarning(
            f"envc: the installed Gymnasium is {installed}, but envc's bit-for-bit parity with "
            f"Gymnasium's environments is proven against Gymnasium {PARITY_GYMNASIUM} only: "
            "envc's envs run, but may differ from this version's own; "
            f"pip install 'gymnasium=={PARITY_GYMNASIUM}' for the proven pairing"
        ),
        stacklevel=3,
    )


def recovered_spec(
    spec_id: str,
    provenance: dict[str, Any] | None,
    accept_changed_spec: bool = False,
    refuse_other_mujoco: bool = False,
    use_recorded_spec: bool = False,
) -> str:
    """The spec a dataset's env creator opens: ``spec_id`` when the dataset carries no
    ``envc_provenance`` (an older dataset), else what the record says (docs/datasets.md,
    "What made a dataset"), warning with a code where it had to compromise."""
    if provenance is None:
        return spec_id
    import warnings

    target, notes = _envc.recover_spec(
        str(provenance.get("dataset_id", "")),
        json.dumps(provenance),
        bool(accept_changed_spec),
        bool(refuse_other_mujoco),
        bool(use_recorded_spec),
    )
    for note in notes:
        code = note[note.find("[") + 1 : note.find("]")] if note.startswith("warning[") else None
        warnings.warn(DatasetWarning(note, code), stacklevel=3)
    return target


def _fps(dt: float) -> int:
    return int(np.round(1.0 / dt))


class EnvcEnv(CoreEnv, gym.Env):
    """A single-agent task env of any envc spec, stepping in Rust.

    ``EnvcEnv("Ant-v5", ctrl_cost_weight=0.1)`` or ``EnvcEnv("my_robot.toml")``. The time limit is
    Gymnasium's ``TimeLimit`` (``gymnasium.make`` and ``envc.make`` add it), exactly as for the
    reference's envs; the env itself never truncates.

    Actions: a float64 array (or anything ``np.asarray`` makes one of) steps with float64 costs;
    a float32 array steps with float32 costs, as numpy computes them in the reference. Bad actions
    (wrong shape, NaN) raise ``ValueError``; ``step`` before ``reset`` raises ``RuntimeError``.
    """

    # Class-level, for gymnasium.make's render-mode check; instances add their render_fps.
    metadata = {"render_modes": list(RENDER_MODES)}

    def __init__(
        self,
        spec_id: str,
        render_mode: str | None = None,
        envc_provenance: dict[str, Any] | None = None,
        accept_changed_spec: bool = False,
        refuse_other_mujoco: bool = False,
        use_recorded_spec: bool = False,
        **overrides: Any,
    ) -> None:
        # A dataset's env spec carries what made it; `recover_environment(accept_changed_spec=...)`
        # passes the options through.
        spec_id = recovered_spec(
            spec_id, envc_provenance, accept_changed_spec, refuse_other_mujoco, use_recorded_spec
        )
        check_render_mode(render_mode)
        overrides = render_overrides(overrides)
        pairs = overrides_to_toml(overrides)
        if "max_episode_steps" not in overrides:
            pairs.append(("max_episode_steps", "0"))
        kind, opened = _envc.open(_id(spec_id), pairs)
        if kind != "task":
            raise _errors.coded(
                f"error[E0602]: `{spec_id}` is a {kind} spec; open it with envc.make (mazes) or "
                "envc.parallel_env (multi-agent specs)",
                "E0602",
            )
        core = cast("_envc.TaskCore", opened)  # a "task" spec opens as a TaskCore
        self._core: _envc.TaskCore | _Closed = core
        self.render_mode = render_mode
        self.metadata = {"render_modes": list(RENDER_MODES), "render_fps": _fps(core.dt)}
        obs_space = gym.spaces.Box(low=core.obs_low, high=core.obs_high, dtype=np.float64)
        self._goal_dim = core.goal_dim
        # A `[goal]` of parts: goals are dicts of named parts (Gymnasium-Robotics' Kitchen).
        self._parts: tuple[tuple[str, int], ...] = tuple(core.goal_parts)
        self._parts_info: tuple[str, ...] = tuple(core.parts_info_keys)
        if self._goal_dim:
            # A `[goal]` task: Gymnasium-Robotics' dict observation (its Dict sorts the keys).
            goal: gym.Space[Any] = gym.spaces.Box(
                -np.inf, np.inf, shape=(self._goal_dim,), dtype=np.float64
            )
            if self._parts:
                goal = gym.spaces.Dict(
                    {
                        name: gym.spaces.Box(-np.inf, np.inf, shape=(n,), dtype=np.float64)
                        for name, n in self._parts
                    }
                )
            self.observation_space: gym.Space[Any] = gym.spaces.Dict(
                dict(desired_goal=goal, achieved_goal=goal, observation=obs_space)
            )
        else:
            self.observation_space = obs_space
        self.action_space = gym.spaces.Box(
            low=core.act_low.astype(np.float32),
            high=core.act_high.astype(np.float32),
            dtype=np.float32,
        )
        self.frame_skip = None
        self.dt = core.dt
        # What the reference reports as numpy float32: a reward of `goal_missed` terms alone,
        # info keys declared `dtype = "float32"`.
        self._f32_reward = bool(core.goal_reward_float32)
        self._f32_keys = tuple(core.float32_info_keys)
        self._bool_keys = tuple(core.bool_info_keys)

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[_F64 | dict[str, _F64], dict[str, Any]]:
        seed = reference_seed(seed, super().reset)
        _errors.options(options)
        obs, info = self._core.reset(seed)
        for k in self._bool_keys:
            if k in info:
                info[k] = np.bool_(info[k] != 0.0)
        if self._parts:
            return self._present_parts(obs, info)
        return obs, info

    def _present_parts(self, obs: Any, info: dict[str, Any]) -> tuple[Any, dict[str, Any]]:
        """A `[goal]` of parts: goals as dicts of named parts, `goal_parts` info as lists of
        names (ordered by value: completion order, else part order)."""
        for key in ("achieved_goal", "desired_goal"):
            flat, off, parts = obs[key], 0, {}
            for name, n in self._parts:
                parts[name] = flat[off : off + n].copy()
                off += n
            obs[key] = parts
        names = [name for name, _ in self._parts]
        for k in self._parts_info:
            if k in info:
                v = np.atleast_1d(info[k])
                ranked = sorted((v[i], i) for i in range(len(names)) if v[i] != 0.0)
                info[k] = [names[i] for _, i in ranked]
        return obs, info

    def _flat_goal(self, goal: Any) -> Any:
        """A dict of named parts as the flat goal vectors they make (anything else as given)."""
        if not (self._parts and isinstance(goal, dict)):
            return goal
        try:
            return np.concatenate(
                [np.asarray(goal[name], dtype=np.float64) for name, _ in self._parts], axis=-1
            )
        except (KeyError, ValueError) as e:
            raise _errors.coded(
                f"error[E1105]: goal parts: expected the keys {[n for n, _ in self._parts]} "
                f"with matching shapes ({e})",
                "E1105",
            ) from None

    def step(
        self, action: object
    ) -> tuple[_F64 | dict[str, _F64], float | np.float32, bool, bool, dict[str, Any]]:
        a = as_actions(action)
        if a.ndim != 1:
            raise _errors.coded(
                f"error[E1101]: action has shape {a.shape}; expected {self.action_space.shape}",
                "E1101",
            )
        if a.dtype == np.float32:
            out = self._core.step_f32(np.ascontiguousarray(a))
        else:
            out = self._core.step(np.ascontiguousarray(a, dtype=np.float64))
        if self._f32_reward or self._f32_keys or self._bool_keys or self._parts:
            obs, reward, terminated, truncated, info = out
            if self._parts:
                obs, info = self._present_parts(obs, info)
            for k in self._f32_keys:
                if k in info:
                    info[k] = np.float32(info[k])
            for k in self._bool_keys:
                if k in info:
                    info[k] = np.bool_(info[k] != 0.0)
            return (
                obs,
                np.float32(reward) if self._f32_reward else reward,
                terminated,
                truncated,
                info,
            )
        return out

    def render(self) -> _Frame | None:
        """A frame in ``render_mode``, as Gymnasium's ``MujocoEnv.render`` (docs/rendering.md)."""
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        # `check_render_mode` let only envc's modes through.
        return self._core.render(cast("_RenderMode", self.render_mode))

    def compute_reward(self, achieved_goal: Any, desired_goal: Any, info: Any = None) -> Any:
        """A ``[goal]`` task's reward for these goals (``info`` is unused), exactly as ``step``
        computes it: a scalar for ``[goal_dim]`` goals, an array of the leading shape for
        ``[..., goal_dim]`` (what hindsight relabelling, e.g. SB3's ``HerReplayBuffer``, calls).
        float32 where the reference computes float32 (``-(d > threshold)``), else float64."""
        if not self._goal_dim:
            raise _errors.coded(
                f"error[E0170]: compute_reward: {self.spec.id if self.spec else 'this env'} has no "
                "[goal] table (docs/spec-reference.md §22)",
                "E0170",
            )
        a, d, lead = goal_batches(
            self._flat_goal(achieved_goal), self._flat_goal(desired_goal), self._goal_dim
        )
        r = self._core.compute_reward(a, d)
        if self._core.goal_reward_float32:
            r = r.astype(np.float32)
        return r.reshape(lead) if lead else r[0]

    def compute_terminated(self, achieved_goal: Any, desired_goal: Any, info: Any = None) -> Any:
        """False for a task without ``[termination.*]`` (Gymnasium-Robotics' Fetch): a bool, or
        a bool array of the leading shape (E0170 for a task with termination conditions)."""
        if self._core.terminations or self._parts:
            raise _errors.coded(
                "error[E0170]: compute_terminated: this task's termination (its "
                "[termination.*] conditions, or the parts of its goal completed) is not "
                "evaluated on given goals; step the env instead",
                "E0170",
            )
        a, _, lead = goal_batches(achieved_goal, desired_goal, self._goal_dim or 1)
        t = np.zeros(a.shape[0], dtype=bool)
        return t.reshape(lead) if lead else bool(t[0])

    def compute_truncated(self, achieved_goal: Any, desired_goal: Any, info: Any = None) -> Any:
        """Always false (the ``TimeLimit`` truncates)."""
        return self.compute_terminated(achieved_goal, desired_goal, info)



def make(id_or_path: str, render_mode: str | None = None, **overrides: Any) -> gym.Env:
    """A Gymnasium env of a bundled id (``"Ant-v5"``, ``"PointMaze_UMaze-v3"``) or a spec file.

    Keyword arguments are the spec's parameters (Python values: bools, numbers, tuples for
    ranges, a path for ``xml_file``); ``max_episode_steps`` sets the ``TimeLimit``. An unknown
    keyword raises ``TypeError`` naming the closest parameter; a bad value raises
    ``envc.SpecError`` (a ``ValueError``) saying which parameter and why.

    The env is wrapped as ``gymnasium.make`` wraps the reference's (``PassiveEnvChecker``,
    ``OrderEnforcing``, ``TimeLimit``): ``envc.make("Ant-v5")`` is ``gym.make("envc/Ant-v5")``.
    A spec file is registered under ``envc/<its id>`` first.
    """
    from ._registry import env_id_for

    if "max_episode_steps" in overrides and overrides["max_episode_steps"] is not None:
        overrides["max_episode_steps"] = _errors.integer(
            overrides["max_episode_steps"], "max_episode_steps", 1
        )
    id_or_path = _id(id_or_path)
    check_render_mode(render_mode)
    return gym.make(env_id_for(id_or_path, overrides), render_mode=render_mode, **overrides)


def _id(id_or_path: Any) -> str:
    """A bundled id or a spec path (``str`` or ``os.PathLike``), as a string."""
    if isinstance(id_or_path, (str, os.PathLike)):
        return os.fspath(id_or_path)
    raise _errors.coded(
        f"error[E1105]: expected a bundled id or a spec path, got {type(id_or_path).__name__}",
        "E1105",
    )

