"""Frames of envc against Gymnasium's MujocoRenderer (MUJOCO_GL=egl), after the same seed and
actions: every v5 env, every render mode, pixel for pixel (docs/rendering.md)."""

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import envc  # noqa: E402

V5 = [
    "Ant-v5",
    "HalfCheetah-v5",
    "Hopper-v5",
    "Humanoid-v5",
    "HumanoidStandup-v5",
    "InvertedDoublePendulum-v5",
    "InvertedPendulum-v5",
    "Pusher-v5",
    "Reacher-v5",
    "Swimmer-v5",
    "Walker2d-v5",
]
STEPS = 12


def frames(env, seed, actions, every=4):
    out = []
    env.reset(seed=seed)
    out.append(env.render())
    for i, a in enumerate(actions):
        _, _, term, trunc, _ = env.step(a)
        if i % every == every - 1:
            out.append(env.render())
        if term or trunc:
            env.reset(seed=seed + 1)
    return out


def compare(ours, theirs):
    """(share of differing pixels, largest channel difference) over all frames."""
    share, worst = 0.0, 0.0
    for a, b in zip(ours, theirs, strict=True):
        assert a.shape == b.shape and a.dtype == b.dtype
        d = np.abs(a.astype(np.float64) - b.astype(np.float64))
        px = d.reshape(a.shape[0], a.shape[1], -1).max(axis=-1)
        share = max(share, float((px != 0).mean()))
        worst = max(worst, float(d.max()))
    return share, worst


def actions_for(env_id, seed, n=STEPS):
    space = gym.make(env_id).action_space
    space.seed(seed)
    return [space.sample() for _ in range(n)]


@pytest.mark.parametrize("env_id", V5)
def test_rgb_frames_match_gymnasium(env_id):
    seed = 7
    acts = actions_for(env_id, seed)
    ours = frames(envc.make(env_id, render_mode="rgb_array"), seed, acts)
    ref = gym.make(env_id, render_mode="rgb_array")
    theirs = frames(ref, seed, acts)
    ref.close()
    assert ours[0].shape == (480, 480, 3)
    assert ours[0].std() > 1.0, "a blank frame"
    share, worst = compare(ours, theirs)
    assert (share, worst) == (0.0, 0.0), f"{env_id}: {share:.2%} pixels differ, up to {worst}"


@pytest.mark.parametrize("env_id", ["Hopper-v5", "Ant-v5"])
def test_depth_and_rgbd_match_gymnasium(env_id):
    acts = actions_for(env_id, 3, 4)
    for mode in ("depth_array", "rgbd_tuple"):
        ours = frames(envc.make(env_id, render_mode=mode), 3, acts, every=2)
        ref = gym.make(env_id, render_mode=mode)
        theirs = frames(ref, 3, acts, every=2)
        ref.close()
        if mode == "rgbd_tuple":
            assert isinstance(ours[0], tuple) and ours[0][1].dtype == np.float32
            ours = [x for pair in ours for x in pair]
            theirs = [x for pair in theirs for x in pair]
        else:
            assert ours[0].shape == (480, 480) and ours[0].dtype == np.float32
        assert compare(ours, theirs) == (0.0, 0.0), f"{env_id} {mode}"


@pytest.mark.parametrize(
    "kwargs",
    [
        {"width": 160, "height": 96},
        {"camera_name": "track"},
        {"camera_id": 0, "width": 64, "height": 64},
        {"default_camera_config": {"distance": 2.5, "azimuth": 30.0, "elevation": -10.0}},
        {"visual_options": {14: True, 16: True}, "max_geom": 2000},
    ],
)
def test_render_parameters_match_gymnasium(kwargs):
    acts = actions_for("Ant-v5", 1, 4)
    ours = frames(envc.make("Ant-v5", render_mode="rgb_array", **kwargs), 1, acts, every=2)
    ref = gym.make("Ant-v5", render_mode="rgb_array", **kwargs)
    theirs = frames(ref, 1, acts, every=2)
    ref.close()
    assert ours[0].shape == (kwargs.get("height", 480), kwargs.get("width", 480), 3)
    assert compare(ours, theirs) == (0.0, 0.0), f"{kwargs}"


def test_unknown_camera_is_a_spec_error():
    with pytest.raises(envc.SpecError) as e:
        envc.make("Ant-v5", render_mode="rgb_array", camera_name="trak")
    assert e.value.code == "E1503"
    assert "did you mean `track`" in str(e.value)
    # gymnasium.make turns "human" into HumanRendering over rgb_array; the env itself refuses it.
    with pytest.raises(ValueError, match="human"):
        envc.EnvcEnv("Ant-v5", render_mode="human")


