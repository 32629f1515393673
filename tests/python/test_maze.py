"""envc mazes from Python against the live Gymnasium-Robotics 1.4.2 reference.

Every bundled maze id with a reference counterpart (PointMaze v3, AntMaze v5, sparse and dense)
runs the same seed and actions through ``gymnasium.make(X)`` and ``gymnasium.make("envc/X")``:
dict observations are compared bitwise, rewards, flags and infos exactly, with auto-reset
continuation. The goal functions (batched, as hindsight relabelling calls them), reset options,
Gymnasium's env checker and bad input are checked too.

Seeds: a fixed one and a fresh one per run (``ENVC_LIVE_SEED`` if set), printed.
"""

from __future__ import annotations

import os
import subprocess
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import envc
from envc._maze import EnvcMazeEnv

gymnasium_robotics = pytest.importorskip("gymnasium_robotics")
gym.register_envs(gymnasium_robotics)

FIXED_SEED = 0
LIVE_SEED = int(os.environ.get("ENVC_LIVE_SEED", np.random.SeedSequence().entropy % 2**32))
print(f"test_maze: live seed {LIVE_SEED} (set ENVC_LIVE_SEED to replay)")
SEEDS = [FIXED_SEED, LIVE_SEED]

MAZE_IDS = envc.bundled_ids("maze")
# The bundled ids the reference registers (all but envc's own examples, e.g. Go1Maze).
REF_IDS = [i for i in MAZE_IDS if i in gym.registry]
OWN_IDS = [i for i in MAZE_IDS if i not in gym.registry]

REPO = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
GO1_XML = os.path.join(REPO, "..", "shared", "models", "unitree_go1", "scene.xml")

# Small maps where random actions reach the goal: terminations and goal updates happen.
NEAR_GOAL = [[1, 1, 1, 1], [1, "r", "g", 1], [1, 1, 1, 1]]
COMBINED = [[1, 1, 1, 1, 1], [1, "c", "c", "c", 1], [1, 1, 1, 1, 1]]

# (id, kwargs): PointMaze and AntMaze, sparse and dense, continuing and not, maze_map, reset_target.
FIXED_CASES = [
    ("PointMaze_UMaze-v3", {}),
    ("PointMaze_Open_Diverse_GRDense-v3", {"continuing_task": False}),
    ("AntMaze_UMaze-v5", {}),
    ("AntMaze_Medium_Diverse_GRDense-v5", {"continuing_task": False}),
    ("PointMaze_UMaze-v3", {"maze_map": NEAR_GOAL, "continuing_task": False}),
    ("PointMaze_OpenDense-v3", {"maze_map": COMBINED, "reset_target": True}),
    ("PointMaze_Open-v3", {"maze_map": COMBINED, "reset_target": True, "continuing_task": False}),
    # Robot parameters go to the robot (its info's costs), as the reference passes them to AntEnv.
    ("AntMaze_OpenDense-v5", {"ctrl_cost_weight": 0.1, "healthy_z_range": (0.3, 1.0)}),
]


def _case_id(case) -> str:
    spec_id, kw = case
    return spec_id + "".join(f"-{k}" for k in kw)


def _pair(spec_id: str, **kw):
    """The reference env and the envc env of one id, made as a user makes them."""
    return gym.make(spec_id, **kw), gym.make(f"envc/{spec_id}", **kw)


def _bits(x) -> bytes:
    return np.asarray(x, dtype=np.float64).tobytes()


def assert_same_obs(ref: dict, got: dict, where: str) -> None:
    assert list(got) == list(ref), where
    for k, v in ref.items():
        g = got[k]
        assert isinstance(g, np.ndarray) and g.dtype == v.dtype == np.float64, (where, k)
        assert g.shape == v.shape, (where, k)
        assert g.tobytes() == v.tobytes(), f"{where}: obs[{k!r}]\nref  {v}\nenvc {g}"


def assert_same_info(ref: dict, got: dict, where: str) -> None:
    assert list(got) == list(ref), where
    for k, v in ref.items():
        if k == "success":
            assert type(got[k]) is bool and got[k] == v, (where, k)
        else:
            # float32 costs (a float32 action) are float32 numbers in the reference and their
            # exact float64 value in envc.
            assert _bits(got[k]) == _bits(v), f"{where}: info[{k!r}] ref {v!r} envc {got[k]!r}"


