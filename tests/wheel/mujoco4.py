"""The installed wheel beside MuJoCo 4.0.1 (tests/wheel/mujoco4.sh): MuJoCo is still the version
installed before envc, envc loads its build for it, and the envs whose trajectories differ between
MuJoCo 3.17.0 and 4.0.1 (docs/mujoco-versions.md) match Gymnasium on 4.0.1 bit for bit under a
fresh seed."""

from __future__ import annotations

import gymnasium as gym
import mujoco
import numpy as np

import envc

SEED = int(np.random.default_rng().integers(2**31))
print(f"mujoco4: seed {SEED}")
assert mujoco.__version__ == "4.0.1", f"installing envc changed MuJoCo to {mujoco.__version__}"
assert envc.__mujoco_version__ == "4.0.1", envc.__mujoco_version__

for env_id in ("Ant-v5", "HalfCheetah-v5", "Hopper-v5", "Humanoid-v5", "HumanoidStandup-v5",
               "Walker2d-v5", "Swimmer-v5", "Pusher-v5"):
    ref, ours = gym.make(env_id), gym.make(f"envc/{env_id}")
    rng = np.random.default_rng(SEED)
    o_ref, _ = ref.reset(seed=SEED)
    o_ours, _ = ours.reset(seed=SEED)
    assert o_ref.tobytes() == o_ours.tobytes(), f"{env_id}: reset differs"
    for t in range(200):
        a = rng.uniform(-1, 1, ref.action_space.shape).astype(ref.action_space.dtype)
        r_ref, r_ours = ref.step(a), ours.step(a)
        assert r_ref[0].tobytes() == r_ours[0].tobytes(), f"{env_id}: observation differs at step {t}"
        assert r_ref[1:4] == r_ours[1:4], f"{env_id}: reward or flags differ at step {t}"
        if r_ref[2] or r_ref[3]:
            o_ref, _ = ref.reset(seed=SEED + t)
            o_ours, _ = ours.reset(seed=SEED + t)
            assert o_ref.tobytes() == o_ours.tobytes(), f"{env_id}: reset after step {t} differs"
    print(f"mujoco4: {env_id} bit-identical over 200 steps")

# Rendering: the frames Gymnasium's renderer draws on 4.0.1 (MUJOCO_GL=egl).
for env_id in ("Hopper-v5", "Ant-v5"):
    ref = gym.make(env_id, render_mode="rgb_array", width=160, height=120)
    ours = gym.make(f"envc/{env_id}", render_mode="rgb_array", width=160, height=120)
    ref.reset(seed=SEED)
    ours.reset(seed=SEED)
    rng = np.random.default_rng(SEED)
    for t in range(5):
        a = rng.uniform(-1, 1, ref.action_space.shape).astype(ref.action_space.dtype)
        ref.step(a)
        ours.step(a)
        assert np.array_equal(ref.render(), ours.render()), f"{env_id}: frame {t} differs"
    print(f"mujoco4: {env_id} frames identical")
