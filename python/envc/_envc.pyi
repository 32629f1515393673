"""Type stubs of envc's native core (the `envc-python` crate). The public API is `envc`'s Python
classes; these are the objects they wrap."""

import os
from collections.abc import Callable
from os import PathLike
from typing import Any, Literal, final

import numpy as np
import numpy.typing as npt
from typing_extensions import Self, disjoint_base

__all__ = [
    "EnvCore",
    "MazeCore",
    "MultiAgentCore",
    "ShardedCollection",
    "SpecError",
    "SpecPolicy",
    "TaskCore",
    "VecCore",
    "__mujoco_version__",
    "__version__",
    "build_dataset",
    "build_driver",
    "build_shard",
    "bundle_root",
    "cli_main",
    "collect",
    "collect_shard",
    "dataset_build_plan",
    "datasets_dir",
    "describe",
    "gpu_plan",
    "open",
    "parameters",
    "read_dataset_spec",
    "recover_spec",
    "register",
    "registry",
    "set_bundle_root",
    "spec_path_problems",
    "with_reference_scores",
]

__mujoco_version__: str
__version__: str

from ._errors import SpecError as SpecError

# The strings the core takes and gives (it refuses any other with a coded error).
_Kind = Literal["task", "maze", "agents"]
_RenderMode = Literal["rgb_array", "depth_array", "rgbd_tuple"]
_Format = Literal["arrow", "hdf5"]
_Policy = Literal["zero", "random", "replay", "callable"]
_Autoreset = Literal["NextStep", "SameStep"]
_F64 = npt.NDArray[np.float64]
# `rgb_array`: (h, w, 3) uint8; `depth_array`: (h, w) float32; `rgbd_tuple`: the pair.
_Frame = (
    npt.NDArray[np.uint8]
    | npt.NDArray[np.float32]
    | tuple[npt.NDArray[np.uint8], npt.NDArray[np.float32]]
)
# What an env's observation is: a task's vector (a `[goal]` task's or a maze's dict of them),
# a multi-agent spec's one per agent.
_Obs = _F64 | dict[str, _F64] | list[_F64]
# A `policy_fn`'s action: anything `numpy.asarray(action, "float32")` reads.
_PolicyFn = Callable[[_F64, np.random.Generator], npt.ArrayLike]

def open(
    id_or_path: str, overrides: list[tuple[str, str]] = ...
) -> tuple[_Kind, TaskCore | MazeCore | MultiAgentCore]:
    """Open any kind of spec: `(kind, core)` with kind "task", "maze" or "agents"."""

def gpu_plan(id_or_path: str, overrides: list[tuple[str, str]] = ...) -> tuple[str, bytes]:
    """The resolved IR of a task spec as JSON, and its compiled model as MJB bytes (`envc.gpu`)."""

def registry(
    only: list[str] | None = None,
) -> list[tuple[str, _Kind, int | None, bool, float | None]]:
    """Every known id (or those of `only`): `(id, kind, max_episode_steps, example,
    reward_threshold)`."""

def spec_path_problems() -> list[str]:
    """The problems of `ENVC_SPEC_PATH`: the entries left out of the registry."""

def recover_spec(
    dataset_id: str,
    provenance: str,
    accept_changed_spec: bool = ...,
    refuse_other_mujoco: bool = ...,
    use_recorded_spec: bool = ...,
) -> tuple[str, list[str]]:
    """The spec to open for a dataset's `envc_provenance` (JSON text): `(id or path, warnings)`."""

def describe(
    id_or_path: str, overrides: list[tuple[str, str]] = ...
) -> tuple[_Kind, str, int | None]:
    """`(kind, id, max_episode_steps)` without building the env, under the overrides."""

def register(path: str | os.PathLike[str]) -> list[str]:
    """Register the ids of a spec file or directory (E0603 for a taken id); returns them."""

def set_bundle_root(path: str | os.PathLike[str]) -> bool:
    """Name the directory holding the bundled specs/ and assets/ (before first use)."""

def cli_main(argv: list[str]) -> int:
    """Run the ``envc`` command line ``argv`` (program name first); return its exit status."""

def bundle_root() -> tuple[str | None, str]:
    """(the bundle root or None, where it comes from or why there is none)."""