def rollout(spec_id: str, kw: dict, seed: int, steps: int, max_steps: int) -> dict:
    """Step both envs with the same actions; after an episode ends, reset without a seed."""
    ref, env = _pair(spec_id, max_episode_steps=max_steps, **kw)
    rng = np.random.default_rng(seed)
    o1, i1 = ref.reset(seed=seed)
    o2, i2 = env.reset(seed=seed)
    assert_same_obs(o1, o2, f"{spec_id} reset")
    assert_same_info(i1, i2, f"{spec_id} reset")
    counts = {"terminated": 0, "truncated": 0, "success": 0, "goal_moves": 0}
    shape = ref.action_space.shape
    for t in range(steps):
        a = rng.uniform(-1.5, 1.5, size=shape)  # out-of-bound values included
        if shape == (2,) and t % 3:
            # The point robot heads for the goal (so goals are reached, and moved).
            x, v = o1["observation"][:2], o1["observation"][2:4]
            a = np.tanh(4.0 * (o1["desired_goal"] - x) - 0.8 * v) * 1.2 + 0.3 * a
        if t % 2:
            a = a.astype(np.float32)
        where = f"{spec_id} {kw} seed {seed} step {t} ({a.dtype})"
        goal = o1["desired_goal"]
        o1, r1, te1, tr1, i1 = ref.step(a.copy())
        o2, r2, te2, tr2, i2 = env.step(a.copy())
        assert_same_obs(o1, o2, where)
        assert type(r2) is type(r1) and _bits(r2) == _bits(r1), (where, r1, r2)
        assert type(te2) is bool and type(tr2) is bool, where
        assert (te2, tr2) == (te1, tr1), where
        assert_same_info(i1, i2, where)
        counts["success"] += i1["success"]
        counts["goal_moves"] += not np.array_equal(goal, o1["desired_goal"])
        if te1 or tr1:
            counts["terminated" if te1 else "truncated"] += 1
            o1, i1 = ref.reset()
            o2, i2 = env.reset()
            assert_same_obs(o1, o2, where + " auto-reset")
            assert_same_info(i1, i2, where + " auto-reset")
    ref.close()
    env.close()
    return counts


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("case", FIXED_CASES, ids=_case_id)
def test_rollout_fixed_cases(case, seed):
    spec_id, kw = case
    counts = rollout(spec_id, kw, seed, steps=400, max_steps=150)
    print(spec_id, kw, counts)
    assert counts["truncated"] + counts["terminated"] >= 2, counts
    if kw.get("maze_map") is not None:
        # Goals are reached: episodes terminate, or the goal moves (reset_target).
        key = "terminated" if kw.get("continuing_task") is False else "goal_moves"
        assert counts[key] >= 1, counts


@pytest.mark.parametrize("seed", [LIVE_SEED])
@pytest.mark.parametrize("spec_id", REF_IDS)
def test_rollout_every_id(spec_id, seed):
    """Every bundled id, with the live seed (in the test id); the seed also picks
    ``continuing_task`` and ``reset_target``."""
    rng = np.random.default_rng([seed, REF_IDS.index(spec_id)])
    kw = {"continuing_task": bool(rng.integers(2)), "reset_target": bool(rng.integers(2))}
    rollout(spec_id, kw, seed, steps=200, max_steps=60)


def test_every_reference_id_is_bundled():
    ref_ids = sorted(
        i for i in gym.registry if i.startswith("PointMaze_") or i.startswith("AntMaze_") and i.endswith("-v5")
    )
    assert len(ref_ids) == 40
    assert sorted(REF_IDS) == ref_ids


@pytest.mark.parametrize("spec_id", REF_IDS)
def test_registration_and_spaces(spec_id):
    """The envc/ id has the reference's TimeLimit, spaces and wrappers."""
    assert gym.spec(f"envc/{spec_id}").max_episode_steps == gym.spec(spec_id).max_episode_steps
    ref, env = _pair(spec_id)
    assert env.observation_space == ref.observation_space
    assert list(env.observation_space.spaces) == list(ref.observation_space.spaces)
    for k, box in ref.observation_space.spaces.items():
        assert env.observation_space[k].dtype == box.dtype
        assert env.observation_space[k].shape == box.shape
    assert env.action_space == ref.action_space
    assert env.action_space.dtype == np.float32
    assert str(env).replace("EnvcMazeEnv<envc/", "<") == str(ref).replace(
        "PointMazeEnv<", "<"
    ).replace("AntMazeEnv<", "<")
    assert isinstance(env.unwrapped, gymnasium_robotics.core.GoalEnv)
    assert env.unwrapped.metadata["render_fps"] == ref.unwrapped.metadata["render_fps"]
    assert env.unwrapped.reward_type == ref.unwrapped.reward_type
    assert env.unwrapped.continuing_task == ref.unwrapped.continuing_task
    assert env.unwrapped.reset_target == ref.unwrapped.reset_target


