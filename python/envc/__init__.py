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

import os as _os
import sys as _sys
from typing import TYPE_CHECKING, Any

from ._mujoco import load_core as _load_core

# `${python:PACKAGE}` in a spec's xml_file is found on this interpreter's search path (the
# resolver reads ENVC_PYTHON_PATH; a user's own setting wins).
_os.environ.setdefault("ENVC_PYTHON_PATH", _os.pathsep.join(p for p in _sys.path if p))

# The native core built for the installed MuJoCo (envc/_mujoco.py): every module below imports it
# as `envc._envc`.
if TYPE_CHECKING:
    from . import _envc  # the checker reads its stub, _envc.pyi
else:
    _envc = _load_core()


def _bundle_root() -> str | None:
    """The package's own specs and models: its data in an installed wheel, or the checkout an
    editable install lives in. ``None`` leaves it to the extension (its embedded copy)."""
    here = _os.path.dirname(_os.path.abspath(__file__))
    for root in (_os.path.join(here, "_bundle"), _os.path.dirname(_os.path.dirname(here))):
        if _os.path.isdir(_os.path.join(root, "specs")) and _os.path.isdir(
            _os.path.join(root, "assets")
        ):
            return root
    return None


if (_root := _bundle_root()) is not None:
    _envc.set_bundle_root(_root)
from ._datasets import collect, recover_environment
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
from ._gym import (
    DatasetWarning,
    EnvcEnv,
    ParityWarning,
    _parity_warning,
    make,
    overrides_to_toml,
)
from ._registry import bundled_ids, register, register_all
from ._vector import EnvcVectorEnv, make_vec

__all__ = [
    "ActionError",
    "ArgumentError",
    "DatasetError",
    "DatasetWarning",
    "EnvcEnv",
    "EnvcMazeEnv",
    "EnvcParallelEnv",
    "EnvcVectorEnv",
    "Error",
    "InternalError",
    "KindError",
    "ModelError",
    "NotResetError",
    "ParityWarning",
    "SimulationError",
    "SpecError",
    "UnknownParameterError",
    "bundled_ids",
    "collect",
    "make",
    "make_vec",
    "overrides_to_toml",
    "parallel_env",
    "recover_environment",
    "register",
]
__version__: str = _envc.__version__
__mujoco_version__ = _envc.__mujoco_version__

# Parity is proven against one Gymnasium release; any other 1.4.x is warned about, once.
import gymnasium as _gymnasium

_parity_warning(_gymnasium.__version__)

register_all()

# Mazes and multi-agent envs need gymnasium-robotics and PettingZoo (the `robotics` extra):
# imported on first use, so `import envc` stays light and works without them.
_LAZY = {
    "EnvcMazeEnv": ("._maze", "EnvcMazeEnv"),
    "EnvcParallelEnv": ("._pettingzoo", "EnvcParallelEnv"),
    "parallel_env": ("._pettingzoo", "parallel_env"),
}


def __getattr__(name: str) -> Any:
    if name == "gpu":
        # The batched executor needs JAX: imported on first use, as an attribute too.
        import importlib

        return importlib.import_module(".gpu", __name__)
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        return getattr(importlib.import_module(module, __name__), attr)
    raise AttributeError(f"module 'envc' has no attribute {name!r}")
