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
from ._envc import SpecError
from ._gym import EnvcEnv, make, overrides_to_toml
from ._registry import bundled_ids, register_all
from ._vector import EnvcVectorEnv, make_vec

__all__ = [
    "EnvcEnv",
    "EnvcVectorEnv",
    "SpecError",
    "bundled_ids",
    "make",
    "make_vec",
    "overrides_to_toml",
]
__version__ = "0.1.0"
__mujoco_version__ = _envc.__mujoco_version__

register_all()
