#!/usr/bin/env python3
"""Record golden trajectories of Gymnasium 1.4.0's MuJoCo v5 and v4 environments (the Python reference).

Usage (run with the project venv, from any directory):

    .venv/bin/python tests/reference/record.py                      # re-record the committed fixtures
    .venv/bin/python tests/reference/record.py --out DIR --seed N --quick   # fresh-seed live cross-check
    .venv/bin/python tests/reference/record.py --verify-golden      # only check the GOLDEN table below

The case table (CASES) is right below; the fixture format and the protocol are documented in
tests/reference/README.md (which is the contract with the Rust parity test).
"""

# ------------------------------------------------------------------------------------------------
# The cases.  One row per recorded trajectory:
#   name        file stem and manifest name
#   env_id      Gymnasium id
#   seeds       (first reset seed, action/protocol RNG seed); replaced by seeds derived from --seed N
#   steps       total env steps T (episodes restart inside; --quick uses QUICK_STEPS instead)
#   max_steps   max_episode_steps override for gym.make, or None for the registered default
#   kwargs      constructor keyword arguments (exact reference names), passed via gym.make
#   note        free text, copied into the manifest
# ------------------------------------------------------------------------------------------------
INF = float("inf")
DEF, ND = 300, 150  # steps of a default-parameter case / of a non-default case
QUICK_STEPS = 100

