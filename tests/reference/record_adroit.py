#!/usr/bin/env python3
"""Record Gymnasium-Robotics 1.4.2's Adroit v1 envs (dense and sparse) for envc's replay test
(tests/adroit.rs) and the live check: from a seed, random actions (half of them float32, some
outside [-1, 1] so the clip shows), every observation, reward, termination, truncation and
`success`, through the 200-step truncation and the reset after it.

    .venv/bin/python tests/reference/record_adroit.py              # re-record the committed fixtures
    .venv/bin/python tests/reference/record_adroit.py --out DIR --seed N

Format (one JSON file per id): `{"id", "numerics", "numerics_settings", "seed", "actions" (hex,
steps x nu, float64 values of the actions given), "float32" (per step: the action was passed as
float32), "obs" (hex per event, the reset first), "reward" (hex per step), "success" (per step,
bool), "terminated", "truncated" (per step), "resets_after" (the steps a reset followed),
"forced" (states past the reward's thresholds, which random actions never reach: per state the
reset `seed`, the `qpos` and `qvel` given to `set_state`, the observation after it and after
each of 12 random steps, "actions", "reward", "success", "terminated", "truncated")}`.
"""
import argparse
import json
import os
import sys
import warnings

import mujoco
import numpy as np

warnings.filterwarnings("ignore")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gymnasium as gym  # noqa: E402
import gymnasium_robotics  # noqa: E402

import numerics_profile  # noqa: E402

gym.register_envs(gymnasium_robotics)

IDS = [f"AdroitHand{t}{r}-v1" for t in ("Door", "Hammer", "Pen", "Relocate") for r in ("", "Sparse")]


def hexa(a):
    return np.ascontiguousarray(np.asarray(a, dtype="<f8")).tobytes().hex()


def record(env_id, seed, steps=205):
    """One rollout over the 200-step limit (so a truncation and a second reset are in it)."""
    env = gym.make(env_id)
    nu = env.action_space.shape[0]
    rng = np.random.default_rng(seed + 7)
    actions, f32, obs_l, rew, succ, term, trunc, resets = [], [], [], [], [], [], [], []
    o, info = env.reset(seed=seed)
    assert info == {}
    obs_l.append(hexa(o))
    for t in range(steps):
        a = rng.uniform(-1.3, 1.3, nu)
        as32 = bool(t % 2)
        if as32:
            a = a.astype(np.float32)
        actions.append(np.asarray(a, dtype=np.float64))
        f32.append(as32)
        o, r, te, tr, info = env.step(a)
        obs_l.append(hexa(o))
        rew.append(float(r))
        succ.append(bool(info["success"]))
        term.append(bool(te))
        trunc.append(bool(tr))
        if te or tr:
            o, _ = env.reset()
            resets.append(t)
            obs_l.append(hexa(o))
    return {
        "id": env_id, "numerics": numerics_profile.profile_name(),
        "numerics_settings": numerics_profile.settings(), "seed": seed,
        "actions": hexa(actions), "float32": f32, "obs": obs_l, "reward": hexa(rew),
        "success": succ, "terminated": term, "truncated": trunc, "resets_after": resets,
    }


def _jnt(m, name):
    return m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name)]


def _best(u, qpos, qvel, adrs, grid, score):
    """The values of qpos[adrs] on `grid` (rows) that minimise `score(u)` after mj_forward."""
    best, arg = np.inf, None
    for row in grid:
        q = qpos.copy()
        q[adrs] = row
        u.set_state(q, qvel)
        x = score(u)
        if x < best:
            best, arg = x, row
    return arg