def parameters(id_or_path: str) -> list[tuple[str, str, str, str]]:
    """`(name, type, default as TOML, doc)` of every parameter."""

def collect(
    id_or_path: str,
    dataset_id: str,
    episodes: int,
    policy: _Policy = ...,
    seed: int | None = ...,
    format: _Format = ...,
    root: str | PathLike[str] | None = ...,
    overrides: list[tuple[str, str]] = ...,
    actions: list[float] | None = ...,
    author: str | None = ...,
    description: str | None = ...,
    env_spec: str | None = ...,
    policy_fn: _PolicyFn | None = ...,
) -> tuple[str, int, int]:
    """`(dataset directory, steps, seed)`."""

def collect_shard(
    id_or_path: str,
    staging: str | PathLike[str],
    start: int,
    end: int,
    seed: int,
    policy: _Policy = ...,
    format: _Format = ...,
    overrides: list[tuple[str, str]] = ...,
    actions: list[float] | None = ...,
    policy_fn: _PolicyFn | None = ...,
) -> list[tuple[int, int]]:
    """A worker's episodes `start..end` into a sharded collection's staging directory:
    `(steps, bytes)` of each."""

def build_dataset(
    spec: str,
    steps: int | None = ...,
    root: str | PathLike[str] | None = ...,
    format: _Format | None = ...,
    dataset_id: str | None = ...,
) -> tuple[str, int, int]:
    """Build a dataset spec's dataset in this process: `(directory, steps, episodes)`."""

def dataset_build_plan(
    spec: str, steps: int | None = ..., format: _Format | None = ...
) -> tuple[int, Literal["steps", "episodes"], int, int, _Format]:
    """`(seed, "steps" | "episodes", budget, max_episode_steps, format)` of a dataset spec."""

def build_shard(
    spec: str, staging: str | PathLike[str], start: int, end: int, format: _Format
) -> list[tuple[int, int]]:
    """A worker's episodes `start..end` of a sharded build: `(steps, bytes)` of each."""

def build_driver(
    spec: str,
    steps: int | None = ...,
    root: str | PathLike[str] | None = ...,
    format: _Format | None = ...,
    dataset_id: str | None = ...,
) -> ShardedCollection:
    """The driver of a sharded build (holds the staging directory's lock)."""

def datasets_dir() -> str:
    """The bundled dataset specs' directory."""

def read_dataset_spec(spec: str) -> dict[str, Any]:
    """A dataset spec file or bundled id, checked (E1801 at its line and column), as its TOML
    data: the tables as written, `[train]` included."""

def with_reference_scores(
    path: str | PathLike[str],
    ref_min_score: float,
    ref_max_score: float,
    num_episodes_average_score: int,
) -> str:
    """The spec's text with `[reference_scores]` set, every other line kept as written."""

@final
class SpecPolicy:
    """A dataset spec's `.npz` policy, run in Rust: `policy(obs) -> float32 action`."""

    def __new__(cls, spec: str, seed: int = ..., deterministic: bool | None = ...) -> Self: ...
    def __call__(self, obs: npt.NDArray[np.float64]) -> npt.NDArray[np.float32]: ...

@final
class ShardedCollection:
    """The driver of a sharded collection (holds the staging directory's lock)."""

    @property
    def seed(self) -> int: ...
    @property
    def staging(self) -> str: ...
    def __new__(
        cls,
        id_or_path: str,
        dataset_id: str,
        episodes: int,
        policy: _Policy = ...,
        seed: int | None = ...,
        format: _Format = ...,
        root: str | PathLike[str] | None = ...,
        overrides: list[tuple[str, str]] = ...,
        actions: list[float] | None = ...,
        author: str | None = ...,
        description: str | None = ...,
        env_spec: str | None = ...,
        callable: bool = ...,
    ) -> Self: ...
    def finish(self, episodes: list[tuple[int, int]], trim: bool = ...) -> str: ...
    def abort(self) -> None: ...