def test_human_rendering_shows_gymnasiums_frame(monkeypatch):
    """`render_mode="human"` through gymnasium.make is HumanRendering over envc's rgb_array; its
    (headless, SDL's dummy driver) pygame window holds exactly the frame Gymnasium renders."""
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    pygame = pytest.importorskip("pygame")
    with pytest.warns(UserWarning, match="HumanRendering"):
        env = gym.make("envc/Hopper-v5", render_mode="human", width=64, height=48)
    assert isinstance(env, gym.wrappers.HumanRendering)
    ref = gym.make("Hopper-v5", render_mode="rgb_array", width=64, height=48)
    for e in (env, ref):
        e.reset(seed=3)
        for _ in range(5):
            e.step(np.full(3, 0.3))
    shown = pygame.surfarray.array3d(pygame.display.get_surface()).transpose(1, 0, 2)
    assert shown.shape == (48, 64, 3)
    assert np.array_equal(shown, ref.render())
    env.close()
    ref.close()


def test_record_video_writes_a_playable_file(tmp_path):
    from gymnasium.wrappers import RecordVideo

    env = RecordVideo(
        envc.make("Hopper-v5", render_mode="rgb_array", width=128, height=128),
        str(tmp_path),
        episode_trigger=lambda i: True,
        disable_logger=True,
    )
    env.reset(seed=0)
    for _ in range(20):
        env.step(env.action_space.sample())
    env.close()
    videos = list(tmp_path.glob("*.mp4"))
    assert len(videos) == 1 and videos[0].stat().st_size > 1000


@pytest.mark.parametrize("env_id", ["AntMaze_UMaze-v5", "PointMaze_UMaze-v3", "PointMaze_Large-v3"])
def test_maze_frames_match_gymnasium_robotics(env_id):
    """The maze world, its walls and the goal marker (the `target` site) where the reference draws it."""
    import gymnasium_robotics

    gym.register_envs(gymnasium_robotics)
    ref = gym.make(env_id, render_mode="rgb_array")
    acts = actions_for(env_id, 5, 8)
    ours = frames(envc.make(env_id, render_mode="rgb_array"), 5, acts)
    theirs = frames(ref, 5, acts)
    ref.close()
    assert compare(ours, theirs) == (0.0, 0.0), env_id


@pytest.mark.parametrize(
    "env_id",
    [
        "FrankaKitchen-v1",
        "AdroitHandDoor-v1",
        "AdroitHandHammer-v1",
        "AdroitHandPen-v1",
        "AdroitHandRelocate-v1",
    ],
)
def test_robotics_frames_match_gymnasium_robotics(env_id):
    """Textured scenes from each reference's camera (its `DEFAULT_CAMERA_CONFIG`, the spec's
    `default_camera_config`), the robot moving under the same actions."""
    import sys

    import gymnasium_robotics

    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "reference"))
    import robotics_patch  # noqa: F401

    gym.register_envs(gymnasium_robotics)
    ref = gym.make(env_id, render_mode="rgb_array")
    acts = actions_for(env_id, 3, 8)
    ours = frames(envc.make(env_id, render_mode="rgb_array"), 3, acts)
    theirs = frames(ref, 3, acts)
    ref.close()
    assert compare(ours, theirs) == (0.0, 0.0), env_id


@pytest.mark.parametrize(
    "env_id", ["FetchReach-v4", "FetchPush-v4", "FetchSlide-v4", "FetchPickAndPlace-v4"]
)
def test_fetch_renders_its_target_and_stays_on_the_reference_while_rendering(env_id):
    """Fetch's render callback (`[goal] marker_site`): the target site drawn at the goal and an
    `mj_forward` before every frame. Frames equal the reference's, and rendering every step
    leaves the observations bit-identical to the reference rendering alike."""
    import sys

    import gymnasium_robotics

    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "reference"))
    import robotics_patch  # noqa: F401

    gym.register_envs(gymnasium_robotics)
    ref = gym.make(env_id, render_mode="rgb_array")
    ours = envc.make(env_id, render_mode="rgb_array")
    rng = np.random.default_rng(4)
    o, _ = ours.reset(seed=4)
    r, _ = ref.reset(seed=4)
    for t in range(60):
        assert compare([ours.render()], [ref.render()]) == (0.0, 0.0), (env_id, t)
        a = rng.uniform(-1, 1, 4)
        o, _, _, trunc, _ = ours.step(a)
        r, _, _, rtrunc, _ = ref.step(a)
        for k in r:
            assert np.array_equal(o[k].view(np.uint64), r[k].view(np.uint64)), (env_id, t, k)
        assert trunc == rtrunc
        if trunc:
            ours.reset()
            ref.reset()
    ref.close()


