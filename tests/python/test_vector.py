"""envc vector envs against Gymnasium's SyncVectorEnv over the reference envs, bit for bit.

Every case steps ``envc`` (1 and 2 threads) and ``gymnasium.make_vec(X, vectorization_mode=
"sync")`` with the same seeds and action batches, across several autoresets, and compares
observations, rewards, flags and infos (values, dtypes and ``_key`` masks, SameStep's
``final_obs`` / ``final_info``) exactly. A fresh seed each run (``ENVC_LIVE_SEED`` if set)
picks the seeds, the actions and one more env; it is printed.
"""

from __future__ import annotations

import os
import random
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import envc

LIVE_SEED = int(os.environ.get("ENVC_LIVE_SEED", random.SystemRandom().randrange(2**32)))
print(f"test_vector: ENVC_LIVE_SEED={LIVE_SEED}")

# Episode lengths that cross several resets in STEPS steps (None: the spec's own limit).
FIXED = {
    "Ant-v5": 40,  # rarely terminates under random actions: a short time limit
    "Hopper-v5": None,  # terminates often
    "Reacher-v5": None,  # truncates at 50
    "InvertedPendulum-v5": None,  # terminates within a few steps
}
STEPS = 130
NUM_ENVS = 3


def _live_id() -> str:
    """One more reference id, chosen by the live seed among the bundled ones Gymnasium has."""
    ids = sorted(
        i for i in envc.bundled_ids("task") if i.endswith("-v5") and i in gym.registry and i not in FIXED
    )
    return random.Random(LIVE_SEED).choice(ids)


CASES = [(i, seed) for i in FIXED for seed in (7, LIVE_SEED)] + [(_live_id(), LIVE_SEED)]
MODES = [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP]


# Info keys whose reference dtype envc cannot know (specs carry no info dtypes); the values are
# still compared exactly. InvertedPendulum-v5's `reward_survive` is `int(not terminated)`.
INT_INFOS = {"reward_survive"}


def same_bits(a, b, what: str) -> None:
    a, b = np.asarray(a), np.asarray(b)
    if b.dtype == np.int64 and a.dtype == np.float64 and what.split("'")[-2] in INT_INFOS:
        assert np.array_equal(a, b), f"{what}: {a} vs reference {b}"
        return
    assert a.dtype == b.dtype, f"{what}: dtype {a.dtype} vs reference {b.dtype}"
    assert a.shape == b.shape, f"{what}: shape {a.shape} vs reference {b.shape}"
    if a.dtype == object:
        for i, (x, y) in enumerate(zip(a, b)):
            assert (x is None) == (y is None), f"{what}[{i}]: {x!r} vs reference {y!r}"
            if x is not None:
                same_bits(x, y, f"{what}[{i}]")
        return
    assert a.tobytes() == b.tobytes(), f"{what}: {a} vs reference {b}"


def same_info(a: dict, b: dict, what: str) -> None:
    assert sorted(a) == sorted(b), f"{what}: keys {sorted(a)} vs reference {sorted(b)}"
    for k in b:
        if isinstance(b[k], dict):
            same_info(a[k], b[k], f"{what}[{k!r}]")
        else:
            same_bits(a[k], b[k], f"{what}[{k!r}]")


def same_step(ours, ref, what: str) -> None:
    for name, x, y in zip(("obs", "reward", "terminated", "truncated"), ours[:4], ref[:4]):
        same_bits(x, y, f"{what} {name}")
    same_info(ours[4], ref[4], f"{what} info")


def make_pair(env_id, limit, mode, threads):
    kw = {} if limit is None else {"max_episode_steps": limit}
    ref = gym.make_vec(
        env_id,
        num_envs=NUM_ENVS,
        vectorization_mode="sync",
        vector_kwargs={"autoreset_mode": mode},
        **kw,
    )
    if threads == 1:
        ours = envc.make_vec(env_id, NUM_ENVS, num_threads=1, autoreset_mode=mode, **kw)
    else:
        ours = gym.make_vec(
            f"envc/{env_id}",
            num_envs=NUM_ENVS,
            vectorization_mode="vector_entry_point",
            num_threads=threads,
            autoreset_mode=mode,
            **kw,
        )
    return ours, ref


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("mode", MODES, ids=lambda m: m.value)
@pytest.mark.parametrize("env_id,seed", CASES)
def test_matches_sync_vector_env(env_id, seed, mode, dtype):
    limit = FIXED.get(env_id, 40)  # the live env: a short limit crosses resets in any env
    ref = make_pair(env_id, limit, mode, 1)[1]
    envs = [make_pair(env_id, limit, mode, t)[0] for t in (1, 2)]
    assert envs[1].num_threads == 2
    for ours in envs:
        assert ours.metadata["autoreset_mode"] == mode
        assert ours.single_observation_space == ref.single_observation_space
        assert ours.single_action_space == ref.single_action_space
        assert ours.observation_space == ref.observation_space
        assert ours.action_space == ref.action_space
    rng = np.random.default_rng(seed)
    low, high = ref.single_action_space.low, ref.single_action_space.high
    span = (high - low).astype(np.float64)
    ended = 0
    mask = rng.random(NUM_ENVS) < 0.5
    mask[rng.integers(NUM_ENVS)] = True
    resets = {
        0: lambda: {"seed": seed},
        STEPS // 2: dict,  # no seed: each env's stream continues
        3 * STEPS // 4: lambda: {"seed": seed + 1, "options": {"reset_mask": mask.copy()}},
    }
    for t in range(STEPS):
        if t in resets:
            kw = resets[t]()
            r = ref.reset(**kw)
            for ours in envs:
                o, info = ours.reset(**resets[t]())
                same_bits(o, r[0], f"{env_id} reset({kw}) obs")
                same_info(info, r[1], f"{env_id} reset({kw}) info")
        a = (low - 0.1 * span + 1.2 * span * rng.random((NUM_ENVS, low.size))).astype(dtype)
        r = ref.step(a)
        for k, ours in enumerate(envs):
            what = f"{env_id} {mode.value} {np.dtype(dtype)} threads={k + 1} step {t}"
            same_step(ours.step(a), r, what)
        ended += int(np.sum(r[2] | r[3]))
    assert ended >= 2, f"{env_id}: only {ended} episodes ended in {STEPS} steps"
    for e in (*envs, ref):
        e.close()


