"""Views of a `GpuVecEnv` for trainers: Gymnasium's `VectorEnv` (numpy, same-step autoreset)
and a Brax / MuJoCo Playground-style functional single-world env (Brax's wrappers vmap it and
add episode limits and autoreset themselves)."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

import jax
import jax.numpy as jnp
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv

if TYPE_CHECKING:
    import numpy.typing as npt

    from . import GpuVecEnv


class GymnasiumView(VectorEnv):
    """``gymnasium.vector.VectorEnv`` over a GPU env: numpy arrays, same-step autoreset
    (``info["final_obs"]`` holds the observation an autoreset replaced)."""

    metadata = {"autoreset_mode": AutoresetMode.SAME_STEP, "render_modes": []}

    def __init__(self, env: GpuVecEnv) -> None:
        self.env = env
        self.num_envs = env.num_envs
        self.single_observation_space = env.single_observation_space
        self.single_action_space = env.single_action_space
        self.observation_space = env.observation_space
        self.action_space = env.action_space

    def reset(
        self,
        *,
        seed: int | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        mask = None if options is None else options.get("reset_mask")
        obs, info = self.env.reset(seed=seed, mask=mask)
        return np.asarray(obs), {k: np.asarray(v) for k, v in info.items()}

    def step(
        self, actions: npt.ArrayLike
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, np.ndarray]]:
        obs, rew, term, trunc, info = self.env.step(jnp.asarray(actions, jnp.float32))
        return (
            np.asarray(obs),
            np.asarray(rew),
            np.asarray(term),
            np.asarray(trunc),
            {k: np.asarray(v) for k, v in info.items()},
        )

    def close_extras(self, **kwargs: Any) -> None:
        self.env.close()


@jax.tree_util.register_dataclass
@dataclasses.dataclass
class BraxState:
    """Brax's `envs.base.State` fields (``pipeline_state``, ``obs``, ``reward``, ``done``,
    ``metrics``, ``info``), with its ``replace``."""

    pipeline_state: Any
    obs: jax.Array
    reward: jax.Array
    done: jax.Array
    metrics: dict[str, jax.Array] = dataclasses.field(default_factory=dict)
    info: dict[str, Any] = dataclasses.field(default_factory=dict)

    def replace(self, **changes: Any) -> BraxState:
        return dataclasses.replace(self, **changes)


class BraxView:
    """One world of the spec as Brax's env protocol: ``reset(rng)``, ``step(state, action)``,
    ``observation_size``, ``action_size``. Termination is the spec's; truncation (the time limit)
    is left to Brax's ``EpisodeWrapper`` with ``episode_length = max_episode_steps``."""

    def __init__(self, env: GpuVecEnv) -> None:
        self._x = env.executor
        self.observation_size = env.obs_dim
        self.action_size = env.act_dim
        self.backend = env.backend.name
        self.dt = env.dt
        self.episode_length = env.max_episode_steps

    def reset(self, rng: jax.Array) -> BraxState:
        d, obs = self._x._init_world(rng)
        metrics = {k: jnp.float32(0.0) for k in self._metric_keys()}
        return BraxState(d, obs, jnp.float32(0.0), jnp.float32(0.0), metrics, {})

    def step(self, state: BraxState, action: jax.Array) -> BraxState:
        d, obs, reward, terminated, info = self._x._step_world(state.pipeline_state, action)
        metrics = {k: jnp.asarray(info[k], jnp.float32) for k in self._metric_keys()}
        return state.replace(
            pipeline_state=d,
            obs=obs,
            reward=reward,
            done=terminated.astype(jnp.float32),
            metrics=metrics,
        )

    def _metric_keys(self) -> list[str]:
        return [i["key"] for i in self._x.plan["info"] if i["len"] == 1]