def test_mamujoco_renders_the_whole_robot_as_the_reference():
    from gymnasium_robotics import mamujoco_v1

    ref = mamujoco_v1.parallel_env("Ant", "2x4", render_mode="rgb_array")
    ours = envc.parallel_env("Ant", "2x4", render_mode="rgb_array")
    ref.reset(seed=2)
    ours.reset(seed=2)
    rng = np.random.default_rng(0)
    got, want = [ours.render()], [ref.render()]
    for _ in range(4):
        acts = {a: rng.uniform(-1, 1, ref.action_space(a).shape).astype(np.float32) for a in ref.agents}
        ref.step(acts)
        ours.step(acts)
        got.append(ours.render())
        want.append(ref.render())
    ref.close()
    assert got[0].shape == (480, 480, 3)
    assert compare(got, want) == (0.0, 0.0)


def test_vector_envs_render_every_env_as_gymnasiums():
    """envc's threaded vector env renders each env as Gymnasium's SyncVectorEnv does."""
    ours = envc.make_vec("Hopper-v5", 3, num_threads=2, render_mode="rgb_array", width=64, height=64)
    ref = gym.make_vec(
        "Hopper-v5", 3, vectorization_mode="sync", render_mode="rgb_array", width=64, height=64
    )
    ours.reset(seed=4)
    ref.reset(seed=4)
    acts = np.tile(np.array([0.3, -0.2, 0.1], dtype=np.float32), (3, 1))
    got, want = list(ours.render()), list(ref.render())
    for _ in range(3):
        ours.step(acts)
        ref.step(acts)
        got += list(ours.render())
        want += list(ref.render())
    ref.close()
    ours.close()
    assert len(got) == 12 and got[0].shape == (64, 64, 3)
    assert compare(got, want) == (0.0, 0.0)


@pytest.mark.parametrize(
    "env_id,seed,reset_cell",
    # PointMaze starts in the cell next to the goal and is driven onto it; the ant (hard to steer
    # by script) starts in the goal's cell, with a seed whose noise puts it within reach.
    [("PointMaze_UMaze-v3", 3, [1, 2]), ("AntMaze_UMaze-v5", 84, [1, 1])],
)
def test_maze_goal_marker_follows_a_resampled_goal_as_the_reference(env_id, seed, reset_cell):
    """A continuing maze with reset_target: the goal is reached and resampled mid-episode. The
    reference writes the marker's `site_pos` after that step, so the marker moves at the next
    physics step's kinematics; every frame through the resample matches."""
    import gymnasium_robotics

    gym.register_envs(gymnasium_robotics)
    kw = dict(continuing_task=True, reset_target=True, render_mode="rgb_array", width=96, height=96)
    ref = gym.make(env_id, **kw)
    ours = envc.make(env_id, **kw)
    opts = {"goal_cell": np.array([1, 1]), "reset_cell": np.array(reset_cell)}
    obs, _ = ref.reset(seed=seed, options=opts)
    ours.reset(seed=seed, options=opts)
    got, want = [ours.render()], [ref.render()]
    first_goal, resampled_at = obs["desired_goal"].copy(), None
    for t in range(300):
        act = np.zeros(ref.action_space.shape, dtype=np.float32)
        if env_id.startswith("Point"):  # a PD law on x, y towards the goal
            err = obs["desired_goal"] - obs["achieved_goal"]
            act = np.clip(2.0 * err - 0.3 * obs["observation"][2:4], -1, 1).astype(np.float32)
        obs, _, _, _, _ = ref.step(act)
        mine, _, _, _, _ = ours.step(act)
        assert np.array_equal(mine["desired_goal"], obs["desired_goal"]), t
        got.append(ours.render())
        want.append(ref.render())
        if resampled_at is None and not np.array_equal(obs["desired_goal"], first_goal):
            resampled_at = t
        if resampled_at is not None and t >= resampled_at + 2:
            break
    ref.close()
    assert resampled_at is not None, "the goal was never reached"
    assert compare(got, want) == (0.0, 0.0)


def test_no_gl_is_a_clear_error_naming_the_packages():
    """Without libEGL (ENVC_EGL_LIBRARY names a missing one, set before envc loads it) making and
    stepping work; the first frame raises RuntimeError with E1501 and the Debian packages."""
    import subprocess
    import sys

    code = """
import envc, numpy as np
env = envc.make("Hopper-v5", render_mode="rgb_array")
env.reset(seed=0)
env.step(np.zeros(3, dtype=np.float32))
try:
    env.render()
except Exception as e:
    print(isinstance(e, RuntimeError) and e.code)
    print(e)
else:
    print("no error")
"""
    env = dict(os.environ, ENVC_EGL_LIBRARY="/nonexistent/libEGL.so.1")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    kind, message = out.stdout.split("\n", 1)
    assert kind == "E1501", out.stdout  # a RuntimeError with its code
    assert "E1501" in message and "/nonexistent/libEGL.so.1" in message, message
    assert "libegl1 libegl-mesa0 libgl1-mesa-dri libgl1" in message, message