def test_seed_lists_and_copy():
    ref = gym.make_vec("Hopper-v5", num_envs=3, vectorization_mode="sync")
    ours = envc.make_vec("Hopper-v5", 3, num_threads=2)
    seeds = [LIVE_SEED, None, 5]
    o, _ = ours.reset(seed=seeds)
    r, _ = ref.reset(seed=seeds)
    same_bits(o[[0, 2]], r[[0, 2]], "reset(seed=list) obs")
    a = np.zeros((3, 3))
    assert ours.step(a)[0] is not ours.step(a)[0]  # copy=True: fresh arrays
    nocopy = envc.EnvcVectorEnv("Hopper-v5", 2, copy=False)
    nocopy.reset(seed=1)
    assert nocopy.step(np.zeros((2, 3)))[0] is nocopy.step(np.zeros((2, 3)))[0]


def test_bad_input_raises_and_moves_nothing():
    ref = gym.make_vec("Hopper-v5", num_envs=2, vectorization_mode="sync")
    ours = envc.make_vec("Hopper-v5", 2)
    with pytest.raises(RuntimeError, match="reset"):
        ours.step(np.zeros((2, 3)))
    with pytest.raises(RuntimeError, match="reset"):
        ours.reset(options={"reset_mask": np.array([True, False])})
    ours.reset(seed=3)
    ref.reset(seed=3)
    bad = [
        np.zeros((3, 3)),
        np.zeros((2, 4)),
        np.zeros(6),
        np.zeros((2, 3, 1)),
        np.array([[0.0, 0.0, 0.0], [0.0, np.nan, 0.0]]),
        np.array([[0.0, np.inf, 0.0], [0.0, 0.0, 0.0]], dtype=np.float32),
        [["a", "b", "c"], ["d", "e", "f"]],
    ]
    for a in bad:
        with pytest.raises(ValueError):
            ours.step(a)
    a = np.full((2, 3), 0.5)
    same_step(ours.step(a), ref.step(a), "step after rejected batches")
    with pytest.raises(ValueError, match="length"):
        ours.reset(seed=[1, 2, 3])
    with pytest.raises(ValueError):
        ours.reset(seed=-1)
    for mask, error in [
        ([True, False], TypeError),
        (np.array([1, 0]), TypeError),
        (np.array([True]), ValueError),
        (np.array([False, False]), ValueError),
    ]:
        with pytest.raises(error, match="reset_mask"):
            ours.reset(options={"reset_mask": mask})
    ours.close()
    with pytest.raises(RuntimeError, match="closed"):
        ours.step(a)
    with pytest.raises(RuntimeError, match="closed"):
        ours.reset()


def test_bad_construction_raises():
    with pytest.raises(ValueError, match="autoreset"):
        envc.make_vec("Hopper-v5", 2, autoreset_mode=AutoresetMode.DISABLED)
    with pytest.raises(ValueError, match="num_envs"):
        envc.EnvcVectorEnv("Hopper-v5", 0)
    with pytest.raises(ValueError, match="num_threads"):
        envc.EnvcVectorEnv("Hopper-v5", 2, num_threads=0)
    with pytest.raises(TypeError):
        envc.make_vec("Hopper-v5", 2, no_such_parameter=1)
    with pytest.raises(envc.SpecError):
        envc.make_vec("Hopper-v5", 2, frame_skip=-1)
    with pytest.raises(TypeError, match="not a task spec"):
        envc.make_vec("PointMaze_UMaze-v3", 2)
    with pytest.raises(TypeError, match="multi-agent"):
        envc.make_vec(envc.bundled_ids("agents")[0], 2)
    # More envs than memory allows is refused before allocating them (was a PanicException
    # part-way through, when an mjData allocation failed).
    with pytest.raises(ValueError, match=r"E1403.*1000000 envs"):
        envc.make_vec("Hopper-v5", 10**6)