CASES = [
    # --- Ant-v5 ---
    ("ant_default_seed0", "Ant-v5", (0, 1000), DEF, None, {}, "defaults"),
    ("ant_default_seed1", "Ant-v5", (1, 1001), DEF, None, {}, "defaults"),
    ("ant_obs_flags", "Ant-v5", (2, 1002), ND, 50,
     dict(exclude_current_positions_from_observation=False, include_cfrc_ext_in_observation=False,
          ctrl_cost_weight=0.3, reset_noise_scale=0.2),
     "obs 29 (x,y kept, no cfrc_ext); truncation every 50 steps"),
    ("ant_contact_health", "Ant-v5", (3, 1003), ND, 60,
     dict(forward_reward_weight=2.0, contact_cost_weight=1e-3, healthy_reward=0.5, main_body="torso",
          healthy_z_range=(0.3, 0.9), contact_force_range=(-0.5, 0.5)),
     "clipped cfrc_ext range, tighter healthy z, main_body by name"),
    ("ant_unhealthy_continue", "Ant-v5", (4, 1004), ND, 60,
     dict(terminate_when_unhealthy=False, healthy_z_range=(0.55, 0.7), main_body=2,
          reset_noise_scale=0.05),
     "runs unhealthy (reward_survive 0) without terminating; velocity from body 2 (front_left_leg)"),
    # --- HalfCheetah-v5 ---
    ("halfcheetah_default_seed0", "HalfCheetah-v5", (0, 1010), DEF, None, {}, "defaults"),
    ("halfcheetah_default_seed2", "HalfCheetah-v5", (2, 1011), DEF, None, {}, "defaults"),
    ("halfcheetah_weights_fs3", "HalfCheetah-v5", (5, 1012), ND, 50,
     dict(frame_skip=3, forward_reward_weight=2.0, ctrl_cost_weight=0.05, reset_noise_scale=0.2,
          exclude_current_positions_from_observation=False),
     "frame_skip 3 (dt 0.03), obs 18"),
    # --- Hopper-v5 ---
    ("hopper_default_seed0", "Hopper-v5", (0, 1020), DEF, None, {}, "defaults; many terminations"),
    ("hopper_default_seed3", "Hopper-v5", (3, 1021), DEF, None, {}, "defaults; many terminations"),
    ("hopper_ranges", "Hopper-v5", (6, 1022), ND, 50,
     dict(forward_reward_weight=0.5, ctrl_cost_weight=0.01, healthy_reward=2.0,
          healthy_state_range=(-50.0, 50.0), healthy_z_range=(0.5, INF), healthy_angle_range=(-0.5, 0.5)),
     "wider health ranges"),
    ("hopper_unhealthy_continue", "Hopper-v5", (7, 1023), ND, 60,
     dict(terminate_when_unhealthy=False, reset_noise_scale=0.05,
          exclude_current_positions_from_observation=False),
     "falls and keeps running unhealthy until truncation; obs 12"),
    # --- Humanoid-v5 ---
    ("humanoid_default_seed0", "Humanoid-v5", (0, 1030), DEF, None, {}, "defaults; many terminations"),
    ("humanoid_default_seed4", "Humanoid-v5", (4, 1031), DEF, None, {}, "defaults; many terminations"),
    ("humanoid_no_cinert_cvel", "Humanoid-v5", (8, 1032), ND, 50,
     dict(include_cinert_in_observation=False, include_cvel_in_observation=False,
          exclude_current_positions_from_observation=False, contact_cost_weight=5e-5,
          contact_cost_range=(-INF, 0.5), forward_reward_weight=1.0, healthy_z_range=(0.9, 2.1)),
     "obs 142; contact cost clipped at 0.5"),
    ("humanoid_no_qfrc_cfrc_unhealthy", "Humanoid-v5", (9, 1033), ND, 60,
     dict(include_qfrc_actuator_in_observation=False, include_cfrc_ext_in_observation=False,
          terminate_when_unhealthy=False, ctrl_cost_weight=0.2, healthy_reward=3.0,
          reset_noise_scale=0.05, contact_cost_range=(0.5, 10.0)),
     "obs 253; falls and runs unhealthy until truncation; contact cost floor 0.5"),
    # --- HumanoidStandup-v5 ---
    ("humanoidstandup_default_seed0", "HumanoidStandup-v5", (0, 1040), DEF, None, {}, "defaults"),
    ("humanoidstandup_default_seed5", "HumanoidStandup-v5", (5, 1041), DEF, None, {}, "defaults"),
    ("humanoidstandup_nondefault", "HumanoidStandup-v5", (10, 1042), ND, 50,
     dict(uph_cost_weight=2.0, ctrl_cost_weight=0.05, impact_cost_weight=1e-5,
          impact_cost_range=(-INF, 0.5), reset_noise_scale=0.05,
          exclude_current_positions_from_observation=False, include_cinert_in_observation=False,
          include_qfrc_actuator_in_observation=False),
     "obs 203; uph_cost_weight is ignored by the reference; impact cost clipped at 0.5"),
    # --- InvertedPendulum-v5 ---
    ("invertedpendulum_default_seed0", "InvertedPendulum-v5", (0, 1050), DEF, None, {},
     "defaults; episodes of a few steps"),
    ("invertedpendulum_default_seed6", "InvertedPendulum-v5", (6, 1051), DEF, None, {},
     "defaults; episodes of a few steps"),
    ("invertedpendulum_noise", "InvertedPendulum-v5", (11, 1052), ND, 40,
     dict(reset_noise_scale=0.1), "larger reset noise (some resets start terminal-ish)"),
    ("invertedpendulum_truncate", "InvertedPendulum-v5", (12, 1053), ND, 3,
     dict(reset_noise_scale=0.001, frame_skip=1),
     "frame_skip 1 and max_episode_steps 3: truncations (sometimes together with termination)"),
    # --- InvertedDoublePendulum-v5 ---
    ("inverteddoublependulum_default_seed0", "InvertedDoublePendulum-v5", (0, 1060), DEF, None, {},
     "defaults; episodes of a few steps"),
    ("inverteddoublependulum_default_seed7", "InvertedDoublePendulum-v5", (7, 1061), DEF, None, {},
     "defaults; episodes of a few steps"),
    ("inverteddoublependulum_healthy_reward", "InvertedDoublePendulum-v5", (13, 1062), ND, 6,
     dict(healthy_reward=5.0, reset_noise_scale=0.02),
     "healthy_reward 5; max_episode_steps 6 so both truncations and terminations occur"),
    # --- Pusher-v5 ---
    ("pusher_default_seed0", "Pusher-v5", (0, 1070), DEF, None, {}, "defaults (100-step episodes)"),
    ("pusher_default_seed8", "Pusher-v5", (8, 1071), DEF, None, {}, "defaults (100-step episodes)"),
    ("pusher_weights", "Pusher-v5", (14, 1072), ND, 40,
     dict(reward_near_weight=1.0, reward_dist_weight=2, reward_control_weight=0.5, frame_skip=3),
     "all three weights, frame_skip 3"),
    # --- Reacher-v5 ---
    ("reacher_default_seed0", "Reacher-v5", (0, 1080), DEF, None, {}, "defaults (50-step episodes)"),
    ("reacher_default_seed9", "Reacher-v5", (9, 1081), DEF, None, {}, "defaults (50-step episodes)"),
    ("reacher_weights", "Reacher-v5", (15, 1082), ND, 40,
     dict(reward_dist_weight=0.5, reward_control_weight=0.1, frame_skip=3), "weights, frame_skip 3"),
    # --- Swimmer-v5 ---
    ("swimmer_default_seed0", "Swimmer-v5", (0, 1090), DEF, None, {}, "defaults"),
    ("swimmer_default_seed10", "Swimmer-v5", (10, 1091), DEF, None, {}, "defaults"),
    ("swimmer_nondefault", "Swimmer-v5", (16, 1092), ND, 50,
     dict(exclude_current_positions_from_observation=False, reset_noise_scale=0.3,
          forward_reward_weight=0.7, ctrl_cost_weight=1e-3),
     "obs 10, large reset noise"),
    # --- Walker2d-v5 ---
    ("walker2d_default_seed0", "Walker2d-v5", (0, 1100), DEF, None, {}, "defaults; many terminations"),
    ("walker2d_default_seed11", "Walker2d-v5", (11, 1101), DEF, None, {}, "defaults; many terminations"),
    ("walker2d_ranges", "Walker2d-v5", (17, 1102), ND, 50,
     dict(healthy_z_range=(0.5, 2.5), healthy_angle_range=(-1.5, 1.5), healthy_reward=2.0,
          forward_reward_weight=0.5, ctrl_cost_weight=0.01),
     "wider health ranges"),
    ("walker2d_unhealthy_continue", "Walker2d-v5", (18, 1103), ND, 60,
     dict(terminate_when_unhealthy=False, healthy_z_range=(1.0, 1.3), reset_noise_scale=0.05,
          exclude_current_positions_from_observation=False),
     "narrow healthy z: runs unhealthy without terminating; obs 18"),
    # ============================ v4 (specs/gymnasium/*_v4.toml) ============================
    # Pusher-v4 is absent: Gymnasium 1.4.0 refuses to build it on MuJoCo >= 3.
    # --- Ant-v4 ---
    ("ant_v4_default_seed0", "Ant-v4", (20, 1200), DEF, None, {}, "defaults (no contact forces)"),
    ("ant_v4_default_seed1", "Ant-v4", (21, 1201), DEF, None, {}, "defaults (no contact forces)"),
    ("ant_v4_contact_forces", "Ant-v4", (22, 1202), ND, 50,
     dict(use_contact_forces=True, contact_cost_weight=1e-3, contact_force_range=(-0.5, 0.5),
          ctrl_cost_weight=0.3, exclude_current_positions_from_observation=False),
     "obs 113 (cfrc_ext of all 14 bodies); contact cost in the reward and in info reward_ctrl"),
    ("ant_v4_unhealthy_continue", "Ant-v4", (23, 1203), ND, 60,
     dict(terminate_when_unhealthy=False, healthy_z_range=(0.55, 0.7), healthy_reward=0.5,
          reset_noise_scale=0.05),
     "runs unhealthy (reward_survive 0) without terminating"),
    # --- HalfCheetah-v4 ---
    ("halfcheetah_v4_default_seed0", "HalfCheetah-v4", (24, 1210), DEF, None, {}, "defaults"),
    ("halfcheetah_v4_default_seed1", "HalfCheetah-v4", (25, 1211), DEF, None, {}, "defaults"),
    ("halfcheetah_v4_nondefault", "HalfCheetah-v4", (26, 1212), ND, 50,
     dict(forward_reward_weight=2.0, ctrl_cost_weight=0.05, reset_noise_scale=0.2,
          exclude_current_positions_from_observation=False),
     "obs 18, weights"),
    # --- Hopper-v4 ---
    ("hopper_v4_default_seed0", "Hopper-v4", (27, 1220), DEF, None, {}, "defaults; many terminations"),
    ("hopper_v4_default_seed1", "Hopper-v4", (28, 1221), DEF, None, {}, "defaults; many terminations"),
    ("hopper_v4_unhealthy_continue", "Hopper-v4", (29, 1222), ND, 60,
     dict(terminate_when_unhealthy=False, healthy_reward=2.0, reset_noise_scale=0.05,
          healthy_angle_range=(-0.5, 0.5), exclude_current_positions_from_observation=False),
     "falls and keeps running unhealthy (reward_survive 0) until truncation; obs 12"),
    # --- Humanoid-v4 ---
    ("humanoid_v4_default_seed0", "Humanoid-v4", (30, 1230), DEF, None, {}, "defaults; many terminations"),
    ("humanoid_v4_default_seed1", "Humanoid-v4", (31, 1231), DEF, None, {}, "defaults; many terminations"),
    ("humanoid_v4_unhealthy_continue", "Humanoid-v4", (32, 1232), ND, 60,
     dict(terminate_when_unhealthy=False, ctrl_cost_weight=0.2, healthy_reward=3.0,
          forward_reward_weight=1.0, reset_noise_scale=0.05,
          exclude_current_positions_from_observation=False),
     "obs 378; falls and runs unhealthy until truncation"),
    # --- HumanoidStandup-v4 (no constructor arguments) ---
    ("humanoidstandup_v4_default_seed0", "HumanoidStandup-v4", (33, 1240), DEF, None, {}, "defaults"),
    ("humanoidstandup_v4_default_seed1", "HumanoidStandup-v4", (34, 1241), DEF, None, {}, "defaults"),
    ("humanoidstandup_v4_truncate", "HumanoidStandup-v4", (35, 1242), ND, 50, {},
     "max_episode_steps 50 (v4 takes no reward or noise arguments)"),
    # --- InvertedPendulum-v4 (no constructor arguments) ---
    ("invertedpendulum_v4_default_seed0", "InvertedPendulum-v4", (36, 1250), DEF, None, {},
     "defaults; episodes of a few steps"),
    ("invertedpendulum_v4_default_seed1", "InvertedPendulum-v4", (37, 1251), DEF, None, {},
     "defaults; episodes of a few steps"),
    ("invertedpendulum_v4_truncate", "InvertedPendulum-v4", (38, 1252), ND, 3, {},
     "max_episode_steps 3: truncations (sometimes together with termination)"),
    # --- InvertedDoublePendulum-v4 (no constructor arguments) ---
    ("inverteddoublependulum_v4_default_seed0", "InvertedDoublePendulum-v4", (39, 1260), DEF, None, {},
     "defaults; episodes of a few steps"),
    ("inverteddoublependulum_v4_default_seed1", "InvertedDoublePendulum-v4", (40, 1261), DEF, None, {},
     "defaults; episodes of a few steps"),
    ("inverteddoublependulum_v4_truncate", "InvertedDoublePendulum-v4", (41, 1262), ND, 6, {},
     "max_episode_steps 6 so both truncations and terminations occur"),
    # --- Reacher-v4 (no constructor arguments) ---
    ("reacher_v4_default_seed0", "Reacher-v4", (42, 1270), DEF, None, {}, "defaults (50-step episodes)"),
    ("reacher_v4_default_seed1", "Reacher-v4", (43, 1271), DEF, None, {}, "defaults (50-step episodes)"),
    ("reacher_v4_truncate", "Reacher-v4", (44, 1272), ND, 40, {}, "max_episode_steps 40"),
    # --- Swimmer-v4 ---
    ("swimmer_v4_default_seed0", "Swimmer-v4", (45, 1280), DEF, None, {}, "defaults"),
    ("swimmer_v4_default_seed1", "Swimmer-v4", (46, 1281), DEF, None, {}, "defaults"),
    ("swimmer_v4_nondefault", "Swimmer-v4", (47, 1282), ND, 50,
     dict(exclude_current_positions_from_observation=False, reset_noise_scale=0.3,
          forward_reward_weight=0.7, ctrl_cost_weight=1e-3),
     "obs 10, large reset noise"),
    # --- Walker2d-v4 ---
    ("walker2d_v4_default_seed0", "Walker2d-v4", (48, 1290), DEF, None, {}, "defaults; many terminations"),
    ("walker2d_v4_default_seed1", "Walker2d-v4", (49, 1291), DEF, None, {}, "defaults; many terminations"),
    ("walker2d_v4_unhealthy_continue", "Walker2d-v4", (50, 1292), ND, 60,
     dict(terminate_when_unhealthy=False, healthy_z_range=(1.0, 1.3), healthy_reward=2.0,
          reset_noise_scale=0.05, exclude_current_positions_from_observation=False),
     "narrow healthy z: runs unhealthy without terminating; obs 18"),
]

