"""The dataset suite: Minari datasets declared as data (``specs/datasets/**.toml``) and built by one
runner, from the command line (``envc dataset build SPEC``) or from Python (:func:`build`), in one
process or on Ray workers, always the same bytes (docs/datasets.md, "The MuJoCo dataset suite").

A dataset spec names the env and its parameters, the tier, the policy (an ``.npz`` MLP run in
Rust, deterministic or with noise from episode k's ``default_rng([seed, k])`` only), the budget,
the seed (episode k is reset with ``seed + k``), the metadata and the reference scores.
"""

from __future__ import annotations

import contextlib
import os
import time
from typing import TYPE_CHECKING, Any, Literal, cast

from . import _envc

if TYPE_CHECKING:
    from ._envc import _Format

__all__ = ["build", "bundled", "main", "policy", "read_spec", "reference_scores"]

# Per-chunk attempts before a sharded build gives up (as envc.ray).
MAX_ATTEMPTS = 4


def bundled() -> list[str]:
    """The ids of the bundled dataset specs (``mujoco/hopper/simple-v0``, ...)."""
    root = _envc.datasets_dir()
    out = []
    for d, _, files in os.walk(root):
        for f in files:
            if f.endswith(".toml"):
                out.append(os.path.relpath(os.path.join(d, f), root)[: -len(".toml")])
    return sorted(out)


def read_spec(spec: str | os.PathLike[str]) -> dict[str, Any]:
    """A dataset spec (a file or a bundled id) as its TOML data, ``[train]`` included, read and
    checked by envc's own reader: a mistake is an ``envc.Error`` with code E1801 at its line and
    column."""
    spec = os.fspath(spec)
    return _envc.read_dataset_spec(os.path.abspath(spec) if os.path.exists(spec) else spec)


def build(
    spec: str | os.PathLike[str],
    *,
    steps: int | None = None,
    root: str | os.PathLike[str] | None = None,
    format: Literal["arrow", "hdf5"] | None = None,
    dataset_id: str | None = None,
    workers: int | None = None,
    address: str | None = None,
) -> str:
    """Build the dataset a spec declares; returns its directory.

    ``spec`` is a dataset spec file or a bundled id (``"mujoco/hopper/simple-v0"``); ``steps``
    replaces the spec's budget (a small build of a tier); ``root`` defaults to
    ``$MINARI_DATASETS_PATH``. With ``workers=N`` the episodes are recorded by N Ray actors
    (``address`` as ``ray.init``; ``None`` starts a local Ray): the same bytes as without.
    """
    spec = os.fspath(spec)
    if os.path.exists(spec):
        spec = os.path.abspath(spec)
    root = None if root is None else os.path.abspath(os.fspath(root))
    if workers is None:
        directory, _steps, _episodes = _envc.build_dataset(spec, steps, root, format, dataset_id)
        return directory
    return _build_on_ray(spec, steps, root, format, dataset_id, int(workers), address)