@disjoint_base
class EnvCore:
    """What every kind's core shares (`open` returns the kind's subclass): reset, step with a
    joint action (a multi-agent spec: the global action), its bounds, dt, the time limit,
    numerics, warnings, render and close."""

    @property
    def kind(self) -> _Kind: ...
    @property
    def id(self) -> str: ...
    @property
    def dt(self) -> float: ...
    @property
    def max_episode_steps(self) -> int | None: ...
    @property
    def act_low(self) -> _F64: ...
    @property
    def act_high(self) -> _F64: ...
    @property
    def numerics(self) -> str: ...
    @numerics.setter
    def numerics(self, name: str) -> None: ...
    @property
    def warnings(self) -> list[str]: ...
    def reset(self, seed: int | None = None) -> tuple[_Obs, dict[str, Any]]: ...
    def step(self, action: _F64) -> tuple[_Obs, float, bool, bool, dict[str, Any]]: ...
    def step_f32(
        self, action: npt.NDArray[np.float32]
    ) -> tuple[_Obs, float, bool, bool, dict[str, Any]]: ...
    def render(self, mode: _RenderMode) -> _Frame:
        """A frame in Gymnasium's `render_mode`: an `(h, w, 3)` uint8 array, an `(h, w)` float32
        depth array, or the pair."""
    def close(self) -> None:
        """Free the renderer (the next `render` makes a new one)."""

@final
class TaskCore(EnvCore):
    """A task env (`envc.EnvcEnv` wraps it)."""

    @property
    def obs_low(self) -> _F64: ...
    @property
    def obs_high(self) -> _F64: ...
    @property
    def params(self) -> list[tuple[str, str]]: ...
    @property
    def goal_dim(self) -> int: ...
    @property
    def goal_parts(self) -> list[tuple[str, int]]: ...
    @property
    def parts_info_keys(self) -> list[str]: ...
    @property
    def goal_reward_float32(self) -> bool: ...
    @property
    def terminations(self) -> int: ...
    @property
    def float32_info_keys(self) -> list[str]: ...
    @property
    def bool_info_keys(self) -> list[str]: ...
    def reset(self, seed: int | None = None) -> tuple[_F64 | dict[str, _F64], dict[str, Any]]: ...
    def step(
        self, action: _F64
    ) -> tuple[_F64 | dict[str, _F64], float, bool, bool, dict[str, Any]]: ...
    def step_f32(
        self, action: npt.NDArray[np.float32]
    ) -> tuple[_F64 | dict[str, _F64], float, bool, bool, dict[str, Any]]: ...
    def state(self) -> tuple[_F64, _F64]: ...
    def compute_reward(self, achieved: _F64, desired: _F64) -> _F64: ...

@final
class MultiAgentCore(EnvCore):
    """A multi-agent env (`envc.EnvcParallelEnv` wraps it); its joint action is the global one."""

    @property
    def base_id(self) -> str: ...
    @property
    def conf(self) -> str: ...
    @property
    def confs(self) -> list[str]: ...
    @property
    def k(self) -> int: ...
    @property
    def possible_agents(self) -> list[str]: ...
    @property
    def agents(self) -> list[str]: ...
    @property
    def state_low(self) -> _F64: ...
    @property
    def state_high(self) -> _F64: ...
    def reset(self, seed: int | None = None) -> tuple[list[_F64], dict[str, Any]]: ...
    def step(self, action: _F64) -> tuple[list[_F64], float, bool, bool, dict[str, Any]]: ...
    def step_f32(
        self, action: npt.NDArray[np.float32]
    ) -> tuple[list[_F64], float, bool, bool, dict[str, Any]]: ...
    def step_agents(
        self, actions: list[_F64]
    ) -> tuple[list[_F64], float, bool, bool, dict[str, Any]]: ...
    def state(self) -> _F64: ...
    def local_actions_to_global(self, actions: list[_F64]) -> _F64: ...
    def global_action_to_local(self, action: _F64) -> list[_F64]: ...
    def global_state_to_local(self, state: _F64) -> list[_F64]: ...
    def local_observations_to_global(self, obs: list[_F64]) -> _F64: ...
    def agent_obs_low(self, agent: int) -> _F64: ...
    def agent_obs_high(self, agent: int) -> _F64: ...
    def agent_act_low(self, agent: int) -> _F64: ...
    def agent_act_high(self, agent: int) -> _F64: ...
    def color_agents(self, on: bool) -> None: ...