# Protocol constants (see README): action range factor, probability of a "special" action.
ACTION_SCALE = 1.5
SPECIAL_PROB = 0.05

# Golden values, recorded from Gymnasium 1.4.0 on MuJoCo 3.17.0 by verify_golden()'s protocol and
# checked by `--verify-golden`; tests/golden.rs holds the same table: env -> (sha(obs0), obs0[0], reward at t=0, steps, sum of rewards,
# sha(last obs), terminated).  Protocol in verify_golden().
GOLDEN = {
    "Ant-v5": ("6d2a57d259c8e2f3", 0.658194704787239, -0.5333905414870339, 50, -44.73110757129683, "2e156614fb3cf0bf", False),
    "HalfCheetah-v5": ("3893de29648ab677", -0.04604265724722594, -0.5318076279428017, 50, -126.27466179588382, "df9290393c4bd624", False),
    "Hopper-v5": ("1615db91f7b6b239", 1.2476978671376386, 0.9367581717518246, 19, 17.31894978108758, "8e0d6c280f122bed", True),
    "Humanoid-v5": ("dc7485050d99c1bc", 1.3908194704787238, 4.862387432048007, 21, 98.05816604618224, "2dbb63226a2faded", True),
    "HumanoidStandup-v5": ("6c12e6770c9961f6", 0.09581947047872388, 34.29042761970081, 50, 1659.5917779894419, "23f116aff42fbeec", False),
    "InvertedPendulum-v5": ("3de12464dc6de755", 0.002739233746429086, 1, 3, 2.0, "c179c057b6a752a4", True),
    "InvertedDoublePendulum-v5": ("2e0c1497986bc784", 0.027392337464290872, 9.173176903084205, 4, 25.939897954833167, "255abcc72fc45f02", True),
    "Pusher-v5": ("a30963a131ed2732", 0.0, -2.190607158475637, 50, -106.2999013731421, "366e055642952e62", False),
    "Reacher-v5": ("481ca8999b42fe37", 0.9996248533822988, -1.4454819905766316, 50, -64.33549595828254, "cbfa2c0b195a1e0d", False),
    "Swimmer-v5": ("b8c8bad02202fb41", -0.09180529521276107, 0.030093296518804918, 50, 3.045338518969584, "deae885f913e30c3", False),
    "Walker2d-v5": ("7c7c18cf80e39d30", 1.2476978671376386, 0.859785999095982, 35, 6.316525015706321, "f425072e66c0de57", True),
}

