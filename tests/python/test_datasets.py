"""Minari datasets from Python: ``envc.collect`` writes what ``envc collect`` writes, and Minari's
own ``DataCollector`` records an envc env into a dataset that loads and replays."""

from __future__ import annotations

import os
import subprocess

import gymnasium as gym
import numpy as np

import envc
from conftest import envc_cli

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))



def _episodes(root, dataset_id, monkeypatch):
    import minari

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(root))
    ds = minari.load_dataset(dataset_id)
    return ds, list(ds.iterate_episodes())


def test_collect_writes_what_the_cli_writes(tmp_path, monkeypatch):
    for spec, kw, set_ in [
        ("Hopper-v5", {"healthy_z_range": (0.5, 2.0)}, ["--set", "healthy_z_range=[0.5, 2.0]"]),
        ("PointMaze_UMaze-v3", {}, []),
    ]:
        py_root, cli_root = tmp_path / f"py-{spec}", tmp_path / f"cli-{spec}"
        envc.collect(spec, "tests/x-v0", 2, seed=11, root=py_root, policy="random", **kw)
        subprocess.run(
            [envc_cli(), "collect", spec, "--dataset-id", "tests/x-v0", "--episodes", "2", "--seed", "11", "--root", str(cli_root), *set_],
            check=True,
            capture_output=True,
        )
        _, a = _episodes(py_root, "tests/x-v0", monkeypatch)
        _, b = _episodes(cli_root, "tests/x-v0", monkeypatch)
        assert len(a) == len(b) == 2
        for x, y in zip(a, b):
            for field in ["actions", "rewards", "terminations", "truncations"]:
                assert np.array_equal(getattr(x, field), getattr(y, field)), (spec, field)
            ox, oy = x.observations, y.observations
            if isinstance(ox, dict):
                assert sorted(ox) == sorted(oy)
                assert all(np.array_equal(ox[k], oy[k]) for k in ox), spec
            else:
                assert np.array_equal(ox, oy), spec


def test_collect_refuses_bad_requests(tmp_path):
    import pytest

    with pytest.raises(TypeError):
        envc.collect("MaMuJoCo-Ant-v1", "tests/a-v0", 1, root=tmp_path)
    with pytest.raises(ValueError):
        envc.collect("Hopper-v5", "tests/b-v0", 1, policy="greedy", root=tmp_path)
    with pytest.raises(ValueError):
        envc.collect("Hopper-v5", "tests/c-v0", 1, policy="replay", actions=np.zeros((5, 4)), root=tmp_path)
    assert not (tmp_path / "tests" / "c-v0").exists(), "a failed recording leaves no dataset"


def test_minari_data_collector_records_an_envc_env(tmp_path, monkeypatch):
    import minari

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path))
    env = minari.DataCollector(gym.make("envc/Hopper-v5", max_episode_steps=30), record_infos=False)
    env.action_space.seed(3)
    for i in range(2):
        env.reset(seed=100 + i)
        done = False
        while not done:
            _, _, term, trunc, _ = env.step(env.action_space.sample())
            done = term or trunc
    env.create_dataset(dataset_id="tests/dc-v0", algorithm_name="random", author="envc tests")
    ds = minari.load_dataset("tests/dc-v0")
    assert ds.total_episodes == 2
    # recover_environment builds the envc env the dataset names, which replays it exactly.
    rec = ds.recover_environment()
    assert rec.spec.id == "envc/Hopper-v5"
    for i, ep in enumerate(ds.iterate_episodes()):
        obs, _ = rec.reset(seed=100 + i)
        assert np.array_equal(obs, ep.observations[0])
        for t in range(len(ep)):
            obs, r, *_ = rec.step(ep.actions[t])
            assert np.array_equal(obs, ep.observations[t + 1]) and r == ep.rewards[t]


def test_a_dataset_can_name_envcs_own_entry_point(tmp_path, monkeypatch):
    import minari

    envc.collect("Walker2d-v5", "tests/w-v0", 2, seed=4, root=tmp_path, env_spec="envc", reset_noise_scale=0.01, max_episode_steps=25)
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path))
    ds = minari.load_dataset("tests/w-v0")
    env = ds.recover_environment()
    assert env.spec.id == "envc/Walker2d-v5" and env.spec.max_episode_steps == 25
    assert env.spec.kwargs["reset_noise_scale"] == 0.01
    metas = list(ds.storage.get_episode_metadata(range(ds.total_episodes)))
    for ep, meta in zip(ds.iterate_episodes(), metas):
        obs, _ = env.reset(seed=int(meta["seed"]))
        assert np.array_equal(obs, ep.observations[0])
        for t in range(len(ep)):
            obs, r, term, trunc, _ = env.step(ep.actions[t])
            assert np.array_equal(obs, ep.observations[t + 1]) and r == ep.rewards[t]
            assert (term, trunc) == (ep.terminations[t], ep.truncations[t])


def test_datasets_of_specs_without_a_python_class_recover_as_envc_envs(tmp_path, monkeypatch):
    """A custom robot's dataset (no `[env] entry_point`) and a maze's name envc's registration
    (not "(no env spec)"), so recover_environment() rebuilds and replays them."""
    import minari

    text = open(os.path.join(ROOT, "specs", "gymnasium", "hopper.toml")).read()
    text = text.replace("../../assets/", os.path.join(ROOT, "assets") + "/")
    text = text.replace('"Hopper-v5"', '"MyHopper-v0"')
    text = "\n".join(l for l in text.splitlines() if not l.startswith("entry_point"))
    spec = tmp_path / "my_hopper.toml"
    spec.write_text(text)
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "ds"))
    for what, ds_id in [(str(spec), "tests/mine-v0"), ("PointMaze_UMaze-v3", "tests/umaze-v0")]:
        envc.collect(what, ds_id, 2, seed=9, root=tmp_path / "ds", max_episode_steps=40)
        ds = minari.load_dataset(ds_id)
        env = ds.recover_environment()
        assert env.spec.id.startswith("envc/"), env.spec
        metas = list(ds.storage.get_episode_metadata(range(ds.total_episodes)))
        for ep, meta in zip(ds.iterate_episodes(), metas):
            obs, _ = env.reset(seed=int(meta["seed"]))
            first = ep.observations[0] if not isinstance(obs, dict) else {k: ep.observations[k][0] for k in obs}
            if isinstance(obs, dict):
                assert all(np.array_equal(obs[k], first[k]) for k in obs)
            else:
                assert np.array_equal(obs, first)
            for t in range(len(ep)):
                obs, r, *_ = env.step(ep.actions[t])
                assert r == ep.rewards[t], (what, t)
