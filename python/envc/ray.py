"""Minari datasets collected on a Ray cluster, identical to one machine's (``envc collect``).

``envc.ray.collect(...)`` shards the episodes into small chunks that Ray actors (one envc env
each, one CPU each) take as they finish the last one, so fast workers take more. Episode ``i``
depends on ``(seed, i)`` only (reset seed ``seed + i``, random actions from
``numpy.random.default_rng([seed, i])``, replayed actions from row 0, a callable's ``rng``
argument ``default_rng([seed, i])``), so the dataset is the same bytes whatever the number of
workers, their speed, and which of them died on the way.

Workers write their episodes straight into the dataset's staging directory (hidden in the
datasets root, which must be storage every node shares, e.g. NFS); the driver holds that
directory's lock, collects only each episode's steps and bytes, then checks that every episode
is in place and renames the dataset into place (docs/datasets.md, "Sharded collection"). A dead
actor's chunk goes to the next free actor (Ray restarts the dead one, on another node if its node
is gone, and it rejoins); a
killed driver leaves only the hidden staging directory, removed by the next collection in that
root: a re-run with the same arguments starts over cleanly.

Command line: ``python -m envc.ray collect Hopper-v5 --dataset-id ns/name-v0 --episodes 100
--seed 0 --workers 4 --address HOST:PORT`` (the other options as ``envc collect``).
"""

from __future__ import annotations

import contextlib
import os
import sys
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Literal, cast

import numpy as np
import numpy.typing as npt

from . import _envc
from ._datasets import _envc_spec_json, _replay_rows
from ._errors import coded
from ._gym import overrides_to_toml

if TYPE_CHECKING:
    from ._envc import _Format, _Policy, _PolicyFn

__all__ = ["collect", "main"]

# Per-chunk attempts before the collection gives up (a chunk whose worker keeps dying is more
# likely to be killing it than to be unlucky).
MAX_ATTEMPTS = 4
# Seconds with no chunk finished and no worker (re)joining before the collection gives up (E1602):
# a cluster that lost the CPUs its actors need waits for them forever otherwise.
STALL_TIMEOUT_S = 900.0
# The driver's longest single wait: Ctrl-C lands within it.
POLL_S = 0.5
# How long an interrupted or failed collection waits for its killed actors' processes to end
# before removing the staging directory (they end in well under a second).
KILL_WAIT_S = 5.0


def _default_root() -> str:
    root = os.environ.get("MINARI_DATASETS_PATH") or os.path.join(
        os.path.expanduser("~"), ".minari", "datasets"
    )
    return os.path.abspath(root)


