"""envc: robot RL environments compiled from TOML specs, bit-identical to Gymnasium's.

Switching costs one line::

    import envc, gymnasium as gym
    env = gym.make("envc/Ant-v5", ctrl_cost_weight=0.1)   # instead of gym.make("Ant-v5", ...)

or ``envc.make("Ant-v5")``, ``envc.make("path/to/my_robot.toml", frame_skip=10)``. Importing
``envc`` registers every bundled id under the ``envc/`` namespace. Every kind of spec (task, maze,
multi-agent) opens through one door: ``envc.make`` for single-agent envs, ``envc.make_vec`` for
vector envs, ``envc.parallel_env`` for multi-agent specs.
"""

from __future__ import annotations

from . import _envc
from ._datasets import collect
from ._errors import (
    ActionError,
    ArgumentError,
    DatasetError,
    Error,
    InternalError,
    KindError,
    ModelError,
    NotResetError,
    SimulationError,
    SpecError,
    UnknownParameterError,
)
from ._gym import EnvcEnv, make, overrides_to_toml
from ._registry import bundled_ids, register_all
from ._vector import EnvcVectorEnv, make_vec

__all__ = [
    "ActionError",
    "ArgumentError",
    "DatasetError",
    "Error",
    "InternalError",
    "KindError",
    "ModelError",
    "NotResetError",
    "SimulationError",
    "UnknownParameterError",
    "EnvcEnv",
    "EnvcMazeEnv",
    "EnvcVectorEnv",
    "EnvcParallelEnv",
    "SpecError",
    "bundled_ids",
    "collect",
    "make",
    "make_vec",
    "overrides_to_toml",
    "parallel_env",
]
__version__ = "0.1.0"
__mujoco_version__ = _envc.__mujoco_version__

register_all()

# Mazes and multi-agent envs need gymnasium-robotics and PettingZoo (the `robotics` extra):
# imported on first use, so `import envc` stays light and works without them.
_LAZY = {
    "EnvcMazeEnv": ("._maze", "EnvcMazeEnv"),
    "EnvcParallelEnv": ("._pettingzoo", "EnvcParallelEnv"),
    "parallel_env": ("._pettingzoo", "parallel_env"),
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        return getattr(importlib.import_module(module, __name__), attr)
    raise AttributeError(f"module 'envc' has no attribute {name!r}")