# ------------------------------------------------------------------------------------------------

import argparse
import hashlib
import json
import math
import os
import re
import sys
import tempfile
import types

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
import numerics_profile  # noqa: E402  (next to this script)

DEFAULT_OUT = os.path.join(HERE, "fixtures")
REQUIREMENTS = os.path.join(HERE, "requirements.txt")


def install_render_shims():
    """gymnasium.envs.mujoco imports `imageio` and `packaging` at module level, but only its renderer
    uses them (imageio.imwrite for human-window screenshots; packaging.version.Version for two
    MuJoCo-version flags).  They are not in requirements.txt (gymnasium is installed without the
    [mujoco] extra), so provide minimal stand-ins when missing.  Physics, obs, rewards are unaffected."""
    shimmed = []
    try:
        import imageio  # noqa: F401
    except ImportError:
        m = types.ModuleType("imageio")

        def imwrite(*_a, **_k):
            raise RuntimeError("imageio is not installed (record.py shim)")

        m.imwrite = imwrite
        sys.modules["imageio"] = m
        shimmed.append("imageio")
    try:
        from packaging.version import Version  # noqa: F401
    except ImportError:
        pkg = types.ModuleType("packaging")
        ver = types.ModuleType("packaging.version")

        class Version:
            def __init__(self, s):
                self.t = tuple(int(re.match(r"\d+", p).group()) for p in s.split(".")[:3])

            def __lt__(self, o):
                return self.t < o.t

            def __ge__(self, o):
                return self.t >= o.t

        ver.Version = Version
        pkg.version = ver
        sys.modules["packaging"] = pkg
        sys.modules["packaging.version"] = ver
        shimmed.append("packaging")
    return shimmed


