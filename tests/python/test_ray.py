"""envc.ray: a dataset collected on a local 2-node Ray cluster (127.0.0.1, 1 CPU per node) is the
same bytes as ``envc collect``'s on one machine, with a worker killed mid-episode and with a
driver killed by SIGKILL (nothing loadable is left; the re-run starts over cleanly).

The cluster is this module's own: its ports, its ``--temp-dir``, stopped by killing the processes
it started (never ``ray stop``, which would stop every Ray on the machine)."""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

ray = pytest.importorskip("ray", reason="envc.ray needs Ray (pip install 'envc[ray]')")

import envc  # noqa: E402
import envc.ray  # noqa: E402
from conftest import envc_cli  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
VENV_BIN = Path(sys.executable).parent
HOPPER = {"max_episode_steps": 50}
# The policies below are defined here, in a module Ray's workers cannot import: ship them by value.
ray.cloudpickle.register_pickle_by_value(sys.modules[__name__])



def _temp_base() -> str:
    """Where the cluster's session files go: $ENVC_RAY_TMP, else /tmp (Ray's unix sockets need a
    short path)."""
    base = os.environ.get("ENVC_RAY_TMP")
    if base:
        return base
    return "/tmp"


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _processes_under(tag: str) -> list[int]:
    """Pids whose command line or open files name our temp dir: the cluster's own processes,
    nobody else's (Ray's agents rename themselves `ray::...`, but keep their logs there open)."""
    pids = []
    for p in Path("/proc").iterdir():
        if not p.name.isdigit() or int(p.name) == os.getpid():
            continue
        try:
            cmd = (p / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            mine = tag in cmd or any(tag in os.readlink(f) for f in (p / "fd").iterdir())
        except OSError:
            continue
        if mine:
            pids.append(int(p.name))
    return pids


@pytest.fixture(scope="module")
def cluster():
    temp = tempfile.mkdtemp(prefix=f"ray-envc-{os.getpid()}-", dir=_temp_base())
    port = _free_port()
    common = [
        "--num-cpus=1",
        "--object-store-memory=200000000",
        "--disable-usage-stats",
        f"--node-manager-port={_free_port()}",
        f"--object-manager-port={_free_port()}",
    ]
    ray_bin = str(VENV_BIN / "ray")
    # Our own HOME: another Ray on this machine may have left ~/.ray/auth_token (token
    # authentication), which is not this cluster's business.
    home = os.path.join(temp, "home")
    os.makedirs(home)
    env = {k: v for k, v in os.environ.items() if not k.startswith("RAY_")}
    env.update(HOME=home, RAY_AUTH_MODE="disabled")
    saved = {"RAY_AUTH_MODE": os.environ.get("RAY_AUTH_MODE")}
    os.environ["RAY_AUTH_MODE"] = "disabled"
    try:
        head = [ray_bin, "start", "--head", "--node-ip-address=127.0.0.1", f"--port={port}",
                f"--temp-dir={temp}", "--include-dashboard=false",
                f"--ray-client-server-port={_free_port()}", *common]
        subprocess.run(head, check=True, capture_output=True, timeout=120, env=env)
        common[3] = f"--node-manager-port={_free_port()}"
        common[4] = f"--object-manager-port={_free_port()}"
        node = [ray_bin, "start", f"--address=127.0.0.1:{port}", "--node-ip-address=127.0.0.1", *common]
        r = subprocess.run(node, capture_output=True, timeout=120, env=env)
        assert r.returncode == 0, r.stdout.decode()[-3000:] + r.stderr.decode()[-3000:]
        address = f"127.0.0.1:{port}"
        ray.init(address=address, log_to_driver=False)
        deadline = time.time() + 60
        while len([n for n in ray.nodes() if n["Alive"]]) < 2:
            assert time.time() < deadline, "the second node never joined"
            time.sleep(0.5)
        yield address
    finally:
        if ray.is_initialized():
            ray.shutdown()
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
        for _ in range(3):
            pids = _processes_under(temp)
            for pid in pids:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            if not pids:
                break
            time.sleep(0.5)
        shutil.rmtree(temp, ignore_errors=True)


@ray.remote(num_cpus=1)
class _Probe:
    def pid(self) -> int:
        return os.getpid()


def _cluster_trouble() -> str | None:
    """Why this machine's test cluster cannot run two plain one-CPU actors (None: it can). A
    collection that failed because its workers kept dying is envc's fault only if plain actors
    live."""
    dead = [(n["NodeManagerAddress"], n["NodeManagerPort"]) for n in ray.nodes() if not n["Alive"]]
    if dead:
        return f"nodes {dead} are dead"
    probes = [_Probe.remote() for _ in range(2)]
    try:
        ray.get([p.pid.remote() for p in probes], timeout=60)
    except Exception as e:  # noqa: BLE001 - any failure of a plain actor is the cluster's
        return f"a plain actor failed too: {type(e).__name__}: {str(e)[:300]}"
    finally:
        for p in probes:
            ray.kill(p)
    return None


def _collect(*args, **kwargs) -> str:
    """envc.ray.collect; a failure from workers that kept dying is a skip when plain actors die on
    this cluster too (the machine's trouble, named in the skip), and a failure otherwise."""
    try:
        return envc.ray.collect(*args, **kwargs)
    except (RuntimeError, envc.DatasetError) as e:
        if "worker died" in str(e) or "E1602" in str(e):
            trouble = _cluster_trouble()
            if trouble:
                pytest.skip(f"the test cluster cannot keep Ray actors alive ({trouble}); envc said: {e}")
        raise


def _both_nodes_alive() -> None:
    """A node of the test cluster that died (before envc ran anything on it) is the machine's
    trouble: the test is skipped, saying so."""
    nodes = ray.nodes()
    if len([n for n in nodes if n["Alive"]]) != 2:
        pytest.skip(f"a node of the test cluster is dead: {[(n['NodeManagerAddress'], n['NodeManagerPort'], n['Alive']) for n in nodes]}")


def _files(d: Path) -> dict[str, bytes]:
    return {str(p.relative_to(d)): p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


def _same_dataset(a: Path, b: Path) -> None:
    fa, fb = _files(a), _files(b)
    assert sorted(fa) == sorted(fb)
    for name in fa:
        assert fa[name] == fb[name], f"{name} differs"


def _load(root: Path, dataset_id: str, monkeypatch):
    import minari

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(root))
    return minari.load_dataset(dataset_id)


def test_per_episode_streams_are_numpy_default_rng_of_seed_and_index(tmp_path):
    """Episode i's random actions are numpy's default_rng([seed, i]) draws, whatever came before
    (the reference here is numpy itself, not envc)."""
    d = Path(envc.collect("Hopper-v5", "tests/rng-v0", 3, seed=7, root=tmp_path, policy="random", **HOPPER))
    import minari

    ds = minari.load_dataset(str(d))
    low, high = np.float64(-1.0), np.float64(1.0)
    for ep in ds.iterate_episodes():
        rng = np.random.default_rng([7, ep.id])
        want = np.array([[rng.uniform(low, high) for _ in range(3)] for _ in range(len(ep.actions))], dtype=np.float32)
        np.testing.assert_array_equal(ep.actions, want)
    seeds = [m["seed"] for m in ds.storage.get_episode_metadata(range(3))]
    assert seeds == [7, 8, 9]
    # Replayed rows restart at row 0 in every episode.
    rows = np.linspace(-1, 1, 12, dtype=np.float32).reshape(4, 3)
    d = Path(envc.collect("Hopper-v5", "tests/replay-v0", 2, seed=3, root=tmp_path, policy="replay", actions=rows, **HOPPER))
    for ep in minari.load_dataset(str(d)).iterate_episodes():
        np.testing.assert_array_equal(ep.actions[:4], rows[: len(ep.actions[:4])])


@pytest.mark.parametrize("fmt", ["arrow", "hdf5"])
def test_two_nodes_write_the_cli_dataset(cluster, tmp_path, monkeypatch, fmt):
    cli_root, ray_root = tmp_path / "cli", tmp_path / "ray"
    subprocess.run(
        [envc_cli(), "collect", "Hopper-v5", "--dataset-id", "tests/hop-v0", "--episodes", "8", "--seed", "5",
         "--format", fmt, "--root", str(cli_root), "--set", "max_episode_steps=50"],
        check=True, capture_output=True,
    )
    _both_nodes_alive()
    stats: dict = {}
    d = _collect("Hopper-v5", "tests/hop-v0", 8, "random", seed=5, num_workers=2, format=fmt,
                         root=ray_root, chunk_size=1, stats=stats, stall_timeout=120, **HOPPER)
    # (Chunks re-run after an actor died under load still give the same bytes: checked below.)
    assert stats["chunks"] == 8, stats
    a, b = cli_root / "tests" / "hop-v0", Path(d)
    if fmt == "arrow":
        _same_dataset(a, b)
    else:
        # HDF5 object headers carry modification times: compare everything else.
        assert (a / "data" / "metadata.json").read_bytes() == (b / "data" / "metadata.json").read_bytes()
    da, db = _load(cli_root, "tests/hop-v0", monkeypatch), _load(ray_root, "tests/hop-v0", monkeypatch)
    assert da.total_steps == db.total_steps and db.total_episodes == 8
    for ea, eb in zip(da.iterate_episodes(), db.iterate_episodes()):
        for k in ("observations", "actions", "rewards", "terminations", "truncations"):
            np.testing.assert_array_equal(getattr(ea, k), getattr(eb, k))
        for k in ea.infos:
            np.testing.assert_array_equal(ea.infos[k], eb.infos[k])
    ma = da.storage.get_episode_metadata(range(8))
    mb = db.storage.get_episode_metadata(range(8))
    assert [dict(m) for m in ma] == [dict(m) for m in mb]
    assert not (ray_root / ".envc-staging").exists()


def _random_policy(obs, rng):
    return rng.uniform(-1.0, 1.0, 3)


class _KillOnce:
    """A callable policy that kills its worker process mid-episode the first time any worker
    reaches step 30 (a marker file makes it once per test, across processes)."""

    def __init__(self, marker: str):
        self.marker, self.steps = marker, 0

    def __call__(self, obs, rng):
        self.steps += 1
        if self.steps == 30:
            try:
                fd = os.open(self.marker, os.O_CREAT | os.O_EXCL)
            except FileExistsError:
                pass
            else:
                os.close(fd)
                os._exit(1)
        return _random_policy(obs, rng)


def test_a_worker_killed_mid_episode_changes_nothing(cluster, tmp_path, monkeypatch):
    one = envc.collect("Hopper-v5", "tests/cb-v0", 8, seed=9, root=tmp_path / "one", policy=_random_policy, **HOPPER)
    stats: dict = {}
    marker = tmp_path / "killed"
    _both_nodes_alive()
    d = _collect("Hopper-v5", "tests/cb-v0", 8, _KillOnce(str(marker)), seed=9, num_workers=2,
                         root=tmp_path / "ray", chunk_size=2, stats=stats, stall_timeout=120, **HOPPER)
    assert marker.exists() and stats["retries"] >= 1
    _same_dataset(Path(one), Path(d))
    assert _load(tmp_path / "ray", "tests/cb-v0", monkeypatch).total_episodes == 8


def test_a_killed_driver_leaves_nothing_loadable_and_a_rerun_starts_over(cluster, tmp_path, monkeypatch):
    root = tmp_path / "root"
    script = textwrap.dedent(f"""
        import time, envc.ray
        def slow(obs, rng):
            time.sleep(0.002)
            return rng.uniform(-1.0, 1.0, 3)
        envc.ray.collect("Hopper-v5", "tests/k-v0", 60, slow, seed=1, num_workers=2, root={str(root)!r},
                         chunk_size=2, address={cluster!r}, stall_timeout=120, max_episode_steps=50)
    """)
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    staging = root / ".envc-staging"
    deadline = time.time() + 90
    while not any(staging.glob("*/ds/data/2")):
        assert p.poll() is None, "the driver ended before it was killed"
        assert time.time() < deadline, "no episode was written in time"
        time.sleep(0.05)
    p.send_signal(signal.SIGKILL)
    p.wait()
    import minari

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(root))
    assert not (root / "tests" / "k-v0").exists()
    assert "tests/k-v0" not in minari.list_local_datasets()
    with pytest.raises(Exception):
        minari.load_dataset("tests/k-v0")
    # The same arguments again: the dead driver's staging directory is removed (its lock is free)
    # and the collection starts over; the result is the one-machine dataset.
    rerun = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=240)
    assert rerun.returncode == 0, rerun.stderr.decode()[-2000:]
    assert [p.name for p in staging.iterdir()] == [] if staging.exists() else True
    ds = minari.load_dataset("tests/k-v0")
    assert ds.total_episodes == 60
    one = envc.collect("Hopper-v5", "tests/k-v0", 60, seed=1, root=tmp_path / "one",
                       policy=lambda o, r: r.uniform(-1.0, 1.0, 3), **HOPPER)
    _same_dataset(Path(one), root / "tests" / "k-v0")