GOAL_CASES = [
    ("PointMaze_UMaze-v3", {}),
    ("PointMaze_UMazeDense-v3", {"continuing_task": False}),
    ("AntMaze_UMazeDense-v5", {}),
    ("AntMaze_UMaze-v5", {"continuing_task": False}),
]


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("case", GOAL_CASES, ids=_case_id)
def test_goal_functions_batched(case, seed):
    """compute_reward / _terminated / _truncated on random batches, as hindsight relabelling
    calls them: the reference's values, bitwise."""
    spec_id, kw = case
    ref, env = _pair(spec_id, **kw)
    ref.reset(seed=seed)
    env.reset(seed=seed)
    r, e = ref.unwrapped, env.unwrapped
    rng = np.random.default_rng(seed)
    n = 513
    a = rng.normal(0.0, 3.0, size=(n, 2))
    d = a + rng.normal(0.0, 0.4, size=(n, 2))  # many pairs within the 0.45 threshold
    info = [{}] * n

    want = r.compute_reward(a, d, info)
    got = e.compute_reward(a, d, info)
    # As SB3's HerReplayBuffer calls it through the wrappers (infos as an array of dicts).
    her = env.get_wrapper_attr("compute_reward")(a, d, np.array(info, dtype=object))
    assert her.tobytes() == want.tobytes()
    assert isinstance(got, np.ndarray) and got.dtype == np.float64 and got.shape == (n,)
    assert got.tobytes() == want.tobytes()
    if r.reward_type == "sparse":
        assert 0 < got.sum() < n  # both outcomes are exercised
    # Non-finite and huge goals (a relabelled buffer may hold anything).
    odd = np.array([[np.nan, 0.0], [np.inf, 0.0], [np.inf, np.inf], [1e308, -1e308], [0.0, 0.0]])
    with np.errstate(over="ignore", invalid="ignore"):
        want_odd = r.compute_reward(odd, np.zeros_like(odd), {})
    assert e.compute_reward(odd, np.zeros_like(odd), {}).tobytes() == want_odd.tobytes()

    # Leading dimensions and broadcasting, as numpy's `norm(..., axis=-1)` takes them.
    a3, d3 = a[:512].reshape(8, 64, 2), d[:512].reshape(8, 64, 2)
    assert e.compute_reward(a3, d3, {}).tobytes() == r.compute_reward(a3, d3, {}).tobytes()
    assert e.compute_reward(a, d[0], {}).tobytes() == r.compute_reward(a, d[0], {}).tobytes()

    # One pair: the reference's scalar types.
    for k in range(64):
        w, g = r.compute_reward(a[k], d[k], {}), e.compute_reward(a[k], d[k], {})
        assert type(g) is type(w) is np.float64 and _bits(g) == _bits(w)
        w, g = r.compute_terminated(a[k], d[k], {}), e.compute_terminated(a[k], d[k], {})
        assert type(g) is type(w) is bool and g == w
        w, g = r.compute_truncated(a[k], d[k], {}), e.compute_truncated(a[k], d[k], {})
        assert type(g) is type(w) is bool and g == w

    # Batched flags: one per pair (the reference's take one norm over the whole batch, so it is
    # compared pair by pair).
    term = e.compute_terminated(a, d, info)
    assert term.dtype == np.bool_ and term.shape == (n,)
    assert term.tolist() == [r.compute_terminated(a[k], d[k], {}) for k in range(n)]
    if not kw.get("continuing_task", True):
        assert 0 < term.sum() < n
    trunc = e.compute_truncated(a, d, info)
    assert trunc.dtype == np.bool_ and trunc.shape == (n,) and not trunc.any()

    # The GoalEnv contract: the step reward and termination are the goal functions of the
    # step's goals (the goal does not move: reset_target is off).
    for _ in range(20):
        o, rew, term1, _, inf = env.step(env.action_space.sample())
        assert _bits(e.compute_reward(o["achieved_goal"], o["desired_goal"], inf)) == _bits(rew)
        assert e.compute_terminated(o["achieved_goal"], o["desired_goal"], inf) == term1
        if term1:
            env.reset()


