"""Vector envs as ``gymnasium.vector.VectorEnv``: ``EnvcVectorEnv`` and ``envc.make_vec``."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, cast

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from . import _envc, _errors
from ._core_env import WithNumerics
from ._gym import (
    RENDER_MODES,
    _fps,
    _id,
    check_render_mode,
    overrides_to_toml,
    render_overrides,
)

if TYPE_CHECKING:
    import numpy.typing as npt

    from ._envc import _F64, _Autoreset, _Frame, _RenderMode

_MODES = (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP)


def _default_threads(num_envs: int) -> int:
    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cpus = os.cpu_count() or 1
    return max(1, min(num_envs, cpus))


class EnvcVectorEnv(WithNumerics, gym.vector.VectorEnv):
    """``num_envs`` copies of one envc task spec, stepped in parallel by Rust threads.

    ``EnvcVectorEnv("Ant-v5", num_envs=8, num_threads=2, ctrl_cost_weight=0.1)``; the same as
    ``gymnasium.make_vec("envc/Ant-v5", num_envs=8, vectorization_mode="vector_entry_point")``.
    It behaves as ``gymnasium.make_vec("Ant-v5", num_envs=8, vectorization_mode="sync")`` does,
    bit for bit under the same seeds and actions:

    * ``reset(seed=s)`` seeds env i with ``s + i`` (a list gives one seed per env); ``None``
      continues each env's stream.
    * ``autoreset_mode``: ``AutoresetMode.NEXT_STEP`` (default: the step after an env ended
      resets it, with reward 0 and both flags false) or ``AutoresetMode.SAME_STEP`` (the ending
      step resets at once; ``info["final_obs"]`` and ``info["final_info"]`` hold what it ended on).
    * Infos in Gymnasium's vector form: ``info[key]`` is an array over envs and
      ``info["_" + key]`` the mask of envs that reported it.
    * A goal-conditioned task (``[goal]``, e.g. ``FetchPush-v4``): observations are dicts of
      batches, ``{"achieved_goal": (n, g), "desired_goal": (n, g), "observation": (n, obs)}``,
      as ``SyncVectorEnv`` concatenates the single env's ``Dict`` space; SAME_STEP's
      ``info["final_obs"]`` holds each ended env's own dict. A goal of named parts
      (``[goal.parts]``, FrankaKitchen-v1) is refused (E0602).
    * Info keys declared float32 or bool come as ``SyncVectorEnv`` batches the single env's
      numpy scalars: float32 arrays; for a bool, an object array of ``np.bool_`` (None where an
      env did not report it).
    * The time limit is the spec's (``max_episode_steps``, as ``TimeLimit`` applies it in the
      reference); ``max_episode_steps=N`` overrides it, ``0`` turns it off.

    Actions are a ``(num_envs, act_dim)`` batch: float64 steps with float64 costs, float32 with
    float32 costs as numpy computes them; a C-contiguous float32 or float64 batch is read in
    place by the threads (no copy), which step with the GIL released. Results and infos are
    built in Rust. ``copy=True`` (Gymnasium's default) returns fresh arrays; ``copy=False``
    returns the same arrays every call (observations, rewards, flags, each info key's values and
    mask, a bool key's object array aside), owned by the env and overwritten by the next
    ``reset`` or ``step``. Bad batches (wrong shape, NaN) raise ``ValueError``; ``step`` before
    ``reset`` and any call after ``close`` raise ``RuntimeError``.
    """

    def __init__(
        self,
        spec_id: str,
        num_envs: int = 1,
        *,
        num_threads: int | None = None,
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
        max_episode_steps: int | None = None,
        copy: bool = True,
        render_mode: str | None = None,
        **overrides: Any,
    ):
        check_render_mode(render_mode)
        overrides = render_overrides(overrides)
        try:
            mode = AutoresetMode(autoreset_mode)
        except ValueError:
            mode = None
        if mode not in _MODES:
            raise _errors.coded(
                f"error[E1105]: autoreset_mode={autoreset_mode!r}: envc vector envs support "
                "NEXT_STEP and SAME_STEP",
                "E1105",
            )
        # Beyond 2**63 is not a count Rust takes; limits::MAX_VEC_ENVS refuses far less (E1403).
        num_envs = _errors.integer(num_envs, "num_envs", 1, 2**63)
        if num_threads is None:
            threads = _default_threads(num_envs)
        else:
            threads = _errors.integer(num_threads, "num_threads", 1, 2**63)
        pairs = overrides_to_toml(overrides)
        if max_episode_steps is not None:
            steps = _errors.integer(max_episode_steps, "max_episode_steps", 0, 2**63)
            pairs.append(("max_episode_steps", str(steps)))
        # AutoresetMode's values are the core's names ("NextStep", "SameStep").
        autoreset = cast("_Autoreset", mode.value)
        core = _envc.VecCore(_id(spec_id), pairs, num_envs, threads, autoreset)
        # One call at a time: the core steps with the GIL released, and refuses a second
        # thread's call while one runs (E1106).
        self._core: _envc.VecCore = core
        self.copy = copy
        if type(self).step is EnvcVectorEnv.step:
            # The core's own method: every check `step` makes is the core's, so a batch step
            # costs one call from Python (a subclass's own `step` is left in place).
            self.step = core.step  # type: ignore[method-assign]
        self.num_envs = int(num_envs)
        self.autoreset_mode = mode
        self.render_mode = render_mode
        self.metadata = {
            "render_modes": list(RENDER_MODES),
            "render_fps": _fps(core.dt),
            "autoreset_mode": mode,
        }
        obs_space = gym.spaces.Box(low=core.obs_low, high=core.obs_high, dtype=np.float64)
        self.single_observation_space: gym.Space[Any] = obs_space
        if core.goal_dim:
            # The single env's Dict (envc.make's: Gymnasium-Robotics' spaces; Dict sorts keys).
            goal = gym.spaces.Box(-np.inf, np.inf, shape=(core.goal_dim,), dtype=np.float64)
            self.single_observation_space = gym.spaces.Dict(
                dict(desired_goal=goal, achieved_goal=goal, observation=obs_space)
            )
        self.single_action_space = gym.spaces.Box(
            low=core.act_low.astype(np.float32),
            high=core.act_high.astype(np.float32),
            dtype=np.float32,
        )
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.dt = core.dt

    @property
    def num_threads(self) -> int:
        """Threads stepping the envs (the calling thread included)."""
        return self._core.threads

    @property
    def copy(self) -> bool:
        """Fresh arrays every call (``True``, Gymnasium's default), or the env's own arrays,
        overwritten by the next ``reset`` or ``step`` (``False``)."""
        return self._copy

    @copy.setter
    def copy(self, value: bool) -> None:
        self._copy = bool(value)
        self._core.copy = self._copy

    def reset(
        self,
        *,
        seed: int | list[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[_F64 | dict[str, _F64], dict[str, Any]]:
        """Reset every env: ``seed=s`` seeds env i with ``s + i``, a list one seed per env.

        ``options={"reset_mask": mask}`` (a bool array over envs) resets only the masked envs,
        as Gymnasium's vector envs do; the infos are then those of the masked envs.
        """
        mask = _errors.options(options).get("reset_mask")
        if mask is not None:
            mask = self._check_mask(mask)
        if isinstance(seed, np.ndarray) and seed.ndim == 0:
            seed = seed.item()
        if seed is None:
            seeds = None
        elif isinstance(seed, (list, tuple, np.ndarray)):
            seeds = [_errors.seed(s) for s in seed]
            if len(seeds) != self.num_envs:
                raise _errors.coded(
                    f"error[E1105]: If seeds are passed as a list the length must match "
                    f"num_envs={self.num_envs} but got length={len(seeds)}.",
                    "E1105",
                )
        else:
            first = _errors.integer(seed, "seed", 0, 2**64 - self.num_envs + 1)
            seeds = [first + i for i in range(self.num_envs)]
        return self._core.reset(seeds, None if mask is None else mask.tolist(), self._copy)

    def _check_mask(self, mask: object) -> np.ndarray:
        """A ``reset_mask`` as Gymnasium's vector envs check it."""
        if not isinstance(mask, np.ndarray):
            raise _errors.coded(
                f"error[E1105]: `options['reset_mask']` must be a numpy array, got {type(mask)}",
                "E1105",
            )
        if mask.shape != (self.num_envs,):
            raise _errors.coded(
                f"error[E1105]: `options['reset_mask']` must have shape `({self.num_envs},)`, "
                f"got {mask.shape}",
                "E1105",
            )
        if mask.dtype != np.bool_:
            raise _errors.coded(
                f"error[E1105]: `options['reset_mask']` must have `dtype=np.bool_`, "
                f"got {mask.dtype}",
                "E1105",
            )
        if not mask.any():
            raise _errors.coded(
                "error[E1105]: `options['reset_mask']` must contain a boolean array with at "
                f"least one True value, got reset_mask={mask}",
                "E1105",
            )
        return mask

    def step(
        self, actions: npt.ArrayLike
    ) -> tuple[
        _F64 | dict[str, _F64], _F64, npt.NDArray[np.bool_], npt.NDArray[np.bool_], dict[str, Any]
    ]:
        """Step every env with its row of ``actions`` (``(num_envs, act_dim)``)."""
        return self._core.step(actions)

    def render(self) -> tuple[_Frame, ...] | None:
        """Every env's frame in ``render_mode``, as a tuple (Gymnasium's vector ``render``)."""
        if self.render_mode is None:
            return None
        # `check_render_mode` let only envc's modes through.
        mode = cast("_RenderMode", self.render_mode)
        return tuple(self._core.render(i, mode) for i in range(self.num_envs))

    def close_extras(self, **kwargs: Any) -> None:
        """Stop the threads and free the envs."""
        core = getattr(self, "_core", None)  # None when __init__ failed
        if core is not None:
            core.close()  # waits for a call running in another thread


def make_vec(
    id_or_path: str,
    num_envs: int = 1,
    num_threads: int | None = None,
    autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
    backend: str | None = None,
    device: str | None = None,
    **overrides: Any,
) -> Any:
    """A vector env of a bundled task id (``"Ant-v5"``) or a task spec file.

    ``envc.make_vec("Ant-v5", 8)`` is ``gymnasium.make_vec("envc/Ant-v5", num_envs=8,
    vectorization_mode="vector_entry_point")``: an :class:`EnvcVectorEnv` stepped by
    ``num_threads`` Rust threads (default: as many as there are CPUs, at most ``num_envs``).
    Keyword arguments are the spec's parameters and ``max_episode_steps``, as for ``envc.make``.

    ``backend="mjx"`` (with ``device="cuda"`` or ``"cpu"``) runs the same spec batched on a GPU
    backend instead: an :class:`envc.gpu.GpuVecEnv` with JAX arrays (docs/gpu.md).
    """
    if backend is not None:
        from . import gpu

        return gpu.make_vec(id_or_path, num_envs, backend=backend, device=device, **overrides)
    from ._registry import env_id_for, spec_of

    num_envs = _errors.integer(num_envs, "num_envs", 1, 2**63)
    env_id = env_id_for(_id(id_or_path), overrides)
    if spec_of(env_id).vector_entry_point is None:
        raise _errors.coded(
            f"error[E0602]: `{id_or_path}` is not a task spec: vector envs step task specs", "E0602"
        )
    return gym.make_vec(
        env_id,
        num_envs=num_envs,
        vectorization_mode="vector_entry_point",
        num_threads=num_threads,
        autoreset_mode=autoreset_mode,
        **overrides,
    )