# The MuJoCo versions envc builds for (envc::MUJOCO_VERSION, feature `mujoco-4.0.1`).
SUPPORTED_MUJOCO = ("3.17.0", "4.0.1")


def pinned_versions():
    pins = {}
    with open(REQUIREMENTS) as f:
        for line in f:
            m = re.match(r"\s*([A-Za-z0-9_.-]+)==(\S+)", line)
            if m:
                pins[m.group(1).lower()] = m.group(2)
    return pins


def toml_literal(v):
    """A Python constructor argument as a TOML literal string (see README)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        r = repr(v)
        return r
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (tuple, list)):
        return "[" + ", ".join(toml_literal(x) for x in v) + "]"
    raise TypeError(f"no TOML literal for {v!r}")


def keys_blob(keys):
    import numpy as np

    for k in keys:
        assert "\n" not in k
    return np.frombuffer("\n".join(keys).encode("utf-8"), dtype=np.uint8).copy()


def sha16(obs):
    import numpy as np

    return hashlib.sha256(np.ascontiguousarray(obs, dtype="<f8").tobytes()).hexdigest()[:16]


# ------------------------------------------------------------------------------------------------
# Golden check (the GOLDEN table)


def verify_golden(gym, np):
    """Protocol: gym.make(env); obs0 = reset(seed=0); up to 50 steps (stop at terminated/truncated)
    with float32 action a_t[i] = float32(k) * high[i], k = ((t+i)%5-2)/2; left-to-right float64 sum."""
    failures = []
    for env_id, exp in GOLDEN.items():
        env = gym.make(env_id)
        obs0, _ = env.reset(seed=0)
        high = env.action_space.high
        n = high.shape[0]
        rewards, obs, term, steps = [], obs0, False, 0
        for t in range(50):
            k = np.array([((t + i) % 5 - 2) / 2 for i in range(n)], dtype=np.float32)
            a = k * high
            assert a.dtype == np.float32
            obs, r, term, trunc, _ = env.step(a)
            rewards.append(r)
            steps += 1
            if term or trunc:
                break
        env.close()
        total = 0.0
        for r in rewards:
            total += float(r)
        r0 = rewards[0] if type(rewards[0]) is int else float(rewards[0])  # IP: a Python int
        got = (sha16(obs0), float(obs0[0]), r0, steps, total, sha16(obs), bool(term))
        cols = ("sha(obs0)", "obs0[0]", "reward t=0", "steps", "sum reward", "sha(last obs)", "terminated")
        bad = [f"{c}: got {g!r} want {e!r}" for c, g, e in zip(cols, got, exp) if not (g == e and type(g) is type(e))]
        status = "ok" if not bad else "MISMATCH " + "; ".join(bad)
        print(f"golden {env_id:27s} sha(obs0)={got[0]} steps={steps:2d} {status}")
        if bad:
            failures.append(env_id)
    return failures


# ------------------------------------------------------------------------------------------------
# Recording


def to_f64(v, what):
    import numpy as np

    a = np.asarray(v, dtype=np.float64)
    assert a.ndim <= 1, f"{what}: unexpected shape {a.shape}"
    return a


def record_case(gym, np, case, steps, reset_seed0, action_seed):
    name, env_id, _, _, max_steps, kwargs, note = case
    make_kw = dict(kwargs)
    if max_steps is not None:
        make_kw["max_episode_steps"] = max_steps
    env = gym.make(env_id, **make_kw)
    # Sanity: the kwargs reached the env (gym.make forwards them to the constructor).
    assert env.spec.kwargs == {**kwargs}, (env.spec.kwargs, kwargs)
    if max_steps is not None:
        assert env.spec.max_episode_steps == max_steps
    rng = np.random.default_rng(action_seed)
    low = env.action_space.low.astype(np.float64)
    high = env.action_space.high.astype(np.float64)
    act_dim = low.shape[0]
    obs_dim = env.observation_space.shape[0]

    actions = np.empty((steps, act_dim), np.float64)
    obs_arr = np.empty((steps, obs_dim), np.float64)
    reward = np.empty(steps, np.float64)
    terminated = np.zeros(steps, bool)
    truncated = np.zeros(steps, bool)
    step_info = None  # key -> list
    step_keys = None
    reset_steps, reset_seeds, reset_obs, reset_info, reset_keys = [], [], [], None, None
    seeded_resets = 0  # number of seeded resets after the first (0 -> next is a large seed)

    mj_warnings = {}  # MuJoCo warning counters (mjData.warning), summed over episodes

    def collect_warnings():
        import mujoco

        for i, w in enumerate(env.unwrapped.data.warning):
            if w.number:
                key = mujoco.mjtWarning(i).name
                mj_warnings[key] = mj_warnings.get(key, 0) + int(w.number)

    def do_reset(t, seed):
        nonlocal reset_info, reset_keys
        collect_warnings()  # mj_resetData zeroes the counters
        o, info = env.reset(seed=seed) if seed is not None else env.reset()
        assert isinstance(o, np.ndarray) and o.dtype == np.float64 and o.shape == (obs_dim,), (o.dtype, o.shape)
        keys = list(info.keys())
        if reset_keys is None:
            reset_keys, reset_info = keys, {k: [] for k in keys}
        assert keys == reset_keys, f"{name}: reset info keys changed: {keys} != {reset_keys}"
        for k in keys:
            reset_info[k].append(to_f64(info[k], f"reset_info.{k}"))
        reset_steps.append(t)
        reset_seeds.append(-1 if seed is None else seed)
        reset_obs.append(o.copy())

    do_reset(0, reset_seed0)
    next_reset_seeded = False
    for t in range(steps):
        if rng.random() < SPECIAL_PROB:
            kind = int(rng.integers(4))
            if kind == 0:
                a = np.zeros(act_dim)
            elif kind == 1:
                a = low.copy()
            elif kind == 2:
                a = high.copy()
            else:
                a = np.where(rng.random(act_dim) < 0.5, low, high)
        else:
            a = rng.uniform(ACTION_SCALE * low, ACTION_SCALE * high)
        assert a.dtype == np.float64 and a.shape == (act_dim,)
        actions[t] = a
        o, r, term, trunc, info = env.step(a.copy())
        assert isinstance(o, np.ndarray) and o.dtype == np.float64 and o.shape == (obs_dim,), (o.dtype, o.shape)
        assert isinstance(term, (bool, np.bool_)) and isinstance(trunc, (bool, np.bool_))
        obs_arr[t] = o
        reward[t] = float(r)
        terminated[t] = bool(term)
        truncated[t] = bool(trunc)
        keys = list(info.keys())
        if step_keys is None:
            step_keys, step_info = keys, {k: [] for k in keys}
        assert keys == step_keys, f"{name}: step info keys changed at t={t}: {keys} != {step_keys}"
        for k in keys:
            step_info[k].append(to_f64(info[k], f"info.{k}"))
        if (term or trunc) and t + 1 < steps:
            if next_reset_seeded:
                # seeded resets alternate: first a large seed (>= 2**32, multi-word SeedSequence
                # entropy), then a small one (< 2**31), ...
                if seeded_resets % 2 == 0:
                    s = int(rng.integers(2**32, 2**62))
                else:
                    s = int(rng.integers(0, 2**31))
                seeded_resets += 1
                do_reset(t + 1, s)
            else:
                do_reset(t + 1, None)
            next_reset_seeded = not next_reset_seeded
    collect_warnings()
    env.close()

    data = {
        "actions": actions,
        "obs": obs_arr,
        "reward": reward,
        "terminated": terminated,
        "truncated": truncated,
        "reset_step": np.asarray(reset_steps, np.int64),
        "reset_seed": np.asarray(reset_seeds, np.int64),
        "reset_obs": np.asarray(reset_obs, np.float64).reshape(len(reset_obs), obs_dim),
        "step_info_keys": keys_blob(step_keys),
        "reset_info_keys": keys_blob(reset_keys),
    }
    for k in step_keys:
        arr = np.stack(step_info[k])
        assert arr.shape[0] == steps
        data["info." + k] = arr
    for k in reset_keys:
        arr = np.stack(reset_info[k])
        assert arr.shape[0] == len(reset_steps)
        data["reset_info." + k] = arr

    meta = {
        "name": name,
        "env_id": env_id,
        "file": name + ".npz",
        "overrides": {**{k: toml_literal(v) for k, v in kwargs.items()},
                      **({"max_episode_steps": toml_literal(max_steps)} if max_steps is not None else {})},
        "steps": steps,
        "episodes": len(reset_steps),
        "note": note,
        "obs_dim": obs_dim,
        "act_dim": act_dim,
        "step_info_keys": step_keys,
        "reset_info_keys": reset_keys,
        "reset_seed0": reset_seed0,
        "action_seed": action_seed,
        "terminations": int(terminated.sum()),
        "truncations": int(truncated.sum()),
        "mujoco_warnings": mj_warnings,
    }
    return data, meta


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=DEFAULT_OUT, help="output directory (default: fixtures/ next to this script)")
    ap.add_argument("--seed", type=int, default=None,
                    help="derive every case's reset and action seeds from N instead of the table's")
    ap.add_argument("--quick", action="store_true", help=f"{QUICK_STEPS} steps per case")
    ap.add_argument("--verify-golden", action="store_true",
                    help="only check the GOLDEN table's values, exit 1 on mismatch")
    ap.add_argument("--skip-golden", action="store_true", help="do not run the golden check before recording")
    args = ap.parse_args()
    out = os.path.abspath(args.out)  # resolve against the caller's cwd before changing it

    # MuJoCo appends warnings (HalfCheetah's settotalmass deprecation) to MUJOCO_LOG.TXT in the cwd:
    # work in a throw-away directory.
    tmp = tempfile.TemporaryDirectory(prefix="envc-record-")
    os.chdir(tmp.name)
    shimmed = install_render_shims()

    import gymnasium as gym
    import mujoco
    import numpy as np

    installed = {"gymnasium": gym.__version__, "mujoco": mujoco.__version__, "numpy": np.__version__}
    pins = pinned_versions()
    for pkg, v in installed.items():
        # MuJoCo: the pinned version, or another one envc supports (a reference venv of its own,
        # tests/reference/README.md); its manifest names it and envc's build for it replays it.
        if pkg == "mujoco" and v in SUPPORTED_MUJOCO:
            continue
        if pins.get(pkg) != v:
            sys.exit(f"record.py: installed {pkg} {v} != pinned {pins.get(pkg)} ({REQUIREMENTS})")
    if shimmed:
        print(f"note: stand-ins for {', '.join(shimmed)} (renderer-only imports of gymnasium.envs.mujoco)")

    if args.verify_golden or not args.skip_golden:
        failures = verify_golden(gym, np)
        if failures:
            sys.exit(f"record.py: golden values of {len(failures)} env(s) not reproduced: {', '.join(failures)}")
        if args.verify_golden:
            print("golden: all 11 envs reproduced")
            return

    names = [c[0] for c in CASES]
    assert len(set(names)) == len(names), "duplicate case names"
    master = np.random.default_rng(args.seed) if args.seed is not None else None

    os.makedirs(out, exist_ok=True)
    cases_meta, total = [], 0
    for case in CASES:
        name, env_id, (s0, aseed), steps = case[0], case[1], case[2], case[3]
        if master is not None:
            s0, aseed = int(master.integers(0, 2**31)), int(master.integers(0, 2**31))
        if args.quick:
            steps = QUICK_STEPS
        data, meta = record_case(gym, np, case, steps, s0, aseed)
        path = os.path.join(out, meta["file"])
        np.savez_compressed(path, **data)
        size = os.path.getsize(path)
        total += size
        cases_meta.append(meta)
        ov = ", ".join(f"{k}={v}" for k, v in meta["overrides"].items()) or "-"
        print(f"{name:40s} {env_id:26s} T={steps:3d} episodes={meta['episodes']:3d} "
              f"term={meta['terminations']:3d} trunc={meta['truncations']:2d} obs={meta['obs_dim']:3d} "
              f"act={meta['act_dim']:2d} seeds=({s0},{aseed}) {size / 1024:7.1f} KiB  [{ov}]"
              + (f" MuJoCo warnings: {meta['mujoco_warnings']}" if meta["mujoco_warnings"] else ""))

    manifest = {
        **installed,
        "numerics": numerics_profile.profile_name(),
        "numerics_settings": numerics_profile.settings(),
        "protocol": "tests/reference/README.md",
        "master_seed": args.seed,
        "quick": args.quick,
        "cases": cases_meta,
    }
    with open(os.path.join(out, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=1)
        f.write("\n")
    stray = sorted(set(f for f in os.listdir(out) if f.endswith(".npz")) - {m["file"] for m in cases_meta})
    if stray:
        print(f"warning: {out} holds .npz files not in the manifest: {', '.join(stray)}")
    print(f"{len(cases_meta)} cases, {total / 1e6:.2f} MB in {out} (numerics {manifest['numerics']})")
    tmp.cleanup()


if __name__ == "__main__":
    main()