@final
class MazeCore(EnvCore):
    """A maze env (`envc.EnvcMazeEnv` wraps it): dict observations, batched goal functions."""

    @property
    def observation_dim(self) -> int: ...
    @property
    def goal(self) -> _F64: ...
    @property
    def map_shape(self) -> tuple[int, int]: ...
    @property
    def continuing_task(self) -> bool: ...
    @property
    def reset_target(self) -> bool: ...
    @property
    def reward_type(self) -> Literal["sparse", "dense"]: ...
    def reset(
        self,
        seed: int | None = None,
        goal_cell: tuple[int, int] | None = None,
        reset_cell: tuple[int, int] | None = None,
    ) -> tuple[dict[str, _F64], dict[str, Any]]: ...
    def step(self, action: _F64) -> tuple[dict[str, _F64], float, bool, bool, dict[str, Any]]: ...
    def step_f32(
        self, action: npt.NDArray[np.float32]
    ) -> tuple[dict[str, _F64], float, bool, bool, dict[str, Any]]: ...
    def compute_reward(self, achieved: _F64, desired: _F64) -> _F64: ...
    def compute_terminated(self, achieved: _F64, desired: _F64) -> npt.NDArray[np.bool_]: ...
    def compute_truncated(self, achieved: _F64, desired: _F64) -> npt.NDArray[np.bool_]: ...

@final
class VecCore:
    """Many task envs stepped by Rust threads, their batches and Gymnasium vector infos built
    in Rust (`envc.EnvcVectorEnv` wraps it)."""

    def __new__(
        cls,
        id_or_path: str,
        overrides: list[tuple[str, str]],
        num_envs: int,
        threads: int,
        autoreset: _Autoreset,
    ) -> Self: ...
    @property
    def num_envs(self) -> int: ...
    @property
    def threads(self) -> int: ...
    @property
    def autoreset(self) -> _Autoreset: ...
    @property
    def id(self) -> str: ...
    @property
    def dt(self) -> float: ...
    @property
    def max_episode_steps(self) -> int | None: ...
    @property
    def obs_low(self) -> _F64: ...
    @property
    def obs_high(self) -> _F64: ...
    @property
    def act_low(self) -> _F64: ...
    @property
    def act_high(self) -> _F64: ...
    @property
    def goal_dim(self) -> int:
        """The length of a `[goal]` task's goal vectors (0: plain observations)."""
    @property
    def numerics(self) -> str: ...
    @numerics.setter
    def numerics(self, name: str) -> None: ...
    @property
    def bytes_per_env(self) -> tuple[int, int]:
        """What each env costs in memory as estimated before making them (E1403): resident
        and mapped bytes."""
    def reset(
        self,
        seeds: list[int | None] | None = None,
        mask: list[bool] | None = None,
        copy: bool = True,
    ) -> tuple[_F64 | dict[str, _F64], dict[str, Any]]:
        """`(obs, info)`; a `[goal]` task's obs is a dict of `achieved_goal`, `desired_goal`
        and `observation` batches."""
    def step(
        self, actions: npt.ArrayLike, copy: bool | None = None
    ) -> tuple[
        _F64 | dict[str, _F64], _F64, npt.NDArray[np.bool_], npt.NDArray[np.bool_], dict[str, Any]
    ]:
        """One batch step; the core refuses a call while another thread's runs (E1106).
        `copy=None` takes `self.copy`."""
    @property
    def copy(self) -> bool: ...
    @copy.setter
    def copy(self, copy: bool) -> None: ...
    def rust_steps(
        self,
        actions: npt.NDArray[np.float32] | npt.NDArray[np.float64],
        first: int,
        count: int,
    ) -> None:
        """The Rust `VecEnv` alone, for benchmarks: `count` steps over the `(k, num_envs,
        act_dim)` batches of `actions` (step t takes batch `(first + t) % k`), nothing built for
        Python in between; the steps count in `env_steps`."""
    @property
    def env_steps(self) -> int:
        """Env steps taken by `step` and `rust_steps`, NextStep's autoreset steps not counted."""
    def render(self, index: int, mode: _RenderMode) -> _Frame:
        """A frame of env `index` in Gymnasium's `render_mode` (as `EnvCore.render`)."""
    def close(self) -> None: ...
