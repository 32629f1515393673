"""The batched executor: one IR, any backend. Reset draws, physics, terms, health, termination,
truncation and info of every world in one jitted XLA program per call; worlds that end are reset
in the same step (masked, compacted: only those worlds run `forward`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, NamedTuple, cast

import jax
import jax.numpy as jnp

from . import _terms

if TYPE_CHECKING:
    import numpy.typing as npt
    from mujoco import mjx

    from ._mjx import MjxBackend
    from ._plan import Plan

    # One world's draw loop state: the accepted draw, the key, whether it is met, the round.
    _Draws = tuple[jax.Array, jax.Array, jax.Array, jax.Array]
    # The reset loop's state: data, observations, counters, worlds left, key, failed draws.
    _Resets = tuple[mjx.Data, jax.Array, jax.Array, jax.Array, jax.Array, jax.Array]

#: Candidates drawn at once for a `resample_until` reset step (Reacher's goal is accepted with
#: probability π/4: all 64 fail with probability below 1e-42); more rounds follow until one is
#: accepted.
RESAMPLE_CANDIDATES = 64
#: Draws before a reset gives up (E1104), as the CPU core's `limits::MAX_RESAMPLE_DRAWS`.
MAX_RESAMPLE_DRAWS = 1_000_000


class State(NamedTuple):
    """Every world's state (leading axis: world)."""

    data: Any  # the backend's batched simulation data
    obs: jax.Array  # (N, obs_dim): the observation the policy sees now
    elapsed: jax.Array  # (N,) int32: steps since the world's reset
    key: jax.Array  # the executor's PRNG key
    failed: jax.Array  # (N,) bool: the world's last reset met no `resample_until` (E1104)


class StepOut(NamedTuple):
    state: State
    obs: jax.Array  # after autoreset: a reset world's first observation
    reward: jax.Array
    terminated: jax.Array
    truncated: jax.Array
    # The step's info; `final_obs` holds the observation before an autoreset.
    info: dict[str, jax.Array]