def _free_cells(maze_map) -> list[tuple[int, int]]:
    return [(i, j) for i, row in enumerate(maze_map) for j, c in enumerate(row) if c != 1]


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("spec_id", ["PointMaze_Medium-v3", "AntMaze_UMazeDense-v5"])
def test_reset_options(spec_id, seed):
    ref, env = _pair(spec_id)
    maze_map = ref.unwrapped.maze.maze_map
    free = _free_cells(maze_map)
    rng = np.random.default_rng(seed)
    cell = lambda: free[rng.integers(len(free))]  # noqa: E731
    options = [
        {"goal_cell": cell(), "reset_cell": cell()},
        {"goal_cell": np.array(cell())},
        {"reset_cell": np.array(cell()), "goal_cell": None},
        {"goal_cell": None, "reset_cell": None},
        {},
        None,
    ]
    for k, opt in enumerate(options):
        s = seed + k if k % 2 == 0 else None
        o1, i1 = ref.reset(seed=s, options=opt)
        o2, i2 = env.reset(seed=s, options=opt)
        assert_same_obs(o1, o2, f"reset options {opt}")
        assert_same_info(i1, i2, f"reset options {opt}")
        if opt and opt.get("goal_cell") is not None:
            want = ref.unwrapped.maze.cell_rowcol_to_xy(np.asarray(opt["goal_cell"]))
            assert np.abs(o2["desired_goal"] - want).max() <= 0.25 * ref.unwrapped.maze.maze_size_scaling
        for t in range(5):
            a = rng.uniform(-1, 1, ref.action_space.shape)
            s1, s2 = ref.step(a), env.step(a)
            assert_same_obs(s1[0], s2[0], f"options {opt} step {t}")
            assert s1[1:4] == s2[1:4]
    wall = next((i, j) for i, row in enumerate(maze_map) for j, c in enumerate(row) if c == 1)
    for bad in ({"goal_cell": wall}, {"reset_cell": wall}):
        with pytest.raises(AssertionError):
            ref.reset(options=bad)
        with pytest.raises(ValueError, match="not a free cell"):
            env.reset(options=bad)
    rows, cols = len(maze_map), len(maze_map[0])
    for bad in ({"goal_cell": (rows, 0)}, {"reset_cell": (0, cols)}):
        with pytest.raises(ValueError, match="not a free cell"):
            env.reset(options=bad)
    for bad in ({"goal_cell": (1,)}, {"goal_cell": (-1, 1)}, {"reset_cell": (1.5, 1)}):
        with pytest.raises(ValueError, match="cell"):
            env.reset(options=bad)


def _checker_warnings(env) -> set[str]:
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        check_env(env.unwrapped, skip_render_check=True)
    return {str(x.message) for x in w}


@pytest.mark.parametrize("spec_id", ["PointMaze_UMaze-v3", "AntMaze_OpenDense-v5"])
def test_env_checker(spec_id):
    """Gymnasium's env checker passes, with no warning the reference does not raise too (the
    reference warns about its infinite observation bounds, so warnings cannot be errors)."""
    ref, env = _pair(spec_id)
    want = _checker_warnings(ref)
    got = _checker_warnings(env)
    assert got <= want, got - want


@pytest.mark.parametrize("spec_id", OWN_IDS)
def test_own_mazes(spec_id):
    """envc's own maze ids (no reference): the goal-conditioned API holds."""
    try:
        env = gym.make(f"envc/{spec_id}")
    except envc.SpecError as e:
        # A robot model that is not shipped (the Go1): the project's shared copy, if present.
        if e.code != "E0301" or not os.path.isfile(GO1_XML):
            raise
        env = gym.make(f"envc/{spec_id}", xml_file=GO1_XML)
    assert isinstance(env.unwrapped, gymnasium_robotics.core.GoalEnv)
    o, info = env.reset(seed=LIVE_SEED)
    assert env.observation_space.contains(o) and type(info["success"]) is bool
    for _ in range(30):
        o, rew, term, trunc, info = env.step(env.action_space.sample())
        assert env.observation_space.contains(o)
        assert _bits(env.unwrapped.compute_reward(o["achieved_goal"], o["desired_goal"], info)) == _bits(rew)
        if term or trunc:
            env.reset()
    # The checker passes; it may only warn about the infinite observation bounds (as for the
    # reference's mazes) and about a robot's own unnormalised actuator ranges (the Go1's).
    allowed = ("infinity", "symmetric and normalized")
    assert not [w for w in _checker_warnings(env) if not any(x in w for x in allowed)]


