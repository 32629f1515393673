"""The MJX backend (MuJoCo's JAX implementation, `mujoco-mjx` 3.17.0): physics and the fields the
term evaluator reads, for one world (the executor vmaps it)."""

from __future__ import annotations

import os
import tempfile
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp

from ._plan import FIELDS

if TYPE_CHECKING:
    import mujoco
    from mujoco import mjx

    from ._plan import Plan
    from ._terms import Fields

NAME = "mjx"


def load_mjmodel(mjb: bytes) -> mujoco.MjModel:
    """The compiled model from envc's MJB bytes (exactly the model the CPU core runs)."""
    import mujoco

    fd, path = tempfile.mkstemp(suffix=".mjb")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(mjb)
        return mujoco.MjModel.from_binary_path(path)
    finally:
        os.unlink(path)


class MjxBackend:
    """Physics through `mjx.step`; fields as flat arrays, named as envc's selectors name them."""

    name = NAME
    fields_supported = FIELDS

    def __init__(self, plan: Plan, device: jax.Device | None = None) -> None:
        from mujoco import mjx

        self.mjx = mjx
        self.mjm = load_mjmodel(plan.mjb)
        try:
            self.m = mjx.put_model(self.mjm, device=device, impl="jax")
            self.d0 = mjx.make_data(self.m, device=device, impl="jax")
        except NotImplementedError as e:
            # MJX's own refusal of a model feature, in envc's coded form by the caller.
            raise _ModelRefused(str(e)) from e
        self.frame_skip = int(plan["frame_skip"])
        self.rne = bool(plan["needs_rne_post_constraint"])
        self.body_mass = jnp.asarray(self.mjm.body_mass, dtype=jnp.float32)

    def ignored_options(self) -> list[str]:
        """`[physics]` options the compiled model sets that MJX would ignore without a word."""
        import mujoco

        o, default = self.mjm.opt, mujoco.MjModel.from_xml_string("<mujoco/>").opt
        out = []
        if o.noslip_iterations != default.noslip_iterations:
            out.append(
                f"[physics] noslip_iterations = {o.noslip_iterations} (MJX has no noslip solver)"
            )
        if o.ccd_iterations != default.ccd_iterations:
            out.append(
                f"[physics] ccd_iterations = {o.ccd_iterations} (MJX ignores it; MuJoCo's default "
                f"is {default.ccd_iterations})"
            )
        return out

    # -- state ----------------------------------------------------------------------------------
    def qpos0(self) -> jax.Array:
        return self.m.qpos0

    def initial(self, qpos: jax.Array, qvel: jax.Array) -> mjx.Data:
        """A fresh world at (qpos, qvel), derived quantities computed (Gymnasium's set_state:
        reset data, write the state, `mj_forward`)."""
        d = self.d0.replace(qpos=qpos, qvel=qvel)
        return self.mjx.forward(self.m, d)

    # -- physics --------------------------------------------------------------------------------
    def physics(self, d: mjx.Data, ctrl: jax.Array) -> mjx.Data:
        """`frame_skip` × `mj_step` with `ctrl`, then `mj_rnePostConstraint` when the spec reads
        contact forces (as the CPU core)."""
        d = d.replace(ctrl=ctrl)

        def body(_: jax.Array, d: mjx.Data) -> mjx.Data:
            return self.mjx.step(self.m, d)

        d = jax.lax.fori_loop(0, self.frame_skip, body, d)
        if self.rne:
            d = self.mjx.rne_postconstraint(self.m, d)
        return d

    # -- fields ---------------------------------------------------------------------------------
    def fields(self, d: mjx.Data, action: jax.Array) -> Fields:
        """A lookup of flat field arrays (only what is asked for is computed)."""
        m = self.m

        def get(name: str) -> jax.Array:
            if name == "qpos":
                return d.qpos
            if name == "qvel":
                return d.qvel
            if name == "qpos0":
                return m.qpos0
            if name == "action":
                return action
            if name == "ctrl":
                return d.ctrl
            if name == "mass_center":
                w = self.body_mass[:, None] * d.xipos
                return jnp.sum(w, axis=0) / jnp.sum(self.body_mass)
            if name in ("cfrc_ext", "cfrc_int", "cacc", "cinert", "ten_velocity"):
                return getattr(d._impl, name).reshape(-1)
            return getattr(d, name).reshape(-1)

        return get


class _ModelRefused(Exception):
    pass
