"""The IR's observation segments, reward terms, health checks and info entries as JAX functions
of one world's fields (a dict of flat arrays, as the CPU core's `Sim::field` gives them). Backend
neutral: a backend supplies the fields, `jax.vmap` batches the worlds.

Same operations as `runtime/src/env/` and `observe.rs`, in the same order where it matters;
sums are not bit-identical (float32, XLA's reduction order): docs/gpu.md states the bound."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import jax.numpy as jnp

if TYPE_CHECKING:
    import jax

    from ._plan import Plan

    # `reward_sum`'s tree: a term's index, or the sum of the subtrees in a list.
    _SumNode = int | list["_SumNode"]

Fields = Callable[[str], Any]


def _gather(f: Fields, sel: dict[str, Any]) -> jax.Array:
    return f(sel["field"])[jnp.asarray(sel["indices"], dtype=jnp.int32)]


def _clip(x: jax.Array, r: list[float] | None) -> jax.Array:
    return x if r is None else jnp.clip(x, r[0], r[1])


def observation(plan: Plan, f: Fields) -> jax.Array:
    parts = []
    for s in plan["observation"]:
        x = _gather(f, s["source"])
        if s["minus"]:
            x = x - _gather(f, s["minus"])
        if s["apply"] == "sin":
            x = jnp.sin(x)
        elif s["apply"] == "cos":
            x = jnp.cos(x)
        elif s["apply"] == "positive":
            x = (x > 0.0).astype(x.dtype)
        parts.append(_clip(x, s["clip"]))
    return jnp.concatenate(parts) if parts else jnp.zeros((0,))


def healthy(plan: Plan, f: Fields) -> jax.Array:
    ok = jnp.bool_(True)
    for h in plan["health"]:
        for s in h["sources"]:
            x = _gather(f, s)
            if h["kind"] == "finite":
                good = jnp.isfinite(x)
            elif h["kind"] == "in_range":
                lo, hi = h["lo"], h["hi"]
                good = (lo <= x) & (x <= hi) if h["closed"] else (lo < x) & (x < hi)
            else:
                op, v = h["op"], h["value"]
                bad = {"lt": x < v, "le": x <= v, "gt": x > v, "ge": x >= v}[op]
                good = ~bad
            ok = ok & jnp.all(good)
    return ok


def velocity_sources(plan: Plan) -> list[dict[str, Any]]:
    """The one-number selections whose value before the step `velocity` terms and infos need,
    in a fixed order (the `before` vector)."""
    out: list[dict[str, Any]] = []
    for t in plan["reward"]:
        if t["kind"] == "velocity" and t["source"] not in out:
            out.append(t["source"])
    for i in plan["info"]:
        if i["kind"] == "velocity" and i["source"] not in out:
            out.append(i["source"])
    return out


def before_values(plan: Plan, f: Fields) -> jax.Array:
    srcs = velocity_sources(plan)
    if not srcs:
        return jnp.zeros((0,))
    return jnp.stack([_gather(f, s)[0] for s in srcs])


def _kernel(
    plan: Plan,
    t: dict[str, Any],
    f: Fields,
    before: jax.Array,
    healthy_now: jax.Array,
    dt: jax.Array,
    timestep: jax.Array,
    weight: float,
) -> jax.Array:
    k = t["kind"]
    if k == "velocity":
        j = velocity_sources(plan).index(t["source"])
        return weight * (_gather(f, t["source"])[0] - before[j]) / dt
    if k == "healthy":
        if t["paid_when_unhealthy"]:
            return weight * jnp.float32(1.0)
        return weight * healthy_now.astype(jnp.float32)
    if k == "sum_squares":
        x = _clip(_gather(f, t["source"]), t["clip_input"])
        return _clip(weight * jnp.sum(x * x), t["clip"])
    if k == "norm":
        x = _gather(f, t["source"])
        if t["minus"]:
            x = x - _gather(f, t["minus"])
        return weight * jnp.sqrt(jnp.sum(x * x))
    if k == "quadratic":
        x = _gather(f, t["source"]) - jnp.asarray(t["targets"])
        return weight * jnp.sum(jnp.asarray(t["coefs"]) * x * x)
    if k == "value":
        x = _gather(f, t["source"])[0]
        d = {"timestep": timestep, "dt": dt, None: 1.0}[t["divide_by"]]
        return weight * (x / d)
    if k == "constant":
        return weight * jnp.float32(1.0)
    raise AssertionError(f"refused before: {k}")


def terms(
    plan: Plan,
    f: Fields,
    before: jax.Array,
    healthy_now: jax.Array,
    dt: jax.Array,
    timestep: jax.Array,
    at_before: bool,
) -> tuple[list[jax.Array | None], list[jax.Array | None]]:
    """Signed term values (weighted, and weight 1 for `unweighted` infos), for the terms
    evaluated after the step (`at_before` False) or at its start (True); others are None."""
    vals: list[jax.Array | None] = []
    unweighted: list[jax.Array | None] = []
    for t in plan["reward"]:
        if t["before"] != at_before:
            vals.append(None)
            unweighted.append(None)
            continue
        sign = -1.0 if t["cost"] else 1.0
        h = jnp.bool_(True) if at_before else healthy_now
        vals.append(sign * _kernel(plan, t, f, before, h, dt, timestep, t["weight"]))
        unweighted.append(sign * _kernel(plan, t, f, before, h, dt, timestep, 1.0))
    return vals, unweighted


def reward_sum(node: _SumNode, vals: list[jax.Array | None]) -> jax.Array:
    if isinstance(node, int):
        return vals[node]
    if not node:
        return jnp.float32(0.0)
    acc = reward_sum(node[0], vals)
    for c in node[1:]:
        acc = acc + reward_sum(c, vals)
    return acc


def info(
    plan: Plan,
    f: Fields,
    before: jax.Array,  # None at reset, which evaluates no `velocity` entry
    vals: list[jax.Array | None],
    unweighted: list[jax.Array | None],
    dt: jax.Array,
    at_reset: bool,
) -> dict[str, jax.Array]:
    out: dict[str, jax.Array] = {}
    srcs = velocity_sources(plan)
    for i in plan["info"]:
        if at_reset and not i["at_reset"]:
            continue
        k = i["kind"]
        if k == "value":
            x = _gather(f, i["source"])
            if i["minus"]:
                x = x - _gather(f, i["minus"])
            v = x[0] if i["len"] == 1 else x
        elif k == "norm":
            x = _gather(f, i["source"])
            v = jnp.sqrt(jnp.sum(x * x))
        elif k == "velocity":
            v = (_gather(f, i["source"])[0] - before[srcs.index(i["source"])]) / dt
        else:
            v = (unweighted if i["unweighted"] else vals)[i["term"]]
        out[i["key"]] = v
    return out