def test_bad_input():
    env = EnvcMazeEnv("PointMaze_UMaze-v3")
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(2))
    env.reset(seed=1)
    for bad in (np.zeros(3), np.zeros((1, 2)), np.float64(0.5), [0.1]):
        with pytest.raises(ValueError, match="action"):
            env.step(bad)
    for bad in ([np.nan, 0.0], [0.0, np.inf], np.array([np.nan, 0], dtype=np.float32)):
        with pytest.raises(ValueError):
            env.step(bad)
    env.step(np.zeros(2))  # the env still works after bad input
    for a, d in ((np.zeros(3), np.zeros(3)), (np.zeros((4, 2)), np.zeros((3, 2))), (1.0, 2.0)):
        with pytest.raises(ValueError, match="goal"):
            env.compute_reward(a, d, {})
        with pytest.raises(ValueError, match="goal"):
            env.compute_terminated(a, d, {})
    with pytest.raises(ValueError, match="seed"):
        env.reset(seed=2**64)
    with pytest.raises(gym.error.Error, match="seed|Seed"):
        env.reset(seed=-1)  # Gymnasium's own check, as for the reference
    env.close()
    with pytest.raises(RuntimeError, match="closed"):
        env.step(np.zeros(2))
    with pytest.raises(RuntimeError, match="closed"):
        env.compute_reward(np.zeros(2), np.zeros(2), {})
    env.close()  # closing twice is allowed

    with pytest.raises(TypeError, match="not a maze"):
        EnvcMazeEnv("Ant-v5")
    with pytest.raises(TypeError):
        gym.make("envc/PointMaze_UMaze-v3", no_such_parameter=1)
    with pytest.raises(envc.SpecError):
        gym.make("envc/PointMaze_UMaze-v3", reward_type="sparse-ish")
    with pytest.raises(envc.SpecError):
        gym.make("envc/PointMaze_UMaze-v3", maze_map=[[1, 1], [1, "x"]])
    # "human" is Gymnasium's HumanRendering over rgb_array; the env itself renders headless only.
    with pytest.warns(UserWarning, match="HumanRendering"):
        human = gym.make("envc/PointMaze_UMaze-v3", render_mode="human")
    assert isinstance(human, gym.wrappers.HumanRendering)
    with pytest.raises(ValueError, match="headless"):
        envc.EnvcMazeEnv("PointMaze_UMaze-v3", render_mode="human")
    env = gym.make("envc/PointMaze_UMaze-v3")
    with pytest.raises(gym.error.ResetNeeded):
        env.step(np.zeros(2))


def test_without_gymnasium_robotics():
    """Without Gymnasium-Robotics the maze class is a plain ``gymnasium.Env`` with the same API."""
    code = (
        "import sys; sys.modules['gymnasium_robotics'] = None\n"
        "import gymnasium as gym, numpy as np, envc\n"
        "env = gym.make('envc/PointMaze_UMaze-v3')\n"
        "assert type(env.unwrapped).__bases__[-1] is gym.Env\n"
        "o, _ = env.reset(seed=1)\n"
        "o, r, *_ = env.step(np.ones(2))\n"
        "assert env.unwrapped.compute_reward(o['achieved_goal'], o['desired_goal'], {}) == r\n"
        "print('ok')\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, env=os.environ
    )
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr


def test_spec_file():
    """A maze spec file opens like its bundled id (here the file PointMaze_UMaze-v3 comes from)."""
    env = EnvcMazeEnv(os.path.join(REPO, "specs", "robotics", "maze", "point_maze.toml"))
    ref = gym.make("PointMaze_UMaze-v3").unwrapped
    o1, i1 = ref.reset(seed=LIVE_SEED)
    o2, i2 = env.reset(seed=LIVE_SEED)
    assert_same_obs(o1, o2, "spec file reset")
    rng = np.random.default_rng(LIVE_SEED)
    for t in range(50):
        a = rng.uniform(-1, 1, 2)
        s1, s2 = ref.step(a), env.step(a)
        assert_same_obs(s1[0], s2[0], f"spec file step {t}")
        assert s1[1:4] == s2[1:4]
        assert_same_info(s1[4], s2[4], f"spec file step {t}")