def _chunks(episodes: int, workers: int, chunk_size: int | None) -> list[tuple[int, int]]:
    # About 8 chunks per worker: small enough for stealing (the tail is at most 1/8 of a worker's
    # share) and for re-running a dead worker's chunk cheaply, few enough that the driver handles
    # 8 completions per worker in all, however many episodes (docs/SCALING.md).
    size = chunk_size or max(1, -(-episodes // (workers * 8)))
    return [(a, min(a + size, episodes)) for a in range(0, episodes, size)]


def _worker_class(ray: Any) -> Any:
    @ray.remote(num_cpus=1, max_restarts=-1, max_task_retries=0)
    class EnvcWorker:
        """One envc env per actor process; each call records one chunk into the staging dir."""

        def pid(self) -> int:
            return os.getpid()

        def run(
            self,
            spec: str,
            staging: str,
            start: int,
            end: int,
            seed: int,
            policy: _Policy,
            fmt: _Format,
            overrides: list[tuple[str, str]],
            rows: list[float] | None,
            policy_fn: _PolicyFn | None,
        ) -> tuple[list[tuple[int, int]], float]:
            from envc import _envc as core

            t0 = time.perf_counter()
            lengths = core.collect_shard(
                spec, staging, start, end, seed, policy, fmt, overrides, rows, policy_fn
            )
            return lengths, time.perf_counter() - t0

    return EnvcWorker


def collect(
    spec_or_id: str,
    dataset_id: str,
    episodes: int = 10,
    policy: Literal["zero", "random", "replay"]
    | Callable[[npt.NDArray[np.float64], np.random.Generator], npt.ArrayLike] = "random",
    *,
    seed: int | None = None,
    num_workers: int = 2,
    format: Literal["arrow", "hdf5"] = "arrow",
    root: str | os.PathLike[str] | None = None,
    actions: Any = None,
    chunk_size: int | None = None,
    address: str | None = None,
    author: str | None = None,
    description: str | None = None,
    env_spec: str = "reference",
    stats: dict[str, Any] | None = None,
    stall_timeout: float | None = STALL_TIMEOUT_S,
    **overrides: Any,
) -> str:
    """Collect a Minari dataset on Ray; returns its directory. Same arguments and same dataset
    as :func:`envc.collect`, plus ``num_workers`` (actors, one CPU each), ``chunk_size``
    (episodes per task; default about episodes / (8 * workers)) and ``address``
    (``ray.init(address)`` when Ray is not initialised yet; ``None`` starts a local Ray).

    ``policy`` may be a callable ``policy(obs, rng) -> action`` (for example an SB3 model's
    ``predict`` wrapped), shipped to the actors by Ray's pickling; ``rng`` is episode i's
    ``numpy.random.default_rng([seed, i])`` and must be its only randomness. ``stats``, when
    given, receives the timings (``total_s``, ``worker_s``, ``finish_s``, ``chunks``,
    ``retries``, ``steps``).

    Chunks go only to actors that have started (answered a ping), so more workers than the
    cluster has CPUs for is not a hang: the actors left unplaced get nothing. If no chunk finishes
    and no actor (re)joins for ``stall_timeout`` seconds (``None``: wait forever), the collection
    raises ``envc.DatasetError`` E1602, kills its actors and publishes nothing.
    """
    import ray

    if isinstance(num_workers, bool) or int(num_workers) < 1:
        raise ValueError(f"num_workers={num_workers!r}: expected an integer ≥ 1")
    if int(episodes) < 1:
        raise ValueError(f"episodes={episodes!r}: expected an integer ≥ 1")
    if stall_timeout is not None and not stall_timeout > 0:
        raise ValueError(f"stall_timeout={stall_timeout!r}: expected seconds > 0, or None")
    episodes, num_workers = int(episodes), int(num_workers)
    policy_fn: _PolicyFn | None = None
    policy_name: _Policy
    if callable(policy):
        policy_fn, policy_name = policy, "callable"
    else:
        policy_name = policy
    rows = _replay_rows(actions)
    if env_spec not in ("reference", "envc"):
        raise ValueError(f"env_spec={env_spec!r}: expected 'reference' or 'envc'")
    spec = os.fspath(spec_or_id)
    if os.path.exists(spec):
        spec = os.path.abspath(spec)  # workers may run elsewhere; the path must be shared too
    spec_json = _envc_spec_json(spec, overrides) if env_spec == "envc" else None
    root = os.path.abspath(os.fspath(root)) if root is not None else _default_root()
    ov = overrides_to_toml(overrides)

    t_start = time.perf_counter()
    driver = _envc.ShardedCollection(
        spec, dataset_id, episodes, policy_name, seed, format, root, ov, rows, author, description,
        spec_json, policy_fn is not None,
    )
    workers: list[Any] = []
    running: dict[Any, tuple[int, tuple[int, int]]] = {}  # chunk in flight -> (worker, chunk)
    try:
        if not ray.is_initialized():
            ray.init(address=address, include_dashboard=False, log_to_driver=False)
        Worker = _worker_class(ray)
        workers = [Worker.remote() for _ in range(num_workers)]
        # The policy and the action rows are shipped once, through the object store.
        fn_ref = ray.put(policy_fn) if policy_fn is not None else None
        rows_ref = ray.put(rows) if rows is not None else None
        pending = list(reversed(_chunks(episodes, num_workers, chunk_size)))
        n_chunks = len(pending)
        attempts: dict[tuple[int, int], int] = {}
        done_eps: list[tuple[int, int] | None] = [None] * episodes  # (steps, bytes) of each
        # A dead actor gets no chunk until it answers a ping (Ray restarts it, on another node
        # if its node is gone, once a CPU is free): a chunk handed to it at once could wait for
        # a CPU the live actors hold until the end, while they could run it.
        pings: dict[Any, int] = {}
        idle: list[int] = []  # live actors with nothing to do (until a dead one's chunk returns)
        tally = {"worker_s": 0.0, "retries": 0, "progress": time.monotonic()}

        def submit(w: int) -> None:
            chunk = pending.pop()
            ref = workers[w].run.remote(
                spec, driver.staging, chunk[0], chunk[1], driver.seed, policy_name, format, ov,
                rows_ref, fn_ref,
            )
            running[ref] = (w, chunk)

        def next_for(w: int) -> None:
            if pending:
                submit(w)
            else:
                idle.append(w)

        def handle(ref: Any) -> None:
            if ref in pings:
                w = pings.pop(ref)
                try:
                    ray.get(ref)
                except (ray.exceptions.RayActorError, ray.exceptions.ActorUnavailableError):
                    time.sleep(0.1)  # still restarting
                    pings[workers[w].pid.remote()] = w
                    return
                tally["progress"] = time.monotonic()
                next_for(w)
                return
            w, chunk = running.pop(ref)
            try:
                got, secs = ray.get(ref)
            except (ray.exceptions.RayActorError, ray.exceptions.ActorUnavailableError) as e:
                # The actor died (killed, out of memory, its node removed): its chunk is queued
                # again for the next free actor; the dead one rejoins once restarted.
                attempts[chunk] = attempts.get(chunk, 0) + 1
                if attempts[chunk] >= MAX_ATTEMPTS:
                    raise RuntimeError(
                        f"episodes {chunk[0]}..{chunk[1]} failed {MAX_ATTEMPTS} times: "
                        f"their worker died each time ({e})"
                    ) from e
                tally["retries"] += 1
                pending.append(chunk)
                pings[workers[w].pid.remote()] = w
                if idle:
                    submit(idle.pop())
                return
            except ray.exceptions.RayTaskError as e:
                # The policy or envc raised: the same error as on one machine.
                raise e.as_instanceof_cause() from None
            tally["worker_s"] += secs
            tally["progress"] = time.monotonic()
            done_eps[chunk[0] : chunk[1]] = [tuple(x) for x in got]
            next_for(w)

        # Every actor starts as a dead one rejoins: with a ping, and gets its first chunk when it
        # answers (an actor the cluster has no CPU for never gets one).
        for w in range(num_workers):
            pings[workers[w].pid.remote()] = w
        while pending or running:
            if not running and not pings:
                raise RuntimeError("every worker is gone and none can be restarted")
            refs = list(running) + list(pings)
            # Every completion that is ready, in one call (a driver of many workers would
            # otherwise scan all outstanding references once per completion).
            ready, _ = ray.wait(refs, num_returns=len(refs), timeout=0)
            if not ready:
                # Waits of at most half a second: Python sees Ctrl-C between them (a signal does
                # not interrupt Ray's wait), and the stall deadline is checked.
                left = (
                    None
                    if stall_timeout is None
                    else tally["progress"] + stall_timeout - time.monotonic()
                )
                wait = POLL_S if left is None else min(max(left, 0.0), POLL_S)
                ready, _ = ray.wait(refs, num_returns=1, timeout=wait)
            for ref in ready:
                handle(ref)
            stalled = (
                stall_timeout is not None
                and time.monotonic() - tally["progress"] > stall_timeout
            )
            if stalled and (pending or running):
                raise coded(
                    f"error[E1602]: the sharded collection of {dataset_id} made no progress for "
                    f"{stall_timeout:g} s: {len(running)} chunk(s) running, "
                    f"{len(pending)} waiting, "
                    f"{len(pings)} worker(s) not (re)started; the cluster may lack the CPUs its "
                    f"actors need ({num_workers} actors of 1 CPU each), or a policy call never "
                    "returns; nothing was published",
                    "E1602",
                )
        t_finish = time.perf_counter()
        # No chunk is pending or running: every episode is recorded.
        recorded = cast("list[tuple[int, int]]", done_eps)
        directory = driver.finish(recorded)
        if stats is not None:
            now = time.perf_counter()
            stats.update(
                total_s=now - t_start,
                worker_s=tally["worker_s"],
                finish_s=now - t_finish,
                chunks=n_chunks,
                retries=tally["retries"],
                steps=sum(e[0] for e in recorded),
            )
        return directory
    finally:
        # The actors go first: one still recording would write into the staging directory while
        # `abort` removes it, and leave part of it behind. `ray.kill` only asks; a chunk in flight
        # resolves (with the actor's death) once its process is gone, so those are waited for.
        for w in workers:
            with contextlib.suppress(Exception):  # an actor already gone
                ray.kill(w)
        if running:
            ray.wait(list(running), num_returns=len(running), timeout=KILL_WAIT_S)
        driver.abort()  # after finish: nothing left to abort


def main(argv: list[str] | None = None) -> int:
    """``python -m envc.ray collect SPEC --dataset-id ... --address HOST:PORT``."""
    import argparse

    p = argparse.ArgumentParser(prog="python -m envc.ray", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    c = sub.add_parser("collect", help="record a Minari dataset on a Ray cluster")
    c.add_argument("spec", help="spec file or bundled env id")
    c.add_argument("--dataset-id", required=True)
    c.add_argument("--episodes", type=int, default=10)
    c.add_argument("--policy", choices=["zero", "random", "replay"], default="random")
    c.add_argument("--actions", help="with --policy replay: a .npy array [T, act_dim]")
    c.add_argument("--seed", type=int)
    c.add_argument("--format", choices=["arrow", "hdf5"], default="arrow")
    c.add_argument(
        "--root", help="datasets root, shared by every node (default $MINARI_DATASETS_PATH)"
    )
    c.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="parameter override (TOML literal)",
    )
    c.add_argument("--workers", type=int, default=2)
    c.add_argument("--chunk-size", type=int)
    c.add_argument("--stall-timeout", type=float, default=STALL_TIMEOUT_S,
                   help="seconds with no progress before giving up (E1602); 0 waits forever")
    c.add_argument(
        "--address", help="Ray cluster address (HOST:PORT or 'auto'); default: a local Ray"
    )
    c.add_argument("--author")
    c.add_argument("--description")
    a = p.parse_args(argv)
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # the package's `tomli` dependency on 3.10
        import tomli as tomllib

    overrides: dict[str, Any] = {}
    for kv in a.set:
        k, sep, v = kv.partition("=")
        if not sep:
            p.error(f"--set {kv!r}: expected KEY=VALUE")
        overrides[k.strip()] = tomllib.loads(f"v = {v}")["v"]
    actions = np.load(a.actions) if a.actions else None
    stats: dict[str, Any] = {}
    t0 = time.perf_counter()
    d = collect(
        a.spec, a.dataset_id, a.episodes, a.policy, seed=a.seed, num_workers=a.workers,
        format=a.format, root=a.root, actions=actions, chunk_size=a.chunk_size, address=a.address,
        author=a.author, description=a.description, stats=stats,
        stall_timeout=a.stall_timeout or None, **overrides,
    )
    secs = time.perf_counter() - t0
    print(
        f"{a.dataset_id}: {a.episodes} episodes, {stats['steps']} steps "
        f"({stats['steps'] / secs:.0f} steps/s on {a.workers} workers, "
        f"{stats['retries']} chunks re-run) written to {d}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
