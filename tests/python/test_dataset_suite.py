"""The dataset suite (specs/datasets/, docs/datasets.md): a tier built from its spec is the same
bytes from Python, from ``envc dataset build`` and on 1 or 2 Ray workers; Minari loads it, its
reference scores give ``minari.get_normalized_score``, and Gymnasium (the reference) replays its
stored seeds and actions to its stored observations, rewards and infos.

The tier is the bundled InvertedPendulum medium spec with two parameters set (a 20-step time
limit, so a small budget holds many episodes, and a reset noise, to check that parameters reach
``recover_environment()``); its policy is the committed ``.npz``, run in Rust."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import envc
import envc.datasets
from conftest import envc_cli

ROOT = Path(__file__).resolve().parents[2]
BUNDLED = ROOT / "specs" / "datasets" / "mujoco" / "invertedpendulum" / "medium-v0.toml"
DATASET = "tests/invertedpendulum/medium-v0"
STEPS = 3000
PARAMS = {"max_episode_steps": 20, "reset_noise_scale": 0.02}


def _tree(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def spec(tmp_path_factory) -> Path:
    """The bundled tier's spec with the test's parameters, its policy path made absolute."""
    text = BUNDLED.read_text()
    policy = tomllib.loads(text)["policy"]["file"]
    text = text.replace(f'file = "{policy}"', f'file = "{(BUNDLED.parent / policy).resolve()}"')
    text = text.replace('env = "InvertedPendulum-v5"\n', 'env = "InvertedPendulum-v5"\nparams = { max_episode_steps = 20, reset_noise_scale = 0.02 }\n', 1)
    p = tmp_path_factory.mktemp("spec") / "medium-v0.toml"
    p.write_text(text)
    return p


@pytest.fixture(scope="module")
def built(spec, tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("py1")
    envc.datasets.build(spec, steps=STEPS, root=root, dataset_id=DATASET)
    return root


def test_same_bytes_twice_and_from_the_cli(spec, built, tmp_path):
    again = tmp_path / "py2"
    envc.datasets.build(spec, steps=STEPS, root=again, dataset_id=DATASET)
    cli = tmp_path / "cli"
    subprocess.run(
        [envc_cli(), "dataset", "build", str(spec), "--steps", str(STEPS), "--root", str(cli), "--dataset-id", DATASET],
        check=True, capture_output=True,
    )
    first = _tree(built)
    assert any(k.endswith("metadata.json") for k in first)
    assert _tree(again) == first
    assert _tree(cli) == first


def test_same_bytes_on_one_and_two_ray_workers(spec, built, tmp_path):
    pytest.importorskip("ray")
    # In a process of its own: a Ray session started and shut down in pytest's process leaves
    # state behind that kills the actors of the next cluster it joins (test_ray.py's).
    script = f"""
import ray, envc.datasets
ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
try:
    for n in (1, 2):
        envc.datasets.build({str(spec)!r}, steps={STEPS}, root={str(tmp_path)!r} + f"/ray{{n}}",
                            dataset_id={DATASET!r}, workers=n)
finally:
    ray.shutdown()