def _build_on_ray(
    spec: str,
    steps: int | None,
    root: str | None,
    format: _Format | None,
    dataset_id: str | None,
    workers: int,
    address: str | None,
) -> str:
    import ray

    if workers < 1:
        raise ValueError(f"workers={workers!r}: expected an integer ≥ 1")
    _seed, kind, budget, max_steps, fmt = _envc.dataset_build_plan(spec, steps, format)
    if root is None:
        root = os.environ.get("MINARI_DATASETS_PATH") or os.path.join(
            os.path.expanduser("~"), ".minari", "datasets"
        )
    driver = _envc.build_driver(spec, steps, os.path.abspath(root), format, dataset_id)
    actors: list[Any] = []
    try:
        if not ray.is_initialized():
            ray.init(address=address, include_dashboard=False, log_to_driver=False)

        class Builder:
            def run(
                self, spec: str, staging: str, start: int, end: int, fmt: _Format
            ) -> list[tuple[int, int]]:
                from envc import _envc as core

                return core.build_shard(spec, staging, start, end, fmt)

        # Ray's class decorator, applied as a call: the checker does not apply class decorators.
        actor_class: Any = ray.remote(num_cpus=1, max_restarts=-1, max_task_retries=0)(Builder)
        actors = [actor_class.remote() for _ in range(workers)]
        lengths: list[tuple[int, int]] = []

        def cut() -> int | None:
            """The episode count the budget takes, once the recorded episodes decide it."""
            if kind == "episodes":
                return budget if len(lengths) >= budget else None
            total = 0
            for k, (steps_k, _b) in enumerate(lengths):
                if budget - total < max_steps:
                    return k
                total += steps_k
            return len(lengths) if budget - total < max_steps else None

        # Rounds: each records the episodes the budget still needs at least (remaining steps /
        # max_episode_steps), plus an estimate from the mean length so far, as chunks over the
        # workers. Episode k depends on (seed, k) only, so episodes recorded beyond the budget
        # are simply removed before publishing: which worker ran what changes nothing.
        while (n_eps := cut()) is None:
            done = len(lengths)
            total = sum(x for x, _b in lengths)
            if kind == "episodes":
                n = budget - done
            else:
                sure = max(1, (budget - total) // max_steps)
                guess = 0
                if done:
                    mean = max(1.0, total / done)
                    guess = int((budget - total - max_steps) / mean * 1.1) + workers
                n = max(sure, guess)
            size = max(1, -(-n // (workers * 4)))
            pending = [(a, min(a + size, done + n)) for a in range(done, done + n, size)]
            got = _run_round(ray, actors, spec, driver.staging, fmt, pending)
            for chunk in sorted(got):
                # `(steps, bytes)` pairs, as tuples whatever Ray's pickling made of them.
                lengths.extend(cast("tuple[int, int]", tuple(x)) for x in got[chunk])
        if n_eps == 0:
            raise ValueError(
                f"a budget of {budget} {kind} holds no episode of up to {max_steps} steps"
            )
        return driver.finish(lengths[:n_eps], trim=True)
    finally:
        driver.abort()
        for a in actors:
            with contextlib.suppress(Exception):  # an actor already gone
                ray.kill(a)


def _run_round(
    ray: Any,
    actors: list[Any],
    spec: str,
    staging: str,
    fmt: _Format,
    pending: list[tuple[int, int]],
) -> dict[tuple[int, int], list[tuple[int, int]]]:
    """Each chunk of `pending` on the next free actor; a dead actor's chunk is queued again."""
    pending = list(reversed(pending))
    running: dict[Any, tuple[int, tuple[int, int]]] = {}
    attempts: dict[tuple[int, int], int] = {}
    got: dict[tuple[int, int], list[tuple[int, int]]] = {}
    free = list(range(len(actors)))
    while pending or running:
        while pending and free:
            w, chunk = free.pop(), pending.pop()
            running[actors[w].run.remote(spec, staging, chunk[0], chunk[1], fmt)] = (w, chunk)
        ready, _ = ray.wait(list(running), num_returns=1)
        for ref in ready:
            w, chunk = running.pop(ref)
            try:
                got[chunk] = ray.get(ref)
            except (ray.exceptions.RayActorError, ray.exceptions.ActorUnavailableError) as e:
                attempts[chunk] = attempts.get(chunk, 0) + 1
                if attempts[chunk] >= MAX_ATTEMPTS:
                    raise RuntimeError(
                        f"episodes {chunk[0]}..{chunk[1]} failed {MAX_ATTEMPTS} times: "
                        f"their worker died each time ({e})"
                    ) from e
                pending.append(chunk)
                time.sleep(0.1)
            except ray.exceptions.RayTaskError as e:
                raise e.as_instanceof_cause() from None
            free.append(w)
    return got


def policy(
    spec: str | os.PathLike[str], *, seed: int = 123, deterministic: bool | None = None
) -> _envc.SpecPolicy:
    """The spec's policy as ``policy(obs) -> action`` (float32), run in Rust without torch:
    the spec's mode unless ``deterministic`` is given; noise from ``default_rng(seed)``."""
    spec = os.fspath(spec)
    return _envc.SpecPolicy(
        os.path.abspath(spec) if os.path.exists(spec) else spec, seed, deterministic
    )


def reference_scores(
    spec: str | os.PathLike[str],
    expert: str | os.PathLike[str] | None = None,
    episodes: int = 100,
) -> dict[str, float]:
    """Minari's reference scores of a dataset spec's evaluation env, computed by Minari's own
    ``get_average_reference_score`` on the reference (Gymnasium) env: ``ref_min_score`` from
    Minari's seeded random policy, ``ref_max_score`` from the expert tier's policy (``expert``,
    default the spec's ``expert-v0`` sibling), each the mean over ``episodes`` episodes, the
    first reset with seed 123 (as Minari). Needs gymnasium and minari."""
    import gymnasium as gym
    from minari.utils import RandomPolicy, get_average_reference_score

    path = _spec_path(spec)
    expert = (
        _spec_path(expert)
        if expert is not None
        else os.path.join(os.path.dirname(path), "expert-v0.toml")
    )
    d = read_spec(path)
    eval_id = d["metadata"].get("eval_env", d["dataset"]["env"])
    params = d["metadata"].get("eval_params", d["dataset"].get("params", {}))
    env = gym.make(eval_id, **params)
    low = get_average_reference_score(env, RandomPolicy(env), episodes)
    env = gym.make(eval_id, **params)
    high = get_average_reference_score(env, policy(expert), episodes)
    return {
        "ref_min_score": float(low),
        "ref_max_score": float(high),
        "num_episodes_average_score": int(episodes),
    }


def _spec_path(spec: str | os.PathLike[str]) -> str:
    spec = os.fspath(spec)
    if os.path.exists(spec):
        return os.path.abspath(spec)
    p = os.path.join(_envc.datasets_dir(), spec + ".toml")
    if os.path.exists(p):
        return os.path.abspath(p)
    raise FileNotFoundError(f"{spec!r}: neither a dataset spec file nor a bundled dataset id")


def main(argv: list[str] | None = None) -> int:
    """``python -m envc.datasets build SPEC [--steps N] [--workers N]`` and
    ``python -m envc.datasets scores SPEC``."""
    import argparse
    import json

    p = argparse.ArgumentParser(prog="python -m envc.datasets")
    sub = p.add_subparsers(dest="command", required=True)
    b = sub.add_parser("build", help="build a dataset from its spec")
    b.add_argument("spec")
    b.add_argument("--steps", type=int)
    b.add_argument("--root")
    b.add_argument("--format", choices=["arrow", "hdf5"])
    b.add_argument("--dataset-id")
    b.add_argument("--workers", type=int)
    b.add_argument("--address")
    s = sub.add_parser("scores", help="Minari's reference scores of a spec's eval env")
    s.add_argument("spec")
    s.add_argument("--episodes", type=int, default=100)
    s.add_argument(
        "--write", action="store_true", help="store them in every tier's spec of this env"
    )
    a = p.parse_args(argv)
    if a.command == "build":
        t0 = time.perf_counter()
        d = build(a.spec, steps=a.steps, root=a.root, format=a.format, dataset_id=a.dataset_id,
                  workers=a.workers, address=a.address)
        print(f"written to {d} in {time.perf_counter() - t0:.1f} s")
    else:
        scores = reference_scores(a.spec, episodes=a.episodes)
        print(json.dumps(scores))
        if a.write:
            for path in write_reference_scores(a.spec, scores):
                print(f"wrote {path}")
    return 0


def write_reference_scores(
    spec: str | os.PathLike[str], scores: dict[str, float]
) -> list[str]:
    """Store ``scores`` as the ``[reference_scores]`` table of every dataset spec beside ``spec``
    (the tiers of one env share them, as Minari's generation scripts did). The edit is
    structural: every other table, comment and blank line stays as written."""
    d = os.path.dirname(_spec_path(spec))
    paths = [os.path.join(d, f) for f in sorted(os.listdir(d)) if f.endswith(".toml")]
    # Every spec edited before any is written: one that is not a dataset spec (E1801) stops all.
    texts = [
        _envc.with_reference_scores(
            p,
            float(scores["ref_min_score"]),
            float(scores["ref_max_score"]),
            int(scores["num_episodes_average_score"]),
        )
        for p in paths
    ]
    for p, text in zip(paths, texts, strict=True):
        with open(p, "w", encoding="utf-8") as fh:
            fh.write(text)
    return paths


if __name__ == "__main__":
    import sys

    sys.exit(main())
