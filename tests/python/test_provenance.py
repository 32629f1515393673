"""Datasets carry what made them (docs/datasets.md, "What made a dataset"): Minari's own
``recover_environment`` (through envc's env class) and ``envc.recover_environment`` rebuild the
env after its spec moved away, refuse a spec edited since (E1212; W1212 when accepted), and warn
(W1214) or refuse (E1214) under another MuJoCo version."""

from __future__ import annotations

import json
import os
import shutil
import warnings

import numpy as np
import pytest

import envc

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def _user_spec(home):
    """Hopper-v5 as a user's spec (another id, no entry point) with its model beside it."""
    (home / "specs").mkdir(parents=True)
    (home / "models").mkdir()
    shutil.copy(os.path.join(ROOT, "assets", "gymnasium", "hopper.xml"), home / "models")
    text = open(os.path.join(ROOT, "specs", "gymnasium", "hopper.toml")).read()
    text = text.replace("../../assets/gymnasium/hopper.xml", "../models/hopper.xml")
    text = text.replace('"Hopper-v5"', '"ProvHopperPy-v0"')
    text = "\n".join(l for l in text.splitlines() if not l.startswith("entry_point"))
    spec = home / "specs" / "prov_hopper.toml"
    spec.write_text(text)
    return spec


def _replays(ds, env):
    """Every stored episode replays in `env` from its stored seed and actions, bit for bit."""
    metas = list(ds.storage.get_episode_metadata(range(ds.total_episodes)))
    for ep, meta in zip(ds.iterate_episodes(), metas):
        obs, _ = env.reset(seed=int(meta["seed"]))
        assert np.array_equal(obs, ep.observations[0])
        for t in range(len(ep)):
            obs, r, *_ = env.step(ep.actions[t])
            assert np.array_equal(obs, ep.observations[t + 1]) and r == ep.rewards[t], t


def test_a_dataset_recovers_after_its_spec_moved_and_refuses_an_edited_one(tmp_path, monkeypatch):
    import minari

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "ds"))
    home = tmp_path / "home"
    spec = _user_spec(home)
    envc.collect(str(spec), "tests/prov-v0", 2, seed=5, root=tmp_path / "ds", max_episode_steps=60)
    ds = minari.load_dataset("tests/prov-v0")
    meta = ds.storage.metadata
    assert meta["mujoco_version"] == envc.__mujoco_version__ == "3.17.0"
    assert meta["envc_version"] == envc.__version__
    files = meta["envc_provenance"]["files"]
    assert [f["path"] for f in files] == ["prov_hopper.toml", "../models/hopper.xml"]
    assert files[0]["text"] == spec.read_text()

    # The spec and its model moved away: Minari's recover_environment still builds the env,
    # from the dataset's own copy, and it replays the stored episodes.
    shutil.move(str(home), str(tmp_path / "moved"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        env = ds.recover_environment()
    assert env.spec.id == "envc/ProvHopperPy-v0"
    assert env.spec.max_episode_steps == 60
    _replays(ds, env)
    _replays(ds, envc.recover_environment(ds))
    _replays(ds, envc.recover_environment(tmp_path / "ds" / "tests" / "prov-v0"))

    # Back, with the spec edited: refused with the code, naming the file; accepted with W1212.
    shutil.move(str(tmp_path / "moved"), str(home))
    spec.write_text(spec.read_text().replace("healthy_reward = { default = 1.0", "healthy_reward = { default = 2.0"))
    for recover in (ds.recover_environment, lambda **kw: envc.recover_environment(ds, **kw)):
        with pytest.raises(envc.DatasetError) as e:
            recover()
        assert e.value.code == "E1212" and "prov_hopper.toml changed" in str(e.value)
        with pytest.warns(envc.DatasetWarning) as w:
            env = recover(accept_changed_spec=True)
        assert [x.message.code for x in w] == ["W1212"]
        env.reset(seed=0)
        # The current spec is the one that runs: its healthy reward is 2.
        _, r, *_ = env.step(np.zeros(3, dtype=np.float32))
        assert r > 1.5
        # Or the dataset's own copy, though a spec is found there: the stored episodes again.
        _replays(ds, recover(use_recorded_spec=True))


def test_another_mujoco_version_warns_and_can_be_refused(tmp_path, monkeypatch):
    import minari

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "ds"))
    # A bundled id, with the reference's class as its env spec: envc's own recovery checks it.
    for spec_kind, ds_id in [("reference", "tests/v-v0"), ("envc", "tests/w-v0")]:
        envc.collect("Hopper-v5", ds_id, 1, seed=1, root=tmp_path / "ds", env_spec=spec_kind)
        path = tmp_path / "ds" / "tests" / ds_id.split("/")[1] / "data" / "metadata.json"
        meta = json.loads(path.read_text())
        assert meta["envc_provenance"]["spec"] == "Hopper-v5"
        meta["mujoco_version"] = meta["envc_provenance"]["mujoco_version"] = "3.16.0"
        env_spec = json.loads(meta["env_spec"])
        if "envc_provenance" in env_spec["kwargs"]:  # the copy envc's env class checks
            env_spec["kwargs"]["envc_provenance"]["mujoco_version"] = "3.16.0"
            meta["env_spec"] = json.dumps(env_spec)
        path.write_text(json.dumps(meta))
        ds = minari.load_dataset(ds_id)
        with pytest.warns(envc.DatasetWarning) as w:
            env = envc.recover_environment(ds)
        assert [x.message.code for x in w] == ["W1214"] and "3.16.0" in str(w[0].message)
        _replays(ds, env)
        with pytest.raises(envc.DatasetError) as e:
            envc.recover_environment(ds, refuse_other_mujoco=True)
        assert e.value.code == "E1214"
    # Through Minari's own recover_environment when the env spec is envc's.
    with pytest.warns(envc.DatasetWarning):
        ds.recover_environment()
    with pytest.raises(envc.DatasetError):
        ds.recover_environment(refuse_other_mujoco=True)


def test_old_datasets_without_a_record_still_recover(tmp_path, monkeypatch):
    import minari

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "ds"))
    envc.collect("Hopper-v5", "tests/old-v0", 1, seed=2, root=tmp_path / "ds", env_spec="envc")
    path = tmp_path / "ds" / "tests" / "old-v0" / "data" / "metadata.json"
    meta = json.loads(path.read_text())
    for key in ("envc_provenance", "mujoco_version"):
        del meta[key]
    env_spec = json.loads(meta["env_spec"])
    del env_spec["kwargs"]["envc_provenance"]
    meta["env_spec"] = json.dumps(env_spec)
    path.write_text(json.dumps(meta))
    ds = minari.load_dataset("tests/old-v0")
    _replays(ds, ds.recover_environment())
    _replays(ds, envc.recover_environment(ds))