"""
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=500)
    assert r.returncode == 0, r.stderr[-3000:]
    for n in (1, 2):
        assert _tree(tmp_path / f"ray{n}") == _tree(built), f"{n} worker(s)"


def test_minari_loads_scores_and_gymnasium_replays(built, monkeypatch):
    minari = pytest.importorskip("minari")
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(built))
    ds = minari.load_dataset(DATASET)
    # The budget: a new episode starts only while at least max_episode_steps steps remain.
    assert STEPS - PARAMS["max_episode_steps"] < ds.total_steps <= STEPS

    # Reference scores as the spec states them: the fraction between them.
    refs = tomllib.loads(BUNDLED.read_text())["reference_scores"]
    lo, hi = refs["ref_min_score"], refs["ref_max_score"]
    got = minari.get_normalized_score(ds, np.array([lo, hi, lo + 0.25 * (hi - lo)]))
    np.testing.assert_allclose(got, [0.0, 1.0, 0.25], atol=1e-12)
    assert ds.storage.metadata["num_episodes_average_score"] == refs["num_episodes_average_score"]

    # recover_environment() is the reference env with the spec's parameters.
    env = ds.recover_environment()
    assert env.spec.kwargs == {"reset_noise_scale": 0.02}
    assert env.spec.max_episode_steps == 20
    assert ds.recover_environment(eval_env=True).spec.id == "InvertedPendulum-v5"

    metas = list(ds.storage.get_episode_metadata(range(ds.total_episodes)))
    assert [int(m["seed"]) for m in metas] == [123 + k for k in range(ds.total_episodes)]
    for ep, meta in zip(ds.iterate_episodes(), metas):
        obs, _ = env.reset(seed=int(meta["seed"]))
        np.testing.assert_array_equal(obs, ep.observations[0])
        for t, a in enumerate(ep.actions):
            obs, r, term, trunc, info = env.step(a)
            np.testing.assert_array_equal(obs, ep.observations[t + 1])
            assert r == ep.rewards[t]
            assert (term, trunc) == (ep.terminations[t], ep.truncations[t])
            for k, v in info.items():
                assert ep.infos[k][t + 1] == v, k
        assert ep.terminations[-1] or ep.truncations[-1]
    # Infos are recorded.
    assert set(ep.infos) >= {"reward_survive"}


def test_policy_runs_without_torch(spec):
    """The spec's policy from Python is the Rust runner: deterministic actions in the bounds."""
    pol = envc.datasets.policy(spec, deterministic=True)
    a = pol(np.zeros(4))
    assert a.dtype == np.float32 and a.shape == (1,)
    assert -3.0 <= a[0] <= 3.0
    np.testing.assert_array_equal(a, pol(np.zeros(4)))
    assert "torch" not in sys.modules


def test_policy_is_the_exported_mlp(spec):
    """The Rust runner against the MLP written out in numpy from the committed `.npz`: ReLU
    layers, then tanh(mu) scaled to the action bounds (SB3's deterministic SAC action)."""
    policy = tomllib.loads(BUNDLED.read_text())["policy"]["file"]
    z = np.load(BUNDLED.parent / policy)
    lo, hi = z["action_low"].astype(np.float64), z["action_high"].astype(np.float64)
    pol = envc.datasets.policy(spec, deterministic=True)
    for obs in np.random.default_rng(5).normal(size=(16, 4)):
        x = obs
        i = 0
        while f"hidden_w{i}" in z:
            x = np.maximum(z[f"hidden_w{i}"].astype(np.float64) @ x + z[f"hidden_b{i}"], 0.0)
            i += 1
        mu = z["mu_w"].astype(np.float64) @ x + z["mu_b"]
        want = (lo + 0.5 * (np.tanh(mu) + 1.0) * (hi - lo)).astype(np.float32)
        np.testing.assert_allclose(pol(obs), want, rtol=0, atol=1e-6)


SUITE = ROOT / "specs" / "datasets" / "mujoco"


def test_reference_scores_are_stored_wherever_an_expert_policy_is():
    """An env whose expert tier's policy is committed has Minari's reference scores in every
    tier, the same in each; one without has none (`get_normalized_score` would be made up)."""
    for env_dir in sorted(p for p in SUITE.iterdir() if p.is_dir()):
        tiers = {p.stem: tomllib.loads(p.read_text()) for p in sorted(env_dir.glob("*.toml"))}
        expert = tiers["expert-v0"]
        has_expert = (env_dir / expert["policy"]["file"]).exists()
        scores = [t.get("reference_scores") for t in tiers.values()]
        if has_expert:
            assert scores[0] is not None and all(s == scores[0] for s in scores), env_dir.name
            assert scores[0]["ref_max_score"] > scores[0]["ref_min_score"], env_dir.name
        else:
            assert all(s is None for s in scores), env_dir.name


def test_reacher_reference_scores_are_minaris_computation():
    """Reacher's stored scores recomputed live, as Minari computes them (its seeded random policy
    and the expert policy, 100 episodes each, on Gymnasium's env): 2 × 5,000 steps."""
    pytest.importorskip("minari")
    spec = SUITE / "reacher" / "expert-v0.toml"
    stored = tomllib.loads(spec.read_text())["reference_scores"]
    got = envc.datasets.reference_scores(spec, episodes=stored["num_episodes_average_score"])
    for k in ("ref_min_score", "ref_max_score"):
        np.testing.assert_allclose(got[k], stored[k], rtol=1e-9, err_msg=k)
