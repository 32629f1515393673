"""The one fix Gymnasium-Robotics 1.4.2 needs on MuJoCo 3.17: `mujoco_utils`' joint functions test
`joint_type in (mjJNT_HINGE, mjJNT_SLIDE)`, which compares pybind11 enums with a numpy int32 and is
always false, so Fetch, Shadow Hand and Kitchen fail at `gym.make` with a bare AssertionError. Here
the four functions see `int(model.jnt_type[id])` instead; nothing numeric changes.

    import robotics_patch  # before gymnasium_robotics makes an env
"""
import functools

from gymnasium_robotics.utils import mujoco_utils


class _IntJointTypes:
    """A model whose `jnt_type` reads as Python ints; everything else is the model's own."""

    def __init__(self, model):
        self._model = model

    def __getattr__(self, name):
        value = getattr(self._model, name)
        return [int(t) for t in value] if name == "jnt_type" else value


def _patched(f):
    @functools.wraps(f)
    def g(model, data, name, *args):
        return f(_IntJointTypes(model), data, name, *args)

    return g


for _name in ("get_joint_qpos", "set_joint_qpos", "get_joint_qvel", "set_joint_qvel"):
    if not getattr(getattr(mujoco_utils, _name), "_envc_patched", False):
        _g = _patched(getattr(mujoco_utils, _name))
        _g._envc_patched = True
        setattr(mujoco_utils, _name, _g)
