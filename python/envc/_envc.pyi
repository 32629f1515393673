"""Type stubs of envc's native core (the `envc-python` crate). The public API is `envc`'s Python
classes; these are the objects they wrap."""

from os import PathLike
import os
from typing import Any, Callable

import numpy as np
import numpy.typing as npt

__mujoco_version__: str
__version__: str

from ._errors import SpecError as SpecError

def open(id_or_path: str, overrides: list[tuple[str, str]] = ...) -> tuple[str, Any]:
    """Open any kind of spec: `(kind, core)` with kind "task", "maze" or "agents"."""

def gpu_plan(id_or_path: str, overrides: list[tuple[str, str]] = ...) -> tuple[str, bytes]:
    """The resolved IR of a task spec as JSON, and its compiled model as MJB bytes (`envc.gpu`)."""

def registry() -> list[tuple[str, str, int | None, bool, float | None]]:
    """Every bundled id: `(id, kind, max_episode_steps, example, reward_threshold)`."""

def describe(
    id_or_path: str, overrides: list[tuple[str, str]] = ...
) -> tuple[str, str, int | None]:
    """`(kind, id, max_episode_steps)` without building the env, under the overrides."""

def register(path: str | os.PathLike[str]) -> list[str]:
    """Register the ids of a spec file or directory (E0603 for a taken id); returns them."""

def set_bundle_root(path: str | os.PathLike[str]) -> bool:
    """Name the directory holding the bundled specs/ and assets/ (before first use)."""

def bundle_root() -> tuple[str | None, str]:
    """(the bundle root or None, where it comes from or why there is none)."""

def parameters(id_or_path: str) -> list[tuple[str, str, str, str]]:
    """`(name, type, default as TOML, doc)` of every parameter."""

def collect(
    id_or_path: str,
    dataset_id: str,
    episodes: int,
    policy: str = ...,
    seed: int | None = ...,
    format: str = ...,
    root: str | PathLike[str] | None = ...,
    overrides: list[tuple[str, str]] = ...,
    actions: list[float] | None = ...,
    author: str | None = ...,
    description: str | None = ...,
    env_spec: str | None = ...,
    policy_fn: Callable[[npt.NDArray[np.float64], np.random.Generator], Any] | None = ...,
) -> tuple[str, int, int]:
    """`(dataset directory, steps, seed)`."""

def collect_shard(
    id_or_path: str,
    staging: str | PathLike[str],
    start: int,
    end: int,
    seed: int,
    policy: str = ...,
    format: str = ...,
    overrides: list[tuple[str, str]] = ...,
    actions: list[float] | None = ...,
    policy_fn: Callable[[npt.NDArray[np.float64], np.random.Generator], Any] | None = ...,
) -> list[tuple[int, int]]:
    """A worker's episodes `start..end` into a sharded collection's staging directory:
    `(steps, bytes)` of each."""

def build_dataset(
    spec: str,
    steps: int | None = ...,
    root: str | PathLike[str] | None = ...,
    format: str | None = ...,
    dataset_id: str | None = ...,
) -> tuple[str, int, int]:
    """Build a dataset spec's dataset in this process: `(directory, steps, episodes)`."""

def dataset_build_plan(
    spec: str, steps: int | None = ..., format: str | None = ...
) -> tuple[int, str, int, int, str]:
    """`(seed, "steps" | "episodes", budget, max_episode_steps, format)` of a dataset spec."""

def build_shard(
    spec: str, staging: str | PathLike[str], start: int, end: int, format: str
) -> list[tuple[int, int]]:
    """A worker's episodes `start..end` of a sharded build: `(steps, bytes)` of each."""

def build_driver(
    spec: str,
    steps: int | None = ...,
    root: str | PathLike[str] | None = ...,
    format: str | None = ...,
    dataset_id: str | None = ...,
) -> ShardedCollection:
    """The driver of a sharded build (holds the staging directory's lock)."""

def datasets_dir() -> str:
    """The bundled dataset specs' directory."""

class SpecPolicy:
    """A dataset spec's `.npz` policy, run in Rust: `policy(obs) -> float32 action`."""

    def __init__(self, spec: str, seed: int = ..., deterministic: bool | None = ...) -> None: ...
    def __call__(self, obs: npt.NDArray[np.float64]) -> npt.NDArray[np.float32]: ...

class ShardedCollection:
    """The driver of a sharded collection (holds the staging directory's lock)."""

    seed: int
    staging: str
    def __init__(
        self,
        id_or_path: str,
        dataset_id: str,
        episodes: int,
        policy: str = ...,
        seed: int | None = ...,
        format: str = ...,
        root: str | PathLike[str] | None = ...,
        overrides: list[tuple[str, str]] = ...,
        actions: list[float] | None = ...,
        author: str | None = ...,
        description: str | None = ...,
        env_spec: str | None = ...,
        callable: bool = ...,
    ) -> None: ...
    def finish(self, episodes: list[tuple[int, int]]) -> str: ...
    def abort(self) -> None: ...