def test_registered_vector_entry_point():
    env = gym.make_vec("envc/Reacher-v5", num_envs=2)  # the vector entry point by default
    assert isinstance(env, envc.EnvcVectorEnv)
    assert env.spec.id == "envc/Reacher-v5"
    env.reset(seed=0)
    for _ in range(50):
        out = env.step(np.zeros((2, 2), dtype=np.float32))
    assert out[3].all() and not out[2].any()  # Reacher's time limit, 50 steps
    env.close()
    # A spec file registers as envc/<its id>, with the vector entry point.
    path = Path(__file__).resolve().parents[2] / "specs/examples/reacher_goal.toml"
    env = envc.make_vec(str(path), 2, max_episode_steps=3)
    assert env.spec.id == "envc/ReacherGoal-v0"
    obs, _ = env.reset(seed=1)
    assert obs.shape == (2, *env.single_observation_space.shape)
    flags = [env.step(env.action_space.sample())[3] for _ in range(3)]
    assert not flags[1].any() and flags[2].all()  # max_episode_steps=3


def test_randomized_envs_replay_bit_for_bit_on_any_thread_count_and_position():
    # Domain randomization (specs/examples/go1_randomized.toml: friction, masses, gains, pushes)
    # draws from each env's seeded stream: 1 or 2 threads, and env k of a vector env against a
    # single env seeded seed + k, give the same bits.
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    spec = os.path.join(root, "specs", "examples", "go1_randomized.toml")
    xml = os.path.abspath(os.path.join(root, "..", "shared", "models", "unitree_go1", "scene.xml"))
    if not os.path.isfile(xml):
        pytest.skip(f"the shared Go1 model is not at {xml}")
    n, steps = 3, 80
    actions = np.random.default_rng(0).uniform(-0.4, 0.4, size=(steps, n, 12))

    def run(threads):
        v = envc.make_vec(spec, num_envs=n, num_threads=threads, xml_file=xml)
        obs, _ = v.reset(seed=11)
        out = [(obs.copy(), None, None)]
        for a in actions:
            obs, r, term, trunc, _ = v.step(a)
            out.append((obs.copy(), r.copy(), term | trunc))
        v.close()
        return out

    one, two = run(1), run(2)
    for (o1, r1, _), (o2, r2, _) in zip(one, two):
        assert np.array_equal(o1, o2) and (r1 is None or np.array_equal(r1, r2))
    single = envc.make(spec, xml_file=xml).unwrapped
    obs, _ = single.reset(seed=13)
    assert np.array_equal(obs, one[0][0][2])
    for t, a in enumerate(actions):
        obs, r, term, trunc, _ = single.step(a[2])
        assert np.array_equal(obs, one[t + 1][0][2]) and r == one[t + 1][1][2]
        if term or trunc:
            break


def test_events_switched_off_by_when_draw_nothing(tmp_path):
    # go1_joystick.toml's [events] carry `when = "domain_randomization"` (default false): off, the
    # env must step exactly as the same spec without any [events]; on, the physics must differ.
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    spec = os.path.join(root, "specs", "examples", "go1_joystick.toml")
    xml = os.path.abspath(os.path.join(root, "..", "shared", "models", "unitree_go1", "scene.xml"))
    if not os.path.isfile(xml):
        pytest.skip(f"the shared Go1 model is not at {xml}")
    text = open(spec).read()
    stripped = tmp_path / "go1_joystick_no_events.toml"
    stripped.write_text(text[: text.index("[events.")])
    actions = np.random.default_rng(1).uniform(-0.3, 0.3, size=(60, 12))

    def run(path, **kw):
        env = envc.make(str(path), xml_file=xml, **kw).unwrapped
        obs, _ = env.reset(seed=21)
        out = [obs.copy()]
        for a in actions:
            obs, r, term, trunc, _ = env.step(a)
            out.append(np.append(obs, r))
            if term or trunc:
                break
        return out

    off, none, on = run(spec), run(stripped), run(spec, domain_randomization=True)
    assert len(off) == len(none) and all(np.array_equal(a, b) for a, b in zip(off, none))
    assert not all(np.array_equal(a, b) for a, b in zip(off, on))


def test_a_second_thread_is_refused_with_e1106_and_close_waits():
    import threading

    env = envc.make_vec("Humanoid-v5", 2, frame_skip=1000)
    env.reset(seed=0)
    started = threading.Event()
    errors = []

    def slow():
        started.set()
        try:
            for _ in range(3):
                env.step(np.zeros((2, 17)))
        except Exception as e:  # noqa: BLE001
            errors.append(e)

    t = threading.Thread(target=slow)
    t.start()
    started.wait()
    import time

    time.sleep(0.05)
    with pytest.raises(envc.Error) as e:
        env.step(np.zeros((2, 17)))
    assert e.value.code == "E1106"
    env.close()  # waits for the running step, then closes
    t.join()
    # The other thread's later steps meet the close: refused while it runs (E1106) or after it.
    assert all(getattr(x, "code", "") == "E1106" or "closed" in str(x) for x in errors), errors