def _placements(env_id, u, qpos, qvel):
    """States where the reward's thresholds are crossed, which random actions never reach: the
    door opened, the hammer lifted and the nail driven, the ball at its target, the pen at its
    goal aligned. Each is a qpos the reference's `set_state` takes; what follows is physics."""
    m, d = u.model, u.data
    out = []
    if "Door" in env_id:
        for hinge in (0.5, 1.1, 1.4):
            q = qpos.copy()
            q[_jnt(m, "door_hinge")] = hinge
            out.append(q)
    elif "Hammer" in env_id:
        nail = [_jnt(m, "nail_dir")]
        gd = lambda u: np.linalg.norm(u.data.site_xpos[u.target_obj_site_id] - u.data.site_xpos[u.goal_site_id])
        for want in (0.0, 0.015):
            v = _best(u, qpos, qvel, nail, np.linspace(-0.2, 0.2, 4001)[:, None], lambda u: abs(gd(u) - want))
            q = qpos.copy()
            q[nail] = v
            q[_jnt(m, "OBJTz")] += 0.1
            out.append(q)
    elif "Relocate" in env_id:
        u.set_state(qpos, qvel)
        delta = d.site_xpos[u.target_obj_site_id] - d.xpos[u.obj_body_id]
        for shift in (0.0, 0.07):
            q = qpos.copy()
            for k, j in enumerate(("OBJTx", "OBJTy", "OBJTz")):
                q[_jnt(m, j)] += delta[k] + (shift if k == 0 else 0.0)
            out.append(q)
    elif "Pen" in env_id:
        u.set_state(qpos, qvel)
        delta = d.site_xpos[u.eps_ball_site_id] - d.xpos[u.obj_body_id]
        q = qpos.copy()
        for k, j in enumerate(("OBJTx", "OBJTy", "OBJTz")):
            q[_jnt(m, j)] += delta[k]
        rot = [_jnt(m, "OBJRx"), _jnt(m, "OBJRy")]
        g = np.linspace(-1.6, 1.6, 81)
        grid = np.array([(a, b) for a in g for b in g])
        sim = lambda u: -np.dot(
            (u.data.site_xpos[u.obj_t_site_id] - u.data.site_xpos[u.obj_b_site_id]) / u.pen_length,
            (u.data.site_xpos[u.tar_t_site_id] - u.data.site_xpos[u.tar_b_site_id]) / u.tar_length,
        )
        q[rot] = _best(u, q, qvel, rot, grid, sim)
        out.append(q)
    u.set_state(qpos, qvel)
    return out


def forced(env_id, seed, steps=12):
    """After a reset, a state set by `set_state` (`_placements`), then random steps."""
    env = gym.make(env_id)
    u = env.unwrapped
    nu = env.action_space.shape[0]
    rng = np.random.default_rng(seed + 11)
    out = []
    for k in range(len(_placements(env_id, *_reset(env, seed)))):
        u_qpos, u_qvel = _reset(env, seed + k)[1:]
        q = _placements(env_id, u, u_qpos, u_qvel)[k]
        u.set_state(q, u_qvel)
        seg = {"seed": seed + k, "qpos": hexa(q), "qvel": hexa(u_qvel), "obs": [hexa(u._get_obs())],
               "actions": [], "reward": [], "success": [], "terminated": [], "truncated": []}
        for _ in range(steps):
            a = rng.uniform(-0.3, 0.3, nu)
            o, r, te, tr, info = env.step(a)
            seg["actions"].append(hexa(a))
            seg["obs"].append(hexa(o))
            seg["reward"].append(hexa([r]))
            seg["success"].append(bool(info["success"]))
            seg["terminated"].append(bool(te))
            seg["truncated"].append(bool(tr))
        out.append(seg)
    return out


def _reset(env, seed):
    env.reset(seed=seed)
    u = env.unwrapped
    return u, u.data.qpos.copy(), u.data.qvel.copy()


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(here, "fixtures", "adroit"))
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--ids", nargs="*", default=IDS)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for env_id in args.ids:
        # The same seed for an id whichever ids are recorded with it.
        seed = args.seed + (IDS.index(env_id) if env_id in IDS else 0)
        rec = record(env_id, seed)
        rec["forced"] = forced(env_id, seed + 100)
        with open(os.path.join(args.out, f"{env_id}.json"), "w") as f:
            json.dump(rec, f, separators=(",", ":"))
        print(f"record_adroit: {env_id} seed {rec['seed']}, {len(rec['float32'])} steps, "
              f"{len(rec['resets_after'])} resets, {sum(rec['success'])} successes; "
              f"{len(rec['forced'])} set states, "
              f"{sum(sum(f['success']) for f in rec['forced'])} successes after them",
              file=sys.stderr)


if __name__ == "__main__":
    main()