def test_ctrl_c_stops_the_driver_within_a_second_and_publishes_nothing(cluster, tmp_path, spawn):
    root = tmp_path / "root"
    script = textwrap.dedent(f"""
        import time, envc.ray
        def slow(obs, rng):
            time.sleep(0.002)
            return rng.uniform(-1.0, 1.0, 3)
        try:
            envc.ray.collect("Hopper-v5", "tests/int-v0", 60, slow, seed=1, num_workers=2,
                             root={str(root)!r}, chunk_size=2, address={cluster!r},
                             stall_timeout=120, max_episode_steps=50)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
    """)
    p = spawn([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    staging = root / ".envc-staging"
    deadline = time.time() + 90
    while not any(staging.glob("*/ds/data/2")):
        assert p.poll() is None, "the driver ended before it was interrupted"
        assert time.time() < deadline, "no episode was written in time"
        time.sleep(0.05)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    assert p.stdout.readline().strip() == "interrupted"
    took = time.monotonic() - sent
    assert p.wait(timeout=60) == 0
    assert took < 1.5, f"{took:.2f} s after SIGINT"
    assert not (root / "tests" / "int-v0").exists()
    left = sorted(str(p.relative_to(staging)) for p in staging.rglob("*")) if staging.exists() else []
    assert left == [], left


def test_more_workers_than_the_cluster_has_cpus_for_finish_on_those_it_has(cluster, tmp_path):
    """Four actors of one CPU on a two-CPU cluster: two are never placed, get no chunk, and the
    collection finishes on the two that started, with the one-process dataset."""
    one = envc.collect("Hopper-v5", "tests/many-v0", 6, seed=2, root=tmp_path / "one", **HOPPER)
    stats: dict = {}
    d = _collect("Hopper-v5", "tests/many-v0", 6, "random", seed=2, num_workers=4,
                         root=tmp_path / "ray", chunk_size=1, stats=stats, stall_timeout=120, **HOPPER)
    assert stats["chunks"] == 6
    _same_dataset(Path(one), Path(d))


def _never_returns(obs, rng):
    time.sleep(3600)


def test_no_progress_for_stall_timeout_is_e1602_and_publishes_nothing(cluster, tmp_path):
    root = tmp_path / "root"
    t0 = time.monotonic()
    with pytest.raises(envc.DatasetError, match=r"error\[E1602\].*no progress for 3 s") as e:
        envc.ray.collect("Hopper-v5", "tests/stall-v0", 4, _never_returns, seed=0, num_workers=2,
                         root=root, stall_timeout=3, **HOPPER)
    assert e.value.code == "E1602"
    assert time.monotonic() - t0 < 90
    assert not (root / "tests" / "stall-v0").exists()
    assert not any((root / ".envc-staging").glob("*")) if (root / ".envc-staging").exists() else True
    with pytest.raises(ValueError, match="stall_timeout"):
        envc.ray.collect("Hopper-v5", "tests/stall-v0", 4, root=root, stall_timeout=0, **HOPPER)


@pytest.mark.parametrize("fmt", ["arrow", "hdf5"])
def test_shards_in_any_order_merge_into_the_one_process_dataset(tmp_path, fmt):
    """The sharded path without Ray: chunks recorded out of order (one twice, as a re-run after a
    worker death) merge into the dataset envc.collect writes."""
    from envc import _envc
    from envc._gym import overrides_to_toml

    one = Path(envc.collect("Hopper-v5", "tests/sh-v0", 7, seed=3, root=tmp_path / "one", format=fmt, **HOPPER))
    ov = overrides_to_toml(HOPPER)
    d = _envc.ShardedCollection("Hopper-v5", "tests/sh-v0", 7, "random", 3, fmt, str(tmp_path / "sh"), ov)
    got: dict[int, tuple[int, int]] = {}
    for lo, hi in [(4, 7), (0, 2), (2, 4), (0, 2)]:
        for i, e in zip(range(lo, hi), _envc.collect_shard("Hopper-v5", d.staging, lo, hi, d.seed, "random", fmt, ov)):
            got[i] = e
    out = Path(d.finish([got[i] for i in range(7)]))
    if fmt == "arrow":
        _same_dataset(one, out)
    else:
        import minari

        a, b = minari.load_dataset(str(one)), minari.load_dataset(str(out))
        for ea, eb in zip(a.iterate_episodes(), b.iterate_episodes()):
            np.testing.assert_array_equal(ea.observations, eb.observations)
            np.testing.assert_array_equal(ea.actions, eb.actions)
        assert (one / "data" / "metadata.json").read_bytes() == (out / "data" / "metadata.json").read_bytes()
    assert not (tmp_path / "sh" / ".envc-staging").exists()
