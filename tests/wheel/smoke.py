"""The installed wheel, away from the checkout (tests/wheel/run.sh runs this in a fresh venv
with the checkout hidden under an empty tmpfs): every kind through ``gymnasium.make`` against the
live reference, bit for bit; PettingZoo; vector envs, rendering, datasets, Ray, ``envc.register``
and ``check_env``. Usage: ``python smoke.py VERSION WORKDIR``."""

from __future__ import annotations

import os
import sys
import tempfile

import gymnasium as gym
import numpy as np

VERSION, WORK = sys.argv[1], sys.argv[2]
SEED = int(np.random.default_rng().integers(2**31))
print(f"smoke: seed {SEED}")

import envc  # noqa: E402
from envc import _envc  # noqa: E402

checks = 0


def check(what: str, ok: bool, detail: str = "") -> None:
    global checks
    if not ok:
        raise SystemExit(f"smoke: FAILED {what} {detail}")
    checks += 1


site = os.path.dirname(os.path.dirname(os.path.abspath(envc.__file__)))
check("version", envc.__version__ == VERSION, f"{envc.__version__} != {VERSION}")
root, origin = _envc.bundle_root()
check("bundle from the package", root is not None and root.startswith(site), f"{root} ({origin})")
check("MuJoCo version", envc.__mujoco_version__ == "3.17.0", envc.__mujoco_version__)


def same(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


def same_info(got: dict, want: dict) -> bool:
    """Same keys and values (a float32 control cost of float32 actions is the same number as
    envc's float64 one; the suite's own tests pin that)."""
    def eq(a, b) -> bool:
        a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
        return a.shape == b.shape and a.tobytes() == b.tobytes()

    return set(got) == set(want) and all(eq(got[k], want[k]) for k in want if not isinstance(want[k], dict))


def rollout_pair(ours, ref, steps: int, seed: int, label: str) -> None:
    """Both envs, the same seed and actions: every observation, reward, flag and info identical."""
    rng = np.random.default_rng(seed)
    (o1, i1), (o2, i2) = ours.reset(seed=seed), ref.reset(seed=seed)
    for t in range(steps):
        if isinstance(o2, dict):
            check(f"{label} obs t={t}", all(same(o1[k], o2[k]) for k in o2))
        else:
            check(f"{label} obs t={t}", same(o1, o2))
        check(f"{label} info t={t}", same_info(i1, i2), f"{sorted(i1)} vs {sorted(i2)}")
        space = ref.action_space
        a = rng.uniform(space.low, space.high).astype(space.dtype)
        o1, r1, te1, tr1, i1 = ours.step(a)
        o2, r2, te2, tr2, i2 = ref.step(a)
        check(f"{label} reward t={t}", float(r1) == float(r2), f"{r1!r} vs {r2!r}")
        check(f"{label} flags t={t}", (te1, tr1) == (te2, tr2))
        if te2 or tr2:
            (o1, i1), (o2, i2) = ours.reset(), ref.reset()


# Every kind through gymnasium.make: tasks (v5, v4), a maze of each robot, against the reference.
for env_id in ["Hopper-v5", "Ant-v5", "Humanoid-v5", "Pusher-v5", "Walker2d-v4"]:
    rollout_pair(gym.make(f"envc/{env_id}"), gym.make(env_id), 25, SEED, env_id)
import gymnasium_robotics  # noqa: E402

gym.register_envs(gymnasium_robotics)
for env_id in ["PointMaze_UMaze-v3", "AntMaze_UMaze-v5"]:
    rollout_pair(gym.make(f"envc/{env_id}"), gym.make(env_id), 25, SEED, env_id)
check("every bundled task and maze is registered", all(
    f"envc/{i}" in gym.registry for i in envc.bundled_ids("task") + envc.bundled_ids("maze")
))
check("bundled ids", len(envc.bundled_ids()) >= 60, str(len(envc.bundled_ids())))

# MaMuJoCo through PettingZoo.
from gymnasium_robotics import mamujoco_v1  # noqa: E402

ours, ref = envc.parallel_env("HalfCheetah", "2x3"), mamujoco_v1.parallel_env("HalfCheetah", "2x3")
(g, _), (w, _) = ours.reset(seed=SEED), ref.reset(seed=SEED)
rng = np.random.default_rng(SEED)
for t in range(20):
    check(f"MaMuJoCo obs t={t}", all(same(g[a], w[a]) for a in ref.possible_agents))
    acts = {a: rng.uniform(-1, 1, ref.action_space(a).shape) for a in ref.possible_agents}
    g, rg, *_ = ours.step(acts)
    w, rw, *_ = ref.step(acts)
    check(f"MaMuJoCo reward t={t}", {a: float(v) for a, v in rg.items()} == {a: float(v) for a, v in rw.items()})

# check_env, vector envs, rendering.
from gymnasium.utils.env_checker import check_env  # noqa: E402

check_env(gym.make("envc/Hopper-v5").unwrapped, skip_render_check=True)
check("check_env", True)
vec = envc.make_vec("Hopper-v5", 3)
obs, _ = vec.reset(seed=SEED)
ref = gym.make("Hopper-v5")
check("make_vec reset", same(obs[1], ref.reset(seed=SEED + 1)[0]))
a = np.zeros((3, 3))
o, *_ = vec.step(a)
check("make_vec step", same(o[1], ref.step(a[1])[0]))
frame = gym.make("envc/Hopper-v5", render_mode="rgb_array", width=64, height=48)
frame.reset(seed=0)
img = frame.render()
check("render", img.shape == (48, 64, 3) and img.dtype == np.uint8 and int(img.max()) > 0)

# Datasets: an HDF5 one (HDF5 is linked into the wheel) loaded by Minari; Ray.
import minari  # noqa: E402

droot = os.path.join(WORK, "datasets")
path = envc.collect("Hopper-v5", "smoke/hopper-v0", 2, seed=SEED, format="hdf5", root=droot)
os.environ["MINARI_DATASETS_PATH"] = droot
ds = minari.load_dataset("smoke/hopper-v0")
check("HDF5 dataset", ds.total_episodes == 2 and os.path.isdir(path))
import envc.ray  # noqa: E402

envc.ray.collect("Hopper-v5", "smoke/ray-v0", 2, "random", seed=SEED, num_workers=1, root=droot)
check("envc.ray", minari.load_dataset("smoke/ray-v0").total_episodes == 2)

# A user's own spec directory, registered by path: opens by id through gymnasium.make.
user = tempfile.mkdtemp(dir=WORK)
with open(os.path.join(root, "specs", "gymnasium", "hopper.toml")) as f:
    text = f.read()
text = text.replace('id = "Hopper-v5"', 'id = "MyHopper-v0"').replace(
    "../../assets/gymnasium/hopper.xml", os.path.join(root, "assets", "gymnasium", "hopper.xml")
)
with open(os.path.join(user, "my_hopper.toml"), "w") as f:
    f.write(text)
check("register", envc.register(user) == ["MyHopper-v0"])
rollout_pair(gym.make("envc/MyHopper-v0"), gym.make("Hopper-v5"), 10, SEED, "MyHopper-v0")
try:
    envc.register(os.path.join(root, "specs", "gymnasium", "hopper_v4.toml"))  # the bundled file itself: no-op
    bad = os.path.join(user, "taken.toml")
    with open(bad, "w") as f:
        f.write(text.replace('id = "MyHopper-v0"', 'id = "Hopper-v5"'))
    envc.register(bad)
    check("a bundled id is not taken over", False)
except envc.SpecError as e:
    check("a bundled id is not taken over", "E0603" in str(e), str(e))
print(f"smoke: {checks} checks passed")