class TaskCore:
    id: str
    dt: float
    max_episode_steps: int | None
    obs_low: npt.NDArray[np.float64]
    obs_high: npt.NDArray[np.float64]
    act_low: npt.NDArray[np.float64]
    act_high: npt.NDArray[np.float64]
    numerics: str
    warnings: list[str]
    params: list[tuple[str, str]]
    def reset(self, seed: int | None = ...) -> tuple[npt.NDArray[np.float64], dict[str, Any]]: ...
    def step(
        self, action: npt.NDArray[np.float64]
    ) -> tuple[npt.NDArray[np.float64], float, bool, bool, dict[str, Any]]: ...
    def step_f32(
        self, action: npt.NDArray[np.float32]
    ) -> tuple[npt.NDArray[np.float64], float, bool, bool, dict[str, Any]]: ...
    def state(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...

_F64 = npt.NDArray[np.float64]

class AgentsCore:
    """A multi-agent env (`envc.EnvcParallelEnv` wraps it)."""

    id: str
    base_id: str
    conf: str
    confs: list[str]
    k: int
    dt: float
    max_episode_steps: int | None
    possible_agents: list[str]
    agents: list[str]
    state_low: _F64
    state_high: _F64
    global_act_low: _F64
    global_act_high: _F64
    numerics: str
    warnings: list[str]
    def reset(self, seed: int | None = ...) -> tuple[list[_F64], dict[str, Any]]: ...
    def step(self, actions: list[_F64]) -> tuple[list[_F64], float, bool, bool, dict[str, Any]]: ...
    def step_global(self, action: _F64) -> tuple[list[_F64], float, bool, bool, dict[str, Any]]: ...
    def step_global_f32(
        self, action: npt.NDArray[np.float32]
    ) -> tuple[list[_F64], float, bool, bool, dict[str, Any]]: ...
    def state(self) -> _F64: ...
    def local_actions_to_global(self, actions: list[_F64]) -> _F64: ...
    def global_action_to_local(self, action: _F64) -> list[_F64]: ...
    def global_state_to_local(self, state: _F64) -> list[_F64]: ...
    def local_observations_to_global(self, observations: list[_F64]) -> _F64: ...
    def obs_low(self, agent: int) -> _F64: ...
    def obs_high(self, agent: int) -> _F64: ...
    def act_low(self, agent: int) -> _F64: ...
    def act_high(self, agent: int) -> _F64: ...
    def color_agents(self, on: bool) -> None: ...

class MazeCore:
    """A maze env (`envc.EnvcMazeEnv` wraps it): dict observations, batched goal functions."""

    id: str
    dt: float
    max_episode_steps: int | None
    observation_dim: int
    act_low: _F64
    act_high: _F64
    goal: _F64
    map_shape: tuple[int, int]
    continuing_task: bool
    reset_target: bool
    reward_type: str
    numerics: str
    warnings: list[str]
    def reset(
        self,
        seed: int | None = ...,
        goal_cell: tuple[int, int] | None = ...,
        reset_cell: tuple[int, int] | None = ...,
    ) -> tuple[dict[str, _F64], dict[str, Any]]: ...
    def step(self, action: _F64) -> tuple[dict[str, _F64], float, bool, bool, dict[str, Any]]: ...
    def step_f32(
        self, action: npt.NDArray[np.float32]
    ) -> tuple[dict[str, _F64], float, bool, bool, dict[str, Any]]: ...
    def compute_reward(self, achieved: _F64, desired: _F64) -> _F64: ...
    def compute_terminated(self, achieved: _F64, desired: _F64) -> npt.NDArray[np.bool_]: ...
    def compute_truncated(self, achieved: _F64, desired: _F64) -> npt.NDArray[np.bool_]: ...

class VecCore:
    """Many task envs stepped by Rust threads into numpy buffers filled in place
    (`envc.EnvcVectorEnv` wraps it)."""

    def __init__(
        self,
        id_or_path: str,
        overrides: list[tuple[str, str]],
        num_envs: int,
        threads: int,
        autoreset: str,
    ) -> None: ...
    num_envs: int
    threads: int
    autoreset: str
    id: str
    dt: float
    max_episode_steps: int | None
    obs_low: _F64
    obs_high: _F64
    act_low: _F64
    act_high: _F64
    numerics: str
    info_keys: list[tuple[str, int, int, bool]]
    buffers: dict[str, np.ndarray]
    generation: int
    """Bumped when a buffer the user made unusable was replaced: read `buffers` again."""
    def reset(self, seeds: list[int | None] | None = ..., mask: npt.NDArray[np.bool_] | None = ...) -> None: ...
    def step(self, actions: npt.NDArray[np.float64]) -> None: ...
    def step_f32(self, actions: npt.NDArray[np.float32]) -> None: ...
    def close(self) -> None: ...
