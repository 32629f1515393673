"""envc on a GPU: thousands of worlds of one task spec, stepped as one XLA program.

``envc.make_vec("Ant-v5", num_envs=4096, backend="mjx", device="cuda")`` (or
``envc.gpu.make_vec``) opens the spec through the same door as the CPU core, takes its resolved IR
and its compiled model, and runs them batched on a pluggable backend; the first is MJX (MuJoCo's
JAX implementation). Arrays in and out are JAX arrays on the device. Parts of a spec the executor
cannot run are refused with one coded error (E1700) that lists them all. docs/gpu.md has the
design, the bounds against the CPU core and the figures."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ._plan import CODE, Plan, Unsupported, load

if TYPE_CHECKING:
    from contextlib import AbstractContextManager

    import gymnasium as gym
    import jax
    import numpy.typing as npt

    from .._errors import Error
    from ._executor import State
    from ._mjx import MjxBackend
    from ._vector import BraxView, GymnasiumView

__all__ = ["CODE", "GpuVecEnv", "Plan", "Unsupported", "backends", "make_vec", "plan"]


def backends() -> tuple[str, ...]:
    """The backends this build knows (each is an implementation of the same executor)."""
    return ("mjx",)


def plan(id_or_path: str, **overrides: Any) -> Plan:
    """The resolved IR and compiled model of a task spec, as the GPU executor reads them."""
    from .._gym import overrides_to_toml

    return load(id_or_path, overrides_to_toml(overrides))


def _device(device: str | None) -> jax.Device | None:
    import jax

    if device is None:
        return None
    platform = {"cuda": "gpu", "gpu": "gpu", "cpu": "cpu"}.get(device)
    if platform is None:
        raise _coded(f"device={device!r}: expected 'cuda' or 'cpu'", "E1105")
    try:
        return jax.devices(platform)[0]
    except RuntimeError as e:
        raise _coded(f"device={device!r}: JAX has no such device ({e})", "E1105") from None


def _coded(message: str, code: str) -> Error:
    from .._errors import coded

    return coded(f"error[{code}]: {message}", code)


def _backend(p: Plan, backend: str, device: jax.Device | None) -> MjxBackend:
    if backend not in backends():
        raise _coded(f"backend={backend!r}: expected one of {', '.join(backends())}", "E1105")
    from . import _mjx

    refused = p.refusals(_mjx.MjxBackend.fields_supported)
    try:
        b = _mjx.MjxBackend(p, device)
    except _mjx._ModelRefused as e:
        refused.append(f"the compiled model: MJX says: {e}")
    else:
        refused.extend(b.ignored_options())
    if refused:
        raise Unsupported(p.id, backend, refused)
    return b


class GpuVecEnv:
    """A batch of worlds of one task spec on a GPU backend (JAX arrays in and out).

    Stateful facade over the functional executor (``self.executor``: ``reset(key)``,
    ``step(state, action)``, ``reset_where(state, mask)``, all jitted). Autoreset is Gymnasium's
    same-step mode: a world that terminates or truncates is reset within the step; the returned
    observation is its first one and ``info["final_obs"]`` holds the last one."""

    def __init__(
        self,
        p: Plan,
        backend: MjxBackend,
        num_envs: int,
        seed: int = 0,
        device: jax.Device | None = None,
    ) -> None:
        import jax

        from ._executor import Executor

        self.plan = p
        self.backend = backend
        self.device = device
        self.num_envs = int(num_envs)
        self.executor = Executor(p, backend, self.num_envs)
        self.obs_dim = int(p["obs_dim"])
        self.act_dim = len(p["act_low"])
        self.act_low = p["act_low"]
        self.act_high = p["act_high"]
        self.dt = float(p["dt"])
        self.max_episode_steps = p["max_episode_steps"]
        self._key = jax.random.PRNGKey(seed)
        self.state: State | None = None
        self._resamples = any(r["resample_until"] for r in p["reset"])

    @property
    def id(self) -> str:
        return self.plan.id

    @property
    def single_observation_space(self) -> gym.spaces.Box:
        """One world's observation space (float32, unbounded), in Gymnasium's vector names."""
        import gymnasium as gym
        import numpy as np

        return gym.spaces.Box(-np.inf, np.inf, (self.obs_dim,), np.float32)

    @property
    def single_action_space(self) -> gym.spaces.Box:
        """One world's action space (float32, the spec's control range)."""
        import gymnasium as gym
        import numpy as np

        return gym.spaces.Box(
            np.asarray(self.act_low, np.float32), np.asarray(self.act_high, np.float32)
        )

    @property
    def observation_space(self) -> gym.spaces.Space[Any]:
        """The batch's observation space: ``single_observation_space`` over ``num_envs`` worlds."""
        import gymnasium as gym

        return gym.vector.utils.batch_space(self.single_observation_space, self.num_envs)

    @property
    def action_space(self) -> gym.spaces.Space[Any]:
        """The batch's action space: ``single_action_space`` over ``num_envs`` worlds."""
        import gymnasium as gym

        return gym.vector.utils.batch_space(self.single_action_space, self.num_envs)

    def _on_device(self) -> AbstractContextManager[Any]:
        import contextlib

        import jax

        return contextlib.nullcontext() if self.device is None else jax.default_device(self.device)

    def reset(
        self, seed: int | None = None, mask: npt.ArrayLike | None = None
    ) -> tuple[jax.Array, dict[str, jax.Array]]:
        """Reset every world (``mask=None``) or only the worlds where ``mask`` holds."""
        with self._on_device():
            return self._reset(seed, mask)

    def _reset(
        self, seed: int | None, mask: npt.ArrayLike | None
    ) -> tuple[jax.Array, dict[str, jax.Array]]:
        import jax

        if seed is not None:
            from .._errors import seed as check_seed

            self._key = jax.random.PRNGKey(check_seed(seed))
        if mask is None or self.state is None:
            state, info = self.executor.reset(self._key)
            self._check_resets(state)
            self.state = state
            return self.state.obs, info
        state = self.executor.reset_where(self.state, mask)
        self._check_resets(state)
        self.state = state
        return self.state.obs, {}

    def _check_resets(self, state: State) -> None:
        """E1104 when a world's reset met no `resample_until` within the draw limit (looked at
        only for specs that have one: it waits for the device)."""
        if not self._resamples:
            return
        import numpy as np

        failed = np.asarray(state.failed)
        if failed.any():
            self.state = None
            raise _coded(
                f"`{self.id}`: {int(failed.sum())} world(s) met no `resample_until` within "
                f"{self.executor.max_draws:,} draws (world {int(np.argmax(failed))} first); "
                "every world needs a reset",
                "E1104",
            )

    def step(
        self, action: npt.ArrayLike
    ) -> tuple[jax.Array, jax.Array, jax.Array, jax.Array, dict[str, jax.Array]]:
        if self.state is None:
            raise _coded("step before reset: call reset() first", "E1103")
        import jax.numpy as jnp

        try:
            a = jnp.asarray(action)
        except (TypeError, ValueError) as e:
            raise _coded(f"actions must be numbers ({e})", "E1101") from None
        if a.dtype.kind not in "biuf":
            raise _coded(f"actions must be real numbers, got {a.dtype}", "E1101")
        want = (self.num_envs, self.act_dim)
        if a.shape != want:
            raise _coded(f"actions have shape {a.shape}; expected {want}", "E1101")
        a = a.astype(jnp.float32)
        if not bool(jnp.all(jnp.isfinite(a))):
            raise _coded("actions contain NaN or infinite entries; nothing was stepped", "E1102")
        with self._on_device():
            out = self.executor.step(self.state, a)
        self._check_resets(out.state)
        self.state = out.state
        return out.obs, out.reward, out.terminated, out.truncated, out.info

    def as_gymnasium(self) -> GymnasiumView:
        """A ``gymnasium.vector.VectorEnv`` view (numpy in and out, same-step autoreset)."""
        from ._vector import GymnasiumView

        return GymnasiumView(self)

    def as_brax(self) -> BraxView:
        """A Brax / Playground-style functional env (``reset(rng)``, ``step(state, action)``)."""
        from ._vector import BraxView

        return BraxView(self)

    def close(self) -> None:
        self.state = None


def make_vec(
    id_or_path: str,
    num_envs: int = 1024,
    backend: str = "mjx",
    device: str | None = None,
    seed: int = 0,
    **overrides: Any,
) -> GpuVecEnv:
    """A batched GPU env of a bundled task id or a task spec file, with the spec's parameters
    as keywords (as ``envc.make``). ``device``: ``"cuda"``, ``"cpu"`` or None (JAX's default)."""
    p = plan(id_or_path, **overrides)
    dev = _device(device)
    b = _backend(p, backend, dev)
    return GpuVecEnv(p, b, num_envs, seed=seed, device=dev)