class Executor:
    def __init__(
        self, plan: Plan, backend: MjxBackend, num_envs: int, reset_chunk: int | None = None
    ) -> None:
        self.plan = plan
        self.b = backend
        self.n = int(num_envs)
        self.dt = jnp.float32(plan["dt"])
        self.timestep = jnp.float32(plan["timestep"])
        self.max_steps = plan["max_episode_steps"]
        # Worlds reset per pass of the reset loop: about 3 % of them, so ~2 % resets per step
        # cost one pass of `forward` over a small batch.
        self.chunk = int(reset_chunk or max(1, min(self.n, -(-self.n * 3 // 100))))
        self.max_draws = MAX_RESAMPLE_DRAWS
        self._jit_reset = jax.jit(self._reset_all)
        self._jit_step = jax.jit(self._step)
        self._jit_reset_where = jax.jit(self._reset_where)
        self._jit_physics = jax.jit(jax.vmap(self.b.physics))

    # -- one world --------------------------------------------------------------------------------
    def _draw(self, key: jax.Array) -> tuple[jax.Array, jax.Array, jax.Array]:
        """The `[reset.*]` steps in declared order: qpos0 / zeros, plus or replaced by draws."""
        qpos = self.b.qpos0()
        qvel = jnp.zeros_like(self.b.d0.qvel)
        ok = jnp.bool_(True)
        for k, r in enumerate(self.plan["reset"]):
            sub = jax.random.fold_in(key, k)
            idx = jnp.asarray(r["target"]["indices"], dtype=jnp.int32)
            n = len(r["target"]["indices"])
            x, met = self._draw_until(sub, r, n)
            ok = ok & met
            if r["target"]["field"] == "qpos":
                qpos = qpos.at[idx].set(x if r["set"] else qpos[idx] + x)
            else:
                qvel = qvel.at[idx].set(x if r["set"] else qvel[idx] + x)
        return qpos, qvel, ok

    @staticmethod
    def _sample(key: jax.Array, dist: dict[str, Any], shape: tuple[int, ...]) -> jax.Array:
        if dist["kind"] == "uniform":
            lo, hi = jnp.asarray(dist["low"]), jnp.asarray(dist["high"])
            return jax.random.uniform(key, shape, minval=lo, maxval=hi)
        if dist["kind"] == "normal":
            return dist["scale"] * jax.random.normal(key, shape)
        return jnp.full(shape, dist["value"])

    def _draw_until(
        self, key: jax.Array, r: dict[str, Any], n: int
    ) -> tuple[jax.Array, jax.Array]:
        """One draw of a reset step, and whether it meets its `resample_until`. Rejection
        sampling in rounds of `RESAMPLE_CANDIDATES` draws: the first candidate that meets the
        condition (the same distribution as redrawing until it holds), drawing round after round
        until one does; after `MAX_RESAMPLE_DRAWS` draws the reset gives up, as the CPU core
        does (E1104 when the caller looks at `State.failed`)."""
        until = r["resample_until"]
        if until is None:
            return self._sample(key, r["dist"], (n,)), jnp.bool_(True)

        def candidates(k: jax.Array) -> tuple[jax.Array, jax.Array]:
            xs = self._sample(k, r["dist"], (RESAMPLE_CANDIDATES, n))
            norms = jnp.sqrt(jnp.sum(xs * xs, axis=1))
            if "norm_below" in until:
                ok = norms < until["norm_below"]
            else:
                ok = norms > until["norm_above"]
            return xs[jnp.argmax(ok)], jnp.any(ok)

        rounds = -(-MAX_RESAMPLE_DRAWS // RESAMPLE_CANDIDATES)

        def more(c: _Draws) -> jax.Array:
            return (~c[2]) & (c[3] < rounds)

        def body(c: _Draws) -> _Draws:
            _, k, _, i = c
            k, sub = jax.random.split(k)
            x, met = candidates(sub)
            return x, k, met, i + 1

        x, met = candidates(key)
        x, _, met, _ = jax.lax.while_loop(
            more, body, (x, jax.random.fold_in(key, 1), met, jnp.int32(1))
        )
        return x, met

    def _init_world(self, key: jax.Array) -> tuple[mjx.Data, jax.Array]:
        d, obs, _ = self._init_checked(key)
        return d, obs

    def _init_checked(self, key: jax.Array) -> tuple[mjx.Data, jax.Array, jax.Array]:
        """A fresh world, its observation, and whether its reset draws met their conditions."""
        qpos, qvel, ok = self._draw(key)
        d = self.b.initial(qpos, qvel)
        f = self.b.fields(d, jnp.zeros_like(d.ctrl))
        return d, _terms.observation(self.plan, f), ok

    def reset_info_world(self, d: mjx.Data) -> dict[str, jax.Array]:
        f = self.b.fields(d, jnp.zeros_like(d.ctrl))
        return _terms.info(self.plan, f, None, [], [], self.dt, at_reset=True)

    def evaluate(
        self,
        d: mjx.Data,
        action: jax.Array,
        before: jax.Array,
        pre_vals: list[jax.Array | None] | None = None,
        pre_unweighted: list[jax.Array | None] | None = None,
    ) -> tuple[jax.Array, jax.Array, jax.Array, dict[str, jax.Array]]:
        """Obs, reward, terminated, info of one world whose post-step data is `d` (`before`:
        the velocity sources' values before the step). Used by the step and by parity checks."""
        f = self.b.fields(d, action)
        h = _terms.healthy(self.plan, f)
        vals, unw = _terms.terms(self.plan, f, before, h, self.dt, self.timestep, False)
        if pre_vals is not None:
            pre_unw = cast("list[jax.Array | None]", pre_unweighted)  # given with `pre_vals`
            vals = [p if v is None else v for v, p in zip(vals, pre_vals, strict=False)]
            unw = [p if v is None else v for v, p in zip(unw, pre_unw, strict=False)]
        reward = _terms.reward_sum(self.plan["reward_sum"], vals)
        terminated = jnp.logical_and(~h, self.plan["terminate_when_unhealthy"])
        info = _terms.info(self.plan, f, before, vals, unw, self.dt, at_reset=False)
        return _terms.observation(self.plan, f), reward, terminated, info

    def _step_world(
        self, d: mjx.Data, action: jax.Array
    ) -> tuple[mjx.Data, jax.Array, jax.Array, jax.Array, dict[str, jax.Array]]:
        f0 = self.b.fields(d, action)
        before = _terms.before_values(self.plan, f0)
        pre_vals, pre_unw = _terms.terms(
            self.plan, f0, before, jnp.bool_(True), self.dt, self.timestep, True
        )
        d = self.b.physics(d, action)
        obs, reward, terminated, info = self.evaluate(d, action, before, pre_vals, pre_unw)
        return d, obs, reward, terminated, info

    # -- batched ----------------------------------------------------------------------------------
    def _reset_all(self, key: jax.Array) -> tuple[State, dict[str, jax.Array]]:
        key, sub = jax.random.split(key)
        keys = jax.random.split(sub, self.n)
        data, obs, ok = jax.vmap(self._init_checked)(keys)
        info = jax.vmap(self.reset_info_world)(data)
        return State(data, obs, jnp.zeros((self.n,), jnp.int32), key, ~ok), info

    def _reset_where(self, state: State, mask: jax.Array) -> State:
        """Reset the worlds where `mask` holds, `chunk` at a time (only they run `forward`);
        every other world's data, observation and counter are left exactly as they were."""
        n, k = self.n, self.chunk

        def body(carry: _Resets) -> _Resets:
            data, obs, elapsed, remaining, key, failed = carry
            idx = jnp.nonzero(remaining, size=k, fill_value=n)[0]
            key, sub = jax.random.split(key)
            new_d, new_obs, ok = jax.vmap(self._init_checked)(jax.random.split(sub, k))

            def put(a: jax.Array, b: jax.Array) -> jax.Array:
                return a.at[idx].set(b, mode="drop")

            data = jax.tree_util.tree_map(put, data, new_d)
            obs = put(obs, new_obs)
            elapsed = elapsed.at[idx].set(0, mode="drop")
            remaining = remaining.at[idx].set(False, mode="drop")
            failed = failed.at[idx].set(~ok, mode="drop")
            return data, obs, elapsed, remaining, key, failed

        carry = (state.data, state.obs, state.elapsed, mask, state.key, state.failed)
        data, obs, elapsed, _, key, failed = jax.lax.while_loop(
            lambda c: jnp.any(c[3]), body, carry
        )
        return State(data, obs, elapsed, key, failed)

    def _step(self, state: State, action: jax.Array) -> StepOut:
        data, obs, reward, terminated, info = jax.vmap(self._step_world)(state.data, action)
        elapsed = state.elapsed + 1
        truncated = elapsed >= self.max_steps if self.max_steps else jnp.zeros_like(terminated)
        done = terminated | truncated
        after = self._reset_where(State(data, obs, elapsed, state.key, state.failed), done)
        info = dict(info)
        info["final_obs"] = obs
        return StepOut(after, after.obs, reward, terminated, truncated, info)

    # -- public -----------------------------------------------------------------------------------
    def reset(self, key: jax.Array) -> tuple[State, dict[str, jax.Array]]:
        out: tuple[State, dict[str, jax.Array]] = self._jit_reset(key)
        return out

    def step(self, state: State, action: jax.Array) -> StepOut:
        out: StepOut = self._jit_step(state, action)
        return out

    def reset_where(self, state: State, mask: npt.ArrayLike) -> State:
        out: State = self._jit_reset_where(state, jnp.asarray(mask, dtype=bool))
        return out

    def physics(self, data: mjx.Data, action: jax.Array) -> mjx.Data:
        """Physics alone (`frame_skip` steps of every world), for benchmarks."""
        return self._jit_physics(data, action)
